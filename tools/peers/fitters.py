"""The fitters being compared, each returning an OCCT Geom_BSplineSurface.

u runs along a section (keel to deck), v across the sections, for every method, so pole
counts read (nu x nv) the same way throughout.

* hullskin (ours): runs the binary, rebuilds the surface from DIR/surface.json (no unit
  question); DIR/surface.igs is read back with IGESControl_Reader as a cross-check.
* OCCT GeomAPI_PointsToBSplineSurface.Interpolate(Array2OfPnt, ParType): Points(i, j) with i
  along u, j along v. It is degree 3, C2, and the parameters of each direction are computed once
  for all rows together (AppDef multi-line: chord = sqrt(sum of squared distances over the
  rows)); ParType is ChordLength (its default), Centripetal or IsoParametric.
* OCCT ThruSections: every section through GeomAPI_Interpolate (cubic, its own chord-length
  parameters), BRepOffsetAPI_ThruSections(isSolid=False, ruled=False, pres3d=1e-6), smoothing
  off, CheckCompatibility on, then the one face's Geom_BSplineSurface.
* geomdl (NURBS-Python): fitting.approximate_surface / interpolate_surface with
  centripetal=True, points u-major (index = i * size_v + j, i along u).
"""

from __future__ import annotations

import json
import os
import shlex
import subprocess
import time

from OCP.Approx import Approx_ParametrizationType
from OCP.BRep import BRep_Tool
from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeWire
from OCP.BRepOffsetAPI import BRepOffsetAPI_ThruSections
from OCP.collections import Array1_double, Array1_int, Array2_double, Array2_gp_Pnt, HArray1_gp_Pnt
from OCP.Geom import Geom_BSplineSurface
from OCP.GeomAPI import GeomAPI_Interpolate, GeomAPI_PointsToBSplineSurface
from OCP.gp import gp_Pnt
from OCP.TopAbs import TopAbs_FACE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS

PARTYPES = {
    "chord": Approx_ParametrizationType.Approx_ChordLength,
    "centripetal": Approx_ParametrizationType.Approx_Centripetal,
    "uniform": Approx_ParametrizationType.Approx_IsoParametric,
}


class FitError(RuntimeError):
    pass


# --------------------------------------------------------------------------------------------
# Building an OCCT surface from plain arrays


def _compress(knots: list[float]) -> tuple[list[float], list[int]]:
    """Full knot vector -> distinct knots and multiplicities (exact equality: the knots are
    copied, not computed, so repeated values are bit-identical)."""
    ks, ms = [], []
    for k in knots:
        if ks and k == ks[-1]:
            ms[-1] += 1
        else:
            ks.append(float(k))
            ms.append(1)
    return ks, ms


def _arr1d(vals) -> Array1_double:
    a = Array1_double(1, len(vals))
    for i, v in enumerate(vals):
        a.SetValue(i + 1, float(v))
    return a


def _arr1i(vals) -> Array1_int:
    a = Array1_int(1, len(vals))
    for i, v in enumerate(vals):
        a.SetValue(i + 1, int(v))
    return a


def bspline_surface(degree, counts, knots_u, knots_v, ctrl, weights=None) -> Geom_BSplineSurface:
    """Geom_BSplineSurface from (p, q), (nu, nv), full knot vectors and u-major control points
    (index i * nv + j); rational when some weight differs from 1."""
    p, q = degree
    nu, nv = counts
    if len(ctrl) != nu * nv:
        raise FitError(f"{len(ctrl)} control points for {nu} x {nv}")
    if len(knots_u) != nu + p + 1 or len(knots_v) != nv + q + 1:
        raise FitError(
            f"knot vectors of {len(knots_u)}, {len(knots_v)} for {nu} x {nv} poles, degree {p},{q}"
        )
    poles = Array2_gp_Pnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            x, y, z = ctrl[i * nv + j]
            poles.SetValue(i + 1, j + 1, gp_Pnt(float(x), float(y), float(z)))
    ku, mu = _compress(knots_u)
    kv, mv = _compress(knots_v)
    if weights is not None and any(abs(w - 1.0) > 0 for w in weights):
        wa = Array2_double(1, nu, 1, nv)
        for i in range(nu):
            for j in range(nv):
                wa.SetValue(i + 1, j + 1, float(weights[i * nv + j]))
        return Geom_BSplineSurface(poles, wa, _arr1d(ku), _arr1d(kv), _arr1i(mu), _arr1i(mv), p, q)
    return Geom_BSplineSurface(poles, _arr1d(ku), _arr1d(kv), _arr1i(mu), _arr1i(mv), p, q)


