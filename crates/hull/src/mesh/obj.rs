//! Wavefront OBJ: the geometry statements of a polygon mesh.
//!
//! Read: `v x y z [w]` (a homogeneous `w` is ignored, as are the three colour values some
//! writers append) and `f i j k ...` with corners written `i`, `i/t`, `i//n` or `i/t/n`;
//! indices count from 1 in the order the `v` lines appear, or from the end when negative
//! (`-1` is the last vertex read so far). A face of more than three corners is taken as a
//! convex polygon and split into a fan of triangles `(1, k, k+1)`. Every other statement
//! (`vt`, `vn`, `o`, `g`, `s`, `usemtl`, `mtllib`, `l`, ...) and `#` comments are skipped.
//! A line ending with `\` continues on the next one.

use nurbs::Vec3;

use super::{mesh_error, mesh_text, TriMesh, TriangleSoup};
use crate::error::{HullError, Location};
use crate::float::real;

/// Parses an OBJ file; `source` names it in messages.
///
/// # Errors
/// [`crate::InputErrorKind::Mesh`] at the line of: a `v` with fewer than three numbers, a bad
/// or non-finite number, a face of fewer than three corners, a corner index that is not an
/// integer, is 0, or refers to a vertex that does not exist (positive indices are checked
/// against all the file's vertices, negative ones against those read so far); and for text
/// that is not UTF-8.
pub fn parse_obj(bytes: &[u8], source: &str) -> Result<TriangleSoup, HullError> {
    let text = mesh_text(bytes, source, "an OBJ text file")?;
    let mut soup = TriangleSoup::default();
    // Faces as (line, first triangle index): positive indices are checked at the end, since
    // OBJ writers may put faces before some of their vertices.
    let mut faces: Vec<(usize, usize)> = Vec::new();
    let mut corners: Vec<i64> = Vec::new();
    let mut joined = String::new();
    let mut lines = text.split('\n').enumerate();
    while let Some((i, raw)) = lines.next() {
        let lineno = i + 1;
        let mut line = raw.strip_suffix('\r').unwrap_or(raw);
        if line.ends_with('\\') {
            joined.clear();
            while let Some(head) = line.strip_suffix('\\') {
                joined.push_str(head);
                joined.push(' ');
                match lines.next() {
                    Some((_, next)) => line = next.strip_suffix('\r').unwrap_or(next),
                    None => {
                        line = "";
                        break;
                    }
                }
            }
            joined.push_str(line);
            line = &joined;
        }
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_ascii_whitespace();
        let at = || Location::line(source, lineno);
        match words.next() {
            Some("v") => {
                let mut c = [0.0; 3];
                for (k, slot) in c.iter_mut().enumerate() {
                    let what = ["the vertex x coordinate", "the vertex y coordinate", "the vertex z coordinate"][k];
                    let Some(w) = words.next() else {
                        return Err(mesh_error(at(), format!("a \"v\" line with {k} numbers"), what));
                    };
                    *slot = match w.parse::<f64>() {
                        Ok(v) if v.is_finite() => v,
                        Ok(_) => return Err(mesh_error(at(), format!("\"{w}\" is not a finite number"), what)),
                        Err(_) => return Err(mesh_error(at(), format!("\"{w}\" is not a number"), what)),
                    };
                }
                soup.vertices.push(Vec3::from_array(c));
            }
            Some("f") => {
                corners.clear();
                for w in words {
                    let index_text = w.split('/').next().unwrap_or("");
                    let expected = "a vertex index: a non-zero integer, optionally followed by /texture/normal";
                    let Ok(index) = index_text.parse::<i64>() else {
                        return Err(mesh_error(at(), format!("face corner \"{w}\""), expected));
                    };
                    let resolved = match index {
                        0 => return Err(mesh_error(at(), format!("face corner \"{w}\" has index 0"), expected)),
                        i if i > 0 => i - 1,
                        i => {
                            let r = soup.vertices.len() as i64 + i;
                            if r < 0 {
                                return Err(mesh_error(
                                    at(),
                                    format!("face corner \"{w}\" reaches before the first vertex"),
                                    &format!(
                                        "a negative index of at most {} in magnitude (the vertices read so far)",
                                        soup.vertices.len()
                                    ),
                                ));
                            }
                            r
                        }
                    };
                    corners.push(resolved);
                }
                if corners.len() < 3 {
                    return Err(mesh_error(
                        at(),
                        format!("a face of {} corner(s)", corners.len()),
                        "at least three corners per face",
                    ));
                }
                faces.push((lineno, soup.triangles.len()));
                for k in 1..corners.len() - 1 {
                    // Indices above u32::MAX are caught by the range check below.
                    let idx = [corners[0], corners[k], corners[k + 1]].map(|i| u32::try_from(i).unwrap_or(u32::MAX));
                    soup.triangles.push(idx);
                }
            }
            _ => {}
        }
    }
    let n = soup.vertices.len();
    if n > u32::MAX as usize {
        return Err(mesh_error(Location::file(source), format!("{n} vertices"), "at most 4294967295 vertices"));
    }
    for (f, &(lineno, first)) in faces.iter().enumerate() {
        let end = faces.get(f + 1).map_or(soup.triangles.len(), |next| next.1);
        if let Some(&bad) = soup.triangles[first..end].iter().flatten().find(|&&i| i as usize >= n) {
            let shown = if bad == u32::MAX { "beyond 4294967295".to_string() } else { (bad + 1).to_string() };
            return Err(mesh_error(
                Location::line(source, lineno),
                format!("face corner refers to vertex {shown}"),
                &format!("an index from 1 to {n}, the file's vertex count"),
            ));
        }
    }
    Ok(soup)
}

