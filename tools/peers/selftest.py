#!/usr/bin/env python3
"""Checks of the comparison's own machinery (cases, surface rebuilding, distance measure).

  python tools/peers/selftest.py          # prints 'N passed, M failed', exit 1 on a failure

Needs no hullskin binary. Takes about a minute (brute-force grids in pure Python).
"""

from __future__ import annotations

import math
import os
import random
import sys
import tempfile
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import cases  # noqa: E402
import fitters  # noqa: E402
from measure import PatchDistance, max_deviation  # noqa: E402

DATA = os.environ.get("HULLSKIN_SHARED_DATA", "/work/shared/data")
RESULTS = []


def check(name):
    def deco(fn):
        try:
            fn()
            RESULTS.append((name, None))
        except Exception:
            RESULTS.append((name, traceback.format_exc()))
        return fn

    return deco


def brute_min(surf, pts, n=300):
    """min over an n x n parameter grid: an UPPER bound of the true distance to the patch."""
    u0, u1, v0, v1 = surf.Bounds()
    grid = []
    for i in range(n + 1):
        u = u0 + (u1 - u0) * i / n
        for j in range(n + 1):
            q = surf.Value(u, v0 + (v1 - v0) * j / n)
            grid.append((q.X(), q.Y(), q.Z()))
    out = []
    for x, y, z in pts:
        out.append(math.sqrt(min((a - x) ** 2 + (b - y) ** 2 + (c - z) ** 2 for a, b, c in grid)))
    return out


@check("exact case: between grid has (4(n-1)+1)(4(m-1)+1) - nm points, none an offset")
def _():
    c = cases.wigley(4)
    nu, nv = c.size
    assert len(c.between) == (4 * (nu - 1) + 1) * (4 * (nv - 1) + 1) - nu * nv, len(c.between)
    offs = set(c.offsets())
    assert not offs.intersection(c.between)


@check("exact cases: offsets and between points lie on the closed-form surface")
def _():
    c = cases.wigley(4)
    L, B, T = 100.0, 10.0, 6.25
    for x, y, z in c.offsets() + c.between:
        # 1e-12 m: the formula evaluated twice in the same order, only rounding can differ.
        assert abs(y - B / 2 * (1 - (2 * x / L) ** 2) * (1 - ((T - z) / T) ** 2)) < 1e-12


@check("hold-out cases: fit + held-out = the full table, first and last kept")
def _():
    for c in cases.series60(DATA):
        n_all = 25 * 8
        assert len(c.offsets()) + len(c.between) == n_all, (
            c.name,
            len(c.offsets()),
            len(c.between),
        )
    wl, st = cases.series60(DATA)
    # the z of the first and last kept waterline are the table's first and last (0 and 1.5 T)
    assert wl.sections[0][0][2] == 0.0 and abs(wl.sections[0][-1][2] - 1.5 * 6.5) < 1e-12
    # stations: x = 0 (AP) first and x = L (FP) last
    assert st.sections[0][0][0] == 0.0 and abs(st.sections[-1][0][0] - 121.92) < 1e-9
    # the typo fix: station 0 (FP, x = L), WL 0.25 has half-breadth 0
    fp = [p for p in wl.sections[-1]]
    assert all(p[1] == 0.0 for p in fp if p[2] <= 6.5), fp


@check("sections CSV round-trips the doubles exactly")
def _():
    c = cases.freeform(4)
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "f.csv")
        cases.write_sections_csv(path, c.sections)
        with open(path) as f:
            lines = f.read().splitlines()
    assert lines[0] == "section,x,y,z"
    back = [tuple(float(v) for v in ln.split(",")[1:]) for ln in lines[1:]]
    assert back == c.offsets()


@check("bspline_surface(rebuilt from an OCCT surface's full knots and poles) is the same surface")
def _():
    s = fitters.occt_interpolate(cases.wigley(4).sections, "centripetal")
    p, q = s.UDegree(), s.VDegree()
    nu, nv = s.NbUPoles(), s.NbVPoles()
    ku = [s.UKnotSequence().Value(i) for i in range(1, nu + p + 2)]
    kv = [s.VKnotSequence().Value(i) for i in range(1, nv + q + 2)]
    ctrl = []
    for i in range(1, nu + 1):
        for j in range(1, nv + 1):
            P = s.Pole(i, j)
            ctrl.append((P.X(), P.Y(), P.Z()))
    r = fitters.bspline_surface((p, q), (nu, nv), ku, kv, ctrl, [1.0] * (nu * nv))
    # Same knots and poles: evaluation is bit-for-bit the same algorithm; 1e-12 m allows rounding.
    assert max_deviation(s, r) < 1e-12


