//! Skinning by approximation: a surface of `nu x nv` control points near the points, least
//! squares along and across the sections (The NURBS Book 9.4).

use super::across::fit_across;
use super::compatible::fit_along;
use super::compatible::least_score;
use super::sections::{classify, data_params, max_count, own_params, Section, UParams};
use super::{checked, AlongParameters, SkinOptions, SkinResult};
use crate::fit::knots::check_ctrl_count;
use crate::fit::{bounding_diagonal, common_parameters};
use crate::{NurbsError, NurbsSurface, Vec3};

/// Approximating skin: a surface with `nu x nv` control points, degrees `(p, q)`, fitted by
/// least squares first along each section, then across the sections (The NURBS Book 9.4.1
/// applied as in 9.4.3's two-stage surface fit).
///
/// Both stages try a few principled choices and keep the one that fits the data best, i.e. the
/// one with the least value of the least-squares objective itself (plus a small energy term
/// that rejects nearly singular fits):
///
/// - the knot placement in each direction: [`approximation_knots`](crate::fit::approximation_knots) (averages of resampled
///   parameters: wide end spans, well conditioned up to interpolation) or
///   [`centred_approximation_knots`](crate::fit::centred_approximation_knots) (The NURBS Book eq. 9.69, centred: the same amount of data
///   in every span);
/// - along the sections, when all non-degenerate sections have the same count: each section on
///   its own parameters, or all on their mean (eq. 9.18, as in global surface interpolation).
///
/// Why (measured on ship offset tables): each choice wins clearly on some tables and loses on
/// others (averaged parameters: a fifth of the RMS error of own ones on the Wigley table, whose
/// sections are alike, 30 % more on the R/V Gunnerus table; centred knots: less than half the
/// error of resampled ones on the Wigley table, whose sections crowd at the ends, 1.7 times
/// more on the Series 60 table), and on the nine tables of `tools/peers` (18 fits) the smaller residual at the
/// points went with the smaller RMS error between them in 17 of 18 choices of knots (the
/// other within 0.1 %) and 18 of 18 choices of parameters. The residual is the quantity least
/// squares minimizes, so the selection adds no criterion of its own; with universal
/// parameters the knots are uniform and only the parameters are chosen.
///
/// 1. Along: for each candidate (parameters x placement), the common `u` knot vector is the
///    mean of the placement's knot vectors of the sections with at least `nu` points (for
///    averaged parameters simply that of the mean), or uniform for
///    [`Parameterization::Universal`](crate::fit::Parameterization::Universal).
///    - With averaged parameters every non-degenerate section is fitted by least squares at
///      them, its ends interpolated (one factorization).
///    - With own parameters, a section with more than `nu` points is fitted by least squares
///      on those knots, its ends interpolated, at the blend of parameters `(1 - w) t + w m` (as
///      in [`skin_interpolate`](crate::fit::skin_interpolate) step 2; `m` spreads the points over the Greville abscissae, now
///      several per abscissa, and still satisfies Schoenberg-Whitney) whose fit has the least
///      `sum_k |C(t_k) - Q_k|^2 + λ E(C)` with `λ = 1e-3 / max_i G_ii`. With own
///      parameters only, a section with slightly more points than `nu` gets nearly singular
///      normal equations on knots placed for other sections, and its curve swings between
///      the points (R/V Gunnerus: 31 m on 5 to 12 m sections); the blend with the least
///      penalized residual keeps it within 0.16 m. A candidate that violates the
///      Schoenberg-Whitney condition is skipped; if all do, the error names the section.
///      A section with at most `nu` points is interpolated by its least-bending-energy curve on
///      those knots, with parameters chosen as in [`skin_interpolate`](crate::fit::skin_interpolate) step 2: approximation
///      must not be worse than interpolation where data are scarce. (With exactly `nu` points
///      that is plain interpolation, at the blend of parameters that bends least.)
///    - Degenerate sections get `nu` copies of their point.
///
///    The placement with the least `sum over sections of (residual + λ E)` is kept (for a
///    section interpolated exactly, `λ E`).
/// 2. Across: the columns of the `K` curves' control points are fitted with `nv` control
///    points; v-parameters of `param.v` are the mean over the columns (eq. 10.8); one
///    factorization per placement for all columns, the first and last sections interpolated,
///    and again the placement with the least `sum over columns of (residual + λ E)` is kept.
/// 3. Of the two parameter choices of step 1 (equal counts only), the surface with the least
///    `sum |S(u_k, v_k) - Q_k|^2` over all offsets is returned (residuals within round-off,
///    as at the interpolation counts, tie, and the tie goes to the least penalized residual
///    of step 1: the less bending along the sections), or only the one
///    [`SkinOptions::along`] imposes is fitted ([`SkinResult::along`] says which it is).
///
/// Degrees: `p = min(degree_u, N - 1)` with `N` the largest non-degenerate section (shorter
/// sections do not lower it), `q = min(degree_v, K - 1)`.
///
/// # Errors
/// As [`skin_interpolate`](crate::fit::skin_interpolate), and [`NurbsError::BadControlPointCount`] unless `p + 1 <= nu <= N`
/// and `q + 1 <= nv <= K`.
pub fn skin_approximate(
    sections: &[Vec<Vec3>],
    nu: usize,
    nv: usize,
    opts: &SkinOptions,
) -> Result<SkinResult, NurbsError> {
    let secs = classify(sections, opts)?;
    let k_count = secs.len();
    let n_max = max_count(&secs);
    let p = opts.degree_u.min(n_max - 1);
    let q = opts.degree_v.min(k_count - 1);
    check_ctrl_count(nu, n_max, p, "skinning along the sections (largest section)")?;
    check_ctrl_count(nv, k_count, q, "skinning across the sections")?;
    let own = own_params(&secs, opts.param.u, p)?;
    let equal = secs.iter().all(|s| matches!(s, Section::Point(..)) || s.len() == n_max);
    let floor = residual_floor(sections);
    let fits = along_candidates(own, equal, opts.along)?.into_iter().map(|(u_of, choice)| {
        let shared = choice == AlongParameters::Mean;
        let (bending, along) = fit_along(&secs, u_of, nu, p, opts.param.u, shared, opts.smoothing)?;
        let across = fit_across(&along.rows, nv, q, opts.param.v, opts.smoothing)?;
        let surface = NurbsSurface::from_parts_unchecked(along.knots, across.knots, across.net);
        let params = data_params(&secs, &across.v, along.u_of);
        let score = surface_residual(&surface, &secs, &params);
        // Residuals within round-off tie, and the tie goes to the less bending along the
        // sections (step 1's penalized residual), not to the rounding.
        Ok(((score.max(floor), bending), SkinResult { surface, params, along: choice }))
    });
    let (_, r) = least_score(fits, "the own-parameter candidate")?;
    checked(r)
}