def _grid(sections) -> Array2_gp_Pnt:
    """Points(i, j): i = point index along a section (u), j = section index (v)."""
    nu, nv = len(sections[0]), len(sections)
    a = Array2_gp_Pnt(1, nu, 1, nv)
    for j, sec in enumerate(sections):
        for i, (x, y, z) in enumerate(sec):
            a.SetValue(i + 1, j + 1, gp_Pnt(x, y, z))
    return a


# --------------------------------------------------------------------------------------------
# OCCT


def occt_interpolate(sections, partype: str = "chord") -> Geom_BSplineSurface:
    """GeomAPI_PointsToBSplineSurface.Interpolate(Points, ParType): degree 3, C2."""
    algo = GeomAPI_PointsToBSplineSurface()
    algo.Interpolate(_grid(sections), PARTYPES[partype])
    if not algo.IsDone():
        raise FitError("GeomAPI_PointsToBSplineSurface.Interpolate not done")
    return algo.Surface()


def occt_thrusections(sections, pres3d: float = 1e-6) -> Geom_BSplineSurface:
    """BRepOffsetAPI_ThruSections over cubic interpolated sections; returns the face's surface."""
    algo = BRepOffsetAPI_ThruSections(False, False, pres3d)
    algo.SetSmoothing(False)
    algo.CheckCompatibility(True)
    for sec in sections:
        h = HArray1_gp_Pnt(1, len(sec))
        for i, (x, y, z) in enumerate(sec):
            h.SetValue(i + 1, gp_Pnt(x, y, z))
        interp = GeomAPI_Interpolate(h, False, 1e-9)
        interp.Perform()
        if not interp.IsDone():
            raise FitError("GeomAPI_Interpolate failed on a section")
        edge = BRepBuilderAPI_MakeEdge(interp.Curve()).Edge()
        algo.AddWire(BRepBuilderAPI_MakeWire(edge).Wire())
    algo.Build()
    if not algo.IsDone():
        raise FitError("BRepOffsetAPI_ThruSections not done")
    faces = []
    ex = TopExp_Explorer(algo.Shape(), TopAbs_FACE)
    while ex.More():
        faces.append(TopoDS.Face(ex.Current()))
        ex.Next()
    if len(faces) != 1:
        raise FitError(f"ThruSections made {len(faces)} faces, expected 1")
    surf = BRep_Tool.Surface_s(faces[0])
    if not isinstance(surf, Geom_BSplineSurface):
        raise FitError(f"ThruSections face is a {type(surf).__name__}, not a B-spline surface")
    return surf


# --------------------------------------------------------------------------------------------
# geomdl (NURBS-Python)


def _geomdl_points(sections):
    """u-major list: index i * size_v + j, i along a section (u), j the section (v)."""
    nu, nv = len(sections[0]), len(sections)
    return [list(sections[j][i]) for i in range(nu) for j in range(nv)], nu, nv


def _from_geomdl(s) -> Geom_BSplineSurface:
    nu, nv = s.ctrlpts_size_u, s.ctrlpts_size_v
    return bspline_surface(
        (s.degree_u, s.degree_v), (nu, nv), s.knotvector_u, s.knotvector_v, s.ctrlpts, None
    )


def geomdl_approx(sections, ctrl, degree=(3, 3), centripetal=True) -> Geom_BSplineSurface:
    """fitting.approximate_surface(points, size_u, size_v, degree_u, degree_v,
    ctrlpts_size_u=NU, ctrlpts_size_v=NV, centripetal=...) (The NURBS Book A9.7 variant)."""
    from geomdl import fitting

    pts, nu, nv = _geomdl_points(sections)
    s = fitting.approximate_surface(
        pts,
        nu,
        nv,
        degree[0],
        degree[1],
        ctrlpts_size_u=ctrl[0],
        ctrlpts_size_v=ctrl[1],
        centripetal=centripetal,
    )
    return _from_geomdl(s)


def geomdl_interp(sections, degree=(3, 3), centripetal=True) -> Geom_BSplineSurface:
    """fitting.interpolate_surface(points, size_u, size_v, degree_u, degree_v, centripetal=...)."""
    from geomdl import fitting

    pts, nu, nv = _geomdl_points(sections)
    s = fitting.interpolate_surface(pts, nu, nv, degree[0], degree[1], centripetal=centripetal)
    return _from_geomdl(s)


# --------------------------------------------------------------------------------------------
# hullskin (ours)


