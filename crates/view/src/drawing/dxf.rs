//! DXF R12 (AC1009) ASCII writers: a [`Drawing`] as 2-D paper geometry in millimetres, and
//! 3-D polylines in model coordinates (stations, waterlines, buttocks) for CAD.
//!
//! R12 is the oldest DXF every CAD program still reads, and it needs no handles or object
//! dictionaries: a file is a HEADER, a TABLES section (linetypes, layers, text styles) and
//! the ENTITIES. The group codes follow the AutoCAD Release 12 DXF reference (AutoCAD R12
//! Customization Manual, appendix "Drawing Interchange and File Formats"):
//!
//! | item                 | entity                                                             |
//! |----------------------|--------------------------------------------------------------------|
//! | [`Item::Polyline`]   | `POLYLINE` (70: 1 if closed) + `VERTEX`es + `SEQEND`               |
//! | [`Item::Polygon`]    | `SOLID`s (a fan of triangles/quads) if convex, else closed `POLYLINE` |
//! | [`Item::Marker`]     | `CIRCLE` of the marker's radius                                    |
//! | [`Item::Text`]       | `TEXT`, height = cap height, 72 = 0/1/2 for start/middle/end       |
//! | 3-D curve            | `POLYLINE` with 70 = 8 (3-D polyline), `VERTEX`es with 70 = 32     |
//!
//! R12 has no true colour and no line weights: each layer gets the AutoCAD Colour Index
//! (ACI) nearest to the colour of its first item, an entity whose colour maps to another ACI
//! carries its own (group 62), and dash patterns become linetypes `DASH1`, `DASH2`, ... in the
//! LTYPE table (paper millimetres, `$LTSCALE` 1). Widths are not written: CAD users set
//! line weights by layer. Every real number goes through [`hull::real`]
//! (shortest round trip), so coordinates read back bit for bit.

use std::io::{self, Write};

use nurbs::Vec3;

use super::model::{Anchor, Drawing, Item, Rgb};
use super::svg::layers;
use hull::{real, Units};

/// The longest layer name R12 accepts.
pub const MAX_LAYER_NAME: usize = 31;

/// Write `d` as a DXF R12 file in paper millimetres (`$INSUNITS` 4, `$MEASUREMENT` 1), origin
/// at the sheet's bottom-left corner.
///
/// Layers come in the order they first appear among the items (after layer `0`, which R12
/// requires); names are sanitised with [`layer_name`]. Polylines and polygons with fewer than
/// two points are skipped, as in the SVG writer.
///
/// # Errors
/// Any error of `w`, and [`io::ErrorKind::InvalidData`] if a coordinate or size is NaN or
/// infinite.
pub fn write_dxf<W: Write>(w: &mut W, d: &Drawing) -> io::Result<()> {
    let groups = layers(d);
    let names = unique_layer_names(groups.iter().map(|(l, _)| *l));
    let layer_aci: Vec<u8> = groups.iter().map(|(_, items)| aci(item_color(items[0]))).collect();
    let mut dashes: Vec<Vec<f64>> = Vec::new();
    for item in &d.items {
        if let Item::Polyline { stroke, .. } = item {
            if let Some(dash) = stroke.dash.as_ref().filter(|d| !d.is_empty()) {
                if !dashes.contains(dash) {
                    dashes.push(dash.clone());
                }
            }
        }
    }
    let (lo, hi) = extents(d);

    let mut f = Dxf { w };
    f.section("HEADER")?;
    f.header_common(Units::Millimetre)?;
    f.var_point("$EXTMIN", lo[0], lo[1], 0.0)?;
    f.var_point("$EXTMAX", hi[0], hi[1], 0.0)?;
    f.var_point2("$LIMMIN", 0.0, 0.0)?;
    f.var_point2("$LIMMAX", d.width_mm, d.height_mm)?;
    f.pair(9, "$LTSCALE")?;
    f.real(40, 1.0)?;
    f.end_section()?;

    f.section("TABLES")?;
    f.ltype_table(&dashes)?;
    f.layer_table(names.iter().map(String::as_str).zip(layer_aci.iter().copied()))?;
    f.style_table()?;
    f.end_section()?;

    f.section("ENTITIES")?;
    for (k, (_, items)) in groups.iter().enumerate() {
        let layer = names[k].as_str();
        for item in items {
            let own = aci(item_color(item));
            let color = (own != layer_aci[k]).then_some(own);
            f.item(item, layer, color, &dashes)?;
        }
    }
    f.end_section()?;
    f.pair(0, "EOF")
}

