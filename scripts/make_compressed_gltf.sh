#!/bin/bash
# scripts/make_compressed_gltf.sh: regenerates tests/data/gltf-compressed (tests/load/test_gltf_compressed.cpp):
#   original.gltf/.bin   the test mesh, uncompressed floats (scripts/make_compressed_gltf.cpp)
#   draco.gltf/.bin      KHR_draco_mesh_compression through Draco's encoder API (positions 14 bits, normals 10, uvs 12)
#   quantized.gltf/.bin  KHR_mesh_quantization as gltfpack writes it (integer positions, 14 bits; normals 8; uvs 12)
#   quantized_vpn.gltf   the same with normalized positions (gltfpack -vpn)
#   meshopt.gltf/.bin    EXT_meshopt_compression + KHR_mesh_quantization (gltfpack -c), and meshopt.glb the same
# Needs Debian's libdraco-dev and gltfpack (the Makefile's PACKAGES).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$here/../tests/data/gltf-compressed}
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
g++ -std=c++17 -O1 -o "$tmp/make_compressed_gltf" "$here/make_compressed_gltf.cpp" -ldraco
"$tmp/make_compressed_gltf" "$out"
cd "$out"
gltfpack -i original.gltf -o quantized.gltf
gltfpack -i original.gltf -o quantized_vpn.gltf -vpn
gltfpack -i original.gltf -o meshopt.gltf -c
gltfpack -i original.gltf -o meshopt.glb -c
ls -l "$out"
