//! Data parameters `t_0 < t_1 < ... < t_m` for fitting (The NURBS Book 9.2.1).
//!
//! With chord lengths `d_k = |Q_k - Q_{k-1}|`:
//! - uniform (eq. 9.3): `t_k = k / m`;
//! - chord length (eq. 9.4-9.5): `t_k = t_{k-1} + d_k / d`, `d = sum_k d_k`;
//! - centripetal (eq. 9.6, Lee 1989): as chord length with `sqrt(d_k)` in place of `d_k`;
//! - universal (Lim 1999, "Universal parametrization in constructing smoothly-connected
//!   B-spline surfaces", CAGD 16): `t_k` is where the basis function `N_{k,p}` of the *uniform*
//!   clamped knot vector with `m + 1` functions takes its maximum. It depends on the degree and
//!   the count only, and must be paired with that uniform knot vector (see
//!   [`crate::fit::knots_for_interpolation`]); the fit then reproduces the data
//!   parameterization's ideal: each point is interpolated where its control point has the
//!   most influence.
//!
//! Every kind returns `t_0 = 0` and `t_m = 1` exactly.

use std::fmt;
use std::str::FromStr;

use crate::basis::{ders_basis_funs, BasisRow};
use crate::knots::MAX_DEGREE;
use crate::tolerance::COINCIDENT_REL;
use crate::{KnotVector, NurbsError, Vec3};

/// How data parameters are chosen from the points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Parameterization {
    /// Equally spaced (eq. 9.3). Ignores the geometry; poor for unevenly spaced data.
    Uniform,
    /// Proportional to the chord lengths (eq. 9.5).
    ChordLength,
    /// Proportional to the square roots of the chord lengths (eq. 9.6): the usual best choice
    /// for data with sharp turns or uneven spacing.
    #[default]
    Centripetal,
    /// Maxima of the uniform B-spline basis functions (Lim 1999); pair with uniform knots.
    Universal,
}

impl Parameterization {
    /// The names accepted by [`FromStr`]: `uniform`, `chord`, `centripetal`, `universal`.
    pub const NAMES: [&'static str; 4] = ["uniform", "chord", "centripetal", "universal"];

    /// The position of the name in [`Parameterization::NAMES`].
    fn index(self) -> usize {
        match self {
            Parameterization::Uniform => 0,
            Parameterization::ChordLength => 1,
            Parameterization::Centripetal => 2,
            Parameterization::Universal => 3,
        }
    }

    /// The name parsed by [`FromStr`].
    pub fn name(self) -> &'static str {
        match self {
            Parameterization::Uniform => "uniform",
            Parameterization::ChordLength => "chord",
            Parameterization::Centripetal => "centripetal",
            Parameterization::Universal => "universal",
        }
    }
}

impl fmt::Display for Parameterization {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing a [`Parameterization`] name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownParameterization(pub String);

impl fmt::Display for UnknownParameterization {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown parameterization {:?}; expected one of {}", self.0, Parameterization::NAMES.join(", "))
    }
}

impl std::error::Error for UnknownParameterization {}

impl FromStr for Parameterization {
    type Err = UnknownParameterization;

    /// Parse `uniform`, `chord` (or `chord-length`, `chordlength`), `centripetal` or
    /// `universal`, ignoring ASCII case.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "uniform" => Ok(Parameterization::Uniform),
            "chord" | "chord-length" | "chordlength" | "chord_length" => Ok(Parameterization::ChordLength),
            "centripetal" => Ok(Parameterization::Centripetal),
            "universal" => Ok(Parameterization::Universal),
            _ => Err(UnknownParameterization(s.to_string())),
        }
    }
}

/// The parameterizations of a skinned surface, one per direction: `u` along the sections and
/// `v` across them.
///
/// The default is centripetal along the sections and chord length across them. Why: a
/// section may turn sharply (a tight arc or a corner), where centripetal parameters (eq. 9.6)
/// keep the interpolant from overshooting; across the sections the data are sections spread
/// along the length, and chord length (eq. 9.5) keeps the surface's speed across them
/// proportional to their spacing, so that a family with half-spaced sections at the ends is
/// not distorted. Measured on the nine tables of `tools/peers` (three exact surfaces, six ship
/// offset tables with every other section or row held out), chord length across the sections
/// lowered the error of the interpolating skin between the points on six tables (by 26 % in
/// RMS on the Series-60-like table, 21 % on the Series 60 table) and changed the other three
/// by less than 0.1 %, and it lowered the least-squares error by 15 % in the geometric mean.
/// Along the sections neither kind wins everywhere (chord length: 22 % less error on the Wigley
/// table, 9 % more on the 116 m cargo ship's); with centripetal parameters the skins
/// lost 5 of the 45 comparisons with the peer tools, with chord length 8.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SkinParameterization {
    /// Along the sections.
    pub u: Parameterization,
    /// Across the sections.
    pub v: Parameterization,
}

