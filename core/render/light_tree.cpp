// core/render/light_tree.cpp: the light tree's bounds, importance, build (binned by pbrt-v4's surface area orientation
// heuristic) and pick (see light_tree.h).
#include "core/render/light_tree.h"

#include <emmintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace pv {

namespace {

// cos(max(0, a - b)) from the sines and cosines of angles a, b in [0, pi].
inline float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
    if (cos_a > cos_b) return 1.f;
    return cos_a * cos_b + sin_a * sin_b;
}

// Numerically stable for nearly parallel and nearly opposite unit vectors.
inline float angle_between(vec3 a, vec3 b) {
    if (glm::dot(a, b) < 0.f) return kPi - 2.f * std::asin(std::min(glm::length(a + b) * 0.5f, 1.f));
    return 2.f * std::asin(std::min(glm::length(b - a) * 0.5f, 1.f));
}

float surface_area(vec3 lo, vec3 hi) {
    const vec3 d = glm::max(hi - lo, vec3(0.f));
    return 2.f * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// The build's cost of a set of emitters (pbrt-v4's EvaluateCost without the axis factor): power times the
// orientation cone's measure times the box's surface area.
double orientation_cost(const LightBounds& b) {
    const double theta_o = std::acos(std::clamp(double(b.cos_o), -1.0, 1.0));
    const double theta_e = std::acos(std::clamp(double(b.cos_e), -1.0, 1.0));
    const double theta_w = std::min(theta_o + theta_e, double(M_PI));
    const double sin_o = std::sqrt(std::max(0.0, 1.0 - double(b.cos_o) * b.cos_o));
    const double m_omega =
        2.0 * M_PI * (1.0 - b.cos_o) +
        M_PI / 2.0 * (2.0 * theta_w * sin_o - std::cos(theta_o - 2.0 * theta_w) - 2.0 * theta_o * sin_o + b.cos_o);
    return double(b.phi) * m_omega * double(surface_area(b.lo, b.hi));
}

}  // namespace

PackedLightBounds::PackedLightBounds(const LightBounds& b)
    : centre(0.5f * (b.lo + b.hi)),
      radius(0.5f * glm::length(b.hi - b.lo)),
      w(b.w),
      phi(b.phi),
      cos_o(b.cos_o),
      sin_o(safe_sqrt(1.f - b.cos_o * b.cos_o)),
      cos_e(b.cos_e),
      two_sided(b.two_sided) {}

float LightBounds::importance(vec3 p, vec3 n) const { return PackedLightBounds(*this).importance(p, n); }

float PackedLightBounds::importance(vec3 p, vec3 n) const {
    const vec3 to_p = p - centre;
    const float d2_true = glm::dot(to_p, to_p);
    const float r2 = radius * radius;
    if (!(d2_true > 0.f) && !(r2 > 0.f)) return 0.f;
    const float inv_d = d2_true > 0.f ? 1.f / std::sqrt(d2_true) : 0.f;
    const vec3 wi = to_p * inv_d;
    // The angle between the cone's axis and the direction to p.
    float cos_w = glm::dot(w, wi);
    if (two_sided) cos_w = std::fabs(cos_w);
    // The half angle theta_b the bounding sphere subtends at p (everything when p is inside it).
    float sin_b = 0.f, cos_b = -1.f;
    if (d2_true > r2) {
        sin_b = radius * inv_d;
        cos_b = safe_sqrt(1.f - sin_b * sin_b);
    }
    // theta' = max(0, theta_w - theta_o - theta_b): the least angle between a normal and a direction to p.
    float cos_p = 1.f;
    if (cos_w < cos_o) {
        const float sin_w = safe_sqrt(1.f - cos_w * cos_w);
        const float cos_x = cos_w * cos_o + sin_w * sin_o;  // cos(theta_w - theta_o) > cos_w >= -1
        const float sin_x = sin_w * cos_o - cos_w * sin_o;
        cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
        if (cos_p <= cos_e) return 0.f;
    }
    // phi cos' / d2, d2 = max(|p - centre|^2, radius^2), without a second division where p is outside the sphere.
    float importance = d2_true > r2 ? phi * cos_p * (inv_d * inv_d) : phi * cos_p / r2;
    if (n != vec3(0.f)) {
        // The receiver's cosine, at most cos(max(0, theta_i - theta_b)).
        const float cos_i = std::fabs(glm::dot(wi, n));
        if (cos_i < cos_b) importance *= cos_i * cos_b + safe_sqrt(1.f - cos_i * cos_i) * sin_b;
    }
    return std::isfinite(importance) ? std::max(importance, 0.f) : 0.f;
}

