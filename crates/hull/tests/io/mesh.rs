//! Hull meshes: readers against each other and against bad files, slicing against exact
//! shapes, mesh hydrostatics against closed forms, and the mesh -> sections -> surface path on
//! real hulls (DTC, DTMB 5415, the OpenFOAM Wigley mesh) against the meshes' own figures and
//! the published ones.

use std::io::Write;

use hull::{
    fit_offsets, mesh_distance, mesh_hydrostatics, parse_mesh, read_mesh, slice_mesh, weld, write_obj, write_stl_ascii,
    write_stl_binary, Axes, FitConfig, FitMethod, Hydrostatics, HydrostaticsOptions, HydrostaticsRow, MeshFormat,
    MeshReadOptions, Offsets, SliceOptions, SliceOutcome, Spacing, Stations, TriMesh, VertexFilter,
};
use nurbs::{assert_near, Vec3};

use crate::common::testdata;

/// The Wigley hull `y = (B/2)(1 - xi^2)(1 - zeta^2)`, `xi = 2x/L - 1`, `zeta = 1 - z/T`, x from
/// the aft end, z up from the keel (the design waterline, the top of the formula, at z = T).
#[derive(Clone, Copy)]
struct Wigley {
    l: f64,
    b: f64,
    t: f64,
}

impl Wigley {
    fn y(&self, x: f64, z: f64) -> f64 {
        let xi = 2.0 * x / self.l - 1.0;
        let zeta = 1.0 - z / self.t;
        0.5 * self.b * (1.0 - xi * xi) * (1.0 - zeta * zeta)
    }

    /// Bounds of the second derivatives `|y_xx|, |y_xz|, |y_zz|` over the hull:
    /// `y_xx = -(4B/L^2)(1 - zeta^2)`, `y_zz = -(B/T^2)(1 - xi^2)`, `y_xz = -(4B/(L T)) xi zeta`.
    fn second_derivative_bounds(&self) -> (f64, f64, f64) {
        (4.0 * self.b / (self.l * self.l), 4.0 * self.b / (self.l * self.t), self.b / (self.t * self.t))
    }

    /// Volume below draft `d`: `2 ∫∫ y = B (2L/3)(d^2/T - d^3/(3T^2))`.
    fn volume(&self, d: f64) -> f64 {
        self.b * 2.0 * self.l / 3.0 * (d * d / self.t - d.powi(3) / (3.0 * self.t * self.t))
    }

    /// A closed mesh of both sides (`nx x nz` quads each, two triangles per quad) and the flat
    /// deck at z = T, welded, outward.
    fn mesh(&self, nx: usize, nz: usize) -> TriMesh {
        let mut pts = Vec::new();
        let node = |i: usize, j: usize| {
            let (x, z) = (self.l * i as f64 / nx as f64, self.t * j as f64 / nz as f64);
            (x, self.y(x, z), z)
        };
        for side in [1.0, -1.0] {
            for i in 0..=nx {
                for j in 0..=nz {
                    let (x, y, z) = node(i, j);
                    pts.push(Vec3::new(x, side * y, z));
                }
            }
        }
        let s = |i: usize, j: usize| (i * (nz + 1) + j) as u32;
        let p = |i: usize, j: usize| ((nx + 1) * (nz + 1) + i * (nz + 1) + j) as u32;
        let mut tris = Vec::new();
        for i in 0..nx {
            for j in 0..nz {
                // Diagonals from the keel towards amidships, mirrored fore and aft: a corner
                // quad at a pointed end then has no triangle lying in the centre plane.
                let fore = 2 * i >= nx;
                let (a, b, c, d) = (s(i, j), s(i + 1, j), s(i + 1, j + 1), s(i, j + 1));
                tris.extend(if fore { [[a, d, b], [b, d, c]] } else { [[a, d, c], [a, c, b]] });
                let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
                tris.extend(if fore { [[a, b, d], [b, c, d]] } else { [[a, c, d], [a, b, c]] });
            }
            tris.extend([[s(i, nz), p(i, nz), p(i + 1, nz)], [s(i, nz), p(i + 1, nz), s(i + 1, nz)]]);
        }
        indexed("wigley", &pts, &tris)
    }
}

/// Welds `pts` exactly and drops the triangles that collapse (the pointed ends, the keel).
fn indexed(name: &str, pts: &[Vec3], tris: &[[u32; 3]]) -> TriMesh {
    let (vertices, remap) = weld(pts, 0.0);
    let triangles = tris
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .collect();
    TriMesh::try_new(name, vertices, triangles).expect("valid mesh")
}

