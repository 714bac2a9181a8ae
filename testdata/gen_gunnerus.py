#!/usr/bin/env python3
"""Write the R/V Gunnerus offsets as a hullskin offset table (metres).

Usage: python3 testdata/gen_gunnerus.py ../shared/data/gunnerus/gunnerus_offsets_long.csv > testdata/gunnerus_offsets.csv

Rows are waterlines (z above baseline), columns stations (x from the aft end), cells
half-breadths; cells null in the source stay empty. Stations with fewer than 4 cells (beyond
the stem) are left out so that every section carries a cubic.
"""
import csv
import sys
from collections import defaultdict

rows = list(csv.DictReader(open(sys.argv[1])))
xs = sorted({float(r["x_m_from_aft_end"]) for r in rows})
zs = sorted({float(r["z_m_above_baseline"]) for r in rows})
cell = {}
count = defaultdict(int)
for r in rows:
    if r["halfbreadth_m"] != "":
        x, z = float(r["x_m_from_aft_end"]), float(r["z_m_above_baseline"])
        cell[(x, z)] = r["halfbreadth_m"]
        count[x] += 1
keep = [x for x in xs if count[x] >= 4]
out = csv.writer(sys.stdout, lineterminator="\n")
out.writerow(["z\\x"] + [repr(x) for x in keep])
for z in zs:
    out.writerow([repr(z)] + [cell.get((x, z), "") for x in keep])
