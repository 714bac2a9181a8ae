//! Evaluation on a tensor grid of parameters: a surface's points and derivatives at every
//! `(us[i], vs[j])`, with the basis functions computed once per parameter instead of once per
//! point.
//!
//! Validity checks, closest-point projectors and curvature maps sample a surface on such grids;
//! pointwise [`NurbsSurface::derivatives`] spends most of its time in the basis functions
//! (A2.3) and in the inner sum over the v row, both of which depend on one parameter only.
//! Here the basis functions are found once per `u` and per `v`, and for each `v` the row sums
//! `t_r^(l) = sum_s N_s^(l)(v) P_{r,s}` once per control row `r`; each point then costs one
//! sum over `p + 1` rows. The arithmetic per point is the same, in the same order, as
//! [`NurbsSurface::derivatives`], so the results are bit-identical to it.

use crate::basis::{ders_basis_funs, BasisRow};
use crate::knots::MAX_DEGREE;
use crate::surface::{add_row, rational_first, rational_surface_derivatives, row_sums};
use crate::{NurbsSurface, SurfaceDerivatives, Vec3};

/// Basis functions and their first two derivatives at one parameter, with its span.
#[derive(Clone, Debug)]
struct Basis {
    span: usize,
    ders: [BasisRow; 3],
}

impl Basis {
    fn at(knots: &crate::KnotVector, t: f64) -> Self {
        let t = knots.clamp(t);
        let span = knots.find_span(t);
        let mut ders = [[0.0; MAX_DEGREE + 1]; 3];
        ders_basis_funs(knots.as_slice(), span, t, knots.degree(), 2, &mut ders);
        Basis { span, ders }
    }

    /// [`Basis::at`] to the first derivative only (the second left 0): the values and first
    /// derivatives are the same to the bit (A2.3 finds each order from the lower ones).
    fn first_at(knots: &crate::KnotVector, t: f64) -> Self {
        let mut b = Basis { span: 0, ders: [[0.0; MAX_DEGREE + 1]; 3] };
        b.first_into(knots, t);
        b
    }

    /// [`Basis::first_at`] in place.
    fn first_into(&mut self, knots: &crate::KnotVector, t: f64) {
        let t = knots.clamp(t);
        self.span = knots.find_span(t);
        ders_basis_funs(knots.as_slice(), self.span, t, knots.degree(), 1, &mut self.ders);
    }
}

/// The point and first partial derivatives at one `(u, v)`: what a validity grid or a
/// closest-point search samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FirstDerivatives {
    pub point: Vec3,
    pub su: Vec3,
    pub sv: Vec3,
}

/// The point and first partial derivatives of one surface at a sequence of parameters, each
/// bit-identical to [`NurbsSurface::first_derivatives`], reusing what a repeated parameter
/// shares with the previous call: the basis functions of a `u` or a `v` equal (to the bit) to
/// the last one, and the control rows' sums against the `v` basis while `v` and the `u` span
/// stay. A search along an iso-line (a root on a grid edge, a line search in `u`) then costs
/// one set of basis functions and `p + 1` row additions per point.
#[derive(Clone, Debug)]
pub struct FirstDerivativesCache<'a> {
    surface: &'a NurbsSurface,
    /// The bits of the last `u` and `v` (`None` before the first call) and their basis functions.
    u: Option<u64>,
    v: Option<u64>,
    bu: Basis,
    bv: Basis,
    /// `(v bits, u span)` of `rows`, the sums of the control rows of that span against the
    /// basis of that `v`.
    rows_of: Option<(u64, usize)>,
    rows: [[[f64; 4]; 3]; MAX_DEGREE + 1],
}

impl<'a> FirstDerivativesCache<'a> {
    /// An empty cache for `surface`.
    pub fn new(surface: &'a NurbsSurface) -> Self {
        let empty = Basis { span: 0, ders: [[0.0; MAX_DEGREE + 1]; 3] };
        FirstDerivativesCache {
            surface,
            u: None,
            v: None,
            bu: empty.clone(),
            bv: empty,
            rows_of: None,
            rows: [[[0.0; 4]; 3]; MAX_DEGREE + 1],
        }
    }

    /// The point and first derivatives at `(u, v)`, as [`NurbsSurface::first_derivatives`].
    pub fn at(&mut self, u: f64, v: f64) -> FirstDerivatives {
        let s = self.surface;
        let (p, q) = (s.degree_u(), s.degree_v());
        let (ub, vb) = (u.to_bits(), v.to_bits());
        if self.u != Some(ub) {
            self.bu.first_into(s.knots_u(), u);
            self.u = Some(ub);
        }
        if self.v != Some(vb) {
            self.bv.first_into(s.knots_v(), v);
            self.v = Some(vb);
        }
        if self.rows_of != Some((vb, self.bu.span)) {
            let (nvn, cw) = (s.n_v(), s.homogeneous());
            for (r, tr) in self.rows.iter_mut().enumerate().take(p + 1) {
                *tr = row_sums::<1>(&cw[(self.bu.span - p + r) * nvn + self.bv.span - q..][..=q], &self.bv.ders);
            }
            self.rows_of = Some((vb, self.bu.span));
        }
        let mut a = [[[0.0f64; 4]; 3]; 3];
        for (r, tr) in self.rows.iter().enumerate().take(p + 1) {
            add_row::<1>(&mut a, &self.bu.ders, r, tr);
        }
        let (point, su, sv) = rational_first(&a);
        FirstDerivatives { point, su, sv }
    }
}

