//! The envelope hold by samples of the surface: a least-squares refit of the coordinates of a
//! control net with the *surface*, not its control net, kept within a box.
//!
//! [`nurbs::fit::bounded_refit`] holds the control points in the box, which by the convex-hull
//! property (The NURBS Book P3.4, P4.4) holds the surface too, but is much stricter than
//! needed: where a section turns sharply at the box's face (a transom at the centre plane, the
//! bilge into a flat of side) the least squares puts control points past the face while the
//! surface stays inside, and holding those points costs accuracy the surface never needed to
//! lose (measured: the Series 60 Cb 0.80 parent's max error at the offsets 63 -> 214 mm).
//!
//! Here the constraints are on the surface at the samples `s_j` of the validity check's grid
//! (`param_grid` with [`PER_SPAN`] samples per knot span each way). For each coordinate `c`
//! whose samples leave the box, with the weights fixed:
//!
//! `min sum_k (A_k x - Q_k,c)^2 + μ |x - x_0|^2`  subject to  `lo_c <= R(s_j) x <= hi_c`,
//!
//! `A_k` and `R(s_j)` the rational basis at the offsets' parameters and at the samples (so
//! the constraints are linear in `x`), `x_0` the coordinate of the net, `μ` as in
//! `bounded_refit` ([`nurbs::fit::BOUNDED_REFIT_PULL`]). A convex quadratic programme, solved
//! by an interior-point method (Clarabel: Goulart and Chen, "Clarabel: an interior-point solver
//! for conic programs with quadratic objectives", 2024), by cutting planes: each round holds,
//! of the samples that crossed, those that cross farthest among their eight grid neighbours
//! (or, when none crossed, the one nearest to crossing), and solves again, until nothing
//! crosses or after [`ROUNDS`] rounds. (Holding every sample that crossed at once, as
//! equalities, flattens whole spans: measured, an error of 2.4 m in y on the Cb 0.80 parent.)
//! The refit is local: only the control points within [`RING`] of a held sample's support
//! move (the points of a collapsed boundary row or column, a pointed end, never), which keeps
//! the programmes small (about 60 ms a refit of R/V Gunnerus at 12 x 47 control points,
//! release build). A held point is the surface's farthest
//! past the bound near its grid sample (golden sections over the cells around it, as the
//! validity check refines its findings), so the check finds nothing there; elsewhere between
//! samples the surface may still pass the bound by a sliver, which the check measures as it
//! does any surface.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use nurbs::basis::{basis_funs, BasisRow};
use nurbs::fit::{check_refit, collapsed_edges, rational_basis_row, ControlBox, BOUNDED_REFIT_PULL};
use nurbs::{NurbsError, NurbsSurface, Vec3, MAX_DEGREE};

use crate::analysis::fold::PER_SPAN;
use crate::analysis::param_grid;
use crate::analysis::validity::refine_max;

/// Rounds of the cutting planes (each one quadratic programme).
pub const ROUNDS: usize = 12;

/// Control points free to move around a constrained sample's support, in each index direction:
/// the refit is local (the rest of the net stays), which keeps the programmes small.
pub const RING: usize = 2;

/// The interior-point method's tolerances (gap and feasibility): far below the validity
/// allowances (0.5 % of the hull's dimensions).
const QP_TOL: f64 = 1e-7;

/// A sample is across when past the bound by more than this share of the coordinate's extent
/// (the interior-point method's round-off, far below any allowance of the validity check).
const ACROSS_SHARE: f64 = 1e-9;

/// One sparse row of the rational basis: `(control index i n_v + j, R_ij(u, v))`.
type Row = Vec<(usize, f64)>;

