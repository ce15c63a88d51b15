// core/render/traceable_scene.cpp: building and editing the scene prepared for tracing (see traceable_scene.h).
#include "core/render/traceable_scene.h"

#include <algorithm>
#include <cmath>
#include <new>

#include "core/base/huge_pages.h"

namespace pv {

TraceableScene::TraceableScene(std::shared_ptr<const Scene> scene, const std::function<void(double)>& build_progress)
    : m_scene(std::move(scene)), m_materials(m_scene->materials) {
    double total = 0.0;
    for (const Portal& p : m_scene->portals) {
        total += double(glm::length(glm::cross(p.edge1, p.edge2)));
        m_portal_cdf.push_back(float(total));
    }
    for (float& c : m_portal_cdf) c = float(double(c) / total);
    if (!m_portal_cdf.empty()) m_portal_cdf.back() = 1.f;
    m_portal_area = float(total);
    m_accel = std::make_unique<Accel>(*m_scene, m_materials, build_progress);
    if (packs_triangles(*m_scene) && m_scene->triangle_count() > 0) {
        // Packed in place: no vector of records beside the region.
        const size_t n = m_scene->triangle_count();
        const std::shared_ptr<std::byte> region = allocate_region(n * sizeof(TriangleRecord));
        auto* records = reinterpret_cast<TriangleRecord*>(region.get());
        for (size_t i = 0; i < n; ++i) new (records + i) TriangleRecord(pack_triangle(*m_scene, i));
        m_records = std::shared_ptr<const TriangleRecord>(region, records);
    }
    m_lights = LightSet(*m_scene, m_materials);
    m_environment_settings = m_scene->environment;
    m_fog = m_scene->fog;
    m_environment = Environment(*m_scene, m_environment_settings);
    update_selection();
    update_media();
}

TraceableScene::~TraceableScene() = default;

void TraceableScene::set_materials(const std::vector<Material>& materials) {
    if (materials.size() != m_scene->materials.size()) return;
    // The light set (and its tree: up to a second for 10^5 emitters) depends only on what emits: an edit of
    // colours, roughness or type keeps it.
    const auto same_light = [](const Material& a, const Material& b) {
        return a.emission == b.emission && a.two_sided_emission == b.two_sided_emission &&
               a.emissive_texture == b.emissive_texture && a.emissive_uv == b.emissive_uv &&
               a.alpha_texture == b.alpha_texture;
    };
    const bool lights_kept = std::equal(materials.begin(), materials.end(), m_materials.begin(), same_light);
    m_materials = materials;
    if (!lights_kept) {
        m_lights = LightSet(*m_scene, m_materials);
        m_lights.set_sampler(m_light_sampler);
    }
    m_accel->set_materials(m_materials);  // alpha cut-outs as edited
    update_selection();
    update_media();
}

void TraceableScene::update_media() {
    m_has_media = !m_fog.empty() || std::any_of(m_materials.begin(), m_materials.end(),
                                                [](const Material& m) { return !m.medium.empty(); });
}

void TraceableScene::set_environment(const EnvironmentSettings& settings) {
    m_environment_settings = settings;
    m_environment = Environment(*m_scene, settings);
    update_selection();
}

void TraceableScene::update_selection() {
    // The light groups follow what emits (a few small vectors: no cost to the render).
    m_groups = make_light_groups(*m_scene, m_materials, m_environment);
    m_lights.set_groups(*m_scene, m_groups.material);
    // Half the light samples to the environment when both it and emissive triangles shine.
    if (m_environment.is_black())
        m_p_env = 0.f;
    else
        m_p_env = m_lights.empty() ? 1.f : 0.5f;
    m_p_portal = m_p_env > 0.f && m_environment.sun_probability() < 1.f && !m_scene->portals.empty() &&
                         m_portal_area > 0.f && std::isfinite(m_portal_area)
                     ? kPortalProbability
                     : 0.f;
    m_p_mix = m_p_portal > 0.f ? m_p_portal
              : m_sky_guide && m_sky_guide->valid() && m_p_env > 0.f && m_environment.sun_probability() < 1.f
                  ? kSkyGuideProbability
                  : 0.f;
}

void TraceableScene::set_sky_guide(std::shared_ptr<const SkyGuide> guide) {
    m_sky_guide = std::move(guide);
    update_selection();
}

float TraceableScene::portal_pdf(vec3 ref, vec3 dir) const {
    float pdf = 0.f;
    for (const Portal& p : m_scene->portals) {
        const vec3 n = glm::cross(p.edge1, p.edge2);  // length: the portal's area
        const float cos_n = glm::dot(dir, n);
        if (cos_n == 0.f) continue;
        const float t = glm::dot(p.corner - ref, n) / cos_n;
        if (!(t > 0.f)) continue;
        // Coordinates of the crossing in (edge1, edge2): d = s e1 + r e2, so d x e2 = s n and e1 x d = r n.
        const vec3 d = ref + t * dir - p.corner;
        const float nn = glm::dot(n, n);
        const float s = glm::dot(glm::cross(d, p.edge2), n) / nn;
        const float r = glm::dot(glm::cross(p.edge1, d), n) / nn;
        if (s < 0.f || s > 1.f || r < 0.f || r > 1.f) continue;
        // Area density 1 / A_total to solid angle: t^2 / |cos| with |cos| = |dir . n| / |n|.
        pdf += t * t * std::sqrt(nn) / (m_portal_area * std::abs(cos_n));
    }
    return std::isfinite(pdf) ? pdf : 0.f;
}

bool TraceableScene::sample_portal(vec3 ref, float u_pick, vec2 u, vec3& wi) const {
    if (m_scene->portals.empty()) return false;
    size_t k = 0;
    while (k + 1 < m_portal_cdf.size() && u_pick >= m_portal_cdf[k]) ++k;
    const Portal& p = m_scene->portals[k];
    const vec3 to = p.corner + u.x * p.edge1 + u.y * p.edge2 - ref;
    const float len = glm::length(to);
    if (!(len > 0.f) || !std::isfinite(len)) return false;
    wi = to / len;
    return true;
}

namespace {
// p_sun pdf_sun + (1 - p_sun) ((1 - q) pdf_sky + q pdf_mix): one expression for the sample's and the escape's pdf.
inline float mixture_pdf(float p_sun, float pdf_sun, float q, float pdf_sky, float pdf_mix) {
    return p_sun * pdf_sun + (1.f - p_sun) * ((1.f - q) * pdf_sky + q * pdf_mix);
}
}  // namespace

float TraceableScene::environment_pdf_mixed(vec3 ref, vec3 dir, float sky_pdf) const {
    return mixture_pdf(m_environment.sun_probability(), m_environment.pdf_sun(dir), m_p_mix, sky_pdf,
                       mix_pdf(ref, dir));
}

vec3 TraceableScene::emitted_escape_and_pdf(vec3 ref, vec3 dir, float* light_pdf) const {
    if (m_environment.is_black()) {
        *light_pdf = 0.f;
        return vec3(0.f);
    }
    // Environment::eval is eval_sun + eval_sky, and light_pdf_escape is escape_pdf of pdf_sky: the same values,
    // with the sky's radiance and pdf from eval_and_pdf_sky's one search.
    float sky_pdf = 0.f;
    const vec3 le = m_environment.eval_and_pdf_sky(dir, &sky_pdf);
    *light_pdf = escape_pdf(ref, dir, sky_pdf);
    return le;
}

bool TraceableScene::sample_environment_mixed(vec3 ref, float u_select, vec2 u, LightSample& ls) const {
    // The sun as before (u.x below its probability); the sky's share goes to the portals or the guide when
    // u_select < q.
    const float p_sun = m_environment.sun_probability(), q = m_p_mix;
    vec3 wi, le;
    float pdf;
    if (u.x >= p_sun && u_select < q) {
        // A direction toward a portal or from the guide; its radiance and sky pdf from one texel search.
        const vec2 up(std::min((u.x - p_sun) / (1.f - p_sun), 0x1.fffffep-1f), u.y);
        float pdf_mix;
        if (m_p_portal > 0.f) {
            if (!sample_portal(ref, u_select / q, up, wi)) return false;
            pdf_mix = portal_pdf(ref, wi);
        } else {
            const int cell = m_sky_guide->cell(ref);  // once, for the sample and its pdf
            wi = m_sky_guide->sample_in(cell, u_select / q, up);
            pdf_mix = m_sky_guide->pdf_in(cell, wi);
        }
        float pdf_sky;
        le = m_environment.eval_and_pdf_sky(wi, &pdf_sky);
        pdf = m_p_env * mixture_pdf(p_sun, m_environment.pdf_sun(wi), q, pdf_sky, pdf_mix);
    } else {
        const std::optional<EnvironmentSample> es = m_environment.sample(u);
        if (!es) return false;
        wi = es->wi;
        le = es->le;
        // A sky direction outside the sun: es->pdf is (1 - p_sun) pdf_sky, no second texel search.
        pdf = u.x >= p_sun && m_environment.pdf_sun(wi) == 0.f
                  ? m_p_env * ((1.f - q) * es->pdf + (1.f - p_sun) * q * mix_pdf(ref, wi))
                  : m_p_env * environment_pdf_mixed(ref, wi, m_environment.pdf_sky(wi));
    }
    if (!(pdf > 0.f)) return false;
    ls.wi = wi;
    ls.le = le;
    ls.pdf = pdf;
    ls.dist = std::numeric_limits<float>::infinity();
    ls.group = kEnvironmentGroup;
    return true;
}

std::optional<PickResult> TraceableScene::pick(const Camera& camera, vec2 film_px) const {
    const Ray ray = camera.generate(film_px, vec2(0.5f));
    Hit hit;
    if (!intersect(ray, hit)) return std::nullopt;
    PickResult r;
    r.triangle = hit.prim;
    r.material = m_scene->material_ids[hit.prim];
    r.distance = hit.t;
    r.position = ray.o + hit.t * ray.d;
    return r;
}

}  // namespace pv
