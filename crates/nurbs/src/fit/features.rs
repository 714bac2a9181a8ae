//! Hull features inside one surface: knuckles and chines, i.e. corners of the sections that
//! run along the hull, kept as tangent discontinuities of a single skinned surface.
//!
//! A B-spline of degree `p` is `C^{p-m}` at a knot of multiplicity `m` (The NURBS Book 2.3,
//! property P2.5), so a knot of multiplicity `m = p` leaves it only `C^0`: the tangent may
//! jump, and the curve passes through the one control point whose basis function is 1 there
//! (P2.2, `N_{i,p}(u_i) = 1` at a knot of multiplicity `p`). A knot of multiplicity `p - 1`
//! keeps the tangent and frees the curvature ([`Continuity`], [`knot_multiplicity`]).
//! A knuckle of the data becomes a knot of multiplicity `p` in the common `u` knot vector,
//! at the same parameter in every section: each section is cut at its corner point, the
//! pieces are fitted on their own, their parameters are mapped to `[a_j, a_{j+1}]` with the
//! same breakpoints `a_j` for every section, and the pieces' knot vectors are joined
//! ([`join_knot_vectors`]). Skinning across the sections then keeps the `C^0` line at
//! `u = a_j` for every `v`: the surface's iso-curve there is the curve through the corners
//! of the sections, the chine line.
//!
//! Corner detection ([`section_corners`]) looks at the turning angle of the polyline of the
//! offsets, `θ_i = angle(Q_i - Q_{i-1}, Q_{i+1} - Q_i)`. A corner is a point where the turn is
//! concentrated: `θ_i >= θ_min` and `θ_i >= dominance * max(θ_{i-1}, θ_{i+1})` (a smooth bend,
//! e.g. a round bilge, spreads its turn over neighbouring points; a knuckle keeps it at one).
//! A single section cannot tell a knuckle from a round bilge sampled by three points, so a
//! corner counts only as part of a *knuckle line* ([`find_knuckle_lines`]): corners of
//! consecutive sections whose positions (fractions of the section's polyline length) differ by
//! at most `match_gap` are linked, and a chain is kept when it spans at least `min_share` of
//! the sections with extent. Sections of a kept line without a detected corner (where the
//! knuckle fades, e.g. towards the stem) get the point nearest to the position interpolated
//! along the line, so that every section carries the same number of knuckles.
//!
//! Flats of side and bottom ([`find_flat_lines`]) are straight runs of offsets on the plane of
//! the largest half-breadth or of the lowest offset; where such a run meets the bilge arc the
//! tangent is continuous and the curvature jumps, and a smooth least-squares skin rings past
//! the plane. [`refit_within_flats`] inserts knots of multiplicity `p - 1` ([`Continuity::C1`])
//! where the flats end and refits the surface with every control point within the planes
//! ([`bounded_refit`]): by the convex-hull property the surface then never crosses them.

use super::banded::BandedCholesky;
use crate::basis::{basis_funs, BasisRow};
use crate::tolerance::COINCIDENT_REL;
use crate::{KnotVector, NurbsError, NurbsSurface, Vec3};

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
    /// Why: a planing hull's chine turns by 30 to 90 degrees with nearly straight bottom and
    /// sides either side (neighbouring turns of a few degrees), while the coarse bilge of the
    /// Series 60 tables turns by up to 51 degrees at one offset with 12 degrees at the next
    /// (dominance 4) in the parallel midbody only (under half of the stations); a chine runs
    /// from the transom to near the stem. Measured on every table in `testdata/`: no knuckle
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

/// Whether a section has extent: not all of its points within [`COINCIDENT_REL`] of the data's
/// size of the first (the same test as the skinning's degenerate sections).
fn has_extent(points: &[Vec3], size: f64) -> bool {
    points.first().is_some_and(|&c| points.iter().any(|p| p.distance(c) > COINCIDENT_REL * size))
}

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
    let size = data_size(sections);
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

/// The diagonal of the bounding box of all points (0 without points).
fn data_size(sections: &[Vec<Vec3>]) -> f64 {
    let mut pts = sections.iter().flatten();
    let Some(&first) = pts.next() else { return 0.0 };
    let (lo, hi) = pts.fold((first, first), |(lo, hi), p| {
        (Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z)), Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z)))
    });
    (hi - lo).norm()
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

/// Which flat a [`FlatLine`] bounds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlatKind {
    /// The flat of bottom: offsets on the plane `z = z_min` of the lowest offset.
    Bottom,
    /// The flat of side: offsets on the plane `y = y_max` of the largest half-breadth.
    Side,
}

/// Settings of flat detection ([`find_flat_lines`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlatOptions {
    /// Least number of consecutive offsets on the plane that make a flat (3: two chords).
    pub min_points: usize,
    /// Least number of sections with the flat's end for a line to be kept.
    pub min_sections: usize,
    /// Distance from the plane, relative to the diagonal of the data's bounding box, within
    /// which an offset lies on it.
    pub plane_rel: f64,
}

impl Default for FlatOptions {
    /// 3 offsets, 3 sections, `1e-6` of the hull's size (a micrometre on a 100 m hull: the
    /// tables give the flats as repeated figures, equal to the last digit).
    ///
    /// Why: two chords on the plane are the least that show a straight run rather than a
    /// point of a curve touching it (the bilge of a hull without parallel midbody touches
    /// `y = B/2` at one offset of the midship station); a line in fewer than 3 sections is a
    /// single station's flat, not a feature of the hull.
    fn default() -> Self {
        FlatOptions { min_points: 3, min_sections: 3, plane_rel: 1e-9 }
    }
}

