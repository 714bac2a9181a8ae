//! IGES 5.3 reader of rational B-spline surfaces (entity 128), the inverse of
//! [`crate::export::write_iges`].
//!
//! The rest of this module's documentation is on [`parse_iges`], where the library's users read it.

use nurbs::Vec3;

use super::cad::{cad_error, output_scale, CadFormat, CadSurface, CadSurfaces, FileUnit, RawSurface, Skipped};
use crate::error::HullError;
use crate::limits;
use crate::units::Units;

/// What an IGES error expects of the records in general.
const RECORD: &str = "80-column IGES records with the section letter S, G, D, P or T in column 73 and the \
                      sequence number in columns 74-80";

/// The ASCII form's records, by section.
struct Sections<'a> {
    /// `(line, columns 1-72, sequence number)` per record, by section S G D P T.
    records: [Vec<(usize, &'a [u8])>; 5],
}

const LETTERS: [u8; 5] = [b'S', b'G', b'D', b'P', b'T'];

/// Reads the entity-128 surfaces of an IGES file (see [`parse_iges`]), converted to `target`, or in
/// the file's unit when `None`.
///
/// The file is read as IGES 5.3 (ANS US PRO/IPO-100-1996) lays it out in chapter 2:
///
/// * **Records** (section 2.2.4): 80 columns, the section letter in column 73 and the sequence
///   number in columns 74-80, counted from 1 in each section; `\r\n` line ends are accepted.
///   Sections come in the order S, G, D, P, T, each at least one record but D and P. The
///   compressed ASCII form (section letter `C`, section 2.3) and the binary form are refused.
/// * **Terminate** (2.2.4.6): one record, `S nnnnnnn G nnnnnnn D nnnnnnn P nnnnnnn`; the counts
///   must match the sections read (a truncated file fails here or earlier, at its place).
/// * **Global** (2.2.4.3): columns 1-72 of the G records, one stream of free-format parameters.
///   Field 1 and field 2 are the parameter and record delimiters as Hollerith constants `1Hc`
///   (defaulted: `,` and `;`); then field 13 the model space scale (real world = model /
///   scale), 14 the units flag and 15 the units name. Flags 1-11 are Table 3's units (1 inch,
///   2 mm, 3 the unit named in field 15, 4 ft, 5 mile, 6 m, 7 km, 8 mil, 9 micron, 10 cm, 11
///   microinch); with flag 3, field 15 must name one of them (`IN`, `INCH`, `MM`, `FT`, `MI`,
///   `M`, `KM`, `MIL`, `UM`, `CM`, `UIN`).
/// * **Directory** (2.2.4.4): two records of ten 8-column fields per entity. Read are the
///   entity type (field 1), the parameter data pointer (2), the transformation matrix pointer
///   (7), the parameter line count (14) and the label (18). The form of a 128 (field 15) only
///   names the shape its parameters give (section 4.24), so it is not read.
/// * **Parameter data** (2.2.4.5): columns 1-64 of the P records, from the entry's first record
///   for its line count, each pointing back to its directory entry in columns 65-72. Free
///   format (2.2.2): integers, reals (with `E` or `D` exponents), Hollerith strings `nHc..c`
///   (which may hold the delimiters), empty fields. The parameters of one entity run over as
///   many records as it needs (the blanks that pad a record are ignored around numbers; a
///   Hollerith string may continue on the next record). The record delimiter ends them.
///
/// **Entity 128** (section 4.24): `128, K1, K2, M1, M2, PROP1..PROP5, S(-M1)..S(N1+M1),
/// T(-M2)..T(N2+M2), W(0,0)..W(K1,K2), X(0,0), Y(0,0), Z(0,0) .. Z(K1,K2), U(0), U(1), V(0), V(1)`
/// with `n_u = K1 + 1` poles of degree `M1` along u (likewise v); weights and points run with
/// the first index fastest (`k = j * n_u + i`), turned into the kernel's u-major order
/// `i * n_v + j`. The weights are read whatever PROP3 (polynomial) says; a PROP3 of 1 with
/// unequal weights is noted. A parameter range `[U(0), U(1)] x [V(0), V(1)]` narrower than the
/// knots' domain is noted, the whole surface returned.
///
/// **Entity 124** (section 4.21), the transformation matrix `R11 R12 R13 T1 R21 .. T3`, when
/// a 128's directory entry points to one: every control point becomes `R p + T` (exact for a
/// NURBS: the map is affine and the weights stay), a 124 pointing to another 124 applied
/// first (3.2.2), chains checked for cycles.
///
/// **Entities 144 and 143** (trimmed and bounded surfaces, 4.34 and 4.32): their base surface,
/// when it is a 128, is returned whole, with a note that the trimming was ignored. Every other
/// entity is counted in one note by type.
///
/// # Errors
/// [`crate::InputErrorKind::Cad`] at the record and parameter that break the format, or the
/// entity whose surface the kernel refuses; [`HullError::Limit`] for more control points than
/// [`limits::MAX_CONTROL_POINTS`].
pub fn parse_iges(bytes: &[u8], source: &str, target: Option<Units>) -> Result<CadSurfaces, HullError> {
    let sections = split_sections(bytes, source)?;
    let [_, g, d, p, _] = &sections.records;
    let global = parse_global(g, source)?;
    let mut notes = Vec::new();
    let (unit_scale, units) = output_scale(&global.unit, target, &mut notes);
    if global.scale != 1.0 {
        notes.push(format!("model space scale {} (global field 13): coordinates divided by it", global.scale));
    }
    let scale = unit_scale / global.scale;
    let file = IgesFile { source, d, p, delims: global.delims };
    let entries = file.directory()?;

    let mut surfaces = Vec::new();
    let mut skipped = Skipped::default();
    let mut trimmed_bases = Vec::new();
    for (k, e) in entries.iter().enumerate() {
        match e.kind {
            128 => {
                let raw = file.surface_128(e, &mut notes)?;
                let raw = file.transformed(raw, e, &entries)?;
                let name = format!("{}{}", e.name(), e.label_text());
                let surface = raw.build(scale, source, e.line, &e.name())?;
                surfaces.push(CadSurface { surface, name });
            }
            // Applied to the surfaces (and matrices) that point to it; a free-standing one is counted.
            124 if entries.iter().any(|o| o.transform == 2 * k + 1) => {}
            143 | 144 => {
                let base = file.base_of(e)?;
                match file.entry(base, &entries, e, "the base surface pointer")? {
                    b if b.kind == 128 => trimmed_bases.push(format!(
                        "{} ({}): its base surface, {}, is returned whole (trimming ignored)",
                        e.name(),
                        entity_name(e.kind),
                        b.name()
                    )),
                    _ => skipped.add(e.kind.to_string()),
                }
            }
            kind => skipped.add(kind.to_string()),
        }
    }
    notes.extend(trimmed_bases);
    let kind = |k: &str| k.parse().map(entity_name).unwrap_or("unknown");
    if let Some(n) = skipped.note(
        |n, k| format!("{n} {} of type {k} ({})", if n == 1 { "entity" } else { "entities" }, kind(k)),
        |n, k| format!("{n} of type {k} ({})", kind(k)),
    ) {
        notes.push(n);
    }
    Ok(CadSurfaces { format: CadFormat::Iges, surfaces, units, notes })
}

/// Splits the file into its sections, checking letters, order, sequence numbers and the
/// terminate record's counts.
fn split_sections<'a>(bytes: &'a [u8], source: &str) -> Result<Sections<'a>, HullError> {
    let mut records: [Vec<(usize, &[u8])>; 5] = Default::default();
    let mut current = 0;
    let mut lines = bytes.split(|&b| b == b'\n').enumerate().peekable();
    while let Some((k, raw)) = lines.next() {
        let line = k + 1;
        let rec = raw.strip_suffix(b"\r").unwrap_or(raw);
        if rec.is_empty() && lines.peek().is_none_or(|(_, r)| r.is_empty()) {
            continue; // the newline after the last record
        }
        let err = |found: String| cad_error(source, Some(line), "record", found, RECORD);
        if rec.len() < 73 {
            if lines.peek().is_none_or(|(_, r)| r.trim_ascii().is_empty()) {
                return Err(cad_error(
                    source,
                    Some(line),
                    "record",
                    format!("the last record has {} columns", rec.len()),
                    "80-column records up to the terminate (T) record: is the file truncated?",
                ));
            }
            return Err(err(format!("a record of {} columns", rec.len())));
        }
        let letter = rec[72];
        let Some(section) = LETTERS.iter().position(|&l| l == letter) else {
            if letter == b'C' {
                return Err(cad_error(
                    source,
                    Some(line),
                    "record",
                    "the compressed ASCII form (section C)".into(),
                    "the fixed 80-column ASCII form of IGES (S, G, D, P, T sections)",
                ));
            }
            return Err(err(format!("section letter {} in column 73", shown_byte(letter))));
        };
        if section < current {
            let (was, now) = (LETTERS[current] as char, letter as char);
            return Err(err(format!("a {now} record after the {was} section")));
        }
        current = section;
        let seq = std::str::from_utf8(&rec[73..]).ok().and_then(|s| s.trim().parse::<usize>().ok());
        let want = records[section].len() + 1;
        if seq != Some(want) {
            let got = String::from_utf8_lossy(&rec[73..]).trim().to_string();
            return Err(err(format!("sequence number \"{got}\" in columns 74-80 where {want} comes next")));
        }
        records[section].push((line, &rec[..72]));
        if section == 4 && lines.peek().is_some_and(|(_, r)| !r.trim_ascii().is_empty()) {
            return Err(cad_error(
                source,
                Some(line + 1),
                "record",
                "a record after the terminate (T) record".into(),
                "the T record last",
            ));
        }
    }
    let last_line = records.iter().flatten().map(|r| r.0).max().unwrap_or(1);
    for (section, name) in [(0, "start (S)"), (1, "global (G)"), (4, "terminate (T)")] {
        if records[section].is_empty() {
            return Err(cad_error(
                source,
                Some(last_line),
                "file",
                format!("no {name} section (the file ends at line {last_line})"),
                "the sections S, G, D, P, T of an IGES file: is it truncated?",
            ));
        }
    }
    let (t_line, t) = records[4][0];
    for (k, letter) in LETTERS[..4].iter().enumerate() {
        let field = &t[8 * k..8 * k + 8];
        let count = std::str::from_utf8(&field[1..]).ok().and_then(|s| s.trim().parse::<usize>().ok());
        if field[0] != *letter || count != Some(records[k].len()) {
            return Err(cad_error(
                source,
                Some(t_line),
                "terminate record",
                format!(
                    "columns {}-{} read \"{}\" where the file has {} {} records",
                    8 * k + 1,
                    8 * k + 8,
                    String::from_utf8_lossy(field),
                    records[k].len(),
                    *letter as char
                ),
                "the record count of each section: is the file truncated?",
            ));
        }
    }
    Ok(Sections { records })
}

