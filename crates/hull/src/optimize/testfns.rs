//! The optimisers' test problems and the checks every algorithm's tests share: one place for
//! the fixtures of GA, PSO and GSA (and LM where it needs them).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use super::{quiet, Control, Objective, OptimResult, Progress, StopReason};

/// A test problem: a box, a start, a function and where its minimum lies (for the sphere, the
/// shift).
pub struct TestFn {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    pub start: Vec<f64>,
    /// The unconstrained minimiser (the sphere's shift; the start where it is the optimum).
    pub optimum: Vec<f64>,
    f: fn(&TestFn, &[f64]) -> f64,
}

impl TestFn {
    /// `f(x) = sum_i (1 + i) (x_i - s_i)^2` on `[-5, 5]^n` from 0, minimum 0 at
    /// `s_i = 1 + i / 4` (shifted off the start so a run must move; beyond the box from
    /// `i = 17`).
    pub fn sphere(n: usize) -> Self {
        TestFn {
            lo: vec![-5.0; n],
            hi: vec![5.0; n],
            start: vec![0.0; n],
            optimum: (0..n).map(|i| 1.0 + 0.25 * i as f64).collect(),
            f: |t, x| x.iter().zip(&t.optimum).enumerate().map(|(i, (a, s))| (1.0 + i as f64) * (a - s).powi(2)).sum(),
        }
    }

    /// Rastrigin shifted by 1.5 on `[-5.12, 5.12]^n` from 0: many local minima, global 0 at
    /// x = 1.5.
    pub fn rastrigin(n: usize) -> Self {
        TestFn {
            lo: vec![-5.12; n],
            hi: vec![5.12; n],
            start: vec![0.0; n],
            optimum: vec![1.5; n],
            f: |_, x| {
                let tau = 2.0 * std::f64::consts::PI;
                x.iter().map(|&a| (a - 1.5).powi(2) - 10.0 * (tau * (a - 1.5)).cos() + 10.0).sum()
            },
        }
    }

    /// `f(x) = sum (x_k - s_k)^2` with `s` = the start, on `[-1, 2]^n`: the start is the
    /// global optimum (value 0), so no run may return anything else.
    pub fn start_is_optimum(n: usize) -> Self {
        let s: Vec<f64> = (0..n).map(|k| 0.1 + 0.37 * k as f64).collect();
        TestFn {
            lo: vec![-1.0; n],
            hi: vec![2.0; n],
            start: s.clone(),
            optimum: s,
            f: |t, x| x.iter().zip(&t.optimum).map(|(a, s)| (a - s).powi(2)).sum(),
        }
    }

    /// The sphere `sum (x_k - 1)^2` on `[-2, 2]^n` from 0, NaN wherever `x_0 > 0.5` (an
    /// infeasible region next to the optimum, which is therefore at `x_0 = 0.5`, value 0.25).
    pub fn nan_region(n: usize) -> Self {
        TestFn {
            lo: vec![-2.0; n],
            hi: vec![2.0; n],
            start: vec![0.0; n],
            optimum: vec![1.0; n],
            f: |t, x| if x[0] > 0.5 { f64::NAN } else { x.iter().zip(&t.optimum).map(|(a, s)| (a - s).powi(2)).sum() },
        }
    }
}

impl Objective for TestFn {
    fn dim(&self) -> usize {
        self.lo.len()
    }
    fn lower(&self) -> &[f64] {
        &self.lo
    }
    fn upper(&self) -> &[f64] {
        &self.hi
    }
    fn value(&self, x: &[f64]) -> f64 {
        (self.f)(self, x)
    }
    fn start(&self) -> Vec<f64> {
        self.start.clone()
    }
}

