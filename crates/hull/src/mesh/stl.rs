//! STL, ASCII and binary: reader and writers.
//!
//! The rest of this module's documentation is on [`parse_stl`], where the library's users read it.

use std::io::{self, Write};

use nurbs::Vec3;

use super::{mesh_error, TriMesh, TriangleSoup};
use crate::error::{HullError, Location};
use crate::float::real;

/// Bytes of the free-text header of a binary STL.
pub const STL_HEADER_LEN: usize = 80;
/// Bytes before the first binary record: the header and the triangle count.
const HEADER: usize = STL_HEADER_LEN + 4;
/// Bytes of one binary record.
const RECORD: usize = 50;

/// True if `bytes` start (after white space) with the keyword `solid`, in any case.
pub fn starts_with_solid(bytes: &[u8]) -> bool {
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace()).unwrap_or(bytes.len());
    bytes[start..].get(..5).is_some_and(|w| w.eq_ignore_ascii_case(b"solid"))
        && bytes.get(start + 5).is_none_or(|b| b.is_ascii_whitespace())
}

/// The triangle count a binary header claims (bytes 80..84), if the file is that long.
fn claimed_count(bytes: &[u8]) -> Option<u32> {
    bytes.get(80..HEADER).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
}

/// The size a binary STL of `n` triangles has.
fn binary_size(n: u32) -> u64 {
    HEADER as u64 + RECORD as u64 * u64::from(n)
}

/// True if the size of `bytes` is exactly that of a binary STL with the count of its header.
pub fn looks_binary(bytes: &[u8]) -> bool {
    claimed_count(bytes).is_some_and(|n| binary_size(n) == bytes.len() as u64)
}

/// Parses an STL file, ASCII or binary (see below for how they are told apart);
/// `source` names it in messages.
///
/// # The two forms of STL
///
/// - **Binary**: an 80-byte header, a little-endian `u32` triangle count `n`, then `n`
///   records of 50 bytes: the normal and the three vertices as 12 little-endian `f32`, and a
///   `u16` attribute. The file is exactly `84 + 50 n` bytes.
/// - **ASCII**: `solid name`, then facets
///   `facet normal nx ny nz / outer loop / vertex x y z (x3) / endloop / endfacet`, then
///   `endsolid name`. Keywords are read case-insensitively, separated by any white space
///   (line breaks included); several solids may follow each other. A loop of more than
///   three vertices is taken as a convex polygon and split into a fan of triangles.
///
/// Some binary files start with `solid` too (their header is free text), so the form is told
/// by the size: a file of exactly `84 + 50 n` bytes, `n` read at byte 80, is binary; otherwise
/// a file starting with `solid` is ASCII; anything else is a damaged binary file, reported
/// with its size and the count its header claims (never allocated for before the size is
/// checked).
///
/// Facet normals are not used (they are often wrong or zero): orientation, where it matters,
/// comes from the vertices' order. Non-finite vertex coordinates are errors; normals are not
/// checked.
///
/// # Errors
/// [`crate::InputErrorKind::Mesh`]: for ASCII files at the line of the first unexpected
/// keyword, bad or non-finite number, or of the unclosed `solid` when the file ends early;
/// for binary files naming the byte offset of a non-finite coordinate, or the size against
/// the header's triangle count.
pub fn parse_stl(bytes: &[u8], source: &str) -> Result<TriangleSoup, HullError> {
    if looks_binary(bytes) {
        return parse_binary(bytes, source);
    }
    if starts_with_solid(bytes) {
        return parse_ascii(bytes, source);
    }
    let at = Location::file(source);
    match claimed_count(bytes) {
        None => Err(mesh_error(
            at,
            format!("a file of {} bytes that does not start with \"solid\"", bytes.len()),
            "an ASCII STL starting with \"solid\", or a binary STL of at least 84 bytes",
        )),
        Some(n) => {
            let room = (bytes.len() - HEADER) / RECORD;
            let (found, expected) = if binary_size(n) > bytes.len() as u64 {
                (
                    format!(
                        "binary STL: the header (byte offset 80) claims {n} triangles, {} bytes, but the file has {} \
                         bytes, room for {room} triangles",
                        binary_size(n),
                        bytes.len()
                    ),
                    "a complete file: 84 + 50 x triangles bytes",
                )
            } else {
                (
                    format!(
                        "binary STL: {} bytes follow the {n} triangles the header (byte offset 80) claims",
                        bytes.len() as u64 - binary_size(n)
                    ),
                    "a file of exactly 84 + 50 x triangles bytes",
                )
            };
            Err(mesh_error(at, found, expected))
        }
    }
}

