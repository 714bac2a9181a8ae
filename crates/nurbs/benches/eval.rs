//! Surface evaluation throughput: points (and second derivatives) per second on one core,
//! sweeping the degree; the degenerate case is a surface with a collapsed edge (a hull's stem).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nurbs::Vec3;

use nurbs::fixtures::rational_surface as surface;

fn grid(n: usize) -> Vec<(f64, f64)> {
    (0..n).flat_map(|i| (0..n).map(move |j| (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64))).collect()
}

fn bench_eval(c: &mut Criterion) {
    let uv = grid(100);
    let mut g = c.benchmark_group("surface_point");
    g.throughput(Throughput::Elements(uv.len() as u64));
    for (name, s) in [
        ("bilinear_2x2", surface(2, 2, 1, 1, false)),
        ("biquadratic_10x8", surface(10, 8, 2, 2, false)),
        ("bicubic_rational_10x8", surface(10, 8, 3, 3, false)),
        ("bicubic_rational_10x8_collapsed_edge", surface(10, 8, 3, 3, true)),
        ("bicubic_rational_40x30", surface(40, 30, 3, 3, false)),
        ("biquintic_10x8", surface(10, 8, 5, 5, false)),
    ] {
        g.bench_with_input(BenchmarkId::from_parameter(name), &s, |b, s| {
            b.iter(|| {
                let mut acc = Vec3::ZERO;
                for &(u, v) in &uv {
                    acc += s.point(black_box(u), black_box(v));
                }
                acc
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("surface_derivatives2");
    g.throughput(Throughput::Elements(uv.len() as u64));
    let s = surface(10, 8, 3, 3, false);
    g.bench_function("bicubic_rational_10x8", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &(u, v) in &uv {
                acc += s.derivatives(black_box(u), black_box(v)).suv.x;
            }
            acc
        })
    });
    g.finish();
}

criterion_group!(benches, bench_eval);
criterion_main!(benches);
