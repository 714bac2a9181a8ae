//! Static pictures: the curvature map of the sample hull (issue floor: under one second for the
//! sample hull), swept over image width and grid density, and the rasterisation of an A3
//! drawing at 150 dpi.
//!
//! Surfaces: the built-in Series 60 sample fitted with the default `approx` (6 x 19 control
//! points) and interpolated (8 x 25, the densest net of those offsets). Degenerate case: a
//! sphere octant whose edge collapses to the pole (a line of grid points with undefined
//! curvature).

use std::f64::consts::FRAC_1_SQRT_2;

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use hull::analysis::CurvatureField;
use hull::{fit_offsets, series60_sample, FitConfig, FitMethod};
use nurbs::{KnotVector, NurbsSurface, Vec3};
use view::{convergence_plot, curvature_map_png, render_png, CurvatureMapOptions, RasterOptions};

fn octant() -> NurbsSurface {
    let c = FRAC_1_SQRT_2;
    let meridian = [(1.0, 0.0, 1.0), (1.0, 1.0, c), (0.0, 1.0, 1.0)];
    let longitude = [(1.0, 0.0, 1.0), (1.0, 1.0, c), (0.0, 1.0, 1.0)];
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for &(rho, z, wm) in &meridian {
        for &(cx, cy, wl) in &longitude {
            pts.push(Vec3::new(rho * cx, rho * cy, z));
            w.push(wm * wl);
        }
    }
    let k = || KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("quadratic knots");
    NurbsSurface::try_new(k(), k(), &pts, Some(&w)).expect("valid octant")
}

fn bench(c: &mut Criterion) {
    let offsets = series60_sample();
    let approx = fit_offsets(&offsets, &FitConfig::default()).expect("the sample fits").surface;
    let interp = fit_offsets(&offsets, &FitConfig { method: FitMethod::Interp, ..FitConfig::default() })
        .expect("the sample interpolates")
        .surface;

    let mut g = c.benchmark_group("curvature_map_png");
    g.sample_size(10);
    // The case: the sample hull at the default options (1600 px, ~160 x 160 grid).
    for (name, surface) in [("sample_approx", &approx), ("sample_interp", &interp), ("octant_pole", &octant())] {
        let o = CurvatureMapOptions { units: "m".into(), ..CurvatureMapOptions::default() };
        g.bench_with_input(BenchmarkId::new("default", name), surface, |b, s| {
            b.iter(|| curvature_map_png(black_box(s), CurvatureField::Gaussian, &o).expect("renders"))
        });
    }
    for width in [800u32, 3200] {
        let o = CurvatureMapOptions { width_px: width, units: "m".into(), ..CurvatureMapOptions::default() };
        g.bench_with_input(BenchmarkId::new("width", width), &approx, |b, s| {
            b.iter(|| curvature_map_png(black_box(s), CurvatureField::Gaussian, &o).expect("renders"))
        });
    }
    for samples in [80usize, 320] {
        let o = CurvatureMapOptions { samples, units: "m".into(), ..CurvatureMapOptions::default() };
        g.bench_with_input(BenchmarkId::new("samples", samples), &approx, |b, s| {
            b.iter(|| curvature_map_png(black_box(s), CurvatureField::Mean, &o).expect("renders"))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("render_png");
    g.sample_size(10);
    let history: Vec<f64> = (0..500).map(|i| 0.05 * (-(i as f64) / 80.0).exp() + 1e-4).collect();
    let plot = convergence_plot(&[("GA", &history), ("PSO", &history[..300])], "bench", "m");
    let mut a3 = plot.clone();
    (a3.width_mm, a3.height_mm) = (420.0, 297.0);
    for (name, d) in [("convergence_200x130mm", &plot), ("a3_sheet", &a3)] {
        g.bench_with_input(BenchmarkId::new("150dpi", name), d, |b, d| {
            b.iter(|| render_png(black_box(d), &RasterOptions::default()).expect("renders"))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
