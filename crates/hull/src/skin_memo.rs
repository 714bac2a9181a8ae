//! The skins of one fit, kept by their settings for a search that fits them again with another
//! envelope hold.
//!
//! The default fit's first alternative ([`crate::alternatives`]) is the same fairing search
//! with the surface held instead of the net ([`HoldOn::Surface`]): the same least squares at
//! the same smoothing weights, held differently. Neither the skin (the unheld least squares,
//! its findings, its knuckle and flat lines) nor its net hold depends on what the hold holds,
//! so the second search takes both from here instead of fitting them again (the net hold is
//! the surface hold's fallback where that one keeps a finding), nor the fairness figures of
//! the unheld least squares the search is to be no less fair than. What is taken is what the
//! fit would give, bit for bit; only its time is that spent now (none).

use std::sync::{Mutex, MutexGuard};

use nurbs::fit::KnuckleLine;
use nurbs::NurbsSurface;

use crate::analysis::Finding;
use crate::fit::{Fairing, FairnessFigures, FitConfig, FitOutcome, HoldOn};
use crate::HullError;

/// A skin: the unheld fit, assembled ([`crate::pipeline`]), with the knuckle lines it kept.
pub(crate) type Skin = (FitOutcome, Vec<KnuckleLine>);

/// A net hold of a skin: the held fit with its findings, when a round of the hold measured
/// them.
pub(crate) type NetHeld = (FitOutcome, Option<Vec<Finding>>);

/// What one set of settings fitted so far.
#[derive(Default)]
struct Kept {
    skin: Option<Skin>,
    net: Option<NetHeld>,
}

/// The skins and net holds fitted so far in one call of the pipeline, by their settings but
/// the hold ([`FitConfig::hold_on`]) and the fairing setting ([`FitConfig::fair`]), and the
/// fairness figures measured of surfaces. Shared by the fits a fairing search runs in parallel.
#[derive(Default)]
pub(crate) struct SkinMemo {
    fits: Mutex<Vec<(FitConfig, Kept)>>,
    figures: Mutex<Vec<(NurbsSurface, FairnessFigures)>>,
}

impl SkinMemo {
    /// The skin of `config`: the one kept for its settings (but the hold), with `config` as
    /// its own and no time spent, else `make()`'s, kept.
    ///
    /// # Errors
    /// Those of `make`, which is called again next time.
    pub(crate) fn skin(
        &self,
        config: &FitConfig,
        make: impl FnOnce() -> Result<Skin, HullError>,
    ) -> Result<Skin, HullError> {
        let (mut skin, kept) = self.kept(config, |k| &mut k.skin, make)?;
        if kept {
            (skin.0.config, skin.0.fit_seconds, skin.0.error_seconds) = (*config, 0.0, 0.0);
        }
        Ok(skin)
    }

    /// The net hold of the skin of `config`, which took `seconds` to fit: the one kept for its
    /// settings (but the hold), with `config` as its own and no time spent beyond `seconds`,
    /// else `make()`'s, kept.
    ///
    /// # Errors
    /// Those of `make`, which is called again next time.
    pub(crate) fn net_held(
        &self,
        config: &FitConfig,
        seconds: f64,
        make: impl FnOnce() -> Result<NetHeld, HullError>,
    ) -> Result<NetHeld, HullError> {
        let (mut held, kept) = self.kept(config, |k| &mut k.net, make)?;
        if kept {
            (held.0.config, held.0.fit_seconds) = (*config, seconds);
        }
        Ok(held)
    }

    /// The fairness figures of `surface` ([`FairnessFigures::of`]): those measured of it
    /// before, else measured now and kept.
    pub(crate) fn fairness(&self, surface: &NurbsSurface) -> FairnessFigures {
        let lock = || self.figures.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(&(_, f)) = lock().iter().find(|(s, _)| s == surface) {
            return f;
        }
        let f = FairnessFigures::of(surface);
        lock().push((surface.clone(), f));
        f
    }

    /// The `slot` kept for `config`'s settings (but the hold) and `true`, else `make()`'s,
    /// kept, and `false`. The lock is not held while `make` runs.
    fn kept<T: Clone>(
        &self,
        config: &FitConfig,
        slot: impl Fn(&mut Kept) -> &mut Option<T>,
        make: impl FnOnce() -> Result<T, HullError>,
    ) -> Result<(T, bool), HullError> {
        // Neither the skin nor its net hold reads the fairing setting (only the smoothing it
        // chose), so a fit with fairing off (the surface hold for fairness fits its least
        // squares so first) takes the skin of the search's plain fit.
        let key = FitConfig { hold_on: HoldOn::Net, fair: Fairing::Off, ..*config };
        let found = self.lock().iter_mut().find(|(c, _)| *c == key).and_then(|(_, k)| slot(k).clone());
        if let Some(t) = found {
            return Ok((t, true));
        }
        let t = make()?;
        let mut fits = self.lock();
        let at = match fits.iter().position(|(c, _)| *c == key) {
            Some(at) => at,
            None => {
                fits.push((key, Kept::default()));
                fits.len() - 1
            }
        };
        *slot(&mut fits[at].1) = Some(t.clone());
        Ok((t, false))
    }

    fn lock(&self) -> MutexGuard<'_, Vec<(FitConfig, Kept)>> {
        // A panic elsewhere leaves the list whole: each entry is written in one assignment.
        self.fits.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}