fn shown_byte(b: u8) -> String {
    if b.is_ascii_graphic() {
        format!("'{}'", b as char)
    } else {
        format!("byte 0x{b:02X}")
    }
}

/// The parameter and record delimiters (global fields 1 and 2).
#[derive(Clone, Copy)]
struct Delims {
    param: u8,
    record: u8,
}

/// Columns of several records as one stream, remembering the line each came from.
struct Stream {
    data: Vec<u8>,
    /// `(offset in data, file line)` of each record's first byte.
    starts: Vec<(usize, usize)>,
}

impl Stream {
    fn new<'a>(records: impl Iterator<Item = (usize, &'a [u8])>) -> Self {
        let mut s = Stream { data: Vec::new(), starts: Vec::new() };
        for (line, cols) in records {
            s.starts.push((s.data.len(), line));
            s.data.extend_from_slice(cols);
        }
        s
    }

    fn line_at(&self, offset: usize) -> usize {
        let k = self.starts.partition_point(|&(o, _)| o <= offset);
        self.starts[k.saturating_sub(1)].1
    }
}

/// One free-format field: its text (a Hollerith string's characters) and line.
struct Field<'a> {
    text: &'a [u8],
    hollerith: bool,
    line: usize,
}

/// The free-format fields of a stream from an offset (IGES 5.3 section 2.2.2), up to the
/// record delimiter.
struct Fields<'a> {
    stream: &'a Stream,
    pos: usize,
    delims: Delims,
    done: bool,
    /// Names the fields' owner in messages: `global section`, `entity 128 at D 3`.
    owner: String,
    source: &'a str,
    /// 1-based number of the next field.
    number: usize,
}

