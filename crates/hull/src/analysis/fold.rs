//! Folds of a skinned hull surface: where it runs backwards across its sections.
//!
//! The rest of this module's documentation is on [`find_folds`], where the library's users read it.

use nurbs::NurbsSurface;
use serde::Serialize;

/// A band of x over which the surface folds back across its sections.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Fold {
    /// Lowest and highest x of the folded samples.
    pub x: (f64, f64),
    /// Parameter range across the sections `(v0, v1)` of the folded samples.
    pub v: (f64, f64),
    /// Folded samples in the band.
    pub samples: usize,
    /// Samples of the grid lines across the band (the folded ones among them).
    pub of: usize,
}

/// Samples per knot span in each direction: enough to see a fold confined to one span between
/// two close sections (Gunnerus's is 0.17 m wide between stations 0.58 m apart).
pub(crate) const PER_SPAN: usize = 8;

/// The folds of `surface` (u along the sections, v across them): contiguous runs of the grid's
/// v lines on which some sample has `x_v` of the sign opposite to the majority's, larger than
/// 1e-9 of the surface's x extent per unit parameter (where sections share an x, as at a
/// transom, `x_v` is zero to round-off and is not a fold), and faces the other way there (its
/// normal turned over with it: see below). Empty for a surface that advances in x
/// everywhere, or one with no extent in x. The folds that
/// [`check_validity`](super::check_validity) reports, on the same grid.
///
/// # What a fold is
///
/// A hull skinned over stations advances in x from one section to the next, so the derivative
/// across the sections keeps one sign: `x_v = ∂x/∂v` of `S(u, v)`. Where it turns the other way
/// and the normal `S_u × S_v` turns over with it (faces inwards there), the surface doubles
/// back on itself and a CAD system sees a self-intersecting skin. Where `x_v` turns but the
/// normal keeps its side, the surface does not double back: along a steep stern or stem
/// profile the sections' v lines run mostly up and down, and the keel line may run a little
/// aft as it drops (the MATLAB trawler's data itself does, 9 mm between its 3rd and 4th
/// sections); that is no fold. Uneven spacing of the sections' parameters causes it
/// (a deck line jumping several metres between two close stations, R/V Gunnerus's forecastle
/// step): the cure is a parameterization across the sections less driven by those jumps
/// (centripetal) or fewer control points across.
///
/// [`find_folds`] samples `x_v` and the normal on a grid refined at every knot span and reports
/// the bands of x where `x_v` has the sign opposite to the surface's majority and the normal
/// faces the other way.
pub fn find_folds(surface: &NurbsSurface) -> Vec<Fold> {
    super::validity::validity_and_folds(surface, &super::Envelope::unbounded(), &[]).1
}

