//! Hydrostatics of a hull **from its NURBS surface** (not from the offsets): the figures naval
//! architects tabulate per draft (the columns of FREE!ship's hydrostatics table), for the
//! whole ship (both sides) from the starboard half-hull surface.
//!
//! The axes, the body measured and the method are documented on [`Hydrostatics`], where the
//! library's users read it.

mod integrate;
mod table;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use nurbs::{NurbsSurface, Vec3};

use crate::error::{DraftRangeKind, HullError, InputNames};
use crate::offsets::Perpendiculars;
use crate::units::Units;

use integrate::{Integrator, Sums};
pub use table::{HydrostaticsTable, HYDROSTATICS_COLUMNS};

/// Density of sea water, t/m³ (ITTC standard 1.025 as in FREE!ship's default).
pub const SEA_WATER_DENSITY: f64 = 1.025;

/// Most drafts [`draft_range`] makes.
pub const MAX_DRAFTS: usize = 10_000;

/// The hydrostatic figures of the whole ship (both sides) at one draft. JSON keys are the
/// column names in lower case ([`HYDROSTATICS_COLUMNS`]). Lengths in the surface's unit `L`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HydrostaticsRow {
    /// Draft `T`: the waterplane's z above the baseline, `L`.
    pub draft: f64,
    /// Length of the waterline (its x extent, centre-plane webs left out), `L`.
    pub lwl: f64,
    /// Breadth of the waterline (twice its largest half-breadth), `L`.
    pub bwl: f64,
    /// Displaced volume, `L³`.
    pub vol: f64,
    /// Displacement `vol x density`, tonnes.
    pub displ: f64,
    /// Longitudinal centre of buoyancy, x, `L`.
    pub lcb: f64,
    /// LCB as a percentage of Lpp from amidships, positive forward (with the perpendiculars).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lcb_pct_lpp: Option<f64>,
    /// Vertical centre of buoyancy (KB) above the baseline, `L`.
    pub vcb: f64,
    /// Block coefficient `vol / (lwl bwl draft)`.
    pub cb: f64,
    /// Block coefficient on Lpp, `vol / (lpp bwl draft)` (with the perpendiculars).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cb_lpp: Option<f64>,
    /// Midship section area at the middle of the waterline length, `L²`.
    pub am: f64,
    /// Midship section coefficient `am / (bwl draft)`.
    pub cm: f64,
    /// Midship section coefficient at amidships of Lpp, `am_pp / (bwl draft)` (with the
    /// perpendiculars).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cm_lpp: Option<f64>,
    /// Waterplane area, `L²`.
    pub aw: f64,
    /// Waterplane coefficient `aw / (lwl bwl)`.
    pub cw: f64,
    /// Prismatic coefficient `vol / (am lwl)`.
    pub cp: f64,
    /// Prismatic coefficient on Lpp, `vol / (am_pp lpp)` (with the perpendiculars).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cp_lpp: Option<f64>,
    /// Longitudinal centre of flotation, x, `L`.
    pub lcf: f64,
    /// LCF as a percentage of Lpp from amidships, positive forward (with the perpendiculars).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lcf_pct_lpp: Option<f64>,
    /// Wetted surface of the hull surface below the waterline, both sides, centre-plane webs
    /// left out ([`Hydrostatics::web_area`]), `L²`.
    pub s: f64,
    /// Tonnes per centimetre immersion, `aw x 1 cm x density`, t/cm.
    pub tpc: f64,
    /// Moment to change trim by 1 cm, `displ bml / (100 L)` (`L` = Lpp, or Lwl without the
    /// perpendiculars; GMl taken as BMl), t·m/cm.
    pub mct: f64,
    /// Transverse metacentric radius `I_T / vol`, `L`.
    pub bmt: f64,
    /// Longitudinal metacentric radius `I_L / vol` (I_L about the LCF), `L`.
    pub bml: f64,
    /// Transverse metacentre above the baseline, `KB + BMt`, `L` (FREE!ship's `KMtrv`).
    #[serde(alias = "kmtrv")]
    pub kmt: f64,
    /// Longitudinal metacentre above the baseline, `KB + BMl`, `L` (FREE!ship's `KMlong`).
    #[serde(alias = "kmlong")]
    pub kml: f64,
}

/// How the hydrostatics are integrated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HydrostaticsOptions {
    /// Water density in t/m³: `displ = vol x density` in tonnes whatever the length unit.
    /// Default [`SEA_WATER_DENSITY`].
    pub density: f64,
    /// The surface's length unit (for the density per cubic unit, TPC and MCT). Default metres.
    pub units: Units,
    /// The perpendiculars, for the coefficients on Lpp and the percentages from amidships;
    /// `None` (the default) leaves those out.
    pub perpendiculars: Option<Perpendiculars>,
    /// Gauss-Legendre points per direction and cell, 1 to 64 (default 8).
    pub order: usize,
    /// Cells per knot span and direction, 1 to 64 (default 2).
    pub split: usize,
}

impl Default for HydrostaticsOptions {
    fn default() -> Self {
        HydrostaticsOptions {
            density: SEA_WATER_DENSITY,
            units: Units::Metre,
            perpendiculars: None,
            order: 8,
            split: 2,
        }
    }
}

impl HydrostaticsRow {
    /// The row of a draft at or below the bottom: every figure 0 (the Lpp figures too, when
    /// the perpendiculars are known).
    pub fn zero(draft: f64, with_lpp: bool) -> Self {
        let z = with_lpp.then_some(0.0);
        HydrostaticsRow {
            draft,
            lcb_pct_lpp: z,
            cb_lpp: z,
            cm_lpp: z,
            cp_lpp: z,
            lcf_pct_lpp: z,
            ..HydrostaticsRow::default()
        }
    }
}

/// A density given in t/m³ as tonnes per cubic `units`: `rho x (metres per unit)³`, so that
/// `displ` is in tonnes for a surface in `units`.
pub fn density_per_cubic_unit(t_per_m3: f64, units: Units) -> f64 {
    t_per_m3 * units.metres_per_unit().powi(3)
}

