//! IGES 5.3 export of one NURBS surface as a Rational B-Spline Surface entity (type 128).
//!
//! The file has the five fixed-format sections of IGES 5.3 (ANS US PRO/IPO-100-1996,
//! chapter 2), every record 80 columns, the section letter in column 73 and the sequence
//! number right-justified in columns 74-80:
//!
//! * **S** (start): a human-readable line.
//! * **G** (global): parameter delimiter `,`, record delimiter `;`, product id, file name,
//!   native system, preprocessor version, integer/float limits, model space scale `1.0`,
//!   units flag and units name, line weights, date, minimum resolution
//!   (`10^floor(log10(1e-7 * size))`, `size` the diagonal of the control-net box), maximum
//!   coordinate (the largest `|x|`, `|y|`, `|z|` of the control points, which bound the
//!   surface), author, organisation, version flag `11` (5.3), drafting standard `0`, and the
//!   model date. Strings are Hollerith constants `nH...`.
//! * **D** (directory): one entry of two records for entity 128, form 0, status `00000000`.
//! * **P** (parameter data, section 4.24 of the standard), in columns 1-64, the directory
//!   pointer in columns 65-72, records split only between fields:
//!   `128, K1, K2, M1, M2, PROP1..PROP5, S(-M1)..S(N1+M1), T(-M2)..T(N2+M2),
//!   W(0,0)..W(K1,K2), X(0,0), Y(0,0), Z(0,0) .. Z(K1,K2), U(0), U(1), V(0), V(1);`
//!   with `K1 = n_u - 1`, `M1 = p` (likewise in v), PROP1/PROP2 = closed in u/v (first and last
//!   control rows identical), PROP3 = 1 (polynomial) only when all weights are equal,
//!   PROP4/PROP5 = 0 (not periodic). Weights and points run with the **first (u) index fastest**,
//!   `for j in 0..n_v { for i in 0..n_u }`, the transpose of the kernel's u-major storage
//!   `i * n_v + j`. The last four numbers are the parameter ranges `[U(0), U(1)] x [V(0), V(1)]`,
//!   the knot-vector domains (readers trim the surface to them).
//! * **T** (terminate): the record counts of S, G, D and P.
//!
//! Reals are written by [`super::float::real`] (shortest round-trip, always with a decimal
//! point), so the file carries the surface bit for bit.

use std::io::{self, Write};

use nurbs::NurbsSurface;

use super::float::real;

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
    format!("{year:04}{month:02}{day:02}.{:02}{:02}{:02}", secs / 3600, secs / 60 % 60, secs % 60)
}

/// Columns of data in an S or G record, and in a P record.
const SG_WIDTH: usize = 72;
const P_WIDTH: usize = 64;
/// Sequence number of the one directory entry, which every P record points back to.
const DE_POINTER: usize = 1;
/// Largest sequence number that fits columns 74-80.
const MAX_SEQUENCE: usize = 9_999_999;

/// Write `surface` as an IGES 5.3 file holding one entity 128 (see the module docs for the
/// exact layout).
///
/// # Errors
/// Whatever `w` returns; [`io::ErrorKind::InvalidData`] if a number is not finite (cannot
/// happen for a surface built by the kernel's validating constructors);
/// [`io::ErrorKind::InvalidInput`] if the surface needs more than 9,999,999 parameter
/// records (about 2.5 million control points).
pub fn write_iges<W: Write>(w: &mut W, surface: &NurbsSurface, meta: &IgesMeta) -> io::Result<()> {
    let start = wrap_text(
        &format!(
            "{} {}: {} written as one IGES 5.3 rational B-spline surface (entity 128).",
            meta.system_id, meta.preprocessor_version, meta.product_id
        ),
        SG_WIDTH,
    );
    let global = pack_fields(&global_fields(surface, meta)?, SG_WIDTH);
    let params = pack_fields(&parameter_fields(surface)?, P_WIDTH);
    if params.len() > MAX_SEQUENCE {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("surface needs {} IGES parameter records; sequence numbers stop at {MAX_SEQUENCE}", params.len()),
        ));
    }

    for (k, text) in start.iter().enumerate() {
        writeln!(w, "{text:<72}S{:>7}", k + 1)?;
    }
    for (k, text) in global.iter().enumerate() {
        writeln!(w, "{text:<72}G{:>7}", k + 1)?;
    }
    // Directory entry: 20 fields of 8 columns over two records (IGES 5.3 section 2.2.4.4).
    let status = "00000000"; // visible, independent, geometry, global top-down
    writeln!(w, "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}", 128, 1, 0, 0, 0, 0, 0, 0, status, 1)?;
    writeln!(
        w,
        "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
        128,
        0,
        0,
        params.len(),
        0,
        "",
        "",
        "SURFACE",
        0,
        2
    )?;
    for (k, text) in params.iter().enumerate() {
        writeln!(w, "{text:<64}{DE_POINTER:>8}P{:>7}", k + 1)?;
    }
    let counts = format!("S{:>7}G{:>7}D{:>7}P{:>7}", start.len(), global.len(), 2, params.len());
    writeln!(w, "{counts:<72}T{:>7}", 1)?;
    Ok(())
}

