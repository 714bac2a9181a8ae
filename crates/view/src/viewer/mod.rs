//! The 3-D viewer: one self-contained HTML page (three.js inlined, no network when opened)
//! showing the hull surface shaded and coloured by a field (Gaussian curvature, mean
//! curvature, error to the offsets), with a colour legend, zebra stripes (reflection lines),
//! the control net and the offsets, mirrored to the full hull.
//!
//! The page embeds, as base64 of little-endian arrays in a JSON block: the vertex grid of the
//! starboard half (Float32 positions, Int16 unit normals), one Float32 value per vertex and
//! field, the control net (Float32) and the offsets with their distances to the surface
//! (Float32). The triangles of the grid and the mirrored half (`y -> -y`, a transform of the
//! same geometry) are made by the page. The colours come from hull's colour maps: the
//! diverging map ([`hull::diverging`]) for curvature, symmetric about zero with its limit at
//! the 98th percentile of `|value|` (a few extreme values at a degenerate stem would otherwise
//! wash out the rest), the sequential map ([`hull::sequential`]) from zero to the largest
//! distance for the error.
//!
//! Axes: x forward, y to starboard, z up, in the offsets' units.

mod mesh;

use std::io::{self, Write};
use std::str::FromStr;

use nurbs::{NurbsSurface, Vec3};
use serde_json::{json, Value};

use crate::markup::{base64, escape};
use hull::{curvature_limit, diverging_stops, sequential_stops, ErrorStats, Offsets, Units, CURVATURE_QUANTILE};
pub use mesh::Resolution;

const TEMPLATE: &str = include_str!("viewer.html");
const SCRIPT: &str = include_str!("viewer.js");
const STYLE: &str = include_str!("viewer.css");
/// three.js, bundled by `tools/vendor-three.sh` (version and sha256 in `assets/three/README.md`).
const THREE_JS: &str = include_str!("../../assets/three/three.min.js");
const THREE_LICENSE: &str = include_str!("../../assets/three/LICENSE");

/// The field the hull is coloured by when the page opens (the page can switch to any other).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Field {
    /// Gaussian curvature `K = k1 k2`, in 1/unit².
    #[default]
    Gaussian,
    /// Mean curvature `H = (k1 + k2) / 2`, in 1/unit, positive where the hull is convex.
    Mean,
    /// Distance of the offsets to the surface, interpolated between them (needs offsets).
    Error,
    /// No field: a plain grey hull.
    None,
}

impl Field {
    /// Every field, in the order of the page's selector.
    pub const ALL: [Field; 4] = [Field::Gaussian, Field::Mean, Field::Error, Field::None];

    /// The name used on the page and accepted by [`FromStr`]: `gaussian`, `mean`, `error`, `none`.
    pub fn key(self) -> &'static str {
        match self {
            Field::Gaussian => "gaussian",
            Field::Mean => "mean",
            Field::Error => "error",
            Field::None => "none",
        }
    }
}

impl FromStr for Field {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Field::ALL
            .into_iter()
            .find(|f| f.key().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| format!("unknown field {s:?}: expected gaussian, mean, error or none"))
    }
}

/// What the viewer page shows when it opens.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewerOptions {
    /// The field the hull is coloured by at first ([`Field::Error`] without offsets falls back
    /// to [`Field::Gaussian`]).
    pub field: Field,
    /// Tessellation of the surface.
    pub resolution: Resolution,
    /// Show the port half too (the surface mirrored in the centre plane `y = 0`).
    pub mirror: bool,
    /// Zebra stripes (reflection lines) instead of the field's colours.
    pub zebra: bool,
    /// Show the control net.
    pub control_net: bool,
    /// Show the offsets as points coloured by their distance to the surface.
    pub offsets: bool,
    /// The page's title.
    pub title: String,
    /// More lines for the particulars panel (name, value), after the computed ones: Lpp, the
    /// fit method, the source file.
    pub notes: Vec<(String, String)>,
}

impl Default for ViewerOptions {
    fn default() -> Self {
        ViewerOptions {
            field: Field::Gaussian,
            resolution: Resolution::default(),
            mirror: true,
            zebra: false,
            control_net: false,
            offsets: true,
            title: "hullskin surface".into(),
            notes: Vec::new(),
        }
    }
}

