// core/load/scene_file.cpp: JSON scene files (nlohmann-json) on top of the OBJ loader.
#include "core/load/scene_file.h"

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/base/error.h"
#include "core/base/file_io.h"
#include "core/image/image_io.h"
#include "core/load/gltf_loader.h"
#include "core/load/json_bounds.h"
#include "core/load/obj_loader.h"
#include "core/load/start_view.h"
#include "core/scene/environment.h"
#include "core/scene/material_params.h"

namespace pv {
namespace {

using nlohmann::json;
using Ptr = json::json_pointer;

constexpr uint64_t kMaxJsonBytes = uint64_t(64) << 20;

void use_default_sky_if_unlit(Scene& scene, bool lighting_given);
// Sets scene.camera to the start view (core/load/start_view.h: inside an interior, else framed), unless the interior
// is one no light of the scene reaches (see the definition); call it once the scene's emitters are known.
void place_at_start_view(Scene& scene);
// set_environment_map without packing the texels: the loaders pack them once, when the scene is complete.
void add_environment_map(Scene& scene, const std::string& spec);

// Reads the values of one JSON scene file. Every error names the file and the JSON pointer of the key
// ("scene.json: /camera/fov: expected a number in [0.01, 179]"); ranges are the CLI's (app/common.cpp).
struct JsonReader {
    std::string file;
    std::vector<std::string>* warnings = nullptr;

