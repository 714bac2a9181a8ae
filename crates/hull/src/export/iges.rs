//! IGES 5.3 export of one NURBS surface as a Rational B-Spline Surface entity (type 128),
//! optionally with curves (the skinned sections) as Rational B-Spline Curve entities (type 126).
//!
//! The rest of this module's documentation is on [`write_iges`], where the library's users read it.

use std::io::{self, Write};

use nurbs::{NurbsCurve, NurbsSurface, Vec3};

use crate::float::real;

/// Units as IGES names them: the global-section units flag (field 14) and units name
/// (field 15), e.g. `6`/`"M"` or `2`/`"MM"` (IGES 5.3 section 2.2.4.3, table 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IgesUnits {
    pub flag: u8,
    pub name: &'static str,
}

impl IgesUnits {
    pub const INCH: IgesUnits = IgesUnits { flag: 1, name: "INCH" };
    pub const MILLIMETRE: IgesUnits = IgesUnits { flag: 2, name: "MM" };
    pub const FOOT: IgesUnits = IgesUnits { flag: 4, name: "FT" };
    pub const METRE: IgesUnits = IgesUnits { flag: 6, name: "M" };
}

impl From<crate::Units> for IgesUnits {
    fn from(units: crate::Units) -> Self {
        IgesUnits { flag: units.iges_flag(), name: units.iges_name() }
    }
}

/// What the global and start sections say about the file. All strings are written as
/// Hollerith constants; characters outside printable ASCII become `?` and each string is cut
/// to [`MAX_STRING_LEN`] characters so it fits one record.
#[derive(Clone, Debug, PartialEq)]
pub struct IgesMeta {
    pub units: IgesUnits,
    /// Global field 3 (and 12): the product the file describes.
    pub product_id: String,
    /// Global field 4: the file's name.
    pub file_name: String,
    /// Global field 5: the sending system.
    pub system_id: String,
    /// Global field 6: the sending system's version.
    pub preprocessor_version: String,
    pub author: String,
    pub organization: String,
    /// Global fields 18 and 25, IGES layout `YYYYMMDD.HHNNSS`; see [`iges_timestamp`].
    /// Passed in (not read from the clock) so output is reproducible.
    pub timestamp: String,
}

impl IgesMeta {
    /// Metadata with the system id `hullskin`, this crate's version, and empty author and
    /// organisation.
    pub fn new(units: IgesUnits, file_name: &str, timestamp: &str) -> Self {
        IgesMeta {
            units,
            product_id: "hull surface".to_string(),
            file_name: file_name.to_string(),
            system_id: "hullskin".to_string(),
            preprocessor_version: env!("CARGO_PKG_VERSION").to_string(),
            author: String::new(),
            organization: String::new(),
            timestamp: timestamp.to_string(),
        }
    }
}

/// Longest Hollerith string written (longer ones are cut), so every string fits one
/// 72-column global record with its `nnH` prefix and delimiter.
pub const MAX_STRING_LEN: usize = 64;

/// IGES date layout `YYYYMMDD.HHNNSS` (UTC) of a Unix time in seconds, e.g.
/// `1_000_000_000 -> "20010909.014640"`. Civil date from the day count by H. Hinnant's
/// `civil_from_days` algorithm (proleptic Gregorian calendar).
pub fn iges_timestamp(unix_seconds: i64) -> String {
    let (year, month, day, h, m, s) = civil_time(unix_seconds);
    format!("{year:04}{month:02}{day:02}.{h:02}{m:02}{s:02}")
}

/// `(year, month, day, hour, minute, second)` (UTC) of a Unix time in seconds, by
/// H. Hinnant's `civil_from_days` (proleptic Gregorian calendar).
pub(crate) fn civil_time(unix_seconds: i64) -> (i64, i64, i64, i64, i64, i64) {
    let days = unix_seconds.div_euclid(86_400);
    let secs = unix_seconds.rem_euclid(86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day, secs / 3600, secs / 60 % 60, secs % 60)
}

/// Columns of data in an S or G record, and in a P record.
const SG_WIDTH: usize = 72;
const P_WIDTH: usize = 64;
/// Largest sequence number that fits columns 74-80.
const MAX_SEQUENCE: usize = 9_999_999;

