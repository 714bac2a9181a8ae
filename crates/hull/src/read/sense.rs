//! Sense checks on offsets as read: the plausible mistakes a parser cannot see, each a
//! warning at its place with the value, what was expected and the flag that settles it.
//!
//! The rest of this module's documentation is on [`SenseKind`], where the library's users read it.

use std::fmt;

use serde::Serialize;

use super::{records, InputFormat};
use crate::error::{HullError, InputErrorKind, Location};
use crate::numfmt::format_short;
use crate::offsets::{bounds_of, Offsets, Section};
use crate::units::Units;

/// The longest ship afloat is about 458 m (Seawise Giant); a hull past 500 m is taken for a
/// mistake in units.
pub const LONGEST_SHIP_M: f64 = 500.0;

/// What to do with outlier cells (README, "Plausible mistakes (sense checks)").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OutlierPolicy {
    /// Keep them and warn at each (the default).
    #[default]
    Warn,
    /// Stop with an error at the first.
    Refuse,
    /// Keep them without a word (the user has checked them).
    Keep,
}

impl std::str::FromStr for OutlierPolicy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "warn" => Ok(OutlierPolicy::Warn),
            "refuse" => Ok(OutlierPolicy::Refuse),
            "keep" => Ok(OutlierPolicy::Keep),
            _ => Err(format!("unknown outlier policy {s:?} (expected warn, refuse or keep)")),
        }
    }
}

/// What a warning is about.
///
/// # The checks
///
/// * **Units named in the header** (`x_mm`, `y [mm]`, `z (ft)`, `halfbreadth_in` ...) that are
///   not the units the offsets are read in (`--units`).
/// * **Size**: a hull longer than any ship afloat (more than 500 m, `LONGEST_SHIP_M`: the
///   offsets are likely millimetres or inches read as metres), a beam larger than the length,
///   a depth larger than the length (a transposed table: waterlines read as stations).
/// * **End spacing**: an end station (or an offset table's end waterline) lying more than
///   5 (`END_GAP`) median spacings beyond its neighbour: a typo in its x or z.
/// * **Outlier cells**: a half-breadth that stands out from its neighbours both along its
///   station and along its waterline (`find_outliers`): a typo, a shifted decimal point, a
///   missing digit. What is done with them is [`OutlierPolicy`].
///
/// The checks only read: the offsets are never changed, so a clean table gives the same
/// offsets, bits for bits, as without them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SenseKind {
    /// A column name naming other units than those read in.
    UnitsInHeader,
    /// A size no ship has in the units read.
    Size,
    /// The table looks transposed.
    Transposed,
    /// A cell out of line with its neighbours.
    Outlier,
    /// An end station or waterline far beyond the others' spacing (a typo in its x or z).
    Spacing,
}

/// One sense warning: where, what kind, and the message (value, expectation, flag).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SenseWarning {
    /// Its place: `file:line:field` where known.
    #[serde(serialize_with = "location_string")]
    pub at: Location,
    /// What it is about.
    pub kind: SenseKind,
    /// The value concerned (in the units read).
    pub value: f64,
    /// The message: what was found, what was expected, the flag that settles it.
    pub message: String,
}

fn location_string<S: serde::Serializer>(at: &Location, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&at.to_string())
}

impl fmt::Display for SenseWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.at, self.message)
    }
}

/// The units a column name states: a `_mm`/`_m`/`_ft`/`_in` suffix, or the unit in brackets
/// or parentheses (`[mm]`, `(ft)`, `(inches)`); `None` when it names none.
pub fn units_in_name(name: &str) -> Option<Units> {
    let n = name.trim().to_ascii_lowercase();
    let unit = |u: &str| match u.trim() {
        "m" | "metre" | "metres" | "meter" | "meters" => Some(Units::Metre),
        "mm" | "millimetre" | "millimetres" | "millimeter" | "millimeters" => Some(Units::Millimetre),
        "ft" | "feet" | "foot" | "'" => Some(Units::Foot),
        "in" | "inch" | "inches" | "\"" => Some(Units::Inch),
        _ => None,
    };
    for (open, close) in [('[', ']'), ('(', ')')] {
        if let (Some(a), Some(b)) = (n.rfind(open), n.rfind(close)) {
            if a < b {
                if let Some(u) = unit(&n[a + 1..b]) {
                    return Some(u);
                }
            }
        }
    }
    let tail = n.rsplit(['_', ' ', '-']).next().filter(|t| t.len() < n.len())?;
    unit(tail)
}

