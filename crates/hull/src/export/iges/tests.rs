use super::super::sample_surface;
use super::*;
use nurbs::{assert_near, KnotVector};

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
    let text = write(&sample_surface(false, true), IgesUnits::METRE);
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
    let text = write(&sample_surface(false, true), IgesUnits::METRE);
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
    let text = write(&sample_surface(false, true), IgesUnits::METRE);
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
    let s = sample_surface(false, true);
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
    let s = sample_surface(false, true);
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
        crate::export::assert_resolution(r, size);
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
    write_iges(&mut out, &sample_surface(false, true), &meta).expect("writes");
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

/// The P fields of the entity whose directory entry starts at D record `d`.
fn entity_fields(text: &str, d: usize) -> Vec<String> {
    let data: String = section(text, 'P')
        .iter()
        .filter(|l| l[64..72].trim().parse::<usize>().expect("DE pointer") == d)
        .map(|l| &l[..64])
        .collect();
    split_fields(&data)
}

#[test]
fn curves_follow_the_surface_as_entity_126() {
    let s = sample_surface(false, true);
    let curves = section_curves(&s, &[-1.0, 0.5, 2.0]);
    assert_eq!(curves.len(), 3);
    let meta = IgesMeta::new(IgesUnits::METRE, "c.igs", "20240102.030405");
    let mut out = Vec::new();
    write_iges_model(&mut out, Some(&s), &curves, &meta).expect("writes");
    let text = String::from_utf8(out).expect("ASCII");
    assert!(text.lines().all(|l| l.len() == 80));
    let d = section(&text, 'D');
    assert_eq!(d.len(), 8);
    let field = |line: &str, k: usize| line[8 * k..8 * k + 8].trim().to_string();
    // Each entry's P pointer and count tile the P section in order.
    let mut next = 1;
    for k in 0..4 {
        assert_eq!(field(d[2 * k], 0), if k == 0 { "128" } else { "126" });
        assert_eq!(field(d[2 * k], 1).parse::<usize>().expect("pointer"), next);
        next += field(d[2 * k + 1], 3).parse::<usize>().expect("count");
        assert_eq!(field(d[2 * k + 1], 7), if k == 0 { "SURFACE" } else { "SECTION" });
        assert_eq!(field(d[2 * k + 1], 8), k.to_string());
    }
    assert_eq!(next - 1, section(&text, 'P').len());
    // The surface's fields are unchanged by the curves.
    let mut alone = Vec::new();
    write_iges(&mut alone, &s, &meta).expect("writes");
    assert_eq!(entity_fields(&text, 1), p_fields(&String::from_utf8(alone).expect("ASCII")));
    for (k, c) in curves.iter().enumerate() {
        let f = entity_fields(&text, 2 * k + 3);
        let n = c.num_control_points();
        let ints: Vec<i64> = f[..7].iter().map(|x| x.parse().expect("integer")).collect();
        // The sample's iso-curves are neither closed nor polynomial.
        let planar = i64::from(plane_normal(&c.control_points()).is_some());
        assert_eq!(ints, [126, n as i64 - 1, c.degree() as i64, planar, 0, 0, 0], "curve {k}");
        let nums: Vec<f64> = f[7..].iter().map(|x| num(x)).collect();
        let knots = c.knots().as_slice();
        assert_eq!(nums.len(), knots.len() + 4 * n + 5);
        assert_eq!(&nums[..knots.len()], knots);
        assert_eq!(&nums[knots.len()..knots.len() + n], c.weights().as_slice());
        for (i, p) in c.control_points().iter().enumerate() {
            assert_eq!(nums[knots.len() + n + 3 * i..][..3], [p.x, p.y, p.z]);
        }
        assert_eq!(nums[nums.len() - 5..nums.len() - 3], [0.0, 1.0]);
        let normal = plane_normal(&c.control_points()).unwrap_or(Vec3::new(0.0, 0.0, 0.0));
        assert_eq!(nums[nums.len() - 3..], [normal.x, normal.y, normal.z]);
    }
}

