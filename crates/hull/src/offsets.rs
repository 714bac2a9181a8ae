//! The offset data model: a hull given as a list of sections, each a list of points.
//!
//! The rest of this module's documentation is on [`Offsets`], where the library's users read it.

use nurbs::Vec3;

use crate::error::{HullError, InputErrorKind, Location};
use crate::units::Units;

/// Two consecutive points closer than `COINCIDENT_REL` times the model size (the diagonal of
/// the bounding box) are the same point: the kernel's tolerance, so that what the reader
/// accepts the fit accepts too.
pub use nurbs::tolerance::COINCIDENT_REL;

/// A section is planar in x when all its x lie within `PLANAR_REL` times the model size of
/// their mean (same reasoning as [`COINCIDENT_REL`]).
pub const PLANAR_REL: f64 = 1e-9;

/// The model size (see [`Offsets::size`]) must lie within `MIN_SIZE ..= MAX_SIZE`, in any
/// units. The fit, the error measure and the hydrostatics square and multiply lengths (sums of
/// squared distances over millions of points, volumes, moments of inertia of the waterplane: up
/// to fifth powers of a length): with lengths between 1e-50 and 1e50 every such product stays a
/// normal f64 (1e-308 to 1e308) with room to spare, while a hull of 1e300 m overflows to
/// infinity and one of 1e-310 m is below the coincidence tolerance's resolution. Real data,
/// micrometres to kilometres, lie twenty orders of magnitude inside either bound.
pub const MIN_SIZE: f64 = 1e-50;
/// See [`MIN_SIZE`].
pub const MAX_SIZE: f64 = 1e50;

/// One section of the hull: its points in order along it (keel to deck).
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    /// The label from the input: a station number or name.
    pub label: String,
    /// The points, in order along the section.
    pub points: Vec<Vec3>,
    /// 1-based source line of each point, for error messages; empty for sections built in
    /// code, otherwise as long as `points`.
    pub lines: Vec<usize>,
    /// 1-based source field column shared by all points (the station's column of an offset
    /// table); `None` when each point is a row of its own (sections CSV) or unknown.
    pub column: Option<usize>,
}

impl Section {
    /// A section built in code, without source positions.
    pub fn new(label: impl Into<String>, points: Vec<Vec3>) -> Self {
        Section { label: label.into(), points, lines: Vec::new(), column: None }
    }

    /// Where point `index` came from in `source`.
    pub fn location(&self, source: &str, index: usize) -> Location {
        let line = self.lines.get(index).copied();
        Location { file: source.to_string(), line, column: line.and(self.column) }
    }

    /// True if every point lies within `tol` of the first: the section is one point, a pointed
    /// stem or stern (empty sections are not).
    pub fn is_point(&self, tol: f64) -> bool {
        self.points.first().is_some_and(|&first| self.points.iter().all(|p| p.distance(first) <= tol))
    }

    /// The mean x of the points, `None` for an empty section.
    pub fn mean_x(&self) -> Option<f64> {
        if self.points.is_empty() {
            None
        } else {
            Some(self.points.iter().map(|p| p.x).sum::<f64>() / self.points.len() as f64)
        }
    }
}

/// A hull's offsets: sections in order along the length, in the user's units.
///
/// # Axes
///
/// hullskin uses one right-handed convention everywhere:
///
/// - **x forward**, along the length, from aft to fore (e.g. x = 0 at the aft perpendicular);
/// - **y to starboard**, as the half-breadth: y >= 0 for the one side of a symmetric hull that
///   offsets describe;
/// - **z up**, from the baseline.
///
/// A section is normally a transverse station (all its points at one x), ordered from keel to
/// deck; sections follow each other along the length. Coordinates stay in the user's
/// [`Units`]; nothing is converted.
#[derive(Clone, Debug, PartialEq)]
pub struct Offsets {
    /// Where the data came from: a file path, or `built-in sample: ...`.
    pub source: String,
    /// The length unit of every coordinate.
    pub units: Units,
    /// The sections, in order along the length.
    pub sections: Vec<Section>,
    /// The perpendiculars, where the data gives them (a Series 60 table scaled by its Lpp, a
    /// table with its Lpp, the built-in sample); `None` when unknown.
    pub perpendiculars: Option<Perpendiculars>,
}