impl<'a> Fields<'a> {
    fn error(&self, line: usize, found: String, expected: &str) -> HullError {
        cad_error(self.source, Some(line), &format!("{}, parameter {}", self.owner, self.number), found, expected)
    }

    /// The next field, `None` after the record delimiter.
    fn next_field(&mut self) -> Result<Option<Field<'a>>, HullError> {
        if self.done {
            return Ok(None);
        }
        let data = &self.stream.data;
        let Delims { param, record } = self.delims;
        let mut i = self.pos;
        while i < data.len() && data[i] == b' ' {
            i += 1;
        }
        let line = self.stream.line_at(i.min(data.len().saturating_sub(1)));
        let digits = data[i..].iter().take_while(|b| b.is_ascii_digit()).count();
        let (text, hollerith, mut end) = if digits > 0 && data.get(i + digits) == Some(&b'H') {
            let n: usize =
                std::str::from_utf8(&data[i..i + digits]).ok().and_then(|s| s.parse().ok()).unwrap_or(usize::MAX);
            let start = i + digits + 1;
            if n > data.len() - start {
                return Err(self.error(
                    line,
                    format!("a Hollerith string of {n} characters with {} left in the section", data.len() - start),
                    "nH followed by n characters",
                ));
            }
            (&data[start..start + n], true, start + n)
        } else {
            let end = data[i..].iter().position(|&b| b == param || b == record).map_or(data.len(), |k| i + k);
            (data[i..end].trim_ascii(), false, end)
        };
        while end < data.len() && data[end] == b' ' {
            end += 1;
        }
        match data.get(end) {
            Some(&b) if b == param => self.pos = end + 1,
            Some(&b) if b == record => self.done = true,
            Some(&b) => {
                return Err(self.error(
                    self.stream.line_at(end),
                    format!("{} after a Hollerith string", shown_byte(b)),
                    "the parameter or record delimiter",
                ))
            }
            None => {
                let at = self.stream.line_at(data.len().saturating_sub(1));
                return Err(self.error(
                    at,
                    format!("the end of the data without the record delimiter {}", shown_byte(record)),
                    "the parameters ended by the record delimiter: is the file truncated?",
                ));
            }
        }
        self.number += 1;
        Ok(Some(Field { text, hollerith, line }))
    }

    /// The next field, which must exist: `what` names it.
    fn field(&mut self, what: &str) -> Result<Field<'a>, HullError> {
        let line = self.stream.line_at(self.pos.min(self.stream.data.len().saturating_sub(1)));
        match self.next_field()? {
            Some(f) => Ok(f),
            None => Err(self.error(line, "the end of the parameters".into(), what)),
        }
    }

    fn number_text(&mut self, what: &str) -> Result<(String, usize), HullError> {
        let f = self.field(what)?;
        if f.hollerith {
            return Err(self.error(f.line, "a Hollerith string".into(), what));
        }
        Ok((String::from_utf8_lossy(f.text).into_owned(), f.line))
    }

    /// An integer; an empty field is `default` when given.
    fn int(&mut self, what: &str, default: Option<i64>) -> Result<i64, HullError> {
        let (text, line) = self.number_text(what)?;
        match (text.parse::<i64>(), default) {
            (Ok(v), _) => Ok(v),
            (Err(_), Some(d)) if text.is_empty() => Ok(d),
            _ => Err(self.num_error(line, &text, what)),
        }
    }

    /// A finite real (`E` or `D` exponent); an empty field is `default` when given.
    fn real(&mut self, what: &str, default: Option<f64>) -> Result<f64, HullError> {
        let (text, line) = self.number_text(what)?;
        if text.is_empty() {
            return default.ok_or_else(|| self.num_error(line, &text, what));
        }
        parse_real(&text).ok_or_else(|| self.num_error(line, &text, what))
    }

    fn num_error(&self, line: usize, text: &str, what: &str) -> HullError {
        let found = if text.is_empty() { "an empty field".to_string() } else { format!("\"{text}\" is not a number") };
        self.refuse(line, found, what)
    }

    /// An error at the field just read (`number` was advanced past it).
    fn refuse(&self, line: usize, found: String, expected: &str) -> HullError {
        let owner = format!("{}, parameter {}", self.owner, self.number.saturating_sub(1));
        cad_error(self.source, Some(line), &owner, found, expected)
    }

    /// A count or pointer: an integer >= 0.
    fn unsigned(&mut self, what: &str) -> Result<(usize, usize), HullError> {
        let line = self.stream.line_at(self.pos.min(self.stream.data.len().saturating_sub(1)));
        let v = self.int(what, None)?;
        usize::try_from(v).map(|u| (u, line)).map_err(|_| self.refuse(line, format!("{v}"), what))
    }
}

