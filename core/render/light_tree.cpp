// core/render/light_tree.cpp: the light tree's bounds, importance, build (binned by pbrt-v4's surface area orientation
// heuristic) and pick (see light_tree.h).
#include "core/render/light_tree.h"

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

LightTree::LightTree(const std::vector<LightBounds>& lights) {
    std::vector<uint32_t> order;
    for (uint32_t k = 0; k < lights.size(); ++k)
        if (lights[k].phi > 0.f && std::isfinite(lights[k].phi) && glm::dot(lights[k].w, lights[k].w) > 0.f)
            order.push_back(k);
    m_trail.assign(lights.size(), 0);
    m_leaf.assign(lights.size(), kNoIndex);
    if (order.empty()) return;
    m_nodes.reserve(2 * order.size() - 1);
    build(order, 0, order.size(), lights, 0, 0);
}

size_t LightTree::memory_bytes() const {
    return m_nodes.capacity() * sizeof(Node) + m_trail.capacity() * sizeof(uint64_t) +
           m_leaf.capacity() * sizeof(uint32_t);
}

uint32_t LightTree::build(std::vector<uint32_t>& order, size_t begin, size_t end,
                          const std::vector<LightBounds>& lights, uint64_t trail, int depth) {
    m_depth = std::max(m_depth, depth);
    const uint32_t node = uint32_t(m_nodes.size());
    m_nodes.emplace_back();
    if (end - begin == 1) {
        const uint32_t k = order[begin];
        m_nodes[node].bounds = PackedLightBounds(lights[k]);
        m_nodes[node].index = k;
        m_nodes[node].leaf = true;
        m_trail[k] = trail;
        m_leaf[k] = node;
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
    build(order, begin, mid, lights, trail, depth + 1);
    const uint32_t second = build(order, mid, end, lights, trail | (uint64_t(1) << depth), depth + 1);
    m_nodes[node].bounds = PackedLightBounds(all);
    m_nodes[node].index = second;
    m_nodes[node].leaf = false;
    return node;
}

float LightTree::first_child_probability(const Node& node, vec3 p, vec3 n) const {
    const float c0 = m_nodes[size_t(&node - m_nodes.data()) + 1].bounds.importance(p, n);
    const float c1 = m_nodes[node.index].bounds.importance(p, n);
    const float sum = c0 + c1;
    if (!(sum > 0.f) || !std::isfinite(sum)) return -1.f;
    return c0 / sum;
}

bool LightTree::sample(vec3 p, vec3 n, float u, uint32_t* k, float* pmf) const {
    if (m_nodes.empty()) return false;
    float prob = 1.f;
    uint32_t i = 0;
    if (m_nodes[0].leaf && !(m_nodes[0].bounds.importance(p, n) > 0.f)) return false;
    while (!m_nodes[i].leaf) {
        const float p0 = first_child_probability(m_nodes[i], p, n);
        if (p0 < 0.f) return false;
        if (u < p0) {
            u = std::min(u / p0, 0x1.fffffep-1f);
            prob *= p0;
            i = i + 1;
        } else {
            const float p1 = 1.f - p0;
            u = std::min((u - p0) / p1, 0x1.fffffep-1f);
            prob *= p1;
            i = m_nodes[i].index;
        }
    }
    *k = m_nodes[i].index;
    *pmf = prob;
    return prob > 0.f;
}

float LightTree::pmf(uint32_t k, vec3 p, vec3 n) const {
    if (k >= m_leaf.size() || m_leaf[k] == kNoIndex) return 0.f;
    if (m_nodes[0].leaf) return m_nodes[0].bounds.importance(p, n) > 0.f ? 1.f : 0.f;
    uint64_t trail = m_trail[k];
    float prob = 1.f;
    uint32_t i = 0;
    while (!m_nodes[i].leaf) {
        const float p0 = first_child_probability(m_nodes[i], p, n);
        if (p0 < 0.f) return 0.f;
        if (trail & 1u) {
            prob *= 1.f - p0;
            i = m_nodes[i].index;
        } else {
            prob *= p0;
            i = i + 1;
        }
        trail >>= 1;
    }
    return prob;
}

}  // namespace pv
