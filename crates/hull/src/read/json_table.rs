//! JSON offset tables: the vessel.js ship specification and the OpenHull station table.
//!
//! The rest of this module's documentation is on [`parse_json_table`], where the library's users read it.

use std::path::Path;

use nurbs::Vec3;
use serde_json::{Map, Value};

use super::views::{MergeOptions, Station, ThreeViews, ViewLine};
use super::{InputFormat, ReadOptions, ReadOutcome};
use crate::error::{HullError, InputErrorKind, Location};
use crate::offsets::{Offsets, Perpendiculars, Section};
use crate::units::Units;

/// The number of station intervals of an OpenHull table (stations 0 .. 20 over Lpp).
pub const OPENHULL_STATIONS: f64 = 20.0;

/// True when a JSON text holds one of the two offset layouts (a `halfBreadths` or a `站号`
/// key): a cheap test to tell it from other JSON inputs such as a fitted surface.
pub fn is_offset_json(text: &str) -> bool {
    text.contains("\"halfBreadths\"") || text.contains("\"站号\"")
}

fn unexpected(at: Location, found: impl Into<String>, expected: impl Into<String>) -> HullError {
    HullError::input(at, InputErrorKind::Unexpected { found: found.into(), expected: expected.into() })
}

/// The place of the last of `keys` found one after the other in `text` (each as `"key"`), or
/// the whole file when the first is not found.
fn locate(text: &str, source: &str, keys: &[&str]) -> Location {
    let mut from = 0;
    let mut found = None;
    for k in keys {
        let needle = format!("\"{k}\"");
        match text[from..].find(&needle) {
            Some(i) => {
                from += i;
                found = Some(from);
                from += needle.len();
            }
            None => break,
        }
    }
    match found {
        Some(pos) => {
            let line = 1 + text[..pos].matches('\n').count();
            let col = 1 + text[..pos].rsplit('\n').next().map_or(0, |l| l.chars().count());
            Location::new(source, line, col)
        }
        None => Location::file(source),
    }
}

