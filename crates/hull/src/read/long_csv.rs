//! The long CSV: one point a row, columns found by their names.
//!
//! The rest of this module's documentation is on [`parse_long_csv`], where the library's users read it.

use std::collections::HashMap;

use nurbs::Vec3;

use super::views::{MergeOptions, Station, ThreeViews, ViewLine};
use super::{parse_number, records, InputFormat, ReadOptions, ReadOutcome, Record};
use crate::error::{HullError, InputErrorKind, Location};
use crate::offsets::{Offsets, Section};

/// Where the columns are (0-based field indices).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Columns {
    /// The x column.
    pub x: usize,
    /// The half-breadth column.
    pub y: usize,
    /// The height column.
    pub z: usize,
    /// The station label column.
    pub label: Option<usize>,
    /// The kind-of-point column.
    pub kind: Option<usize>,
    /// The line-name column.
    pub line: Option<usize>,
}

fn is_axis(name: &str, axis: char) -> bool {
    let mut chars = name.chars();
    chars.next() == Some(axis) && matches!(chars.next(), None | Some('_' | ' ' | '(' | '['))
}

impl Columns {
    /// Finds the columns in a header record; `None` unless x, y and z columns are all named
    /// (and no field of the header is a number).
    pub(crate) fn find(header: &Record<'_>) -> Option<Columns> {
        let names: Vec<String> = header.fields.iter().map(|f| f.text.to_ascii_lowercase()).collect();
        if names.iter().any(|n| n.parse::<f64>().is_ok()) {
            return None;
        }
        let pos = |pred: &dyn Fn(&str) -> bool| names.iter().position(|n| pred(n));
        let y = pos(&|n| {
            is_axis(n, 'y') || n.contains("halfbreadth") || n.contains("half_breadth") || n.contains("half-breadth")
        })?;
        Some(Columns {
            x: pos(&|n| is_axis(n, 'x'))?,
            y,
            z: pos(&|n| is_axis(n, 'z'))?,
            label: pos(&|n| matches!(n, "section" | "sections" | "station" | "station_index" | "frame")),
            kind: pos(&|n| matches!(n, "point_type" | "kind" | "type")),
            line: pos(&|n| matches!(n, "source_keys" | "line")),
        })
    }
}

/// The view a kind of point belongs to, `Ok(None)` for a kind that is not on the hull's side.
fn view_of(kind: &str) -> Result<Option<super::View>, ()> {
    use super::View;
    let k = kind.to_ascii_lowercase();
    if k.contains("centreline") && k.contains("deck") || k.contains("centerline") && k.contains("deck") {
        return Ok(None);
    }
    if k.contains("raised") || k.contains("bulwark") {
        return Ok(None);
    }
    if k.contains("waterline") {
        Ok(Some(View::Waterline))
    } else if k.contains("buttock") {
        Ok(Some(View::Buttock))
    } else if k.contains("keel") || k.contains("profile") || k.contains("stem") || k.contains("stern") {
        Ok(Some(View::Profile))
    } else if k.contains("deck") {
        Ok(Some(View::Deck))
    } else {
        Err(())
    }
}

