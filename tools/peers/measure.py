"""Distance from points to a surface patch, measured the same way for every method.

d(P) = min over the closed parameter rectangle of |P - S(u, v)|, computed as the least of
  * Extrema_GenExtPS (gradient algorithm, Extrema_ExtFlag_MIN) on a dense sampling grid
    (SAMPLES_PER_SPAN samples per knot span in each direction, at least MIN_SAMPLES): every
    local minimum of the sampled distance is refined by Newton. GeomAPI_ProjectPointOnSurf's
    own grid is too coarse for surfaces that fold between offsets (OCCT Interpolate on the
    Gunnerus table: it put an offset that the surface interpolates 0.22 m away), and the
    tree algorithm (nearest sample only) missed the same point too;
  * GeomAPI_ProjectPointOnSurf (Extrema_ExtPS: all interior points where P - S is normal to
    the surface; LowerDistance is the least of them);
  * GeomAPI_ProjectPointOnCurve on the four boundary iso-curves, and the four corners,
    because the nearest point of a patch can lie on its boundary, where P - S need not be
    normal to the surface and the orthogonal projections find nothing.
selftest.py checks the result against brute-force grids.
"""

from __future__ import annotations

import math

from OCP.Extrema import Extrema_ExtAlgo, Extrema_ExtFlag, Extrema_GenExtPS
from OCP.GeomAdaptor import GeomAdaptor_Surface
from OCP.GeomAPI import GeomAPI_ProjectPointOnCurve, GeomAPI_ProjectPointOnSurf
from OCP.gp import gp_Pnt

SAMPLES_PER_SPAN = 6
MIN_SAMPLES = 48
MAX_SAMPLES = 800


def _samples(n_spans: int) -> int:
    return max(MIN_SAMPLES, min(MAX_SAMPLES, SAMPLES_PER_SPAN * n_spans + 1))


class PatchDistance:
    def __init__(self, surf):
        self.surf = surf
        u0, u1, v0, v1 = surf.Bounds()
        self.adaptor = GeomAdaptor_Surface(surf)
        self.ext = Extrema_GenExtPS()
        self.ext.SetFlag(Extrema_ExtFlag.Extrema_ExtFlag_MIN)
        self.ext.SetAlgo(Extrema_ExtAlgo.Extrema_ExtAlgo_Grad)
        self.nsu = _samples(surf.NbUKnots() - 1)
        self.nsv = _samples(surf.NbVKnots() - 1)
        self.ext.Initialize(self.adaptor, self.nsu, self.nsv, u0, u1, v0, v1, 1e-12, 1e-12)
        self.proj = GeomAPI_ProjectPointOnSurf()
        self.proj.Init(surf, u0, u1, v0, v1)
        self.edges = []
        for iso, a, b in (
            (surf.UIso(u0), v0, v1),
            (surf.UIso(u1), v0, v1),
            (surf.VIso(v0), u0, u1),
            (surf.VIso(v1), u0, u1),
        ):
            pc = GeomAPI_ProjectPointOnCurve()
            pc.Init(iso, a, b)
            self.edges.append(pc)
        self.corners = [surf.Value(u, v) for u in (u0, u1) for v in (v0, v1)]

    def __call__(self, p) -> float:
        gp = gp_Pnt(*p)
        best = min(gp.Distance(c) for c in self.corners)
        self.ext.Perform(gp)
        if self.ext.IsDone():
            for k in range(1, self.ext.NbExt() + 1):
                best = min(best, math.sqrt(self.ext.SquareDistance(k)))
        self.proj.Perform(gp)
        if self.proj.NbPoints() > 0:
            best = min(best, self.proj.LowerDistance())
        for pc in self.edges:
            pc.Perform(gp)
            if pc.NbPoints() > 0:
                best = min(best, pc.LowerDistance())
        return best


def stats(dists) -> dict:
    if not dists:
        return {"n": 0, "max": math.nan, "rms": math.nan}
    return {
        "n": len(dists),
        "max": max(dists),
        "rms": math.sqrt(sum(d * d for d in dists) / len(dists)),
    }


def measure(surf, offsets, between) -> dict:
    pd = PatchDistance(surf)
    d_off = [pd(p) for p in offsets]
    d_btw = [pd(p) for p in between]
    return {"offsets": stats(d_off), "between": stats(d_btw)}


def poles(surf) -> dict:
    return {
        "nu": surf.NbUPoles(),
        "nv": surf.NbVPoles(),
        "degree": [surf.UDegree(), surf.VDegree()],
        "rational": bool(surf.IsURational() or surf.IsVRational()),
    }


def max_deviation(a, b, n: int = 25) -> float:
    """max |a(u, v) - b(u, v)| over an n x n grid of each surface's own normalized domain."""
    au0, au1, av0, av1 = a.Bounds()
    bu0, bu1, bv0, bv1 = b.Bounds()
    worst = 0.0
    for i in range(n):
        s = i / (n - 1)
        for j in range(n):
            t = j / (n - 1)
            pa = a.Value(au0 + s * (au1 - au0), av0 + t * (av1 - av0))
            pb = b.Value(bu0 + s * (bu1 - bu0), bv0 + t * (bv1 - bv0))
            worst = max(worst, pa.Distance(pb))
    return worst