/// A line along the hull where a flat of bottom or side meets the curved part of the sections
/// (a straight run meeting an arc: the tangent is continuous there, the curvature jumps).
#[derive(Clone, Debug, PartialEq)]
pub struct FlatLine {
    pub kind: FlatKind,
    /// The flat's plane: `z` of the lowest offset for the bottom, `y` of the largest
    /// half-breadth for the side.
    pub plane: f64,
    /// Per section, the index of the offset where the flat ends (the last offset on the plane
    /// before the curved part, or the first after it); `None` where the section has no such
    /// flat: the line fades out where the flat shortens to nothing.
    pub index: Vec<Option<usize>>,
}

impl FlatLine {
    /// The number of sections where the flat's end is found.
    pub fn count(&self) -> usize {
        self.index.iter().flatten().count()
    }
}

/// The interior ends of the longest run of at least `min_points` consecutive points with
/// `on(point)`; each end paired with `true` when the run lies before it (its upper end).
fn run_ends(points: &[Vec3], min_points: usize, on: impl Fn(&Vec3) -> bool) -> Vec<(usize, bool)> {
    let mut best: Option<(usize, usize)> = None;
    let mut i = 0;
    while i < points.len() {
        if !on(&points[i]) {
            i += 1;
            continue;
        }
        let start = i;
        while i < points.len() && on(&points[i]) {
            i += 1;
        }
        let len = i - start;
        if len >= min_points.max(2) && best.is_none_or(|(a, b)| len > b - a) {
            best = Some((start, i));
        }
    }
    let Some((a, b)) = best else { return Vec::new() };
    let mut out = Vec::new();
    if a > 0 {
        out.push((a, false));
    }
    if b < points.len() {
        out.push((b - 1, true));
    }
    out
}

/// The flat lines of a family of sections: in every section with extent, the longest run of
/// at least `min_points` consecutive offsets on the plane of the flat of bottom (`z` within
/// `plane_rel * size` of the lowest offset of all sections) and of the flat of side (`y` within
/// that of the largest half-breadth), and the run's interior ends (an end that is the section's
/// first or last offset meets nothing). Each kind and end (the run's upper or lower end along
/// the section) is one line, kept when found in at least `min_sections` sections. In a
/// section where the ends of two lines are not in the order of the lines' mean positions (a
/// square corner: the flat bottom ending where the flat side starts), both are left out there.
/// Lines are returned in the order of their mean index fraction along the sections.
///
/// Deterministic: the result depends only on the points and the options.
///
/// # Errors
/// [`NurbsError::Incompatible`] for `min_points < 2`, `min_sections < 1` or `plane_rel` not in
/// `[0, 1)`; [`NurbsError::NonFinitePoint`] for a NaN or infinite coordinate.
pub fn find_flat_lines(sections: &[Vec<Vec3>], opts: &FlatOptions) -> Result<Vec<FlatLine>, NurbsError> {
    if opts.min_points < 2 || opts.min_sections < 1 || !(opts.plane_rel >= 0.0 && opts.plane_rel < 1.0) {
        return Err(NurbsError::Incompatible { what: format!("flat detection: settings out of range: {opts:?}") });
    }
    if let Some(index) = sections.iter().flatten().position(|p| !p.is_finite()) {
        return Err(NurbsError::NonFinitePoint { index });
    }
    let size = data_size(sections);
    let Some(first) = sections.iter().flatten().next() else { return Ok(Vec::new()) };
    let (y_max, z_min) = sections.iter().flatten().fold((first.y, first.z), |(y, z), p| (y.max(p.y), z.min(p.z)));
    let tol = opts.plane_rel * size;
    // Lines keyed by (kind, upper end): Bottom-upper, Bottom-lower, Side-upper, Side-lower.
    let keys = [(FlatKind::Bottom, true), (FlatKind::Bottom, false), (FlatKind::Side, true), (FlatKind::Side, false)];
    let mut index = vec![vec![None; sections.len()]; keys.len()];
    for (k, pts) in sections.iter().enumerate() {
        if !has_extent(pts, size) {
            continue;
        }
        let bottom = run_ends(pts, opts.min_points, |p| (p.z - z_min).abs() <= tol);
        let side = run_ends(pts, opts.min_points, |p| (p.y - y_max).abs() <= tol);
        for (kind, ends) in [(FlatKind::Bottom, bottom), (FlatKind::Side, side)] {
            for (i, upper) in ends {
                let l = keys.iter().position(|&key| key == (kind, upper)).expect("every kind and end has a key");
                index[l][k] = Some(i);
            }
        }
    }
    let mut lines: Vec<FlatLine> = keys
        .iter()
        .zip(index)
        .map(|(&(kind, _), index)| FlatLine {
            kind,
            plane: if kind == FlatKind::Bottom { z_min } else { y_max },
            index,
        })
        .filter(|l| l.count() >= opts.min_sections)
        .collect();
    let mean_fraction = |l: &FlatLine| {
        let f: Vec<f64> = l
            .index
            .iter()
            .zip(sections)
            .filter_map(|(i, pts)| i.map(|i| i as f64 / (pts.len().max(2) - 1) as f64))
            .collect();
        f.iter().sum::<f64>() / f.len().max(1) as f64
    };
    lines.sort_by(|a, b| mean_fraction(a).total_cmp(&mean_fraction(b)));
    // Out-of-order ends (including two lines at one offset) are left out of that section.
    for k in 0..sections.len() {
        let present: Vec<usize> = (0..lines.len()).filter(|&l| lines[l].index[k].is_some()).collect();
        let ordered = present.windows(2).all(|w| lines[w[0]].index[k] < lines[w[1]].index[k]);
        if !ordered {
            present.iter().for_each(|&l| lines[l].index[k] = None);
        }
    }
    lines.retain(|l| l.count() >= opts.min_sections);
    Ok(lines)
}