/// Parses a long CSV (see [`parse_long_csv`]).
///
/// ```text
/// station_index,x_m_from_aft_end,waterline_index,z_m_above_baseline,halfbreadth_m,halfbreadth_is_null_in_source
/// 20,11.6,0,0.0,0.0,0
/// 21,12.18,0,0.0,0.0,0
/// 0,0.0,1,0.5,0.0,0
/// ...
/// ```
///
/// The header names the columns, in any order, case-insensitive:
///
/// - `x`, `y`, `z`: a column named `x` or starting with `x_` (`x_m_from_AP`), the same for `z`;
///   for `y` also any name containing `halfbreadth`, `half_breadth` or `half-breadth`. So
///   `x,z,y` (station, height, half-breadth) is read as it says.
/// - optional, the station label: `section`, `sections`, `station`, `station_index`, `frame`;
///   without it the stations are told apart by their `x`.
/// - optional, the kind of point: `point_type`, `kind` or `type` (see below), and the name of
///   its line: `source_keys` or `line`.
/// - any other column is not read (listed in a note).
///
/// An empty half-breadth is a missing offset (a `null` of the source) and is skipped.
///
/// **Without a kind column** every row is an offset of its station: each station (label, or
/// x) becomes one section, its points in order of height (ties by half-breadth), keel to deck;
/// rows of a station need not be consecutive (tables written waterline by waterline). The
/// sections are put in order of x.
///
/// **With a kind column** the rows are the lines of a lines plan, merged by
/// the three-views merge ([`Merged`](crate::Merged)): kinds containing `waterline` are waterline half-breadths, `buttock`
/// buttock heights, `keel` (or `profile`, `stem`, `stern`) centre-plane profile points, and
/// `deck_edge` or `deck` the deck line at side (the main deck); kinds naming a `centreline`
/// or `centerline` deck height, a `raised` deck or a `bulwark` lie above the hull's side and
/// are not read (counted in a note). Any other kind is an error.
///
/// Axes: as written (x forward, y half-breadth >= 0, z up), in the units given.
///
/// # Errors
///
/// [`HullError::Input`] at `source:line:column` for: an empty text, a header without x, y
/// and z columns, no data rows, a coordinate that is not a finite number, a negative
/// half-breadth, an empty x or z, and an unknown kind of point.
pub fn parse_long_csv(text: &str, source: &str, options: &ReadOptions) -> Result<ReadOutcome, HullError> {
    let recs = records(text, source)?;
    let Some((header, rows)) = recs.split_first() else {
        return Err(HullError::input(Location::file(source), InputErrorKind::Empty));
    };
    let Some(cols) = Columns::find(header) else {
        return Err(HullError::input(
            Location::line(source, header.line),
            InputErrorKind::Unexpected {
                found: "a header without x, y and z columns".into(),
                expected: "a long CSV header naming an x column (x or x_...), a z column (z or z_...) and a \
                    half-breadth column (y, y_... or ...halfbreadth...)"
                    .into(),
            },
        ));
    };
    if rows.is_empty() {
        return Err(HullError::input(
            Location::line(source, header.line),
            InputErrorKind::NoRows { expected: "one row per point".into() },
        ));
    }
    let unit = options.units.plural_name();
    let used = [Some(cols.x), Some(cols.y), Some(cols.z), cols.label, cols.kind, cols.line];
    let mut notes = Vec::new();
    let unread: Vec<&str> = header
        .fields
        .iter()
        .enumerate()
        .filter(|(i, _)| !used.contains(&Some(*i)))
        .map(|(_, f)| f.text.as_ref())
        .collect();
    if !unread.is_empty() {
        notes.push(format!("columns not read: {}", unread.join(", ")));
    }

    struct Point<'a> {
        label: String,
        p: Vec3,
        line: usize,
        kind: Option<&'a str>,
        line_name: Option<&'a str>,
    }
    let mut points = Vec::new();
    let mut missing = 0usize;
    for row in rows {
        let field = |i: usize| row.fields.get(i).map_or("", |f| f.text.as_ref());
        let num = |i: usize, what: &str| {
            parse_number(
                field(i),
                || row.at(source, i + 1),
                || format!("{what} in {unit} (column \"{}\")", header.fields[i].text),
            )
        };
        // x and z first: a row cut short has an empty half-breadth, but no missing offset
        // lacks its station or height.
        let x = num(cols.x, "the x coordinate")?;
        let z = num(cols.z, "the height z")?;
        if field(cols.y).is_empty() {
            missing += 1;
            continue;
        }
        let y = num(cols.y, "the half-breadth y")?;
        if y < 0.0 {
            return Err(HullError::input(row.at(source, cols.y + 1), InputErrorKind::NegativeHalfBreadth { y }));
        }
        let label = match cols.label.map(field) {
            Some(l) if !l.is_empty() => l.to_string(),
            _ => field(cols.x).to_string(),
        };
        points.push(Point {
            label,
            p: Vec3::new(x, y + 0.0, z),
            line: row.line,
            kind: cols.kind.map(field),
            line_name: cols.line.map(field),
        });
        if let Some(k) = cols.kind {
            if view_of(field(k)).is_err() {
                return Err(HullError::input(
                    row.at(source, k + 1),
                    InputErrorKind::Unexpected {
                        found: format!("kind of point \"{}\"", field(k)),
                        expected: "a kind naming a waterline, buttock, keel (profile, stem, stern) or deck \
                            edge point, or a centreline deck, raised deck or bulwark point (not read)"
                            .into(),
                    },
                ));
            }
        }
    }
    if missing > 0 {
        notes.push(format!("{missing} row(s) with an empty half-breadth (missing offsets) skipped"));
    }

    // Stations in order of first appearance, then of x.
    let mut order: Vec<(String, f64)> = Vec::new();
    let mut index: HashMap<String, usize> = HashMap::new();
    for p in &points {
        if !index.contains_key(&p.label) {
            index.insert(p.label.clone(), order.len());
            order.push((p.label.clone(), p.p.x));
        }
    }

    if cols.kind.is_none() {
        let mut sections: Vec<Section> = order
            .iter()
            .map(|(l, _)| Section { label: l.clone(), points: Vec::new(), lines: Vec::new(), column: None })
            .collect();
        let mut by_station: Vec<Vec<(Vec3, usize)>> = vec![Vec::new(); order.len()];
        for p in &points {
            by_station[index[&p.label]].push((p.p, p.line));
        }
        for (s, mut pts) in sections.iter_mut().zip(by_station) {
            pts.sort_by(|a, b| (a.0.z, a.0.y).partial_cmp(&(b.0.z, b.0.y)).unwrap_or(std::cmp::Ordering::Equal));
            s.points = pts.iter().map(|(p, _)| *p).collect();
            s.lines = pts.iter().map(|(_, l)| *l).collect();
        }
        let sorted = sort_by_x(&mut sections);
        if sorted {
            notes.push("sections put in order of x (aft to fore)".into());
        }
        let offsets = Offsets::new(source.to_string(), options.units, sections);
        let mut out = ReadOutcome::plain(offsets, InputFormat::LongCsv, super::AS_WRITTEN);
        out.notes = notes;
        return Ok(out);
    }

    // A lines plan: views, merged.
    order.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut views = ThreeViews {
        source: source.to_string(),
        units: options.units,
        stations: order
            .iter()
            .map(|(l, x)| Station { label: l.clone(), x: *x, curve: ViewLine::new(l.clone(), Vec::new()) })
            .collect(),
        waterlines: Vec::new(),
        buttocks: Vec::new(),
        profile: Vec::new(),
        deck: Vec::new(),
        dense: false,
    };
    let mut skipped: HashMap<String, usize> = HashMap::new();
    let mut lines_of: HashMap<(u8, String), usize> = HashMap::new();
    for p in &points {
        let kind = p.kind.unwrap_or("");
        let Ok(Some(view)) = view_of(kind) else {
            *skipped.entry(kind.to_string()).or_default() += 1;
            continue;
        };
        let (slot, list, default_name) = match view {
            super::View::Waterline => (0u8, &mut views.waterlines, format!("WL z = {}", p.p.z)),
            super::View::Buttock => (1, &mut views.buttocks, format!("buttock y = {}", p.p.y)),
            super::View::Profile => (2, &mut views.profile, "profile".to_string()),
            _ => (3, &mut views.deck, "deck".to_string()),
        };
        let name = match p.line_name {
            Some(n) if !n.is_empty() && slot < 2 => n.to_string(),
            _ => default_name,
        };
        let i = *lines_of.entry((slot, name.clone())).or_insert_with(|| {
            list.push(ViewLine::new(name.clone(), Vec::new()));
            list.len() - 1
        });
        list[i].push(p.p, p.line);
    }
    let mut skipped: Vec<(String, usize)> = skipped.into_iter().collect();
    skipped.sort();
    for (k, n) in skipped {
        notes.push(format!("{n} point(s) of kind \"{k}\" not read (above the hull's side)"));
    }
    for l in views.profile.iter_mut().chain(views.deck.iter_mut()) {
        sort_line_by_x(l);
    }
    let merged = views.merge(&MergeOptions { tolerance: options.tolerance });
    Ok(ReadOutcome::merged(merged, InputFormat::LongCsv, super::AS_WRITTEN, notes))
}

