//! Test data shared by the kernel's tests and, with the feature `fixtures`, by the tests of the
//! crates above it (the benchmarks include this file): one place for each fixture. Not part
//! of the API.

use crate::Vec3;

/// A rounded-box section at `x`: a straight run on the plane `z = 0` from `(0, 0)` to
/// `(b - r, 0)` in `n_flat` chords, a quarter circle of radius `r` in 3 chords, a straight
/// run on the plane `y = b` from `(b, r)` to `(b, h)` in `n_side` chords.
pub fn rounded_box_section(x: f64, b: f64, r: f64, h: f64, n_flat: usize, n_side: usize) -> Vec<Vec3> {
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

/// 9 sections: the middle 5 rounded boxes (on `z = 0` to `y = 2`, on `y = 3` from `z = 1`),
/// the two at each end narrower quarter ellipses.
pub fn rounded_box_sections() -> Vec<Vec<Vec3>> {
    (0..9)
        .map(|k| {
            let x = k as f64;
            if (2..7).contains(&k) {
                rounded_box_section(x, 3.0, 1.0, 4.0, 4, 3)
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

/// The R/V Gunnerus sections of `testdata/gunnerus_sections.csv` (`section,x,y,z`, one row per
/// point, a section's rows together; the offset table's points, see `testdata/README.md`): 62
/// sections of 8 to 16 points, bottom to top.
pub fn gunnerus_sections() -> Vec<Vec<Vec3>> {
    let text = include_str!("../../../testdata/gunnerus_sections.csv");
    let mut sections: Vec<(&str, Vec<Vec3>)> = Vec::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').collect();
        let num = |i: usize| -> f64 { f[i].trim().parse().expect("a number") };
        let p = Vec3::new(num(1), num(2), num(3));
        match sections.last_mut() {
            Some((label, pts)) if *label == f[0] => pts.push(p),
            _ => sections.push((f[0], vec![p])),
        }
    }
    sections.into_iter().map(|(_, pts)| pts).collect()
}
