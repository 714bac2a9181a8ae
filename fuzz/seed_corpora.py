#!/usr/bin/env python3
"""Fills fuzz/corpus/<target>/ with the seeds of each fuzz target (docs/fuzzing.md).

Seeds: the small inputs of testdata/ each target reads (at most 16 KiB, so that libFuzzer's
default input length stays small and the runs fast), the regression inputs of
testdata/fuzz/<target>/, and a few generated inputs written to fuzz/seeds/ (committed; this
script rewrites them byte for byte): a small closed Wigley hull as ASCII STL, binary STL, OBJ
and gzipped STL, and surface JSONs (bilinear and bicubic, polynomial and rational). The IGES
and STEP seeds of fuzz/seeds/cad/ are committed as written, not generated here:
hullskin_*.igs/.stp by `hullskin export fuzz/seeds/surface_json/<name>.json --timestamp 0`,
occt_*.igs/.stp by tools/occt_write.py (Open CASCADE).

Usage, from the repository root: python3 fuzz/seed_corpora.py
Standard library only.
"""

import gzip
import json
import shutil
import struct
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
FUZZ = ROOT / "fuzz"
TESTDATA = ROOT / "testdata"
MAX_SEED = 16 * 1024

TEXT_OFFSETS = [
    "sections_example.csv",
    "offsets_example.csv",
    "series60_cb060_offsets.csv",
    "wigley_offsets.csv",
    "gunnerus_offsets.csv",
    "cargo116_offsets.csv",
    "freeship_curves_example.txt",
    "freeship_wigley_offsets.txt",
    "matlab_frigate.csv",
    "raw/series60/cb0p6.csv",
    "raw/cargo116/offsets_table.json",
    "raw/cargo116/principals.json",
    "peers/s60cb060_st.csv",
    "peers/cargo116_wl.csv",
]


def wigley_mesh(nx=5, nz=3, length=10.0, beam=1.0, draft=0.625):
    """A closed Wigley hull, both sides and a flat deck at the waterline: vertices, triangles.

    y = +-(B/2)(1 - (2x/L)^2)(1 - (z/T)^2), x in [-L/2, L/2] shifted to [0, L], z from the
    keel (z = 0) to the deck (z = T). Sides meet exactly at the stems and the keel (y = 0).
    """
    verts, index = [], {}

    def vid(x, y, z):
        key = (x, y + 0.0, z)  # -0.0 and 0.0 are one vertex
        if key not in index:
            index[key] = len(verts)
            verts.append(key)
        return index[key]

    grid = {}
    for i in range(nx):
        x = -length / 2 + length * i / (nx - 1)
        for k in range(nz):
            zd = draft * (1 - k / (nz - 1))  # depth below the deck
            y = beam / 2 * (1 - (2 * x / length) ** 2) * (1 - (zd / draft) ** 2)
            z = draft - zd
            for side in (1, -1):
                grid[i, k, side] = vid(round(x + length / 2, 9), round(side * y, 9), round(z, 9))
    tris = []
    for i in range(nx - 1):
        for k in range(nz - 1):
            for side in (1, -1):
                a, b = grid[i, k, side], grid[i + 1, k, side]
                c, d = grid[i + 1, k + 1, side], grid[i, k + 1, side]
                # The diagonal away from the stem: a triangle of the keel and stem corners
                # alone would lie in the centre plane, shared by both sides.
                quad = [(a, b, c), (a, c, d)] if 2 * i < nx - 1 else [(a, b, d), (b, c, d)]
                tris += quad if side == 1 else [(x, z, y) for x, y, z in quad]
        top = nz - 1
        a, b = grid[i, top, 1], grid[i + 1, top, 1]
        c, d = grid[i + 1, top, -1], grid[i, top, -1]
        tris += [(a, b, c), (a, c, d)]
    tris = [t for t in tris if len(set(t)) == 3]
    return verts, tris


def num(v):
    return repr(float(v))


def stl_ascii(verts, tris):
    out = ["solid wigley"]
    for t in tris:
        out.append("  facet normal 0 0 0")
        out.append("    outer loop")
        for i in t:
            out.append("      vertex " + " ".join(num(c) for c in verts[i]))
        out.append("    endloop")
        out.append("  endfacet")
    out.append("endsolid wigley")
    return ("\n".join(out) + "\n").encode()


def stl_binary(verts, tris):
    head = b"binary wigley".ljust(80, b" ")
    body = b"".join(
        struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *verts[i]) for i in t) + b"\0\0" for t in tris
    )
    return head + struct.pack("<I", len(tris)) + body


def obj(verts, tris):
    out = ["# wigley", "o hull"]
    out += ["v " + " ".join(num(c) for c in v) for v in verts]
    out += ["f " + " ".join(f"{i + 1}//1" for i in t) for t in tris]
    return ("\n".join(out) + "\n").encode()


