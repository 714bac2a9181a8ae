#!/usr/bin/env python3
"""Check an IGES or STEP file written by hullskin with a real CAD kernel (Open CASCADE, via OCP).

Usage: occt_check.py FILE.igs|FILE.stp EXPECTED.json

The format is taken from the extension (.igs/.iges: IGESControl_Reader, .stp/.step:
STEPControl_Reader). EXPECTED.json (written by crates/hull/tests/io/occt_iges.rs and exports.rs)
holds
  {"surface": <a hullskin-surface JSON document, see crates/hull/src/export/surface_json.rs>,
   "iges_units": {"flag": 6, "name": "M"},     # IGES: the global section's unit
   "units": "m" | "mm" | "ft" | "in",           # STEP (or IGES without "iges_units")
   "samples": [[u, v, x, y, z], ...],           # points of our own evaluator, in the file's units
   "curves": [{"degree": p, "knots": [...], "control_points": [[x, y, z], ...],
               "weights": [...], "samples": [[t, x, y, z], ...]}, ...],   # optional
   "reference": {"samples": [[u, v, x, y, z], ...], "tolerance": t},    # optional
   "envelope": {"lo": [x, y, z], "hi": [x, y, z], "allowance": [ax, ay, az], "grid": n}}
                                                # optional, in the file's units

The file is read twice:
  * "native": xstep.cascade.unit set to the file's own unit, so OCCT must not scale;
  * "default_mm": xstep.cascade.unit = MM (OCCT's default), so OCCT must scale every
    length by the file unit in millimetres (1000 for M, 1 for MM, 304.8 for FT, 25.4 for IN).
Each read must give exactly one face whose surface is a Geom_BSplineSurface with our
rational flag, degrees, pole counts, knots, parameter bounds, poles and weights, the face
bounded by the whole parameter rectangle, and S(u, v) equal to our samples within
1e-9 of the model size (the diagonal of the control-net box), scaled by the unit factor.
The file's unit must be the expected one (IGES: global section flag and name; STEP: the
length unit OCCT finds in the representation context). With "curves", the shape must also
hold exactly that many free edges (not bounding a face), in order, each a Geom_BSplineCurve
with our degree, pole count, knots, poles, weights and C(t) at the samples, within the same
tolerance. With "reference" (the rational surface a polynomial export approximates), OCCT's
S(u, v) must be within "tolerance" (a length in the file's units) of every reference point;
the largest distance is reported as reference_deviation. With "envelope" (the offsets' box
and how far past each face hullskin's validity check allows the surface), OCCT's S(u, v)
on an n x n grid over the face's parameter rectangle must stay within the box widened by
the allowance on every side; how far it goes past each face is reported as
envelope_excess (below lo, above hi, per coordinate; negative inside).

Prints a JSON summary on stdout; exit status 0 if every check passed, 1 on a mismatch,
2 if the inputs could not be read.
"""

import json
import math
import os
import sys

# Relative tolerance on points, poles and bounds: both sides evaluate the same rational
# B-spline in double precision, so they agree to ~1e-15; 1e-9 leaves room for OCCT's own
# arithmetic (unit scaling, knot normalisation) while any real error (a transposed net, a
# lost weight, a wrong range) is orders of magnitude larger.
REL_TOL = 1e-9

# Our unit symbol -> (IGES 5.3 units flag, STEP length unit name as OCCT reports it).
SYMBOLS = {"m": (6, "metre"), "mm": (2, "millimetre"), "ft": (4, "FOOT"), "in": (1, "INCH")}

# IGES 5.3 units flag -> (OCCT's xstep.cascade.unit name, millimetres per unit).
UNITS = {
    1: ("INCH", 25.4),
    2: ("MM", 1.0),
    4: ("FT", 304.8),
    5: ("MI", 1609344.0),
    6: ("M", 1000.0),
    7: ("KM", 1e6),
    8: ("MIL", 0.0254),
    9: ("UM", 0.001),
    10: ("CM", 10.0),
    11: ("UIN", 0.0000254),
}


