//! Exports of the fitted surface to exchange formats: IGES 5.3 (surface entity 128, section
//! curves entity 126, and a polynomial approximation for systems that drop weights), STEP
//! AP214, triangle meshes to a chordal tolerance (STL, OBJ, binary glTF, from the kernel's
//! [`nurbs::tessellate()`]) and the lossless
//! hullskin surface JSON. Writers are generic over [`std::io::Write`] and format every real
//! number of text formats through [`crate::float::real`].

mod iges;
mod mesh_out;
mod mirror;
mod polynomial;
mod step;
mod surface_json;

pub use iges::{
    greville_v, iges_timestamp, section_curves, section_parameters, write_iges, write_iges_model, IgesMeta, IgesUnits,
    MAX_STRING_LEN,
};
pub use mesh_out::{curvature_colors, mesh_name, obj_comments, srgb_to_linear, stl_header, write_glb};
pub use mirror::mirrored_full_hull;
pub use polynomial::{
    polynomial_approximation, PolynomialApproximation, MAX_CONTROL_POINTS as MAX_POLYNOMIAL_CONTROL_POINTS,
    MIN_POLYNOMIAL_TOLERANCE_REL,
};
pub use step::{step_timestamp, write_step, StepMeta};
pub use surface_json::{read_surface_json, write_surface_json, SurfaceFile, SurfaceJsonError};
/// The exponent `e` of the declared resolution `10^e` of an export (IGES global field 19,
/// STEP's `UNCERTAINTY_MEASURE_WITH_UNIT`): `floor(log10(1e-7 size))`, `size` the diagonal of
/// the control net's box (1 where it is zero or not finite).
fn resolution_exponent(size: f64) -> i32 {
    let size = if size > 0.0 && size.is_finite() { size } else { 1.0 };
    (1e-7 * size).log10().floor() as i32
}

/// `10^e` as the decimal `1e<e>`: parsed rather than `powi`, so that it prints exactly.
fn power_of_ten(e: i32) -> f64 {
    format!("1e{e}").parse().expect("a decimal power of ten parses")
}

/// The declared resolution of an export, `10^floor(log10(1e-7 size))` ([`resolution_exponent`]).
fn resolution(size: f64) -> f64 {
    power_of_ten(resolution_exponent(size))
}

/// The surface of the IGES and STEP unit tests: bicubic in u, quadratic in v, v domain
/// `[-1, 2]`, non-uniform knots; every count differs between u and v, so a transposition error
/// shows. `double_knot` makes the interior u knot 0.3 double (a 6 x 4 net, for STEP's knot
/// multiplicities; else 5 x 4); `rational` gives weights from 1 to 1.55, else all 2 (a
/// polynomial surface written with a constant weight).
#[cfg(test)]
fn sample_surface(double_knot: bool, rational: bool) -> nurbs::NurbsSurface {
    let interior: &[f64] = if double_knot { &[0.3, 0.3] } else { &[0.3] };
    let ku = [&[0.0; 4][..], interior, &[1.0; 4]].concat();
    let ku = nurbs::KnotVector::try_new(3, ku).expect("valid");
    let kv = nurbs::KnotVector::try_new(2, vec![-1.0, -1.0, -1.0, 0.25, 2.0, 2.0, 2.0]).expect("valid");
    let (nu, nv) = (ku.num_basis(), kv.num_basis());
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            pts.push(nurbs::Vec3::new(10.0 * i as f64, 1.5 * j as f64 + 0.1 * i as f64, 0.3 * (i * j) as f64 - 40.0));
            w.push(if rational { 1.0 + 0.1 * i as f64 + 0.05 * j as f64 } else { 2.0 });
        }
    }
    nurbs::NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
}

/// What the IGES and STEP tests check of the resolution `r` a file declares for a control net
/// of diagonal `size`: a power of ten within a factor 10 below `1e-7 size`.
#[cfg(test)]
fn assert_resolution(r: f64, size: f64) {
    assert!(r <= 1e-7 * size && r > 1e-8 * size, "resolution {r} for size {size}");
    nurbs::assert_near!(r.log10(), r.log10().round(), 1e-12);
}
