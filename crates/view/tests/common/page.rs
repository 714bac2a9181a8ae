//! Reading the self-contained pages (the HTML report, the viewer) in tests: the workspace's one
//! copy, included by view's unit tests and the command line's tests.

/// The bytes of a base64 text (a `data:` URI's payload).
pub fn unbase64(s: &str) -> Vec<u8> {
    base64::Engine::decode(&base64::engine::general_purpose::STANDARD, s).expect("base64")
}

/// The distinct `http(s)://` URLs of a text, sorted.
pub fn urls(text: &str) -> Vec<&str> {
    let mut out: Vec<&str> = text
        .match_indices("http")
        .map(|(k, _)| &text[k..])
        .filter(|rest| rest.starts_with("http://") || rest.starts_with("https://"))
        .map(|rest| &rest[..rest.find(|c: char| "\"'&<> )".contains(c)).unwrap_or(rest.len())])
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}