class Checks:
    def __init__(self):
        self.items = []

    def add(self, name, ok, detail=None):
        self.items.append({"name": name, "ok": bool(ok), "detail": detail})
        return ok

    @property
    def ok(self):
        return all(c["ok"] for c in self.items)


def quiet_occt():
    """Silence OCCT's messenger (it prints to stdout, which carries our JSON)."""
    from OCP.Message import Message, Message_Gravity

    for printer in Message.DefaultMessenger_s().Printers():
        printer.SetTraceLevel(Message_Gravity.Message_Fail)


def file_format(path):
    """"step" for .stp/.step, else "iges"."""
    return "step" if os.path.splitext(path)[1].lower() in (".stp", ".step") else "iges"


def read_file(fmt, path, cascade_unit):
    """Read `path` with xstep.cascade.unit = cascade_unit; return (reader, shape, status)."""
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.Interface import Interface_Static

    if fmt == "step":
        from OCP.STEPControl import STEPControl_Controller, STEPControl_Reader

        STEPControl_Controller.Init_s()  # registers the xstep.* parameters
        reader_type = STEPControl_Reader
    else:
        from OCP.IGESControl import IGESControl_Controller, IGESControl_Reader

        IGESControl_Controller.Init_s()
        reader_type = IGESControl_Reader
    if not Interface_Static.SetCVal_s("xstep.cascade.unit", cascade_unit):
        raise RuntimeError(f"OCCT refused xstep.cascade.unit = {cascade_unit}")
    reader = reader_type()
    status = reader.ReadFile(path)
    if status != IFSelect_RetDone:
        return reader, None, str(status)
    reader.TransferRoots()
    return reader, reader.OneShape(), str(status)


def read_iges(path, cascade_unit):
    """Read an IGES file (see read_file)."""
    return read_file("iges", path, cascade_unit)


def step_length_units(reader):
    """The length unit names OCCT finds in a STEP file's representation contexts."""
    from OCP.collections import Sequence_TCollection_AsciiString as Names

    length, angle, solid = Names(), Names(), Names()
    reader.FileUnits(length, angle, solid)
    return [length.Value(k).ToCString() for k in range(1, length.Length() + 1)]


def faces(shape):
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    out = []
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():
        out.append(TopoDS.Face(explorer.Current()))
        explorer.Next()
    return out


def free_edges(shape):
    """Edges that bound no face, in the order of the shape."""
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    out = []
    explorer = TopExp_Explorer(shape, TopAbs_EDGE, TopAbs_FACE)
    while explorer.More():
        out.append(TopoDS.Edge(explorer.Current()))
        explorer.Next()
    return out


def rel_err(a, b, scale):
    return abs(a - b) / scale


def expected_units(expected, fmt):
    """(cascade unit name, mm per unit, IGES flag, IGES name, STEP name) of the expectation."""
    if "iges_units" in expected:
        flag = expected["iges_units"]["flag"]
        name = expected["iges_units"]["name"]
        step_name = next((n for f, n in SYMBOLS.values() if f == flag), None)
    else:
        flag, step_name = SYMBOLS[expected["units"]]
        name = UNITS[flag][0]
    cascade, mm = UNITS[flag]
    return cascade, mm, flag, name, step_name


def knot_sequence(seq):
    return [seq.Value(k) for k in range(1, seq.Length() + 1)]


