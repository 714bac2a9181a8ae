//! FREE!ship (and DELFTship) text exchange: the "Offsets as 3D points" export and the curve
//! import text.
//!
//! The rest of this module's documentation is on [`parse_freeship_offsets`], where the library's users read it.

use nurbs::Vec3;

use super::views::{MergeOptions, Station, ThreeViews, ViewLine};
use super::{parse_number, split_lines, InputFormat, ReadOptions, ReadOutcome};
use crate::error::{HullError, InputErrorKind, Location};
use crate::offsets::Offsets;
use crate::units::Units;

const KEYWORDS: [&str; 4] = ["station", "buttock", "waterline", "diagonal"];

/// True for a FREE!ship description line: `Station 12.000` (or a buttock, waterline or
/// diagonal) or `CONTROLCURVE`.
pub fn is_header(line: &str) -> bool {
    let toks: Vec<&str> = line.split_whitespace().collect();
    match toks.as_slice() {
        [k] => k.eq_ignore_ascii_case("controlcurve"),
        [k, v] => KEYWORDS.iter().any(|w| k.eq_ignore_ascii_case(w)) && v.replace(',', ".").parse::<f64>().is_ok(),
        _ => false,
    }
}

fn unexpected(at: Location, found: impl Into<String>, expected: impl Into<String>) -> HullError {
    HullError::input(at, InputErrorKind::Unexpected { found: found.into(), expected: expected.into() })
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Station,
    Buttock,
    Waterline,
    Other,
}

struct Intersection {
    kind: Kind,
    label: String,
    position: f64,
    segments: Vec<ViewLine>,
    /// The count of an `N segments.` line, with its line number.
    declared: Option<(u64, usize)>,
    /// The `SEGMENT i` lines read.
    segment_lines: u64,
}

/// An `N segments.` line must be followed by N `SEGMENT i` lines before the next description
/// line: a count that disagrees means a file cut short or edited by hand (the count itself is
/// never used to allocate).
fn check_segment_count(item: Option<&Intersection>, source: &str) -> Result<(), HullError> {
    match item {
        Some(&Intersection { declared: Some((n, line)), segment_lines, ref label, .. }) if n != segment_lines => {
            Err(unexpected(
                Location::line(source, line),
                format!("\"{n} segments.\" for {label}, followed by {segment_lines} SEGMENT line(s)"),
                "as many SEGMENT i lines as the count says, each before its points",
            ))
        }
        _ => Ok(()),
    }
}

