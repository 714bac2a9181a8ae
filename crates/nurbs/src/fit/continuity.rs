//! Continuity at a knot, and joining the knot vectors of pieces.
//!
//! A B-spline of degree `p` is `C^{p-m}` at a knot of multiplicity `m` (The NURBS Book 2.3,
//! property P2.5), so a knot of multiplicity `m = p` leaves it only `C^0`: the tangent may
//! jump, and the curve passes through the one control point whose basis function is 1 there
//! (P2.2, `N_{i,p}(u_i) = 1` at a knot of multiplicity `p`). A knot of multiplicity `p - 1`
//! keeps the tangent and frees the curvature ([`Continuity`], [`knot_multiplicity`]).

use crate::{KnotVector, NurbsError};

/// The continuity kept at a feature of a section.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Continuity {
    /// Position only: a knuckle or chine, where the tangent jumps.
    C0,
    /// Position and tangent: the end of a flat (a straight run) where the curvature jumps.
    C1,
}

/// The multiplicity of the interior knot that gives `continuity` to a B-spline of degree
/// `degree >= 1`: `p - k` for `C^k` (The NURBS Book P2.5), i.e. `p` for a knuckle and `p - 1`
/// for a tangent-continuous join, at least 1.
pub fn knot_multiplicity(degree: usize, continuity: Continuity) -> usize {
    let k = match continuity {
        Continuity::C0 => 0,
        Continuity::C1 => 1,
    };
    degree.saturating_sub(k).max(1)
}

/// Join the knot vectors of consecutive pieces, each on its own domain, into one on `[0, 1]`:
/// piece `j` is mapped affinely onto `[breaks[j], breaks[j+1]]` (`breaks[0] = 0`, the last
/// 1), its interior knots kept, and each join gets multiplicity `p`, the degree shared by all
/// pieces (a `C^0` join: [`knot_multiplicity`] of [`Continuity::C0`]). With `N_j` basis
/// functions per piece the result has `sum N_j - (pieces - 1)` of them: the last control point
/// of a piece and the first of the next are one, the curve's point at the join (The NURBS
/// Book 5.3, knot removal in reverse: two clamped curves that meet join into one curve with a
/// knot of multiplicity `p` at the meeting point).
///
/// # Errors
/// [`NurbsError::Incompatible`] for no piece, pieces of different degrees or a breakpoint list
/// that does not strictly increase from 0 to 1 with one more entry than pieces.
///
/// ```
/// use nurbs::fit::{join_knot_vectors, knot_multiplicity, Continuity};
/// use nurbs::KnotVector;
/// // Two cubic pieces joined at 0.4: the join is a knot of multiplicity p = 3, a C0 corner.
/// let a = KnotVector::uniform(3, 4)?;
/// let b = KnotVector::uniform(3, 5)?;
/// let j = join_knot_vectors(&[a.clone(), b.clone()], &[0.0, 0.4, 1.0])?;
/// assert_eq!(j.multiplicity(0.4), knot_multiplicity(3, Continuity::C0));
/// assert_eq!(j.num_basis(), a.num_basis() + b.num_basis() - 1);
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn join_knot_vectors(pieces: &[KnotVector], breaks: &[f64]) -> Result<KnotVector, NurbsError> {
    let Some(first) = pieces.first() else {
        return Err(NurbsError::Incompatible { what: "joining knot vectors: no piece".into() });
    };
    let p = first.degree();
    if pieces.iter().any(|k| k.degree() != p) {
        return Err(NurbsError::Incompatible { what: "joining knot vectors of different degrees".into() });
    }
    let increasing = breaks.windows(2).all(|w| w[1] > w[0]);
    if breaks.len() != pieces.len() + 1 || !increasing || breaks[0] != 0.0 || breaks[pieces.len()] != 1.0 {
        return Err(NurbsError::Incompatible {
            what: format!(
                "joining {} knot vectors needs {} breakpoints increasing from 0 to 1, got {breaks:?}",
                pieces.len(),
                pieces.len() + 1
            ),
        });
    }
    let mut knots = vec![0.0; p + 1];
    for (j, kv) in pieces.iter().enumerate() {
        let (a, b) = (breaks[j], breaks[j + 1]);
        let (s, e) = kv.domain();
        let u = kv.as_slice();
        knots.extend(u[p + 1..u.len() - p - 1].iter().map(|&x| a + (x - s) / (e - s) * (b - a)));
        let end = if j + 1 == pieces.len() { p + 1 } else { p };
        knots.extend(std::iter::repeat_n(b, end));
    }
    KnotVector::try_new(p, knots)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joined_knots_have_multiplicity_p_at_the_breaks() {
        let a = KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0]).expect("valid");
        let b = KnotVector::uniform(3, 4).expect("valid");
        let j = join_knot_vectors(&[a.clone(), b.clone()], &[0.0, 0.4, 1.0]).expect("valid");
        assert_eq!(j.as_slice(), &[0.0, 0.0, 0.0, 0.0, 0.2, 0.4, 0.4, 0.4, 1.0, 1.0, 1.0, 1.0]);
        assert_eq!(j.multiplicity(0.4), knot_multiplicity(3, Continuity::C0));
        assert_eq!(j.num_basis(), a.num_basis() + b.num_basis() - 1);
        assert_eq!(knot_multiplicity(3, Continuity::C1), 2);
        assert_eq!(knot_multiplicity(1, Continuity::C1), 1);
        assert!(join_knot_vectors(&[a.clone(), b.clone()], &[0.0, 1.0]).is_err());
        assert!(join_knot_vectors(&[a.clone(), b], &[0.0, 0.0, 1.0]).is_err());
        assert!(join_knot_vectors(&[a, KnotVector::uniform(2, 3).expect("valid")], &[0.0, 0.5, 1.0]).is_err());
        assert!(join_knot_vectors(&[], &[0.0, 1.0]).is_err());
    }
}