/// Write 3-D polylines in model coordinates, one `POLYLINE` (flag 8) per curve, for CAD:
/// e.g. `("stations", points)` for every station cut. Curves with fewer than two points are
/// skipped. `$INSUNITS` is set from `units` (6 m, 4 mm, 2 ft, 1 in); each layer gets its own
/// colour from a fixed cycle (blue, red, green, magenta, cyan, yellow) in first-appearance
/// order.
///
/// # Errors
/// Any error of `w`; [`io::ErrorKind::InvalidData`] if a coordinate is NaN or infinite.
pub fn write_dxf_3d_lines<W: Write>(w: &mut W, curves: &[(&str, Vec<Vec3>)], units: Units) -> io::Result<()> {
    const CYCLE: [u8; 6] = [5, 1, 3, 6, 4, 2];
    let mut order: Vec<&str> = Vec::new();
    for (layer, _) in curves {
        if !order.contains(layer) {
            order.push(layer);
        }
    }
    let names = unique_layer_names(order.iter().copied());
    let pts = curves.iter().filter(|(_, p)| p.len() >= 2).flat_map(|(_, p)| p.iter());
    let (lo, hi) = pts.fold(
        (
            Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
            -Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
        ),
        |(lo, hi), p| {
            (
                Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z)),
                Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z)),
            )
        },
    );
    let (lo, hi) = if lo.x <= hi.x { (lo, hi) } else { (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.0)) };

    let mut f = Dxf { w };
    f.section("HEADER")?;
    f.header_common(units)?;
    f.var_point("$EXTMIN", lo.x, lo.y, lo.z)?;
    f.var_point("$EXTMAX", hi.x, hi.y, hi.z)?;
    f.end_section()?;
    f.section("TABLES")?;
    f.ltype_table(&[])?;
    f.layer_table(names.iter().map(String::as_str).zip((0..names.len()).map(|k| CYCLE[k % CYCLE.len()])))?;
    f.style_table()?;
    f.end_section()?;
    f.section("ENTITIES")?;
    for (layer, points) in curves {
        if points.len() < 2 {
            continue;
        }
        let k = order.iter().position(|l| l == layer).expect("every layer was collected above");
        f.pair(0, "POLYLINE")?;
        f.pair(8, &names[k])?;
        f.int(66, 1)?;
        f.point(0.0, 0.0, 0.0)?;
        f.int(70, 8)?;
        for p in points {
            f.pair(0, "VERTEX")?;
            f.pair(8, &names[k])?;
            f.point(p.x, p.y, p.z)?;
            f.int(70, 32)?;
        }
        f.pair(0, "SEQEND")?;
        f.pair(8, &names[k])?;
    }
    f.end_section()?;
    f.pair(0, "EOF")
}

/// A layer name R12 accepts: characters other than ASCII letters, digits, `$`, `-` and `_`
/// become `_`, at most [`MAX_LAYER_NAME`] characters, `_` if empty. Layer names are
/// case-insensitive in DXF; the case is kept.
pub fn layer_name(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || matches!(c, '$' | '-' | '_') { c } else { '_' })
        .take(MAX_LAYER_NAME)
        .collect();
    if s.is_empty() {
        "_".into()
    } else {
        s
    }
}

