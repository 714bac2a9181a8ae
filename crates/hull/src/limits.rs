//! Documented caps on what hullskin accepts, each with the reason for its size, and the checks
//! that enforce them where the data enter (file reading, offsets, meshes, drawings, fit and
//! optimisation settings, surface JSON).
//!
//! The table of the caps with the reason for each size is in the crate docs (`lib.rs`,
//! section Limits), where the library's users read it.

use std::io::Read;
use std::path::Path;

pub use crate::error::LimitExceeded;
pub use crate::numfmt::thousands;
use crate::HullError;

/// Bytes of an offsets file (any format of [`crate::read_offsets`]). A sections CSV holds about
/// 40 bytes a point, so [`MAX_POINTS`] is about 80 MB; 256 MiB leaves room for comments, wide
/// number formats and JSON.
pub const MAX_OFFSETS_FILE_BYTES: u64 = 256 << 20;
/// Bytes of a mesh file (STL, OBJ, VRML, before gunzip; the decompressed size has the same cap,
/// [`crate::mesh::MAX_DECOMPRESSED`]). A binary STL of [`MAX_MESH_TRIANGLES`] is 1.0 GB.
pub const MAX_MESH_FILE_BYTES: u64 = 1 << 30;
/// Bytes of a drawing to digitise (DXF, SVG). A traced body plan is a few MB.
pub const MAX_DRAWING_FILE_BYTES: u64 = 256 << 20;
/// Bytes of a `surface.json`. [`MAX_CONTROL_POINTS`] poles at about 80 bytes a line, plus their
/// weights, is under 400 MB.
pub const MAX_SURFACE_JSON_BYTES: u64 = 1 << 30;
/// Bytes of an IGES or STEP file read for its B-spline surfaces ([`crate::read_cad_surfaces`]). A pole
/// is four reals of at most 24 characters: in IGES about 110 bytes with the delimiters and the
/// 16 columns of sequence numbers per 64 of data, in STEP a `CARTESIAN_POINT` line of about
/// 90 bytes plus its reference and weight; [`MAX_CONTROL_POINTS`] poles stay under 500 MB.
pub const MAX_CAD_FILE_BYTES: u64 = 1 << 30;
/// Entity instances of one STEP file: the reader keeps 24 bytes of index per instance (240 MB
/// at the cap), and the largest surface needs one `CARTESIAN_POINT` per pole.
pub const MAX_STEP_INSTANCES: usize = 10_000_000;
/// Sections (stations) of one offsets set: one every centimetre along a 100 m hull.
pub const MAX_SECTIONS: usize = 10_000;
/// Points of one section: 0.1 mm spacing along a 10 m girth.
pub const MAX_POINTS_PER_SECTION: usize = 100_000;
/// Points of one offsets set. The fit error projects every point onto the surface (tens of
/// microseconds each), so 2 M points take about a minute on two cores.
pub const MAX_POINTS: usize = 2_000_000;
/// Control points along one direction: as many as the points of the largest section.
pub const MAX_CONTROL_POINTS_PER_DIRECTION: usize = 100_000;
/// Control points of one surface: 4 M homogeneous poles are 128 MB, and an interpolating skin
/// of [`MAX_POINTS`] offsets (one pole per offset) fits.
pub const MAX_CONTROL_POINTS: usize = 4_000_000;
/// Triangles of one mesh: read as a triangle soup (three `f64` vertices and an index triple,
/// 84 bytes) then welded, 20 M triangles stay under 2 GiB; a binary STL of that size is 1.0 GB.
pub const MAX_MESH_TRIANGLES: usize = 20_000_000;
/// Entities (curves, paths) of one drawing to digitise; a traced body plan has a few thousand.
pub const MAX_DRAWING_ENTITIES: usize = 1_000_000;
/// Variables of a weight optimisation (one per control point, or `n_u + n_v` for the rank-one
/// layout). Levenberg-Marquardt solves a dense `n x n` system: 10,000 variables are 800 MB.
pub const MAX_OPTIM_VARIABLES: usize = 10_000;
/// Iterations (generations) of a weight optimisation: 5,000 times the GA's default.
pub const MAX_OPTIM_ITERATIONS: usize = 1_000_000;
/// Population (GA), particles (PSO) or agents (GSA): 200 times the GA's default.
pub const MAX_OPTIM_POPULATION: usize = 10_000;
/// Objective evaluations, population x iterations: 10,000 times the GA's default 50 x 200.
pub const MAX_OPTIM_EVALUATIONS: u64 = 100_000_000;