/// Parses a JSON offset table (either layout, told apart by its keys). `dir` is the folder of
/// the file, where an OpenHull table's `principals.json` is looked for.
///
/// **vessel.js** (`structure.hull` of a ship specification, e.g. R/V Gunnerus in
/// `shared/data/gunnerus/gunnerus.json`; layout from vessel.js `source/classes/Hull.js`):
///
/// ```json
/// {"structure": {"hull": {
///   "attributes": {"LOA": 36.25, "BOA": 9.6, "Depth": 6.6},
///   "halfBreadths": {"waterlines": [0, 0.0758, ...], "stations": [0, 0.016, ...],
///                    "table": [[null, 0, 0.0237, ...], ...]}}}}
/// ```
///
/// Normalised: `x = station LOA` (from the aft end of LOA, forward), `z = waterline Depth`
/// (from the baseline), `y = cell BOA / 2`, in metres (converted to the requested units).
/// `table[i][j]` is waterline `i` at station `j`; `null` is a missing offset. Each station
/// becomes one section, keel to deck, labelled with its index. vessel.js gives the hull as one
/// table: its waterlines and stations are the same cells, so there is nothing to cross-check;
/// a non-empty `buttockHeights` is not read (noted).
///
/// **OpenHull** (`offsets_table.json` of the 116 m coastal cargo ship,
/// `shared/data/coastal_cargo_116m/`): an object of stations, each an object of values in
/// millimetres:
///
/// ```json
/// {"2": {"站号": 2.0, "船底线": 0.0, "1000WL": 4236.0, ..., "1000纵剖线": 28.0, ...,
///        "主甲板宽": 8086.0, "主甲边高": 9149.0, ...}}
/// ```
///
/// - `站号`: the station number, 0 at the AP; `x = station spacing`, the spacing being
///   `Lpp / 20` when [`super::ReadOptions::dimensions`] are given, else `station_spacing_m` (or `lpp_m / 20`)
///   of a `principals.json` beside the file;
/// - `NNNNWL`: the half-breadth on the waterline NNNN mm above the baseline;
/// - `NNNN纵剖线`: the height of the buttock NNNN mm off the centreline;
/// - `船底线`: the height of the bottom (keel) line on the centreline;
/// - `主甲板宽`, `主甲边高`: the main-deck edge, half-breadth and height;
/// - `主甲中高` (main deck at the centreline), `船楼甲板宽`, `楼甲边高`, `楼甲中高` (raised
///   deck), `舷墙宽`, `舷墙高` (bulwark): above the hull's side, not read (noted).
///
/// The waterlines, buttocks, keel and deck are the three views of the three-views merge ([`Merged`](crate::Merged)), merged into
/// one section per station with the buttocks checked against the waterlines.
///
/// Errors give the line and column of the JSON text (characters, 1-based) where the parser
/// stopped, or of the key whose value is wrong.
///
/// # Errors
///
/// [`HullError::Input`] for text that is not JSON (at the parser's line and column), a JSON
/// of neither layout (a `hullskin-surface` JSON is named as such), a missing or non-numeric
/// dimension or value, a table whose rows do not match its waterlines and stations, a
/// negative half-breadth, an unknown OpenHull key, and an OpenHull table without a known
/// station spacing; [`HullError::Io`] when a `principals.json` exists but cannot be read.
pub fn parse_json_table(
    text: &str,
    source: &str,
    options: &ReadOptions,
    dir: Option<&Path>,
) -> Result<ReadOutcome, HullError> {
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    let value: Value = serde_json::from_str(text).map_err(|e| {
        let msg = e.to_string();
        let msg = msg.split(" at line ").next().unwrap_or(&msg).to_string();
        unexpected(
            Location::new(source, e.line().max(1), e.column().max(1)),
            format!("invalid JSON: {msg}"),
            "a JSON offset table: a vessel.js ship (structure.hull.halfBreadths) or an OpenHull station table",
        )
    })?;
    if let Some(hull) = value.pointer("/structure/hull").filter(|h| h.get("halfBreadths").is_some()) {
        return vessel_js(hull, text, source, options.units);
    }
    if let Some(map) = value.as_object().filter(|m| !m.is_empty() && m.values().all(|v| v.get("站号").is_some())) {
        return openhull(map, text, source, options, dir);
    }
    let found = if value.get("format").and_then(Value::as_str) == Some("hullskin-surface") {
        "a hullskin surface JSON, not offsets".to_string()
    } else {
        "a JSON of no known offset layout".to_string()
    };
    Err(unexpected(
        Location::file(source),
        found,
        "a vessel.js ship with structure.hull.halfBreadths {waterlines, stations, table}, or an OpenHull \
            table of stations each with a 站号 key",
    ))
}

/// The line of each row of the `"table"` array of `"halfBreadths"`: the line of each `[` one
/// level inside the table's outer array (the rows hold numbers and nulls only).
fn table_row_lines(text: &str) -> Vec<usize> {
    let Some(hb) = text.find("\"halfBreadths\"") else { return Vec::new() };
    let Some(t) = text[hb..].find("\"table\"") else { return Vec::new() };
    let start = hb + t;
    let mut line = 1 + text[..start].matches('\n').count();
    let mut depth = 0usize;
    let mut out = Vec::new();
    for c in text[start..].chars() {
        match c {
            '\n' => line += 1,
            '[' => {
                depth += 1;
                if depth == 2 {
                    out.push(line);
                }
            }
            ']' => {
                if depth <= 1 {
                    break;
                }
                depth -= 1;
            }
            _ => {}
        }
    }
    out
}

fn number(v: Option<&Value>, at: impl FnOnce() -> Location, what: &str) -> Result<f64, HullError> {
    match v.and_then(Value::as_f64) {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(unexpected(
            at(),
            match v {
                None => format!("no {what}"),
                Some(v) => format!("{what} {v}"),
            },
            format!("{what} as a number"),
        )),
    }
}

fn numbers(v: Option<&Value>, at: impl Fn() -> Location, what: &str) -> Result<Vec<f64>, HullError> {
    let Some(arr) = v.and_then(Value::as_array) else {
        return Err(unexpected(at(), format!("no array of {what}"), format!("\"{what}\": [numbers]")));
    };
    arr.iter().map(|x| number(Some(x), &at, what)).collect()
}