fn parse_binary(bytes: &[u8], source: &str) -> Result<TriangleSoup, HullError> {
    let n = claimed_count(bytes).expect("looks_binary checked the header") as usize;
    crate::limits::check_mesh_triangles(source, n as u64)?;
    let mut vertices = Vec::with_capacity(3 * n);
    let mut triangles = Vec::with_capacity(n);
    let f32_at = |o: usize| f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
    for t in 0..n {
        let record = HEADER + RECORD * t;
        for k in 0..3 {
            let o = record + 12 + 12 * k;
            let c = [f32_at(o), f32_at(o + 4), f32_at(o + 8)];
            if let Some(j) = c.iter().position(|v| !v.is_finite()) {
                return Err(mesh_error(
                    Location::file(source),
                    format!(
                        "binary STL: triangle {}, vertex {}, coordinate {} at byte offset {} is {}",
                        t + 1,
                        k + 1,
                        ["x", "y", "z"][j],
                        o + 4 * j,
                        c[j]
                    ),
                    "finite coordinates",
                ));
            }
            vertices.push(Vec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2])));
        }
        let i = 3 * t as u32;
        triangles.push([i, i + 1, i + 2]);
    }
    Ok(TriangleSoup { vertices, triangles })
}

/// White-space separated words of a text, with their 1-based line numbers.
struct Lexer<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Lexer<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Lexer { bytes, pos: 0, line: 1 }
    }

    /// The next word and its line.
    fn next(&mut self) -> Option<(&'a [u8], usize)> {
        let b = self.bytes;
        let mut i = self.pos;
        while i < b.len() && b[i].is_ascii_whitespace() {
            if b[i] == b'\n' {
                self.line += 1;
            }
            i += 1;
        }
        if i == b.len() {
            self.pos = i;
            return None;
        }
        let start = i;
        while i < b.len() && !b[i].is_ascii_whitespace() {
            i += 1;
        }
        self.pos = i;
        Some((&b[start..i], self.line))
    }

    /// Skips the rest of the current line (a solid's name).
    fn skip_line(&mut self) {
        while self.pos < self.bytes.len() && self.bytes[self.pos] != b'\n' {
            self.pos += 1;
        }
    }
}

/// A word for messages: at most 40 characters, lossily decoded.
fn shown(word: &[u8]) -> String {
    let s = String::from_utf8_lossy(&word[..word.len().min(40)]).into_owned();
    if word.len() > 40 {
        format!("{s}...")
    } else {
        s
    }
}

/// The ASCII parser's state: the text, the source name and the output.
struct Ascii<'a> {
    lx: Lexer<'a>,
    source: &'a str,
    soup: TriangleSoup,
}