def vrml(verts, tris):
    out = ["#VRML V2.0 utf8", "# wigley", "Shape {", "  geometry IndexedFaceSet {", "    coord Coordinate {",
           "      point ["]
    out += ["        " + " ".join(num(c) for c in v) + "," for v in verts]
    out += ["      ]", "    }", "    coordIndex ["]
    out += ["      " + ", ".join(str(i) for i in t) + ", -1," for t in tris]
    out += ["    ]", "  }", "}"]
    return ("\n".join(out) + "\n").encode()


def surface(p, q, nu, nv, rational):
    def knots(deg, n):
        inner = n - deg - 1
        return [0.0] * (deg + 1) + [(k + 1) / (inner + 1) for k in range(inner)] + [1.0] * (deg + 1)

    pts, w = [], []
    for i in range(nu):
        for j in range(nv):
            x = 10.0 * i / (nu - 1)
            z = 1.0 * j / (nv - 1)
            y = 0.5 * (1 - (2 * x / 10.0 - 1) ** 2) * (0.2 + 0.8 * z)
            pts.append([x, round(y, 6), z])
            w.append(1.0 + 0.5 * ((i + j) % 2) if rational else 1.0)
    doc = {
        "format": "hullskin-surface",
        "version": 1,
        "units": "m",
        "degree": [p, q],
        "control_points_count": [nu, nv],
        "knots_u": knots(p, nu),
        "knots_v": knots(q, nv),
        "control_points": pts,
        "weights": w,
    }
    return (json.dumps(doc, indent=1) + "\n").encode()


def vessel_js():
    """R/V Gunnerus's vessel.js table (testdata/raw/gunnerus), every sixth station."""
    ship = json.loads((TESTDATA / "raw/gunnerus/gunnerus.json").read_text())
    hull = ship["structure"]["hull"]
    hb = hull["halfBreadths"]
    keep = range(0, len(hb["stations"]), 6)
    small_hb = {
        "waterlines": hb["waterlines"],
        "stations": [hb["stations"][j] for j in keep],
        "table": [[row[j] for j in keep] for row in hb["table"]],
    }
    attributes = {k: hull["attributes"][k] for k in ("LOA", "BOA", "Depth")}
    doc = {"structure": {"hull": {"attributes": attributes, "halfBreadths": small_hb}}}
    return (json.dumps(doc) + "\n").encode()


def dxf_entities():
    """Every DXF entity the reader knows, once, in a body plan of three stations."""
    ents = [
        "0\nLINE\n8\nST0\n10\n0\n20\n0\n30\n0\n11\n-1\n21\n0.5\n31\n0",
        "0\nARC\n8\nST0\n10\n-1\n20\n1.5\n40\n1\n50\n180\n51\n270",
        "0\nCIRCLE\n8\nDECK\n10\n0\n20\n5\n40\n0.2",
        "0\nELLIPSE\n8\nST1\n10\n0\n20\n2\n11\n2\n21\n0\n40\n0.5\n41\n4.712389\n42\n6.283185",
        "0\nLWPOLYLINE\n8\nST2\n90\n3\n70\n0\n10\n0\n20\n0\n10\n2\n20\n0\n42\n0.4142\n10\n3\n20\n1",
        "0\nPOLYLINE\n8\nST3\n66\n1\n70\n0\n0\nVERTEX\n10\n0\n20\n0\n0\nVERTEX\n10\n-2\n20\n0.5\n42\n-0.2"
        "\n0\nVERTEX\n10\n-2.5\n20\n3\n0\nSEQEND",
        "0\nSPLINE\n8\nST4\n70\n8\n71\n3\n72\n8\n73\n4\n74\n0\n40\n0\n40\n0\n40\n0\n40\n0\n40\n1\n40\n1"
        "\n40\n1\n40\n1\n41\n1\n41\n0.8\n41\n0.8\n41\n1\n10\n0\n20\n0\n10\n1.5\n20\n0\n10\n2\n20\n1\n10\n2\n20\n3",
        "0\nSPLINE\n8\nST5\n71\n3\n74\n4\n11\n0\n21\n0\n11\n-1\n21\n1\n11\n-1.5\n21\n2\n11\n-1.6\n21\n3",
        "0\nARC\n8\nST6\n10\n1\n20\n1\n40\n1\n50\n0\n51\n90\n210\n0\n220\n0\n230\n-1",
        "0\nTEXT\n8\nLABELS\n10\n2.1\n20\n3.1\n1\nST 4 %%d\n72\n1\n11\n2.2\n21\n3.2",
        "0\nMTEXT\n8\nLABELS\n10\n-2.6\n20\n3.1\n3\n{\\fArial|b0;Station\\P}\n1\n3\\S1^2;",
        "0\nINSERT\n2\nB\n10\n0\n20\n0",
    ]
    header = "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n4\n0\nENDSEC\n"
    body = "0\nSECTION\n2\nENTITIES\n" + "\n".join(ents) + "\n0\nENDSEC\n0\nEOF\n"
    return (header + body).encode()