LightBounds light_bounds_union(const LightBounds& a, const LightBounds& b) {
    if (a.phi == 0.f) return b;
    if (b.phi == 0.f) return a;
    LightBounds u;
    u.lo = glm::min(a.lo, b.lo);
    u.hi = glm::max(a.hi, b.hi);
    u.phi = a.phi + b.phi;
    u.cos_e = std::min(a.cos_e, b.cos_e);
    u.two_sided = a.two_sided || b.two_sided;
    // The cone around both cones.
    const float theta_a = std::acos(std::clamp(a.cos_o, -1.f, 1.f)),
                theta_b = std::acos(std::clamp(b.cos_o, -1.f, 1.f));
    const float theta_d = angle_between(a.w, b.w);
    if (std::min(theta_d + theta_b, kPi) <= theta_a) {
        u.w = a.w;
        u.cos_o = a.cos_o;
    } else if (std::min(theta_d + theta_a, kPi) <= theta_b) {
        u.w = b.w;
        u.cos_o = b.cos_o;
    } else {
        const float theta_o = 0.5f * (theta_a + theta_d + theta_b);
        const vec3 axis = glm::cross(a.w, b.w);
        if (theta_o >= kPi || !(glm::dot(axis, axis) > 0.f)) {
            u.w = a.w;
            u.cos_o = -1.f;  // every direction
        } else {
            // a.w rotated toward b.w by theta_o - theta_a about their common normal.
            const vec3 k = safe_normalize(axis);
            const float theta_r = theta_o - theta_a;
            u.w = safe_normalize(a.w * std::cos(theta_r) + glm::cross(k, a.w) * std::sin(theta_r));
            u.cos_o = std::cos(theta_o);
        }
    }
    return u;
}

LightBounds triangle_light_bounds(vec3 p0, vec3 p1, vec3 p2, float phi, bool two_sided) {
    LightBounds b;
    b.lo = glm::min(p0, glm::min(p1, p2));
    b.hi = glm::max(p0, glm::max(p1, p2));
    b.phi = phi;
    b.w = safe_normalize(glm::cross(p1 - p0, p2 - p0));
    b.cos_o = 1.f;
    b.cos_e = 0.f;  // cos(pi / 2)
    b.two_sided = two_sided;
    return b;
}

