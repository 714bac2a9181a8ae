//! Gauss-Legendre quadrature, the one rule of the workspace: the fitting energies of the
//! kernel and the surface integrals of the crates above it (fairness, hydrostatics) all take it
//! from here.

/// Gauss-Legendre nodes and weights on `[-1, 1]`: `int_{-1}^{1} f = sum_k w_k f(x_k)`, exact
/// for polynomials of degree `2 n - 1`.
///
/// ```
/// use nurbs::GaussLegendre;
/// // Three points integrate x^4 exactly: int_0^2 x^4 dx = 32 / 5.
/// let q: f64 = GaussLegendre::new(3).on(0.0, 2.0).map(|(x, w)| w * x.powi(4)).sum();
/// assert!((q - 6.4).abs() < 1e-14);
/// // ... but not x^6 (degree 2 n = 6): int_0^2 x^6 dx = 128 / 7.
/// let q: f64 = GaussLegendre::new(3).on(0.0, 2.0).map(|(x, w)| w * x.powi(6)).sum();
/// assert!((q - 128.0 / 7.0).abs() > 1e-3);
/// ```
#[derive(Clone, Debug)]
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl GaussLegendre {
    /// The `n`-point rule (`n >= 1`). The nodes are the roots of the Legendre polynomial
    /// `P_n`, found by Newton's method from Tricomi's estimate `cos(pi (k + 3/4) / (n + 1/2))`,
    /// with `P_n` from the three-term recurrence `(j+1) P_{j+1} = (2j+1) x P_j - j P_{j-1}`;
    /// the weights are `w_k = 2 / ((1 - x_k^2) P_n'(x_k)^2)` (Abramowitz & Stegun 25.4.29).
    pub fn new(n: usize) -> Self {
        let n = n.max(1);
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as f64;
        for k in 0..n.div_ceil(2) {
            let mut x = (std::f64::consts::PI * (k as f64 + 0.75) / (nf + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() <= 1e-16 * x.abs().max(1.0) {
                    let (_, d) = legendre(n, x);
                    dp = d;
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            // Symmetric pairs, the node of the middle (odd n) is 0.
            nodes[k] = -x;
            nodes[n - 1 - k] = x;
            weights[k] = w;
            weights[n - 1 - k] = w;
        }
        if n % 2 == 1 {
            nodes[n / 2] = 0.0;
        }
        GaussLegendre { nodes, weights }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the rule has no node (never: `new` makes at least one).
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The nodes on `[-1, 1]`, ascending.
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// The weights of [`GaussLegendre::nodes`].
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The nodes and weights mapped onto `[a, b]`, ascending.
    pub fn on(&self, a: f64, b: f64) -> impl Iterator<Item = (f64, f64)> + '_ {
        let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
        self.nodes.iter().zip(&self.weights).map(move |(&x, &w)| (m + h * x, h * w))
    }
}

/// `P_n(x)` and `P_n'(x)`.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for j in 1..n {
        let jf = j as f64;
        let p2 = ((2.0 * jf + 1.0) * x * p1 - jf * p0) / (jf + 1.0);
        p0 = p1;
        p1 = p2;
    }
    let p = if n == 0 { 1.0 } else { p1 };
    // P_n'(x) = n (x P_n - P_{n-1}) / (x^2 - 1).
    let d = n as f64 * (x * p - p0) / (x * x - 1.0);
    (p, d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{assert_near, MAX_DEGREE};

    #[test]
    fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
        for n in [1, 2, 3, 5, 8, 16, 24] {
            let gl = GaussLegendre::new(n);
            assert_eq!(gl.len(), n);
            // int_a^b x^k dx = (b^(k+1) - a^(k+1)) / (k + 1) on a non-symmetric interval.
            let (a, b) = (-0.3, 1.7);
            for k in 0..2 * n {
                let q: f64 = gl.on(a, b).map(|(x, w)| w * x.powi(k as i32)).sum();
                let exact = (b.powi(k as i32 + 1) - a.powi(k as i32 + 1)) / (k as f64 + 1.0);
                // Round-off of n terms of size up to 1.7^47: relative 1e-13.
                assert_near!(q, exact, 1e-13 * exact.abs().max(1.0), "n {n} k {k}");
            }
        }
    }

    #[test]
    fn gauss_legendre_nodes_ascend_and_weights_sum_to_the_length() {
        let gl = GaussLegendre::new(9);
        let nodes: Vec<(f64, f64)> = gl.on(2.0, 5.0).collect();
        assert!(nodes.windows(2).all(|w| w[0].0 < w[1].0));
        assert!(nodes.iter().all(|&(x, w)| (2.0..=5.0).contains(&x) && w > 0.0));
        // Weights sum to b - a up to round-off.
        assert_near!(nodes.iter().map(|n| n.1).sum::<f64>(), 3.0, 1e-14);
    }

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        for m in 1..=MAX_DEGREE {
            let gl = GaussLegendre::new(m);
            let (x, w) = (gl.nodes(), gl.weights());
            for d in 0..2 * m {
                let q: f64 = x.iter().zip(w).map(|(xi, wi)| wi * xi.powi(d as i32)).sum();
                let exact = if d % 2 == 1 { 0.0 } else { 2.0 / (d + 1) as f64 };
                // Sums of m <= 15 terms of size <= 2: a few ulps each.
                assert_near!(q, exact, 1e-14, "m {m} degree {d}");
            }
        }
    }
}