/// The drafts `from, from + step, ...` up to `to` (included when reached within 1e-9 step;
/// the last one is then `to` exactly).
///
/// # Errors
/// [`HullError::DraftRange`] if a value is not finite, `step` is 0 or points away from `to`, or
/// the range holds more than [`MAX_DRAFTS`] drafts.
pub fn draft_range(from: f64, to: f64, step: f64) -> Result<Vec<f64>, HullError> {
    if !(from.is_finite() && to.is_finite() && step.is_finite()) {
        return Err(HullError::DraftRange { from, to, step, kind: DraftRangeKind::NotFinite });
    }
    if step == 0.0 {
        return Err(HullError::DraftRange { from, to, step, kind: DraftRangeKind::ZeroStep });
    }
    if (to - from) * step < 0.0 {
        return Err(HullError::DraftRange { from, to, step, kind: DraftRangeKind::AwayFromTo });
    }
    let steps = ((to - from) / step + 1e-9).floor();
    if !(steps < MAX_DRAFTS as f64) {
        return Err(HullError::DraftRange { from, to, step, kind: DraftRangeKind::TooMany { max: MAX_DRAFTS } });
    }
    let n = steps as usize + 1;
    Ok((0..n)
        .map(|k| {
            let t = from + k as f64 * step;
            if k + 1 == n && (t - to).abs() <= 1e-9 * step.abs() {
                to
            } else {
                t
            }
        })
        .collect())
}

/// The drafts of a hydrostatic table as a user asks for it, checked: `draft` alone, or the
/// range from it to `to` by `step` ([`draft_range`]); no draft (`None`) gives none. Every draft
/// must be finite and above 0 and the density (t/m³) finite and positive; `names` spells the
/// inputs in the messages as the user wrote them.
///
/// ```
/// use hull::{table_drafts, InputNames};
///
/// assert_eq!(table_drafts(Some(2.0), Some(3.0), Some(0.5), 1.025, InputNames::Flags)?, [2.0, 2.5, 3.0]);
/// let e = table_drafts(Some(0.0), None, None, 1.025, InputNames::Flags).unwrap_err();
/// assert_eq!(e.to_string(), "--draft 0: expected a draft greater than 0");
/// let e = table_drafts(Some(1.0), None, None, -1.0, InputNames::Keywords).unwrap_err();
/// assert_eq!(e.to_string(), "density -1: expected a positive density in t/m³");
/// # Ok::<(), hull::HullError>(())
/// ```
///
/// # Errors
/// [`HullError::Setting`] naming the input: a draft or `to` not above 0 (or not finite), a
/// density not positive; [`HullError::DraftStepWithoutTo`] for `to` without `step` or the
/// other way round; and those of [`draft_range`].
pub fn table_drafts(
    draft: Option<f64>,
    to: Option<f64>,
    step: Option<f64>,
    density: f64,
    names: InputNames,
) -> Result<Vec<f64>, HullError> {
    let p = names.prefix();
    for (name, value) in [("draft", draft), ("to", to)] {
        if let Some(t) = value.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(HullError::Setting {
                name: format!("{p}{name}"),
                value: t,
                expected: "a draft greater than 0",
            });
        }
    }
    if !(density.is_finite() && density > 0.0) {
        return Err(HullError::Setting {
            name: format!("{p}density"),
            value: density,
            expected: "a positive density in t/m³",
        });
    }
    match (draft, to, step) {
        (Some(from), Some(to), Some(step)) => draft_range(from, to, step),
        (_, None, None) => Ok(draft.into_iter().collect()),
        _ => Err(HullError::DraftStepWithoutTo { names }),
    }
}