def check_curves(checks, label, shape, factor, expected, size):
    """The free edges against expected["curves"]; returns the largest point error."""
    from OCP.BRep import BRep_Tool
    from OCP.Geom import Geom_BSplineCurve, Geom_TrimmedCurve

    curves = expected.get("curves") or []
    edges = free_edges(shape)
    if not checks.add(f"{label}: curve count", len(edges) == len(curves), f"OCCT {len(edges)}, ours {len(curves)}"):
        return None
    worst = 0.0
    compared = 0
    for k, (edge, ours) in enumerate(zip(edges, curves)):
        c = BRep_Tool.Curve_s(edge, 0.0, 0.0)
        if isinstance(c, Geom_TrimmedCurve):
            c = c.BasisCurve()
        if not checks.add(f"{label}: curve {k} is a B-spline", isinstance(c, Geom_BSplineCurve), type(c).__name__):
            continue
        p, knots, pts = ours["degree"], ours["knots"], ours["control_points"]
        weights = ours.get("weights") or [1.0] * len(pts)
        same_shape = c.Degree() == p and c.NbPoles() == len(pts)
        checks.add(f"{label}: curve {k} degree and poles", same_shape, f"OCCT {(c.Degree(), c.NbPoles())}")
        if not same_shape:
            continue
        span = knots[-1] - knots[0] or 1.0
        kk = knot_sequence(c.KnotSequence())
        ok = len(kk) == len(knots) and all(rel_err(a, b, span) <= REL_TOL for a, b in zip(kk, knots))
        checks.add(f"{label}: curve {k} knots", ok, None if ok else f"OCCT {kk}, ours {knots}")
        pole_err = weight_err = 0.0
        w0 = c.Weight(1)
        for i, ours_pt in enumerate(pts):
            pole = c.Pole(i + 1)
            for a, b in zip((pole.X(), pole.Y(), pole.Z()), ours_pt):
                pole_err = max(pole_err, rel_err(a, b * factor, size * factor))
            weight_err = max(weight_err, abs(c.Weight(i + 1) * weights[0] - weights[i] * w0))
        checks.add(f"{label}: curve {k} poles", pole_err <= REL_TOL, f"max error {pole_err:.3e} of size")
        checks.add(f"{label}: curve {k} weights", weight_err <= REL_TOL * weights[0] * w0, f"{weight_err:.3e}")
        for t, x, y, z in ours["samples"]:
            pt = c.Value(t)
            for a, b in zip((pt.X(), pt.Y(), pt.Z()), (x, y, z)):
                worst = max(worst, rel_err(a, b * factor, size * factor))
            compared += 1
    checks.add(
        f"{label}: curve points at {compared} samples",
        worst <= REL_TOL and compared > 0,
        f"max error {worst:.3e} of size {size}",
    )
    return worst