fn vessel_js(hull: &Value, text: &str, source: &str, units: Units) -> Result<ReadOutcome, HullError> {
    let attr = hull.get("attributes");
    let at_attr = |k: &str| locate(text, source, &["attributes", k]);
    let loa = number(attr.and_then(|a| a.get("LOA")), || at_attr("LOA"), "LOA")?;
    let boa = number(attr.and_then(|a| a.get("BOA")), || at_attr("BOA"), "BOA")?;
    let depth = number(attr.and_then(|a| a.get("Depth")), || at_attr("Depth"), "Depth")?;
    for (name, v) in [("LOA", loa), ("BOA", boa), ("Depth", depth)] {
        if v <= 0.0 {
            return Err(unexpected(at_attr(name), format!("{name} {v}"), format!("{name} > 0 in metres")));
        }
    }
    let hb = &hull["halfBreadths"];
    let at_hb = |k: &str| locate(text, source, &["halfBreadths", k]);
    let wls = numbers(hb.get("waterlines"), || at_hb("waterlines"), "waterlines")?;
    let sts = numbers(hb.get("stations"), || at_hb("stations"), "stations")?;
    let Some(table) = hb.get("table").and_then(Value::as_array) else {
        return Err(unexpected(at_hb("table"), "no table", "\"table\": one array per waterline"));
    };
    if table.len() != wls.len() {
        return Err(unexpected(
            at_hb("table"),
            format!("{} table rows for {} waterlines", table.len(), wls.len()),
            "one table row per waterline",
        ));
    }
    // Metres in the file; the requested units by division (exact for metres).
    let m = units.metres_per_unit();
    let mut sections: Vec<Section> = sts
        .iter()
        .enumerate()
        .map(|(j, _)| Section { label: j.to_string(), points: Vec::new(), lines: Vec::new(), column: None })
        .collect();
    let row_lines = table_row_lines(text);
    let line_of_row = |i: usize| row_lines.get(i).copied().unwrap_or(0);
    let mut order: Vec<usize> = (0..wls.len()).collect();
    order.sort_by(|&a, &b| wls[a].total_cmp(&wls[b]));
    for &i in &order {
        let row_at = || match line_of_row(i) {
            0 => Location::file(source),
            l => Location::line(source, l),
        };
        let Some(row) = table[i].as_array().filter(|r| r.len() == sts.len()) else {
            return Err(unexpected(
                row_at(),
                format!("table row {i} is not an array of {} cells", sts.len()),
                "one cell (a number or null) per station in each table row",
            ));
        };
        for (j, cell) in row.iter().enumerate() {
            if cell.is_null() {
                continue;
            }
            let v = number(Some(cell), row_at, &format!("the half-breadth of waterline {i} at station {j}"))?;
            if v < 0.0 {
                return Err(HullError::input(row_at(), InputErrorKind::NegativeHalfBreadth { y: v }));
            }
            let p = Vec3::new(sts[j] * loa / m, v * boa / 2.0 / m + 0.0, wls[i] * depth / m);
            sections[j].points.push(p);
            sections[j].lines.push(line_of_row(i));
        }
    }
    let empty: Vec<String> = sections.iter().filter(|s| s.points.is_empty()).map(|s| s.label.clone()).collect();
    sections.retain(|s| !s.points.is_empty());
    let mut notes = Vec::new();
    if !empty.is_empty() {
        notes.push(format!("stations without any half-breadth left out: {}", empty.join(", ")));
    }
    if hull
        .get("buttockHeights")
        .is_some_and(|b| b.as_object().is_some_and(|o| !o.is_empty()) || b.as_array().is_some_and(|a| !a.is_empty()))
    {
        notes.push("buttockHeights not read (the half-breadth table alone gives the sections)".into());
    }
    notes.push(
        "vessel.js gives one table: its waterlines and stations are the same cells, nothing to cross-check".into(),
    );
    let mut out = ReadOutcome::plain(
        Offsets::new(source, units, sections),
        InputFormat::JsonTable,
        format!(
            "vessel.js: x = station x LOA ({loa} m) from the aft end, forward; y = cell x BOA/2 ({boa} m); z \
                = waterline x Depth ({depth} m) from the baseline{}",
            converted("metres", units)
        ),
    );
    out.notes = notes;
    Ok(out)
}

/// `"; metres converted to feet"` when the file's unit (`from`, plural) is not `units`, else
/// nothing.
fn converted(from: &str, units: Units) -> String {
    if units.plural_name() == from {
        String::new()
    } else {
        format!("; {from} converted to {}", units.plural_name())
    }
}

