//! Property tests across the pipeline: any valid set of hull-like sections (random counts,
//! uneven spacing, a pointed or zero-width end) fits by both methods; interpolation passes
//! through its data; the error in the report is the error re-measured from the written file.

use hull::{fit_offsets, measure_fit_error, Algorithm, FitConfig, FitMethod, Offsets, OptimSettings, Section, Units};
use nurbs::Vec3;
use proptest::prelude::*;

/// Sections of a random hull: stations at increasing x, each from the keel line up to a
/// deck, half-breadths from a smooth random shape; `end` makes the first station zero-width
/// (1) or a single point, repeated (2: a pointed stem).
fn hull_sections() -> impl Strategy<Value = Offsets> {
    hull_sections_of(3..14, 0..3)
}

/// [`hull_sections`] with `stations` sections and the first section's `end` kind drawn from
/// the given ranges (`3..5, 2..3`: three or four sections, the first a point).
fn hull_sections_of(stations: std::ops::Range<usize>, ends: std::ops::Range<u8>) -> impl Strategy<Value = Offsets> {
    (prop::collection::vec((0.3f64..2.0, 4usize..12), stations), 0.5f64..3.0, 0.1f64..1.0, ends).prop_map(
        |(stations, beam, fullness, end)| {
            let mut x = 0.0;
            let n = stations.len();
            let sections = stations
                .iter()
                .enumerate()
                .map(|(k, &(dx, count))| {
                    x += dx;
                    let s = k as f64 / (n - 1) as f64;
                    let width = if end > 0 && k == 0 { 0.0 } else { beam * (0.2 + (std::f64::consts::PI * s).sin()) };
                    let points = (0..count)
                        .map(|i| {
                            let t = i as f64 / (count - 1) as f64;
                            let z = if end == 2 && k == 0 { 1.0 } else { 2.0 * t * t + 0.3 * t };
                            let y = width * (1.0 - (1.0 - t).powf(1.0 + 4.0 * fullness));
                            Vec3::new(x, y, z)
                        })
                        .collect();
                    Section::new(format!("{k}"), points)
                })
                .collect();
            Offsets::new("proptest", Units::Metre, sections)
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn every_method_fits_and_interpolation_passes_through(offsets in hull_sections()) {
        let size = offsets.size();
        let interp = fit_offsets(&offsets, &FitConfig { method: FitMethod::Interp, ..FitConfig::default() })
            .map_err(|e| TestCaseError::fail(format!("interp: {e}")))?;
        // Round-off of banded solves and of projection on a model of this size.
        prop_assert!(interp.error.overall.max <= 1e-9 * size, "interp max {} size {}", interp.error.overall.max, size);
        // One pole per offset along the sections: as many as the largest section that is not a
        // single (repeated) point.
        let n_max = offsets
            .sections
            .iter()
            .filter(|s| !s.is_point(0.0))
            .map(|s| s.points.len())
            .max()
            .unwrap_or(0);
        prop_assert_eq!(interp.surface.n_u(), n_max);
        prop_assert_eq!(interp.surface.n_v(), offsets.sections.len());
        let approx = fit_offsets(&offsets, &FitConfig::default())
            .map_err(|e| TestCaseError::fail(format!("approx: {e}")))?;
        prop_assert!(approx.error.overall.max.is_finite());
        prop_assert!(approx.error.overall.rms <= approx.error.overall.max);
    }

    #[test]
    fn reported_error_equals_error_remeasured_from_the_written_file(offsets in hull_sections()) {
        let out = fit_offsets(&offsets, &FitConfig::default()).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let dir = tempfile::tempdir().map_err(|e| TestCaseError::fail(e.to_string()))?;
        hull::write_fit_outputs(dir.path(), &offsets, &out).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let text = std::fs::read_to_string(dir.path().join("surface.json")).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let (surface, _) = hull::read_surface_json(&text).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(&surface, &out.surface);
        let again = measure_fit_error(&surface, &offsets, Some(&out.params));
        prop_assert_eq!(again.overall, out.error.overall);
        let report: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(dir.path().join("report.json")).map_err(|e| TestCaseError::fail(e.to_string()))?,
        ).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(report["error"]["max"].as_f64(), Some(again.overall.max));
        prop_assert_eq!(report["error"]["rms"].as_f64(), Some(again.overall.rms));
    }

}

proptest! {
    // Each case runs five optimisations: fewer cases, short runs.
    #![proptest_config(ProptestConfig { cases: 8, ..ProptestConfig::default() })]

    /// Every weight optimiser fits any valid set of sections, and (starting from the offsets'
    /// foot points on the plain approximation, the default) never ends worse than it in true
    /// RMS: the objective at the start is the approximation's true RMS, the optimisers only
    /// keep a lower objective, and the objective bounds the true RMS from above.
    #[test]
    fn every_optimiser_fits_and_never_ends_above_the_approximation(offsets in hull_sections(), seed in 0u64..1000) {
        let approx = fit_offsets(&offsets, &FitConfig::default())
            .map_err(|e| TestCaseError::fail(format!("approx: {e}")))?;
        for algorithm in [Algorithm::Ga, Algorithm::Pso, Algorithm::Gsa, Algorithm::Lm, Algorithm::GsaLm] {
            let optim = OptimSettings { seed, iterations: Some(6), population: Some(8), ..OptimSettings::default() };
            let config = FitConfig { method: FitMethod::Optimized(algorithm), optim, ..FitConfig::default() };
            let out = fit_offsets(&offsets, &config)
                .map_err(|e| TestCaseError::fail(format!("{}: {e}", algorithm.name())))?;
            let rms = out.error.overall.rms;
            prop_assert!(rms.is_finite() && out.error.overall.max.is_finite(), "{}: rms {rms}", algorithm.name());
            prop_assert!(out.surface.weights().iter().all(|w| w.is_finite() && *w > 0.0));
            // Projection round-off: the closest points are found to ~1e-12 of the model size.
            prop_assert!(
                rms <= approx.error.overall.rms * (1.0 + 1e-9) + 1e-12 * offsets.size(),
                "{}: rms {rms} above approx {}",
                algorithm.name(),
                approx.error.overall.rms
            );
        }
    }
}

proptest! {
    // A fixed seed: this property has failed on rare tables (tables of three sections of which
    // one is a pointed end, whose net-held fit faces inwards at the sheer; see
    // `a_pointed_end_facing_inwards_is_refitted_held_on_its_surface`). Measured since the
    // surface hold is the first alternative: of 3,300 tables of this strategy (300 cases of
    // each of 11 seeds) the default parameters left 8 unsound and the alternatives none (7 by
    // the surface hold), of 800 of three or four sections with a pointed end 11 and none (all
    // by the surface hold; the parameterizations and counts alone left 2). Random seeds could
    // still make the suite flaky; these 512 cases pass (about 40 s in the test profile), and a
    // regression on them fails.
    #![proptest_config(ProptestConfig {
        cases: 512,
        rng_seed: proptest::test_runner::RngSeed::Fixed(11),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Issue 11's floor: the command line's default fit (`--fair auto`, held within the
    /// envelope, refereed by its held-out error) of random hull-like sections has no validity finding: no fold, nothing past
    /// the offsets' envelope or a flat, no inward-facing facets.
    #[test]
    fn the_default_fit_of_hull_like_sections_is_valid(offsets in hull_sections()) {
        let out = command_line_default_fit(&offsets)?;
        let kinds: Vec<&str> = out.validity.iter().map(|f| f.kind.name()).collect();
        prop_assert!(out.validity.is_empty(), "findings {:?}: {:?}", kinds, out.validity);
    }
}

/// The command line's default fit (`--fair auto`, held within the envelope, refereed by its
/// held-out error) of `offsets`.
fn command_line_default_fit(offsets: &hull::Offsets) -> Result<hull::FitOutcome, TestCaseError> {
    let config = FitConfig { fair: hull::Fairing::Auto { tolerance: None }, ..FitConfig::default() };
    let fit = |c: &hull::Control<'_>| hull::fit_offsets_within(offsets, &config, hull::Goal::Count, c);
    hull::quiet(fit).map(|(out, _)| out).map_err(|e| TestCaseError::fail(e.to_string()))
}

proptest! {
    // The tables that failed the property above most: three or four sections, the first a
    // point (of 800, 11 had a finding before the alternatives, 2 with the parameterizations
    // and counts alone, none with the surface hold first). A fixed seed, as above.
    #![proptest_config(ProptestConfig {
        cases: 256,
        rng_seed: proptest::test_runner::RngSeed::Fixed(6),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// The same floor on tables of three or four sections with a pointed end.
    #[test]
    fn the_default_fit_of_a_short_table_with_a_pointed_end_is_valid(offsets in hull_sections_of(3..5, 2..3)) {
        let out = command_line_default_fit(&offsets)?;
        let kinds: Vec<&str> = out.validity.iter().map(|f| f.kind.name()).collect();
        prop_assert!(out.validity.is_empty(), "findings {:?}: {:?}", kinds, out.validity);
    }
}

/// One of those rare tables (found at proptest seed 5, case 341 of a strategy of three or four
/// sections with a pointed end): three sections, the first a point. Across three sections the
/// net interpolates them (quadratic, three rows), and its sheer rises 0.18 m above the highest
/// offset between the last two; the envelope hold of the net pulls the top row's poles down
/// within the box, below the row under them, and the surface faces inwards along the sheer
/// beside the point (0.0018 m², u = 1, v = 0.44, measured). Held on its surface instead
/// (`HoldOn::Surface`, the first alternative) the default fit is sound, and is used (measured:
/// max error 0.137 m against the net-held fit's 0.278 m); so is the next alternative, universal
/// parameters along the sections with the net held, at 0.283 m.
#[test]
fn a_pointed_end_facing_inwards_is_refitted_held_on_its_surface() {
    let section = |name: &str, x: f64, yz: &[(f64, f64)]| {
        Section::new(name.to_string(), yz.iter().map(|&(y, z)| Vec3::new(x, y, z)).collect())
    };
    let offsets = Offsets::new(
        "pointed end",
        Units::Metre,
        vec![
            section("0", 0.6858800653162003, &[(0.0, 1.0); 4]),
            section(
                "1",
                1.259192736308352,
                &[
                    (0.0, 0.0),
                    (0.6009354150314464, 0.10555555555555554),
                    (1.0432828144287705, 0.3222222222222222),
                    (1.3447847757626483, 0.65),
                    (1.5254695710536126, 1.0888888888888888),
                    (1.6089788690194538, 1.638888888888889),
                    (1.6264712120031901, 2.3),
                ],
            ),
            section(
                "2",
                2.536854066500366,
                &[
                    (0.0, 0.0),
                    (0.14014460921823418, 0.2),
                    (0.22413079596044155, 0.65),
                    (0.26294771734209643, 1.35),
                    (0.2710785353338652, 2.3),
                ],
            ),
        ],
    );
    let config = FitConfig { fair: hull::Fairing::Auto { tolerance: None }, ..FitConfig::default() };
    let out = fit_offsets(&offsets, &config).expect("fits");
    assert!(out.validity.is_empty(), "{:?}", out.validity);
    let choice = out.fairing.as_ref().and_then(|f| f.alternatives.as_ref()).expect("an alternative was needed");
    assert_eq!(choice.findings, 1, "the default parameters face inwards: {choice:?}");
    let used: Vec<(&str, &str)> =
        choice.tried.iter().filter(|t| t.accepted).map(|t| (t.param, t.hold.name())).collect();
    assert_eq!(used, [("centripetal,chord", "surface")]);
    assert_eq!(out.config.hold_on, hull::HoldOn::Surface);
    assert!(out.error.overall.max <= choice.limit);
    let param = hull::ALTERNATIVE_PARAMETERIZATIONS[0];
    let universal = fit_offsets(&offsets, &FitConfig { param, ..config }).expect("fits");
    assert!(universal.validity.is_empty(), "{:?}", universal.validity);
    assert!(out.error.overall.max < 0.6 * universal.error.overall.max);
}
