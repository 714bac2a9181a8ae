//! What every evaluation of a [`WeightProblem`] shares, independent of the weights: the band
//! layout of the control points in the normal matrix `G` ([`Pattern`]) and the B-spline
//! products of every offset, with their derivatives for the parameter unknowns
//! ([`BasisTable`]).

use nurbs::basis::{basis_funs, ders_basis_funs, BasisRow};
use nurbs::MAX_DEGREE;

use super::WeightProblem;

/// The structure shared by all evaluations: band layout of the control points and the offsets
/// of one offset's `(p+1)(q+1)` control points from its first.
#[derive(Clone, Debug)]
pub(super) struct Pattern {
    pub(super) n_u: usize,
    pub(super) n_v: usize,
    pub(super) p: usize,
    pub(super) q: usize,
    /// Half-bandwidth of `G`.
    pub(super) bw: usize,
    /// Band order: u-major (`pos = i n_v + j`) or v-major (`pos = j n_u + i`).
    pub(super) u_major: bool,
    /// `(p+1)(q+1)`.
    pub(super) nb: usize,
    /// Local entry `l` (in increasing band position) sits at `first + off[l]`.
    pub(super) off: Vec<usize>,
    /// Local entry `l` is `(a, b)`: `N_{i0+a}(u) N_{j0+b}(v)`.
    pub(super) ab: Vec<(usize, usize)>,
    /// Length of the local index's inner (band-contiguous) dimension: `q + 1` in u-major
    /// order, `p + 1` in v-major; local entry `l = o inner + i` sits at `o so + i` from the
    /// offset's first control point.
    pub(super) inner: usize,
    /// Row stride of the band storage: `bw + inner`, the padding taking the upper-triangle
    /// half of the diagonal blocks, so every block is written whole.
    pub(super) stride: usize,
    /// The blocks of `h h^T` for one offset: `(l, band index minus first stride, first l2)`,
    /// each `inner` long: entries `(l, l2 .. l2 + inner)` for every outer index up to `l`'s.
    pub(super) blocks: Vec<(usize, usize, usize)>,
    /// Band position -> u-major control index `i n_v + j`.
    pub(super) grid: Vec<usize>,
}

impl Pattern {
    pub(super) fn new(p: usize, q: usize, n_u: usize, n_v: usize) -> Self {
        let (bw_u, bw_v) = (p * n_v + q, q * n_u + p);
        let u_major = bw_u <= bw_v;
        let bw = if u_major { bw_u } else { bw_v };
        let mut ab = Vec::with_capacity((p + 1) * (q + 1));
        if u_major {
            for a in 0..=p {
                for b in 0..=q {
                    ab.push((a, b));
                }
            }
        } else {
            for b in 0..=q {
                for a in 0..=p {
                    ab.push((a, b));
                }
            }
        }
        let pos = |i: usize, j: usize| if u_major { i * n_v + j } else { j * n_u + i };
        let off: Vec<usize> = ab.iter().map(|&(a, b)| pos(a, b)).collect();
        // Entry (r, c) = (first + off_l, first + off_l2) sits at r stride + c + bw - r
        // = first stride + off_l (stride - 1) + off_l2 + bw; with l = (o, i), l2 = (o2, i2),
        // off_l2 = o2 so + i2 is contiguous in i2. For o2 = o the entries i2 > i lie above the
        // diagonal, at most inner - 1 columns: in row r's padding.
        let (inner, so) = if u_major { (q + 1, n_v) } else { (p + 1, n_u) };
        let stride = bw + inner;
        let mut blocks = Vec::new();
        for (l, &o_l) in off.iter().enumerate() {
            for o2 in 0..=l / inner {
                blocks.push((l, o_l * (stride - 1) + o2 * so + bw, o2 * inner));
            }
        }
        let mut grid = vec![0; n_u * n_v];
        for i in 0..n_u {
            for j in 0..n_v {
                grid[pos(i, j)] = i * n_v + j;
            }
        }
        Pattern { n_u, n_v, p, q, bw, u_major, nb: ab.len(), off, ab, inner, stride, blocks, grid }
    }