impl Ascii<'_> {
    fn error(&self, line: usize, found: String, expected: &str) -> HullError {
        mesh_error(Location::line(self.source, line), found, expected)
    }

    /// The next word, which must be the keyword `kw`.
    fn keyword(&mut self, kw: &str, context: &str) -> Result<(), HullError> {
        match self.lx.next() {
            Some((w, _)) if w.eq_ignore_ascii_case(kw.as_bytes()) => Ok(()),
            Some((w, line)) => Err(self.error(line, format!("\"{}\"", shown(w)), &format!("\"{kw}\" {context}"))),
            None => Err(self.error(self.lx.line, "the end of the file".into(), &format!("\"{kw}\" {context}"))),
        }
    }

    /// The next word as a finite number.
    fn number(&mut self, what: &str) -> Result<f64, HullError> {
        let Some((w, line)) = self.lx.next() else {
            return Err(self.error(self.lx.line, "the end of the file".into(), what));
        };
        let value = std::str::from_utf8(w).ok().and_then(|s| s.parse::<f64>().ok());
        match value {
            Some(v) if v.is_finite() => Ok(v),
            Some(_) => Err(self.error(line, format!("\"{}\" is not a finite number", shown(w)), what)),
            None => Err(self.error(line, format!("\"{}\" is not a number", shown(w)), what)),
        }
    }

    /// One solid, its `solid` keyword and name already read; returns at `endsolid`.
    fn solid(&mut self, opened: usize) -> Result<(), HullError> {
        loop {
            let Some((w, line)) = self.lx.next() else {
                return Err(self.error(
                    self.lx.line,
                    format!("the end of the file inside the solid opened on line {opened}"),
                    "\"facet\" or \"endsolid\"",
                ));
            };
            if w.eq_ignore_ascii_case(b"endsolid") {
                self.lx.skip_line();
                return Ok(());
            }
            if !w.eq_ignore_ascii_case(b"facet") {
                return Err(self.error(line, format!("\"{}\"", shown(w)), "\"facet\" or \"endsolid\""));
            }
            self.facet(line)?;
        }
    }

    /// One facet, its `facet` keyword (on line `line`) already read.
    fn facet(&mut self, line: usize) -> Result<(), HullError> {
        self.keyword("normal", "after \"facet\"")?;
        for _ in 0..3 {
            // Normals are not used; only their presence is checked.
            if self.lx.next().is_none() {
                return Err(self.error(self.lx.line, "the end of the file".into(), "three normal components"));
            }
        }
        self.keyword("outer", "after the facet normal")?;
        self.keyword("loop", "after \"outer\"")?;
        let first = self.soup.vertices.len();
        loop {
            match self.lx.next() {
                Some((w, _)) if w.eq_ignore_ascii_case(b"vertex") => {
                    let x = self.number("the vertex x coordinate")?;
                    let y = self.number("the vertex y coordinate")?;
                    let z = self.number("the vertex z coordinate")?;
                    self.soup.vertices.push(Vec3::new(x, y, z));
                }
                Some((w, l)) if w.eq_ignore_ascii_case(b"endloop") => {
                    let n = self.soup.vertices.len() - first;
                    if n < 3 {
                        return Err(self.error(
                            l,
                            format!("\"endloop\" after {n} vertices (facet on line {line})"),
                            "three vertices per facet",
                        ));
                    }
                    if self.soup.vertices.len() > u32::MAX as usize {
                        return Err(self.error(l, "more than 4294967295 vertices".into(), "a smaller mesh"));
                    }
                    let f = first as u32;
                    for k in 1..n as u32 - 1 {
                        self.soup.triangles.push([f, f + k, f + k + 1]);
                    }
                    break;
                }
                Some((w, l)) => {
                    return Err(self.error(l, format!("\"{}\"", shown(w)), "\"vertex\" or \"endloop\""));
                }
                None => {
                    return Err(self.error(
                        self.lx.line,
                        format!("the end of the file inside the facet opened on line {line}"),
                        "\"vertex\" or \"endloop\"",
                    ));
                }
            }
        }
        self.keyword("endfacet", "after \"endloop\"")
    }
}

fn parse_ascii(bytes: &[u8], source: &str) -> Result<TriangleSoup, HullError> {
    let mut p = Ascii { lx: Lexer::new(bytes), source, soup: TriangleSoup::default() };
    // A facet line is about 40 bytes, a facet 7 lines: a good guess of the capacity.
    p.soup.vertices.reserve(bytes.len() / 100);
    p.soup.triangles.reserve(bytes.len() / 300);
    while let Some((w, line)) = p.lx.next() {
        if !w.eq_ignore_ascii_case(b"solid") {
            return Err(p.error(line, format!("\"{}\"", shown(w)), "\"solid\" or the end of the file"));
        }
        p.lx.skip_line();
        p.solid(line)?;
    }
    Ok(p.soup)
}