/// A surface prepared for hydrostatics at any number of drafts.
///
/// # Axes and the body measured
///
/// The surface is the starboard half hull: x forward, y to starboard (half-breadth >= 0), z up
/// from the baseline, its y = 0 edges on the centre plane. The body measured at draft `T` is
/// the solid between the centre plane and the surface below the waterplane `z = T`,
/// mirrored to port: `{(x, eta, z) : (x, z) under the surface's side view, z <= T,
/// |eta| <= y(x, z)}`. Where the surface stops short of the centre plane (a flat of keel
/// at the baseline, a transom at constant x) the body is closed by planes of constant z or x.
///
/// # Method
///
/// All volume figures are surface integrals over the hull surface alone, by the divergence
/// theorem (Gauss): with `F = (0, y g, 0)`, `div F = g`, and on every closing plane of the
/// body (centre plane `y = 0`, waterplane, flat bottom `z = const`, transom `x = const`)
/// either `y = 0` or `n_y = 0`, so
///
/// ```text
/// V/2      = ∫∫ y n_y dA            = ∫∫ y (S_u × S_v)_y du dv      (g = 1)
/// V/2 LCB  = ∫∫ x y n_y dA                                           (g = x)
/// V/2 VCB  = ∫∫ z y n_y dA                                           (g = z)
/// S/2      = ∫∫ |S_u × S_v| du dv                                    (wetted surface)
/// ```
///
/// over the part of the parameter domain where `z(u, v) <= T`. `(S_u × S_v)_y` is the Jacobian
/// of `(u, v) -> (x, z)`, so `V/2` is the half-breadth integrated over the side view; its sign
/// is the surface's orientation and is divided out (any direction of u and v works).
///
/// The waterplane figures are line integrals along the waterline, the level set `z(u, v) = T`
/// (`Γ dx` around the waterplane, where `Γ = 0` on the centre plane and `dx = 0` on a transom):
///
/// ```text
/// AW  = 2 ∫ y dx                LCF = ∫ x y dx / ∫ y dx
/// I_T = (2/3) ∫ y³ dx           I_L = 2 ∫ (x - LCF)² y dx
/// ```
///
/// `Lwl` and `Bwl` are the waterline's x extent and twice its largest half-breadth (found on
/// the quadrature nodes of the waterline and refined by Brent's maximiser). `AM` is the
/// area of the section at the **middle of the waterline length** `x_m = (x_aft + x_fore)/2`
/// (this module's convention; FREE!ship uses the middle of its Lpp): `AM = 2 |∫ y dz|` along
/// the level set `x(u, v) = x_m` below the waterline.
///
/// # Quadrature
///
/// Each knot span is split into `split x split` cells, each integrated by an `order x order`
/// Gauss-Legendre rule. Cells wholly below the waterline (by the bounding box of the span's
/// control points) take the tensor rule; cells wholly above are skipped; a cell cut by the
/// waterline is integrated as an iterated integral: `z` is checked to be monotone along one
/// parameter on the cell, the cell's outer range is split where the waterline crosses the
/// cell's inner ends, and each outer Gauss node gets the waterline's exact parameter (Brent's
/// root finder, to round-off) and an inner Gauss rule over the wet side. The integrands are
/// analytic inside a span and the clipped ones stay so, so the rule converges exponentially;
/// a non-rational bicubic span below the waterline is integrated exactly for the volume and
/// its moments (`x y n_y` has degree 11 in each parameter, order 8 is exact to 15). The
/// monotone parameter is chosen from the signs of `z_u`, `z_v` on a 4 x 4 grid of interior
/// samples; cells monotone in neither are split in four (up to 6 levels). The sums run in a fixed order, so
/// results are the same bits whatever the number of threads ([`Hydrostatics::range`] runs
/// drafts in parallel).
///
/// # Accuracy (measured, `crates/hull/tests/shape/hydrostatics.rs`)
///
/// * Exact Wigley hull (a degree (2,2) Bézier patch reproduces it exactly), at 0.1 T .. T
///   against the closed forms: every figure but S within 7e-14 relative (round-off: the
///   integrands are polynomials the rule integrates exactly); S within 1.2e-9 of an independent
///   2-D Gauss rule on the explicit formula (S's integrand is a square root; 0.148791 L² at T,
///   the published value, to its 6 digits).
/// * Fitted surfaces (Series 60 Cb 0.60 and 0.80, Wigley offsets; interp and approx): the
///   default rule (order 8, split 2) against order 16, split 4 at three drafts: every figure
///   but S within 4e-14 relative, S within 4e-10. The quadrature error is thus far below the
///   fit's own (fitted Wigley offsets: 6e-6 from the closed forms; Series 60: see the tests).
/// * The waterline is lifted by 16 ulps of the largest |z| (round-off on a knot line or a
///   level top edge then counts as wet), a bias of `AW x 16 ulp / V`, about 1e-14 relative.
/// * `dV/dT = AW`, `d(V LCB)/dT = AW LCF`, `d(V KB)/dT = T AW` hold to the 1e-7 of the
///   central differences that check them: the line integrals agree with the surface ones.
///
/// Speed (criterion, `benches/hydrostatics.rs`, release): about 1 ms per draft for the
/// Series 60 sample fitted by approximation (6 x 19 control points), 2 ms by interpolation
/// (8 x 25).
///
/// # Conventions and units
///
/// * `Draft` is `T`, the waterplane's z (above the baseline z = 0).
/// * Coefficients on the waterline as FREE!ship: `CB = Vol/(Lwl Bwl T)`, `CM = AM/(Bwl T)`,
///   `CP = Vol/(AM Lwl)`, `CW = AW/(Lwl Bwl)`.
/// * With the perpendiculars known ([`HydrostaticsOptions::perpendiculars`]: the AP and FP
///   x, `Lpp = FP - AP`, amidships at their middle), also the trade's coefficients on Lpp:
///   `CB_Lpp = Vol/(Lpp Bwl T)`, `CM_Lpp = AM_pp/(Bwl T)`, `CP_Lpp = Vol/(AM_pp Lpp)`, with
///   `AM_pp` the section area at amidships; and `LCB`, `LCF` as a percentage of Lpp from
///   amidships, **positive forward** (`100 (LCB - x_mid) / Lpp`), as Todd's Series 60 tables
///   give them. Without them these are absent (`None`, left out of the tables).
/// * `LCB` and `LCF` are also x coordinates in the surface's axes.
/// * Stability: `KB = VCB`, `BMt = I_T/Vol`, `BMl = I_L/Vol` (I_L about the LCF),
///   `KMt = KB + BMt`, `KMl = KB + BMl`.
/// * `TPC` (tonnes per centimetre immersion) `= AW x 1 cm x density`.
/// * `MCT` (moment to change trim by 1 cm, t·m/cm) `= Displ BMl / (100 L)` with `L = Lpp`
///   when the perpendiculars are known, else `Lwl`. The centre of gravity is unknown here,
///   so `GMl` is taken as `BMl` (the usual approximation: `KB - KG` is small against `BMl`,
///   about 1 % of it for ordinary ships).
/// * Lengths in the surface's length unit `L` ([`HydrostaticsOptions::units`]); areas `L²`,
///   volumes `L³`. `Displ = Vol x density` in tonnes, the density given in t/m³ (the default
///   1.025 is sea water) and converted to tonnes per cubic `L`. `TPC` is in t/cm and `MCT` in
///   t·m/cm whatever `L`.
/// * A draft at or below the lowest point of the surface gives a row of zeros (no volume, no
///   waterplane: every figure 0, never NaN). A draft above the highest point of the surface
///   is an error ([`HullError::Draft`]): the hull would be submerged. A draft at a level top
///   edge of the surface (the Wigley hull at its design draft) takes that edge as the
///   waterline. Where the top edge dips below the draft, the waterplane is open there and the
///   figures are those of the surface below the draft.
/// * The wetted surface is the area of the surface below the waterline (both sides); a flat
///   of keel or a transom not modelled by the surface is not counted, nor is a centre-plane
///   web (below).
///
/// # Centre-plane webs
///
/// A station sliced from a mesh as two pieces (the DTC's bulb below and its stem above, a skeg
/// and the hull over a propeller aperture) is joined along the centre plane, so the skinned
/// surface carries a zero-thickness **web** lying in `y = 0` between the pieces. It is inside
/// the mirrored hull: never wetted, and no part of the waterline's length. A knot span is a
/// web when all its control points lie within `|y| <= 2e-3 x` the control net's diagonal (by
/// the convex hull property the whole span then lies in that slab) and it is not joined,
/// through such spans, to the keel line (a domain edge in the slab running along the ship:
/// there the hull's fine ends close onto the centre plane, thin but wetted on both sides).
/// The bound and its measurements are at `integrate::WEB_REL`. Web spans are integrated as
/// any other (so `V`, its moments and the waterplane keep them: they add `y n_y ~ 0`), but
/// their area goes to [`Hydrostatics::web_area`] instead of `S`, and their waterline pieces
/// are left out of `Lwl`, `Bwl` and the middle of `Lwl` (so of `AM`, `CB`, `CM`, `CW`, `CP`).
/// Whole spans are classified, so no quadrature cell is cut by a web's boundary and the rules
/// stay exact; a surface without a web span gives the same bits as without the rule (no span
/// of the Series 60, Wigley, Gunnerus, cargo ship or DTMB 5415 surfaces is one).
///
/// The rule is coarse: a span holding both a web and a part of the hull (a bulb's top running
/// into the web) counts as hull. On the DTC fitted at 41 stations the web spans lie above the
/// bulb: at `T = 0.4 m` they hold 0.0038 m² (approx) and 0.0127 m² (interp), 0.04 % and
/// 0.15 % of S; at the design draft 0.244 m none is wet: the waterline grazes the bulb's top,
/// where the fitted surface strays 1 to 7 mm from the centre plane over both the bulb's neck
/// (x 5.99 .. 6.08 m) and the web (6.08 .. 6.16 m), and no tolerance on `y` or on the normal
/// tells them apart (the sliced data itself puts the waterline 1.2 mm off the centre plane at
/// x = 6.123 m, where the mesh's waterline has ended at 6.077 m). `Lwl` there stays 6.218 m
/// (approx) and 6.176 m (interp) against the mesh's 6.091 m.
#[derive(Clone, Debug)]
pub struct Hydrostatics<'a> {
    /// One integrator per patch of the hull (one for a single surface).
    patches: Vec<Integrator<'a>>,
    options: HydrostaticsOptions,
}