/// Parses a FREE!ship offsets export.
///
/// Layouts as FREE!ship writes and reads them (FREE!ship 2.6 / FREE!ship Plus, GPL, unit
/// `FreeShipUnit.pas`: `TFreeEdit.File_ExportOffsets`, `TFreeEdit.File_ImportChines`,
/// `TFreeIntersection.FGetDescription`).
///
/// **Offsets export** (File > Export > Offsets, `*.txt`): every intersection of the model, the
/// stations first, then the buttocks, the waterlines, the diagonals and the control curves:
///
/// ```text
/// Station 25.000
///            25.0000     0.0000     0.0000
///            25.0000     2.8125     0.6250
///            25.0000     4.4531     1.2500    KNUCKLE
/// Buttock 1.000
///             4.9875     1.0000     0.0000
/// Waterline 2.500
/// 2 segments.
/// SEGMENT 1
///             0.0000     0.0000     2.5000
/// SEGMENT 2
/// ...
/// CONTROLCURVE
/// ...
/// ```
///
/// - A description line: `Station`, `Buttock`, `Waterline` or `Diagonal`, a space, then the
///   plane's position with three decimals (`FloatToStrF(..., ffFixed, 7, 3)`: x of a station,
///   y of a buttock, z of a waterline); or `CONTROLCURVE`.
/// - When the intersection has more than one piece, a line `N segments.` and a line
///   `SEGMENT i` before each piece.
/// - One point a line: eight spaces, then x, y, z each with four decimals right-aligned in ten
///   characters, separated by one space (`MakeLength(P, 4, 10)`); a knuckle point ends with
///   `    KNUCKLE`.
///
/// The stations are the body plan, the waterlines and buttocks the other two views: they are
/// merged by the three-views merge ([`Merged`](crate::Merged)) (each station curve is a section, keel to deck; every waterline
/// and buttock crossing the station is checked against it and the disagreements reported).
/// The pieces of a station are joined in file order, each turned to continue from the end of
/// the one before. Diagonals and control curves are not read (noted).
///
/// **Curve import text** (File > Import > Chines, `*.txt`):
///
/// ```text
/// 0
///   25.0 0.0 0.0
///   25.0 2.8125 0.625
///
///   50.0 0.0 0.0
///   ...
/// EOF
/// ```
///
/// The first line is the units, `0` metric (metres) or `1` imperial (feet); then the curves as
/// `x y z` lines, a blank line between two curves; an `EOF` line (or the end of the file) ends
/// the data. Each curve becomes one section (points as in a point cloud); the
/// coordinates are converted from the file's units to the units asked for.
///
/// Axes: FREE!ship's, as written: x forward from the model's origin (where the designer put
/// it, usually the aft perpendicular), y the half-breadth of the modelled side, z up from the
/// baseline. A file whose half-breadths are all <= 0 (the other side) is mirrored, y -> -y,
/// with a note; a file with both signs is an error.
///
/// # Errors
///
/// [`HullError::Input`] at `source:line:column` (column = number on the line) for: no
/// station, a point before any description line, a point line without three numbers (or
/// with text other than `KNUCKLE` after them), a number that is not finite (a decimal comma is
/// named), an unknown description line, half-breadths of both signs.
pub fn parse_freeship_offsets(text: &str, source: &str, options: &ReadOptions) -> Result<ReadOutcome, HullError> {
    super::decode(text.as_bytes(), source)?;
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    let unit = options.units.plural_name();
    let mut items: Vec<Intersection> = Vec::new();
    for (i, raw) in split_lines(text).enumerate() {
        let lineno = i + 1;
        let line = raw.trim();
        if line.is_empty() {
            continue;
        }
        let toks: Vec<&str> = line.split_whitespace().collect();
        let first = toks[0];
        if first.parse::<f64>().is_ok() && !(toks.len() == 2 && toks[1].eq_ignore_ascii_case("segments.")) {
            let Some(item) = items.last_mut() else {
                return Err(unexpected(
                    Location::line(source, lineno),
                    "a point before any description line",
                    "a description line such as Station 12.000 before the points",
                ));
            };
            let knuckle = toks.len() == 4 && toks[3].eq_ignore_ascii_case("knuckle");
            if toks.len() != 3 && !knuckle {
                return Err(unexpected(
                    Location::new(source, lineno, toks.len().min(4)),
                    format!("\"{line}\""),
                    "a point: x y z, optionally followed by KNUCKLE",
                ));
            }
            let mut v = [0.0; 3];
            for k in 0..3 {
                v[k] = parse_number(
                    toks[k],
                    || Location::new(source, lineno, k + 1),
                    || format!("the {} coordinate in {unit}", ["x", "y", "z"][k]),
                )?;
            }
            if item.segments.is_empty() {
                item.segments.push(ViewLine::new(item.label.clone(), Vec::new()));
            }
            let seg = item.segments.last_mut().expect("a segment was just ensured");
            seg.push(Vec3::new(v[0], v[1], v[2]), lineno);
            continue;
        }
        if toks.len() == 2 && toks[1].eq_ignore_ascii_case("segments.") {
            // "N segments.": the SEGMENT lines follow.
            let n = first.parse::<u64>().map_err(|_| {
                unexpected(
                    Location::new(source, lineno, 1),
                    format!("segment count \"{}\"", super::shown(first)),
                    "a whole number of segments: N segments.",
                )
            })?;
            if let Some(item) = items.last_mut() {
                item.declared = Some((n, lineno));
            }
            continue;
        }
        if first.eq_ignore_ascii_case("segment") && toks.len() == 2 {
            match items.last_mut() {
                Some(item) => {
                    item.segment_lines += 1;
                    item.segments.push(ViewLine::new(format!("{} segment {}", item.label, toks[1]), Vec::new()))
                }
                None => {
                    return Err(unexpected(
                        Location::line(source, lineno),
                        "a SEGMENT line before any description line",
                        "a description line such as Station 12.000 first",
                    ))
                }
            }
            continue;
        }
        if is_header(line) {
            let kind = match first.to_ascii_lowercase().as_str() {
                "station" => Kind::Station,
                "buttock" => Kind::Buttock,
                "waterline" => Kind::Waterline,
                _ => Kind::Other,
            };
            let position = match toks.get(1) {
                Some(t) => parse_number(
                    t,
                    || Location::new(source, lineno, 2),
                    || format!("the position of the {} in {unit}", first.to_ascii_lowercase()),
                )?,
                None => 0.0,
            };
            check_segment_count(items.last(), source)?;
            items.push(Intersection {
                kind,
                label: line.to_string(),
                position,
                segments: Vec::new(),
                declared: None,
                segment_lines: 0,
            });
            continue;
        }
        return Err(unexpected(
            Location::line(source, lineno),
            format!("line \"{line}\""),
            "a FREE!ship offsets line: Station/Buttock/Waterline/Diagonal <position>, CONTROLCURVE, N \
                segments., SEGMENT i, or a point x y z [KNUCKLE]",
        ));
    }
    check_segment_count(items.last(), source)?;

    // Mirror a file of the other side; refuse mixed signs.
    let ys = || items.iter().flat_map(|it| it.segments.iter()).flat_map(|s| s.points.iter()).map(|p| p.y);
    let mut notes = Vec::new();
    let negative = ys().any(|y| y < 0.0);
    if negative {
        if ys().any(|y| y > 0.0) {
            let (line, y) = items
                .iter()
                .flat_map(|it| it.segments.iter())
                .flat_map(|s| s.points.iter().zip(&s.lines))
                .find(|(p, _)| p.y < 0.0)
                .map(|(p, l)| (*l, p.y))
                .unwrap_or((0, 0.0));
            return Err(HullError::input(Location::new(source, line, 2), InputErrorKind::NegativeHalfBreadth { y }));
        }
        for it in &mut items {
            if it.kind == Kind::Buttock {
                it.position = -it.position;
            }
            for s in &mut it.segments {
                for p in &mut s.points {
                    p.y = -p.y + 0.0;
                }
            }
        }
        notes.push("every half-breadth is <= 0 (the other side): mirrored, y -> -y".into());
    }

    let mut views = ThreeViews {
        source: source.to_string(),
        units: options.units,
        stations: Vec::new(),
        waterlines: Vec::new(),
        buttocks: Vec::new(),
        profile: Vec::new(),
        deck: Vec::new(),
        dense: true,
    };
    let mut others = 0;
    let mut joined = Vec::new();
    for it in items {
        match it.kind {
            Kind::Station => {
                if it.segments.len() > 1 {
                    joined.push(it.label.clone());
                }
                let curve = join(it.segments, &it.label);
                if curve.points.is_empty() {
                    continue;
                }
                let x = curve.points.iter().map(|p| p.x).sum::<f64>() / curve.points.len() as f64;
                let label = it.label.split_whitespace().nth(1).unwrap_or(&it.label).to_string();
                views.stations.push(Station { label, x, curve });
            }
            Kind::Waterline => views.waterlines.extend(it.segments),
            Kind::Buttock => views.buttocks.extend(it.segments),
            Kind::Other => others += 1,
        }
    }
    if views.stations.is_empty() {
        return Err(unexpected(
            Location::file(source),
            "no station",
            "at least one Station <x> block of points (export the stations of the model)",
        ));
    }
    views.stations.sort_by(|a, b| a.x.total_cmp(&b.x));
    if !joined.is_empty() {
        notes.push(format!("stations of several segments joined end to end: {}", joined.join(", ")));
    }
    if others > 0 {
        notes.push(format!("{others} diagonal(s) and control curve(s) not read"));
    }
    let merged = views.merge(&MergeOptions { tolerance: options.tolerance });
    Ok(ReadOutcome::merged(
        merged,
        InputFormat::FreeshipOffsets,
        "FREE!ship's, as written: x forward from the model's origin, y half-breadth, z up from the baseline",
        notes,
    ))
}