impl NurbsSurface {
    /// The points and partial derivatives up to second order at every `(us[i], vs[j])`,
    /// v-major: node `(i, j)` is at index `j * us.len() + i`. Each entry is bit-identical to
    /// [`derivatives(us[i], vs[j])`](NurbsSurface::derivatives) (parameters clamped to the
    /// domain the same way), at a fraction of its cost when the grid has more than a few nodes
    /// per line. Empty when either list is.
    ///
    /// ```
    /// # use nurbs::{KnotVector, NurbsSurface, Vec3};
    /// let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).unwrap();
    /// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0)];
    /// let s = NurbsSurface::try_new(k.clone(), k, &pts, None).unwrap();
    /// let (us, vs) = ([0.0, 0.25, 1.0], [0.5, 0.75]);
    /// let grid = s.derivatives_grid(&us, &vs);
    /// assert_eq!(grid.len(), 6);
    /// assert_eq!(grid[1 * 3 + 2], s.derivatives(1.0, 0.75));
    /// ```
    pub fn derivatives_grid(&self, us: &[f64], vs: &[f64]) -> Vec<SurfaceDerivatives> {
        let mut out = Vec::with_capacity(us.len() * vs.len());
        self.homogeneous_grid::<2>(us, vs, |a| out.push(rational_surface_derivatives(a)));
        out
    }

    /// [`derivatives_grid`](NurbsSurface::derivatives_grid) to first order only (about half
    /// the work): each entry bit-identical to the `point`, `su` and `sv` of
    /// [`derivatives`](NurbsSurface::derivatives).
    pub fn first_derivatives_grid(&self, us: &[f64], vs: &[f64]) -> Vec<FirstDerivatives> {
        let mut out = Vec::with_capacity(us.len() * vs.len());
        self.homogeneous_grid::<1>(us, vs, |a| {
            let (s00, s10, s01) = rational_first(a);
            out.push(FirstDerivatives { point: s00, su: s10, sv: s01 });
        });
        out
    }

    /// The point and first partial derivatives at one `(u, v)`: bit-identical to the `point`,
    /// `su` and `sv` of [`derivatives`](NurbsSurface::derivatives) (the same sums in the same
    /// order, without the second-order ones), at about half its cost. For searches that need
    /// no curvature (roots on a plane, Newton steps).
    pub fn first_derivatives(&self, u: f64, v: f64) -> FirstDerivatives {
        let (bu, bv) = (Basis::first_at(self.knots_u(), u), Basis::first_at(self.knots_v(), v));
        let (p, q) = (self.degree_u(), self.degree_v());
        let (nvn, cw) = (self.n_v(), self.homogeneous());
        let mut a = [[[0.0f64; 4]; 3]; 3];
        for r in 0..=p {
            let t = row_sums::<1>(&cw[(bu.span - p + r) * nvn + bv.span - q..][..=q], &bv.ders);
            add_row::<1>(&mut a, &bu.ders, r, &t);
        }
        let (point, su, sv) = rational_first(&a);
        FirstDerivatives { point, su, sv }
    }

    /// The points at every `(us[i], vs[j])`, v-major as
    /// [`derivatives_grid`](NurbsSurface::derivatives_grid), each bit-identical to
    /// [`point`](NurbsSurface::point).
    pub fn points_grid(&self, us: &[f64], vs: &[f64]) -> Vec<Vec3> {
        let mut out = Vec::with_capacity(us.len() * vs.len());
        self.homogeneous_grid::<0>(us, vs, |a| out.push(Vec3::new(a[0][0][0], a[0][0][1], a[0][0][2]) / a[0][0][3]));
        out
    }