impl SkinParameterization {
    /// The same kind in both directions.
    pub const fn both(kind: Parameterization) -> Self {
        SkinParameterization { u: kind, v: kind }
    }

    /// `u` and `v` as named, e.g. `centripetal,chord`, or one name when they agree (the form
    /// [`FromStr`] reads back).
    pub fn name(self) -> &'static str {
        const N: usize = Parameterization::NAMES.len();
        // Every pair spelled out once, so that the name is a `&'static str` (it goes into
        // reports as is).
        const PAIRS: [[&str; N]; N] = [
            ["uniform", "uniform,chord", "uniform,centripetal", "uniform,universal"],
            ["chord,uniform", "chord", "chord,centripetal", "chord,universal"],
            ["centripetal,uniform", "centripetal,chord", "centripetal", "centripetal,universal"],
            ["universal,uniform", "universal,chord", "universal,centripetal", "universal"],
        ];
        PAIRS[self.u.index()][self.v.index()]
    }
}

impl Default for SkinParameterization {
    /// Centripetal along the sections, chord length across them.
    fn default() -> Self {
        SkinParameterization { u: Parameterization::Centripetal, v: Parameterization::ChordLength }
    }
}

impl From<Parameterization> for SkinParameterization {
    fn from(kind: Parameterization) -> Self {
        SkinParameterization::both(kind)
    }
}

impl fmt::Display for SkinParameterization {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SkinParameterization {
    type Err = UnknownParameterization;

    /// `KIND` (both directions) or `U,V` (along, across the sections), each a name accepted by
    /// [`Parameterization::from_str`].
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.split_once(',') {
            Some((u, v)) => Ok(SkinParameterization { u: u.parse()?, v: v.parse()? }),
            None => s.parse().map(SkinParameterization::both),
        }
    }
}

/// Data parameters in `[0, 1]` for `points` (The NURBS Book eq. 9.3-9.6; Lim 1999 for
/// [`Parameterization::Universal`], which uses `degree`; the other kinds ignore it).
///
/// # Errors
/// - [`NurbsError::TooFewPoints`] for fewer than 2 points, or for `Universal` fewer than
///   `degree + 1`;
/// - [`NurbsError::BadDegree`] for `Universal` with a degree outside `1..=MAX_DEGREE`;
/// - [`NurbsError::NonFinitePoint`] for a point with a NaN or infinite coordinate;
/// - [`NurbsError::CoincidentPoints`] if two consecutive points are closer than
///   [`COINCIDENT_REL`] times the polyline length (for every kind: the interpolant of such data
///   would have a cusp or a loop, and chord-based parameters would repeat).
///
/// ```
/// use nurbs::fit::{parameterize, Parameterization};
/// use nurbs::Vec3;
/// // Chords of 1, 2 and 1: chord-length parameters 0, 1/4, 3/4, 1 (eq. 9.5); centripetal ones
/// // follow the square roots of the chords (eq. 9.6).
/// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(1.0, 3.0, 0.0)];
/// assert_eq!(parameterize(&pts, Parameterization::ChordLength, 3)?, vec![0.0, 0.25, 0.75, 1.0]);
/// let c = parameterize(&pts, Parameterization::Centripetal, 3)?;
/// let s = 2.0 + 2f64.sqrt();
/// assert!((c[1] - 1.0 / s).abs() < 1e-15 && (c[2] - (1.0 + 2f64.sqrt()) / s).abs() < 1e-15);
/// // Points given twice are refused.
/// assert!(parameterize(&[pts[0], pts[0], pts[1]], Parameterization::ChordLength, 1).is_err());
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn parameterize(points: &[Vec3], kind: Parameterization, degree: usize) -> Result<Vec<f64>, NurbsError> {
    parameterize_labelled(points, kind, degree, "points")
}

