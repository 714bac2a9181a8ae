#!/usr/bin/env python3
"""Why hullskin's approx loses to geomdl on some cases: a numpy model of the two-stage skin fit.

`skin()` re-implements hullskin's `skin_approximate` (crates/nurbs/src/fit/skin.rs) as read on
2026-11-22: every section gets ITS OWN parameters (centripetal or chord), the common u knots are
the mean of the sections' centred eq. 9.68-9.69 knot vectors, each section is fitted by least
squares with its ends interpolated, then the columns of the sections' control points are fitted
across, with v parameters averaged over the columns. With `--hullskin` the script runs the binary
too and prints both, so the model can be checked against the real thing (it matched to 4
significant digits on wigley, freeform and cargo116_st). Variants, one change each:

* `averaged`: the sections share one u parameter vector (the mean of theirs), as geomdl's
  `compute_params_surface` does;
* `book knots`: the knots of The NURBS Book eq. 9.69 as printed (geomdl's
  `compute_knot_vector2`) instead of the centred form.

  python tools/peers/approx_variants.py --cases wigley,freeform --hullskin target/release/hullskin

Needs numpy (in requirements.txt). A diagnostic, not part of compare.py's verdicts.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import cases  # noqa: E402
import fitters  # noqa: E402
from measure import measure  # noqa: E402


def basis_row(n: int, p: int, knots, t: float) -> np.ndarray:
    """[N_{0,p}(t) .. N_{n-1,p}(t)] by Cox-de Boor (The NURBS Book eq. 2.5), closed at the end."""
    U = list(knots)
    m = len(U) - 1
    N = np.zeros(m)
    for i in range(m):
        if U[i] <= t < U[i + 1] or (t == U[-1] and U[i] < t <= U[i + 1]):
            N[i] = 1.0
            if t < U[-1]:
                break
    for k in range(1, p + 1):
        new = np.zeros(m - k)
        for i in range(m - k):
            a = (t - U[i]) / (U[i + k] - U[i]) * N[i] if U[i + k] != U[i] else 0.0
            b = (
                (U[i + k + 1] - t) / (U[i + k + 1] - U[i + 1]) * N[i + 1]
                if U[i + k + 1] != U[i + 1]
                else 0.0
            )
            new[i] = a + b
        N = new
    return N[:n]


def params(pts, kind: str) -> np.ndarray:
    d = [float(np.linalg.norm(np.subtract(b, a))) for a, b in zip(pts[:-1], pts[1:])]
    if kind == "centripetal":
        d = [math.sqrt(x) for x in d]
    s = np.concatenate([[0.0], np.cumsum(d)])
    return s / s[-1]


def knots(t, n: int, p: int, book: bool) -> list[float]:
    """Eq. 9.68-9.69: u_{p+j} = T(j d - 1) as printed (book), or the centred T(j d - 1/2)."""
    m = len(t)
    interior = n - p - 1
    d = m / (interior + 1)
    shift = 1.0 if book else 0.5

    def T(x):
        i = min(int(math.floor(x)), m - 2)
        a = x - i
        return (1 - a) * t[i] + a * t[i + 1]

    return [0.0] * (p + 1) + [T(j * d - shift) for j in range(1, interior + 1)] + [1.0] * (p + 1)


def lsq(Q, t, U, n: int, p: int) -> np.ndarray:
    """Least squares with the end points interpolated (The NURBS Book 9.4.1)."""
    Q = np.asarray(Q, dtype=float)
    A = np.array([basis_row(n, p, U, tk) for tk in t])
    P = np.zeros((n, 3))
    P[0], P[-1] = Q[0], Q[-1]
    R = Q - np.outer(A[:, 0], Q[0]) - np.outer(A[:, -1], Q[-1])
    P[1:-1] = np.linalg.lstsq(A[1:-1, 1:-1], R[1:-1], rcond=None)[0]
    return P


def skin(sections, nu: int, nv: int, kind: str, averaged=False, book=False, p=3, q=3):
    tu = [params(s, kind) for s in sections]
    if averaged:
        mean = np.mean(tu, axis=0)
        tu = [mean] * len(sections)
    ku = np.mean([knots(t, nu, p, book) for t in tu], axis=0)
    rows = [lsq(s, t, ku, nu, p) for s, t in zip(sections, tu)]
    K = len(sections)
    v = np.mean([params([rows[k][i] for k in range(K)], kind) for i in range(nu)], axis=0)
    kv = knots(v, nv, q, book)
    net = np.array([lsq([rows[k][i] for k in range(K)], v, kv, nv, q) for i in range(nu)])
    ctrl = [tuple(x) for x in net.reshape(-1, 3)]
    return fitters.bspline_surface((p, q), (nu, nv), list(ku), list(kv), ctrl, None)


def line(label, m):
    return (
        f"  {label:34s} offsets RMS {m['offsets']['rms'] * 1e3:9.4g}  between max "
        f"{m['between']['max'] * 1e3:9.4g}  RMS {m['between']['rms'] * 1e3:9.4g}  (mm)"
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="wigley,freeform,cargo116_st")
    ap.add_argument("--param", default="centripetal", choices=["centripetal", "chord"])
    ap.add_argument("--hullskin", help="also run and measure the real binary")
    ap.add_argument("--data", default="/work/shared/data")
    args = ap.parse_args(argv)
    by_name = {c.name: c for c in cases.all_cases(args.data, 4)}
    hs = fitters.Hullskin(args.hullskin, param=args.param) if args.hullskin else None
    with tempfile.TemporaryDirectory() as work:
        for name in args.cases.split(","):
            c = by_name[name]
            csv_path = os.path.join(work, f"{name}.csv")
            cases.write_sections_csv(csv_path, c.sections)
            for ctrl in c.approx:
                print(f"{name} {ctrl[0]}x{ctrl[1]} ({args.param})")
                offs, btw = c.offsets(), c.between
                if hs:
                    s, *_ = hs.fit(csv_path, os.path.join(work, f"{name}_{ctrl}"), "approx", ctrl)
                    print(line("hullskin binary", measure(s, offs, btw)))
                for label, kw in [
                    ("model of hullskin", {}),
                    ("model, averaged parameters", {"averaged": True}),
                    ("model, book knots", {"book": True}),
                    ("model, averaged + book knots", {"averaged": True, "book": True}),
                ]:
                    s = skin(c.sections, ctrl[0], ctrl[1], args.param, **kw)
                    print(line(label, measure(s, offs, btw)))
                g = fitters.geomdl_approx(c.sections, ctrl, centripetal=args.param == "centripetal")
                print(line("geomdl approximate_surface", measure(g, offs, btw)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
