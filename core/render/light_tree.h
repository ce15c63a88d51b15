// core/render/light_tree.h: a bounding volume hierarchy over the finite emitters (the emissive triangles) for choosing
// one in proportion to an estimate of its contribution at a shading point (Conty Estevez and Kulla 2018, "Importance
// Sampling of Many Lights with Adaptive Tree Splitting", in the form of pbrt-v4's BVHLightSampler). Each node bounds
// its emitters' positions (a box), total power (phi) and emission directions (a cone: axis w, spread theta_o of the
// normals about w, theta_e the further angle each emits over, pi/2 for a surface). A pick descends from the root,
// choosing a child with probability proportional to its importance for the shading point p and normal n
// (LightBounds::importance); the probability of the emitter reached is the product of the choices, and pmf()
// recomputes it exactly by walking the same nodes along the emitter's stored bit trail (bit i: which child at
// depth i), with the same arithmetic, so the density MIS weighs a BSDF-found emitter with is the sampling density.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/math.h"

namespace pv {

// What a node (or one emitter) can send toward a point.
struct LightBounds {
    vec3 lo{0.f}, hi{0.f};  // box around the emitters
    float phi = 0.f;        // total power (any fixed scale: only ratios matter)
    vec3 w{0.f, 0.f, 1.f};  // unit axis of the normals' cone
    float cos_o = 1.f;      // cos theta_o: every normal is within theta_o of w
    float cos_e = 0.f;      // cos theta_e: each emits within theta_e of its normal (0: a surface, pi/2)
    bool two_sided = false;

    // An upper bound, up to a constant, on what these emitters send to a surface at p with normal n (n = 0: no
    // cosine at the receiver): phi / max(d^2, r^2) (d from the box's centre, r its half diagonal) times a bound on
    // the cosine at the emitters, cos(max(0, theta_w - theta_o - theta_b)) or 0 beyond theta_e, and on the cosine
    // at the receiver, cos(max(0, theta_i - theta_b)), theta_b the half angle the box's bounding sphere subtends.
    float importance(vec3 p, vec3 n) const;
};

// LightBounds as the pick reads them: the box as its bounding sphere, the cone's sine precomputed, so that an
// importance costs four square roots and two divisions. The same function as LightBounds::importance.
struct PackedLightBounds {
    vec3 centre{0.f};
    float radius = 0.f;  // the box's half diagonal
    vec3 w{0.f, 0.f, 1.f};
    float phi = 0.f;
    float cos_o = 1.f, sin_o = 0.f, cos_e = 0.f;
    bool two_sided = false;

    PackedLightBounds() = default;
    explicit PackedLightBounds(const LightBounds& b);
    float importance(vec3 p, vec3 n) const;
};

// Bounds of the union (the smallest cone around both cones, pbrt-v4's DirectionCone Union).
LightBounds light_bounds_union(const LightBounds& a, const LightBounds& b);

// The bounds of one emissive triangle of emitted power phi (luminance x area, doubled when two-sided).
LightBounds triangle_light_bounds(vec3 p0, vec3 p1, vec3 p2, float phi, bool two_sided);

class LightTree {
public:
    LightTree() = default;
    // Built over `lights` (emitter k: lights[k]); emitters of power not positive and finite are left out (pmf 0).
    explicit LightTree(const std::vector<LightBounds>& lights);

    bool empty() const { return m_nodes.empty(); }
    // Picks an emitter for shading point p (normal n, or 0) with u in [0, 1): its index in *k and probability in
    // *pmf. False when no emitter can light p (every importance 0).
    bool sample(vec3 p, vec3 n, float u, uint32_t* k, float* pmf) const;
    // The probability sample() picks emitter k for (p, n).
    float pmf(uint32_t k, vec3 p, vec3 n) const;

    size_t node_count() const { return m_nodes.size(); }
    size_t memory_bytes() const;
    int depth() const { return m_depth; }

private:
    struct Node {
        PackedLightBounds bounds;
        uint32_t index = 0;  // a leaf: its emitter; an interior node: its second child (the first is the next node)
        bool leaf = false;
    };
    uint32_t build(std::vector<uint32_t>& order, size_t begin, size_t end, const std::vector<LightBounds>& lights,
                   uint64_t trail, int depth);
    // The probability of the first child of interior node `node` (ci[0] / (ci[0] + ci[1])); -1 when neither child
    // can light p.
    float first_child_probability(const Node& node, vec3 p, vec3 n) const;

    std::vector<Node> m_nodes;      // depth first, the root at 0
    std::vector<uint64_t> m_trail;  // per emitter: bit i set when the pick goes to the second child at depth i
    std::vector<uint32_t> m_leaf;   // per emitter: its leaf node, kNoIndex when left out
    int m_depth = 0;
};

}  // namespace pv
