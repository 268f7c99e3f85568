//! XML text escaping, shared by the writers of XML: the experiment's SVG figures and the 3MF
//! model.

/// `text` with the five characters XML reserves replaced by their entities, for element
/// content and attribute values alike.
pub(crate) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::escape;

    #[test]
    fn the_five_reserved_characters_become_entities() {
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
        assert_eq!(escape("it's > 1"), "it&apos;s &gt; 1");
        assert_eq!(escape("plain ü"), "plain ü");
    }
}
