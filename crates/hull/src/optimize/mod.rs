//! Optimisers of the NURBS weights: the objective is kept apart from the algorithms, so the
//! Genetic Algorithm, Particle Swarm Optimization, the Gravitational Search Algorithm and the
//! local solvers all minimise one [`Objective`] over `&[f64]`. The rest of this module's
//! documentation is on [`Objective`] and [`Control`], where the library's users read it.

use std::sync::atomic::{AtomicBool, Ordering};

use nurbs::NurbsSurface;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

mod driver;
mod ga;
mod gsa;
mod linalg;
mod lm;
mod net_energy;
mod pso;
mod weights;

pub use driver::{optimize_weights, Algorithm, OptimReport, OptimSettings, Optimized};
pub use ga::{run as run_ga, GaOptions};
pub use gsa::{run as run_gsa, GsaOptions, GsaRandom};
pub use lm::{run as run_lm, LmOptions};
pub use pso::{run as run_pso, PsoOptions, PsoVariant};
pub use weights::{
    JacobianKind, Linearization, NormalEquations, ParamFreedom, WeightLayout, WeightMode, WeightOptions, WeightProblem,
};

/// A fitted surface and the data parameters of its offsets: where a weight optimisation starts
/// ([`crate::FitOutcome`] is one). The optimisers need no more of a fit, and know no more.
pub trait FittedSurface {
    /// The surface.
    fn surface(&self) -> &NurbsSurface;
    /// The data parameters `(u, v)` of every offset, one list per section.
    fn params(&self) -> &[Vec<(f64, f64)>];
    /// The offsets' closest points on the surface (in input order), each projection started
    /// at its parameters, where they were found already; `None` to project them.
    fn foot_points(&self) -> Option<&[(f64, f64)]> {
        None
    }
}

/// A function to minimise over a box: one objective for the Genetic Algorithm, Particle Swarm
/// Optimization, the Gravitational Search Algorithm and the local solvers.
///
/// Reproducibility: every algorithm draws its random numbers from one ChaCha8 stream seeded by
/// the caller, in a fixed order on the calling thread; only the objective evaluations of a
/// population run in parallel (rayon), and each evaluation is a pure function of its vector.
/// So the same seed gives bit-identical results whatever the thread count.
///
/// Every run starts from [`Objective::start`] (all weights 1) and never returns anything worse
/// than it (elitism), records the best value after each iteration, and stops early, keeping
/// its best, when [`Control::stop`] is raised (Ctrl-C).
pub trait Objective: Sync {
    /// Number of variables.
    fn dim(&self) -> usize;
    /// Lower bounds, one per variable.
    fn lower(&self) -> &[f64];
    /// Upper bounds, one per variable.
    fn upper(&self) -> &[f64];
    /// The value at `x` (inside the box). A non-finite value marks an infeasible point and is
    /// treated as `+inf` by the algorithms.
    fn value(&self, x: &[f64]) -> f64;
    /// The known good starting point (for weights: all 1, i.e. zero log-weights).
    fn start(&self) -> Vec<f64>;
    /// The box GA, PSO and GSA search, inside the bounds and containing the start (their unit
    /// cube is this box). Default: the bounds. A problem whose useful moves are far smaller
    /// than its bounds narrows it (see [`weights::WeightOptions::search_scale`]).
    fn search_box(&self) -> (Vec<f64>, Vec<f64>) {
        (self.lower().to_vec(), self.upper().to_vec())
    }
}

/// Why a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The iteration budget was used.
    Iterations,
    /// A convergence criterion was met.
    Converged,
    /// [`Control::stop`] was raised.
    Interrupted,
}

impl StopReason {
    /// How the run ended, in words for the summary and the report page.
    pub fn phrase(self) -> &'static str {
        match self {
            StopReason::Iterations => "iteration budget used",
            StopReason::Converged => "converged",
            StopReason::Interrupted => "interrupted",
        }
    }
}

/// The outcome of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct OptimResult {
    /// The best point found.
    pub x: Vec<f64>,
    /// Its value.
    pub value: f64,
    /// Objective evaluations done.
    pub evaluations: usize,
    /// Iterations (generations) done.
    pub iterations: usize,
    /// The best value after each iteration (`history[0]` is the start's value).
    pub history: Vec<f64>,
    pub stop: StopReason,
}

/// One progress report, sent after each iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    pub iteration: usize,
    pub iterations: usize,
    pub best: f64,
    pub evaluations: usize,
}

/// How a caller watches and stops a run: progress after each iteration, and a flag that, once
/// raised (the command line raises it on Ctrl-C), ends the run at the end of its iteration,
/// keeping the best found so far (never worse than [`Objective::start`]).
pub struct Control<'a> {
    /// Raised (e.g. by a Ctrl-C handler) to stop the run at the end of the current iteration.
    pub stop: &'a AtomicBool,
    /// Called after each iteration.
    pub progress: &'a (dyn Fn(Progress) + Sync),
}

impl Control<'_> {
    /// True once a stop was requested.
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// A control that never stops and reports nothing.
pub fn quiet<R>(f: impl FnOnce(&Control<'_>) -> R) -> R {
    let stop = AtomicBool::new(false);
    let control = Control { stop: &stop, progress: &|_| {} };
    f(&control)
}

/// The random stream of a run.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// Evaluate a population in parallel; non-finite values become `+inf`. The result does not
/// depend on the thread count (each value is a pure function of its vector).
pub fn evaluate_all(obj: &dyn Objective, xs: &[Vec<f64>]) -> Vec<f64> {
    xs.par_iter()
        .map(|x| {
            let f = obj.value(x);
            if f.is_finite() {
                f
            } else {
                f64::INFINITY
            }
        })
        .collect()
}

/// The test problems and shared checks of the algorithms' tests.
#[cfg(test)]
pub(crate) mod testfns;
