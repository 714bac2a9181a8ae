//! The input and skinning flags shared by `fit`, `compare`, `hydrostatics` and `report`.

use std::path::PathBuf;
use std::sync::LazyLock;

use clap::builder::PossibleValue;
use clap::{Args, ValueEnum};
use hull::{Fairing, FitConfig, FitMethod, Offsets, OptimSettings, Units};
use nurbs::fit::{CornerOptions, SkinParameterization};

use crate::parse::{parse_fair, parse_pair, parse_param, parse_units};

/// Which offsets, and how the sections are skinned.
#[derive(Debug, Clone, Args)]
pub struct SkinArgs {
    /// Offsets file: a sections CSV (header `section,x,y,z`) or an offset table CSV (first row
    /// station positions, first column waterline heights, cells half-breadths), or any format
    /// of `hull::read_offsets` (Series 60 table, long CSV, JSON table, point cloud, FREE!ship text),
    /// recognised by its content; or a hull mesh (`.stl`, `.obj`, `.wrl`, each optionally `.gz`), sliced at
    /// stations first (`--stations`, `--spacing`, `--at`, ...). Without it the
    /// built-in Series 60 Cb 0.60 parent hull is used.
    pub input: Option<PathBuf>,
    /// Control points NU,NV of the approximation and of the weight-optimised methods (u along
    /// each section, v across sections; also NUxNV, as the summary prints them). Default: three
    /// quarters of the offsets in each direction (of the largest section along u, of the
    /// sections along v). Interpolation has its own count: one per offset.
    #[arg(long, value_parser = parse_pair)]
    pub ctrl: Option<(usize, usize)>,
    /// Degrees P,Q in u (along sections) and v (across sections).
    #[arg(long, default_value = "3,3", value_parser = parse_pair)]
    pub degree: (usize, usize),
    /// Parameterization of the offsets: centripetal, chord, uniform or universal; one name for
    /// both directions, or U,V for along the sections (u) and across them (v).
    #[arg(long, default_value = "centripetal,chord", value_parser = parse_param)]
    pub param: SkinParameterization,
    /// Units of the input coordinates, carried to the exports and the reported errors: m, mm,
    /// ft or in.
    /// Default m. A surface.json carries its own units: `export --units` converts it to these,
    /// the other commands say the flag does not apply.
    #[arg(long, value_parser = parse_units)]
    pub units: Option<Units>,
    /// Length between perpendiculars, breadth and design draft (in `--units`) that scale a
    /// dimensionless Series 60 table (default: the Cb 0.60 parent's 121.92, 16.26, 6.50 m);
    /// `--lpp` alone also gives the station spacing (Lpp / 20) of an OpenHull JSON table.
    /// In `hydrostatics` and `report`, `--lpp` (with `--ap`) also places the perpendiculars for
    /// the coefficients on Lpp and LCB, LCF in % Lpp from amidships.
    #[arg(long, allow_negative_numbers = true)]
    pub lpp: Option<f64>,
    /// Outlier cells of the offsets (a half-breadth out of line with its neighbours along
    /// both its station and its waterline: a typo, a shifted decimal point): `warn` names each
    /// and fits the offsets as read, `refuse` stops at the first, `keep` fits them silently.
    #[arg(long, value_name = "POLICY", default_value = "warn", value_parser = parse_outliers)]
    pub outliers: hull::OutlierPolicy,
    /// x of the aft perpendicular (default 0), with `--lpp`: the FP is at AP + Lpp.
    #[arg(long, value_name = "X", requires = "lpp", allow_negative_numbers = true)]
    pub ap: Option<f64>,
    /// Moulded breadth B for a Series 60 table (with `--lpp` and `--design-draft`).
    #[arg(long, requires_all = ["lpp", "design_draft"])]
    pub beam: Option<f64>,
    /// Design draft T (the 1.0 waterline) for a Series 60 table (with `--lpp` and `--beam`).
    #[arg(long, requires_all = ["lpp", "beam"])]
    pub design_draft: Option<f64>,
    /// Knuckles (chines) of the sections: `auto` keeps every knuckle line found (a corner of
    /// at least `--corner-angle` degrees, sharper than its neighbours, running through three
    /// quarters of the sections) as a crease of the surface; `auto+flats` also keeps an
    /// approximation inside the flat of side and flat of bottom found in the offsets (no
    /// ringing past B/2 or below the keel, at more control points); `off` fits one smooth
    /// surface.
    #[arg(long, value_enum, default_value = "auto")]
    pub knuckles: KnuckleArg,
    /// Least turning angle, in degrees, of a section's corner for `--knuckles auto`.
    #[arg(long, default_value = "30", value_parser = parse_corner_angle)]
    pub corner_angle: f64,
    /// Fairness of the approximation and of the optimised weights: `auto` (the fairest
    /// surface whose max error at the offsets is within the plain approximation's, or within
    /// --tolerance, that does not fold), a weight
    /// LAMBDA of the control net's second differences (e.g. 1e-3), or 0 for the plain least
    /// squares. Interpolation is not faired.
    #[arg(long, value_name = "LAMBDA", default_value = "auto", value_parser = parse_fair, allow_hyphen_values = true)]
    pub fair: Fairing,
    /// The offsets' envelope (the box of the offsets: the centre plane, the largest
    /// half-breadth, the lowest and highest offsets, the end sections): `hold` refits an
    /// approximation that leaves it by more than the validity allowance with its control net
    /// held just past the faces it crossed (half the allowance), so that the surface stays
    /// within the allowance (the convex-hull property); an optimised surface that leaves it is
    /// held the same way (its weights kept), or gives way to the held approximation where that
    /// is closer to the offsets (with `--fair auto`, also to the approximation held on its
    /// surface, where it is sound and the optimised surface more than twice as far).
    /// `hold-surface` holds the surface's points instead of its net (sampled 8, then 16 per
    /// knot span; the end sections' planes on the net), which
    /// lets poles go past a face where the surface stays within it: closer to the offsets
    /// where a rounded section meets a face (the default fit takes it by itself when the
    /// net-held fit folds or faces inwards). `free` keeps the plain least squares and reports
    /// where it leaves.
    #[arg(long, value_enum, default_value = "hold")]
    pub envelope: EnvelopeArg,
    /// How a mesh input (`.stl`, `.obj`, `.wrl`, each optionally `.gz`) is sliced into sections first.
    #[command(flatten)]
    pub mesh: crate::slice::MeshArgs,
}

