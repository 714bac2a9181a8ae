//! Skins with knuckle lines: each section cut at its corners, the pieces fitted on their own
//! and joined with knots of multiplicity `p` at common breakpoints (a `C^0` line along `u`).

use super::across::{cross_params, fit_across, interpolate_across};
use super::approximate::{along_candidates, skin_approximate};
use super::compatible::{fit_along, least_score, share_control_points, AlongFit};
use super::interpolate::{interpolate_along, skin_interpolate};
use super::sections::{classify, data_params, max_count, own_params, Section, UParams};
use super::{checked, AlongParameters, SkinOptions, SkinResult};
use crate::fit::continuity::join_knot_vectors;
use crate::fit::knots::check_ctrl_count;
use crate::fit::Parameterization;
use crate::{NurbsError, NurbsSurface, Vec3};

/// The sections cut at their knuckles: `cuts[k]` are section `k`'s knuckle indices (strictly
/// increasing, interior, the same count `c` for every section with extent; ignored for a
/// degenerate one).
pub(super) struct KnucklePlan {
    pub(super) cuts: Vec<Vec<usize>>,
    /// The number of knuckles `c` of every section with extent.
    pub(super) count: usize,
}

impl KnucklePlan {
    /// Check `knuckles` against the sections.
    ///
    /// # Errors
    /// [`NurbsError::Incompatible`] naming the section whose knuckle list is not one entry per
    /// section, not strictly increasing, not interior, or of another count than the first
    /// section with extent.
    pub(super) fn new(secs: &[Section], knuckles: &[Vec<usize>]) -> Result<Self, NurbsError> {
        if knuckles.len() != secs.len() {
            return Err(NurbsError::Incompatible {
                what: format!("knuckles: {} lists for {} sections (one list per section)", knuckles.len(), secs.len()),
            });
        }
        let mut count = None;
        let mut cuts = Vec::with_capacity(secs.len());
        for (k, (s, cut)) in secs.iter().zip(knuckles).enumerate() {
            let Section::Regular(pts) = s else {
                cuts.push(Vec::new());
                continue;
            };
            let interior = cut.iter().all(|&i| i >= 1 && i + 1 < pts.len());
            if !interior || cut.windows(2).any(|w| w[1] <= w[0]) {
                return Err(NurbsError::Incompatible {
                    what: format!(
                        "section {k}: knuckle indices {cut:?} must strictly increase between 1 and {} \
                         (interior points of its {} points)",
                        pts.len().saturating_sub(2),
                        pts.len()
                    ),
                });
            }
            match count {
                None => count = Some(cut.len()),
                Some(c) if c != cut.len() => {
                    return Err(NurbsError::Incompatible {
                        what: format!(
                            "section {k}: {} knuckles where the sections before have {c} \
                             (a knuckle line must run through every section with extent)",
                            cut.len()
                        ),
                    })
                }
                Some(_) => {}
            }
            cuts.push(cut.clone());
        }
        Ok(KnucklePlan { cuts, count: count.unwrap_or(0) })
    }