/// The aft and forward perpendiculars: their x in the surface's axes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Perpendiculars {
    /// x of the aft perpendicular (AP).
    pub aft: f64,
    /// x of the forward perpendicular (FP).
    pub fore: f64,
}

impl Perpendiculars {
    /// The perpendiculars `Lpp` apart, the AP at `aft`.
    ///
    /// # Errors
    /// [`HullError::Perpendiculars`] unless `aft` is finite and `lpp` a positive finite length.
    pub fn try_new(aft: f64, lpp: f64) -> Result<Self, HullError> {
        if !(aft.is_finite() && lpp.is_finite() && lpp > 0.0 && (aft + lpp).is_finite()) {
            return Err(HullError::Perpendiculars { aft, lpp });
        }
        Ok(Perpendiculars { aft, fore: aft + lpp })
    }

    /// Length between perpendiculars.
    pub fn lpp(&self) -> f64 {
        self.fore - self.aft
    }

    /// x of amidships, half way between the perpendiculars.
    pub fn midship(&self) -> f64 {
        0.5 * (self.aft + self.fore)
    }

    /// `x` as a percentage of Lpp from amidships, positive forward.
    pub fn percent_from_midship(&self, x: f64) -> f64 {
        100.0 * (x - self.midship()) / self.lpp()
    }
}

/// The axis-aligned bounding box `(min, max)` of the finite points of `points`, `None` when
/// there are none.
pub(crate) fn bounds_of(points: impl Iterator<Item = Vec3>) -> Option<(Vec3, Vec3)> {
    let mut pts = points.filter(|p| p.is_finite());
    let first = pts.next()?;
    Some(pts.fold((first, first), |(lo, hi), p| {
        (Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z)), Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z)))
    }))
}

impl Offsets {
    /// Offsets from `source` in `units`, without known perpendiculars.
    pub fn new(source: impl Into<String>, units: Units, sections: Vec<Section>) -> Self {
        Offsets { source: source.into(), units, sections, perpendiculars: None }
    }

    /// Total number of points over all sections.
    pub fn num_points(&self) -> usize {
        self.sections.iter().map(|s| s.points.len()).sum()
    }

