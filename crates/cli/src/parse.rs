//! Value parsers shared by the subcommands' flags.

use hull::Units;
use nurbs::fit::SkinParameterization;

/// `NU,NV` or `P,Q`: two non-negative integers.
pub(crate) fn parse_pair(s: &str) -> Result<(usize, usize), String> {
    let (a, b) = s.split_once(',').ok_or_else(|| format!("expected two integers like 8,12, got `{s}`"))?;
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
