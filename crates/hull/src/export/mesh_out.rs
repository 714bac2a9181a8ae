//! Mesh exports of a [`Tessellation`]: STL (binary and ASCII), Wavefront OBJ and binary glTF
//! 2.0 (`.glb`). STL and OBJ are written by the one writer of each format
//! ([`crate::mesh::stl`], [`crate::mesh::obj`]), given the labels made here; glTF is written
//! here.
//!
//! The formats are documented on [`stl_header`] (binary STL), [`mesh_name`] (ASCII STL),
//! [`obj_comments`] (OBJ) and [`write_glb`] (glTF), where the library's users read them.
//!
//! Text numbers go through [`crate::float::real`]; binary ones are IEEE little-endian.

use std::io::{self, Write};

use nurbs::{Tessellation, Vec3};

use crate::colormap::{curvature_limit, diverging};
use crate::float::real;
use crate::Units;

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// `name` as a name token of STL and OBJ: printable ASCII without spaces (others become
/// `_`); `hull` if nothing is left.
///
/// **STL ASCII**: `solid NAME` ([`mesh_name`]), per triangle `facet normal nx ny nz`,
/// `outer loop`, three `vertex x y z`, `endloop`, `endfacet`; `endsolid NAME`.
pub fn mesh_name(name: &str) -> String {
    let t: String = name.chars().map(|c| if c.is_ascii_graphic() { c } else { '_' }).collect();
    if t.is_empty() {
        "hull".into()
    } else {
        t
    }
}

/// The binary STL header of a mesh named `name` in `units`:
/// `hullskin binary STL NAME units SYMBOL` (cut to 80 bytes by the writer).
///
/// **STL binary**: the header [`stl_header`] (ASCII, never starting with `solid`, so
/// readers do not take it for ASCII STL, naming the units), then per triangle the unit
/// normal and the three corners as little-endian f32. The normal is the triangle's own,
/// agreeing with its counter-clockwise winding (outward).
pub fn stl_header(name: &str, units: Units) -> String {
    format!("hullskin binary STL {} units {}", mesh_name(name), units.symbol())
}

/// The OBJ comments of a mesh named `name`, triangulated to `tolerance` in `units`: the
/// version, the tolerance, the units and the axes.
///
/// **OBJ**: the comments [`obj_comments`] naming the units, `o NAME`, `v x y z` and
/// `vn nx ny nz` per vertex (the surface's outward normal there), `f a//a b//b c//c` per
/// triangle (1-based).
///
/// STL and OBJ keep the surface's coordinates and units (neither format records units; the
/// OBJ comment and the STL header name them).
///
/// # Errors
/// [`io::ErrorKind::InvalidData`] for a non-finite tolerance.
pub fn obj_comments(name: &str, tolerance: f64, units: Units) -> io::Result<Vec<String>> {
    Ok(vec![
        format!(
            "hullskin {}: {} triangulated to {} {}",
            env!("CARGO_PKG_VERSION"),
            mesh_name(name),
            real(tolerance)?,
            units.symbol()
        ),
        format!("units: {}; axes: x forward, y to starboard, z up", units.plural_name()),
    ])
}

/// The glTF position of a model point in `units`: metres, `(X, Y, Z) = (y, z, x)`.
pub fn gltf_position(p: Vec3, units: Units) -> [f32; 3] {
    let k = units.metres_per_unit();
    [(p.y * k) as f32, (p.z * k) as f32, (p.x * k) as f32]
}

/// The glTF direction of a model direction (the same permutation, no scaling), renormalised
/// in f32.
pub fn gltf_direction(n: Vec3) -> [f32; 3] {
    let d = [n.y as f32, n.z as f32, n.x as f32];
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if len > 0.0 {
        d.map(|c| c / len)
    } else {
        [0.0, 1.0, 0.0]
    }
}

/// sRGB channel (0..=255) to linear (IEC 61966-2-1).
pub fn srgb_to_linear(c: u8) -> f32 {
    let c = f64::from(c) / 255.0;
    (if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }) as f32
}

/// Linear RGB of every vertex: its Gaussian curvature on the diverging map.
pub fn curvature_colors(tess: &Tessellation) -> Vec<[f32; 3]> {
    let limit = curvature_limit(&tess.gaussian);
    tess.gaussian
        .iter()
        .map(|&k| {
            let c = diverging(k, limit);
            [srgb_to_linear(c.0), srgb_to_linear(c.1), srgb_to_linear(c.2)]
        })
        .collect()
}