/// Write `surface` as an IGES 5.3 file holding one entity 128 (see below for the
/// exact layout).
///
/// The file has the five fixed-format sections of IGES 5.3 (ANS US PRO/IPO-100-1996,
/// chapter 2), every record 80 columns, the section letter in column 73 and the sequence
/// number right-justified in columns 74-80:
///
/// * **S** (start): a human-readable line.
/// * **G** (global): parameter delimiter `,`, record delimiter `;`, product id, file name,
///   native system, preprocessor version, integer/float limits, model space scale `1.0`,
///   units flag and units name, line weights, date, minimum resolution
///   (`10^floor(log10(1e-7 * size))`, `size` the diagonal of the control-net box), maximum
///   coordinate (the largest `|x|`, `|y|`, `|z|` of the control points, which bound the
///   surface), author, organisation, version flag `11` (5.3), drafting standard `0`, and the
///   model date. Strings are Hollerith constants `nH...`.
/// * **D** (directory): one entry of two records for entity 128, form 0, status `00000000`.
/// * **P** (parameter data, section 4.24 of the standard), in columns 1-64, the directory
///   pointer in columns 65-72, records split only between fields:
///   `128, K1, K2, M1, M2, PROP1..PROP5, S(-M1)..S(N1+M1), T(-M2)..T(N2+M2),
///   W(0,0)..W(K1,K2), X(0,0), Y(0,0), Z(0,0) .. Z(K1,K2), U(0), U(1), V(0), V(1);`
///   with `K1 = n_u - 1`, `M1 = p` (likewise in v), PROP1/PROP2 = closed in u/v (first and last
///   control rows identical), PROP3 = 1 (polynomial) only when all weights are equal,
///   PROP4/PROP5 = 0 (not periodic). Weights and points run with the **first (u) index fastest**,
///   `for j in 0..n_v { for i in 0..n_u }`, the transpose of the kernel's u-major storage
///   `i * n_v + j`. The last four numbers are the parameter ranges `[U(0), U(1)] x [V(0), V(1)]`,
///   the knot-vector domains (readers trim the surface to them).
/// * With curves ([`write_iges_model`]), each curve follows as one more directory entry (D
///   records `2k + 1` and `2k + 2`) and its parameter records (section 4.23):
///   `126, K, M, PROP1..PROP4, T(-M)..T(N+M), W(0)..W(K), X(0), Y(0), Z(0) .. Z(K), V(0), V(1),
///   XNORM, YNORM, ZNORM;` (see `curve_fields`); every P record points back to its entity's
///   first D record, and the global section's maximum coordinate and resolution cover the
///   curves too.
/// * **T** (terminate): the record counts of S, G, D and P.
///
/// Reals are written by [`crate::float::real`] (shortest round-trip, always with a decimal
/// point), so the file carries the surface bit for bit.
///
/// # Errors
/// Whatever `w` returns; [`io::ErrorKind::InvalidData`] if a number is not finite (cannot
/// happen for a surface built by the kernel's validating constructors);
/// [`io::ErrorKind::InvalidInput`] if the surface needs more than 9,999,999 parameter
/// records (about 2.5 million control points).
pub fn write_iges<W: Write>(w: &mut W, surface: &NurbsSurface, meta: &IgesMeta) -> io::Result<()> {
    write_iges_model(w, Some(surface), &[], meta)
}

