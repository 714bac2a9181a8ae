"""Test cases for the peer comparison: offsets to fit and the points to measure between them.

Two kinds of case:

* ``exact``: offsets sampled from a closed-form surface S(a, b) at uneven stations a_i and
  waterlines b_j; the "between" points are S on a grid DENSITY times finer in both directions,
  without the offsets themselves (so they measure the fit where it was not told anything).
* ``holdout``: a real offset table with no exact surface. The fit gets every other waterline
  (or station), always keeping the first and the last so nothing is extrapolated; the "between"
  points are the offsets that were held out.

Every case is a list of sections (constant-station curves), each a list of points ordered keel
to deck; the sections are ordered along the length. u runs along a section, v across sections.
"""

from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass, field

Point = tuple[float, float, float]


@dataclass
class Case:
    name: str
    title: str
    kind: str  # "exact" | "holdout"
    sections: list[list[Point]]  # [section][point], u along a section, v across sections
    between: list[Point]  # exact points between offsets, or held-out offsets
    approx: list[tuple[int, int]]  # (NU, NV) control-point counts for the approx runs
    notes: list[str] = field(default_factory=list)

    @property
    def size(self) -> tuple[int, int]:
        """(points per section, number of sections) = (data count in u, data count in v)."""
        return len(self.sections[0]), len(self.sections)

    def offsets(self) -> list[Point]:
        return [p for sec in self.sections for p in sec]


# --------------------------------------------------------------------------------------------
# Sampling helpers


def cosine_spacing(n: int, lo: float, hi: float) -> list[float]:
    """n points on [lo, hi], dense at both ends: lo + (hi-lo)(1 - cos(pi k/(n-1)))/2."""
    return [lo + (hi - lo) * 0.5 * (1.0 - math.cos(math.pi * k / (n - 1))) for k in range(n)]


def half_cosine_spacing(n: int, lo: float, hi: float) -> list[float]:
    """n points on [lo, hi], dense at lo only: lo + (hi-lo)(1 - cos(pi/2 k/(n-1)))."""
    return [lo + (hi - lo) * (1.0 - math.cos(0.5 * math.pi * k / (n - 1))) for k in range(n)]


def refine(params: list[float], density: int) -> list[float]:
    """Insert density-1 equally spaced values between consecutive params (density=4 -> 4x)."""
    out = []
    for a, b in zip(params[:-1], params[1:]):
        out.extend(a + (b - a) * k / density for k in range(density))
    out.append(params[-1])
    return out


def approx_counts(nu: int, nv: int, degree: int = 3) -> list[tuple[int, int]]:
    """The two (NU, NV) settings of the approx runs for nu x nv data (u along a section):
    about 65 % / 45 % and 85 % / 62 % of the data counts (7x9 and 9x13 for 11 x 21 data),
    at least degree + 1 and at most the data count."""

    def clip(k, n):
        return max(degree + 1, min(n, k))

    return [
        (clip(round(0.65 * nu), nu), clip(round(0.45 * nv), nv)),
        (clip(round(0.85 * nu), nu), clip(round(0.62 * nv), nv)),
    ]


def exact_case(name, title, surf, a_params, b_params, density, notes) -> Case:
    """Offsets S(a_i, b_j); between = S on the density-times finer grid minus the offsets."""
    sections = [[surf(a, b) for b in b_params] for a in a_params]
    fa, fb = refine(a_params, density), refine(b_params, density)
    between = [
        surf(a, b)
        for i, a in enumerate(fa)
        for j, b in enumerate(fb)
        if not (i % density == 0 and j % density == 0)
    ]
    approx = approx_counts(len(b_params), len(a_params))
    return Case(name, title, "exact", sections, between, approx, list(notes))


# --------------------------------------------------------------------------------------------
# Exact surfaces


