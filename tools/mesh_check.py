#!/usr/bin/env python3
"""Read a mesh written by hullskin (STL binary or ASCII, OBJ, binary glTF) with real readers.

Usage: mesh_check.py FILE.stl|FILE.obj|FILE.glb

Every file is loaded with trimesh (trimesh.load(..., process=False), so vertices and faces
stay as written) and checked for what its format requires:

  * STL: binary when the size is 84 + 50 n for the count n in bytes 80..84 and the header does
    not start with "solid", else ASCII starting "solid" and ending "endsolid"; every stored
    facet normal unit length and agreeing with the right-hand winding of its corners (dot
    product > 0.99).
  * OBJ: as many "vn" as "v" lines; faces reference existing vertices.
  * glTF binary (glTF 2.0 section 4.4 and 5): parsed twice, by pygltflib and by a strict
    reader here: the GLB header (magic, version 2, total length), a JSON chunk then a BIN
    chunk, 4-byte aligned; asset.version "2.0"; every accessor inside its buffer view and
    every view inside the buffer, offsets aligned to the component size, vertex attributes to
    4 bytes; buffer.byteLength <= BIN chunk <= byteLength + 3; one triangle primitive (mode 4
    or absent) with POSITION (float VEC3, min/max present and equal to the data), NORMAL
    (float VEC3, unit length within 1e-4), COLOR_0 (float VEC3/VEC4 in [0, 1]), indices
    (unsigned, < vertex count, count a multiple of 3, no restart value), all attributes of one
    count; scene, node, mesh and material references valid.

Prints a JSON summary on stdout: {"ok", "format", "reader" (versions), "checks" [...],
"failed" [...], "vertices" [[x, y, z], ...], "faces" [[a, b, c], ...], "face_normals" (STL,
as stored in the file), "vertex_normals" (OBJ, glTF), "colors" (glTF, linear RGB)}. The glTF
arrays are the raw accessor data (glTF axes and metres). Exit status 0 if every check passed,
1 on a failed check, 2 if the file could not be read.
"""

import json
import os
import struct
import sys


class Checks:
    def __init__(self):
        self.items = []

    def add(self, name, ok, detail=None):
        self.items.append({"name": name, "ok": bool(ok), "detail": detail})
        return ok

    @property
    def ok(self):
        return all(c["ok"] for c in self.items)


def tolist(a):
    return [[float(x) for x in row] for row in a]


def load_trimesh(path, file_type=None):
    import trimesh

    kwargs = {"process": False}
    if file_type == "obj":
        kwargs["maintain_order"] = True
    loaded = trimesh.load(path, file_type=file_type, **kwargs)
    if isinstance(loaded, trimesh.Scene):
        geoms = list(loaded.geometry.values())
        if len(geoms) != 1:
            raise ValueError(f"{len(geoms)} geometries in the scene, expected 1")
        return geoms[0]
    return loaded


def check_stl(path, checks, out):
    import numpy as np

    data = open(path, "rb").read()
    binary = len(data) >= 84 and not data.startswith(b"solid")
    if binary:
        n = struct.unpack_from("<I", data, 80)[0]
        checks.add("binary STL size is 84 + 50 n", len(data) == 84 + 50 * n, f"{len(data)} bytes, n = {n}")
        stored = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]), offset=84)
        normals = stored["n"].astype(float)
        corners = stored["v"].astype(float)
    else:
        text = data.decode("ascii")
        last = text.rstrip().split("\n")[-1]
        checks.add("ASCII STL solid ... endsolid", text.startswith("solid") and last.startswith("endsolid"))
        normals, verts = [], []
        for line in text.splitlines():
            t = line.split()
            if t[:2] == ["facet", "normal"]:
                normals.append([float(x) for x in t[2:5]])
            elif t[:1] == ["vertex"]:
                verts.append([float(x) for x in t[1:4]])
        normals = np.array(normals)
        corners = np.array(verts).reshape(-1, 3, 3)
        n = len(normals)
    out["format"] = "stl-binary" if binary else "stl-ascii"
    mesh = load_trimesh(path, "stl")
    checks.add("trimesh face count", len(mesh.faces) == n, f"trimesh {len(mesh.faces)}, file {n}")
    tri = mesh.vertices[mesh.faces]
    checks.add("trimesh corners equal the file's", np.array_equal(tri, corners), None)
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    length = np.linalg.norm(cross, axis=1)
    checks.add("no degenerate facet", bool((length > 0).all()), f"{int((length <= 0).sum())} degenerate")
    unit = np.abs(np.linalg.norm(normals, axis=1) - 1.0).max() if n else 0.0
    checks.add("stored normals unit", unit < 1e-5, f"max | |n| - 1 | {unit:.2e}")
    agree = (np.einsum("ij,ij->i", normals, cross / np.maximum(length, 1e-300)[:, None])).min() if n else 1.0
    checks.add("stored normals agree with the winding", agree > 0.99, f"min dot {agree:.6f}")
    out["vertices"] = tolist(mesh.vertices)
    out["faces"] = mesh.faces.tolist()
    out["face_normals"] = tolist(normals)


