//! Corner lines of a family of sections: tangent discontinuities (knuckles, chines) that run
//! across the sections, kept as `C^0` lines of a single skinned surface.
//!
//! A corner of the data becomes a knot of multiplicity `p` in the common `u` knot vector
//! ([`crate::fit::Continuity::C0`]), at the same parameter in every section: each section is
//! cut at its corner point, the pieces are fitted on their own, their parameters are mapped to
//! `[a_j, a_{j+1}]` with the same breakpoints `a_j` for every section, and the pieces' knot
//! vectors are joined ([`crate::fit::join_knot_vectors`]). Skinning across the sections then
//! keeps the `C^0` line at `u = a_j` for every `v`: the surface's iso-curve there is the curve
//! through the corners of the sections.
//!
//! Corner detection ([`section_corners`]) looks at the turning angle of the polyline of the
//! points, `θ_i = angle(Q_i - Q_{i-1}, Q_{i+1} - Q_i)`. A corner is a point where the turn is
//! concentrated: `θ_i >= θ_min` and `θ_i >= dominance * max(θ_{i-1}, θ_{i+1})` (a smooth bend,
//! e.g. a round arc, spreads its turn over neighbouring points; a corner keeps it at one).
//! A single section cannot tell a corner from a tight arc sampled by three points, so a
//! corner counts only as part of a *corner line* ([`find_knuckle_lines`]): corners of
//! consecutive sections whose positions (fractions of the section's polyline length) differ by
//! at most `match_gap` are linked, and a chain is kept when it spans at least `min_share` of
//! the sections with extent. Sections of a kept line without a detected corner (where the
//! corner fades, e.g. towards a pointed end) get the point nearest to the position
//! interpolated along the line, so that every section carries the same number of corners.

use super::extent::{bounding_diagonal, has_extent};
use crate::tolerance::COINCIDENT_REL;
use crate::{NurbsError, Vec3};

/// Settings of knuckle detection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerOptions {
    /// Least turning angle of a corner, in degrees.
    pub min_angle_deg: f64,
    /// A corner turns at least this many times as much as each of its neighbours.
    pub dominance: f64,
    /// Least share (0..=1) of the sections with extent in which a knuckle line is detected.
    pub min_share: f64,
    /// Largest difference of position (fraction of the polyline length) between the corners
    /// of a line in consecutive sections.
    pub match_gap: f64,
}

impl Default for CornerOptions {
    /// 30 degrees, dominance 3, on three quarters of the sections, positions within 0.15.
    ///
    /// Why (measured on ship offset tables): a hard corner turns by 30 to 90 degrees with
    /// nearly straight runs either side (neighbouring turns of a few degrees) and runs through
    /// nearly all the sections, while a coarsely sampled round turn of the Series 60 tables
    /// turns by up to 51 degrees at one point with 12 degrees at the next (dominance 4) in
    /// under half of the sections. Measured on every table in `testdata/`: no knuckle
    /// line is found on any of them with these settings.
    fn default() -> Self {
        CornerOptions { min_angle_deg: 30.0, dominance: 3.0, min_share: 0.75, match_gap: 0.15 }
    }
}

impl CornerOptions {
    /// Check the settings.
    ///
    /// # Errors
    /// [`NurbsError::Incompatible`] naming the setting that is out of range: the angle must lie
    /// in `(0, 180)`, the dominance be at least 1, the share in `(0, 1]`, the gap in `(0, 1]`.
    pub fn validate(&self) -> Result<(), NurbsError> {
        let bad = |what: &str, v: f64, range: &str| {
            Err(NurbsError::Incompatible { what: format!("corner detection: {what} {v} is out of range ({range})") })
        };
        if !(self.min_angle_deg > 0.0 && self.min_angle_deg < 180.0) {
            return bad("angle", self.min_angle_deg, "expected degrees in (0, 180)");
        }
        if !(self.dominance >= 1.0 && self.dominance.is_finite()) {
            return bad("dominance", self.dominance, "expected at least 1");
        }
        if !(self.min_share > 0.0 && self.min_share <= 1.0) {
            return bad("share of sections", self.min_share, "expected in (0, 1]");
        }
        if !(self.match_gap > 0.0 && self.match_gap <= 1.0) {
            return bad("position gap", self.match_gap, "expected in (0, 1]");
        }
        Ok(())
    }
}

