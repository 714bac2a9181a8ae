//! The hull domain of hullskin, on top of the `nurbs` kernel: the offset data model and its
//! readers, the offsets -> surface pipeline, fit error, and exports.
//!
//! Axes everywhere: x forward (aft to fore), y to starboard (half-breadth, >= 0), z up from
//! the baseline; coordinates stay in the user's [`Units`].
//!
//! Read offsets, fit one surface, measure it and write IGES (what `hullskin fit` does):
//!
//! ```
//! use hull::{fit_offsets, series60_sample, write_iges, FitConfig, Hydrostatics, HydrostaticsOptions, IgesMeta, Units};
//!
//! // The built-in Series 60 Cb 0.60 parent (Todd 1963): 25 stations by 8 waterlines, metres.
//! // A file is read the same way: `hull::read_offsets(path, Units::Metre)?`.
//! let offsets = series60_sample();
//! // The library's default fit: the skinning approximation held within the offsets' envelope
//! // (the command line also fairs it, `fair: Fairing::Auto { tolerance: None }`, and referees
//! // it by its held-out error: `fit_offsets_within(.., Goal::Count, ..)`, see `refereed_by_held_out`).
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
//!
//! # Cargo features
//!
//! Both on by default; without one the crate builds the same API, and the input that needs
//! the part left out is refused with [`HullError::FeatureDisabled`] naming the feature.
//!
//! | feature | what it enables | dependencies |
//! | --- | --- | --- |
//! | `gzip` | gzip-compressed meshes (`.stl.gz`, `.obj.gz`, `.wrl.gz`) in [`read_mesh`], [`parse_mesh`], [`gunzip`] | flate2 |
//! | `svg` | SVG drawings in [`read_drawing`], [`parse_drawing`], [`parse_svg`] (DXF needs nothing) | svgtypes, roxmltree |
//!
//! # Limits
//!
//! Documented caps on what hullskin accepts, each with the reason for its size, checked where
//! the data enter (file reading, offsets, meshes, drawings, fit and optimisation settings,
//! surface JSON).
//!
//! The caps are sized so that the biggest legitimate job fits in a few GiB of memory and runs
//! in seconds to minutes on a two-core machine; they guard against mistakes (a runaway
//! resampling, a typo such as `--iterations 1e9`, a corrupt header claiming four billion
//! triangles), not against ships. Real offset tables have 10 to 60 stations of 5 to 40 points;
//! the densest data at hand (sections sliced from a 1.4 M-triangle mesh) have a few thousand
//! points per section. Above a cap the input is refused with [`HullError::Limit`], e.g.
//!
//! ```text
//! scan.csv: 3,200,000 points exceed the cap of 2,000,000 (expected at most 2,000,000 offsets in all;
//! see README Limits)
//! ```
//!
//! | cap | value | why |
//! | --- | --- | --- |
//! | [`MAX_OFFSETS_FILE_BYTES`] | 256 MiB | a 2 M-point sections CSV is about 80 MB |
//! | [`MAX_MESH_FILE_BYTES`] | 1 GiB | a binary STL of [`MAX_MESH_TRIANGLES`] is 1 GB |
//! | [`MAX_DRAWING_FILE_BYTES`] | 256 MiB | a body-plan drawing is a few MB |
//! | [`MAX_SURFACE_JSON_BYTES`] | 1 GiB | [`MAX_CONTROL_POINTS`] poles at ~80 bytes a line, plus weights |
//! | [`MAX_CAD_FILE_BYTES`] | 1 GiB | [`MAX_CONTROL_POINTS`] poles as IGES or STEP text: ~110 bytes each |
//! | [`MAX_STEP_INSTANCES`] | 10,000,000 | one `CARTESIAN_POINT` per pole of the largest surface, and more |
//! | [`MAX_SECTIONS`] | 10,000 | a section every 1 cm over a 100 m hull |
//! | [`MAX_POINTS_PER_SECTION`] | 100,000 | 0.1 mm spacing over a 10 m girth |
//! | [`MAX_POINTS`] | 2,000,000 | one projection each for the fit error: ~1 min on 2 cores |
//! | [`MAX_CONTROL_POINTS_PER_DIRECTION`] | 100,000 | as many as the points of a section |
//! | [`MAX_CONTROL_POINTS`] | 4,000,000 | 128 MB of homogeneous poles, 2 M-point interpolation |
//! | [`MAX_MESH_TRIANGLES`] | 20,000,000 | ~85 bytes each read and welded: under 2 GiB |
//! | [`MAX_DRAWING_ENTITIES`] | 1,000,000 | a traced body plan has a few thousand |
//! | [`MAX_OPTIM_VARIABLES`] | 10,000 | Levenberg-Marquardt's dense step matrix: 800 MB |
//! | [`MAX_OPTIM_ITERATIONS`] | 1,000,000 | 5,000 times the GA's default 200 |
//! | [`MAX_OPTIM_POPULATION`] | 10,000 | 200 times the GA's default 50 |
//! | [`MAX_OPTIM_EVALUATIONS`] | 100,000,000 | population x iterations: 10,000 times the GA's default |

