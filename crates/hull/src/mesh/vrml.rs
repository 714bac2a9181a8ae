//! VRML (`.wrl`): the indexed face sets of a VRML 1.0 or VRML 2.0 (VRML97) world, as CAD and
//! hull design programs (FastShip, Rhino, FREE!ship) export a hull.
//!
//! Read: every `IndexedFaceSet`'s `coordIndex` (faces of three or more corners, each ended by
//! `-1` or by the end of the list; a face of more than three is taken as a convex polygon and
//! split into a fan of triangles `(1, k, k+1)`, as OBJ's), with its coordinates: in VRML 2.0
//! its own `coord Coordinate { point [...] }` (or `coord USE name`), in VRML 1.0 the last
//! `Coordinate3 { point [...] }` before it in its `Separator` (a `Separator` keeps the
//! coordinates set inside it to itself). Every other node and field (materials, normals,
//! texture coordinates, `IndexedLineSet`, `PointSet`, viewpoints, ...) is skipped, as are `#`
//! comments and quoted strings; commas count as spaces.
//!
//! Not read, and refused with the line where they appear rather than read wrongly: a transform
//! other than the identity (`Transform`, `Translation`, `Rotation`, `Scale`, `MatrixTransform`
//! with a `translation`, `rotation`, `scale`, `scaleFactor` or `matrix` that moves the mesh,
//! `RotationXYZ` with an `angle`: hullskin does not apply them; `--axes` and `--shift` bring a mesh into its axes), `Inline`
//! and `WWWInline` (another file's geometry), and `PROTO` / `EXTERNPROTO` (node types the file
//! defines itself).

use std::collections::HashMap;

use nurbs::Vec3;

use super::{mesh_error, mesh_text, TriangleSoup};
use crate::error::{HullError, Location};

/// What the errors expect of a VRML file, where nothing more precise applies.
const EXPECTED: &str = "a VRML 1.0 or 2.0 file of IndexedFaceSet nodes with their coordinates";

/// A token of the VRML text.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Token<'a> {
    Open(char),
    Close(char),
    Word(&'a str),
}

/// The tokens of a VRML text (braces and brackets, and words: names and numbers), each with
/// its 1-based line, read one at a time (a file of up to `MAX_MESH_FILE_BYTES` is never held as
/// tokens); comments, strings and commas are skipped.
struct Lexer<'a> {
    text: &'a str,
    i: usize,
    line: usize,
    peeked: Option<Option<(Token<'a>, usize)>>,
}

impl<'a> Lexer<'a> {
    fn new(text: &'a str) -> Self {
        Lexer { text, i: 0, line: 1, peeked: None }
    }

    fn scan(&mut self) -> Option<(Token<'a>, usize)> {
        let bytes = self.text.as_bytes();
        while self.i < bytes.len() {
            let b = bytes[self.i];
            match b {
                b'\n' => {
                    self.line += 1;
                    self.i += 1;
                }
                b'#' => {
                    while self.i < bytes.len() && bytes[self.i] != b'\n' {
                        self.i += 1;
                    }
                }
                b'"' => {
                    self.i += 1;
                    while self.i < bytes.len() && bytes[self.i] != b'"' {
                        match bytes[self.i] {
                            // An escaped character, which may be a line end.
                            b'\\' => {
                                self.i += 1;
                                if bytes.get(self.i) == Some(&b'\n') {
                                    self.line += 1;
                                }
                            }
                            b'\n' => self.line += 1,
                            _ => {}
                        }
                        self.i += 1;
                    }
                    self.i += 1;
                }
                b'{' | b'[' | b'}' | b']' => {
                    self.i += 1;
                    let c = b as char;
                    let t = if matches!(b, b'{' | b'[') { Token::Open(c) } else { Token::Close(c) };
                    return Some((t, self.line));
                }
                b if b.is_ascii_whitespace() || b == b',' => self.i += 1,
                _ => {
                    let start = self.i;
                    while self.i < bytes.len()
                        && !matches!(bytes[self.i], b'{' | b'}' | b'[' | b']' | b'#' | b'"' | b',')
                        && !bytes[self.i].is_ascii_whitespace()
                    {
                        self.i += 1;
                    }
                    return Some((Token::Word(&self.text[start..self.i]), self.line));
                }
            }
        }
        None
    }

