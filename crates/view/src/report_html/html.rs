//! Small HTML helpers of the report: escaping, numbers, tables, base64 data URIs.
//!
//! Everything written here is also well-formed XML (polyglot XHTML5): attributes always
//! quoted, void elements closed (`<img .../>`), only the five XML entities and numeric
//! character references, so the page reads in any browser and in an XML parser alike.

use std::fmt::Write as _;

pub(crate) use crate::markup::{base64, escape as esc, escape_document as esc_srcdoc};

/// `v` with 4 significant digits (`n/a` if not finite): the report's one number format.
pub(crate) fn num(v: f64) -> String {
    if v.is_finite() {
        hull::format_sig(v, 4)
    } else {
        "n/a".into()
    }
}

/// `v` with a fixed number of decimals (`n/a` if not finite).
pub(crate) fn fixed(v: f64, decimals: usize) -> String {
    if v.is_finite() {
        format!("{v:.decimals$}")
    } else {
        "n/a".into()
    }
}

/// A point `(x, y, z)` with 4 significant digits per coordinate.
pub(crate) fn point(p: [f64; 3]) -> String {
    format!("({}, {}, {})", num(p[0]), num(p[1]), num(p[2]))
}

/// A header cell, with the unit on a second line when given.
pub(crate) fn th(label: &str, unit: Option<&str>) -> String {
    match unit {
        Some(u) => format!("<th scope=\"col\">{}<span class=\"unit\">{}</span></th>", esc(label), esc(u)),
        None => format!("<th scope=\"col\">{}</th>", esc(label)),
    }
}

/// A left-aligned header of a key column.
pub(crate) fn th_key(label: &str) -> String {
    format!("<th scope=\"col\" class=\"key\">{}</th>", esc(label))
}

/// A number cell showing `shown`, carrying the exact value (shortest digits that read back to
/// the same `f64`) in `data-value` for scripts and tests.
pub(crate) fn td_num(v: f64, shown: &str) -> String {
    format!("<td data-value=\"{v}\">{}</td>", esc(shown))
}

/// A number cell with 4 significant digits.
pub(crate) fn td(v: f64) -> String {
    td_num(v, &num(v))
}

/// A left-aligned key cell.
pub(crate) fn td_key(s: &str) -> String {
    format!("<td class=\"key\">{}</td>", esc(s))
}

/// A left-aligned wrapping text cell (already HTML).
pub(crate) fn td_html(html: &str) -> String {
    format!("<td class=\"text\">{html}</td>")
}

/// A table: `id` (may be empty), header cells, rows of cells; rows flagged `true` get the class
/// `mark` (highlighted). Wrapped in a horizontally scrolling block.
pub(crate) fn table(id: &str, class: &str, head: &[String], rows: &[(bool, Vec<String>)]) -> String {
    let mut t = String::from("<div class=\"scroll\">");
    let id_attr = if id.is_empty() { String::new() } else { format!(" id=\"{}\"", esc(id)) };
    let _ = write!(t, "<table{id_attr} class=\"{}\">\n<thead><tr>", esc(class));
    for h in head {
        t.push_str(h);
    }
    t.push_str("</tr></thead>\n<tbody>\n");
    for (mark, cells) in rows {
        t.push_str(if *mark { "<tr class=\"mark\">" } else { "<tr>" });
        for c in cells {
            t.push_str(c);
        }
        t.push_str("</tr>\n");
    }
    t.push_str("</tbody>\n</table></div>\n");
    t
}

/// A two-column table of names and values (the values already HTML).
pub(crate) fn kv_table(id: &str, rows: &[(String, String)]) -> String {
    let mut t = String::new();
    let id_attr = if id.is_empty() { String::new() } else { format!(" id=\"{}\"", esc(id)) };
    let _ = writeln!(t, "<table{id_attr} class=\"kv\"><tbody>");
    for (k, v) in rows {
        let _ = writeln!(t, "<tr><td>{}</td><td>{v}</td></tr>", esc(k));
    }
    t.push_str("</tbody></table>\n");
    t
}

/// An `<img>` of PNG bytes as a `data:` URI, with its pixel size.
pub(crate) fn png_img(png: &[u8], width: u32, height: u32, alt: &str, id: &str) -> String {
    format!(
        "<img id=\"{}\" src=\"data:image/png;base64,{}\" width=\"{width}\" height=\"{height}\" alt=\"{}\"/>",
        esc(id),
        base64(png),
        esc(alt)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_cells_carry_the_exact_value() {
        let v = 0.1 + 0.2;
        let cell = td(v);
        assert_eq!(cell, "<td data-value=\"0.30000000000000004\">0.3000</td>");
        assert_eq!(num(f64::NAN), "n/a");
        assert_eq!(fixed(2.0 / 3.0, 3), "0.667");
    }
}