    /// The homogeneous derivatives `a[k][l]` (`k + l <= ORDER`, the rest left 0) at every
    /// node, v-major, handed to `emit` in order: the sums of
    /// [`derivatives`](NurbsSurface::derivatives), with each control row's sums
    /// (`row_sums` in `surface.rs`) made once per v.
    fn homogeneous_grid<const ORDER: usize>(&self, us: &[f64], vs: &[f64], mut emit: impl FnMut(&[[[f64; 4]; 3]; 3])) {
        if us.is_empty() || vs.is_empty() {
            return;
        }
        let (p, q) = (self.degree_u(), self.degree_v());
        let bu: Vec<Basis> = us.iter().map(|&u| Basis::at(self.knots_u(), u)).collect();
        // The control rows any u touches: only these get row sums.
        let r_lo = bu.iter().map(|b| b.span - p).min().unwrap_or(0);
        let r_hi = bu.iter().map(|b| b.span).max().unwrap_or(0);
        let nvn = self.n_v();
        let cw = self.homogeneous();
        let mut t = vec![[[0.0f64; 4]; 3]; r_hi + 1 - r_lo];
        for &v in vs {
            let bv = Basis::at(self.knots_v(), v);
            for (k, tr) in t.iter_mut().enumerate() {
                *tr = row_sums::<ORDER>(&cw[(r_lo + k) * nvn + bv.span - q..][..=q], &bv.ders);
            }
            for b in &bu {
                let mut a = [[[0.0f64; 4]; 3]; 3];
                for r in 0..=p {
                    add_row::<ORDER>(&mut a, &b.ders, r, &t[b.span - p + r - r_lo]);
                }
                emit(&a);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::{KnotVector, NurbsSurface, Vec3};

    /// A rational bicubic-by-quadratic surface with interior knots (one double) and uneven
    /// weights, from a fixed linear congruential sequence.
    fn wavy() -> NurbsSurface {
        let ku = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.2, 0.5, 0.5, 0.8, 1., 1., 1., 1.]).expect("valid");
        let kv = KnotVector::try_new(2, vec![0., 0., 0., 0.3, 0.6, 1., 1., 1.]).expect("valid");
        let (nu, nv) = (ku.num_basis(), kv.num_basis());
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                pts.push(Vec3::new(i as f64 + 0.3 * next(), j as f64 + 0.3 * next(), next()));
                w.push(0.5 + next());
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
    }

    /// Every node equals the pointwise evaluation exactly: same operations, same order. The
    /// parameters include knots (where the span to the right is taken), both domain ends,
    /// values outside the domain (clamped), NaN (clamped to the start) and an unsorted list.
    #[test]
    fn a_grid_evaluation_equals_pointwise_derivatives_bit_for_bit() {
        let s = wavy();
        let us = [0.0, 0.2, 0.5, 0.73, 1.0, -0.5, 1.5, 0.11, f64::NAN, 0.49999];
        let vs = [1.0, 0.0, 0.3, 0.6, 0.45, 2.0, 0.05];
        let grid = s.derivatives_grid(&us, &vs);
        let first = s.first_derivatives_grid(&us, &vs);
        let points = s.points_grid(&us, &vs);
        assert_eq!((grid.len(), first.len()), (us.len() * vs.len(), us.len() * vs.len()));
        // The cache sees each v repeated along a row, then a new v with the last u repeated.
        let mut cache = crate::FirstDerivativesCache::new(&s);
        for (j, &v) in vs.iter().enumerate() {
            for (i, &u) in us.iter().enumerate() {
                let d = s.derivatives(u, v);
                assert_eq!(grid[j * us.len() + i], d, "node ({u}, {v})");
                let f = first[j * us.len() + i];
                assert_eq!((f.point, f.su, f.sv), (d.point, d.su, d.sv), "first order at ({u}, {v})");
                let f = s.first_derivatives(u, v);
                assert_eq!((f.point, f.su, f.sv), (d.point, d.su, d.sv), "pointwise first order at ({u}, {v})");
                let c = cache.at(u, v);
                assert_eq!((c.point, c.su, c.sv), (d.point, d.su, d.sv), "cached first order at ({u}, {v})");
                assert_eq!(points[j * us.len() + i], s.point(u, v), "point at ({u}, {v})");
            }
        }
        // A grid whose u values touch only some control rows (the row sums are restricted).
        let narrow = [0.55, 0.6];
        let g = s.derivatives_grid(&narrow, &vs);
        for (j, &v) in vs.iter().enumerate() {
            for (i, &u) in narrow.iter().enumerate() {
                assert_eq!(g[j * narrow.len() + i], s.derivatives(u, v));
            }
        }
        // Alternating searches along u and along v, crossing spans, as a root search does.
        let mut cache = crate::FirstDerivativesCache::new(&s);
        for k in 0..200 {
            let t = f64::from(k) / 199.0;
            for (u, v) in [(t, 0.45), (0.45, t), (t, 0.6), (0.5, 1.0 - t)] {
                let (c, d) = (cache.at(u, v), s.derivatives(u, v));
                assert_eq!((c.point, c.su, c.sv), (d.point, d.su, d.sv), "({u}, {v})");
            }
        }
        assert!(s.derivatives_grid(&[], &vs).is_empty());
        assert!(s.derivatives_grid(&us, &[]).is_empty());
        assert!(s.first_derivatives_grid(&[], &vs).is_empty());
    }
}
