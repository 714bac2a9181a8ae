//! Brent's methods in one dimension: a root in a bracket and a maximum on an interval, without
//! derivatives (the root of a coordinate's level set along an iso-curve, [`crate::IsoCurve`];
//! the extreme of a function along a curve).

/// A root of `f` in `[a, b]` where `fa = f(a)` and `fb = f(b)` have opposite signs (or one
/// is zero), by Brent's method (Brent 1973, "Algorithms for Minimization without Derivatives",
/// ch. 4, procedure `zero`): inverse quadratic interpolation and secant steps safeguarded by
/// bisection, to `4 eps |x| + xtol`.
///
/// ```
/// let f = |x: f64| x * x - 2.0;
/// let r = nurbs::brent_root(f, 0.0, 2.0, f(0.0), f(2.0), 0.0);
/// assert!((r - 2f64.sqrt()).abs() <= 4.0 * f64::EPSILON * 2f64.sqrt());
/// ```
pub fn brent_root(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, fa: f64, fb: f64, xtol: f64) -> f64 {
    if fa == 0.0 {
        return a;
    }
    if fb == 0.0 {
        return b;
    }
    let (mut a, mut b, mut fa, mut fb) = (a, b, fa, fb);
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
    for _ in 0..200 {
        if (fb > 0.0) == (fc > 0.0) {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * xtol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return b;
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qq = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0));
                q = (qq - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b);
    }
    b
}

/// The maximum of `f` on `[a, b]` by Brent's method (Brent 1973, ch. 5, procedure
/// `localmin`: golden-section steps accelerated by parabolic interpolation), to the
/// tolerance `sqrt(eps) |x| + xtol`; returns `(x, f(x))`, the best point evaluated, the ends
/// `a` and `b` included (so a maximum at an end is found exactly).
pub fn brent_max(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, xtol: f64) -> (f64, f64) {
    let c = 0.5 * (3.0 - 5f64.sqrt());
    let sqrt_eps = f64::EPSILON.sqrt();
    let mut best = (a, f(a));
    let fb_end = f(b);
    if fb_end > best.1 {
        best = (b, fb_end);
    }
    // Minimise g = -f.
    let (mut lo, mut hi) = (a.min(b), a.max(b));
    let mut x = lo + c * (hi - lo);
    let (mut w, mut v) = (x, x);
    let mut fx = -f(x);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e) = (0.0f64, 0.0f64);
    for _ in 0..200 {
        if -fx > best.1 {
            best = (x, -fx);
        }
        let m = 0.5 * (lo + hi);
        let tol = sqrt_eps * x.abs() + xtol / 3.0;
        let t2 = 2.0 * tol;
        if (x - m).abs() <= t2 - 0.5 * (hi - lo) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol {
            // Parabola through x, w, v.
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            let r = e;
            e = d;
            if p.abs() < (0.5 * q * r).abs() && p > q * (lo - x) && p < q * (hi - x) {
                d = p / q;
                let u = x + d;
                if u - lo < t2 || hi - u < t2 {
                    d = if x < m { tol } else { -tol };
                }
                golden = false;
            }
        }
        if golden {
            e = if x < m { hi - x } else { lo - x };
            d = c * e;
        }
        let u = if d.abs() >= tol {
            x + d
        } else if d > 0.0 {
            x + tol
        } else {
            x - tol
        };
        let fu = -f(u);
        if fu <= fx {
            if u < x {
                hi = x;
            } else {
                lo = x;
            }
            v = w;
            fv = fw;
            w = x;
            fw = fx;
            x = u;
            fx = fu;
        } else {
            if u < x {
                lo = u;
            } else {
                hi = u;
            }
            if fu <= fw || w == x {
                v = w;
                fv = fw;
                w = u;
                fw = fu;
            } else if fu <= fv || v == x || v == w {
                v = u;
                fv = fu;
            }
        }
    }
    if -fx > best.1 {
        best = (x, -fx);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    #[test]
    fn brent_finds_roots_to_round_off() {
        let f = |x: f64| x * x * x - 2.0;
        let r = brent_root(f, 0.0, 3.0, f(0.0), f(3.0), 0.0);
        // The cube root of 2 to a few ulps.
        assert_near!(r, 2f64.cbrt(), 4.0 * f64::EPSILON * 2.0);
        // Zero at an end is returned as is.
        assert_eq!(brent_root(|x| x - 1.0, 1.0, 2.0, 0.0, 1.0, 0.0), 1.0);
        // A flat then steep function (a curve leaving a flat).
        let g = |x: f64| (x - 0.9).max(0.0).powi(3) - 1e-6;
        let r = brent_root(g, 0.0, 1.0, g(0.0), g(1.0), 0.0);
        assert_near!(r, 0.91, 1e-14);
    }

    #[test]
    fn brent_max_finds_an_interior_and_an_end_maximum_in_few_steps() {
        let mut calls = 0;
        let (x, fx) = brent_max(
            |x| {
                calls += 1;
                (3.0 * x).sin() - (x - 0.3).powi(4)
            },
            0.0,
            1.0,
            1e-12,
        );
        // sin(3x) peaks at pi/6 = 0.5236; the quartic moves it a little. The location to
        // about sqrt(eps) (a flat maximum), the value to round-off.
        let x_true = {
            // Newton on the derivative 3 cos(3x) - 4 (x - 0.3)^3.
            let mut t: f64 = 0.52;
            for _ in 0..50 {
                let g = 3.0 * (3.0 * t).cos() - 4.0 * (t - 0.3f64).powi(3);
                let h = -9.0 * (3.0 * t).sin() - 12.0 * (t - 0.3f64).powi(2);
                t -= g / h;
            }
            t
        };
        assert_near!(x, x_true, 1e-7);
        assert_near!(fx, (3.0 * x_true).sin() - (x_true - 0.3).powi(4), 1e-15);
        assert!(calls < 40, "{calls} evaluations");
        // Monotone: the end.
        let (x, _) = brent_max(|x| x, 0.0, 1.0, 0.0);
        assert_eq!(x, 1.0);
    }
}
