//! The lines plan: building the drawing (cuts, offset errors, layout) and writing it as SVG and
//! DXF. The target: the lines plan of a 21 x 11 hull (21 stations of 11 points, fitted
//! by the default pipeline) in under a second, `lines_plan` + `write_svg` together.
//!
//! Cases: `table_21x11` (the target), the built-in Series 60 sample (25 x 8) without and with
//! curvature combs, and the degenerate Wigley Bezier patch (3 x 3 poles, both ends and the keel
//! collapsed onto the centre plane: every station and buttock ends on a degenerate edge).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use hull::{fit_offsets, series60_sample, FitConfig, Offsets, Section, Units};
use nurbs::{NurbsSurface, Vec3};
use view::{lines_plan, write_dxf, write_svg, LinesPlanOptions};

/// `k` stations of `n` points of `y = b/2 (1 - 0.8 (2x/l)^2) (1 - (1 - z/t)^4)`.
fn hull_table(k: usize, n: usize) -> Offsets {
    let (l, b, t) = (100.0, 16.0, 6.0);
    let sections = (0..k)
        .map(|s| {
            let x = l * s as f64 / (k - 1) as f64;
            let xi = 2.0 * x / l - 1.0;
            let pts = (0..n)
                .map(|j| {
                    let z = t * j as f64 / (n - 1) as f64;
                    Vec3::new(x, b / 2.0 * (1.0 - 0.8 * xi * xi) * (1.0 - (1.0 - z / t).powi(4)), z)
                })
                .collect();
            Section::new(format!("{s}"), pts)
        })
        .collect();
    Offsets::new("bench hull 21 x 11", Units::Metre, sections)
}

/// The Wigley hull (L 100 m, B 10 m, T 6.25 m) as a degree (2, 2) Bezier patch: the tests'
/// patch.
#[allow(dead_code)]
#[path = "../../hull/tests/common/surfaces.rs"]
mod surfaces;

fn wigley() -> NurbsSurface {
    surfaces::wigley_patch(100.0, 10.0, 6.25)
}

fn bench_lines_plan(c: &mut Criterion) {
    let table = hull_table(21, 11);
    let table_fit = fit_offsets(&table, &FitConfig::default()).expect("the bench table fits").surface;
    let sample = series60_sample();
    let sample_fit = fit_offsets(&sample, &FitConfig::default()).expect("the sample fits").surface;
    let plain = LinesPlanOptions::default();
    let combs = LinesPlanOptions { combs: true, ..LinesPlanOptions::default() };

    let mut g = c.benchmark_group("lines_plan_svg");
    g.sample_size(10);
    g.bench_function("table_21x11", |b| {
        b.iter(|| {
            let d = lines_plan(&table_fit, Some(&table), Units::Metre, &plain);
            let mut out = Vec::with_capacity(1 << 20);
            write_svg(&mut out, &d).expect("writes to memory");
            black_box(out.len())
        })
    });
    for (name, opts) in [("sample_25x8", &plain), ("sample_25x8_combs", &combs)] {
        g.bench_function(name, |b| {
            b.iter(|| {
                let d = lines_plan(&sample_fit, Some(&sample), Units::Metre, opts);
                let mut out = Vec::with_capacity(1 << 20);
                write_svg(&mut out, &d).expect("writes to memory");
                black_box(out.len())
            })
        });
    }
    let w = wigley();
    g.bench_function("wigley_bezier_degenerate", |b| {
        b.iter(|| black_box(lines_plan(&w, None, Units::Metre, &plain).items.len()))
    });
    g.finish();

    // The writers alone, on the sample's plan with combs (the largest drawing).
    let d = lines_plan(&sample_fit, Some(&sample), Units::Metre, &combs);
    let mut g = c.benchmark_group("writers");
    g.bench_function("write_svg_sample", |b| {
        b.iter(|| {
            let mut out = Vec::with_capacity(1 << 20);
            write_svg(&mut out, &d).expect("writes to memory");
            black_box(out.len())
        })
    });
    g.bench_function("write_dxf_sample", |b| {
        b.iter(|| {
            let mut out = Vec::with_capacity(1 << 22);
            write_dxf(&mut out, &d).expect("writes to memory");
            black_box(out.len())
        })
    });
    g.finish();
}

criterion_group!(benches, bench_lines_plan);
criterion_main!(benches);