fn slice(mesh: &TriMesh, stations: Stations, points: usize) -> SliceOutcome {
    slice_mesh(mesh, &SliceOptions { stations, points, ..SliceOptions::default() }).expect("slices")
}

/// The mesh `testdata/mesh/{name}` read in `axes` and sliced as `hullskin fit MESH` slices it:
/// 41 cosine stations of 30 points.
fn read_sliced(name: &str, axes: Axes) -> SliceOutcome {
    let options = MeshReadOptions { axes, ..MeshReadOptions::default() };
    let mesh = read_mesh(&testdata(&format!("mesh/{name}")), &options).expect("reads");
    slice(&mesh, Stations::Count { n: 41, spacing: Spacing::Cosine }, 30)
}

#[test]
fn a_tessellated_wigley_hull_is_closed_and_outward() {
    let mesh = Wigley { l: 100.0, b: 10.0, t: 6.25 }.mesh(40, 10);
    let e = mesh.edge_counts();
    assert_eq!((e.open, e.non_manifold), (0, 0), "{e:?}");
    let h = mesh_hydrostatics(&mesh, 6.25);
    assert!(!h.inward && !h.half && h.open_edges_below == 0, "{h:?}");
}

#[test]
fn sections_of_a_tessellated_wigley_hull_lie_on_the_exact_hull() {
    let w = Wigley { l: 100.0, b: 10.0, t: 6.25 };
    let (nx, nz) = (40, 10);
    let (hx, hz) = (w.l / nx as f64, w.t / nz as f64);
    let mesh = w.mesh(nx, nz);
    let (dxx, dxz, dzz) = w.second_derivative_bounds();
    // Stations on the grid lines: the cut runs through the mesh's vertices (the plane is taken
    // just aft of them), which lie on the hull, so the section is the polyline through exact
    // points and deviates from y(z) by at most the sag of a parabola's chord, |y_zz| hz^2 / 8.
    let on_grid: Vec<f64> = (1..nx).step_by(3).map(|i| hx * i as f64).collect();
    // Anywhere else the cut crosses triangles, where linear interpolation errs by at most
    // (1/2)(|y_xx| hx^2 + 2 |y_xz| hx hz + |y_zz| hz^2) (Taylor's remainder at each corner).
    let off_grid: Vec<f64> = (0..29).map(|k| 1.3 + 3.37 * k as f64).collect();
    for (xs, bound) in
        [(on_grid, dzz * hz * hz / 8.0), (off_grid, 0.5 * (dxx * hx * hx + 2.0 * dxz * hx * hz + dzz * hz * hz))]
    {
        let n = xs.len();
        let out = slice(&mesh, Stations::At(xs.clone()), 4 * nz + 1);
        assert_eq!(out.offsets.sections.len(), n, "{:?}", out.dropped);
        for (s, info) in out.offsets.sections.iter().zip(&out.stations) {
            assert!(info.deck_removed && info.pieces == 1 && !info.open_top, "{info:?}");
            // Starts at the keel on the centre plane, ends at the deck edge (within the bound
            // off the grid, where the deck edge is interpolated too).
            assert_near!(s.points[0], Vec3::new(info.x, 0.0, 0.0), 1e-12);
            assert_near!(*s.points.last().expect("points"), Vec3::new(info.x, w.y(info.x, w.t), w.t), bound + 1e-12);
            for p in &s.points {
                assert_eq!(p.x, info.x);
                let dev = (p.y - w.y(p.x, p.z)).abs();
                assert!(dev <= bound + 1e-12, "x {} z {}: |y - y(x, z)| = {dev:e} > {bound:e}", p.x, p.z);
            }
        }
    }
}