@check("distance to points offset along the normal by d is d")
def _():
    s = fitters.occt_interpolate(cases.wigley(4).sections, "centripetal")
    pd = PatchDistance(s)
    u0, u1, v0, v1 = s.Bounds()
    from OCP.GeomLProp import GeomLProp_SLProps

    d = 0.01  # 1 cm, far below the surface's smallest radius of curvature (~metres)
    rng = random.Random(1)
    for _ in range(50):
        u = u0 + (u1 - u0) * rng.uniform(0.1, 0.9)
        v = v0 + (v1 - v0) * rng.uniform(0.1, 0.9)
        props = GeomLProp_SLProps(s, u, v, 1, 1e-9)
        n = props.Normal()
        P = s.Value(u, v)
        q = (P.X() + d * n.X(), P.Y() + d * n.Y(), P.Z() + d * n.Z())
        # 1e-9 m: Newton's convergence on a point 1 cm off a smooth patch.
        assert abs(pd(q) - d) < 1e-9, (u, v, pd(q))


def _brute_check(surf, pts, label):
    pd = PatchDistance(surf)
    measured = [pd(p) for p in pts]
    brute = brute_min(surf, pts)
    for m, b, p in zip(measured, brute, pts):
        # The grid minimum is an upper bound of the true distance; the measure may only be
        # smaller (or equal up to 1e-9 m of convergence). Larger means a missed minimum.
        assert m <= b + 1e-9, f"{label}: measured {m} > grid {b} at {p}"


@check("measure never exceeds a 300x300 brute-force grid (folding OCCT surface, Gunnerus)")
def _():
    c = {k.name: k for k in cases.gunnerus(DATA)}["gunnerus_st"]
    s = fitters.occt_interpolate(c.sections, "chord")
    rng = random.Random(2)
    pts = rng.sample(c.offsets(), 15) + rng.sample(c.between, 15)
    pts.append((5.8, 0.0, 0.5))  # the offset that GeomAPI_ProjectPointOnSurf alone put at 0.22 m
    _brute_check(s, pts, "occt chord gunnerus_st")


@check("measure never exceeds a 300x300 brute-force grid (geomdl approx edges, free-form)")
def _():
    c = cases.freeform(4)
    s = fitters.geomdl_approx(c.sections, (7, 8))
    rng = random.Random(3)
    # edge offsets: their nearest point is often on the patch boundary
    edge = [
        p
        for k, sec in enumerate(c.sections)
        for i, p in enumerate(sec)
        if k in (0, len(c.sections) - 1) or i in (0, len(sec) - 1)
    ]
    _brute_check(s, rng.sample(edge, 15) + rng.sample(c.between, 15), "geomdl approx freeform")


@check("measure never exceeds a brute-force grid (ThruSections, Series 60)")
def _():
    c = cases.series60(DATA)[1]
    s = fitters.occt_thrusections(c.sections)
    rng = random.Random(4)
    _brute_check(s, rng.sample(c.between, 20), "thrusections s60")


@check("compare.py end to end with a stand-in hullskin (fake_hullskin.py = geomdl)")
def _():
    import json

    import compare

    fake = f"{sys.executable} {os.path.join(HERE, 'fake_hullskin.py')}"
    with tempfile.TemporaryDirectory() as d:
        js = os.path.join(d, "r.json")
        argv = ["--hullskin", fake, "--cases", "cargo116_st", "--data", DATA, "--inputs", d]
        argv += ["--work", d, "--out-md", os.path.join(d, "r.md"), "--out-json", js]
        import contextlib
        import io

        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            assert compare.main(argv) == 0
        res = json.load(open(js))["cases"][0]
    rows = {r["method"]: r for r in res["rows"]}
    assert not [r for r in res["rows"] if "error" in r], res["rows"]
    v = {x["floor"]: x for x in res["verdicts"]}
    assert v["interp passes through every offset"]["holds"] is True
    # the stand-in IS geomdl, so every approx floor is a tie and must hold
    approx = [x for k, x in v.items() if k.startswith("approx ")]
    assert len(approx) == 2 and all(x["holds"] for x in approx), approx
    # compare.py names the row after its --param (default centripetal,chord); the stand-in
    # fits with geomdl's one flag, centripetal both ways, as the peer row does.
    ours = next(r for name, r in rows.items() if name.startswith("hullskin interp ("))
    peer = rows["geomdl interpolate_surface (centripetal)"]
    assert ours["between"] == peer["between"], (ours["between"], peer["between"])
    # IGES written in metres by OCCT with ~10 significant digits: 1e-6 m on a 116 m ship
    for r in res["rows"]:
        if r["family"] == "hullskin":
            assert r["iges_check"]["unit"]["metres_per_unit"] == 1.0
            assert r["iges_check"]["max_deviation_from_json"] < 1e-6, r["iges_check"]


def main():
    failed = [(n, e) for n, e in RESULTS if e]
    for n, e in RESULTS:
        print(("ok   " if not e else "FAIL ") + n)
        if e:
            print(e)
    print(f"{len(RESULTS) - len(failed)} passed, {len(failed)} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
