// core/scene_file.cpp: JSON scene files (nlohmann-json) on top of the OBJ loader.
#include "core/scene_file.h"

#include "core/error.h"
#include "core/obj_loader.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace pv {
namespace {

using nlohmann::json;

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
            const json& c = j["camera"];
            if (c.contains("eye")) scene.camera.eye = read_vec3(c["eye"], path, "eye");
            if (c.contains("target")) scene.camera.target = read_vec3(c["target"], path, "target");
            if (c.contains("up")) scene.camera.up = read_vec3(c["up"], path, "up");
            if (c.contains("fov")) scene.camera.vfov_deg = read_float(c["fov"], path, "fov");
            if (c.contains("aperture")) scene.camera.aperture = read_float(c["aperture"], path, "aperture");
            if (c.contains("focus_distance"))
                scene.camera.focus_distance = read_float(c["focus_distance"], path, "focus_distance");
            scene.has_camera = true;
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
    return scene;
}

}  // namespace

Scene load_scene(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".json" || ext == ".JSON") return load_json(path);
    if (ext == ".obj" || ext == ".OBJ") {
        Scene scene = load_obj(path);
        scene.camera = scene.framing_camera();
        return scene;
    }
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(path + ": no such file; expected a .json scene or an .obj");
    throw Error(path + ": unknown scene format '" + ext + "'; expected .json or .obj");
}

}  // namespace pv
