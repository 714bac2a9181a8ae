"""Design studies: many fits mapped over a Dask cluster, tabulated with pandas.

A study is a list of variants, each a dict:

``name``
    the row's label (default: its index);
``offsets``
    a :class:`hullskin.Offsets`, a path (seen by the workers), or None for the built-in
    Series 60 Cb 0.60 parent;
``scale``
    optional ``(x, y, z)`` factors applied to the offsets (:meth:`hullskin.Offsets.scaled`):
    length, breadth and depth;
``fit``
    optional keyword arguments of :func:`hullskin.fit` (method, ctrl, seed, ...);
``draft``
    optional draft of the hydrostatics (default: ``draft_share`` of the offsets' depth).

:func:`run` fits every variant (serially, or on a ``dask.distributed`` client) and returns a
:class:`pandas.DataFrame`, one row per variant in the given order: particulars (L, B, T, L/B,
B/T), the method and parameterization of the surface written (the default fit's held-out
referee may take chord lengths for some variants), fit errors (max, RMS, held out), fairness
(thin-plate energy and Gaussian curvature range of the fitted surface), validity findings, and
hydrostatics at the draft. A variant whose fit fails is a row with its ``error`` message, never an exception.
Every figure comes from the library's deterministic computations, so a run on any cluster is
bit-identical to a serial run (timings are left out of the table).

The same code runs on any Dask cluster: a ``LocalCluster`` on one machine, SLURM through
``dask_jobqueue.SLURMCluster``, Kubernetes through ``dask_kubernetes.operator.KubeCluster``
(see crates/python/README.md). The workers need ``hullskin`` installed (the same version) and,
for path variants, the files.
"""

from __future__ import annotations

import math
from typing import Any, Dict, Iterable, List, Optional

import hullskin

# Columns of the table, in order (the hydrostatics' names are those of `hullskin hydrostatics`).
PARTICULARS = ["name", "source", "method", "parameterization", "lpp", "beam", "draft", "depth", "l_over_b", "b_over_t"]
FIT = ["ctrl_u", "ctrl_v", "max_error", "rms_error", "held_out_rms", "findings", "thin_plate", "gaussian_min",
       "gaussian_max"]
HYDROSTATICS = ["vol", "displ", "cb", "cm", "cp", "cw", "lcb", "vcb", "aw", "lcf", "s", "kmt", "kml"]
COLUMNS = PARTICULARS + FIT + HYDROSTATICS + ["error"]


def _offsets(variant: Dict[str, Any]) -> "hullskin.Offsets":
    o = variant.get("offsets")
    if o is None or isinstance(o, (str, bytes)) or hasattr(o, "__fspath__"):
        o = hullskin.read_offsets(o)
    scale = variant.get("scale")
    if scale is not None:
        o = o.scaled(*scale)
    return o


def fit_row(variant: Dict[str, Any], draft_share: float = 0.6) -> Dict[str, Any]:
    """One row of the table: the variant fitted, measured and its hydrostatics computed; on
    any error (bad offsets, a fit the kernel refuses, bad arguments) the row carries the
    message in ``error`` and NaN elsewhere."""
    row: Dict[str, Any] = {c: math.nan for c in COLUMNS}
    row.update(name=str(variant.get("name", "")), source="", method="", parameterization="", error="")
    try:
        o = _offsets(variant)
        row["source"] = o.source
        f = hullskin.fit(o, **variant.get("fit", {}))
        report = f.report
        row["method"] = report["method"]
        row["parameterization"] = report["parameterization"]
        zs = [float(z) for s in o.sections for z in s[:, 2]]
        ys = [float(y) for s in o.sections for y in s[:, 1]]
        xs = [float(x) for s in o.sections for x in s[:, 0]]
        depth = max(zs) - min(zs)
        draft = variant.get("draft", min(zs) + draft_share * depth)
        lpp = o.perpendiculars[1] - o.perpendiculars[0] if o.perpendiculars else max(xs) - min(xs)
        beam = 2.0 * max(ys)
        row.update(lpp=lpp, beam=beam, draft=draft, depth=depth, l_over_b=lpp / beam, b_over_t=beam / draft)
        e = f.error
        held = e.get("held_out") or {}
        row.update(ctrl_u=report["surface"]["control_points"][0], ctrl_v=report["surface"]["control_points"][1],
                   max_error=e["max"], rms_error=e["rms"], held_out_rms=held.get("rms", math.nan),
                   findings=len(f.validity))
        fairness = report["fairness"]
        row.update(thin_plate=fairness["thin_plate"], gaussian_min=fairness["gaussian"][0],
                   gaussian_max=fairness["gaussian"][1])
        h = f.surface.hydrostatics(draft=draft)["rows"][0]
        row.update({k: h[k] for k in HYDROSTATICS})
    except Exception as e:  # noqa: BLE001 — a failed fit is a row with its message
        row["error"] = f"{type(e).__name__}: {e}"
    return row


def run(variants: Iterable[Dict[str, Any]], client: Optional[Any] = None, draft_share: float = 0.6):
    """Fit every variant and tabulate: serially without ``client``, else on the Dask cluster of
    ``client`` (a ``dask.distributed.Client``), one task per variant. Returns a
    ``pandas.DataFrame`` with the columns of :data:`COLUMNS`, rows in the variants' order;
    on a cluster ``df.attrs["workers"]`` maps each worker's address to the rows it fitted."""
    import pandas as pd

    variants = [dict(v, name=v.get("name", i)) for i, v in enumerate(variants)]
    if client is None:
        rows: List[Dict[str, Any]] = [fit_row(v, draft_share) for v in variants]
        workers: Dict[str, int] = {}
    else:
        futures = client.map(fit_row, variants, draft_share=draft_share, pure=False)
        rows = client.gather(futures)
        who = client.who_has(futures)
        workers = {}
        for holders in who.values():
            for w in holders[:1]:
                workers[w] = workers.get(w, 0) + 1
    df = pd.DataFrame(rows, columns=COLUMNS)
    df.attrs["workers"] = workers
    return df


def series60_variants(l_over_b: Iterable[float], b_over_t: Iterable[float], **fit: Any) -> List[Dict[str, Any]]:
    """The Series 60 Cb 0.60 parent (L/B 7.5, B/T 2.5) transformed to each (L/B, B/T): breadth
    scaled for L/B, then depth for B/T at the parent's design draft, length kept."""
    parent = hullskin.read_offsets()
    lpp = parent.perpendiculars[1] - parent.perpendiculars[0]
    beam = 2.0 * max(float(s[:, 1].max()) for s in parent.sections)
    draft = 6.5  # the parent's design draft (the 1.0 waterline of the table)
    out = []
    for lb in l_over_b:
        for bt in b_over_t:
            sy = (lpp / lb) / beam
            sz = (beam * sy / bt) / draft
            out.append({"name": f"L/B {lb:g}, B/T {bt:g}", "offsets": parent, "scale": (1.0, sy, sz),
                        "draft": draft * sz, "fit": dict(fit)})
    return out
