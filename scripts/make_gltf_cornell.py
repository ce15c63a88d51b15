#!/usr/bin/env python3
"""Writes the built-in Cornell box (assets/cornell-box) as glTF 2.0, for comparing the glTF path with the OBJ one.

    python3 scripts/make_gltf_cornell.py [OUT.gltf]        (default: /tmp/cornell-box.gltf)

The same conversion as tests/load/test_gltf_loader.cpp's cornell_as_gltf: the OBJ's vertices, its faces fanned into
triangles as the OBJ loader does, one primitive per material with baseColorFactor = Kd, metallic 0 and
KHR_materials_specular factor 0 (a pure Lambertian base: the OBJ's BSDF), the light's Ke as emissiveFactor x
KHR_materials_emissive_strength (one-sided, as the OBJ scene's), and scene.json's camera as a camera node.
"""
import base64
import json
import math
import os
import struct
import sys

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets", "cornell-box")


def main(argv):
    out = argv[1] if len(argv) > 1 else "/tmp/cornell-box.gltf"
    kd, ke, order = {}, {}, []
    cur = None
    for line in open(os.path.join(HERE, "cornell-box.mtl")):
        t = line.split()
        if not t:
            continue
        if t[0] == "newmtl":
            cur = t[1]
            order.append(cur)
        elif t[0] == "Kd":
            kd[cur] = [float(x) for x in t[1:4]]
        elif t[0] == "Ke":
            ke[cur] = [float(x) for x in t[1:4]]
    pos, tris = [], {m: [] for m in order}
    mat = None
    for line in open(os.path.join(HERE, "cornell-box.obj")):
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            pos.append([float(x) for x in t[1:4]])
        elif t[0] == "usemtl":
            mat = t[1]
        elif t[0] == "f":
            f = [int(x.split("/")[0]) for x in t[1:]]
            f = [i - 1 if i > 0 else len(pos) + i for i in f]
            for k in range(1, len(f) - 1):
                tris[mat] += [f[0], f[k], f[k + 1]]
    cam = json.load(open(os.path.join(HERE, "scene.json")))["camera"]

    buf = bytearray()
    views, accessors = [], []

    def add(data, fmt, count, kind, ctype, minmax=None):
        while len(buf) % 4:
            buf.append(0)
        off = len(buf)
        buf.extend(struct.pack("<" + fmt * (len(data)), *data))
        views.append({"buffer": 0, "byteOffset": off, "byteLength": len(buf) - off})
        a = {"bufferView": len(views) - 1, "componentType": ctype, "count": count, "type": kind}
        if minmax:
            a["min"], a["max"] = minmax
        accessors.append(a)
        return len(accessors) - 1

    flat = [c for p in pos for c in p]
    pa = add(flat, "f", len(pos), "VEC3", 5126,
             ([min(p[i] for p in pos) for i in range(3)], [max(p[i] for p in pos) for i in range(3)]))
    prims, materials = [], []
    for m in order:
        if not tris[m]:
            continue
        ia = add(tris[m], "I", len(tris[m]), "SCALAR", 5125)
        prims.append({"attributes": {"POSITION": pa}, "indices": ia, "material": len(materials)})
        g = {"name": m,
             "pbrMetallicRoughness": {"baseColorFactor": kd[m] + [1.0], "metallicFactor": 0.0},
             "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}
        e = ke.get(m)
        if e and max(e) > 0:
            s = max(e)
            g["emissiveFactor"] = [x / s for x in e]
            g["extensions"]["KHR_materials_emissive_strength"] = {"emissiveStrength": s}
        materials.append(g)
    eye = cam["eye"]
    doc = {
        "asset": {"version": "2.0", "generator": "pathview scripts/make_gltf_cornell.py"},
        "extensionsUsed": ["KHR_materials_specular", "KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": eye, "rotation": [0, 1, 0, 0]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": math.radians(cam["fov"]), "znear": 1.0}}],
        "meshes": [{"primitives": prims}],
        "materials": materials,
        "buffers": [{"byteLength": len(buf),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf)).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    with open(out, "w") as fh:
        json.dump(doc, fh, indent=1)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
