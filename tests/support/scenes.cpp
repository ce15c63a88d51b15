// tests/support/scenes.cpp: see scenes.h.
#include "tests/support/scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <mutex>

#include "core/frame/renderer.h"
#include "core/load/scene_file.h"
#include "core/scene/environment.h"
#include "tests/support/chi2.h"

namespace pv::test {

uint32_t add_material(Scene& scene, const Material& m) {
    scene.materials.push_back(m);
    return static_cast<uint32_t>(scene.materials.size() - 1);
}

void add_quad(Scene& scene, vec3 p0, vec3 p1, vec3 p2, vec3 p3, uint32_t material) {
    scene.add_triangle(p0, p1, p2, material);
    scene.add_triangle(p0, p2, p3, material);
}

void add_icosphere(Scene& scene, vec3 centre, float radius, int subdiv, uint32_t material, bool inward) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<dvec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    for (dvec3& p : v) p = glm::normalize(p);
    std::vector<uvec3> f = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                            {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                            {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int s = 0; s < subdiv; ++s) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(glm::normalize(v[a] + v[b]));
            const uint32_t id = static_cast<uint32_t>(v.size() - 1);
            mid[key] = id;
            return id;
        };
        std::vector<uvec3> nf;
        for (const uvec3& tri : f) {
            const uint32_t a = midpoint(tri.x, tri.y), b = midpoint(tri.y, tri.z), c = midpoint(tri.z, tri.x);
            nf.insert(nf.end(), {{tri.x, a, c}, {tri.y, b, a}, {tri.z, c, b}, {a, b, c}});
        }
        f.swap(nf);
    }
    const uint32_t base = static_cast<uint32_t>(scene.positions.size());
    for (const dvec3& p : v) scene.positions.push_back(centre + radius * vec3(p));
    for (const uvec3& tri : f) {
        scene.triangles.push_back(inward ? uvec3(base + tri.x, base + tri.z, base + tri.y) : base + tri);
        scene.material_ids.push_back(material);
        if (!scene.normal_indices.empty()) scene.normal_indices.push_back(uvec3(kNoIndex));
        if (!scene.uv_indices.empty()) scene.uv_indices.push_back(uvec3(kNoIndex));
    }
}

void add_uv_sphere(Scene& scene, vec3 centre, float radius, int nu, int nv, uint32_t material, bool smooth) {
    auto dir = [&](int i, int j) {
        const double phi = 2.0 * M_PI * double(i % nu) / nu, theta = M_PI * double(j) / nv;
        return dvec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    };
    if (smooth && scene.normal_indices.size() != scene.triangles.size())
        scene.normal_indices.assign(scene.triangles.size(), uvec3(kNoIndex));
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            // Outward winding: (i, j), (i, j+1), (i+1, j+1) ... seen from outside.
            const dvec3 a = dir(i, j), b = dir(i + 1, j), c = dir(i + 1, j + 1), d = dir(i, j + 1);
            auto tri = [&](dvec3 p, dvec3 q, dvec3 r) {
                const vec3 pp = centre + radius * vec3(p);
                vec3 qq = centre + radius * vec3(q), rr = centre + radius * vec3(r);
                if (glm::length(glm::cross(qq - pp, rr - pp)) == 0.f) return;  // pole slivers
                vec3 n0 = vec3(p), n1 = vec3(q), n2 = vec3(r);
                // Orient outward.
                if (glm::dot(glm::cross(qq - pp, rr - pp), pp + qq + rr - 3.f * centre) < 0.f) {
                    std::swap(qq, rr);
                    std::swap(n1, n2);
                }
                scene.add_triangle(pp, qq, rr, material);
                if (smooth && scene.normal_indices.size() < scene.triangles.size())
                    scene.normal_indices.push_back(uvec3(kNoIndex));
                if (smooth) {
                    const uint32_t nb = static_cast<uint32_t>(scene.normals.size());
                    scene.normals.insert(scene.normals.end(), {n0, n1, n2});
                    scene.normal_indices.back() = uvec3(nb, nb + 1, nb + 2);
                }
            };
            tri(a, d, c);
            tri(a, c, b);
        }
}

void Tracer::for_each_sample(const CameraDesc& camera_desc, const RenderSettings& settings, int width, int height,
                             int spp, const std::function<void(int, int, uint32_t, vec3)>& fn,
                             bool pixel_centre) const {
    const ScopedFtzDaz ftz;  // the renderer's floating-point mode
    const Camera camera(camera_desc, width, height);
    Sampler sampler(settings.seed, settings.sampler);
    PathCounters counters;
    for (int index = 0; index < spp; ++index)
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const Ray ray = camera_ray(camera, sampler, x, y, uint32_t(index), pixel_centre);
                fn(x, y, uint32_t(index), trace_path(*this, settings, ray, sampler, counters));
            }
}

Film Tracer::render(const CameraDesc& camera, const RenderSettings& settings, int width, int height, int spp,
                    bool pixel_centre, uint64_t* dropped) const {
    Film film(width, height);
    uint64_t drops = 0;
    for_each_sample(
        camera, settings, width, height, spp,
        [&](int x, int y, uint32_t i, vec3 L) { drops += film.add(x, y, i, L) ? 0 : 1; }, pixel_centre);
    if (dropped) *dropped = drops;
    return film;
}

