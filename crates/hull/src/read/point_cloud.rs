//! Station point clouds: whitespace-separated `x y z` (or `y z`) points, one section per block.
//!
//! The rest of this module's documentation is on [`parse_point_cloud`], where the library's users read it.

use nurbs::Vec3;

use super::{split_lines, InputFormat, ReadOutcome};
use crate::error::{HullError, InputErrorKind, Location};
use crate::offsets::{Offsets, Section};
use crate::units::Units;

/// One block of points read.
#[derive(Clone, Debug)]
pub(crate) struct Block {
    pub label: Option<String>,
    pub points: Vec<Vec3>,
    pub lines: Vec<usize>,
}

fn unexpected(at: Location, found: impl Into<String>, expected: impl Into<String>) -> HullError {
    HullError::input(at, InputErrorKind::Unexpected { found: found.into(), expected: expected.into() })
}

/// The station position named in a header: the number after `x =`, `x=` or `x`.
fn header_x(header: &str) -> Option<f64> {
    let lower = header.to_ascii_lowercase();
    let toks: Vec<&str> = lower.split(|c: char| c.is_whitespace() || c == '=').filter(|t| !t.is_empty()).collect();
    toks.windows(2)
        .find(|w| w[0] == "x")
        .and_then(|w| w[1].parse::<f64>().ok())
        .filter(|v| v.is_finite())
        .or_else(|| toks.iter().find_map(|t| t.strip_prefix("x=").and_then(|v| v.parse().ok())))
}

/// Reads the blocks of the lines `(lineno, text)`; `stop` ends the data (FREE!ship's `EOF`).
/// `split_on_x`: when no blank line or header separates any points, cut where x changes.
pub(crate) fn read_blocks<'a>(
    lines: impl Iterator<Item = (usize, &'a str)>,
    source: &str,
    units: Units,
) -> Result<(Vec<Block>, bool), HullError> {
    let unit = units.plural_name();
    let mut blocks: Vec<Block> = Vec::new();
    let mut current = Block { label: None, points: Vec::new(), lines: Vec::new() };
    let mut header_xs: Vec<Option<f64>> = Vec::new();
    let mut current_x: Option<f64> = None;
    let mut separated = false;
    let mut columns: Option<usize> = None;
    let flush = |b: &mut Block, blocks: &mut Vec<Block>, xs: &mut Vec<Option<f64>>, x: Option<f64>| {
        if !b.points.is_empty() || b.label.is_some() {
            blocks.push(std::mem::replace(b, Block { label: None, points: Vec::new(), lines: Vec::new() }));
            xs.push(x);
        }
    };
    for (lineno, raw) in lines {
        let line = raw.trim();
        if line.is_empty() {
            if !current.points.is_empty() {
                separated = true;
            }
            flush(&mut current, &mut blocks, &mut header_xs, current_x);
            current_x = None;
            continue;
        }
        if line.starts_with('#') || line.starts_with('%') {
            continue;
        }
        if line.contains(';') || line.contains(',') {
            let sep = if line.contains(';') { ';' } else { ',' };
            return Err(unexpected(
                Location::line(source, lineno),
                format!("a line with {sep:?} in it"),
                "numbers separated by spaces or tabs, with decimal points (a CSV needs a header such as x,y,z)",
            ));
        }
        let toks: Vec<&str> = line.split_whitespace().collect();
        if toks[0].parse::<f64>().is_err() {
            // A header: starts a new block.
            if !current.points.is_empty() {
                separated = true;
            }
            flush(&mut current, &mut blocks, &mut header_xs, current_x);
            current.label = Some(line.to_string());
            current_x = header_x(line);
            continue;
        }
        let n = toks.len();
        if !(2..=3).contains(&n) || columns.is_some_and(|c| c != n) {
            return Err(unexpected(
                Location::new(source, lineno, n.min(4)),
                format!("{n} numbers on a line"),
                match columns {
                    Some(c) => format!("{c} numbers per point, as on the first point line"),
                    None => "3 numbers per point (x y z) or 2 (y z) under a header giving x".into(),
                },
            ));
        }
        columns = Some(n);
        let mut v = [0.0; 3];
        for (k, t) in toks.iter().enumerate() {
            let what = if n == 3 { ["x", "y", "z"][k] } else { ["y", "z", ""][k] };
            v[k] = super::parse_number(
                t,
                || Location::new(source, lineno, k + 1),
                || format!("the {what} coordinate in {unit}"),
            )?;
        }
        let p = if n == 3 {
            Vec3::new(v[0], v[1], v[2])
        } else {
            let Some(x) = current_x else {
                return Err(unexpected(
                    Location::line(source, lineno),
                    "a y z point without a station position",
                    "a header line giving the station's x (station 5 x = 12.5) before y z points",
                ));
            };
            Vec3::new(x, v[0], v[1])
        };
        if p.y < 0.0 {
            let col = if n == 3 { 2 } else { 1 };
            return Err(HullError::input(
                Location::new(source, lineno, col),
                InputErrorKind::NegativeHalfBreadth { y: p.y },
            ));
        }
        current.points.push(Vec3::new(p.x, p.y + 0.0, p.z));
        current.lines.push(lineno);
    }
    flush(&mut current, &mut blocks, &mut header_xs, current_x);
    let labelled = blocks.iter().any(|b| b.label.is_some());
    if !separated && !labelled && blocks.len() == 1 {
        // One run of points: stations where x changes.
        let whole = blocks.remove(0);
        let mut cut: Vec<Block> = Vec::new();
        for (p, l) in whole.points.iter().zip(&whole.lines) {
            match cut.last_mut() {
                Some(b) if b.points[0].x == p.x => {
                    b.points.push(*p);
                    b.lines.push(*l);
                }
                _ => cut.push(Block { label: None, points: vec![*p], lines: vec![*l] }),
            }
        }
        return Ok((cut, true));
    }
    blocks.retain(|b| !b.points.is_empty());
    Ok((blocks, false))
}

