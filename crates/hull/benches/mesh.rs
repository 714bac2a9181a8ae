//! Reading and slicing hull meshes. The speed floor (issue 5): reading and slicing a
//! 100,000-triangle mesh in under a second, measured on the DTC (116,062 triangles, a 3.5 MB
//! gzip of a 21 MB ASCII STL) read from the compressed bytes and sliced at 41 stations.
//!
//! Sweeps: the input form (gzip ASCII, plain ASCII, binary STL, OBJ), the station count (11 to
//! 641), and a degenerate case: every station through mesh vertices (41 stations at vertex x),
//! where the symbolic perturbation of the plane does all the work.

use std::path::Path;

use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use hull::{
    gunzip, mesh_hydrostatics, parse_mesh, slice_mesh, write_obj, write_stl_binary, MeshReadOptions, SliceOptions,
    Spacing, Stations,
};

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mesh/DTC-scaled.stl.gz");
    let gz = std::fs::read(&path).expect("testdata/mesh/DTC-scaled.stl.gz");
    let opts = MeshReadOptions::default();
    let ascii = gunzip(&gz, "dtc").expect("gzip");
    let mesh = parse_mesh(&gz, "dtc", None, &opts).expect("the DTC mesh");
    let mut binary = Vec::new();
    write_stl_binary(&mut binary, &mesh, "dtc").expect("writes");
    let mut obj = Vec::new();
    write_obj(&mut obj, &mesh, &[], None).expect("writes");

    let mut g = c.benchmark_group("mesh_read_dtc");
    g.sample_size(10);
    for (name, bytes) in [("stl_ascii_gz", &gz), ("stl_ascii", &ascii), ("stl_binary", &binary), ("obj", &obj)] {
        g.bench_with_input(BenchmarkId::from_parameter(name), bytes, |b, bytes| {
            b.iter(|| parse_mesh(black_box(bytes), "dtc", None, &opts).expect("reads"))
        });
    }
    g.finish();

    let slice = |stations: Stations| SliceOptions { stations, ..SliceOptions::default() };
    let mut g = c.benchmark_group("mesh_slice_dtc");
    g.sample_size(20);
    for n in [11, 41, 161, 641] {
        let o = slice(Stations::Count { n, spacing: Spacing::Cosine });
        g.bench_with_input(BenchmarkId::new("cosine", n), &o, |b, o| {
            b.iter(|| slice_mesh(black_box(&mesh), o).expect("slices"))
        });
    }
    // Degenerate: 41 stations each through vertices of the mesh.
    let mut xs: Vec<f64> = mesh.vertices.iter().map(|p| p.x).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let at: Vec<f64> = (1..=41).map(|k| xs[k * (xs.len() - 1) / 42]).collect();
    let o = slice(Stations::At(at));
    g.bench_with_input(BenchmarkId::new("through_vertices", 41), &o, |b, o| {
        b.iter(|| slice_mesh(black_box(&mesh), o).expect("slices"))
    });
    g.finish();

    let mut g = c.benchmark_group("mesh_floor_dtc");
    g.sample_size(10);
    let o = slice(Stations::Count { n: 41, spacing: Spacing::Cosine });
    g.bench_function("read_gz_and_slice_41", |b| {
        b.iter(|| {
            let mesh = parse_mesh(black_box(&gz), "dtc", None, &opts).expect("reads");
            slice_mesh(&mesh, &o).expect("slices")
        })
    });
    g.bench_function("hydrostatics_at_design_draft", |b| b.iter(|| mesh_hydrostatics(black_box(&mesh), 0.244)));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
