//! The hullskin surface JSON format: one NURBS surface, lossless, for other programs and for
//! reading back.
//!
//! The rest of this module's documentation is on [`write_surface_json`], where the library's users read it.

use std::io::{self, Write};

use nurbs::{KnotVector, NurbsError, NurbsSurface, Vec3};

use crate::Units;
use serde::{Deserialize, Serialize};

/// The value of the `"format"` key.
pub const FORMAT_NAME: &str = "hullskin-surface";
/// The layout version this build writes and reads.
pub const FORMAT_VERSION: u32 = 1;

/// The JSON document, field for field.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SurfaceFile {
    pub format: String,
    pub version: u32,
    pub units: String,
    pub degree: [usize; 2],
    pub control_points_count: [usize; 2],
    pub knots_u: Vec<f64>,
    pub knots_v: Vec<f64>,
    pub control_points: Vec<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<f64>>,
}

impl SurfaceFile {
    /// The document describing `surface` (always with explicit weights).
    pub fn from_surface(surface: &NurbsSurface, units: Units) -> Self {
        SurfaceFile {
            format: FORMAT_NAME.to_string(),
            version: FORMAT_VERSION,
            units: units.symbol().to_string(),
            degree: [surface.degree_u(), surface.degree_v()],
            control_points_count: [surface.n_u(), surface.n_v()],
            knots_u: surface.knots_u().as_slice().to_vec(),
            knots_v: surface.knots_v().as_slice().to_vec(),
            control_points: surface.control_points().iter().map(|p| [p.x, p.y, p.z]).collect(),
            weights: Some(surface.weights()),
        }
    }

    /// Validate the document and build the surface.
    ///
    /// # Errors
    /// [`SurfaceJsonError::Format`], [`SurfaceJsonError::Version`],
    /// [`SurfaceJsonError::Count`] or [`SurfaceJsonError::Nurbs`] naming the offending key.
    pub fn to_surface(&self) -> Result<NurbsSurface, SurfaceJsonError> {
        if self.format != FORMAT_NAME {
            return Err(SurfaceJsonError::Format { found: self.format.clone() });
        }
        if self.version != FORMAT_VERSION {
            return Err(SurfaceJsonError::Version { found: self.version });
        }
        let [p, q] = self.degree;
        let ku = KnotVector::try_new(p, self.knots_u.clone())
            .map_err(|source| SurfaceJsonError::Nurbs { key: "knots_u", source })?;
        let kv = KnotVector::try_new(q, self.knots_v.clone())
            .map_err(|source| SurfaceJsonError::Nurbs { key: "knots_v", source })?;
        let implied = [ku.num_basis(), kv.num_basis()];
        if implied != self.control_points_count {
            return Err(SurfaceJsonError::Count { declared: self.control_points_count, implied });
        }
        crate::limits::control_points("surface JSON", implied[0], implied[1]).map_err(SurfaceJsonError::Limit)?;
        let points: Vec<Vec3> = self.control_points.iter().map(|&[x, y, z]| Vec3::new(x, y, z)).collect();
        NurbsSurface::try_new(ku, kv, &points, self.weights.as_deref()).map_err(|source| {
            let key = match source {
                NurbsError::WeightCount { .. } | NurbsError::BadWeight { .. } => "weights",
                _ => "control_points",
            };
            SurfaceJsonError::Nurbs { key, source }
        })
    }
}

/// Why a surface JSON document was refused.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SurfaceJsonError {
    #[error("surface JSON, line {line}, column {column}: {message}")]
    Syntax { line: usize, column: usize, message: String },
    #[error("not a hullskin surface: \"format\" is {found:?}, expected \"{FORMAT_NAME}\"")]
    Format { found: String },
    #[error("surface JSON version {found} is not supported (this build reads version {FORMAT_VERSION})")]
    Version { found: u32 },
    #[error("surface JSON: \"control_points_count\" is {declared:?}, but the degrees and knots give {implied:?}")]
    Count { declared: [usize; 2], implied: [usize; 2] },
    /// More control points than [`crate::limits::MAX_CONTROL_POINTS`] (or per direction).
    #[error("{0}")]
    Limit(crate::limits::LimitExceeded),
    #[error("surface JSON, \"{key}\": {source}")]
    Nurbs {
        key: &'static str,
        #[source]
        source: NurbsError,
    },
}

