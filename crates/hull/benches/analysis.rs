//! Shape analysis times on the fitted Series 60 sample and on a fitted 21 x 11 offset table:
//! the curvature map by grid size, the cuts of a lines plan (21 stations, 10 waterlines, 5
//! buttocks; the issue asks for a curvature map and a lines plan of a 21 x 11 hull in under a
//! second), the fairness report, and degenerate planes (the baseline waterline on the keel
//! edge, the FP station on the stem edge: a whole grid line in the plane).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use hull::{
    curvature_map, cut_surface, cut_surface_many, fairness_report, fit_offsets, series60_sample, CurvatureMapOptions,
    CutOptions, CutPlane, FairnessOptions, FitConfig, Offsets, Section, Units, SAMPLE_PARTICULARS,
};
use nurbs::{NurbsSurface, Vec3};

/// 21 stations by 11 waterlines of a parabolic hull `y = b/2 (1 - 0.8 (2x/l)^2) (1 - (1 - z/t)^4)`.
fn table_21x11() -> Offsets {
    let (l, b, t) = (100.0, 16.0, 6.0);
    let sections = (0..21)
        .map(|s| {
            let x = l * s as f64 / 20.0;
            let xc = x - l / 2.0;
            let pts = (0..11)
                .map(|j| {
                    let z = t * j as f64 / 10.0;
                    let y = b / 2.0 * (1.0 - 0.8 * (2.0 * xc / l).powi(2)) * (1.0 - (1.0 - z / t).powi(4));
                    Vec3::new(x, y, z)
                })
                .collect();
            Section::new(format!("{s}"), pts)
        })
        .collect();
    Offsets::new("bench 21x11", Units::Metre, sections)
}

/// 21 stations from end to end, 10 waterlines and 5 buttocks strictly inside.
fn lines_plan(length: f64, half_breadth: f64, depth: f64) -> Vec<CutPlane> {
    let mut planes: Vec<CutPlane> = (0..=20).map(|k| CutPlane::Station(length * k as f64 / 20.0)).collect();
    planes.extend((1..=10).map(|k| CutPlane::Waterline(depth * k as f64 / 11.0)));
    planes.extend((1..=5).map(|k| CutPlane::Buttock(half_breadth * k as f64 / 6.0)));
    planes
}

fn cases() -> Vec<(&'static str, NurbsSurface, Vec<CutPlane>)> {
    let p = SAMPLE_PARTICULARS;
    let s60 = fit_offsets(&series60_sample(), &FitConfig::default()).expect("the sample fits").surface;
    let t = fit_offsets(&table_21x11(), &FitConfig::default()).expect("the table fits").surface;
    vec![
        ("series60", s60, lines_plan(p.lpp, p.beam / 2.0, 1.5 * p.draft)),
        ("table_21x11", t, lines_plan(100.0, 8.0, 6.0)),
    ]
}

fn bench(c: &mut Criterion) {
    let cases = cases();
    let opts = CutOptions::default();

    let mut g = c.benchmark_group("curvature_map");
    for (name, s, _) in &cases[..1] {
        for n in [25, 50, 100] {
            let o = CurvatureMapOptions { grid: (n, n), ..CurvatureMapOptions::default() };
            g.bench_with_input(BenchmarkId::new(format!("{n}x{n}"), name), s, |b, s| {
                b.iter(|| curvature_map(black_box(s), &o).summary())
            });
        }
    }
    g.finish();

    let mut g = c.benchmark_group("lines_plan_cuts");
    for (name, s, planes) in &cases {
        g.bench_with_input(BenchmarkId::new("36_planes_parallel", name), s, |b, s| {
            b.iter(|| cut_surface_many(black_box(s), planes, &opts))
        });
        g.bench_with_input(BenchmarkId::new("36_planes_one_by_one", name), s, |b, s| {
            b.iter(|| planes.iter().map(|&p| cut_surface(black_box(s), p, &opts)).collect::<Vec<_>>())
        });
    }
    // Grid sweep: the grid is sampled once per call; finer grids find smaller features.
    for n in [32, 64, 128] {
        let o = CutOptions { grid: (n, n), ..CutOptions::default() };
        let (name, s, planes) = &cases[0];
        g.bench_with_input(BenchmarkId::new(format!("grid_{n}"), name), s, |b, s| {
            b.iter(|| cut_surface_many(black_box(s), planes, &o))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("cut_degenerate");
    let (_, s60, _) = &cases[0];
    let p = SAMPLE_PARTICULARS;
    for (label, plane) in [
        ("station_midship", CutPlane::Station(p.lpp / 2.0)),
        ("baseline_on_keel_edge", CutPlane::Waterline(0.0)),
        ("fp_station_on_stem_edge", CutPlane::Station(p.lpp)),
    ] {
        g.bench_function(label, |b| b.iter(|| cut_surface(black_box(s60), plane, &opts)));
    }
    g.finish();

    let mut g = c.benchmark_group("fairness_report");
    g.sample_size(20);
    for (name, s, _) in &cases {
        g.bench_with_input(BenchmarkId::from_parameter(name), s, |b, s| {
            b.iter(|| fairness_report(black_box(s), &FairnessOptions::default()))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
