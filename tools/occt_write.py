#!/usr/bin/env python3
"""Write B-spline surfaces with Open CASCADE (via OCP) as IGES and STEP, for hullskin's readers.

Usage: occt_write.py OUT_DIR

Builds two Geom_BSplineSurface in millimetres (OCCT's model unit):
  * "rational": degrees (3, 2), u knots 0 0 0 0 0.3 0.3 0.7 1 1 1 1 (a double knot), v knots
    -1 -1 -1 0.25 2 2 2, 7 x 4 poles, weights 0.6 to 1.8;
  * "polynomial": degrees (2, 3), u knots 0 0 0 0.4 0.65 1 1 1, v knots 0 0 0 0 0.5 1 1 1 1,
    5 x 5 poles, no weights;
every number a short decimal (OCCT's IGES writer prints 10 significant digits);
each as one face, written by IGESControl_Writer (faces mode: a trimmed surface, entity 144,
over the entity 128) and STEPControl_Writer (AsIs: an ADVANCED_FACE), with the file unit
millimetres and metres (IGESControl_Writer's unit argument; write.step.unit). Files are
OUT_DIR/<surface>_<unit>.igs and .stp.

Writes OUT_DIR/expected.json (stdout carries OCCT's transfer statistics), a JSON document:
  {"ocp_version": ..., "files": [{"file": "rational_mm.igs", "format": "iges" | "step",
    "unit": "mm" | "m", "surface": "rational" | "polynomial", "rational": bool,
    "degree": [p, q], "count": [nu, nv], "knots_u": [...], "knots_v": [...] (full vectors),
    "poles_mm": [[x, y, z], ...] (u-major: index i * nv + j), "weights": [...] (u-major)}]}
The poles are the model's, in millimetres, whatever the file's unit: a reader asked for
millimetres must give them back (OCCT scales to the file's unit on writing).
Exit status 0 when every file was written, 2 otherwise.
"""

import json
import os
import sys


def knots_full(distinct, mults):
    return [k for k, m in zip(distinct, mults) for _ in range(m)]


def definitions():
    """(name, p, q, distinct u knots, u mults, distinct v knots, v mults, poles, weights or None)."""
    rational = dict(
        p=3, q=2, ku=[0.0, 0.3, 0.7, 1.0], mu=[4, 2, 1, 4], kv=[-1.0, 0.25, 2.0], mv=[3, 1, 3]
    )
    polynomial = dict(p=2, q=3, ku=[0.0, 0.4, 0.65, 1.0], mu=[3, 1, 1, 3], kv=[0.0, 0.5, 1.0], mv=[4, 1, 4])
    out = []
    for name, d in (("rational", rational), ("polynomial", polynomial)):
        nu = sum(d["mu"]) - d["p"] - 1
        nv = sum(d["mv"]) - d["q"] - 1
        poles, weights = [], []
        for i in range(nu):
            for j in range(nv):
                a, b = i / (nu - 1), j / (nv - 1)
                beam = 8000.0 * (1.0 - (2.0 * a - 1.0) ** 4) + 10.0
                # Rounded to 0.001 mm (at most 9 significant digits): OCCT's IGES writer prints
                # reals with 10, so the file then holds these numbers exactly.
                xyz = [120000.0 * a, beam * (0.3 + 0.7 * b) + 1.5 * i, 6500.0 * b - 200.0 * a + 0.25 * i * j]
                poles.append([round(c, 3) for c in xyz])
                weights.append(round(0.6 + 1.2 * ((i * 7 + j * 3) % 11) / 10.0, 6))
        out.append((name, d, nu, nv, poles, weights if name == "rational" else None))
    return out