/// Write an IGES 5.3 file holding `surface` as entity 128 (when given) followed by every curve
/// of `curves` as a rational B-spline curve, entity 126 (see [`write_iges`]). Directory
/// entries are numbered 1, 3, 5, .. in that order; the surface is labelled `SURFACE`, the
/// curves `SECTION` with subscripts 1, 2, ...
///
/// # Errors
/// As [`write_iges`]; also [`io::ErrorKind::InvalidInput`] if there is nothing to write.
pub fn write_iges_model<W: Write>(
    w: &mut W,
    surface: Option<&NurbsSurface>,
    curves: &[NurbsCurve],
    meta: &IgesMeta,
) -> io::Result<()> {
    struct Entity {
        kind: u32,
        label: &'static str,
        subscript: usize,
        params: Vec<String>,
    }
    let mut entities = Vec::new();
    if let Some(s) = surface {
        entities.push(Entity {
            kind: 128,
            label: "SURFACE",
            subscript: 0,
            params: pack_fields(&parameter_fields(s)?, P_WIDTH),
        });
    }
    for (k, c) in curves.iter().enumerate() {
        entities.push(Entity {
            kind: 126,
            label: "SECTION",
            subscript: k + 1,
            params: pack_fields(&curve_fields(c)?, P_WIDTH),
        });
    }
    if entities.is_empty() {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "nothing to write: no surface and no curve"));
    }
    let what = match (surface.is_some(), curves.len()) {
        (true, 0) => "one IGES 5.3 rational B-spline surface (entity 128)".to_string(),
        (true, n) => {
            format!("one IGES 5.3 rational B-spline surface (entity 128) and {n} rational B-spline curves (entity 126)")
        }
        (false, n) => format!("{n} IGES 5.3 rational B-spline curves (entity 126)"),
    };
    let start = wrap_text(
        &format!("{} {}: {} written as {what}.", meta.system_id, meta.preprocessor_version, meta.product_id),
        SG_WIDTH,
    );
    let (lo, hi) = model_bounds(surface, curves);
    let global = pack_fields(&global_fields(lo, hi, meta)?, SG_WIDTH);
    let p_total: usize = entities.iter().map(|e| e.params.len()).sum();
    if p_total > MAX_SEQUENCE || 2 * entities.len() > MAX_SEQUENCE {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("the model needs {p_total} IGES parameter records; sequence numbers stop at {MAX_SEQUENCE}"),
        ));
    }

    for (k, text) in start.iter().enumerate() {
        writeln!(w, "{text:<72}S{:>7}", k + 1)?;
    }
    for (k, text) in global.iter().enumerate() {
        writeln!(w, "{text:<72}G{:>7}", k + 1)?;
    }
    // Directory entries: 20 fields of 8 columns over two records (IGES 5.3 section 2.2.4.4).
    let status = "00000000"; // visible, independent, geometry, global top-down
    let mut first_p = 1;
    for (k, e) in entities.iter().enumerate() {
        let d = 2 * k + 1;
        writeln!(
            w,
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
            e.kind, first_p, 0, 0, 0, 0, 0, 0, status, d
        )?;
        writeln!(
            w,
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
            e.kind,
            0,
            0,
            e.params.len(),
            0,
            "",
            "",
            e.label,
            e.subscript,
            d + 1
        )?;
        first_p += e.params.len();
    }
    let mut seq = 0;
    for (k, e) in entities.iter().enumerate() {
        for text in &e.params {
            seq += 1;
            writeln!(w, "{text:<64}{:>8}P{seq:>7}", 2 * k + 1)?;
        }
    }
    let counts = format!("S{:>7}G{:>7}D{:>7}P{:>7}", start.len(), global.len(), 2 * entities.len(), p_total);
    writeln!(w, "{counts:<72}T{:>7}", 1)?;
    Ok(())
}

/// Box of every control point of the surface and the curves.
fn model_bounds(surface: Option<&NurbsSurface>, curves: &[NurbsCurve]) -> (Vec3, Vec3) {
    let inf = f64::INFINITY;
    let (mut lo, mut hi) = (Vec3::new(inf, inf, inf), Vec3::new(-inf, -inf, -inf));
    let mut add = |p: Vec3| {
        lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
        hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
    };
    if let Some(s) = surface {
        let (a, b) = s.control_bounds();
        add(a);
        add(b);
    }
    for c in curves {
        c.control_points().into_iter().for_each(&mut add);
    }
    (lo, hi)
}

/// The global-section fields, each already formatted, in order 1..=25.
fn global_fields(lo: Vec3, hi: Vec3, meta: &IgesMeta) -> io::Result<Vec<String>> {
    let max_coord = [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z].iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let size = (hi - lo).norm();
    let exponent = super::resolution_exponent(size);
    let power_of_ten = super::power_of_ten;
    let resolution = power_of_ten(exponent);
    let date = hollerith(&meta.timestamp);
    Ok(vec![
        hollerith(","),
        hollerith(";"),
        hollerith(&meta.product_id),
        hollerith(&meta.file_name),
        hollerith(&meta.system_id),
        hollerith(&meta.preprocessor_version),
        "32".into(),  // bits of an integer
        "38".into(),  // max power of ten, single precision
        "6".into(),   // significant digits, single precision
        "308".into(), // max power of ten, double precision
        "15".into(),  // significant digits, double precision
        hollerith(&meta.product_id),
        real(1.0)?, // model space scale
        meta.units.flag.to_string(),
        hollerith(meta.units.name),
        "1".into(),                        // line weight gradations
        real(power_of_ten(exponent + 3))?, // width of the maximum line weight
        date.clone(),
        real(resolution)?,
        real(max_coord)?,
        hollerith(&meta.author),
        hollerith(&meta.organization),
        "11".into(), // IGES 5.3
        "0".into(),  // no drafting standard
        date,        // model creation/modification date
    ])
}