    /// The axis-aligned bounding box `(min, max)` of all points, `None` when there are none.
    /// Non-finite coordinates are skipped.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        bounds_of(self.sections.iter().flat_map(|s| s.points.iter().copied()))
    }

    /// The model size: the diagonal of [`Offsets::bounds`], 0 without points.
    pub fn size(&self) -> f64 {
        self.bounds().map_or(0.0, |(lo, hi)| (hi - lo).norm())
    }

    /// Checks that the offsets can be skinned, in this order:
    ///
    /// 1. every coordinate is finite;
    /// 2. there are at least 2 sections;
    /// 3. every section has at least `max(min_points_per_section, 1)` points (pass the fit's
    ///    degree + 1);
    /// 4. the model size lies within [`MIN_SIZE`] and [`MAX_SIZE`] (no coordinate so large
    ///    that lengths overflow, no model collapsed to a point or below any tolerance);
    /// 5. no two consecutive points of a section coincide (distance <= [`COINCIDENT_REL`] x
    ///    model size), unless the whole section collapses to one point (a pointed stem or
    ///    stern end, all its points equal), and only the first and last sections may so
    ///    collapse (a zero-length section between two others pinches the hull: refused);
    /// 6. no section planar in x crosses itself: two of its segments that are not neighbours
    ///    do not cross in the (y, z) plane (a point typed out of order along the curve makes
    ///    a loop the skinned surface would fold over); segments that only touch are accepted;
    /// 7. when every section is planar in x (see [`PLANAR_REL`]), the sections' x are strictly
    ///    monotone (increasing or decreasing, as the first two set it; a difference within the
    ///    tolerance counts as equal: a station given twice is refused). Free-form sections
    ///    whose x varies are not order-checked.
    ///
    /// # Errors
    ///
    /// The first failed check, as [`HullError::Input`] located at the offending point's source
    /// line (and column for offset tables): [`InputErrorKind::NonFiniteCoordinate`],
    /// [`InputErrorKind::TooFewSections`], [`InputErrorKind::TooFewPoints`],
    /// [`InputErrorKind::ModelSize`], [`InputErrorKind::RepeatedPoint`],
    /// [`InputErrorKind::PointSection`], [`InputErrorKind::SectionCrosses`] or
    /// [`InputErrorKind::SectionOrder`]; and
    /// [`HullError::Limit`] above the caps [`crate::MAX_SECTIONS`], [`crate::MAX_POINTS_PER_SECTION`]
    /// and [`crate::MAX_POINTS`].
    pub fn validate(&self, min_points_per_section: usize) -> Result<(), HullError> {
        crate::limits::check_offsets(self)?;
        let src = self.source.as_str();
        for s in &self.sections {
            if let Some(i) = s.points.iter().position(|p| !p.is_finite()) {
                return Err(HullError::input(
                    s.location(src, i),
                    InputErrorKind::NonFiniteCoordinate {
                        label: s.label.clone(),
                        index: i,
                        point: s.points[i].to_array(),
                    },
                ));
            }
        }
        if self.sections.len() < 2 {
            return Err(HullError::input(
                Location::file(src),
                InputErrorKind::TooFewSections { got: self.sections.len() },
            ));
        }
        let needed = min_points_per_section.max(1);
        for s in &self.sections {
            if s.points.len() < needed {
                return Err(HullError::input(
                    s.location(src, 0),
                    InputErrorKind::TooFewPoints { label: s.label.clone(), got: s.points.len(), needed },
                ));
            }
        }
        self.check_size()?;
        let tol = COINCIDENT_REL * self.size();
        let last = self.sections.len() - 1;
        for (k, s) in self.sections.iter().enumerate() {
            if s.is_point(tol) {
                if k == 0 || k == last {
                    continue; // a pointed end
                }
                return Err(HullError::input(
                    s.location(src, 0),
                    InputErrorKind::PointSection { label: s.label.clone(), point: s.points[0].to_array() },
                ));
            }
            for (i, w) in s.points.windows(2).enumerate() {
                if w[0].distance(w[1]) <= tol {
                    return Err(HullError::input(
                        s.location(src, i + 1),
                        InputErrorKind::RepeatedPoint {
                            label: s.label.clone(),
                            index: i + 1,
                            line: s.lines.get(i + 1).copied(),
                            previous_line: s.lines.get(i).copied(),
                            point: w[1].to_array(),
                        },
                    ));
                }
            }
        }
        self.check_crossings(PLANAR_REL * self.size())?;
        self.check_order(PLANAR_REL * self.size())
    }

    /// Step 4 of [`Offsets::validate`]: the size within [`MIN_SIZE`] and [`MAX_SIZE`]; a model
    /// too large is located at its largest coordinate. Every coordinate is finite by now.
    fn check_size(&self) -> Result<(), HullError> {
        // The largest coordinate bounds the size within a factor sqrt(3) and cannot overflow.
        let mut largest: Option<(usize, usize, f64)> = None;
        for (k, s) in self.sections.iter().enumerate() {
            for (i, p) in s.points.iter().enumerate() {
                let m = p.x.abs().max(p.y.abs()).max(p.z.abs());
                if largest.is_none_or(|(_, _, l)| m > l) {
                    largest = Some((k, i, m));
                }
            }
        }
        let Some((k, i, m)) = largest else { return Ok(()) };
        let src = self.source.as_str();
        if m > MAX_SIZE / 2.0 || self.size() > MAX_SIZE {
            let s = &self.sections[k];
            return Err(HullError::input(
                s.location(src, i),
                InputErrorKind::ModelSize { size: self.size(), largest: m, at: Some((s.label.clone(), i)) },
            ));
        }
        if self.size() < MIN_SIZE {
            return Err(HullError::input(
                Location::file(src),
                InputErrorKind::ModelSize { size: self.size(), largest: m, at: None },
            ));
        }
        Ok(())
    }

    /// Step 6 of [`Offsets::validate`]: the first section planar in x (within `tol`) two of
    /// whose segments cross in the (y, z) plane.
    fn check_crossings(&self, tol: f64) -> Result<(), HullError> {
        for s in &self.sections {
            let Some(x) = s.mean_x() else { continue };
            if s.points.len() < 4 || s.points.iter().any(|p| (p.x - x).abs() > tol) {
                continue;
            }
            let yz: Vec<[f64; 2]> = s.points.iter().map(|p| [p.y, p.z]).collect();
            if let Some((a, b)) = first_crossing(&yz) {
                return Err(HullError::input(
                    s.location(&self.source, b + 1),
                    InputErrorKind::SectionCrosses {
                        label: s.label.clone(),
                        segment: (b, s.lines.get(b).copied(), s.lines.get(b + 1).copied()),
                        crossed: (a, s.lines.get(a).copied(), s.lines.get(a + 1).copied()),
                    },
                ));
            }
        }
        Ok(())
    }

    /// Step 5 of [`Offsets::validate`]; every section has a point by now.
    fn check_order(&self, tol: f64) -> Result<(), HullError> {
        let mut xs = Vec::with_capacity(self.sections.len());
        for s in &self.sections {
            let Some(x) = s.mean_x() else { return Ok(()) };
            if s.points.iter().any(|p| (p.x - x).abs() > tol) {
                return Ok(()); // free-form section: no order along x to check
            }
            xs.push(x);
        }
        let increasing = xs[1] >= xs[0];
        for i in 1..xs.len() {
            let step = if increasing { xs[i] - xs[i - 1] } else { xs[i - 1] - xs[i] };
            if step <= tol {
                let (s, prev) = (&self.sections[i], &self.sections[i - 1]);
                return Err(HullError::input(
                    s.location(&self.source, 0),
                    InputErrorKind::SectionOrder {
                        label: s.label.clone(),
                        x: xs[i],
                        previous_label: prev.label.clone(),
                        previous_x: xs[i - 1],
                        increasing,
                    },
                ));
            }
        }
        Ok(())
    }
}

