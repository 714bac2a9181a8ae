#!/usr/bin/env python3
"""Write the standard Wigley hull as a hullskin offset table (metres), exact from its formula.

Usage: python3 testdata/gen_wigley.py > testdata/wigley_offsets.csv

Formula (Wigley 1942; shared/data/wigley/PROVENANCE.md), x amidships, z at the waterline:

    y(x, z) = (B/2) (1 - (2x/L)^2) (1 - (z/T)^2),   -L/2 <= x <= L/2,  -T <= z <= 0

with the standard proportions L/B = 10, L/T = 16 at L = 100 m: B = 10 m, T = 6.25 m. Written in
hullskin's axes: x from the aft end (x = 0 .. L), z from the keel (baseline; z = T is the design
waterline, the top of the formula's hull). 21 stations every L/20 (5 m) by 11 waterlines every
T/10 (0.625 m), so 2x/L = (i - 10)/10 and z/T = (k - 10)/10 at station i, waterline k: every
half-breadth 5 (1 - a^2/100) (1 - b^2/100) is an exact decimal, written without rounding. The
end stations (x = 0 and L) and the keel row are 0: the stem and stern are vertical lines, the
keel a straight line. Exact properties for checks: Cb = 4/9, KB = 5T/8, Aw = (2/3) L B.
"""
from decimal import Decimal

L, B, T = Decimal(100), Decimal(10), Decimal("6.25")
STATIONS, WATERLINES = 21, 11


def fmt(v: Decimal) -> str:
    s = format(v, "f")
    if "." in s:
        s = s.rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def main() -> None:
    xs = [L * i / (STATIONS - 1) for i in range(STATIONS)]
    print(",".join(["z\\x"] + [fmt(x) for x in xs]))
    for k in range(WATERLINES):
        z = T * k / (WATERLINES - 1)
        zeta = (z - T) / T
        cells = [B / 2 * (1 - (2 * x / L - 1) ** 2) * (1 - zeta**2) for x in xs]
        print(",".join([fmt(z)] + [fmt(y) for y in cells]))


if __name__ == "__main__":
    main()
