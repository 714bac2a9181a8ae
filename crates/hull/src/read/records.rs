//! Delimited text: lines, fields, the delimiter of the file and numbers with a decimal point
//! or comma (the rules of [`super`]).

use std::borrow::Cow;

use crate::error::{HullError, InputErrorKind, Location};

use super::text::check_no_nul;

/// One field of a record: its trimmed (and unquoted) text and 1-based column.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Field<'a> {
    pub text: Cow<'a, str>,
    pub column: usize,
}

/// One data line: its 1-based line number and all its fields (at least one not empty).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Record<'a> {
    pub line: usize,
    pub fields: Vec<Field<'a>>,
}

impl Record<'_> {
    /// The number of fields up to the last non-empty one: spreadsheets often append empty
    /// fields, which carry nothing.
    pub fn significant_len(&self) -> usize {
        self.fields.iter().rposition(|f| !f.text.is_empty()).map_or(0, |i| i + 1)
    }

    /// The place of field `column` (1-based).
    pub fn at(&self, source: &str, column: usize) -> Location {
        Location::new(source, self.line, column)
    }
}

/// Splits a text into records (see the module docs for the rules).
///
/// # Errors
///
/// Binary text (NUL), an unterminated quote, text after a closing quote, or a line that uses
/// another delimiter than the file's first data line (`;` or tabs in a comma file,
/// [`InputErrorKind::Separator`]; any other, [`InputErrorKind::SeparatorChange`]).
pub(crate) fn records<'a>(text: &'a str, source: &str) -> Result<Vec<Record<'a>>, HullError> {
    check_no_nul(text, source)?;
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    let mut out = Vec::new();
    let mut delimiter = None;
    for (i, line) in split_lines(text).enumerate() {
        let lineno = i + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let (sep, first_line) = *delimiter.get_or_insert((delimiter_of(trimmed), lineno));
        let mut fields = split_fields(line, sep, source, lineno)?;
        if fields.iter().all(|f| f.text.is_empty()) {
            continue; // ",,,": an empty spreadsheet row
        }
        if sep != ',' {
            for f in &mut fields {
                if let Some(number) = decimal_comma_number(&f.text) {
                    f.text = Cow::Owned(number);
                }
            }
        }
        if fields.len() == 1 {
            let other = [',', ';', '\t'].into_iter().find(|&c| c != sep && fields[0].text.contains(c));
            match other {
                Some(separator) if sep == ',' => {
                    return Err(HullError::input(
                        Location::line(source, lineno),
                        InputErrorKind::Separator { separator },
                    ))
                }
                Some(separator) => {
                    return Err(HullError::input(
                        Location::line(source, lineno),
                        InputErrorKind::SeparatorChange { separator, expected: sep, first_line },
                    ))
                }
                None => {}
            }
        }
        out.push(Record { line: lineno, fields });
    }
    Ok(out)
}

/// The delimiter a file's first data line sets (see the module docs): `;`, else a tab, when the
/// line holds it and every piece between them holds at most one comma, not at either end (a
/// decimal comma); else `,`.
pub(super) fn delimiter_of(first: &str) -> char {
    let splits_cleanly = |sep: char| {
        first.contains(sep)
            && first
                .split(sep)
                .map(str::trim)
                .all(|p| p.matches(',').count() <= 1 && !p.starts_with(',') && !p.ends_with(','))
    };
    [';', '\t'].into_iter().find(|&sep| splits_cleanly(sep)).unwrap_or(',')
}

/// `1,5` as `1.5`: a field holding one comma, no point, that reads as a finite number once the
/// comma is a point; `None` for anything else (labels, `1.000,5`, `1,2,3`).
pub(super) fn decimal_comma_number(text: &str) -> Option<String> {
    if text.matches(',').count() != 1 || text.contains('.') {
        return None;
    }
    let number = text.replacen(',', ".", 1);
    // The digits around the comma must be digits: `,5` and `5,` are written by no spreadsheet.
    let (before, after) = text.split_once(',')?;
    let digit_ends = before.ends_with(|c: char| c.is_ascii_digit()) && after.starts_with(|c: char| c.is_ascii_digit());
    (digit_ends && number.parse::<f64>().is_ok_and(f64::is_finite)).then_some(number)
}