#[test]
fn mesh_volume_of_the_wigley_hull_converges_at_second_order_to_the_closed_form() {
    // The mesh is the hull's piecewise-linear interpolant: its volume errs by c h^2 + O(h^4),
    // so halving the grid divides the error by 4 (up to the h^4 term), and Richardson's
    // (4 V_h/2 - V_h) / 3 removes the h^2 term.
    let w = Wigley { l: 100.0, b: 10.0, t: 6.25 };
    for draft in [w.t, 0.5 * w.t] {
        let exact = w.volume(draft);
        let v: Vec<f64> = [(20, 8), (40, 16), (80, 32)]
            .iter()
            .map(|&(nx, nz)| mesh_hydrostatics(&w.mesh(nx, nz), draft).volume)
            .collect();
        let err: Vec<f64> = v.iter().map(|vi| vi - exact).collect();
        assert!(err[0] < 0.0 && err[1] < 0.0, "an inscribed polyhedron of a convex section: {err:?}");
        for k in 0..2 {
            let ratio = err[k] / err[k + 1];
            assert!((3.9..4.1).contains(&ratio), "draft {draft}: error ratio {ratio} ({err:?})");
        }
        let richardson = (4.0 * v[2] - v[1]) / 3.0;
        assert!(((richardson - exact) / exact).abs() < 1e-5, "draft {draft}: {richardson} vs {exact}");
        // The half-grid wetted surface approaches the closed form's 0.148791 L^2 at T.
        if draft == w.t {
            let s = mesh_hydrostatics(&w.mesh(80, 32), draft).wetted_surface;
            assert!(((s / (w.l * w.l) - 0.148791) / 0.148791).abs() < 2e-4, "S = {s}");
        }
    }
}

/// A Wigley mesh whose coordinates are exact in `f32` (dyadic fractions of few bits), so that
/// every format, binary STL included, holds it exactly.
fn dyadic_wigley() -> TriMesh {
    Wigley { l: 64.0, b: 8.0, t: 4.0 }.mesh(16, 8)
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(bytes).expect("compresses");
    enc.finish().expect("compresses")
}

#[test]
fn ascii_and_binary_stl_obj_and_gzip_read_the_same_mesh() {
    let mesh = dyadic_wigley();
    let opts = MeshReadOptions::default();
    let mut ascii = Vec::new();
    write_stl_ascii(&mut ascii, &mesh, "wigley").expect("writes");
    let mut binary = Vec::new();
    write_stl_binary(&mut binary, &mesh, "solid wigley (binary, starting with solid on purpose)").expect("writes");
    let from_ascii = parse_mesh(&ascii, "a.stl", None, &opts).expect("ascii");
    let from_binary = parse_mesh(&binary, "b.stl", Some(MeshFormat::Stl), &opts).expect("binary");
    let from_gz = parse_mesh(&gzip(&ascii), "a.stl.gz", None, &opts).expect("gzip");
    let mut obj = Vec::new();
    write_obj(&mut obj, &from_ascii, &[], None).expect("writes");
    let from_obj = parse_mesh(&obj, "a.obj", None, &opts).expect("obj");
    // Every STL facet brings its own three corners: welding gives back the shared vertices.
    assert_eq!(from_ascii.vertices.len(), mesh.vertices.len());
    assert_eq!(from_ascii.triangles.len(), mesh.triangles.len());
    for other in [&from_binary, &from_gz, &from_obj] {
        assert_eq!((&other.vertices, &other.triangles), (&from_ascii.vertices, &from_ascii.triangles));
    }
    // The same triangles as the mesh written, corner for corner.
    for t in 0..mesh.triangles.len() {
        assert_eq!(from_ascii.corners(t), mesh.corners(t));
    }
}

/// The FastShip sample designs (`shared/data/fastship_sample_hulls/`, VRML 1.0 as FREE!ship
/// Plus ships them) read as their `PROVENANCE.md` describes them, counted there apart from
/// hullskin: one surface each, tessellated as 32 x 32 quads (2,048 triangles), bounding boxes
/// as stored (printed there to the millimetre, or to 0.1 m for the tanker's breadth and depth:
/// 0.05 m allows both). Written as OBJ and read back, each is the same welded mesh.
#[test]
fn the_fastship_vrml_hulls_read_as_their_provenance_describes() {
    let opts = MeshReadOptions::default();
    for (name, lo, hi) in [
        ("fastship_50dragger.wrl.gz", [0.0, 0.001, -4.267], [15.24, 2.895, 0.0]),
        ("fastship_70ktanker.wrl.gz", [-1.805, 0.0, 0.0], [235.082, 16.1, 18.7]),
        ("fastship_cont.wrl.gz", [0.0, 0.0, -17.5], [145.0, 11.0, 0.0]),
    ] {
        let path = testdata(&format!("mesh/{name}"));
        let bytes = hull::gunzip(&std::fs::read(&path).expect("reads"), name).expect("gunzips");
        let soup = hull::parse_vrml(&bytes, name).expect("parses");
        assert_eq!(soup.triangles.len(), 2048, "{name}");
        for k in 0..3 {
            let (min, max) =
                soup.vertices.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p[k]), b.max(p[k])));
            assert!((min - lo[k]).abs() < 0.05 && (max - hi[k]).abs() < 0.05, "{name} axis {k}: {min} .. {max}");
        }
        let mesh = read_mesh(&path, &opts).expect("reads");
        let mut obj = Vec::new();
        write_obj(&mut obj, &mesh, &[], None).expect("writes");
        let back = parse_mesh(&obj, "back.obj", None, &opts).expect("reads back");
        assert_eq!((&back.vertices, &back.triangles), (&mesh.vertices, &mesh.triangles), "{name}");
    }
    // The container ship with its vertical axis turned up (z = -17.5 at the deck as stored):
    // its 41 cosine stations less the sliver at the stem's tip, keel at z = 0 amidships, up to
    // the deck at 17.5 m.
    let out = read_sliced("fastship_cont.wrl.gz", "x,y,-z".parse().expect("axes"));
    assert_eq!(out.offsets.sections.len(), 40, "{:?}", out.dropped);
    let mid = &out.offsets.sections[20].points;
    assert!(mid[0].z.abs() < 1e-3 && (mid[mid.len() - 1].z - 17.5).abs() < 0.05, "{:?}", (mid[0], mid[mid.len() - 1]));
}

