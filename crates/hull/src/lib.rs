//! The hull domain of hullskin, on top of the `nurbs` kernel: the offset data model and its
//! readers, the offsets -> surface pipeline, fit error, and exports.
//!
//! Axes everywhere: x forward (aft to fore), y to starboard (half-breadth, >= 0), z up from
//! the baseline; coordinates stay in the user's [`Units`].
//!
//! Read offsets, fit one surface, measure it and write IGES (what `hullskin fit` does):
//!
//! ```
//! use hull::export::{write_iges, IgesMeta};
//! use hull::{fit_offsets, series60_sample, FitConfig, Hydrostatics, HydrostaticsOptions, Units};
//!
//! // The built-in Series 60 Cb 0.60 parent (Todd 1963): 25 stations by 8 waterlines, metres.
//! // A file is read the same way: `hull::read_offsets(path, Units::Metre)?`.
//! let offsets = series60_sample();
//! // The default fit: skinning approximation, faired, held within the offsets' envelope.
//! let fit = fit_offsets(&offsets, &FitConfig::default())?;
//! // Every offset's true (closest-point) distance to the surface, and the validity checks.
//! assert!(fit.error.overall.max < 0.2, "max error {} m", fit.error.overall.max);
//! assert!(fit.validity.is_empty(), "{:?}", fit.validity);
//! // Hydrostatics at the design draft on the data's perpendiculars: Todd's CB 0.60 within 1 %.
//! let options = HydrostaticsOptions { perpendiculars: offsets.perpendiculars, ..HydrostaticsOptions::default() };
//! let row = Hydrostatics::new(&fit.surface, &options)?.at(6.5)?;
//! assert!((row.cb_lpp.expect("perpendiculars known") / 0.60 - 1.0).abs() < 0.01);
//! // IGES 5.3, entity 128, in metres.
//! let mut iges = Vec::new();
//! write_iges(&mut iges, &fit.surface, &IgesMeta::new(Units::Metre.into(), "hull.igs", "20261206.000000"))?;
//! assert!(iges.len() > 1000);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod analysis;
pub mod colormap;
mod compare;
mod curvature_range;
pub mod digitize;
mod error;
pub mod export;
mod export_format;
pub mod fairing;
mod fit;
pub mod fit_error;
mod flats;
pub mod float;
mod held_out;
pub mod hydrostatics;
#[cfg(test)]
mod layering;
pub mod limits;
pub mod mesh;
mod mesh_comparison;
mod numfmt;
mod offsets;
pub mod optimize;
mod output;
mod pipeline;
pub mod read;
mod report;
mod sample;
mod surface_input;
mod tolerance_search;
mod units;

pub use analysis::{check_fit_validity, check_validity, Envelope, Finding, FindingKind};
pub use compare::{
    check_floors, compare_offsets, compare_offsets_with, comparison_json, comparison_markdown, comparison_table,
    floors_markdown, CompareConfig, CompareOptimization, CompareRow, Comparison, CurvatureSampling, FloorCheck, Floors,
    OptimRunner, RowError, RowStatus, RowValidity, COMPARE_METHODS, FAIR_ROWS, FLOOR_RELATIVE_TOLERANCE,
};
pub use curvature_range::{gaussian_curvature_range, CurvatureRange, CURVATURE_GRID};
pub use error::{
    DigitizeKind, DraftRangeKind, ExportToleranceKind, FormatKind, HeldOutKind, HullError, InputErrorKind, InputNames,
    Location, MirrorKind, SliceKind, WeightsKind,
};
pub use export_format::{export_timestamp, ExportFormat};
pub use fairing::{FairReport, Fairing};
pub use fit::{EnvelopeHold, FitConfig, FitMethod, FitOutcome, Knuckles};
pub use fit_error::{measure_fit_error, overfit, ErrorStats, FitError, HeldOutError, SectionError, WorstPoint};
pub use flats::{find_flat_lines, flat_bounds, refit_within_flats, FlatKind, FlatLine, FlatOptions};
pub use held_out::{
    held_out_error, held_out_error_with, held_out_for_config, held_out_for_config_with, held_out_refit_config,
    held_out_wanted, overfitting_warning, HeldOutOptions,
};
pub use hydrostatics::{
    density_per_cubic_unit, draft_range, hydrostatics, hydrostatics_range, table_drafts, Hydrostatics,
    HydrostaticsOptions, HydrostaticsRow, HydrostaticsTable, HYDROSTATICS_COLUMNS, SEA_WATER_DENSITY,
};
pub use mesh_comparison::{compare_mesh_and_surface, MeshComparison};
pub use numfmt::{format_figure, format_short, format_sig};
pub use offsets::{Offsets, Perpendiculars, Section, COINCIDENT_REL, MAX_SIZE, MIN_SIZE, PLANAR_REL};
pub use output::{check_finite, discard_staged_outputs, write_atomic, OutputDir};
pub use pipeline::{default_ctrl, fit_offsets, fit_offsets_with, HOLD_SHARE};
pub use read::{
    decode, detect_format, parse_offset_table, parse_offsets, parse_sections_csv, read_offsets, write_sections_csv,
    InputFormat,
};
pub use read::{parse_cad_surfaces, read_cad_surfaces, CadFormat, CadSurface, CadSurfaces};
pub use read::{
    parse_offsets_with, read_offsets_with, Disagreement, MainDimensions, ReadOptions, ReadOutcome, SuspiciousPolicy,
    SuspiciousValue, ThreeViews,
};
pub use report::{
    measured_summary_table, measured_warnings, summary_table, summary_warnings, write_fit_outputs,
    write_fit_outputs_with_report, write_report_json, InputSummary, Measured, Report, SurfaceSummary,
};
pub use sample::{series60_sample, Particulars, SAMPLE_PARTICULARS, SERIES60_CB060_CSV, SERIES60_SOURCE};
pub use surface_input::{detect_surface_input, holds_surface, is_mesh_path, strip_bom, SurfaceInput};
pub use tolerance_search::{
    default_tolerance, fit_offsets_within, fit_to_tolerance, Goal, Referee, ToleranceFit, ToleranceSearch,
    ToleranceSettings, TriedCount, DEFAULT_TOLERANCE_OF_BEAM,
};
pub use units::Units;
