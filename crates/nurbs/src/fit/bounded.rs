//! A surface refitted with its control net within a box of half-spaces, so that the whole
//! surface, a convex combination of its control points, stays within them ([`bounded_refit`]).

use crate::basis::{basis_funs, BasisRow};
use crate::linalg::BandedCholesky;
use crate::{NurbsError, NurbsSurface, Vec3};

/// A box for the control points of a surface: `lo[c] <= P[c] <= hi[c]` for `c` = x, y, z. An
/// infinite bound is no bound. By the convex-combination property (The NURBS Book P3.4 and P4.4:
/// with positive weights every point of the surface is a convex combination of its control points),
/// a net within the box keeps the whole surface within it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControlBox {
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

impl Default for ControlBox {
    /// No bound at all.
    fn default() -> Self {
        ControlBox { lo: [f64::NEG_INFINITY; 3], hi: [f64::INFINITY; 3] }
    }
}

impl ControlBox {
    /// Whether no coordinate is bounded.
    pub fn is_empty(&self) -> bool {
        self.lo.iter().chain(&self.hi).all(|b| b.is_infinite())
    }

    /// Whether `p` lies within the box (bounds included).
    pub fn contains(&self, p: Vec3) -> bool {
        let a = p.to_array();
        (0..3).all(|c| a[c] >= self.lo[c] && a[c] <= self.hi[c])
    }

    /// The bound of coordinate `c` that `x` lies past, if any.
    fn crossed(&self, c: usize, x: f64) -> Option<f64> {
        if x < self.lo[c] {
            Some(self.lo[c])
        } else if x > self.hi[c] {
            Some(self.hi[c])
        } else {
            None
        }
    }
}

/// What [`bounded_refit`] did: the control-point coordinates it held on a bound, by coordinate
/// x, y, z (0 for a coordinate the net did not cross).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BoundedRefit {
    pub held: [usize; 3],
}

impl BoundedRefit {
    /// Coordinates held on a bound in all.
    pub fn total(&self) -> usize {
        self.held.iter().sum()
    }
}

/// Relative weight `λ` of the pull towards the starting control points in [`bounded_refit`]:
/// `μ = λ max_i (A^T A)_ii`. Small, so that the data decide wherever they reach (the refit's
/// residual stays that of least squares), but enough to keep control points the data hardly
/// reach (the row of a pointed end, the ends of a short section) where the skin put them.
pub const BOUNDED_REFIT_PULL: f64 = 1e-3;