/// The FastShip container ship's stem rises from z = 2.0 m at the station at x = 141.4 m to
/// 14.6 m at the next, 1.5 m forward: the least squares across the sections rings there, and the
/// default fit folds at its default 23x30 control points and at one fewer or one more across,
/// whatever the hold, parameterization or smoothing. Two fewer across (23x28) it is sound, and
/// that is the default fit ([`hull::ALTERNATIVE_COUNTS_ACROSS`]; before 2026-12-08 only one
/// fewer and one more were tried, and a surface with two folds and 4.2 m² facing inwards at the
/// stem's top was written).
#[test]
fn the_container_ships_default_fit_is_sound_two_control_points_fewer_across() {
    let offsets = read_sliced("fastship_cont.wrl.gz", "x,y,-z".parse().expect("axes")).offsets;
    // As `hullskin fit` fits by default (the library's default leaves the fairing off).
    let config = FitConfig { fair: hull::Fairing::Auto { tolerance: None }, ..FitConfig::default() };
    let out = fit_offsets(&offsets, &config).expect("fits");
    assert!(out.validity.is_empty(), "{:?}", out.validity.iter().map(|f| f.kind).collect::<Vec<_>>());
    assert_eq!((out.surface.n_u(), out.surface.n_v()), (23, 28));
    let alternatives = out.fairing.as_ref().and_then(|f| f.alternatives.as_ref()).expect("alternatives tried");
    assert_eq!(alternatives.control_points, [23, 30]);
    assert!(alternatives.findings > 0);
    for across in [29, 31] {
        let t = alternatives.tried.iter().find(|t| t.control_points == [23, across]).expect("tried");
        assert!(t.findings > 0 && !t.accepted, "23x{across}: {} findings", t.findings);
    }
}

/// A mesh stored with z down (FastShip's container ship and dragger) is sliced into sections
/// that run down from the keel: the slicer's warnings say the mesh looks upside down and name
/// the axes that turn it up (without it the container ship's fit fails on a self-crossing
/// section with no hint why). Turned up, and on every upright mesh of `testdata/mesh/`, no
/// such warning.
#[test]
fn a_mesh_stored_upside_down_is_warned_of() {
    let up: Axes = "x,y,-z".parse().expect("axes");
    let upside_down = |name: &str, axes: Axes| {
        read_sliced(name, axes).warnings().into_iter().find(|w| w.contains("looks upside down"))
    };
    for name in ["fastship_cont.wrl.gz", "fastship_50dragger.wrl.gz"] {
        let w = upside_down(name, Axes::default()).expect("warned");
        assert!(w.contains("try --axes x,y,-z"), "{name}: {w}");
        assert_eq!(upside_down(name, up), None, "{name} turned up");
    }
    for name in ["fastship_70ktanker.wrl.gz", "DTC-scaled.stl.gz", "dtmb5415.stl.gz", "wigley.stl.gz"] {
        assert_eq!(upside_down(name, Axes::default()), None, "{name}");
    }
}