/// `--knuckles`: a [`hull::KnuckleChoice`] by its name, each listed with its description.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KnuckleArg(pub hull::KnuckleChoice);

impl ValueEnum for KnuckleArg {
    fn value_variants<'a>() -> &'a [Self] {
        static ALL: LazyLock<[KnuckleArg; 3]> = LazyLock::new(|| hull::KnuckleChoice::ALL.map(KnuckleArg));
        &*ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.0.name()).help(self.0.description()))
    }
}

/// `--envelope`: a [`hull::EnvelopeChoice`] by its name, each listed with its description.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EnvelopeArg(pub hull::EnvelopeChoice);

impl ValueEnum for EnvelopeArg {
    fn value_variants<'a>() -> &'a [Self] {
        static ALL: LazyLock<[EnvelopeArg; 3]> = LazyLock::new(|| hull::EnvelopeChoice::ALL.map(EnvelopeArg));
        &*ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.0.name()).help(self.0.description()))
    }
}

/// An angle in degrees strictly between 0 and 180.
fn parse_corner_angle(s: &str) -> Result<f64, String> {
    let a: f64 = s.trim().parse().map_err(|_| format!("`{s}` is not a number (expected degrees, e.g. 30)"))?;
    if a > 0.0 && a < 180.0 {
        Ok(a)
    } else {
        Err(format!("{a} is out of range (expected degrees between 0 and 180, exclusive)"))
    }
}

impl Default for SkinArgs {
    fn default() -> Self {
        SkinArgs {
            input: None,
            ctrl: None,
            degree: (3, 3),
            param: SkinParameterization::default(),
            units: None,
            lpp: None,
            ap: None,
            outliers: hull::OutlierPolicy::Warn,
            beam: None,
            design_draft: None,
            knuckles: KnuckleArg(hull::KnuckleChoice::Auto),
            corner_angle: CornerOptions::default().min_angle_deg,
            fair: Fairing::Auto { tolerance: None },
            envelope: EnvelopeArg(hull::EnvelopeChoice::Hold),
            mesh: crate::slice::MeshArgs::default(),
        }
    }
}

impl SkinArgs {
    /// The offsets: the input file read in `units`, or the built-in sample.
    pub fn offsets(&self) -> anyhow::Result<Offsets> {
        Ok(self.offsets_with_warnings()?.0)
    }

    /// [`SkinArgs::offsets`] with the sense warnings of the reading (printed as they are found).
    pub fn offsets_with_warnings(&self) -> anyhow::Result<(Offsets, Vec<hull::SenseWarning>)> {
        Ok(match &self.input {
            Some(path) if crate::slice::is_mesh_path(path) => {
                (crate::slice::mesh_offsets(path, &self.mesh, self.units())?, Vec::new())
            }
            Some(path) => {
                let outcome = hull::read_offsets_with(path, &self.read_options())?;
                self.note_flags_not_applied(outcome.format, false);
                read_with_warnings(outcome)
            }
            None => (hull::series60_sample(), Vec::new()),
        })
    }

