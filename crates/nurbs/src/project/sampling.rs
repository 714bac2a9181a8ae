//! Where the projectors sample before Newton starts: parameters by knot span, graded and
//! denser where the tangent turns, and a bounding sphere per span.

use crate::Vec3;

/// Sample parameters with `counts[i]` equal intervals in span `i` of `br`, plus, when `grade`
/// says so for the first (last) end, [`GRADED_LEVELS`] extra samples halving the first (last)
/// interval towards that end. Returns the parameters, each span's first sample index and each
/// span's final interval count.
pub(super) fn sample_params_by_span(
    br: &[f64],
    counts: &[usize],
    grade: (bool, bool),
) -> (Vec<f64>, Vec<usize>, Vec<usize>) {
    let mut out = Vec::with_capacity(counts.iter().sum::<usize>() + 2 * GRADED_LEVELS + 1);
    let mut starts = Vec::with_capacity(counts.len());
    let mut finals = Vec::with_capacity(counts.len());
    let last = counts.len() - 1;
    for (i, (w, &g)) in br.windows(2).zip(counts).enumerate() {
        starts.push(out.len());
        let h = (w[1] - w[0]) / g as f64;
        let mut n = g;
        for k in 0..g {
            out.push(w[0] + h * k as f64);
            if k == 0 && i == 0 && grade.0 {
                out.extend((1..=GRADED_LEVELS).rev().map(|l| w[0] + h / (1u32 << l) as f64));
                n += GRADED_LEVELS;
            }
        }
        if i == last && grade.1 {
            out.extend((1..=GRADED_LEVELS).map(|l| w[1] - h / (1u32 << l) as f64));
            n += GRADED_LEVELS;
        }
        finals.push(n);
    }
    out.push(br[br.len() - 1]);
    (out, starts, finals)
}

/// Extra sample rows graded towards a collapsed edge (at 1/2, 1/4, 1/8 of the first interval):
/// near a stem the parameterization is polar-like and the distance varies fastest there.
pub(super) const GRADED_LEVELS: usize = 3;

/// Largest tangent turning per sampling interval, in radians: spans whose tangent turns more
/// get more intervals, so a sharp bend cannot hide a second minimum between two samples.
pub(super) const TURN_PER_INTERVAL: f64 = 0.3;
/// Upper limit of sampling intervals per knot span.
pub(super) const MAX_INTERVALS: usize = 64;
/// Sub-steps per span used to measure the turning.
pub(super) const TURN_STEPS: usize = 16;

/// Intervals per span of `br`: at least `base`, and enough that the tangent `tangent(t)` turns
/// by at most [`TURN_PER_INTERVAL`] per interval (measured at [`turning_params`]).
pub(super) fn intervals_by_turning(br: &[f64], base: usize, tangent: impl Fn(f64) -> Vec3) -> Vec<usize> {
    let ts: Vec<Vec3> = turning_params(br).into_iter().map(tangent).collect();
    ts.chunks(TURN_STEPS + 1).map(|span| intervals_for_turning(span, base)).collect()
}

/// The parameters at which a span's turning is measured: [`TURN_STEPS`] steps per span of
/// `br`, both ends included, span `k`'s at `k * (TURN_STEPS + 1)..(k + 1) * (TURN_STEPS + 1)`.
pub(super) fn turning_params(br: &[f64]) -> Vec<f64> {
    br.windows(2)
        .flat_map(|w| {
            (0..=TURN_STEPS).map(move |k| {
                if k == TURN_STEPS {
                    w[1]
                } else {
                    w[0] + (w[1] - w[0]) * k as f64 / TURN_STEPS as f64
                }
            })
        })
        .collect()
}

/// Intervals for one span whose tangents at [`turning_params`] are `ts`: at least `base`, and
/// enough that the tangent turns by at most [`TURN_PER_INTERVAL`] per interval. Tangents
/// shorter than 1e-6 of the longest in the span (a collapsed edge) have no direction and are
/// skipped.
pub(super) fn intervals_for_turning(ts: &[Vec3], base: usize) -> usize {
    let longest = ts.iter().map(|t| t.norm()).fold(0.0, f64::max);
    let mut total = 0.0;
    let mut prev: Option<Vec3> = None;
    for &t in ts {
        let has_direction = t.norm() > 1e-6 * longest; // false for NaN too
        if !has_direction {
            continue;
        }
        if let Some(p) = prev {
            total += p.cross(t).norm().atan2(p.dot(t));
        }
        prev = Some(t);
    }
    let need = (total / TURN_PER_INTERVAL).ceil();
    let need = if need.is_finite() { need as usize } else { base };
    need.clamp(base, MAX_INTERVALS.max(base))
}

/// The parameters of every span's fine grid for [`span_radius`]: `2 * counts[i] + 1` equal
/// steps over span `i` of `br`, both ends included, and where each span's start in the list.
pub(super) fn fine_params(br: &[f64], counts: &[usize]) -> (Vec<f64>, Vec<usize>) {
    let mut out = Vec::new();
    let mut starts = Vec::with_capacity(counts.len());
    for (w, &g) in br.windows(2).zip(counts) {
        starts.push(out.len());
        let f = 2 * g;
        out.extend((0..=f).map(|a| if a == f { w[1] } else { w[0] + (w[1] - w[0]) * a as f64 / f as f64 }));
    }
    (out, starts)
}

/// Radius about `center` of a sphere holding the surface over one span sampled with
/// `fu / 2 x fv / 2` intervals, from its points `at(a, b)` at half that spacing (`a <= fu`,
/// `b <= fv`, [`fine_params`]): the farthest of them, plus the largest deviation of the half-spacing samples from the bilinear interpolation of the
/// coarse ones. That deviation is a second-order sag, four times the sag left between the fine
/// samples, so the bound holds wherever the second derivatives vary little over a cell.
pub(super) fn span_radius(at: impl Fn(usize, usize) -> Vec3, center: Vec3, fu: usize, fv: usize) -> f64 {
    let mut far: f64 = 0.0;
    let mut sag: f64 = 0.0;
    for a in 0..=fu {
        for b in 0..=fv {
            let p = at(a, b);
            far = far.max((p - center).norm());
            let (a_odd, b_odd) = (a % 2 == 1, b % 2 == 1);
            let interp = match (a_odd, b_odd) {
                (false, false) => continue,
                (true, false) => (at(a - 1, b) + at(a + 1, b)) * 0.5,
                (false, true) => (at(a, b - 1) + at(a, b + 1)) * 0.5,
                (true, true) => (at(a - 1, b - 1) + at(a + 1, b - 1) + at(a - 1, b + 1) + at(a + 1, b + 1)) * 0.25,
            };
            sag = sag.max((p - interp).norm());
        }
    }
    far + sag
}