def surface_from_json(path: str) -> tuple[Geom_BSplineSurface, dict]:
    with open(path) as f:
        d = json.load(f)
    if d.get("format") != "hullskin-surface":
        raise FitError(f"{path}: format {d.get('format')!r}, expected 'hullskin-surface'")
    if d.get("units", "m") != "m":
        raise FitError(f"{path}: units {d.get('units')!r}, expected 'm'")
    surf = bspline_surface(
        d["degree"],
        d["control_points_count"],
        d["knots_u"],
        d["knots_v"],
        d["control_points"],
        d.get("weights"),
    )
    return surf, d


# IGES global-section unit flag -> metres per file unit (IGES 5.3, section 2.2.4.3, field 14).
IGES_UNITS = {
    1: 0.0254,
    2: 0.001,
    4: 0.3048,
    5: 1609.344,
    6: 1.0,
    7: 1000.0,
    8: 0.0000254,
    9: 1e-6,
    10: 0.01,
    11: 0.0254e-6,
}


def _quiet_occt():
    """Drop OCCT's default console printer (the IGES loader's 'Total number of loaded
    entities' on stdout); failures are detected from return statuses, not from messages."""
    from OCP.Message import Message, Message_PrinterOStream

    Message.DefaultMessenger_s().RemovePrinters(Message_PrinterOStream.get_type_descriptor_s())


def surface_from_iges(path: str):
    """The first rational B-spline surface entity (128) of an IGES file, rebuilt in metres.

    The entity is read as written (IGESControl_Reader.ReadFile loads the model; no shape
    transfer), so OCCT's process-wide unit settings (xstep.cascade.unit), which do not reset
    between reads, play no part; the file's own unit flag gives the scale. Returns
    (surface, {"unit_flag", "unit_name", "metres_per_unit"}).
    """
    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.IGESControl import IGESControl_Reader
    from OCP.IGESGeom import IGESGeom_BSplineSurface

    _quiet_occt()
    reader = IGESControl_Reader()
    if reader.ReadFile(path) != IFSelect_ReturnStatus.IFSelect_RetDone:
        raise FitError(f"IGESControl_Reader could not read {path}")
    model = reader.IGESModel()
    gs = model.GlobalSection()
    flag = gs.UnitFlag()
    name = gs.UnitName().ToCString() if gs.UnitName() else ""
    if flag not in IGES_UNITS:
        raise FitError(f"{path}: IGES unit flag {flag} ({name!r}) not supported here")
    k = IGES_UNITS[flag]
    for i in range(1, model.NbEntities() + 1):
        e = model.Entity(i)
        if not isinstance(e, IGESGeom_BSplineSurface):
            continue
        p, q = e.DegreeU(), e.DegreeV()
        nu, nv = e.UpperIndexU() + 1, e.UpperIndexV() + 1
        ku = [e.KnotU(j) for j in range(-p, nu + 1)]
        kv = [e.KnotV(j) for j in range(-q, nv + 1)]
        ctrl, w = [], []
        for a in range(nu):
            for b in range(nv):
                c = e.TransformedPole(a, b)
                ctrl.append((c.X() * k, c.Y() * k, c.Z() * k))
                w.append(e.Weight(a, b))
        surf = bspline_surface((p, q), (nu, nv), ku, kv, ctrl, w)
        return surf, {"unit_flag": flag, "unit_name": name, "metres_per_unit": k}
    raise FitError(f"{path}: no B-spline surface entity (128)")


class Hullskin:
    """Runs `CMD fit INPUT -o DIR --method M [--ctrl NU,NV] --degree 3,3 --param P`."""

    def __init__(self, command: str, timeout: float = 600.0, param: str = "centripetal"):
        self.argv = shlex.split(command)
        self.timeout = timeout
        self.param = param

    def fit(self, csv_path: str, out_dir: str, method: str, ctrl=None, degree=(3, 3)):
        os.makedirs(out_dir, exist_ok=True)
        argv = self.argv + [
            "fit",
            csv_path,
            "-o",
            out_dir,
            "--method",
            method,
            "--degree",
            f"{degree[0]},{degree[1]}",
            "--param",
            self.param,
        ]
        if ctrl is not None:
            argv += ["--ctrl", f"{ctrl[0]},{ctrl[1]}"]
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(argv, capture_output=True, text=True, timeout=self.timeout)
        except (OSError, subprocess.TimeoutExpired) as e:
            raise FitError(f"{shlex.join(argv)}: {e}") from e
        elapsed = time.perf_counter() - t0
        if proc.returncode != 0:
            msg = (proc.stderr or proc.stdout).strip().splitlines()
            raise FitError(
                f"exit {proc.returncode}: {msg[-1] if msg else '(no output)'} [{shlex.join(argv)}]"
            )
        surf, meta = surface_from_json(os.path.join(out_dir, "surface.json"))
        return surf, meta, elapsed, argv