/// Sanitised names, made unique (case-insensitively, and distinct from layer `0`) with a
/// numeric suffix.
fn unique_layer_names<'a>(names: impl Iterator<Item = &'a str>) -> Vec<String> {
    let mut used: Vec<String> = vec!["0".into()];
    let mut out = Vec::new();
    for n in names {
        let base = layer_name(n);
        let mut candidate = base.clone();
        let mut k = 2;
        while used.iter().any(|u| u.eq_ignore_ascii_case(&candidate)) {
            let suffix = format!("_{k}");
            let keep = base.len().min(MAX_LAYER_NAME - suffix.len());
            candidate = format!("{}{suffix}", &base[..keep]);
            k += 1;
        }
        used.push(candidate.clone());
        out.push(candidate);
    }
    out
}

/// The RGB of AutoCAD Colour Index `n` (1-255; 0 and 256, BYBLOCK and BYLAYER, give black).
///
/// 1-9 are the named colours; 10-249 are 24 hues 15° apart (`n / 10 - 1`), each in five
/// values 255, 165, 127, 76, 38 (`(n % 10) / 2`), the odd ones at half saturation; 250-255
/// are greys from 51 to 255 in steps of 40.8. This is the table AutoCAD's colour dialog shows
/// (channel values truncated, as AutoCAD and ezdxf do).
pub fn aci_rgb(n: u8) -> Rgb {
    match n {
        1 => Rgb(255, 0, 0),
        2 => Rgb(255, 255, 0),
        3 => Rgb(0, 255, 0),
        4 => Rgb(0, 255, 255),
        5 => Rgb(0, 0, 255),
        6 => Rgb(255, 0, 255),
        7 => Rgb(255, 255, 255),
        8 => Rgb(128, 128, 128),
        9 => Rgb(192, 192, 192),
        10..=249 => {
            let hue = f64::from(n / 10 - 1) * 15.0;
            let k = n % 10;
            let value = [255.0, 165.0, 127.0, 76.0, 38.0][usize::from(k / 2)];
            // Fully saturated hue (HSV with s = v = 1), channel by channel.
            let channel = |offset: f64| {
                let h = (hue + offset).rem_euclid(360.0);
                let c = if h < 60.0 {
                    1.0
                } else if h < 120.0 {
                    (120.0 - h) / 60.0
                } else if h < 240.0 {
                    0.0
                } else if h < 300.0 {
                    (h - 240.0) / 60.0
                } else {
                    1.0
                };
                let c = if k % 2 == 1 { 0.5 + 0.5 * c } else { c };
                (value * c).floor() as u8
            };
            // Red peaks at hue 0, green at 120, blue at 240.
            Rgb(channel(0.0), channel(-120.0), channel(-240.0))
        }
        250..=255 => {
            let g = (51.0 + 40.8 * f64::from(n - 250)).floor() as u8;
            Rgb(g, g, g)
        }
        _ => Rgb::BLACK,
    }
}

/// The ACI nearest to `c` (Euclidean distance in RGB, lowest index on a tie). Black and white
/// give 7, the foreground colour (drawn black on a white sheet, white on a dark screen), as
/// CAD drawings use it.
pub fn aci(c: Rgb) -> u8 {
    if c == Rgb::BLACK || c == Rgb::WHITE {
        return 7;
    }
    let d2 = |n: u8| {
        let a = aci_rgb(n);
        let d = |x: u8, y: u8| (i32::from(x) - i32::from(y)).pow(2);
        d(a.0, c.0) + d(a.1, c.1) + d(a.2, c.2)
    };
    (1..=255u8).filter(|&n| n != 7).min_by_key(|&n| (d2(n), n)).expect("the range is not empty")
}

fn item_color(item: &Item) -> Rgb {
    match item {
        Item::Polyline { stroke, .. } => stroke.color,
        Item::Polygon { fill, .. } | Item::Marker { fill, .. } => *fill,
        Item::Text { color, .. } => *color,
    }
}

/// Bounding box of every drawn point (markers with their radius, texts by their anchor); the
/// whole sheet when there is nothing.
fn extents(d: &Drawing) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let mut add = |p: [f64; 2], r: f64| {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k] - r);
            hi[k] = hi[k].max(p[k] + r);
        }
    };
    for item in &d.items {
        match item {
            Item::Polyline { points, .. } | Item::Polygon { points, .. } if points.len() >= 2 => {
                points.iter().for_each(|&p| add(p, 0.0))
            }
            Item::Marker { at, size_mm, .. } => add(*at, 0.5 * size_mm),
            Item::Text { at, .. } => add(*at, 0.0),
            _ => {}
        }
    }
    if lo[0] <= hi[0] {
        (lo, hi)
    } else {
        ([0.0, 0.0], [d.width_mm, d.height_mm])
    }
}

