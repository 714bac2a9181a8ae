#!/usr/bin/env python3
"""Write the 116.6 m coastal cargo ship as a hullskin sections CSV (metres), keel to deck.

Usage: python3 testdata/gen_cargo116.py ../shared/data/coastal_cargo_116m/offsets_long.csv > testdata/cargo116_offsets.csv

Source: shared/data/coastal_cargo_116m/offsets_long.csv (see its PROVENANCE.md): stations 0
(AP) .. 20 (FP) every 5.40 m, x from the AP; waterline half-breadths every 1 m from 1 to 8 m,
buttock heights at 1, 3, 5, 7 m off the centreline, the keel (bottom line) height on the
centreline and the main-deck edge. Each station becomes one section whose points are, in order
of height z (ties by half-breadth y): the keel point (y = 0), the waterline points, the buttock
points and the main-deck edge. Left out:
  - raised-deck, bulwark and centreline-deck points (above the hull's side, not on it);
  - buttock points above the main-deck edge (7 m at stations 0 and 19, 3 m and 5 m at 20),
    and buttock points that contradict the waterlines: in the order of (z, y) a buttock point is
    kept only if its y lies between the half-breadths of its neighbours among the other points
    (keel, waterlines, deck edge). The provenance notes that the two sets disagree at stations
    1-3; this rule drops 3 m and 7 m at station 1, 5 m at station 2 and 7 m at station 3.
    The points left out are listed on stderr.
Station 0 (the counter, hull only above z = 5.85 m) is kept: its points are consistent.
"""
import csv
import sys
from collections import defaultdict


def fmt(v: float) -> str:
    r = repr(float(v))
    return "0" if r in ("0.0", "-0.0") else r


def sections(path: str):
    pts = defaultdict(list)  # station -> [(kind, y, z)]
    x_of = {}
    with open(path, newline="", encoding="utf-8") as f:
        for r in csv.DictReader(f):
            st = int(r["station"])
            x_of[st] = float(r["x_m_from_AP"])
            kind = r["point_type"]
            y, z = float(r["y_m_halfbreadth"]), float(r["z_m_above_baseline"])
            if kind in ("waterline_halfbreadth", "buttock_height", "main_deck_edge", "keel_point_on_centreline"):
                pts[st].append((kind, y, z))
    out = []
    for st in sorted(pts):
        deck = [p for p in pts[st] if p[0] == "main_deck_edge"]
        z_deck = deck[0][2] if deck else float("inf")
        frame = sorted((p for p in pts[st] if p[0] != "buttock_height" and p[2] <= z_deck), key=lambda p: (p[2], p[1]))
        kept = list(frame)
        for b in (p for p in pts[st] if p[0] == "buttock_height"):
            key = (b[2], b[1])
            below = [p for p in frame if (p[2], p[1]) < key]
            above = [p for p in frame if (p[2], p[1]) > key]
            if below and above and min(below[-1][1], above[0][1]) <= b[1] <= max(below[-1][1], above[0][1]):
                kept.append(b)
            else:
                print(f"station {st}: buttock point y={b[1]} z={b[2]} left out", file=sys.stderr)
        kept.sort(key=lambda p: (p[2], p[1]))
        out.append((st, x_of[st], [(y, z) for _, y, z in kept]))
    return out


def main(path: str) -> None:
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["section", "x", "y", "z"])
    for st, x, section in sections(path):
        for y, z in section:
            w.writerow([f"st{st}", fmt(x), fmt(y), fmt(z)])


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
