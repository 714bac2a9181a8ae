//! Flags of the weight optimisation, shared by `fit` and `compare`.

use clap::Args;
use hull::{OptimSettings, WeightLayout, WeightMode, WeightOptions};

/// Settings of the weight optimisers (methods ga, pso, gsa, lm, gsa+lm).
#[derive(Debug, Clone, Args)]
pub struct OptimArgs {
    /// Seed of the optimisers' random numbers: the same seed gives the same surface, whatever
    /// the thread count.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Iterations (generations) of GA, PSO or GSA, or the iteration cap of LM (for gsa+lm: of
    /// both phases). Default: each algorithm's own (GA 200, PSO 200, GSA 500, LM 100).
    #[arg(long)]
    pub iterations: Option<usize>,
    /// Population of GA, particles of PSO, agents of GSA. Default: 50, 40, 50.
    #[arg(long)]
    pub population: Option<usize>,
    /// Weight layout: `full` (one weight per control point) or `rank1` (w_ij = a_i b_j, fewer
    /// variables, less over-fitting between the offsets).
    #[arg(long, default_value = "full", value_parser = str::parse::<WeightLayout>)]
    pub weights: WeightLayout,
    /// Control points while the weights move: `resolved` (least squares for every weight
    /// vector) or `fixed` (those of the plain approximation).
    #[arg(long = "control-points", default_value = "resolved", value_parser = str::parse::<WeightMode>)]
    pub control_points: WeightMode,
    /// Finish with a joint fit of the weights and the offsets' parameters (moves each
    /// offset's parameters toward its foot point).
    #[arg(long)]
    pub param_correction: bool,
    /// Start the weights from the skinning's own parameters of the offsets instead of their
    /// foot points on the plain approximation (the default; the foot points make the objective
    /// the true distance at the start).
    #[arg(long)]
    pub fitted_params: bool,
}

impl Default for OptimArgs {
    fn default() -> Self {
        let d = OptimSettings::default();
        OptimArgs {
            seed: d.seed,
            iterations: None,
            population: None,
            weights: d.weights.layout,
            control_points: d.weights.mode,
            param_correction: false,
            fitted_params: !d.foot_point_start,
        }
    }
}

impl OptimArgs {
    /// The library settings.
    pub fn settings(&self) -> OptimSettings {
        OptimSettings {
            seed: self.seed,
            iterations: self.iterations,
            population: self.population,
            weights: WeightOptions { mode: self.control_points, layout: self.weights, ..WeightOptions::default() },
            parameter_correction: self.param_correction,
            foot_point_start: !self.fitted_params,
        }
    }
}