def wigley(density: int) -> Case:
    """Wigley hull y = B/2 (1 - (2x/L)^2)(1 - (d/T)^2), d = T - z the depth below the waterline.

    x in [-L/2, L/2], z in [0, T] measured up from the keel (z = 0 keel, z = T waterline);
    L = 100, B = 10, T = 6.25 m. 21 cosine-spaced stations, 11 waterlines dense near the keel.
    """
    L, B, T = 100.0, 10.0, 6.25

    def s(x, z):
        d = T - z
        return (x, B / 2 * (1 - (2 * x / L) ** 2) * (1 - (d / T) ** 2), z)

    xs = cosine_spacing(21, -L / 2, L / 2)
    zs = half_cosine_spacing(11, 0.0, T)
    return exact_case(
        "wigley",
        "Wigley hull, L 100 m, 21 stations x 11 waterlines (exact surface)",
        s,
        xs,
        zs,
        density,
        [
            "y = B/2 (1-(2x/L)^2)(1-((T-z)/T)^2), L=100, B=10, T=6.25 m, z up from the keel",
            "stations cosine-spaced (dense at bow and stern), waterlines "
            "z = T(1-cos(pi/2 k/10)) (dense at the keel)",
        ],
    )


def s60_like(density: int) -> Case:
    """Analytic Series-60-like hull with flat of keel, a sharp bilge amidships and fine ends.

    xi = 2x/L - 1 in [-1, 1], t = z/T in [0, 1]:
      y = B/2 f(xi) [w(xi) + (1 - w(xi)) (1 - (1 - t)^n(xi))]
      f = 1 - xi^4 (waterline ends), w = 0.6 (1 - xi^2)^3 (half-siding of the flat of keel),
      n = 2 + 10 (1 - xi^2)^2 (12 amidships: box section with a tight bilge; 2 at the ends: V).
    L = 121.92, B = 16.26, T = 6.5 m (the Series 60 Cb 0.60 particulars). The surface is a graph
    y(x, z); its z = 0 edge is the flat-of-keel boundary, as in a real offset table's baseline.
    """
    L, B, T = 121.92, 16.26, 6.5

    def s(x, z):
        xi = 2 * x / L - 1
        t = z / T
        f = 1 - xi**4
        w = 0.6 * (1 - xi * xi) ** 3
        n = 2 + 10 * (1 - xi * xi) ** 2
        return (x, B / 2 * f * (w + (1 - w) * (1 - (1 - t) ** n)), z)

    xs = cosine_spacing(21, 0.0, L)
    zs = half_cosine_spacing(11, 0.0, T)
    return exact_case(
        "s60like",
        "Series-60-like analytic hull (flat of keel, sharp bilge), 21 x 11 (exact surface)",
        s,
        xs,
        zs,
        density,
        [
            "y = B/2 f [w + (1-w)(1-(1-z/T)^n)], xi = 2x/L-1, f = 1-xi^4, "
            "w = 0.6(1-xi^2)^3, n = 2+10(1-xi^2)^2; L=121.92, B=16.26, T=6.5 m",
            "bilge amidships: y goes from 0.6 B/2 to 0.93 B/2 within z < 0.2 T",
        ],
    )


def freeform(density: int) -> Case:
    """Free-form surface: sin/cos bumps over a curved strip, 15 sections of 12 points.

    v (sections) s in [0, 1], u (along a section) t in [0, 1], both unevenly sampled:
      s_k = k/14 + 0.06 sin(2 pi k/14), t_j = j/11 - 0.05 sin(2 pi j/11).
    Strip centre line: an arc of radius R = 20 m over phi = -0.6 + 1.2 s; across it the strip
    runs W = 8 m along the arc's normal; height h = 1.2 sin(3 pi s) cos(1.3 pi t)
    + 0.5 sin(3 pi t) cos(pi s).
    """
    R, W = 20.0, 8.0

    def s(sv, tu):
        phi = -0.6 + 1.2 * sv
        cx, cy = R * math.sin(phi), R * (1 - math.cos(phi))
        nx, ny = -math.sin(phi), math.cos(phi)
        h = 1.2 * math.sin(3 * math.pi * sv) * math.cos(1.3 * math.pi * tu) + 0.5 * math.sin(
            3 * math.pi * tu
        ) * math.cos(math.pi * sv)
        return (cx + (tu - 0.5) * W * nx, cy + (tu - 0.5) * W * ny, h)

    ss = [k / 14 + 0.06 * math.sin(2 * math.pi * k / 14) for k in range(15)]
    ts = [j / 11 - 0.05 * math.sin(2 * math.pi * j / 11) for j in range(12)]
    return exact_case(
        "freeform",
        "Free-form bumps over a curved strip, 15 sections x 12 points (exact surface)",
        s,
        ss,
        ts,
        density,
        [
            "arc R=20 m, strip width 8 m, h = 1.2 sin(3 pi s) cos(1.3 pi t) "
            "+ 0.5 sin(3 pi t) cos(pi s)",
        ],
    )