impl<'a> Hydrostatics<'a> {
    /// Prepare `surface` (the starboard half hull, axes as documented on [`Hydrostatics`]).
    ///
    /// # Errors
    /// [`HullError::Setting`] if the density is not a positive finite number or the order or
    /// split is outside 1..=64; [`HullError::Perpendiculars`] if the perpendiculars are not a
    /// positive length apart.
    pub fn new(surface: &'a NurbsSurface, options: &HydrostaticsOptions) -> Result<Self, HullError> {
        Hydrostatics::patches(std::slice::from_ref(surface), options)
    }

    /// Prepare a hull made of several patches (each a piece of the starboard half hull, as a
    /// CAD model or the DTMB 5415's main and bow grids give it), integrated together: volumes,
    /// moments, areas and the waterplane's integrals add up over the patches (each a surface
    /// integral over its own part of the hull, the sign of its orientation divided out on its
    /// own), the waterline's ends and breadth are the extremes over them, the midship section
    /// the sum of their sections. The patches should not overlap (an overlap counts twice).
    ///
    /// # Errors
    /// As [`Hydrostatics::new`], and [`HullError::NoSurface`] for no patch at all.
    pub fn patches(surfaces: &'a [NurbsSurface], options: &HydrostaticsOptions) -> Result<Self, HullError> {
        if !(options.density.is_finite() && options.density > 0.0) {
            return Err(HullError::Setting {
                name: "density".to_string(),
                value: options.density,
                expected: "a positive number (t/m³)",
            });
        }
        if let Some(p) = options.perpendiculars {
            Perpendiculars::try_new(p.aft, p.lpp())?;
        }
        for (name, n) in [("order", options.order), ("split", options.split)] {
            if !(1..=64).contains(&n) {
                return Err(HullError::Setting {
                    name: format!("hydrostatics {name}"),
                    value: n as f64,
                    expected: "1 to 64",
                });
            }
        }
        if surfaces.is_empty() {
            return Err(HullError::NoSurface);
        }
        let patches = surfaces.iter().map(|s| Integrator::new(s, options.order, options.split)).collect();
        Ok(Hydrostatics { patches, options: *options })
    }

    /// The highest z of the surface (sampled on 8 points per knot span and direction): the
    /// largest draft accepted.
    pub fn top(&self) -> f64 {
        self.patches.iter().map(|p| p.top).fold(f64::NEG_INFINITY, f64::max)
    }

    /// The lowest z of the surface (sampled as [`Hydrostatics::top`]).
    pub fn bottom(&self) -> f64 {
        self.patches.iter().map(|p| p.bottom).fold(f64::INFINITY, f64::min)
    }

    /// The model size: the largest patch's.
    fn size(&self) -> f64 {
        self.patches.iter().map(|p| p.size).fold(0.0, f64::max)
    }

    /// Check a draft: finite and not above the top.
    fn check(&self, draft: f64) -> Result<(), HullError> {
        if !draft.is_finite() {
            return Err(HullError::Draft { draft, reason: "expected a finite number".into() });
        }
        let top = self.top();
        // 1e-9 of the model: the sampled top is a hair below the true one.
        if draft > top + 1e-9 * self.size() {
            return Err(HullError::Draft {
                draft,
                reason: format!(
                    "above the top of the surface (highest z {top:.6}): the hull would be submerged \
                     (expected a draft of at most {top:.6})"
                ),
            });
        }
        Ok(())
    }

    /// The figures at `draft`.
    ///
    /// # Errors
    /// [`HullError::Draft`] if `draft` is not finite or lies above the top of the surface.
    pub fn at(&self, draft: f64) -> Result<HydrostaticsRow, HullError> {
        self.check(draft)?;
        Ok(self.row(draft))
    }

    /// The figures at each draft of [`draft_range`]`(from, to, step)`, computed in parallel
    /// (each draft on its own, so the rows are the same bits as from [`Hydrostatics::at`]).
    ///
    /// # Errors
    /// As [`draft_range`], or [`HullError::Draft`] for the first draft (in order) above the
    /// top of the surface.
    pub fn range(&self, from: f64, to: f64, step: f64) -> Result<Vec<HydrostaticsRow>, HullError> {
        let drafts = draft_range(from, to, step)?;
        self.rows(&drafts)
    }

    /// The figures at each of `drafts`, computed in parallel, in the order given.
    ///
    /// # Errors
    /// [`HullError::Draft`] for the first draft (in order) that is not finite or lies above
    /// the top of the surface; nothing is computed then.
    pub fn rows(&self, drafts: &[f64]) -> Result<Vec<HydrostaticsRow>, HullError> {
        for &t in drafts {
            self.check(t)?;
        }
        Ok(drafts.par_iter().map(|&t| self.row(t)).collect())
    }