namespace {

inline __m128 select(__m128 mask, __m128 a, __m128 b) { return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b)); }
inline __m128 abs4(__m128 x) { return _mm_andnot_ps(_mm_set1_ps(-0.f), x); }
inline __m128 madd(__m128 a, __m128 b, __m128 c) { return _mm_add_ps(_mm_mul_ps(a, b), c); }
// The importances (PackedLightBounds::importance, lane by lane, up to rounding) of a node's children q..q+3 for p
// (normal n, has_n false: none). The sines and 1 / d come from d^2 and unnormalised dot products, so that the square
// roots and the division run side by side rather than one after another.
inline __m128 importance4(const LightTree::Node& nd, size_t q, vec3 p, vec3 n, bool has_n) {
    const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.f);
    const __m128 tx = _mm_sub_ps(_mm_set1_ps(p.x), _mm_load_ps(nd.cx + q));
    const __m128 ty = _mm_sub_ps(_mm_set1_ps(p.y), _mm_load_ps(nd.cy + q));
    const __m128 tz = _mm_sub_ps(_mm_set1_ps(p.z), _mm_load_ps(nd.cz + q));
    const __m128 d2 = madd(tz, tz, madd(ty, ty, _mm_mul_ps(tx, tx)));
    const __m128 radius = _mm_load_ps(nd.radius + q);
    const __m128 r2 = _mm_mul_ps(radius, radius);
    // 1 / d^2 and 1 / d (0 where d^2 is so small that 1 / d^2 would overflow: p is at the centre).
    const __m128 d_positive = _mm_cmpgt_ps(d2, _mm_set1_ps(0x1p-100f));
    __m128 alive = _mm_or_ps(d_positive, _mm_cmpgt_ps(r2, zero));
    const __m128 inv_d2 = _mm_and_ps(d_positive, _mm_div_ps(one, d2));
    const __m128 inv_d = _mm_mul_ps(_mm_sqrt_ps(d2), inv_d2);
    // The angle between the cone's axis and the direction to p: its cosine d cos_w and sine d sin_w first.
    __m128 dcos_w =
        madd(_mm_load_ps(nd.wz + q), tz, madd(_mm_load_ps(nd.wy + q), ty, _mm_mul_ps(_mm_load_ps(nd.wx + q), tx)));
    dcos_w = select(_mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(nd.two_sided + q))), abs4(dcos_w),
                    dcos_w);
    const __m128 sin_w = _mm_mul_ps(_mm_sqrt_ps(_mm_max_ps(_mm_sub_ps(d2, _mm_mul_ps(dcos_w, dcos_w)), zero)), inv_d);
    const __m128 cos_w = _mm_mul_ps(dcos_w, inv_d);
    // The half angle theta_b the bounding sphere subtends at p (everything when p is inside it).
    const __m128 outside = _mm_cmpgt_ps(d2, r2);
    const __m128 sin_b = _mm_and_ps(outside, _mm_mul_ps(radius, inv_d));
    const __m128 cos_b =
        select(outside, _mm_sqrt_ps(_mm_max_ps(_mm_sub_ps(one, _mm_mul_ps(r2, inv_d2)), zero)), _mm_set1_ps(-1.f));
    // theta' = max(0, theta_w - theta_o - theta_b): the least angle between a normal and a direction to p.
    const __m128 cos_o = _mm_load_ps(nd.cos_o + q), sin_o = _mm_load_ps(nd.sin_o + q);
    const __m128 cos_x = madd(sin_w, sin_o, _mm_mul_ps(cos_w, cos_o));
    const __m128 sin_x = _mm_sub_ps(_mm_mul_ps(sin_w, cos_o), _mm_mul_ps(cos_w, sin_o));
    const __m128 beyond = _mm_cmplt_ps(cos_w, cos_o);
    const __m128 cos_p =
        select(_mm_andnot_ps(_mm_cmpgt_ps(cos_x, cos_b), beyond), madd(sin_x, sin_b, _mm_mul_ps(cos_x, cos_b)), one);
    alive = _mm_andnot_ps(_mm_and_ps(beyond, _mm_cmple_ps(cos_p, _mm_load_ps(nd.cos_e + q))), alive);
    // phi cos' / max(|p - centre|^2, radius^2).
    const __m128 inv_dist2 = select(outside, inv_d2, _mm_load_ps(nd.inv_r2 + q));
    __m128 imp = _mm_mul_ps(_mm_mul_ps(_mm_load_ps(nd.phi + q), cos_p), inv_dist2);
    if (has_n) {
        // The receiver's cosine, at most cos(max(0, theta_i - theta_b)).
        const __m128 dcos_i =
            abs4(madd(tz, _mm_set1_ps(n.z), madd(ty, _mm_set1_ps(n.y), _mm_mul_ps(tx, _mm_set1_ps(n.x)))));
        const __m128 sin_i =
            _mm_mul_ps(_mm_sqrt_ps(_mm_max_ps(_mm_sub_ps(d2, _mm_mul_ps(dcos_i, dcos_i)), zero)), inv_d);
        const __m128 cos_i = _mm_mul_ps(dcos_i, inv_d);
        imp = select(_mm_cmplt_ps(cos_i, cos_b), _mm_mul_ps(imp, madd(sin_i, sin_b, _mm_mul_ps(cos_i, cos_b))), imp);
    }
    // Finite and positive, or 0 (a NaN compares false).
    alive = _mm_and_ps(alive, _mm_cmplt_ps(abs4(imp), _mm_set1_ps(std::numeric_limits<float>::infinity())));
    return _mm_and_ps(alive, _mm_max_ps(imp, zero));
}