/// The turning angle in radians at every point of a polyline: `θ_i` between the chords
/// `Q_i - Q_{i-1}` and `Q_{i+1} - Q_i` for interior points (`acos` of the normalized dot
/// product, clamped to `[-1, 1]`), 0 at the two ends and where a chord has no length.
///
/// ```
/// use nurbs::fit::turning_angles;
/// use nurbs::Vec3;
/// // A square corner turns by 90 degrees; the ends and a straight run turn by none.
/// let q = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, 2.0, 0.0)];
/// let t = turning_angles(&q);
/// assert!((t[1] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// assert_eq!((t[0], t[2], t[3]), (0.0, 0.0, 0.0));
/// ```
pub fn turning_angles(points: &[Vec3]) -> Vec<f64> {
    let n = points.len();
    let mut out = vec![0.0; n];
    for i in 1..n.saturating_sub(1) {
        let a = points[i] - points[i - 1];
        let b = points[i + 1] - points[i];
        let (la, lb) = (a.norm(), b.norm());
        if la > 0.0 && lb > 0.0 && la.is_finite() && lb.is_finite() {
            out[i] = (a.dot(b) / (la * lb)).clamp(-1.0, 1.0).acos();
        }
    }
    out
}

/// A corner of one section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionCorner {
    /// The index of the corner point in the section.
    pub index: usize,
    /// Its turning angle, in degrees.
    pub angle_deg: f64,
    /// Its position: polyline length from the first point to it over the whole length.
    pub position: f64,
}

/// The polyline length fractions `s_i` of the points, 0 to 1 (all 0 for a section without
/// length).
fn positions(points: &[Vec3]) -> Vec<f64> {
    let mut s = Vec::with_capacity(points.len());
    let mut acc = 0.0;
    s.push(0.0);
    for w in points.windows(2) {
        acc += w[1].distance(w[0]);
        s.push(acc);
    }
    if acc > 0.0 && acc.is_finite() {
        s.iter_mut().for_each(|x| *x /= acc);
    } else {
        s.iter_mut().for_each(|x| *x = 0.0);
    }
    s
}

/// The corners of one section (see the module documentation): interior points whose turning
/// angle is at least `min_angle_deg` and at least `dominance` times each neighbour's, in order.
/// A section with fewer than 3 points, or with a chord shorter than [`COINCIDENT_REL`] of its
/// length, has none.
pub fn section_corners(points: &[Vec3], opts: &CornerOptions) -> Vec<SectionCorner> {
    let theta = turning_angles(points);
    let s = positions(points);
    let total: f64 = points.windows(2).map(|w| w[1].distance(w[0])).sum();
    let degenerate = points.len() < 3
        || !(total > 0.0 && total.is_finite())
        || points.windows(2).any(|w| w[1].distance(w[0]) <= COINCIDENT_REL * total);
    if degenerate {
        return Vec::new();
    }
    let min = opts.min_angle_deg.to_radians();
    (1..points.len() - 1)
        .filter(|&i| {
            let t = theta[i];
            let neighbour = theta[i - 1].max(theta[i + 1]);
            t >= min && t >= opts.dominance * neighbour
        })
        .map(|i| SectionCorner { index: i, angle_deg: theta[i].to_degrees(), position: s[i] })
        .collect()
}