/// A box for the control points of a surface: `lo[c] <= P[c] <= hi[c]` for `c` = x, y, z. An
/// infinite bound is no bound. By the convex-hull property (The NURBS Book P3.4 and P4.4: with
/// positive weights every point of the surface is a convex combination of its control points),
/// a net within the box keeps the whole surface within it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ControlBox {
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

impl Default for ControlBox {
    /// No bound at all.
    fn default() -> Self {
        ControlBox { lo: [f64::NEG_INFINITY; 3], hi: [f64::INFINITY; 3] }
    }
}

impl ControlBox {
    /// The half-spaces of the flats `lines` ([`FlatLine::plane`]): `y <= plane` for a line of
    /// [`FlatKind::Side`], `z >= plane` for one of [`FlatKind::Bottom`]; no other bound.
    pub fn of_flats(lines: &[FlatLine]) -> Self {
        let plane = |kind| lines.iter().find(|l| l.kind == kind).map(|l| l.plane);
        let mut b = ControlBox::default();
        if let Some(y) = plane(FlatKind::Side) {
            b.hi[1] = y;
        }
        if let Some(z) = plane(FlatKind::Bottom) {
            b.lo[2] = z;
        }
        b
    }

    /// Whether no coordinate is bounded.
    pub fn is_empty(&self) -> bool {
        self.lo.iter().chain(&self.hi).all(|b| b.is_infinite())
    }

    /// Whether `p` lies within the box (bounds included).
    pub fn contains(&self, p: Vec3) -> bool {
        let a = p.to_array();
        (0..3).all(|c| a[c] >= self.lo[c] && a[c] <= self.hi[c])
    }

    /// The bound of coordinate `c` that `x` lies past, if any.
    fn crossed(&self, c: usize, x: f64) -> Option<f64> {
        if x < self.lo[c] {
            Some(self.lo[c])
        } else if x > self.hi[c] {
            Some(self.hi[c])
        } else {
            None
        }
    }
}

/// What [`bounded_refit`] did: the control-point coordinates it held on a bound, by coordinate
/// x, y, z (0 for a coordinate the net did not cross).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BoundedRefit {
    pub held: [usize; 3],
}

impl BoundedRefit {
    /// Coordinates held on a bound in all.
    pub fn total(&self) -> usize {
        self.held.iter().sum()
    }
}

/// Relative weight `λ` of the pull towards the starting control points in [`bounded_refit`]:
/// `μ = λ max_i (A^T A)_ii`. Small, so that the data decide wherever they reach (the refit's
/// residual stays that of least squares), but enough to keep control points the data hardly
/// reach (a pointed stem's row, the ends of a short section) where the skin put them.
pub const BOUNDED_REFIT_PULL: f64 = 1e-3;