def check_obj(path, checks, out):
    lines = open(path, encoding="ascii").read().splitlines()
    nv = sum(1 for l in lines if l.startswith("v "))
    nvn = sum(1 for l in lines if l.startswith("vn "))
    nf = sum(1 for l in lines if l.startswith("f "))
    checks.add("one vn per v", nv == nvn, f"{nv} v, {nvn} vn")
    mesh = load_trimesh(path, "obj")
    checks.add("trimesh vertex count", len(mesh.vertices) == nv, f"trimesh {len(mesh.vertices)}, file {nv}")
    checks.add("trimesh face count", len(mesh.faces) == nf, f"trimesh {len(mesh.faces)}, file {nf}")
    checks.add("faces reference vertices", int(mesh.faces.max()) < len(mesh.vertices) and int(mesh.faces.min()) >= 0)
    out["format"] = "obj"
    out["vertices"] = tolist(mesh.vertices)
    out["faces"] = mesh.faces.tolist()
    out["vertex_normals"] = tolist(mesh.vertex_normals)


COMPONENTS = {5120: ("b", 1), 5121: ("B", 1), 5122: ("h", 2), 5123: ("H", 2), 5125: ("I", 4), 5126: ("f", 4)}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}


def check_glb(path, checks, out):
    import numpy as np
    import pygltflib

    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<III", data, 0)
    checks.add("GLB magic", magic == 0x46546C67, hex(magic))
    checks.add("GLB version 2", version == 2, version)
    checks.add("GLB length", length == len(data), f"header {length}, file {len(data)}")
    jlen, jtype = struct.unpack_from("<II", data, 12)
    checks.add("JSON chunk first", jtype == 0x4E4F534A, hex(jtype))
    checks.add("JSON chunk 4-byte aligned", jlen % 4 == 0, jlen)
    doc = json.loads(data[20 : 20 + jlen].decode("utf-8"))
    at = 20 + jlen
    blen, btype = struct.unpack_from("<II", data, at)
    checks.add("BIN chunk second", btype == 0x004E4942, hex(btype))
    checks.add("BIN chunk 4-byte aligned", blen % 4 == 0, blen)
    checks.add("nothing after the BIN chunk", at + 8 + blen == len(data))
    bin_ = data[at + 8 : at + 8 + blen]

    # pygltflib: an independent parse of the whole file.
    g = pygltflib.GLTF2().load_binary(path)
    checks.add("pygltflib reads one mesh", len(g.meshes) == 1 and len(g.meshes[0].primitives) == 1)
    checks.add("pygltflib binary blob", len(g.binary_blob() or b"") == blen)

    checks.add("asset.version 2.0", doc.get("asset", {}).get("version") == "2.0", doc.get("asset"))
    buffers = doc.get("buffers", [])
    ok = len(buffers) == 1 and "uri" not in buffers[0]
    ok = ok and buffers[0]["byteLength"] <= blen <= buffers[0]["byteLength"] + 3
    checks.add("one buffer, the BIN chunk", ok, buffers)
    views = doc.get("bufferViews", [])
    for k, v in enumerate(views):
        end = v.get("byteOffset", 0) + v["byteLength"]
        checks.add(f"bufferView {k} inside the buffer", v["buffer"] == 0 and end <= buffers[0]["byteLength"])

    def accessor(k, attribute):
        a = doc["accessors"][k]
        fmt, size = COMPONENTS[a["componentType"]]
        width = WIDTH[a["type"]]
        v = views[a["bufferView"]]
        offset = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        stride = v.get("byteStride", size * width)
        checks.add(f"accessor {k} offset aligned", offset % size == 0 and stride % size == 0)
        if attribute:
            checks.add(f"accessor {k} vertex attribute aligned to 4", offset % 4 == 0 and stride % 4 == 0)
        need = a.get("byteOffset", 0) + stride * (a["count"] - 1) + size * width
        checks.add(f"accessor {k} inside its view", need <= v["byteLength"], f"{need} > {v['byteLength']}")
        values = np.array(
            [struct.unpack_from("<" + fmt * width, bin_, offset + stride * i) for i in range(a["count"])]
        )
        return a, values

    scenes, nodes, meshes = doc.get("scenes", []), doc.get("nodes", []), doc.get("meshes", [])
    checks.add("default scene exists", 0 <= doc.get("scene", 0) < len(scenes))
    checks.add("scene nodes exist", all(0 <= n < len(nodes) for s in scenes for n in s.get("nodes", [])))
    checks.add("node meshes exist", all(0 <= n.get("mesh", 0) < len(meshes) for n in nodes))
    prim = meshes[0]["primitives"][0]
    checks.add("triangles", prim.get("mode", 4) == 4, prim.get("mode"))
    mat = prim.get("material")
    checks.add("material exists", mat is None or 0 <= mat < len(doc.get("materials", [])))
    attrs = prim["attributes"]
    checks.add("POSITION, NORMAL, COLOR_0", {"POSITION", "NORMAL", "COLOR_0"} <= set(attrs), sorted(attrs))

    pa, pos = accessor(attrs["POSITION"], True)
    checks.add("POSITION float VEC3", pa["componentType"] == 5126 and pa["type"] == "VEC3")
    ok = "min" in pa and "max" in pa and list(pos.min(axis=0)) == pa["min"] and list(pos.max(axis=0)) == pa["max"]
    checks.add("POSITION min/max equal the data", ok, {"min": pa.get("min"), "max": pa.get("max")})
    na, nrm = accessor(attrs["NORMAL"], True)
    checks.add("NORMAL float VEC3", na["componentType"] == 5126 and na["type"] == "VEC3")
    unit = float(np.abs(np.linalg.norm(nrm, axis=1) - 1.0).max())
    checks.add("NORMAL unit length", unit < 1e-4, f"max | |n| - 1 | {unit:.2e}")
    ca, col = accessor(attrs["COLOR_0"], True)
    checks.add("COLOR_0 float VEC3/VEC4", ca["componentType"] == 5126 and ca["type"] in ("VEC3", "VEC4"))
    checks.add("COLOR_0 in [0, 1]", float(col.min()) >= 0.0 and float(col.max()) <= 1.0)
    counts = {pa["count"], na["count"], ca["count"]}
    checks.add("attributes of one count", len(counts) == 1, sorted(counts))
    ia, idx = accessor(prim["indices"], False)
    checks.add("indices unsigned SCALAR", ia["componentType"] in (5121, 5123, 5125) and ia["type"] == "SCALAR")
    restart = {5121: 0xFF, 5123: 0xFFFF, 5125: 0xFFFFFFFF}[ia["componentType"]]
    idx = idx.reshape(-1)
    checks.add("indices in range", int(idx.max()) < pa["count"] and int(idx.min()) >= 0 and restart not in idx)
    checks.add("index count a multiple of 3", ia["count"] % 3 == 0, ia["count"])
    faces = idx.reshape(-1, 3)

    mesh = load_trimesh(path)
    checks.add("trimesh vertices equal the accessor", np.array_equal(np.asarray(mesh.vertices), pos))
    checks.add("trimesh faces equal the indices", np.array_equal(np.asarray(mesh.faces), faces))
    out["format"] = "glb"
    out["vertices"] = tolist(pos)
    out["faces"] = faces.tolist()
    out["vertex_normals"] = tolist(nrm)
    out["colors"] = tolist(col)
    out["asset"] = doc["asset"]


def main(argv):
    if len(argv) != 2:
        print(json.dumps({"ok": False, "error": "usage: mesh_check.py FILE.stl|FILE.obj|FILE.glb"}))
        return 2
    path = argv[1]
    ext = os.path.splitext(path)[1].lower()
    checks = Checks()
    out = {}
    try:
        import numpy
        import pygltflib
        import trimesh

        out["reader"] = {"trimesh": trimesh.__version__, "numpy": numpy.__version__, "pygltflib": pygltflib.__version__}
        {".stl": check_stl, ".obj": check_obj, ".glb": check_glb}[ext](path, checks, out)
    except Exception as exc:  # noqa: BLE001 - any failure to read is reported, not raised
        print(json.dumps({"ok": False, "error": f"{type(exc).__name__}: {exc}", "checks": checks.items}))
        return 2
    out["ok"] = checks.ok
    out["failed"] = [c for c in checks.items if not c["ok"]]
    out["checks"] = checks.items
    print(json.dumps(out))
    return 0 if checks.ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