/// A finite IGES real: `1.5`, `-2.`, `.5E3`, `1.0D-7`.
fn parse_real(text: &str) -> Option<f64> {
    let t = text.replace(['D', 'd'], "E");
    t.parse::<f64>().ok().filter(|x| x.is_finite())
}

/// What the global section says.
struct Global {
    delims: Delims,
    scale: f64,
    unit: FileUnit,
}

/// IGES 5.3 Table 3: units flag, names, metres per unit.
const UNIT_TABLE: [(i64, &[&str], f64); 10] = [
    (1, &["IN", "INCH"], 0.0254),
    (2, &["MM"], 1e-3),
    (4, &["FT"], 0.3048),
    (5, &["MI"], 1609.344),
    (6, &["M"], 1.0),
    (7, &["KM"], 1e3),
    (8, &["MIL"], 0.0254e-3),
    (9, &["UM"], 1e-6),
    (10, &["CM"], 1e-2),
    (11, &["UIN"], 0.0254e-6),
];

fn parse_global(records: &[(usize, &[u8])], source: &str) -> Result<Global, HullError> {
    let stream = Stream::new(records.iter().copied());
    let data = &stream.data;
    let err = |at: usize, found: String, expected: &str| {
        cad_error(source, Some(stream.line_at(at)), "global section", found, expected)
    };
    // Fields 1 and 2 (section 2.2.4.3.1-2): `1Hc` or empty, each followed by the delimiter.
    let delimiter = |at: usize, default: u8| -> (u8, usize) {
        match data.get(at..at + 3) {
            Some([b'1', b'H', c]) => (*c, at + 3),
            _ => (default, at),
        }
    };
    let (param, mut pos) = delimiter(0, b',');
    if data.get(pos) != Some(&param) {
        return Err(err(pos, "no parameter delimiter after field 1".into(), "1Hc, followed by c (or a default ,)"));
    }
    pos += 1;
    let (record, next) = delimiter(pos, b';');
    if record == param
        || record == b' '
        || param == b' '
        || [param, record].iter().any(|c| c.is_ascii_digit() || *c == b'H')
    {
        return Err(err(
            0,
            format!("delimiters {} and {}", shown_byte(param), shown_byte(record)),
            "two distinct delimiters, neither a blank, a digit nor H",
        ));
    }
    pos = next;
    let delims = Delims { param, record };
    let mut fields =
        Fields { stream: &stream, pos, delims, done: false, owner: "global section".into(), source, number: 3 };
    if data.get(pos) == Some(&record) {
        fields.done = true;
    } else if data.get(pos) != Some(&param) {
        return Err(err(pos, "no delimiter after field 2".into(), "1Hc followed by the parameter delimiter"));
    } else {
        fields.pos += 1;
    }
    let mut scale = 1.0;
    let mut flag = 1;
    let mut name = String::new();
    // Fields 3 to 12 are strings and integers not needed here.
    while let Some(f) = fields.next_field()? {
        let number = fields.number - 1;
        let text = String::from_utf8_lossy(f.text).into_owned();
        match number {
            13 if !text.is_empty() => {
                scale = parse_real(&text)
                    .filter(|s| *s > 0.0)
                    .ok_or_else(|| err_at(source, f.line, 13, format!("\"{text}\""), "a positive model space scale"))?;
            }
            14 if !text.is_empty() => {
                flag = text
                    .parse()
                    .map_err(|_| err_at(source, f.line, 14, format!("\"{text}\""), "a units flag 1 to 11"))?;
            }
            15 => name = text.trim().to_ascii_uppercase(),
            _ => {}
        }
        if number >= 15 {
            break;
        }
    }
    let line = records.last().map_or(1, |r| r.0);
    let unit = match flag {
        3 => UNIT_TABLE
            .iter()
            .find(|(_, names, _)| names.contains(&name.as_str()))
            .map(|&(_, _, metres)| FileUnit { metres, name: name.clone() })
            .ok_or_else(|| {
                err_at(
                    source,
                    line,
                    15,
                    format!("units flag 3 with the units name \"{name}\""),
                    "a unit name of IGES 5.3 Table 3: IN, INCH, MM, FT, MI, M, KM, MIL, UM, CM or UIN",
                )
            })?,
        _ => UNIT_TABLE
            .iter()
            .find(|(f, ..)| *f == flag)
            .map(|&(_, names, metres)| FileUnit { metres, name: names[names.len() - 1].to_string() })
            .ok_or_else(|| {
                err_at(source, line, 14, format!("units flag {flag}"), "a units flag 1 to 11 (IGES 5.3 Table 3)")
            })?,
    };
    Ok(Global { delims, scale, unit })
}