/// Total length of the polyline through `pts` in the station plane.
fn length(pts: &[Vec3]) -> f64 {
    pts.windows(2).map(|w| (w[1].y - w[0].y).hypot(w[1].z - w[0].z)).sum()
}

/// Turns blocks into sections keel to deck and aft to fore (see [`parse_point_cloud`]); returns
/// the notes.
pub(crate) fn sections_of(blocks: Vec<Block>) -> (Vec<Section>, Vec<String>) {
    let mut notes = Vec::new();
    let mut sorted_labels = Vec::new();
    let mut sections: Vec<Section> = blocks
        .into_iter()
        .map(|b| {
            let label = b.label.unwrap_or_else(|| format!("x{}", b.points[0].x));
            let mut pts: Vec<(Vec3, usize)> = b.points.into_iter().zip(b.lines).collect();
            let key = |p: &(Vec3, usize)| (p.0.z, p.0.y);
            let mut by_height = pts.clone();
            by_height.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap_or(std::cmp::Ordering::Equal));
            let given: Vec<Vec3> = pts.iter().map(|p| p.0).collect();
            let sorted: Vec<Vec3> = by_height.iter().map(|p| p.0).collect();
            // 1e-9 relative: only a real shortening counts, not round-off of equal lengths.
            if length(&sorted) < length(&given) * (1.0 - 1e-9) {
                pts = by_height;
                sorted_labels.push(label.clone());
            } else if pts.len() > 1 && pts[0].0.z > pts[pts.len() - 1].0.z {
                pts.reverse();
            }
            Section {
                label,
                points: pts.iter().map(|p| p.0).collect(),
                lines: pts.iter().map(|p| p.1).collect(),
                column: None,
            }
        })
        .collect();
    if !sorted_labels.is_empty() {
        notes.push(format!(
            "points of {} section(s) not in order along their curve, sorted by height (ties by half-breadth): {}",
            sorted_labels.len(),
            sorted_labels.join(", ")
        ));
    }
    if super::long_csv::sort_by_x(&mut sections) {
        notes.push("sections put in order of x (aft to fore)".into());
    }
    (sections, notes)
}

