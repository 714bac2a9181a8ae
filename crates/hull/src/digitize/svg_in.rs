//! SVG reader for drawn body plans: paths, polylines, lines and texts, with their transforms.
//!
//! The rest of this module's documentation is on [`parse_svg`], where the library's users read it.

use std::collections::BTreeMap;

use roxmltree::{Document, Node};
use svgtypes::{Length, LengthUnit, NumberListParser, PathParser, PathSegment, Transform, ViewBox};

use super::geom::{Affine, Segment, P2};
use super::{drawing_error, Curve, Label, Sketch, SketchFormat};
use crate::error::{HullError, Location};

const SVG_NS: &str = "http://www.w3.org/2000/svg";
const INKSCAPE_NS: &str = "http://www.inkscape.org/namespaces/inkscape";

/// Groups (`<g>`, `<a>`, `<switch>`, nested `<svg>`) nested deeper than this are refused: the
/// walk over them recurses, and a hostile file of thousands of nested groups would overflow the
/// stack. Drawing programs nest layers and groups a few levels (Inkscape's layers and sublayers,
/// a CAD export's blocks): 256 is far above any drawing.
pub const MAX_GROUP_DEPTH: usize = 256;

/// Parse an SVG held in `text`; `source` names it in messages.
///
/// # What is read
///
/// Coordinates are the root's user coordinates (the `viewBox` system, y down): every element's
/// geometry is mapped through the `transform`s of its ancestors and its own (SVG 1.1 section
/// 7.5: the child's matrix is applied first). Read:
///
/// - `<path d>` with every command of SVG 1.1 section 8.3 (`M L H V C S Q T A Z` and their
///   relative forms; `S` and `T` reflect the previous control point; arcs by the endpoint to
///   centre conversion of appendix F.6.5, kept exact rather than approximated); each subpath
///   is one [`Curve`];
/// - `<polyline>`, `<polygon>` (closed), `<line>`;
/// - `<text>` (with its `<tspan>`s) as a [`Label`] at its first `x`, `y`;
/// - a curve's name: its `<title>` child, else its `id` unless that is an editor's automatic
///   one (`path123`, `g7`);
/// - a curve's layer: the innermost Inkscape layer around it (`inkscape:groupmode="layer"`,
///   named by `inkscape:label`), else the innermost `<g>` with an `inkscape:label` or a
///   non-automatic `id`.
///
/// Skipped, and listed in [`Sketch::notes`]: `<rect>`, `<circle>`, `<ellipse>`, `<use>`,
/// `<image>`, and anything under `display="none"`; `<defs>`, `<symbol>`, `<clipPath>`,
/// `<mask>`, `<pattern>`, `<marker>` and non-SVG elements silently.
///
/// [`Sketch::unit_mm`]: the root's `width` in an absolute unit over the `viewBox` width; one
/// CSS pixel (25.4 / 96 mm) without a `viewBox`; unknown when `width` is missing or relative.
///
/// # Errors
/// [`HullError::Input`] with [`crate::InputErrorKind::Drawing`] at the line and column of:
/// malformed XML, a root that is not `<svg>`, a `transform`, path data, `points` list or
/// coordinate that does not parse, or a non-finite number. (In a build without the cargo
/// feature `svg`, on by default, [`HullError::FeatureDisabled`].)
pub fn parse_svg(text: &str, source: &str) -> Result<Sketch, HullError> {
    let opts = roxmltree::ParsingOptions { allow_dtd: true, ..roxmltree::ParsingOptions::default() };
    let doc = Document::parse_with_options(text, opts).map_err(|e| {
        let p = e.pos();
        let msg = e.to_string();
        let msg = msg.strip_suffix(&format!(" at {}:{}", p.row, p.col)).unwrap_or(&msg).to_string();
        drawing_error(
            Location::new(source, p.row as usize, p.col as usize),
            format!("malformed XML: {msg}"),
            "an SVG file",
        )
    })?;
    let root = doc.root_element();
    let mut r = Reader {
        doc: &doc,
        source,
        sketch: Sketch {
            source: source.to_string(),
            format: SketchFormat::Svg,
            unit_mm: None,
            curves: Vec::new(),
            labels: Vec::new(),
            notes: Vec::new(),
        },
        skipped: BTreeMap::new(),
    };
    if root.tag_name().name() != "svg" {
        return Err(drawing_error(
            r.loc(root),
            format!("root element <{}>", root.tag_name().name()),
            "an SVG document: root element <svg>",
        ));
    }
    r.sketch.unit_mm = unit_mm(root);
    r.walk(root, Affine::IDENTITY, &Layer { name: String::new(), inkscape: false })?;
    for (kind, (count, loc)) in std::mem::take(&mut r.skipped) {
        r.sketch.notes.push(format!("{kind} ({count}, first at {loc}) skipped: not a path, polyline or line"));
    }
    Ok(r.sketch)
}

