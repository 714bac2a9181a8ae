//! Skinning by interpolation: the surface through every point (The NURBS Book 10.3).

use super::across::{cross_params, interpolate_across};
use super::compatible::{AlongFit, SectionFits};
use super::sections::{classify, data_params, in_section, max_count, own_params, Section, UParams};
use super::{checked, AlongParameters, SkinOptions, SkinResult};
use crate::fit::interp::InterpolationSolver;
use crate::fit::knots::knots_for_interpolation;
use crate::fit::param::parameterize_labelled;
use crate::fit::{common_parameters, Parameterization};
use crate::{KnotVector, NurbsError, NurbsSurface, Vec3};

/// Interpolating skin (The NURBS Book 9.2.5 A9.4 and 10.3): a surface through every input point,
/// with one pole per offset of the largest section along `u` and one per section along `v`.
///
/// - All non-degenerate sections have the same count `n` (degenerate ones may have any
///   count): global surface interpolation, A9.4. One u-parameter vector, the mean of the
///   sections' own parameters (eq. 9.18) of kind `param.u`, the optimal knots of
///   [`crate::fit::optimal_knots`] (or uniform for [`Parameterization::Universal`]), degree
///   `p = min(degree_u, n - 1)`; each section is interpolated with that one factorization. The
///   net is `n x K`.
/// - Otherwise, with `N = max_k n_k`: one knot vector along `u` with `N` basis functions and
///   degree `p = min(degree_u, N - 1)` for all sections, so the net is `N x K`.
///   1. The *full* sections (`n_k = N`) are treated exactly as in A9.4: the common parameters
///      `ū` are the mean of their own parameters, the knots are those of `ū` (optimal, or
///      uniform for [`Parameterization::Universal`]), and each full section is interpolated at
///      `ū` with one factorization, nonsingular by construction (Schoenberg-Whitney).
///   2. A shorter section is interpolated by the curve of least bending energy
///      `∫ |C''(t)|^2 dt` on the common knots ([`FairInterpolationSolver`](crate::fit::FairInterpolationSolver)): the `N - n_k`
///      degrees of freedom the interpolation conditions leave are spent on fairness, so a
///      straight or circular section stays straight or round between its points. Its
///      parameters span `[0, 1]`: a partial section (one that stops lower or starts higher
///      than the others) is stretched over the whole `u` range, so the `u = 0`
///      and `u = 1` edges follow the first and last points of every section, as in the
///      classical skin. They are chosen among the blends `(1 - w) t + w m`,
///      `w ∈ {0, 1/4, 1/2, 3/4, 1}`, of the section's own parameters `t` (of the chosen kind)
///      and the Greville spread `m` of the knots (`n_k` points placed over the Greville
///      abscissae `ξ_i = (u_{i+1} + ... + u_{i+p}) / p` in proportion to their index, where
///      every point has a basis function of its own), as the one whose fair curve has the
///      least energy. Why: own parameters alone follow the section's spacing but may crowd
///      points between the common knots; when `n_k` is close to `N` the curve is then nearly
///      a plain interpolant on ill-fitting knots and overshoots (on R/V Gunnerus, 15-point
///      sections on 16 poles bulge by 1 m, 11% of the section's length), while `m` alone
///      ignores the spacing. The least-energy blend is never worse in energy than either, and
///      on the Gunnerus table and on sections made by dropping random points from its
///      16-point sections it kept the bulge beyond the section's own interpolant below 0.5% of
///      the section length, where own parameters reach 11% to 50%. [`SkinResult::params`]
///      are the parameters used.
///   3. With equal counts every step reduces to the first case, so the two agree.
///
/// The energy criterion for the parameters is that of "best parametric interpolation": the
/// parameters on a fixed interval for which the interpolating spline has the least
/// `∫ |C''|^2` (Scherer 1997, "Uniqueness of best parametric interpolation by cubic spline
/// curves", Constructive Approximation 13; Kozera and Noakes, "Leap-Frog" optimization of
/// interpolation knots). Here it only picks among five blends, for five small factorizations
/// per short section.
///
/// Across the sections: the columns of the sections' control points `R_{k,i}` are interpolated
/// with degree `q = min(degree_v, K - 1)` at v-parameters of kind `param.v` (the mean over the
/// columns of `R`, eq. 10.8) on their knots (optimal, or uniform for universal), one
/// factorization for all columns. Why the control points and not the data (A9.4 takes the
/// data columns): the control-point columns are what is interpolated, their spacing is the
/// surface's; on the nine tables of `tools/peers/results.md` this lowered the error between
/// the points by 1 % in the geometric mean, by 18 % (max) on R/V Gunnerus, whose sections
/// differ most in shape, and changed no other table by more than 1 %.
///
/// # Errors
/// [`NurbsError::BadDegree`]; [`NurbsError::TooFewPoints`] for fewer than 2 sections, an empty
/// section, or only degenerate sections; [`NurbsError::NonFinitePoint`] (index counted through
/// all sections in order); [`NurbsError::CoincidentPoints`] for consecutive equal points within
/// a section (the message names it) or two coincident sections; [`NurbsError::SingularSystem`]
/// (naming the section when its fair interpolation fails even after reparameterization).
///
/// ```
/// use nurbs::fit::{skin_interpolate, SkinOptions};
/// use nurbs::Vec3;
/// // Four sections of five points on a paraboloid: the skin passes through every point.
/// let sections: Vec<Vec<Vec3>> = (0..4)
///     .map(|k| (0..5).map(|i| (k as f64, i as f64 / 4.0)).map(|(x, y)| Vec3::new(x, y, x * x + y * y)).collect())
///     .collect();
/// let skin = skin_interpolate(&sections, &SkinOptions::default())?;
/// for (sec, params) in sections.iter().zip(&skin.params) {
///     for (q, &(u, v)) in sec.iter().zip(params) {
///         assert!(skin.surface.point(u, v).distance(*q) < 1e-12);
///     }
/// }
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn skin_interpolate(sections: &[Vec<Vec3>], opts: &SkinOptions) -> Result<SkinResult, NurbsError> {
    let secs = classify(sections, opts)?;
    let q = opts.degree_v.min(secs.len() - 1);
    let n = max_count(&secs);
    if secs.iter().all(|s| matches!(s, Section::Point(..)) || s.len() == n) {
        interpolate_equal(&secs, n, q, opts)
    } else {
        interpolate_ragged(&secs, q, opts)
    }
    .and_then(|(surface, v, u_of)| {
        checked(SkinResult { params: data_params(&secs, &v, u_of), surface, along: AlongParameters::LeastResidual })
    })
}