/// The folds of `surface` from samples `(x, x_v)` on the v lines `vs` (`rows[j]` on `vs[j]`),
/// with the majority's sign of `x_v` (+1 when the surface advances in x with v, -1 when it
/// runs aft; +1 for a surface with no extent in x, which has no fold).
pub(crate) fn folds_on_grid(surface: &NurbsSurface, vs: &[f64], rows: &[Vec<(f64, f64)>]) -> (Vec<Fold>, f64) {
    let (lo, hi) = surface.control_bounds();
    let (v0, v1) = surface.domain_v();
    let extent = hi.x - lo.x;
    if !(extent > 0.0) || !(v1 > v0) {
        return (Vec::new(), 1.0);
    }
    let tol = 1e-9 * extent / (v1 - v0);
    let balance: f64 = rows.iter().flatten().map(|&(_, xv)| if xv.abs() > tol { xv.signum() } else { 0.0 }).sum();
    let sign = if balance < 0.0 { -1.0 } else { 1.0 };
    let folded = |xv: f64| sign * xv < -tol;
    let mut folds: Vec<Fold> = Vec::new();
    let mut open = false;
    for (j, row) in rows.iter().enumerate() {
        let bad: Vec<f64> = row.iter().filter(|&&(_, xv)| folded(xv)).map(|&(x, _)| x).collect();
        if bad.is_empty() {
            open = false;
            continue;
        }
        let (xmin, xmax) = bad.iter().fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        match folds.last_mut().filter(|_| open) {
            Some(f) => {
                f.x = (f.x.0.min(xmin), f.x.1.max(xmax));
                f.v.1 = vs[j];
                f.samples += bad.len();
                f.of += row.len();
            }
            None => folds.push(Fold { x: (xmin, xmax), v: (vs[j], vs[j]), samples: bad.len(), of: row.len() }),
        }
        open = true;
    }
    (folds, sign)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::{KnotVector, Vec3};

    /// A ruled-in-u (2 rows of poles), cubic-in-v surface on uniform knots whose pole `(i, j)`
    /// is `pole(i, j, xs[j])`.
    fn ruled(xs: &[f64], pole: impl Fn(usize, usize, f64) -> Vec3) -> NurbsSurface {
        let ku = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let n = xs.len();
        let mut kv = vec![0.0; 4];
        kv.extend((1..n - 3).map(|i| i as f64 / (n - 3) as f64));
        kv.extend([1.0; 4]);
        let kv = KnotVector::try_new(3, kv).expect("valid");
        let pts: Vec<Vec3> = (0..2)
            .flat_map(|i| xs.iter().enumerate().map(move |(j, &x)| (i, j, x)))
            .map(|(i, j, x)| pole(i, j, x))
            .collect();
        NurbsSurface::try_new(ku, kv, &pts, None).expect("valid")
    }

    /// A ruled-in-u, cubic-in-v strip over x with the x of its poles across given by `xs`
    /// (y, z from the pole's indices): x_v follows the differences of `xs`.
    fn strip(xs: &[f64]) -> NurbsSurface {
        ruled(xs, |i, _, x| Vec3::new(x, 1.0 + 0.1 * x, i as f64))
    }

    #[test]
    fn a_surface_advancing_in_x_has_no_fold() {
        assert!(find_folds(&strip(&[0.0, 1.0, 2.0, 3.5, 5.0, 6.0, 7.0])).is_empty());
        // Two sections at one x (a transom's edge and its hull section): x_v = 0, not a fold.
        assert!(find_folds(&strip(&[0.0, 0.0, 0.0, 0.0, 2.0, 4.0, 6.0])).is_empty());
        // Running aft (x decreasing throughout) is the majority's direction: no fold either.
        assert!(find_folds(&strip(&[7.0, 6.0, 5.0, 3.5, 2.0, 1.0, 0.0])).is_empty());
    }

    /// A ruled-in-u, cubic-in-v strip down a steep profile: the poles' x from `xs`, z falling
    /// 10 per pole, y from the pole's index across. `S_u x S_v = (0, 1, 0) x (x_v, 0, z_v) =
    /// (z_v, 0, -x_v)` keeps its side wherever `z_v < 0`, whatever `x_v` does.
    fn steep(xs: &[f64]) -> NurbsSurface {
        ruled(xs, |i, j, x| Vec3::new(x, i as f64, -10.0 * j as f64))
    }

    /// True if `x_v` turns somewhere along the middle u line.
    fn turns(s: &NurbsSurface) -> bool {
        (0..=1000).any(|k| s.derivatives(0.5, k as f64 / 1000.0).sv.x < 0.0)
    }

    /// The trawler's stern (issue 11): down a steep profile the keel line runs back a little
    /// (poles' x 200.3, 200.1, 200.4 over a 400 long strip). `x_v` turns, the normal keeps its
    /// side and the run back is far within [`FOLD_RUN_REL`](super::super::FOLD_RUN_REL) of the
    /// length: no fold. The same x on a level strip turns the normal over: a fold.
    #[test]
    fn a_steep_profile_running_back_a_little_is_no_fold() {
        let xs = [0.0, 100.0, 200.0, 200.3, 200.1, 200.4, 300.0, 400.0];
        let s = steep(&xs);
        assert!(turns(&s), "the test needs x_v to turn");
        assert!(find_folds(&s).is_empty());
        assert!(turns(&strip(&xs)));
        assert_eq!(find_folds(&strip(&xs)).len(), 1);
    }

    /// A hook: down the same steep profile the surface runs back by 8 % of its length (poles
    /// 4 then 3 over 6) without turning over. That is a fold, reported with the run-back
    /// allowance as its limit.
    #[test]
    fn a_steep_profile_running_back_far_is_a_fold() {
        let s = steep(&[0.0, 1.0, 2.0, 4.0, 3.0, 5.0, 6.0]);
        assert_eq!(find_folds(&s).len(), 1);
        let findings = super::super::check_validity(&s, &super::super::Envelope::unbounded(), &[]);
        let fold = findings.iter().find(|f| f.kind == super::super::FindingKind::Fold).expect("a fold");
        // The allowance: FOLD_RUN_REL of the control net's x extent, 6.
        assert!((fold.limit - 6e-3).abs() < 1e-15 && fold.size > fold.limit, "{fold:?}");
        // Said as a hook, not as a self-intersection.
        let message = fold.message("m");
        assert!(message.contains("hooks back") && !message.contains("self-intersecting"), "{message}");
    }

    #[test]
    fn a_pole_pulled_back_past_its_neighbour_folds_the_surface_there() {
        // Poles 3 and 4 swap order in x: x_v < 0 around v of pole 3.5 only.
        let s = strip(&[0.0, 1.0, 2.0, 4.0, 3.0, 5.0, 6.0, 7.0, 8.0]);
        let folds = find_folds(&s);
        assert_eq!(folds.len(), 1, "{folds:?}");
        let f = folds[0];
        // x_v of a cubic B-spline is a quadratic B-spline on the differences of the poles
        // (NURBS Book eq. 3.4): negative only where the -1 difference dominates, inside the
        // x range of the swapped poles.
        assert!(f.x.0 > 2.0 && f.x.1 < 5.0, "{f:?}");
        assert!(f.samples > 0 && f.samples <= f.of, "{f:?}");
        // Every u sample on a folded v line is folded (the strip is ruled in u).
        assert_eq!(f.samples, f.of, "{f:?}");
        // The band is where x_v < 0: check it against the derivative directly.
        let mid = 0.5 * (f.v.0 + f.v.1);
        assert!(s.derivatives(0.5, mid).sv.x < 0.0);
    }
}
