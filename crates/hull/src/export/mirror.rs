//! The full hull as one surface: the starboard half and its mirror image in the centre plane
//! (`y -> -y`) joined along the keel line: of the half's edges running along the ship, the one
//! nearest the centre plane.
//!
//! The rest of this module's documentation is on [`mirrored_full_hull`], where the library's users read it.

use nurbs::{KnotVector, NurbsSurface, Vec3};

use crate::error::{HullError, MirrorKind};

/// How far from the centre plane, relative to the control net's diagonal, the control points
/// of the edge to join along may lie: a fitted keel line sits on y = 0 to round-off.
pub const ON_CENTRE_PLANE_REL: f64 = 1e-9;

/// The full hull of the starboard half `surface`: one surface, port and starboard.
///
/// # The join
///
/// The two halves are joined along the keel line: of the half's edges running along the ship,
/// the one nearest the centre plane (`y = 0`). Along the parameter across that edge (say `u`,
/// with the edge at `u = a` and the half on `[a, b]`), the port half is the mirrored net in
/// reverse order and the starboard half follows (The NURBS Book 5.2, curves joined at a common
/// end point, C0 there):
///
/// * when the edge's control points lie on the centre plane (within 1e-9 of the net's size,
///   `ON_CENTRE_PLANE_REL`; by the convex hull property the edge curve lies there too), the two
///   halves share them: port on `[2a - b, a]`, the junction `a` of multiplicity `p`;
/// * otherwise (a flat of keel left open, as the offsets of a flat-bottomed hull give it) a
///   flat strip across the centre plane bridges the edge and its mirror image: one Bezier span
///   of degree `p` on `[a - d, a]` whose control points run evenly along the straight line
///   from each mirrored edge point to the edge point (a straight line, at the edge point's
///   weight: linear precision), port on `[a - d - (b - a), a - d]`.
///
/// Either way each half of the result is the half (or its mirror) point for point.
///
/// # Errors
/// [`HullError::Mirror`] when no edge of the surface runs along the ship, or the surface lies
/// port of the centre plane.
pub fn mirrored_full_hull(surface: &NurbsSurface) -> Result<NurbsSurface, HullError> {
    let (lo, hi) = surface.control_bounds();
    let tol = ON_CENTRE_PLANE_REL * (hi - lo).norm();
    let (nu, nv) = (surface.n_u(), surface.n_v());
    // Each edge: (across u, at the start of its parameter, its control points' largest |y|,
    // their x extent). The seam is the keel line: of the edges running along the ship (over
    // half its length: not a stem, a stern or a transom, which may lie on the centre plane
    // too), the one nearest the centre plane.
    let measure = |pts: &mut dyn Iterator<Item = Vec3>| {
        pts.fold((0.0_f64, f64::INFINITY, f64::NEG_INFINITY), |(y, a, b), p| (y.max(p.y.abs()), a.min(p.x), b.max(p.x)))
    };
    let edges = [
        (true, true, measure(&mut (0..nv).map(|j| surface.control_point(0, j)))),
        (true, false, measure(&mut (0..nv).map(|j| surface.control_point(nu - 1, j)))),
        (false, true, measure(&mut (0..nu).map(|i| surface.control_point(i, 0)))),
        (false, false, measure(&mut (0..nu).map(|i| surface.control_point(i, nv - 1)))),
    ];
    let &(across_u, at_start, (off, _, _)) = edges
        .iter()
        .filter(|e| e.2 .2 - e.2 .1 >= 0.5 * (hi.x - lo.x))
        .min_by(|a, b| a.2 .0.total_cmp(&b.2 .0))
        .ok_or(HullError::Mirror(MirrorKind::NoLongitudinalEdge))?;
    // A fitted half may dip a little port of the centre plane (the validity check says so);
    // a surface wholly port of it is no starboard half.
    if !(hi.y > tol) {
        return Err(HullError::Mirror(MirrorKind::PortSide { largest_y: hi.y }));
    }
    // Work across u with the edge at the start; transpose or reverse to get there and back.
    let mut s = if across_u { surface.clone() } else { surface.transposed() };
    if !at_start {
        s = s.reversed_u();
    }
    let joined = join_mirror_u(&s, off > tol)?;
    Ok(if across_u { joined } else { joined.transposed() })
}