/// Warnings for header fields of a CSV-family file naming units other than `units`.
fn header_units(text: &str, source: &str, units: Units) -> Vec<SenseWarning> {
    let Ok(recs) = records(text, source) else { return Vec::new() };
    let Some(header) = recs.first() else { return Vec::new() };
    header
        .fields
        .iter()
        .filter_map(|f| {
            let named = units_in_name(&f.text)?;
            (named != units).then(|| SenseWarning {
                at: header.at(source, f.column),
                kind: SenseKind::UnitsInHeader,
                value: f64::NAN,
                message: format!(
                    "column {:?} names {}, but the offsets are read in {}: pass --units {} if the values are {}",
                    f.text.as_ref(),
                    named.plural_name(),
                    units.plural_name(),
                    named.symbol(),
                    named.plural_name()
                ),
            })
        })
        .collect()
}

/// The place of point `k` of `s`, naming its field: the section's column (a table's cell), or
/// the y field of a row.
fn place(s: &Section, source: &str, k: usize, y_column: Option<usize>) -> Location {
    let mut at = s.location(source, k);
    if at.column.is_none() && at.line.is_some() {
        at.column = y_column;
    }
    at
}

/// Warnings on the hull's size in `offsets.units`: longer than any ship, beam or depth larger
/// than the length.
fn size(offsets: &Offsets, format: InputFormat, outliers: &[Outlier]) -> Vec<SenseWarning> {
    // The bounds without the outlier cells (one cell typed 81.3 for 8.13 is no beam of 163 m).
    let kept = offsets.sections.iter().enumerate().flat_map(|(s, sec)| {
        sec.points.iter().enumerate().filter(move |&(k, _)| !outliers.iter().any(|o| (o.section, o.point) == (s, k)))
    });
    let Some((lo, hi)) = bounds_of(kept.map(|(_, p)| *p)) else { return Vec::new() };
    let source = &offsets.source;
    let units = offsets.units;
    let u = units.symbol();
    let (length, beam, depth) = (hi.x - lo.x, 2.0 * hi.y.max(-lo.y), hi.z - lo.z);
    let length_m = length * units.metres_per_unit();
    let mut out = Vec::new();
    // The point at the largest x: where the length comes from.
    let fore = offsets
        .sections
        .iter()
        .flat_map(|s| s.points.iter().enumerate().map(move |(k, p)| (s, k, p.x)))
        .max_by(|a, b| a.2.total_cmp(&b.2))
        .map_or_else(|| Location::file(source), |(s, k, _)| s.location(source, k));
    if length_m > LONGEST_SHIP_M {
        let likely = [Units::Millimetre, Units::Inch, Units::Foot]
            .into_iter()
            .find(|c| *c != units && (1.0..=LONGEST_SHIP_M).contains(&(length * c.metres_per_unit())));
        let fix = match likely {
            Some(c) => format!(
                "if the offsets are in {} (a hull {} m long) pass --units {}",
                c.plural_name(),
                format_short(length * c.metres_per_unit()),
                c.symbol()
            ),
            None => "check the units (--units m, mm, ft or in)".to_string(),
        };
        out.push(SenseWarning {
            at: fore,
            kind: SenseKind::Size,
            value: length,
            message: format!(
                "the hull is {} {u} long{}, longer than any ship afloat (expected at most {} m): {fix}",
                format_short(length),
                if units == Units::Metre { String::new() } else { format!(" ({} m)", format_short(length_m)) },
                format_short(LONGEST_SHIP_M)
            ),
        });
    }
    let transposed_hint = if format == InputFormat::OffsetTable {
        "the table looks transposed: an offset table has the stations' x across its header row and the \
         waterlines' z down its first column"
    } else {
        "check the axes: x runs along the ship, y is the half-breadth, z is up"
    };
    if length > 0.0 && depth > length {
        out.push(SenseWarning {
            at: Location::file(source),
            kind: SenseKind::Transposed,
            value: depth,
            message: format!(
                "the hull is {} {u} deep and {} {u} long (expected a depth below the length): {transposed_hint}",
                format_short(depth),
                format_short(length)
            ),
        });
    } else if length > 0.0 && beam > length {
        out.push(SenseWarning {
            at: Location::file(source),
            kind: SenseKind::Transposed,
            value: beam,
            message: format!(
                "the hull is {} {u} broad (twice the largest half-breadth) and {} {u} long (expected a beam \
                 below the length): {transposed_hint}",
                format_short(beam),
                format_short(length)
            ),
        });
    }
    out
}

