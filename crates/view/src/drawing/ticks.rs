//! Round tick marks for the scales of drawings and pictures (the lines plan's rulers, the
//! curvature picture's and the convergence plot's axes).

/// Round tick positions covering `[lo, hi]`, about `target` of them, and their step: the step
/// is the `{1, 2, 5} x 10^k` whose tick count `(hi - lo) / step` is nearest to `target` (the
/// larger step on a tie), after Heckbert, "Nice numbers for graph labels", Graphics Gems (1990).
/// Empty if the range is not finite or `hi < lo`.
pub(crate) fn nice_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, f64) {
    if !(lo.is_finite() && hi.is_finite() && hi >= lo) {
        return (Vec::new(), 0.0);
    }
    let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
    let target = target.max(1) as f64;
    let mag = 10f64.powf((span / target).log10().floor());
    let mut step = mag;
    for s in [0.5, 1.0, 2.0, 5.0, 10.0, 20.0].map(|m| m * mag) {
        if (span / s - target).abs() <= (span / step - target).abs() {
            step = s;
        }
    }
    // Tolerance of 1e-9 steps so that an end lying on a multiple of the step is kept despite
    // rounding in `lo / step`.
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    let ticks = (first..=last).map(|i| i as f64 * step).collect();
    (ticks, step)
}

/// `v` written with as many decimals as the tick `step` needs (`0.25` for step 0.05, `120` for
/// step 20); `-0` is written `0`.
pub(crate) fn format_tick(v: f64, step: f64) -> String {
    let decimals = if step > 0.0 && step.is_finite() { (-(step.log10() - 1e-9).floor()).max(0.0) as usize } else { 0 };
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        "0".into()
    } else {
        s
    }
}

/// `10` with `e` as a superscript exponent: `10⁻³`, `10⁰`, `10²`.
// For the convergence plot's log axis (the PNG pictures).
#[cfg_attr(not(feature = "png"), allow(dead_code))]
pub(crate) fn power_of_ten(e: i32) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::from("10");
    if e < 0 {
        s.push('⁻');
    }
    for d in e.unsigned_abs().to_string().bytes() {
        s.push(SUP[(d - b'0') as usize]);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_ticks_are_round_and_cover_the_range() {
        let (t, step) = nice_ticks(0.0, 121.92, 6);
        // 121.92 / 20 = 6.1 ticks is nearest to 6 (10 gives 12.2, 50 gives 2.4).
        assert_eq!(step, 20.0);
        assert_eq!(t, vec![0.0, 20.0, 40.0, 60.0, 80.0, 100.0, 120.0]);
        // Step 0.2 gives 3 intervals (1 from 4), 0.1 gives 6 (2 from 4), 0.5 gives 1.2.
        let (t, step) = nice_ticks(-0.3, 0.3, 4);
        assert!((step - 0.2).abs() < 1e-15);
        assert_eq!(t.len(), 3); // -0.2, 0, 0.2
        assert!(nice_ticks(f64::NAN, 1.0, 5).0.is_empty());
    }

    #[test]
    fn tick_formats() {
        assert_eq!(format_tick(0.25, 0.05), "0.25");
        assert_eq!(format_tick(120.0, 20.0), "120");
        assert_eq!(format_tick(-1e-17, 0.1), "0");
    }

    #[test]
    fn superscript_powers() {
        assert_eq!(power_of_ten(-3), "10⁻³");
        assert_eq!(power_of_ten(0), "10⁰");
        assert_eq!(power_of_ten(12), "10¹²");
    }
}
