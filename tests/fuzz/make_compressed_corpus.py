#!/usr/bin/env python3
"""Writes the seed corpora of the decompressor fuzzers from tests/data/gltf-compressed (scripts/make_compressed_gltf.sh):
tests/fuzz/corpus-draco: the Draco stream of draco.gltf (fuzz_draco wraps its input in a .glb);
tests/fuzz/corpus-meshopt: each compressed buffer view of meshopt.gltf as fuzz_meshopt reads its input: 5 bytes (mode,
filter, byteStride, count as 16 bits little-endian), then the compressed stream.
Deterministic: run it again and the files are the same.
Usage: tests/fuzz/make_compressed_corpus.py
"""
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "data", "gltf-compressed")
MODES = ["ATTRIBUTES", "TRIANGLES", "INDICES"]
FILTERS = ["NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"]

os.makedirs(os.path.join(HERE, "corpus-draco"), exist_ok=True)
os.makedirs(os.path.join(HERE, "corpus-meshopt"), exist_ok=True)
with open(os.path.join(DATA, "draco.bin"), "rb") as f:
    draco = f.read()
with open(os.path.join(HERE, "corpus-draco", "seed_draco.bin"), "wb") as f:
    f.write(draco)

with open(os.path.join(DATA, "meshopt.gltf")) as f:
    gltf = json.load(f)
with open(os.path.join(DATA, "meshopt.bin"), "rb") as f:
    bin_data = f.read()
for i, view in enumerate(gltf["bufferViews"]):
    e = view.get("extensions", {}).get("EXT_meshopt_compression")
    if not e:
        continue
    start = e.get("byteOffset", 0)
    stream = bin_data[start:start + e["byteLength"]]
    header = struct.pack("<BBBH", MODES.index(e["mode"]), FILTERS.index(e.get("filter", "NONE")), e["byteStride"],
                         e["count"])
    with open(os.path.join(HERE, "corpus-meshopt", "seed_view%d.bin" % i), "wb") as f:
        f.write(header + stream)