// The caps agree with each other and with the memory they promise, checked at compile time.
const _: () = {
    // The soup of the largest mesh (3 f64 vertices + 3 u32 indices = 84 bytes a triangle) and
    // the homogeneous net of the largest surface (32 bytes a pole) stay under 2 GiB.
    assert!(MAX_MESH_TRIANGLES as u64 * 84 < 2 << 30);
    assert!(MAX_CONTROL_POINTS as u64 * 32 < 2 << 30);
    // LM's dense normal matrix of the largest optimisation: n^2 f64 under 1 GiB.
    assert!((MAX_OPTIM_VARIABLES as u64).pow(2) * 8 < 1 << 30);
    // A binary STL (84 + 50 n bytes) of the largest mesh is readable under the file cap.
    assert!(84 + 50 * MAX_MESH_TRIANGLES as u64 <= MAX_MESH_FILE_BYTES);
    // An interpolating skin of the largest offsets set (one pole per offset) is allowed.
    assert!(MAX_POINTS <= MAX_CONTROL_POINTS);
    assert!(MAX_POINTS_PER_SECTION <= MAX_CONTROL_POINTS_PER_DIRECTION);
    // The largest surface's poles fit the STEP instance cap and the CAD file cap (~110 bytes each).
    assert!(MAX_CONTROL_POINTS < MAX_STEP_INSTANCES);
    assert!(MAX_CONTROL_POINTS as u64 * 110 < MAX_CAD_FILE_BYTES);
    // Population x iterations of the largest run is within the evaluation cap's type.
    assert!((MAX_OPTIM_ITERATIONS as u64).checked_mul(MAX_OPTIM_POPULATION as u64).is_some());
};

/// A byte count as people write it: `1 GiB`, `256 MiB`, else `1,234 bytes`.
fn size_text(bytes: u64) -> String {
    match bytes {
        b if b > 0 && b % (1 << 30) == 0 => format!("{} GiB", b >> 30),
        b if b > 0 && b % (1 << 20) == 0 => format!("{} MiB", b >> 20),
        b => format!("{} bytes", thousands(b)),
    }
}

/// `Err` when `value > cap`.
fn check(input: &str, what: impl Into<String>, value: usize, cap: usize, expected: &str) -> Result<(), HullError> {
    if value > cap {
        Err(LimitExceeded::new(input, what, value as u64, cap as u64, expected).into())
    } else {
        Ok(())
    }
}

