//! Hydrostatics from the surface: one draft and a 10-draft range on the built-in Series 60
//! sample (approximation and interpolation fits), the exact Wigley patch (one Bezier span,
//! every cell cut by the waterline at a partial draft), and the degenerate draft at the Wigley's
//! top edge (the waterline along a domain edge).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use hull::{fit_offsets, series60_sample, FitConfig, FitMethod, Hydrostatics, HydrostaticsOptions};
use nurbs::NurbsSurface;

/// The exact Wigley patch of the tests (L 100 m, B 10 m, T 6.25 m).
#[allow(dead_code)]
#[path = "../tests/common/surfaces.rs"]
mod surfaces;

fn wigley_patch() -> NurbsSurface {
    surfaces::wigley_patch(100.0, 10.0, 6.25)
}

fn bench(c: &mut Criterion) {
    let sample = series60_sample();
    let surfaces = [
        ("series60_approx", fit_offsets(&sample, &FitConfig::default()).expect("fits").surface, 6.5),
        (
            "series60_interp",
            fit_offsets(&sample, &FitConfig { method: FitMethod::Interp, ..FitConfig::default() })
                .expect("fits")
                .surface,
            6.5,
        ),
        ("wigley_patch_half_draft", wigley_patch(), 3.125),
        ("wigley_patch_top_edge", wigley_patch(), 6.25),
    ];
    let opts = HydrostaticsOptions::default();
    let mut g = c.benchmark_group("hydrostatics_one_draft");
    for (name, s, t) in &surfaces {
        g.bench_with_input(BenchmarkId::from_parameter(name), s, |b, s| {
            b.iter(|| Hydrostatics::new(black_box(s), &opts).and_then(|h| h.at(*t)).expect("a draft on the hull"))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("hydrostatics_10_drafts");
    g.sample_size(20);
    for (name, s, _) in &surfaces[..2] {
        g.bench_with_input(BenchmarkId::from_parameter(name), s, |b, s| {
            b.iter(|| Hydrostatics::new(black_box(s), &opts).and_then(|h| h.range(0.65, 6.5, 0.65)).expect("drafts"))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