/// The parameter-data fields of entity 128 (IGES 5.3 section 4.24), in order.
fn parameter_fields(s: &NurbsSurface) -> io::Result<Vec<String>> {
    let (nu, nv) = (s.n_u(), s.n_v());
    let h = s.homogeneous();
    let w0 = h[0][3];
    let polynomial = h.iter().all(|c| c[3] == w0);
    let closed_u = (0..nv).all(|j| h[j] == h[(nu - 1) * nv + j]);
    let closed_v = (0..nu).all(|i| h[i * nv] == h[i * nv + nv - 1]);
    let flag = |b: bool| if b { "1".to_string() } else { "0".to_string() };
    let mut f = vec![
        "128".to_string(),
        (nu - 1).to_string(),
        (nv - 1).to_string(),
        s.degree_u().to_string(),
        s.degree_v().to_string(),
        flag(closed_u),
        flag(closed_v),
        flag(polynomial),
        "0".into(),
        "0".into(),
    ];
    for &k in s.knots_u().as_slice().iter().chain(s.knots_v().as_slice()) {
        f.push(real(k)?);
    }
    // IGES order: the u index i varies fastest.
    let order = || (0..nv).flat_map(move |j| (0..nu).map(move |i| i * nv + j));
    for k in order() {
        f.push(real(h[k][3])?);
    }
    let points = s.control_points();
    for k in order() {
        let p = points[k];
        for c in [p.x, p.y, p.z] {
            f.push(real(c)?);
        }
    }
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    for x in [u0, u1, v0, v1] {
        f.push(real(x)?);
    }
    Ok(f)
}

/// The parameter-data fields of entity 126 (IGES 5.3 section 4.23), in order:
/// `126, K, M, PROP1..PROP4, T(-M)..T(N+M), W(0)..W(K), X(0), Y(0), Z(0) .. Z(K), V(0), V(1),
/// XNORM, YNORM, ZNORM` with `K = n - 1`, `M = p`, PROP1 = planar (every control point within
/// `1e-9` of the polygon's size of one plane, whose unit normal ends the list; `0, 0, 0`
/// otherwise), PROP2 = closed (first and last control points equal), PROP3 = polynomial (all
/// weights equal), PROP4 = 0 (not periodic), and `[V(0), V(1)]` the knot domain.
fn curve_fields(c: &NurbsCurve) -> io::Result<Vec<String>> {
    let h = c.homogeneous();
    let n = h.len();
    let polynomial = h.iter().all(|x| x[3] == h[0][3]);
    let pts = c.control_points();
    let closed = h[0] == h[n - 1];
    let normal = plane_normal(&pts);
    let flag = |b: bool| if b { "1".to_string() } else { "0".to_string() };
    let mut f = vec![
        "126".to_string(),
        (n - 1).to_string(),
        c.degree().to_string(),
        flag(normal.is_some()),
        flag(closed),
        flag(polynomial),
        "0".into(),
    ];
    for &k in c.knots().as_slice() {
        f.push(real(k)?);
    }
    for x in h {
        f.push(real(x[3])?);
    }
    for p in &pts {
        for x in [p.x, p.y, p.z] {
            f.push(real(x)?);
        }
    }
    let (t0, t1) = c.domain();
    let nrm = normal.unwrap_or(Vec3::new(0.0, 0.0, 0.0));
    for x in [t0, t1, nrm.x, nrm.y, nrm.z] {
        f.push(real(x)?);
    }
    Ok(f)
}

