#!/usr/bin/env python3
"""Measured comparison of hullskin's skinning against peer tools (see README.md here).

For every case (cases.py): write the sections CSV, fit it with
  hullskin interp, OCCT GeomAPI_PointsToBSplineSurface.Interpolate (chord length = its default,
  and centripetal), geomdl interpolate_surface, hullskin approx and geomdl approximate_surface
  at the same control-point counts, and OCCT ThruSections,
then measure every surface with the same distance (measure.py) at the offsets and between them
(exact surface points, or the held-out offsets), and print/write a Markdown table per case plus
the verdict on each floor of the issue.

  python tools/peers/compare.py --hullskin target/release/hullskin
  python tools/peers/compare.py --hullskin "cargo run --release -q -p hullskin --" --cases wigley
  python tools/peers/compare.py            # peers only (no hullskin rows, floors not judged)
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import shlex
import subprocess
import sys
import tempfile
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import cases as cases_mod  # noqa: E402
import fitters  # noqa: E402
from measure import max_deviation, measure, poles  # noqa: E402

# The interpolating surface must pass through every offset: max distance at the offsets below
# this (metres). The projection itself is converged far tighter (Extrema's Newton stops at
# ~1e-9 relative in parameter), so 1e-6 m = 1 micron on hulls of 8-120 m is a pass/fail line,
# not a noise floor.
PASS_THROUGH_TOL = 1e-6
# "No worse than": ours <= peer * (1 + REL_SLACK). The slack only absorbs the projection's own
# convergence (relative 1e-9 of the distances measured), it does not forgive real differences.
REL_SLACK = 1e-6


def versions(hullskin_cmd):
    v = {"python": sys.version.split()[0]}
    try:
        from importlib.metadata import version

        for pkg in ("cadquery-ocp-novtk", "cadquery-ocp", "geomdl"):
            try:
                v[pkg] = version(pkg)
            except Exception:
                pass
    except ImportError:
        pass
    if hullskin_cmd:
        try:
            out = subprocess.run(
                shlex.split(hullskin_cmd) + ["--version"],
                capture_output=True,
                text=True,
                timeout=600,
            )
            text = (out.stdout or out.stderr).strip().splitlines()
            v["hullskin"] = text[0] if out.returncode == 0 and text else "(--version failed)"
        except (OSError, subprocess.TimeoutExpired) as e:
            v["hullskin"] = f"unavailable: {e}"
    return v


def run_case(case, args, hullskin, inputs_dir, work_dir, log):
    """Fit the case with every method and measure; returns the JSON-able result."""
    csv_path = os.path.join(inputs_dir, f"{case.name}.csv")
    cases_mod.write_sections_csv(csv_path, case.sections)
    if case.kind == "holdout":
        cases_mod.write_points_csv(
            os.path.join(inputs_dir, f"{case.name}_holdout.csv"), case.between
        )
    offsets = case.offsets()
    nu_d, nv_d = case.size
    rows = []

    def add(method, family, role, fit_fn, ctrl=None):
        row = {"method": method, "family": family, "role": role, "ctrl": ctrl}
        t0 = time.perf_counter()
        try:
            out = fit_fn()
            surf, extra = out if isinstance(out, tuple) else (out, {})
            row["fit_seconds"] = round(time.perf_counter() - t0, 4)
            row.update(extra)
            row["poles"] = poles(surf)
            m = measure(surf, offsets, case.between)
            row.update(offsets=m["offsets"], between=m["between"])
        except Exception as e:  # a failing method is a result, not a crash of the comparison
            row["error"] = f"{type(e).__name__}: {e}"
            if args.verbose:
                traceback.print_exc()
        rows.append(row)
        log(f"  {case.name}: {method}: {summary(row)}")

    def ours(method, ctrl=None):
        def fit():
            tag = method if ctrl is None else f"{method}_{ctrl[0]}x{ctrl[1]}"
            out_dir = os.path.join(work_dir, case.name, tag)
            surf, _meta, secs, argv = hullskin.fit(csv_path, out_dir, method, ctrl)
            extra = {"command": shlex.join(argv), "run_seconds": round(secs, 4)}
            igs = os.path.join(out_dir, "surface.igs")
            if os.path.exists(igs):
                try:
                    isurf, unit = fitters.surface_from_iges(igs)
                    extra["iges_check"] = {
                        "unit": unit,
                        "poles": [isurf.NbUPoles(), isurf.NbVPoles()],
                        "max_deviation_from_json": max_deviation(surf, isurf),
                    }
                except Exception as e:
                    extra["iges_check"] = {"error": f"{type(e).__name__}: {e}"}
            return surf, extra

        return fit

    # Interpolation
    if hullskin:
        add(f"hullskin interp ({args.param})", "hullskin", "interp", ours("interp"))
    add(
        "OCCT PointsToBSplineSurface.Interpolate (chord length, default)",
        "occt",
        "interp",
        lambda: fitters.occt_interpolate(case.sections, "chord"),
    )
    add(
        "OCCT PointsToBSplineSurface.Interpolate (centripetal)",
        "occt",
        "interp",
        lambda: fitters.occt_interpolate(case.sections, "centripetal"),
    )
    add(
        "geomdl interpolate_surface (centripetal)",
        "geomdl",
        "interp",
        lambda: fitters.geomdl_interp(case.sections),
    )
    # The default fit (issue 11) against NURBS-Python's approximation with about half the
    # offsets' count each way.
    if hullskin:
        add(f"hullskin default fit ({args.param})", "hullskin", "default", ours("approx"))
    half = [max(4, math.ceil(nu_d / 2)), max(4, math.ceil(nv_d / 2))]
    add(
        f"geomdl approximate_surface {half[0]}x{half[1]} (centripetal), half the offsets' count",
        "geomdl",
        "half",
        lambda: fitters.geomdl_approx(case.sections, tuple(half)),
        half,
    )
    # Approximation at fixed counts
    for nu, nv in case.approx:
        ctrl = [nu, nv]
        if hullskin:
            add(
                f"hullskin approx {nu}x{nv} ({args.param})",
                "hullskin",
                "approx",
                ours("approx", ctrl),
                ctrl,
            )
        add(
            f"geomdl approximate_surface {nu}x{nv} (centripetal)",
            "geomdl",
            "approx",
            lambda nu=nu, nv=nv: fitters.geomdl_approx(case.sections, (nu, nv)),
            ctrl,
        )
    # Skinning by OCCT
    add(
        "OCCT ThruSections (GeomAPI_Interpolate sections)",
        "occt",
        "thrusections",
        lambda: fitters.occt_thrusections(case.sections),
    )
    return {
        "name": case.name,
        "title": case.title,
        "kind": case.kind,
        "data_size": {"nu": nu_d, "nv": nv_d},
        "n_offsets": len(offsets),
        "n_between": len(case.between),
        "input_csv": os.path.relpath(csv_path, ROOT),
        "notes": case.notes,
        "rows": rows,
    }


def summary(row):
    if "error" in row:
        return "FAILED " + row["error"]
    p = row["poles"]
    return (
        f"{p['nu']}x{p['nv']} poles, offsets max {row['offsets']['max']:.3g} rms "
        f"{row['offsets']['rms']:.3g}, between max {row['between']['max']:.3g} rms "
        f"{row['between']['rms']:.3g} m"
    )


# --------------------------------------------------------------------------------------------
# Floors


def _find(rows, family, role, ctrl=None, contains=None):
    for r in rows:
        if r["family"] == family and r["role"] == role and "error" not in r:
            if ctrl is not None and r.get("ctrl") != ctrl:
                continue
            if contains is not None and contains not in r["method"]:
                continue
            return r
    return None


def _le(a, b):
    return a <= b * (1 + REL_SLACK) + 1e-15


def judge(result):
    """The floors of the issue for one case; each verdict names the numbers it compared."""
    rows = result["rows"]
    verdicts = []
    ours_i = _find(rows, "hullskin", "interp")
    failed_ours = [r for r in rows if r["family"] == "hullskin" and "error" in r]
    for r in failed_ours:
        verdicts.append({"floor": f"{r['method']} runs", "holds": False, "detail": r["error"]})
    if ours_i:
        m = ours_i["offsets"]["max"]
        verdicts.append(
            {
                "floor": "interp passes through every offset",
                "holds": m <= PASS_THROUGH_TOL,
                "detail": f"max distance at offsets {m:.3g} m (limit {PASS_THROUGH_TOL:g} m)",
            }
        )
        for tag in ("chord length", "centripetal"):
            peer = _find(rows, "occt", "interp", contains=tag)
            if not peer:
                continue
            om, orms = ours_i["between"]["max"], ours_i["between"]["rms"]
            pm, prms = peer["between"]["max"], peer["between"]["rms"]
            verdicts.append(
                {
                    "floor": f"interp between offsets <= OCCT Interpolate ({tag})",
                    "holds": _le(om, pm) and _le(orms, prms),
                    "detail": f"between max {om * 1e3:.4g} vs {pm * 1e3:.4g} mm (x{om / pm:.3f}), "
                    f"RMS {orms * 1e3:.4g} vs {prms * 1e3:.4g} mm (x{orms / prms:.3f})",
                }
            )
    for r in rows:
        if r["family"] != "hullskin" or r["role"] != "approx" or "error" in r:
            continue
        peer = _find(rows, "geomdl", "approx", ctrl=r["ctrl"])
        if not peer:
            continue
        pairs = [
            ("between max", r["between"]["max"], peer["between"]["max"]),
            ("between RMS", r["between"]["rms"], peer["between"]["rms"]),
            ("offsets RMS", r["offsets"]["rms"], peer["offsets"]["rms"]),
        ]
        verdicts.append(
            {
                "floor": f"approx {r['ctrl'][0]}x{r['ctrl'][1]} <= geomdl approximate_surface",
                "holds": all(_le(a, b) for _, a, b in pairs),
                "detail": ", ".join(
                    f"{k} {a * 1e3:.4g} vs {b * 1e3:.4g} mm (x{a / b if b else math.inf:.3f})"
                    for k, a, b in pairs
                ),
            }
        )
    default, half = _find(rows, "hullskin", "default"), _find(rows, "geomdl", "half")
    if default and half:
        pairs = [
            ("between max", default["between"]["max"], half["between"]["max"]),
            ("between RMS", default["between"]["rms"], half["between"]["rms"]),
        ]
        dp = default["poles"]
        ip = ours_i["poles"] if ours_i else None
        fewer = ip is None or dp["nu"] * dp["nv"] <= ip["nu"] * ip["nv"]
        verdicts.append(
            {
                "floor": f"default fit <= geomdl approximate_surface {half['ctrl'][0]}x{half['ctrl'][1]} "
                "(half the offsets' count), with no more poles than interp",
                "holds": all(_le(a, b) for _, a, b in pairs) and fewer,
                "detail": ", ".join(
                    f"{k} {a * 1e3:.4g} vs {b * 1e3:.4g} mm (x{a / b if b else math.inf:.3f})"
                    for k, a, b in pairs
                )
                + f"; poles {dp['nu']}x{dp['nv']}"
                + (f" vs interp {ip['nu']}x{ip['nv']}" if ip else ""),
            }
        )
    ts = _find(rows, "occt", "thrusections")
    if ts:
        p = ts["poles"]
        ref = ours_i or _find(rows, "occt", "interp")
        rp = ref["poles"] if ref else None
        ratio = (p["nu"] * p["nv"]) / (rp["nu"] * rp["nv"]) if rp else math.nan
        detail = (
            f"{p['nu']}x{p['nv']} poles, degree {p['degree'][0]},{p['degree'][1]} "
            f"(x{ratio:.1f} the poles of {ref['method'] if ref else '?'}); between max "
            f"{ts['between']['max'] * 1e3:.4g} mm, RMS {ts['between']['rms'] * 1e3:.4g} mm"
        )
        if ours_i:
            detail += (
                f" vs ours max {ours_i['between']['max'] * 1e3:.4g} mm, RMS "
                f"{ours_i['between']['rms'] * 1e3:.4g} mm"
            )
        verdicts.append({"floor": "report: OCCT ThruSections", "holds": None, "detail": detail})
    return verdicts


# --------------------------------------------------------------------------------------------
# Output


def mm(v):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    return f"{v * 1000:.4g}"


def case_markdown(res):
    k = "exact surface" if res["kind"] == "exact" else "held-out offsets"
    lines = [
        f"### {res['name']}: {res['title']}",
        "",
        f"Input `{res['input_csv']}`: {res['data_size']['nv']} sections x "
        f"{res['data_size']['nu']} points ({res['n_offsets']} offsets); "
        f"between = {res['n_between']} points ({k}).",
    ]
    lines += [f"- {n}" for n in res["notes"]]
    lines += [
        "",
        "| method | poles nu x nv | degree | offsets max (mm) | offsets RMS (mm) "
        "| between max (mm) | between RMS (mm) | fit s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in res["rows"]:
        if "error" in r:
            lines.append(f"| {r['method']} | failed: {r['error'][:200]} | | | | | | |")
            continue
        p = r["poles"]
        lines.append(
            f"| {r['method']} | {p['nu']} x {p['nv']} | {p['degree'][0]},{p['degree'][1]} "
            f"| {mm(r['offsets']['max'])} | {mm(r['offsets']['rms'])} "
            f"| {mm(r['between']['max'])} | {mm(r['between']['rms'])} | {r['fit_seconds']:.3g} |"
        )
    igs = [r for r in res["rows"] if "iges_check" in r]
    lines.append("")
    bad = [r for r in igs if "error" in r["iges_check"]]
    for r in bad:
        lines.append(f"- IGES read-back of {r['method']}: {r['iges_check']['error']}")
    good = [r["iges_check"] for r in igs if "error" not in r["iges_check"]]
    if good:
        worst = max(g["max_deviation_from_json"] for g in good)
        units = sorted({g["unit"]["unit_name"] or str(g["unit"]["unit_flag"]) for g in good})
        lines.append(
            f"- hullskin's surface.igs, entity 128 read with IGESControl_Reader ({len(good)} "
            f"runs, unit {', '.join(units)}): max deviation from surface.json {worst:.3g} m on "
            "a 25 x 25 parameter grid."
        )
    if res.get("verdicts"):
        lines += ["", "| floor | holds | numbers |", "|---|---|---|"]
        for v in res["verdicts"]:
            h = "report" if v["holds"] is None else ("yes" if v["holds"] else "**NO**")
            lines.append(f"| {v['floor']} | {h} | {v['detail']} |")
    lines.append("")
    return "\n".join(lines)


def overall_markdown(results, meta):
    lines = [
        "# hullskin vs peer tools: measured",
        "",
        f"Generated by `tools/peers/compare.py` on {meta['date']}; command: `{meta['argv']}`.",
        "Versions: "
        + ", ".join(v if v.startswith(k) else f"{k} {v}" for k, v in meta["versions"].items())
        + ".",
        "",
        "All surfaces are measured the same way: distance from each point to the closed patch "
        "(least of OCCT Extrema_GenExtPS on a dense sampling grid, GeomAPI_ProjectPointOnSurf, "
        "and the four boundary iso-curves and corners; see README.md). *offsets*: the points "
        "that were fitted; *between*: points of the exact "
        f"surface on a {meta['density']}x finer grid, offsets excluded (exact cases), or the "
        "held-out offsets (real tables: every other waterline or station held out, first and "
        "last kept). Distances in mm. u runs along a section (keel to deck), v across "
        "sections; poles are nu x nv.",
        "",
    ]
    all_v = [(r["name"], v) for r in results for v in r.get("verdicts", [])]
    judged = [(n, v) for n, v in all_v if v["holds"] is not None]
    if judged:
        lost = [(n, v) for n, v in judged if not v["holds"]]
        lines += [
            "## Floors",
            "",
            f"{len(judged) - len(lost)} of {len(judged)} judged floors hold.",
            "",
        ]
        if lost:
            lines += ["| case | floor | numbers |", "|---|---|---|"]
            lines += [f"| {n} | {v['floor']} | {v['detail']} |" for n, v in lost]
            lines.append("")
    elif not meta["hullskin"]:
        lines += ["No hullskin command given (--hullskin): peers only, floors not judged.", ""]
    lines.append("## Cases")
    lines.append("")
    for r in results:
        lines.append(case_markdown(r))
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        "--hullskin",
        help="command that runs hullskin, e.g. target/release/hullskin or "
        "'cargo run --release -q -p hullskin --' (omit: peers only)",
    )
    ap.add_argument("--cases", help="comma-separated case names (default: all)")
    ap.add_argument("--list", action="store_true", help="list the cases and exit")
    ap.add_argument("--data", default="/work/shared/data", help="shared data folder (real tables)")
    ap.add_argument(
        "--inputs",
        default=os.path.join(ROOT, "testdata", "peers"),
        help="where the case CSVs are written",
    )
    ap.add_argument("--work", help="folder for hullskin outputs (default: a new temp folder)")
    ap.add_argument("--out-md", default=os.path.join(HERE, "results.md"))
    ap.add_argument("--out-json", default=os.path.join(HERE, "results.json"))
    ap.add_argument("--density", type=int, default=4, help="between-grid refinement (exact cases)")
    ap.add_argument("--param", default="centripetal,chord", help="hullskin --param value (its default)")
    ap.add_argument("--timeout", type=float, default=900.0, help="seconds per hullskin run")
    ap.add_argument(
        "--strict", action="store_true", help="exit 1 when a floor does not hold (default: exit 0)"
    )
    ap.add_argument("-v", "--verbose", action="store_true")
    args = ap.parse_args(argv)

    all_cases = cases_mod.all_cases(args.data, args.density)
    if args.list:
        for c in all_cases:
            nu, nv = c.size
            print(f"{c.name:14s} {c.kind:8s} {nv:3d} sections x {nu:2d} points  {c.title}")
        return 0
    if args.cases:
        wanted = args.cases.split(",")
        unknown = set(wanted) - {c.name for c in all_cases}
        if unknown:
            ap.error(f"unknown case(s) {sorted(unknown)}; --list shows them")
        all_cases = [c for c in all_cases if c.name in wanted]
    os.makedirs(args.inputs, exist_ok=True)
    work = args.work or tempfile.mkdtemp(prefix="hullskin-peers-")
    hullskin = fitters.Hullskin(args.hullskin, args.timeout, args.param) if args.hullskin else None

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    meta = {
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "argv": "python tools/peers/compare.py "
        + shlex.join(sys.argv[1:] if argv is None else argv),
        "versions": versions(args.hullskin),
        "density": args.density,
        "hullskin": args.hullskin,
        "work": work,
        "pass_through_tol_m": PASS_THROUGH_TOL,
        "rel_slack": REL_SLACK,
    }
    results = []
    for case in all_cases:
        log(f"case {case.name}: {case.title}")
        res = run_case(case, args, hullskin, args.inputs, work, log)
        if hullskin:
            res["verdicts"] = judge(res)
        results.append(res)
        print(case_markdown(res))
    with open(args.out_json, "w") as f:
        json.dump({"meta": meta, "cases": results}, f, indent=1)
        f.write("\n")
    md = overall_markdown(results, meta)
    with open(args.out_md, "w") as f:
        f.write(md)
    log(f"wrote {args.out_md} and {args.out_json}; hullskin outputs in {work}")
    lost = [v for r in results for v in r.get("verdicts", []) if v["holds"] is False]
    return 1 if (lost and args.strict) else 0


if __name__ == "__main__":
    sys.exit(main())
