#!/usr/bin/env python3
"""Read a DXF file written by hullskin with ezdxf and print what a CAD program would see.

Usage: dxf_check.py FILE.dxf

The file is loaded with ezdxf.readfile (strict: no recover mode) and audited with
doc.audit(). The summary printed as JSON on stdout holds:

  dxfversion, header {$ACADVER, $INSUNITS, $MEASUREMENT, $EXTMIN, $EXTMAX},
  layers [{name, color, linetype}] in table order,
  linetypes [{name, pattern}],
  counts {layer: {dxftype: n}},
  entities [...] in file order, each {type, layer, color (62, 256 = BYLAYER)} plus
    POLYLINE: closed, flags, vertices [[x, y, z], ...]
    CIRCLE:   center [x, y, z], radius
    TEXT:     insert, align_point (or null), height, halign, text (escapes decoded)
    SOLID:    vertices [[x, y, z] x 4] in DXF order (corners 1, 2, 4, 3)
  audit {errors: [...], fixes: [...]}.

Exit status 0 if the file was read and the audit found no error, 1 if the audit found
errors, 2 if the file could not be read.

Used by crates/view/tests/lines_plan.rs, which compares the summary with the drawing it
wrote.
"""

import json
import sys


def vec(v):
    return [float(c) for c in v]


def entity_summary(e):
    d = {"type": e.dxftype(), "layer": e.dxf.layer, "color": int(e.dxf.get("color", 256))}
    t = d["type"]
    if t == "POLYLINE":
        d["flags"] = int(e.dxf.flags)
        d["closed"] = bool(e.is_closed)
        d["vertices"] = [vec(v.dxf.location) for v in e.vertices]
        d["linetype"] = e.dxf.get("linetype", "BYLAYER")
    elif t == "CIRCLE":
        d["center"] = vec(e.dxf.center)
        d["radius"] = float(e.dxf.radius)
    elif t == "TEXT":
        d["insert"] = vec(e.dxf.insert)
        d["align_point"] = vec(e.dxf.align_point) if e.dxf.hasattr("align_point") else None
        d["height"] = float(e.dxf.height)
        d["halign"] = int(e.dxf.get("halign", 0))
        d["text"] = e.dxf.text
    elif t == "SOLID":
        d["vertices"] = [vec(e.dxf.get(f"vtx{k}", (0, 0, 0))) for k in range(4)]
    return d


def main(argv):
    if len(argv) != 2:
        print(json.dumps({"ok": False, "error": "usage: dxf_check.py FILE.dxf"}))
        return 2
    try:
        import ezdxf

        doc = ezdxf.readfile(argv[1])
    except Exception as exc:  # noqa: BLE001 - any failure to read is reported, not raised
        print(json.dumps({"ok": False, "error": f"{type(exc).__name__}: {exc}"}))
        return 2

    header = {}
    for name in ("$ACADVER", "$INSUNITS", "$MEASUREMENT", "$EXTMIN", "$EXTMAX"):
        if name in doc.header:
            v = doc.header[name]
            header[name] = vec(v) if isinstance(v, (tuple, list)) or hasattr(v, "x") else v
    layers = [
        {"name": layer.dxf.name, "color": int(layer.dxf.color), "linetype": layer.dxf.linetype} for layer in doc.layers
    ]
    linetypes = []
    for lt in doc.linetypes:
        pattern = []
        if hasattr(lt, "pattern_tags"):
            pattern = [float(x) for x in lt.simplified_line_pattern()] if lt.pattern_tags.tags else []
        linetypes.append({"name": lt.dxf.name, "pattern": pattern})

    entities = [entity_summary(e) for e in doc.modelspace()]
    counts = {}
    for e in entities:
        per_layer = counts.setdefault(e["layer"], {})
        per_layer[e["type"]] = per_layer.get(e["type"], 0) + 1

    auditor = doc.audit()
    audit = {
        "errors": [str(x.message) for x in auditor.errors],
        "fixes": [str(x.message) for x in auditor.fixes],
    }
    ok = not auditor.has_errors
    print(
        json.dumps(
            {
                "ok": ok,
                "ezdxf_version": ezdxf.__version__,
                "dxfversion": doc.dxfversion,
                "header": header,
                "layers": layers,
                "linetypes": linetypes,
                "counts": counts,
                "entities": entities,
                "audit": audit,
            }
        )
    )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