/// The first pair `(a, b)`, `a + 1 < b`, of segments `[p_a, p_a+1]` and `[p_b, p_b+1]` of the
/// polyline `pts` that cross properly: each segment's ends lie strictly on opposite sides of the
/// other's line, by the sign of the orientation determinant
/// `orient(p, q, r) = (q - p) x (r - p)` (O'Rourke, *Computational Geometry in C*, 2nd ed.,
/// section 7.2, `SegSegInt` without the touching cases). "First" is the least `b`, then `a`.
///
/// A sweep over the segments in order of their lowest z keeps the work near linear for
/// sections that rise from keel to deck (only segments overlapping in z are compared); it is
/// quadratic only for sections that go up and down across their whole height.
fn first_crossing(pts: &[[f64; 2]]) -> Option<(usize, usize)> {
    let n = pts.len().checked_sub(1)?; // segments
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    let crosses = |a: usize, b: usize| {
        let (p, q, r, t) = (pts[a], pts[a + 1], pts[b], pts[b + 1]);
        let (d1, d2) = (orient(p, q, r), orient(p, q, t));
        let (d3, d4) = (orient(r, t, p), orient(r, t, q));
        d1 * d2 < 0.0 && d3 * d4 < 0.0
    };
    let z_range = |i: usize| (pts[i][1].min(pts[i + 1][1]), pts[i][1].max(pts[i + 1][1]));
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| z_range(a).0.total_cmp(&z_range(b).0));
    let mut active: Vec<usize> = Vec::new();
    let mut best: Option<(usize, usize)> = None;
    for &i in &order {
        let lo = z_range(i).0;
        active.retain(|&j| z_range(j).1 >= lo);
        for &j in &active {
            let (a, b) = (i.min(j), i.max(j));
            if b > a + 1 && crosses(a, b) && best.is_none_or(|(ba, bb)| (b, a) < (bb, ba)) {
                best = Some((a, b));
            }
        }
        active.push(i);
    }
    best
}

impl crate::limits::OffsetCounts for Offsets {
    fn source(&self) -> &str {
        &self.source
    }

    fn section_sizes(&self) -> Vec<(&str, usize)> {
        self.sections.iter().map(|s| (s.label.as_str(), s.points.len())).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box-like hull: `n` stations at x = 0, 1, ..., each with 4 points keel to deck.
    fn boxy(n: usize) -> Offsets {
        let sections = (0..n)
            .map(|i| {
                let x = i as f64;
                let pts = vec![
                    Vec3::new(x, 0.0, 0.0),
                    Vec3::new(x, 1.0, 0.0),
                    Vec3::new(x, 1.0, 1.0),
                    Vec3::new(x, 1.0, 2.0),
                ];
                let mut s = Section::new(format!("{i}"), pts);
                s.lines = (0..4).map(|k| 2 + 4 * i + k).collect();
                s
            })
            .collect();
        Offsets::new("box.csv", Units::Metre, sections)
    }

    fn err(o: &Offsets, min: usize) -> String {
        o.validate(min).err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into())
    }