/// Write `surface` in the layout described below: one key per line, one control point per
/// line.
///
/// ```json
/// {
///   "format": "hullskin-surface",
///   "version": 1,
///   "units": "m",
///   "degree": [3, 3],
///   "control_points_count": [5, 4],
///   "knots_u": [0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0],
///   "knots_v": [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
///   "control_points": [
///     [0.0, 0.0, 0.0],
///     ...
///   ],
///   "weights": [1.0, ...]
/// }
/// ```
///
/// * `degree` is `[p, q]`, the degrees in u and v; `control_points_count` is `[n_u, n_v]`.
/// * `knots_u` / `knots_v` are the full clamped knot vectors (`n_u + p + 1` and `n_v + q + 1`
///   numbers, the first and last `p + 1` equal); the surface is defined on
///   `[knots_u[p], knots_u[n_u]] x [knots_v[q], knots_v[n_v]]`.
/// * `control_points` holds `n_u * n_v` Euclidean points `[x, y, z]` **u-major**: the point
///   `P_ij` (`i` along u, `j` along v) is at index `i * n_v + j`.
/// * `weights` holds the `n_u * n_v` weights in the same order (all `1.0` for a polynomial
///   surface; the reader also accepts the key missing, meaning all `1.0`).
/// * `units` names the length unit of the coordinates (`"m"`, `"mm"`, `"ft"`, `"in"`).
///
/// The surface is `S(u,v) = sum_ij N_i,p(u) N_j,q(v) w_ij P_ij / sum_ij N_i,p(u) N_j,q(v) w_ij`
/// (The NURBS Book eq. 4.15). Numbers are written with the shortest representation that
/// reads back to the same `f64`, so knots, weights and points survive a round trip exactly.
/// The reader validates everything (knot vectors, counts, finite values, positive weights)
/// and reports the first problem; it never panics.
///
/// # Errors
/// Whatever `w` returns.
pub fn write_surface_json<W: Write>(w: &mut W, surface: &NurbsSurface, units: Units) -> io::Result<()> {
    let doc = SurfaceFile::from_surface(surface, units);
    writeln!(w, "{{")?;
    writeln!(w, "  \"format\": {},", json(&doc.format)?)?;
    writeln!(w, "  \"version\": {},", doc.version)?;
    writeln!(w, "  \"units\": {},", json(&doc.units)?)?;
    writeln!(w, "  \"degree\": {},", json(&doc.degree)?)?;
    writeln!(w, "  \"control_points_count\": {},", json(&doc.control_points_count)?)?;
    writeln!(w, "  \"knots_u\": {},", json(&doc.knots_u)?)?;
    writeln!(w, "  \"knots_v\": {},", json(&doc.knots_v)?)?;
    writeln!(w, "  \"control_points\": [")?;
    for (k, p) in doc.control_points.iter().enumerate() {
        let comma = if k + 1 < doc.control_points.len() { "," } else { "" };
        writeln!(w, "    {}{comma}", json(p)?)?;
    }
    writeln!(w, "  ],")?;
    writeln!(w, "  \"weights\": {}", json(&doc.weights)?)?;
    writeln!(w, "}}")?;
    Ok(())
}

