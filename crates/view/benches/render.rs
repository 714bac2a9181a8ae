//! Static pictures: the curvature map of the sample hull (issue floor: under one second for the
//! sample hull), swept over image width and grid density, and the rasterisation of an A3
//! drawing at 150 dpi.
//!
//! Surfaces: the built-in Series 60 sample fitted with the default `approx` (6 x 19 control
//! points) and interpolated (8 x 25, the densest net of those offsets). Degenerate case: a
//! sphere octant whose edge collapses to the pole (a line of grid points with undefined
//! curvature).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use hull::{fit_offsets, series60_sample, CurvatureField, FitConfig, FitMethod};
use nurbs::NurbsSurface;
use view::{convergence_plot, curvature_map_png, render_png, CurvatureImageOptions, RasterOptions};

/// The unit sphere's octant, u from the equator to the pole (the edge u = 1 collapses to it).
fn octant() -> NurbsSurface {
    nurbs::fixtures::sphere_octant(1.0).reversed_u()
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
        let o = CurvatureImageOptions { units: "m".into(), ..CurvatureImageOptions::default() };
        g.bench_with_input(BenchmarkId::new("default", name), surface, |b, s| {
            b.iter(|| curvature_map_png(black_box(s), CurvatureField::Gaussian, &o).expect("renders"))
        });
    }
    for width in [800u32, 3200] {
        let o = CurvatureImageOptions { width_px: width, units: "m".into(), ..CurvatureImageOptions::default() };
        g.bench_with_input(BenchmarkId::new("width", width), &approx, |b, s| {
            b.iter(|| curvature_map_png(black_box(s), CurvatureField::Gaussian, &o).expect("renders"))
        });
    }
    for samples in [80usize, 320] {
        let o = CurvatureImageOptions { samples, units: "m".into(), ..CurvatureImageOptions::default() };
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
