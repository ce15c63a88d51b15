// core/scene_file.cpp: JSON scene files (nlohmann-json) on top of the OBJ loader.
#include "core/scene_file.h"

#include "core/environment.h"
#include "core/error.h"
#include "core/image_io.h"
#include "core/obj_loader.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace pv {
namespace {

using nlohmann::json;

void use_default_sky_if_unlit(Scene& scene, bool lighting_given);

vec3 read_vec3(const json& j, const std::string& file, const char* key) {
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
        throw Error(file + ": \"" + key + "\" must be an array of 3 numbers");
    const vec3 v(j[0].get<float>(), j[1].get<float>(), j[2].get<float>());
    if (!is_finite(v)) throw Error(file + ": \"" + key + "\" must be finite");
    return v;
}

float read_float(const json& j, const std::string& file, const char* key) {
    if (!j.is_number()) throw Error(file + ": \"" + key + "\" must be a number");
    const float v = j.get<float>();
    if (!std::isfinite(v)) throw Error(file + ": \"" + key + "\" must be finite");
    return v;
}

// A camera object; keys it lacks keep the values of `base`.
CameraDesc read_camera(const json& c, const std::string& file, CameraDesc base) {
    if (!c.is_object()) throw Error(file + ": a camera must be an object");
    if (c.contains("eye")) base.eye = read_vec3(c["eye"], file, "eye");
    if (c.contains("target")) base.target = read_vec3(c["target"], file, "target");
    if (c.contains("up")) base.up = read_vec3(c["up"], file, "up");
    if (c.contains("fov")) base.vfov_deg = read_float(c["fov"], file, "fov");
    if (c.contains("aperture")) base.aperture = read_float(c["aperture"], file, "aperture");
    if (c.contains("focus_distance")) base.focus_distance = read_float(c["focus_distance"], file, "focus_distance");
    return base;
}

json camera_json(const CameraDesc& c) {
    return json{{"eye", {c.eye.x, c.eye.y, c.eye.z}},
                {"target", {c.target.x, c.target.y, c.target.z}},
                {"up", {c.up.x, c.up.y, c.up.z}},
                {"fov", c.vfov_deg},
                {"aperture", c.aperture},
                {"focus_distance", c.focus_distance}};
}

// Applies a material override: the "type" chooses the BSDF, other keys set its parameters.
void apply_override(Material& m, const json& o, const std::string& file) {
    vec3 base(0.8f), spec(0.04f);
    float rough = 0.2f, ior = 1.5f;
    if (auto* l = std::get_if<Lambertian>(&m.bsdf)) base = l->albedo;
    if (auto* g = std::get_if<Glossy>(&m.bsdf)) base = g->diffuse, spec = g->specular, rough = g->alpha;
    if (auto* r = std::get_if<Mirror>(&m.bsdf)) spec = r->reflectance;
    if (auto* d = std::get_if<Dielectric>(&m.bsdf)) ior = d->eta;
    std::string type = bsdf_type_name(m.bsdf);
    if (o.contains("type")) type = o["type"].get<std::string>();
    if (o.contains("base_color")) base = glm::clamp(read_vec3(o["base_color"], file, "base_color"), 0.f, 1.f);
    if (o.contains("specular")) spec = glm::clamp(read_vec3(o["specular"], file, "specular"), 0.f, 1.f);
    if (o.contains("roughness")) rough = glm::clamp(read_float(o["roughness"], file, "roughness"), kMinAlpha, 1.f);
    if (o.contains("ior")) ior = read_float(o["ior"], file, "ior");
    if (o.contains("emission")) m.emission = glm::max(read_vec3(o["emission"], file, "emission"), vec3(0.f));
    if (type == "diffuse") m.bsdf = Lambertian{base};
    else if (type == "glossy") m.bsdf = Glossy{base, spec, rough};
    else if (type == "mirror") m.bsdf = Mirror{spec};
    else if (type == "glass") {
        if (!(ior > 0.f)) throw Error(file + ": material '" + m.name + "': ior must be positive");
        m.bsdf = Dielectric{ior};
    } else
        throw Error(file + ": material '" + m.name + "': unknown type '" + type +
                    "'; expected diffuse, glossy, mirror or glass");
}

Scene load_json(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot open for reading");
    json j;
    try {
        j = json::parse(in);
    } catch (const json::exception& e) {
        throw Error(path + ": invalid JSON: " + e.what());
    }
    if (!j.is_object() || !j.contains("obj") || !j["obj"].is_string())
        throw Error(path + ": expected an object with an \"obj\" file name");
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    ObjOptions opts;
    if (j.contains("two_sided_emitters")) opts.two_sided_emission = j["two_sided_emitters"].get<bool>();
    Scene scene = load_obj((dir / j["obj"].get<std::string>()).string(), opts);
    scene.source = path;
    try {
        if (j.contains("background")) scene.background = glm::max(read_vec3(j["background"], path, "background"), vec3(0.f));
        scene.camera = scene.framing_camera();
        if (j.contains("camera")) {
            scene.camera = read_camera(j["camera"], path, scene.camera);
            scene.has_camera = true;
        }
        if (j.contains("bookmarks")) {
            if (!j["bookmarks"].is_array()) throw Error(path + ": \"bookmarks\" must be an array");
            for (const json& b : j["bookmarks"]) {
                Scene::Bookmark bm{b.value("name", std::string("view ") + std::to_string(scene.bookmarks.size() + 1)),
                                   read_camera(b, path, scene.camera)};
                scene.bookmarks.push_back(std::move(bm));
            }
        }
        if (j.contains("environment")) {
            const json& e = j["environment"];
            if (e.contains("map")) {
                const std::string map = e["map"].get<std::string>();
                set_environment(scene, map == "sky" ? map : (dir / map).string());  // "sky": the default sky
            }
            if (e.contains("color")) scene.background = glm::max(read_vec3(e["color"], path, "color"), vec3(0.f));
            if (e.contains("rotation")) scene.environment_rotation_deg = read_float(e["rotation"], path, "rotation");
            if (e.contains("strength")) scene.environment_strength = read_float(e["strength"], path, "strength");
        }
        if (j.contains("sun")) {
            const json& sun = j["sun"];
            if (sun.contains("direction")) scene.sun_direction = read_vec3(sun["direction"], path, "direction");
            if (sun.contains("angular_radius"))
                scene.sun_angular_radius_deg = read_float(sun["angular_radius"], path, "angular_radius");
            if (sun.contains("irradiance")) {
                const json& e = sun["irradiance"];
                scene.sun_irradiance =
                    glm::max(e.is_number() ? vec3(read_float(e, path, "irradiance")) : read_vec3(e, path, "irradiance"),
                             vec3(0.f));
            }
        }
        if (j.contains("materials")) {
            for (const auto& [name, o] : j["materials"].items()) {
                bool found = false;
                for (Material& m : scene.materials)
                    if (m.name == name) {
                        apply_override(m, o, path);
                        found = true;
                    }
                if (!found) scene.warnings.push_back(path + ": material override '" + name + "' matches no material");
            }
        }
    } catch (const json::exception& e) {
        throw Error(path + ": " + e.what());
    }
    use_default_sky_if_unlit(scene, j.contains("background") || j.contains("environment") || j.contains("sun"));
    return scene;
}


void use_default_sky_if_unlit(Scene& scene, bool lighting_given) {
    if (lighting_given || scene.has_emitters() || scene.triangles.empty()) return;
    set_environment(scene, "sky");
    scene.default_sky_warning = scene.warnings.size();
    scene.warnings.push_back(scene.source +
                             ": the scene has no emitter; lit by the default sky (--environment overrides)");
}

}  // namespace