/// Parse and validate a surface JSON document; returns the surface and its `units` string.
///
/// # Errors
/// [`SurfaceJsonError::Syntax`] (with line and column) for malformed JSON or a missing or
/// mistyped key, otherwise as [`SurfaceFile::to_surface`].
pub fn read_surface_json(text: &str) -> Result<(NurbsSurface, String), SurfaceJsonError> {
    let doc: SurfaceFile = serde_json::from_str(text).map_err(|e| SurfaceJsonError::Syntax {
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    let surface = doc.to_surface()?;
    Ok((surface, doc.units))
}

/// Compact JSON of one value (serde_json writes `f64` with the shortest round-trip digits).
fn json<T: Serialize + ?Sized>(value: &T) -> io::Result<String> {
    serde_json::to_string(value).map_err(io::Error::other)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::assert_near;

    /// Rational, non-uniform, different sizes in u and v; coordinates and weights with
    /// many significant digits so a lossy format would show.
    fn sample() -> NurbsSurface {
        let ku =
            KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.1234567890123, 0.7, 1.0, 1.0, 1.0, 1.0]).expect("valid");
        let kv = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0 / 3.0, 1.0, 1.0, 1.0]).expect("valid");
        let (nu, nv) = (ku.num_basis(), kv.num_basis());
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                let (a, b) = (i as f64, j as f64);
                pts.push(Vec3::new(a.sqrt() * 12.345, (b + 0.1).ln(), 1e-7 * a * b - 3.0 / 7.0));
                w.push(1.0 + (a * 0.37 + b * 0.11).sin().abs());
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
    }

    fn to_text(s: &NurbsSurface, units: Units) -> String {
        let mut out = Vec::new();
        write_surface_json(&mut out, s, units).expect("writes to memory");
        String::from_utf8(out).expect("JSON is UTF-8")
    }

    #[test]
    fn round_trip_keeps_every_number() {
        let s = sample();
        let text = to_text(&s, Units::Millimetre);
        let (back, units) = read_surface_json(&text).expect("reads back");
        assert_eq!(units, "mm");
        // Knots, weights and the Euclidean points written are exactly what is read.
        assert_eq!(back.knots_u(), s.knots_u());
        assert_eq!(back.knots_v(), s.knots_v());
        assert_eq!(back.weights(), s.weights());
        let doc: SurfaceFile = serde_json::from_str(&text).expect("parses");
        assert_eq!(doc, SurfaceFile::from_surface(&s, Units::Millimetre));
        // The kernel stores w P, so P comes back through (P w) / w: equal to within one
        // rounding of each operation (2 ulp), and the surface evaluates to the same points.
        for (a, b) in back.control_points().iter().zip(s.control_points()) {
            for (x, y) in [(a.x, b.x), (a.y, b.y), (a.z, b.z)] {
                assert!((x - y).abs() <= 2.0 * f64::EPSILON * y.abs(), "{x:e} vs {y:e}");
            }
        }
        let (lo, hi) = s.control_bounds();
        let size = (hi - lo).norm();
        for k in 0..=10 {
            let (u, v) = (k as f64 / 10.0, (k as f64 * 0.37).fract());
            // Same arithmetic on inputs within 2 ulp: relative 1e-14 of the model size.
            assert_near!(back.point(u, v), s.point(u, v), 1e-14 * size);
        }
    }

    #[test]
    fn polynomial_round_trip_is_bit_exact() {
        let ku = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0]).expect("valid");
        let kv = KnotVector::uniform(1, 3).expect("valid");
        let pts: Vec<Vec3> =
            (0..12).map(|k| Vec3::new((k as f64).sqrt(), 0.1 * k as f64, -1.0 / (k as f64 + 3.0))).collect();
        let s = NurbsSurface::try_new(ku, kv, &pts, None).expect("valid");
        let (back, _) = read_surface_json(&to_text(&s, Units::Metre)).expect("reads back");
        assert_eq!(back, s);
        // Writing again gives the same text.
        assert_eq!(to_text(&back, Units::Metre), to_text(&s, Units::Metre));
    }

    #[test]
    fn layout_is_the_documented_one() {
        let s = sample();
        let text = to_text(&s, Units::Metre);
        let v: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        assert_eq!(v["format"], "hullskin-surface");
        assert_eq!(v["version"], 1);
        assert_eq!(v["units"], "m");
        assert_eq!(v["degree"], serde_json::json!([3, 2]));
        assert_eq!(v["control_points_count"], serde_json::json!([s.n_u(), s.n_v()]));
        // u-major: entry i * n_v + j is P_ij.
        let (i, j) = (3, 1);
        let p = s.control_point(i, j);
        let e = &v["control_points"][i * s.n_v() + j];
        assert_eq!([e[0].as_f64(), e[1].as_f64(), e[2].as_f64()], [Some(p.x), Some(p.y), Some(p.z)]);
        assert_eq!(v["weights"][i * s.n_v() + j].as_f64(), Some(s.weight(i, j)));
        // One control point per line.
        assert_eq!(
            text.lines().filter(|l| l.trim_start().starts_with('[') && l.contains(']')).count(),
            s.n_u() * s.n_v()
        );
    }

    #[test]
    fn missing_weights_mean_polynomial() {
        let s = sample();
        let mut doc = SurfaceFile::from_surface(&s, Units::Metre);
        doc.weights = None;
        let text = serde_json::to_string(&doc).expect("serializes");
        let (back, _) = read_surface_json(&text).expect("reads");
        assert!(!back.is_rational());
        assert!(back.weights().iter().all(|&w| w == 1.0));
    }

    #[test]
    fn bad_documents_are_refused_with_the_reason() {
        let good = serde_json::to_value(SurfaceFile::from_surface(&sample(), Units::Metre)).expect("serializes");
        let bad = |edit: &dyn Fn(&mut serde_json::Value)| {
            let mut v = good.clone();
            edit(&mut v);
            read_surface_json(&v.to_string()).expect_err("must be refused")
        };
        assert!(matches!(bad(&|v| v["format"] = "other".into()), SurfaceJsonError::Format { .. }));
        assert!(matches!(bad(&|v| v["version"] = 2.into()), SurfaceJsonError::Version { found: 2 }));
        assert!(matches!(bad(&|v| v["degree"][0] = 0.into()), SurfaceJsonError::Nurbs { key: "knots_u", .. }));
        assert!(matches!(bad(&|v| v["degree"][1] = 40.into()), SurfaceJsonError::Nurbs { key: "knots_v", .. }));
        assert!(matches!(
            bad(&|v| v["knots_u"][4] = (-1.0).into()),
            SurfaceJsonError::Nurbs { key: "knots_u", source: NurbsError::DecreasingKnots { .. } }
        ));
        assert!(matches!(
            bad(&|v| v["control_points_count"][0] = 99.into()),
            SurfaceJsonError::Count { declared: [99, _], .. }
        ));
        assert!(matches!(
            bad(&|v| {
                v["control_points"].as_array_mut().expect("array").pop();
            }),
            SurfaceJsonError::Nurbs { key: "control_points", .. }
        ));
        assert!(matches!(bad(&|v| v["weights"][2] = (-1.0).into()), SurfaceJsonError::Nurbs { key: "weights", .. }));
        assert!(matches!(
            bad(&|v| {
                v["weights"].as_array_mut().expect("array").push(1.0.into());
            }),
            SurfaceJsonError::Nurbs { key: "weights", .. }
        ));
        assert!(matches!(bad(&|v| v["control_points"][0] = "x".into()), SurfaceJsonError::Syntax { .. }));
        assert!(matches!(
            bad(&|v| v["control_points"][0][1] = serde_json::Value::Null),
            SurfaceJsonError::Syntax { .. }
        ));
        match read_surface_json("{\n  \"format\": \"hullskin-surface\",\n  \"version\": 1,,\n}") {
            Err(SurfaceJsonError::Syntax { line, .. }) => assert_eq!(line, 3),
            other => panic!("expected a syntax error, got {other:?}"),
        }
        // Numbers too large for f64 are refused, not turned into infinity.
        let huge = good.to_string().replacen("\"knots_u\":[0.0", "\"knots_u\":[1e999", 1);
        assert!(read_surface_json(&huge).is_err());
    }
}