/// Keep a surface within a box ([`ControlBox`]), by the convex-hull property (The NURBS Book
/// P3.4 and P4.4: with positive weights `S(u, v)` lies in the convex hull of its control
/// points): once every control point is within the box, so is every point of the surface. A
/// least-squares skin rings past a flat of side or bottom (a straight run meeting the bilge
/// arc): on the 116 m cargo ship it dips 0.14 m below the flat bottom, on the Series 60 Cb 0.80
/// parent it bulges 36 mm beyond the flat side; it crosses the centre plane where a section
/// leaves it steeply (the Series 60 sterns).
///
/// Each coordinate `c` the net crosses is refitted on the surface's own knots, the points
/// `Q_k` at their parameters `(u_k, v_k)`:
///
/// `min sum_k (A_k x - Q_k,c)^2 + μ |x - x_0|^2`,  `A_ki = R_ij(u_k, v_k)`,
///
/// `R_ij = N_{i,p} N_{j,q} w_ij / sum N N w` the rational basis of the surface's weights, which
/// are kept (`N_{i,p}(u_k) N_{j,q}(v_k)` for a non-rational surface), with `x_0` the surface's control points and `μ = BOUNDED_REFIT_PULL max_i (A^T A)_ii`,
/// subject to `lo_c <= x_i <= hi_c`, by an active set (Nocedal and Wright 16.5): each round
/// holds on its bound every coordinate the last solve put across and releases the held ones
/// the objective pulls inwards (a multiplier of the wrong sign), then solves for the free
/// ones, until nothing changes or after 60 rounds; whatever is still across then is put on
/// its bound, so the box holds in every case. A collapsed boundary row or column of the net
/// (a pointed end) stays where it is. Coordinates the net does not cross are left as
/// they are. The normal equations are banded (half-bandwidth `min(p n_v + q, q n_u + p)`, the
/// unknowns ordered u- or v-major to get it) and solved by banded Cholesky,
/// `O(n_u n_v b^2)` per round for bandwidth `b`.
///
/// Returns `None` when no control point lies outside the box (the surface is left as it is).
///
/// # Errors
/// [`NurbsError::Incompatible`] for a weight that is not positive, an empty box (`lo > hi` or
/// a NaN bound), parameters and points of different lengths, or a parameter outside the
/// domain;
/// [`NurbsError::SingularSystem`] when the normal equations are too ill-conditioned (a pivot
/// below `1e-12` of its diagonal); [`NurbsError::NonFinitePoint`];
/// [`NurbsError::NonFiniteResult`].
pub fn bounded_refit(
    surface: &NurbsSurface,
    params: &[(f64, f64)],
    points: &[Vec3],
    bounds: &ControlBox,
) -> Result<Option<(NurbsSurface, BoundedRefit)>, NurbsError> {
    let weights = surface.weights();
    if weights.iter().any(|&w| !(w > 0.0)) {
        return Err(NurbsError::Incompatible { what: "bounded refit of a surface with a weight <= 0".into() });
    }
    if (0..3).any(|c| !(bounds.lo[c] <= bounds.hi[c])) {
        return Err(NurbsError::Incompatible {
            what: format!("bounded refit: the box {:?}..{:?} is empty (expected lo <= hi)", bounds.lo, bounds.hi),
        });
    }
    if params.len() != points.len() {
        return Err(NurbsError::Incompatible {
            what: format!("bounded refit: {} parameters for {} points", params.len(), points.len()),
        });
    }
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(NurbsError::NonFinitePoint { index });
    }
    let ((u0, u1), (v0, v1)) = (surface.domain_u(), surface.domain_v());
    if params.iter().any(|&(u, v)| !(u >= u0 && u <= u1 && v >= v0 && v <= v1)) {
        return Err(NurbsError::Incompatible { what: "bounded refit: a parameter outside the domain".into() });
    }
    let mut net = surface.control_points();
    let crossed: Vec<usize> =
        (0..3).filter(|&c| net.iter().any(|p| bounds.crossed(c, p.to_array()[c]).is_some())).collect();
    if crossed.is_empty() {
        return Ok(None);
    }
    // The sparse rows of the collocation matrix: (control index, R_ij(u, v)), the rational
    // basis `N_i(u) N_j(v) w_ij / sum N N w` of the fixed weights (`N_i(u) N_j(v)` when all
    // are 1).
    let (ku, kv) = (surface.knots_u(), surface.knots_v());
    let (p, q, n_v, n_ctrl) = (ku.degree(), kv.degree(), surface.n_v(), net.len());
    let mut rows: Vec<Vec<(usize, f64)>> = Vec::with_capacity(points.len());
    let (mut bu, mut bv): (BasisRow, BasisRow) = ([0.0; crate::MAX_DEGREE + 1], [0.0; crate::MAX_DEGREE + 1]);
    for &(u, v) in params {
        let (su, sv) = (ku.find_span(u), kv.find_span(v));
        basis_funs(ku.as_slice(), su, u, p, &mut bu);
        basis_funs(kv.as_slice(), sv, v, q, &mut bv);
        let mut row = Vec::with_capacity((p + 1) * (q + 1));
        for (a, &nu) in bu[..=p].iter().enumerate() {
            for (b, &nv) in bv[..=q].iter().enumerate() {
                let i = (su - p + a) * n_v + (sv - q + b);
                row.push((i, nu * nv * weights[i]));
            }
        }
        let sum: f64 = row.iter().map(|(_, w)| w).sum();
        row.iter_mut().for_each(|(_, w)| *w /= sum);
        rows.push(row);
    }
    let mut diag = vec![0.0; n_ctrl];
    rows.iter().flatten().for_each(|&(i, w)| diag[i] += w * w);
    let pinned = collapsed_edges(&net, surface.n_u(), n_v);
    // The unknowns' order: two control points interact only within p + 1 rows and q + 1
    // columns, so u-major (as the net) the normal matrix has half-bandwidth p n_v + q, v-major
    // q n_u + p; the smaller is taken (Gunnerus, 12 x 47 poles: 39 against 144, a 14th of the
    // factorization's work), and holding some only narrows it.
    let n_u = surface.n_u();
    let (order, bandwidth): (Vec<usize>, usize) = if p * n_v + q <= q * n_u + p {
        ((0..n_ctrl).collect(), p * n_v + q)
    } else {
        ((0..n_v).flat_map(|j| (0..n_u).map(move |i| i * n_v + j)).collect(), q * n_u + p)
    };
    let mu = BOUNDED_REFIT_PULL * diag.iter().copied().fold(0.0, f64::max);
    let mut report = BoundedRefit::default();
    for c in crossed {
        let start: Vec<f64> = net.iter().map(|p| p.to_array()[c]).collect();
        // The bound each coordinate is held on, if any; a pinned one at its start.
        let mut held: Vec<Option<f64>> = (0..n_ctrl).map(|i| pinned[i].then_some(start[i])).collect();
        let mut x = start.clone();
        for _ in 0..MAX_ACTIVE_SET_ROUNDS {
            // Hold what lies across; release what the objective pulls inwards (its gradient
            // points outwards: a negative Lagrange multiplier, Nocedal and Wright 16.5).
            let grad = gradient(&rows, points, &x, &start, mu, c);
            let mut changed = false;
            for i in (0..n_ctrl).filter(|&i| !pinned[i]) {
                match held[i] {
                    None => {
                        if let Some(b) = bounds.crossed(c, x[i]) {
                            held[i] = Some(b);
                            changed = true;
                        }
                    }
                    Some(b) => {
                        let pulls_in = if b == bounds.hi[c] { grad[i] > 0.0 } else { grad[i] < 0.0 };
                        if pulls_in {
                            held[i] = None;
                            changed = true;
                        }
                    }
                }
            }
            if !changed {
                break;
            }
            let free: Vec<usize> = order.iter().copied().filter(|&i| held[i].is_none()).collect();
            let mut slot = vec![usize::MAX; n_ctrl];
            free.iter().enumerate().for_each(|(f, &i)| slot[i] = f);
            let m = free.len();
            if m == 0 {
                x.iter_mut().zip(&held).for_each(|(xi, h)| *xi = h.unwrap_or(*xi));
                break;
            }
            let mut a = BandedCholesky::zeros(m, bandwidth.min(m.saturating_sub(1)));
            let mut sol: Vec<[f64; 1]> = free.iter().map(|&i| [mu * start[i]]).collect();
            for f in 0..m {
                a.add(f, f, mu);
            }
            for (row, q) in rows.iter().zip(points) {
                // The point less the part of the held control points.
                let target = q.to_array()[c] - row.iter().filter_map(|&(i, w)| held[i].map(|b| w * b)).sum::<f64>();
                for &(i, wi) in row.iter().filter(|(i, _)| held[*i].is_none()) {
                    sol[slot[i]][0] += wi * target;
                    for &(j, wj) in row.iter().filter(|(j, _)| held[*j].is_none() && slot[*j] <= slot[i]) {
                        a.add(slot[i], slot[j], wi * wj);
                    }
                }
            }
            a.factor("bounded refit")?;
            a.solve(&mut sol);
            if sol.iter().any(|x| !x[0].is_finite()) {
                return Err(NurbsError::NonFiniteResult { what: "bounded refit".into() });
            }
            for i in 0..n_ctrl {
                x[i] = held[i].unwrap_or_else(|| sol[slot[i]][0]);
            }
        }
        // Whatever the rounds left across (a cycle cut short) goes onto its bound: the box
        // holds in every case.
        for xi in x.iter_mut() {
            if let Some(b) = bounds.crossed(c, *xi) {
                *xi = b;
            }
        }
        report.held[c] =
            (0..n_ctrl).filter(|&i| (x[i] == bounds.lo[c] || x[i] == bounds.hi[c]) && start[i] != x[i]).count();
        for (pt, &xi) in net.iter_mut().zip(&x) {
            let mut arr = pt.to_array();
            arr[c] = xi;
            *pt = Vec3::from_array(arr);
        }
    }
    let out = NurbsSurface::try_new(ku.clone(), kv.clone(), &net, surface.is_rational().then_some(&weights[..]))?;
    Ok(Some((out, report)))
}