Film render_with_renderer(std::shared_ptr<const Scene> scene, const CameraDesc& camera, const RenderSettings& settings,
                          int width, int height, int spp, int threads, uint64_t* dropped) {
    Renderer r(std::move(scene), threads);
    r.restart(camera, settings, width, height);
    for (int i = 0; i < spp; ++i) r.render_pass();
    if (dropped) *dropped = r.stats().dropped;
    return r.film();
}

std::shared_ptr<const Scene> cornell_box() {
    static std::mutex mutex;
    static std::shared_ptr<const Scene> scene;
    std::lock_guard<std::mutex> lock(mutex);
    if (!scene) scene = std::make_shared<Scene>(load_scene(builtin_scene_path()));
    return scene;
}

void expect_finite_and_lit(const Image& img) {
    double sum = 0.0;
    for (float v : img.rgb) {
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
    }
    EXPECT_GT(sum, 0.0);
}

void expect_environment_samples_follow_pdf(const TraceableScene& ts, vec3 ref) {
    Chi2Options o;
    o.sample_count = 300000;
    o.test_count = 2;
    const auto r = chi2_test(
        [&](Pcg32& g) -> std::optional<vec3> {
            const float us = g.next_float();
            const float u0 = g.next_float();
            LightSample ls;
            if (!ts.sample_light(ref, vec3(0.f), us, vec2(u0, g.next_float()), ls)) return std::nullopt;
            EXPECT_TRUE(std::isinf(ls.dist));
            EXPECT_NEAR(ls.pdf, ts.light_pdf_escape(ref, ls.wi), 1e-4 * ls.pdf);
            return ls.wi;
        },
        [&](vec3 w) { return double(ts.light_pdf_escape(ref, w)); }, o);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdf_integral, 1.0, 1e-2) << r.message;
}

std::shared_ptr<Scene> open_box(bool emitter) {
    auto scene = std::make_shared<Scene>();
    std::vector<uint32_t> codes(8 * 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) codes[size_t(y * 8 + x)] = ((x + y) & 1) ? 0xff2040c0u : 0xffe0d0a0u;
    scene->textures.push_back(Texture(8, 8, codes));
    Material floor;
    floor.base_color_texture = 0;
    const uint32_t m_floor = add_material(*scene, floor);
    Material wall;
    wall.bsdf = Lambertian{vec3(0.6f, 0.5f, 0.4f)};
    const uint32_t m_wall = add_material(*scene, wall);
    Material mirror;
    mirror.bsdf = Mirror{vec3(0.9f)};
    const uint32_t m_mirror = add_material(*scene, mirror);
    Material glossy;
    glossy.bsdf = Glossy{vec3(0.3f, 0.4f, 0.3f), vec3(0.2f), 0.15f};
    const uint32_t m_glossy = add_material(*scene, glossy);
    Material glass;
    glass.bsdf = Dielectric{1.5f};
    const uint32_t m_glass = add_material(*scene, glass);

    // The floor's two triangles (add_quad: (p0 p1 p2), (p0 p2 p3)) with uvs; the checker repeats twice across it.
    add_quad(*scene, vec3(-1, 0, -1), vec3(-1, 0, 1), vec3(1, 0, 1), vec3(1, 0, -1), m_floor);
    scene->uvs = {vec2(0.f, 0.f), vec2(0.f, 2.f), vec2(2.f, 2.f), vec2(2.f, 0.f)};
    scene->uv_indices = {uvec3(0, 1, 2), uvec3(0, 2, 3)};  // later triangles get none (Scene::add_triangle)
    add_quad(*scene, vec3(-1, 0, -1), vec3(1, 0, -1), vec3(1, 1.5f, -1), vec3(-1, 1.5f, -1), m_wall);
    add_quad(*scene, vec3(-1, 0, 1), vec3(-1, 0, -1), vec3(-1, 1.5f, -1), vec3(-1, 1.5f, 1), m_mirror);
    add_quad(*scene, vec3(1, 0, -1), vec3(1, 0, 1), vec3(1, 1.5f, 1), vec3(1, 1.5f, -1), m_glossy);
    add_icosphere(*scene, vec3(0.3f, 0.35f, 0.f), 0.3f, 2, m_glass);
    if (emitter) {
        Material light;
        light.emission = vec3(6.f);
        const uint32_t m_light = add_material(*scene, light);
        add_quad(*scene, vec3(-0.4f, 1.4f, -0.4f), vec3(0.4f, 1.4f, -0.4f), vec3(0.4f, 1.4f, 0.4f),
                 vec3(-0.4f, 1.4f, 0.4f), m_light);
    }
    scene->textures.push_back(make_default_sky());
    scene->environment_map = uint32_t(scene->textures.size() - 1);
    scene->camera.eye = vec3(0.f, 1.2f, 2.6f);
    scene->camera.target = vec3(0.f, 0.4f, 0.f);
    scene->camera.vfov_deg = 50.f;
    scene->has_camera = true;
    return scene;
}

}  // namespace pv::test