/// True if the polygon turns one way only (collinear vertices allowed) and is not degenerate.
fn is_convex(p: &[[f64; 2]]) -> bool {
    let n = p.len();
    let mut sign = 0.0;
    for i in 0..n {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        if cross != 0.0 {
            if sign != 0.0 && cross.signum() != sign {
                return false;
            }
            sign = cross.signum();
        }
    }
    sign != 0.0
}

/// The Windows-1252 bytes 0x80-0x9F and the characters they stand for (0x81, 0x8D, 0x8F,
/// 0x90 and 0x9D are unassigned); 0xA0-0xFF are Latin-1, the same code points as Unicode.
const CP1252_HIGH: [(u8, char); 27] = [
    (0x80, '\u{20AC}'),
    (0x82, '\u{201A}'),
    (0x83, '\u{0192}'),
    (0x84, '\u{201E}'),
    (0x85, '\u{2026}'),
    (0x86, '\u{2020}'),
    (0x87, '\u{2021}'),
    (0x88, '\u{02C6}'),
    (0x89, '\u{2030}'),
    (0x8A, '\u{0160}'),
    (0x8B, '\u{2039}'),
    (0x8C, '\u{0152}'),
    (0x8E, '\u{017D}'),
    (0x91, '\u{2018}'),
    (0x92, '\u{2019}'),
    (0x93, '\u{201C}'),
    (0x94, '\u{201D}'),
    (0x95, '\u{2022}'),
    (0x96, '\u{2013}'),
    (0x97, '\u{2014}'),
    (0x98, '\u{02DC}'),
    (0x99, '\u{2122}'),
    (0x9A, '\u{0161}'),
    (0x9B, '\u{203A}'),
    (0x9C, '\u{0153}'),
    (0x9E, '\u{017E}'),
    (0x9F, '\u{0178}'),
];

/// Text as R12 holds it: one line in the file's code page (`$DWGCODEPAGE` ANSI_1252, i.e.
/// Windows-1252), so `±`, `°`, `é`, `–` are single bytes every reader decodes; characters
/// outside that code page as AutoCAD's `\U+XXXX` escapes (beyond the Basic Multilingual
/// Plane as `?`); control characters as spaces.
fn dxf_text(s: &str) -> Vec<u8> {
    let mut out = Vec::with_capacity(s.len());
    for c in s.chars() {
        let code = c as u32;
        if c.is_control() {
            out.push(b' ');
        } else if code < 0x80 || (0xA0..=0xFF).contains(&code) {
            out.push(code as u8);
        } else if let Some(&(b, _)) = CP1252_HIGH.iter().find(|(_, ch)| *ch == c) {
            out.push(b);
        } else if code <= 0xFFFF {
            out.extend_from_slice(format!("\\U+{code:04X}").as_bytes());
        } else {
            out.push(b'?');
        }
    }
    out
}

/// Group-code/value writer.
struct Dxf<'a, W: Write> {
    w: &'a mut W,
}

