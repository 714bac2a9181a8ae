#!/usr/bin/env python3
"""Writes the bad-input corpus of testdata/bad/ (issue 6): the files, manifest.csv and README.md.

Every file is small (the largest under 100 KiB) and made up; the corpus is committed, this
script only documents how each file was made and rewrites them all identically (deterministic:
no clock, a fixed random seed, gzip with mtime 0).

    python3 testdata/bad/gen.py

manifest.csv columns, read by crates/cli/tests/cli/bad_input.rs:

- file: the path under testdata/bad/;
- command: the subcommand run on it (fit, hydrostatics, export, report, digitize, slice);
- args: extra arguments, space-separated (usually none);
- exit: `fail` (exit code non-zero, not a panic) or `ok` for the few hostile but valid files
  that are accepted with a note (`says` is then a phrase of the note);
- at: the place the message must name right after the file name: `:LINE:COL`, `:LINE` (then
  any column or none), `:` (some line), or empty (no line: a binary file, a whole-file
  problem, a directory);
- says: a phrase the message must contain (what is wrong, or what was expected);
- why: what is wrong with the file (also the README line).

accepted/manifest.csv: file, clean (the clean file it must fit exactly like), why.
"""

import gzip
import io
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

# The README's sections CSV example (testdata/sections_example.csv): line 1 is the header,
# aft is on lines 2-5, mid on 6-9, fore on 10-13.
SECTIONS = [
    ("aft", 0, [(0, 0), (1.2, 0.3), (1.8, 1.0), (2.0, 2.0)]),
    ("mid", 5, [(0, 0), (2.0, 0.1), (2.5, 1.0), (2.6, 2.0)]),
    ("fore", 10, [(0, 0), (0.6, 0.5), (1.2, 1.2), (1.6, 2.0)]),
]


def example_rows():
    return [[name, str(x), str(y), str(z)] for name, x, pts in SECTIONS for y, z in pts]


def sections_csv(rows=None, header="section,x,y,z", nl="\n", sep=","):
    """The example as text; `rows` replaces the data rows (lists of strings)."""
    if rows is None:
        rows = example_rows()
    return header + nl + "".join(sep.join(r) + nl for r in rows)


# The README's offset table example (testdata/offsets_example.csv).
TABLE = """Z\\x,0,5,10,15
0,0.4,1.6,1.5,
0.5,1.2,2.3,2.2,0.3
1,1.6,2.5,2.45,0.8
1.5,1.8,2.6,2.55,1.2
2,1.9,2.65,2.6,1.5
"""

SERIES60 = """,0 ,0.25,0.5,0.75,1,SAR
0,0,0.1,0.2,0.3,0.4,0
5,0.5,0.7,0.8,0.9,1,0.5
10,0.6,0.9,1,1,1,1
15,0.5,0.7,0.8,0.9,1,0.5
20,0,0.1,0.2,0.3,0.4,0
MaxBm,0.9,0.95,1,1,1,
"""

LONG = "x,z,y\n" + "".join(f"{x},{z},{y}\n" for _, x, pts in SECTIONS for y, z in pts)

CLOUD = "".join(f"{x} {y} {z}\n" for _, x, pts in SECTIONS for y, z in pts)

FREESHIP = "".join(
    f"Station {x:.3f}\n" + "".join(f"        {x:10.4f} {y:10.4f} {z:10.4f}\n" for y, z in pts)
    for _, x, pts in SECTIONS
)

FREESHIP_CURVES = "0\n" + "\n".join(
    "".join(f"   {x} {y} {z}\n" for y, z in pts) for _, x, pts in SECTIONS
) + "EOF\n"

VESSEL_JS = """{"structure": {"hull": {
  "attributes": {"LOA": 10, "BOA": 4, "Depth": 2},
  "halfBreadths": {
    "waterlines": [0, 0.5, 1],
    "stations": [0, 0.5, 1],
    "table": [[0.1, 0.4, 0.1], [0.3, 0.6, 0.3], [0.4, 0.7, 0.4]]
  }
}}}
"""

SURFACE = """{
  "format": "hullskin-surface",
  "version": 1,
  "units": "m",
  "degree": [1, 1],
  "control_points_count": [2, 2],
  "knots_u": [0, 0, 1, 1],
  "knots_v": [0, 0, 1, 1],
  "control_points": [
    [0, 0, 0],
    [10, 0, 0],
    [0, 2, 2],
    [10, 2, 2]
  ],
  "weights": [1, 1, 1, 1]
}
"""

DXF_HEAD = "0\nSECTION\n2\nENTITIES\n"
DXF_LINE = "0\nLINE\n8\nST0\n10\n0.0\n20\n0.0\n30\n0.0\n11\n10.0\n21\n20.0\n31\n0.0\n"

SVG = """<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" width="200mm" height="150mm" viewBox="0 0 200 150">
  <path d="M 100 100 L 120 90 L 130 60"/>
  <path d="M 100 100 L 110 95 L 115 60"/>
</svg>
"""


