#!/usr/bin/env python3
"""Write one hull of the BSpline3D-MATLAB offsets as a hullskin sections CSV (keel to deck).

Usage: python3 testdata/gen_matlab_offsets.py SET ../shared/data/bspline3d_matlab_offsets > testdata/matlab_SET.csv
       SET is one of: trawler, series60, dtmb5415_main, wpb, frigate, yacht

Source: shared/data/bspline3d_matlab_offsets/ (see its PROVENANCE.md; MIT, (c) 2025 Dr. Faisal
Ayob; the original sources of the hulls are not stated). Units as in the source (metres by their
magnitudes). Every number is carried over exactly (decimal arithmetic, no rounding); the only
change is a shift of origin: x = 0 at the set's aft-most point and z = 0 at its lowest point
(the baseline), both rounded to the millimetre, so that x runs forward from the aft end and z
up from the baseline (a point may lie up to 0.5 mm below or aft of 0). In every set
used, the source axes already are x forward, y half-breadth >= 0 (checked), z up.

Two kinds of source data:
  - 21 x 21 grids (`*_x.dat`, `*_y.dat`, `*_z.dat`, entry (i, j) = point j of curve i), resampled
    by the source, not raw offsets: curve i becomes section `c<i>`; its points are reversed
    where needed to run keel to deck. The curves are nearly planar stations amidships but not
    at the ends (the first and last curves of trawler and series60 are the stern and stem
    profiles, y = 0), so the sections are free-form.
  - station point clouds (N x 3, `x y z` per line): the points of one x form a section.

Per set (`i` curve, `j` point):
  trawler      TrawlerOffset_{x,y,z}.dat. Curve 0 the transom (aft), 20 the stem profile; points
               run deck to keel in the source, reversed.
  series60     Series60Offset_{x,y,z}.dat. Curve 0 the stern profile, 20 the stem profile;
               deck to keel in the source, reversed.
  dtmb5415_main  DTMB5415_main_offset_{x,y,z}.dat only: the hull from the transom edge
               (x = -5.72 m) to x = -0.65 m, keel to deck as in the source. The bow patch
               (stem and sonar dome; its curves overlap the main patch from x = -0.82 m and
               are not stations) and the transom patch (the transom face) are left out, so this
               is the main part, open at both ends, not the whole ship.
  wpb          wpb_offset_{bottom,mid,top}_{x,y,z}.dat joined station by station: curve i of
               the three patches lies at one x and the patches meet edge to edge (bottom's
               last point is mid's first, mid's last top's first, equal within 4 µm, checked
               within 10 µm), so each section is bottom, then mid and top without their first
               point (the repeat of the joint): 61 points keel to deck. Curves run bow to stern in the source;
               sections are written stern to bow.
  frigate      frigate_1Surface.dat. In the source each station lists buttock points, then
               waterline points, then the keel and deck points; a section is its points in
               order of (z, y). Stations with fewer than 4 points cannot carry a cubic and are
               left out (x = 2, the stem head: 2 points). Stations are written stern to bow.
  yacht        yatch_offset3.dat (the latest of the three variants). Points run keel to deck in
               the source; stations run bow to stern there and are written stern to bow. The
               first section (bow, x = 6.48) is the stem profile, y = 0.

Rules applied to every set, reported on stderr:
  - two consecutive points of a section that coincide (distance <= 1e-9 times the set's
    bounding-box diagonal, the reader's COINCIDENT_REL) are one point: the second is dropped;
  - a point with y < 0 is an error (none in these sets), so is a section whose z is not
    non-decreasing (a check that the keel-to-deck order is right; none in these sets), except
    at the profile curves with y = 0 everywhere.
Not converted: catamaran (a demi-hull offset from the centreplane with wet deck and roof: its
sections are U-shaped around the demi-hull's keel, both ends at deck level, not keel to deck) and
swath (closed pod and strut sections around an axis off the centreplane).
"""
import sys
from decimal import Decimal
from pathlib import Path

COINCIDENT_REL = Decimal("1e-9")
# The WPB patches meet within 4 µm (the source's rounding); a wider gap is a real mismatch.
JOINT_TOL = Decimal("1e-5")
# Origin shifts are rounded to this step (1 mm) so that the shifted figures keep the source's
# digits instead of carrying a round-off residue such as -1.6e-15.
SHIFT_STEP = Decimal("0.001")


