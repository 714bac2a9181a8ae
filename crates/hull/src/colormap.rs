//! Colour maps shared by every picture (lines plan markers, curvature maps, the 3-D viewer's
//! legend): a sequential map for magnitudes (fit error) and a diverging map for signed fields
//! (Gaussian and mean curvature), both piecewise linear between a few stops; and where the
//! diverging map of a curvature field saturates ([`curvature_limit`]).

/// A colour, 8 bits per channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    pub const BLACK: Rgb = Rgb(0, 0, 0);
    pub const WHITE: Rgb = Rgb(255, 255, 255);
    pub const GREY: Rgb = Rgb(128, 128, 128);

    /// `#rrggbb`.
    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

/// Sequential stops (viridis, sampled at 0, 1/4, 1/2, 3/4, 1).
const SEQUENTIAL: [[u8; 3]; 5] = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];

/// Diverging stops: blue (negative), white (zero), red (positive).
const DIVERGING: [[u8; 3]; 5] = [[33, 102, 172], [146, 197, 222], [247, 247, 247], [244, 165, 130], [178, 24, 43]];

fn ramp(stops: &[[u8; 3]], t: f64) -> Rgb {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (stops.len() - 1) as f64;
    let i = (x.floor() as usize).min(stops.len() - 2);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (stops[i], stops[i + 1]);
    Rgb(mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2]))
}

/// Colour of `value` in `[lo, hi]` on the sequential map (clamped; NaN gives the low end).
pub fn sequential(value: f64, lo: f64, hi: f64) -> Rgb {
    let span = hi - lo;
    ramp(&SEQUENTIAL, if span > 0.0 { (value - lo) / span } else { 0.0 })
}

/// Colour of a signed `value` on the diverging map, white at 0, full colour at `±limit`
/// (clamped; NaN gives white).
pub fn diverging(value: f64, limit: f64) -> Rgb {
    let t = if limit > 0.0 && value.is_finite() { 0.5 + 0.5 * value / limit } else { 0.5 };
    ramp(&DIVERGING, t)
}

/// The sequential stops as `#rrggbb`, low to high (for legends and the viewer).
pub fn sequential_stops() -> Vec<String> {
    SEQUENTIAL.iter().map(|c| Rgb(c[0], c[1], c[2]).hex()).collect()
}

/// The diverging stops as `#rrggbb`, negative to positive.
pub fn diverging_stops() -> Vec<String> {
    DIVERGING.iter().map(|c| Rgb(c[0], c[1], c[2]).hex()).collect()
}

/// Quantile of `|curvature|` at which the diverging colour map saturates (the 3-D viewer, the
/// glTF export).
pub const CURVATURE_QUANTILE: f64 = 0.98;

/// The `q`-quantile (`0 <= q <= 1`) of the finite `|values|`, by the nearest-rank rule;
/// `None` if no value is finite.
pub fn abs_quantile(values: &[f64], q: f64) -> Option<f64> {
    let mut a: Vec<f64> = values.iter().filter(|v| v.is_finite()).map(|v| v.abs()).collect();
    if a.is_empty() {
        return None;
    }
    a.sort_by(f64::total_cmp);
    let rank = ((q.clamp(0.0, 1.0) * a.len() as f64).ceil() as usize).clamp(1, a.len());
    Some(a[rank - 1])
}

/// The limit `±L` at which a curvature field saturates the diverging map: the
/// [`CURVATURE_QUANTILE`] of `|K|` (nearest rank), 1 if there is no positive one.
pub fn curvature_limit(values: &[f64]) -> f64 {
    abs_quantile(values, CURVATURE_QUANTILE).filter(|&l| l > 0.0).unwrap_or(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantile_by_nearest_rank() {
        let v: Vec<f64> = (1..=100).map(|i| -(i as f64)).chain([f64::NAN]).collect();
        assert_eq!(abs_quantile(&v, 0.98), Some(98.0));
        assert_eq!(abs_quantile(&v, 1.0), Some(100.0));
        assert_eq!(abs_quantile(&v, 0.0), Some(1.0));
        assert_eq!(abs_quantile(&[f64::NAN], 0.5), None);
    }

    #[test]
    fn ends_and_middle_hit_the_stops() {
        assert_eq!(sequential(0.0, 0.0, 1.0), Rgb(68, 1, 84));
        assert_eq!(sequential(1.0, 0.0, 1.0), Rgb(253, 231, 37));
        assert_eq!(sequential(0.5, 0.0, 1.0), Rgb(33, 145, 140));
        assert_eq!(diverging(0.0, 3.0), Rgb(247, 247, 247));
        assert_eq!(diverging(-3.0, 3.0), Rgb(33, 102, 172));
        assert_eq!(diverging(7.0, 3.0), Rgb(178, 24, 43));
    }

    #[test]
    fn out_of_range_and_nan_are_clamped() {
        assert_eq!(sequential(-5.0, 0.0, 1.0), sequential(0.0, 0.0, 1.0));
        assert_eq!(sequential(f64::NAN, 0.0, 1.0), sequential(0.0, 0.0, 1.0));
        assert_eq!(diverging(f64::NAN, 1.0), Rgb(247, 247, 247));
        assert_eq!(sequential(0.3, 1.0, 1.0), Rgb(68, 1, 84));
    }

    #[test]
    fn halfway_between_stops_is_the_mean() {
        // t = 1/8 lies halfway between stops 0 and 1.
        let c = sequential(0.125, 0.0, 1.0);
        assert_eq!(c, Rgb(64, 42, 112)); // (68+59)/2 = 63.5 -> 64, (1+82)/2 = 41.5 -> 42, (84+139)/2 = 111.5 -> 112
    }
}