    /// Piece `j` (`0..=count`) of every section: the points from knuckle `j - 1` (or the
    /// first point) to knuckle `j` (or the last), both included; degenerate sections whole.
    pub(super) fn piece<'a>(&self, secs: &[Section<'a>], j: usize) -> Vec<Section<'a>> {
        secs.iter()
            .zip(&self.cuts)
            .map(|(s, cut)| match s {
                Section::Regular(pts) => {
                    let a = if j == 0 { 0 } else { cut[j - 1] };
                    let b = if j == self.count { pts.len() - 1 } else { cut[j] };
                    Section::Regular(&pts[a..=b])
                }
                Section::Point(c, n) => Section::Point(*c, *n),
            })
            .collect()
    }

    /// The breakpoints `0 = a_0 < a_1 < ... < a_c < a_{c+1} = 1`: `a_j` is the mean over the
    /// sections with extent of the whole section's own parameter (of `kind`) at its knuckle
    /// `j - 1`, as The NURBS Book eq. 9.18 averages the parameters of a column of points.
    pub(super) fn breaks(&self, secs: &[Section], kind: Parameterization, p: usize) -> Result<Vec<f64>, NurbsError> {
        let own = own_params(secs, kind, p)?;
        let mut sum = vec![0.0; self.count];
        let mut used = 0usize;
        for (t, cut) in own.iter().zip(&self.cuts) {
            if let Some(t) = t {
                used += 1;
                sum.iter_mut().zip(cut).for_each(|(s, &i)| *s += t[i]);
            }
        }
        let mut b = Vec::with_capacity(self.count + 2);
        b.push(0.0);
        b.extend(sum.iter().map(|s| s / used.max(1) as f64));
        b.push(1.0);
        Ok(b)
    }

    /// Join the pieces' fits (each on `[0, 1]`) into one along `u` ([`join_knot_vectors`]):
    /// piece `j` on `[a_j, a_{j+1}]`, the shared control point at a knuckle set to the
    /// section's knuckle point (both pieces interpolate it at their ends), the parameters
    /// mapped the same way and the knuckle's given once, exactly `a_j`.
    pub(super) fn join(&self, secs: &[Section], breaks: &[f64], pieces: Vec<AlongFit>) -> Result<AlongFit, NurbsError> {
        let knots = join_knot_vectors(&pieces.iter().map(|f| f.knots.clone()).collect::<Vec<_>>(), breaks)?;
        let mut rows = Vec::with_capacity(secs.len());
        let mut u_of: UParams = Vec::with_capacity(secs.len());
        for (k, (s, cut)) in secs.iter().zip(&self.cuts).enumerate() {
            let mut row: Vec<Vec3> = Vec::with_capacity(knots.num_basis());
            let mut t: Vec<f64> = Vec::new();
            for (j, piece) in pieces.iter().enumerate() {
                let (a, b) = (breaks[j], breaks[j + 1]);
                let skip = usize::from(j > 0);
                row.extend_from_slice(&piece.rows[k][skip..]);
                if let Some(pt) = &piece.u_of[k] {
                    t.extend(pt[skip..].iter().map(|&x| if x >= 1.0 { b } else { a + x * (b - a) }));
                }
                if let (Section::Regular(pts), Some(&i)) = (s, cut.get(j)) {
                    // The knuckle: the last control point of this piece (the first of the next).
                    let last = row.len() - 1;
                    row[last] = pts[i];
                }
            }
            rows.push(row);
            u_of.push(match s {
                Section::Regular(_) => Some(t),
                Section::Point(..) => None,
            });
        }
        Ok(AlongFit { knots, rows, u_of })
    }
}

/// The degree along the sections and the knuckle plan, or `None` when no section has a
/// knuckle (the plain skin then applies).
pub(super) fn knuckle_setup(
    secs: &[Section],
    knuckles: &[Vec<usize>],
    opts: &SkinOptions,
) -> Result<Option<(KnucklePlan, usize, Vec<f64>)>, NurbsError> {
    let plan = KnucklePlan::new(secs, knuckles)?;
    if plan.count == 0 {
        return Ok(None);
    }
    let p = opts.degree_u.min(max_count(secs) - 1);
    let breaks = plan.breaks(secs, opts.param.u, p)?;
    Ok(Some((plan, p, breaks)))
}

/// [`skin_interpolate`] keeping knuckles (chines): `knuckles[k]` lists the indices of the
/// knuckle points of section `k` (strictly increasing, interior; the same count `c` for every
/// section with extent, ignored for a degenerate one; see
/// [`crate::fit::find_knuckle_lines`] and [`crate::fit::knuckle_indices`]).
///
/// Each section is cut at its knuckles into `c + 1` pieces; piece `j` of every section is
/// fitted along `u` as a section of its own (as [`skin_interpolate`] steps 1-2, with the
/// whole surface's degree `p = min(degree_u, N - 1)`; a piece with fewer than `p + 1` points in
/// every section becomes one Bezier segment through its points, of least bending energy:
/// straight between two points), its parameters mapped to `[a_j, a_{j+1}]`, where `a_j` is the
/// mean over the sections of the whole section's parameter at knuckle `j - 1`; the pieces are
/// joined with a knot of multiplicity `p` at each `a_j` ([`crate::fit::join_knot_vectors`])
/// and the knuckle point as the shared control point. Across the sections the columns are
/// interpolated as in [`skin_interpolate`]. The surface is then `C^0` along `u = a_j`, an
/// iso-curve through every section's knuckle point, and as smooth as the plain skin
/// elsewhere; it passes through every offset. With no knuckle (`c = 0`) it is
/// [`skin_interpolate`].
///
/// # Errors
/// As [`skin_interpolate`], and [`NurbsError::Incompatible`] for a knuckle list that does not
/// fit its section (one list per section, interior indices strictly increasing, the same count
/// in every section with extent).
pub fn skin_interpolate_with_knuckles(
    sections: &[Vec<Vec3>],
    knuckles: &[Vec<usize>],
    opts: &SkinOptions,
) -> Result<SkinResult, NurbsError> {
    let secs = classify(sections, opts)?;
    let Some((plan, p, breaks)) = knuckle_setup(&secs, knuckles, opts)? else {
        return skin_interpolate(sections, opts);
    };
    let q = opts.degree_v.min(secs.len() - 1);
    let pieces = (0..=plan.count)
        .map(|j| interpolate_along(&plan.piece(&secs, j), p, opts.param.u))
        .collect::<Result<Vec<_>, _>>()?;
    let along = plan.join(&secs, &breaks, pieces)?;
    let n = along.knots.num_basis();
    let v = cross_params(n, secs.len(), |i, k| along.rows[k][i], opts.param.v, q)?;
    let (kv, net) = interpolate_across(&along.rows, &v, opts.param.v, q)?;
    let surface = NurbsSurface::from_parts_unchecked(along.knots, kv, net);
    checked(SkinResult { params: data_params(&secs, &v, along.u_of), surface, along: AlongParameters::LeastResidual })
}