// The importances of a node's children into c; returns their sum (pairwise).
float child_importances(const LightTree::Node& nd, vec3 p, vec3 n, bool has_n, float* c) {
    // The lanes are filled from the first: a node of at most four children (the Cornell box's quad) takes one pass.
    for (size_t q = 0; q < size_t(LightTree::kWidth); q += 4)
        _mm_store_ps(c + q, q == 0 || nd.child[q] != kNoIndex ? importance4(nd, q, p, n, has_n) : _mm_setzero_ps());
    if constexpr (LightTree::kWidth == 4) return (c[0] + c[1]) + (c[2] + c[3]);
    return ((c[0] + c[1]) + (c[2] + c[3])) + ((c[4] + c[5]) + (c[6] + c[7]));
}

bool usable(float sum) { return sum > 0.f && sum < std::numeric_limits<float>::infinity(); }

}  // namespace

LightTree::LightTree(const std::vector<LightBounds>& lights) {
    std::vector<uint32_t> order;
    for (uint32_t k = 0; k < lights.size(); ++k)
        if (lights[k].phi > 0.f && std::isfinite(lights[k].phi) && glm::dot(lights[k].w, lights[k].w) > 0.f)
            order.push_back(k);
    m_trail.assign(lights.size(), 0);
    m_leaf.assign(lights.size(), kNoIndex);
    if (order.empty()) return;
    std::vector<BuildNode> bin;
    bin.reserve(2 * order.size() - 1);
    build(bin, order, 0, order.size(), lights, 0);
    // Each node takes kWidthLog2 levels of the binary tree (and has at least two children but at the root of a
    // single emitter): fewer nodes than emitters.
    m_nodes.reserve(std::max<size_t>(order.size() - 1, 1));
    collapse(bin, 0, 0, 0);
    m_nodes.shrink_to_fit();  // about n / 3 nodes of 8 lanes
}

size_t LightTree::memory_bytes() const {
    return m_nodes.capacity() * sizeof(Node) + m_trail.capacity() * sizeof(uint64_t) +
           m_leaf.capacity() * sizeof(uint32_t);
}

