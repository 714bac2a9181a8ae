//! Levenberg-Marquardt's cost by problem size: one LM run (all weights 1, the skinning's
//! parameters, default options, so the step is dense or matrix-free as `lm/model.rs` decides)
//! against the plain approximation of the same table, sweeping the number of weights `d` from
//! the Series 60 table (114) to the sailing yacht (780). The degenerate case is the rank-one
//! layout of the largest table (`n_u + n_v` variables: always the dense step).
//!
//! Each table also runs with the step forced dense and forced matrix-free at the same budget
//! (`lm_dense`, `lm_matrix_free`), which shows where the choice flips. On the fair objective
//! (`fair_*`: the net's second differences at [`hull::NET_FAIR`] and the log-weights'
//! smoothing at [`hull::WEIGHT_SMOOTHING`], what `hullskin fit --method lm` optimises) each
//! table runs LM as chosen (`lm`) and, up to 256 weights, with the matrix-free step's
//! preconditioner forced to the first point's factored normal matrix (`lm_stale`) or to
//! Jacobi's diagonal (`lm_jacobi`), which shows where the stale factor pays. Whole-command timings
//! (foot-point start, both starts, error measurement) are `tools/lm_speed.sh`'s table in the
//! README.
//!
//! `cargo bench -p hullskin-hull --bench lm_size`

use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hull::{
    fit_offsets, quiet, read_offsets, run_lm, FitConfig, LmOptions, Units, WeightLayout, WeightOptions, WeightProblem,
    NET_FAIR, WEIGHT_SMOOTHING,
};

/// The tables swept, by size: (name, file in testdata/).
const TABLES: [(&str, &str); 6] = [
    ("series60", "series60_cb065_offsets.csv"),
    ("cargo116", "cargo116_offsets.csv"),
    ("dtmb5415_main", "matlab_dtmb5415_main.csv"),
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
        let fair = WeightProblem::from_fit(&plain, &offsets, WeightOptions::default())
            .and_then(|p| p.with_fairness(NET_FAIR, WEIGHT_SMOOTHING))
            .expect("shapes match");
        let d = hull::Objective::dim(&fair);
        let id = format!("fair_{name}_d{d}");
        for (label, forced) in [("lm", None), ("lm_stale", Some(true)), ("lm_jacobi", Some(false))] {
            if forced.is_some() && d > 256 {
                continue;
            }
            let o = LmOptions { stale_factor: forced, ..LmOptions::default() };
            g.bench_function(BenchmarkId::new(label, &id), |b| b.iter(|| quiet(|c| run_lm(&fair, &o, c))));
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