/// Millimetres per user unit (see [`parse_svg`]).
fn unit_mm(root: Node<'_, '_>) -> Option<f64> {
    let vb = root.attribute("viewBox").and_then(|v| v.parse::<ViewBox>().ok()).filter(|v| v.w > 0.0);
    let width = root.attribute("width").and_then(|v| v.parse::<Length>().ok()).and_then(length_mm);
    match (vb, width) {
        (Some(vb), Some(w)) => Some(w / vb.w),
        (Some(_), None) => None,
        (None, _) => Some(25.4 / 96.0),
    }
}

/// An absolute length in millimetres (CSS units: 1 in = 25.4 mm = 96 px = 72 pt = 6 pc).
fn length_mm(l: Length) -> Option<f64> {
    let k = match l.unit {
        LengthUnit::Mm => 1.0,
        LengthUnit::Cm => 10.0,
        LengthUnit::In => 25.4,
        LengthUnit::Pt => 25.4 / 72.0,
        LengthUnit::Pc => 25.4 / 6.0,
        LengthUnit::Px | LengthUnit::None => 25.4 / 96.0,
        _ => return None,
    };
    Some(l.number * k).filter(|v| v.is_finite() && *v > 0.0)
}

/// The layer a curve is on, and whether it comes from an Inkscape layer (which inner plain
/// groups do not override).
#[derive(Clone, Debug)]
struct Layer {
    name: String,
    inkscape: bool,
}

/// True for ids that editors make up (`path123`, `g7`, `layer1`, `text12-3`).
fn automatic_id(id: &str) -> bool {
    let stem = id.trim_end_matches(|c: char| c.is_ascii_digit() || c == '-');
    stem.len() < id.len()
        && matches!(
            stem,
            "g" | "path" | "layer" | "polyline" | "polygon" | "line" | "text" | "tspan" | "rect" | "svg" | "use" | "a"
        )
}

struct Reader<'d, 'i, 's> {
    doc: &'d Document<'i>,
    source: &'s str,
    sketch: Sketch,
    skipped: BTreeMap<String, (usize, Location)>,
}