/// [`parameterize`] with `what` naming the data in errors.
pub(crate) fn parameterize_labelled(
    points: &[Vec3],
    kind: Parameterization,
    degree: usize,
    what: &str,
) -> Result<Vec<f64>, NurbsError> {
    let n = points.len();
    if n < 2 {
        return Err(NurbsError::TooFewPoints { what: what.to_string(), needed: 2, got: n });
    }
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(NurbsError::NonFinitePoint { index });
    }
    let chords = chord_lengths(points);
    check_chords(&chords, what)?;
    match kind {
        Parameterization::Uniform => Ok(uniform_params(n)),
        Parameterization::ChordLength => Ok(accumulate(chords.iter().copied())),
        Parameterization::Centripetal => Ok(accumulate(chords.iter().map(|d| d.sqrt()))),
        Parameterization::Universal => universal_params(n, degree, what),
    }
}

/// `|Q_k - Q_{k-1}|` for `k = 1..=m`.
pub(crate) fn chord_lengths(points: &[Vec3]) -> Vec<f64> {
    points.windows(2).map(|w| w[1].distance(w[0])).collect()
}

/// Error if any chord is below `COINCIDENT_REL` times the total length (all zero included).
fn check_chords(chords: &[f64], what: &str) -> Result<(), NurbsError> {
    let total: f64 = chords.iter().sum();
    match chords.iter().position(|&d| d <= COINCIDENT_REL * total) {
        Some(index) => Err(NurbsError::CoincidentPoints { what: what.to_string(), index, next: index + 1 }),
        None => Ok(()),
    }
}

/// `t_k = k / m`, `m + 1 = n`.
pub(crate) fn uniform_params(n: usize) -> Vec<f64> {
    let m = (n - 1) as f64;
    (0..n).map(|k| if k + 1 == n { 1.0 } else { k as f64 / m }).collect()
}

/// Running sums of positive increments normalized to `[0, 1]`, the last exactly 1.
fn accumulate(increments: impl Iterator<Item = f64> + Clone) -> Vec<f64> {
    let total: f64 = increments.clone().sum();
    let mut t = Vec::with_capacity(increments.size_hint().0 + 1);
    t.push(0.0);
    let mut acc = 0.0;
    for d in increments {
        acc += d;
        t.push(acc / total);
    }
    if let Some(last) = t.last_mut() {
        *last = 1.0;
    }
    t
}

/// The universal parameters of Lim (1999): `t_k = argmax N_{k,p}(u)` on the uniform clamped
/// knot vector with `n` basis functions on `[0, 1]`.
///
/// By symmetry of that knot vector `N_{n-1-k}(u) = N_k(1 - u)`, so `t_{n-1-k} = 1 - t_k`; a
/// function whose support `[u_k, u_{k+p+1}]` has `p + 2` distinct equally spaced knots is a
/// translated cardinal B-spline, symmetric about the middle of its support, which is then its
/// maximum. The few functions near the clamped ends (at most `p - 1` on each side besides the
/// first, maximal at 0) are unimodal, and their maximum is found by bisection on the sign of
/// `N'_{k,p}` (A2.3) to the last bit.
///
/// # Errors
/// [`NurbsError::TooFewPoints`] if `n <= degree`, [`NurbsError::BadDegree`].
pub(crate) fn universal_params(n: usize, degree: usize, what: &str) -> Result<Vec<f64>, NurbsError> {
    if degree == 0 || degree > MAX_DEGREE {
        return Err(NurbsError::BadDegree { degree, max: MAX_DEGREE });
    }
    if n <= degree {
        return Err(NurbsError::TooFewPoints {
            what: format!("{what} (universal, degree {degree})"),
            needed: degree + 1,
            got: n,
        });
    }
    let kv = KnotVector::uniform(degree, n)?;
    let p = degree;
    let k = kv.as_slice();
    let mut t = vec![0.0; n];
    for i in 0..n {
        t[i] = if 2 * i + 1 == n {
            0.5
        } else if 2 * i + 1 > n {
            1.0 - t[n - 1 - i]
        } else if i == 0 {
            0.0
        } else if i >= p && i + p < n {
            0.5 * (k[i] + k[i + p + 1])
        } else {
            basis_maximum(&kv, i)
        };
    }
    t[n - 1] = 1.0;
    Ok(t)
}

