//! Planar cuts and tessellation of the kernel's fixtures: the time of one `cut_surface` by
//! axis planes, swept over the surface's size, and of one `tessellate`, swept over the chord
//! tolerance (4x and 1x the default, `TessellationOptions::for_surface`: a tenth of it takes
//! seconds on the random nets). The degenerate case is a surface with an edge collapsed to a point (the sphere
//! octant's pole; a random net with a collapsed edge), where normals and curvature are taken
//! as limits.

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use nurbs::fixtures::{half_cylinder_along_x, rational_surface, sphere_octant};
use nurbs::{cut_surface, tessellate, AxisPlane, CutOptions, TessellationOptions};

fn bench_cut(c: &mut Criterion) {
    let mut g = c.benchmark_group("cut_surface");
    let opts = CutOptions::default();
    let cases = [
        ("half_cylinder_x", half_cylinder_along_x(2.0, 10.0), AxisPlane::x(4.0)),
        ("half_cylinder_z", half_cylinder_along_x(2.0, 10.0), AxisPlane::z(1.0)),
        ("sphere_octant_through_pole", sphere_octant(1.0), AxisPlane::y(0.0)),
        ("bicubic_rational_10x8_x", rational_surface(10, 8, 3, 3, false), AxisPlane::x(0.5)),
        ("bicubic_rational_10x8_collapsed_edge_x", rational_surface(10, 8, 3, 3, true), AxisPlane::x(0.5)),
        ("bicubic_rational_40x30_x", rational_surface(40, 30, 3, 3, false), AxisPlane::x(0.5)),
    ];
    for (name, s, plane) in &cases {
        assert!(!cut_surface(s, *plane, &opts).is_empty(), "{name}: the plane misses the surface");
        g.bench_with_input(BenchmarkId::from_parameter(name), s, |b, s| {
            b.iter(|| cut_surface(black_box(s), *plane, &opts))
        });
    }
    g.finish();
}

fn bench_tessellate(c: &mut Criterion) {
    let mut g = c.benchmark_group("tessellate");
    let cases = [
        ("half_cylinder", half_cylinder_along_x(2.0, 10.0)),
        ("sphere_octant", sphere_octant(1.0)),
        ("bicubic_rational_10x8", rational_surface(10, 8, 3, 3, false)),
        ("bicubic_rational_10x8_collapsed_edge", rational_surface(10, 8, 3, 3, true)),
    ];
    for (name, s) in &cases {
        let default = TessellationOptions::for_surface(s);
        for rel in [4.0, 1.0] {
            let opts = TessellationOptions { tolerance: default.tolerance * rel, mirror: false };
            g.bench_with_input(BenchmarkId::new(*name, format!("tol_x{rel}")), s, |b, s| {
                b.iter(|| tessellate(black_box(s), &opts).expect("tessellates"))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench_cut, bench_tessellate);
criterion_main!(benches);