impl Reader<'_, '_, '_> {
    fn loc(&self, n: Node<'_, '_>) -> Location {
        let p = self.doc.text_pos_at(n.range().start);
        Location::new(self.source, p.row as usize, p.col as usize)
    }

    /// The place of attribute `name`'s value of `n`.
    fn attr_loc(&self, n: Node<'_, '_>, name: &str) -> Location {
        match n.attributes().find(|a| a.name() == name && a.namespace().is_none()) {
            Some(a) => {
                let p = self.doc.text_pos_at(a.range_value().start);
                Location::new(self.source, p.row as usize, p.col as usize)
            }
            None => self.loc(n),
        }
    }

    fn skip(&mut self, kind: String, at: Location) {
        self.skipped.entry(kind).or_insert((0, at)).0 += 1;
    }

    fn walk(&mut self, node: Node<'_, '_>, ctm: Affine, layer: &Layer) -> Result<(), HullError> {
        for child in node.children().filter(Node::is_element) {
            if child.tag_name().namespace().is_some_and(|ns| ns != SVG_NS) {
                continue;
            }
            let name = child.tag_name().name();
            let hidden = child.attribute("display") == Some("none")
                || child.attribute("style").is_some_and(|s| s.replace(' ', "").contains("display:none"));
            if hidden {
                self.skip(format!("hidden <{name}>"), self.loc(child));
                continue;
            }
            if matches!(name, "g" | "a" | "switch" | "svg") && child.ancestors().nth(MAX_GROUP_DEPTH + 2).is_some() {
                return Err(drawing_error(
                    self.loc(child),
                    format!("<{name}> nested more than {MAX_GROUP_DEPTH} groups deep"),
                    &format!("groups nested at most {MAX_GROUP_DEPTH} deep"),
                ));
            }
            let m = ctm.compose(&self.transform(child)?);
            match name {
                "g" | "a" | "switch" => {
                    let inner = self.group_layer(child, layer);
                    self.walk(child, m, &inner)?;
                }
                "svg" => {
                    let x = self.coord(child, "x")?;
                    let y = self.coord(child, "y")?;
                    self.walk(child, m.compose(&Affine { e: x, f: y, ..Affine::IDENTITY }), layer)?;
                }
                "path" => self.path(child, &m, layer)?,
                "polyline" | "polygon" => self.polyline(child, &m, layer)?,
                "line" => {
                    let a = [self.coord(child, "x1")?, self.coord(child, "y1")?];
                    let b = [self.coord(child, "x2")?, self.coord(child, "y2")?];
                    self.push(child, vec![Segment::Line(a, b).transformed(&m)], false, layer);
                }
                "text" => self.text(child, &m, layer)?,
                "rect" | "circle" | "ellipse" | "use" | "image" => self.skip(format!("<{name}>"), self.loc(child)),
                _ => {}
            }
        }
        Ok(())
    }

    fn group_layer(&self, g: Node<'_, '_>, outer: &Layer) -> Layer {
        let label = g.attribute((INKSCAPE_NS, "label"));
        let id = g.attribute("id").filter(|id| !automatic_id(id));
        if g.attribute((INKSCAPE_NS, "groupmode")) == Some("layer") {
            if let Some(n) = label.or(g.attribute("id")) {
                return Layer { name: n.to_string(), inkscape: true };
            }
        } else if !outer.inkscape {
            if let Some(n) = label.or(id) {
                return Layer { name: n.to_string(), inkscape: false };
            }
        }
        outer.clone()
    }

    fn transform(&self, n: Node<'_, '_>) -> Result<Affine, HullError> {
        let Some(t) = n.attribute("transform") else { return Ok(Affine::IDENTITY) };
        let bad = |why: String| {
            drawing_error(self.attr_loc(n, "transform"), why, "an SVG transform list such as translate(10 20) scale(2)")
        };
        let t: Transform = t.parse().map_err(|e| bad(format!("transform {t:?}: {e}")))?;
        let m = Affine { a: t.a, b: t.b, c: t.c, d: t.d, e: t.e, f: t.f };
        if !m.is_finite() {
            return Err(bad(format!("transform {:?} is not finite", n.attribute("transform").unwrap_or(""))));
        }
        Ok(m)
    }

    /// A coordinate attribute in user units (0 when absent).
    fn coord(&self, n: Node<'_, '_>, name: &str) -> Result<f64, HullError> {
        let Some(v) = n.attribute(name) else { return Ok(0.0) };
        match v.parse::<Length>() {
            Ok(Length { number, unit: LengthUnit::None | LengthUnit::Px }) if number.is_finite() => Ok(number),
            _ => Err(drawing_error(self.attr_loc(n, name), format!("{name}={v:?}"), "a finite number in user units")),
        }
    }

    fn numbers(&self, n: Node<'_, '_>, name: &str) -> Result<Vec<f64>, HullError> {
        let Some(v) = n.attribute(name) else { return Ok(Vec::new()) };
        let mut out = Vec::new();
        for x in NumberListParser::from(v) {
            match x {
                Ok(x) if x.is_finite() => out.push(x),
                Ok(x) => {
                    return Err(drawing_error(
                        self.attr_loc(n, name),
                        format!("{name}: {x} is not finite"),
                        "finite numbers",
                    ))
                }
                Err(e) => {
                    return Err(drawing_error(
                        self.attr_loc(n, name),
                        format!("{name}={v:?}: {e}"),
                        "a list of numbers",
                    ))
                }
            }
        }
        Ok(out)
    }

    /// The `<title>` child's text, else a non-automatic `id`.
    fn name(n: Node<'_, '_>) -> Option<String> {
        let title = n.children().find(|c| c.has_tag_name((SVG_NS, "title")) || c.has_tag_name("title"));
        match title.map(text_of) {
            Some(t) if !t.is_empty() => Some(t),
            _ => n.attribute("id").filter(|id| !automatic_id(id)).map(str::to_string),
        }
    }

    fn push(&mut self, n: Node<'_, '_>, segments: Vec<Segment>, closed: bool, layer: &Layer) {
        if segments.is_empty() {
            return;
        }
        self.sketch.curves.push(Curve {
            segments,
            layer: layer.name.clone(),
            name: Self::name(n),
            closed,
            at: self.loc(n),
            kind: n.tag_name().name().to_string(),
        });
    }

    fn polyline(&mut self, n: Node<'_, '_>, m: &Affine, layer: &Layer) -> Result<(), HullError> {
        let v = self.numbers(n, "points")?;
        if v.len() % 2 != 0 {
            return Err(drawing_error(
                self.attr_loc(n, "points"),
                format!("points has {} numbers", v.len()),
                "x,y pairs: an even count of numbers",
            ));
        }
        let p: Vec<P2> = v.chunks(2).map(|c| [c[0], c[1]]).collect();
        let closed = n.tag_name().name() == "polygon" && p.len() > 2;
        let mut segs: Vec<Segment> = p.windows(2).map(|w| Segment::Line(w[0], w[1]).transformed(m)).collect();
        if closed {
            segs.push(Segment::Line(p[p.len() - 1], p[0]).transformed(m));
        }
        self.push(n, segs, closed, layer);
        Ok(())
    }

    fn path(&mut self, n: Node<'_, '_>, m: &Affine, layer: &Layer) -> Result<(), HullError> {
        let d = n.attribute("d").unwrap_or("");
        let mut subpaths: Vec<(Vec<Segment>, bool)> = Vec::new();
        let mut segs: Vec<Segment> = Vec::new();
        let (mut cur, mut start): (P2, P2) = ([0.0, 0.0], [0.0, 0.0]);
        // The last control point of a C/S (cubic) or Q/T (quadratic) command, for reflection.
        let mut last: Option<(P2, bool)> = None;
        for seg in PathParser::from(d) {
            let seg = seg.map_err(|e| {
                drawing_error(self.attr_loc(n, "d"), format!("path data: {e}"), "SVG path data (SVG 1.1 section 8.3)")
            })?;
            let at = |abs: bool, x: f64, y: f64| if abs { [x, y] } else { [cur[0] + x, cur[1] + y] };
            let mut ctrl = None;
            let next = match seg {
                PathSegment::MoveTo { abs, x, y } => {
                    if !segs.is_empty() {
                        subpaths.push((std::mem::take(&mut segs), false));
                    }
                    start = at(abs, x, y);
                    start
                }
                PathSegment::LineTo { abs, x, y } => {
                    let p = at(abs, x, y);
                    segs.push(Segment::Line(cur, p));
                    p
                }
                PathSegment::HorizontalLineTo { abs, x } => {
                    let p = [if abs { x } else { cur[0] + x }, cur[1]];
                    segs.push(Segment::Line(cur, p));
                    p
                }
                PathSegment::VerticalLineTo { abs, y } => {
                    let p = [cur[0], if abs { y } else { cur[1] + y }];
                    segs.push(Segment::Line(cur, p));
                    p
                }
                PathSegment::CurveTo { abs, x1, y1, x2, y2, x, y } => {
                    let (c1, c2, p) = (at(abs, x1, y1), at(abs, x2, y2), at(abs, x, y));
                    segs.push(Segment::Bezier(vec![cur, c1, c2, p]));
                    ctrl = Some((c2, true));
                    p
                }
                PathSegment::SmoothCurveTo { abs, x2, y2, x, y } => {
                    let c1 = reflect(last, true, cur);
                    let (c2, p) = (at(abs, x2, y2), at(abs, x, y));
                    segs.push(Segment::Bezier(vec![cur, c1, c2, p]));
                    ctrl = Some((c2, true));
                    p
                }
                PathSegment::Quadratic { abs, x1, y1, x, y } => {
                    let (c1, p) = (at(abs, x1, y1), at(abs, x, y));
                    segs.push(Segment::Bezier(vec![cur, c1, p]));
                    ctrl = Some((c1, false));
                    p
                }
                PathSegment::SmoothQuadratic { abs, x, y } => {
                    let c1 = reflect(last, false, cur);
                    let p = at(abs, x, y);
                    segs.push(Segment::Bezier(vec![cur, c1, p]));
                    ctrl = Some((c1, false));
                    p
                }
                PathSegment::EllipticalArc { abs, rx, ry, x_axis_rotation, large_arc, sweep, x, y } => {
                    let p = at(abs, x, y);
                    if let Some(s) = Segment::svg_arc(cur, p, rx, ry, x_axis_rotation, large_arc, sweep) {
                        segs.push(s);
                    }
                    p
                }
                PathSegment::ClosePath { .. } => {
                    if cur != start {
                        segs.push(Segment::Line(cur, start));
                    }
                    if !segs.is_empty() {
                        subpaths.push((std::mem::take(&mut segs), true));
                    }
                    start
                }
            };
            if !(next[0].is_finite() && next[1].is_finite()) {
                return Err(drawing_error(
                    self.attr_loc(n, "d"),
                    "path data with a non-finite number".into(),
                    "finite numbers",
                ));
            }
            cur = next;
            last = ctrl;
        }
        if !segs.is_empty() {
            subpaths.push((segs, false));
        }
        for (segs, closed) in subpaths {
            let segs: Vec<Segment> = segs.iter().map(|s| s.transformed(m)).collect();
            if segs.iter().flat_map(Segment::hull_points).flatten().any(|c| !c.is_finite()) {
                return Err(drawing_error(
                    self.attr_loc(n, "d"),
                    "path data whose points are not finite once transformed".into(),
                    "finite numbers",
                ));
            }
            self.push(n, segs, closed, layer);
        }
        Ok(())
    }

    fn text(&mut self, n: Node<'_, '_>, m: &Affine, layer: &Layer) -> Result<(), HullError> {
        // The first x and y of the text, else of its first tspan that has them.
        let mut pos = [self.numbers(n, "x")?.first().copied(), self.numbers(n, "y")?.first().copied()];
        for t in n.descendants().filter(|d| d.has_tag_name((SVG_NS, "tspan")) || d.has_tag_name("tspan")) {
            if pos[0].is_none() {
                pos[0] = self.numbers(t, "x")?.first().copied();
            }
            if pos[1].is_none() {
                pos[1] = self.numbers(t, "y")?.first().copied();
            }
        }
        let text = text_of(n);
        if text.is_empty() {
            return Ok(());
        }
        self.sketch.labels.push(Label {
            at: m.apply([pos[0].unwrap_or(0.0), pos[1].unwrap_or(0.0)]),
            text,
            layer: layer.name.clone(),
            loc: self.loc(n),
        });
        Ok(())
    }
}