    /// A note on standard error for each reading flag that does nothing to an input of
    /// `format`: `--beam` and `--design-draft` (a Series 60 table's), `--lpp` (a Series 60 or
    /// OpenHull table's, and the perpendiculars where `lpp_used`).
    pub fn note_flags_not_applied(&self, format: hull::InputFormat, lpp_used: bool) {
        let name = format.name();
        if format != hull::InputFormat::Series60Table {
            for (flag, given) in [("--beam", self.beam.is_some()), ("--design-draft", self.design_draft.is_some())] {
                if given {
                    eprintln!("hullskin: note: {flag} scales a Series 60 table only; it does nothing to this {name}");
                }
            }
        }
        let scales = matches!(format, hull::InputFormat::Series60Table | hull::InputFormat::JsonTable);
        if self.lpp.is_some() && !scales && !lpp_used {
            eprintln!(
                "hullskin: note: --lpp scales a Series 60 table or spaces an OpenHull table's stations (and places \
                 the perpendiculars of hydrostatics and report); it does nothing to this {name}"
            );
        }
    }

    /// The units of offsets read: `--units`, metres by default.
    pub fn units(&self) -> Units {
        self.units.unwrap_or_default()
    }

    /// The perpendiculars: `--lpp` from `--ap` (default 0) when given, else the data's own
    /// (`data`, where the input gives them).
    ///
    /// # Errors
    /// An Lpp that is not a positive length, or an AP that is not finite.
    pub fn perpendiculars(&self, data: Option<hull::Perpendiculars>) -> anyhow::Result<Option<hull::Perpendiculars>> {
        match self.lpp {
            Some(lpp) => Ok(Some(hull::Perpendiculars::try_new(self.ap.unwrap_or(0.0), lpp).map_err(|_| {
                anyhow::anyhow!("--lpp {lpp} --ap {}: expected a positive Lpp and a finite AP", self.ap.unwrap_or(0.0))
            })?)),
            None => Ok(data),
        }
    }

    /// The readers' options: `--units`, and `--lpp`, `--beam`, `--design-draft` as the dimensions
    /// (breadth and draft of an `--lpp` alone are unused: only an OpenHull table reads it).
    pub fn read_options(&self) -> hull::ReadOptions {
        let dimensions = self.lpp.map(|lpp| hull::MainDimensions {
            lpp,
            beam: self.beam.unwrap_or(f64::NAN),
            draft: self.design_draft.unwrap_or(f64::NAN),
        });
        // Sections too short for the degree along them are left out (noted) by the readers of
        // the formats where they are a property of the source (end stations beyond a stem).
        let min_points = self.degree.0 + 1;
        hull::ReadOptions {
            units: self.units(),
            dimensions,
            min_points,
            outliers: self.outliers,
            ..hull::ReadOptions::default()
        }
    }

    /// The library's fit settings: these skinning flags with `method` and the weight
    /// optimisers' `optim`.
    pub fn fit_config(&self, method: FitMethod, optim: OptimSettings) -> FitConfig {
        let corner = CornerOptions { min_angle_deg: self.corner_angle, ..CornerOptions::default() };
        let (envelope, hold_on) = self.envelope.0.settings();
        FitConfig {
            method,
            degree: self.degree,
            ctrl: self.ctrl,
            param: self.param,
            optim,
            knuckles: self.knuckles.0.knuckles(corner),
            fair: self.fair,
            smoothing: 0.0,
            envelope,
            hold_on,
            ..FitConfig::default()
        }
    }
}

fn parse_outliers(s: &str) -> Result<hull::OutlierPolicy, String> {
    s.parse()
}

/// Offsets measured against a surface (`--offsets` of `fit` and `report`): read in the
/// surface's `units`, with the other reading flags (`--lpp`, ...) as for any offsets input;
/// notes and warnings printed, the warnings kept (for `report.json`).
///
/// # Errors
/// Those of [`hull::read_offsets_with`].
pub fn read_offsets_for_surface(
    skin: &SkinArgs,
    path: &std::path::Path,
    units: Units,
) -> Result<(Offsets, Vec<hull::SenseWarning>), hull::HullError> {
    let options = hull::ReadOptions { units, ..skin.read_options() };
    Ok(read_with_warnings(hull::read_offsets_with(path, &options)?))
}

/// Prints what a reader assumed and found (axes, notes, suspicious values, disagreements
/// between views) on stderr, one `hullskin: note:` line each, and every sense warning as a
/// `hullskin: warning:` line; returns the offsets.
pub fn report_reading(outcome: hull::ReadOutcome) -> Offsets {
    read_with_warnings(outcome).0
}

/// [`report_reading`], keeping the sense warnings (for `report.json`).
pub fn read_with_warnings(outcome: hull::ReadOutcome) -> (Offsets, Vec<hull::SenseWarning>) {
    if outcome.format != hull::InputFormat::SectionsCsv && outcome.format != hull::InputFormat::OffsetTable
        || !outcome.notes.is_empty()
        || !outcome.suspicious.is_empty()
        || !outcome.disagreements.is_empty()
    {
        for m in outcome.messages() {
            eprintln!("hullskin: note: {m}");
        }
    }
    for w in &outcome.warnings {
        eprintln!("hullskin: warning: {w}");
    }
    (outcome.offsets, outcome.warnings)
}
