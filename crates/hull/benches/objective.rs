//! The weight-optimisation objective's hot loop: evaluations per second by problem size, with
//! fixed and with re-solved (variable projection, banded normal equations) control points, and
//! the time of a Levenberg-Marquardt run.
//!
//! Sizes sweep `n_u x n_v` bicubic nets over hull-like tables of `K` sections of `N` points;
//! the reference case is `10x8_250` (floors: 100,000 evaluations/s fixed, 20,000/s
//! re-solved, one core). Degenerate case: the rank-one layout (`n_u + n_v` variables, the same
//! system to solve per evaluation). Criterion reports throughput in evaluations per second
//! (`elem/s`).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use hull::{
    fit_offsets, quiet, run_lm, series60_sample, FitConfig, LmOptions, Objective, Offsets, Section, Units,
    WeightLayout, WeightMode, WeightOptions, WeightProblem,
};
use nurbs::Vec3;

/// `k` stations of `n` waterlines of `y = b/2 (1 - (2x/l)^2 (0.8)) (1 - (1 - z/t)^4)`.
fn hull_table(k: usize, n: usize) -> Offsets {
    let (l, b, t) = (100.0, 16.0, 6.0);
    let sections = (0..k)
        .map(|s| {
            let x = -l / 2.0 + l * s as f64 / (k - 1) as f64;
            let pts = (0..n)
                .map(|j| {
                    let z = t * j as f64 / (n - 1) as f64;
                    let y = b / 2.0 * (1.0 - 0.8 * (2.0 * x / l).powi(2)) * (1.0 - (1.0 - z / t).powi(4));
                    Vec3::new(x, y, z)
                })
                .collect();
            Section::new(format!("{s}"), pts)
        })
        .collect();
    Offsets::new("bench hull", Units::Metre, sections)
}

fn problem(offsets: &Offsets, ctrl: (usize, usize), mode: WeightMode, layout: WeightLayout) -> WeightProblem {
    let cfg = FitConfig { ctrl: Some(ctrl), ..FitConfig::default() };
    let fit = fit_offsets(offsets, &cfg).expect("bench table fits");
    let opts = WeightOptions { mode, layout, ..WeightOptions::default() };
    WeightProblem::from_fit(&fit, offsets, opts).expect("shapes match")
}

fn bench(c: &mut Criterion) {
    // (label, sections, points per section, control points)
    let sizes = [
        ("6x6_150", 15, 10, (6, 6)),
        ("10x8_250", 25, 10, (10, 8)),
        ("12x16_600", 40, 15, (12, 16)),
        ("16x24_1200", 60, 20, (16, 24)),
    ];
    let mut g = c.benchmark_group("objective_value");
    g.throughput(Throughput::Elements(1));
    for (label, k, n, ctrl) in sizes {
        let offsets = hull_table(k, n);
        for (name, mode, layout) in [
            ("fixed", WeightMode::Fixed, WeightLayout::Full),
            ("resolved", WeightMode::Resolved, WeightLayout::Full),
            ("resolved_rank_one", WeightMode::Resolved, WeightLayout::RankOne),
        ] {
            let p = problem(&offsets, ctrl, mode, layout);
            // A point off the start, inside the box.
            let x: Vec<f64> = (0..p.dim()).map(|i| 0.3 * ((i as f64) * 0.7).sin()).collect();
            assert!(p.value(&x).is_finite());
            g.bench_with_input(BenchmarkId::new(name, label), &x, |b, x| b.iter(|| p.value(black_box(x))));
        }
    }
    // The built-in Series 60 table at its default control points (the GSA floor's case).
    let offsets = series60_sample();
    for (name, mode) in [("fixed", WeightMode::Fixed), ("resolved", WeightMode::Resolved)] {
        let p = problem(&offsets, (6, 19), mode, WeightLayout::Full);
        let x: Vec<f64> = (0..p.dim()).map(|i| 0.3 * ((i as f64) * 0.7).sin()).collect();
        g.bench_with_input(BenchmarkId::new(name, "series60_6x19_200"), &x, |b, x| b.iter(|| p.value(black_box(x))));
    }
    g.finish();

    let mut g = c.benchmark_group("lm_series60_6x12");
    g.sample_size(20);
    let offsets = series60_sample();
    for (name, layout) in [("full", WeightLayout::Full), ("rank_one", WeightLayout::RankOne)] {
        let p = problem(&offsets, (6, 12), WeightMode::Resolved, layout);
        g.bench_function(name, |b| b.iter(|| quiet(|c| run_lm(black_box(&p), &LmOptions::default(), c))));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