fn err_at(source: &str, line: usize, field: usize, found: String, expected: &str) -> HullError {
    cad_error(source, Some(line), &format!("global section, field {field}"), found, expected)
}

/// One directory entry, the fields read.
struct Entry {
    /// Sequence number of its first D record (odd).
    seq: usize,
    line: usize,
    kind: i64,
    first_p: usize,
    transform: usize,
    p_count: usize,
    label: String,
}

impl Entry {
    fn name(&self) -> String {
        format!("entity {} at D {}", self.kind, self.seq)
    }

    fn label_text(&self) -> String {
        if self.label.is_empty() {
            String::new()
        } else {
            format!(" ({})", self.label)
        }
    }
}

/// The parts of the file the entities are read from.
struct IgesFile<'a> {
    source: &'a str,
    d: &'a [(usize, &'a [u8])],
    p: &'a [(usize, &'a [u8])],
    delims: Delims,
}

impl<'a> IgesFile<'a> {
    fn directory(&self) -> Result<Vec<Entry>, HullError> {
        if self.d.len() % 2 == 1 {
            let line = self.d.last().map_or(1, |r| r.0);
            return Err(cad_error(
                self.source,
                Some(line),
                "directory section",
                format!("{} records", self.d.len()),
                "two D records per entity",
            ));
        }
        let mut out = Vec::with_capacity(self.d.len() / 2);
        for (k, pair) in self.d.chunks(2).enumerate() {
            let seq = 2 * k + 1;
            let field = |rec: usize, n: usize, what: &str| -> Result<i64, HullError> {
                let (line, cols) = pair[rec];
                let text = String::from_utf8_lossy(&cols[8 * (n - 1)..8 * n]).trim().to_string();
                if text.is_empty() {
                    return Ok(0);
                }
                text.parse().map_err(|_| {
                    cad_error(
                        self.source,
                        Some(line),
                        &format!("directory entry D {seq}, field {}", n + 10 * rec),
                        format!("\"{text}\" is not an integer"),
                        what,
                    )
                })
            };
            let kind = field(0, 1, "the entity type number")?;
            let pointer = |v: i64| usize::try_from(v).unwrap_or(0);
            let entry = Entry {
                seq,
                line: pair[0].0,
                kind,
                first_p: pointer(field(0, 2, "the parameter data pointer")?),
                transform: pointer(field(0, 7, "the transformation matrix pointer")?),
                p_count: pointer(field(1, 4, "the parameter line count")?),
                label: String::from_utf8_lossy(&pair[1].1[56..64]).trim().to_string(),
            };
            if field(1, 1, "the entity type number")? != kind {
                return Err(cad_error(
                    self.source,
                    Some(pair[1].0),
                    &format!("directory entry D {seq}, field 11"),
                    format!("entity type {} on the second record, {kind} on the first", field(1, 1, "")?),
                    "the same entity type on both records",
                ));
            }
            out.push(entry);
        }
        Ok(out)
    }