std::string save_bookmark(const std::string& path, const std::string& name, const CameraDesc& camera) {
    namespace fs = std::filesystem;
    const std::string ext = fs::path(path).extension().string();
    const bool is_json = ext == ".json" || ext == ".JSON";
    const std::string out = is_json ? path : path + ".json";
    json j = json::object();
    std::error_code ec;
    if (fs::exists(out, ec)) {
        std::ifstream in(out);
        try {
            j = json::parse(in);
        } catch (const json::exception& e) {
            throw Error(out + ": cannot add a bookmark: invalid JSON: " + e.what());
        }
    }
    if (!is_json && !j.contains("obj")) j["obj"] = fs::path(path).filename().string();
    json& list = j["bookmarks"];
    if (!list.is_array()) list = json::array();
    json entry = camera_json(camera);
    entry["name"] = name;
    bool replaced = false;
    for (json& b : list)
        if (b.value("name", std::string()) == name) {
            b = entry;
            replaced = true;
        }
    if (!replaced) list.push_back(entry);
    const std::string tmp = out + ".tmp." + std::to_string(static_cast<long>(::getpid()));
    {
        std::ofstream f(tmp);
        f << j.dump(2) << "\n";
        if (!f) {
            fs::remove(tmp, ec);
            throw Error(out + ": cannot write the bookmark (permission denied or disk full?)");
        }
    }
    fs::rename(tmp, out, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw Error(out + ": cannot write the bookmark: " + ec.message());
    }
    return out;
}