def surface(d, nu, nv, poles, weights):
    from OCP.Geom import Geom_BSplineSurface
    from OCP.gp import gp_Pnt
    # OCP 7.8+ names the NCollection arrays by element type (TColgp_Array2OfPnt and the like).
    from OCP.collections import Array1_double as TColStd_Array1OfReal
    from OCP.collections import Array1_int as TColStd_Array1OfInteger
    from OCP.collections import Array2_double as TColStd_Array2OfReal
    from OCP.collections import Array2_gp_Pnt as TColgp_Array2OfPnt

    def arr_real(xs):
        a = TColStd_Array1OfReal(1, len(xs))
        for k, x in enumerate(xs):
            a.SetValue(k + 1, x)
        return a

    def arr_int(xs):
        a = TColStd_Array1OfInteger(1, len(xs))
        for k, x in enumerate(xs):
            a.SetValue(k + 1, x)
        return a

    net = TColgp_Array2OfPnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            x, y, z = poles[i * nv + j]
            net.SetValue(i + 1, j + 1, gp_Pnt(x, y, z))
    args = [net]
    if weights is not None:
        w = TColStd_Array2OfReal(1, nu, 1, nv)
        for i in range(nu):
            for j in range(nv):
                w.SetValue(i + 1, j + 1, weights[i * nv + j])
        args.append(w)
    args += [arr_real(d["ku"]), arr_real(d["kv"]), arr_int(d["mu"]), arr_int(d["mv"]), d["p"], d["q"]]
    return Geom_BSplineSurface(*args)


def write_iges(face, path, unit):
    from OCP.IGESControl import IGESControl_Controller, IGESControl_Writer

    IGESControl_Controller.Init_s()
    w = IGESControl_Writer({"mm": "MM", "m": "M"}[unit], 0)  # 0: faces (BRep mode off)
    if not w.AddShape(face):
        raise RuntimeError(f"IGESControl_Writer refused the face for {path}")
    w.ComputeModel()
    if not w.Write(path):
        raise RuntimeError(f"IGESControl_Writer could not write {path}")


def write_step(face, path, unit):
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Controller, STEPControl_Writer

    STEPControl_Controller.Init_s()
    Interface_Static.SetCVal_s("xstep.cascade.unit", "MM")
    if not Interface_Static.SetCVal_s("write.step.unit", {"mm": "MM", "m": "M"}[unit]):
        raise RuntimeError("OCCT refused write.step.unit")
    w = STEPControl_Writer()
    if w.Transfer(face, STEPControl_AsIs) != IFSelect_RetDone:
        raise RuntimeError(f"STEPControl_Writer refused the face for {path}")
    if w.Write(path) != IFSelect_RetDone:
        raise RuntimeError(f"STEPControl_Writer could not write {path}")


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out_dir = sys.argv[1]
    os.makedirs(out_dir, exist_ok=True)
    import OCP
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace

    files = []
    for name, d, nu, nv, poles, weights in definitions():
        s = surface(d, nu, nv, poles, weights)
        face = BRepBuilderAPI_MakeFace(s, 1e-6).Face()
        for unit in ("mm", "m"):
            for fmt, ext, write in (("iges", "igs", write_iges), ("step", "stp", write_step)):
                file = f"{name}_{unit}.{ext}"
                write(face, os.path.join(out_dir, file), unit)
                files.append(
                    {
                        "file": file,
                        "format": fmt,
                        "unit": unit,
                        "surface": name,
                        "rational": weights is not None,
                        "degree": [d["p"], d["q"]],
                        "count": [nu, nv],
                        "knots_u": knots_full(d["ku"], d["mu"]),
                        "knots_v": knots_full(d["kv"], d["mv"]),
                        "poles_mm": poles,
                        "weights": weights if weights is not None else [1.0] * (nu * nv),
                    }
                )
    doc = {"ocp_version": getattr(OCP, "__version__", "unknown"), "files": files}
    with open(os.path.join(out_dir, "expected.json"), "w") as f:
        json.dump(doc, f)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except Exception as e:  # noqa: BLE001 - reported, exit 2
        print(f"occt_write.py: {e}", file=sys.stderr)
        sys.exit(2)