uint32_t LightTree::collapse(const std::vector<BuildNode>& bin, uint32_t b, uint64_t trail, int shift) {
    // The children: b's binary descendants kWidthLog2 levels down, or the leaves above them (b itself, a leaf root).
    std::array<uint32_t, kWidth> slots{};
    int count = 1;
    slots[0] = b;
    for (int level = 0; level < kWidthLog2; ++level) {
        std::array<uint32_t, kWidth> next{};
        int n = 0;
        for (int i = 0; i < count; ++i) {
            const BuildNode& s = bin[slots[size_t(i)]];
            if (s.emitter != kNoIndex) {
                next[size_t(n++)] = slots[size_t(i)];
            } else {
                next[size_t(n++)] = s.child[0];
                next[size_t(n++)] = s.child[1];
            }
        }
        slots = next;
        count = n;
    }
    const uint32_t node = uint32_t(m_nodes.size());
    m_nodes.emplace_back();
    {
        Node& nd = m_nodes.back();
        for (size_t i = 0; i < size_t(kWidth); ++i) {
            // Empty lanes: power 0, so importance 0.
            PackedLightBounds pb;
            if (int(i) < count) pb = PackedLightBounds(bin[slots[i]].bounds);
            nd.cx[i] = pb.centre.x;
            nd.cy[i] = pb.centre.y;
            nd.cz[i] = pb.centre.z;
            nd.radius[i] = pb.radius;
            nd.inv_r2[i] = 1.f / (pb.radius * pb.radius);
            nd.wx[i] = pb.w.x;
            nd.wy[i] = pb.w.y;
            nd.wz[i] = pb.w.z;
            nd.phi[i] = int(i) < count ? pb.phi : 0.f;
            nd.cos_o[i] = pb.cos_o;
            nd.sin_o[i] = pb.sin_o;
            nd.cos_e[i] = pb.cos_e;
            nd.two_sided[i] = pb.two_sided ? 0xffffffffu : 0u;
            nd.child[i] = kNoIndex;
        }
    }
    for (int i = 0; i < count; ++i) {
        const uint32_t s = slots[size_t(i)];
        const uint64_t t = trail | (uint64_t(i) << shift);
        uint32_t child;
        if (bin[s].emitter != kNoIndex) {
            child = kLeafBit | bin[s].emitter;
            m_trail[bin[s].emitter] = t;
            m_leaf[bin[s].emitter] = node;
        } else {
            child = collapse(bin, s, t, shift + kWidthLog2);
        }
        m_nodes[node].child[i] = child;
    }
    return node;
}

uint32_t LightTree::build(std::vector<BuildNode>& out, std::vector<uint32_t>& order, size_t begin, size_t end,
                          const std::vector<LightBounds>& lights, int depth) {
    m_depth = std::max(m_depth, depth);
    const uint32_t node = uint32_t(out.size());
    out.emplace_back();
    if (end - begin == 1) {
        const uint32_t k = order[begin];
        out[node].bounds = lights[k];
        out[node].emitter = k;
        return node;
    }
    LightBounds all;
    vec3 c_lo(std::numeric_limits<float>::infinity()), c_hi(-std::numeric_limits<float>::infinity());
    for (size_t i = begin; i < end; ++i) {
        const LightBounds& b = lights[order[i]];
        all = light_bounds_union(all, b);
        const vec3 c = 0.5f * (b.lo + b.hi);
        c_lo = glm::min(c_lo, c);
        c_hi = glm::max(c_hi, c);
    }
    auto centroid = [&](uint32_t k, int axis) { return 0.5f * (lights[k].lo[axis] + lights[k].hi[axis]); };

    // Binned split by the surface area orientation heuristic, along every axis the centroids spread over.
    constexpr int kBuckets = 12;
    auto bucket_of = [&](uint32_t k, int axis) {
        const float t = (centroid(k, axis) - c_lo[axis]) / (c_hi[axis] - c_lo[axis]);
        return std::clamp(int(t * kBuckets), 0, kBuckets - 1);
    };
    double best_cost = std::numeric_limits<double>::infinity();
    int best_axis = -1, best_split = 0;
    // Deep in a degenerate tree (many emitters in one place), halves by count keep the bit trail within 64 bits.
    constexpr int kMaxHeuristicDepth = 40;
    const vec3 diag = all.hi - all.lo;
    const float max_extent = max_component(diag);
    for (int axis = 0; axis < 3 && depth < kMaxHeuristicDepth; ++axis) {
        if (!(c_hi[axis] > c_lo[axis]) || !(diag[axis] > 0.f)) continue;
        std::array<LightBounds, kBuckets> buckets{};
        for (size_t i = begin; i < end; ++i) {
            const uint32_t k = order[i];
            LightBounds& b = buckets[size_t(bucket_of(k, axis))];
            b = light_bounds_union(b, lights[k]);
        }
        // Costs of splitting after bucket s: prefix and suffix unions.
        std::array<double, kBuckets - 1> cost{};
        LightBounds below;
        for (int s = 0; s < kBuckets - 1; ++s) {
            below = light_bounds_union(below, buckets[size_t(s)]);
            cost[size_t(s)] = below.phi > 0.f ? orientation_cost(below) : 0.0;
        }
        LightBounds above;
        for (int s = kBuckets - 2; s >= 0; --s) {
            above = light_bounds_union(above, buckets[size_t(s) + 1]);
            cost[size_t(s)] += above.phi > 0.f ? orientation_cost(above) : 0.0;
        }
        const double kr = double(max_extent) / double(diag[axis]);  // favours splitting long boxes
        for (int s = 0; s < kBuckets - 1; ++s) {
            const double c = kr * cost[size_t(s)];
            if (c < best_cost && std::isfinite(c)) {
                best_cost = c;
                best_axis = axis;
                best_split = s;
            }
        }
    }
    size_t mid = begin;
    if (best_axis >= 0) {
        mid = size_t(std::partition(order.begin() + long(begin), order.begin() + long(end),
                                    [&](uint32_t k) { return bucket_of(k, best_axis) <= best_split; }) -
                     order.begin());
    }
    if (mid == begin || mid == end) {
        // No useful split: halves by count along the centroids' longest axis.
        const vec3 ext = c_hi - c_lo;
        const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
        mid = begin + (end - begin) / 2;
        std::nth_element(order.begin() + long(begin), order.begin() + long(mid), order.begin() + long(end),
                         [&](uint32_t a, uint32_t b) {
                             const float ca = centroid(a, axis), cb = centroid(b, axis);
                             return ca < cb || (ca == cb && a < b);
                         });
    }
    const uint32_t first = build(out, order, begin, mid, lights, depth + 1);
    const uint32_t second = build(out, order, mid, end, lights, depth + 1);
    out[node].bounds = all;
    out[node].child[0] = first;
    out[node].child[1] = second;
    return node;
}