# --------------------------------------------------------------------------------------------
# Real offset tables (hold-out)


def keep_index(i: int, n: int) -> bool:
    """Every other index, always keeping the first and the last (no extrapolation)."""
    return i % 2 == 0 or i == n - 1


def holdout_cases(base: str, title: str, grid: list[list[Point]], notes):
    """Two cases from a full grid [station][waterline]: hold out waterlines, hold out stations."""
    ns, nw = len(grid), len(grid[0])
    fit_wl = [[p for j, p in enumerate(sec) if keep_index(j, nw)] for sec in grid]
    out_wl = [p for sec in grid for j, p in enumerate(sec) if not keep_index(j, nw)]
    fit_st = [sec for i, sec in enumerate(grid) if keep_index(i, ns)]
    out_st = [p for i, sec in enumerate(grid) if not keep_index(i, ns) for p in sec]
    kw = sum(keep_index(j, nw) for j in range(nw))
    ks = sum(keep_index(i, ns) for i in range(ns))
    return [
        Case(
            f"{base}_wl",
            f"{title}: fit {kw} of {nw} waterlines x {ns} stations, measure the other "
            f"{nw - kw} waterlines",
            "holdout",
            fit_wl,
            out_wl,
            approx_counts(len(fit_wl[0]), len(fit_wl)),
            list(notes),
        ),
        Case(
            f"{base}_st",
            f"{title}: fit {ks} of {ns} stations x {nw} waterlines, measure the other "
            f"{ns - ks} stations",
            "holdout",
            fit_st,
            out_st,
            approx_counts(len(fit_st[0]), len(fit_st)),
            list(notes),
        ),
    ]


def series60(data_dir: str) -> list[Case]:
    """Series 60 Cb 0.60 parent (Todd 1963), dimensional: Lpp 121.92, B 16.26, T 6.5 m.

    y = cell * MaxBm[col] * B/2, x = (1 - station/20) L (from the AP), z = col * T.
    Station 0, WL 0.25 reads 10 in the source: set to 0 (see PROVENANCE.md).
    """
    L, B, T = 121.92, 16.26, 6.5
    path = os.path.join(data_dir, "series60", "cb0p6.csv")
    with open(path, newline="") as f:
        rows = [[c.strip() for c in r] for r in csv.reader(f)]
    cols = [float(c) for c in rows[0][1:9]]
    maxbm = next(r for r in rows if r[0] == "MaxBm")
    maxbm = [float(c) for c in maxbm[1:9]]
    stations = []
    for r in rows[1:]:
        if r[0] == "MaxBm":
            continue
        st = float(r[0])
        cells = [float(c) for c in r[1:9]]
        if st == 0.0 and cells[2] == 10.0:
            cells[2] = 0.0  # the known typo: station 0, WL 0.25
        stations.append((st, cells))
    stations.sort(key=lambda sc: -sc[0])  # increasing x: AP (station 20) first
    grid = [
        [((1 - st / 20) * L, cells[k] * maxbm[k] * B / 2, cols[k] * T) for k in range(8)]
        for st, cells in stations
    ]
    return holdout_cases(
        "s60cb060",
        "Series 60 Cb 0.60 (25 stations x 8 waterlines)",
        grid,
        [
            "/work/shared/data/series60/cb0p6.csv (Todd 1963), L=121.92, B=16.26, T=6.5 m; "
            "station 0 WL 0.25 typo 10 -> 0",
        ],
    )


