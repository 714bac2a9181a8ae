//! Triangle meshes of a hull (STL, OBJ, VRML): reading, slicing into sections for the fit, and
//! measuring a fitted surface against the mesh.
//!
//! - [`read_mesh`] / [`parse_mesh`]: ASCII and binary STL ([`stl`]), Wavefront OBJ ([`obj`]),
//!   VRML 1.0 and 2.0 indexed face sets ([`vrml`]), each gzip-compressed or not (recognised
//!   by the gzip magic bytes, whatever the file name), the text forms with or without a UTF-8
//!   byte-order mark; the triangles are welded into an indexed [`TriMesh`] (the kernel's one
//!   mesh type, which a tessellated surface is too, written by [`stl::write_stl_ascii`],
//!   [`stl::write_stl_binary`] and [`obj::write_obj`]).
//! - [`slice::slice_mesh`]: cuts at stations `x = const`, each chained into one polyline on
//!   the starboard side from the keel to the deck edge, resampled, as [`crate::Offsets`].
//! - [`hydrostatics::mesh_hydrostatics`]: volume, centres, wetted surface and waterplane of the
//!   mesh at a draft, by the divergence theorem on the triangles clipped at the waterplane.
//! - [`distance::mesh_distance`]: the distance of the mesh's vertices to a fitted surface.
//!
//! The axes and units a mesh is read in are documented on [`MeshReadOptions`], where the
//! library's users read them.

mod distance;
mod gzip;
mod hydrostatics;
mod obj;
mod slice;
mod stl;
mod vrml;

use std::collections::HashMap;
use std::fmt;
use std::path::Path;
use std::str::FromStr;

use nurbs::{TriMesh, Vec3};

use crate::error::{HullError, InputErrorKind, Location};

pub use distance::{mesh_distance, MeshDistance, VertexFilter};
pub use gzip::{gunzip, is_gzip, MAX_DECOMPRESSED};
pub use hydrostatics::{mesh_hydrostatics, MeshHydrostatics};
pub use obj::{parse_obj, write_obj};
pub use slice::{
    slice_mesh, station_positions, DroppedStation, Resample, SliceOptions, SliceOutcome, Spacing, StationInfo,
    Stations, END_INSET, END_SLIVER, MAX_STATIONS,
};
pub use stl::{looks_binary, parse_stl, starts_with_solid, write_stl_ascii, write_stl_binary, STL_HEADER_LEN};
pub use vrml::parse_vrml;

/// A signed permutation of the axes: which coordinate of the file (and with which sign) gives
/// hullskin's x, y and z. Written `x,y,z` (the identity), `z,x,y`, `-x,-y,z`, ...; it must
/// name each of x, y, z once. An odd permutation or an odd number of minus signs mirrors
/// the mesh (its triangles then turn the other way, which nothing here depends on).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Axes {
    /// `(source axis 0..3, negate)` for hullskin's x, y, z.
    map: [(usize, bool); 3],
}

impl Default for Axes {
    /// The identity `x,y,z`.
    fn default() -> Self {
        Axes { map: [(0, false), (1, false), (2, false)] }
    }
}

impl Axes {
    /// True for the identity `x,y,z`.
    pub fn is_identity(&self) -> bool {
        *self == Axes::default()
    }

    /// The point of the file `p` in hullskin's axes.
    pub fn apply(&self, p: Vec3) -> Vec3 {
        let c = |(axis, neg): (usize, bool)| if neg { -p[axis] } else { p[axis] };
        Vec3::new(c(self.map[0]), c(self.map[1]), c(self.map[2]))
    }
}

impl FromStr for Axes {
    type Err = HullError;

