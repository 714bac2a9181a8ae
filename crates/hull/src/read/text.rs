//! The text of an input file: UTF-8 with or without a byte-order mark; UTF-16 and NUL bytes
//! refused with a message saying so.

use crate::error::{HullError, InputErrorKind, Location};

/// Checks raw bytes are UTF-8 text and returns them as a `&str`.
///
/// # Errors
///
/// [`InputErrorKind::Utf16`] for a UTF-16 byte-order mark, [`InputErrorKind::Binary`] for
/// invalid UTF-8 or a NUL byte, located at the line of the first bad byte.
pub fn decode<'a>(bytes: &'a [u8], source: &str) -> Result<&'a str, HullError> {
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) || looks_utf16(bytes) {
        return Err(HullError::input(Location::line(source, 1), InputErrorKind::Utf16));
    }
    let line_of = |pos: usize| 1 + bytes[..pos].iter().filter(|&&b| b == b'\n').count();
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let pos = e.valid_up_to();
        HullError::input(
            Location::line(source, line_of(pos)),
            InputErrorKind::Binary { detail: format!("invalid UTF-8 at byte offset {pos}") },
        )
    })?;
    check_no_nul(text, source)?;
    Ok(text)
}

/// UTF-16 without a byte-order mark: ASCII text in UTF-16 has a NUL in every other byte. True
/// when, over the first 64 bytes (at least 4), all the odd bytes or all the even bytes are NUL
/// and none of the others is.
pub(super) fn looks_utf16(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(64) & !1];
    if head.len() < 4 {
        return false;
    }
    let nul_at = |parity: usize| head.iter().skip(parity).step_by(2).all(|&b| b == 0);
    let none_at = |parity: usize| head.iter().skip(parity).step_by(2).all(|&b| b != 0);
    (nul_at(1) && none_at(0)) || (nul_at(0) && none_at(1))
}

/// A NUL character never occurs in a CSV text: its presence means a binary file.
pub(super) fn check_no_nul(text: &str, source: &str) -> Result<(), HullError> {
    match text.find('\0') {
        Some(pos) => Err(HullError::input(
            Location::line(source, 1 + text[..pos].matches('\n').count()),
            InputErrorKind::Binary { detail: format!("NUL byte at byte offset {pos}") },
        )),
        None => Ok(()),
    }
}