/// Reads the whole of `path`, refusing a file larger than `cap` bytes before reading it (and
/// one that grows past `cap` while being read): `kind` names the file in the message, e.g.
/// `an offsets file`.
///
/// # Errors
/// [`HullError::Io`] when the file cannot be opened or read, [`HullError::Limit`] when it is
/// larger than `cap`.
pub fn read_capped(path: &Path, cap: u64, kind: &str) -> Result<Vec<u8>, HullError> {
    let io = |error| HullError::Io { path: path.to_path_buf(), error };
    let file = std::fs::File::open(path).map_err(io)?;
    let input = path.display().to_string();
    let too_big = |len: u64| {
        HullError::from(LimitExceeded::new(&input, "bytes", len, cap, format!("{kind} of at most {}", size_text(cap))))
    };
    // The length on disk when known (0 for pipes and special files, which are read up to the cap).
    let len = file.metadata().map(|m| m.len()).unwrap_or(0);
    if len > cap {
        return Err(too_big(len));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(cap + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > cap {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

/// Refuses a file larger than `cap` bytes from its length on disk, for callers that then read
/// it themselves (a file whose length cannot be read passes: the read reports the problem).
///
/// # Errors
/// [`HullError::Limit`] when the file is larger than `cap`.
pub fn check_file_size(path: &Path, cap: u64, kind: &str) -> Result<(), HullError> {
    match std::fs::metadata(path) {
        Ok(m) if m.len() > cap => Err(LimitExceeded::new(
            &path.display().to_string(),
            "bytes",
            m.len(),
            cap,
            format!("{kind} of at most {}", size_text(cap)),
        )
        .into()),
        _ => Ok(()),
    }
}

/// What the offsets caps count, as the data model gives it ([`crate::Offsets`] does): this
/// module knows the caps, not the types they bound, so every module may use it.
pub trait OffsetCounts {
    /// The input's name, for messages.
    fn source(&self) -> &str;
    /// Each section's label and number of points, in order.
    fn section_sizes(&self) -> Vec<(&str, usize)>;
}

/// Checks the counts of an offsets set: sections, points per section, points in all.
///
/// # Errors
/// [`HullError::Limit`] above [`MAX_SECTIONS`], [`MAX_POINTS_PER_SECTION`] or [`MAX_POINTS`].
pub fn check_offsets(offsets: &impl OffsetCounts) -> Result<(), HullError> {
    let src = offsets.source();
    let sizes = offsets.section_sizes();
    check(src, "sections", sizes.len(), MAX_SECTIONS, "at most 10,000 sections")?;
    for &(label, points) in &sizes {
        let what = format!("points in section \"{label}\"");
        check(src, what, points, MAX_POINTS_PER_SECTION, "at most 100,000 points per section")?;
    }
    let points = sizes.iter().map(|&(_, n)| n).sum();
    check(src, "points", points, MAX_POINTS, "at most 2,000,000 offsets in all")
}

/// Checks the control-point counts `(nu, nv)` of a surface to be built or read.
///
/// # Errors
/// [`HullError::Limit`] above [`MAX_CONTROL_POINTS_PER_DIRECTION`] in either direction or
/// [`MAX_CONTROL_POINTS`] in all.
pub fn check_control_points(input: &str, nu: usize, nv: usize) -> Result<(), HullError> {
    control_points(input, nu, nv).map_err(HullError::from)
}

/// [`check_control_points`] as a plain [`LimitExceeded`] (for readers with their own errors).
pub(crate) fn control_points(input: &str, nu: usize, nv: usize) -> Result<(), LimitExceeded> {
    let per = MAX_CONTROL_POINTS_PER_DIRECTION;
    for (n, dir) in [(nu, "u"), (nv, "v")] {
        if n > per {
            let what = format!("control points along {dir}");
            return Err(LimitExceeded::new(input, what, n as u64, per as u64, "at most 100,000 per direction"));
        }
    }
    let total = nu as u64 * nv as u64;
    if total > MAX_CONTROL_POINTS as u64 {
        return Err(LimitExceeded::new(
            input,
            format!("control points ({nu} x {nv})"),
            total,
            MAX_CONTROL_POINTS as u64,
            "at most 4,000,000 control points in all",
        ));
    }
    Ok(())
}

/// Checks the triangle count of a mesh (read, or claimed by a binary STL header).
///
/// # Errors
/// [`HullError::Limit`] above [`MAX_MESH_TRIANGLES`].
pub fn check_mesh_triangles(input: &str, triangles: u64) -> Result<(), HullError> {
    if triangles > MAX_MESH_TRIANGLES as u64 {
        return Err(LimitExceeded::new(
            input,
            "triangles",
            triangles,
            MAX_MESH_TRIANGLES as u64,
            "a mesh of at most 20,000,000 triangles (decimate it first)",
        )
        .into());
    }
    Ok(())
}

/// Checks the entity count of a drawing to digitise.
///
/// # Errors
/// [`HullError::Limit`] above [`MAX_DRAWING_ENTITIES`].
pub fn check_drawing_entities(input: &str, entities: usize) -> Result<(), HullError> {
    check(input, "drawing entities", entities, MAX_DRAWING_ENTITIES, "at most 1,000,000 curves in the drawing")
}

/// The sizes of a weight optimisation the caps bound, as its settings give them
/// ([`crate::optimize::OptimSettings`] does).
pub trait OptimSizes {
    /// Variables (weights) optimised on a surface of `nu x nv` control points.
    fn variables(&self, nu: usize, nv: usize) -> usize;
    /// Iterations asked for (`None`: the algorithm's default).
    fn iterations(&self) -> Option<usize>;
    /// Population asked for (`None`: the algorithm's default).
    fn population(&self) -> Option<usize>;
}

/// Checks the sizes of a weight optimisation of a surface with `nu x nv` control points.
///
/// # Errors
/// [`HullError::Limit`] above [`MAX_OPTIM_VARIABLES`], [`MAX_OPTIM_ITERATIONS`],
/// [`MAX_OPTIM_POPULATION`] or [`MAX_OPTIM_EVALUATIONS`].
pub fn check_optimization(input: &str, settings: &impl OptimSizes, nu: usize, nv: usize) -> Result<(), HullError> {
    let variables = settings.variables(nu, nv);
    check(
        input,
        "optimisation variables (weights)",
        variables,
        MAX_OPTIM_VARIABLES,
        "at most 10,000 weights: fewer control points, or --weight-layout rank-one",
    )?;
    let iterations = settings.iterations().unwrap_or(0);
    check(input, "optimisation iterations", iterations, MAX_OPTIM_ITERATIONS, "at most 1,000,000 iterations")?;
    let population = settings.population().unwrap_or(0);
    check(input, "population members", population, MAX_OPTIM_POPULATION, "a population of at most 10,000")?;
    let evaluations = iterations.max(1) as u64 * population.max(1) as u64;
    if evaluations > MAX_OPTIM_EVALUATIONS {
        return Err(LimitExceeded::new(
            input,
            "objective evaluations (population x iterations)",
            evaluations,
            MAX_OPTIM_EVALUATIONS,
            "at most 100,000,000 evaluations",
        )
        .into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::{OptimSettings, WeightLayout};
    use crate::{Offsets, Section, Units};
    use nurbs::Vec3;

    #[test]
    fn thousands_groups_digits_by_three() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(1000), "1,000");
        assert_eq!(thousands(3_200_000), "3,200,000");
        assert_eq!(thousands(u64::MAX), "18,446,744,073,709,551,615");
        assert_eq!(size_text(MAX_MESH_FILE_BYTES), "1 GiB");
        assert_eq!(size_text(MAX_OFFSETS_FILE_BYTES), "256 MiB");
        assert_eq!(size_text(1025), "1,025 bytes");
    }

    #[test]
    fn too_many_points_are_refused_with_the_counts() {
        let row: Vec<Vec3> = (0..=MAX_POINTS_PER_SECTION).map(|i| Vec3::new(0.0, i as f64, 0.0)).collect();
        let offsets = Offsets {
            source: "scan.csv".into(),
            units: Units::Metre,
            perpendiculars: None,
            sections: vec![Section::new("7", row.clone()), Section::new("8", row)],
        };
        let e = check_offsets(&offsets).expect_err("100,001 points in a section");
        assert_eq!(
            e.to_string(),
            "scan.csv: 100,001 points in section \"7\" exceed the cap of 100,000 (expected at most 100,000 points \
             per section; see README Limits)"
        );
        let ok = Offsets { sections: vec![Section::new("a", vec![Vec3::ZERO; 3]); 2], ..offsets };
        assert!(check_offsets(&ok).is_ok());
    }

    #[test]
    fn control_points_are_capped_per_direction_and_in_all() {
        assert!(check_control_points("t", 2000, 2000).is_ok());
        let e = check_control_points("t", 2001, 2000).expect_err("4,002,000 > 4,000,000");
        match e {
            HullError::Limit(l) => assert_eq!((l.value, l.cap), (4_002_000, 4_000_000)),
            other => panic!("{other}"),
        }
        let e = check_control_points("t", 3, 100_001).expect_err("too many along v");
        assert!(e.to_string().contains("100,001 control points along v"), "{e}");
    }

    #[test]
    fn optimisation_sizes_are_capped() {
        let mut s = OptimSettings::default();
        assert!(check_optimization("t", &s, 100, 100).is_ok());
        let e = check_optimization("t", &s, 101, 100).expect_err("10,100 weights");
        assert!(e.to_string().contains("10,100 optimisation variables"), "{e}");
        s.weights.layout = WeightLayout::RankOne;
        assert!(check_optimization("t", &s, 101, 100).is_ok(), "201 rank-one variables");
        s.iterations = Some(1_000_000);
        s.population = Some(101);
        let e = check_optimization("t", &s, 10, 10).expect_err("101,000,000 evaluations");
        assert!(e.to_string().contains("101,000,000 objective evaluations"), "{e}");
        s.iterations = Some(2_000_000);
        let e = check_optimization("t", &s, 10, 10).expect_err("iterations");
        assert!(e.to_string().contains("2,000,000 optimisation iterations"), "{e}");
    }

    #[test]
    fn a_binary_stl_header_claiming_billions_is_refused_before_any_allocation() {
        // 84 bytes: an 80-byte header and a count of 4,000,000,000 triangles with no records.
        let mut stl = vec![0u8; 80];
        stl.extend_from_slice(&4_000_000_000u32.to_le_bytes());
        let e = crate::mesh::parse_mesh(
            &stl,
            "big.stl",
            Some(crate::mesh::MeshFormat::Stl),
            &crate::mesh::MeshReadOptions::default(),
        )
        .expect_err("no room for the claimed triangles");
        assert!(e.to_string().contains("claims 4000000000 triangles"), "{e}");
        // A header whose count matches the length but exceeds the cap: refused by the cap
        // before the soup is allocated (a 1 GB file is not made here: the check itself).
        let e = check_mesh_triangles("big.stl", 21_000_000).expect_err("above 20 M");
        assert!(e.to_string().starts_with("big.stl: 21,000,000 triangles exceed the cap of 20,000,000"), "{e}");
        assert!(check_mesh_triangles("ok.stl", 20_000_000).is_ok());
    }

    #[test]
    fn fits_and_optimisations_beyond_the_caps_are_refused_before_they_run() {
        let offsets = crate::series60_sample();
        let cfg = crate::FitConfig { ctrl: Some((100_001, 4)), ..crate::FitConfig::default() };
        let e = crate::fit_offsets(&offsets, &cfg).expect_err("too many control points along u");
        assert!(matches!(&e, HullError::Limit(l) if l.value == 100_001 && l.what == "control points along u"), "{e}");
        let mut optim = OptimSettings { iterations: Some(5_000_000), ..OptimSettings::default() };
        optim.weights.layout = WeightLayout::RankOne;
        let method = crate::FitMethod::Optimized(crate::optimize::Algorithm::Ga);
        let cfg = crate::FitConfig { method, optim, ctrl: Some((5, 8)), ..crate::FitConfig::default() };
        let e = crate::fit_offsets(&offsets, &cfg).expect_err("5 M iterations");
        assert!(e.to_string().contains("5,000,000 optimisation iterations exceed the cap of 1,000,000"), "{e}");
    }

    #[test]
    fn surface_json_with_too_many_control_points_is_refused() {
        // 2,001 x 2,000 control points declared by the knots alone (degree 1): refused before
        // the surface is built; the check needs no control points listed.
        let knots = |n: usize| {
            let mut k = vec![0.0];
            k.extend((0..n).map(|i| i as f64 / (n - 1) as f64));
            k.push(1.0);
            k
        };
        let text = serde_json::json!({
            "format": "hullskin-surface", "version": 1, "units": "m", "degree": [1, 1],
            "control_points_count": [2001, 2000], "knots_u": knots(2001), "knots_v": knots(2000),
            "control_points": [], "weights": null
        })
        .to_string();
        let e = crate::export::read_surface_json(&text).expect_err("4,002,000 control points");
        assert_eq!(
            e.to_string(),
            "surface JSON: 4,002,000 control points (2001 x 2000) exceed the cap of 4,000,000 (expected at most \
             4,000,000 control points in all; see README Limits)"
        );
    }

    #[test]
    fn large_files_are_refused_before_reading() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("big.csv");
        // A sparse file: 2 GiB on paper, no blocks on disk; refused from its length alone.
        let f = std::fs::File::create(&path).expect("create");
        f.set_len(2 << 30).expect("sparse length");
        let e = read_capped(&path, MAX_OFFSETS_FILE_BYTES, "an offsets file").expect_err("2 GiB > 256 MiB");
        assert!(
            e.to_string().ends_with(
                "2,147,483,648 bytes exceed the cap of 268,435,456 (expected an offsets file of at most 256 MiB; \
                 see README Limits)"
            ),
            "{e}"
        );
        std::fs::write(&path, b"section,x,y,z\n").expect("write");
        assert_eq!(read_capped(&path, 14, "x").expect("14 bytes fit a cap of 14"), b"section,x,y,z\n");
        assert!(matches!(read_capped(&path, 13, "x"), Err(HullError::Limit(_))));
        assert!(matches!(read_capped(&dir.path().join("none"), 10, "x"), Err(HullError::Io { .. })));
        // Checked from the length alone, for readers that read the file themselves.
        let e = check_file_size(&path, 13, "a surface.json").expect_err("14 > 13");
        assert!(
            e.to_string().ends_with(
                "14 bytes exceed the cap of 13 (expected a surface.json of at most 13 bytes; see README Limits)"
            ),
            "{e}"
        );
        assert!(check_file_size(&path, 14, "x").is_ok());
        assert!(check_file_size(&dir.path().join("none"), 0, "x").is_ok(), "the read reports a missing file");
        // Through the offsets reader: the same refusal, naming the file.
        let big = dir.path().join("huge.csv");
        std::fs::File::create(&big).expect("create").set_len(MAX_OFFSETS_FILE_BYTES + 1).expect("sparse");
        let e = crate::read_offsets(&big, Units::Metre).expect_err("256 MiB + 1");
        assert!(matches!(&e, HullError::Limit(l) if l.value == MAX_OFFSETS_FILE_BYTES + 1), "{e}");
    }
}
