//! Text for markup (SVG, HTML, XHTML): escaping and base64, shared by the drawing writers, the
//! 3-D viewer and the report.

use base64::Engine as _;

/// XML-escape text content and attribute values (`&`, `<`, `>`, `"`, `'`); control characters
/// other than tab, which XML 1.0 cannot hold, become spaces. Also right for HTML.
pub(crate) fn escape(s: &str) -> String {
    escape_with(s, false)
}

/// A whole document for an attribute (an iframe's `srcdoc`): [`escape`], and the white space an
/// XML parser would normalise in an attribute value (line feed, carriage return, tab) as
/// character references, so that both an HTML and an XML reader give back exactly `s`.
// For the report (with the PNG pictures), which holds the viewer page in an iframe.
#[cfg_attr(not(feature = "png"), allow(dead_code))]
pub(crate) fn escape_document(s: &str) -> String {
    escape_with(s, true)
}

fn escape_with(s: &str, keep_white_space: bool) -> String {
    let mut out = String::with_capacity(s.len() + s.len() / 16);
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\n' if keep_white_space => out.push_str("&#10;"),
            '\r' if keep_white_space => out.push_str("&#13;"),
            '\t' if keep_white_space => out.push_str("&#9;"),
            '\t' => out.push(c),
            c if c.is_control() && !(keep_white_space && (c == '\n' || c == '\r')) => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Standard base64 (RFC 4648 section 4) with padding.
pub(crate) fn base64(bytes: &[u8]) -> String {
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_the_five_xml_characters_and_blanks_controls() {
        assert_eq!(escape("a<b>&\"c'\u{1}\td"), "a&lt;b&gt;&amp;&quot;c&apos; \td");
        assert_eq!(escape("x\ny"), "x y");
    }

    #[test]
    fn document_escaping_survives_an_xml_reader() {
        let doc = "<p class=\"a\">x & y\n\tz\r\n</p>";
        let xml = format!("<r a=\"{}\"/>", escape_document(doc));
        let parsed = roxmltree::Document::parse(&xml).expect("well-formed");
        assert_eq!(parsed.root_element().attribute("a"), Some(doc));
    }

    #[test]
    fn base64_matches_the_rfc_4648_vectors() {
        // RFC 4648 section 10.
        for (plain, coded) in [("", ""), ("f", "Zg=="), ("fo", "Zm8="), ("foo", "Zm9v"), ("foobar", "Zm9vYmFy")] {
            assert_eq!(base64(plain.as_bytes()), coded);
        }
    }
}