/// Write the viewer page of `surface` (the starboard half hull) to `w`: one self-contained
/// HTML file that needs no network. `offsets`, when given, add the error field and the offset
/// markers; `units` labels every length.
///
/// The same inputs give the same bytes.
///
/// # Errors
/// Whatever `w` returns.
pub fn write_viewer_html<W: Write + ?Sized>(
    w: &mut W,
    surface: &NurbsSurface,
    offsets: Option<&Offsets>,
    units: Units,
    options: &ViewerOptions,
) -> io::Result<()> {
    let data = page_data(surface, offsets, units, options);
    // JSON in a <script> element: `<` only occurs inside strings, where \u003c means the same.
    let data = serde_json::to_string(&data).map_err(io::Error::other)?.replace('<', "\\u003c");
    let mut rest = TEMPLATE;
    while let Some(start) = rest.find("{{") {
        w.write_all(&rest.as_bytes()[..start])?;
        let len = rest[start..].find("}}").expect("the template's markers are closed");
        match &rest[start + 2..start + len] {
            "TITLE" => w.write_all(escape(&options.title).as_bytes())?,
            "STYLE" => w.write_all(STYLE.as_bytes())?,
            "THREE_LICENSE" => w.write_all(THREE_LICENSE.replace("--", "- -").as_bytes())?,
            "THREE" => w.write_all(THREE_JS.as_bytes())?,
            "DATA" => w.write_all(data.as_bytes())?,
            "SCRIPT" => w.write_all(SCRIPT.as_bytes())?,
            other => panic!("unknown template marker {other}"),
        }
        rest = &rest[start + len + 2..];
    }
    w.write_all(rest.as_bytes())
}

/// Float32 little-endian, base64; non-finite values become 0.
fn f32_base64(values: impl IntoIterator<Item = f64>) -> String {
    let bytes: Vec<u8> =
        values.into_iter().flat_map(|v| (if v.is_finite() { v as f32 } else { 0.0 }).to_le_bytes()).collect();
    base64(&bytes)
}

fn vec3_base64(points: &[Vec3]) -> String {
    f32_base64(points.iter().flat_map(|p| [p.x, p.y, p.z]))
}

/// Unit vectors as Int16 little-endian `round(32767 c)`, base64 (WebGL's normalized SHORT).
fn normals_base64(normals: &[Vec3]) -> String {
    let bytes: Vec<u8> = normals
        .iter()
        .flat_map(|n| [n.x, n.y, n.z])
        .flat_map(|c| ((c.clamp(-1.0, 1.0) * 32767.0).round() as i16).to_le_bytes())
        .collect();
    base64(&bytes)
}

/// A number for the page's text, with 4 significant digits (deterministic).
fn num(x: f64) -> String {
    if !x.is_finite() {
        return "n/a".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.3e}")
    }
}

/// Smallest and largest finite value.
fn finite_range(values: &[f64]) -> (f64, f64) {
    values.iter().filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)))
}

fn curvature_field(label: &str, symbol: &str, unit: String, values: &[f64], note: &str) -> Value {
    let (min, max) = finite_range(values);
    let limit = curvature_limit(values);
    json!({
        "label": label,
        "symbol": symbol,
        "unit": unit,
        "map": "diverging",
        "values": f32_base64(values.iter().copied()),
        "min": min,
        "max": max,
        "lo": -limit,
        "hi": limit,
        "note": format!(
            "{note} Colours saturate at \u{b1}{} (the {}th percentile of |{symbol}|).",
            num(limit),
            (CURVATURE_QUANTILE * 100.0).round()
        ),
    })
}