/// Where the unimodal `N_{i,p}` is largest, by bisection on the sign of its derivative.
fn basis_maximum(kv: &KnotVector, i: usize) -> f64 {
    let p = kv.degree();
    let k = kv.as_slice();
    let slope = |u: f64| {
        let span = kv.find_span(u);
        let mut ders: [BasisRow; 2] = [[0.0; MAX_DEGREE + 1]; 2];
        ders_basis_funs(k, span, u, p, 1, &mut ders);
        // N_{i,p} is entry i - (span - p) of the row; outside the row it vanishes.
        match (i + p).checked_sub(span) {
            Some(j) if j <= p => ders[1][j],
            _ => 0.0,
        }
    };
    let (mut lo, mut hi) = (k[i], k[i + p + 1]);
    while hi - lo > f64::EPSILON * hi.abs().max(1.0) {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if slope(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The element-wise mean of several parameter vectors of equal length (The NURBS Book eq. 9.18:
/// `t_k = (1/K) sum_l t_k^l`, used by global surface interpolation and skinning so that all
/// sections share one parameter vector). The mean of strictly increasing vectors with equal end
/// values is strictly increasing with the same ends.
///
/// # Errors
/// [`NurbsError::TooFewPoints`] if `sections` is empty, [`NurbsError::Incompatible`] if the
/// lengths differ.
pub fn common_parameters(sections: &[Vec<f64>]) -> Result<Vec<f64>, NurbsError> {
    let first = sections.first().ok_or_else(|| NurbsError::TooFewPoints {
        what: "parameter vectors to average".into(),
        needed: 1,
        got: 0,
    })?;
    let n = first.len();
    if let Some((l, s)) = sections.iter().enumerate().find(|(_, s)| s.len() != n) {
        return Err(NurbsError::Incompatible {
            what: format!("parameter vector {l} has {} values, parameter vector 0 has {n}", s.len()),
        });
    }
    let k = sections.len() as f64;
    let mut t: Vec<f64> = (0..n).map(|i| sections.iter().map(|s| s[i]).sum::<f64>() / k).collect();
    // Keep the ends exact when every section has them (sum / K can round).
    if sections.iter().all(|s| s.first() == first.first()) {
        if let (Some(a), Some(&b)) = (t.first_mut(), first.first()) {
            *a = b;
        }
    }
    if sections.iter().all(|s| s.last() == first.last()) {
        if let (Some(a), Some(&b)) = (t.last_mut(), first.last()) {
            *a = b;
        }
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::basis::basis_funs;

    fn pts(xy: &[(f64, f64)]) -> Vec<Vec3> {
        xy.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect()
    }

    #[test]
    fn names_round_trip() {
        for name in Parameterization::NAMES {
            let k: Parameterization = name.parse().expect("known name");
            assert_eq!(k.to_string(), name);
        }
        assert_eq!("Chord-Length".parse::<Parameterization>(), Ok(Parameterization::ChordLength));
        assert!("foley".parse::<Parameterization>().is_err());
    }

    #[test]
    fn skin_parameterization_names_round_trip() {
        let kinds = Parameterization::NAMES.map(|n| n.parse::<Parameterization>().expect("known name"));
        for u in kinds {
            for v in kinds {
                let pair = SkinParameterization { u, v };
                let name = pair.name();
                assert_eq!(name.parse::<SkinParameterization>(), Ok(pair), "{name}");
                // One name when the directions agree, "u,v" otherwise.
                assert_eq!(name.contains(','), u != v, "{name}");
                assert!(name.starts_with(u.name()), "{name}");
            }
        }
        let one: SkinParameterization = "Chord-Length".parse().expect("one name");
        assert_eq!(one, SkinParameterization::both(Parameterization::ChordLength));
        let two: SkinParameterization = " centripetal , chord ".parse().expect("two names");
        assert_eq!(two, SkinParameterization::default());
        assert!("centripetal,foley".parse::<SkinParameterization>().is_err());
        assert!("centripetal,chord,uniform".parse::<SkinParameterization>().is_err());
    }

    #[test]
    fn chord_and_centripetal_follow_the_formulas() {
        // Chords 3, 4 (a 3-4-5 corner) and 9: total 16; square roots sqrt3, 2, 3.
        let q = pts(&[(0.0, 0.0), (3.0, 0.0), (3.0, 4.0), (3.0, 13.0)]);
        let c = parameterize(&q, Parameterization::ChordLength, 3).expect("valid");
        // Each value is one or two additions and a division: round-off below 1e-15.
        for (a, b) in c.iter().zip([0.0, 3.0 / 16.0, 7.0 / 16.0, 1.0]) {
            assert_near!(*a, b, 1e-15);
        }
        let s = 3f64.sqrt() + 5.0;
        let z = parameterize(&q, Parameterization::Centripetal, 3).expect("valid");
        for (a, b) in z.iter().zip([0.0, 3f64.sqrt() / s, (3f64.sqrt() + 2.0) / s, 1.0]) {
            assert_near!(*a, b, 1e-15);
        }
        let u = parameterize(&q, Parameterization::Uniform, 3).expect("valid");
        assert_eq!(u, vec![0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]);
    }

    #[test]
    fn universal_parameters_are_basis_maxima() {
        for p in 1..=5 {
            for n in p + 1..p + 9 {
                let t = universal_params(n, p, "test").expect("valid");
                let kv = KnotVector::uniform(p, n).expect("valid");
                assert_eq!((t[0], t[n - 1]), (0.0, 1.0));
                for i in 0..n {
                    // Symmetric about 1/2, strictly increasing.
                    assert_near!(t[i] + t[n - 1 - i], 1.0, 1e-15);
                    if i > 0 {
                        assert!(t[i] > t[i - 1], "p {p} n {n} t {t:?}");
                    }
                    // N_i is not larger a little to either side of t_i (it is a maximum); the
                    // step 1e-7 leaves a margin far above the bisection's last-bit accuracy.
                    let value = |u: f64| {
                        let span = kv.find_span(u);
                        let mut row = [0.0; MAX_DEGREE + 1];
                        basis_funs(kv.as_slice(), span, u, p, &mut row);
                        (i + p).checked_sub(span).filter(|&j| j <= p).map_or(0.0, |j| row[j])
                    };
                    let here = value(t[i]);
                    for u in [t[i] - 1e-7, t[i] + 1e-7] {
                        if (0.0..=1.0).contains(&u) {
                            assert!(value(u) <= here + 1e-15, "p {p} n {n} i {i}");
                        }
                    }
                }
            }
        }
        // Bezier case: the Bernstein polynomial B_{i,p} is largest at i/p.
        let t = universal_params(4, 3, "test").expect("valid");
        for (i, ti) in t.iter().enumerate() {
            assert_near!(*ti, i as f64 / 3.0, 1e-14);
        }
    }

    #[test]
    fn errors_name_the_fault() {
        let one = pts(&[(1.0, 2.0)]);
        assert!(matches!(
            parameterize(&one, Parameterization::ChordLength, 3),
            Err(NurbsError::TooFewPoints { needed: 2, got: 1, .. })
        ));
        let dup = pts(&[(0.0, 0.0), (1.0, 0.0), (1.0, 0.0), (2.0, 0.0)]);
        for kind in [Parameterization::Uniform, Parameterization::Centripetal, Parameterization::Universal] {
            assert!(matches!(parameterize(&dup, kind, 2), Err(NurbsError::CoincidentPoints { index: 1, next: 2, .. })));
        }
        let nan = pts(&[(0.0, 0.0), (f64::NAN, 0.0), (2.0, 0.0)]);
        assert!(matches!(
            parameterize(&nan, Parameterization::ChordLength, 2),
            Err(NurbsError::NonFinitePoint { index: 1 })
        ));
        let three = pts(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)]);
        assert!(matches!(
            parameterize(&three, Parameterization::Universal, 3),
            Err(NurbsError::TooFewPoints { needed: 4, got: 3, .. })
        ));
    }

    #[test]
    fn common_parameters_average() {
        let a = vec![0.0, 0.2, 1.0];
        let b = vec![0.0, 0.4, 1.0];
        let t = common_parameters(&[a.clone(), b]).expect("same length");
        assert_near!(t[1], 0.3, 1e-16);
        assert_eq!((t[0], t[2]), (0.0, 1.0));
        assert!(matches!(common_parameters(&[a, vec![0.0, 1.0]]), Err(NurbsError::Incompatible { .. })));
        assert!(common_parameters(&[]).is_err());
    }
}