    #[test]
    fn counts_and_bounds() {
        let o = boxy(3);
        assert_eq!(o.num_points(), 12);
        assert_eq!(o.bounds(), Some((Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 2.0))));
        // Diagonal of a 2 x 1 x 2 box is 3 exactly; sqrt(9) is exact in f64.
        assert_eq!(o.size(), 3.0);
        let empty = Offsets::new("e", Units::Foot, vec![]);
        assert_eq!(empty.bounds(), None);
        assert_eq!(empty.size(), 0.0);
    }

    #[test]
    fn a_regular_hull_validates_in_either_direction() {
        let mut o = boxy(4);
        assert!(o.validate(4).is_ok());
        o.sections.reverse();
        assert!(o.validate(4).is_ok());
    }

    #[test]
    fn too_few_sections() {
        assert_eq!(err(&boxy(1), 2), "box.csv: 1 section(s) (expected at least 2 sections to skin a surface)");
    }

    #[test]
    fn too_few_points_names_the_section_its_line_and_the_counts() {
        let o = boxy(3);
        let e = err(&o, 5);
        assert!(e.starts_with("box.csv:2: section \"0\" has 4 point(s) (expected at least 5 points"), "{e}");
        let mut o = boxy(3);
        o.sections[1].column = Some(3);
        o.sections[1].points.truncate(2);
        let e = err(&o, 3);
        assert!(e.starts_with("box.csv:6:3: section \"1\" has 2 point(s) (expected at least 3"), "{e}");
    }

    #[test]
    fn repeated_consecutive_points_name_both_lines() {
        let mut o = boxy(3);
        // A distance of half the tolerance (1e-9 x size 3) still counts as the same point.
        o.sections[2].points[2] = o.sections[2].points[1] + Vec3::new(0.0, 0.0, 1.5e-9);
        let e = err(&o, 2);
        assert!(e.starts_with("box.csv:12: section \"2\": point 3 (line 12) repeats point 2 (line 11)"), "{e}");
        // Twice the tolerance is a distinct point.
        o.sections[2].points[2] = o.sections[2].points[1] + Vec3::new(0.0, 0.0, 6e-9);
        assert!(o.validate(2).is_ok());
    }

    #[test]
    fn a_section_collapsed_to_one_point_is_a_legal_pointed_end() {
        let mut o = boxy(3);
        let tip = Vec3::new(2.0, 0.0, 1.0);
        o.sections[2].points = vec![tip; 4];
        assert!(o.validate(4).is_ok());
        // ...but it still needs the minimum number of points.
        o.sections[2].points = vec![tip];
        o.sections[2].lines.truncate(1);
        assert!(err(&o, 4).contains("has 1 point(s)"));
    }

    #[test]
    fn non_finite_coordinates_are_rejected_first() {
        let mut o = boxy(1); // also too few sections: the finiteness check comes first
        o.sections[0].points[3].y = f64::NAN;
        let e = err(&o, 2);
        assert!(e.starts_with("box.csv:5: section \"0\": point 4 has a non-finite coordinate (0, NaN, 2)"), "{e}");
    }

    #[test]
    fn planar_sections_out_of_order_are_named() {
        let mut o = boxy(4);
        o.sections.swap(2, 3);
        let e = err(&o, 2);
        assert!(e.starts_with("box.csv:10: section \"2\" at x = 2 is not forward of section \"3\" at x = 3"), "{e}");
        assert!(e.contains("x strictly increasing"), "{e}");
        let mut o = boxy(4);
        o.sections.reverse(); // 3, 2, 1, 0: decreasing
        o.sections.swap(2, 3); // 3, 2, 0, 1: section "1" breaks the order
        let e = err(&o, 2);
        assert!(e.starts_with("box.csv:6: section \"1\" at x = 1 is not aft of section \"0\" at x = 0"), "{e}");
        assert!(e.contains("strictly decreasing"), "{e}");
    }

    #[test]
    fn two_sections_at_the_same_x_are_out_of_order() {
        let mut o = boxy(3);
        for p in &mut o.sections[2].points {
            p.x = 1.0;
        }
        assert!(err(&o, 2).contains("at x = 1 is not forward of section \"1\" at x = 1"));
    }

    #[test]
    fn free_form_sections_skip_the_order_check() {
        let mut o = boxy(3);
        o.sections.swap(0, 2);
        // Section "1" tilts in x: the data are not stations, so their order is not checked.
        o.sections[1].points[3].x += 0.5;
        assert!(o.validate(2).is_ok());
    }

    #[test]
    fn locations_without_source_lines_print_the_file_only() {
        let mut o = boxy(2);
        for s in &mut o.sections {
            s.lines.clear();
            s.column = Some(4);
        }
        o.sections[1].points.truncate(1);
        assert!(err(&o, 2).starts_with("box.csv: section \"1\" has 1 point(s)"));
    }

    #[test]
    fn only_the_end_sections_may_be_one_point() {
        let mut o = boxy(4);
        for k in [0, 3] {
            let p = o.sections[k].points[0];
            o.sections[k].points.iter_mut().for_each(|q| *q = p);
        }
        assert!(o.validate(4).is_ok(), "pointed stern and stem: {}", err(&o, 4));
        let p = o.sections[1].points[2];
        o.sections[1].points.iter_mut().for_each(|q| *q = p);
        // Section "1" starts on line 6 (the header is line 1, four lines a section).
        assert!(err(&o, 4).starts_with("box.csv:6: section \"1\" collapses to one point (1, 1, 1)"), "{}", err(&o, 4));
    }

    #[test]
    fn a_section_that_crosses_itself_is_refused_at_the_later_segment() {
        let mut o = boxy(3);
        // (0,0) -> (2.5,1.5) -> (2.5,0.5) -> (0.5,2): the third segment cuts the first at
        // y = 1.76, z = 1.06 (z = 0.6 y meets y = 2.5 - 2t, z = 0.5 + 1.5t at t = 1/2.7).
        o.sections[1].points =
            [(0.0, 0.0), (2.5, 1.5), (2.5, 0.5), (0.5, 2.0)].iter().map(|&(y, z)| Vec3::new(1.0, y, z)).collect();
        assert!(
            err(&o, 4).starts_with(
                "box.csv:9: section \"1\" crosses itself: its segment from point 3 to 4 (lines 8-9) crosses its \
                 segment from point 1 to 2 (lines 6-7)"
            ),
            "{}",
            err(&o, 4)
        );
    }

    #[test]
    fn first_crossing_finds_proper_crossings_only() {
        // A hollow garboard goes down and up again without crossing.
        assert_eq!(first_crossing(&[[0.0, 0.1], [0.5, 0.0], [1.0, 0.2], [1.2, 1.0], [1.3, 2.0]]), None);
        // A bow-tie: segments 0 and 2 cross at (1, 1).
        assert_eq!(first_crossing(&[[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0]]), Some((0, 2)));
        // Touching at a vertex (the polyline comes back to its point 1) is not a crossing.
        assert_eq!(first_crossing(&[[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [2.0, 2.0], [1.0, 1.0]]), None);
        // The first crossing is the one of the earliest later segment: 3 crosses 0 and 1 crosses none.
        let z = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.5, -1.0], [0.4, 5.0]];
        assert_eq!(first_crossing(&z), Some((0, 2)));
        assert_eq!(first_crossing(&[]), None);
        assert_eq!(first_crossing(&[[0.0, 0.0]]), None);
    }

    #[test]
    fn the_model_size_must_suit_f64_arithmetic() {
        // Micrometres to light years: any realistic scale validates.
        for scale in [1e-6, 1.0, 1e16] {
            let mut o = boxy(3);
            o.sections.iter_mut().flat_map(|s| s.points.iter_mut()).for_each(|p| *p = *p * scale);
            assert!(o.validate(4).is_ok(), "scale {scale}: {}", err(&o, 4));
        }
        let mut o = boxy(3);
        o.sections[2].points[3].z = 1e300;
        // Section "2", point 4 is on line 2 + 4 * 2 + 3 = 13.
        assert!(
            err(&o, 4).starts_with(
                "box.csv:13: the model's size (bounding-box diagonal) is inf with coordinates up to 1e300 \
                 (section \"2\", point 4)"
            ),
            "{}",
            err(&o, 4)
        );
        let mut o = boxy(3);
        o.sections.iter_mut().flat_map(|s| s.points.iter_mut()).for_each(|p| *p = *p * 1e-310);
        assert!(err(&o, 4).starts_with("box.csv: the model's size"), "{}", err(&o, 4));
    }
}