/// A knuckle (or chine) line: one corner point in every section with extent.
#[derive(Clone, Debug, PartialEq)]
pub struct KnuckleLine {
    /// Per section, the index of the knuckle point; `None` for a section without extent (all
    /// its points at one place: a pointed stem or stern).
    pub index: Vec<Option<usize>>,
    /// Per section, whether the corner was detected there (`false`: the nearest point was
    /// taken, or the section has no extent).
    pub detected: Vec<bool>,
    /// Per section, the turning angle of the polyline at the knuckle point, in degrees (0 for
    /// a section without extent).
    pub angle_deg: Vec<f64>,
}

impl KnuckleLine {
    /// The number of sections where the corner was detected.
    pub fn detected_count(&self) -> usize {
        self.detected.iter().filter(|&&d| d).count()
    }

    /// The largest turning angle along the line, in degrees.
    pub fn max_angle_deg(&self) -> f64 {
        self.angle_deg.iter().copied().fold(0.0, f64::max)
    }
}

/// A chain of corners under construction: `(section, corner)` pairs in section order.
type Chain = Vec<(usize, SectionCorner)>;

/// The knuckle lines of a family of sections (module documentation): corners of every
/// section ([`section_corners`]) linked from section to section (a corner joins the chain
/// whose last corner, at most two sections with extent back, has the nearest position within
/// `match_gap`; each chain takes at most one corner per section), chains kept when they span
/// at least `min_share` of the sections with extent, ordered along the sections by mean
/// position. Lines that cross another (a different order in a section where both are
/// detected) are dropped, the one with fewer detections first. In sections where a line was
/// not detected the point is the interior point whose position is nearest to the one
/// interpolated linearly (in section index) between the nearest detections, constant beyond
/// the first and last, chosen so that every section's knuckle indices strictly increase and
/// stay interior; a line that cannot be placed in a section with too few points is dropped.
///
/// Deterministic: the result depends only on the points and the options.
///
/// # Errors
/// [`NurbsError::Incompatible`] for options out of range ([`CornerOptions::validate`]),
/// [`NurbsError::NonFinitePoint`] for a NaN or infinite coordinate (index counted through all
/// sections in order).
pub fn find_knuckle_lines(sections: &[Vec<Vec3>], opts: &CornerOptions) -> Result<Vec<KnuckleLine>, NurbsError> {
    opts.validate()?;
    if let Some(index) = sections.iter().flatten().position(|p| !p.is_finite()) {
        return Err(NurbsError::NonFinitePoint { index });
    }
    let size = bounding_diagonal(sections.iter().flatten());
    let regular: Vec<usize> = (0..sections.len()).filter(|&k| has_extent(&sections[k], size)).collect();
    if regular.is_empty() {
        return Ok(Vec::new());
    }
    // Link corners into chains, section by section (only sections with extent).
    let mut chains: Vec<Chain> = Vec::new();
    for (rank, &k) in regular.iter().enumerate() {
        let corners = section_corners(&sections[k], opts);
        // Candidate links (gap, chain, corner), nearest first; chains whose last corner is at
        // most two sections with extent back.
        let mut links: Vec<(f64, usize, usize)> = Vec::new();
        for (ci, chain) in chains.iter().enumerate() {
            let &(last_k, last) = chain.last().expect("chains are never empty");
            let last_rank = regular.iter().position(|&r| r == last_k).expect("chains hold regular sections");
            if rank - last_rank > 2 {
                continue;
            }
            for (j, c) in corners.iter().enumerate() {
                let gap = (c.position - last.position).abs();
                if gap <= opts.match_gap {
                    links.push((gap, ci, j));
                }
            }
        }
        links.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut chain_used = vec![false; chains.len()];
        let mut corner_used = vec![false; corners.len()];
        for (_, ci, j) in links {
            if !chain_used[ci] && !corner_used[j] {
                chain_used[ci] = true;
                corner_used[j] = true;
                chains[ci].push((k, corners[j]));
            }
        }
        for (j, c) in corners.iter().enumerate() {
            if !corner_used[j] {
                chains.push(vec![(k, *c)]);
            }
        }
    }
    let needed = (opts.min_share * regular.len() as f64 - 1e-9).ceil().max(1.0) as usize;
    let mut kept: Vec<Chain> = chains.into_iter().filter(|c| c.len() >= needed).collect();
    let mean_position = |c: &Chain| c.iter().map(|(_, x)| x.position).sum::<f64>() / c.len() as f64;
    kept.sort_by(|a, b| mean_position(a).total_cmp(&mean_position(b)));
    // Drop crossing lines: while two lines disagree in order somewhere, drop the weaker.
    loop {
        let mut crossing = None;
        'pairs: for a in 0..kept.len() {
            for b in a + 1..kept.len() {
                for &(k, ca) in &kept[a] {
                    if let Some(&(_, cb)) = kept[b].iter().find(|(kb, _)| *kb == k) {
                        if ca.index >= cb.index {
                            crossing = Some((a, b));
                            break 'pairs;
                        }
                    }
                }
            }
        }
        match crossing {
            Some((a, b)) => {
                let drop = if kept[a].len() < kept[b].len() { a } else { b };
                kept.remove(drop);
            }
            None => break,
        }
    }
    // Place every kept line in every section with extent; drop a line that does not fit.
    loop {
        match place_lines(sections, &regular, &kept) {
            Ok(lines) => return Ok(lines),
            Err(weakest) => {
                kept.remove(weakest);
            }
        }
    }
}