const CameraDesc& find_bookmark(const Scene& scene, const std::string& name) {
    std::string names;
    for (const Scene::Bookmark& b : scene.bookmarks) {
        if (b.name == name) return b.camera;
        names += (names.empty() ? "" : ", ") + b.name;
    }
    throw Error(scene.source + ": no bookmark '" + name + "'; the scene has: " + (names.empty() ? "none" : names));
}

void set_environment(Scene& scene, const std::string& spec) {
    // A colour: "r,g,b" or a single number.
    std::vector<float> values;
    {
        size_t pos = 0;
        bool numeric = !spec.empty();
        while (numeric && pos <= spec.size()) {
            const size_t comma = std::min(spec.find(',', pos), spec.size());
            const std::string part = spec.substr(pos, comma - pos);
            char* end = nullptr;
            const float v = std::strtof(part.c_str(), &end);
            if (part.empty() || end != part.c_str() + part.size()) numeric = false;
            else values.push_back(v);
            pos = comma + 1;
        }
        if (!numeric) values.clear();
    }
    if (values.size() == 1 || values.size() == 3) {
        const vec3 c = values.size() == 1 ? vec3(values[0]) : vec3(values[0], values[1], values[2]);
        if (!is_finite(c) || c.x < 0.f || c.y < 0.f || c.z < 0.f)
            throw Error("--environment " + spec + ": a colour must be finite and non-negative");
        scene.background = c;
        scene.environment_map = kNoIndex;
        return;
    }
    Texture map;
    if (spec == "sky") {
        map = make_default_sky();
    } else {
        const std::string ext = std::filesystem::path(spec).extension().string();
        if (ext == ".exr" || ext == ".EXR") {
            const Image img = read_exr(spec);
            std::vector<vec4> texels(size_t(img.width) * size_t(img.height));
            for (size_t i = 0; i < texels.size(); ++i) {
                const vec3 c(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]);
                texels[i] = vec4(is_finite(c) ? glm::max(c, vec3(0.f)) : vec3(0.f), 1.f);
            }
            map = Texture(img.width, img.height, std::move(texels));
        } else {
            std::error_code ec;
            if (!std::filesystem::is_regular_file(spec, ec))
                throw Error(spec + ": no such file; expected an environment map (.exr, .hdr, .png) or r,g,b");
            map = Texture::load(spec);
        }
    }
    scene.textures.push_back(std::move(map));
    scene.environment_map = static_cast<uint32_t>(scene.textures.size() - 1);
}

Scene load_scene(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".json" || ext == ".JSON") return load_json(path);
    if (ext == ".obj" || ext == ".OBJ") {
        Scene scene = load_obj(path);
        scene.camera = scene.framing_camera();
        use_default_sky_if_unlit(scene, false);
        return scene;
    }
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(path + ": no such file; expected a .json scene or an .obj");
    throw Error(path + ": unknown scene format '" + ext + "'; expected .json or .obj");
}

}  // namespace pv