#[test]
fn the_axes_option_brings_a_mesh_in_other_axes_back() {
    // Written with y up and z to port (a graphics convention): file (x, y, z) = (x, z, -y).
    let mesh = dyadic_wigley();
    let turned = mesh.clone().map_vertices(|p| Vec3::new(p.x, p.z, -p.y));
    let mut text = Vec::new();
    write_stl_ascii(&mut text, &turned, "turned").expect("writes");
    let axes: Axes = "x,-z,y".parse().expect("axes");
    let shift = Vec3::new(-32.0, 0.0, 1.5);
    let back = parse_mesh(&text, "t.stl", None, &MeshReadOptions { axes, shift, ..MeshReadOptions::default() })
        .expect("reads");
    for t in 0..mesh.triangles.len() {
        let want = mesh.corners(t).map(|p| p + shift);
        assert_eq!(back.corners(t), want);
    }
    // Shifting moves the hydrostatics' origin and nothing else (exact in binary fractions).
    let (a, b) = (mesh_hydrostatics(&mesh, 2.0), mesh_hydrostatics(&back, 3.5));
    assert_near!(b.volume, a.volume, 1e-12 * a.volume);
    assert_near!(b.lcb, a.lcb - 32.0, 1e-12);
    assert_near!(b.vcb, a.vcb + 1.5, 1e-12);
}

#[test]
fn bad_files_are_errors_naming_the_file_and_the_place() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mesh = dyadic_wigley();
    let mut ascii = Vec::new();
    write_stl_ascii(&mut ascii, &mesh, "w").expect("writes");
    let mut binary = Vec::new();
    write_stl_binary(&mut binary, &mesh, "hullskin").expect("writes");
    let text = String::from_utf8(ascii.clone()).expect("utf-8");
    let cut_at = text.find("endloop").expect("a facet") + 3;
    let line_of_cut = 1 + text[..cut_at].matches('\n').count();
    let cases: Vec<(&str, Vec<u8>, String)> = vec![
        ("truncated.stl", ascii[..cut_at].to_vec(), format!("truncated.stl:{line_of_cut}: \"end\"")),
        (
            "short.stl",
            binary[..binary.len() - 7].to_vec(),
            "short.stl: binary STL: the header (byte offset 80) claims".into(),
        ),
        (
            "count.stl",
            {
                let mut b = binary.clone();
                b[80..84].copy_from_slice(&1_000_000_000u32.to_le_bytes());
                b
            },
            "claims 1000000000 triangles".into(),
        ),
        (
            "nan.stl",
            text.replacen("vertex ", "vertex nan ", 1).into_bytes(),
            "nan.stl:4: \"nan\" is not a finite number".into(),
        ),
        ("word.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 zero\n".to_vec(), "word.obj:3: \"zero\" is not a number".into()),
        (
            "face.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n".to_vec(),
            "face.obj:4: face corner refers to vertex 4".into(),
        ),
        ("empty.stl", b"solid e\nendsolid e\n".to_vec(), "empty.stl: no triangle (expected at least one facet)".into()),
        ("data.bin", vec![7u8; 10], "data.bin: a file that is neither STL, OBJ nor VRML".into()),
    ];
    for (name, bytes, expected) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).expect("write");
        let e = read_mesh(&path, &MeshReadOptions::default()).expect_err(name).to_string();
        let shown = e.replace(&format!("{}/", dir.path().display()), "");
        assert!(shown.contains(&expected), "{name}: {shown}");
    }
    let e = read_mesh(&dir.path().join("none.stl"), &MeshReadOptions::default()).expect_err("missing");
    assert!(matches!(e, hull::HullError::Io { .. }), "{e}");
}

/// The surface's hydrostatics at `draft`.
fn surface_row(offsets: &Offsets, method: FitMethod, draft: f64) -> (HydrostaticsRow, nurbs::NurbsSurface) {
    let fit = fit_offsets(offsets, &FitConfig { method, ..FitConfig::default() }).expect("fits");
    let row =
        Hydrostatics::new(&fit.surface, &HydrostaticsOptions::default()).expect("valid").at(draft).expect("draft");
    (row, fit.surface)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b) / b
}