def load_matrix(path: Path):
    return [[Decimal(t) for t in line.split()] for line in path.read_text().splitlines() if line.strip()]


def grid(folder: Path, pattern: str):
    """The curves of a 21 x 21 patch: list of curves, each a list of (x, y, z)."""
    xs, ys, zs = (load_matrix(folder / pattern.format(c)) for c in "xyz")
    return [list(zip(xs[i], ys[i], zs[i])) for i in range(len(xs))]


def clouds(path: Path):
    """Station point clouds: consecutive lines with equal x form one station, in file order."""
    stations = []
    for row in load_matrix(path):
        p = tuple(row)
        if stations and stations[-1][0][0] == p[0]:
            stations[-1].append(p)
        else:
            stations.append([p])
    return stations


def trawler(root: Path):
    return [(f"c{i}", c[::-1]) for i, c in enumerate(grid(root / "trawler", "TrawlerOffset_{}.dat"))]


def series60(root: Path):
    return [(f"c{i}", c[::-1]) for i, c in enumerate(grid(root / "series60", "Series60Offset_{}.dat"))]


def dtmb5415_main(root: Path):
    return [(f"c{i}", c) for i, c in enumerate(grid(root / "dtmb5415", "DTMB5415_main_offset_{}.dat"))]


def wpb(root: Path):
    parts = [grid(root / "wpb", f"wpb_offset_{p}_{{}}.dat") for p in ("bottom", "mid", "top")]
    out = []
    for i, (bottom, mid, top) in enumerate(zip(*parts)):
        gap = max(dist(bottom[-1], mid[0]), dist(mid[-1], top[0]))
        if gap > JOINT_TOL:
            sys.exit(f"wpb curve {i}: the patches are {fmt(gap)} apart at their joint")
        out.append((f"c{i}", bottom + mid[1:] + top[1:]))
    return out[::-1]


def frigate(root: Path):
    out = []
    for pts in clouds(root / "frigate" / "frigate_1Surface.dat"):
        x = pts[0][0]
        if len(pts) < 4:
            print(f"frigate: station x = {fmt(x)} left out ({len(pts)} points, fewer than 4)", file=sys.stderr)
            continue
        out.append((f"x{fmt(x)}", sorted(pts, key=lambda p: (p[2], p[1]))))
    return out[::-1]


def yacht(root: Path):
    return [(f"x{fmt(pts[0][0])}", pts) for pts in clouds(root / "yacht" / "yatch_offset3.dat")][::-1]


SETS = {f.__name__: f for f in (trawler, series60, dtmb5415_main, wpb, frigate, yacht)}


def fmt(v: Decimal) -> str:
    s = format(v, "f")
    if "." in s:
        s = s.rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def dist(a, b) -> Decimal:
    return sum((p - q) ** 2 for p, q in zip(a, b)).sqrt()


def clean(name: str, sections):
    pts = [p for _, s in sections for p in s]
    lo = [min(p[k] for p in pts) for k in range(3)]
    hi = [max(p[k] for p in pts) for k in range(3)]
    tol = COINCIDENT_REL * dist(lo, hi)
    out = []
    for label, s in sections:
        kept = [s[0]]
        for p in s[1:]:
            if dist(p, kept[-1]) <= tol:
                print(f"{name}: section {label}: repeated point {[fmt(c) for c in p]} dropped", file=sys.stderr)
            else:
                kept.append(p)
        if any(p[1] < 0 for p in kept):
            sys.exit(f"{name}: section {label}: negative half-breadth")
        profile = all(p[1] == 0 for p in kept)
        if not profile and any(b[2] < a[2] for a, b in zip(kept, kept[1:])):
            sys.exit(f"{name}: section {label}: z decreases, not keel to deck")
        out.append((label, kept))
    return out, lo[0].quantize(SHIFT_STEP), lo[2].quantize(SHIFT_STEP)


def main(name: str, root: str) -> None:
    if name not in SETS:
        sys.exit(f"unknown set {name!r}; one of: {', '.join(SETS)}")
    sections, x0, z0 = clean(name, SETS[name](Path(root)))
    print("section,x,y,z")
    for label, s in sections:
        for x, y, z in s:
            print(f"{label},{fmt(x - x0)},{fmt(y)},{fmt(z - z0)}")
    n = sum(len(s) for _, s in sections)
    print(f"{name}: {len(sections)} sections, {n} points; x shifted by {fmt(-x0)}, z by {fmt(-z0)}", file=sys.stderr)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