/// Keep a surface within a box ([`ControlBox`]), by the convex-combination property (The NURBS Book
/// P3.4 and P4.4: with positive weights `S(u, v)` is a convex combination of its control
/// points): once every control point is within the box, so is every point of the surface. A
/// least-squares skin rings past the plane of a straight run of its data where the run meets
/// an arc (measured on ship offset tables: 0.14 m below such a plane on a 116 m ship, 36 mm
/// beyond one on the Series 60 Cb 0.80 parent); it crosses a plane of symmetry where a section
/// leaves it steeply.
///
/// Each coordinate `c` the net crosses is refitted on the surface's own knots, the points
/// `Q_k` at their parameters `(u_k, v_k)`:
///
/// `min sum_k (A_k x - Q_k,c)^2 + μ |x - x_0|^2`,  `A_ki = R_ij(u_k, v_k)`,
///
/// `R_ij = N_{i,p} N_{j,q} w_ij / sum N N w` the rational basis of the surface's weights, which
/// are kept (`N_{i,p}(u_k) N_{j,q}(v_k)` for a non-rational surface), with `x_0` the surface's control points and `μ = BOUNDED_REFIT_PULL max_i (A^T A)_ii`,
/// subject to `lo_c <= x_i <= hi_c`, by an active set (Nocedal and Wright 16.5): each round
/// holds on its bound every coordinate the last solve put across and releases the held ones
/// the objective pulls inwards (a multiplier of the wrong sign), then solves for the free
/// ones, until nothing changes or after 60 rounds; whatever is still across then is put on
/// its bound, so the box holds in every case. A collapsed boundary row or column of the net
/// (a pointed end) stays where it is. Coordinates the net does not cross are left as
/// they are. The normal equations are banded (half-bandwidth `min(p n_v + q, q n_u + p)`, the
/// unknowns ordered u- or v-major to get it) and solved by banded Cholesky,
/// `O(n_u n_v b^2)` per round for bandwidth `b`.
///
/// Returns `None` when no control point lies outside the box (the surface is left as it is).
///
/// # Errors
/// [`NurbsError::Incompatible`] for a weight that is not positive, an empty box (`lo > hi` or
/// a NaN bound), parameters and points of different lengths, or a parameter outside the
/// domain;
/// [`NurbsError::SingularSystem`] when the normal equations are too ill-conditioned (a pivot
/// below `1e-12` of its diagonal); [`NurbsError::NonFinitePoint`];
/// [`NurbsError::NonFiniteResult`].
pub fn bounded_refit(
    surface: &NurbsSurface,
    params: &[(f64, f64)],
    points: &[Vec3],
    bounds: &ControlBox,
) -> Result<Option<(NurbsSurface, BoundedRefit)>, NurbsError> {
    check_refit_input(surface, params, points, &[bounds], "bounded refit")?;
    let mut net = surface.control_points();
    let crossed: Vec<usize> =
        (0..3).filter(|&c| net.iter().any(|p| bounds.crossed(c, p.to_array()[c]).is_some())).collect();
    if crossed.is_empty() {
        return Ok(None);
    }
    let rows = rational_rows(surface, params);
    let (n_v, n_ctrl) = (surface.n_v(), net.len());
    let mut diag = vec![0.0; n_ctrl];
    rows.iter().flatten().for_each(|&(i, w)| diag[i] += w * w);
    let pinned = collapsed_edges(&net, surface.n_u(), n_v);
    let (order, bandwidth) = unknown_order(surface);
    let mu = BOUNDED_REFIT_PULL * diag.iter().copied().fold(0.0, f64::max);
    let mut report = BoundedRefit::default();
    for c in crossed {
        let start: Vec<f64> = net.iter().map(|p| p.to_array()[c]).collect();
        // The bound each coordinate is held on, if any; a pinned one at its start.
        let mut held: Vec<Option<f64>> = (0..n_ctrl).map(|i| pinned[i].then_some(start[i])).collect();
        let mut x = start.clone();
        for _ in 0..MAX_ACTIVE_SET_ROUNDS {
            // Hold what lies across; release what the objective pulls inwards (its gradient
            // points outwards: a negative Lagrange multiplier, Nocedal and Wright 16.5).
            let grad = gradient(&rows, points, &x, &start, mu, c);
            let mut changed = false;
            for i in (0..n_ctrl).filter(|&i| !pinned[i]) {
                match held[i] {
                    None => {
                        if let Some(b) = bounds.crossed(c, x[i]) {
                            held[i] = Some(b);
                            changed = true;
                        }
                    }
                    Some(b) => {
                        let pulls_in = if b == bounds.hi[c] { grad[i] > 0.0 } else { grad[i] < 0.0 };
                        if pulls_in {
                            held[i] = None;
                            changed = true;
                        }
                    }
                }
            }
            if !changed {
                break;
            }
            let free: Vec<usize> = order.iter().copied().filter(|&i| held[i].is_none()).collect();
            let mut slot = vec![usize::MAX; n_ctrl];
            free.iter().enumerate().for_each(|(f, &i)| slot[i] = f);
            let m = free.len();
            if m == 0 {
                x.iter_mut().zip(&held).for_each(|(xi, h)| *xi = h.unwrap_or(*xi));
                break;
            }
            let mut a = BandedCholesky::zeros(m, bandwidth.min(m.saturating_sub(1)));
            let mut sol: Vec<[f64; 1]> = free.iter().map(|&i| [mu * start[i]]).collect();
            for f in 0..m {
                a.add(f, f, mu);
            }
            for (row, q) in rows.iter().zip(points) {
                // The point less the part of the held control points.
                let target = q.to_array()[c] - row.iter().filter_map(|&(i, w)| held[i].map(|b| w * b)).sum::<f64>();
                for &(i, wi) in row.iter().filter(|(i, _)| held[*i].is_none()) {
                    sol[slot[i]][0] += wi * target;
                    for &(j, wj) in row.iter().filter(|(j, _)| held[*j].is_none() && slot[*j] <= slot[i]) {
                        a.add(slot[i], slot[j], wi * wj);
                    }
                }
            }
            a.factor("bounded refit")?;
            a.solve(&mut sol);
            if sol.iter().any(|x| !x[0].is_finite()) {
                return Err(NurbsError::NonFiniteResult { what: "bounded refit".into() });
            }
            for i in 0..n_ctrl {
                x[i] = held[i].unwrap_or_else(|| sol[slot[i]][0]);
            }
        }
        // Whatever the rounds left across (a cycle cut short) goes onto its bound: the box
        // holds in every case.
        for xi in x.iter_mut() {
            if let Some(b) = bounds.crossed(c, *xi) {
                *xi = b;
            }
        }
        report.held[c] =
            (0..n_ctrl).filter(|&i| (x[i] == bounds.lo[c] || x[i] == bounds.hi[c]) && start[i] != x[i]).count();
        for (pt, &xi) in net.iter_mut().zip(&x) {
            let mut arr = pt.to_array();
            arr[c] = xi;
            *pt = Vec3::from_array(arr);
        }
    }
    Ok(Some((with_net(surface, &net)?, report)))
}