/// DTC (`testdata/mesh/DTC-scaled.stl.gz`, OpenFOAM's tutorial mesh; PROVENANCE in
/// `shared/data/dtc/`): 41 cosine stations, fitted by interpolation and approximation; volume
/// and wetted surface at T = 0.244 m within 0.5 % of the mesh's own and 1 % of the published
/// (el Moctar et al. 2012: V 0.827 m^3, S 6.243 m^2).
#[test]
fn dtc_sliced_at_41_stations_meets_the_volume_and_wetted_surface_floors() {
    let mesh = read_mesh(&testdata("mesh/DTC-scaled.stl.gz"), &MeshReadOptions::default()).expect("reads");
    assert_eq!((mesh.triangles.len(), mesh.vertices.len(), mesh.degenerate), (116_062, 58_033, 0));
    let e = mesh.edge_counts();
    assert_eq!((e.open, e.non_manifold), (0, 0));
    let draft = 0.244;
    let m = mesh_hydrostatics(&mesh, draft);
    // The mesh's own figures as PROVENANCE.md gives them (5 significant digits, independent
    // scratch script): the clipped polyhedron is integrated exactly, so only their rounding
    // separates the two.
    assert_near!(m.volume, 0.82671, 0.5e-5);
    assert_near!(m.wetted_surface, 6.2448, 0.5e-4);
    // PROVENANCE's LCB 2.93000 m lies 1.1e-5 m (4e-6 relative) from ours, beyond its last
    // digit: its script's summation or rounding; both agree with OpenFOAM's LCG 2.9295 m.
    assert_near!(m.lcb, 2.93000, 2e-5);
    assert_near!(m.vcb, 0.13445, 0.5e-5);
    assert_near!(m.bwl, 0.8585, 0.5e-4);

    let out = slice(&mesh, Stations::Count { n: 41, spacing: Spacing::Cosine }, 30);
    assert_eq!(out.offsets.sections.len(), 41, "{:?}", out.dropped);
    // The bulb and the stem are cut apart at the last 5 stations, the shaft boss and the hull
    // above the propeller aperture at one station aft; every piece is chained keel to deck.
    let joined: Vec<usize> =
        out.stations.iter().filter(|s| s.pieces == 2).map(|s| s.label.parse().expect("n")).collect();
    assert_eq!(joined, vec![7, 37, 38, 39, 40, 41]);
    for (s, info) in out.offsets.sections.iter().zip(&out.stations) {
        assert!(info.deck_removed && !info.open_top, "{info:?}");
        let (keel, edge) = (s.points[0], s.points[s.points.len() - 1]);
        assert!(keel.y == 0.0 && keel.z < draft + 0.02, "station {}: keel {keel:?}", info.label);
        // The DTC's deck is flat at z = 0.572322 m: every section ends at its edge.
        assert_near!(edge.z, 0.572322, 1e-6, "station {}", info.label);
    }
    // Measured (see the report of issue 5): interp V +0.011 %, S +0.305 %; approx V +0.024 %,
    // S +0.041 % against the mesh. The wetted surface is the harder figure: the single surface
    // spans the propeller aperture with a web on the centre plane.
    for method in [FitMethod::Interp, FitMethod::Approx] {
        let (row, surface) = surface_row(&out.offsets, method, draft);
        for (what, got, mesh_value, published) in
            [("V", row.vol, m.volume, 0.827), ("S", row.s, m.wetted_surface, 6.243)]
        {
            assert!(rel(got, mesh_value).abs() < 0.005, "{method}: {what} {got} vs mesh {mesh_value}");
            assert!(rel(got, published).abs() < 0.01, "{method}: {what} {got} vs published {published}");
        }
        // The centre-plane web between the bulb and the stem: whole knot spans of it lie in the
        // centre plane above the bulb (left out of S at T = 0.4 m: measured 0.0038 m² approx,
        // 0.0127 m² interp, 0.04 % and 0.15 % of S; bound 0.3 %, a sliver of the bow). At the
        // design draft the waterline grazes the bulb's top, where no span lies wholly in the
        // centre plane: nothing is left out there (Lwl stays 6.22 m approx, 6.18 m interp
        // against the mesh's 6.09 m: see the hydrostatics module docs, "Centre-plane webs").
        let h = Hydrostatics::new(&surface, &HydrostaticsOptions::default()).expect("valid");
        assert_eq!(h.web_area(draft).expect("a draft on the hull"), 0.0, "{method}");
        let high = h.at(0.4).expect("a draft on the hull");
        let web = h.web_area(0.4).expect("a draft on the hull");
        assert!(web > 0.0 && web < 0.003 * high.s, "{method}: web {web} of S {}", high.s);
        // Distance of the wetted vertices (every 16th, to keep the debug-build test short) to
        // the surface: measured on all 18,857 of them, RMS 4.6 mm (interp) and 4.3 mm (approx)
        // with the largest, 5 cm, at the shaft boss's aft end inside the aperture.
        let filter = VertexFilter { every: 16, ..VertexFilter::for_sections(&out.offsets, draft).expect("points") };
        let d = mesh_distance(&mesh, &surface, &filter);
        assert!(d.stats.points > 1000, "{}", d.stats.points);
        assert!(d.stats.rms < 0.0075 && d.stats.mean < 0.003 && d.stats.max < 0.06, "{method}: {:?}", d.stats);
    }
}