bool LightTree::sample(vec3 p, vec3 n, float u, uint32_t* k, float* pmf) const {
    if (m_nodes.empty()) return false;
    const bool has_n = n != vec3(0.f);
    float prob = 1.f;
    uint32_t node = 0;
    for (;;) {
        alignas(16) float c[kWidth];
        const float sum = child_importances(m_nodes[node], p, n, has_n, c);
        if (!usable(sum)) return false;
        // Child j where u sum falls among the running sums, never one of importance 0: the last positive one
        // where rounding carries u sum past them all.
        const float t = u * sum;
        float below[kWidth];
        float run = 0.f;
        int last = 0, j = 0;
        for (int i = 0; i < kWidth; ++i) {
            below[i] = run;
            if (c[i] > 0.f) last = i;
            run += c[i];
            if (i < kWidth - 1 && t >= run) j = i + 1;
        }
        j = std::min(j, last);
        prob *= c[j] / sum;
        u = std::min(std::max(t - below[j], 0.f) / c[j], 0x1.fffffep-1f);
        const uint32_t child = m_nodes[node].child[j];
        if (child & kLeafBit) {
            *k = child & ~kLeafBit;
            *pmf = prob;
            return prob > 0.f;
        }
        node = child;
    }
}

float LightTree::pmf(uint32_t k, vec3 p, vec3 n) const {
    if (k >= m_leaf.size() || m_leaf[k] == kNoIndex) return 0.f;
    const bool has_n = n != vec3(0.f);
    uint64_t trail = m_trail[k];
    float prob = 1.f;
    uint32_t node = 0;
    for (;;) {
        alignas(16) float c[kWidth];
        const float sum = child_importances(m_nodes[node], p, n, has_n, c);
        if (!usable(sum)) return 0.f;
        const size_t j = size_t(trail & uint64_t(kWidth - 1));
        trail >>= kWidthLog2;
        prob *= c[j] / sum;
        const uint32_t child = m_nodes[node].child[j];
        if (child & kLeafBit) return prob;
        node = child;
    }
}

}  // namespace pv
