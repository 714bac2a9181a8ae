//! Surface evaluation throughput: points (and second derivatives) per second on one core,
//! sweeping the degree; the degenerate case is a surface with a collapsed edge (a hull's stem).

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nurbs::{KnotVector, NurbsSurface, Vec3};

/// A deterministic rational surface with `nu x nv` control points, degrees `(p, q)`, non-uniform
/// knots and weights in [0.5, 2]; `collapse` pinches the first row to one point.
fn surface(nu: usize, nv: usize, p: usize, q: usize, collapse: bool) -> NurbsSurface {
    let knots = |n: usize, d: usize| {
        let mut k = vec![0.0; d + 1];
        let segs = n - d;
        for i in 1..segs {
            let t = i as f64 / segs as f64;
            k.push(t + 0.3 * t * (1.0 - t) * (i as f64).sin() / segs as f64);
        }
        k.extend(std::iter::repeat_n(1.0, d + 1));
        KnotVector::try_new(d, k).expect("valid knots")
    };
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (x, y) = (i as f64, j as f64);
            let y = if collapse && i == 0 { 0.0 } else { y };
            pts.push(Vec3::new(x, y, (0.7 * x).sin() * (0.5 * y).cos()));
            w.push(1.0 + 0.5 * ((i * 7 + j * 3) % 5) as f64 / 4.0 - 0.25);
        }
    }
    NurbsSurface::try_new(knots(nu, p), knots(nv, q), &pts, Some(&w)).expect("valid surface")
}

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