/// Writes `mesh` as an ASCII STL named `name` (written as given: see
/// [`crate::export::mesh_name`] for a name made safe), the facet normals those of
/// [`TriMesh::face_normal`], every number in its shortest round-trip form (so the file reads
/// back to the very same vertices).
///
/// # Errors
/// Those of `w`; [`io::ErrorKind::InvalidData`] for a non-finite coordinate.
pub fn write_stl_ascii<W: Write + ?Sized>(w: &mut W, mesh: &TriMesh, name: &str) -> io::Result<()> {
    writeln!(w, "solid {name}")?;
    for t in 0..mesh.triangles.len() {
        let c = mesh.corners(t);
        let n = mesh.face_normal(t);
        writeln!(w, "  facet normal {} {} {}", real(n.x)?, real(n.y)?, real(n.z)?)?;
        writeln!(w, "    outer loop")?;
        for p in c {
            writeln!(w, "      vertex {} {} {}", real(p.x)?, real(p.y)?, real(p.z)?)?;
        }
        writeln!(w, "    endloop")?;
        writeln!(w, "  endfacet")?;
    }
    writeln!(w, "endsolid {name}")
}

/// Writes `mesh` as a binary STL with `header` (cut or padded with spaces to
/// [`STL_HEADER_LEN`] bytes; [`crate::export::stl_header`] makes one that readers do not take
/// for ASCII). Coordinates and the facet normals of [`TriMesh::face_normal`] are rounded to
/// `f32`, the format's precision; the attribute is 0.
///
/// # Errors
/// Those of `w`; [`io::ErrorKind::InvalidInput`] for more than `u32::MAX` triangles.
pub fn write_stl_binary<W: Write + ?Sized>(w: &mut W, mesh: &TriMesh, header: &str) -> io::Result<()> {
    let mut h = [b' '; STL_HEADER_LEN];
    let text = header.as_bytes();
    let len = text.len().min(STL_HEADER_LEN);
    h[..len].copy_from_slice(&text[..len]);
    w.write_all(&h)?;
    let n = u32::try_from(mesh.triangles.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "more than 4294967295 triangles"))?;
    w.write_all(&n.to_le_bytes())?;
    for t in 0..mesh.triangles.len() {
        let c = mesh.corners(t);
        let mut record = [0u8; RECORD];
        let values = std::iter::once(mesh.face_normal(t)).chain(c).flat_map(|p| [p.x, p.y, p.z]);
        for (k, v) in values.enumerate() {
            record[4 * k..4 * k + 4].copy_from_slice(&(v as f32).to_le_bytes());
        }
        w.write_all(&record)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO: &str = "solid two\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   \
                       vertex 0 1 0\n  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n   \
                       vertex 1 1 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid two\n";

    fn err(text: &[u8]) -> String {
        parse_stl(text, "h.stl").expect_err("bad file").to_string()
    }

    #[test]
    fn ascii_reads_case_and_white_space_tolerantly() {
        let soup = parse_stl(TWO.as_bytes(), "h.stl").expect("valid");
        assert_eq!(soup.triangles.len(), 2);
        assert_eq!(soup.vertices[4], Vec3::new(1.0, 1.0, 0.0));
        let messy = "  SOLID  \r\nFacet Normal 0 0 1 Outer\tLoop\n\nVERTEX 0 0 0 vertex 1 0 0\r\n vertex 0 1 0 \
                     vertex -1 1 0 EndLoop EndFacet EndSolid\nsolid b\nendsolid";
        let soup = parse_stl(messy.as_bytes(), "h.stl").expect("valid");
        // A 4-vertex loop becomes a fan of 2 triangles.
        assert_eq!(soup.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn ascii_errors_name_the_line_and_what_was_expected() {
        assert_eq!(
            err(TWO.replace("vertex 1 1 0", "vertex 1 x 0").as_bytes()),
            "h.stl:12: \"x\" is not a number (expected the vertex y coordinate)"
        );
        assert_eq!(
            err(TWO.replace("vertex 1 1 0", "vertex 1 NaN 0").as_bytes()),
            "h.stl:12: \"NaN\" is not a finite number (expected the vertex y coordinate)"
        );
        assert_eq!(
            err(TWO.replacen("   vertex 0 1 0\n", "", 1).as_bytes()),
            "h.stl:6: \"endloop\" after 2 vertices (facet on line 2) (expected three vertices per facet)"
        );
        let truncated = &TWO[..TWO.find("endloop\n endfacet\nendsolid").expect("present")];
        assert_eq!(
            err(truncated.as_bytes()),
            "h.stl:14: the end of the file inside the facet opened on line 9 (expected \"vertex\" or \"endloop\")"
        );
        assert_eq!(
            err(TWO.replace("endsolid two\n", "").as_bytes()),
            "h.stl:16: the end of the file inside the solid opened on line 1 (expected \"facet\" or \"endsolid\")"
        );
        assert_eq!(
            err(TWO.replacen("outer loop", "outer lop", 1).as_bytes()),
            "h.stl:3: \"lop\" (expected \"loop\" after \"outer\")"
        );
    }

    fn binary(n_claimed: u32, coords: &[[f32; 9]]) -> Vec<u8> {
        let mut b = b"solid but binary".to_vec();
        b.resize(80, 0);
        b.extend(n_claimed.to_le_bytes());
        for c in coords {
            b.extend([0u8; 12]);
            for v in c {
                b.extend(v.to_le_bytes());
            }
            b.extend([0u8; 2]);
        }
        b
    }

    #[test]
    fn binary_starting_with_solid_is_told_by_its_size() {
        let t = [[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.5]];
        let soup = parse_stl(&binary(1, &t), "b.stl").expect("valid binary");
        assert_eq!(soup.vertices, vec![Vec3::new(0., 0., 0.), Vec3::new(1., 0., 0.), Vec3::new(0., 1., 0.5)]);
    }

    #[test]
    fn binary_counts_that_do_not_fit_are_errors_not_allocations() {
        let t = [[0.0; 9]];
        let mut b = binary(u32::MAX, &t);
        b[0] = b'X'; // not "solid": a damaged binary file
        let e = err(&b);
        assert!(e.starts_with("h.stl: binary STL: the header (byte offset 80) claims 4294967295 triangles"), "{e}");
        assert!(e.contains("room for 1 triangles"), "{e}");
        let mut long = binary(0, &t);
        long[0] = b'X';
        assert!(err(&long).contains("50 bytes follow the 0 triangles"), "{}", err(&long));
        assert!(err(b"abc").contains("a file of 3 bytes"), "{}", err(b"abc"));
    }

    #[test]
    fn binary_non_finite_coordinates_name_the_byte_offset() {
        let t = [[0.0, 0.0, 0.0, 1.0, f32::NAN, 0.0, 0.0, 1.0, 0.0]];
        let e = err(&binary(1, &t));
        // Record at 84, vertices from 96; vertex 2 starts at 108, its y at 112.
        assert!(e.contains("triangle 1, vertex 2, coordinate y at byte offset 112 is NaN"), "{e}");
    }

    #[test]
    fn writers_round_trip() {
        let soup = parse_stl(TWO.as_bytes(), "h.stl").expect("valid");
        let mesh = TriMesh::try_new("m", soup.vertices, soup.triangles).expect("valid");
        let mut a = Vec::new();
        write_stl_ascii(&mut a, &mesh, "m").expect("writes");
        assert_eq!(parse_stl(&a, "a").expect("reads").vertices, mesh.vertices);
        let mut b = Vec::new();
        write_stl_binary(&mut b, &mesh, "solid m").expect("writes");
        assert_eq!(b.len(), 84 + 50 * 2);
        // Small integers are exact in f32.
        assert_eq!(parse_stl(&b, "b").expect("reads").vertices, mesh.vertices);
    }
}
