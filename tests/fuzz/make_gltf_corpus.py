#!/usr/bin/env python3
"""Writes the seed corpus of the glTF fuzzer (fuzz_gltf) into tests/fuzz/corpus-gltf: small valid files, as .gltf
text with data: URIs and as .glb, that reach every part of the loader (node transforms, accessor types, strides,
sparse accessors, strips and fans, cameras, lights, materials with embedded PNG textures, alpha modes, texture
transforms). Deterministic: run it again and the files are the same.
Usage: tests/fuzz/make_gltf_corpus.py [output folder, default: tests/fuzz/corpus-gltf]
"""
import base64
import json
import os
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "corpus-gltf")
os.makedirs(OUT, exist_ok=True)

FLOAT, UBYTE, BYTE, USHORT, SHORT, UINT = 5126, 5121, 5120, 5123, 5122, 5125


def png(w, h):
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    rgba = bytes((x * 60 + y * 90 + k * 50) & 0xFF if k < 3 else (255 if (x + y) % 2 else 64)
                 for y in range(h) for x in range(w) for k in range(4))
    raw = b"".join(b"\0" + rgba[y * w * 4:(y + 1) * w * 4] for y in range(h))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


class Doc:
    def __init__(self):
        self.j = {"asset": {"version": "2.0"}}
        self.bin = b""

    def view(self, data, stride=0):
        self.bin += b"\0" * (-len(self.bin) % 4)
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride:
            v["byteStride"] = stride
        self.bin += data
        self.j.setdefault("bufferViews", []).append(v)
        return len(self.j["bufferViews"]) - 1

    def acc(self, view, ctype, count, typ, offset=0, normalized=False):
        a = {"componentType": ctype, "count": count, "type": typ}
        if view is not None:
            a["bufferView"] = view
        if offset:
            a["byteOffset"] = offset
        if normalized:
            a["normalized"] = True
        self.j.setdefault("accessors", []).append(a)
        return len(self.j["accessors"]) - 1

    def floats(self, values, typ):
        n = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[typ]
        return self.acc(self.view(struct.pack("<%df" % len(values), *values)), FLOAT, len(values) // n, typ)

    def add(self, key, value):
        self.j.setdefault(key, []).append(value)
        return len(self.j[key]) - 1

    def gltf(self):
        j = dict(self.j)
        j["buffers"] = [{"byteLength": len(self.bin),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(self.bin).decode()}]
        return json.dumps(j, sort_keys=True).encode()

    def glb(self):
        j = dict(self.j)
        j["buffers"] = [{"byteLength": len(self.bin)}]
        js = json.dumps(j, sort_keys=True).encode()
        js += b" " * (-len(js) % 4)
        b = self.bin + b"\0" * (-len(self.bin) % 4)
        return (b"glTF" + struct.pack("<II", 2, 12 + 8 + len(js) + 8 + len(b)) + struct.pack("<II", len(js), 0x4E4F534A)
                + js + struct.pack("<II", len(b), 0x004E4942) + b)


def put(name, doc):
    with open(os.path.join(OUT, name + ".gltf"), "wb") as f:
        f.write(doc.gltf())
    with open(os.path.join(OUT, name + ".glb"), "wb") as f:
        f.write(doc.glb())


def triangle(d, material=None):
    pos = d.floats([0, 0, 0, 1, 0, 0, 0, 1, 0], "VEC3")
    nrm = d.floats([0, 0, 1] * 3, "VEC3")
    uv = d.floats([0, 0, 1, 0, 0, 1], "VEC2")
    p = {"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}}
    if material is not None:
        p["material"] = material
    return d.add("meshes", {"primitives": [p]})


# A triangle under nested nodes (TRS, matrix, a mirror), a camera and a light.
d = Doc()
m = triangle(d)
leaf = d.add("nodes", {"mesh": m, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 2, 1]})
mirror = d.add("nodes", {"mesh": m, "scale": [-1, 1, 1]})
d.j["cameras"] = [{"name": "cam", "type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}]
cam = d.add("nodes", {"camera": 0, "translation": [0, 0, 6]})
d.j["extensionsUsed"] = ["KHR_lights_punctual"]
d.j["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "spot", "color": [1, 0.9, 0.8], "intensity": 5,
                                                          "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}]}}
light = d.add("nodes", {"translation": [0, 3, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}})
root = d.add("nodes", {"rotation": [0, 0.3826834, 0, 0.9238795], "children": [leaf, mirror, cam, light]})
d.j["scenes"] = [{"nodes": [root]}]
d.j["scene"] = 0
put("seed_nodes", d)

# Accessor types: interleaved float positions + normalized ubyte uvs (stride 16), normalized byte normals,
# quantized short positions, 8/16/32-bit indices, a strip, a fan, a sparse accessor, lines.
d = Doc()
inter = b"".join(struct.pack("<3f2B2x", *p, *t) for p, t in
                 zip([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [(0, 0), (255, 0), (255, 255), (0, 255)]))
iv = d.view(inter, 16)
pos = d.acc(iv, FLOAT, 4, "VEC3")
uv = d.acc(iv, UBYTE, 4, "VEC2", 12, True)
nrm = d.acc(d.view(struct.pack("<16b", *([0, 0, 127, 0] * 4)), 4), BYTE, 4, "VEC3", 0, True)
idx8 = d.acc(d.view(bytes([0, 1, 2, 0, 2, 3])), UBYTE, 6, "SCALAR")
qpos = d.acc(d.view(struct.pack("<10h", 0, 0, 0, 100, 0, 0, 0, 100, 0, 0)), SHORT, 3, "VEC3")
idx16 = d.acc(d.view(struct.pack("<3H", 0, 1, 2)), USHORT, 3, "SCALAR")
idx32 = d.acc(d.view(struct.pack("<3I", 2, 1, 0)), UINT, 3, "SCALAR")
strip = d.floats([0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0], "VEC3")
sparse = d.acc(None, FLOAT, 3, "VEC3")
d.j["accessors"][sparse]["sparse"] = {"count": 2, "indices": {"bufferView": d.view(bytes([1, 2])), "componentType": UBYTE},
                                      "values": {"bufferView": d.view(struct.pack("<6f", 1, 0, 0, 0, 1, 0))}}
d.j["meshes"] = [{"primitives": [
    {"attributes": {"POSITION": pos, "NORMAL": nrm, "TEXCOORD_0": uv}, "indices": idx8},
    {"attributes": {"POSITION": qpos}, "indices": idx16},
    {"attributes": {"POSITION": qpos}, "indices": idx32, "mode": 4},
    {"attributes": {"POSITION": strip}, "mode": 5},
    {"attributes": {"POSITION": strip}, "mode": 6},
    {"attributes": {"POSITION": sparse}},
    {"attributes": {"POSITION": strip}, "mode": 1}]}]
d.j["nodes"] = [{"mesh": 0}]
d.j["scenes"] = [{"nodes": [0]}]
d.j["extensionsUsed"] = ["KHR_mesh_quantization"]
put("seed_accessors", d)

# Materials: an embedded PNG as base colour (factor, MASK, texture transform), emission with strength, BLEND,
# transmission, volume, ior, specular.
d = Doc()
img = d.view(png(4, 4))
d.j["images"] = [{"bufferView": img, "mimeType": "image/png"}]
d.j["textures"] = [{"source": 0}]
d.j["materials"] = [
    {"name": "masked", "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": True,
     "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 0.5,
                              "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
                                  "offset": [0.5, 0], "rotation": 0.3, "scale": [2, 2]}}}}},
    {"name": "lamp", "emissiveFactor": [1, 0.8, 0.5], "emissiveTexture": {"index": 0},
     "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 12}}},
    {"name": "glass", "alphaMode": "BLEND", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5], "roughnessFactor": 0},
     "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.45},
                    "KHR_materials_volume": {"thicknessFactor": 0.1, "attenuationColor": [0.9, 0.5, 0.5],
                                             "attenuationDistance": 2},
                    "KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1, 0.9, 0.9]}}}]
d.j["extensionsUsed"] = ["KHR_texture_transform", "KHR_materials_emissive_strength", "KHR_materials_transmission",
                         "KHR_materials_ior", "KHR_materials_volume", "KHR_materials_specular"]
nodes = []
for k in range(3):
    nodes.append(d.add("nodes", {"mesh": triangle(d, k), "translation": [2 * k, 0, 0]}))
d.j["scenes"] = [{"nodes": nodes}]
put("seed_materials", d)