/// The ranges of x and z, for the axes note.
pub(crate) fn ranges_note(sections: &[Section]) -> String {
    let pts = || sections.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = pts().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.x), b.max(p.x)));
    let (z0, z1) = pts().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.z), b.max(p.z)));
    format!("origin as in the file: x from {x0} to {x1}, z from {z0} to {z1}")
}

/// Parses a station point cloud (see [`parse_point_cloud`]).
///
/// ```text
/// % frigate, one station after another (BSpline3D-MATLAB frigate_1Surface.dat)
///   0.0000000e+000  7.5000000e-001  6.8290000e+000
///   0.0000000e+000  1.5000000e+000  8.5630000e+000
///  -2.0000000e+000  7.5000000e-001  5.3710000e+000
/// ```
///
/// ```text
/// station 5 x = 12.5
/// 0.0 0.0
/// 1.2 0.4
///
/// station 6 x = 15
/// 0.0 0.1
/// 1.3 0.5
/// ```
///
/// - One point a line: three numbers `x y z`, or two numbers `y z` whose station position is
///   given by its block's header (`x = 12.5`, `x=12.5` or `x 12.5` anywhere in it). Numbers are
///   separated by spaces or tabs; Fortran/MATLAB exponents (`7.5e-001`) are fine.
/// - Blocks are separated by blank lines or by header lines (any line whose first word is not
///   a number; its text labels the block). Lines starting with `#` or `%` are comments.
/// - A file without any blank line or header between its points (the MATLAB clouds) is cut
///   into stations where `x` changes: consecutive points at one `x` form a station.
///
/// Each block becomes one section, labelled by its header or `x<position>` (`x-78`). Points
/// are put keel to deck: a section whose heights fall is reversed; a section given in no order
/// along its curve (the frigate lists buttock, waterline, keel and deck points in turn) is
/// recognised by the polyline through its points in order of height (ties by half-breadth)
/// being shorter than the one in the file's order, and is sorted so, with a note. A section
/// whose points follow its curve (even one whose height goes down and up, such as a hollow
/// garboard) keeps its order.
/// Stations listed fore to aft are put aft to fore (a note says so).
///
/// Axes: as written, assumed x forward, y the half-breadth (>= 0; a negative y is an error),
/// z up; the origin is kept (the note gives the ranges of x and z, so a reader sees whether x
/// runs from the AP or from midship).
///
/// # Errors
///
/// [`HullError::Input`] at `source:line:column` (column = number on the line) for: binary
/// text, no points, a line with commas or semicolons, a point line without 2 or 3 numbers or
/// with another count than the first, a number that is not finite, `y z` points without a
/// station position, and a negative half-breadth.
pub fn parse_point_cloud(text: &str, source: &str, units: Units) -> Result<ReadOutcome, HullError> {
    super::decode(text.as_bytes(), source)?;
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    let (blocks, cut_on_x) = read_blocks(split_lines(text).enumerate().map(|(i, l)| (i + 1, l)), source, units)?;
    if blocks.is_empty() {
        return Err(HullError::input(Location::file(source), InputErrorKind::Empty));
    }
    let (sections, mut notes) = sections_of(blocks);
    if cut_on_x {
        notes.insert(0, "no blank lines or headers: stations cut where x changes".into());
    }
    let axes = format!("assumed x forward, y half-breadth, z up; {}", ranges_note(&sections));
    let mut out = ReadOutcome::plain(Offsets::new(source, units, sections), InputFormat::PointCloud, axes);
    out.notes = notes;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<ReadOutcome, HullError> {
        parse_point_cloud(text, "c.dat", Units::Metre)
    }

    fn err(text: &str) -> String {
        parse(text).err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into())
    }

    #[test]
    fn a_run_of_points_is_cut_where_x_changes_and_put_aft_to_fore() {
        let o = parse("% cloud\n 2 0 0\n 2 1 1\n 0 0.0e+000 1.0e-001\n 0 1 1\n").expect("valid");
        let s = &o.offsets.sections;
        assert_eq!(s.iter().map(|s| s.label.as_str()).collect::<Vec<_>>(), ["x0", "x2"]);
        assert_eq!(s[0].points, vec![Vec3::new(0.0, 0.0, 0.1), Vec3::new(0.0, 1.0, 1.0)]);
        assert_eq!(s[0].lines, vec![4, 5]);
        assert!(o.notes.iter().any(|n| n.contains("cut where x changes")), "{:?}", o.notes);
        assert!(o.axes.contains("x from 0 to 2"), "{}", o.axes);
    }

    #[test]
    fn headers_and_blank_lines_make_blocks_and_y_z_points_take_x_from_the_header() {
        let o = parse("station 5 x = 12.5\n0 0\n1.2 0.4\n\nstation 6 x=15\n0 0.1\n1.3 0.5\n").expect("valid");
        let s = &o.offsets.sections;
        assert_eq!(s[0].label, "station 5 x = 12.5");
        assert_eq!(s[1].points[1], Vec3::new(15.0, 1.3, 0.5));
        // Blank-line blocks of x y z: one section each, even when x varies inside a block.
        let o = parse("0 0 0\n0.1 1 1\n\n5 0 0\n5 1 1\n").expect("valid");
        assert_eq!(o.offsets.sections.len(), 2);
        assert_eq!(o.offsets.sections[0].points.len(), 2);
    }

    #[test]
    fn unordered_points_are_sorted_by_height_ordered_curves_keep_their_order() {
        // Buttock, waterline, keel and deck points in turn: sorted by (z, y).
        let o = parse("0 1 0.2\n0 2 1\n0 0 0\n0 2.2 2\n").expect("valid");
        let z: Vec<f64> = o.offsets.sections[0].points.iter().map(|p| p.z).collect();
        assert_eq!(z, vec![0.0, 0.2, 1.0, 2.0]);
        assert!(o.notes.iter().any(|n| n.contains("sorted by height")), "{:?}", o.notes);
        // A hollow garboard traced along its curve (z goes down then up): kept.
        let hollow = "0 0 0.2\n0 1 0.1\n0 2 0.3\n0 2.2 1.5\n";
        let o = parse(hollow).expect("valid");
        assert_eq!(o.offsets.sections[0].points[1], Vec3::new(0.0, 1.0, 0.1));
        assert!(o.notes.iter().all(|n| !n.contains("sorted by height")));
        // Deck to keel: reversed.
        let o = parse("0 2 2\n0 1 1\n0 0 0\n").expect("valid");
        assert_eq!(o.offsets.sections[0].points[0].z, 0.0);
        assert_eq!(o.offsets.sections[0].lines, vec![3, 2, 1]);
    }

    #[test]
    fn bad_clouds_are_located() {
        assert!(err("").starts_with("c.dat: no data"));
        assert!(err("% nothing\n\n").starts_with("c.dat: no data"));
        assert_eq!(err("0 0 0\n0 1 x\n"), "c.dat:2:3: \"x\" is not a number (expected the z coordinate in metres)");
        assert!(err("0 0 0\n0 1\n").starts_with("c.dat:2:2: 2 numbers on a line (expected 3 numbers per point"));
        assert!(err("0 0 0 0\n").starts_with("c.dat:1:4: 4 numbers on a line"));
        assert!(err("0 -1 0\n").starts_with("c.dat:1:2: half-breadth -1 is negative"));
        assert!(err("station 1\n0 0\n").starts_with("c.dat:2: a y z point without a station position"));
        assert!(err("0 0 nan\n").contains("not a finite number"));
        assert!(err("0 0 0\n0 1;1\n").starts_with("c.dat:2: a line with ';'"));
        assert!(err("0 0 0\n0\u{0} 1 1\n").contains("binary"));
    }
}