/// Every section's indices of the ordered `chains`; `Err(i)` names the line to drop (the one
/// with the fewest detections among those that could not be placed in some section).
fn place_lines(sections: &[Vec<Vec3>], regular: &[usize], chains: &[Chain]) -> Result<Vec<KnuckleLine>, usize> {
    let n_lines = chains.len();
    let mut lines: Vec<KnuckleLine> = (0..n_lines)
        .map(|_| KnuckleLine {
            index: vec![None; sections.len()],
            detected: vec![false; sections.len()],
            angle_deg: vec![0.0; sections.len()],
        })
        .collect();
    for &k in regular {
        let pts = &sections[k];
        let s = positions(pts);
        let theta = turning_angles(pts);
        // Detected indices first; the others are placed between them.
        let mut idx: Vec<Option<usize>> =
            chains.iter().map(|c| c.iter().find(|(kc, _)| *kc == k).map(|(_, x)| x.index)).collect();
        let detected: Vec<bool> = idx.iter().map(Option::is_some).collect();
        for l in 0..n_lines {
            if idx[l].is_some() {
                continue;
            }
            let target = interpolated_position(&chains[l], k);
            // Interior indices strictly between the neighbouring lines' indices in this section
            // (the nearest lower line already placed or detected, the nearest higher detected).
            let lo = idx[..l].iter().rev().flatten().next().map_or(1, |&i| i + 1);
            let hi = idx[l + 1..].iter().flatten().next().map_or(pts.len().saturating_sub(2), |&i| i.saturating_sub(1));
            // Leave room for the undetected lines above that still need a point of their own.
            let above_unplaced = idx[l + 1..].iter().take_while(|i| i.is_none()).count();
            let hi = hi.saturating_sub(above_unplaced);
            if pts.len() < 3 || lo > hi {
                return Err(weakest(chains, l));
            }
            let best = (lo..=hi)
                .min_by(|&a, &b| (s[a] - target).abs().total_cmp(&(s[b] - target).abs()).then(a.cmp(&b)))
                .expect("lo <= hi");
            idx[l] = Some(best);
        }
        for l in 0..n_lines {
            let i = idx[l].expect("every line placed");
            if l > 0 && idx[l - 1].is_some_and(|prev| prev >= i) {
                return Err(weakest(chains, l));
            }
            lines[l].index[k] = Some(i);
            lines[l].detected[k] = detected[l];
            lines[l].angle_deg[k] = theta[i].to_degrees();
        }
    }
    Ok(lines)
}