/// Everything the page shows, as JSON.
fn page_data(surface: &NurbsSurface, offsets: Option<&Offsets>, units: Units, options: &ViewerOptions) -> Value {
    let m = mesh::tessellate(surface, &options.resolution);
    let u = units.symbol();
    let mut fields = serde_json::Map::new();
    fields.insert(
        "gaussian".into(),
        curvature_field(
            "Gaussian curvature",
            "K",
            format!("1/{u}\u{b2}"),
            &m.gaussian,
            "K = k1 k2: > 0 dome-like, < 0 saddle-like, 0 developable (flat or cylindrical).",
        ),
    );
    fields.insert(
        "mean".into(),
        curvature_field(
            "Mean curvature",
            "H",
            format!("1/{u}"),
            &m.mean,
            "H = (k1 + k2) / 2, > 0 where the hull is convex (outward normal).",
        ),
    );
    let errors = offsets.map(|o| mesh::offset_errors(surface, o)).filter(|e| !e.distance.is_empty());
    let offsets_json = if let Some(e) = &errors {
        let field = mesh::interpolate_errors(&m, e, surface.domain_u(), surface.domain_v());
        let stats = ErrorStats::from_distances(&e.distance);
        fields.insert(
            "error".into(),
            json!({
                "label": "Distance to the offsets",
                "symbol": "d",
                "unit": u,
                "map": "sequential",
                "values": f32_base64(field.iter().copied()),
                "min": 0.0,
                "max": stats.max,
                "lo": 0.0,
                "hi": if stats.max > 0.0 { stats.max } else { 1.0 },
                "note": format!(
                    "Measured at the {} offsets (markers), interpolated between them (Shepard). \
                     Max {} {u}, RMS {} {u}.",
                    stats.points, num(stats.max), num(stats.rms)
                ),
            }),
        );
        json!({
            "count": e.points.len(),
            "points": vec3_base64(&e.points),
            "distance": f32_base64(e.distance.iter().copied()),
            "max": stats.max,
        })
    } else {
        Value::Null
    };
    let field = match options.field {
        Field::Error if errors.is_none() => Field::Gaussian,
        f => f,
    };
    let net = surface.control_points();
    json!({
        "format": "hullskin-viewer 1",
        "title": options.title,
        "units": u,
        "grid": {
            "nu": m.nu,
            "nv": m.nv,
            "flip": m.flipped,
            "positions": vec3_base64(&m.positions),
            "normals": normals_base64(&m.normals),
        },
        "fields": fields,
        "net": { "nu": surface.n_u(), "nv": surface.n_v(), "points": vec3_base64(&net) },
        "offsets": offsets_json,
        "colormaps": { "diverging": diverging_stops(), "sequential": sequential_stops() },
        "initial": {
            "field": field.key(),
            "mirror": options.mirror,
            "zebra": options.zebra,
            "net": options.control_net,
            "offsets": options.offsets && errors.is_some(),
        },
        "particulars": particulars(surface, &m, offsets, errors.as_ref(), units, options),
    })
}

/// The particulars panel: extent, surface, tessellation, fit error, then the caller's notes.
fn particulars(
    s: &NurbsSurface,
    m: &mesh::Mesh,
    offsets: Option<&Offsets>,
    errors: Option<&mesh::OffsetErrors>,
    units: Units,
    options: &ViewerOptions,
) -> Vec<[String; 2]> {
    let u = units.symbol();
    let (lo, hi) = m.positions.iter().filter(|p| p.is_finite()).fold(
        (
            Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
            -Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
        ),
        |(a, b), p| {
            (Vec3::new(a.x.min(p.x), a.y.min(p.y), a.z.min(p.z)), Vec3::new(b.x.max(p.x), b.y.max(p.y), b.z.max(p.z)))
        },
    );
    let mut rows = vec![
        ["Length (x extent)".to_string(), format!("{} {u}  (x {} .. {})", num(hi.x - lo.x), num(lo.x), num(hi.x))],
        ["Beam (2 max y)".into(), format!("{} {u}", num(2.0 * hi.y))],
        ["Depth (z extent)".into(), format!("{} {u}  (z {} .. {})", num(hi.z - lo.z), num(lo.z), num(hi.z))],
        [
            "Surface".into(),
            format!(
                "degree {} x {}, {} x {} poles{}",
                s.degree_u(),
                s.degree_v(),
                s.n_u(),
                s.n_v(),
                if s.is_rational() { ", rational" } else { "" }
            ),
        ],
        [
            "Knot spans".into(),
            format!("{} x {}", s.knots_u().interior_breaks().len() + 1, s.knots_v().interior_breaks().len() + 1),
        ],
        ["Tessellation".into(), format!("{} x {} vertices, {} triangles per half", m.nu, m.nv, m.triangles())],
    ];
    for (name, values, unit) in [("K", &m.gaussian, format!("1/{u}\u{b2}")), ("H", &m.mean, format!("1/{u}"))] {
        let (a, b) = finite_range(values);
        rows.push([format!("{name} range"), format!("{} .. {} {unit}", num(a), num(b))]);
    }
    if let (Some(o), Some(e)) = (offsets, errors) {
        let stats = ErrorStats::from_distances(&e.distance);
        rows.push(["Offsets".into(), format!("{} points in {} sections", e.points.len(), o.sections.len())]);
        rows.push([
            "Fit error".into(),
            format!("max {} {u}, mean {} {u}, RMS {} {u}", num(stats.max), num(stats.mean), num(stats.rms)),
        ]);
    }
    rows.extend(options.notes.iter().map(|(k, v)| [k.clone(), v.clone()]));
    rows.push(["Units".into(), format!("{} ({})", units.plural_name(), u)]);
    rows
}

