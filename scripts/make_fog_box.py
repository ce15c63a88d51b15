#!/usr/bin/env python3
"""Writes assets/fog-box: the built-in Cornell box (as glTF, by make_gltf_cornell.py) filled with fog, lit by its
ceiling light and a point lamp hanging inside (KHR_lights_punctual), for `pathview bench fog-box` and the media docs
(docs/media.md). The fog scatters about one event across the box (sigma_t x 556 = 0.83) and mostly forward.

    python3 scripts/make_fog_box.py            (run from the repository root)
"""
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "assets", "fog-box")
sys.path.insert(0, HERE)
import make_gltf_cornell  # noqa: E402


def main():
    os.makedirs(OUT, exist_ok=True)
    gltf = os.path.join(OUT, "fog-box.gltf")
    make_gltf_cornell.main(["make_gltf_cornell.py", gltf])
    doc = json.load(open(gltf))
    doc["asset"]["generator"] = "pathview scripts/make_fog_box.py"
    doc["extensionsUsed"].append("KHR_lights_punctual")
    # A warm lamp of 40000 (intensity per steradian, scene units) 150 below the ceiling, left of centre.
    doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "point", "name": "lamp", "color": [1.0, 0.85, 0.6], "intensity": 40000.0}]}}
    doc["nodes"].append({"name": "lamp", "translation": [200.0, 400.0, 250.0],
                         "extensions": {"KHR_lights_punctual": {"light": 0}}})
    doc["scenes"][0]["nodes"].append(len(doc["nodes"]) - 1)
    with open(gltf, "w") as fh:
        json.dump(doc, fh, indent=1)
    cam = json.load(open(os.path.join(HERE, "..", "assets", "cornell-box", "scene.json")))["camera"]
    scene = {
        "obj": "fog-box.gltf",
        "camera": cam,
        "fog": {"sigma_s": 0.0012, "sigma_a": 0.0003, "g": 0.3},
    }
    with open(os.path.join(OUT, "scene.json"), "w") as fh:
        json.dump(scene, fh, indent=2)
        fh.write("\n")
    print(os.path.join(OUT, "scene.json"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