/// Puts a line's points (and their source lines) in order of x.
pub(crate) fn sort_line_by_x(l: &mut ViewLine) {
    let mut idx: Vec<usize> = (0..l.points.len()).collect();
    idx.sort_by(|&a, &b| l.points[a].x.total_cmp(&l.points[b].x));
    l.points = idx.iter().map(|&i| l.points[i]).collect();
    if l.lines.len() == idx.len() {
        l.lines = idx.iter().map(|&i| l.lines[i]).collect();
    }
}

/// Sorts sections by their mean x when every section lies at one x; returns whether the order
/// changed.
pub(crate) fn sort_by_x(sections: &mut [Section]) -> bool {
    let planar = sections.iter().all(|s| s.points.windows(2).all(|w| w[0].x == w[1].x));
    if !planar {
        return false;
    }
    let key = |s: &Section| s.mean_x().unwrap_or(f64::INFINITY);
    let before: Vec<String> = sections.iter().map(|s| s.label.clone()).collect();
    sections.sort_by(|a, b| key(a).total_cmp(&key(b)));
    sections.iter().map(|s| &s.label).ne(before.iter())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::Units;

    fn parse(text: &str) -> Result<ReadOutcome, HullError> {
        parse_long_csv(text, "long.csv", &ReadOptions::default())
    }

    fn err(text: &str) -> String {
        parse(text).err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into())
    }

    #[test]
    fn columns_are_found_by_name_in_any_order() {
        let recs = records("X_m,Z (m),Half-Breadth,station,notes\n", "t").expect("valid");
        let c = Columns::find(&recs[0]).expect("found");
        assert_eq!((c.x, c.z, c.y, c.label, c.kind), (0, 1, 2, Some(3), None));
        let none = records("x,z,width\n", "t").expect("valid");
        assert!(Columns::find(&none[0]).is_none());
        let numeric = records("x,y,z,1\n", "t").expect("valid");
        assert!(Columns::find(&numeric[0]).is_none(), "a number in the header is data");
        let xy = records("xy,x,y,z\n", "t").expect("valid");
        assert_eq!(Columns::find(&xy[0]).map(|c| c.x), Some(1), "`xy` is not an x column");
    }

    #[test]
    fn x_z_y_rows_become_sections_keel_to_deck_in_order_of_x() {
        // Written waterline by waterline, station 10 before station 0.
        let o = parse("x,z,y\n10,0,1\n0,0,0.5\n10,1,2\n0,1,1.5\n10,2,\n0,2,2\n").expect("valid");
        let s = &o.offsets.sections;
        assert_eq!(s.iter().map(|s| s.label.as_str()).collect::<Vec<_>>(), ["0", "10"]);
        assert_eq!(s[0].points, vec![Vec3::new(0.0, 0.5, 0.0), Vec3::new(0.0, 1.5, 1.0), Vec3::new(0.0, 2.0, 2.0)]);
        assert_eq!(s[0].lines, vec![3, 5, 7]);
        assert_eq!(s[1].points.len(), 2, "the empty half-breadth is a missing offset");
        assert!(o.notes.iter().any(|n| n.contains("1 row(s) with an empty half-breadth")), "{:?}", o.notes);
        assert!(o.notes.iter().any(|n| n.contains("order of x")), "{:?}", o.notes);
        assert_eq!(o.offsets.units, Units::Metre);
    }

    #[test]
    fn kinds_make_three_views() {
        let text = "station,x,point_type,y,z\n\
                    1,0,keel_point_on_centreline,0,0\n\
                    1,0,waterline_halfbreadth,2,1\n\
                    1,0,buttock_height,1,0\n\
                    1,0,main_deck_edge,2,2\n\
                    1,0,bulwark_top,2.1,3\n\
                    2,5,keel_point_on_centreline,0,0\n\
                    2,5,waterline_halfbreadth,2,1\n\
                    2,5,buttock_height,1,1.5\n\
                    2,5,main_deck_edge,2,2\n";
        let o = parse(text).expect("valid");
        assert_eq!(o.offsets.sections.len(), 2);
        assert_eq!(o.offsets.sections[0].points.len(), 4);
        assert_eq!(o.disagreements.len(), 1);
        assert_eq!(o.disagreements[0].station, "2");
        assert_eq!(o.disagreements[0].at.to_string(), "long.csv:9");
        assert!(o.notes.iter().any(|n| n.contains("\"bulwark_top\"")), "{:?}", o.notes);
    }

    #[test]
    fn bad_rows_are_located() {
        assert!(err("").starts_with("long.csv: no data"));
        assert!(err("x,z,y\n").starts_with("long.csv:1: no data rows"));
        assert_eq!(
            err("x,z,y\n0,0,0\n0,a,1\n"),
            "long.csv:3:2: \"a\" is not a number (expected the height z in metres (column \"z\"))"
        );
        assert!(err("x,z,y\n0,0,-1\n").starts_with("long.csv:2:3: half-breadth -1 is negative"));
        assert!(err("x,z,y\n,0,1\n").starts_with("long.csv:2:1: empty field (expected the x coordinate"));
        // A row cut after its x lacks its z too: not a missing offset.
        assert!(err("x,z,y\n0,0,1\n0,1,1\n5").starts_with("long.csv:4:2: empty field (expected the height z"));
        assert!(err("x,z,y,kind\n0,0,1,chine\n").starts_with("long.csv:2:4: kind of point \"chine\""));
        assert!(err("a,b,c\n0,0,1\n").starts_with("long.csv:1: a header without x, y and z columns"));
    }
}