/// Refit `surface` (fitted to `points` at `params`) so that it stays within `bounds` at the
/// samples of its validity grid (module docs). Returns the surface and the number of sample
/// constraints active at the solution, or `None` when no sample leaves the box.
///
/// # Errors
/// As [`check_refit`]; [`NurbsError::SingularSystem`] when a programme cannot be solved (the
/// solver's status named); [`NurbsError::NonFiniteResult`].
pub fn sampled_refit(
    surface: &NurbsSurface,
    params: &[(f64, f64)],
    points: &[Vec3],
    bounds: &ControlBox,
) -> Result<Option<(NurbsSurface, usize)>, NurbsError> {
    check_refit("sampled refit", surface, params, points, bounds)?;
    let w = surface.weights();
    let us = param_grid(surface.knots_u(), 16, true, PER_SPAN);
    let vs = param_grid(surface.knots_v(), 16, true, PER_SPAN);
    let samples = Samples::new(surface, &w, &us, &vs);
    let mut net = surface.control_points();
    let mut s_vals = Vec::new();
    let crossed: Vec<usize> = (0..3)
        .filter(|&c| {
            let x: Vec<f64> = net.iter().map(|p| p.to_array()[c]).collect();
            samples.values(&x, &mut s_vals);
            let extent = extent(&s_vals);
            s_vals.iter().any(|&s| crossing(bounds, c, s, extent).is_some())
        })
        .collect();
    if crossed.is_empty() {
        return Ok(None);
    }
    let rows: Vec<Row> = params.iter().map(|&(u, v)| rational_basis_row(surface, &w, u, v)).collect();
    let (n_u, n_v) = (surface.n_u(), surface.n_v());
    let n = net.len();
    let pinned = collapsed_edges(&net, n_u, n_v);
    let gram = Gram::new(&rows, points, n, surface.degree_u() * n_v + surface.degree_v());
    let mu = BOUNDED_REFIT_PULL * (0..n).map(|i| gram.get(i, i)).fold(0.0, f64::max);
    let mut held_total = 0;
    for c in crossed {
        let x0: Vec<f64> = net.iter().map(|p| p.to_array()[c]).collect();
        samples.values(&x0, &mut s_vals);
        let extent = extent(&s_vals);
        // The constrained samples with their bound and side: the peaks of what crossed, round by
        // round (cutting planes; a constraint once taken stays), and the control points free
        // to move: those within RING of a constrained sample's support.
        let mut held = vec![false; s_vals.len()];
        let mut held_rows: Vec<(Row, f64, bool)> = Vec::new();
        let mut free = vec![false; n];
        let mut x = x0.clone();
        for _ in 0..ROUNDS {
            let mut added = 0;
            // The peaks of what crossed; when no sample crossed, the sample nearest to crossing
            // (the surface may cross between samples, as the validity check looks for too).
            let mut candidates = peaks(&s_vals, us.len(), bounds, c, extent);
            if candidates.is_empty() {
                let worst = (0..s_vals.len())
                    .max_by(|&a, &b| excess(bounds, c, s_vals[a]).total_cmp(&excess(bounds, c, s_vals[b])));
                candidates.extend(worst);
            }
            for k in candidates {
                if held[k] {
                    continue;
                }
                // The side the sample is nearest to (or past), and the surface's farthest point
                // past it near the sample (golden sections over the grid cells around it).
                let upper = s_vals[k] - bounds.hi[c] >= bounds.lo[c] - s_vals[k];
                let (i, j) = (k % us.len(), k / us.len());
                let side = |t: f64| if upper { t - bounds.hi[c] } else { bounds.lo[c] - t };
                let at =
                    |u: f64, v: f64| side(rational_basis_row(surface, &w, u, v).iter().map(|&(i, r)| r * x[i]).sum());
                let (u, v, e) = refine_max(&us, &vs, i, j, at);
                if !(e > ACROSS_SHARE * extent) {
                    continue;
                }
                held[k] = true;
                let row = rational_basis_row(surface, &w, u, v);
                for &(i, _) in &row {
                    let (iu, jv) = (i / n_v, i % n_v);
                    for a in iu.saturating_sub(RING)..(iu + RING + 1).min(n_u) {
                        for b in jv.saturating_sub(RING)..(jv + RING + 1).min(n_v) {
                            free[a * n_v + b] = !pinned[a * n_v + b];
                        }
                    }
                }
                held_rows.push((row, if upper { bounds.hi[c] } else { bounds.lo[c] }, upper));
                added += 1;
            }
            if added == 0 {
                break;
            }
            let local = Local::new(&free, &gram, &x0, mu, c);
            let xf = local.solve(&held_rows)?;
            for (&i, &v) in local.vars.iter().zip(&xf) {
                x[i] = v;
            }
            samples.values(&x, &mut s_vals);
        }
        held_total += held_rows.len();
        for (pt, &xi) in net.iter_mut().zip(&x) {
            let mut a = pt.to_array();
            a[c] = xi;
            *pt = Vec3::from_array(a);
        }
    }
    let out = NurbsSurface::try_new(
        surface.knots_u().clone(),
        surface.knots_v().clone(),
        &net,
        surface.is_rational().then_some(&w[..]),
    )?;
    Ok(Some((out, held_total)))
}

/// The spread of sample values (at least a round-off floor).
fn extent(s: &[f64]) -> f64 {
    let (lo, hi) = s.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &s| (lo.min(s), hi.max(s)));
    (hi - lo).max(f64::MIN_POSITIVE)
}

