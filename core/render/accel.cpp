// core/render/accel.cpp: Embree 3 device, scene and queries.
#include "core/render/accel.h"

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <limits>
#include <mutex>

#include "core/base/error.h"
#include "core/sampling/rng.h"

namespace pv {

void enable_ftz_daz() {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

ScopedFtzDaz::ScopedFtzDaz() : m_saved(_mm_getcsr()) { enable_ftz_daz(); }
ScopedFtzDaz::~ScopedFtzDaz() { _mm_setcsr(m_saved); }

namespace {

// Embree reports errors through a callback; we keep the first message and throw after the call returns,
// since throwing through Embree's C frames is not allowed.
struct DeviceErrors {
    std::mutex mutex;
    std::string message;
};

void on_embree_error(void* user, RTCError code, const char* str) {
    auto* errors = static_cast<DeviceErrors*>(user);
    std::lock_guard<std::mutex> lock(errors->mutex);
    if (errors->message.empty())
        errors->message = "Embree error " + std::to_string(int(code)) + ": " + (str ? str : "(no message)");
}

bool on_memory(void* user, ssize_t bytes, bool) {
    static_cast<std::atomic<int64_t>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
    return true;
}

// Triangles of the two Embree geometries: opaque ones (no filter) and those whose material has an alpha cut-out.
constexpr unsigned kOpaqueGeometry = 0, kAlphaGeometry = 1;

}  // namespace

struct Accel::Impl {
    DeviceErrors errors;
    std::atomic<int64_t> memory{0};
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    AccelStats stats;
    const Scene* source = nullptr;
    std::vector<uint32_t> alpha;     // per material: its alpha texture (the edited materials'), or kNoIndex
    std::vector<uint32_t> prims[2];  // per geometry: the Scene triangle of each primID (empty: the identity)

    uint32_t scene_prim(unsigned geom, unsigned prim) const {
        const std::vector<uint32_t>& map = prims[geom];
        return map.empty() ? prim : map[prim];
    }
    void check(const char* what) {
        std::lock_guard<std::mutex> lock(errors.mutex);
        if (!errors.message.empty()) throw Error(std::string(what) + ": " + errors.message);
    }
    void build(const std::function<void(double)>* progress);
    static void alpha_filter(const RTCFilterFunctionNArguments* args);
    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

// Stochastic alpha test (Enderton et al. 2010, "Stochastic Transparency"): a hit on a texel of opacity a is
// kept with probability a, decided by a hash of the ray and the triangle, so the decision is deterministic per ray
// and light passes through in proportion 1 - a. Runs for camera, bounce and shadow rays alike, on the alpha
// geometry only.
void Accel::Impl::alpha_filter(const RTCFilterFunctionNArguments* args) {
    const auto* im = static_cast<const Impl*>(args->geometryUserPtr);
    const Scene& scene = *im->source;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const uint32_t prim = im->scene_prim(kAlphaGeometry, RTCHitN_primID(args->hit, args->N, i));
        const uint32_t texture = im->alpha[scene.material_ids[prim]];
        if (texture == kNoIndex) continue;
        const vec2 uv = scene.uv_at(prim, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i));
        const float alpha = scene.textures[texture].lookup(uv).w;
        if (alpha >= 1.f) continue;
        uint64_t h = prim;
        const float key[6] = {RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                              RTCRayN_org_z(args->ray, args->N, i), RTCRayN_dir_x(args->ray, args->N, i),
                              RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i)};
        for (float k : key) {
            uint32_t bits;
            std::memcpy(&bits, &k, 4);
            h = hash_combine(h, bits);
        }
        const float u = float(h >> 40) * 0x1p-24f;
        if (u >= alpha) args->valid[i] = 0;
    }
}

namespace {

std::vector<uint32_t> alpha_textures(const std::vector<Material>& materials) {
    std::vector<uint32_t> out(materials.size());
    for (size_t i = 0; i < materials.size(); ++i) out[i] = materials[i].alpha_texture;
    return out;
}

}  // namespace