SVG = """<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="80mm" viewBox="-50 -70 100 80">
  <g id="body" transform="matrix(10 0 0 -10 0 0) rotate(0.5) skewX(0.1)">
    <path id="ST1" d="M0 0 C-1 0 -2 0.5 -2 1.5 S-2.5 3 -2.6 4"/>
    <path d="m 0,0 q 1,0 2,1 t 0.5,2 l 0.1,1 z M 0 5 h 1 v 1 H 0 V 5 Z"><title>ST9</title></path>
    <path d="M0,0 A 1.5 1 30 1 0 -1.5,2 a1 1 0 01 1 1"/>
    <polyline points="0,0 -0.5,1 -0.7,3"/>
    <polygon points="0,0 1,0 1,1"/>
    <line x1="0" y1="0" x2="0" y2="6"/>
  </g>
  <g transform="translate(5,5) scale(2)"><g transform="translate(1 1)">
    <path d="M1e1-2e-1L3.5.5"/></g></g>
  <text x="-30" y="-40">ST1</text>
  <text x="30" y="-40"><tspan>ST 9</tspan></text>
</svg>
"""


def write_seeds():
    seeds = FUZZ / "seeds"
    verts, tris = wigley_mesh()
    files = {
        "mesh/wigley_ascii.stl": stl_ascii(verts, tris),
        "mesh/wigley_binary.stl": stl_binary(verts, tris),
        "mesh/wigley.obj": obj(verts, tris),
        "mesh/wigley.wrl": vrml(verts, tris),
        # mtime 0: the same bytes on every run.
        "mesh/wigley_ascii.stl.gz": gzip.compress(stl_ascii(verts, tris), mtime=0),
        "json_table/gunnerus_vessel_js.json": vessel_js(),
        "drawing/entities.dxf": dxf_entities(),
        "drawing/paths.svg": SVG.encode(),
        "surface_json/bilinear.json": surface(1, 1, 2, 2, False),
        "surface_json/bicubic.json": surface(3, 3, 5, 4, False),
        "surface_json/rational.json": surface(2, 3, 4, 5, True),
    }
    for name, data in files.items():
        path = seeds / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    return seeds


def small(paths):
    return [p for p in paths if p.is_file() and p.stat().st_size <= MAX_SEED]


def main():
    seeds = write_seeds()
    mesh = sorted((seeds / "mesh").iterdir())
    offsets = small(TESTDATA / n for n in TEXT_OFFSETS)
    bad = sorted((TESTDATA / "bad").glob("**/*")) if (TESTDATA / "bad").is_dir() else []
    drawings = sorted((TESTDATA / "digitize").glob("*.dxf")) + sorted((TESTDATA / "digitize").glob("*.svg"))
    drawings += sorted((seeds / "drawing").iterdir())
    per_target = {
        "decode": offsets + small(bad),
        "read_detect": offsets + small(bad) + sorted((seeds / "json_table").iterdir()),
        "read_sections_csv": offsets,
        "read_offset_table": offsets,
        "read_series60_table": offsets,
        "read_long_csv": offsets,
        "read_json_table": [p for p in offsets if p.suffix == ".json"] + sorted((seeds / "json_table").iterdir()),
        "read_point_cloud": offsets,
        "read_freeship_offsets": offsets,
        "read_freeship_curves": offsets,
        "mesh_stl": [p for p in mesh if ".stl" in p.name and not p.name.endswith(".gz")],
        "mesh_obj": [p for p in mesh if p.suffix == ".obj"],
        "mesh_vrml": [p for p in mesh if p.suffix == ".wrl"],
        "mesh_parse_slice": mesh,
        "drawing_dxf": [p for p in drawings if p.suffix == ".dxf"],
        "drawing_svg": [p for p in drawings if p.suffix == ".svg"],
        "drawing_digitize": drawings,
        "surface_json": sorted((seeds / "surface_json").iterdir()),
        "read_iges": sorted((seeds / "cad").glob("*.igs")),
        "read_step": sorted((seeds / "cad").glob("*.stp")),
    }
    for target, files in per_target.items():
        corpus = FUZZ / "corpus" / target
        corpus.mkdir(parents=True, exist_ok=True)
        regressions = TESTDATA / "fuzz" / target
        if regressions.is_dir():
            files = files + sorted(p for p in regressions.iterdir() if p.is_file())
        for p in files:
            shutil.copyfile(p, corpus / f"seed-{p.parent.name}-{p.name}")
        print(f"{target}: {len(files)} seeds")


if __name__ == "__main__":
    main()
