//! External truth for the kernel's evaluation: points, first and second partial derivatives,
//! unit normals, Gaussian and mean curvature of six NURBS surfaces against values computed by
//! Open CASCADE 8.0.1 (`testdata/oracle/surfaces.json`, provenance in its README).
//!
//! The oracle's conventions (its `about` field): control points u-major `i * n_v + j`, full
//! clamped knot vectors, `normal = normalize(S_u x S_v)`, mean curvature positive when the
//! surface bends toward that normal -- the same as [`nurbs::Curvature`].
//!
//! At a parameter on an interior knot of multiplicity `s` the surface is only `C^(p - s)` in
//! that direction, so a derivative of order above `p - s` there is one-sided and depends on
//! which span an implementation picks (ours takes the span to the right). Such values are not
//! compared. The oracle's `about` names multiplicity >= 2; the rule `order <= p - s` also skips
//! the second u-derivatives of the degree-2 surface at its simple u-knots (`C^1` there).
//! (At those 6 values OCCT happens to agree with our right-hand span to round-off, but that
//! is a convention, not a fact to test.)

use nurbs::{KnotVector, NurbsSurface, SurfaceDerivatives, Vec3};
use serde_json::Value;

/// Both kernels evaluate in f64 with different algorithms (OCCT: its own basis recursion and
/// rational quotient; ours: A2.3 + A4.4). The oracle's README reports agreement to about 1e-12;
/// the largest differences measured here are printed by each test. 1e-10 relative to the
/// scale of each quantity on its surface leaves room for the conditioning of the rational
/// quotient (weights from 0.5 to 2) and for the cancellation in second derivatives, while any
/// wrong index, basis function or quotient term shows up as an O(1) relative error.
const REL: f64 = 1e-10;

fn oracle() -> Value {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../testdata/oracle/surfaces.json");
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {path}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path} is not JSON: {e}"))
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("expected a number, got {v}"))
}

fn nums(v: &Value) -> Vec<f64> {
    v.as_array().unwrap_or_else(|| panic!("expected an array, got {v}")).iter().map(num).collect()
}

fn vec3(v: &Value) -> Vec3 {
    let c = nums(v);
    assert_eq!(c.len(), 3, "expected 3 coordinates, got {v}");
    Vec3::new(c[0], c[1], c[2])
}

fn count(v: &Value) -> usize {
    usize::try_from(v.as_u64().unwrap_or_else(|| panic!("expected a count, got {v}"))).expect("small count")
}

/// One oracle surface, built through the public constructors.
struct Case {
    name: String,
    surface: NurbsSurface,
    samples: Vec<Value>,
}

fn cases() -> Vec<Case> {
    let data = oracle();
    let about = data["about"].as_str().expect("the oracle documents its conventions");
    assert!(about.contains("u-major") && about.contains("normalize(Su x Sv)"), "conventions changed: {about}");
    data["surfaces"]
        .as_array()
        .expect("a list of surfaces")
        .iter()
        .map(|entry| {
            let s = &entry["surface"];
            let name = s["name"].as_str().expect("named").to_string();
            let ku = KnotVector::try_new(count(&s["degree_u"]), nums(&s["knots_u"])).expect("valid u knots");
            let kv = KnotVector::try_new(count(&s["degree_v"]), nums(&s["knots_v"])).expect("valid v knots");
            assert_eq!((ku.num_basis(), kv.num_basis()), (count(&s["n_u"]), count(&s["n_v"])), "{name}");
            let points: Vec<Vec3> = s["ctrlpts"].as_array().expect("control points").iter().map(vec3).collect();
            let weights = (!s["weights"].is_null()).then(|| nums(&s["weights"]));
            let surface = NurbsSurface::try_new(ku, kv, &points, weights.as_deref()).expect("valid surface");
            let samples = entry["samples"].as_array().expect("samples").clone();
            assert!(!samples.is_empty(), "{name} has no samples");
            Case { name, surface, samples }
        })
        .collect()
}

/// The order of continuity of the surface at `t` in one direction: `p - s` on an interior knot
/// of multiplicity `s`, unbounded elsewhere.
fn continuity(kv: &KnotVector, t: f64) -> usize {
    kv.interior_breaks().iter().find(|b| b.0 == t).map_or(usize::MAX, |b| kv.degree() - b.1)
}

/// Tracks the largest relative difference of one quantity.
struct Worst {
    what: &'static str,
    rel: f64,
    at: String,
    compared: usize,
}

impl Worst {
    fn new(what: &'static str) -> Self {
        Worst { what, rel: 0.0, at: String::new(), compared: 0 }
    }

    /// Compare `ours` with `occt`, relative to `scale`.
    fn check(&mut self, case: &str, u: f64, v: f64, ours: Vec3, occt: Vec3, scale: f64) {
        let rel = (ours - occt).norm() / scale;
        assert!(
            rel <= REL,
            "{case}: {} at (u, v) = ({u}, {v}): ours {ours:?}, OCCT {occt:?}, relative difference {rel:e}",
            self.what
        );
        self.compared += 1;
        if rel > self.rel {
            self.rel = rel;
            self.at = format!("{case} ({u}, {v})");
        }
    }