/// The index of the chain with the fewest corners (the first on a tie), a line `l` being the
/// one that failed when all are equal.
fn weakest(chains: &[Chain], l: usize) -> usize {
    let min = chains.iter().map(Vec::len).min().unwrap_or(0);
    if chains[l].len() == min {
        l
    } else {
        chains.iter().position(|c| c.len() == min).unwrap_or(l)
    }
}

/// The position of `chain` at section `k`: linear in the section index between the nearest
/// detections before and after, the nearest one's beyond the ends.
fn interpolated_position(chain: &Chain, k: usize) -> f64 {
    let before = chain.iter().rev().find(|(kc, _)| *kc < k);
    let after = chain.iter().find(|(kc, _)| *kc > k);
    match (before, after) {
        (Some(&(ka, a)), Some(&(kb, b))) => {
            let w = (k - ka) as f64 / (kb - ka) as f64;
            (1.0 - w) * a.position + w * b.position
        }
        (Some(&(_, a)), None) => a.position,
        (None, Some(&(_, b))) => b.position,
        (None, None) => 0.5,
    }
}

/// Every section's knuckle indices from `lines`, in increasing order (empty for a section
/// without extent): the `knuckles` argument of [`crate::fit::skin_interpolate_with_knuckles`].
pub fn knuckle_indices(lines: &[KnuckleLine], n_sections: usize) -> Vec<Vec<usize>> {
    (0..n_sections).map(|k| lines.iter().filter_map(|l| l.index.get(k).copied().flatten()).collect()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// A cornered section at `x`: a straight run from `(0, 0)` to the corner `(b, h)` in
    /// `n_bottom` chords, then to `(b + f, h + d)` in `n_side` chords.
    fn cornered_section(x: f64, b: f64, h: f64, f: f64, d: f64, n_bottom: usize, n_side: usize) -> Vec<Vec3> {
        let mut pts: Vec<Vec3> =
            (0..=n_bottom).map(|i| i as f64 / n_bottom as f64).map(|t| Vec3::new(x, b * t, h * t)).collect();
        pts.extend((1..=n_side).map(|i| i as f64 / n_side as f64).map(|t| Vec3::new(x, b + f * t, h + d * t)));
        pts
    }

    #[test]
    fn turning_angles_of_a_square_corner_and_a_line() {
        let q =
            [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(1.0, 3.0, 0.0)];
        let t = turning_angles(&q);
        // acos of an exact 0 and an exact 1: pi/2 and 0 to the last bit of acos.
        assert_near!(t[1], std::f64::consts::FRAC_PI_2, 1e-15);
        assert_eq!((t[0], t[2], t[3]), (0.0, 0.0, 0.0));
        let c = section_corners(&q, &CornerOptions::default());
        assert_eq!(c.len(), 1);
        assert_eq!(c[0].index, 1);
        // Chords 1, 2, 1: the corner is a quarter of the way.
        assert_near!(c[0].position, 0.25, 1e-15);
    }

    #[test]
    fn a_round_arc_has_no_corner_and_a_sharp_turn_has_one() {
        // A quarter circle of 9 points: every interior turn is 11.25 degrees, none dominates.
        let arc: Vec<Vec3> = (0..9)
            .map(|i| i as f64 * std::f64::consts::FRAC_PI_2 / 8.0)
            .map(|a| Vec3::new(0.0, a.sin(), 1.0 - a.cos()))
            .collect();
        assert!(section_corners(&arc, &CornerOptions::default()).is_empty());
        // Deadrise 15 degrees to the chine, vertical side: turn 75 degrees at the chine.
        let b = 3.0;
        let s = cornered_section(0.0, b, b * 15f64.to_radians().tan(), 0.0, 2.0, 4, 3);
        let c = section_corners(&s, &CornerOptions::default());
        assert_eq!(c.iter().map(|c| c.index).collect::<Vec<_>>(), vec![4]);
        // Two chords' directions, each exact to a few ulps: the angle to ~1e-13 degrees.
        assert_near!(c[0].angle_deg, 75.0, 1e-12);
    }

    #[test]
    fn knuckle_lines_link_sections_and_fill_the_gaps() {
        // 10 sections, the chine detected in all but the last two, where the side turns by 4
        // degrees only (below the threshold): the line is kept
        // (8 of 10 >= 75 %) and filled there with the nearest point.
        let mut sections: Vec<Vec<Vec3>> = (0..10)
            .map(|k| {
                // Side at 4 degrees less than the bottom's 14.9 degrees in the last two.
                let side = (0.8f64 / 3.0).atan() - 4f64.to_radians();
                let (f, d) = if k >= 8 { (2.0, 2.0 * side.tan()) } else { (0.0, 2.0) };
                cornered_section(k as f64, 3.0, 0.8, f, d, 4, 3)
            })
            .collect();
        // A pointed stem at the end: no extent, no knuckle.
        sections.push(vec![Vec3::new(10.0, 0.0, 1.0); 5]);
        let lines = find_knuckle_lines(&sections, &CornerOptions::default()).expect("valid");
        assert_eq!(lines.len(), 1);
        let l = &lines[0];
        assert_eq!(l.detected_count(), 8);
        for k in 0..10 {
            assert_eq!(l.index[k], Some(4), "section {k}");
        }
        assert_eq!(l.index[10], None);
        assert_eq!(knuckle_indices(&lines, 11)[3], vec![4]);
        assert!(knuckle_indices(&lines, 11)[10].is_empty());
        // Stricter share: 8 of 10 is not 90 %.
        let strict = CornerOptions { min_share: 0.9, ..CornerOptions::default() };
        assert!(find_knuckle_lines(&sections, &strict).expect("valid").is_empty());
    }

    #[test]
    fn corners_in_few_sections_make_no_line() {
        // A corner in 3 of 10 sections (a transom's edge aft): no line.
        let sections: Vec<Vec<Vec3>> = (0..10)
            .map(|k| {
                if k < 3 {
                    cornered_section(k as f64, 3.0, 0.8, 0.0, 2.0, 4, 3)
                } else {
                    (0..8)
                        .map(|i| i as f64 * std::f64::consts::FRAC_PI_2 / 7.0)
                        .map(|a| Vec3::new(k as f64, 3.0 * a.sin(), 3.0 * (1.0 - a.cos())))
                        .collect()
                }
            })
            .collect();
        assert!(find_knuckle_lines(&sections, &CornerOptions::default()).expect("valid").is_empty());
        let loose = CornerOptions { min_share: 0.3, ..CornerOptions::default() };
        let lines = find_knuckle_lines(&sections, &loose).expect("valid");
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0].detected_count(), 3);
    }

    #[test]
    fn bad_options_and_points_are_reported() {
        let s = vec![vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)]; 2];
        for bad in [
            CornerOptions { min_angle_deg: 0.0, ..CornerOptions::default() },
            CornerOptions { min_angle_deg: f64::NAN, ..CornerOptions::default() },
            CornerOptions { dominance: 0.5, ..CornerOptions::default() },
            CornerOptions { min_share: 0.0, ..CornerOptions::default() },
            CornerOptions { match_gap: 2.0, ..CornerOptions::default() },
        ] {
            assert!(matches!(find_knuckle_lines(&s, &bad), Err(NurbsError::Incompatible { .. })), "{bad:?}");
        }
        let nan = vec![vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(f64::NAN, 0.0, 0.0)]];
        assert!(matches!(
            find_knuckle_lines(&nan, &CornerOptions::default()),
            Err(NurbsError::NonFinitePoint { index: 1 })
        ));
        assert!(find_knuckle_lines(&[], &CornerOptions::default()).expect("nothing to find").is_empty());
    }
}