/// [`bounded_refit`] with room made for the flats first: a non-rational skin `surface` fitted
/// to `sections` (offsets at `params[k][i]`) is refined by knot insertion (The NURBS Book
/// A5.3 and 5.3: the surface is unchanged, only its control net grows), then refitted within
/// the flats' planes ([`ControlBox::of_flats`]). Inserted, each up to multiplicity
/// `p - 1` (the surface may stay `C^1` there and its curvature jump, as the hull's does where a
/// straight run meets the bilge arc, The NURBS Book P2.5):
///
/// - along `u`, for every line, at the mean `u` of the offsets where its flat ends;
/// - across `v`, for every line, at the `v` of its first and last section (the ends of the
///   parallel middle body, where the flat fades out), when interior.
///
/// Why the extra knots: held on the planes, the control points of the plain net cannot follow
/// the bilge's curvature jump, and the refit's error grows (measured on the Series 60 Cb 0.80
/// parent at 6 x 19 control points: max 63 -> 120 mm); with the knots the refit at 8 x 23
/// stays below the plain fit's error at 6 x 19 (max 54 mm, RMS 12 mm against 63 and 16 mm),
/// though above the plain fit at 8 x 23 (10 mm), which bulges 21 mm beyond the flat side.
///
/// Returns `None` when `lines` is empty or the refit moves nothing.
///
/// # Errors
/// As [`bounded_refit`] and [`NurbsSurface::insert_knot_u`]; [`NurbsError::Incompatible`] when
/// `params` and `sections` differ in shape or a line's index is out of range.
pub fn refit_within_flats(
    surface: &NurbsSurface,
    params: &[Vec<(f64, f64)>],
    sections: &[Vec<Vec3>],
    lines: &[FlatLine],
) -> Result<Option<(NurbsSurface, BoundedRefit)>, NurbsError> {
    if lines.is_empty() {
        return Ok(None);
    }
    let shape_ok = params.len() == sections.len()
        && params.iter().zip(sections).all(|(a, b)| a.len() == b.len())
        && lines.iter().all(|l| {
            l.index.len() == sections.len() && l.index.iter().zip(sections).all(|(i, s)| i.is_none_or(|i| i < s.len()))
        });
    if !shape_ok {
        return Err(NurbsError::Incompatible {
            what: "refit within flats: parameters, sections and flat lines differ in shape".into(),
        });
    }
    let mut refined = surface.clone();
    let raise =
        |kv: &KnotVector, t: f64| knot_multiplicity(kv.degree(), Continuity::C1).saturating_sub(kv.multiplicity(t));
    for l in lines {
        let us: Vec<f64> = l.index.iter().enumerate().filter_map(|(k, i)| Some(params[k][(*i)?].0)).collect();
        let (a, b) = refined.domain_u();
        let u = us.iter().sum::<f64>() / us.len().max(1) as f64;
        let r = raise(refined.knots_u(), u);
        if !us.is_empty() && u > a && u < b && r > 0 {
            refined = refined.insert_knot_u(u, r)?;
        }
        let with: Vec<usize> = l.index.iter().enumerate().filter_map(|(k, i)| i.map(|_| k)).collect();
        for k in [with.first(), with.last()].into_iter().flatten() {
            let Some(&(_, v)) = params[*k].first() else { continue };
            let (a, b) = refined.domain_v();
            let r = raise(refined.knots_v(), v);
            if v > a && v < b && r > 0 {
                refined = refined.insert_knot_v(v, r)?;
            }
        }
    }
    let flat_params: Vec<(f64, f64)> = params.iter().flatten().copied().collect();
    let points: Vec<Vec3> = sections.iter().flatten().copied().collect();
    bounded_refit(&refined, &flat_params, &points, &ControlBox::of_flats(lines))
}