def stl_binary(triangles, claimed=None, header=b"hullskin bad-input corpus"):
    out = bytearray(header.ljust(80, b" "))
    out += struct.pack("<I", len(triangles) if claimed is None else claimed)
    for tri in triangles:
        out += struct.pack("<3f", 0, 0, 0)
        for v in tri:
            out += struct.pack("<3f", *v)
        out += struct.pack("<H", 0)
    return bytes(out)


def stl_ascii(triangles):
    s = "solid bad\n"
    for tri in triangles:
        s += "  facet normal 0 0 0\n    outer loop\n"
        for v in tri:
            s += "      vertex {} {} {}\n".format(*v)
        s += "    endloop\n  endfacet\n"
    return s + "endsolid bad\n"


def box():
    """A closed box 10 x 4 x 2 (both sides of y = 0), 12 triangles."""
    xs, ys, zs = (0.0, 10.0), (-2.0, 2.0), (0.0, 2.0)
    c = [(xs[i], ys[j], zs[k]) for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, cc, d in quads:
        tris += [(c[a], c[b], c[cc]), (c[a], c[cc], c[d])]
    return tris


# The same box as OBJ quads.
OBJ_BOX = "v 0 -2 0\nv 10 -2 0\nv 10 2 0\nv 0 2 0\nv 0 -2 2\nv 10 -2 2\nv 10 2 2\nv 0 2 2\n" \
    "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n"
# The same box as VRML 2.0 (a line per statement; corner indices from 0).
WRL_BOX = "#VRML V2.0 utf8\n# the OBJ box\nShape {\n  geometry IndexedFaceSet {\n    coord Coordinate {\n" \
    "      point [\n" + "".join(f"        {l[2:]},\n" for l in OBJ_BOX.split("\n") if l.startswith("v ")) + \
    "      ]\n    }\n    coordIndex [\n" + \
    "".join("      " + ", ".join(str(int(i) - 1) for i in l[2:].split()) + ", -1,\n"
            for l in OBJ_BOX.split("\n") if l.startswith("f ")) + "    ]\n  }\n}\n"


def gz(data):
    buf = io.BytesIO()
    with gzip.GzipFile(fileobj=buf, mode="wb", mtime=0, filename="") as f:
        f.write(data)
    return buf.getvalue()


# (file, content, command, at, says, why)
BAD = []


def bad(name, content, command, at, says, why, args="", exit="fail"):
    assert not any("," in f for f in (name, command, at, says, args)), name  # manifest.csv fields
    BAD.append((name, content, command, args, exit, at, says, why))


def build():
    rows = example_rows()
    rnd = random.Random(6)

    # ----- sections CSV -----
    text = sections_csv()
    bad("sections_truncated_row.csv", text[: text.rindex(",")], "fit", ":13", "row has 3 fields",
        "the last row is cut after its y (file truncated mid-row): row 13 has 3 fields, 4 expected")
    r = example_rows()
    r[5][2] = '"2.0'
    bad("sections_unterminated_quote.csv", sections_csv(r), "fit", ":7:3", "no closing quote",
        "a quoted field opened and never closed (line 7, field 3)")
    r = example_rows()
    r[4][3] = '"0"0'
    bad("sections_text_after_quote.csv", sections_csv(r), "fit", ":6:4", "follows the closing quote",
        "text after a closing quote (line 6, field 4)")
    bad("sections_comma_decimal_comma.csv",
        sections_csv([[a, b, c.replace(".", ","), d.replace(".", ",")] for a, b, c, d in rows]),
        "fit", ":3", "decimal commas", "decimal commas in a comma-separated file: the numbers split into extra fields")
    bad("sections_mixed_separators.csv",
        "section;x;y;z\n" + "".join((";" if i < 5 else ",").join(x) + "\n" for i, x in enumerate(rows)),
        "fit", ":7", "separated by commas", "semicolons on lines 1-6, commas from line 7 on")
    r = example_rows()
    r[5][2] = "nan"
    bad("sections_nan.csv", sections_csv(r), "fit", ":7:3", "not a finite number", "`nan` as a half-breadth")
    r = example_rows()
    r[6][3] = "-inf"
    bad("sections_inf.csv", sections_csv(r), "fit", ":8:4", "not a finite number", "`-inf` as a height")
    r = example_rows()
    r[2][1] = "1e400"
    bad("sections_overflow.csv", sections_csv(r), "fit", ":4:2", "not a finite number",
        "`1e400` overflows an f64")
    bad("sections_huge.csv", sections_csv([[a, b + "e300", c + "e300", d + "e300"] for a, b, c, d in rows]),
        "fit", ":10", "model's size", "coordinates of 1e300 m: finite, but their squares overflow")
    bad("sections_tiny.csv", sections_csv([[a, b + "e-310", c + "e-310", d + "e-310"] for a, b, c, d in rows]),
        "fit", "", "model's size", "coordinates of 1e-310 m (subnormal): a hull smaller than any tolerance")
    r = example_rows()
    for row in r[8:]:
        row[1] = "5"
    bad("sections_duplicate_station.csv", sections_csv(r), "fit", ":10", "not forward of",
        "two sections at the same x = 5 (mid and fore)")
    r = example_rows()
    for row in r[4:8]:
        row[1] = "12"
    bad("sections_unordered_stations.csv", sections_csv(r), "fit", ":10", "not forward of",
        "sections at x = 0, 12, 10: out of order along the length")
    r = example_rows()
    r.append(["aft", "0", "2.2", "3.0"])
    bad("sections_label_returns.csv", sections_csv(r), "fit", ":14:1", "appears again",
        "section aft comes back after fore (rows not together)")
    r = example_rows()
    r[6][2:] = r[5][2:]
    bad("sections_repeated_point.csv", sections_csv(r), "fit", ":8", "repeats point",
        "a point typed twice (lines 7 and 8)")
    r = example_rows()
    for row in r[4:8]:
        row[2:] = ["1", "1"]
    bad("sections_zero_length_middle.csv", sections_csv(r), "fit", ":6", "collapses to one point",
        "the middle section collapses to one point (a zero-length section between two full ones)")
    r = example_rows()
    r[4:8] = [["mid", "5", y, z] for y, z in [("0", "0"), ("2.5", "1.5"), ("2.5", "0.5"), ("0.5", "2.0")]]
    bad("sections_self_intersecting.csv", sections_csv(r), "fit", ":9", "crosses itself",
        "the middle section crosses itself (its last segment cuts its first)")
    bad("sections_header_only.csv", "section,x,y,z\n", "fit", ":1", "no data rows", "a header and nothing else")
    bad("sections_one_section.csv", sections_csv(rows[:4]), "fit", "", "expected at least 2 sections",
        "one section only: nothing to skin across")
    bad("sections_too_few_points.csv", sections_csv(rows[:4] + rows[4:6] + rows[8:]), "fit", ":6",
        "expected at least 4 points", "the middle section has 2 points, a cubic needs 4")
    bad("sections_bad_header.csv", sections_csv(header="section,x,y"), "fit", ":1", "row has 3 fields",
        "the header names 3 columns, the rows have 4")
    r = example_rows()
    r[3][2] = "9" * 20000 + "x"
    bad("sections_huge_field.csv", sections_csv(r), "fit", ":5:3", "is not a number",
        "a 20001-character field (the message must not repeat it whole)")
    bad("sections_nul.csv", sections_csv().replace("mid,5,2.5", "mid,5,2\0.5"), "fit", ":8", "binary file",
        "a NUL byte inside line 8")
    bad("sections_latin1.csv", sections_csv().replace("fore", "f\xf8re").encode("latin-1"), "fit", ":10",
        "invalid UTF-8", "a Latin-1 label (byte 0xF8) on line 10: not UTF-8")
    utf16 = sections_csv(nl="\r\n", sep="\t", header="section\tx\ty\tz")
    bad("utf16le_bom.csv", b"\xff\xfe" + utf16.encode("utf-16-le"), "fit", ":1", "UTF-16",
        "UTF-16 LE with a BOM (a spreadsheet's \"Unicode text\")")
    bad("utf16be_bom.csv", b"\xfe\xff" + utf16.encode("utf-16-be"), "fit", ":1", "UTF-16",
        "UTF-16 BE with a BOM")
    bad("utf16le_no_bom.csv", utf16.encode("utf-16-le"), "fit", ":1", "UTF-16",
        "UTF-16 LE without a BOM (every other byte NUL)")
    bad("empty.csv", b"", "fit", "", "no data", "an empty file")
    bad("blank_and_comments.csv", "\n   \n# only a comment\n\t\n,,,\n", "fit", "", "no data",
        "only blank lines, a comment and an empty spreadsheet row")
    bad("binary_garbage.csv", bytes(rnd.randrange(256) for _ in range(4096)), "fit", ":", "binary",
        "4 KiB of random bytes")
    bad("png_named_csv.csv", b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x10\0\0\0\x10\x08\x02\0\0\0", "fit", ":1",
        "binary file", "a PNG image named .csv")
    bad("huge_line.csv", "z\\x," + ",".join(str(i) for i in range(1, 12000)) + "\n0," + "1," * 11998 + "1\n"
        + "1,abc\n", "fit", ":3:2", "is not a number",
        "an offset table 12000 stations wide (lines of 60 KiB), then a word in a cell")

    # ----- offset table -----
    bad("table_station_unordered.csv", TABLE.replace("Z\\x,0,5,10,15", "Z\\x,0,10,5,15"), "fit", ":1:4",
        "strictly increasing", "station positions 0, 10, 5, 15: not monotone")
    bad("table_duplicate_station.csv", TABLE.replace("Z\\x,0,5,10,15", "Z\\x,0,5,5,15"), "fit", ":1:4",
        "strictly increasing", "station 5 twice in the header")
    bad("table_waterline_unordered.csv", TABLE.replace("\n1,1.6", "\n0.25,1.6"), "fit", ":4:1",
        "strictly increasing", "waterline 0.25 after 0.5")
    bad("table_negative.csv", TABLE.replace("1.2,2.3", "-1.2,2.3"), "fit", ":3:2", "negative",
        "a negative half-breadth")
    bad("table_extra_cell.csv", TABLE.replace("2.55,1.2", "2.55,1.2,7"), "fit", ":5:6",
        "beyond the last station", "a cell right of the last station column")
    bad("table_no_stations.csv", "Z\\x\n0\n1\n", "fit", ":1", "no station columns",
        "a corner cell and waterlines, no stations")
    bad("table_empty_station.csv", "Z\\x,0,5,10,15\n0,0.4,1.6,1.5,\n1,1.2,2.3,2.2,\n2,1.6,2.5,2.45,\n",
        "fit", ":1:5", "no half-breadth", "station 15 has no cell at all")
    bad("table_truncated_number.csv", TABLE.replace("2.45", "2.4e"), "fit", ":4:4", "is not a number",
        "`2.4e`: a number cut after its exponent mark")
    bad("table_thousands_separator.csv", TABLE.replace(",", ";").replace("0;0.4;", "0;1.000,5;"), "fit", ":2:2",
        "is not a number", "`1.000,5` (a thousands point and a decimal comma) in a semicolon file")
    bad("table_comma_decimal_comma.csv", TABLE.replace("1.8,2.6", "1,8,2,6"), "fit", ":5",
        "decimal comma", "decimal commas in a comma-separated table: extra cells")
    bad("table_missing_header.csv", "\n".join(TABLE.split("\n")[1:]), "fit", ":1:1", "expected a header",
        "the header row is missing: the first row is data")

    # ----- Series 60 table -----
    bad("s60_negative_cell.csv", SERIES60.replace("10,0.6,0.9", "10,-0.6,0.9"), "fit", ":4:2", "negative",
        "a negative fraction of the maximum breadth")
    bad("s60_maxbm_text.csv", SERIES60.replace("MaxBm,0.9", "MaxBm,abc"), "fit", ":7:2", "not a number",
        "a word in the MaxBm row")
    bad("s60_station_beyond_ap.csv", SERIES60.replace("\n20,0,", "\n25,0,"), "fit", ":6:1", "station",
        "station 25: Todd's stations run 0 to 20")

    # ----- long CSV -----
    bad("long_nan.csv", LONG.replace("5,1.0,2.5", "5,1.0,NaN"), "fit", ":8:3", "not a finite number",
        "`NaN` half-breadth in a long CSV")
    bad("long_unknown_kind.csv", "x,z,y,kind\n0,0,0,waterline\n0,1,1,waterline\n5,1,2,spaceship\n", "fit", ":4:4",
        "spaceship", "an unknown point kind")
    bad("long_truncated.csv", LONG[: LONG.rindex("\n", 0, -1) + 3], "fit", ":13", "empty field",
        "a long CSV cut after the first field of its last row")

    # ----- JSON offset tables -----
    bad("json_truncated.json", VESSEL_JS[:150], "fit", ":", "EOF", "a vessel.js table cut after 150 bytes")
    bad("json_deep.json", '{"structure": ' + "[" * 20000 + "]" * 20000 + "}", "fit", ":1",
        "recursion", "20000 nested arrays (a stack-overflow attempt)")
    bad("json_wrong_type.json", VESSEL_JS.replace('"table": [[0.1, 0.4, 0.1]', '"table": ["abc", [0.1, 0.4, 0.1]'),
        "fit", ":", "expected", "a string where a row of half-breadths belongs")
    bad("json_huge_number.json", VESSEL_JS.replace('"LOA": 10', '"LOA": 1e999'), "fit", ":2",
        "number out of range", "`1e999`: out of range for an f64")
    bad("json_nan_literal.json", VESSEL_JS.replace("0.4, 0.1]", "NaN, 0.1]"), "fit", ":6", "expected value",
        "`NaN`, which JSON does not have")
    bad("openhull_string_value.json", '{"2": {"站号": 2.0, "船底线": 0.0, "1000WL": "wide"}}', "fit", ":",
        "1000WL", "an OpenHull half-breadth given as a string", args="--lpp 100")

    # ----- point clouds -----
    bad("cloud_nan.dat", CLOUD.replace("5 2.5 1.0", "5 nan 1.0"), "fit", ":7:2", "not a finite number",
        "a `nan` in a point cloud")
    bad("cloud_negative_y.dat", CLOUD.replace("5 2.5 1.0", "5 -2.5 1.0"), "fit", ":7:2", "negative",
        "a negative half-breadth in a point cloud")
    bad("cloud_ragged.dat", CLOUD.replace("5 2.5 1.0", "5 2.5"), "fit", ":7", "expected",
        "a point of 2 numbers among points of 3")
    bad("cloud_two_columns.dat", "".join(f"{y} {z}\n" for _, _, pts in SECTIONS for y, z in pts), "fit", ":",
        "expected", "`y z` points with no block header giving the station x")

    # ----- FREE!ship -----
    bad("freeship_short_point.txt", FREESHIP.replace("     5.0000     2.5000     1.0000", "     5.0000     2.5000"),
        "fit", ":9", "expected a point", "a FREE!ship point with 2 numbers")
    bad("freeship_segment_count.txt", FREESHIP.replace("Station 5.000\n", "Station 5.000\n4294967295 segments.\n"),
        "fit", ":", "segment", "a station claiming 4294967295 segments, none given")
    bad("freeship_curves_word.txt", FREESHIP_CURVES.replace("5 2.5 1.0", "5 2.5 one"), "fit", ":", "not a number",
        "a word in a FREE!ship curve text")

    # ----- surface JSON (hydrostatics, export) -----
    bad("surface_truncated.json", SURFACE[:200], "hydrostatics", ":", "EOF", "a surface JSON cut mid-array")
    bad("surface_deep.json", '{"format": "hullskin-surface", "knots_u": ' + "[" * 20000, "hydrostatics", ":1",
        "expected f64", "20000 nested arrays where the knots belong")
    bad("surface_bad_knots.json", SURFACE.replace('"knots_u": [0, 0, 1, 1]', '"knots_u": [0, 1, 0, 1]'),
        "export", "", "knots_u", "a decreasing knot vector")
    bad("surface_count_mismatch.json", SURFACE.replace('"control_points_count": [2, 2]',
                                                       '"control_points_count": [4000000000, 4000000000]'),
        "hydrostatics", "", "control_points_count", "a control-point count of 4e9 x 4e9 with 4 points given")
    bad("surface_huge_degree.json", SURFACE.replace('"degree": [1, 1]', '"degree": [4000000000, 1]'),
        "hydrostatics", "", "knots_u", "degree 4e9 with 4 knots")
    bad("surface_negative_weight.json", SURFACE.replace('"weights": [1, 1, 1, 1]', '"weights": [1, -1, 1, 1]'),
        "export", "", "weights", "a negative weight")
    bad("surface_nan_point.json", SURFACE.replace("[10, 0, 0]", "[10, NaN, 0]"), "hydrostatics", ":11",
        "expected value", "`NaN` in a control point (not JSON)")
    bad("surface_huge_point.json", SURFACE.replace("[10, 0, 0]", "[10, 1e308, 1e308]"), "hydrostatics", "",
        "overflows", "control points of 1e308: finite, but the volume overflows")
    bad("surface_wrong_units.json", SURFACE.replace('"units": "m"', '"units": "furlong"'), "hydrostatics", "",
        "units", "unknown units")
    bad("surface_string_number.json", SURFACE.replace('"version": 1', '"version": "1"'), "hydrostatics", ":3:16",
        "expected u32", "the version as a string")
    bad("surface_bom_truncated.json", "\ufeff" + SURFACE[:230], "report", ":", "EOF",
        "a surface JSON with a BOM, cut short, for a report")
    bad("report_offsets_inf.csv", sections_csv()[:-4] + "inf\n", "report", ":13:4", "not a finite number",
        "offsets with `inf` as the last height, for a report")
    bad("surface_wrong_format.json", SURFACE.replace("hullskin-surface", "rhino-surface"), "export", "",
        "hullskin-surface", "another program's JSON")

    # ----- meshes (fit slices them; slice reads them) -----
    bad("stl_claims_4g_triangles.stl", stl_binary(box()[:1], claimed=0xFFFFFFFF), "fit", "", "4294967295",
        "a binary STL whose header claims 4294967295 triangles, one given")
    bad("stl_binary_truncated.stl", stl_binary(box())[:84 + 50 * 5 + 17], "slice", "", "triangles",
        "a binary STL of 12 triangles cut in the sixth")
    bad("stl_header_only.stl", stl_binary([])[:80], "slice", "", "", "80 bytes: a binary STL header and no count")
    bad("stl_ascii_truncated.stl", stl_ascii(box())[:700], "fit", ":", "expected",
        "an ASCII STL cut mid-facet")
    bad("stl_ascii_nan.stl", stl_ascii(box()).replace("vertex 10.0 2.0 2.0", "vertex 10.0 nan 2.0", 1), "slice",
        ":", "finite", "a `nan` vertex coordinate")
    bad("stl_ascii_word.stl", stl_ascii(box()).replace("vertex 10.0 2.0 2.0", "vertex 10.0 two 2.0", 1), "slice",
        ":", "two", "a word as a vertex coordinate")
    zero = [((0.0, 0.0, 0.0), (5.0, 1.0, 1.0), (10.0, 2.0, 2.0)), ((1.0, 1.0, 1.0), (1.0, 1.0, 1.0), (2.0, 0.0, 0.0))]
    bad("stl_zero_area.stl", stl_binary(zero * 4), "fit", "", "",
        "8 zero-area triangles (collinear or repeated corners)")
    fin = [((0.0, 0.0, 0.0), (10.0, 0.0, 0.0), (5.0, 2.0 * k, 2.0 - k)) for k in (0.0, 0.5, 1.0)]
    bad("stl_non_manifold.stl", stl_binary(fin), "slice", "", "1 non-manifold edges",
        "TOLERATED: three triangles sharing one edge (a non-manifold fan): sliced, the count of non-manifold edges "
        "noted (one fin lies in the centre plane, so each cut is the V of the other two)", exit="ok")
    bad("stl_open_single.stl", stl_binary([((0.0, 0.0, 0.0), (10.0, 1.0, 0.0), (5.0, 1.0, 2.0))]), "slice", "",
        "3 open", "TOLERATED: one triangle, an open mesh: sliced into straight sections, its open edges noted "
        "(hull meshes are often open at the deck)", exit="ok")
    port = [tuple((x, y - 3.0, z) for x, y, z in tri) for tri in box()]
    bad("stl_port_side_only.stl", stl_binary(port), "fit", "", "starboard",
        "a box wholly on the port side (y from -5 to -1): nothing to slice on the starboard side")
    bad("stl_gz_truncated.stl.gz", gz(stl_ascii(box()).encode())[:150], "fit", "", "gzip",
        "a gzip stream cut short")
    bad("stl_gz_zeros.stl.gz", gz(b"\0" * (32 << 20)), "fit", "", "", "a 32 MiB run of zeros, gzipped to 32 KiB")
    bad("stl_solid_then_binary.stl", b"solid x\n" + bytes(rnd.randrange(256) for _ in range(300)), "slice", ":",
        "", "starts with `solid` like an ASCII STL, then binary bytes")
    bad("mesh_empty.stl", b"", "slice", "", "", "an empty STL file")
    obj = OBJ_BOX
    bad("obj_index_out_of_range.obj", obj.replace("f 2 6 7 3", "f 2 6 7 99"), "fit", ":12", "99",
        "a face corner 99 of 8 vertices")
    bad("obj_index_zero.obj", obj.replace("f 2 6 7 3", "f 2 6 0 3"), "slice", ":12", "index 0",
        "a face corner 0 (OBJ counts from 1)")
    bad("obj_huge_index.obj", obj.replace("f 2 6 7 3", "f 2 6 7 99999999999999999999999"), "slice", ":12",
        "99999999999999999999999", "a face index beyond any integer")
    bad("obj_nan_vertex.obj", obj.replace("v 10 2 2", "v 10 nan 2"), "fit", ":7", "finite", "a `nan` vertex")
    bad("obj_no_faces.obj", "\n".join(obj.split("\n")[:8]) + "\n", "slice", "", "triangle", "vertices, no face")
    wrl = WRL_BOX
    bad("vrml_index_out_of_range.wrl", wrl.replace("1, 5, 6, 2, -1", "1, 5, 6, 99, -1"), "fit", ":21", "99",
        "a face corner 99 of 8 points (VRML counts from 0)")
    bad("vrml_odd_point_list.wrl", wrl.replace("10 2 2,", "10 2,"), "slice", ":13", "not a multiple of 3",
        "a point with two coordinates")
    bad("vrml_transform.wrl", wrl.replace("Shape {", "Transform { translation 0 0 1.5 children [ Shape {").replace(
        "  }\n}\n", "  }\n} ] }\n"), "fit", ":3", "does not apply transforms",
        "the box moved by a Transform, which hullskin would not apply")
    bad("vrml_no_header.wrl", wrl.replace("#VRML V2.0 utf8", "VRML V2.0 utf8"), "slice", ":1", "#VRML V1.0",
        "the `#VRML` header line missing")

    # ----- drawings (digitize) -----
    dxf = DXF_HEAD + DXF_LINE + "0\nENDSEC\n0\nEOF\n"
    bad("dxf_truncated.dxf", dxf[: dxf.index("21\n")], "digitize", ":", "expected", "a DXF cut inside a LINE")
    bad("dxf_bad_group_code.dxf", dxf.replace("8\nST0", "eight\nST0"), "digitize", ":7", "eight",
        "a group code that is not an integer")
    bad("dxf_nan_coordinate.dxf", dxf.replace("11\n10.0", "11\nnan"), "digitize", ":", "nan", "a `nan` coordinate")
    bad("dxf_no_entities.dxf", "0\nSECTION\n2\nHEADER\n0\nENDSEC\n0\nEOF\n", "digitize", "", "expected",
        "a DXF without any curve")
    bad("dxf_binary.dxf", b"AutoCAD Binary DXF\r\n\x1a\0" + bytes(rnd.randrange(256) for _ in range(200)),
        "digitize", "", "", "a binary DXF")
    bad("svg_truncated.svg", SVG[:200], "digitize", ":", "expected", "an SVG cut inside an element")
    bad("svg_bad_path.svg", SVG.replace("L 120 90", "L 120 ninety"), "digitize", ":3", "path",
        "a word inside a path's d")
    bad("svg_deep.svg", '<svg xmlns="http://www.w3.org/2000/svg">' + "<g>" * 5000 + "</g>" * 5000 + "</svg>",
        "digitize", ":1", "nested more than", "5000 nested groups")
    bad("svg_entity_bomb.svg", '<?xml version="1.0"?>\n<!DOCTYPE svg [\n<!ENTITY a "aaaaaaaaaa">\n'
        + "".join(f'<!ENTITY {chr(98 + i)} "' + ("&" + chr(97 + i) + ";") * 10 + '">\n' for i in range(9))
        + ']>\n<svg xmlns="http://www.w3.org/2000/svg"><title>&j;</title><path d="M 0 0 L 1 1"/></svg>\n',
        "digitize", ":", "entit", "a billion-laughs entity expansion (10^10 characters)")
    bad("svg_no_curves.svg", '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"/>\n', "digitize", "",
        "expected", "an SVG without any curve")

    lw = DXF_HEAD + "0\nLWPOLYLINE\n8\nST0\n90\n4000000000\n70\n0\n10\n0\n20\n0\n10\n5\n20\n5\n0\nENDSEC\n0\nEOF\n"
    bad("dxf_lwpolyline_count.dxf", lw, "digitize", "", "expected at least 2 sections",
        "an LWPOLYLINE announcing 4e9 vertices (group 90) with 2 given: read as its 2 (the count is not trusted), "
        "then one station only")
    sp = DXF_HEAD + "0\nSPLINE\n8\nST0\n71\n1000000000\n72\n4000000000\n73\n4000000000\n10\n0\n20\n0\n" \
        "0\nENDSEC\n0\nEOF\n"
    bad("dxf_spline_counts.dxf", sp, "digitize", ":5", "announces 4000000000 knots",
        "a SPLINE of degree 1e9 announcing 4e9 knots and 4e9 control points, giving none")
    bad("dxf_huge_arc.dxf", DXF_HEAD + "0\nARC\n8\nST0\n10\n0\n20\n0\n40\n1e308\n50\n0\n51\n359.9999\n"
        "0\nENDSEC\n0\nEOF\n", "digitize", ":5", "centreline", "an ARC of radius 1e308 around the datum")
    bad("svg_overflow_number.svg", SVG.replace("L 120 90", "L 1e999 90"), "digitize", ":3", "invalid number",
        "`1e999` in a path: overflows an f64")
    bad("svg_huge_arc.svg", SVG.replace("L 120 90", "A 1e308 1e308 0 1 1 120 90"), "digitize", ":3", "not finite",
        "an elliptical arc of radii 1e308 whose points overflow")
    bad("bom_only.csv", "\ufeff", "fit", "", "no data", "a UTF-8 byte-order mark and nothing else")

    # ----- directories -----
    bad("directory.csv", None, "fit", "", "", "a directory where a file belongs")


ACCEPTED = []


def accepted():
    clean = sections_csv()

    def comma(s):
        return s.replace(".", ",")

    ACCEPTED.append(("sections_clean.csv", clean, "sections_clean.csv", "the README's sections CSV example"))
    ACCEPTED.append(("sections_semicolon_decimal_comma.csv",
                     comma(sections_csv(sep=";", header="section;x;y;z", nl="\r\n")),
                     "sections_clean.csv", "`;` separators and decimal commas, CRLF (a European spreadsheet)"))
    ACCEPTED.append(("sections_semicolon_decimal_point.csv", sections_csv(sep=";", header="section;x;y;z"),
                     "sections_clean.csv", "`;` separators with decimal points"))
    ACCEPTED.append(("sections_bom.csv", "\ufeff" + clean, "sections_clean.csv", "a UTF-8 byte-order mark"))
    lines = clean.split("\n")
    mixed = "".join(line + ("\r\n", "\n", "\r")[i % 3] for i, line in enumerate(lines[:-1]))
    ACCEPTED.append(("sections_mixed_line_ends.csv", mixed, "sections_clean.csv", "CRLF, LF and CR line ends mixed"))
    ACCEPTED.append(("sections_tabs.csv", sections_csv(sep="\t", header="section\tx\ty\tz"), "sections_clean.csv",
                     "tab-separated"))
    ACCEPTED.append(("sections_tabs_decimal_comma_bom.csv",
                     "\ufeff" + comma(sections_csv(sep="\t", header="section\tx\ty\tz", nl="\r\n")),
                     "sections_clean.csv", "tabs, decimal commas, BOM and CRLF (a spreadsheet's text export)"))
    ACCEPTED.append(("table_clean.csv", TABLE, "table_clean.csv", "the README's offset table example"))
    ACCEPTED.append(("table_semicolon_decimal_comma.csv",
                     "\ufeff" + comma(TABLE.replace(",", ";")).replace("\n", "\r\n"),
                     "table_clean.csv", "`;` and decimal commas, BOM, CRLF"))
    ACCEPTED.append(("long_clean.csv", LONG, "long_clean.csv", "a long CSV (x,z,y)"))
    ACCEPTED.append(("long_tabs_decimal_comma.csv", comma(LONG.replace(",", "\t")), "long_clean.csv",
                     "the long CSV tab-separated with decimal commas"))
    ACCEPTED.append(("cloud_clean.dat", CLOUD, "cloud_clean.dat", "a station point cloud"))
    ACCEPTED.append(("cloud_bom_crlf.dat", "\ufeff" + CLOUD.replace("\n", "\r\n"), "cloud_clean.dat",
                     "the point cloud with a BOM and CRLF"))
    ACCEPTED.append(("box_clean.obj", OBJ_BOX, "box_clean.obj", "a closed box as OBJ (sliced, then fitted)"))
    ACCEPTED.append(("box_bom_crlf.obj", "\ufeff" + OBJ_BOX.replace("\n", "\r\n"), "box_clean.obj",
                     "the OBJ box with a BOM and CRLF"))
    ACCEPTED.append(("box_clean.stl", stl_ascii(box()), "box_clean.stl", "the box as an ASCII STL"))
    ACCEPTED.append(("box_clean.wrl", WRL_BOX, "box_clean.obj", "the OBJ box as VRML 2.0"))
    ACCEPTED.append(("box_bom.stl", "\ufeff" + stl_ascii(box()), "box_clean.stl",
                     "the ASCII STL box with a BOM"))
    ACCEPTED.append(("table_semicolon_quoted.csv", TABLE.replace(",", ";").replace("2.45", '"2,45"'),
                     "table_clean.csv", "`;` with one decimal-comma cell quoted"))


def main():
    build()
    accepted()
    names = set()
    with open(os.path.join(HERE, "manifest.csv"), "w", newline="\n") as m:
        m.write("file,command,args,exit,at,says,why\n")
        for name, content, command, args, exit, at, says, why in BAD:
            assert name not in names, name
            names.add(name)
            path = os.path.join(HERE, name)
            if content is None:
                os.makedirs(path, exist_ok=True)
                with open(os.path.join(path, "README.md"), "w") as f:
                    f.write("A directory given where the CLI expects a file (see ../README.md).\n")
            else:
                data = content.encode("utf-8") if isinstance(content, str) else content
                with open(path, "wb") as f:
                    f.write(data)
            m.write(",".join([name, command, args, exit, at, says, '"' + why.replace('"', '""') + '"']) + "\n")
    adir = os.path.join(HERE, "accepted")
    os.makedirs(adir, exist_ok=True)
    with open(os.path.join(adir, "manifest.csv"), "w", newline="\n") as m:
        m.write("file,clean,why\n")
        for name, content, clean, why in ACCEPTED:
            with open(os.path.join(adir, name), "wb") as f:
                f.write(content.encode("utf-8"))
            m.write(",".join([name, clean, '"' + why.replace('"', '""') + '"']) + "\n")
    write_readme()
    print(f"{len(BAD)} bad files, {len(ACCEPTED)} accepted files")


def place(at):
    if at == "":
        return "the file"
    if at == ":":
        return "`file:LINE`"
    return f"`file{at}`"


def write_readme():
    out = [
        "# testdata/bad: the bad-input corpus (issue 6)",
        "",
        "Hostile and broken inputs for every format the CLI reads, run by",
        "`crates/cli/tests/cli/bad_input.rs` (`cargo test -p hullskin --test cli bad_input::`): on each file the",
        "CLI must exit non-zero without a panic, a signal, a hang (60 s) or more than 1 GiB of address",
        "space, and its message must name the file, the place (line, or line and column, for text",
        "inputs) and say what is wrong. The few files marked TOLERATED are hostile but valid: they",
        "must succeed, with the note given. The files are small, made up, and written by `gen.py`",
        "(`python3 testdata/bad/gen.py` rewrites them identically); `manifest.csv` is the table below",
        "as the test reads it. `accepted/` holds files a user expects to work (decimal commas with `;`,",
        "BOMs, CRLF or mixed line ends, tabs): each must fit to the same surface, byte for byte, as",
        "its clean counterpart.",
        "",
        "| file | run with | what is wrong | the CLI must say |",
        "|---|---|---|---|",
    ]
    for name, _content, command, args, exit, at, says, why in BAD:
        run = command + (" " + args if args else "")
        must = f"succeed, noting \"{says}\"" if exit == "ok" else place(at) + (f", \"{says}\"" if says else "")
        out.append(f"| `{name}` | `{run}` | {why.replace('|', '/')} | {must} |")
    out += [
        "",
        "## accepted/",
        "",
        "| file | same offsets as | what differs |",
        "|---|---|---|",
    ]
    for name, _content, clean, why in ACCEPTED:
        out.append(f"| `{name}` | `{clean}` | {why} |")
    with open(os.path.join(HERE, "README.md"), "w", newline="\n") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