    /// Parses `x,y,z`, `-z,x,y`, ... (case and spaces ignored).
    fn from_str(s: &str) -> Result<Self, HullError> {
        let bad = || HullError::UnknownAxes { text: s.to_string() };
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        if parts.len() != 3 {
            return Err(bad());
        }
        let mut map = [(0, false); 3];
        let mut seen = [false; 3];
        for (slot, part) in map.iter_mut().zip(&parts) {
            let lower = part.to_ascii_lowercase();
            let (neg, name) = match lower.strip_prefix('-') {
                Some(rest) => (true, rest.trim()),
                None => (false, lower.strip_prefix('+').unwrap_or(&lower).trim()),
            };
            let axis = match name {
                "x" => 0,
                "y" => 1,
                "z" => 2,
                _ => return Err(bad()),
            };
            if seen[axis] {
                return Err(bad());
            }
            seen[axis] = true;
            *slot = (axis, neg);
        }
        Ok(Axes { map })
    }
}

impl fmt::Display for Axes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, &(axis, neg)) in self.map.iter().enumerate() {
            if k > 0 {
                f.write_str(",")?;
            }
            if neg {
                f.write_str("-")?;
            }
            f.write_str(["x", "y", "z"][axis])?;
        }
        Ok(())
    }
}

/// The mesh file formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// STL, ASCII or binary (told apart by [`stl::parse_stl`]).
    Stl,
    /// Wavefront OBJ.
    Obj,
    /// VRML 1.0 or 2.0 (VRML97): its indexed face sets.
    Vrml,
}

impl MeshFormat {
    /// The format named by a file name's extension (`.stl`, `.obj`, `.wrl`, `.vrml`, each
    /// optionally followed by `.gz`, and `.wrz`, gzipped VRML; case-insensitive), `None` for
    /// another name.
    pub fn from_path(path: &Path) -> Option<MeshFormat> {
        let name = path.file_name()?.to_string_lossy().to_ascii_lowercase();
        let name = name.strip_suffix(".gz").unwrap_or(&name);
        if name.ends_with(".stl") {
            Some(MeshFormat::Stl)
        } else if name.ends_with(".obj") {
            Some(MeshFormat::Obj)
        } else if [".wrl", ".vrml", ".wrz"].iter().any(|e| name.ends_with(e)) {
            Some(MeshFormat::Vrml)
        } else {
            None
        }
    }

    /// The format told from the content: VRML if the text starts with `#VRML`, STL if it
    /// starts with `solid` or the size fits a binary STL's triangle count, OBJ if the first
    /// statement is an OBJ keyword; `None` otherwise.
    pub fn sniff(bytes: &[u8]) -> Option<MeshFormat> {
        if bytes.starts_with(b"#VRML") {
            return Some(MeshFormat::Vrml);
        }
        if stl::looks_binary(bytes) || stl::starts_with_solid(bytes) {
            return Some(MeshFormat::Stl);
        }
        let text = &bytes[..bytes.len().min(4096)];
        for line in text.split(|&b| b == b'\n') {
            let word = line.split(|b| b.is_ascii_whitespace()).find(|w| !w.is_empty());
            match word {
                None => continue,
                Some(w) if w.starts_with(b"#") => continue,
                Some(w) => {
                    return [&b"v"[..], b"vn", b"vt", b"f", b"o", b"g", b"mtllib", b"usemtl", b"s"]
                        .contains(&w)
                        .then_some(MeshFormat::Obj)
                }
            }
        }
        None
    }
}

/// Settings of [`read_mesh`] and [`parse_mesh`].
///
/// # Axes and units
///
/// The mesh is expected in hullskin's axes (see [`crate::Offsets`]): **x forward** (from the
/// aft perpendicular or any origin), **y across** with the centre plane at `y = 0` (the mesh
/// holds both sides, or only the starboard side `y >= 0`), **z up** (from the keel or any
/// origin). Meshes in other axes are brought to these by [`MeshReadOptions::axes`], a signed
/// permutation applied first, and [`MeshReadOptions::shift`], a translation applied after it:
/// the point `p` of the file becomes `axes(p) + shift`. For instance a mesh with z forward and
/// y up (common in graphics) is read with axes `z,x,y`; a mesh whose bow points to -x with
/// `-x,-y,z` (a half turn about z, which keeps the frame right-handed).
///
/// Coordinates are not converted: as for offsets, the units (`--units`) are a label carried
/// to the outputs ([`crate::Units`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshReadOptions {
    /// The file's axes as hullskin's (default identity `x,y,z`).
    pub axes: Axes,
    /// Added to every vertex after `axes` (default 0): e.g. `(0, 0, T)` brings a mesh with
    /// z = 0 at the waterline to z = 0 at the keel.
    pub shift: Vec3,
    /// Vertices closer than this (in the file's units) are merged into one. The default 0
    /// merges only exactly equal coordinates, which is right for STL writers that print every
    /// vertex the same way each time it appears; raise it for meshes whose shared corners
    /// differ by round-off.
    pub weld_tolerance: f64,
}