    fn next(&mut self) -> Option<(Token<'a>, usize)> {
        match self.peeked.take() {
            Some(t) => t,
            None => self.scan(),
        }
    }

    fn peek(&mut self) -> Option<(Token<'a>, usize)> {
        if self.peeked.is_none() {
            self.peeked = Some(self.scan());
        }
        self.peeked.flatten()
    }

    /// The word next, if the next token is one (not consumed).
    fn peek_word(&mut self) -> Option<&'a str> {
        match self.peek() {
            Some((Token::Word(w), _)) => Some(w),
            _ => None,
        }
    }

    /// The numbers of a field's value: a bracketed list, or as many bare numbers as follow
    /// (up to `most`), each with its line; `what` names the field in errors.
    fn numbers(&mut self, most: usize, source: &str, what: &str) -> Result<Vec<(f64, usize)>, HullError> {
        let at = |line: usize| Location::line(source, line);
        let mut out = Vec::new();
        let open = match self.peek() {
            Some((Token::Open('['), line)) => {
                self.next();
                Some(line)
            }
            _ => None,
        };
        loop {
            match self.peek() {
                Some((Token::Close(']'), _)) if open.is_some() => {
                    self.next();
                    return Ok(out);
                }
                Some((Token::Word(w), line)) if open.is_some() || out.len() < most => match w.parse::<f64>() {
                    Ok(v) if v.is_finite() => {
                        self.next();
                        out.push((v, line));
                    }
                    Ok(_) => return Err(mesh_error(at(line), format!("\"{w}\" is not a finite number"), what)),
                    Err(_) if open.is_some() => {
                        return Err(mesh_error(at(line), format!("\"{w}\" is not a number"), what))
                    }
                    Err(_) => return Ok(out),
                },
                None => match open {
                    Some(line) => return Err(mesh_error(at(line), "a list not closed by \"]\"".to_string(), what)),
                    None => return Ok(out),
                },
                Some((_, line)) if open.is_some() => {
                    return Err(mesh_error(at(line), "a brace inside a list of numbers".to_string(), what));
                }
                Some(_) => return Ok(out),
            }
        }
    }
}

/// A block of coordinates read: where its points start in the soup, and how many.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Coords {
    first: usize,
    count: usize,
}

/// An open node: its type, the VRML 1.0 coordinates in effect when it began (restored at its
/// end for a `Separator`), and for an `IndexedFaceSet` its faces and coordinates so far.
struct Node<'a> {
    kind: &'a str,
    line: usize,
    saved: Option<Coords>,
    faces: Vec<(usize, Vec<i64>)>,
    coord: Option<Coords>,
    /// The name this node was given by `DEF`.
    name: Option<&'a str>,
}

/// The transform fields and the values that leave the mesh where it is.
fn identity_of(field: &str) -> Option<&'static [f64]> {
    const MATRIX: [f64; 16] = [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.];
    match field {
        "translation" => Some(&[0.0; 3]),
        "scale" | "scaleFactor" => Some(&[1.0; 3]),
        // VRML 1.0's `RotationXYZ { axis X angle A }`.
        "angle" => Some(&[0.0]),
        "matrix" => Some(&MATRIX),
        _ => None,
    }
}

/// The nodes whose fields move the geometry after them or inside them.
const TRANSFORMS: [&str; 6] = ["Transform", "Translation", "Rotation", "Scale", "MatrixTransform", "RotationXYZ"];