// Every type that appears in a public signature is in the `pub use` list below.
#![warn(unnameable_types)]

mod alternatives;
mod analysis;
mod colormap;
mod compare;
mod curvature_range;
mod digitize;
mod error;
mod export;
mod export_format;
mod fairing;
mod fit;
mod fit_choices;
mod fit_error;
mod flats;
mod float;
mod held_out;
mod held_out_referee;
mod hydrostatics;
#[cfg(test)]
mod layering;
mod limits;
mod mesh;
mod mesh_comparison;
mod numfmt;
mod offsets;
mod optimize;
mod output;
mod pipeline;
mod read;
mod report;
mod sample;
mod skin_memo;
mod surface_input;
mod tolerance_search;
mod units;

// Validity, curvature maps, planar cuts (the kernel's cuts, by the lines plan's `CutPlane`) and fairness
// of a fitted surface.
pub use analysis::{
    bending_energy, check_fit_validity, check_validity, curvature_map, cut_surface, cut_surface_many,
    default_quadrature, fairness_report, find_folds, gauss_legendre, point_bounds, BendingEnergy, CurvatureField,
    CurvatureMap, CurvatureMapOptions, CurvatureSample, CurvatureSummary, CutCurve, CutFairness, CutOptions, CutPlane,
    CutPoint, Degeneracy, Envelope, Extreme, FairnessOptions, FairnessReport, FieldStats, Finding, FindingKind, Flat,
    Fold, GridLines, Place, PlaneFairness, PlaneSelection, ENVELOPE_REL, FOLD_RUN_REL,
};
// Colour maps shared by the pictures, the viewer and the coloured meshes.
pub use colormap::{
    abs_quantile, curvature_limit, diverging, diverging_stops, sequential, sequential_stops, Rgb, CURVATURE_QUANTILE,
};
// Fit methods compared side by side, with their floors.
pub use compare::{
    check_floors, compare_offsets, compare_offsets_with, comparison_json, comparison_markdown, comparison_table,
    floors_markdown, CompareConfig, CompareOptimization, CompareRow, Comparison, CurvatureSampling, FloorCheck, Floors,
    OptimRunner, RowError, RowStatus, RowValidity, COMPARE_METHODS, FAIR_ROWS, FLOOR_RELATIVE_TOLERANCE,
};
// The range of Gaussian curvature over a surface.
pub use curvature_range::{gaussian_curvature_range, CurvatureRange, CURVATURE_GRID};
// Drawn body plans (DXF, SVG) read and digitised into offsets.
pub use digitize::{
    digitize, label_number, parse_drawing, parse_dxf, parse_svg, read_drawing, seg_dist, Affine, Curve, CurveOrder,
    DigitizeOptions, Digitized, DrawingScale, Label, Segment, Side, Sketch, SketchFormat, Spline, StationIds,
    StationInfo, StationX, P2,
};
// The one error type and the places it names.
pub use error::{
    DigitizeKind, DraftRangeKind, ExportToleranceKind, FormatKind, HeldOutKind, HullError, InputErrorKind, InputNames,
    LimitExceeded, Location, MirrorKind, SliceKind, WeightsKind,
};
// Surface exports (IGES, STEP, surface.json, tessellated meshes, glTF) and their parts.
pub use export::{
    curvature_colors, greville_v, iges_timestamp, mesh_name, mirrored_full_hull, obj_comments,
    polynomial_approximation, read_surface_json, section_curves, section_parameters, srgb_to_linear, step_timestamp,
    stl_header, write_glb, write_iges, write_iges_model, write_step, write_surface_json, IgesMeta, IgesUnits,
    PolynomialApproximation, StepMeta, SurfaceFile, SurfaceJsonError, MAX_POLYNOMIAL_CONTROL_POINTS, MAX_STRING_LEN,
    MIN_POLYNOMIAL_TOLERANCE_REL,
};
// Export formats chosen by name, and the timestamp written into exports.
pub use export_format::{export_timestamp, ExportFormat};
// Fairing: the control net's energy and the weights' smoothness traded against the error.
pub use fairing::{FairReport, Fairing, AUTO_LAMBDAS, BETWEEN_WEIGHTS, NET_FAIR, UNSOUND_SLACK, WEIGHT_SMOOTHING};
// The default fit made again on another parameterization or count, for validity.
pub use alternatives::{
    ALTERNATIVE_COUNTS_ACROSS, ALTERNATIVE_PARAMETERIZATIONS, FAIRNESS_PARAMETERIZATIONS, SCREEN_SLACK,
};
// The offsets -> surface pipeline: its settings and outcome.
pub use fit::{
    AlternativeReason, AlternativeTry, Alternatives, EnvelopeHold, FairTry, FairnessFigures, FitConfig, FitMethod,
    FitOutcome, HoldOn, Knuckles,
};
// The hold and knuckle settings by the names the command line and Python take.
pub use fit_choices::{EnvelopeChoice, KnuckleChoice};
// Fit error at the offsets and held out of the fit.
pub use fit_error::{measure_fit_error, overfit, ErrorStats, FitError, HeldOutError, SectionError, WorstPoint};
// Flats of bottom and side.
pub use flats::{find_flat_lines, flat_bounds, refit_within_flats, FlatKind, FlatLine, FlatOptions};
// Exact text of a real number for files.
pub use float::{plain, real, Notation, MAX_REAL_LEN};
// Held-out error: refits leaving sections out.
pub use held_out::{
    held_out_error, held_out_error_with, held_out_for_config, held_out_for_config_with, held_out_refit_config,
    held_out_wanted, overfitting_warning, HeldOutOptions,
};
// The default fit refereed by its held-out error against the plain approximation's.
pub use fit::{HeldOutReferee, RefereeTry};
pub use held_out_referee::{refereed_by_held_out, RefereeAlternative, HELD_OUT_ALTERNATIVES};
// Hydrostatics of a surface, one draft or a table.
pub use hydrostatics::{
    density_per_cubic_unit, draft_range, hydrostatics, hydrostatics_range, table_drafts, Hydrostatics,
    HydrostaticsOptions, HydrostaticsRow, HydrostaticsTable, HYDROSTATICS_COLUMNS, MAX_DRAFTS, SEA_WATER_DENSITY,
};
// Caps on inputs and settings (README "Limits").
pub use limits::{
    check_file_size, MAX_CAD_FILE_BYTES, MAX_CONTROL_POINTS, MAX_CONTROL_POINTS_PER_DIRECTION, MAX_DRAWING_ENTITIES,
    MAX_DRAWING_FILE_BYTES, MAX_MESH_FILE_BYTES, MAX_MESH_TRIANGLES, MAX_OFFSETS_FILE_BYTES, MAX_OPTIM_EVALUATIONS,
    MAX_OPTIM_ITERATIONS, MAX_OPTIM_POPULATION, MAX_OPTIM_VARIABLES, MAX_POINTS, MAX_POINTS_PER_SECTION, MAX_SECTIONS,
    MAX_STEP_INSTANCES, MAX_SURFACE_JSON_BYTES,
};
// Triangle meshes: read (STL, OBJ, VRML, gzip), sliced into offsets, measured, written.
pub use mesh::{
    gunzip, looks_binary as looks_like_binary_stl, mesh_distance, mesh_hydrostatics, parse_mesh, parse_obj, parse_stl,
    parse_vrml, read_mesh, slice_mesh, starts_with_solid, station_positions, weld, write_obj, write_stl_ascii,
    write_stl_binary, Axes, DroppedStation, MeshDistance, MeshFormat, MeshHydrostatics, MeshReadOptions, Resample,
    SliceOptions, SliceOutcome, Spacing, StationInfo as KeptStation, Stations, TriangleSoup, VertexFilter, END_INSET,
    END_SLIVER, MAX_DECOMPRESSED, MAX_STATIONS, STL_HEADER_LEN,
};
// The kernel's triangle mesh and tessellation, under the paths hull has always given them.
pub use nurbs::{
    tessellate, EdgeCounts, Tessellation, TessellationOptions, TriMesh, MAX_GRID_LINES, MIN_TESSELLATION_TOLERANCE_REL,
};
// A mesh compared with a surface fitted to its slices.
pub use mesh_comparison::{compare_mesh_and_surface, MeshComparison};
// Figures rounded for people.
pub use numfmt::{format_figure, format_short, format_sig};
// The offsets: sections of points, with the units and perpendiculars.
pub use offsets::{Offsets, Perpendiculars, Section, COINCIDENT_REL, MAX_SIZE, MIN_SIZE, PLANAR_REL};
// Weight optimisers (GA, PSO, GSA, Levenberg-Marquardt) over one objective.
pub use optimize::{
    optimize_weights, quiet, run_ga, run_gsa, run_lm, run_pso, Algorithm, Control, FittedSurface, GaOptions,
    GsaOptions, GsaRandom, JacobianKind, Linearization, LmOptions, NormalEquations, Objective, OptimReport,
    OptimResult, OptimSettings, Optimized, ParamFreedom, Progress, PsoOptions, PsoVariant, StopReason, WeightLayout,
    WeightMode, WeightOptions, WeightProblem,
};
// Output directories written all or nothing.
pub use output::{check_finite, discard_staged_outputs, write_atomic, OutputDir};
// The fit itself.
pub use pipeline::{default_ctrl, fit_offsets, fit_offsets_with, HOLD_SHARE, HOLD_SLACK};
// Offsets readers (every format, detected by content), their options and sense checks.
pub use read::{
    decode, detect_format, is_header as is_freeship_header, is_offset_json, parse_as as parse_cad_surfaces_as,
    parse_cad_surfaces, parse_freeship_curves, parse_freeship_offsets, parse_iges, parse_json_table, parse_long_csv,
    parse_offset_table, parse_offsets, parse_offsets_with, parse_point_cloud, parse_sections_csv, parse_series60_table,
    parse_step, read_cad_surfaces, read_offsets, read_offsets_with, write_sections_csv, CadFormat, CadSurface,
    CadSurfaces, Disagreement, InputFormat, MainDimensions, MergeOptions, Merged, OutlierPolicy, ReadOptions,
    ReadOutcome, SenseKind, SenseWarning, Series60Table, Station, SuspiciousPolicy, SuspiciousValue, ThreeViews, View,
    ViewLine, DEFAULT_TOLERANCE_REL, OUTLIER_SHARE,
};
// The fit's report: summary, warnings, report.json and the output files.
pub use report::{
    fit_decisions, measured_summary_table, measured_warnings, summary_table, summary_warnings, write_fit_outputs,
    write_fit_outputs_with_report, write_report_json, InputSummary, Measured, Report, SurfaceSummary,
};
// The built-in Series 60 sample.
pub use sample::{series60_sample, wigley_hull, Particulars, SAMPLE_PARTICULARS, SERIES60_CB060_CSV, SERIES60_SOURCE};
// What an input file holds: offsets, a surface or a mesh.
pub use surface_input::{detect_surface_input, holds_surface, is_mesh_path, strip_bom, SurfaceInput};
// The search for the fewest control points within a tolerance.
pub use tolerance_search::{
    default_tolerance, fit_offsets_within, fit_to_tolerance, Goal, Referee, RefereeBasis, ToleranceFit,
    ToleranceSearch, ToleranceSettings, TriedCount, DEFAULT_TOLERANCE_OF_BEAM,
};
// Length units.
pub use units::Units;
