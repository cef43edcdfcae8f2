//! Escaping text for HTML (the report page, the claims page) and XML (JUnit), written once:
//! the markup characters become entities in both; XML also keeps line breaks and tabs as
//! character references (so that attribute values keep them) and replaces the characters XML 1.0
//! cannot carry (most control characters) by U+FFFD.

#[derive(Clone, Copy, PartialEq, Eq)]
enum Markup {
    Html,
    Xml,
}

/// Escapes text for HTML element content and attribute values.
pub fn escape_html(s: &str) -> String {
    escape(s, Markup::Html)
}

/// Escapes text for XML attribute values and character data.
pub fn escape_xml(s: &str) -> String {
    escape(s, Markup::Xml)
}

fn escape(s: &str, markup: Markup) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        let entity = match (ch, markup) {
            ('&', _) => "&amp;",
            ('<', _) => "&lt;",
            ('>', _) => "&gt;",
            ('"', _) => "&quot;",
            ('\'', Markup::Html) => "&#39;",
            ('\'', Markup::Xml) => "&apos;",
            ('\n', Markup::Xml) => "&#10;",
            ('\r', Markup::Xml) => "&#13;",
            ('\t', Markup::Xml) => "&#9;",
            (c, Markup::Xml) if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => "\u{FFFD}",
            (c, _) => {
                out.push(c);
                continue;
            }
        };
        out.push_str(entity);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup_and_control_characters() {
        assert_eq!(escape_xml(r#"a<b>&"c"'d'"#), "a&lt;b&gt;&amp;&quot;c&quot;&apos;d&apos;");
        assert_eq!(escape_xml("x\ny\u{1}"), "x&#10;y\u{FFFD}");
        assert_eq!(escape_html(r#"a<b>&"c"'d'"#), "a&lt;b&gt;&amp;&quot;c&quot;&#39;d&#39;");
        assert_eq!(escape_html("x\ny\u{1}"), "x\ny\u{1}");
    }
}