/// How many times the median spacing an end station or an end waterline of a table may lie
/// beyond its neighbour. Real tables space their end stations closer (half stations) or alike;
/// a decimal point shifted in the last x or z puts it 9 spacings or more away.
pub const END_GAP: f64 = 5.0;

/// Warnings for an end station (any format) or an end waterline (an offset table) lying more
/// than [`END_GAP`] median spacings beyond its neighbour.
///
/// `header_line` is an offset table's header line, where its stations' x are written.
fn spacing(offsets: &Offsets, format: InputFormat, header_line: Option<usize>) -> Vec<SenseWarning> {
    let source = &offsets.source;
    let u = offsets.units.symbol();
    let mut out = Vec::new();
    // (value, its place, what it is) in order, for the stations and the table's waterlines.
    let stations: Vec<(f64, Location, String)> = offsets
        .sections
        .iter()
        .filter_map(|s| {
            let mut at = s.location(source, 0);
            if format == InputFormat::OffsetTable {
                at.line = header_line;
            }
            s.mean_x().map(|x| (x, at, format!("station {}", s.label)))
        })
        .collect();
    let mut lines = vec![(stations, "x", "stations")];
    if format == InputFormat::OffsetTable {
        let mut zs: Vec<(f64, Location, String)> = Vec::new();
        for s in &offsets.sections {
            for (k, p) in s.points.iter().enumerate() {
                if !zs.iter().any(|(z, _, _)| *z == p.z) {
                    let mut at = s.location(source, k);
                    at.column = Some(1);
                    zs.push((p.z, at, format!("waterline z = {}", format_short(p.z))));
                }
            }
        }
        zs.sort_by(|a, b| a.0.total_cmp(&b.0));
        lines.push((zs, "z", "waterlines"));
    }
    for (values, axis, what) in lines {
        if values.len() < 4 {
            continue;
        }
        let mut gaps: Vec<f64> = values.windows(2).map(|w| (w[1].0 - w[0].0).abs()).collect();
        let (first, last) = (gaps[0], gaps[gaps.len() - 1]);
        gaps.sort_by(f64::total_cmp);
        let median = gaps[gaps.len() / 2];
        if !(median > 0.0) {
            continue;
        }
        for (gap, (value, at, name)) in [(first, &values[0]), (last, &values[values.len() - 1])] {
            if gap > END_GAP * median {
                out.push(SenseWarning {
                    at: at.clone(),
                    kind: SenseKind::Spacing,
                    value: *value,
                    message: format!(
                        "{name} at {axis} = {} {u} lies {} {u} beyond its neighbour, where the {what} are {} {u} \
                         apart (a typo in its {axis}, a shifted decimal point?)",
                        format_short(*value),
                        format_short(gap),
                        format_short(median)
                    ),
                });
            }
        }
    }
    out
}

/// An outlier cell: a half-breadth out of line with its neighbours in both directions.
#[derive(Clone, Debug, PartialEq)]
pub struct Outlier {
    /// Its section (index in the offsets).
    pub section: usize,
    /// Its point in the section.
    pub point: usize,
    /// The half-breadth read.
    pub value: f64,
    /// What its neighbours along the station give (linear in z between them).
    pub along_station: f64,
    /// What its neighbours along the waterline give (linear in x between the neighbouring
    /// sections' half-breadths at its z).
    pub along_waterline: f64,
}

/// Share of the largest half-breadth a cell must stand out by in both directions to be an
/// outlier. Measured on the 30 clean tables of `testdata/` (`crates/hull/tests/io/sense.rs`): at
/// 0.08 the coarse hand-made `offsets_example.csv` (4 stations) already shows two false
/// outliers at its bilge, at 0.12 no clean table shows one; 0.15 keeps a margin. A decimal
/// point shifted or a digit lost in a large cell moves it by far more.
pub const OUTLIER_SHARE: f64 = 0.15;

/// The half-breadth of `s` at height `z`: the point at that z if exactly one lies there, else
/// linear between the one pair of consecutive points bracketing it; `None` outside its z
/// range, or where the section meets that height more than once (a flat, a tumblehome):
/// there is no one waterline to compare with.
fn y_at(s: &Section, z: f64, tol: f64) -> Option<f64> {
    let mut on = s.points.iter().enumerate().filter(|(_, p)| (p.z - z).abs() <= tol);
    if let Some((k, p)) = on.next() {
        let steep_to = |j: usize| s.points.get(j).is_some_and(|q| steep(*p, *q));
        return (on.next().is_none() && (steep_to(k.wrapping_sub(1)) || steep_to(k + 1))).then_some(p.y);
    }
    let mut crossing = s.points.windows(2).filter_map(|w| {
        let (a, b) = (w[0], w[1]);
        let (lo, hi) = if a.z <= b.z { (a.z, b.z) } else { (b.z, a.z) };
        (lo < z && z < hi).then(|| steep(a, b).then(|| a.y + (b.y - a.y) * (z - a.z) / (b.z - a.z)))
    });
    let y = crossing.next()??;
    crossing.next().is_none().then_some(y)
}

