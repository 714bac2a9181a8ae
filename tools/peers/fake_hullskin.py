#!/usr/bin/env python3
"""A stand-in for `hullskin fit`, to test compare.py's plumbing without the Rust binary.

  python fake_hullskin.py fit INPUT -o DIR --method interp|approx [--ctrl NU,NV]
                              [--degree P,Q] [--param centripetal|chord]

Fits with geomdl (interpolate_surface / approximate_surface) and writes DIR/surface.json in
hullskin's format, DIR/surface.igs (OCCT's IGES writer, unit metres) and DIR/report.json.
It is NOT a peer and never appears in results; selftest.py uses it.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import sys


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("cmd", choices=["fit"])
    ap.add_argument("input")
    ap.add_argument("-o", dest="out", required=True)
    ap.add_argument("--method", choices=["interp", "approx"], required=True)
    ap.add_argument("--ctrl")
    ap.add_argument("--degree", default="3,3")
    ap.add_argument("--param", default="centripetal")
    a = ap.parse_args(argv)
    from geomdl import fitting

    secs: dict[int, list] = {}
    with open(a.input, newline="") as f:
        for r in csv.DictReader(f):
            secs.setdefault(int(r["section"]), []).append(
                [float(r["x"]), float(r["y"]), float(r["z"])]
            )
    sections = [secs[k] for k in sorted(secs)]
    nu, nv = len(sections[0]), len(sections)
    pts = [sections[j][i] for i in range(nu) for j in range(nv)]
    p, q = (int(v) for v in a.degree.split(","))
    # The parameterization along the sections (hullskin's --param U,V or one name for both).
    cen = a.param.split(",")[0] == "centripetal"
    if a.method == "interp":
        s = fitting.interpolate_surface(pts, nu, nv, p, q, centripetal=cen)
    else:
        # Without --ctrl, hullskin's default: three quarters of the offsets each way.
        ctrl = a.ctrl or f"{max(p + 1, (3 * nu + 3) // 4)},{max(q + 1, (3 * nv + 3) // 4)}"
        cu, cv = (int(v) for v in ctrl.split(","))
        s = fitting.approximate_surface(
            pts, nu, nv, p, q, ctrlpts_size_u=cu, ctrlpts_size_v=cv, centripetal=cen
        )
    os.makedirs(a.out, exist_ok=True)
    doc = {
        "format": "hullskin-surface",
        "version": 1,
        "units": "m",
        "degree": [s.degree_u, s.degree_v],
        "control_points_count": [s.ctrlpts_size_u, s.ctrlpts_size_v],
        "knots_u": list(s.knotvector_u),
        "knots_v": list(s.knotvector_v),
        "control_points": [list(c) for c in s.ctrlpts],
        "weights": [1.0] * (s.ctrlpts_size_u * s.ctrlpts_size_v),
    }
    with open(os.path.join(a.out, "surface.json"), "w") as f:
        json.dump(doc, f)
    with open(os.path.join(a.out, "report.json"), "w") as f:
        json.dump({"fake": True}, f)

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import fitters
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.IGESControl import IGESControl_Writer

    surf = fitters.bspline_surface(
        doc["degree"],
        doc["control_points_count"],
        doc["knots_u"],
        doc["knots_v"],
        doc["control_points"],
        doc["weights"],
    )
    face = BRepBuilderAPI_MakeFace(surf, 1e-7).Face()
    w = IGESControl_Writer("M", 0)
    gs = w.Model().GlobalSection()
    gs.SetCascadeUnit(1000.0)  # the shape's length unit, in mm: metres
    w.Model().SetGlobalSection(gs)
    w.AddShape(face)
    w.ComputeModel()
    if not w.Write(os.path.join(a.out, "surface.igs")):
        print("IGES write failed", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
