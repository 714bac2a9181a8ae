//! Fitting cost: skinning a family of sections (interpolation and least squares) and curve
//! interpolation, sweeping the family's size. The degenerate cases are a family whose end
//! sections have zero width (vertical lines, as in a ship's offset table) and one whose end
//! sections collapse to single points (pointed ends), plus unequal point counts (`ragged`, and
//! the R/V Gunnerus sections: 62 of 8 to 16 points), which take the common-knot path with fair
//! constrained interpolation of the shorter sections.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use nurbs::fit::{interpolate_curve_auto, skin_approximate, skin_interpolate, Parameterization, SkinOptions};
use nurbs::{fixtures, Vec3};

/// `k` sections of `n` points of a Wigley-like body, `y = B/2 (1 - (2x/L)^2) (1 - (1 - z/T)^4)`:
/// zero width at both ends. `pointed` collapses the end sections to one point each; `ragged`
/// drops the top point of every other section.
fn table(k: usize, n: usize, pointed: bool, ragged: bool) -> Vec<Vec<Vec3>> {
    let (l, b, t) = (100.0, 16.0, 6.0);
    (0..k)
        .map(|s| {
            let x = -l / 2.0 + l * s as f64 / (k - 1) as f64;
            if pointed && (s == 0 || s == k - 1) {
                return vec![Vec3::new(x, 0.0, t / 2.0)];
            }
            let count = if ragged && s % 2 == 1 { n - 1 } else { n };
            (0..count)
                .map(|j| {
                    // Cosine spacing of the points: dense at the bottom, as in real tables.
                    let z = t * (1.0 - (std::f64::consts::FRAC_PI_2 * j as f64 / (n - 1) as f64).cos());
                    let y = b / 2.0 * (1.0 - (2.0 * x / l).powi(2)) * (1.0 - (1.0 - z / t).powi(4));
                    Vec3::new(x, y, z)
                })
                .collect()
        })
        .collect()
}

fn bench_skin(c: &mut Criterion) {
    let opts = SkinOptions::default();
    let cases = [
        ("21x11", table(21, 11, false, false)),
        ("21x11_pointed", table(21, 11, true, false)),
        ("21x11_ragged", table(21, 11, false, true)),
        ("64x20", table(64, 20, false, false)),
        ("gunnerus_62x8-16", fixtures::gunnerus_sections()),
    ];
    let mut g = c.benchmark_group("skin_interpolate");
    for (name, s) in &cases {
        g.bench_with_input(BenchmarkId::from_parameter(name), s, |bch, s| {
            bch.iter(|| skin_interpolate(black_box(s), &opts).expect("valid table"))
        });
    }
    g.finish();
    let mut g = c.benchmark_group("skin_approximate");
    for (name, s, nu, nv) in [
        ("21x11_to_8x12", &cases[0].1, 8, 12),
        ("21x11_pointed_to_8x12", &cases[1].1, 8, 12),
        ("21x11_ragged_to_8x12", &cases[2].1, 8, 12),
        ("64x20_to_12x24", &cases[3].1, 12, 24),
        ("gunnerus_to_4x40", &cases[4].1, 4, 40),
        ("gunnerus_to_8x40", &cases[4].1, 8, 40),
        ("gunnerus_to_12x40", &cases[4].1, 12, 40),
    ] {
        // Before fair constrained interpolation, nu above the smallest section (8 for
        // Gunnerus) was refused: skip what the kernel refuses rather than abort the run.
        if skin_approximate(s, nu, nv, &opts).is_err() {
            continue;
        }
        g.bench_with_input(BenchmarkId::from_parameter(name), s, |bch, s| {
            bch.iter(|| skin_approximate(black_box(s), nu, nv, &opts).expect("valid table"))
        });
    }
    g.finish();
}

fn bench_curve(c: &mut Criterion) {
    let mut g = c.benchmark_group("interpolate_curve");
    for n in [11usize, 64, 512] {
        let pts: Vec<Vec3> = (0..n)
            .map(|i| {
                let s = 6.0 * i as f64 / (n - 1) as f64;
                Vec3::new(s, s.sin(), 0.3 * (2.0 * s).cos())
            })
            .collect();
        for p in [3usize, 5] {
            g.bench_with_input(BenchmarkId::new(format!("p{p}"), n), &pts, |bch, pts| {
                bch.iter(|| interpolate_curve_auto(black_box(pts), p, Parameterization::Centripetal).expect("valid"))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench_skin, bench_curve);
criterion_main!(benches);