/// The first control point of an `S` (cubic) or `T` (quadratic) command: the previous
/// command's last control point reflected about the current point when the previous command
/// was of the same kind, else the current point (SVG 1.1 section 8.3.6-8.3.7).
fn reflect(last: Option<(P2, bool)>, cubic: bool, cur: P2) -> P2 {
    match last {
        Some((c, k)) if k == cubic => [2.0 * cur[0] - c[0], 2.0 * cur[1] - c[1]],
        _ => cur,
    }
}

/// The text of an element and its descendants, white space collapsed.
fn text_of(n: Node<'_, '_>) -> String {
    let raw: String = n.descendants().filter(Node::is_text).filter_map(|t| t.text()).collect::<Vec<_>>().join(" ");
    raw.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn svg(body: &str) -> String {
        format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="50mm" viewBox="0 0 200 100">{body}</svg>"#
        )
    }

    fn close(a: P2, b: P2) -> bool {
        (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-12
    }

    #[test]
    fn units_come_from_width_and_viewbox() {
        let s = parse_svg(&svg(""), "u.svg").expect("parses");
        assert_eq!(s.unit_mm, Some(0.5));
        let s = parse_svg(r#"<svg xmlns="http://www.w3.org/2000/svg" width="300"/>"#, "u.svg").expect("parses");
        assert_eq!(s.unit_mm, Some(25.4 / 96.0));
        let s = parse_svg(r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 9 9"/>"#, "u.svg").expect("parses");
        assert_eq!(s.unit_mm, None);
    }

    /// Relative commands, H/V, S reflection and Z: the path's points land where the absolute
    /// arithmetic puts them.
    #[test]
    fn path_commands_absolute_and_relative() {
        let s = parse_svg(
            &svg(r#"<path d="m10 10 h5 v5 l-5 0 z M0 0 c0 10 10 10 10 0 s10 -10 10 0 q5 5 10 0 t10 0"/>"#),
            "p.svg",
        )
        .expect("parses");
        assert_eq!(s.curves.len(), 2);
        assert!(s.curves[0].closed);
        assert_eq!(
            s.curves[0].points(1e-6),
            vec![[10.0, 10.0], [15.0, 10.0], [15.0, 15.0], [10.0, 15.0], [10.0, 10.0]]
        );
        let c = &s.curves[1];
        let Segment::Bezier(b) = &c.segments[1] else { panic!("a cubic") };
        // S reflects (10, 10) about (10, 0): (10, -10); its own control (20, -10), end (20, 0).
        assert_eq!(b, &vec![[10.0, 0.0], [10.0, -10.0], [20.0, -10.0], [20.0, 0.0]]);
        let Segment::Bezier(t) = &c.segments[3] else { panic!("a quadratic") };
        // T reflects (25, 5) about (30, 0): (35, -5).
        assert_eq!(t, &vec![[30.0, 0.0], [35.0, -5.0], [40.0, 0.0]]);
        assert!(close(c.segments[3].end(), [40.0, 0.0]));
    }

    /// Group transforms compose outer-first: translate(100 0) scale(2) maps (1, 1) to (102, 2).
    #[test]
    fn transforms_nest_and_layers_name_groups() {
        let s = parse_svg(
            &svg(r#"<g id="ST4" transform="translate(100 0)"><g id="g12" transform="scale(2)">
                    <polyline points="1,1 2,3"><title>4</title></polyline>
                    <line x1="0" y1="0" x2="1" y2="0" transform="matrix(0 1 -1 0 0 0)"/></g></g>
                  <text x="5" y="6" transform="translate(1 1)"><tspan>ST</tspan> <tspan>4</tspan></text>"#),
            "t.svg",
        )
        .expect("parses");
        assert_eq!(s.curves[0].points(1e-6), vec![[102.0, 2.0], [104.0, 6.0]]);
        assert_eq!(s.curves[0].layer, "ST4", "the automatic id g12 does not name a layer");
        assert_eq!(s.curves[0].name.as_deref(), Some("4"));
        // matrix(0 1 -1 0) turns (1, 0) to (0, 1); then scale 2, translate 100.
        assert_eq!(s.curves[1].points(1e-6), vec![[100.0, 0.0], [100.0, 2.0]]);
        assert_eq!(s.labels[0].text, "ST 4");
        assert_eq!(s.labels[0].at, [6.0, 7.0]);
    }

    #[test]
    fn inkscape_layers_win() {
        let s = parse_svg(
            r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape">
               <g inkscape:groupmode="layer" inkscape:label="ST 7" id="layer1"><g id="inner"><path d="M0 0 L1 1"/></g></g></svg>"#,
            "i.svg",
        )
        .expect("parses");
        assert_eq!(s.curves[0].layer, "ST 7");
    }

    /// An SVG arc keeps its exact circle: every flattened point at the radius.
    #[test]
    fn arcs_stay_exact() {
        let s = parse_svg(&svg(r#"<path d="M 60 50 A 10 10 0 0 0 50 40"/>"#), "a.svg").expect("parses");
        for p in s.curves[0].points(1e-6) {
            assert!(((p[0] - 50.0).hypot(p[1] - 50.0) - 10.0).abs() < 1e-12, "{p:?}");
        }
    }

    #[test]
    fn skipped_and_hidden_elements_are_noted() {
        let s = parse_svg(
            &svg(r#"<rect width="1" height="1"/><circle r="1"/><circle r="2"/><g style="display: none"><path d="M0 0 L1 1"/></g>"#),
            "n.svg",
        )
        .expect("parses");
        assert!(s.curves.is_empty());
        assert_eq!(s.notes.len(), 3, "{:?}", s.notes);
        assert!(s.notes.iter().any(|n| n.starts_with("<circle> (2, first at n.svg:1:")), "{:?}", s.notes);
    }

    #[test]
    fn broken_files_name_line_and_column() {
        let err = |t: &str| parse_svg(t, "b.svg").expect_err("broken").to_string();
        let e = err("<svg xmlns=\"http://www.w3.org/2000/svg\">\n<path d=\"M0 0\">\n</svg>");
        assert_eq!(e, "b.svg:3:1: malformed XML: expected 'path' tag, not 'svg' (expected an SVG file)");
        let e = err("<svg xmlns=\"http://www.w3.org/2000/svg\">\n <path d=\"M 0 0 L 1 x\"/></svg>");
        assert!(e.starts_with("b.svg:2:11: path data: "), "{e}");
        let e = err("<svg xmlns=\"http://www.w3.org/2000/svg\"><g transform=\"shift(1)\"/></svg>");
        assert!(e.contains("transform \"shift(1)\""), "{e}");
        assert!(err("<html/>").starts_with("b.svg:1:1: root element <html> (expected an SVG document"));
        assert!(err(&svg(r#"<polyline points="1 2 3"/>"#)).contains("points has 3 numbers"));
        assert!(err(&svg(r#"<line x1="1mm"/>"#)).contains("x1=\"1mm\""));
    }

    #[test]
    fn groups_nested_past_the_cap_are_refused_not_overflowing_the_stack() {
        let nested = |depth: usize| {
            format!(
                "<svg xmlns=\"http://www.w3.org/2000/svg\">{}<path d=\"M 0 0 L 1 1\"/>{}</svg>",
                "<g>".repeat(depth),
                "</g>".repeat(depth)
            )
        };
        // The path inside the innermost of MAX_GROUP_DEPTH groups is read.
        let s = parse_svg(&nested(MAX_GROUP_DEPTH), "n.svg").expect("deep but within the cap");
        assert_eq!(s.curves.len(), 1);
        // 20000 groups stop at the first group past the cap (ancestors: itself, the groups
        // around it, <svg> and the document), whose column is 1 + 40 (the <svg> tag) + 3 per
        // <g> before it.
        let e = parse_svg(&nested(20_000), "n.svg").expect_err("too deep").to_string();
        let col = 41 + 3 * MAX_GROUP_DEPTH;
        assert!(e.starts_with(&format!("n.svg:1:{col}: <g> nested more than {MAX_GROUP_DEPTH} groups deep")), "{e}");
    }
}
