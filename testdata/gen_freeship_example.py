#!/usr/bin/env python3
"""Write testdata/freeship_wigley_offsets.txt: a FREE!ship "Offsets as 3D points" export, by hand.

The layout is FREE!ship's own (FreeShipUnit.pas, TFreeEdit.File_ExportOffsets): a description
line per intersection ("Station 30.000", "Buttock 2.000", "Waterline 2.500": FloatToStrF(.., ffFixed,
7, 3)), "N segments." and "SEGMENT i" lines for intersections in more than one piece, then one
point a line: eight spaces, x y z each with 4 decimals right-aligned in 10 characters, one space
between, "    KNUCKLE" after a knuckle point; the stations first, then the buttocks, the waterlines,
a control curve.

The hull is the Wigley hull y = (B/2)(1 - (2 xi / L)^2)(1 - ((T - z)/T)^2), xi = x - L/2,
L = 100 m, B = 10 m, T = 6.25 m (x from the aft end, z up from the keel, z = T the waterline, as
testdata/wigley_offsets.csv), cut like a FREE!ship model would be:
5 stations (x = 10, 30, 50, 70, 90) with points every 0.625 m from the keel (y = 0 on the
centreline) to z = T, written deck to keel for stations 10 and 30 (FREE!ship gives no order); two
buttocks (y = 1, 2) and one waterline (z = 2.5) as curves every 5 m along x, the waterline in two
segments (aft and fore of midship); one control curve (not read). Every figure is the formula
rounded to 4 decimals as FREE!ship prints it.

Usage: python3 testdata/gen_freeship_example.py > testdata/freeship_wigley_offsets.txt
"""
import math

L, B, T = 100.0, 10.0, 6.25


def y(x, z):
    xi = 2 * (x - L / 2) / L
    return (B / 2) * (1 - xi * xi) * (1 - ((T - z) / T) ** 2)


def pt(x, yy, z, knuckle=False):
    s = "        " + " ".join(f"{v:10.4f}" for v in (x, yy, z))
    return s + ("    KNUCKLE" if knuckle else "")


out = []
for x in (10.0, 30.0, 50.0, 70.0, 90.0):
    out.append(f"Station {x:.3f}")
    zs = [k * 0.625 for k in range(11)]
    pts = [pt(x, y(x, z), z, knuckle=(k == 10)) for k, z in enumerate(zs)]
    if x < 40:
        pts.reverse()
    out.extend(pts)
for b in (1.0, 2.0):
    out.append(f"Buttock {b:.3f}")
    for k in range(21):
        x = 5.0 * k
        c = (B / 2) * (1 - (2 * (x - L / 2) / L) ** 2)
        if c > b:
            out.append(pt(x, b, T * (1 - math.sqrt(1 - b / c))))
out.append(f"Waterline {2.5:.3f}")
out.append("2 segments.")
for seg, ks in ((1, range(0, 11)), (2, range(10, 21))):
    out.append(f"SEGMENT {seg}")
    out.extend(pt(5.0 * k, y(5.0 * k, 2.5), 2.5) for k in ks)
out.append("CONTROLCURVE")
out.extend(pt(5.0 * k, 0.0, 0.0) for k in range(0, 21, 10))
print("\n".join(out))