pub(super) fn interpolate_equal(
    secs: &[Section],
    n: usize,
    q: usize,
    opts: &SkinOptions,
) -> Result<(NurbsSurface, Vec<f64>, UParams), NurbsError> {
    let kind = opts.param.u;
    let p = opts.degree_u.min(n - 1);
    let mut own = Vec::new();
    for (k, s) in secs.iter().enumerate() {
        if let Section::Regular(pts) = s {
            own.push(parameterize_labelled(pts, kind, p, "points").map_err(|e| in_section(e, k))?);
        }
    }
    let u = common_parameters(&own)?;
    let ku = knots_for_interpolation(&u, p, kind)?;
    let solver = InterpolationSolver::new(&u, &ku)?;
    let rows: Vec<Vec<Vec3>> = secs
        .iter()
        .enumerate()
        .map(|(k, s)| match s {
            Section::Regular(pts) => solver.control_points(pts).map_err(|e| in_section(e, k)),
            Section::Point(c, _) => Ok(vec![*c; n]),
        })
        .collect::<Result<_, _>>()?;
    let v = cross_params(n, secs.len(), |i, k| rows[k][i], opts.param.v, q)?;
    let (kv, net) = interpolate_across(&rows, &v, opts.param.v, q)?;
    let u_of = secs.iter().map(|s| (s.len() == n || matches!(s, Section::Regular(_))).then(|| u.clone())).collect();
    Ok((NurbsSurface::from_parts_unchecked(ku, kv, net), v, u_of))
}

/// The unequal-count interpolating skin of [`skin_interpolate`] (steps 1-3). It is correct for
/// equal counts too, and then gives the surface of [`interpolate_equal`].
pub(super) fn interpolate_ragged(
    secs: &[Section],
    q: usize,
    opts: &SkinOptions,
) -> Result<(NurbsSurface, Vec<f64>, UParams), NurbsError> {
    let n = max_count(secs);
    let p = opts.degree_u.min(n - 1);
    let along = interpolate_along(secs, p, opts.param.u)?;
    let v = cross_params(n, secs.len(), |i, k| along.rows[k][i], opts.param.v, q)?;
    let (kv, net) = interpolate_across(&along.rows, &v, opts.param.v, q)?;
    Ok((NurbsSurface::from_parts_unchecked(along.knots, kv, net), v, along.u_of))
}

/// Steps 1-2 of [`skin_interpolate`] along the sections with degree `p`: one knot vector with
/// `N = max(max_k n_k, p + 1)` basis functions, the full sections (`n_k = N`) interpolated at
/// their mean parameters, the others by their least-energy curves. When no section is full
/// (fewer than `p + 1` points in every section: a short piece between knuckles) the knots are
/// those of one Bezier segment, and every section is interpolated by its least-energy curve
/// (a straight line through two points).
pub(super) fn interpolate_along(secs: &[Section], p: usize, kind: Parameterization) -> Result<AlongFit, NurbsError> {
    let n = max_count(secs).max(p + 1);
    let own = own_params(secs, kind, p)?;
    let full: Vec<Vec<f64>> = own.iter().flatten().filter(|t| t.len() == n).cloned().collect();
    let (ku, solver, u) = if full.is_empty() {
        (KnotVector::uniform(p, n)?, None, Vec::new())
    } else {
        let u = common_parameters(&full)?;
        let ku = knots_for_interpolation(&u, p, kind)?;
        let solver = InterpolationSolver::new(&u, &ku)?;
        (ku, Some(solver), u)
    };
    let mut fits = SectionFits::new(&ku);
    let mut rows: Vec<Vec<Vec3>> = Vec::with_capacity(secs.len());
    let mut u_of: UParams = Vec::with_capacity(secs.len());
    for (k, (s, t)) in secs.iter().zip(own).enumerate() {
        match (s, t, &solver) {
            (Section::Regular(pts), _, Some(solver)) if pts.len() == n => {
                rows.push(solver.control_points(pts).map_err(|e| in_section(e, k))?);
                u_of.push(Some(u.clone()));
            }
            (Section::Regular(pts), Some(t), _) => {
                let (_, cp, used) = fits.interpolate(pts, t, k)?;
                rows.push(cp);
                u_of.push(Some(used));
            }
            (Section::Point(c, count), _, _) => {
                rows.push(vec![*c; n]);
                u_of.push((*count == n && !u.is_empty()).then(|| u.clone()));
            }
            (Section::Regular(_), None, _) => unreachable!("own_params gives every regular section parameters"),
        }
    }
    drop(fits);
    Ok(AlongFit { knots: ku, rows, u_of })
}