/// The station spacing of an OpenHull table, in metres, and where it came from.
fn openhull_spacing(options: &ReadOptions, dir: Option<&Path>, source: &str) -> Result<(f64, String), HullError> {
    if let Some(d) = options.dimensions {
        let lpp_m = d.lpp * options.units.metres_per_unit();
        return Ok((lpp_m / OPENHULL_STATIONS, format!("Lpp {} {} given / 20", d.lpp, options.units)));
    }
    let path = dir.map(|d| d.join("principals.json"));
    let Some(path) = path.filter(|p| p.is_file()) else {
        return Err(unexpected(
            Location::file(source),
            "an OpenHull table without a station spacing",
            "a principals.json beside it with station_spacing_m or lpp_m, or the Lpp given (hullskin --lpp)",
        ));
    };
    crate::limits::check_file_size(&path, crate::limits::MAX_OFFSETS_FILE_BYTES, "a principals.json")?;
    let bytes = std::fs::read(&path).map_err(|error| HullError::Io { path: path.clone(), error })?;
    let psource = path.display().to_string();
    let text = super::decode(&bytes, &psource)?;
    let v: Value = serde_json::from_str(text).map_err(|e| {
        unexpected(
            Location::new(&psource, e.line().max(1), e.column().max(1)),
            format!("invalid JSON: {e}"),
            "the ship's principal particulars",
        )
    })?;
    let positive = |k: &str| v.get(k).and_then(Value::as_f64).filter(|x| x.is_finite() && *x > 0.0);
    if let Some(s) = positive("station_spacing_m") {
        Ok((s, format!("station_spacing_m {s} of {psource}")))
    } else if let Some(l) = positive("lpp_m") {
        Ok((l / OPENHULL_STATIONS, format!("lpp_m {l} of {psource} / 20")))
    } else {
        Err(unexpected(
            Location::file(&psource),
            "no station_spacing_m or lpp_m",
            "a positive station_spacing_m or lpp_m in metres",
        ))
    }
}