/// Joins the segments of one intersection end to end, each turned so that it starts at the
/// end of the one before nearest to it.
fn join(segments: Vec<ViewLine>, label: &str) -> ViewLine {
    let mut out = ViewLine::new(label, Vec::new());
    for mut s in segments.into_iter().filter(|s| !s.points.is_empty()) {
        if let Some(&end) = out.points.last() {
            let (first, last) = (s.points[0], s.points[s.points.len() - 1]);
            if last.distance(end) < first.distance(end) {
                s.points.reverse();
                s.lines.reverse();
            }
        }
        if out.points.last().is_some_and(|&end| s.points[0] == end) {
            // The joint, repeated by both pieces.
            s.points.remove(0);
            if !s.lines.is_empty() {
                s.lines.remove(0);
            }
        }
        let has_lines = out.lines.len() == out.points.len() && s.lines.len() == s.points.len();
        out.points.extend(s.points);
        if has_lines {
            out.lines.extend(s.lines);
        } else {
            out.lines.clear();
        }
    }
    out
}

/// Parses FREE!ship's curve import text (see [`parse_freeship_offsets`]), converting its units to
/// `units`.
///
/// # Errors
///
/// [`HullError::Input`]: a first line other than `0` or `1`, and every error of
/// [`super::point_cloud::parse_point_cloud`] in the curves.
pub fn parse_freeship_curves(text: &str, source: &str, units: Units) -> Result<ReadOutcome, HullError> {
    super::decode(text.as_bytes(), source)?;
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    let mut lines = split_lines(text).enumerate().map(|(i, l)| (i + 1, l)).filter(|(_, l)| !l.trim().is_empty());
    let Some((lineno, first)) = lines.next() else {
        return Err(HullError::input(Location::file(source), InputErrorKind::Empty));
    };
    let file_units = match first.trim() {
        "0" => Units::Metre,
        "1" => Units::Foot,
        other => {
            return Err(unexpected(
                Location::new(source, lineno, 1),
                format!("units line \"{other}\""),
                "0 (metric) or 1 (imperial) on the first line of a FREE!ship curve file",
            ))
        }
    };
    let body = split_lines(text)
        .enumerate()
        .map(|(i, l)| (i + 1, l))
        .skip(lineno)
        .take_while(|(_, l)| !l.trim().eq_ignore_ascii_case("eof"));
    let (blocks, _) = super::point_cloud::read_blocks(body, source, file_units)?;
    if blocks.is_empty() {
        return Err(HullError::input(Location::file(source), InputErrorKind::Empty));
    }
    let (mut sections, notes) = super::point_cloud::sections_of(blocks);
    // Feet to metres and back: one multiplication by the exact ratio of the definitions.
    let scale = file_units.metres_per_unit() / units.metres_per_unit();
    if file_units != units {
        for s in &mut sections {
            for p in &mut s.points {
                *p = *p * scale;
            }
        }
    }
    let axes = format!(
        "FREE!ship's, as written (x forward, y half-breadth, z up); units {} in the file{}; {}",
        file_units.symbol(),
        if file_units != units { format!(", converted to {}", units.symbol()) } else { String::new() },
        super::point_cloud::ranges_note(&sections)
    );
    let mut out = ReadOutcome::plain(Offsets::new(source, units, sections), InputFormat::FreeshipCurves, axes);
    out.notes = notes;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXPORT: &str = "Station 10.000
          10.0000     0.0000     0.0000
          10.0000     1.5000     0.0000
          10.0000     2.0000     0.5000
          10.0000     2.0000     2.0000    KNUCKLE
Station 0.000
2 segments.
SEGMENT 1
           0.0000     1.0000     2.0000
           0.0000     1.0000     1.0000
SEGMENT 2
           0.0000     0.0000     0.5000
           0.0000     1.0000     1.0000
Buttock 1.000
          10.0000     1.0000     0.0000
Waterline 1.000
           0.0000     1.0000     1.0000
          10.0000     2.0000     1.0000
CONTROLCURVE
           5.0000     0.0000     0.0000
";

    fn opts() -> ReadOptions {
        ReadOptions { tolerance: Some(1e-3), ..ReadOptions::default() }
    }

    #[test]
    fn headers_are_recognised() {
        assert!(is_header("Station 12.000"));
        assert!(is_header("waterline -0,500"));
        assert!(is_header("CONTROLCURVE"));
        assert!(!is_header("Station"));
        assert!(!is_header("station 5 x = 1"));
    }

    #[test]
    fn stations_are_the_sections_and_the_other_views_are_checked() {
        let o = parse_freeship_offsets(EXPORT, "f.txt", &opts()).expect("valid");
        let s = &o.offsets.sections;
        assert_eq!(s.iter().map(|s| s.label.as_str()).collect::<Vec<_>>(), ["0.000", "10.000"]);
        // Station 0's two segments joined (the second turned round, the joint once) and run
        // keel to deck.
        let yz: Vec<(f64, f64)> = s[0].points.iter().map(|p| (p.y, p.z)).collect();
        assert_eq!(yz, vec![(0.0, 0.5), (1.0, 1.0), (1.0, 2.0)]);
        // The waterline z = 1 gives y = 1 at x = 0 (on the curve) and 2 at x = 10 (on it);
        // the buttock y = 1 at x = 10, z = 0 lies on the flat bottom: no disagreement.
        assert!(o.disagreements.is_empty(), "{:?}", o.disagreements);
        assert!(o.notes.iter().any(|n| n.contains("joined")), "{:?}", o.notes);
        assert!(o.notes.iter().any(|n| n.contains("1 diagonal(s) and control curve(s)")), "{:?}", o.notes);
        // Move the waterline at x = 10 out by 0.3: one disagreement there.
        let bad = EXPORT.replace("10.0000     2.0000     1.0000", "10.0000     2.3000     1.0000");
        let o = parse_freeship_offsets(&bad, "f.txt", &opts()).expect("valid");
        assert_eq!(o.disagreements.len(), 1);
        let d = &o.disagreements[0];
        assert_eq!((d.station.as_str(), d.z), ("10.000", 1.0));
        assert!((d.difference + 0.3).abs() < 1e-12, "{d}");
        assert_eq!(d.at.to_string(), "f.txt:18");
    }

    #[test]
    fn the_other_side_is_mirrored_and_mixed_signs_refused() {
        let negate_y = |l: &str| {
            let t: Vec<&str> = l.split_whitespace().collect();
            if t.len() >= 3 && t[1].parse::<f64>().is_ok() {
                format!("{} -{} {}", t[0], t[1], t[2..].join(" "))
            } else {
                l.to_string()
            }
        };
        let port: String = EXPORT.lines().map(|l| negate_y(l) + "\n").collect();
        let o = parse_freeship_offsets(&port, "f.txt", &opts()).expect("valid");
        assert!(o.notes.iter().any(|n| n.contains("mirrored")));
        assert!(o.offsets.sections.iter().flat_map(|s| &s.points).all(|p| p.y >= 0.0));
        let mixed = EXPORT.replacen("     2.0000     0.5", "    -2.0000     0.5", 1);
        let e = parse_freeship_offsets(&mixed, "f.txt", &opts()).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.starts_with("f.txt:4:2: half-breadth -2 is negative"), "{e}");
    }

    #[test]
    fn bad_exports_are_located() {
        let err =
            |t: &str| parse_freeship_offsets(t, "f.txt", &opts()).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(err("  1 2 3\n").starts_with("f.txt:1: a point before any description line"));
        assert!(err("Station 1.000\n 1 2\n").starts_with("f.txt:2:2: \"1 2\" (expected a point"));
        assert!(err("Station 1.000\n 1 2,5 3\n").starts_with("f.txt:2:2: \"2,5\" has a decimal comma"));
        assert!(err("Station 1.000\n 1 2 3\nChine 4\n").starts_with("f.txt:3: line \"Chine 4\""));
        assert!(err("Waterline 1.000\n 1 2 3\n").starts_with("f.txt: no station"));
        assert!(err("Station 1.000\n 1 2 3 BEND\n").starts_with("f.txt:2:4:"));
    }

    #[test]
    fn segment_counts_must_match_the_segment_lines() {
        let err =
            |t: &str| parse_freeship_offsets(t, "f.txt", &opts()).err().map(|e| e.to_string()).unwrap_or_default();
        // A count far beyond the file (never allocated), at the end of the file and before
        // the next description line.
        let huge = EXPORT.replace("2 segments.", "4294967295 segments.");
        assert!(
            err(&huge)
                .starts_with("f.txt:7: \"4294967295 segments.\" for Station 0.000, followed by 2 SEGMENT line(s)"),
            "{}",
            err(&huge)
        );
        let e = err("Station 1.000\n3 segments.\nSEGMENT 1\n 1 0 0\n 1 1 1\n");
        assert!(e.starts_with("f.txt:2: \"3 segments.\" for Station 1.000, followed by 1 SEGMENT line(s)"), "{e}");
        assert!(err("Station 1.000\n2.5 segments.\n").starts_with("f.txt:2:1: segment count \"2.5\""));
        // The export as FREE!ship writes it reads.
        assert!(parse_freeship_offsets(EXPORT, "f.txt", &opts()).is_ok());
    }

    #[test]
    fn curve_text_reads_units_and_blocks() {
        let text = "1\n  0 0 0\n  0 1 1\n\n  10 0 0\n  10 1 1\nEOF\nignored after EOF\n";
        let o = parse_freeship_curves(text, "c.txt", Units::Metre).expect("valid");
        assert_eq!(o.offsets.sections.len(), 2);
        // 1 ft = 0.3048 m exactly by definition; 10 ft = 3.048 m within one rounding.
        assert!((o.offsets.sections[1].points[1].x - 3.048).abs() < 1e-15);
        assert!(o.axes.contains("units ft in the file, converted to m"), "{}", o.axes);
        let same = parse_freeship_curves(text, "c.txt", Units::Foot).expect("valid");
        assert_eq!(same.offsets.sections[1].points[1], Vec3::new(10.0, 1.0, 1.0));
        let e =
            parse_freeship_curves("2\n0 0 0\n", "c.txt", Units::Metre).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.starts_with("c.txt:1:1: units line \"2\""), "{e}");
        assert!(parse_freeship_curves("0\nEOF\n", "c.txt", Units::Metre).is_err());
    }
}