/// The least `sum |S(u_k, v_k) - Q_k|^2` step 3 tells apart: `(1e-12 size)^2` per point, `size`
/// the diagonal of the points' bounding box. Below it a residual is round-off: at the
/// interpolation counts every candidate passes through the points, and which residual came out
/// smaller depended on the order of summation in the band Cholesky factor (the Series 60 Cb 0.65
/// parent at 8x25: 1.5e-25 and 1.8e-25 swapped places, and the net, which the choice decides
/// between the points, moved by 1.7 m). Far above that rounding and far below any
/// approximation's residual (1e-12 of a 122 m hull is 0.1 nm).
fn residual_floor(sections: &[Vec<Vec3>]) -> f64 {
    let n = sections.iter().map(Vec::len).sum::<usize>();
    n as f64 * (1e-12 * bounding_diagonal(sections.iter().flatten())).powi(2)
}

/// The parameter candidates along the sections, each with the choice it is, from each
/// section's own parameters `own`: own ones, and where the sections have `equal` counts all on
/// their mean (eq. 9.18); only the one `along` imposes, where it can be had.
pub(super) fn along_candidates(
    own: UParams,
    equal: bool,
    along: AlongParameters,
) -> Result<Vec<(UParams, AlongParameters)>, NurbsError> {
    if !equal || along == AlongParameters::Own {
        return Ok(vec![(own, AlongParameters::Own)]);
    }
    let mean = common_parameters(&own.iter().flatten().cloned().collect::<Vec<_>>())?;
    let shared = (own.iter().map(|t| t.as_ref().map(|_| mean.clone())).collect(), AlongParameters::Mean);
    Ok(match along {
        AlongParameters::Mean => vec![shared],
        _ => vec![(own, AlongParameters::Own), shared],
    })
}

/// `sum |S(u, v) - Q|^2` over every input point at its parameters.
pub(super) fn surface_residual(surface: &NurbsSurface, secs: &[Section], params: &[Vec<(f64, f64)>]) -> f64 {
    secs.iter()
        .zip(params)
        .map(|(s, par)| {
            par.iter()
                .enumerate()
                .map(|(i, &(u, v))| {
                    let q = match s {
                        Section::Regular(pts) => pts[i],
                        Section::Point(c, _) => *c,
                    };
                    surface.point(u, v).distance(q).powi(2)
                })
                .sum::<f64>()
        })
        .sum()
}
