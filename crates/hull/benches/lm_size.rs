//! Levenberg-Marquardt's cost by problem size: one LM run (all weights 1, the skinning's
//! parameters, default options, so the step is dense or matrix-free as `lm/model.rs` decides)
//! against the plain approximation of the same table, sweeping the number of weights `d` from
//! the Series 60 table (114) to the sailing yacht (780). The degenerate case is the rank-one
//! layout of the largest table (`n_u + n_v` variables: always the dense step).
//!
//! Each table also runs with the step forced dense and forced matrix-free at the same budget
//! (`lm_dense`, `lm_matrix_free`), which shows where the choice flips. Whole-command timings
//! (foot-point start, both starts, error measurement) are `tools/lm_speed.sh`'s table in the
//! README.
//!
//! `cargo bench -p hullskin-hull --bench lm_size`

use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hull::{
    fit_offsets, quiet, read_offsets, run_lm, FitConfig, LmOptions, Units, WeightLayout, WeightOptions, WeightProblem,
};

/// The tables swept, by size: (name, file in testdata/).
const TABLES: [(&str, &str); 5] = [
    ("series60", "series60_cb065_offsets.csv"),
    ("cargo116", "cargo116_offsets.csv"),
    ("frigate", "matlab_frigate.csv"),
    ("gunnerus", "gunnerus_offsets.csv"),
    ("yacht", "matlab_yacht.csv"),
];

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("lm_size");
    g.sample_size(10);
    g.measurement_time(Duration::from_secs(4));
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata");
    for (name, file) in TABLES {
        let offsets = read_offsets(&dir.join(file), Units::Metre).expect("testdata table reads");
        let cfg = FitConfig::default();
        let plain = fit_offsets(&offsets, &cfg).expect("fits");
        let layouts: &[WeightLayout] =
            if name == "yacht" { &[WeightLayout::Full, WeightLayout::RankOne] } else { &[WeightLayout::Full] };
        for &layout in layouts {
            let opts = WeightOptions { layout, ..WeightOptions::default() };
            let problem = WeightProblem::from_fit(&plain, &offsets, opts).expect("shapes match");
            let id = format!("{name}_{}_d{}", layout.name(), hull::Objective::dim(&problem));
            g.bench_function(BenchmarkId::new("approx", &id), |b| {
                b.iter(|| fit_offsets(&offsets, &cfg).expect("fits"))
            });
            for (label, forced) in [("lm", None), ("lm_dense", Some(false)), ("lm_matrix_free", Some(true))] {
                if layout == WeightLayout::RankOne && forced == Some(true) {
                    continue;
                }
                let o = LmOptions { matrix_free: forced, ..LmOptions::default() };
                g.bench_function(BenchmarkId::new(label, &id), |b| b.iter(|| quiet(|c| run_lm(&problem, &o, c))));
            }
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