    /// The entry that the pointer `d` of `from` refers to.
    fn entry<'e>(&self, d: usize, entries: &'e [Entry], from: &Entry, what: &str) -> Result<&'e Entry, HullError> {
        if d % 2 == 1 && d / 2 < entries.len() {
            return Ok(&entries[d / 2]);
        }
        Err(cad_error(
            self.source,
            Some(from.line),
            &from.name(),
            format!("{what} {d} is no directory entry"),
            &format!("an odd D sequence number from 1 to {}", 2 * entries.len() - 1),
        ))
    }

    /// The parameter fields of `e`, after its entity type number (checked).
    fn params(&self, e: &Entry) -> Result<(Stream, String), HullError> {
        let name = e.name();
        let start = e.first_p.wrapping_sub(1);
        if e.first_p == 0 || e.p_count == 0 || start >= self.p.len() || self.p.len() - start < e.p_count {
            return Err(cad_error(
                self.source,
                Some(e.line),
                &name,
                format!(
                    "parameter data at P {} for {} records, the P section has {}",
                    e.first_p,
                    e.p_count,
                    self.p.len()
                ),
                "parameter records within the P section: is the file truncated?",
            ));
        }
        let records = &self.p[start..start + e.p_count];
        for &(line, cols) in records {
            let back = String::from_utf8_lossy(&cols[64..72]).trim().parse::<usize>().ok();
            if back != Some(e.seq) {
                return Err(cad_error(
                    self.source,
                    Some(line),
                    &name,
                    format!("a P record pointing to D \"{}\"", String::from_utf8_lossy(&cols[64..72]).trim()),
                    &format!("the records of this entity pointing back to D {} in columns 65-72", e.seq),
                ));
            }
        }
        Ok((Stream::new(records.iter().map(|&(l, c)| (l, &c[..64]))), name))
    }

    fn fields<'s>(&'s self, stream: &'s Stream, name: String, e: &Entry) -> Result<Fields<'s>, HullError> {
        let mut f =
            Fields { stream, pos: 0, delims: self.delims, done: false, owner: name, source: self.source, number: 0 };
        let kind = f.int("the entity type number", None)?;
        if kind != e.kind {
            return Err(f.error(
                e.line,
                format!("entity type {kind} in the parameter data"),
                &format!("{}, as in the directory entry", e.kind),
            ));
        }
        Ok(f)
    }

    /// The parameters of entity 128 (section 4.24) as a surface in the kernel's order.
    fn surface_128(&self, e: &Entry, notes: &mut Vec<String>) -> Result<RawSurface, HullError> {
        let (stream, name) = self.params(e)?;
        let mut f = self.fields(&stream, name.clone(), e)?;
        let count = |f: &mut Fields, what: &str| f.unsigned(what).map(|(v, _)| v);
        let k1 = count(&mut f, "K1, the upper index of the poles along u (>= 1)")?;
        let k2 = count(&mut f, "K2, the upper index of the poles along v (>= 1)")?;
        let m1 = count(&mut f, "M1, the degree along u (1 to 15)")?;
        let m2 = count(&mut f, "M2, the degree along v (1 to 15)")?;
        let (nu, nv) = (k1.saturating_add(1), k2.saturating_add(1));
        limits::control_points(&format!("{}:{}: {name}", self.source, e.line), nu, nv).map_err(HullError::from)?;
        for (m, k, dir) in [(m1, k1, "u"), (m2, k2, "v")] {
            if !(1..=nurbs::MAX_DEGREE).contains(&m) || m > k {
                return Err(cad_error(
                    self.source,
                    Some(stream.line_at(0)),
                    &name,
                    format!("degree {m} along {dir} with {} poles", k + 1),
                    "a degree from 1 to 15 and more poles than the degree",
                ));
            }
        }
        // Each parameter takes at least its delimiter: refuse a count the data cannot hold
        // before allocating for it.
        let needed = (nu + m1 + 1) + (nv + m2 + 1) + 4 * nu * nv + 4 + 5;
        let left = stream.data.len() - f.pos.min(stream.data.len());
        if needed > left {
            return Err(cad_error(
                self.source,
                Some(e.line),
                &name,
                format!("{nu} x {nv} poles of degree {m1} x {m2}, {needed} more parameters, in {left} characters of parameter data"),
                "as many parameters as K1, K2, M1 and M2 call for: is the file truncated or a count wrong?",
            ));
        }
        let mut props = [0i64; 5];
        for (k, p) in props.iter_mut().enumerate() {
            *p = f.int(&format!("PROP{}, a flag 0 or 1", k + 1), Some(0))?;
        }
        let knots = |n: usize, m: usize, letter: char, f: &mut Fields| -> Result<Vec<f64>, HullError> {
            (0..n + m + 1).map(|k| f.real(&format!("the knot {letter}({})", k as i64 - m as i64), None)).collect()
        };
        let ku = knots(nu, m1, 'S', &mut f)?;
        let kv = knots(nv, m2, 'T', &mut f)?;
        let n = nu * nv;
        let mut weights = vec![0.0; n];
        for j in 0..nv {
            for i in 0..nu {
                weights[i * nv + j] = f.real(&format!("the weight W({i},{j})"), None)?;
            }
        }
        let mut points = vec![Vec3::ZERO; n];
        for j in 0..nv {
            for i in 0..nu {
                let mut c = [0.0; 3];
                for (a, axis) in c.iter_mut().zip(['X', 'Y', 'Z']) {
                    *a = f.real(&format!("the coordinate {axis}({i},{j})"), None)?;
                }
                points[i * nv + j] = Vec3::new(c[0], c[1], c[2]);
            }
        }
        let mut range = [0.0; 4];
        for (r, what) in range.iter_mut().zip(["U(0)", "U(1)", "V(0)", "V(1)"]) {
            *r = f.real(&format!("the parameter range {what}"), None)?;
        }
        let domain = [ku[m1], ku[nu], kv[m2], kv[nv]];
        if range[0] > domain[0] || range[1] < domain[1] || range[2] > domain[2] || range[3] < domain[3] {
            notes.push(format!(
                "{name}: parameter range [{}, {}] x [{}, {}] inside the knots' domain [{}, {}] x [{}, {}]: the whole surface is returned",
                range[0], range[1], range[2], range[3], domain[0], domain[1], domain[2], domain[3]
            ));
        }
        if props[2] == 1 && weights.iter().any(|&w| w != weights[0]) {
            notes.push(format!("{name}: PROP3 says polynomial but the weights differ: the weights are used"));
        }
        Ok(RawSurface { degree: (m1, m2), knots: (ku, kv), points, weights })
    }

    /// `raw` with the transformation matrix chain of `e` applied (section 3.2.2).
    fn transformed(&self, mut raw: RawSurface, e: &Entry, entries: &[Entry]) -> Result<RawSurface, HullError> {
        let mut pointer = e.transform;
        let mut from = e;
        let mut seen = Vec::new();
        while pointer != 0 {
            let t = self.entry(pointer, entries, from, "the transformation matrix pointer")?;
            if t.kind != 124 {
                return Err(cad_error(
                    self.source,
                    Some(from.line),
                    &from.name(),
                    format!("a transformation matrix pointer to {}", t.name()),
                    "a pointer to an entity 124",
                ));
            }
            if seen.contains(&t.seq) {
                return Err(cad_error(
                    self.source,
                    Some(t.line),
                    &t.name(),
                    format!("a cycle of transformation matrices through D {}", t.seq),
                    "a chain of 124 entities that ends",
                ));
            }
            seen.push(t.seq);
            let (stream, name) = self.params(t)?;
            let mut f = self.fields(&stream, name, t)?;
            let mut m = [0.0; 12];
            for (k, x) in m.iter_mut().enumerate() {
                let what = if k % 4 == 3 { format!("T{}", k / 4 + 1) } else { format!("R{}{}", k / 4 + 1, k % 4 + 1) };
                *x = f.real(&format!("the matrix element {what}"), None)?;
            }
            for p in &mut raw.points {
                let (x, y, z) = (p.x, p.y, p.z);
                *p = Vec3::new(
                    m[0] * x + m[1] * y + m[2] * z + m[3],
                    m[4] * x + m[5] * y + m[6] * z + m[7],
                    m[8] * x + m[9] * y + m[10] * z + m[11],
                );
            }
            pointer = t.transform;
            from = t;
        }
        Ok(raw)
    }

    /// The base surface pointer of a 144 (PTS, parameter 1) or 143 (SPTR, parameter 2).
    fn base_of(&self, e: &Entry) -> Result<usize, HullError> {
        let (stream, name) = self.params(e)?;
        let mut f = self.fields(&stream, name, e)?;
        if e.kind == 143 {
            f.int("the bounded surface type", Some(0))?;
        }
        f.unsigned("a pointer to the base surface").map(|(v, _)| v)
    }
}

