#!/bin/bash
# scripts/make_compressed_showcase.sh: writes assets/compressed-instanced/scene.glb, the compressed + instanced
# showcase (`pathview bench compressed-instanced`, `pathview view assets/compressed-instanced/scene.glb`): the bumpy
# sphere of tests/data/gltf-compressed (960 triangles) placed by 400 nodes on a 20 x 20 grid with varied scales over
# a ground plane, a camera and a sun, run through gltfpack -c (EXT_meshopt_compression + KHR_mesh_quantization:
# the nodes keep sharing one mesh). Needs gltfpack (the Makefile's PACKAGES).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=$here/../assets/compressed-instanced
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$here/../tests/data/gltf-compressed/original.bin" "$tmp/"
python3 - "$here/../tests/data/gltf-compressed/original.gltf" "$tmp/instanced.gltf" <<'PY'
import base64, json, math, struct, sys
g = json.load(open(sys.argv[1]))
# A ground plane: 4 vertices (position, normal, uv) in its own data: URI buffer.
pos = [-40, 0, -40, 40, 0, -40, 40, 0, 40, -40, 0, 40]
nrm = [0, 1, 0] * 4
uv = [0, 0, 1, 0, 1, 1, 0, 1]
idx = [0, 2, 1, 0, 3, 2]
data = struct.pack("<12f", *pos) + struct.pack("<12f", *nrm) + struct.pack("<8f", *uv) + struct.pack("<6I", *idx)
g["buffers"].append({"uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode(),
                     "byteLength": len(data)})
b = len(g["buffers"]) - 1
v0 = len(g["bufferViews"])
g["bufferViews"] += [{"buffer": b, "byteOffset": 0, "byteLength": 48}, {"buffer": b, "byteOffset": 48, "byteLength": 48},
                     {"buffer": b, "byteOffset": 96, "byteLength": 32}, {"buffer": b, "byteOffset": 128, "byteLength": 24}]
a0 = len(g["accessors"])
g["accessors"] += [{"bufferView": v0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-40, 0, -40], "max": [40, 0, 40]},
                   {"bufferView": v0 + 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                   {"bufferView": v0 + 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                   {"bufferView": v0 + 3, "componentType": 5125, "count": 6, "type": "SCALAR"}]
g["materials"].append({"pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.62, 1], "metallicFactor": 0, "roughnessFactor": 0.8}})
g["meshes"].append({"primitives": [{"attributes": {"POSITION": a0, "NORMAL": a0 + 1, "TEXCOORD_0": a0 + 2},
                                    "indices": a0 + 3, "material": len(g["materials"]) - 1}]})
nodes = [{"mesh": 1, "name": "ground"}]
n = 20
for i in range(n):
    for j in range(n):
        s = 0.35 + 0.25 * (0.5 + 0.5 * math.sin(1.7 * i + 2.3 * j))
        nodes.append({"mesh": 0, "translation": [(i - (n - 1) / 2) * 1.6, s * 1.15, (j - (n - 1) / 2) * 1.6],
                      "scale": [s, s, s], "name": "sphere_%d_%d" % (i, j)})
t = math.radians(-22)
nodes.append({"camera": 0, "translation": [0, 12, 30], "rotation": [math.sin(t / 2), 0, 0, math.cos(t / 2)], "name": "camera"})
r = math.radians(-50)
nodes.append({"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": [math.sin(r / 2), 0.3, 0, math.cos(r / 2)], "name": "sun"})
g["nodes"] = nodes
g["scenes"] = [{"nodes": list(range(len(nodes)))}]
g["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1, "aspectRatio": 1.5}}]
g["extensionsUsed"] = ["KHR_lights_punctual"]
g["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 3, "color": [1, 0.95, 0.85]}]}}
json.dump(g, open(sys.argv[2], "w"))
PY
gltfpack -i "$tmp/instanced.gltf" -o "$out/scene.glb" -c -kn
ls -l "$out"