impl Default for MeshReadOptions {
    fn default() -> Self {
        MeshReadOptions { axes: Axes::default(), shift: Vec3::new(0.0, 0.0, 0.0), weld_tolerance: 0.0 }
    }
}

/// Reads a mesh file: STL (ASCII or binary), OBJ or VRML, optionally gzip-compressed. The
/// format is taken from the extension ([`MeshFormat::from_path`]), else from the content
/// ([`MeshFormat::sniff`]); a gzip stream is recognised by its magic bytes.
///
/// # Errors
/// [`HullError::Io`] when the file cannot be read; [`HullError::Input`] for a corrupt gzip
/// stream, an unknown format, and every error of [`parse_mesh`].
pub fn read_mesh(path: &Path, options: &MeshReadOptions) -> Result<TriMesh, HullError> {
    let bytes = crate::limits::read_capped(path, crate::limits::MAX_MESH_FILE_BYTES, "a mesh file")?;
    let source = path.display().to_string();
    parse_mesh(&bytes, &source, MeshFormat::from_path(path), options)
}

/// Parses a mesh held in memory; `source` names it in messages, `format` is the format when
/// known (else sniffed from the content). Gzip-compressed bytes are decompressed first
/// ([`gunzip`]; [`HullError::FeatureDisabled`] without the cargo feature `gzip`).
///
/// # Errors
/// [`InputErrorKind::Mesh`] located at the line (text formats) or naming the byte offset
/// (binary STL) of the first problem: see [`stl::parse_stl`], [`obj::parse_obj`] and
/// [`vrml::parse_vrml`]; and for a mesh whose format cannot be told, or that has no triangle.
pub fn parse_mesh(
    bytes: &[u8],
    source: &str,
    format: Option<MeshFormat>,
    options: &MeshReadOptions,
) -> Result<TriMesh, HullError> {
    let inflated;
    let bytes = if is_gzip(bytes) {
        inflated = gunzip(bytes, source)?;
        &inflated[..]
    } else {
        bytes
    };
    // A UTF-8 byte-order mark before an ASCII STL or an OBJ (a Windows editor's): skipped, unless
    // the bytes are a binary STL whose free-text header happens to start with it.
    let bytes = match bytes.strip_prefix(b"\xEF\xBB\xBF") {
        Some(text) if !stl::looks_binary(bytes) => text,
        _ => bytes,
    };
    let format = format.or_else(|| MeshFormat::sniff(bytes)).ok_or_else(|| {
        mesh_error(
            Location::file(source),
            "a file that is neither STL, OBJ nor VRML".to_string(),
            "an STL file (starting with \"solid\", or binary), an OBJ file (v and f lines) or a VRML file \
             (starting with \"#VRML\"), optionally gzipped",
        )
    })?;
    let soup = match format {
        MeshFormat::Stl => stl::parse_stl(bytes, source)?,
        MeshFormat::Obj => obj::parse_obj(bytes, source)?,
        MeshFormat::Vrml => vrml::parse_vrml(bytes, source)?,
    };
    if soup.triangles.is_empty() {
        return Err(mesh_error(Location::file(source), "no triangle".to_string(), "at least one facet"));
    }
    crate::limits::check_mesh_triangles(source, soup.triangles.len() as u64)?;
    if !(options.weld_tolerance >= 0.0 && options.weld_tolerance.is_finite()) {
        return Err(HullError::Setting {
            name: "weld tolerance".to_string(),
            value: options.weld_tolerance,
            expected: "a finite distance >= 0",
        });
    }
    let points: Vec<Vec3> = soup.vertices.iter().map(|&p| options.axes.apply(p) + options.shift).collect();
    let (vertices, remap) = weld(&points, options.weld_tolerance);
    let mut triangles = Vec::with_capacity(soup.triangles.len());
    let mut degenerate = 0;
    for t in &soup.triangles {
        let [a, b, c] = t.map(|i| remap[i as usize]);
        if a == b || b == c || c == a {
            degenerate += 1;
        } else {
            triangles.push([a, b, c]);
        }
    }
    Ok(TriMesh { source: source.to_string(), vertices, triangles, degenerate, normals: Vec::new() })
}

