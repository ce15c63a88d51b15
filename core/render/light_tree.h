// core/render/light_tree.h: a bounding volume hierarchy over the emissive triangles for choosing one in proportion
// to an estimate of its contribution at a shading point (Conty Estevez and Kulla 2018, in the form of pbrt-v4's
// BVHLightSampler), with the exact probability of each pick for MIS.
#pragma once

#include <cstdint>
#include <vector>

#include "core/base/math.h"

// its emitters' positions (a box), total power (phi) and emission directions (a cone: axis w, spread theta_o of the
// normals about w, theta_e the further angle each emits over, pi/2 for a surface). A pick descends from the root,
// choosing a child with probability proportional to its importance for the shading point p and normal n
// (LightBounds::importance); the probability of the emitter reached is the product of the choices, and pmf()
// recomputes it exactly by walking the same nodes along the emitter's stored trail (which child at each depth),
// with the same arithmetic, so the density MIS weighs a BSDF-found emitter with is the sampling density.
// The binary tree built is collapsed into an 8-wide one (each node's children are its binary descendants three levels
// down, or the leaves above them) whose nodes hold their children's bounds side by side, lane by lane: a step of the
// pick computes the eight importances in two independent passes of 4-wide SSE arithmetic and chooses among them, so
// a pick takes a third of the binary tree's steps. Choosing among the descendants by their own bounds, tighter than
// their ancestors', also lowers the error per sample (many-lights: 0.82x that of 4 lanes, 0.61x that of the binary
// tree) and the dead ends.

// log2 of the light tree's node width: 3, eight lanes (2, four lanes, also works: a cheaper step, a worse pick).
#ifndef PV_LIGHT_TREE_WIDTH_LOG2
#define PV_LIGHT_TREE_WIDTH_LOG2 3
#endif

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

// LightBounds as a node's lane holds them: the box as its bounding sphere, the cone's sine precomputed. Its scalar
// importance is LightBounds::importance; the pick's four-lane one (light_tree.cpp) agrees up to rounding.
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

    // The wide nodes (each holds up to kWidth children's bounds).
    size_t node_count() const { return m_nodes.size(); }
    size_t memory_bytes() const;
    // The binary tree's depth (the wide tree's is about 1 / kWidthLog2 of it).
    int depth() const { return m_depth; }

    // A node: its children's bounds as PackedLightBounds (and 1 / radius^2), one lane each, laid out so that each
    // pass of 4-wide arithmetic gives four importances. An empty lane has phi 0 (importance 0).
    static constexpr int kWidthLog2 = PV_LIGHT_TREE_WIDTH_LOG2;
    static constexpr int kWidth = 1 << kWidthLog2;
    struct alignas(64) Node {
        float cx[kWidth], cy[kWidth], cz[kWidth], radius[kWidth], inv_r2[kWidth];  // bounding spheres
        float wx[kWidth], wy[kWidth], wz[kWidth], phi[kWidth];                     // cone axes, powers
        float cos_o[kWidth], sin_o[kWidth], cos_e[kWidth];
        uint32_t two_sided[kWidth];  // all bits set when two-sided
        uint32_t child[kWidth];      // kLeafBit | emitter, or the child node's index
    };
    static constexpr uint32_t kLeafBit = 0x80000000u;

private:
    struct BuildNode {
        LightBounds bounds;
        uint32_t child[2] = {0, 0};   // an interior node's children
        uint32_t emitter = kNoIndex;  // a leaf's emitter
    };
    uint32_t build(std::vector<BuildNode>& out, std::vector<uint32_t>& order, size_t begin, size_t end,
                   const std::vector<LightBounds>& lights, int depth);
    uint32_t collapse(const std::vector<BuildNode>& bin, uint32_t b, uint64_t trail, int shift);

    std::vector<Node> m_nodes;      // the root at 0
    std::vector<uint64_t> m_trail;  // per emitter: its lane at each depth, kWidthLog2 bits each from bit 0
    std::vector<uint32_t> m_leaf;   // per emitter: the node holding it, kNoIndex when left out
    int m_depth = 0;
};

}  // namespace pv