    /// The area of the centre-plane webs below `draft`, both sides, `L²`: left out of
    /// [`HydrostaticsRow::s`] (see [`Hydrostatics`], "Centre-plane webs"); 0 on a surface
    /// without webs or at a draft at or below the bottom.
    ///
    /// # Errors
    /// [`HullError::Draft`] as [`Hydrostatics::at`].
    pub fn web_area(&self, draft: f64) -> Result<f64, HullError> {
        self.check(draft)?;
        Ok(self
            .patches
            .iter()
            .filter(|p| p.has_web && draft > p.bottom)
            .map(|p| 2.0 * p.wet(draft + p.eps, 2.0 * p.eps).sums.web)
            .sum())
    }

    /// The figures at a checked draft.
    fn row(&self, t: f64) -> HydrostaticsRow {
        let zero = HydrostaticsRow::zero(t, self.options.perpendiculars.is_some());
        // Each patch's part: its wet sums with the sign of its orientation divided out, moments
        // taken about the first patch's x0 (for a single patch the same arithmetic as ever).
        let x0 = self.patches[0].x0;
        let mut sum = Sums::default();
        let mut wets = Vec::with_capacity(self.patches.len());
        for p in &self.patches {
            if t <= p.bottom {
                continue;
            }
            // The waterline a hair above the draft: points on it within round-off count as
            // wet, so a waterline along a knot line or a level top edge is found whatever the
            // rounding.
            let level = t + p.eps;
            let wet = p.wet(level, 2.0 * p.eps);
            let s: Sums = wet.sums;
            let sigma = if s.vol >= 0.0 { 1.0 } else { -1.0 };
            let d = p.x0 - x0;
            sum.vol += sigma * s.vol;
            sum.mx += sigma * (s.mx + d * s.vol);
            sum.mz += sigma * s.mz;
            sum.area += s.area;
            sum.wa += sigma * s.wa;
            sum.wx += sigma * (s.wx + d * s.wa);
            sum.wxx += sigma * (s.wxx + d * (2.0 * s.wx + d * s.wa));
            sum.wt += sigma * s.wt;
            wets.push((p, wet, level));
        }
        let half_vol = sum.vol;
        if !(half_vol > 0.0) {
            return zero;
        }
        let vol = 2.0 * half_vol;
        let lcb = x0 + sum.mx / sum.vol;
        let vcb = sum.mz / sum.vol;
        let half_aw = sum.wa;
        let (aw, lcf, i_t, i_l) = if half_aw > 0.0 {
            let lcf_rel = sum.wx / sum.wa;
            let i_l = 2.0 * (sum.wxx - lcf_rel * sum.wx);
            (2.0 * half_aw, x0 + lcf_rel, 2.0 * sum.wt, i_l)
        } else {
            (0.0, 0.0, 0.0, 0.0)
        };
        // The waterline's extremes over the patches.
        let extreme = |g: &dyn Fn(Vec3) -> f64| {
            wets.iter().filter_map(|(p, wet, level)| p.waterline_max(wet, *level, g).map(|(v, _)| v)).reduce(f64::max)
        };
        let aft = extreme(&|p: Vec3| -p.x).map(|v| -v);
        let fore = extreme(&|p: Vec3| p.x);
        let half_b = extreme(&|p: Vec3| p.y);
        let section = |x: f64| -> f64 { wets.iter().map(|(p, _, level)| 2.0 * p.half_section_area(x, *level)).sum() };
        let (lwl, bwl, am) = match (aft, fore, half_b) {
            (Some(a), Some(f), Some(b)) => (f - a, 2.0 * b.max(0.0), section(0.5 * (a + f))),
            _ => (0.0, 0.0, 0.0),
        };
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
        let rho = density_per_cubic_unit(self.options.density, self.options.units);
        let displ = vol * rho;
        let (bmt, bml) = (i_t / vol, i_l / vol);
        // One centimetre in the surface's unit.
        let cm = 0.01 / self.options.units.metres_per_unit();
        let pp = self.options.perpendiculars;
        let am_pp = pp.map(|p| section(p.midship()));
        let length = pp.map_or(lwl, |p| p.lpp());
        HydrostaticsRow {
            draft: t,
            lwl,
            bwl,
            vol,
            displ,
            lcb,
            lcb_pct_lpp: pp.map(|p| p.percent_from_midship(lcb)),
            vcb,
            cb: ratio(vol, lwl * bwl * t),
            cb_lpp: pp.map(|p| ratio(vol, p.lpp() * bwl * t)),
            am,
            cm: ratio(am, bwl * t),
            cm_lpp: am_pp.map(|a| ratio(a, bwl * t)),
            aw,
            cw: ratio(aw, lwl * bwl),
            cp: ratio(vol, am * lwl),
            cp_lpp: pp.zip(am_pp).map(|(p, a)| ratio(vol, a * p.lpp())),
            lcf,
            lcf_pct_lpp: pp.map(|p| if aw > 0.0 { p.percent_from_midship(lcf) } else { 0.0 }),
            s: 2.0 * sum.area,
            tpc: aw * cm * rho,
            mct: ratio(displ * bml, 100.0 * length),
            bmt,
            bml,
            kmt: vcb + bmt,
            kml: vcb + bml,
        }
    }
}

/// The figures of `surface` at `draft` (see [`Hydrostatics`]).
///
/// # Errors
/// As [`Hydrostatics::new`] and [`Hydrostatics::at`].
pub fn hydrostatics(
    surface: &NurbsSurface,
    draft: f64,
    options: &HydrostaticsOptions,
) -> Result<HydrostaticsRow, HullError> {
    Hydrostatics::new(surface, options)?.at(draft)
}