/// Triangles as read from a file, before welding: vertex positions and index triples (STL
/// gives three new vertices per facet; OBJ and VRML their own vertex lists).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleSoup {
    /// Vertex positions in the file's axes.
    pub vertices: Vec<Vec3>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

/// Merges points closer than `tol` (exactly equal ones for `tol == 0`; `-0.0` equals `0.0`):
/// returns the distinct points, in order of first appearance, and for every input point the
/// index of the point it became. With `tol > 0` each point joins the first earlier kept point
/// within `tol` (found through a hash grid of cell `tol`), so the result does not depend on
/// anything but the input order.
pub fn weld(points: &[Vec3], tol: f64) -> (Vec<Vec3>, Vec<u32>) {
    let mut kept: Vec<Vec3> = Vec::new();
    let mut remap = Vec::with_capacity(points.len());
    if tol > 0.0 {
        let cell = |p: Vec3| [p.x, p.y, p.z].map(|c| (c / tol).floor() as i64);
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        for &p in points {
            let c = cell(p);
            let mut found: Option<u32> = None;
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        // Wrapping: cells of coordinates beyond i64 (saturated) never panic.
                        let key = [c[0].wrapping_add(dx), c[1].wrapping_add(dy), c[2].wrapping_add(dz)];
                        for &i in grid.get(&key).into_iter().flatten() {
                            if kept[i as usize].distance(p) <= tol && found.is_none_or(|f| i < f) {
                                found = Some(i);
                            }
                        }
                    }
                }
            }
            let index = match found {
                Some(i) => i,
                None => {
                    let i = kept.len() as u32;
                    kept.push(p);
                    grid.entry(c).or_default().push(i);
                    i
                }
            };
            remap.push(index);
        }
    } else {
        let key = |p: Vec3| [p.x, p.y, p.z].map(|c| if c == 0.0 { 0 } else { c.to_bits() });
        let mut map: HashMap<[u64; 3], u32> = HashMap::with_capacity(points.len() / 4);
        for &p in points {
            let next = kept.len() as u32;
            let index = *map.entry(key(p)).or_insert(next);
            if index == next {
                kept.push(p);
            }
            remap.push(index);
        }
    }
    (kept, remap)
}

/// The text of a text mesh format (OBJ, VRML), or an [`InputErrorKind::Mesh`] error at the
/// line of the first byte that is not UTF-8; `expected` names the format.
pub(crate) fn mesh_text<'a>(bytes: &'a [u8], source: &str, expected: &str) -> Result<&'a str, HullError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let pos = e.valid_up_to();
        let line = 1 + bytes[..pos].iter().filter(|&&b| b == b'\n').count();
        mesh_error(Location::line(source, line), format!("invalid UTF-8 at byte offset {pos}"), expected)
    })
}

