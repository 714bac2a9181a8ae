//! The fairness energy of a control net: second differences of the control points, the
//! discrete surrogate of the thin-plate energy `∫∫ |S_uu|^2 + 2 |S_uv|^2 + |S_vv|^2`
//! (P-splines: Eilers and Marx, *Flexible smoothing with B-splines and penalties*, Statistical
//! Science 11 (1996); the surface form in The NURBS Book's fairing references).
//!
//! The rest of this module's documentation is on [`WeightOptions::fair`](super::WeightOptions::fair),
//! where the library's users read it.

use nurbs::KnotVector;

/// One row of `D`: up to four `(control index i n_v + j, coefficient)` entries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stencil {
    pub entries: [(usize, f64); 4],
    pub len: usize,
}

impl Stencil {
    fn new(entries: &[(usize, f64)]) -> Self {
        let mut e = [(0, 0.0); 4];
        e[..entries.len()].copy_from_slice(entries);
        Stencil { entries: e, len: entries.len() }
    }

    /// The non-zero entries.
    pub fn entries(&self) -> &[(usize, f64)] {
        &self.entries[..self.len]
    }
}

/// The difference operator `D` of a control net (see [`WeightOptions::fair`](super::WeightOptions::fair)).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NetEnergy {
    rows: Vec<Stencil>,
}

/// Control rows (along one direction) on which the surface is only C0: `s - 1` for every
/// interior knot of multiplicity `>= degree` starting at index `s`.
fn crease_rows(knots: &KnotVector) -> Vec<usize> {
    let p = knots.degree();
    let k = knots.as_slice();
    let mut rows = Vec::new();
    let mut s = p + 1;
    let end = k.len() - p - 1;
    while s < end {
        let mut e = s;
        while e + 1 < end && k[e + 1] == k[s] {
            e += 1;
        }
        if e + 1 - s >= p {
            rows.push(s - 1);
        }
        s = e + 1;
    }
    rows
}

impl NetEnergy {
    /// The operator of an `n_u x n_v` net on knots `ku` (along u, index `i`) and `kv` (index
    /// `j`), creases left out (see [`WeightOptions::fair`](super::WeightOptions::fair)).
    pub fn new(n_u: usize, n_v: usize, ku: &KnotVector, kv: &KnotVector) -> Self {
        let c = |i: usize, j: usize| i * n_v + j;
        let (cu, cv) = (crease_rows(ku), crease_rows(kv));
        let mut rows = Vec::new();
        // Along u (i), for every j.
        for j in 0..n_v {
            if ku.degree() >= 2 {
                for i in 1..n_u.saturating_sub(1) {
                    if !cu.contains(&i) {
                        rows.push(Stencil::new(&[(c(i - 1, j), 1.0), (c(i, j), -2.0), (c(i + 1, j), 1.0)]));
                    }
                }
            } else {
                for i in 1..n_u {
                    rows.push(Stencil::new(&[(c(i - 1, j), -1.0), (c(i, j), 1.0)]));
                }
            }
        }
        // Along v (j), for every i.
        for i in 0..n_u {
            if kv.degree() >= 2 {
                for j in 1..n_v.saturating_sub(1) {
                    if !cv.contains(&j) {
                        rows.push(Stencil::new(&[(c(i, j - 1), 1.0), (c(i, j), -2.0), (c(i, j + 1), 1.0)]));
                    }
                }
            } else {
                for j in 1..n_v {
                    rows.push(Stencil::new(&[(c(i, j - 1), -1.0), (c(i, j), 1.0)]));
                }
            }
        }
        // Twist, weight 2 in E (sqrt 2 in D).
        let t = std::f64::consts::SQRT_2;
        for i in 0..n_u.saturating_sub(1) {
            for j in 0..n_v.saturating_sub(1) {
                rows.push(Stencil::new(&[(c(i, j), t), (c(i + 1, j), -t), (c(i, j + 1), -t), (c(i + 1, j + 1), t)]));
            }
        }
        NetEnergy { rows }
    }

    /// The rows of `D`.
    pub fn rows(&self) -> &[Stencil] {
        &self.rows
    }

    /// Number of rows of `D`.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether `D` has no row (a net too small to have a second difference).
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// `E = |D P|^2` of the net `point(c)`, `c = i n_v + j`.
    pub fn value(&self, point: impl Fn(usize) -> [f64; 3]) -> f64 {
        self.rows
            .iter()
            .map(|r| {
                let mut acc = [0.0; 3];
                for &(c, w) in r.entries() {
                    let p = point(c);
                    for d in 0..3 {
                        acc[d] += w * p[d];
                    }
                }
                acc[0] * acc[0] + acc[1] * acc[1] + acc[2] * acc[2]
            })
            .sum()
    }