/// The global-section fields, each already formatted, in order 1..=25.
fn global_fields(surface: &NurbsSurface, meta: &IgesMeta) -> io::Result<Vec<String>> {
    let (lo, hi) = surface.control_bounds();
    let max_coord = [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z].iter().fold(0.0f64, |m, c| m.max(c.abs()));
    let size = (hi - lo).norm();
    let size = if size > 0.0 && size.is_finite() { size } else { 1.0 };
    let exponent = (1e-7 * size).log10().floor() as i32;
    // Parsed rather than `powi` so these are exactly the decimals 1.0E<e>.
    let power_of_ten = |e: i32| -> f64 { format!("1e{e}").parse().expect("a decimal power of ten parses") };
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
mod tests {
    use super::*;
    use nurbs::{assert_near, KnotVector, Vec3};

    /// A 5 x 4 control net, bicubic in u and quadratic in v, non-uniform knots, non-unit
    /// weights: every count differs between u and v, so a transposition error shows.
    fn sample_surface() -> NurbsSurface {
        let ku = KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0, 1.0]).expect("valid");
        let kv = KnotVector::try_new(2, vec![-1.0, -1.0, -1.0, 0.25, 2.0, 2.0, 2.0]).expect("valid");
        let (nu, nv) = (ku.num_basis(), kv.num_basis());
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                pts.push(Vec3::new(10.0 * i as f64, 1.5 * j as f64 + 0.1 * i as f64, 0.3 * (i * j) as f64 - 40.0));
                w.push(1.0 + 0.1 * i as f64 + 0.05 * j as f64);
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
    }

    fn write(s: &NurbsSurface, units: IgesUnits) -> String {
        let mut meta = IgesMeta::new(units, "test.igs", "20240102.030405");
        meta.author = "A. Author".into();
        meta.organization = "Org, Inc.; test".into();
        let mut out = Vec::new();
        write_iges(&mut out, s, &meta).expect("writes to memory");
        String::from_utf8(out).expect("IGES is ASCII")
    }

    fn section(text: &str, letter: char) -> Vec<&str> {
        text.lines().filter(|l| l.as_bytes().get(72) == Some(&(letter as u8))).collect()
    }

    /// Split free-format IGES parameters (`,` between fields, `;` at the end), understanding
    /// Hollerith strings `nH...` that may contain delimiters.
    fn split_fields(data: &str) -> Vec<String> {
        let b = data.as_bytes();
        let mut fields = Vec::new();
        let mut k = 0;
        loop {
            let start = k;
            while k < b.len() && b[k].is_ascii_digit() {
                k += 1;
            }
            if k < b.len() && b[k] == b'H' && k > start {
                let n: usize = data[start..k].parse().expect("Hollerith count");
                fields.push(data[start..k + 1 + n].to_string());
                k += 1 + n;
            } else {
                while k < b.len() && b[k] != b',' && b[k] != b';' {
                    k += 1;
                }
                fields.push(data[start..k].trim().to_string());
            }
            assert!(k < b.len(), "parameter data must end with ';': {data}");
            if b[k] == b';' {
                return fields;
            }
            k += 1;
        }
    }

    fn p_fields(text: &str) -> Vec<String> {
        split_fields(&section(text, 'P').iter().map(|l| &l[..64]).collect::<String>())
    }

    fn num(field: &str) -> f64 {
        field.parse().unwrap_or_else(|_| panic!("not a number: {field:?}"))
    }

    #[test]
    fn records_are_80_columns_in_order_with_counts() {
        let text = write(&sample_surface(), IgesUnits::METRE);
        let letters: String = text.lines().map(|l| char::from(l.as_bytes()[72])).collect();
        // Sections appear in the order S, G, D, P, T, each a contiguous block.
        let mut order: Vec<char> = letters.chars().collect();
        order.dedup();
        assert_eq!(order, ['S', 'G', 'D', 'P', 'T']);
        for letter in ['S', 'G', 'D', 'P', 'T'] {
            for (k, line) in section(&text, letter).iter().enumerate() {
                assert_eq!(line.len(), 80, "record {line:?}");
                assert!(line.is_ascii());
                assert_eq!(line[73..].trim_start().parse::<usize>().expect("sequence number"), k + 1, "{line}");
                assert_eq!(line[73..].len(), 7);
            }
        }
        let t = section(&text, 'T');
        assert_eq!(t.len(), 1);
        for (k, letter) in ['S', 'G', 'D', 'P'].into_iter().enumerate() {
            let field = &t[0][8 * k..8 * k + 8];
            assert_eq!(field.as_bytes()[0], letter as u8);
            assert_eq!(field[1..].trim().parse::<usize>().expect("count"), section(&text, letter).len());
        }
        assert_eq!(section(&text, 'D').len(), 2);
        assert!(text.ends_with('\n'));
    }

    #[test]
    fn directory_entry_fields() {
        let text = write(&sample_surface(), IgesUnits::METRE);
        let d = section(&text, 'D');
        let field = |line: &str, k: usize| line[8 * k..8 * k + 8].trim().to_string();
        assert_eq!(field(d[0], 0), "128");
        assert_eq!(field(d[0], 1), "1", "parameter data start at P record 1");
        assert_eq!(field(d[0], 8), "00000000");
        assert_eq!(field(d[1], 0), "128");
        assert_eq!(field(d[1], 3).parse::<usize>().expect("count"), section(&text, 'P').len());
        assert_eq!(field(d[1], 4), "0", "form 0");
    }

    #[test]
    fn parameter_records_split_between_fields_and_point_to_the_entry() {
        let text = write(&sample_surface(), IgesUnits::METRE);
        let p = section(&text, 'P');
        assert!(p.len() > 3, "the sample needs several records to test the split");
        for line in &p {
            let data = line[..64].trim_end();
            assert!(data.ends_with(',') || data.ends_with(';'), "record split inside a field: {line}");
            assert_eq!(line[64..72].trim(), "1");
        }
    }

    #[test]
    fn parameter_data_parse_back_to_the_surface() {
        let s = sample_surface();
        let text = write(&s, IgesUnits::METRE);
        let f = p_fields(&text);
        let (nu, nv, p, q) = (s.n_u(), s.n_v(), s.degree_u(), s.degree_v());
        let ints: Vec<i64> = f[..10].iter().map(|x| x.parse().expect("integer")).collect();
        assert_eq!(ints, [128, nu as i64 - 1, nv as i64 - 1, p as i64, q as i64, 0, 0, 0, 0, 0]);
        let nums: Vec<f64> = f[10..].iter().map(|x| num(x)).collect();
        let (ku, kv) = (s.knots_u().as_slice(), s.knots_v().as_slice());
        assert_eq!(nums.len(), ku.len() + kv.len() + 4 * nu * nv + 4);
        // Exact: shortest round-trip formatting loses nothing.
        assert_eq!(&nums[..ku.len()], ku);
        assert_eq!(&nums[ku.len()..ku.len() + kv.len()], kv);
        let w = &nums[ku.len() + kv.len()..][..nu * nv];
        let xyz = &nums[ku.len() + kv.len() + nu * nv..][..3 * nu * nv];
        for j in 0..nv {
            for i in 0..nu {
                let k = j * nu + i; // IGES: first index fastest
                assert_eq!(w[k], s.weight(i, j), "W({i},{j})");
                let c = s.control_point(i, j);
                assert_eq!([xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]], [c.x, c.y, c.z], "P({i},{j})");
            }
        }
        let ranges = &nums[nums.len() - 4..];
        assert_eq!(ranges, [0.0, 1.0, -1.0, 2.0]);
    }

    #[test]
    fn global_section_fields() {
        let s = sample_surface();
        for units in [IgesUnits::METRE, IgesUnits::MILLIMETRE, IgesUnits::FOOT, IgesUnits::INCH] {
            let text = write(&s, units);
            let g = split_fields(&section(&text, 'G').iter().map(|l| &l[..72]).collect::<String>());
            assert_eq!(g.len(), 25);
            assert_eq!(g[0], "1H,");
            assert_eq!(g[1], "1H;");
            assert_eq!(g[3], "8Htest.igs");
            assert_eq!(num(&g[12]), 1.0);
            assert_eq!(g[13], units.flag.to_string());
            assert_eq!(g[14], format!("{}H{}", units.name.len(), units.name));
            assert_eq!(g[17], "15H20240102.030405");
            assert_eq!(g[20], "9HA. Author");
            assert_eq!(g[21], "15HOrg, Inc.; test");
            assert_eq!(g[22], "11");
            assert_eq!(g[23], "0");
            // Largest |coordinate| of the control net: z = -40 at i = j = 0.
            let (lo, hi) = s.control_bounds();
            assert_near!(num(&g[19]), 40.0, 0.0);
            assert_near!(lo.z, -40.0, 0.0);
            // Resolution: a power of ten between 1e-7 and 1e-6 times the net's diagonal.
            let size = (hi - lo).norm();
            let r = num(&g[18]);
            assert!(r <= 1e-7 * size && r > 1e-8 * size, "resolution {r} for size {size}");
            assert_near!(r.log10(), r.log10().round(), 1e-12);
        }
    }

    #[test]
    fn polynomial_flag_only_for_equal_weights() {
        let ku = KnotVector::uniform(2, 4).expect("valid");
        let kv = KnotVector::uniform(1, 2).expect("valid");
        let pts: Vec<Vec3> = (0..8).map(|k| Vec3::new(k as f64, (k * k) as f64, 1.0)).collect();
        for (weights, polynomial) in
            [(vec![2.0; 8], "1"), (vec![1.0; 8], "1"), ((0..8).map(|k| 1.0 + k as f64).collect(), "0")]
        {
            let s = NurbsSurface::try_new(ku.clone(), kv.clone(), &pts, Some(&weights)).expect("valid");
            let f = p_fields(&write(&s, IgesUnits::METRE));
            assert_eq!(f[7], polynomial, "weights {weights:?}");
        }
    }

    #[test]
    fn closed_flags_follow_the_control_net() {
        // A full circle of control rows in u (first row = last row): closed in u, not in v.
        let ku = KnotVector::uniform(1, 4).expect("valid");
        let kv = KnotVector::uniform(1, 2).expect("valid");
        let ring = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (1.0, 0.0)];
        let pts: Vec<Vec3> = ring.iter().flat_map(|&(x, y)| [Vec3::new(x, y, 0.0), Vec3::new(x, y, 1.0)]).collect();
        let s = NurbsSurface::try_new(ku, kv, &pts, None).expect("valid");
        let f = p_fields(&write(&s, IgesUnits::METRE));
        assert_eq!((f[5].as_str(), f[6].as_str()), ("1", "0"));
    }

    #[test]
    fn strings_are_sanitized_and_cut() {
        assert_eq!(hollerith("Åsa"), "3H?sa");
        assert_eq!(hollerith(""), "");
        assert_eq!(hollerith(&"x".repeat(100)), format!("64H{}", "x".repeat(64)));
        let mut meta = IgesMeta::new(IgesUnits::METRE, &"long name ".repeat(20), "20240102.030405");
        meta.author = "é".repeat(80);
        let mut out = Vec::new();
        write_iges(&mut out, &sample_surface(), &meta).expect("writes");
        let text = String::from_utf8(out).expect("ASCII");
        assert!(text.lines().all(|l| l.len() == 80 && l.is_ascii()));
    }

    #[test]
    fn units_convert_to_the_constants() {
        assert_eq!(IgesUnits::from(crate::Units::Metre), IgesUnits::METRE);
        assert_eq!(IgesUnits::from(crate::Units::Millimetre), IgesUnits::MILLIMETRE);
        assert_eq!(IgesUnits::from(crate::Units::Foot), IgesUnits::FOOT);
        assert_eq!(IgesUnits::from(crate::Units::Inch), IgesUnits::INCH);
    }

    #[test]
    fn timestamps() {
        assert_eq!(iges_timestamp(0), "19700101.000000");
        assert_eq!(iges_timestamp(1_000_000_000), "20010909.014640");
        // 2000-02-29 23:59:59 UTC, a leap day in a year divisible by 400.
        assert_eq!(iges_timestamp(951_868_799), "20000229.235959");
        assert_eq!(iges_timestamp(-1), "19691231.235959");
    }
}