/// The checks [`bounded_refit`] and [`held_refit`](super::held_refit) make of their input
/// (`what` names the caller in the error): positive weights, boxes that are not empty, as many
/// parameters as points, finite points, parameters within the domain.
pub(super) fn check_refit_input(
    surface: &NurbsSurface,
    params: &[(f64, f64)],
    points: &[Vec3],
    boxes: &[&ControlBox],
    what: &str,
) -> Result<(), NurbsError> {
    if surface.weights().iter().any(|&w| !(w > 0.0)) {
        return Err(NurbsError::Incompatible { what: format!("{what} of a surface with a weight <= 0") });
    }
    if let Some(b) = boxes.iter().find(|b| (0..3).any(|c| !(b.lo[c] <= b.hi[c]))) {
        return Err(NurbsError::Incompatible {
            what: format!("{what}: the box {:?}..{:?} is empty (expected lo <= hi)", b.lo, b.hi),
        });
    }
    if params.len() != points.len() {
        return Err(NurbsError::Incompatible {
            what: format!("{what}: {} parameters for {} points", params.len(), points.len()),
        });
    }
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(NurbsError::NonFinitePoint { index });
    }
    let ((u0, u1), (v0, v1)) = (surface.domain_u(), surface.domain_v());
    if params.iter().any(|&(u, v)| !(u >= u0 && u <= u1 && v >= v0 && v <= v1)) {
        return Err(NurbsError::Incompatible { what: format!("{what}: a parameter outside the domain") });
    }
    Ok(())
}

/// The sparse rows of the collocation matrix at `params`: (control index, `R_ij(u, v)`), the
/// rational basis `N_i(u) N_j(v) w_ij / sum N N w` of the surface's fixed weights
/// (`N_i(u) N_j(v)` when all are 1), control points u-major.
pub(super) fn rational_rows(surface: &NurbsSurface, params: &[(f64, f64)]) -> Vec<Vec<(usize, f64)>> {
    let weights = surface.weights();
    let (ku, kv) = (surface.knots_u(), surface.knots_v());
    let (p, q, n_v) = (ku.degree(), kv.degree(), surface.n_v());
    let mut rows: Vec<Vec<(usize, f64)>> = Vec::with_capacity(params.len());
    let (mut bu, mut bv): (BasisRow, BasisRow) = ([0.0; crate::MAX_DEGREE + 1], [0.0; crate::MAX_DEGREE + 1]);
    for &(u, v) in params {
        let (su, sv) = (ku.find_span(u), kv.find_span(v));
        basis_funs(ku.as_slice(), su, u, p, &mut bu);
        basis_funs(kv.as_slice(), sv, v, q, &mut bv);
        let mut row = Vec::with_capacity((p + 1) * (q + 1));
        for (a, &nu) in bu[..=p].iter().enumerate() {
            for (b, &nv) in bv[..=q].iter().enumerate() {
                let i = (su - p + a) * n_v + (sv - q + b);
                row.push((i, nu * nv * weights[i]));
            }
        }
        let sum: f64 = row.iter().map(|(_, w)| w).sum();
        row.iter_mut().for_each(|(_, w)| *w /= sum);
        rows.push(row);
    }
    rows
}