def gunnerus(data_dir: str) -> list[Case]:
    """R/V Gunnerus (vessel.js table), block z = 0 .. 4.0 m (9 waterlines) x stations 0 .. 56.

    Aft of x = 16.8 m the table stops at the main deck (z = 4.0 m), and the stations beyond 56
    have the bulb with a gap above it (centreline points between bulb and stem): the block is
    the largest rectangle of the grid with data in every cell except the rising keel, whose
    nulls are set to 0 (on the centreline) as vessel.js does.
    """
    path = os.path.join(data_dir, "gunnerus", "gunnerus_offsets_long.csv")
    cells = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            si, wi = int(r["station_index"]), int(r["waterline_index"])
            y = r["halfbreadth_m"]
            cells[(si, wi)] = (
                float(r["x_m_from_aft_end"]),
                float(y) if y != "" else None,
                float(r["z_m_above_baseline"]),
            )
    grid = []
    for si in range(57):
        sec = []
        for wi in range(9):
            x, y, z = cells[(si, wi)]
            sec.append((x, 0.0 if y is None else y, z))
        grid.append(sec)
    return holdout_cases(
        "gunnerus",
        "R/V Gunnerus (57 stations x 9 waterlines, z <= 4 m)",
        grid,
        [
            "/work/shared/data/gunnerus/gunnerus_offsets_long.csv, stations 0-56 (x 0-32.2 m), "
            "waterlines 0-8 (z 0-4.0 m); null half-breadths below the hull set to 0 "
            "(centreline), as vessel.js does",
        ],
    )


def coastal_cargo(data_dir: str) -> list[Case]:
    """116 m coastal cargo ship: stations 1 .. 20 x waterlines 1 .. 8 m (8 per station).

    Station 0 has only 3 waterlines (counter stern above z = 5.85 m) and the table has no z = 0
    half-breadth (flat of bottom), so the regular block is stations 1-20 x WL 1000-8000 mm.
    Buttocks and deck lines are not used (they break the one-point-per-waterline layout).
    """
    path = os.path.join(data_dir, "coastal_cargo_116m", "offsets_long.csv")
    pts = {}
    with open(path, newline="", encoding="utf-8") as f:
        for r in csv.DictReader(f):
            if r["point_type"] != "waterline_halfbreadth":
                continue
            st, z = int(r["station"]), float(r["z_m_above_baseline"])
            pts[(st, round(z))] = (float(r["x_m_from_AP"]), float(r["y_m_halfbreadth"]), z)
    grid = [[pts[(st, wl)] for wl in range(1, 9)] for st in range(1, 21)]
    return holdout_cases(
        "cargo116",
        "116 m coastal cargo ship (20 stations x 8 waterlines)",
        grid,
        [
            "/work/shared/data/coastal_cargo_116m/offsets_long.csv, stations 1-20, "
            "waterlines 1-8 m (station 0 has only 3 waterlines; no z=0 half-breadths)",
        ],
    )


def all_cases(data_dir: str, density: int) -> list[Case]:
    cases = [wigley(density), s60_like(density), freeform(density)]
    for loader in (series60, gunnerus, coastal_cargo):
        cases.extend(loader(data_dir))
    return cases


# --------------------------------------------------------------------------------------------
# CSV I/O


def fmt(v: float) -> str:
    """Shortest round-trip decimal (repr), so the CSV holds exactly the doubles fitted."""
    r = repr(float(v))
    return "0" if r in ("0.0", "-0.0") else r


def write_sections_csv(path: str, sections: list[list[Point]]) -> None:
    """hullskin's sections CSV: header section,x,y,z; a section's points keel to deck."""
    with open(path, "w", newline="") as f:
        f.write("section,x,y,z\n")
        for k, sec in enumerate(sections):
            for x, y, z in sec:
                f.write(f"{k},{fmt(x)},{fmt(y)},{fmt(z)}\n")


def write_points_csv(path: str, points: list[Point]) -> None:
    with open(path, "w", newline="") as f:
        f.write("x,y,z\n")
        for x, y, z in points:
            f.write(f"{fmt(x)},{fmt(y)},{fmt(z)}\n")