/// An [`InputErrorKind::Mesh`] error at `at`.
pub(crate) fn mesh_error(at: Location, found: String, expected: &str) -> HullError {
    HullError::input(at, InputErrorKind::Mesh { found, expected: expected.to_string() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_parse_print_and_apply() {
        let a: Axes = " -X , z,y ".parse().expect("valid axes");
        assert_eq!(a.to_string(), "-x,z,y");
        let p = a.apply(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(p, Vec3::new(-1.0, 3.0, 2.0));
        assert!(Axes::default().is_identity());
        assert_eq!("x,y,z".parse::<Axes>().expect("identity"), Axes::default());
        for bad in ["x,y", "x,x,z", "x,y,w", "x,y,z,x", "", "--x,y,z"] {
            let e = bad.parse::<Axes>().expect_err(bad).to_string();
            assert!(e.contains("each of x, y, z once"), "{bad}: {e}");
        }
    }

    #[test]
    fn exact_weld_merges_equal_points_and_signed_zeros() {
        let p = |x, y, z| Vec3::new(x, y, z);
        let pts = [p(0.0, 0.0, 0.0), p(1.0, 0.0, 0.0), p(-0.0, 0.0, 0.0), p(1.0, 0.0, 1e-300), p(1.0, 0.0, 0.0)];
        let (kept, remap) = weld(&pts, 0.0);
        assert_eq!(kept, vec![pts[0], pts[1], pts[3]]);
        assert_eq!(remap, vec![0, 1, 0, 2, 1]);
    }

    #[test]
    fn tolerance_weld_joins_the_first_earlier_point_within_reach() {
        let p = |x: f64| Vec3::new(x, 0.5, 0.5);
        // -0.009 joins 0.0 across a grid cell boundary (cells of 0.01); 0.025 does not
        // (0.025 > 0.01 from both); 0.0305 joins 0.025.
        let pts = [p(0.0), p(0.025), p(-0.009), p(0.0305), p(0.009)];
        let (kept, remap) = weld(&pts, 0.01);
        assert_eq!(kept, vec![p(0.0), p(0.025)]);
        assert_eq!(remap, vec![0, 1, 0, 1, 0]);
    }

    #[test]
    fn format_from_name_and_content() {
        assert_eq!(MeshFormat::from_path(Path::new("a/Hull.STL.gz")), Some(MeshFormat::Stl));
        assert_eq!(MeshFormat::from_path(Path::new("hull.obj")), Some(MeshFormat::Obj));
        assert_eq!(MeshFormat::from_path(Path::new("cont.WRL")), Some(MeshFormat::Vrml));
        assert_eq!(MeshFormat::from_path(Path::new("hull.wrl.gz")), Some(MeshFormat::Vrml));
        assert_eq!(MeshFormat::from_path(Path::new("hull.wrz")), Some(MeshFormat::Vrml));
        assert_eq!(MeshFormat::from_path(Path::new("hull.csv")), None);
        assert_eq!(MeshFormat::sniff(b"#VRML V2.0 utf8\n"), Some(MeshFormat::Vrml));
        assert_eq!(MeshFormat::sniff(b"  solid hull\nfacet"), Some(MeshFormat::Stl));
        assert_eq!(MeshFormat::sniff(b"# made by hand\n\nv 0 0 0\n"), Some(MeshFormat::Obj));
        assert_eq!(MeshFormat::sniff(b"section,x,y,z\n"), None);
    }

    #[test]
    fn a_byte_order_mark_before_a_text_mesh_is_skipped() {
        let opts = MeshReadOptions::default();
        let stl = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        for (text, format) in [(stl, None), (stl, Some(MeshFormat::Stl)), (obj, None), (obj, Some(MeshFormat::Obj))] {
            let plain = parse_mesh(text.as_bytes(), "t", format, &opts).expect("plain");
            let bom = parse_mesh(format!("\u{FEFF}{text}").as_bytes(), "t", format, &opts).expect("with a BOM");
            assert_eq!((bom.vertices, bom.triangles), (plain.vertices, plain.triangles), "{format:?}");
        }
        // A binary STL whose 80-byte header starts with the BOM's bytes keeps its header.
        let mut bin = b"\xEF\xBB\xBFbinary".to_vec();
        bin.resize(80, b' ');
        bin.extend_from_slice(&1u32.to_le_bytes());
        for v in [[0f32; 3], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            v.iter().for_each(|c| bin.extend_from_slice(&c.to_le_bytes()));
        }
        bin.extend_from_slice(&[0, 0]);
        assert_eq!(parse_mesh(&bin, "b.stl", None, &opts).expect("binary").triangles.len(), 1);
    }
}