/// Unit normal of the plane holding every point of `pts` within `1e-9` of their spread, or
/// `None` if they are not planar or are collinear. The plane passes through the centroid `c`
/// and is spanned by `a - c` (`a` the point farthest from `c`) and the point `b` farthest from
/// that line.
fn plane_normal(pts: &[Vec3]) -> Option<Vec3> {
    let c = pts.iter().fold(Vec3::new(0.0, 0.0, 0.0), |s, &p| s + p) * (1.0 / pts.len() as f64);
    let a = *pts.iter().max_by(|p, q| p.distance(c).total_cmp(&q.distance(c)))?;
    let spread = a.distance(c);
    let b = *pts.iter().max_by(|p, q| (**p - c).cross(a - c).norm().total_cmp(&(**q - c).cross(a - c).norm()))?;
    let n = (a - c).cross(b - c);
    if !(n.norm() > 1e-9 * spread * spread) {
        return None;
    }
    let n = n.normalized()?;
    pts.iter().all(|&p| (p - c).dot(n).abs() <= 1e-9 * spread).then_some(n)
}

/// The iso-curves `C_k(u) = S(u, v_k)` at each of `vs` (exact, [`NurbsSurface::iso_curve_u`]):
/// the skinned sections when `vs` are the sections' parameters ([`section_parameters`]).
/// Curves that collapse to a point (every control point within `1e-12` of the surface's
/// size of the first: a pointed stem) are left out, as IGES cannot hold them as entity 126.
pub fn section_curves(surface: &NurbsSurface, vs: &[f64]) -> Vec<NurbsCurve> {
    let (lo, hi) = surface.control_bounds();
    let tol = 1e-12 * (hi - lo).norm();
    vs.iter()
        .map(|&v| surface.iso_curve_u(v))
        .filter(|c| {
            let pts = c.control_points();
            pts.iter().any(|p| p.distance(pts[0]) > tol)
        })
        .collect()
}

/// The v parameter of every section of a fit: the mean of its offsets' v (they share one v
/// when the sections were interpolated). Empty sections are skipped.
pub fn section_parameters(params: &[Vec<(f64, f64)>]) -> Vec<f64> {
    params.iter().filter(|p| !p.is_empty()).map(|p| p.iter().map(|uv| uv.1).sum::<f64>() / p.len() as f64).collect()
}

/// The Greville abscissae of the v knots, `v_j = (v_(j+1) + .. + v_(j+q)) / q` (de Boor, *A
/// Practical Guide to Splines*, the node values): one parameter per control column, near
/// where each column acts most; stand-ins for the section parameters when only the surface is
/// known.
pub fn greville_v(surface: &NurbsSurface) -> Vec<f64> {
    let q = surface.degree_v();
    let k = surface.knots_v().as_slice();
    (0..surface.n_v()).map(|j| k[j + 1..=j + q].iter().sum::<f64>() / q as f64).collect()
}

/// `nH...` with non-printable-ASCII characters replaced by `?` and the string cut to
/// [`MAX_STRING_LEN`]; an empty string is an empty (defaulted) field.
fn hollerith(s: &str) -> String {
    let clean: String =
        s.chars().map(|c| if c.is_ascii_graphic() || c == ' ' { c } else { '?' }).take(MAX_STRING_LEN).collect();
    if clean.is_empty() {
        String::new()
    } else {
        format!("{}H{clean}", clean.len())
    }
}

/// Join fields with `,`, end with `;`, and break into records of at most `width` columns,
/// only between fields (so no number or string is split across records). Every field is
/// shorter than `width` (reals at most 24 characters, strings at most 67).
fn pack_fields(fields: &[String], width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for (k, field) in fields.iter().enumerate() {
        let delimiter = if k + 1 == fields.len() { ';' } else { ',' };
        if !line.is_empty() && line.len() + field.len() + 1 > width {
            lines.push(std::mem::take(&mut line));
        }
        line.push_str(field);
        line.push(delimiter);
    }
    lines.push(line);
    lines
}

/// Break free text into records of at most `width` characters (printable ASCII only).
fn wrap_text(text: &str, width: usize) -> Vec<String> {
    let clean: Vec<char> = text.chars().map(|c| if c.is_ascii_graphic() || c == ' ' { c } else { '?' }).collect();
    clean.chunks(width).map(|c| c.iter().collect()).collect()
}

#[cfg(test)]
mod tests;
