//! The one place that turns an `f64` into exact text for files (IGES, STEP, DXF, STL, OBJ,
//! glTF, CSV); `numfmt` rounds figures for people ([`crate::format_figure`]).
//!
//! The layout is documented on [`real`], where the library's users read it.

use std::io;

/// Longest string [`real`] can return.
pub const MAX_REAL_LEN: usize = 24;

/// Shortest round-trip text of `x` with a decimal point and an `E` exponent when needed.
///
/// Every real number a writer of this crate emits goes through this function, so all exports
/// agree on one representation: the *shortest* decimal string that parses back to the very
/// same `f64` (Rust's float formatting is shortest-round-trip, Ryu/Grisu style), laid out the
/// way IGES 5.3 (section 2.2.2.3, "Real numbers") and ISO 10303-21 readers expect:
///
/// * always a decimal point: `3.0`, never `3`;
/// * plain notation for `1e-5 <= |x| < 1e16`: `0.25`, `-12.5`, `0.00003`;
/// * otherwise a mantissa with a decimal point and an upper-case `E` exponent: `1.0E-7`,
///   `-2.5E20`;
/// * `-0.0` is written `0.0`; NaN and infinities are refused (no exchange format can hold them).
///
/// The longest possible output is 24 characters (`-2.2250738585072014E-308`), which IGES
/// writers rely on when they pack fields into 64-column records.
///
/// # Errors
/// [`io::ErrorKind::InvalidData`] if `x` is NaN or infinite.
pub fn real(x: f64) -> io::Result<String> {
    if !x.is_finite() {
        return Err(io::Error::new(io::ErrorKind::InvalidData, format!("cannot write the non-finite number {x}")));
    }
    if x == 0.0 {
        return Ok("0.0".to_string());
    }
    let a = x.abs();
    if (1e-5..1e16).contains(&a) {
        // `Display` never uses an exponent and prints the shortest round-trip digits.
        let mut s = format!("{x}");
        if !s.contains('.') {
            s.push_str(".0");
        }
        Ok(s)
    } else {
        // `UpperExp` prints the same shortest digits as `d[.ddd]E[-]e`.
        let s = format!("{x:E}");
        let (mantissa, exponent) = s.split_once('E').expect("UpperExp output always has an exponent");
        let point = if mantissa.contains('.') { "" } else { ".0" };
        Ok(format!("{mantissa}{point}E{exponent}"))
    }
}

/// Shortest round-trip text of `x` in plain decimal notation: Rust's `Display`, never an
/// exponent, no decimal point for an integer (`12`, `0.30000000000000004`, `1e-30` as
/// `0.000000000000000000000000000001`), `-0.0` as `0`.
///
/// # Errors
/// [`io::ErrorKind::InvalidData`] if `x` is NaN or infinite.
pub fn plain(x: f64) -> io::Result<String> {
    if !x.is_finite() {
        return Err(io::Error::new(io::ErrorKind::InvalidData, format!("cannot write the non-finite number {x}")));
    }
    Ok(if x == 0.0 { "0".to_string() } else { format!("{x}") })
}

/// How a text writer spells its numbers; both notations read back to the very same `f64`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Notation {
    /// [`real`]: always a decimal point, an `E` exponent outside `1e-5 <= |x| < 1e16`.
    #[default]
    Exchange,
    /// [`plain`]: never an exponent, integers without a decimal point.
    Plain,
}

impl Notation {
    /// `x` in this notation.
    ///
    /// # Errors
    /// [`io::ErrorKind::InvalidData`] if `x` is NaN or infinite.
    pub fn format(self, x: f64) -> io::Result<String> {
        match self {
            Notation::Exchange => real(x),
            Notation::Plain => plain(x),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn documented_examples() {
        let cases = [
            (1e-7, "1.0E-7"),
            (3.0, "3.0"),
            (-0.25, "-0.25"),
            (0.0, "0.0"),
            (-0.0, "0.0"),
            (3e-5, "0.00003"),
            (1e16, "1.0E16"),
            (-2.5e20, "-2.5E20"),
            (0.1, "0.1"),
            (std::f64::consts::FRAC_1_SQRT_2, "0.7071067811865476"),
        ];
        for (x, want) in cases {
            assert_eq!(real(x).expect("finite"), want, "formatting {x:e}");
        }
    }

    #[test]
    fn non_finite_is_refused() {
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(real(x).expect_err("non-finite").kind(), io::ErrorKind::InvalidData);
            assert_eq!(plain(x).expect_err("non-finite").kind(), io::ErrorKind::InvalidData);
        }
    }

    #[test]
    fn plain_notation_has_no_exponent() {
        let cases = [(12.0, "12"), (-0.0, "0"), (0.1 + 0.2, "0.30000000000000004"), (1e21, "1000000000000000000000")];
        for (x, want) in cases {
            assert_eq!(Notation::Plain.format(x).expect("finite"), want);
        }
        assert_eq!(Notation::Exchange.format(12.0).expect("finite"), "12.0");
    }

    /// Bit-exact round trip over a spread of bit patterns (a fixed LCG, so the test is
    /// deterministic), plus the extremes; every string has a decimal point and fits the
    /// documented maximum length.
    #[test]
    fn round_trips_bit_exactly() {
        let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut values =
            vec![f64::MIN_POSITIVE, -f64::MIN_POSITIVE, f64::MAX, f64::MIN, 5e-324, 1e-5, 1e16, 9.999999999999998e15];
        for _ in 0..20_000 {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let x = f64::from_bits(state);
            if x.is_finite() {
                values.push(x);
            }
            // Also ordinary magnitudes, where the plain notation is used.
            values.push(((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 1e4);
        }
        for x in values {
            let s = real(x).expect("finite");
            let back: f64 = s.parse().expect("parses");
            assert!(back == x || (x == 0.0 && back == 0.0), "{x:e} -> {s} -> {back:e}");
            assert!(back.to_bits() == x.to_bits() || x == 0.0, "sign or bits lost: {x:e} -> {s}");
            assert!(s.contains('.'), "no decimal point in {s}");
            assert!(!s.contains('e'), "lower-case exponent in {s}");
            assert!(s.len() <= MAX_REAL_LEN, "{s} is longer than {MAX_REAL_LEN}");
        }
    }
}