    fn report(&self) {
        assert!(self.compared > 0, "{}: nothing compared", self.what);
        eprintln!(
            "{:>10}: {} samples, largest relative difference {:.1e} at {}",
            self.what, self.compared, self.rel, self.at
        );
    }
}

/// The largest norm of a sampled quantity over a surface, the scale its differences are
/// measured against (never below `floor`).
fn scale(samples: &[Value], key: &str, floor: f64) -> f64 {
    samples.iter().map(|s| vec3(&s[key]).norm()).fold(floor, f64::max)
}

fn uv(sample: &Value) -> (f64, f64) {
    (num(&sample["u"]), num(&sample["v"]))
}

#[test]
fn points_and_first_derivatives_match_occt() {
    let mut worst = [Worst::new("point"), Worst::new("S_u"), Worst::new("S_v")];
    for case in cases() {
        let s = &case.surface;
        let (lo, hi) = s.control_bounds();
        let size = (hi - lo).norm();
        let (su_scale, sv_scale) = (scale(&case.samples, "su", 0.0), scale(&case.samples, "sv", 0.0));
        for sample in &case.samples {
            let (u, v) = uv(sample);
            let d = s.derivatives(u, v);
            worst[0].check(&case.name, u, v, d.point, vec3(&sample["point"]), size);
            worst[0].check(&case.name, u, v, s.point(u, v), vec3(&sample["point"]), size);
            if continuity(s.knots_u(), u) >= 1 {
                worst[1].check(&case.name, u, v, d.su, vec3(&sample["su"]), su_scale);
            }
            if continuity(s.knots_v(), v) >= 1 {
                worst[2].check(&case.name, u, v, d.sv, vec3(&sample["sv"]), sv_scale);
            }
        }
    }
    worst.iter().for_each(Worst::report);
}

#[test]
fn second_derivatives_match_occt_where_defined() {
    let mut worst = [Worst::new("S_uu"), Worst::new("S_uv"), Worst::new("S_vv")];
    let mut skipped = 0;
    for case in cases() {
        let s = &case.surface;
        // One scale for all second derivatives of a surface: some vanish identically (S_vv of
        // a degree-1 direction, S_uv of the cylinder) and differ from OCCT by round-off only.
        let sc = ["suu", "suv", "svv"].map(|k| scale(&case.samples, k, 0.0)).into_iter().fold(0.0, f64::max);
        for sample in &case.samples {
            let (u, v) = uv(sample);
            let (cu, cv) = (continuity(s.knots_u(), u), continuity(s.knots_v(), v));
            let d = s.derivatives(u, v);
            let pairs = [(d.suu, "suu", cu >= 2), (d.suv, "suv", cu >= 1 && cv >= 1), (d.svv, "svv", cv >= 2)];
            for (k, (ours, key, defined)) in pairs.into_iter().enumerate() {
                if defined {
                    worst[k].check(&case.name, u, v, ours, vec3(&sample[key]), sc);
                } else {
                    skipped += 1;
                }
            }
        }
    }
    worst.iter().for_each(Worst::report);
    eprintln!("{skipped} one-sided second derivatives not compared");
}

/// The largest principal curvature `|H| + sqrt(H^2 - K)` over the samples of a surface.
fn curvature_scale(samples: &[Value]) -> f64 {
    samples
        .iter()
        .map(|s| {
            let (k, h) = (num(&s["gaussian"]), num(&s["mean"]));
            h.abs() + (h * h - k).max(0.0).sqrt()
        })
        .fold(0.0, f64::max)
}

#[test]
fn normals_and_curvatures_match_occt_where_defined() {
    let mut worst = [Worst::new("normal"), Worst::new("gaussian"), Worst::new("mean")];
    for case in cases() {
        let s = &case.surface;
        let kappa = curvature_scale(&case.samples);
        assert!(kappa > 0.0, "{}: a curved surface", case.name);
        for sample in &case.samples {
            let (u, v) = uv(sample);
            let (cu, cv) = (continuity(s.knots_u(), u), continuity(s.knots_v(), v));
            if cu < 1 || cv < 1 {
                continue;
            }
            let d: SurfaceDerivatives = s.derivatives(u, v);
            let normal = s.normal(u, v).expect("the oracle surfaces are regular at the samples");
            worst[0].check(&case.name, u, v, normal, vec3(&sample["normal"]), 1.0);
            if cu < 2 || cv < 2 {
                continue;
            }
            let c = d.curvature().expect("regular");
            let k = |x: f64| Vec3::new(x, 0.0, 0.0);
            // K ~ kappa^2 and H ~ kappa: relative to the largest principal curvature.
            worst[1].check(&case.name, u, v, k(c.gaussian), k(num(&sample["gaussian"])), kappa * kappa);
            worst[2].check(&case.name, u, v, k(c.mean), k(num(&sample["mean"])), kappa);
            let c2 = s.curvature(u, v).expect("regular");
            assert_eq!((c2.gaussian, c2.mean), (c.gaussian, c.mean));
        }
    }
    worst.iter().for_each(Worst::report);
}