void Accel::Impl::build(const std::function<void(double)>* progress) {
    const Scene& s = *source;
    if (scene) rtcReleaseScene(scene);
    scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
    // Robust mode: without it Embree's faster triangle test reports false hits on slivers whose vertices span
    // many orders of magnitude, even from origins offset beyond p's error bound (tests/render/test_reintersection.cpp).
    // It also makes Embree 3.13 ignore RTC_BUILD_QUALITY_HIGH (no spatial splits: docs/ray-speed.md).
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    // Split the triangles by whether their material has a cut-out; a geometry holding all of them keeps the
    // identity mapping (no lookup per hit).
    prims[kOpaqueGeometry].clear();
    prims[kAlphaGeometry].clear();
    for (uint32_t t = 0; t < uint32_t(s.triangles.size()); ++t)
        prims[alpha[s.material_ids[t]] != kNoIndex ? kAlphaGeometry : kOpaqueGeometry].push_back(t);
    RTCBuffer vertices = nullptr;
    for (const unsigned g : {kOpaqueGeometry, kAlphaGeometry}) {
        std::vector<uint32_t>& list = prims[g];
        if (list.empty()) continue;
        if (!vertices) {
            // One vertex buffer for both geometries; Embree reads 16 bytes at the last vertex, hence the padding.
            vertices = rtcNewBuffer(device, s.positions.size() * sizeof(vec3) + sizeof(float));
            check("Embree buffer allocation");
            std::memcpy(rtcGetBufferData(vertices), s.positions.data(), s.positions.size() * sizeof(vec3));
        }
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        rtcSetGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices, 0, sizeof(vec3),
                             s.positions.size());
        auto* idx = static_cast<uvec3*>(
            rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, sizeof(uvec3), list.size()));
        check("Embree buffer allocation");
        for (size_t i = 0; i < list.size(); ++i) idx[i] = s.triangles[list[i]];
        if (g == kAlphaGeometry) {
            rtcSetGeometryUserData(geom, this);
            rtcSetGeometryIntersectFilterFunction(geom, alpha_filter);
            rtcSetGeometryOccludedFilterFunction(geom, alpha_filter);
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometryByID(scene, geom, g);
        rtcReleaseGeometry(geom);
        if (list.size() == s.triangles.size()) list.clear();  // every triangle, in order: the identity
    }
    if (vertices) rtcReleaseBuffer(vertices);
    if (progress && *progress) {
        rtcSetSceneProgressMonitorFunction(
            scene,
            [](void* user, double fraction) {
                (*static_cast<const std::function<void(double)>*>(user))(fraction);
                return true;  // never cancel
            },
            const_cast<std::function<void(double)>*>(progress));
    }
    rtcCommitScene(scene);
    check("Embree scene build");
}

Accel::Accel(const Scene& s, const std::function<void(double)>& progress) : Accel(s, s.materials, progress) {}

Accel::Accel(const Scene& s, const std::vector<Material>& materials, const std::function<void(double)>& progress)
    : m_impl(std::make_unique<Impl>()) {
    const auto start = std::chrono::steady_clock::now();
    Impl& im = *m_impl;
    im.device = rtcNewDevice(nullptr);
    if (!im.device)
        throw Error("Embree: cannot create a device (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(im.device, on_embree_error, &im.errors);
    rtcSetDeviceMemoryMonitorFunction(im.device, on_memory, &im.memory);
    im.source = &s;
    im.alpha = alpha_textures(materials.size() == s.materials.size() ? materials : s.materials);
    im.build(&progress);
    im.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    im.stats.bytes = static_cast<size_t>(std::max<int64_t>(0, im.memory.load()));
}

void Accel::set_materials(const std::vector<Material>& materials) {
    Impl& im = *m_impl;
    if (materials.size() != im.alpha.size()) return;
    std::vector<uint32_t> alpha = alpha_textures(materials);
    // Edits that leave every cut-out as it was (colours, roughness, emission: all the viewer edits) touch
    // nothing, so they never race with a query (ProgressiveRenderer::pick runs on the UI thread).
    if (alpha == im.alpha) return;
    bool same_split = true;
    for (size_t i = 0; i < alpha.size(); ++i) same_split &= (alpha[i] == kNoIndex) == (im.alpha[i] == kNoIndex);
    im.alpha = std::move(alpha);
    if (same_split) return;
    const auto start = std::chrono::steady_clock::now();
    im.build(nullptr);
    im.stats.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    im.stats.bytes = static_cast<size_t>(std::max<int64_t>(0, im.memory.load()));
}

Accel::~Accel() = default;

const AccelStats& Accel::stats() const { return m_impl->stats; }

namespace {
// Embree's RayK::valid(): every origin and direction component within +-1.844e18 (and not NaN). Debian's Embree
// asserts on anything else (an abort, e.g. for a framing camera placed beyond a scene whose vertices reach 1.8e18),
// so such rays hit nothing instead.
// The smallest normal float, not 0: a hit whose distance is below it (typically one that flushed to zero under FTZ,
// like a spawned ray's own surface a few denormals away) is not a hit. Rays are spawned from offset origins with
// tmin "0" (offset_ray_origin), and t = +-0 must not count.
constexpr float kTnear = std::numeric_limits<float>::min();

inline bool embree_ray_valid(const Ray& ray) {
    constexpr float kLarge = 1.844e18f;
    for (int i = 0; i < 3; ++i)
        if (!(std::fabs(ray.o[i]) <= kLarge) || !(std::fabs(ray.d[i]) <= kLarge)) return false;
    return !std::isnan(ray.tmax);
}
}  // namespace

bool Accel::intersect(const Ray& ray, Hit& hit) const {
    if (!embree_ray_valid(ray)) return false;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x;
    rh.ray.org_y = ray.o.y;
    rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x;
    rh.ray.dir_y = ray.d.y;
    rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = kTnear;
    rh.ray.tfar = ray.tmax;
    rh.ray.time = 0.f;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_impl->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rh.ray.tfar;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    hit.prim = m_impl->scene_prim(rh.hit.geomID, rh.hit.primID);
    return true;
}

bool Accel::occluded(const Ray& ray) const {
    if (!embree_ray_valid(ray)) return false;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.tnear = kTnear;
    r.tfar = ray.tmax;
    r.time = 0.f;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(m_impl->scene, &ctx, &r);
    return r.tfar < 0.f;  // Embree sets tfar = -inf on a hit
}

}  // namespace pv