fn openhull(
    map: &Map<String, Value>,
    text: &str,
    source: &str,
    options: &ReadOptions,
    dir: Option<&Path>,
) -> Result<ReadOutcome, HullError> {
    let (spacing_m, spacing_from) = openhull_spacing(options, dir, source)?;
    let units = options.units;
    // Millimetres in the file; `mm / (1000 m_per_unit)` is exact for metres and millimetres.
    let per_mm = 1000.0 * units.metres_per_unit();
    let mm = |v: f64| v / per_mm;
    let mut views = ThreeViews {
        source: source.to_string(),
        units,
        stations: Vec::new(),
        waterlines: Vec::new(),
        buttocks: Vec::new(),
        profile: vec![ViewLine::new("船底线 (bottom line)", Vec::new())],
        deck: vec![ViewLine::new("主甲板 (main deck edge)", Vec::new())],
        dense: false,
    };
    let mut not_read = std::collections::BTreeMap::<String, usize>::new();
    for (key, st) in map {
        let at = |k: &str| locate(text, source, &[key, k]);
        let line_of = |k: &str| at(k).line.unwrap_or(0);
        let Some(obj) = st.as_object() else {
            return Err(unexpected(
                locate(text, source, &[key]),
                format!("station \"{key}\" is not an object"),
                "an object of values",
            ));
        };
        let number_at = |k: &str| number(obj.get(k), || at(k), k);
        let station = number_at("站号")?;
        let x = station * spacing_m / units.metres_per_unit();
        views.stations.push(Station {
            label: format!("st{station}"),
            x,
            curve: ViewLine::new(key.clone(), Vec::new()),
        });
        for (k, v) in obj {
            let value = || number(Some(v), || at(k), k);
            if let Some(z) = k.strip_suffix("WL").and_then(|n| n.parse::<f64>().ok()) {
                let y = value()?;
                if y < 0.0 {
                    return Err(HullError::input(at(k), InputErrorKind::NegativeHalfBreadth { y }));
                }
                let i = match views.waterlines.iter().position(|l| l.label == *k) {
                    Some(i) => i,
                    None => {
                        views.waterlines.push(ViewLine::new(k.clone(), Vec::new()));
                        views.waterlines.len() - 1
                    }
                };
                views.waterlines[i].push(Vec3::new(x, mm(y) + 0.0, mm(z)), line_of(k));
            } else if let Some(y) = k.strip_suffix("纵剖线").and_then(|n| n.parse::<f64>().ok()) {
                let z = value()?;
                let i = match views.buttocks.iter().position(|l| l.label == *k) {
                    Some(i) => i,
                    None => {
                        views.buttocks.push(ViewLine::new(k.clone(), Vec::new()));
                        views.buttocks.len() - 1
                    }
                };
                views.buttocks[i].push(Vec3::new(x, mm(y), mm(z)), line_of(k));
            } else {
                match k.as_str() {
                    "站号" => {}
                    "船底线" => views.profile[0].push(Vec3::new(x, 0.0, mm(value()?)), line_of(k)),
                    "主甲板宽" => {
                        let z = number(obj.get("主甲边高"), || at(k), "主甲边高 (main-deck height at side) beside 主甲板宽")?;
                        views.deck[0].push(Vec3::new(x, mm(value()?) + 0.0, mm(z)), line_of(k));
                    }
                    "主甲边高" | "主甲中高" | "船楼甲板宽" | "楼甲边高" | "楼甲中高" | "舷墙宽" | "舷墙高" => {
                        if k != "主甲边高" {
                            *not_read.entry(k.clone()).or_default() += 1;
                        }
                    }
                    _ => {
                        return Err(unexpected(
                            at(k),
                            format!("key \"{k}\""),
                            "OpenHull keys: 站号, NNNNWL, NNNN纵剖线, 船底线, 主甲板宽, 主甲边高, 主甲中高, 船楼甲板宽, 楼甲边高, 楼甲中高, \
                                舷墙宽, 舷墙高",
                        ))
                    }
                }
            }
        }
    }
    views.stations.sort_by(|a, b| a.x.total_cmp(&b.x));
    for l in
        views.waterlines.iter_mut().chain(views.buttocks.iter_mut()).chain(&mut views.profile).chain(&mut views.deck)
    {
        super::long_csv::sort_line_by_x(l);
    }
    let mut notes = vec![format!("station spacing {spacing_m} m from {spacing_from}")];
    if !not_read.is_empty() {
        let keys: Vec<String> = not_read.iter().map(|(k, n)| format!("{k} ({n})")).collect();
        notes.push(format!(
            "not read (centreline deck, raised deck and bulwark, above the hull's side): {}",
            keys.join(", ")
        ));
    }
    let mut merged = views.merge(&MergeOptions { tolerance: options.tolerance });
    // Station 0 is the AP and the stations are twentieths of Lpp.
    let lpp = OPENHULL_STATIONS * spacing_m / units.metres_per_unit();
    merged.offsets.perpendiculars = Perpendiculars::try_new(0.0, lpp).ok();
    Ok(ReadOutcome::merged(
        merged,
        InputFormat::JsonTable,
        format!(
            "OpenHull: x = station x {spacing_m} m from the AP (station 0), forward; y, z from millimetres, z \
                above the baseline; converted to {}",
            units.plural_name()
        ),
        notes,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::read::MainDimensions;

    fn err(text: &str) -> String {
        parse_json_table(text, "t.json", &ReadOptions::default(), None)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_else(|| "no error".into())
    }

    const VESSEL: &str = r#"{"structure": {"hull": {
  "attributes": {"LOA": 10, "BOA": 4, "Depth": 2},
  "halfBreadths": {"waterlines": [0, 0.5, 1], "stations": [0, 0.5, 1],
    "table": [
      [null, 0.5, null],
      [0.25, 1, 0],
      [0.5, 1, 0.25]
    ]}}}}"#;

    #[test]
    fn offset_json_is_told_from_a_surface_json() {
        assert!(is_offset_json(VESSEL) && is_offset_json(OPENHULL));
        assert!(!is_offset_json("{\"format\": \"hullskin-surface\", \"version\": 1}"));
    }

    #[test]
    fn vessel_js_scales_by_loa_boa_and_depth() {
        let o = parse_json_table(VESSEL, "v.json", &ReadOptions::default(), None).expect("valid");
        let s = &o.offsets.sections;
        assert_eq!(s.len(), 3);
        // x = 0.5 x 10, y = cell x 4/2, z = waterline x 2: binary fractions, exact.
        assert_eq!(s[1].points, vec![Vec3::new(5.0, 1.0, 0.0), Vec3::new(5.0, 2.0, 1.0), Vec3::new(5.0, 2.0, 2.0)]);
        assert_eq!(s[0].points.len(), 2, "the null is a missing offset");
        assert_eq!(s[0].lines, vec![6, 7], "each point on its table row's line");
        let mm = ReadOptions { units: Units::Millimetre, ..ReadOptions::default() };
        let o = parse_json_table(VESSEL, "v.json", &mm, None).expect("valid");
        assert_eq!(o.offsets.sections[1].points[0], Vec3::new(5000.0, 1000.0, 0.0));
    }

    const OPENHULL: &str = r#"{
 "0": {"站号": 0.0, "船底线": 0.0, "1000WL": 2000.0, "1000纵剖线": 0.0, "主甲板宽": 2000.0, "主甲边高": 2000.0, "舷墙高": 2500.0},
 "1": {"站号": 1.0, "船底线": 0.0, "1000WL": 2000.0, "1000纵剖线": 1500.0, "主甲板宽": 2000.0, "主甲边高": 2000.0}
}"#;

    #[test]
    fn openhull_stations_merge_waterlines_buttocks_keel_and_deck() {
        let opts = ReadOptions {
            dimensions: Some(MainDimensions { lpp: 100.0, beam: 4.0, draft: 1.0 }),
            ..ReadOptions::default()
        };
        let o = parse_json_table(OPENHULL, "c.json", &opts, None).expect("valid");
        assert_eq!(o.offsets.sections.len(), 2);
        let yz: Vec<(f64, f64)> = o.offsets.sections[0].points.iter().map(|p| (p.y, p.z)).collect();
        // keel (0, 0), buttock (1, 0), waterline (2, 1), deck (2, 2), in metres.
        assert_eq!(yz, vec![(0.0, 0.0), (1.0, 0.0), (2.0, 1.0), (2.0, 2.0)]);
        assert_eq!(o.offsets.sections[1].points[0].x, 5.0, "Lpp / 20");
        // Station 1's buttock at z = 1.5 lies between the waterline (2, 1) and the deck (2, 2):
        // y = 1 is outside [2, 2].
        assert_eq!(o.disagreements.len(), 1);
        assert_eq!(o.disagreements[0].at.to_string(), "c.json:3", "the line of the buttock's key");
        assert!(o.notes.iter().any(|n| n.contains("舷墙高 (1)")), "{:?}", o.notes);
    }

    #[test]
    fn bad_json_is_located() {
        assert_eq!(
            err("{\n \"a\": [1, 2,,]\n}"),
            "t.json:2:13: invalid JSON: expected value (expected a JSON offset table: a vessel.js ship \
             (structure.hull.halfBreadths) or an OpenHull station table)"
        );
        assert!(err("{\"format\": \"hullskin-surface\"}").starts_with("t.json: a hullskin surface JSON, not offsets"));
        assert!(err("{\"x\": 1}").starts_with("t.json: a JSON of no known offset layout"));
        assert!(err(&VESSEL.replace("\"BOA\": 4", "\"BOA\": \"4\""))
            .starts_with("t.json:2:29: BOA \"4\" (expected BOA as a number)"));
        assert!(
            err(&VESSEL.replace("[0.25, 1, 0]", "[0.25, 1]")).starts_with("t.json:6: table row 1 is not an array of 3")
        );
        assert!(
            err(&VESSEL.replace("[0.25, 1, 0]", "[0.25, -1, 0]")).starts_with("t.json:6: half-breadth -1 is negative")
        );
        assert!(err(&VESSEL.replace("\"waterlines\": [0, 0.5, 1]", "\"waterlines\": [0, 0.5]"))
            .contains("3 table rows for 2 waterlines"));
        assert!(err(OPENHULL).starts_with("t.json: an OpenHull table without a station spacing"));
        let opts = ReadOptions {
            dimensions: Some(MainDimensions { lpp: 100.0, beam: 4.0, draft: 1.0 }),
            ..ReadOptions::default()
        };
        let bad = OPENHULL.replace("\"舷墙高\"", "\"chine\"");
        let e = parse_json_table(&bad, "t.json", &opts, None).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.starts_with("t.json:2:97: key \"chine\" (expected OpenHull keys"), "{e}");
    }
}
