//! Fit times on real offset tables, kernel only (skinning) and end to end (skinning plus the
//! true error of every offset by projection): the Series 60 Cb 0.60 table (25 x 8) and the
//! dense R/V Gunnerus table (62 stations of 4 to 16 waterlines, unequal counts: the case that
//! makes knot-merging skinners explode).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use hull::{fit_offsets, measure_fit_error, series60_sample, FitConfig, FitMethod, Offsets, Units};
use nurbs::fit::{skin_approximate, skin_interpolate, SkinOptions};
use nurbs::Vec3;

fn gunnerus() -> Offsets {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/gunnerus_offsets.csv");
    hull::read_offsets(&path, Units::Metre).expect("testdata/gunnerus_offsets.csv reads")
}

fn sections(o: &Offsets) -> Vec<Vec<Vec3>> {
    o.sections.iter().map(|s| s.points.clone()).collect()
}

fn bench(c: &mut Criterion) {
    let cases = [("series60_25x8", series60_sample(), (6, 19)), ("gunnerus_62x16", gunnerus(), (12, 40))];
    let opts = SkinOptions::default();
    let mut g = c.benchmark_group("skin_kernel");
    for (name, offsets, (nu, nv)) in &cases {
        let secs = sections(offsets);
        g.bench_with_input(BenchmarkId::new("interp", name), &secs, |b, s| {
            b.iter(|| skin_interpolate(black_box(s), &opts).expect("fits"))
        });
        g.bench_with_input(BenchmarkId::new(format!("approx_{nu}x{nv}"), name), &secs, |b, s| {
            b.iter(|| skin_approximate(black_box(s), *nu, *nv, &opts).expect("fits"))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("fit_end_to_end");
    g.sample_size(20);
    for (name, offsets, ctrl) in &cases {
        for method in [FitMethod::Interp, FitMethod::Approx] {
            let cfg = FitConfig { method, ctrl: Some(*ctrl), ..FitConfig::default() };
            g.bench_with_input(BenchmarkId::new(method.name(), name), offsets, |b, o| {
                b.iter(|| fit_offsets(black_box(o), &cfg).expect("fits"))
            });
        }
    }
    g.finish();

    let mut g = c.benchmark_group("error_by_projection");
    g.sample_size(20);
    for (name, offsets, ctrl) in &cases {
        let cfg = FitConfig { ctrl: Some(*ctrl), ..FitConfig::default() };
        let out = fit_offsets(offsets, &cfg).expect("fits");
        g.bench_with_input(BenchmarkId::from_parameter(name), offsets, |b, o| {
            b.iter(|| measure_fit_error(&out.surface, black_box(o), Some(&out.params)))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
