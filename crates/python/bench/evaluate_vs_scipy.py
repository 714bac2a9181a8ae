"""Evaluation speed: hullskin's vectorised Surface.evaluate against SciPy's NdBSpline.

A 10 x 8 bicubic rational surface (clamped uniform knots, seeded random control points and
weights in [0.5, 2]) is evaluated at 1e6 (u, v) pairs in one call; SciPy's NdBSpline evaluates
the same surface's non-rational part (same knots and control points, weights dropped) at the
same pairs. hullskin runs on all cores (rayon) and, in a child process, on one
(RAYON_NUM_THREADS=1); NdBSpline runs on one. Best of 5 runs each. Prints a table.

    python crates/python/bench/evaluate_vs_scipy.py [--points N]

Whole-program timing is a script, not a test (STYLE.md 12).
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

import hullskin

P = Q = 3
NU, NV = 10, 8


def clamped(n, p):
    inner = np.linspace(0.0, 1.0, n - p + 1)
    return np.concatenate([np.zeros(p), inner, np.ones(p)])


def surface(rational=True):
    rng = np.random.default_rng(14)
    tu, tv = clamped(NU, P), clamped(NV, Q)
    i, j = np.meshgrid(np.arange(NU), np.arange(NV), indexing="ij")
    cp = np.stack([i * 10.0, j * 2.0, np.zeros_like(i, dtype=float)], axis=-1) + rng.normal(0, 1.0, (NU, NV, 3))
    w = rng.uniform(0.5, 2.0, (NU, NV)) if rational else np.ones((NU, NV))
    return tu, tv, cp, w


def best(f, runs=5):
    times = []
    out = None
    for _ in range(runs):
        t0 = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t0)
    return min(times), out


def hullskin_time(n):
    tu, tv, cp, w = surface()
    s = hullskin.Surface((P, Q), tu, tv, cp, w)
    rng = np.random.default_rng(1)
    u, v = rng.random(n), rng.random(n)
    t, _ = best(lambda: s.evaluate(u, v))
    return t


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=1_000_000)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    n = args.points
    if args.child:
        print(json.dumps({"seconds": hullskin_time(n)}))
        return

    import scipy
    from scipy.interpolate import NdBSpline

    tu, tv, cp, w = surface()
    rng = np.random.default_rng(1)
    u, v = rng.random(n), rng.random(n)

    # Same surface, weights all 1: hullskin and SciPy must agree (a check that the two
    # evaluate the same thing, not only fast).
    s1 = hullskin.Surface((P, Q), tu, tv, cp)
    spl = NdBSpline((tu, tv), cp, (P, Q))
    k = 10_000
    diff = np.abs(s1.evaluate(u[:k], v[:k]) - spl(np.stack([u[:k], v[:k]], axis=-1))).max()

    xi = np.stack([u, v], axis=-1)
    t_scipy, _ = best(lambda: spl(xi))
    t_all = hullskin_time(n)
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    r = subprocess.run([sys.executable, __file__, "--points", str(n), "--child"], env=env, capture_output=True,
                       text=True, check=True)
    t_one = json.loads(r.stdout)["seconds"]

    cores = os.cpu_count()
    print(f"{NU}x{NV} bicubic surface, {n:,} (u, v) pairs in one call; best of 5; {cores} cores; "
          f"numpy {np.__version__}, scipy {scipy.__version__}, hullskin {hullskin.__version__}")
    print(f"non-rational check: max |hullskin - NdBSpline| = {diff:.3e} over {k:,} pairs")
    print()
    print(f"| {'evaluator':<44} | {'seconds':>8} | {'Mpairs/s':>8} | {'vs NdBSpline':>12} |")
    print(f"|{'-' * 46}|{'-' * 10}|{'-' * 10}|{'-' * 14}|")
    rows = [
        ("scipy NdBSpline, non-rational part, 1 thread", t_scipy),
        ("hullskin Surface.evaluate, rational, 1 thread", t_one),
        (f"hullskin Surface.evaluate, rational, {cores} threads", t_all),
    ]
    for name, t in rows:
        print(f"| {name:<44} | {t:8.4f} | {n / t / 1e6:8.2f} | {t_scipy / t:11.1f}x |")


if __name__ == "__main__":
    main()
