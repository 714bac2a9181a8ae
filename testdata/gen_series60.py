#!/usr/bin/env python3
"""Generate testdata/series60_cb060_offsets.csv, the built-in sample hull of hullskin.

Input: Todd's dimensionless Series 60 Cb 0.60 parent table (cb0p6.csv, see testdata/README.md).
Output: a dimensional offset table in hullskin's format, in metres:
  - header row: corner cell `z\\x`, then station positions x (from the AP, forward positive),
    in increasing x (AP first): x = (1 - station/20) * Lpp;
  - one row per waterline, z ascending: z = (z/T) * T;
  - cells: half-breadths y = cell * MaxBm[waterline] * B/2.
Lpp = 121.92 m, B = 16.26 m, T = 6.50 m (L/B 7.5, B/T 2.5). The known typo of the source
(station 0, WL 0.25 reads 10) is set to 0. Arithmetic is exact (decimal), so the file holds the
exact products of the published three-decimal figures; no rounding.

Usage: python3 testdata/gen_series60.py path/to/cb0p6.csv > testdata/series60_cb060_offsets.csv
"""
import csv
import sys
from decimal import Decimal

LPP = Decimal("121.92")
B = Decimal("16.26")
T = Decimal("6.50")


def fmt(d: Decimal) -> str:
    s = format(d.normalize(), "f")
    return "0" if s in ("-0", "0") else s


def main(path: str) -> None:
    with open(path, newline="") as f:
        rows = [[c.strip() for c in r] for r in csv.reader(f)]
    header, body = rows[0], rows[1:]
    wl = [Decimal(h) for h in header[1:] if h and h != "SAR"]  # z/T of each waterline column
    maxbm_row = next(r for r in body if r[0] == "MaxBm")
    maxbm = [Decimal(c) for c in maxbm_row[1 : 1 + len(wl)]]
    stations = []  # (station number, [fraction per waterline])
    for r in body:
        if r[0] == "MaxBm":
            continue
        cells = [Decimal(c) for c in r[1 : 1 + len(wl)]]
        stations.append((Decimal(r[0]), cells))
    # Known defect 1 of PROVENANCE.md: station 0 (FP), WL 0.25 reads 10; it is 0.
    for st, cells in stations:
        if st == 0 and cells[wl.index(Decimal("0.25"))] == 10:
            cells[wl.index(Decimal("0.25"))] = Decimal(0)
    stations.sort(key=lambda s: -s[0])  # AP (station 20, x = 0) first: x increasing
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(["z\\x"] + [fmt((1 - st / 20) * LPP) for st, _ in stations])
    for k, zt in enumerate(wl):
        out.writerow([fmt(zt * T)] + [fmt(cells[k] * maxbm[k] * B / 2) for _, cells in stations])


if __name__ == "__main__":
    main(sys.argv[1])