/// The figures of `surface` at the drafts `from` to `to` by `step` (see [`draft_range`]).
///
/// # Errors
/// As [`Hydrostatics::new`] and [`Hydrostatics::range`].
pub fn hydrostatics_range(
    surface: &NurbsSurface,
    from: f64,
    to: f64,
    step: f64,
    options: &HydrostaticsOptions,
) -> Result<Vec<HydrostaticsRow>, HullError> {
    Hydrostatics::new(surface, options)?.range(from, to, step)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{fit_offsets, series60_sample, FitConfig};
    use nurbs::{assert_near, KnotVector, Vec3};

    /// Half-breadth, length and depth of the box barge.
    const HB: f64 = 4.0;
    const LB: f64 = 30.0;
    const D: f64 = 5.0;

    /// A box barge's starboard half: one surface with a knuckle (a double knot... a degree-1
    /// knot) at the bilge: u runs across the flat bottom from the centre plane to the bilge,
    /// then up the side to the deck edge; v runs along the length.
    fn barge() -> NurbsSurface {
        barge_topped([0.0, 0.0])
    }

    /// The barge with the deck edge's ends at `D + dz` (aft, fore), as a fit leaves a level
    /// edge: level to round-off.
    fn barge_topped(dz: [f64; 2]) -> NurbsSurface {
        let ku = KnotVector::try_new(1, vec![0.0, 0.0, 0.5, 1.0, 1.0]).expect("valid");
        let kv = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let section = [(0.0, 0.0), (HB, 0.0), (HB, D)];
        let mut pts = Vec::new();
        for (k, (y, z)) in section.into_iter().enumerate() {
            for (x, dz) in [0.0, LB].into_iter().zip(dz) {
                pts.push(Vec3::new(x, y, if k == 2 { z + dz } else { z }));
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, None).expect("valid barge")
    }

    #[test]
    fn a_deck_edge_level_to_round_off_is_the_waterline_at_its_draft() {
        // The Wigley table's approximation has its top edge within 17 ulps of its level on one
        // build; 16 lost the waterline there (Lwl 78.3 for 100). 100 ulps either way, below the
        // 1024 of `EDGE_ULPS`: the waterline is the deck edge, as on the exact barge.
        let ulp = f64::EPSILON * D;
        for dz in [[100.0 * ulp, -100.0 * ulp], [-100.0 * ulp, 100.0 * ulp], [100.0 * ulp, 100.0 * ulp]] {
            let s = barge_topped(dz);
            let h = Hydrostatics::new(&s, &HydrostaticsOptions::default()).expect("valid options");
            let row = h.at(D).expect("a draft on the hull");
            // The waterplane and its length exactly; the volume to the deck edge's tilt.
            assert_near!(row.lwl, LB, 1e-12 * LB, "{dz:?}");
            assert_near!(row.aw, 2.0 * HB * LB, 1e-12 * HB * LB, "{dz:?}");
            assert_near!(row.vol, 2.0 * HB * LB * D, 1e-12 * HB * LB * D, "{dz:?}");
        }
    }

    fn barge_truth(t: f64) -> HydrostaticsRow {
        let (b, vol) = (2.0 * HB, 2.0 * HB * LB * t);
        let (bmt, bml) = (LB * b.powi(3) / 12.0 / vol, b * LB.powi(3) / 12.0 / vol);
        HydrostaticsRow {
            draft: t,
            lwl: LB,
            bwl: b,
            vol,
            displ: vol * SEA_WATER_DENSITY,
            lcb: LB / 2.0,
            vcb: t / 2.0,
            cb: 1.0,
            am: b * t,
            cm: 1.0,
            aw: b * LB,
            cw: 1.0,
            cp: 1.0,
            lcf: LB / 2.0,
            s: LB * (b + 2.0 * t),
            // 1 cm of the waterplane's prism, in tonnes.
            tpc: b * LB * 0.01 * SEA_WATER_DENSITY,
            // On Lwl = LB (no perpendiculars given).
            mct: vol * SEA_WATER_DENSITY * bml / (100.0 * LB),
            bmt,
            bml,
            kmt: t / 2.0 + bmt,
            kml: t / 2.0 + bml,
            ..HydrostaticsRow::default()
        }
    }

    fn assert_rows_near(got: &HydrostaticsRow, want: &HydrostaticsRow, rel: f64) {
        for ((g, w), (name, _)) in got.values().iter().zip(want.values()).zip(HYDROSTATICS_COLUMNS) {
            match (*g, w) {
                (Some(g), Some(w)) => assert_near!(g, w, rel * w.abs().max(1.0), "{name} at draft {}", want.draft),
                (g, w) => assert_eq!(g, w, "{name} at draft {}", want.draft),
            }
        }
    }

    #[test]
    fn box_barge_has_the_box_figures_in_any_parameter_orientation() {
        let s = barge();
        let surfaces = [s.clone(), s.transposed(), s.reversed_u(), s.transposed().reversed_u()];
        for (k, surface) in surfaces.iter().enumerate() {
            let h = Hydrostatics::new(surface, &HydrostaticsOptions::default()).expect("valid options");
            assert_eq!((h.bottom(), h.top()), (0.0, D));
            // 1.0: the draft at the deck edge, the top edge being the waterline.
            for t in [0.3, 2.5, D] {
                // Polynomial integrands of low degree, integrated exactly: round-off only
                // (plus the lift of the waterline by 16 ulps).
                assert_rows_near(&h.at(t).expect("a draft on the hull"), &barge_truth(t), 1e-12);
            }
            assert_eq!(h.at(0.0).expect("the bottom"), HydrostaticsRow { draft: 0.0, ..Default::default() }, "{k}");
        }
    }

    #[test]
    fn figures_on_lpp_and_per_centimetre_follow_the_trade_in_any_unit() {
        // The barge read as feet, its perpendiculars 28 ft apart from x = 0 (amidships at 14,
        // 1 ft aft of the barge's middle): closed forms of a box.
        let s = barge();
        let pp = Perpendiculars::try_new(0.0, 28.0).expect("valid");
        let opts = HydrostaticsOptions { units: Units::Foot, perpendiculars: Some(pp), ..Default::default() };
        let h = Hydrostatics::new(&s, &opts).expect("valid options");
        let t = 2.5;
        let r = h.at(t).expect("a draft on the hull");
        let want = barge_truth(t);
        let (ft, b) = (0.3048_f64, 2.0 * HB);
        // The box's volume in m³ times the density: tonnes.
        assert_near!(r.displ, want.vol * ft.powi(3) * SEA_WATER_DENSITY, 1e-12 * r.displ);
        assert_near!(r.cb_lpp.expect("with Lpp"), want.vol / (28.0 * b * t), 1e-12);
        // A box's section is the same everywhere: CM 1 at amidships too; CP = LB / Lpp.
        assert_near!(r.cm_lpp.expect("with Lpp"), 1.0, 1e-12);
        assert_near!(r.cp_lpp.expect("with Lpp"), LB / 28.0, 1e-12);
        // LCB and LCF at 15 ft, amidships at 14: 1/28 of Lpp forward, positive.
        assert_near!(r.lcb_pct_lpp.expect("with Lpp"), 100.0 / 28.0, 1e-10);
        assert_near!(r.lcf_pct_lpp.expect("with Lpp"), 100.0 / 28.0, 1e-10);
        // 1 cm of immersion: AW in m² x 0.01 m x 1.025 t/m³, whatever the surface's unit.
        assert_near!(r.tpc, b * LB * ft * ft * 0.01 * SEA_WATER_DENSITY, 1e-12 * r.tpc);
        // MCT on Lpp: Displ BMl / (100 Lpp), BMl / Lpp being a ratio of lengths.
        assert_near!(r.mct, r.displ * want.bml / (100.0 * 28.0), 1e-12 * r.mct);
        for (got, w, name) in [(r.bmt, want.bmt, "BMt"), (r.bml, want.bml, "BMl"), (r.kmt, want.kmt, "KMt")] {
            assert_near!(got, w, 1e-12 * w, "{name}");
        }
        // Below the bottom the figures on Lpp are zeros, not absent.
        assert_eq!(h.at(0.0).expect("the bottom"), HydrostaticsRow::zero(0.0, true));
        assert!(Perpendiculars::try_new(0.0, 0.0).is_err() && Perpendiculars::try_new(f64::NAN, 1.0).is_err());
        let bad = HydrostaticsOptions { perpendiculars: Some(Perpendiculars { aft: 3.0, fore: 1.0 }), ..opts };
        assert!(Hydrostatics::new(&s, &bad).is_err());
    }

    /// Lengths of the wedge and the web, height of the bulb of [`barge_with_web`].
    const E1: f64 = 6.0;
    const E2: f64 = 2.5;
    const Z1: f64 = 2.0;

    /// The box barge lengthened forward by a box bulb of height `Z1` over `E1 + E2`, whose
    /// side above the bulb tapers to the centre plane over `E1` (a wedge), then runs in the
    /// centre plane over `E2`: a zero-thickness web above the bulb, as a station sliced from a
    /// mesh as two pieces joined on y = 0. Degree 1; stations at x = 0, LB, LB + E1,
    /// LB + E1 + E2; each section keel (0, 0), bottom (HB, 0), bulb side (HB, Z1), then (g, Z1)
    /// and (g, D) with g = HB aft (the box) and 0 forward.
    fn barge_with_web() -> NurbsSurface {
        let ku = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 2.0, 3.0, 4.0, 4.0]).expect("valid");
        let kv = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 2.0, 3.0, 3.0]).expect("valid");
        let stations = [(0.0, HB), (LB, HB), (LB + E1, 0.0), (LB + E1 + E2, 0.0)];
        let mut pts = Vec::new();
        for k in 0..5 {
            for &(x, g) in &stations {
                let (y, z) = [(0.0, 0.0), (HB, 0.0), (HB, Z1), (g, Z1), (g, D)][k];
                pts.push(Vec3::new(x, y, z));
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, None).expect("valid barge")
    }

    #[test]
    fn a_centre_plane_web_is_left_out_of_the_wetted_surface_and_the_waterline() {
        let surface = barge_with_web();
        let h = Hydrostatics::new(&surface, &HydrostaticsOptions::default()).expect("valid options");
        // Below the bulb's top the web is dry and the waterline runs along the bulb to its end.
        let low = h.at(1.0).expect("a draft");
        assert_near!(low.lwl, LB + E1 + E2, 1e-12 * LB);
        assert_eq!(h.web_area(1.0).expect("a draft"), 0.0);
        for t in [3.0, D] {
            let r = h.at(t).expect("a draft");
            // Closed forms (plane pieces: the rule is exact, round-off only). Half volume: the
            // box, the bulb, the wedge above it; the web adds nothing.
            let half_vol = HB * LB * t + HB * (E1 + E2) * Z1 + 0.5 * HB * E1 * (t - Z1);
            assert_near!(r.vol, 2.0 * half_vol, 1e-12 * r.vol, "vol at {t}");
            assert_near!(r.lwl, LB + E1, 1e-12 * LB, "the waterline ends where the wedge meets y = 0, at {t}");
            assert_near!(r.bwl, 2.0 * HB, 1e-12 * HB, "Bwl at {t}");
            let half_aw = HB * LB + 0.5 * HB * E1;
            assert_near!(r.aw, 2.0 * half_aw, 1e-12 * r.aw, "AW at {t}");
            assert_near!(r.cw, half_aw / ((LB + E1) * HB), 1e-12, "CW on Lwl at {t}");
            // Half S: bottom, box side, bulb sides, bulb top (a triangle over the wedge, a
            // rectangle under the web), the wedge's side above the bulb.
            let half_s = HB * (LB + E1 + E2)
                + LB * t
                + (E1 + E2) * Z1
                + HB * (0.5 * E1 + E2)
                + (E1 * E1 + HB * HB).sqrt() * (t - Z1);
            assert_near!(r.s, 2.0 * half_s, 1e-12 * r.s, "S at {t}");
            // The web's area, E2 x (t - Z1) on each side, is what was left out.
            assert_near!(h.web_area(t).expect("a draft"), 2.0 * E2 * (t - Z1), 1e-12 * E2 * t, "web at {t}");
        }
        assert_eq!(h.web_area(0.0).expect("the bottom"), 0.0);
        assert!(h.web_area(D + 1.0).is_err());
    }

    #[test]
    fn thin_parts_joined_to_the_centre_plane_edges_are_hull_not_web() {
        // The box barge's keel edge lies on the centre plane; scaled to a breadth below the web
        // tolerance (HB x 1e-4 against 2e-3 of the diagonal), every span is in the slab but
        // joined to that edge: a thin hull, wetted on both sides, not a web.
        let thin = barge();
        let pts: Vec<Vec3> = thin.control_points().iter().map(|p| Vec3::new(p.x, p.y * 1e-4, p.z)).collect();
        let s = NurbsSurface::try_new(thin.knots_u().clone(), thin.knots_v().clone(), &pts, None).expect("valid");
        let h = Hydrostatics::new(&s, &HydrostaticsOptions::default()).expect("valid options");
        let r = h.at(2.5).expect("a draft");
        assert_eq!(h.web_area(2.5).expect("a draft"), 0.0);
        // Round-off only: the same plane pieces as the barge, 1e-4 as broad.
        assert_near!(r.s, 2.0 * (HB * 1e-4 * LB + LB * 2.5), 1e-12 * r.s);
        assert_near!(r.lwl, LB, 1e-12 * LB);
    }

    #[test]
    fn drafts_outside_the_hull_are_zero_or_refused() {
        let s = barge();
        let h = Hydrostatics::new(&s, &HydrostaticsOptions::default()).expect("valid options");
        let below = h.at(-1.0).expect("below the bottom is no error");
        assert_eq!(below, HydrostaticsRow { draft: -1.0, ..Default::default() });
        assert!(below.values().iter().flatten().all(|v| v.is_finite()));
        let err = h.at(D + 0.01).expect_err("above the top");
        assert!(matches!(err, HullError::Draft { .. }) && err.to_string().contains("above the top"), "{err}");
        assert!(matches!(h.at(f64::NAN), Err(HullError::Draft { .. })));
        // A range reaching above the top computes nothing.
        assert!(h.range(1.0, D + 1.0, 1.0).is_err());
        for bad in [
            HydrostaticsOptions { density: 0.0, ..Default::default() },
            HydrostaticsOptions { density: f64::NAN, ..Default::default() },
            HydrostaticsOptions { order: 0, ..Default::default() },
            HydrostaticsOptions { split: 65, ..Default::default() },
        ] {
            assert!(matches!(Hydrostatics::new(&s, &bad), Err(HullError::Setting { .. })), "{bad:?}");
        }
    }

    #[test]
    fn draft_range_counts_from_the_start_and_ends_on_to() {
        assert_eq!(draft_range(1.0, 2.0, 0.25).expect("valid"), vec![1.0, 1.25, 1.5, 1.75, 2.0]);
        // 0.1 steps do not add up exactly; the last draft is `to` itself.
        let r = draft_range(0.5, 1.5, 0.1).expect("valid");
        assert_eq!((r.len(), r[10]), (11, 1.5));
        assert_near!(r[3], 0.8, 1e-15);
        assert_eq!(draft_range(3.0, 1.0, -1.0).expect("downward"), vec![3.0, 2.0, 1.0]);
        assert_eq!(draft_range(2.0, 2.0, 1.0).expect("one draft"), vec![2.0]);
        // A range that does not land on `to` stops below it.
        assert_eq!(draft_range(0.0, 1.0, 0.4).expect("valid"), vec![0.0, 0.4, 0.8]);
        for (from, to, step) in
            [(1.0, 2.0, 0.0), (1.0, 2.0, -0.5), (2.0, 1.0, 0.5), (1.0, f64::NAN, 0.1), (0.0, 1.0, 1e-9)]
        {
            assert!(matches!(draft_range(from, to, step), Err(HullError::DraftRange { .. })), "{from} {to} {step}");
        }
    }

    #[test]
    fn density_converts_per_cubic_unit() {
        assert_eq!(density_per_cubic_unit(1.025, Units::Metre), 1.025);
        // 1 ft³ = 0.3048³ m³ = 0.028316846592 m³ exactly.
        assert_near!(density_per_cubic_unit(1.025, Units::Foot), 1.025 * 0.028316846592, 1e-15);
        assert_near!(density_per_cubic_unit(1.0, Units::Millimetre), 1e-9, 1e-24);
    }

    /// Green's theorem in the parameter domain ties the waterline integral to the wet surface:
    /// `∮ y dx` around the wet part = `∫∫ (x_v y_u - x_u y_v) du dv = pxy`, the boundary being the
    /// waterline plus the domain edges below it. So `wa = pxy - Σ edges ∫ y dx`, the edges
    /// integrated here on their own (Gauss on each knot span, split at the waterline).
    #[test]
    fn waterline_integral_obeys_greens_theorem() {
        let fit = fit_offsets(&series60_sample(), &FitConfig::default()).expect("the sample fits");
        let s = &fit.surface;
        let integ = Integrator::new(s, 8, 2);
        let gl = nurbs::GaussLegendre::new(12);
        for t in [1.0, 3.25, 6.5, 8.0] {
            let level = t + integ.eps;
            let sums = integ.wet(level, 2.0 * integ.eps).sums;
            let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
            // (does u run along the edge, the other parameter's value, ccw orientation)
            let edges = [(true, v0, 1.0), (false, u1, 1.0), (true, v1, -1.0), (false, u0, -1.0)];
            let mut edge_sum = 0.0;
            for (along_u, fixed, orient) in edges {
                let at = |w: f64| if along_u { (w, fixed) } else { (fixed, w) };
                let knots = if along_u { s.knots_u() } else { s.knots_v() };
                let mut breaks: Vec<f64> = knots.as_slice().to_vec();
                breaks.dedup();
                for w in breaks.windows(2) {
                    let z = |p: f64| {
                        let (u, v) = at(p);
                        s.point(u, v).z - level
                    };
                    let (a, b) = (w[0], w[1]);
                    let mut pieces = vec![(a, b)];
                    if (z(a) <= 0.0) != (z(b) <= 0.0) {
                        let r = nurbs::brent_root(z, a, b, z(a), z(b), 0.0);
                        pieces = vec![(a, r), (r, b)];
                    }
                    for (p, q) in pieces {
                        if z(0.5 * (p + q)) > 0.0 {
                            continue;
                        }
                        for (x, wx) in gl.on(p, q) {
                            let (u, v) = at(x);
                            let d = s.derivatives(u, v);
                            let dx = if along_u { d.su.x } else { d.sv.x };
                            edge_sum += orient * wx * d.point.y * dx;
                        }
                    }
                }
            }
            // Two quadratures of the same number: round-off and the edges' rule only.
            assert_near!(sums.wa, sums.pxy - edge_sum, 1e-10 * sums.wa.abs(), "draft {t}");
            assert!(sums.wa.abs() > 100.0, "a real waterplane at {t}: {}", sums.wa);
            // Every cut cell of this hull is monotone along one parameter (no fallback).
            assert_eq!(integ.wet(level, 2.0 * integ.eps).unresolved, 0, "draft {t}");
        }
    }
}