impl<W: Write> Dxf<'_, W> {
    fn pair(&mut self, code: u16, value: &str) -> io::Result<()> {
        self.pair_bytes(code, value.as_bytes())
    }

    fn pair_bytes(&mut self, code: u16, value: &[u8]) -> io::Result<()> {
        writeln!(self.w, "{code:>3}")?;
        self.w.write_all(value)?;
        self.w.write_all(b"\n")
    }

    fn int(&mut self, code: u16, value: i64) -> io::Result<()> {
        write!(self.w, "{code:>3}\n{value:>6}\n")
    }

    fn real(&mut self, code: u16, value: f64) -> io::Result<()> {
        let v = real(value)?;
        self.pair(code, &v)
    }

    /// Groups 10/20/30.
    fn point(&mut self, x: f64, y: f64, z: f64) -> io::Result<()> {
        self.real(10, x)?;
        self.real(20, y)?;
        self.real(30, z)
    }

    fn section(&mut self, name: &str) -> io::Result<()> {
        self.pair(0, "SECTION")?;
        self.pair(2, name)
    }

    fn end_section(&mut self) -> io::Result<()> {
        self.pair(0, "ENDSEC")
    }

    fn var_point(&mut self, name: &str, x: f64, y: f64, z: f64) -> io::Result<()> {
        self.pair(9, name)?;
        self.point(x, y, z)
    }

    fn var_point2(&mut self, name: &str, x: f64, y: f64) -> io::Result<()> {
        self.pair(9, name)?;
        self.real(10, x)?;
        self.real(20, y)
    }

    /// `$ACADVER`, the code page, and the units: `$INSUNITS` (the drawing unit, an AutoCAD
    /// 2000 variable that R12 readers skip and current readers use) and `$MEASUREMENT`
    /// (1 metric, 0 imperial).
    fn header_common(&mut self, units: Units) -> io::Result<()> {
        self.pair(9, "$ACADVER")?;
        self.pair(1, "AC1009")?;
        self.pair(9, "$DWGCODEPAGE")?;
        self.pair(3, "ANSI_1252")?;
        self.pair(9, "$INSBASE")?;
        self.point(0.0, 0.0, 0.0)?;
        self.pair(9, "$INSUNITS")?;
        let (insunits, metric) = match units {
            Units::Inch => (1, 0),
            Units::Foot => (2, 0),
            Units::Millimetre => (4, 1),
            Units::Metre => (6, 1),
        };
        self.int(70, insunits)?;
        self.pair(9, "$MEASUREMENT")?;
        self.int(70, metric)
    }

    fn table(&mut self, name: &str, count: usize) -> io::Result<()> {
        self.pair(0, "TABLE")?;
        self.pair(2, name)?;
        self.int(70, count as i64)
    }

    fn ltype_table(&mut self, dashes: &[Vec<f64>]) -> io::Result<()> {
        self.table("LTYPE", 1 + dashes.len())?;
        self.pair(0, "LTYPE")?;
        self.pair(2, "CONTINUOUS")?;
        self.int(70, 0)?;
        self.pair(3, "Solid line")?;
        self.int(72, 65)?;
        self.int(73, 0)?;
        self.real(40, 0.0)?;
        for (k, dash) in dashes.iter().enumerate() {
            // An odd-length SVG dash array repeats to even length; DXF needs the pairs spelled out.
            let elements: Vec<f64> = if dash.len() % 2 == 1 { dash.repeat(2) } else { dash.clone() };
            self.pair(0, "LTYPE")?;
            self.pair(2, &format!("DASH{}", k + 1))?;
            self.int(70, 0)?;
            let text: Vec<String> = elements.iter().map(|x| format!("{x}")).collect();
            self.pair(3, &format!("Dashes {} mm", text.join(" ")))?;
            self.int(72, 65)?;
            self.int(73, elements.len() as i64)?;
            self.real(40, elements.iter().map(|x| x.abs()).sum())?;
            for (i, x) in elements.iter().enumerate() {
                // Dashes positive, gaps negative.
                self.real(49, if i % 2 == 0 { x.abs() } else { -x.abs() })?;
            }
        }
        self.pair(0, "ENDTAB")
    }

    fn layer_table<'b>(&mut self, layers: impl ExactSizeIterator<Item = (&'b str, u8)>) -> io::Result<()> {
        self.table("LAYER", 1 + layers.len())?;
        for (name, color) in std::iter::once(("0", 7)).chain(layers) {
            self.pair(0, "LAYER")?;
            self.pair(2, name)?;
            self.int(70, 0)?;
            self.int(62, i64::from(color))?;
            self.pair(6, "CONTINUOUS")?;
        }
        self.pair(0, "ENDTAB")
    }

    fn style_table(&mut self) -> io::Result<()> {
        self.table("STYLE", 1)?;
        self.pair(0, "STYLE")?;
        self.pair(2, "STANDARD")?;
        self.int(70, 0)?;
        self.real(40, 0.0)?;
        self.real(41, 1.0)?;
        self.real(50, 0.0)?;
        self.int(71, 0)?;
        self.real(42, 2.5)?;
        self.pair(3, "txt")?;
        self.pair(4, "")?;
        self.pair(0, "ENDTAB")
    }

    fn entity(&mut self, kind: &str, layer: &str, color: Option<u8>) -> io::Result<()> {
        self.pair(0, kind)?;
        self.pair(8, layer)?;
        if let Some(c) = color {
            self.int(62, i64::from(c))?;
        }
        Ok(())
    }

    fn polyline2(
        &mut self,
        points: &[[f64; 2]],
        closed: bool,
        layer: &str,
        color: Option<u8>,
        ltype: Option<&str>,
    ) -> io::Result<()> {
        self.entity("POLYLINE", layer, color)?;
        if let Some(lt) = ltype {
            self.pair(6, lt)?;
        }
        self.int(66, 1)?;
        self.point(0.0, 0.0, 0.0)?;
        self.int(70, i64::from(closed))?;
        for p in points {
            self.entity("VERTEX", layer, color)?;
            self.point(p[0], p[1], 0.0)?;
        }
        self.entity("SEQEND", layer, color)
    }

    fn item(&mut self, item: &Item, layer: &str, color: Option<u8>, dashes: &[Vec<f64>]) -> io::Result<()> {
        match item {
            Item::Polyline { points, closed, stroke, .. } => {
                if points.len() < 2 {
                    return Ok(());
                }
                let ltype = stroke
                    .dash
                    .as_ref()
                    .and_then(|d| dashes.iter().position(|x| x == d))
                    .map(|k| format!("DASH{}", k + 1));
                self.polyline2(points, *closed, layer, color, ltype.as_deref())
            }
            Item::Polygon { points, .. } => {
                if points.len() < 2 {
                    return Ok(());
                }
                if points.len() >= 3 && is_convex(points) {
                    // A fan of quads (and a last triangle): SOLID corners 1, 2, 3, 4 are
                    // stored in the order 1, 2, 4, 3 (R12 reference, SOLID).
                    let mut i = 1;
                    while i + 1 < points.len() {
                        let (a, b, c) = (points[0], points[i], points[i + 1]);
                        let d = if i + 2 < points.len() { points[i + 2] } else { c };
                        self.entity("SOLID", layer, color)?;
                        for (k, p) in [a, b, d, c].iter().enumerate() {
                            let k = k as u16;
                            self.real(10 + k, p[0])?;
                            self.real(20 + k, p[1])?;
                            self.real(30 + k, 0.0)?;
                        }
                        i += 2;
                    }
                    Ok(())
                } else {
                    self.polyline2(points, true, layer, color, None)
                }
            }
            Item::Marker { at, size_mm, .. } => {
                self.entity("CIRCLE", layer, color)?;
                self.point(at[0], at[1], 0.0)?;
                self.real(40, 0.5 * size_mm)
            }
            Item::Text { at, text, size_mm, anchor, .. } => {
                self.entity("TEXT", layer, color)?;
                self.point(at[0], at[1], 0.0)?;
                self.real(40, *size_mm)?;
                self.pair_bytes(1, &dxf_text(text))?;
                let justify = match anchor {
                    Anchor::Start => 0,
                    Anchor::Middle => 1,
                    Anchor::End => 2,
                };
                if justify != 0 {
                    self.int(72, justify)?;
                    self.real(11, at[0])?;
                    self.real(21, at[1])?;
                    self.real(31, 0.0)?;
                }
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drawing::model::Stroke;

    /// The (code, value) pairs of a DXF text.
    fn pairs(text: &str) -> Vec<(i32, String)> {
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len() % 2, 0, "odd number of lines");
        lines.chunks(2).map(|c| (c[0].trim().parse().expect("group code"), c[1].trim().to_string())).collect()
    }

    fn dxf(d: &Drawing) -> String {
        let mut out = Vec::new();
        write_dxf(&mut out, d).expect("writes to memory");
        // Text is Windows-1252; the tests look at ASCII content only.
        String::from_utf8_lossy(&out).into_owned()
    }

    #[test]
    fn text_is_windows_1252_with_escapes_beyond() {
        assert_eq!(dxf_text("a±°é"), b"a\xB1\xB0\xE9");
        assert_eq!(dxf_text("1–2 €"), b"1\x962 \x80");
        assert_eq!(dxf_text("Ω\n\u{1F600}"), b"\\U+03A9 ?");
        for (b, c) in CP1252_HIGH {
            assert_eq!(dxf_text(&c.to_string()), [b]);
        }
    }

    #[test]
    fn aci_table_matches_known_entries() {
        // Values from AutoCAD's colour dialog (and ezdxf's DXF_DEFAULT_COLORS).
        assert_eq!(aci_rgb(10), Rgb(255, 0, 0));
        assert_eq!(aci_rgb(11), Rgb(255, 127, 127));
        assert_eq!(aci_rgb(13), Rgb(165, 82, 82));
        assert_eq!(aci_rgb(20), Rgb(255, 63, 0));
        assert_eq!(aci_rgb(21), Rgb(255, 159, 127));
        assert_eq!(aci_rgb(60), Rgb(191, 255, 0));
        assert_eq!(aci_rgb(150), Rgb(0, 127, 255));
        assert_eq!(aci_rgb(245), Rgb(127, 63, 79));
        assert_eq!(aci_rgb(250), Rgb(51, 51, 51));
        assert_eq!(aci_rgb(255), Rgb(255, 255, 255));
    }

    #[test]
    fn nearest_aci_of_each_table_colour_is_itself_or_an_equal_colour() {
        for n in 1..=255u8 {
            let c = aci_rgb(n);
            let m = aci(c);
            if c == Rgb::WHITE || c == Rgb::BLACK {
                assert_eq!(m, 7);
            } else {
                assert_eq!(aci_rgb(m), c, "ACI {n} -> {m}");
                assert!(m <= n);
            }
        }
        assert_eq!(aci(Rgb(250, 5, 5)), 1);
        assert_eq!(aci(Rgb::BLACK), 7);
    }

    #[test]
    fn layer_names_are_sanitised_and_unique() {
        assert_eq!(layer_name("stations"), "stations");
        assert_eq!(layer_name("a b/c"), "a_b_c");
        assert_eq!(layer_name(&"x".repeat(40)).len(), MAX_LAYER_NAME);
        let names = unique_layer_names(["a b", "a_b", "0", "A_B"].into_iter());
        assert_eq!(names, ["a_b", "a_b_2", "0_2", "A_B_3"]);
    }

    #[test]
    fn convexity() {
        assert!(is_convex(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]));
        assert!(!is_convex(&[[0.0, 0.0], [2.0, 0.0], [1.0, 0.5], [2.0, 2.0], [0.0, 2.0]]));
        assert!(!is_convex(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]));
    }

    #[test]
    fn structure_and_exact_numbers() {
        let mut d = Drawing::new(420.0, 297.0, "t");
        d.push(Item::Polyline {
            points: vec![[0.1, 0.2], [100.0 / 3.0, 50.0], [30.0, 60.0]],
            closed: true,
            stroke: Stroke { color: Rgb::BLACK, width_mm: 0.5, dash: Some(vec![3.0, 1.5]) },
            layer: "stations".into(),
        });
        d.push(Item::Marker { at: [10.0, 20.0], size_mm: 2.0, fill: Rgb(255, 0, 0), layer: "stations".into() });
        d.push(Item::Text {
            at: [5.0, 5.0],
            text: "Ø 1".into(),
            size_mm: 2.5,
            anchor: Anchor::End,
            color: Rgb::BLACK,
            layer: "title".into(),
        });
        d.push(Item::Polygon {
            points: vec![[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]],
            fill: Rgb(0, 0, 255),
            layer: "legend".into(),
        });
        let text = dxf(&d);
        let p = pairs(&text);
        assert_eq!(p.first(), Some(&(0, "SECTION".into())));
        assert_eq!(p.last(), Some(&(0, "EOF".into())));
        let at = |code: i32, value: &str| p.iter().position(|x| x.0 == code && x.1 == value);
        let ver = at(9, "$ACADVER").expect("$ACADVER");
        assert_eq!(p[ver + 1], (1, "AC1009".into()));
        // Extents: the polygon's corner (0, 0) and the polyline's vertices x = 100/3, y = 60.
        let ext = at(9, "$EXTMIN").expect("$EXTMIN");
        assert_eq!(&p[ext + 1..ext + 3], &[(10, "0.0".into()), (20, "0.0".into())]);
        let ext = at(9, "$EXTMAX").expect("$EXTMAX");
        assert_eq!(&p[ext + 1..ext + 3], &[(10, real(100.0 / 3.0).expect("finite")), (20, "60.0".into())]);
        // Every number reads back exactly: 100/3 is written with all its digits.
        assert!(p.iter().any(|x| x.0 == 10 && x.1.parse::<f64>().expect("real") == 100.0 / 3.0));
        // One POLYLINE with three VERTEXes and a SEQEND, closed, dashed; a CIRCLE of radius 1.
        assert_eq!(p.iter().filter(|x| x.0 == 0 && x.1 == "VERTEX").count(), 3);
        let poly = at(0, "POLYLINE").expect("POLYLINE");
        assert_eq!(p[poly + 1], (8, "stations".into()));
        assert!(p[poly..poly + 10].contains(&(70, "1".into())));
        assert!(p[poly..poly + 10].contains(&(6, "DASH1".into())));
        let circle = at(0, "CIRCLE").expect("CIRCLE");
        assert!(p[circle..circle + 8].contains(&(40, "1.0".into())));
        // The marker is red on a black layer: it carries its own colour.
        assert!(p[circle..circle + 4].contains(&(62, "1".into())));
        let t = at(0, "TEXT").expect("TEXT");
        assert!(p[t..t + 14].contains(&(1, "\u{FFFD} 1".into())), "Ø is the Windows-1252 byte 0xD8");
        assert!(p[t..t + 14].contains(&(72, "2".into())));
        assert_eq!(p.iter().filter(|x| x.0 == 0 && x.1 == "SOLID").count(), 1);
        // Layer table: 0 plus the three layers, in first-appearance order.
        let layers: Vec<&str> =
            p.windows(2).filter(|w| w[0] == (0, "LAYER".into()) && w[1].0 == 2).map(|w| w[1].1.as_str()).collect();
        assert_eq!(layers, ["0", "stations", "title", "legend"]);
    }

    #[test]
    fn three_d_polylines() {
        let curves = vec![
            ("stations", vec![Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 3.0)]),
            ("waterlines", vec![Vec3::new(0.0, 1.0, 2.0)]),
            ("stations", vec![Vec3::new(2.0, 0.5, 0.0), Vec3::new(2.0, 1.5, -1.0), Vec3::new(2.0, 2.0, 3.0)]),
        ];
        let mut out = Vec::new();
        write_dxf_3d_lines(&mut out, &curves, Units::Metre).expect("writes");
        let p = pairs(&String::from_utf8(out).expect("ASCII"));
        assert_eq!(p.iter().filter(|x| x.0 == 0 && x.1 == "POLYLINE").count(), 2);
        assert_eq!(p.iter().filter(|x| x.0 == 0 && x.1 == "VERTEX").count(), 5);
        assert_eq!(p.iter().filter(|x| *x == &(70, "8".into())).count(), 2);
        let ins = p.iter().position(|x| x.1 == "$INSUNITS").expect("$INSUNITS");
        assert_eq!(p[ins + 1], (70, "6".into()));
        let lo = p.iter().position(|x| x.1 == "$EXTMIN").expect("$EXTMIN");
        assert_eq!(&p[lo + 1..lo + 4], &[(10, "1.0".into()), (20, "0.0".into()), (30, "-1.0".into())]);
    }
}