    pub(super) fn n(&self) -> usize {
        self.n_u * self.n_v
    }

    pub(super) fn pos(&self, i: usize, j: usize) -> usize {
        if self.u_major {
            i * self.n_v + j
        } else {
            j * self.n_u + i
        }
    }
}

/// The B-spline products of every offset (and, for parameter optimisation, their derivatives
/// in `u` and `v`), independent of the weights.
#[derive(Clone, Debug, Default)]
pub(crate) struct BasisTable {
    /// Band position of each offset's first control point.
    pub(super) first: Vec<usize>,
    /// `m nb` products, local order.
    pub(super) vals: Vec<f64>,
    /// `d/du` of the products (empty unless asked for).
    pub(super) du: Vec<f64>,
    /// `d/dv` of the products (empty unless asked for).
    pub(super) dv: Vec<f64>,
    /// `N_{i0+a,p}(u_k)`, `p + 1` per offset, and `i0` of each offset.
    pub(super) nu: Vec<f64>,
    pub(super) i0: Vec<usize>,
    /// `N_{j0+b,q}(v_k)`, `q + 1` per offset.
    pub(super) nv: Vec<f64>,
    /// Runs `[k0, k1)` of consecutive offsets sharing one `v` (a skinned section): their
    /// contributions to `G` share the factor `N(v) N(v)^T` and are assembled together.
    pub(super) runs: Vec<(usize, usize)>,
}

impl WeightProblem {
    /// Basis products at `params` (clamped), with first derivatives if `derivs`.
    pub(crate) fn basis_table(&self, params: &[(f64, f64)], derivs: bool) -> BasisTable {
        let pat = &self.pat;
        let (p, q, nb) = (pat.p, pat.q, pat.nb);
        let m = params.len();
        let mut t = BasisTable {
            first: Vec::with_capacity(m),
            vals: Vec::with_capacity(m * nb),
            du: Vec::with_capacity(if derivs { m * nb } else { 0 }),
            dv: Vec::with_capacity(if derivs { m * nb } else { 0 }),
            nu: Vec::with_capacity(m * (p + 1)),
            i0: Vec::with_capacity(m),
            nv: Vec::with_capacity(m * (q + 1)),
            runs: Vec::new(),
        };
        let mut last_v = f64::NAN;
        let mut nu = [[0.0; MAX_DEGREE + 1]; 2];
        let mut nv = [[0.0; MAX_DEGREE + 1]; 2];
        for &(u, v) in params {
            let (u, v) = (self.ku.clamp(u), self.kv.clamp(v));
            let (su, sv) = (self.ku.find_span(u), self.kv.find_span(v));
            if derivs {
                ders_basis_funs(self.ku.as_slice(), su, u, p, 1, &mut nu);
                ders_basis_funs(self.kv.as_slice(), sv, v, q, 1, &mut nv);
            } else {
                let (mut bu, mut bv): (BasisRow, BasisRow) = ([0.0; MAX_DEGREE + 1], [0.0; MAX_DEGREE + 1]);
                basis_funs(self.ku.as_slice(), su, u, p, &mut bu);
                basis_funs(self.kv.as_slice(), sv, v, q, &mut bv);
                nu[0] = bu;
                nv[0] = bv;
            }
            t.first.push(pat.pos(su - p, sv - q));
            t.i0.push(su - p);
            t.nu.extend_from_slice(&nu[0][..=p]);
            t.nv.extend_from_slice(&nv[0][..=q]);
            let k = t.first.len() - 1;
            match t.runs.last_mut() {
                Some(r) if v == last_v => r.1 = k + 1,
                _ => t.runs.push((k, k + 1)),
            }
            last_v = v;
            for &(a, b) in &pat.ab {
                t.vals.push(nu[0][a] * nv[0][b]);
                if derivs {
                    t.du.push(nu[1][a] * nv[0][b]);
                    t.dv.push(nu[0][a] * nv[1][b]);
                }
            }
        }
        t
    }
}