/// The OpenFOAM Wigley mesh (L = 1 m, B = 0.1 m, T = 0.0625 m, z = 0 at the waterline, open
/// at the top, triangles facing inward): shifted to the keel, sliced, fitted, against the
/// closed forms V = (4/9) L B T, KB = 5T/8, S = 0.148791 L^2.
#[test]
fn openfoam_wigley_mesh_against_the_closed_forms() {
    let t = 0.0625;
    let opts = MeshReadOptions { shift: Vec3::new(0.5, 0.0, t), ..MeshReadOptions::default() };
    let mesh = read_mesh(&testdata("mesh/wigley.stl.gz"), &opts).expect("reads");
    let w = Wigley { l: 1.0, b: 0.1, t };
    let m = mesh_hydrostatics(&mesh, t);
    assert!(m.inward && !m.half && m.open_edges_below == 0, "{m:?}");
    // The faceting of 12,896 triangles: V -0.32 %, S -0.04 %, KB +0.06 % (PROVENANCE.md: Cb
    // 0.4430, KB 0.6254 T); bounds at twice those.
    assert!(rel(m.volume, w.volume(t)).abs() < 0.0065, "{}", m.volume);
    assert!(rel(m.wetted_surface, 0.148791).abs() < 0.001, "{}", m.wetted_surface);
    assert!(rel(m.vcb, 0.625 * t).abs() < 0.0012, "{}", m.vcb);
    let out = slice(&mesh, Stations::Count { n: 41, spacing: Spacing::Cosine }, 30);
    assert_eq!(out.offsets.sections.len(), 41, "{:?}", out.dropped);
    for (s, info) in out.offsets.sections.iter().zip(&out.stations) {
        // Open at the top: no deck to cut; the sections end at the mesh's top edge, z = 0.1025.
        assert!(info.open_top && !info.deck_removed && info.pieces == 1, "{info:?}");
        assert_near!(s.points[s.points.len() - 1].z, t + 0.04, 1e-6);
        // Keel to top, the end stations included: their cut (2 µm wide, 1e-5 of L from the
        // stem) runs 3.3 mm down the centre plane before it turns up the side, and starts at
        // the bottom of that run, on the keel (before, 3.5 mm above it: the fit then dipped
        // below the keel at the stem and the envelope hold made a curvature spike there).
        assert_eq!(s.points[0].y, 0.0, "{}", s.label);
        assert!(s.points[0].z.abs() < 2e-4, "{}: keel at z = {}", s.label, s.points[0].z);
        assert!(s.points.windows(2).all(|w| w[1].z > w[0].z), "{}: z rises keel to top", s.label);
        for p in s.points.iter().filter(|p| p.z <= t) {
            // The mesh's faceting: 1.57e-4 m at most from the formula below the waterline,
            // measured (0.3 % of B/2).
            assert!((p.y - w.y(p.x, p.z)).abs() < 2e-4, "{p:?}: {}", w.y(p.x, p.z));
        }
    }
    for method in [FitMethod::Interp, FitMethod::Approx] {
        let (row, _) = surface_row(&out.offsets, method, t);
        // The fitted surface follows the mesh (V within 0.01 %, S within 0.03 %, measured), so
        // it keeps the mesh's faceting error against the closed forms.
        assert!(rel(row.vol, m.volume).abs() < 5e-4, "{method}: V {} vs {}", row.vol, m.volume);
        assert!(rel(row.s, m.wetted_surface).abs() < 1e-3, "{method}: S {} vs {}", row.s, m.wetted_surface);
        assert!(rel(row.vol, w.volume(t)).abs() < 0.0065, "{method}: V {}", row.vol);
        assert!(rel(row.s, 0.148791).abs() < 0.001, "{method}: S {}", row.s);
    }
}

