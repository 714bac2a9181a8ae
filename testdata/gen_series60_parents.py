#!/usr/bin/env python3
"""Generate the Series 60 parent hulls other than Cb 0.60 as hullskin offset tables (metres).

The conversion is gen_series60.py's (same layout, exact decimal arithmetic, no rounding of the
products); only the particulars change. Every parent gets Lpp = 121.92 m (the built-in Cb 0.60
sample's), its own L/B from Todd (1963) as listed in shared/data/series60/PROVENANCE.md
(7.25, 7.00, 6.75, 6.50 for Cb 0.65, 0.70, 0.75, 0.80) and B/T = 2.5; B and T are rounded to
the centimetre, as the Cb 0.60 sample's 16.26 m and 6.50 m are (121.92 / 7.5 = 16.256).

Usage: python3 testdata/gen_series60_parents.py CB path/to/cb0pN.csv > testdata/series60_cbNNN_offsets.csv
       e.g.  python3 testdata/gen_series60_parents.py 0.70 ../shared/data/series60/cb0p7.csv \
                 > testdata/series60_cb070_offsets.csv
"""
import os
import sys
from decimal import ROUND_HALF_EVEN, Decimal

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gen_series60  # noqa: E402  (the converter of the Cb 0.60 sample)

LPP = Decimal("121.92")
L_OVER_B = {"0.60": "7.50", "0.65": "7.25", "0.70": "7.00", "0.75": "6.75", "0.80": "6.50"}
B_OVER_T = Decimal("2.5")
CM = Decimal("0.01")


def particulars(cb: str) -> tuple[Decimal, Decimal, Decimal]:
    """(Lpp, B, T) in metres, B and T rounded to the centimetre."""
    b = (LPP / Decimal(L_OVER_B[cb])).quantize(CM, rounding=ROUND_HALF_EVEN)
    t = (b / B_OVER_T).quantize(CM, rounding=ROUND_HALF_EVEN)
    return LPP, b, t


def main(cb: str, path: str) -> None:
    if cb not in L_OVER_B:
        sys.exit(f"unknown parent Cb {cb!r} (expected one of {', '.join(L_OVER_B)})")
    gen_series60.LPP, gen_series60.B, gen_series60.T = particulars(cb)
    gen_series60.main(path)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
