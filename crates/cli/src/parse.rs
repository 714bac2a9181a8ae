//! Value parsers shared by the subcommands' flags.

use hull::{Fairing, FitMethod, Units};
use nurbs::fit::SkinParameterization;

/// `NU,NV` or `P,Q`: two non-negative integers, also as `NUxNV`, the way the summary prints a
/// count (so a count read there can be given back as it is).
pub(crate) fn parse_pair(s: &str) -> Result<(usize, usize), String> {
    let (a, b) = s
        .split_once(',')
        .or_else(|| s.split_once(['x', 'X']))
        .ok_or_else(|| format!("expected two integers like 8,12 (or 8x12), got `{s}`"))?;
    let p = |t: &str| t.trim().parse::<usize>().map_err(|_| format!("`{t}` is not a non-negative integer (in `{s}`)"));
    Ok((p(a)?, p(b)?))
}

/// One parameterization name for both directions, or `U,V`.
pub(crate) fn parse_param(s: &str) -> Result<SkinParameterization, String> {
    s.parse().map_err(|e| format!("{e}"))
}

/// `m`, `mm`, `ft` or `in`.
pub(crate) fn parse_units(s: &str) -> Result<Units, String> {
    s.parse().map_err(|e| format!("{e}"))
}

/// `auto` or a fairness weight `λ >= 0` (`0`: the plain least squares).
pub(crate) fn parse_fair(s: &str) -> Result<Fairing, String> {
    let t = s.trim();
    if t.eq_ignore_ascii_case("auto") {
        return Ok(Fairing::Auto { tolerance: None });
    }
    match t.parse::<f64>() {
        Ok(0.0) => Ok(Fairing::Off),
        Ok(l) if l > 0.0 && l.is_finite() => Ok(Fairing::Lambda(l)),
        _ => Err(format!("`{s}` is not a fairness weight (expected auto, 0, or a finite number > 0 such as 1e-3)")),
    }
}

/// The fit of an offsets input to commands that take a surface (`hydrostatics`, `export`):
/// `interp` or `approx`; an optimised method is refused with the way to it.
pub(crate) fn parse_skin_method(s: &str) -> Result<FitMethod, String> {
    match s.parse::<FitMethod>()? {
        m @ (FitMethod::Interp | FitMethod::Approx) => Ok(m),
        m => Err(format!(
            "{} optimises weights: fit with `hullskin fit --method {}` and pass its surface.json \
             (expected interp or approx)",
            m.name(),
            m.name()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::parse_pair;

    #[test]
    fn a_pair_reads_with_a_comma_or_as_the_summary_prints_it() {
        assert_eq!(parse_pair("8,12"), Ok((8, 12)));
        assert_eq!(parse_pair(" 8 , 12 "), Ok((8, 12)));
        assert_eq!(parse_pair("12x47"), Ok((12, 47)));
        assert_eq!(parse_pair("12X47"), Ok((12, 47)));
        let e = parse_pair("12;47").expect_err("no separator");
        assert!(e.contains("expected two integers like 8,12 (or 8x12), got `12;47`"), "{e}");
        let e = parse_pair("8x-1").expect_err("negative");
        assert!(e.contains("`-1` is not a non-negative integer (in `8x-1`)"), "{e}");
        assert!(parse_pair("8x12x3").is_err());
    }
}
