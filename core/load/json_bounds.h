// core/load/json_bounds.h: the shape of untrusted JSON text bounded before a parser sees it (issue 41 item 4).
// nlohmann's parse and tinygltf's conversion recurse once per nesting level and allocate per value, so a small file
// nested 200,000 deep overflows the stack, and a file of a few MB of nulls or empty nodes costs GBs. This scan is
// iterative and allocates only its own stack (bounded by max_depth): it walks the text once, checking nesting
// depth, the total count of values and each array's length, and throws a one-line Error naming the file and the
// JSON pointer of the first value past a bound. It does not validate the JSON: text it cannot follow is left for
// the parser to refuse.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pv {

struct JsonBounds {
    size_t max_depth = 64;                // nested arrays/objects; glTF needs < 10, scene files < 8
    size_t max_values = size_t(1) << 23;  // scalars, arrays and objects, object keys not counted
    size_t max_array = size_t(1) << 22;   // the elements of any one array
    // Tighter bounds on the arrays found under these keys of the root object (glTF's top-level lists).
    std::vector<std::pair<std::string, size_t>> root_arrays;
};

// Throws Error("<file>: <pointer>: ...") at the first bound exceeded.
void check_json_bounds(std::string_view text, const std::string& file, const JsonBounds& bounds);

// The bounds for a glTF's JSON: the above, and 2^18 nodes, meshes, accessors, bufferViews, materials, textures,
// images, samplers, cameras, skins, animations, scenes, buffers.
const JsonBounds& gltf_json_bounds();

}  // namespace pv