/// The control points of the net's collapsed boundary rows and columns (all of one row or
/// column at one place: a pointed end, a degenerate edge), u-major with `n_v` per row: a
/// refit moving them apart would open the point into a tiny curve whose normals are noise, so
/// [`bounded_refit`] keeps them where they are (a point within the box stays within it).
fn collapsed_edges(net: &[Vec3], n_u: usize, n_v: usize) -> Vec<bool> {
    let mut pinned = vec![false; net.len()];
    let lines: [Vec<usize>; 4] = [
        (0..n_v).collect(),
        ((n_u - 1) * n_v..n_u * n_v).collect(),
        (0..n_u).map(|i| i * n_v).collect(),
        (0..n_u).map(|i| i * n_v + n_v - 1).collect(),
    ];
    for line in lines {
        let first = net[line[0]];
        if line.iter().all(|&i| net[i] == first) {
            line.iter().for_each(|&i| pinned[i] = true);
        }
    }
    pinned
}

/// Rounds of the active set in [`bounded_refit`] (each one solve); the bound is enforced after
/// the last in any case.
const MAX_ACTIVE_SET_ROUNDS: usize = 60;

/// The gradient (halved) of `sum_k (A_k x - Q_k,c)^2 + μ |x - x_0|^2`.
fn gradient(rows: &[Vec<(usize, f64)>], points: &[Vec3], x: &[f64], start: &[f64], mu: f64, c: usize) -> Vec<f64> {
    let mut g: Vec<f64> = x.iter().zip(start).map(|(a, b)| mu * (a - b)).collect();
    for (row, q) in rows.iter().zip(points) {
        let r = row.iter().map(|&(i, w)| w * x[i]).sum::<f64>() - q.to_array()[c];
        row.iter().for_each(|&(i, w)| g[i] += w * r);
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    /// A chine section: keel `(0, 0)` to chine `(b, h)` in `n_bottom` chords, chine to sheer
    /// `(b + f, h + d)` in `n_side` chords, at `x`.
    fn chine_section(x: f64, b: f64, h: f64, f: f64, d: f64, n_bottom: usize, n_side: usize) -> Vec<Vec3> {
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
    fn a_round_bilge_has_no_corner_and_a_chine_has_one() {
        // A quarter circle of 9 points: every interior turn is 11.25 degrees, none dominates.
        let arc: Vec<Vec3> = (0..9)
            .map(|i| i as f64 * std::f64::consts::FRAC_PI_2 / 8.0)
            .map(|a| Vec3::new(0.0, a.sin(), 1.0 - a.cos()))
            .collect();
        assert!(section_corners(&arc, &CornerOptions::default()).is_empty());
        // Deadrise 15 degrees to the chine, vertical side: turn 75 degrees at the chine.
        let b = 3.0;
        let s = chine_section(0.0, b, b * 15f64.to_radians().tan(), 0.0, 2.0, 4, 3);
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
                chine_section(k as f64, 3.0, 0.8, f, d, 4, 3)
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
                    chine_section(k as f64, 3.0, 0.8, 0.0, 2.0, 4, 3)
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

    /// A box-bilge section at `x`: flat bottom from the keel `(0, 0)` to `(b - r, 0)` in
    /// `n_flat` chords, a quarter circle of radius `r` in 3 chords, flat side from `(b, r)` to
    /// `(b, h)` in `n_side` chords. Without flats (`b = r`, `n_flat = 0`) a round section.
    fn box_section(x: f64, b: f64, r: f64, h: f64, n_flat: usize, n_side: usize) -> Vec<Vec3> {
        let mut pts: Vec<Vec3> =
            (0..=n_flat).map(|i| Vec3::new(x, (b - r) * i as f64 / n_flat.max(1) as f64, 0.0)).collect();
        if n_flat == 0 {
            pts.truncate(1);
        }
        for i in 1..=3 {
            let a = std::f64::consts::FRAC_PI_2 * i as f64 / 3.0;
            pts.push(Vec3::new(x, b - r + r * a.sin(), r - r * a.cos()));
        }
        pts.extend((1..=n_side).map(|i| Vec3::new(x, b, r + (h - r) * i as f64 / n_side as f64)));
        pts
    }

    /// 9 sections: the middle 5 with flats (bottom to `y = 2`, side from `z = 1`, B/2 = 3), the
    /// two at each end narrower and without them.
    fn box_hull() -> Vec<Vec<Vec3>> {
        (0..9)
            .map(|k| {
                let x = k as f64;
                if (2..7).contains(&k) {
                    box_section(x, 3.0, 1.0, 4.0, 4, 3)
                } else {
                    let b = 2.0 + 0.3 * (k as f64 - 4.0).abs().min(3.0).recip();
                    // Round, narrower, 8 points.
                    (0..8)
                        .map(|i| std::f64::consts::FRAC_PI_2 * i as f64 / 7.0)
                        .map(|a| Vec3::new(x, b * a.sin(), 4.0 * (1.0 - a.cos())))
                        .collect()
                }
            })
            .collect()
    }

    #[test]
    fn flat_lines_end_where_the_flats_meet_the_bilge() {
        let hull = box_hull();
        let lines = find_flat_lines(&hull, &FlatOptions::default()).expect("valid");
        assert_eq!(lines.iter().map(|l| l.kind).collect::<Vec<_>>(), vec![FlatKind::Bottom, FlatKind::Side]);
        assert_eq!((lines[0].plane, lines[1].plane), (0.0, 3.0));
        for k in 0..9 {
            // Bottom: keel and 4 chords, the last flat offset index 4; side from index 4 + 3.
            let (b, s) = if (2..7).contains(&k) { (Some(4), Some(7)) } else { (None, None) };
            assert_eq!((lines[0].index[k], lines[1].index[k]), (b, s), "section {k}");
        }
        assert_eq!(lines[0].count(), 5);
        // In fewer sections than asked for: no line.
        let strict = FlatOptions { min_sections: 6, ..FlatOptions::default() };
        assert!(find_flat_lines(&hull, &strict).expect("valid").is_empty());
        // A square corner (flat bottom straight into the flat side) is a knuckle, not a flat's
        // end: both ends fall on one offset and are left out.
        let square: Vec<Vec<Vec3>> = (0..4)
            .map(|k| {
                let x = k as f64;
                vec![
                    Vec3::new(x, 0.0, 0.0),
                    Vec3::new(x, 1.0, 0.0),
                    Vec3::new(x, 2.0, 0.0),
                    Vec3::new(x, 2.0, 1.0),
                    Vec3::new(x, 2.0, 2.0),
                ]
            })
            .collect();
        assert!(find_flat_lines(&square, &FlatOptions::default()).expect("valid").is_empty());
        // Bad settings and points.
        for bad in [
            FlatOptions { min_points: 1, ..FlatOptions::default() },
            FlatOptions { min_sections: 0, ..FlatOptions::default() },
            FlatOptions { plane_rel: f64::NAN, ..FlatOptions::default() },
        ] {
            assert!(matches!(find_flat_lines(&hull, &bad), Err(NurbsError::Incompatible { .. })), "{bad:?}");
        }
        let mut nan = hull.clone();
        nan[0][1].y = f64::NAN;
        assert!(matches!(find_flat_lines(&nan, &FlatOptions::default()), Err(NurbsError::NonFinitePoint { index: 1 })));
        assert!(find_flat_lines(&[], &FlatOptions::default()).expect("nothing to find").is_empty());
    }

    #[test]
    fn a_bounded_refit_keeps_the_net_and_the_surface_within_the_planes() {
        let hull = box_hull();
        let opts = crate::fit::SkinOptions::default();
        let fit = crate::fit::skin_approximate(&hull, 6, 7, &opts).expect("fits");
        let lines = find_flat_lines(&hull, &FlatOptions::default()).expect("valid");
        let bounds = ControlBox::of_flats(&lines);
        let open = ControlBox::default();
        assert_eq!(bounds, ControlBox { lo: [open.lo[0], open.lo[1], 0.0], hi: [open.hi[0], 3.0, open.hi[2]] });
        let crossing = |s: &NurbsSurface| s.control_points().iter().any(|p| p.y > 3.0 || p.z < 0.0);
        // The least-squares net rings past the flats (else this test would show nothing).
        assert!(crossing(&fit.surface));
        let params: Vec<(f64, f64)> = fit.params.iter().flatten().copied().collect();
        let points: Vec<Vec3> = hull.iter().flatten().copied().collect();
        let (refit, report) = bounded_refit(&fit.surface, &params, &points, &bounds).expect("valid").expect("moved");
        assert!(!crossing(&refit) && report.held[0] == 0 && report.total() > 0, "{report:?}");
        // Same knots, and the convex-hull property on a grid (no round-off can cross: a convex
        // combination of values <= 3 is <= 3 up to one rounding of the sum, 4e-16 here).
        assert_eq!((refit.knots_u(), refit.knots_v()), (fit.surface.knots_u(), fit.surface.knots_v()));
        for i in 0..=40 {
            for j in 0..=40 {
                let p = refit.point(i as f64 / 40.0, j as f64 / 40.0);
                assert!(p.y <= 3.0 + 1e-15 && p.z >= -1e-15, "{p:?}");
            }
        }
        // x is left as it was.
        let before = fit.surface.control_points();
        assert!(refit.control_points().iter().zip(&before).all(|(a, b)| a.x == b.x));
        // Already within: nothing to do; and the refit's own result is within.
        assert!(bounded_refit(&refit, &params, &points, &bounds).expect("valid").is_none());
        assert!(bounded_refit(&fit.surface, &params, &points, &ControlBox::default()).expect("valid").is_none());
        // Bad input.
        assert!(bounded_refit(&fit.surface, &params[1..], &points, &bounds).is_err());
        let outside = vec![(2.0, 0.5); params.len()];
        assert!(bounded_refit(&fit.surface, &outside, &points, &bounds).is_err());
        // A rational surface keeps its weights, and its net and every point come within the
        // box (positive weights: the convex-hull property holds for the rational basis).
        let w: Vec<f64> = (0..fit.surface.control_points().len()).map(|i| 1.0 + 0.5 * ((i % 5) as f64 / 4.0)).collect();
        let rational =
            NurbsSurface::try_new(fit.surface.knots_u().clone(), fit.surface.knots_v().clone(), &before, Some(&w))
                .expect("valid");
        assert!(crossing(&rational));
        let (r, _) = bounded_refit(&rational, &params, &points, &bounds).expect("valid").expect("moved");
        assert!(!crossing(&r) && r.weights() == w);
        for i in 0..=40 {
            for j in 0..=40 {
                let p = r.point(i as f64 / 40.0, j as f64 / 40.0);
                // The rational combination divides once more: a few roundings of 3, 1e-15.
                assert!(p.y <= 3.0 + 1e-14 && p.z >= -1e-14, "{p:?}");
            }
        }
        // An empty box is refused.
        let empty = ControlBox { lo: [0.0, 1.0, 0.0], hi: [1.0, 0.5, 1.0] };
        assert!(bounded_refit(&fit.surface, &params, &points, &empty).is_err());
    }

    #[test]
    fn a_bounded_refit_keeps_a_pointed_end_a_point() {
        // The box hull with its first section a pointed stem: the skin's first row of poles is
        // one point, and the refit (which crosses the flats) leaves it there, where moving it
        // apart would open the point into a tiny curve of noisy normals.
        let mut hull = box_hull();
        hull[0] = vec![Vec3::new(0.0, 0.0, 2.0); 8];
        let fit = crate::fit::skin_approximate(&hull, 6, 7, &crate::fit::SkinOptions::default()).expect("fits");
        let first: Vec<Vec3> = (0..fit.surface.n_u()).map(|i| fit.surface.control_point(i, 0)).collect();
        assert!(first.iter().all(|p| *p == first[0]), "the skin's stem row is one point");
        let params: Vec<(f64, f64)> = fit.params.iter().flatten().copied().collect();
        let points: Vec<Vec3> = hull.iter().flatten().copied().collect();
        let lines = find_flat_lines(&hull, &FlatOptions::default()).expect("valid");
        let (refit, report) = bounded_refit(&fit.surface, &params, &points, &ControlBox::of_flats(&lines))
            .expect("valid")
            .expect("moved");
        assert!(report.total() > 0);
        for i in 0..refit.n_u() {
            assert_eq!(refit.control_point(i, 0), first[0], "pole {i} of the stem row");
        }
    }

    #[test]
    fn a_refit_within_flats_adds_c1_knots_at_the_flat_ends() {
        let hull = box_hull();
        let fit = crate::fit::skin_approximate(&hull, 6, 7, &crate::fit::SkinOptions::default()).expect("fits");
        let lines = find_flat_lines(&hull, &FlatOptions::default()).expect("valid");
        let (s, _) = refit_within_flats(&fit.surface, &fit.params, &hull, &lines).expect("valid").expect("moved");
        let p = s.degree_u();
        // Each line's mean u of its flat ends carries a knot of multiplicity p - 1 (C1).
        for l in &lines {
            let us: Vec<f64> = l.index.iter().enumerate().filter_map(|(k, i)| Some(fit.params[k][(*i)?].0)).collect();
            let u = us.iter().sum::<f64>() / us.len() as f64;
            assert_eq!(s.knots_u().multiplicity(u), knot_multiplicity(p, Continuity::C1), "u = {u}");
        }
        // Across: the first and last section with flats (2 and 6) bound the parallel middle body.
        for k in [2, 6] {
            let v = fit.params[k][0].1;
            assert_eq!(s.knots_v().multiplicity(v), knot_multiplicity(s.degree_v(), Continuity::C1), "v = {v}");
        }
        // The knots give the held net room: the refit within the flats meets the offsets closer
        // than the bounded refit on the plain knots, and closer than the plain fit (measured
        // max 0.111 m plain, 0.317 m bounded, 0.038 m with the knots).
        let params: Vec<(f64, f64)> = fit.params.iter().flatten().copied().collect();
        let points: Vec<Vec3> = hull.iter().flatten().copied().collect();
        let residual = |s: &NurbsSurface| {
            params.iter().zip(&points).map(|(&(u, v), q)| s.point(u, v).distance(*q)).fold(0.0, f64::max)
        };
        let (bounded, _) = bounded_refit(&fit.surface, &params, &points, &ControlBox::of_flats(&lines))
            .expect("valid")
            .expect("moved");
        let (plain, held, knotted) = (residual(&fit.surface), residual(&bounded), residual(&s));
        eprintln!("box hull, max residual: plain {plain:.4}, bounded {held:.4}, with C1 knots {knotted:.4}");
        assert!(knotted < held && knotted < plain, "{plain} {held} {knotted}");
        assert!(refit_within_flats(&fit.surface, &fit.params, &hull, &[]).expect("valid").is_none());
        assert!(refit_within_flats(&fit.surface, &fit.params[1..], &hull, &lines).is_err());
    }
}