/// The order of the unknowns (control indices) for banded normal equations, with its
/// half-bandwidth: two control points interact only within `p + 1` rows and `q + 1` columns,
/// so u-major (as the net) the normal matrix has half-bandwidth `p n_v + q`, v-major
/// `q n_u + p`; the smaller is taken (Gunnerus, 12 x 47 poles: 39 against 144, a 14th of the
/// factorization's work), and leaving some unknowns out only narrows it.
pub(super) fn unknown_order(surface: &NurbsSurface) -> (Vec<usize>, usize) {
    let (p, q) = (surface.knots_u().degree(), surface.knots_v().degree());
    let (n_u, n_v) = (surface.n_u(), surface.n_v());
    if p * n_v + q <= q * n_u + p {
        ((0..n_u * n_v).collect(), p * n_v + q)
    } else {
        ((0..n_v).flat_map(|j| (0..n_u).map(move |i| i * n_v + j)).collect(), q * n_u + p)
    }
}

/// `surface` with the control points `net` (u-major), its knots and weights kept.
pub(super) fn with_net(surface: &NurbsSurface, net: &[Vec3]) -> Result<NurbsSurface, NurbsError> {
    let weights = surface.weights();
    NurbsSurface::try_new(
        surface.knots_u().clone(),
        surface.knots_v().clone(),
        net,
        surface.is_rational().then_some(&weights[..]),
    )
}

/// The control points of the net's collapsed boundary rows and columns (all of one row or
/// column at one place: a pointed end, a degenerate edge), u-major with `n_v` per row: a
/// refit moving them apart would open the point into a tiny curve whose normals are noise, so
/// [`bounded_refit`] keeps them where they are (a point within the box stays within it).
pub(super) fn collapsed_edges(net: &[Vec3], n_u: usize, n_v: usize) -> Vec<bool> {
    let mut pinned = vec![false; net.len()];
    let lines: [Vec<usize>; 4] = [
        (0..n_v).collect(),
        ((n_u - 1) * n_v..n_u * n_v).collect(),
        (0..n_u).map(|i| i * n_v).collect(),
        (0..n_u).map(|i| i * n_v + n_v - 1).collect(),
    ];
    for line in lines {
        let first = net[line[0]];
        if line.iter().all(|&i| net[i] == first) {
            line.iter().for_each(|&i| pinned[i] = true);
        }
    }
    pinned
}

/// Rounds of the active set in [`bounded_refit`] (each one solve); the bound is enforced after
/// the last in any case.
const MAX_ACTIVE_SET_ROUNDS: usize = 60;