/// The rational basis of a surface on a tensor grid of parameters (v-major, sample
/// `k = b n_us + a` at `(us[a], vs[b])`), the B-splines found once per parameter.
struct Samples<'a> {
    w: &'a [f64],
    n_v: usize,
    /// Per `u`: its first control row and `N_{i,p}(u)`; per `v` likewise.
    iu: Vec<(usize, BasisRow)>,
    jv: Vec<(usize, BasisRow)>,
    p: usize,
    q: usize,
}

impl<'a> Samples<'a> {
    fn new(surface: &NurbsSurface, w: &'a [f64], us: &[f64], vs: &[f64]) -> Self {
        let basis = |knots: &nurbs::KnotVector, t: f64| {
            let (p, span) = (knots.degree(), knots.find_span(t));
            let mut b: BasisRow = [0.0; MAX_DEGREE + 1];
            basis_funs(knots.as_slice(), span, t, p, &mut b);
            (span - p, b)
        };
        Samples {
            w,
            n_v: surface.n_v(),
            iu: us.iter().map(|&u| basis(surface.knots_u(), u)).collect(),
            jv: vs.iter().map(|&v| basis(surface.knots_v(), v)).collect(),
            p: surface.degree_u(),
            q: surface.degree_v(),
        }
    }

    /// `out[k] = R(s_k) x`.
    fn values(&self, x: &[f64], out: &mut Vec<f64>) {
        out.clear();
        for (j0, nv) in &self.jv {
            for (i0, nu) in &self.iu {
                let (mut num, mut den) = (0.0, 0.0);
                for (a, &na) in nu[..=self.p].iter().enumerate() {
                    for (b, &nb) in nv[..=self.q].iter().enumerate() {
                        let i = (i0 + a) * self.n_v + j0 + b;
                        let r = na * nb * self.w[i];
                        num += r * x[i];
                        den += r;
                    }
                }
                out.push(num / den);
            }
        }
    }
}

/// The samples of a grid (`nu` along u, v-major) past a bound that cross it farthest among
/// their eight neighbours: one constraint per crossing region and round, since holding a whole
/// region on the bound would flatten every span it touches.
fn peaks(s: &[f64], nu: usize, bounds: &ControlBox, c: usize, extent: f64) -> Vec<usize> {
    let nv = s.len() / nu.max(1);
    let excess = |k: usize| match crossing(bounds, c, s[k], extent) {
        Some(b) => (s[k] - b).abs(),
        None => 0.0,
    };
    let mut out = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let k = j * nu + i;
            let e = excess(k);
            if e == 0.0 {
                continue;
            }
            let mut top = true;
            for dj in -1i64..=1 {
                for di in -1i64..=1 {
                    let (ii, jj) = (i as i64 + di, j as i64 + dj);
                    if (di, dj) == (0, 0) || ii < 0 || jj < 0 || ii >= nu as i64 || jj >= nv as i64 {
                        continue;
                    }
                    let kk = jj as usize * nu + ii as usize;
                    // Ties go to the first in grid order.
                    let ek = excess(kk);
                    if ek > e || (ek == e && kk < k) {
                        top = false;
                    }
                }
            }
            if top {
                out.push(k);
            }
        }
    }
    out
}

/// How far the value `s` of coordinate `c` is past the nearer of its bounds (negative inside).
fn excess(bounds: &ControlBox, c: usize, s: f64) -> f64 {
    (s - bounds.hi[c]).max(bounds.lo[c] - s)
}

/// The bound of coordinate `c` that the sample value `s` is past (beyond round-off), if any.
fn crossing(bounds: &ControlBox, c: usize, s: f64, extent: f64) -> Option<f64> {
    let tol = ACROSS_SHARE * extent;
    if s < bounds.lo[c] - tol {
        Some(bounds.lo[c])
    } else if s > bounds.hi[c] + tol {
        Some(bounds.hi[c])
    } else {
        None
    }
}

/// `A^T A` (u-major control indices, half-bandwidth `bw = p n_v + q`: two control points
/// share an offset only within `p + 1` rows and `q + 1` columns) and `A^T Q`, coordinate by
/// coordinate.
struct Gram {
    bw: usize,
    /// Entry `(i, j)`, `i <= j <= i + bw`, at `i (bw + 1) + j - i`.
    band: Vec<f64>,
    atq: Vec<[f64; 3]>,
}

