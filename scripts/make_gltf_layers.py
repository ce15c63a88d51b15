#!/usr/bin/env python3
"""Writes a glTF 2.0 scene of the layers over the metallic-roughness base: KHR_materials_clearcoat and _sheen.

    python3 scripts/make_gltf_layers.py [OUT.gltf]        (default: /tmp/layers.gltf)
    build/pathview view /tmp/layers.gltf

Three rows of four spheres: front, base roughness 0.2, 0.5, 0.8, 1: a red car paint (a red base of metallic
0.3 under a smooth clearcoat, clearcoatFactor 1); middle, a dark blue velvet (base roughness 1, KHR_materials_sheen, sheen colour
(0.9, 0.8, 1), sheen roughness 0.3 to 1 along the row); back, base roughness 0.2 to 1, both (a white clearcoat of roughness 0.3 over a sheen
over a green base). Beside them, a white sphere under a white coat and a white sheen: in a white environment it
disappears (its albedo is 1 everywhere). The floor, light panel, camera, sphere mesh and buffer layout are those of
scripts/make_gltf_showcase.py.
"""
import base64
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_gltf_showcase import Builder, checker_png, quad, sphere  # noqa: E402


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "/tmp/layers.gltf"
    b = Builder()
    sph_attr, sph_idx = b.mesh(sphere())
    quad_attr, quad_idx = b.mesh(quad(1.0, 1.0))
    materials, meshes, nodes = [], [], []

    def add_object(name, material, attr, idx, translation, scale):
        materials.append(dict(material, name=name))
        meshes.append({"name": name, "primitives": [{"attributes": attr, "indices": idx,
                                                     "material": len(materials) - 1}]})
        nodes.append({"name": name, "mesh": len(meshes) - 1, "translation": translation, "scale": [scale] * 3})

    for i, r in enumerate([0.2, 0.5, 0.8, 1.0]):
        x = (i - 1.5) * 0.55
        add_object(f"car paint r{r}",
                   {"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.04, 0.03, 1], "metallicFactor": 0.3,
                                             "roughnessFactor": r},
                    "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                                               "clearcoatRoughnessFactor": 0.0}}},
                   sph_attr, sph_idx, [x, 0.22, 0.6], 0.22)
        add_object(f"velvet sheen r{0.3 + 0.7 * i / 3:.2f}",
                   {"pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.06, 0.25, 1], "metallicFactor": 0.0,
                                             "roughnessFactor": 1.0},
                    "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.8, 1.0],
                                                           "sheenRoughnessFactor": 0.3 + 0.7 * i / 3}}},
                   sph_attr, sph_idx, [x, 0.22, 0.05], 0.22)
        add_object(f"coat and sheen r{r}",
                   {"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.45, 0.15, 1], "metallicFactor": 0.0,
                                             "roughnessFactor": r},
                    "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                                               "clearcoatRoughnessFactor": 0.3},
                                   "KHR_materials_sheen": {"sheenColorFactor": [1.0, 0.9, 0.6],
                                                           "sheenRoughnessFactor": 0.5}}},
                   sph_attr, sph_idx, [x, 0.22, -0.5], 0.22)
    add_object("white coat and sheen",
               {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0,
                                         "roughnessFactor": 0.5},
                "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.2},
                               "KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.5}}},
               sph_attr, sph_idx, [1.45, 0.3, 0.3], 0.3)
    add_object("floor", {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {
        "KHR_texture_transform": {"scale": [4.0, 4.0]}}}, "metallicFactor": 0.0, "roughnessFactor": 0.6}},
               quad_attr, quad_idx, [0, 0, 0], 4.0)
    add_object("panel", {"pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                         "emissiveFactor": [1.0, 0.95, 0.85],
                         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 6.0}}},
               quad_attr, quad_idx, [0.0, 1.9, 0.2], 1.2)
    nodes[-1]["rotation"] = [1.0, 0.0, 0.0, 0.0]  # facing down
    tilt = -0.42
    nodes.append({"name": "front", "camera": 0, "translation": [0.3, 1.9, 4.4],
                  "rotation": [math.sin(tilt / 2), 0.0, 0.0, math.cos(tilt / 2)]})
    gltf = {
        "asset": {"version": "2.0", "generator": "pathview scripts/make_gltf_layers.py"},
        "extensionsUsed": ["KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_emissive_strength",
                           "KHR_texture_transform"],
        "scene": 0,
        "scenes": [{"name": "layers", "nodes": list(range(len(nodes)))}],
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
    with open(out, "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    print(f"wrote {out} ({len(b.buf)} bytes of buffers)")


if __name__ == "__main__":
    main()