/// Writes `mesh` as OBJ text: a `#` line per comment of `comments`, a `#` line counting the
/// vertices and triangles, `o object` if an object name is given, one `v` line per vertex,
/// one `vn` line per vertex normal if the mesh has them, and one `f` line per triangle
/// (1-based, `f a//a b//b c//c` with normals, `f a b c` without); numbers in their shortest
/// round-trip form.
///
/// # Errors
/// Those of `w`; [`std::io::ErrorKind::InvalidData`] for a non-finite coordinate.
pub fn write_obj<W: std::io::Write + ?Sized>(
    w: &mut W,
    mesh: &TriMesh,
    comments: &[String],
    object: Option<&str>,
) -> std::io::Result<()> {
    for c in comments {
        writeln!(w, "# {c}")?;
    }
    writeln!(w, "# {} vertices, {} triangles", mesh.vertices.len(), mesh.triangles.len())?;
    if let Some(name) = object {
        writeln!(w, "o {name}")?;
    }
    for v in &mesh.vertices {
        writeln!(w, "v {} {} {}", real(v.x)?, real(v.y)?, real(v.z)?)?;
    }
    for n in &mesh.normals {
        writeln!(w, "vn {} {} {}", real(n.x)?, real(n.y)?, real(n.z)?)?;
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|k| u64::from(k) + 1);
        if mesh.normals.is_empty() {
            writeln!(w, "f {a} {b} {c}")?;
        } else {
            writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse_obj(text.as_bytes(), "h.obj").expect_err("bad file").to_string()
    }

    #[test]
    fn reads_every_corner_form_negative_indices_and_fans() {
        let text = "# square\r\nv 0 0 0\nv 1 0 0 1.0\nv 1 1 0 0.5 0.5 0.5\nvt 0 0\nvn 0 0 1\no sq\n\
                    f 1/1/1 2//1 3/1\nv 0 1 \\\n 0\nf -4 -2 -1 # negative\nf 1 2 3 4\n";
        let soup = parse_obj(text.as_bytes(), "h.obj").expect("valid");
        assert_eq!(soup.vertices.len(), 4);
        assert_eq!(soup.vertices[3], Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(soup.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn errors_name_the_line() {
        assert_eq!(err("v 0 0\n"), "h.obj:1: a \"v\" line with 2 numbers (expected the vertex z coordinate)");
        assert_eq!(err("\nv 0 inf 0\n"), "h.obj:2: \"inf\" is not a finite number (expected the vertex y coordinate)");
        assert_eq!(
            err("v 0 0 0\nv 1 0 0\nf 1 2\n"),
            "h.obj:3: a face of 2 corner(s) (expected at least three corners per face)"
        );
        assert!(err("v 0 0 0\nf 1 x 2\n").starts_with("h.obj:2: face corner \"x\" (expected a vertex index"));
        assert!(err("v 0 0 0\nf 0 1 1\n").starts_with("h.obj:2: face corner \"0\" has index 0"));
        assert_eq!(
            err("v 0 0 0\nv 1 0 0\nf 1 2 -3\n"),
            "h.obj:3: face corner \"-3\" reaches before the first vertex (expected a negative index of at most 2 in \
             magnitude (the vertices read so far))"
        );
        assert_eq!(
            err("v 0 0 0\nv 1 0 0\nf 1 2 7\nv 1 1 0\n"),
            "h.obj:3: face corner refers to vertex 7 (expected an index from 1 to 3, the file's vertex count)"
        );
    }

    #[test]
    fn writer_round_trips() {
        let text = "v 0 0 0\nv 1 0 0.125\nv 1 1 0\nf 1 2 3\n";
        let soup = parse_obj(text.as_bytes(), "h.obj").expect("valid");
        let mesh = TriMesh::try_new("m", soup.vertices.clone(), soup.triangles.clone()).expect("valid");
        let mut out = Vec::new();
        write_obj(&mut out, &mesh, &[], None).expect("writes");
        assert_eq!(parse_obj(&out, "o").expect("reads"), soup);
    }
}