/// The gradient (halved) of `sum_k (A_k x - Q_k,c)^2 + μ |x - x_0|^2`.
fn gradient(rows: &[Vec<(usize, f64)>], points: &[Vec3], x: &[f64], start: &[f64], mu: f64, c: usize) -> Vec<f64> {
    let mut g: Vec<f64> = x.iter().zip(start).map(|(a, b)| mu * (a - b)).collect();
    for (row, q) in rows.iter().zip(points) {
        let r = row.iter().map(|&(i, w)| w * x[i]).sum::<f64>() - q.to_array()[c];
        row.iter().for_each(|&(i, w)| g[i] += w * r);
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::rounded_box_sections;

    #[test]
    fn a_bounded_refit_keeps_the_net_and_the_surface_within_the_planes() {
        let sections = rounded_box_sections();
        let opts = crate::fit::SkinOptions::default();
        let fit = crate::fit::skin_approximate(&sections, 6, 7, &opts).expect("fits");
        // The half-spaces z >= 0 and y <= 3 of the two straight runs.
        let open = ControlBox::default();
        let bounds = ControlBox { lo: [open.lo[0], open.lo[1], 0.0], hi: [open.hi[0], 3.0, open.hi[2]] };
        let crossing = |s: &NurbsSurface| s.control_points().iter().any(|p| p.y > 3.0 || p.z < 0.0);
        // The least-squares net rings past the planes (else this test would show nothing).
        assert!(crossing(&fit.surface));
        let params: Vec<(f64, f64)> = fit.params.iter().flatten().copied().collect();
        let points: Vec<Vec3> = sections.iter().flatten().copied().collect();
        let (refit, report) = bounded_refit(&fit.surface, &params, &points, &bounds).expect("valid").expect("moved");
        assert!(!crossing(&refit) && report.held[0] == 0 && report.total() > 0, "{report:?}");
        // Same knots, and the convex-combination property on a grid (no round-off can cross: a convex
        // combination of values <= 3 is <= 3 up to one rounding of the sum, 4e-16 here).
        assert_eq!((refit.knots_u(), refit.knots_v()), (fit.surface.knots_u(), fit.surface.knots_v()));
        for i in 0..=40 {
            for j in 0..=40 {
                let p = refit.point(i as f64 / 40.0, j as f64 / 40.0);
                assert!(p.y <= 3.0 + 1e-15 && p.z >= -1e-15, "{p:?}");
            }
        }
        // x is left as it was.
        let before = fit.surface.control_points();
        assert!(refit.control_points().iter().zip(&before).all(|(a, b)| a.x == b.x));
        // Already within: nothing to do; and the refit's own result is within.
        assert!(bounded_refit(&refit, &params, &points, &bounds).expect("valid").is_none());
        assert!(bounded_refit(&fit.surface, &params, &points, &ControlBox::default()).expect("valid").is_none());
        // Bad input.
        assert!(bounded_refit(&fit.surface, &params[1..], &points, &bounds).is_err());
        let outside = vec![(2.0, 0.5); params.len()];
        assert!(bounded_refit(&fit.surface, &outside, &points, &bounds).is_err());
        // A rational surface keeps its weights, and its net and every point come within the
        // box (positive weights: the convex-combination property holds for the rational basis).
        let w: Vec<f64> = (0..fit.surface.control_points().len()).map(|i| 1.0 + 0.5 * ((i % 5) as f64 / 4.0)).collect();
        let rational =
            NurbsSurface::try_new(fit.surface.knots_u().clone(), fit.surface.knots_v().clone(), &before, Some(&w))
                .expect("valid");
        assert!(crossing(&rational));
        let (r, _) = bounded_refit(&rational, &params, &points, &bounds).expect("valid").expect("moved");
        assert!(!crossing(&r) && r.weights() == w);
        for i in 0..=40 {
            for j in 0..=40 {
                let p = r.point(i as f64 / 40.0, j as f64 / 40.0);
                // The rational combination divides once more: a few roundings of 3, 1e-15.
                assert!(p.y <= 3.0 + 1e-14 && p.z >= -1e-14, "{p:?}");
            }
        }
        // An empty box is refused.
        let empty = ControlBox { lo: [0.0, 1.0, 0.0], hi: [1.0, 0.5, 1.0] };
        assert!(bounded_refit(&fit.surface, &params, &points, &empty).is_err());
    }

    #[test]
    fn a_bounded_refit_keeps_a_pointed_end_a_point() {
        // The box sections with the first one a point: the skin's first row of poles is
        // one point, and the refit (which crosses the planes) leaves it there, where moving it
        // apart would open the point into a tiny curve of noisy normals.
        let mut sections = rounded_box_sections();
        sections[0] = vec![Vec3::new(0.0, 0.0, 2.0); 8];
        let fit = crate::fit::skin_approximate(&sections, 6, 7, &crate::fit::SkinOptions::default()).expect("fits");
        let first: Vec<Vec3> = (0..fit.surface.n_u()).map(|i| fit.surface.control_point(i, 0)).collect();
        assert!(first.iter().all(|p| *p == first[0]), "the skin's first row is one point");
        let params: Vec<(f64, f64)> = fit.params.iter().flatten().copied().collect();
        let points: Vec<Vec3> = sections.iter().flatten().copied().collect();
        let bounds =
            ControlBox { lo: [f64::NEG_INFINITY, f64::NEG_INFINITY, 0.0], hi: [f64::INFINITY, 3.0, f64::INFINITY] };
        let (refit, report) = bounded_refit(&fit.surface, &params, &points, &bounds).expect("valid").expect("moved");
        assert!(report.total() > 0);
        for i in 0..refit.n_u() {
            assert_eq!(refit.control_point(i, 0), first[0], "pole {i} of the first row");
        }
    }
}