/// Lines of `text`, ended by `\r\n`, `\n` or a lone `\r`; a final line end does not start
/// one more (empty) line.
pub(crate) fn split_lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let s = rest?;
        match s.find(['\r', '\n']) {
            Some(i) => {
                let skip = if s[i..].starts_with("\r\n") { 2 } else { 1 };
                let after = &s[i + skip..];
                rest = if after.is_empty() { None } else { Some(after) };
                Some(&s[..i])
            }
            None => {
                rest = None;
                Some(s)
            }
        }
    })
}

/// Splits one line at `sep` into trimmed fields, unquoting `"..."` fields.
pub(super) fn split_fields<'a>(
    line: &'a str,
    sep: char,
    source: &str,
    lineno: usize,
) -> Result<Vec<Field<'a>>, HullError> {
    // A tab delimiter is not a blank to trim.
    let is_blank = |c: char| c == ' ' || (c == '\t' && sep != '\t');
    let mut fields = Vec::new();
    let mut rest = line;
    loop {
        let column = fields.len() + 1;
        let start = rest.trim_start_matches(is_blank);
        if let Some(quoted) = start.strip_prefix('"') {
            // A quoted field: up to the first quote not doubled.
            let mut value = String::new();
            let mut chars = quoted.char_indices();
            let end = loop {
                match chars.next() {
                    None => {
                        return Err(HullError::input(
                            Location::new(source, lineno, column),
                            InputErrorKind::UnterminatedQuote,
                        ))
                    }
                    Some((i, '"')) => {
                        if quoted[i + 1..].starts_with('"') {
                            value.push('"');
                            chars.next();
                        } else {
                            break i + 1;
                        }
                    }
                    Some((_, c)) => value.push(c),
                }
            };
            let after = &quoted[end..];
            let (stray, next) = match after.find(sep) {
                Some(i) => (&after[..i], Some(&after[i + sep.len_utf8()..])),
                None => (after, None),
            };
            if !stray.trim_matches(is_blank).is_empty() {
                return Err(HullError::input(
                    Location::new(source, lineno, column),
                    InputErrorKind::TextAfterQuote { text: stray.trim_matches(is_blank).to_string() },
                ));
            }
            fields.push(Field { text: Cow::Owned(value.trim_matches(is_blank).to_string()), column });
            match next {
                Some(n) => rest = n,
                None => break,
            }
        } else {
            match start.find(sep) {
                Some(i) => {
                    fields.push(Field { text: Cow::Borrowed(start[..i].trim_matches(is_blank)), column });
                    rest = &start[i + sep.len_utf8()..];
                }
                None => {
                    fields.push(Field { text: Cow::Borrowed(start.trim_matches(is_blank)), column });
                    break;
                }
            }
        }
    }
    Ok(fields)
}

/// Parses a finite decimal number from a field, saying what it should have been otherwise.
///
/// # Errors
///
/// [`InputErrorKind::EmptyField`], [`InputErrorKind::DecimalComma`],
/// [`InputErrorKind::NotFinite`] (`nan`, `inf`, overflow) or [`InputErrorKind::NotANumber`].
pub(crate) fn parse_number(
    text: &str,
    at: impl FnOnce() -> Location,
    expected: impl FnOnce() -> String,
) -> Result<f64, HullError> {
    if text.is_empty() {
        return Err(HullError::input(at(), InputErrorKind::EmptyField { expected: expected() }));
    }
    let text_ = shown(text);
    let kind = match text.parse::<f64>() {
        Ok(v) if v.is_finite() => return Ok(v),
        // Rust's parser takes "nan", "inf", "infinity" in any case, and overflows to inf.
        Ok(_) => InputErrorKind::NotFinite { text: text_, expected: expected() },
        Err(_) if text.contains(',') && text.replacen(',', ".", 1).parse::<f64>().is_ok_and(f64::is_finite) => {
            InputErrorKind::DecimalComma { text: text_, expected: expected() }
        }
        Err(_) => InputErrorKind::NotANumber { text: text_, expected: expected() },
    };
    Err(HullError::input(at(), kind))
}

/// A field as quoted in a message: whole up to 64 characters, else its first 64 and its length,
/// so that a runaway field (a file of one 100 MB line) does not flood the terminal.
pub(crate) fn shown(text: &str) -> String {
    const MAX: usize = 64;
    match text.char_indices().nth(MAX) {
        None => text.to_string(),
        Some((end, _)) => format!("{}... ({} characters)", &text[..end], text.chars().count()),
    }
}
