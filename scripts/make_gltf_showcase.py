#!/usr/bin/env python3
"""Writes assets/gltf-showcase/showcase.gltf: glTF 2.0's metallic-roughness model in one small scene.

Two rows of spheres over roughness 0, 0.25, 0.5, 0.75, 1 (front: dielectric, metallic 0; back: gold metal,
metallic 1), a glass sphere (KHR_materials_transmission + KHR_materials_volume, tinted by Beer-Lambert
attenuation), a checker-textured floor (baseColorTexture, an embedded PNG), an emissive panel
(KHR_materials_emissive_strength) and a camera. Geometry, the texture and everything else are generated here, so
the file is reproducible: python3 scripts/make_gltf_showcase.py
"""
import base64
import json
import math
import os
import struct
import zlib

OUT = os.path.join(os.path.dirname(__file__), "..", "assets", "gltf-showcase", "showcase.gltf")


def sphere(rings=24, segments=48):
    pos, nrm, uv, idx = [], [], [], []
    for r in range(rings + 1):
        th = math.pi * r / rings
        for s in range(segments + 1):
            ph = 2 * math.pi * s / segments
            n = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            pos.append(n)
            nrm.append(n)
            uv.append((s / segments, r / rings))
    for r in range(rings):
        for s in range(segments):
            a = r * (segments + 1) + s
            b = a + segments + 1
            if r != 0:
                idx += [a, a + 1, b]
            if r != rings - 1:
                idx += [a + 1, b + 1, b]
    return pos, nrm, uv, idx


def quad(size, uv_scale):
    h = size / 2
    pos = [(-h, 0, -h), (h, 0, -h), (h, 0, h), (-h, 0, h)]
    nrm = [(0, 1, 0)] * 4
    uv = [(0, 0), (uv_scale, 0), (uv_scale, uv_scale), (0, uv_scale)]
    return pos, nrm, uv, [0, 2, 1, 0, 3, 2]


def checker_png(n=64, cells=8):
    rows = b""
    for y in range(n):
        row = bytearray([0])
        for x in range(n):
            light = ((x * cells // n) + (y * cells // n)) % 2 == 0
            row += bytes((200, 200, 200) if light else (60, 70, 85))
        rows += bytes(row)

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", n, n, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


class Builder:
    def __init__(self):
        self.buf = bytearray()
        self.views, self.accessors = [], []

    def add(self, data, fmt, count, kind, comp, target, minmax=None):
        while len(self.buf) % 4:
            self.buf.append(0)
        offset = len(self.buf)
        self.buf += struct.pack("<" + fmt * 1, *data) if False else b"".join(struct.pack("<" + fmt, *d) for d in data)
        self.views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(self.buf) - offset, "target": target})
        acc = {"bufferView": len(self.views) - 1, "componentType": comp, "count": count, "type": kind}
        if minmax:
            acc["min"], acc["max"] = minmax
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def mesh(self, geo):
        pos, nrm, uv, idx = geo
        lo = [min(p[i] for p in pos) for i in range(3)]
        hi = [max(p[i] for p in pos) for i in range(3)]
        return {
            "POSITION": self.add(pos, "3f", len(pos), "VEC3", 5126, 34962, (lo, hi)),
            "NORMAL": self.add(nrm, "3f", len(nrm), "VEC3", 5126, 34962),
            "TEXCOORD_0": self.add(uv, "2f", len(uv), "VEC2", 5126, 34962),
        }, self.add([(i,) for i in idx], "I", len(idx), "SCALAR", 5125, 34963)


def main():
    b = Builder()
    sph_attr, sph_idx = b.mesh(sphere())
    quad_attr, quad_idx = b.mesh(quad(1.0, 1.0))
    materials, meshes, nodes = [], [], []

    def add_object(name, material, attr, idx, translation, scale):
        materials.append(dict(material, name=name))
        meshes.append({"name": name, "primitives": [{"attributes": attr, "indices": idx,
                                                     "material": len(materials) - 1}]})
        nodes.append({"name": name, "mesh": len(meshes) - 1, "translation": translation, "scale": [scale] * 3})

    roughness = [0.0, 0.25, 0.5, 0.75, 1.0]
    for i, r in enumerate(roughness):
        x = (i - 2) * 0.55
        add_object(f"dielectric r{r}", {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.08, 1],
                                                                  "metallicFactor": 0.0, "roughnessFactor": r}},
                   sph_attr, sph_idx, [x, 0.22, 0.35], 0.22)
        add_object(f"gold r{r}", {"pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.78, 0.34, 1],
                                                            "metallicFactor": 1.0, "roughnessFactor": r}},
                   sph_attr, sph_idx, [x, 0.22, -0.25], 0.22)
    add_object("glass", {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0,
                                                  "roughnessFactor": 0.0},
                         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                        "KHR_materials_volume": {"thicknessFactor": 0.6,
                                                                 "attenuationColor": [0.55, 0.85, 0.75],
                                                                 "attenuationDistance": 0.5}}},
               sph_attr, sph_idx, [0.75, 0.25, 1.05], 0.25)
    add_object("floor", {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0,
                                                  "roughnessFactor": 0.6}},
               quad_attr, quad_idx, [0, 0, 0], 4.0)
    # The panel faces down (-y) over the spheres: its quad is turned over by a rotation of pi about x.
    add_object("panel", {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                         "emissiveFactor": [1.0, 0.95, 0.85],
                         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 6.0}}},
               quad_attr, quad_idx, [0.0, 1.9, 0.2], 1.2)
    nodes[-1]["rotation"] = [1.0, 0.0, 0.0, 0.0]
    # The camera looks from +z, slightly above, toward the grid's centre (-z is a glTF camera's forward).
    tilt = -0.42
    nodes.append({"name": "front", "camera": 0, "translation": [0.0, 1.55, 3.2],
                  "rotation": [math.sin(tilt / 2), 0.0, 0.0, math.cos(tilt / 2)]})
    gltf = {
        "asset": {"version": "2.0", "generator": "pathview scripts/make_gltf_showcase.py"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"name": "showcase", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "cameras": [{"name": "front", "type": "perspective", "perspective": {"yfov": 0.62, "znear": 0.01,
                                                                              "aspectRatio": 1.5}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(checker_png()).decode()}],
        "buffers": [{"byteLength": len(b.buf),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(b.buf)).decode()}],
        "bufferViews": b.views,
        "accessors": b.accessors,
    }
    # The floor's texture repeats: its uvs span [0, 1] over 4 m, so scale them to 8 checker tiles per metre.
    for m in materials:
        if m["name"] == "floor":
            m["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
                "KHR_texture_transform": {"scale": [4.0, 4.0]}}
    gltf["extensionsUsed"].append("KHR_texture_transform")
    os.makedirs(os.path.dirname(OUT), exist_ok=True)
    with open(OUT, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    print(f"wrote {os.path.normpath(OUT)} ({len(b.buf)} bytes of buffers)")


if __name__ == "__main__":
    main()
