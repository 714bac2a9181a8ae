//! Closest-point projection throughput: projections per second on one core, as the fit-error
//! measurement projects every offset point onto the fitted surface. Sweeps the sampling grid
//! and the surface size; the degenerate case is a surface with a collapsed edge (a hull's
//! stem), the hard one query points far from the surface.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use nurbs::{NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};

use nurbs::fixtures::rational_surface as surface;

/// `n` query points at `S(u, v) + offset * normal`, `(u, v)` on a scrambled grid, `offset` in
/// `[-scale, scale]` (like offsets measured around a fitted hull).
fn queries(s: &NurbsSurface, n: usize, scale: f64) -> Vec<Vec3> {
    (0..n)
        .map(|k| {
            let (u, v) = ((k as f64 * 0.618_034).fract(), (k as f64 * 0.414_214).fract());
            let d = s.derivatives(u, v);
            let normal = d.normal().unwrap_or(Vec3::new(0.0, 0.0, 1.0));
            d.point + normal * (scale * (2.0 * (k as f64 * 0.732_051).fract() - 1.0))
        })
        .collect()
}

fn bench_project(c: &mut Criterion) {
    let mut g = c.benchmark_group("surface_project");
    let n = 1000;
    g.throughput(Throughput::Elements(n as u64));
    let cases = [
        ("bicubic_rational_10x8_near", surface(10, 8, 3, 3, false), 0.05, 4),
        ("bicubic_rational_10x8_near_grid2", surface(10, 8, 3, 3, false), 0.05, 2),
        ("bicubic_rational_10x8_near_grid8", surface(10, 8, 3, 3, false), 0.05, 8),
        ("bicubic_rational_10x8_off_0.5", surface(10, 8, 3, 3, false), 0.5, 4),
        ("bicubic_rational_10x8_far_20", surface(10, 8, 3, 3, false), 20.0, 4),
        ("bicubic_rational_10x8_collapsed_edge", surface(10, 8, 3, 3, true), 0.05, 4),
        ("bicubic_rational_40x30_near", surface(40, 30, 3, 3, false), 0.05, 4),
    ];
    for (name, s, scale, grid) in &cases {
        let proj = SurfaceProjector::new(s, ProjectionOptions { grid: *grid, ..ProjectionOptions::default() });
        let qs = queries(s, n, *scale);
        g.bench_with_input(BenchmarkId::from_parameter(name), &qs, |b, qs| b.iter(|| proj.project_many(black_box(qs))));
    }
    g.finish();

    let mut g = c.benchmark_group("surface_projector_new");
    for (name, s) in [
        ("bicubic_rational_10x8", surface(10, 8, 3, 3, false)),
        ("bicubic_rational_40x30", surface(40, 30, 3, 3, false)),
    ] {
        g.bench_with_input(BenchmarkId::from_parameter(name), &s, |b, s| {
            b.iter(|| SurfaceProjector::new(black_box(s), ProjectionOptions::default()))
        });
    }
    g.finish();
}

criterion_group!(benches, bench_project);
criterion_main!(benches);