#[test]
fn curves_alone_and_nothing_at_all() {
    let s = sample_surface(false, true);
    let curves = section_curves(&s, &[0.0, 1.0]);
    let meta = IgesMeta::new(IgesUnits::METRE, "c.igs", "20240102.030405");
    let mut out = Vec::new();
    write_iges_model(&mut out, None, &curves, &meta).expect("writes");
    let text = String::from_utf8(out).expect("ASCII");
    let d = section(&text, 'D');
    assert_eq!(d.len(), 4);
    assert!(d.iter().all(|l| l[..8].trim() == "126"));
    let start: String = section(&text, 'S').iter().map(|l| &l[..72]).collect();
    assert!(start.contains("2 IGES 5.3 rational B-spline curves (entity 126)"), "{start}");
    let err = write_iges_model(&mut Vec::new(), None, &[], &meta).expect_err("nothing to write");
    assert_eq!(err.kind(), io::ErrorKind::InvalidInput);
}

#[test]
fn planar_curves_carry_their_normal() {
    // A section in the plane x = 3: planar, normal +-x.
    let k = KnotVector::uniform(2, 4).expect("valid");
    let pts = [Vec3::new(3.0, 0.0, 0.0), Vec3::new(3.0, 1.0, 0.2), Vec3::new(3.0, 2.0, 1.0), Vec3::new(3.0, 2.1, 3.0)];
    let c = NurbsCurve::try_new(k, &pts, None).expect("valid");
    let n = plane_normal(&pts).expect("planar");
    assert!((n.x.abs() - 1.0).abs() < 1e-15 && n.y.abs() < 1e-15 && n.z.abs() < 1e-15);
    let f = curve_fields(&c).expect("fields");
    assert_eq!(&f[3..6], ["1", "0", "1"]);
    assert_eq!(num(&f[f.len() - 3]).abs(), 1.0);
    // Collinear and skew points have no plane.
    assert!(plane_normal(&[Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0), Vec3::new(2.0, 2.0, 2.0)]).is_none());
    let skew = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, 1.0)];
    assert!(plane_normal(&skew).is_none());
}

#[test]
fn section_parameters_and_collapsed_sections() {
    assert_eq!(section_parameters(&[vec![(0.0, 0.25), (1.0, 0.25)], vec![], vec![(0.5, 1.0)]]), [0.25, 1.0]);
    // A surface whose v = 1 column collapses to one point: that iso-curve is left out.
    let ku = KnotVector::uniform(1, 3).expect("valid");
    let kv = KnotVector::uniform(1, 2).expect("valid");
    let pts: Vec<Vec3> = (0..3).flat_map(|i| [Vec3::new(0.0, i as f64, 0.0), Vec3::new(5.0, 0.0, 0.0)]).collect();
    let s = NurbsSurface::try_new(ku, kv, &pts, None).expect("valid");
    assert_eq!(section_curves(&s, &[0.0, 0.5, 1.0]).len(), 2);
    // Greville abscissae of a clamped cubic: the ends and the knot averages.
    let g = greville_v(&sample_surface(false, true));
    assert_eq!(g.len(), sample_surface(false, true).n_v());
    assert_eq!((g[0], g[g.len() - 1]), (-1.0, 2.0));
    assert!(g.windows(2).all(|w| w[0] < w[1]));
}

#[test]
fn timestamps() {
    assert_eq!(iges_timestamp(0), "19700101.000000");
    assert_eq!(iges_timestamp(1_000_000_000), "20010909.014640");
    // 2000-02-29 23:59:59 UTC, a leap day in a year divisible by 400.
    assert_eq!(iges_timestamp(951_868_799), "20000229.235959");
    assert_eq!(iges_timestamp(-1), "19691231.235959");
}
