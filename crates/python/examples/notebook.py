"""hullskin from Python, notebook style: read offsets, fit, print the error and the
hydrostatics, plot the sections and the curvature (matplotlib, Agg backend: PNG files).

    python crates/python/examples/notebook.py [OFFSETS] [--out DIR]

Without OFFSETS the Series 60 Cb 0.60 parent of testdata/ is used. Run by the Python tests
(crates/python/tests/test_example.py), so it keeps working.
"""

# %% Imports and arguments
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import hullskin  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[3]
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("offsets", nargs="?", default=str(ROOT / "testdata" / "series60_cb060_offsets.csv"))
parser.add_argument("--out", default="hullskin-out/notebook", help="directory of the PNG files")
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

# %% Read the offsets: sections as NumPy arrays (x forward, y half-breadth, z up)
offsets = hullskin.read_offsets(args.offsets)
print(offsets)
for note in offsets.notes:
    print("note:", note)
for warning in offsets.warnings:
    print("warning:", warning)

# %% Fit one surface (as `hullskin fit` does) and print its true error
fit = hullskin.fit(offsets)
e = fit.error
u = offsets.units
print(f"{fit.method}: max error {e['max']:.4g} {u}, RMS {e['rms']:.4g} {u} over {e['points']} offsets")
if e.get("held_out"):
    print(f"held out ({e['held_out']['folds']} folds): RMS {e['held_out']['rms']:.4g} {u}")
worst = max(e["per_section"], key=lambda s: s["max"])
print(f"worst section {worst['section']}: max {worst['max']:.4g} {u}")
print("validity:", "sound" if not fit.validity else [f["kind"] for f in fit.validity])
print("timings (s):", {k: round(v, 4) for k, v in fit.timings.items()})

# %% Hydrostatics at the depth of the offsets' highest waterline
surface = fit.surface
top = max(float(s[:, 2].max()) for s in offsets.sections)
table = surface.hydrostatics(draft=top)
row = table["rows"][0]
for key in ("draft", "vol", "displ", "lcb", "vcb", "aw", "lcf", "s", "cb", "cm", "cp", "cw", "kmt"):
    print(f"{key:>6} {row[key]:.6g}")

# %% Plot the sections: the offsets and the surface through them (a body plan)
fig, ax = plt.subplots(figsize=(7, 5))
ts = np.linspace(0.0, 1.0, 200)
for pts in offsets.sections:
    v = float(np.mean(surface.closest_points(pts)["v"]))
    curve = surface.evaluate(ts, v)
    side = 1.0 if pts[:, 0].mean() >= np.mean([s[:, 0].mean() for s in offsets.sections]) else -1.0
    ax.plot(side * curve[:, 1], curve[:, 2], "b-", lw=0.8)
    ax.plot(side * pts[:, 1], pts[:, 2], "k.", ms=3)
ax.set_aspect("equal")
ax.set_xlabel(f"half-breadth ({u}); fore body right, aft body left")
ax.set_ylabel(f"z ({u})")
ax.set_title(f"{fit.method}: max error {e['max']:.3g} {u}")
fig.savefig(out / "sections.png", dpi=120)

# %% Plot the curvature: Gaussian curvature over the parameter domain
uu, vv = np.meshgrid(np.linspace(0, 1, 120), np.linspace(0, 1, 240), indexing="ij")
k = surface.curvature(uu, vv)["gaussian"]
fig, ax = plt.subplots(figsize=(8, 4))
lim = np.nanpercentile(np.abs(k), 98)
im = ax.pcolormesh(vv, uu, k, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="auto")
fig.colorbar(im, ax=ax, label=f"Gaussian curvature (1/{u}²)")
ax.set_xlabel("v (along the hull)")
ax.set_ylabel("u (along the sections)")
fig.savefig(out / "curvature.png", dpi=120)
print(f"wrote {out / 'sections.png'} and {out / 'curvature.png'}")