/// Parses a VRML file; `source` names it in messages.
///
/// # Errors
/// [`crate::InputErrorKind::Mesh`] at the line of: a text that does not start with `#VRML
/// V1.0` or `#VRML V2.0`; a bad or non-finite number, or a point list whose count is not a
/// multiple of three; a face of one or two corners, a corner index below -1 or past its
/// coordinates, a face set with no coordinates; a transform that moves the mesh, `Inline`,
/// `PROTO`; unbalanced braces or brackets; and for text that is not UTF-8.
pub fn parse_vrml(bytes: &[u8], source: &str) -> Result<TriangleSoup, HullError> {
    let at = |line: usize| Location::line(source, line);
    let text = mesh_text(bytes, source, "a VRML text file")?;
    let header = text.lines().next().unwrap_or("");
    if !(header.starts_with("#VRML V1.0") || header.starts_with("#VRML V2.0")) {
        let shown: String = header.chars().take(40).collect();
        return Err(mesh_error(
            at(1),
            format!("a first line \"{shown}\""),
            "\"#VRML V1.0 ascii\" or \"#VRML V2.0 utf8\"",
        ));
    }
    let mut lexer = Lexer::new(text);
    let mut soup = TriangleSoup::default();
    let mut stack: Vec<Node<'_>> = Vec::new();
    // Brackets opened outside a list this reader reads (a `children [...]`, a material's
    // colours), with their lines.
    let mut lists: Vec<usize> = Vec::new();
    // VRML 1.0's current coordinates.
    let mut current: Option<Coords> = None;
    let mut named: HashMap<&str, Coords> = HashMap::new();
    // The last three tokens the loop read, words only (`DEF name Type {`); a list of numbers
    // read clears them.
    let mut recent: [Option<&str>; 3] = [None; 3];
    while let Some((tok, line)) = lexer.next() {
        match tok {
            Token::Open('{') => {
                // `Type {` or `DEF name Type {`.
                let kind = recent[2]
                    .ok_or_else(|| mesh_error(at(line), "\"{\" with no node type before it".to_string(), EXPECTED))?;
                let name = (recent[0] == Some("DEF")).then_some(recent[1]).flatten();
                let saved = matches!(kind, "Separator" | "TransformSeparator").then_some(current).flatten();
                stack.push(Node { kind, line, saved, faces: Vec::new(), coord: None, name });
                recent = [None; 3];
            }
            Token::Close('}') => {
                let node = stack
                    .pop()
                    .ok_or_else(|| mesh_error(at(line), "a \"}\" with no node open".to_string(), EXPECTED))?;
                match node.kind {
                    "Separator" | "TransformSeparator" => current = node.saved,
                    "IndexedFaceSet" if !node.faces.is_empty() => match node.coord.or(current) {
                        Some(c) => add_faces(&mut soup, &node.faces, c, source)?,
                        None => {
                            return Err(mesh_error(
                                at(node.line),
                                "an IndexedFaceSet with no coordinates".to_string(),
                                "a coord Coordinate (VRML 2.0) or a Coordinate3 before it (VRML 1.0)",
                            ))
                        }
                    },
                    _ => {}
                }
                recent = [None; 3];
            }
            Token::Open(_) => {
                lists.push(line);
                recent = [None; 3];
            }
            Token::Close(_) => {
                if lists.pop().is_none() {
                    return Err(mesh_error(at(line), "a \"]\" with no list open".to_string(), EXPECTED));
                }
                recent = [None; 3];
            }
            Token::Word(w) => {
                let kind = stack.last().map_or("", |n| n.kind);
                recent = [recent[1], recent[2], Some(w)];
                match (kind, w) {
                    (_, "PROTO" | "EXTERNPROTO") => {
                        return Err(mesh_error(
                            at(line),
                            format!("a {w} (a node type the file defines)"),
                            "a VRML file of the standard nodes only",
                        ))
                    }
                    (_, "Inline" | "WWWInline") => {
                        return Err(mesh_error(
                            at(line),
                            format!("an {w} node (geometry in another file, not read)"),
                            "a VRML file holding its geometry itself",
                        ))
                    }
                    ("Coordinate3" | "Coordinate", "point") => {
                        let what = "the point list: x y z triples";
                        let nums = lexer.numbers(3, source, what)?;
                        recent = [None; 3];
                        if nums.len() % 3 != 0 {
                            let place = odd_line(&nums).unwrap_or(line);
                            return Err(mesh_error(
                                at(place),
                                format!("a point list of {} numbers, not a multiple of 3", nums.len()),
                                what,
                            ));
                        }
                        let c = Coords { first: soup.vertices.len(), count: nums.len() / 3 };
                        soup.vertices.extend(nums.chunks_exact(3).map(|t| Vec3::new(t[0].0, t[1].0, t[2].0)));
                        let n = stack.len();
                        if let Some(name) = stack[n - 1].name {
                            named.insert(name, c);
                        }
                        // VRML 1.0: the current coordinates; VRML 2.0: the face set's own.
                        current = Some(c);
                        if n >= 2 && stack[n - 2].kind == "IndexedFaceSet" {
                            stack[n - 2].coord = Some(c);
                        }
                    }
                    ("IndexedFaceSet", "coordIndex") => {
                        let what = "corner indices from 0, each face ended by -1";
                        let nums = lexer.numbers(1, source, what)?;
                        recent = [None; 3];
                        let faces = &mut stack.last_mut().expect("inside a node").faces;
                        let mut face: Option<(usize, Vec<i64>)> = None;
                        for (v, l) in nums {
                            if v.fract() != 0.0 || v < -1.0 {
                                return Err(mesh_error(at(l), format!("corner index {v}"), what));
                            }
                            if v == -1.0 {
                                faces.extend(face.take());
                            } else {
                                face.get_or_insert_with(|| (l, Vec::new())).1.push(v as i64);
                            }
                        }
                        faces.extend(face);
                    }
                    ("IndexedFaceSet", "coord") if lexer.peek_word() == Some("USE") => {
                        lexer.next();
                        let name = lexer.peek_word().unwrap_or("");
                        lexer.next();
                        let c = *named.get(name).ok_or_else(|| {
                            mesh_error(at(line), format!("coord USE {name}"), "a Coordinate defined (DEF) before it")
                        })?;
                        stack.last_mut().expect("inside a node").coord = Some(c);
                        recent = [None; 3];
                    }
                    (_, "USE") => {
                        // VRML 1.0: a Coordinate3 used again becomes the current coordinates.
                        let name = lexer.peek_word();
                        if let Some(&c) = name.and_then(|n| named.get(n)) {
                            current = Some(c);
                        }
                        if name.is_some() {
                            lexer.next();
                        }
                        recent = [None; 3];
                    }
                    (t, f) if TRANSFORMS.contains(&t) && (f == "rotation" || identity_of(f).is_some()) => {
                        let what = "a transform that leaves the mesh where it is (hullskin does not apply transforms; \
                                    --axes and --shift bring a mesh into its axes)";
                        let most = if f == "rotation" { 4 } else { identity_of(f).map_or(0, <[f64]>::len) };
                        let values: Vec<f64> = lexer.numbers(most, source, what)?.iter().map(|n| n.0).collect();
                        recent = [None; 3];
                        let moves = if f == "rotation" {
                            values.get(3).is_some_and(|&a| a != 0.0)
                        } else {
                            identity_of(f).is_some_and(|id| values.iter().zip(id).any(|(v, i)| v != i))
                        };
                        if moves {
                            let shown: Vec<String> = values.iter().map(|v| v.to_string()).collect();
                            return Err(mesh_error(at(line), format!("{t} {f} {}", shown.join(" ")), what));
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    if let Some(&line) = lists.last() {
        return Err(mesh_error(at(line), "a \"[\" list not closed by \"]\"".to_string(), EXPECTED));
    }
    if let Some(open) = stack.last() {
        return Err(mesh_error(at(open.line), format!("a {} node not closed by \"}}\"", open.kind), EXPECTED));
    }
    Ok(soup)
}

/// Where a list of numbers with a coordinate missing (or one too many) most likely went wrong:
/// where the list is written a whole number of points a line (the usual layout), the first line
/// that is not; else its last line.
fn odd_line(nums: &[(f64, usize)]) -> Option<usize> {
    let mut per_line: Vec<(usize, usize)> = Vec::new();
    for &(_, line) in nums {
        match per_line.last_mut() {
            Some((l, n)) if *l == line => *n += 1,
            _ => per_line.push((line, 1)),
        }
    }
    let whole = per_line.iter().filter(|(_, n)| n % 3 == 0).count();
    if 2 * whole >= per_line.len() {
        per_line.iter().find(|(_, n)| n % 3 != 0).map(|(l, _)| *l)
    } else {
        per_line.last().map(|(l, _)| *l)
    }
}

/// The triangles of `faces` (corner indices into `coords`, each face with the line it
/// starts on) added to `soup`.
fn add_faces(
    soup: &mut TriangleSoup,
    faces: &[(usize, Vec<i64>)],
    coords: Coords,
    source: &str,
) -> Result<(), HullError> {
    for (line, corners) in faces {
        let at = || Location::line(source, *line);
        if corners.len() < 3 {
            return Err(mesh_error(
                at(),
                format!("a face of {} corner(s)", corners.len()),
                "at least three corners per face",
            ));
        }
        if let Some(&bad) = corners.iter().find(|&&i| i as usize >= coords.count) {
            return Err(mesh_error(
                at(),
                format!("corner index {bad}"),
                &format!("an index from 0 to {}, its coordinates' last point", coords.count.saturating_sub(1)),
            ));
        }
        let index = |i: i64| u32::try_from(coords.first + i as usize).unwrap_or(u32::MAX);
        for k in 1..corners.len() - 1 {
            soup.triangles.push([index(corners[0]), index(corners[k]), index(corners[k + 1])]);
        }
    }
    if soup.vertices.len() > u32::MAX as usize {
        let n = soup.vertices.len();
        return Err(mesh_error(Location::file(source), format!("{n} vertices"), "at most 4294967295 vertices"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square as two faces: a quad in VRML 1.0, two triangles in VRML 2.0.
    const V1: &str = "#VRML V1.0 ascii\n\
        Separator {\n\
          Material { diffuseColor 0 0 0.67 }\n\
          DEF pts Coordinate3 { point [ 0 0 0, 1 0 0, # a comment, 9 9 9\n 1 1 0, 0 1 0 ] }\n\
          IndexedFaceSet { coordIndex [ 0, 1, 2, 3, -1 ] }\n\
        }\n";
    const V2: &str = "#VRML V2.0 utf8\n\
        WorldInfo { info [ \"made by { hand ]\" ] }\n\
        Transform { translation 0 0 0 children [\n\
          Shape { appearance Appearance { material Material { } }\n\
            geometry IndexedFaceSet { coordIndex [ 0 1 2 -1 0 2 3 ]\n\
              coord Coordinate { point [ 0 0 0 1 0 0 1 1 0 0 1 0 ] } } }\n\
        ] }\n";

    #[test]
    fn both_versions_give_the_same_triangles() {
        let one = parse_vrml(V1.as_bytes(), "a.wrl").expect("VRML 1.0");
        let two = parse_vrml(V2.as_bytes(), "b.wrl").expect("VRML 2.0");
        assert_eq!(one.vertices.len(), 4);
        assert_eq!(one.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!((two.vertices, two.triangles), (one.vertices, one.triangles));
    }

    #[test]
    fn coordinates_follow_the_separators_and_the_face_sets() {
        // VRML 1.0: the second face set uses the coordinates before the first Separator's,
        // which its own Coordinate3 did not outlive; the third reuses the first by name.
        let text = "#VRML V1.0 ascii\n\
            DEF a Coordinate3 { point [ 0 0 0, 1 0 0, 0 1 0 ] }\n\
            Separator { Coordinate3 { point [ 5 5 5, 6 5 5, 5 6 5, 5 5 6 ] } IndexedFaceSet { coordIndex [ 1 2 3 ] } }\n\
            IndexedFaceSet { coordIndex [ 2 1 0 -1 ] }\n\
            Coordinate3 { point [ 7 7 7 ] }\n\
            USE a\n\
            IndexedFaceSet { coordIndex [ 0 1 2 ] }\n";
        let soup = parse_vrml(text.as_bytes(), "s.wrl").expect("reads");
        assert_eq!(soup.triangles, vec![[4, 5, 6], [2, 1, 0], [0, 1, 2]]);
        // VRML 2.0: `coord USE`.
        let text = "#VRML V2.0 utf8\n\
            Shape { geometry IndexedFaceSet { coord DEF c Coordinate { point [ 0 0 0 1 0 0 0 1 0 ] } coordIndex [ 0 1 2 ] } }\n\
            Shape { geometry IndexedFaceSet { coordIndex [ 2 1 0 ] coord USE c } }\n";
        let soup = parse_vrml(text.as_bytes(), "u.wrl").expect("reads");
        assert_eq!(soup.triangles, vec![[0, 1, 2], [2, 1, 0]]);
        assert_eq!(soup.vertices.len(), 3);
    }

    #[test]
    fn line_sets_and_other_lists_are_not_faces() {
        let text = "#VRML V2.0 utf8\n\
            Shape { geometry IndexedLineSet { coord Coordinate { point [ 0 0 0 1 0 0 ] } coordIndex [ 0 1 -1 ] } }\n";
        let soup = parse_vrml(text.as_bytes(), "l.wrl").expect("reads");
        assert!(soup.triangles.is_empty());
    }

    #[test]
    fn bad_files_are_refused_at_their_line() {
        let cases: [(&str, &str); 13] = [
            ("solid x\n", "a.wrl:1: a first line \"solid x\""),
            (
                "#VRML V1.0 ascii\nCoordinate3 { point [ 0 0 0, 1 0 ] }\n",
                "a.wrl:2: a point list of 5 numbers, not a multiple of 3",
            ),
            (
                "#VRML V1.0 ascii\nCoordinate3 { point [\n0 0 0,\n1 0,\n1 1 0,\n0 1 0 ] }\n",
                "a.wrl:4: a point list of 11 numbers, not a multiple of 3",
            ),
            ("#VRML V1.0 ascii\nCoordinate3 { point [ 0 0 zero ] }\n", "a.wrl:2: \"zero\" is not a number"),
            (
                "#VRML V1.0 ascii\nCoordinate3 { point [ 0 0 0 1 0 0 0 1 0 ] }\nIndexedFaceSet { coordIndex [\n 0 1 -1 ] }\n",
                "a.wrl:4: a face of 2 corner(s)",
            ),
            (
                "#VRML V1.0 ascii\nCoordinate3 { point [ 0 0 0 1 0 0 0 1 0 ] }\nIndexedFaceSet { coordIndex [ 0 1 3 ] }\n",
                "a.wrl:3: corner index 3 (expected an index from 0 to 2",
            ),
            ("#VRML V1.0 ascii\nIndexedFaceSet { coordIndex [ 0 1 2 ] }\n", "a.wrl:2: an IndexedFaceSet with no coordinates"),
            (
                "#VRML V2.0 utf8\nTransform {\n translation 0 0 1.5 children [ ] }\n",
                "a.wrl:3: Transform translation 0 0 1.5",
            ),
            ("#VRML V2.0 utf8\nInline { url \"hull.wrl\" }\n", "a.wrl:2: an Inline node"),
            (
                "#VRML V1.0 ascii\nInfo { string \"a\\\nb\" }\nRotationXYZ { axis Z angle 0.5 }\n",
                "a.wrl:4: RotationXYZ angle 0.5",
            ),
            ("#VRML V1.0 ascii\nSeparator {\n Coordinate3 { point [ 0 0 0 ] }\n", "a.wrl:2: a Separator node not closed"),
            ("#VRML V2.0 utf8\nGroup { children [\n Shape { }\n", "a.wrl:2: a \"[\" list not closed"),
            ("#VRML V1.0 ascii\nCoordinate3 { point [ 0 0 0\n } ]\n", "a.wrl:3: a brace inside a list of numbers"),
        ];
        for (text, message) in cases {
            let e = parse_vrml(text.as_bytes(), "a.wrl").expect_err(message).to_string();
            assert!(e.contains(message), "{message}: {e}");
        }
        // Identity transforms are no obstacle.
        let text = "#VRML V1.0 ascii\nRotation { rotation 0 0 1 0 }\nScale { scaleFactor 1 1 1 }\n";
        assert!(parse_vrml(text.as_bytes(), "a.wrl").is_ok());
    }
}