/// DTMB 5415 (navaltoolbox's 3,436-facet mesh, full scale): the sonar dome below the baseline
/// and the transom. Published at T = 6.15 m: V 8424 m^3, S 2972.6 m^2; the mesh's own: V
/// 8386.5 m^3 (-0.45 %), S 2985.4 m^2 (+0.43 %).
#[test]
fn dtmb5415_sliced_and_fitted_against_its_mesh() {
    let mesh = read_mesh(&testdata("mesh/dtmb5415.stl.gz"), &MeshReadOptions::default()).expect("reads");
    let draft = 6.15;
    let m = mesh_hydrostatics(&mesh, draft);
    assert_near!(m.volume, 8386.5, 0.05);
    assert_near!(m.wetted_surface, 2985.4, 0.05);
    let out = slice(&mesh, Stations::Count { n: 41, spacing: Spacing::Cosine }, 30);
    // The end stations, 1e-5 of the length inside the mesh's extremes, cut slivers: 68 mm off
    // the top of the raked stern, 6 mm off the tip of the flared deck (2.1 and 2.2 % of the next
    // stations' cuts): both dropped, the hull ending in a point there (kept, the first hooked
    // the default fit 0.59 m behind the stern, the last spiked its curvature to 1.2e7 1/m²).
    assert_eq!(out.offsets.sections.len(), 39, "{:?}", out.dropped);
    let ends: Vec<&str> = out.dropped.iter().map(|d| d.label.as_str()).collect();
    assert_eq!(ends, ["1", "41"]);
    assert!(out.dropped.iter().all(|d| d.reason.starts_with("an end sliver")), "{:?}", out.dropped);
    // The sonar dome: the keel of the stations through it lies below the baseline, down to the
    // dome's bottom at z = -3.02 m.
    let lowest = out.offsets.sections.iter().map(|s| s.points[0].z).fold(f64::INFINITY, f64::min);
    assert!((-3.03..-2.8).contains(&lowest), "{lowest}");
    let (row, _) = surface_row(&out.offsets, FitMethod::Interp, draft);
    // Measured: V +0.05 %, S +0.83 % against the mesh. The wetted surface misses the 0.5 %
    // floor: the coarse mesh (1,720 vertices) is faceted, and between the dome's forward
    // end and the stem the one surface spans the notch of the profile.
    assert!(rel(row.vol, m.volume).abs() < 0.002, "V {}", row.vol);
    assert!(rel(row.s, m.wetted_surface).abs() < 0.012, "S {}", row.s);
    assert!(rel(row.vol, 8424.0).abs() < 0.01, "V {} vs published", row.vol);
    assert!(rel(row.s, 2972.6).abs() < 0.015, "S {} vs published", row.s);
}

/// LM on the DTMB 5415 mesh's offsets lowers the error at the offsets (RMS 38 against 96 mm)
/// but its surface faces inwards in places; the approximation it started from is sound, so that
/// one is written, as it is (no fairing search: with `auto` it looks for an approximation with
/// fewer defects than a sound one has, and on this mesh it kept the plain fit after 10 fits,
/// 60 % of LM's time).
#[test]
fn lm_on_the_dtmb5415_mesh_gives_way_to_the_sound_approximation_it_started_from() {
    let mesh = read_mesh(&testdata("mesh/dtmb5415.stl.gz"), &MeshReadOptions::default()).expect("reads");
    let offsets = slice_mesh(&mesh, &SliceOptions::default()).expect("slices").offsets;
    // `hullskin fit --method lm`: the fair objective.
    let fair = FitConfig { fair: hull::Fairing::Auto { tolerance: None }, ..FitConfig::default() };
    let out =
        fit_offsets(&offsets, &FitConfig { method: FitMethod::Optimized(hull::Algorithm::Lm), ..fair }).expect("fits");
    let plain = fit_offsets(&offsets, &FitConfig::default()).expect("fits");
    assert!(plain.validity.is_empty(), "{:?}", plain.validity);
    assert_eq!(out.rejected.len(), 1, "{:?}", out.rejected);
    assert!(out.rejected[0].contains("the sound approximation is kept"), "{}", out.rejected[0]);
    assert_eq!(out.config.method, FitMethod::Approx);
    assert_eq!(out.surface, plain.surface);
    assert!(out.validity.is_empty() && out.fairing.is_none());
    // The rejected optimisation is still reported (the summary's `weights by lm` line), as
    // where LM gives way for the envelope hold.
    let o = out.optimization.as_ref().expect("the rejected optimisation's record");
    assert_eq!(o.algorithm, "lm");
}
