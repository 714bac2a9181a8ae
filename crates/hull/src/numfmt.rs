//! Numbers for people: the one place that rounds a figure to significant digits for text
//! (tables, messages, drawings, the report). Full precision stays in CSV and JSON.

/// The exponent of `a > 0` after rounding to `sig` digits (0.99996 rounds to 1.000, so 0).
fn exponent(a: f64, sig: usize) -> i32 {
    let e = a.log10().floor() as i32;
    let unit = 10f64.powi(e + 1 - sig as i32);
    if (a / unit).round() * unit >= 10f64.powi(e + 1) {
        e + 1
    } else {
        e
    }
}

/// `v` to `sig` significant digits: decimal for `1e-3 <= |v| < 1e5`, else scientific
/// (`1.23e-5`); `0` as `0`.
pub fn format_sig(v: f64, sig: usize) -> String {
    let sig = sig.max(1);
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { format!("{v}") };
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let decimals = (sig as i32 - 1 - exponent(a, sig)).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.*e}", sig - 1)
    }
}

/// Most decimals [`format_sig_plain`] writes: below `1e-9` a figure prints as zero.
const MAX_PLAIN_DECIMALS: i32 = 9;

/// `v` to at least `sig` significant digits in plain notation, for tables: large numbers keep
/// every integer digit (`123457` for 123456.7 to 5 digits), small ones at most
/// [`MAX_PLAIN_DECIMALS`] decimals; `0` as `0`, `-0` as `0`.
pub(crate) fn format_sig_plain(v: f64, sig: usize) -> String {
    let sig = sig.max(1);
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    let decimals = (sig as i32 - 1 - exponent(v.abs(), sig)).clamp(0, MAX_PLAIN_DECIMALS) as usize;
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        "0".into()
    } else {
        s
    }
}

/// Significant digits of the figures in text tables ([`format_figure`]; full precision stays
/// in CSV and JSON).
pub const TEXT_DIGITS: usize = 5;

/// `v` as a figure in a text table or summary: 5 (`TEXT_DIGITS`) significant digits in plain
/// notation (`0.0027689`, `121.92`, `123457`).
pub fn format_figure(v: f64) -> String {
    format_sig_plain(v, TEXT_DIGITS)
}

/// Significant digits of a number in a message ([`format_short`]).
pub const MESSAGE_DIGITS: usize = 4;

/// `v` for a message: 4 (`MESSAGE_DIGITS`) significant digits without trailing zeros
/// (`121.9`, `400`, `0.0125`, `1.235e-5`); from 1e5 to 1e15 the whole number (`121920`).
pub fn format_short(v: f64) -> String {
    if (1e5..1e15).contains(&v.abs()) {
        return format!("{v:.0}");
    }
    let s = format_sig(v, MESSAGE_DIGITS);
    let (mantissa, exponent) = match s.find('e') {
        Some(i) => s.split_at(i),
        None => (s.as_str(), ""),
    };
    let mantissa = if mantissa.contains('.') { mantissa.trim_end_matches('0').trim_end_matches('.') } else { mantissa };
    format!("{mantissa}{exponent}")
}

/// `n` with a comma every three digits: `3200000` -> `3,200,000`.
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_formats() {
        assert_eq!(format_sig(0.012345, 3), "0.0123");
        assert_eq!(format_sig(1234.5, 3), "1234"); // integer part kept whole, no decimals
        assert_eq!(format_sig(1.2345e-5, 3), "1.23e-5");
        assert_eq!(format_sig(0.0, 3), "0");
        assert_eq!(format_sig(0.99996, 3), "1.00");
        assert_eq!(format_sig(-0.0999, 2), "-0.10");
    }

    #[test]
    fn short_formats_drop_trailing_zeros() {
        assert_eq!(format_short(400.0), "400");
        assert_eq!(format_short(121.92), "121.9");
        assert_eq!(format_short(1.025), "1.025");
        assert_eq!(format_short(0.012500), "0.0125");
        assert_eq!(format_short(-1.5e-5), "-1.5e-5");
        assert_eq!(format_short(0.30000000000000004), "0.3");
        assert_eq!(format_short(0.0), "0");
        assert_eq!(format_short(121920.4), "121920");
    }

    #[test]
    fn plain_formats_keep_integer_digits_and_never_use_exponents() {
        assert_eq!(format_sig_plain(0.830241, 5), "0.83024");
        assert_eq!(format_sig_plain(6.25, 5), "6.2500");
        assert_eq!(format_sig_plain(8635.17, 5), "8635.2");
        assert_eq!(format_sig_plain(123456.7, 5), "123457");
        assert_eq!(format_sig_plain(0.99999996, 5), "1.0000");
        assert_eq!(format_sig_plain(-1.5e-4, 4), "-0.0001500");
        assert_eq!(format_sig_plain(1e-12, 4), "0");
        assert_eq!(format_sig_plain(-0.0, 4), "0");
        assert_eq!(format_sig_plain(0.0, 4), "0");
    }
}