def check_read(checks, label, path, cascade_unit, factor, expected):
    """All checks of one read; `factor` = OCCT length / our length."""
    fmt = file_format(path)
    from OCP.BRep import BRep_Tool
    from OCP.BRepTools import BRepTools
    from OCP.Geom import Geom_BSplineSurface

    surf = expected["surface"]
    p, q = surf["degree"]
    nu, nv = surf["control_points_count"]
    knots_u, knots_v = surf["knots_u"], surf["knots_v"]
    points = surf["control_points"]
    weights = surf.get("weights") or [1.0] * (nu * nv)
    rational = any(w != weights[0] for w in weights)
    lo = [min(c[k] for c in points) for k in range(3)]
    hi = [max(c[k] for c in points) for k in range(3)]
    size = math.dist(lo, hi) or 1.0
    dom_u = (knots_u[p], knots_u[nu])
    dom_v = (knots_v[q], knots_v[nv])
    span = max(dom_u[1] - dom_u[0], dom_v[1] - dom_v[0])
    info = {"cascade_unit": cascade_unit, "expected_scale": factor}

    reader, shape, status = read_file(fmt, path, cascade_unit)
    if not checks.add(f"{label}: read", shape is not None, status):
        return info
    _, _, flag, name, step_name = expected_units(expected, fmt)
    if fmt == "step":
        names = step_length_units(reader)
        info["file_length_units"] = names
        checks.add(f"{label}: length unit", names == [step_name], f"OCCT {names}, ours {step_name!r}")
    else:
        gs = reader.IGESModel().GlobalSection()
        info["file_unit_flag"] = gs.UnitFlag()
        info["file_unit_name"] = gs.UnitName().ToCString()
        checks.add(
            f"{label}: global units",
            gs.UnitFlag() == flag and info["file_unit_name"] == name,
            f"flag {gs.UnitFlag()} name {info['file_unit_name']!r}",
        )
    if "curves" in expected:
        info["curves"] = len(expected["curves"])
        info["max_curve_point_error_rel"] = check_curves(checks, label, shape, factor, expected, size)
    fs = faces(shape)
    if not checks.add(f"{label}: exactly one face", len(fs) == 1, f"{len(fs)} faces"):
        return info
    face = fs[0]
    s = BRep_Tool.Surface_s(face)
    kind = s.DynamicType().Name()
    if not checks.add(f"{label}: Geom_BSplineSurface", isinstance(s, Geom_BSplineSurface), kind):
        return info
    occ_rational = s.IsURational() or s.IsVRational()
    checks.add(f"{label}: rational flag", occ_rational == rational, f"OCCT {occ_rational}, ours {rational}")
    checks.add(
        f"{label}: degrees", (s.UDegree(), s.VDegree()) == (p, q), f"OCCT {(s.UDegree(), s.VDegree())}, ours {(p, q)}"
    )
    checks.add(
        f"{label}: pole counts",
        (s.NbUPoles(), s.NbVPoles()) == (nu, nv),
        f"OCCT {(s.NbUPoles(), s.NbVPoles())}, ours {(nu, nv)}",
    )
    if (s.NbUPoles(), s.NbVPoles(), s.UDegree(), s.VDegree()) != (nu, nv, p, q):
        return info

    u1, u2, v1, v2 = s.Bounds()
    err = max(rel_err(a, b, span) for a, b in zip((u1, u2, v1, v2), dom_u + dom_v))
    checks.add(f"{label}: surface bounds", err <= REL_TOL, f"OCCT {[u1, u2, v1, v2]}, ours {list(dom_u + dom_v)}")
    fu1, fu2, fv1, fv2 = BRepTools.UVBounds_s(face)
    err = max(rel_err(a, b, span) for a, b in zip((fu1, fu2, fv1, fv2), dom_u + dom_v))
    checks.add(f"{label}: face bounds", err <= REL_TOL, f"OCCT {[fu1, fu2, fv1, fv2]}, ours {list(dom_u + dom_v)}")

    ku = [s.UKnotSequence().Value(k) for k in range(1, s.UKnotSequence().Length() + 1)]
    kv = [s.VKnotSequence().Value(k) for k in range(1, s.VKnotSequence().Length() + 1)]
    ok = len(ku) == len(knots_u) and len(kv) == len(knots_v)
    ok = ok and all(rel_err(a, b, span) <= REL_TOL for a, b in zip(ku + kv, knots_u + knots_v))
    checks.add(f"{label}: knot sequences", ok, None if ok else f"OCCT {ku} / {kv}, ours {knots_u} / {knots_v}")

    # Poles(i, j) with i along u: ours are u-major, index i * nv + j. Weights are compared up
    # to one common factor (a polynomial surface may come back with weights 1).
    pole_err = weight_err = 0.0
    w00 = s.Weight(1, 1)
    for i in range(nu):
        for j in range(nv):
            ours = points[i * nv + j]
            pole = s.Pole(i + 1, j + 1)
            for a, b in zip((pole.X(), pole.Y(), pole.Z()), ours):
                pole_err = max(pole_err, rel_err(a, b * factor, size * factor))
            weight_err = max(weight_err, abs(s.Weight(i + 1, j + 1) * weights[0] - weights[i * nv + j] * w00))
    info["max_pole_error_rel"] = pole_err
    checks.add(f"{label}: poles (scaled by {factor})", pole_err <= REL_TOL, f"max error {pole_err:.3e} of size")
    checks.add(f"{label}: weights", weight_err <= REL_TOL * weights[0] * w00, f"max error {weight_err:.3e}")

    point_err = 0.0
    for u, v, x, y, z in expected["samples"]:
        pt = s.Value(u, v)
        for a, b in zip((pt.X(), pt.Y(), pt.Z()), (x, y, z)):
            point_err = max(point_err, rel_err(a, b * factor, size * factor))
    info["samples"] = len(expected["samples"])
    info["max_point_error_rel"] = point_err
    checks.add(
        f"{label}: points at {len(expected['samples'])} samples (scaled by {factor})",
        point_err <= REL_TOL and len(expected["samples"]) > 0,
        f"max error {point_err:.3e} of size {size}",
    )
    # A second surface the file approximates (the rational original of a polynomial export):
    # OCCT's S(u, v) within the given tolerance (file units) of its points.
    reference = expected.get("reference")
    if reference:
        dev = 0.0
        for u, v, x, y, z in reference["samples"]:
            pt = s.Value(u, v)
            dev = max(dev, math.dist((pt.X(), pt.Y(), pt.Z()), (x * factor, y * factor, z * factor)) / factor)
        info["reference_deviation"] = dev
        checks.add(
            f"{label}: within {reference['tolerance']} of the reference at {len(reference['samples'])} points",
            dev <= reference["tolerance"] and len(reference["samples"]) > 0,
            f"max deviation {dev:.3e}",
        )
    # The offsets' envelope, seen by OCCT's own evaluator on a grid over the face.
    envelope = expected.get("envelope")
    if envelope:
        n = int(envelope["grid"])
        lo = [c * factor for c in envelope["lo"]]
        hi = [c * factor for c in envelope["hi"]]
        allow = [c * factor for c in envelope["allowance"]]
        least, most = [math.inf] * 3, [-math.inf] * 3
        for a in range(n + 1):
            u = fu1 + (fu2 - fu1) * a / n
            for b in range(n + 1):
                pt = s.Value(u, fv1 + (fv2 - fv1) * b / n)
                for k, c in enumerate((pt.X(), pt.Y(), pt.Z())):
                    least[k] = min(least[k], c)
                    most[k] = max(most[k], c)
        below = [(lo[k] - least[k]) / factor for k in range(3)]
        above = [(most[k] - hi[k]) / factor for k in range(3)]
        info["envelope_excess"] = {"below": below, "above": above, "grid": n}
        inside = all(below[k] <= allow[k] / factor and above[k] <= allow[k] / factor for k in range(3))
        checks.add(
            f"{label}: within the envelope at {(n + 1) ** 2} points",
            inside,
            f"past the faces below {below}, above {above}, allowed {[c / factor for c in allow]}",
        )
    # The scale OCCT applied, measured: the largest pole coordinate over ours.
    ours_max = max(abs(c) for pt in points for c in pt)
    occ_max = max(
        abs(c)
        for i in range(1, nu + 1)
        for j in range(1, nv + 1)
        for c in (s.Pole(i, j).X(), s.Pole(i, j).Y(), s.Pole(i, j).Z())
    )
    info["measured_scale"] = occ_max / ours_max if ours_max > 0 else None
    return info


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    iges_path, expected_path = argv[1], argv[2]
    try:
        with open(expected_path, encoding="utf-8") as f:
            expected = json.load(f)
        cascade_name, mm_per_unit, _, _, _ = expected_units(expected, file_format(iges_path))
    except (OSError, ValueError, KeyError) as e:
        print(json.dumps({"ok": False, "error": f"cannot read {expected_path}: {e!r}"}))
        return 2
    if not os.path.isfile(iges_path):
        print(json.dumps({"ok": False, "error": f"no such file {iges_path}"}))
        return 2

    import OCP

    # OCCT writes through C++ streams to fd 1; send fd 1 to stderr while it works so that
    # stdout carries only the JSON summary.
    sys.stdout.flush()
    saved_stdout = os.dup(1)
    os.dup2(2, 1)
    checks = Checks()
    try:
        quiet_occt()
        reads = {
            "native": check_read(checks, "native", iges_path, cascade_name, 1.0, expected),
            "default_mm": check_read(checks, "default_mm", iges_path, "MM", mm_per_unit, expected),
        }
    finally:
        sys.stdout.flush()
        os.dup2(saved_stdout, 1)
        os.close(saved_stdout)
    summary = {
        "file": iges_path,
        "format": file_format(iges_path),
        "ok": checks.ok,
        "ocp_version": getattr(OCP, "__version__", "unknown"),
        "tolerance_rel": REL_TOL,
        "reads": reads,
        "failed": [c for c in checks.items if not c["ok"]],
        "checks": checks.items,
    }
    print(json.dumps(summary, indent=1))
    return 0 if checks.ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
