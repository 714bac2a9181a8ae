//! SVG 1.1 writer of a [`Drawing`].
//!
//! The sheet is written at its true size (`width="420mm"`) with a `viewBox` in millimetres, so
//! one user unit is one paper millimetre and the file prints at scale. The drawing model has y
//! up from the bottom-left corner; SVG has y down from the top-left, so every point is written
//! as `(x, height - y)`.
//!
//! Each layer becomes one `<g id="layer">`, in the order the layers first appear among the
//! items; within a layer the items keep their order. Numbers are written with at most three
//! decimals (1 µm on paper), trailing zeros dropped, so the output is compact and the same
//! bytes on every platform. Text is XML-escaped.

use std::collections::HashSet;
use std::io::{self, Write};

use super::model::{Anchor, Drawing, Item, Stroke};
use crate::markup::escape;

/// SVG sizes fonts by the em; the model sizes text by its cap height. The cap height of the
/// usual sans-serif faces (Helvetica, Arial, DejaVu Sans) is 0.72-0.73 em, so
/// `font-size = cap height / 0.72`.
pub const CAP_HEIGHT_PER_EM: f64 = 0.72;

/// Write `d` as an SVG 1.1 document.
///
/// Polylines and polygons with fewer than two points are skipped (they draw nothing); closed
/// polylines become unfilled `<polygon>`s, markers `<circle>`s.
///
/// # Errors
/// Any error of `w`, and [`io::ErrorKind::InvalidData`] if a coordinate or size is NaN or
/// infinite (SVG cannot hold it).
pub fn write_svg<W: Write>(w: &mut W, d: &Drawing) -> io::Result<()> {
    let h = d.height_mm;
    writeln!(w, r#"<?xml version="1.0" encoding="UTF-8" standalone="no"?>"#)?;
    writeln!(
        w,
        r#"<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{}mm" height="{}mm" viewBox="0 0 {} {}" font-family="Helvetica, Arial, sans-serif" stroke-linecap="round" stroke-linejoin="round">"#,
        num(d.width_mm)?,
        num(h)?,
        num(d.width_mm)?,
        num(h)?
    )?;
    writeln!(w, "<title>{}</title>", escape(&d.title))?;
    let mut ids = HashSet::new();
    for (layer, items) in layers(d) {
        writeln!(w, r#"<g id="{}">"#, unique_id(layer, &mut ids))?;
        for item in items {
            write_item(w, item, h)?;
        }
        writeln!(w, "</g>")?;
    }
    writeln!(w, "</svg>")
}

/// The items grouped by layer, layers in order of first appearance, items in drawing order
/// within each layer (shared with the DXF writer so both files list the same things in the
/// same order).
pub(crate) fn layers(d: &Drawing) -> Vec<(&str, Vec<&Item>)> {
    let mut out: Vec<(&str, Vec<&Item>)> = Vec::new();
    for item in &d.items {
        match out.iter_mut().find(|(name, _)| *name == item.layer()) {
            Some((_, items)) => items.push(item),
            None => out.push((item.layer(), vec![item])),
        }
    }
    out
}

fn write_item<W: Write>(w: &mut W, item: &Item, h: f64) -> io::Result<()> {
    match item {
        Item::Polyline { points, closed, stroke, .. } => {
            if points.len() < 2 {
                return Ok(());
            }
            let tag = if *closed { "polygon" } else { "polyline" };
            writeln!(w, r#"<{tag} points="{}" fill="none"{}/>"#, point_list(points, h)?, stroke_attrs(stroke)?)
        }
        Item::Polygon { points, fill, .. } => {
            if points.len() < 2 {
                return Ok(());
            }
            writeln!(w, r#"<polygon points="{}" fill="{}" stroke="none"/>"#, point_list(points, h)?, fill.hex())
        }
        Item::Marker { at, size_mm, fill, .. } => writeln!(
            w,
            r#"<circle cx="{}" cy="{}" r="{}" fill="{}"/>"#,
            num(at[0])?,
            num(h - at[1])?,
            num(0.5 * size_mm)?,
            fill.hex()
        ),
        Item::Text { at, text, size_mm, anchor, color, .. } => {
            let anchor = match anchor {
                Anchor::Start => "start",
                Anchor::Middle => "middle",
                Anchor::End => "end",
            };
            writeln!(
                w,
                r#"<text x="{}" y="{}" font-size="{}" text-anchor="{anchor}" fill="{}">{}</text>"#,
                num(at[0])?,
                num(h - at[1])?,
                num(size_mm / CAP_HEIGHT_PER_EM)?,
                color.hex(),
                escape(text)
            )
        }
    }
}

fn stroke_attrs(s: &Stroke) -> io::Result<String> {
    let mut a = format!(r#" stroke="{}" stroke-width="{}""#, s.color.hex(), num(s.width_mm)?);
    if let Some(dash) = s.dash.as_ref().filter(|d| !d.is_empty()) {
        let parts: io::Result<Vec<String>> = dash.iter().map(|&x| num(x)).collect();
        a.push_str(&format!(r#" stroke-dasharray="{}""#, parts?.join(" ")));
    }
    Ok(a)
}

fn point_list(points: &[[f64; 2]], h: f64) -> io::Result<String> {
    let mut s = String::with_capacity(points.len() * 16);
    for (i, p) in points.iter().enumerate() {
        if i > 0 {
            s.push(' ');
        }
        s.push_str(&num(p[0])?);
        s.push(',');
        s.push_str(&num(h - p[1])?);
    }
    Ok(s)
}

/// `x` rounded to 3 decimals, without trailing zeros or a trailing point, `-0` written `0`.
///
/// # Errors
/// [`io::ErrorKind::InvalidData`] for NaN and infinities.
pub(crate) fn num(x: f64) -> io::Result<String> {
    if !x.is_finite() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("cannot write the non-finite number {x} in SVG"),
        ));
    }
    let mut s = format!("{x:.3}");
    if s.contains('.') {
        let trimmed = s.trim_end_matches('0').trim_end_matches('.').len();
        s.truncate(trimmed);
    }
    if s == "-0" {
        s = "0".into();
    }
    Ok(s)
}

/// A valid, unique XML id for a layer name: characters other than ASCII letters, digits, `-`
/// and `_` become `_`, a leading digit or `-` gets a `_` prefix, and a repeated id gets a
/// numeric suffix. Plain layer names (`stations`, `offsets`) are kept as they are.
fn unique_id(layer: &str, used: &mut HashSet<String>) -> String {
    let mut id: String =
        layer.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect();
    if !id.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_') {
        id.insert(0, '_');
    }
    let mut candidate = id.clone();
    let mut k = 2;
    while !used.insert(candidate.clone()) {
        candidate = format!("{id}_{k}");
        k += 1;
    }
    candidate
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::model::Rgb;

    fn sample() -> Drawing {
        let mut d = Drawing::new(100.0, 50.0, "A & B <test>");
        d.push(Item::Polyline {
            points: vec![[10.0, 10.0], [20.0, 40.0]],
            closed: false,
            stroke: Stroke { color: Rgb(255, 0, 0), width_mm: 0.35, dash: Some(vec![2.0, 1.0]) },
            layer: "stations".into(),
        });
        d.push(Item::Marker { at: [5.0, 5.0], size_mm: 1.0, fill: Rgb::BLACK, layer: "offsets".into() });
        d.push(Item::Text {
            at: [50.0, 45.0],
            text: "WL \"1\" <x>".into(),
            size_mm: 3.6,
            anchor: Anchor::Middle,
            color: Rgb::BLACK,
            layer: "stations".into(),
        });
        d.push(Item::Polygon {
            points: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
            fill: Rgb(1, 2, 3),
            layer: "9 bad id".into(),
        });
        d
    }

    fn svg(d: &Drawing) -> String {
        let mut out = Vec::new();
        write_svg(&mut out, d).expect("writes to memory");
        String::from_utf8(out).expect("UTF-8")
    }

    #[test]
    fn numbers_are_compact_and_rounded_to_a_micrometre() {
        for (x, want) in [(1.0, "1"), (0.25, "0.25"), (-0.0004, "0"), (12.3456, "12.346"), (-3.1, "-3.1"), (0.0, "0")] {
            assert_eq!(num(x).expect("finite"), want, "{x}");
        }
        assert_eq!(num(f64::NAN).expect_err("NaN").kind(), io::ErrorKind::InvalidData);
    }

    #[test]
    fn layers_group_in_first_appearance_order_and_y_is_flipped() {
        let s = svg(&sample());
        let doc = roxmltree::Document::parse(&s).expect("well-formed XML");
        let root = doc.root_element();
        assert_eq!(root.attribute("width"), Some("100mm"));
        assert_eq!(root.attribute("viewBox"), Some("0 0 100 50"));
        let groups: Vec<&str> =
            root.children().filter(|n| n.has_tag_name("g")).filter_map(|g| g.attribute("id")).collect();
        assert_eq!(groups, ["stations", "offsets", "_9_bad_id"]);
        // Both `stations` items are in the first group, the polyline first.
        let first = root.children().find(|n| n.has_tag_name("g")).expect("a group");
        let tags: Vec<&str> = first.children().filter(|n| n.is_element()).map(|n| n.tag_name().name()).collect();
        assert_eq!(tags, ["polyline", "text"]);
        let line = first.children().find(|n| n.has_tag_name("polyline")).expect("polyline");
        // y = 10 and 40 on a 50 mm high sheet are 40 and 10 from the top.
        assert_eq!(line.attribute("points"), Some("10,40 20,10"));
        assert_eq!(line.attribute("stroke-dasharray"), Some("2 1"));
        assert_eq!(line.attribute("stroke"), Some("#ff0000"));
        let text = first.children().find(|n| n.has_tag_name("text")).expect("text");
        assert_eq!(text.text(), Some("WL \"1\" <x>"));
        assert_eq!(text.attribute("text-anchor"), Some("middle"));
        // Cap height 3.6 mm is a 5 mm font.
        assert_eq!(text.attribute("font-size"), Some("5"));
        let title = root.children().find(|n| n.has_tag_name("title")).expect("title");
        assert_eq!(title.text(), Some("A & B <test>"));
        let circle = doc.descendants().find(|n| n.has_tag_name("circle")).expect("marker");
        assert_eq!((circle.attribute("cy"), circle.attribute("r")), (Some("45"), Some("0.5")));
    }

    #[test]
    fn same_drawing_same_bytes_and_non_finite_refused() {
        assert_eq!(svg(&sample()), svg(&sample()));
        let mut d = sample();
        d.push(Item::Marker { at: [f64::NAN, 1.0], size_mm: 1.0, fill: Rgb::BLACK, layer: "x".into() });
        let mut out = Vec::new();
        assert_eq!(write_svg(&mut out, &d).expect_err("NaN").kind(), io::ErrorKind::InvalidData);
    }

    #[test]
    fn ids_are_unique_and_valid() {
        let mut used = HashSet::new();
        assert_eq!(unique_id("a b", &mut used), "a_b");
        assert_eq!(unique_id("a_b", &mut used), "a_b_2");
        assert_eq!(unique_id("-x", &mut used), "_-x");
        assert_eq!(unique_id("", &mut used), "_");
    }
}