/// A JSON string literal.
fn json_string(s: &str) -> String {
    serde_json::to_string(s).expect("a string always serializes")
}

fn json_reals(xs: &[f64]) -> io::Result<String> {
    Ok(format!("[{}]", xs.iter().map(|&x| real(x)).collect::<io::Result<Vec<_>>>()?.join(",")))
}

/// Component-wise min and max of f32 triples, as the f64 values of those f32s.
fn bounds(v: &[[f32; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in v {
        for k in 0..3 {
            lo[k] = lo[k].min(f64::from(p[k]));
            hi[k] = hi[k].max(f64::from(p[k]));
        }
    }
    (lo, hi)
}

/// glTF constants (glTF 2.0 section 5.1.3 and 5.11.1).
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const TRIANGLES: u32 = 4;
const GLB_MAGIC: u32 = 0x4654_6C67;
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// Write the mesh of `tess` (in `units`) as one binary glTF 2.0 file.
///
/// **glTF binary** (Khronos glTF 2.0, section 4.4 "GLB file format specification"): a
/// 12-byte header (`glTF`, version 2, total length), a JSON chunk padded with spaces and a
/// BIN chunk, each 4-byte aligned. One mesh of one indexed triangle primitive (mode 4) with
/// `POSITION` (f32 VEC3, with the `min`/`max` the specification requires), `NORMAL` (f32
/// unit VEC3), `COLOR_0` (f32 VEC3, linear RGB) and `u32` indices, one material
/// (white, not metallic, double-sided as the surface is open), one node and one scene.
/// glTF fixes metres and +Y up (section 3.4), so lengths are converted to metres and the
/// axes permuted cyclically, `(X, Y, Z) = (y, z, x)`: up is up, forward is +Z, and the
/// permutation is a rotation (no mirror image). `COLOR_0` is the Gaussian curvature on the
/// diverging map [`diverging`] (blue negative, white zero, red positive), saturating at
/// [`curvature_limit`] (the 98th percentile of `|K|`, as in the 3-D viewer),
/// its sRGB stops turned into linear values as glTF requires
/// (`c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4`, IEC 61966-2-1). The
/// `extras` of the asset record the source units, the axes and the curvature limit.
///
/// # Errors
/// Whatever `w` returns; [`io::ErrorKind::InvalidInput`] for an empty mesh or one too large
/// for the 32-bit lengths of GLB; [`io::ErrorKind::InvalidData`] for a non-finite number.
pub fn write_glb<W: Write>(w: &mut W, tess: &Tessellation, name: &str, units: Units) -> io::Result<()> {
    let mesh = &tess.mesh;
    if mesh.triangles.is_empty() {
        return Err(invalid("no triangles to write".into()));
    }
    let positions: Vec<[f32; 3]> = mesh.vertices.iter().map(|&p| gltf_position(p, units)).collect();
    if positions.iter().flatten().any(|c| !c.is_finite()) {
        return Err(io::Error::new(io::ErrorKind::InvalidData, "a vertex is not finite in f32"));
    }
    let normals: Vec<[f32; 3]> = mesh.normals.iter().map(|&n| gltf_direction(n)).collect();
    let colors = curvature_colors(tess);
    let limit = curvature_limit(&tess.gaussian);
    let n = positions.len();
    let vec3_bytes = 12 * n;
    let index_bytes = 12 * mesh.triangles.len();
    let bin_len = 3 * vec3_bytes + index_bytes;
    let too_big = || invalid(format!("{n} vertices and {} triangles do not fit a GLB file", mesh.triangles.len()));
    let bin_len_u32 = u32::try_from(bin_len).map_err(|_| too_big())?;

    let (lo, hi) = bounds(&positions);
    let view = |k: usize, offset: usize, len: usize, target: u32| {
        format!(
            "{{\"buffer\":0,\"byteOffset\":{offset},\"byteLength\":{len},\"target\":{target},\"name\":\"view{k}\"}}"
        )
    };
    let views = [
        view(0, 0, vec3_bytes, ARRAY_BUFFER),
        view(1, vec3_bytes, vec3_bytes, ARRAY_BUFFER),
        view(2, 2 * vec3_bytes, vec3_bytes, ARRAY_BUFFER),
        view(3, 3 * vec3_bytes, index_bytes, ELEMENT_ARRAY_BUFFER),
    ];
    let accessors = [
        format!(
            "{{\"bufferView\":0,\"componentType\":{FLOAT},\"count\":{n},\"type\":\"VEC3\",\"min\":{},\"max\":{},\
             \"name\":\"POSITION\"}}",
            json_reals(&lo)?,
            json_reals(&hi)?
        ),
        format!("{{\"bufferView\":1,\"componentType\":{FLOAT},\"count\":{n},\"type\":\"VEC3\",\"name\":\"NORMAL\"}}"),
        format!("{{\"bufferView\":2,\"componentType\":{FLOAT},\"count\":{n},\"type\":\"VEC3\",\"name\":\"COLOR_0\"}}"),
        format!(
            "{{\"bufferView\":3,\"componentType\":{UNSIGNED_INT},\"count\":{},\"type\":\"SCALAR\",\"name\":\"indices\"}}",
            3 * mesh.triangles.len()
        ),
    ];
    let name_json = json_string(name);
    let generator = json_string(&format!("hullskin {}", env!("CARGO_PKG_VERSION")));
    let extras = format!(
        "{{\"source_units\":{},\"axes\":\"X = starboard (y), Y = up (z), Z = forward (x); metres\",\
         \"color\":\"Gaussian curvature, diverging map, saturating at +-{} 1/m^2\",\"gaussian_curvature_limit\":{},\
         \"tolerance\":{}}}",
        json_string(units.symbol()),
        real(limit / units.metres_per_unit().powi(2))?,
        real(limit / units.metres_per_unit().powi(2))?,
        real(tess.tolerance * units.metres_per_unit())?,
    );
    let mut json = format!(
        "{{\"asset\":{{\"version\":\"2.0\",\"generator\":{generator},\"extras\":{extras}}},\"scene\":0,\
         \"scenes\":[{{\"name\":{name_json},\"nodes\":[0]}}],\"nodes\":[{{\"name\":{name_json},\"mesh\":0}}],\
         \"meshes\":[{{\"name\":{name_json},\"primitives\":[{{\"attributes\":{{\"POSITION\":0,\"NORMAL\":1,\
         \"COLOR_0\":2}},\"indices\":3,\"material\":0,\"mode\":{TRIANGLES}}}]}}],\
         \"materials\":[{{\"name\":\"hull\",\"pbrMetallicRoughness\":{{\"baseColorFactor\":[1.0,1.0,1.0,1.0],\
         \"metallicFactor\":0.0,\"roughnessFactor\":0.7}},\"doubleSided\":true}}],\
         \"accessors\":[{}],\"bufferViews\":[{}],\"buffers\":[{{\"byteLength\":{bin_len}}}]}}",
        accessors.join(","),
        views.join(",")
    );
    while json.len() % 4 != 0 {
        json.push(' ');
    }
    let json_len = u32::try_from(json.len()).map_err(|_| too_big())?;
    let total = 12u64 + 8 + u64::from(json_len) + 8 + u64::from(bin_len_u32);
    let total = u32::try_from(total).map_err(|_| too_big())?;

    w.write_all(&GLB_MAGIC.to_le_bytes())?;
    w.write_all(&2u32.to_le_bytes())?;
    w.write_all(&total.to_le_bytes())?;
    w.write_all(&json_len.to_le_bytes())?;
    w.write_all(&CHUNK_JSON.to_le_bytes())?;
    w.write_all(json.as_bytes())?;
    w.write_all(&bin_len_u32.to_le_bytes())?;
    w.write_all(&CHUNK_BIN.to_le_bytes())?;
    let mut buf = Vec::with_capacity(bin_len);
    for v in [&positions, &normals, &colors] {
        for c in v.iter().flatten() {
            buf.extend_from_slice(&c.to_le_bytes());
        }
    }
    for i in mesh.triangles.iter().flatten() {
        buf.extend_from_slice(&i.to_le_bytes());
    }
    w.write_all(&buf)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::write_obj;
    use crate::mesh::{write_stl_ascii, write_stl_binary};
    use nurbs::{tessellate, TessellationOptions};

    fn cylinder_mesh(mirror: bool) -> Tessellation {
        let surface = nurbs::fixtures::quarter_cylinder_along_x(2.0, 3.0);
        tessellate(&surface, &TessellationOptions { tolerance: 1e-2, mirror }).expect("tessellates")
    }

    fn le_u32(b: &[u8], at: usize) -> u32 {
        u32::from_le_bytes(b[at..at + 4].try_into().expect("4 bytes"))
    }

    fn le_f32(b: &[u8], at: usize) -> f32 {
        f32::from_le_bytes(b[at..at + 4].try_into().expect("4 bytes"))
    }

    #[test]
    fn binary_stl_layout() {
        let tess = cylinder_mesh(true);
        let mut out = Vec::new();
        write_stl_binary(&mut out, &tess.mesh, &stl_header("cyl", Units::Metre)).expect("writes");
        assert_eq!(out.len(), 84 + 50 * tess.mesh.triangles.len());
        assert!(!out.starts_with(b"solid"));
        assert_eq!(le_u32(&out, 80) as usize, tess.mesh.triangles.len());
        // Every record: the corners of its triangle in f32, and a unit normal agreeing with
        // the winding.
        for (t, rec) in out[84..].chunks(50).enumerate() {
            let f = |k: usize| f64::from(le_f32(rec, 4 * k));
            let n = Vec3::new(f(0), f(1), f(2));
            assert!((n.norm() - 1.0).abs() < 1e-6);
            for (c, &k) in tess.mesh.triangles[t].iter().enumerate() {
                let p = tess.mesh.vertices[k as usize];
                let q = Vec3::new(f(3 + 3 * c), f(4 + 3 * c), f(5 + 3 * c));
                // f32 rounding: half an ulp of |p| <= 3 is below 2.4e-7.
                assert!(p.distance(q) < 5e-7, "{p:?} vs {q:?}");
            }
            assert!(n.dot(tess.mesh.face_normal(t)) > 1.0 - 1e-6);
            assert_eq!(&rec[48..], &[0, 0]);
        }
    }

    #[test]
    fn ascii_stl_and_obj_parse_back() {
        let tess = cylinder_mesh(false);
        let mut out = Vec::new();
        write_stl_ascii(&mut out, &tess.mesh, &mesh_name("my hull")).expect("writes");
        let text = String::from_utf8(out).expect("ASCII");
        assert!(text.starts_with("solid my_hull\n") && text.ends_with("endsolid my_hull\n"));
        let vertices: Vec<Vec3> = text
            .lines()
            .filter_map(|l| l.trim().strip_prefix("vertex "))
            .map(|l| {
                let c: Vec<f64> = l.split(' ').map(|x| x.parse().expect("a number")).collect();
                Vec3::new(c[0], c[1], c[2])
            })
            .collect();
        assert_eq!(vertices.len(), 3 * tess.mesh.triangles.len());
        for (k, v) in vertices.iter().enumerate() {
            // Shortest round-trip text: exact.
            assert_eq!(*v, tess.mesh.vertices[tess.mesh.triangles[k / 3][k % 3] as usize]);
        }
        assert_eq!(text.matches("facet normal").count(), tess.mesh.triangles.len());

        let mut out = Vec::new();
        let comments = obj_comments("hull", tess.tolerance, Units::Foot).expect("finite");
        write_obj(&mut out, &tess.mesh, &comments, Some(&mesh_name("hull"))).expect("writes");
        let text = String::from_utf8(out).expect("ASCII");
        assert!(text.contains("# units: feet"));
        let v: Vec<&str> = text.lines().filter(|l| l.starts_with("v ")).collect();
        let vn: Vec<&str> = text.lines().filter(|l| l.starts_with("vn ")).collect();
        let f: Vec<&str> = text.lines().filter(|l| l.starts_with("f ")).collect();
        assert_eq!(
            (v.len(), vn.len(), f.len()),
            (tess.mesh.vertices.len(), tess.mesh.normals.len(), tess.mesh.triangles.len())
        );
        let first: Vec<f64> = v[0][2..].split(' ').map(|x| x.parse().expect("a number")).collect();
        assert_eq!(Vec3::new(first[0], first[1], first[2]), tess.mesh.vertices[0]);
        let [a, b, c] = tess.mesh.triangles[0].map(|k| k + 1);
        assert_eq!(f[0], format!("f {a}//{a} {b}//{b} {c}//{c}"));
    }

    #[test]
    fn glb_layout_and_accessors() {
        let tess = cylinder_mesh(true);
        let mut out = Vec::new();
        write_glb(&mut out, &tess, "cyl", Units::Millimetre).expect("writes");
        assert_eq!(le_u32(&out, 0), GLB_MAGIC);
        assert_eq!(le_u32(&out, 4), 2);
        assert_eq!(le_u32(&out, 8) as usize, out.len());
        let json_len = le_u32(&out, 12) as usize;
        assert_eq!(le_u32(&out, 16), CHUNK_JSON);
        assert_eq!(json_len % 4, 0);
        let doc: serde_json::Value = serde_json::from_slice(&out[20..20 + json_len]).expect("JSON chunk");
        let bin_at = 20 + json_len;
        let bin_len = le_u32(&out, bin_at) as usize;
        assert_eq!(le_u32(&out, bin_at + 4), CHUNK_BIN);
        let bin = &out[bin_at + 8..];
        assert_eq!(bin.len(), bin_len);
        assert_eq!(doc["buffers"][0]["byteLength"].as_u64(), Some(bin_len as u64));
        // POSITION: metres, permuted axes; min and max exactly those of the data.
        let n = tess.mesh.vertices.len();
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for (k, p) in tess.mesh.vertices.iter().enumerate() {
            let q = [le_f32(bin, 12 * k), le_f32(bin, 12 * k + 4), le_f32(bin, 12 * k + 8)];
            assert_eq!(q, [(p.y * 1e-3) as f32, (p.z * 1e-3) as f32, (p.x * 1e-3) as f32]);
            for c in 0..3 {
                lo[c] = lo[c].min(q[c]);
                hi[c] = hi[c].max(q[c]);
            }
        }
        let acc = &doc["accessors"][0];
        for c in 0..3 {
            assert_eq!(acc["min"][c].as_f64(), Some(f64::from(lo[c])));
            assert_eq!(acc["max"][c].as_f64(), Some(f64::from(hi[c])));
        }
        // NORMAL unit length, COLOR_0 in [0, 1], indices in range.
        for k in 0..n {
            let o = 12 * n + 12 * k;
            let len = (0..3).map(|c| le_f32(bin, o + 4 * c).powi(2)).sum::<f32>().sqrt();
            assert!((len - 1.0).abs() < 1e-6);
            for c in 0..3 {
                assert!((0.0..=1.0).contains(&le_f32(bin, 24 * n + 12 * k + 4 * c)));
            }
        }
        let indices = &bin[36 * n..];
        assert_eq!(indices.len(), 12 * tess.mesh.triangles.len());
        assert!(indices.chunks(4).all(|b| (u32::from_le_bytes(b.try_into().expect("4")) as usize) < n));
    }

    #[test]
    fn colors_follow_the_diverging_map() {
        assert_eq!(srgb_to_linear(0), 0.0);
        assert_eq!(srgb_to_linear(255), 1.0);
        // sRGB 0.5 is linear 0.214 (IEC 61966-2-1).
        assert!((srgb_to_linear(128) - 0.2158605).abs() < 1e-6);
        let limit = curvature_limit(&[0.0, -1.0, 2.0, f64::NAN, 0.5]);
        assert_eq!(limit, 2.0);
        assert_eq!(curvature_limit(&[0.0, f64::NAN]), 1.0);
        let mut tess = cylinder_mesh(false);
        tess.gaussian = (0..tess.mesh.vertices.len()).map(|k| k as f64 - 10.0).collect();
        let colors = curvature_colors(&tess);
        // K = 0 is white (247, 247, 247 in sRGB).
        let white = srgb_to_linear(247);
        assert_eq!(colors[10], [white, white, white]);
    }

    #[test]
    fn empty_mesh_is_refused() {
        let mut tess = cylinder_mesh(false);
        tess.mesh.triangles.clear();
        assert_eq!(
            write_glb(&mut Vec::new(), &tess, "x", Units::Metre).expect_err("empty").kind(),
            io::ErrorKind::InvalidInput
        );
    }
}
