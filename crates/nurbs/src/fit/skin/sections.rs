//! The input of skinning, checked: sections with extent and degenerate (single-point)
//! sections, and their own parameters along `u`.

use super::SkinOptions;
use crate::fit::extent::{bounding_diagonal, has_extent};
use crate::fit::param::{parameterize_labelled, uniform_params};
use crate::fit::Parameterization;
use crate::{NurbsError, Vec3, MAX_DEGREE};

/// One section, checked and classified.
pub(super) enum Section<'a> {
    /// Distinct consecutive points (checked by the parameterization).
    Regular(&'a [Vec3]),
    /// All points at one place.
    Point(Vec3, usize),
}

impl Section<'_> {
    pub(super) fn len(&self) -> usize {
        match self {
            Section::Regular(s) => s.len(),
            Section::Point(_, n) => *n,
        }
    }
}

/// Validate the sections and find the degenerate ones.
pub(super) fn classify<'a>(sections: &'a [Vec<Vec3>], opts: &SkinOptions) -> Result<Vec<Section<'a>>, NurbsError> {
    for degree in [opts.degree_u, opts.degree_v] {
        if degree == 0 || degree > MAX_DEGREE {
            return Err(NurbsError::BadDegree { degree, max: MAX_DEGREE });
        }
    }
    if sections.len() < 2 {
        return Err(NurbsError::TooFewPoints { what: "skinning (sections)".into(), needed: 2, got: sections.len() });
    }
    let mut flat = 0;
    for (k, s) in sections.iter().enumerate() {
        if s.is_empty() {
            return Err(NurbsError::TooFewPoints { what: format!("section {k}"), needed: 1, got: 0 });
        }
        if let Some(i) = s.iter().position(|p| !p.is_finite()) {
            return Err(NurbsError::NonFinitePoint { index: flat + i });
        }
        flat += s.len();
    }
    let size = bounding_diagonal(sections.iter().flatten());
    let out: Vec<Section> = sections
        .iter()
        .map(|s| if has_extent(s, size) { Section::Regular(s) } else { Section::Point(s[0], s.len()) })
        .collect();
    if !out.iter().any(|s| matches!(s, Section::Regular(_))) {
        return Err(NurbsError::TooFewPoints {
            what: "skinning: every section is a single point; sections with extent".into(),
            needed: 1,
            got: 0,
        });
    }
    Ok(out)
}

/// Prefix `what` of an error with the section it concerns.
pub(super) fn in_section(e: NurbsError, k: usize) -> NurbsError {
    let tag = |w: String| format!("section {k}: {w}");
    match e {
        NurbsError::TooFewPoints { what, needed, got } => NurbsError::TooFewPoints { what: tag(what), needed, got },
        NurbsError::CoincidentPoints { what, index, next } => {
            NurbsError::CoincidentPoints { what: tag(what), index, next }
        }
        NurbsError::BadControlPointCount { what, count, min, max } => {
            NurbsError::BadControlPointCount { what: tag(what), count, min, max }
        }
        NurbsError::SingularSystem { what } => NurbsError::SingularSystem { what: tag(what) },
        NurbsError::TooManyControlPoints { what, count, points, distinct, max } => {
            NurbsError::TooManyControlPoints { what: tag(what), count, points, distinct, max }
        }
        NurbsError::Incompatible { what } => NurbsError::Incompatible { what: tag(what) },
        NurbsError::NonFiniteResult { what } => NurbsError::NonFiniteResult { what: tag(what) },
        NurbsError::DecreasingParameters { what, index, prev, value } => {
            NurbsError::DecreasingParameters { what: tag(what), index, prev, value }
        }
        other => other,
    }
}

/// The largest point count of a non-degenerate section.
pub(super) fn max_count(secs: &[Section]) -> usize {
    secs.iter()
        .filter_map(|s| if let Section::Regular(s) = s { Some(s.len()) } else { None })
        .max()
        .expect("classify keeps one regular section")
}

/// Every non-degenerate section's own parameters of `kind` (for universal parameters, of degree
/// `min(p, n_k - 1)`, the highest its count carries).
pub(super) fn own_params(secs: &[Section], kind: Parameterization, p: usize) -> Result<UParams, NurbsError> {
    secs.iter()
        .enumerate()
        .map(|(k, s)| match s {
            Section::Regular(pts) => {
                parameterize_labelled(pts, kind, p.min(pts.len() - 1), "points").map(Some).map_err(|e| in_section(e, k))
            }
            Section::Point(..) => Ok(None),
        })
        .collect()
}

/// `u` parameters per section (`None` for a degenerate section: spread uniformly).
pub(super) type UParams = Vec<Option<Vec<f64>>>;

pub(super) fn data_params(secs: &[Section], v: &[f64], u_of: UParams) -> Vec<Vec<(f64, f64)>> {
    secs.iter()
        .zip(u_of)
        .zip(v)
        .map(|((s, u), &vk)| {
            let u = u.unwrap_or_else(|| if s.len() < 2 { vec![0.0] } else { uniform_params(s.len()) });
            u.into_iter().map(|uk| (uk, vk)).collect()
        })
        .collect()
}