/// The name of an IGES entity type (IGES 5.3 chapter 4), for notes.
pub fn entity_name(kind: i64) -> &'static str {
    match kind {
        0 => "null",
        100 => "circular arc",
        102 => "composite curve",
        104 => "conic arc",
        106 => "copious data",
        108 => "plane",
        110 => "line",
        112 => "parametric spline curve",
        114 => "parametric spline surface",
        116 => "point",
        118 => "ruled surface",
        120 => "surface of revolution",
        122 => "tabulated cylinder",
        123 => "direction",
        124 => "transformation matrix",
        126 => "rational B-spline curve",
        128 => "rational B-spline surface",
        130 => "offset curve",
        140 => "offset surface",
        141 => "boundary",
        142 => "curve on a parametric surface",
        143 => "bounded surface",
        144 => "trimmed surface",
        186 => "manifold solid B-rep object",
        190 => "plane surface",
        192 => "right circular cylindrical surface",
        194 => "right circular conical surface",
        196 => "spherical surface",
        198 => "toroidal surface",
        202 => "angular dimension",
        206 => "diameter dimension",
        212 => "general note",
        214 => "leader",
        216 => "linear dimension",
        308 => "subfigure definition",
        314 => "colour",
        402 => "associativity instance",
        406 => "property",
        408 => "singular subfigure instance",
        410 => "view",
        502 => "vertex",
        504 => "edge",
        508 => "loop",
        510 => "face",
        514 => "shell",
        _ => "unknown",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(text: &str, letter: char, seq: usize) -> String {
        format!("{text:<72}{letter}{seq:>7}\n")
    }

    /// A file of the given G and P texts (one entity 128 whose P data are `p`), laid out by
    /// hand, so the reader is tested apart from the writer.
    fn file(g: &[&str], p: &[&str]) -> String {
        let mut s = record("hand-made", 'S', 1);
        for (k, l) in g.iter().enumerate() {
            s += &record(l, 'G', k + 1);
        }
        s += &record(
            &format!("{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}", 128, 1, 0, 0, 0, 0, 0, 0, "00000000"),
            'D',
            1,
        );
        s += &record(
            &format!("{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}", 128, 0, 0, p.len(), 0, "", "", "PATCH", 0),
            'D',
            2,
        );
        for (k, l) in p.iter().enumerate() {
            s += &format!("{l:<64}{:>8}P{:>7}\n", 1, k + 1);
        }
        s += &record(&format!("S{:>7}G{:>7}D{:>7}P{:>7}", 1, g.len(), 2, p.len()), 'T', 1);
        s
    }

    /// A bilinear patch, corners (0,0,0) (2,0,0) (0,1,0) (2,1,1) in IGES order.
    const BILINEAR: [&str; 3] = [
        "128,1,1,1,1,0,0,1,0,0,0.,0.,1.,1.,0.,0.,1.,1.,1.,1.,1.,1.,",
        "0.,0.,0.,2.,0.,0.,0.,1.,0.,",
        "2.,1.,1.,0.,1.,0.,1.;",
    ];

    #[test]
    fn custom_delimiters_hollerith_and_units_flag_3() {
        // Delimiters / and #, a Hollerith string holding them, flag 3 naming centimetres,
        // the parameters on two records.
        let g = ["1H//1H#/5Ha/b#c/4Hx.ig/1Hs/1Hv/32/38/6/308/15/1Hx/1.0/3/2HCM/1/1.0#"];
        let p = [
            "128/1/1/1/1/0/0/1/0/0/0./0./1./1./0./0./1./1./1./1./1./1./0./",
            "0./0./2./0./0./0./1./0./2./1./1./0./1./0./1.#",
        ];
        let got = parse_iges(file(&g, &p).as_bytes(), "t.igs", None).expect("reads");
        assert_eq!(got.units, Units::Metre, "centimetres are none of Units: metres");
        assert!(got.notes.iter().any(|n| n.contains("CM")), "{:?}", got.notes);
        let s = &got.surfaces[0].surface;
        // 2 cm = 0.02 m; scale 1e-2 applied once: relative rounding only.
        assert!((s.control_point(1, 1) - Vec3::new(0.02, 0.01, 0.01)).norm() < 1e-17);
        assert_eq!(got.surfaces[0].name, "entity 128 at D 1 (PATCH)");
    }

    #[test]
    fn default_delimiters_and_inches() {
        let got = parse_iges(file(&[",,;"], &BILINEAR).as_bytes(), "t.igs", None).expect("reads");
        assert_eq!(got.units, Units::Inch, "flag 1 (inches) by default");
        assert_eq!(got.surfaces[0].surface.control_point(1, 0), Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(got.surfaces[0].surface.control_point(0, 1), Vec3::new(0.0, 1.0, 0.0));
    }

    #[test]
    fn errors_name_line_entity_and_parameter() {
        let mut bad = BILINEAR;
        bad[1] = "0.,0.,0.,2.,x,0.,0.,1.,0.,";
        let e = parse_iges(file(&[",,;"], &bad).as_bytes(), "t.igs", None).expect_err("x");
        assert_eq!(
            e.to_string(),
            "t.igs:6: entity 128 at D 1, parameter 26: \"x\" is not a number (expected the coordinate Y(1,0))"
        );
        let e = parse_iges(b"short\nrecords\n", "t.igs", None).expect_err("short");
        assert!(e.to_string().starts_with("t.igs:1: record: a record of 5 columns"), "{e}");
        let e = parse_iges(b"cut\n", "t.igs", None).expect_err("cut");
        assert!(e.to_string().starts_with("t.igs:1: record: the last record has 3 columns"), "{e}");
        assert!(e.to_string().ends_with("is the file truncated?)"), "{e}");
    }

    #[test]
    fn real_numbers_in_iges_forms() {
        assert_eq!(parse_real("1.0D-3"), Some(1e-3));
        assert_eq!(parse_real("-2."), Some(-2.0));
        assert_eq!(parse_real(".5E1"), Some(5.0));
        assert_eq!(parse_real("1E999"), None);
        assert_eq!(parse_real("1.0.0"), None);
    }
}