/// [`skin_approximate`] keeping knuckles (chines), `knuckles` as in
/// [`skin_interpolate_with_knuckles`]; `nu` counts the control points of the whole surface
/// along `u`, knuckle points included.
///
/// The sections are cut into pieces as for interpolation. Piece `j`, whose largest section
/// has `N_j` points, gets `nu_j` control points with `sum_j nu_j - c = nu` and
/// `p + 1 <= nu_j <= max(N_j, p + 1)`, as near to `N_j (nu + c) / sum_j N_j` as those bounds
/// allow (the control points follow the data; ties and rounding resolved in piece order).
/// A piece with `nu_j = max(N_j, p + 1)` is interpolated (as in
/// [`skin_interpolate_with_knuckles`]); any other is fitted by least squares as in
/// [`skin_approximate`] step 1 (its ends, the knuckle points, interpolated), on own and, with
/// equal counts, on averaged parameters, keeping the fit with the least penalized residual
/// (or only the one [`SkinOptions::along`] imposes).
/// The pieces are joined as for interpolation, and the columns fitted across the sections as
/// in [`skin_approximate`] step 2 with `nv` control points. With no knuckle it is
/// [`skin_approximate`].
///
/// # Errors
/// As [`skin_approximate`] and [`skin_interpolate_with_knuckles`];
/// [`NurbsError::BadControlPointCount`] when `nu` cannot be shared out under those bounds (it
/// names the range).
pub fn skin_approximate_with_knuckles(
    sections: &[Vec<Vec3>],
    knuckles: &[Vec<usize>],
    nu: usize,
    nv: usize,
    opts: &SkinOptions,
) -> Result<SkinResult, NurbsError> {
    let secs = classify(sections, opts)?;
    let Some((plan, p, breaks)) = knuckle_setup(&secs, knuckles, opts)? else {
        return skin_approximate(sections, nu, nv, opts);
    };
    let q = opts.degree_v.min(secs.len() - 1);
    check_ctrl_count(nv, secs.len(), q, "skinning across the sections")?;
    let piece_secs: Vec<Vec<Section>> = (0..=plan.count).map(|j| plan.piece(&secs, j)).collect();
    let counts: Vec<usize> = piece_secs.iter().map(|s| max_count(s)).collect();
    let shares = share_control_points(nu, &counts, p)?;
    let mut pieces = Vec::with_capacity(piece_secs.len());
    let mut chosen = Vec::with_capacity(piece_secs.len());
    for (piece, (&n_j, &nu_j)) in piece_secs.iter().zip(counts.iter().zip(&shares)) {
        if nu_j == n_j.max(p + 1) {
            pieces.push(interpolate_along(piece, p, opts.param.u)?);
            continue;
        }
        let own = own_params(piece, opts.param.u, p)?;
        let equal = piece.iter().all(|s| matches!(s, Section::Point(..)) || s.len() == n_j);
        let fits = along_candidates(own, equal, opts.along)?.into_iter().map(|(u_of, choice)| {
            let shared = choice == AlongParameters::Mean;
            fit_along(piece, u_of, nu_j, p, opts.param.u, shared, opts.smoothing).map(|(s, f)| (s, (f, choice)))
        });
        let (_, (fit, choice)) = least_score(fits, "the own-parameter candidate")?;
        chosen.push(choice);
        pieces.push(fit);
    }
    // One choice for the whole skin, or none where the pieces (fitted by least squares) differ.
    let along = match chosen.split_first() {
        Some((&first, rest)) if rest.iter().all(|&c| c == first) => first,
        _ => AlongParameters::LeastResidual,
    };
    let joined = plan.join(&secs, &breaks, pieces)?;
    let across = fit_across(&joined.rows, nv, q, opts.param.v, opts.smoothing)?;
    let surface = NurbsSurface::from_parts_unchecked(joined.knots, across.knots, across.net);
    checked(SkinResult { params: data_params(&secs, &across.v, joined.u_of), surface, along })
}