    [[noreturn]] void fail(const Ptr& at, const std::string& what) const {
        throw Error(file + ": " + (at.empty() ? std::string("/") : at.to_string()) + ": " + what);
    }
    // The object at `at`; keys other than `known` get a warning (a misspelt key would be ignored otherwise).
    const json& object(const json& j, const Ptr& at, std::initializer_list<const char*> known) const {
        if (!j.is_object()) fail(at, "expected an object");
        if (warnings && known.size())
            for (const auto& [key, value] : j.items()) {
                bool ok = false;
                for (const char* k : known) ok = ok || key == k;
                if (!ok) warnings->push_back(file + ": " + (at / key).to_string() + ": unknown key, ignored");
            }
        return j;
    }
    float number(const json& j, const Ptr& at, float lo, float hi) const {
        char range[96];
        std::snprintf(range, sizeof range, "expected a number in [%g, %g]", double(lo), double(hi));
        if (!j.is_number()) fail(at, range);
        // Compared as the float it becomes: the bounds are floats, and 0.001 (a double) is below 1e-3f.
        const double v = j.get<double>();
        const float f = float(v);
        if (!std::isfinite(v) || !std::isfinite(f) || f < lo || f > hi) fail(at, range);
        return f;
    }
    vec3 vec(const json& j, const Ptr& at, float lo, float hi) const {
        char range[128];
        std::snprintf(range, sizeof range, "expected an array of 3 numbers in [%g, %g]", double(lo), double(hi));
        if (!j.is_array() || j.size() != 3) fail(at, range);
        vec3 v;
        for (int i = 0; i < 3; ++i) {
            if (!j[size_t(i)].is_number()) fail(at / size_t(i), range);
            v[i] = number(j[size_t(i)], at / size_t(i), lo, hi);
        }
        return v;
    }
    vec3 direction(const json& j, const Ptr& at) const {
        const vec3 v = vec(j, at, -1e30f, 1e30f);
        if (!(glm::length(v) > 0.f)) fail(at, "expected a non-zero direction");
        return v;
    }
    std::string string(const json& j, const Ptr& at) const {
        if (!j.is_string()) fail(at, "expected a string");
        return j.get<std::string>();
    }
    bool boolean(const json& j, const Ptr& at) const {
        if (!j.is_boolean()) fail(at, "expected true or false");
        return j.get<bool>();
    }
};

constexpr float kBig = 1e30f;  // the CLI's upper bound of unbounded quantities
constexpr float kMaxPortalEdge = 1e9f;
// Every light sample of the sky tests each portal (TraceableScene::portal_pdf sums over the portals a ray crosses),
// so the cost per sample grows with their count: a window needs one, a building's facade a few dozen.
constexpr size_t kMaxPortals = 64;

// A camera object; keys it lacks keep the values of `base`.
CameraDesc read_camera(const JsonReader& r, const json& j, const Ptr& at, CameraDesc base, bool is_bookmark) {
    const json& c = is_bookmark ? r.object(j, at, {"name", "eye", "target", "up", "fov", "aperture", "focus_distance"})
                                : r.object(j, at, {"eye", "target", "up", "fov", "aperture", "focus_distance"});
    if (c.contains("eye")) base.eye = r.vec(c["eye"], at / "eye", -kBig, kBig);
    if (c.contains("target")) base.target = r.vec(c["target"], at / "target", -kBig, kBig);
    if (c.contains("up")) base.up = r.direction(c["up"], at / "up");
    if (c.contains("fov")) base.vfov_deg = r.number(c["fov"], at / "fov", 0.01f, 179.f);
    if (c.contains("aperture")) base.aperture = r.number(c["aperture"], at / "aperture", 0.f, kBig);
    if (c.contains("focus_distance"))
        base.focus_distance = r.number(c["focus_distance"], at / "focus_distance", 0.f, kBig);
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

HomogeneousMedium read_medium(const JsonReader& r, const json& j, const Ptr& at);

// Applies a material override: the "type" chooses the BSDF, other keys set its parameters; "medium" the medium
// inside a closed mesh of it.
void apply_override(Material& m, const JsonReader& r, const json& j, const Ptr& at) {
    const json& o =
        r.object(j, at,
                 {"type", "base_color", "specular", "roughness", "ior", "emission", "metallic", "transmission",
                  "specular_factor", "thin_walled", "attenuation_color", "attenuation_distance", "clearcoat",
                  "clearcoat_roughness", "sheen_color", "sheen_roughness", "light_group", "medium"});
    BsdfParams p = bsdf_params(m.bsdf);
    if (o.contains("type")) {
        const std::string type = r.string(o["type"], at / "type");
        if (!parse_bsdf_type(type, p.type))
            r.fail(at / "type",
                   "unknown type '" + type + "'; expected diffuse, glossy, mirror, glass or metallic-roughness");
    }
    if (o.contains("base_color")) p.base = r.vec(o["base_color"], at / "base_color", 0.f, 1.f);
    if (o.contains("specular")) p.specular = r.vec(o["specular"], at / "specular", 0.f, 1.f);
    if (o.contains("roughness")) p.roughness = r.number(o["roughness"], at / "roughness", 0.f, 1.f);
    if (o.contains("ior")) p.ior = r.number(o["ior"], at / "ior", 1e-3f, 1e3f);
    // Metallic-roughness parameters (glTF's names, snake_case); the other types ignore them.
    if (o.contains("metallic")) p.metallic = r.number(o["metallic"], at / "metallic", 0.f, 1.f);
    if (o.contains("transmission")) p.transmission = r.number(o["transmission"], at / "transmission", 0.f, 1.f);
    if (o.contains("specular_factor"))
        p.specular_weight = r.number(o["specular_factor"], at / "specular_factor", 0.f, 1.f);
    if (o.contains("thin_walled")) p.thin_walled = r.boolean(o["thin_walled"], at / "thin_walled");
    if (o.contains("attenuation_color"))
        p.attenuation_color = r.vec(o["attenuation_color"], at / "attenuation_color", 0.f, 1.f);
    if (o.contains("attenuation_distance"))
        p.attenuation_distance = r.number(o["attenuation_distance"], at / "attenuation_distance", 1e-6f, kBig);
    if (o.contains("clearcoat")) p.clearcoat = r.number(o["clearcoat"], at / "clearcoat", 0.f, 1.f);
    if (o.contains("clearcoat_roughness"))
        p.clearcoat_roughness = r.number(o["clearcoat_roughness"], at / "clearcoat_roughness", 0.f, 1.f);
    if (o.contains("sheen_color")) p.sheen_color = r.vec(o["sheen_color"], at / "sheen_color", 0.f, 1.f);
    if (o.contains("sheen_roughness"))
        p.sheen_roughness = r.number(o["sheen_roughness"], at / "sheen_roughness", 0.f, 1.f);
    if (o.contains("emission")) m.emission = r.vec(o["emission"], at / "emission", 0.f, kBig);
    if (o.contains("light_group")) {
        m.light_group = r.string(o["light_group"], at / "light_group");
        if (m.light_group.empty())
            r.fail(at / "light_group", "empty; expected the name of the light group its emission belongs to");
    }
    if (o.contains("medium")) m.medium = read_medium(r, o["medium"], at / "medium");
    // A mirror's reflectance is its "specular" colour when given (the MTL's Ks), else its base colour.
    if (p.type == BsdfType::Mirror && o.contains("specular")) p.base = p.specular;
    set_bsdf(m, p);  // the one conversion (keeps a glossy material's diffuse + specular <= 1), fitted to m's textures
}

// "portals": an array of parallelograms {corner, edge1, edge2}, finite and of non-zero area.
std::vector<Portal> read_portals(const JsonReader& r, const json& j, const Ptr& at) {
    if (!j.is_array()) r.fail(at, "expected an array of {corner, edge1, edge2} objects");
    if (j.size() > kMaxPortals)
        r.fail(at, std::to_string(j.size()) + " portals; at most " + std::to_string(kMaxPortals) +
                       " are supported (every light sample of the sky tests each one): merge adjacent openings "
                       "into one parallelogram");
    std::vector<Portal> portals;
    for (size_t i = 0; i < j.size(); ++i) {
        const Ptr pi = at / i;
        const json& o = r.object(j[i], pi, {"corner", "edge1", "edge2"});
        for (const char* key : {"corner", "edge1", "edge2"})
            if (!o.contains(key)) r.fail(pi / key, "missing; expected an array of 3 numbers");
        Portal p;
        p.corner = r.vec(o["corner"], pi / "corner", -kBig, kBig);
        // Edges within 1e9 keep |edge1 x edge2|^2, which the portal's pdf divides by, finite in float.
        p.edge1 = r.vec(o["edge1"], pi / "edge1", -kMaxPortalEdge, kMaxPortalEdge);
        p.edge2 = r.vec(o["edge2"], pi / "edge2", -kMaxPortalEdge, kMaxPortalEdge);
        const float area = glm::length(glm::cross(p.edge1, p.edge2));
        if (!(area > 0.f) || !std::isfinite(area)) r.fail(pi, "degenerate portal: edge1 x edge2 has zero area");
        portals.push_back(p);
    }
    return portals;
}

// The file's "bookmarks", after the model's cameras; keys a bookmark lacks keep the start view's values.
void add_bookmarks(const JsonReader& r, const JsonReader& rs, const json& list, const Ptr& list_at, Scene& scene) {
    for (size_t i = 0; i < list.size(); ++i) {
        const Ptr at = list_at / i;
        const json& b = rs.object(list[i], at, {});
        std::string name = "view " + std::to_string(scene.bookmarks.size() + 1);
        if (b.contains("name")) {
            name = r.string(b["name"], at / "name");
            if (name.empty()) r.fail(at / "name", "empty; expected the bookmark's name (a non-empty string)");
        } else {
            scene.warnings.push_back(r.file + ": " + at.to_string() +
                                     ": no \"name\"; expected the bookmark's name (a non-empty string); "
                                     "listed as '" +
                                     name + "'");
        }
        scene.bookmarks.push_back(Scene::Bookmark{name, read_camera(rs, b, at, scene.camera, true)});
    }
}

// "environment" and "sun" (objects, checked) over the scene's environment; a map is named relative to `dir`.
void apply_lighting(const JsonReader& r, const json& env, const json& sun, const std::filesystem::path& dir,
                    Scene& scene) {
    const Ptr root;
    if (env.contains("map")) {
        const std::string map = r.string(env["map"], root / "environment" / "map");
        add_environment_map(scene, map == "sky" ? map : (dir / map).string());  // "sky": the default sky
    }
    if (env.contains("color"))
        scene.environment.background = r.vec(env["color"], root / "environment" / "color", 0.f, kBig);
    if (env.contains("rotation"))
        scene.environment.rotation_deg = r.number(env["rotation"], root / "environment" / "rotation", -kBig, kBig);
    if (env.contains("strength"))
        scene.environment.strength = r.number(env["strength"], root / "environment" / "strength", 0.f, kBig);
    if (sun.contains("direction"))
        scene.environment.sun_direction = r.direction(sun["direction"], root / "sun" / "direction");
    if (sun.contains("angular_radius"))
        scene.environment.sun_angular_radius_deg =
            r.number(sun["angular_radius"], root / "sun" / "angular_radius", kSunRadiusMinDeg, kSunRadiusMaxDeg);
    if (sun.contains("irradiance")) {
        const json& e = sun["irradiance"];
        const Ptr at = root / "sun" / "irradiance";
        scene.environment.sun_irradiance = e.is_number() ? vec3(r.number(e, at, 0.f, kBig)) : r.vec(e, at, 0.f, kBig);
    }
}

// A homogeneous medium (core/scene/medium.h), checked: "sigma_s" and "sigma_a" (per scene unit), or "albedo" and
// "density" (sigma_t = density, sigma_s = albedo x density), not both pairs; colours as one number or 3; "g" (the
// Henyey-Greenstein asymmetry) in [-0.99, 0.99].
HomogeneousMedium read_medium(const JsonReader& r, const json& j, const Ptr& at) {
    r.object(j, at, {"sigma_s", "sigma_a", "albedo", "density", "g"});
    auto colour = [&](const char* key, float hi) {
        const json& e = j[key];
        return e.is_number() ? vec3(r.number(e, at / key, 0.f, hi)) : r.vec(e, at / key, 0.f, hi);
    };
    const bool coefficients = j.contains("sigma_s") || j.contains("sigma_a");
    const bool albedo = j.contains("albedo") || j.contains("density");
    if (coefficients && albedo) r.fail(at, "give sigma_s and sigma_a, or albedo and density, not both");
    HomogeneousMedium m;
    if (albedo) {
        if (!j.contains("density")) r.fail(at / "density", "missing; expected a number (with albedo)");
        const vec3 a = j.contains("albedo") ? colour("albedo", 1.f) : vec3(1.f);
        m = HomogeneousMedium::from_albedo(a, r.number(j["density"], at / "density", 0.f, kBig), 0.f);
    } else {
        if (j.contains("sigma_s")) m.sigma_s = colour("sigma_s", kBig);
        if (j.contains("sigma_a")) m.sigma_a = colour("sigma_a", kBig);
    }
    if (j.contains("g")) m.g = r.number(j["g"], at / "g", -kMaxMediumG, kMaxMediumG);
    return m;
}

// "materials": each key overrides the materials of that name (rs warns about unknown keys).
void apply_material_overrides(const JsonReader& rs, const json& materials, const Ptr& at, Scene& scene) {
    for (const auto& [name, o] : materials.items()) {
        bool found = false;
        for (Material& m : scene.materials)
            if (m.name == name) {
                apply_override(m, rs, o, at / name);
                found = true;
            }
        if (!found) scene.warnings.push_back(rs.file + ": material override '" + name + "' matches no material");
    }
}

}  // namespace

Scene load_scene_json_text(const std::string& text, const std::string& path) {
    check_json_bounds(text, path, JsonBounds{});
    json j;
    try {
        j = json::parse(text);
    } catch (const json::exception& e) {
        throw Error(path + ": invalid JSON: " + e.what());
    }
    std::vector<std::string> warnings;
    const JsonReader r{path, &warnings};
    const Ptr root;
    r.object(j, root,
             {"obj", "camera", "background", "environment", "sun", "portals", "bookmarks", "two_sided_emitters",
              "materials", "fog"});
    if (!j.contains("obj")) r.fail(root / "obj", "missing; expected the OBJ file name");
    const std::string obj = r.string(j["obj"], root / "obj");
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    ObjOptions opts;
    if (j.contains("two_sided_emitters"))
        opts.two_sided_emission = r.boolean(j["two_sided_emitters"], root / "two_sided_emitters");
    // Everything in the JSON is checked before the (possibly long) OBJ load.
    const json none = json::object();
    const json& cam = j.contains("camera") ? j["camera"] : none;
    read_camera(r, cam, root / "camera", CameraDesc{}, false);
    if (j.contains("bookmarks") && !j["bookmarks"].is_array()) r.fail(root / "bookmarks", "expected an array");
    const json& env = j.contains("environment")
                          ? r.object(j["environment"], root / "environment", {"map", "color", "rotation", "strength"})
                          : none;
    const json& sun =
        j.contains("sun") ? r.object(j["sun"], root / "sun", {"direction", "irradiance", "angular_radius"}) : none;
    const json& materials = j.contains("materials") ? r.object(j["materials"], root / "materials", {}) : none;
    const std::vector<Portal> portals =
        j.contains("portals") ? read_portals(r, j["portals"], root / "portals") : std::vector<Portal>{};
    const HomogeneousMedium fog = j.contains("fog") ? read_medium(r, j["fog"], root / "fog") : HomogeneousMedium{};

    // "obj" may name a glTF file (.gltf, .glb); its camera is the start view unless "camera" is given, and its
    // cameras come before the file's "bookmarks".
    const std::string model_path = (dir / obj).string();
    Scene scene = is_gltf_path(obj) ? load_gltf(model_path) : load_obj(model_path, opts);
    if (is_gltf_path(obj) && opts.two_sided_emission)
        for (Material& m : scene.materials) m.two_sided_emission = true;
    scene.source = path;
    scene.portals = portals;
    scene.fog = fog;
    scene.warnings.insert(scene.warnings.end(), warnings.begin(), warnings.end());
    const JsonReader rs{path, &scene.warnings};
    if (j.contains("background")) scene.environment.background = r.vec(j["background"], root / "background", 0.f, kBig);
    // No camera in the file: the start view (core/load/start_view.h; placed below, once the material overrides have
    // said which surfaces emit), unless "camera" gives one (over the framing).
    const bool start_view = !scene.has_camera && !j.contains("camera");
    if (!scene.has_camera && j.contains("camera")) scene.camera = scene.framing_camera();
    if (j.contains("camera")) {
        scene.camera = read_camera(r, cam, root / "camera", scene.camera, false);
        scene.has_camera = true;
    }
    if (j.contains("bookmarks")) add_bookmarks(r, rs, j["bookmarks"], root / "bookmarks", scene);
    apply_lighting(r, env, sun, dir, scene);
    apply_material_overrides(rs, materials, root / "materials", scene);
    if (start_view) place_at_start_view(scene);
    use_default_sky_if_unlit(scene, j.contains("background") || j.contains("environment") || j.contains("sun") ||
                                        !scene.punctual_lights.empty());
    pack_texels(scene.textures);  // the surfaces' textures and the map in one region, on huge pages
    return scene;
}

namespace {

// Inside only where light reaches the inside view. A sealed interior (every probe from the eye, upward ones too,
// hits a surface) in a scene with no emitting surface and no punctual light is reached by a sky or sun only through
// gaps or glass: the conference room started inside gave an image of mean 0.0006 at 4 spp. Such a scene is framed
// from outside instead, and a warning says so. An open interior (an atrium, Sponza's court) or one with a lamp starts
// inside.
void place_at_start_view(Scene& scene) {
    const StartView start = choose_start_view(scene);
    if (start.inside && start.sealed && !scene.has_emitters() && scene.punctual_lights.empty()) {
        scene.camera = scene.framing_camera();
        scene.warnings.push_back(scene.source +
                                 ": starts outside: the scene's interior is closed and has no lamp, so no light would "
                                 "reach a view inside it (a scene file's \"camera\" can start inside)");
        return;
    }
    scene.camera = start.camera;
}

void use_default_sky_if_unlit(Scene& scene, bool lighting_given) {
    if (lighting_given || scene.has_emitters() || scene.triangles.empty()) return;
    add_environment_map(scene, "sky");
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
        const std::string text = read_regular_file(out, kMaxJsonBytes, "a JSON scene file");
        check_json_bounds(text, out, JsonBounds{});
        try {
            j = json::parse(text);
        } catch (const json::exception& e) {
            throw Error(out + ": cannot add a bookmark: invalid JSON: " + e.what());
        }
        if (!j.is_object()) throw Error(out + ": cannot add a bookmark: /: expected an object");
    }
    if (!is_json && !j.contains("obj")) j["obj"] = fs::path(path).filename().string();
    json& list = j["bookmarks"];
    if (!list.is_array()) list = json::array();
    json entry = camera_json(camera);
    entry["name"] = name;
    bool replaced = false;
    for (json& b : list)
        if (b.is_object() && b.contains("name") && b["name"] == name) {
            b = entry;
            replaced = true;
        }
    if (!replaced) list.push_back(entry);
    const std::string text = j.dump(2) + "\n";
    write_file_atomically(out, [&](int fd) { write_all(fd, text.data(), text.size(), out); });
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

namespace {

void add_environment_map(Scene& scene, const std::string& spec) {
    Texture map;
    if (spec == "sky") {
        map = make_default_sky();
    } else {
        std::error_code ec;
        if (!std::filesystem::exists(spec, ec))
            throw Error(spec + ": no such file; expected an environment map (.exr, .hdr, .png)");
        map = Texture::load(spec, false, &scene.warnings);
    }
    scene.textures.push_back(std::move(map));
    scene.environment_map = static_cast<uint32_t>(scene.textures.size() - 1);
}

}  // namespace

void set_environment_map(Scene& scene, const std::string& spec) {
    add_environment_map(scene, spec);
    pack_texels(scene.textures);  // the map joins the surfaces' textures in one region
}

Scene load_scene(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".json" || ext == ".JSON")
        return load_scene_json_text(read_regular_file(path, kMaxJsonBytes, "a JSON scene file"), path);
    if (ext == ".obj" || ext == ".OBJ" || is_gltf_path(path)) {
        Scene scene = is_gltf_path(path) ? load_gltf(path) : load_obj(path);
        if (!scene.has_camera) place_at_start_view(scene);
        use_default_sky_if_unlit(scene, !scene.punctual_lights.empty());  // glTF punctual lights
        pack_texels(scene.textures);  // the surfaces' textures and the sky in one region, on huge pages
        return scene;
    }
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
        throw Error(path + ": no such file; expected a .json scene, an .obj, a .gltf or a .glb");
    if (std::filesystem::is_directory(path, ec))
        throw Error(path + ": is a folder; expected a .json scene, an .obj, a .gltf or a .glb");
    throw Error(path + ": unknown scene format '" + ext + "'; expected .json, .obj, .gltf or .glb");
}

}  // namespace pv
