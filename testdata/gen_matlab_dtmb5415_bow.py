#!/usr/bin/env python3
"""Write the bow patch of the BSpline3D-MATLAB DTMB 5415 grids as a hullskin sections CSV, in the
axes of `matlab_dtmb5415_main.csv` (the same origin shift), so that the two fitted surfaces
together make the hull from the transom edge to the stem (hydrostatics tests).

Usage: python3 testdata/gen_matlab_dtmb5415_bow.py ../shared/data/bspline3d_matlab_offsets > testdata/matlab_dtmb5415_bow.csv

Source: DTMB5415_bow_offset_{x,y,z}.dat of shared/data/bspline3d_matlab_offsets/dtmb5415/ (MIT,
(c) 2025 Dr. Faisal Ayob; see its PROVENANCE.md), a 21 x 21 grid, entry (i, j) = point j of
curve i, keel to deck in the source. Read with `gen_matlab_offsets.py`'s own functions; every
number carried over exactly (decimal arithmetic), shifted by the main patch's origin shift
(x + 5.724 m, z + 0), so z < 0 on the sonar dome.

Curves 0 to 4 (stations at x = -0.824 .. -0.66 m in the source) lie inside the main patch, whose
last curve is the station x = -0.654 m (the two patches overlap there): they are left out, and
the bow starts at curve 5, which runs from x = -0.655 m at the keel to about -0.61 m at the deck,
next to the main patch's end (a sliver of at most a few hundredths of a metre between the two).
The transom patch (the transom face, about 0.02 % of the displaced volume) is not converted.
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gen_matlab_offsets import clean, dtmb5415_main, fmt, grid  # noqa: E402

FIRST_CURVE = 5


def main(root: str) -> None:
    _, x0, z0 = clean("dtmb5415_main", dtmb5415_main(Path(root)))
    curves = grid(Path(root) / "dtmb5415", "DTMB5415_bow_offset_{}.dat")
    sections, _, _ = clean("dtmb5415_bow", [(f"c{i}", c) for i, c in enumerate(curves) if i >= FIRST_CURVE])
    print("section,x,y,z")
    for label, s in sections:
        for x, y, z in s:
            print(f"{label},{fmt(x - x0)},{fmt(y)},{fmt(z - z0)}")
    n = sum(len(s) for _, s in sections)
    print(f"dtmb5415_bow: {len(sections)} sections, {n} points; x shifted by {fmt(-x0)}, z by {fmt(-z0)}", file=sys.stderr)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
