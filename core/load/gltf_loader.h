// core/load/gltf_loader.h: glTF 2.0 import (.gltf + .bin + images, or one .glb) through tinygltf, with the checks
// tinygltf lacks (below the includes, with what is read).
#pragma once

#include <string>

#include "core/scene/scene.h"

// The checks tinygltf lacks: every accessor, buffer view and index is bounds-checked before a byte is read, images are
// decoded by Texture::decode (the guarded stb/OpenEXR path and its memory budget), external files are regular files of
// bounded size, and the node hierarchy may not contain a cycle. Errors (pv::Error, one line) name the file and the
// JSON pointer of what is wrong: "scene.gltf: /accessors/3: reads bytes 0..96 of bufferView 1, which has 64".
//
// What is read: the default scene's (else the first scene's) node hierarchy with TRS or matrix transforms (normals
// by the inverse transpose; a negative determinant flips the winding so that the front face stays
// counter-clockwise), mesh primitives of mode TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN (points and lines are
// skipped with one warning), accessors of every component type (normalized integers as the specification maps
// them), byteStride, sparse accessors, data: URIs, external files, a .glb's embedded buffer and images,
// POSITION, NORMAL, TEXCOORD_0, TEXCOORD_1 and COLOR_0 (Scene::colors). Cameras: the first perspective camera met in
// the default scene is the start view (its yfov; pathview's own aspect), and every camera a node places is a bookmark
// named after the camera (else its node). KHR_lights_punctual lights fill Scene::punctual_lights. A file whose
// extensionsRequired names an extension pathview does not read is refused naming it; an extension only used and not
// read gets one warning. Materials: see core/load/gltf_materials.cpp and README (metallic-roughness, emission,
// alpha modes).

namespace pv {

// Loads a .gltf or .glb file (told by its first four bytes: "glTF" is binary). The camera is the file's first
// perspective camera (Scene::has_camera) or, without one, framing_camera(). Throws pv::Error as above.
Scene load_gltf(const std::string& path);
// The same from a file's bytes in memory; `name` names it in messages and its folder is where external files
// (.bin, images) are looked for. For tests and the fuzzer.
Scene load_gltf_from_memory(const std::string& bytes, const std::string& name);
// True if `path`'s extension is .gltf or .glb (any letter case).
bool is_gltf_path(const std::string& path);

}  // namespace pv