impl Gram {
    fn new(rows: &[Row], points: &[Vec3], n: usize, bw: usize) -> Self {
        let mut band = vec![0.0; n * (bw + 1)];
        let mut atq = vec![[0.0; 3]; n];
        for (row, pt) in rows.iter().zip(points) {
            let q = pt.to_array();
            for &(i, ri) in row {
                for t in 0..3 {
                    atq[i][t] += ri * q[t];
                }
                for &(j, rj) in row.iter().filter(|(j, _)| i <= *j) {
                    band[i * (bw + 1) + j - i] += ri * rj;
                }
            }
        }
        Gram { bw, band, atq }
    }

    /// `(A^T A)_ij`.
    fn get(&self, i: usize, j: usize) -> f64 {
        let (a, b) = (i.min(j), i.max(j));
        if b - a > self.bw {
            0.0
        } else {
            self.band[a * (self.bw + 1) + b - a]
        }
    }
}

/// The least squares of one coordinate over the free control points `vars` (the others at
/// `x0`): `P = A_F^T A_F + μ I` (upper triangle, as Clarabel takes it) and
/// `q = -(A^T Q - A^T A x_fixed)_F - μ x0_F`.
struct Local<'a> {
    vars: Vec<usize>,
    slot: Vec<usize>,
    p_mat: CscMatrix<f64>,
    q: Vec<f64>,
    x0: &'a [f64],
}

impl<'a> Local<'a> {
    fn new(free: &[bool], gram: &Gram, x0: &'a [f64], mu: f64, c: usize) -> Self {
        let n = free.len();
        let vars: Vec<usize> = (0..n).filter(|&i| free[i]).collect();
        let mut slot = vec![usize::MAX; n];
        vars.iter().enumerate().for_each(|(f, &i)| slot[i] = f);
        let nf = vars.len();
        // Column by column (the vars in increasing order), rows i <= j.
        let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
        let mut q = vec![0.0; nf];
        for (f, &j) in vars.iter().enumerate() {
            for i in j.saturating_sub(gram.bw)..=j {
                let g = gram.get(i, j);
                if free[i] && (g != 0.0 || i == j) {
                    rowval.push(slot[i]);
                    nzval.push(if i == j { g + mu } else { g });
                }
            }
            colptr.push(rowval.len());
            let fixed: f64 = (j.saturating_sub(gram.bw)..(j + gram.bw + 1).min(n))
                .filter(|&l| !free[l])
                .map(|l| gram.get(j, l) * x0[l])
                .sum();
            q[f] = -(gram.atq[j][c] - fixed) - mu * x0[j];
        }
        let p_mat = CscMatrix::new(nf, nf, colptr, rowval, nzval);
        Local { vars, slot, p_mat, q, x0 }
    }

    /// The free control points' coordinate with the samples `held` within their bounds.
    fn solve(&self, held: &[(Row, f64, bool)]) -> Result<Vec<f64>, NurbsError> {
        let nf = self.vars.len();
        let (mut ai, mut aj, mut av, mut b) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        // R x <= hi as R x + s = hi, R x >= lo as -R x + s = -lo, s >= 0; the fixed control
        // points' part on the right.
        for &(ref r, bound, upper) in held {
            let sign = if upper { 1.0 } else { -1.0 };
            let row = b.len();
            let mut fixed = 0.0;
            for &(i, w) in r {
                match self.slot[i] {
                    usize::MAX => fixed += w * self.x0[i],
                    f => {
                        ai.push(row);
                        aj.push(f);
                        av.push(sign * w);
                    }
                }
            }
            b.push(sign * (bound - fixed));
        }
        let m = b.len();
        let a_mat = CscMatrix::new_from_triplets(m, nf, ai, aj, av);
        let cones = [SupportedConeT::NonnegativeConeT(m)];
        let failed =
            |what: String| NurbsError::SingularSystem { what: format!("sampled refit within the envelope: {what}") };
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_threads(1)
            .tol_gap_abs(QP_TOL)
            .tol_gap_rel(QP_TOL)
            .tol_feas(QP_TOL)
            .build()
            .map_err(|e| failed(format!("{e:?}")))?;
        let mut solver = DefaultSolver::new(&self.p_mat, &self.q, &a_mat, &b, &cones, settings)
            .map_err(|e| failed(format!("{e:?}")))?;
        solver.solve();
        let status = solver.solution.status;
        if !matches!(status, SolverStatus::Solved | SolverStatus::AlmostSolved) {
            return Err(failed(format!("{status:?}")));
        }
        let x = solver.solution.x.clone();
        if x.iter().any(|t| !t.is_finite()) {
            return Err(NurbsError::NonFiniteResult { what: "sampled refit".into() });
        }
        Ok(x)
    }
}