/// Largest `|dy/dz|` of a piece of section where its half-breadth at a height is well defined
/// (the section runs within about 27° of the vertical): flatter, near a flat of bottom or at a
/// bilge, a small change of height moves the half-breadth a lot and z-interpolation says
/// little.
pub const STEEP_SLOPE: f64 = 2.0;

/// True when the chord `a`-`b` runs steeper than [`STEEP_SLOPE`].
fn steep(a: nurbs::Vec3, b: nurbs::Vec3) -> bool {
    (b.y - a.y).abs() <= STEEP_SLOPE * (b.z - a.z).abs()
}

/// The cells that depart from both predictions (along the station and along the waterline)
/// by more than [`OUTLIER_SHARE`] of the largest half-breadth, the same way. Only cells with
/// neighbours on both sides in both directions are judged (not the end sections, nor a
/// section's first and last points), where the section and its neighbours run steeper than
/// [`STEEP_SLOPE`] (the side, not a flat of bottom or a bilge's turn) and none of the three
/// `zigzags`: a spike in one cell pushes it away from both lines, while a knuckle, a chine
/// or a stem departs along one direction only.
pub fn find_outliers(offsets: &Offsets) -> Vec<Outlier> {
    let Some((lo, hi)) = offsets.bounds() else { return Vec::new() };
    let threshold = OUTLIER_SHARE * hi.y.max(0.0);
    let tol = 1e-9 * (hi - lo).norm();
    let secs = &offsets.sections;
    let mut out = Vec::new();
    for s in 1..secs.len().saturating_sub(1) {
        if secs[s - 1..=s + 1].iter().any(zigzags) {
            continue;
        }
        for k in 1..secs[s].points.len().saturating_sub(1) {
            let Some(on_station) = along_station(&secs[s], k, tol) else { continue };
            let p = secs[s].points[k];
            let Some(on_waterline) = along_waterline(secs, s, p.z, tol) else { continue };
            let (ra, rw) = (p.y - on_station, p.y - on_waterline);
            if !(ra.abs() > threshold && rw.abs() > threshold && ra.signum() == rw.signum()) {
                continue;
            }
            out.push(Outlier {
                section: s,
                point: k,
                value: p.y,
                along_station: on_station,
                along_waterline: on_waterline,
            });
        }
    }
    out
}

/// How many times its range of half-breadths a section's half-breadth may travel, keel to
/// deck, and still be a hull's section: once for a section widening to the deck, about twice
/// with tumblehome or a bulb, three times with both. More is a section that zigzags (an
/// off-centre pod or strut whose points were sorted by height), no half-breadth y(z) to judge
/// a cell against.
pub const ZIGZAG_TRAVEL: f64 = 3.0;

/// True when `sec`'s half-breadths travel more than [`ZIGZAG_TRAVEL`] times their range.
fn zigzags(sec: &Section) -> bool {
    let (lo, hi) = sec.points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.y), b.max(p.y)));
    let travel: f64 = sec.points.windows(2).map(|w| (w[1].y - w[0].y).abs()).sum();
    travel > ZIGZAG_TRAVEL * (hi - lo)
}

/// The half-breadth point `k` of `sec` would have on the chord of its two neighbours (linear
/// in z); `None` at the ends, on a level run (a flat of bottom, a deck: z does not tell the
/// points apart), where z turns back (no function y(z) there), or where the chord runs flatter
/// than [`STEEP_SLOPE`].
fn along_station(sec: &Section, k: usize, tol: f64) -> Option<f64> {
    let (a, p, b) = (*sec.points.get(k.checked_sub(1)?)?, *sec.points.get(k)?, *sec.points.get(k + 1)?);
    if (p.z - a.z).abs() <= tol || (b.z - p.z).abs() <= tol || (p.z - a.z) * (b.z - p.z) < 0.0 || !steep(a, b) {
        return None;
    }
    Some(a.y + (b.y - a.y) * (p.z - a.z) / (b.z - a.z))
}