/// For tests: the page's JSON data block, parsed.
#[cfg(test)]
fn data_block(html: &str) -> Value {
    let start = html.find("id=\"hull-data\"").expect("data block");
    let open = start + html[start..].find('>').expect("tag end") + 1;
    let close = open + html[open..].find("</script>").expect("closed");
    serde_json::from_str(&html[open..close]).expect("valid JSON")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_page::unbase64;
    use hull::{fit_offsets, series60_sample, FitConfig};

    fn f32s(s: &Value) -> Vec<f32> {
        unbase64(s.as_str().expect("string"))
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
            .collect()
    }

    fn i16s(s: &Value) -> Vec<i16> {
        unbase64(s.as_str().expect("string"))
            .chunks(2)
            .map(|c| i16::from_le_bytes(c.try_into().expect("2 bytes")))
            .collect()
    }

    fn sample_page(options: &ViewerOptions) -> (String, NurbsSurface, Offsets) {
        let offsets = series60_sample();
        let surface = fit_offsets(&offsets, &FitConfig::default()).expect("the sample fits").surface;
        let mut out = Vec::new();
        write_viewer_html(&mut out, &surface, Some(&offsets), offsets.units, options).expect("writes to memory");
        (String::from_utf8(out).expect("UTF-8"), surface, offsets)
    }

    #[test]
    fn embedded_data_decodes_to_the_grid_and_lies_on_the_surface() {
        let (html, surface, offsets) = sample_page(&ViewerOptions::default());
        let d = data_block(&html);
        let (nu, nv) = (d["grid"]["nu"].as_u64().expect("nu") as usize, d["grid"]["nv"].as_u64().expect("nv") as usize);
        // The default resolution: at least 60 x 40, whichever way round the surface runs.
        assert!(nu.min(nv) >= 40 && nu.max(nv) >= 60, "{nu} x {nv}");
        let pos = f32s(&d["grid"]["positions"]);
        let nrm = i16s(&d["grid"]["normals"]);
        assert_eq!(pos.len(), 3 * nu * nv);
        assert_eq!(nrm.len(), 3 * nu * nv);
        for key in ["gaussian", "mean", "error"] {
            assert_eq!(f32s(&d["fields"][key]["values"]).len(), nu * nv, "{key}");
        }
        // Every vertex and normal is the tessellation's, to f32 rounding (1e-7 relative of
        // ~120 m) and Int16 quantisation (1/32767 per component).
        let m = mesh::tessellate(&surface, &Resolution::default());
        assert_eq!((m.nu, m.nv), (nu, nv));
        for (k, (p, n)) in m.positions.iter().zip(&m.normals).enumerate() {
            for c in 0..3 {
                assert!(
                    (pos[3 * k + c] as f64 - p[c]).abs() < 2e-5,
                    "vertex {k}: {:?} vs {p:?}",
                    &pos[3 * k..3 * k + 3]
                );
                assert!((nrm[3 * k + c] as f64 / 32767.0 - n[c]).abs() < 2e-5, "normal {k}");
            }
        }
        // The grid's corners are the surface's corners.
        let ((u0, u1), (v0, v1)) = (surface.domain_u(), surface.domain_v());
        for (k, (u, v)) in [(0, (u0, v0)), (nv - 1, (u0, v1)), (nu * nv - 1, (u1, v1))] {
            assert!(surface.point(u, v).distance(m.positions[k]) < 1e-12, "corner {k}");
        }
        // Unit normals after Int16 quantisation (1/32767 per component).
        for n in nrm.chunks(3) {
            let len = n.iter().map(|&c| (c as f64 / 32767.0).powi(2)).sum::<f64>().sqrt();
            assert!((len - 1.0).abs() < 1e-4, "{len}");
        }
        // Offsets: every point, with distances matching the fit's own error measurement.
        let measured = hull::measure_fit_error(&surface, &offsets, None).overall;
        assert_eq!(d["offsets"]["count"].as_u64(), Some(offsets.num_points() as u64));
        assert_eq!(f32s(&d["offsets"]["points"]).len(), 3 * offsets.num_points());
        let dist = f32s(&d["offsets"]["distance"]);
        let max = dist.iter().copied().fold(0.0f32, f32::max) as f64;
        // Same projection; f32 storage rounds at 1e-7 relative.
        assert!((max - measured.max).abs() <= 1e-6 * measured.max.max(1e-9), "{max} vs {}", measured.max);
        let net = f32s(&d["net"]["points"]);
        assert_eq!(net.len(), 3 * surface.n_u() * surface.n_v());
    }

    #[test]
    fn curvature_limits_are_symmetric_percentiles() {
        let (html, ..) = sample_page(&ViewerOptions::default());
        let d = data_block(&html);
        for key in ["gaussian", "mean"] {
            let f = &d["fields"][key];
            let (lo, hi) = (f["lo"].as_f64().expect("lo"), f["hi"].as_f64().expect("hi"));
            assert!(hi > 0.0 && lo == -hi, "{key}: {lo} {hi}");
            let values: Vec<f64> = f32s(&f["values"]).into_iter().map(f64::from).collect();
            let inside = values.iter().filter(|v| v.abs() <= hi * (1.0 + 1e-6)).count() as f64 / values.len() as f64;
            // Nearest rank: at least 98 % within the limit; ties could raise it, never lower it.
            assert!(inside >= CURVATURE_QUANTILE, "{key}: {inside}");
            assert!(hi <= f["max"].as_f64().expect("max").abs().max(f["min"].as_f64().expect("min").abs()));
        }
        assert_eq!(d["fields"]["error"]["map"], "sequential");
        assert_eq!(d["colormaps"]["diverging"], json!(diverging_stops()));
        assert_eq!(d["colormaps"]["sequential"], json!(sequential_stops()));
    }

    #[test]
    fn page_loads_nothing_from_outside() {
        let (html, ..) = sample_page(&ViewerOptions::default());
        // No attribute, CSS url() or module import that could fetch something.
        for bad in ["src=", "href=", "url(", "@import", "import(", "fetch(", "XMLHttpRequest", "<link", "<iframe"] {
            assert!(!html.contains(bad), "the page contains {bad:?}");
        }
        // The only absolute URL is the XHTML namespace name used by three.js's createElementNS,
        // an identifier that is never loaded.
        for scheme in ["http://", "https://"] {
            for (at, _) in html.match_indices(scheme) {
                let rest = &html[at..];
                assert!(
                    rest.starts_with("http://www.w3.org/1999/xhtml"),
                    "URL in the page: {}",
                    &rest[..60.min(rest.len())]
                );
            }
        }
        assert!(html.contains(THREE_JS), "three.js inlined whole");
        assert!(html.contains("The MIT License"), "three.js licence notice");
    }

    #[test]
    fn same_input_same_bytes_and_options_change_only_the_options() {
        let (a, ..) = sample_page(&ViewerOptions::default());
        let (b, ..) = sample_page(&ViewerOptions::default());
        assert!(a == b, "two writes of the same page differ");
        let opts = ViewerOptions {
            field: Field::Mean,
            mirror: false,
            zebra: true,
            title: "S60 <test> & co".into(),
            notes: vec![("Lpp".into(), "121.92 m".into())],
            ..ViewerOptions::default()
        };
        let (c, ..) = sample_page(&opts);
        let d = data_block(&c);
        assert_eq!(
            d["initial"],
            json!({"field": "mean", "mirror": false, "zebra": true, "net": false, "offsets": true})
        );
        assert!(c.contains("<title>S60 &lt;test&gt; &amp; co</title>"));
        assert_eq!(d["title"], "S60 <test> & co");
        assert!(d["particulars"].as_array().expect("rows").iter().any(|r| r == &json!(["Lpp", "121.92 m"])));
    }

    #[test]
    fn error_field_needs_offsets() {
        let offsets = series60_sample();
        let surface = fit_offsets(&offsets, &FitConfig::default()).expect("fits").surface;
        let mut out = Vec::new();
        let opts = ViewerOptions { field: Field::Error, ..ViewerOptions::default() };
        write_viewer_html(&mut out, &surface, None, Units::Metre, &opts).expect("writes");
        let d = data_block(&String::from_utf8(out).expect("UTF-8"));
        assert_eq!(d["initial"]["field"], "gaussian");
        assert!(d["fields"]["error"].is_null() && d["offsets"].is_null());
        assert_eq!(d["initial"]["offsets"], false);
    }

    #[test]
    fn field_names_round_trip() {
        for f in Field::ALL {
            assert_eq!(f.key().parse::<Field>(), Ok(f));
        }
        assert!("curvature".parse::<Field>().is_err());
    }

    #[test]
    fn numbers_have_four_significant_digits() {
        assert_eq!(num(121.92), "121.9");
        assert_eq!(num(0.012345), "0.01235");
        assert_eq!(num(-3.0), "-3.000");
        assert_eq!(num(2.5e-5), "2.500e-5");
        assert_eq!(num(f64::NAN), "n/a");
        assert_eq!(num(0.0), "0");
    }
}