    /// The entries of `D^T D` on and below the diagonal, as `(row c, column c', value)` with
    /// `c >= c'` in the ordering `order(c)` (each pair once, summed).
    pub fn gram_lower(&self, order: impl Fn(usize) -> usize) -> Vec<(usize, usize, f64)> {
        let mut map = std::collections::BTreeMap::new();
        for r in &self.rows {
            for &(a, wa) in r.entries() {
                for &(b, wb) in r.entries() {
                    let (pa, pb) = (order(a), order(b));
                    if pa >= pb {
                        *map.entry((pa, pb)).or_insert(0.0) += wa * wb;
                    }
                }
            }
        }
        map.into_iter().map(|((a, b), v)| (a, b, v)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn knots(p: usize, n: usize) -> KnotVector {
        KnotVector::uniform(p, n).expect("valid")
    }

    #[test]
    fn a_net_linear_in_its_indices_has_no_energy_and_a_bump_has_some() {
        let (nu, nv) = (5, 6);
        let e = NetEnergy::new(nu, nv, &knots(3, nu), &knots(3, nv));
        // Rows: (nu - 2) nv along u, nu (nv - 2) along v, (nu - 1)(nv - 1) twists.
        assert_eq!(e.len(), 3 * 6 + 5 * 4 + 4 * 5);
        let linear = |c: usize| {
            let (i, j) = ((c / nv) as f64, (c % nv) as f64);
            [2.0 * i + 0.5 * j, -j, 3.0 + i - j]
        };
        // Zero but for the round-off of the sqrt(2) twist weights on numbers of size ~10.
        assert!(e.value(linear) < 1e-24, "{}", e.value(linear));
        // One point lifted by h: its own u and v rows (-2h each), the four neighbours' rows
        // (h each, two in u and two in v), and the four twists touching it (sqrt 2 h each):
        // 4 h^2 + 4 h^2 + 4 h^2 + 4 * 2 h^2 = 20 h^2 for an interior point.
        let h = 0.25;
        let bumped = |c: usize| {
            let mut p = linear(c);
            if c == 2 * nv + 3 {
                p[2] += h;
            }
            p
        };
        assert!((e.value(bumped) - 20.0 * h * h).abs() < 1e-12, "{}", e.value(bumped));
    }

    #[test]
    fn second_differences_across_a_crease_are_left_out() {
        // u knots with a triple interior knot (degree 3): C0 at control row 3.
        let ku = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.5, 0.5, 0.5, 1., 1., 1., 1.]).expect("valid");
        assert_eq!(crease_rows(&ku), vec![3]);
        assert_eq!(crease_rows(&knots(3, 8)), Vec::<usize>::new());
        let (nu, nv) = (7, 4);
        let e = NetEnergy::new(nu, nv, &ku, &knots(3, nv));
        // A V-shaped net, kinked at row 3: no energy along u (each leg is straight).
        let v_shape = |c: usize| {
            let (i, j) = ((c / nv) as f64, (c % nv) as f64);
            [i, j, (i - 3.0).abs()]
        };
        let along_u: f64 = e.rows()[..nv * (nu - 3)]
            .iter()
            .map(|r| r.entries().iter().map(|&(c, w)| w * v_shape(c)[2]).sum::<f64>().powi(2))
            .sum();
        assert_eq!(along_u, 0.0);
        assert_eq!(e.value(v_shape), 0.0);
    }

    #[test]
    fn the_gram_matrix_gives_the_energy() {
        let (nu, nv) = (4, 5);
        let e = NetEnergy::new(nu, nv, &knots(2, nu), &knots(3, nv));
        let pt = |c: usize| [(c as f64 * 0.37).sin(), (c as f64 * 0.11).cos(), (c * c) as f64 * 0.01];
        let g = e.gram_lower(|c| c);
        let mut quad = 0.0;
        for &(a, b, v) in &g {
            let (pa, pb) = (pt(a), pt(b));
            let dotp = pa[0] * pb[0] + pa[1] * pb[1] + pa[2] * pb[2];
            quad += if a == b { v * dotp } else { 2.0 * v * dotp };
        }
        // Same sums in another order: round-off of a few hundred terms of size ~1.
        assert!((quad - e.value(pt)).abs() < 1e-12 * e.value(pt).max(1.0), "{quad} vs {}", e.value(pt));
    }
}