/// The half-breadth section `s` would have at height `z` between its two neighbouring
/// sections (linear in x between their half-breadths at `z`); `None` for an end section, or
/// where a neighbour has no one half-breadth at `z` ([`y_at`]).
fn along_waterline(secs: &[Section], s: usize, z: f64, tol: f64) -> Option<f64> {
    let (prev, cur, next) = (secs.get(s.checked_sub(1)?)?, secs.get(s)?, secs.get(s + 1)?);
    let (xa, xs, xb) = (prev.mean_x()?, cur.mean_x()?, next.mean_x()?);
    if !(xa < xs && xs < xb) {
        return None;
    }
    let (ya, yb) = (y_at(prev, z, tol)?, y_at(next, z, tol)?);
    Some(ya + (yb - ya) * (xs - xa) / (xb - xa))
}

/// The message of an outlier: its value, the neighbours' predictions, a likely cause.
fn outlier_message(o: &Outlier, s: &Section, units: Units) -> String {
    let p = s.points[o.point];
    let u = units.symbol();
    let expected = 0.5 * (o.along_station + o.along_waterline);
    let ratio = o.value / expected;
    let cause = if (7.0..14.0).contains(&ratio) || (1.0 / 14.0..1.0 / 7.0).contains(&ratio) {
        " (a shifted decimal point?)"
    } else {
        " (a typo or a missing digit?)"
    };
    format!(
        "half-breadth {} {u} at station {} (x = {}), z = {} stands out from its neighbours{cause}: expected about {} \
         (along the station {}, along the waterline {}); correct the cell, or pass --outliers keep to fit it as \
         it is (--outliers refuse stops)",
        format_short(o.value),
        s.label,
        format_short(p.x),
        format_short(p.z),
        format_short(expected),
        format_short(o.along_station),
        format_short(o.along_waterline)
    )
}

/// Every sense check of offsets read from `text` as `format`, in `offsets.units`.
///
/// # Errors
/// [`HullError::Input`] at the first outlier cell with [`OutlierPolicy::Refuse`].
pub fn sense_check(
    text: &str,
    offsets: &Offsets,
    format: InputFormat,
    policy: OutlierPolicy,
) -> Result<Vec<SenseWarning>, HullError> {
    let source = &offsets.source;
    let mut out = Vec::new();
    if matches!(format, InputFormat::SectionsCsv | InputFormat::OffsetTable | InputFormat::LongCsv) {
        out.extend(header_units(text, source, offsets.units));
    }
    // The outliers are left out of the size checks even when kept unreported: they are the
    // finding, not a transposed table.
    let outliers = find_outliers(offsets);
    out.extend(size(offsets, format, &outliers));
    let header_line = records(text, source).ok().and_then(|r| r.first().map(|h| h.line));
    out.extend(spacing(offsets, format, header_line));
    if policy == OutlierPolicy::Keep {
        return Ok(out);
    }
    // The y field of a sections CSV row (its header names it); the other formats place their
    // cells.
    let y_column = (format == InputFormat::SectionsCsv).then(|| records(text, source).ok()).flatten().and_then(|r| {
        r.first()
            .and_then(|h| h.fields.iter().find(|f| super::sections_csv::base_name(&f.text) == "y").map(|f| f.column))
    });
    for o in outliers {
        let s = &offsets.sections[o.section];
        let at = place(s, source, o.point, y_column);
        let message = outlier_message(&o, s, offsets.units);
        if policy == OutlierPolicy::Refuse {
            return Err(HullError::input(
                at,
                InputErrorKind::Unexpected {
                    found: format!("an outlier cell: {message}"),
                    expected: "a half-breadth in line with its neighbours".into(),
                },
            ));
        }
        out.push(SenseWarning { at, kind: SenseKind::Outlier, value: o.value, message });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_are_read_from_column_names() {
        for (name, want) in [
            ("x_mm", Some(Units::Millimetre)),
            ("halfbreadth_mm", Some(Units::Millimetre)),
            ("y [mm]", Some(Units::Millimetre)),
            ("z (ft)", Some(Units::Foot)),
            ("Z (Feet)", Some(Units::Foot)),
            ("x_in", Some(Units::Inch)),
            ("x (inches)", Some(Units::Inch)),
            ("x_m", Some(Units::Metre)),
            ("x", None),
            ("section", None),
            ("mm", None),
            ("x_over_lpp", None),
            ("station", None),
        ] {
            assert_eq!(units_in_name(name), want, "{name}");
        }
    }
}