/// The mirror image of `s` in `y = 0` joined to `s` along its `u = a` edge, across a flat
/// strip when `bridge` (see [`mirrored_full_hull`]).
fn join_mirror_u(s: &NurbsSurface, bridge: bool) -> Result<NurbsSurface, HullError> {
    let p = s.degree_u();
    let k = s.knots_u().as_slice();
    let (a, b) = (k[0], k[k.len() - 1]);
    let (nu, nv) = (s.n_u(), s.n_v());
    // The strip's parameter length: one average span of the half.
    let d = if bridge { (b - a) / (nu - p) as f64 } else { 0.0 };
    // Port: the knots reflected about c = a - d/2, so that it ends at a - d; its end clamp
    // kept p times with a bridge (the strip's span starts there), dropped otherwise (the
    // starboard knots from a bring the junction's p).
    let c = a - 0.5 * d;
    let mut knots: Vec<f64> = k.iter().rev().map(|&t| 2.0 * c - t).collect();
    knots.truncate(knots.len() - if bridge { 1 } else { p + 1 });
    knots.extend_from_slice(&k[1..]);
    let ku = KnotVector::try_new(p, knots).map_err(|e| HullError::Mirror(MirrorKind::Kernel(e)))?;
    let strip = if bridge { p - 1 } else { 0 };
    let mut pts = Vec::with_capacity((2 * nu + strip) * nv);
    let mut w = Vec::with_capacity((2 * nu + strip) * nv);
    let mirror = |q: Vec3| Vec3::new(q.x, -q.y, q.z);
    for i in (usize::from(!bridge)..nu).rev() {
        for j in 0..nv {
            pts.push(mirror(s.control_point(i, j)));
            w.push(s.weight(i, j));
        }
    }
    for t in 1..=strip {
        for j in 0..nv {
            let q = s.control_point(0, j);
            pts.push(mirror(q) + (q - mirror(q)) * (t as f64 / p as f64));
            w.push(s.weight(0, j));
        }
    }
    for i in 0..nu {
        for j in 0..nv {
            pts.push(s.control_point(i, j));
            w.push(s.weight(i, j));
        }
    }
    NurbsSurface::try_new(ku, s.knots_v().clone(), &pts, Some(&w)).map_err(|e| HullError::Mirror(MirrorKind::Kernel(e)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{fit_offsets, series60_sample, FitConfig};

    /// Both halves of `full` are `half` and its mirror image, point for point; the strip
    /// between them (of parameter length `d`) is flat, in the plane of the keel's points.
    fn check_halves(half: &NurbsSurface, full: &NurbsSurface, d: f64) {
        let ((u0, u1), (v0, v1)) = (half.domain_u(), half.domain_v());
        let ((f0, f1), g) = (full.domain_u(), full.domain_v());
        assert!((f1 - f0 - (2.0 * (u1 - u0) + d)).abs() <= 1e-12 * (u1 - u0) && g == (v0, v1), "{:?}", full.domain_u());
        let scale = 1.0 + half.control_bounds().1.norm();
        // Port at the parameter reflected about the middle of the strip.
        let c = u0 - 0.5 * d;
        for a in 0..=10 {
            for e in 0..=10 {
                let (u, v) = (u0 + (u1 - u0) * a as f64 / 10.0, v0 + (v1 - v0) * e as f64 / 10.0);
                let p = half.point(u, v);
                // Joined nets evaluate the same basis on each side: round-off only.
                let q = full.point(u, v);
                assert!((q - p).norm() <= 1e-12 * scale, "starboard at ({u}, {v}): {q:?} vs {p:?}");
                let m = full.point(2.0 * c - u, v);
                assert!((m - Vec3::new(p.x, -p.y, p.z)).norm() <= 1e-12 * scale, "port at ({u}, {v}): {m:?}");
                if d > 0.0 {
                    // The strip: the keel point's x and z, y between its mirror and itself.
                    let keel = half.point(u0, v);
                    let s = full.point(u0 - d * a as f64 / 10.0, v);
                    assert!((s.x - keel.x).abs() + (s.z - keel.z).abs() <= 1e-12 * scale, "strip at {v}: {s:?}");
                    assert!(s.y.abs() <= keel.y.abs() + 1e-12 * scale, "strip at {v}: {s:?} vs {keel:?}");
                }
            }
        }
    }

    #[test]
    fn a_flat_of_keel_is_bridged_and_each_half_is_kept() {
        // The sample's sections start on the flat of keel (z = 0, y up to 5.8 m): a strip.
        let half = fit_offsets(&series60_sample(), &FitConfig::default()).expect("the sample fits").surface;
        assert!(half.control_point(0, half.n_v() / 2).y > 1.0, "a flat of keel");
        let full = mirrored_full_hull(&half).expect("mirrors");
        let d = (full.domain_u().1 - full.domain_u().0) - 2.0 * (half.domain_u().1 - half.domain_u().0);
        assert!(d > 0.0, "a strip");
        check_halves(&half, &full, d);
        // Any edge is found: transposed, the same full hull transposed.
        assert_eq!(mirrored_full_hull(&half.transposed()).expect("a v edge"), full.transposed());
    }

    #[test]
    fn a_keel_on_the_centre_plane_is_shared() {
        // The Wigley hull's keel line lies on y = 0: the halves share it, no strip.
        let o = crate::read_offsets(
            &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/wigley_offsets.csv"),
            crate::Units::Metre,
        )
        .expect("reads");
        let half = fit_offsets(&o, &FitConfig::default()).expect("fits").surface;
        let full = mirrored_full_hull(&half).expect("mirrors");
        assert_eq!(full.n_u(), 2 * half.n_u() - 1);
        check_halves(&half, &full, 0.0);
    }

    #[test]
    fn a_surface_port_of_the_centre_plane_is_refused() {
        let half = fit_offsets(&series60_sample(), &FitConfig::default()).expect("fits").surface;
        let pts: Vec<Vec3> = half.control_points().iter().map(|p| Vec3::new(p.x, p.y - 20.0, p.z)).collect();
        let off = NurbsSurface::try_new(half.knots_u().clone(), half.knots_v().clone(), &pts, Some(&half.weights()))
            .expect("valid");
        let err = mirrored_full_hull(&off).expect_err("port of y = 0").to_string();
        assert!(err.contains("starboard half"), "{err}");
    }
}