/// A runner: objective, seed, control -> result.
pub type Runner<'a> = &'a (dyn Fn(&dyn Objective, u64, &Control<'_>) -> OptimResult + Sync);

/// A run's remaining gap on the sphere, `(f - f*) / (f(start) - f*)`, with `f*` the minimum
/// on its box, `sum c_k (clamp(s_k) - s_k)^2`; checks the run's invariants first.
pub fn sphere_gap(s: &TestFn, r: &OptimResult) -> f64 {
    check_invariants(s, r);
    let clamped: Vec<f64> = s.optimum.iter().zip(s.lo.iter().zip(&s.hi)).map(|(&v, (&l, &h))| v.clamp(l, h)).collect();
    let fmin = s.value(&clamped);
    (r.value - fmin) / (r.history[0] - fmin)
}

/// The sphere's gap after a run of `name` below `bound` for each `(dimension, bound)`, on
/// seeds `0..seeds`.
pub fn sphere_gaps_below(name: &str, run: Runner<'_>, cases: &[(usize, f64)], seeds: u64) {
    for &(d, bound) in cases {
        let obj = TestFn::sphere(d);
        for seed in 0..seeds {
            let r = quiet(|c| run(&obj, seed, c));
            let gap = sphere_gap(&obj, &r);
            assert!(gap < bound, "{name} d={d} seed {seed}: gap {gap:e}");
        }
    }
}

/// Rastrigin in 5 variables ends below `bound` after a run of `name` on seeds 0 and 1, the
/// run's invariants held.
pub fn rastrigin_below(name: &str, run: Runner<'_>, bound: f64) {
    let obj = TestFn::rastrigin(5);
    for seed in 0..2 {
        let r = quiet(|c| run(&obj, seed, c));
        check_invariants(&obj, &r);
        assert!(r.value < bound, "{name} seed {seed}: {}", r.value);
    }
}

/// The result's own invariants: the history starts at the start's value, never increases,
/// ends at the returned value, and the returned value is the objective at the returned x.
pub fn check_invariants(obj: &dyn Objective, r: &OptimResult) {
    let f0 = obj.value(&obj.start());
    assert_eq!(r.history[0], f0, "history[0] is the start's value");
    assert_eq!(r.history.len(), r.iterations + 1);
    assert!(r.history.windows(2).all(|w| w[1] <= w[0]), "history increased: {:?}", r.history);
    assert_eq!(*r.history.last().expect("history is never empty"), r.value);
    assert_eq!(obj.value(&r.x), r.value, "value is f(x)");
    assert!(r.x.iter().zip(obj.lower().iter().zip(obj.upper())).all(|(x, (l, h))| l <= x && x <= h));
}

/// The start is the optimum: the result is exactly the start.
pub fn never_worse_than_start(run: Runner<'_>) {
    let obj = TestFn::start_is_optimum(6);
    let r = quiet(|c| run(&obj, 3, c));
    check_invariants(&obj, &r);
    assert_eq!(r.value, 0.0);
    assert_eq!(r.x, obj.start());
}

/// Stop raised from the progress callback after iteration 3: the run ends there, keeping
/// its best.
pub fn interrupt_after_three(run: Runner<'_>) {
    let obj = TestFn::sphere(5);
    let stop = AtomicBool::new(false);
    let calls = AtomicUsize::new(0);
    let progress = |p: Progress| {
        calls.fetch_add(1, Ordering::Relaxed);
        if p.iteration == 3 {
            stop.store(true, Ordering::Relaxed);
        }
    };
    let control = Control { stop: &stop, progress: &progress };
    let r = run(&obj, 11, &control);
    assert_eq!(r.stop, StopReason::Interrupted);
    assert_eq!(r.iterations, 3);
    assert_eq!(calls.load(Ordering::Relaxed), 3);
    check_invariants(&obj, &r);
    assert!(r.value < r.history[0], "three iterations near the start improve the sphere");
}

/// Same seed: bit-identical results on 1 and 2 threads; another seed: a different result.
pub fn reproducible(run: Runner<'_>) {
    let obj = TestFn::rastrigin(4);
    let on = |threads: usize, seed: u64| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a rayon pool");
        pool.install(|| quiet(|c| run(&obj, seed, c)))
    };
    let a = on(1, 42);
    let b = on(2, 42);
    assert_eq!(a, b, "same seed, different thread counts");
    let c = on(2, 43);
    assert_ne!(a.history, c.history, "different seeds");
}

/// NaN in part of the box is +inf: no panic, the result is feasible and improves.
pub fn nan_region(run: Runner<'_>) {
    let obj = TestFn::nan_region(3);
    let r = quiet(|c| run(&obj, 5, c));
    check_invariants(&obj, &r);
    assert!(r.value.is_finite() && r.x[0] <= 0.5);
    assert!(r.value < 1.1 * 0.25 + 0.01 && r.value >= 0.25, "value {}", r.value);
}
