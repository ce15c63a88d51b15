// core/load/json_bounds.cpp: see json_bounds.h.
#include "core/load/json_bounds.h"

#include <algorithm>

#include "core/base/error.h"

namespace pv {
namespace {

struct Frame {
    bool array = false;
    bool expect_key = false;  // objects: the next string is a key
    size_t count = 0;         // values begun in this container
    size_t limit = 0;         // arrays: the most elements allowed
    std::string_view key;     // objects: the current member's key (raw, escapes as written)
};

// RFC 6901: '~' as ~0, '/' as ~1; the key's JSON escapes are left as written (enough to find the place).
void append_token(std::string& out, std::string_view key) {
    for (char c : key) {
        if (c == '~')
            out += "~0";
        else if (c == '/')
            out += "~1";
        else
            out += c;
    }
}

std::string pointer(const std::vector<Frame>& stack) {
    std::string p;
    for (const Frame& f : stack) {
        if (p.size() > 200) return p + "/...";
        p += '/';
        if (f.array)
            p += std::to_string(f.count == 0 ? 0 : f.count - 1);
        else
            append_token(p, f.key);
    }
    return p.empty() ? "/" : p;
}

}  // namespace

void check_json_bounds(const std::string_view text, const std::string& file, const JsonBounds& b) {
    std::vector<Frame> stack;
    stack.reserve(b.max_depth + 1);
    size_t values = 0;
    const size_t n = text.size();
    auto fail = [&](const std::string& what) { throw Error(file + ": " + pointer(stack) + ": " + what); };
    // A value begins here (not an object key): count it, and its place in its container.
    auto begin_value = [&]() {
        if (++values > b.max_values) fail("more than " + std::to_string(b.max_values) + " JSON values in the file");
        if (stack.empty()) return;
        Frame& f = stack.back();
        if (f.array) {
            ++f.count;
            if (f.count > f.limit) fail("an array of more than " + std::to_string(f.limit) + " elements");
        }
    };
    size_t i = 0;
    while (i < n) {
        const char c = text[i];
        switch (c) {
            case ' ':
            case '\t':
            case '\n':
            case '\r':
            case ',':
                if (c == ',' && !stack.empty() && !stack.back().array) stack.back().expect_key = true;
                ++i;
                break;
            case ':':
                if (!stack.empty()) stack.back().expect_key = false;
                ++i;
                break;
            case '[':
            case '{': {
                begin_value();
                Frame f;
                f.array = c == '[';
                f.expect_key = !f.array;
                f.limit = b.max_array;
                if (f.array && stack.size() == 1 && !stack[0].array)
                    for (const auto& [key, limit] : b.root_arrays)
                        if (stack[0].key == key) f.limit = std::min(limit, b.max_array);
                if (stack.size() >= b.max_depth)
                    fail("JSON nested more than " + std::to_string(b.max_depth) + " levels deep");
                stack.push_back(f);
                ++i;
                break;
            }
            case ']':
            case '}':
                if (stack.empty()) return;  // unbalanced: the parser's to report
                stack.pop_back();
                ++i;
                break;
            case '"': {
                const size_t start = ++i;
                while (i < n && text[i] != '"') i += text[i] == '\\' ? 2 : 1;
                if (i >= n) return;  // unterminated: the parser's to report
                const std::string_view s = text.substr(start, i - start);
                ++i;
                if (!stack.empty() && !stack.back().array && stack.back().expect_key) {
                    stack.back().key = s;
                    stack.back().expect_key = false;
                } else {
                    begin_value();
                }
                break;
            }
            default:  // a number, true, false, null (or text the parser will refuse)
                begin_value();
                while (i < n && text[i] != ',' && text[i] != ']' && text[i] != '}' && text[i] != ' ' &&
                       text[i] != '\n' && text[i] != '\r' && text[i] != '\t' && text[i] != ':')
                    ++i;
                if (i < n && text[i] == ':') ++i;  // never stall on stray text
                break;
        }
    }
}

const JsonBounds& gltf_json_bounds() {
    static const JsonBounds bounds = [] {
        JsonBounds b;
        constexpr size_t kElements = size_t(1) << 18;
        for (const char* key : {"nodes", "meshes", "accessors", "bufferViews", "materials", "textures", "images",
                                "samplers", "cameras", "skins", "animations", "scenes", "buffers"})
            b.root_arrays.emplace_back(key, kElements);
        return b;
    }();
    return bounds;
}

}  // namespace pv
