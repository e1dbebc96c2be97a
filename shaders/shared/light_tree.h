// The light tree: a binary tree over the scene's bounded lights (emissive
// triangles and spheres, point and spot lights) whose nodes bound their
// lights' positions, power and directions of emission, so that a shading
// point chooses a light in proportion to an estimate of what each subtree
// sends it, not to its power alone (Conty Estevez and Kulla, "Importance
// Sampling of Many Lights with Adaptive Tree Splitting", HPG 2018; pbrt-v4's
// BVHLightSampler, whose importance this is, section 12.6.3 of the 4th
// edition). The environment and directional lights lie outside it: the
// light alias table picks between the tree as a whole and each of them by
// power (shared/path/light_choice.h).
//
// Built on the host (host/wavefront/light_tree.h); nodes depth-first, an
// interior node's first child right after it. A light's path from the root,
// one bit per level (1: the second child), is its trail, from which its
// probability at a point is recomputed for MIS.
#ifndef VKPATH_SHARED_LIGHT_TREE_H
#define VKPATH_SHARED_LIGHT_TREE_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/records.h"
#include "shared/unit_vector.h"

// LightTreeNode::flags.
#define VKP_LIGHT_NODE_LEAF 1u       // `index` is a light, not the second child
#define VKP_LIGHT_NODE_TWO_SIDED 2u  // emits about -axis as about axis
// Every light of it is a triangle of normal `axis` (cosNormals 1), emitting
// only toward points p with dot(p, axis) > frontPlane
#define VKP_LIGHT_NODE_PLANAR 4u
// Leaves lie at depth <= this (root 0), so a trail fits a word with the
// all-ones word (VKP_NO_LIGHT) left over for a light outside the tree.
#define VKP_LIGHT_TREE_MAX_DEPTH 31u
// A tree walk's number is rescaled at every level; it places the point on
// the chosen light only where the light's probability kept it this fine
// (2^-24 / pmf, the float's error after the rescaling, at most 2^-16), else
// the point's number is drawn afresh (shared/path/next_event.h).
#define VKP_LIGHT_TREE_REUSE_MIN_PMF 0.00390625f

VKP_NAMESPACE_BEGIN

// LightTreeNode's fields (type, name, first 32-bit word; shared/records.h).
#define VKP_LIGHT_TREE_NODE_FIELDS(F)                                                     \
    /* the box of the lights' points (world space, rounded outward) */                    \
    F(vec3, boundsMin, 0)                                                                 \
    /* the lights' power (luminance-weighted watts: the alias table's weights) */         \
    F(float, power, 3)                                                                    \
    F(vec3, boundsMax, 4)                                                                 \
    /* interior: the second child's index; leaf: the light's index */                     \
    F(uint, index, 7)                                                                     \
    /* unit axis of the cone that holds the lights' surface normals (spot: its axis) */   \
    F(vec3, axis, 8)                                                                      \
    /* cosine of that cone's half-angle (-1: every direction) */                          \
    F(float, cosNormals, 11)                                                              \
    /* cosine of the angle beyond the normals' cone that emission reaches (0: pi/2) */    \
    F(float, cosEmission, 12)                                                             \
    /* VKP_LIGHT_NODE_* */                                                                \
    F(uint, flags, 13)                                                                    \
    /* planar nodes: the least dot(x, axis) over their lights' points x (rounded down) */ \
    F(float, frontPlane, 14)                                                              \
    /* 0: whole texels */                                                                 \
    F(uint, padding, 15)
struct LightTreeNode {
    VKP_LIGHT_TREE_NODE_FIELDS(VKP_FIELD_DECLARE)
};

// cos(a - b) for angles a, b in [0, pi] given by sine and cosine, 1 where
// a < b (the clamped difference max(0, a - b)).
VKP_FN float cosSubtractClamped(float sinA, float cosA, float sinB, float cosB) {
    if (cosA > cosB) return 1.0f;
    return cosA * cosB + sinA * sinB;
}

// sin(max(0, a - b)), likewise.
VKP_FN float sinSubtractClamped(float sinA, float cosA, float sinB, float cosB) {
    if (cosA > cosB) return 0.0f;
    return sinA * cosB - cosA * sinB;
}

// What `node`'s lights may send to the point `p` of unit normal `n`, up to a
// common factor: zero behind a planar node (VKP_LIGHT_NODE_PLANAR), else its
// power, over the squared distance from p to its box,
// times the cosine of the least angle between a direction from its lights
// toward p and the cone of their normals, times the cosine of the least
// angle between n (either side: a surface may transmit) and a direction
// toward the box, both angles less the box's extent seen from p (the cone
// that holds its bounding sphere). n = 0: a point of no surface (the second
// cosine is 1).
//
// Zero only where no light of the node can reach p (every direction toward
// p lies beyond the emission's reach), so sampling by it is unbiased; any
// other value only steers the samples. The cosines are pbrt-v4's
// (LightBounds::Importance). The distance is not: pbrt-v4 divides by the
// squared distance to the box's centre, at least its half-diagonal
// squared, which gives a node the same weight whether p lies under its
// near edge or far beyond it; in a field of small lamps low over a floor
// (tools/bench/suite/make-suite-scenes lamp_field) half of each choice near
// the root then went to lamps tens of metres away. To the box's nearest
// point (at least 10^-4 of its half-diagonal squared, where p is inside
// it), the same scene's error at equal samples fell 15-fold
// (docs/BENCHMARKS.md, "Many lights: the light tree").
VKP_FN float lightNodeImportance(VKP_IN(LightTreeNode) node, vec3 p, vec3 n) {
    // Behind or in the plane of one-sided lights that share it (a point on
    // a lamp's back, or on the ceiling around a panel, within the float
    // rounding of p's coordinates): none reaches p. The cone test below
    // cannot say so where p lies within the box's bounding sphere, and the
    // nearest-point distance would make such a node p's likeliest.
    if ((node.flags & VKP_LIGHT_NODE_PLANAR) != 0u &&
        dot(p, node.axis) <= node.frontPlane + 1e-5f * max(max(abs(p.x), abs(p.y)), abs(p.z)))
        return 0.0f;
    vec3 centre = 0.5f * (node.boundsMin + node.boundsMax);
    vec3 halfDiagonal = 0.5f * (node.boundsMax - node.boundsMin);
    float radius2 = dot(halfDiagonal, halfDiagonal);
    vec3 d = p - centre;
    float distance2 = dot(d, d);
    // The cone of directions from p that holds the box's bounding sphere.
    float cosBounds = -1.0f;
    if (distance2 > radius2) cosBounds = sqrt(max(0.0f, 1.0f - radius2 / distance2));
    float sinBounds = sqrt(max(0.0f, 1.0f - cosBounds * cosBounds));
    // The angle between the normals' axis and the direction from the lights to p.
    vec3 toPoint = distance2 > 0.0f ? d / sqrt(distance2) : node.axis;
    float cosAxis = dot(node.axis, toPoint);
    if ((node.flags & VKP_LIGHT_NODE_TWO_SIDED) != 0u) cosAxis = abs(cosAxis);
    float sinAxis = sqrt(max(0.0f, 1.0f - cosAxis * cosAxis));
    // Less the normals' spread, then less the box's extent.
    float sinNormals = sqrt(max(0.0f, 1.0f - node.cosNormals * node.cosNormals));
    float cosBeyond = cosSubtractClamped(sinAxis, cosAxis, sinNormals, node.cosNormals);
    float sinBeyond = sinSubtractClamped(sinAxis, cosAxis, sinNormals, node.cosNormals);
    float cosLeast = cosSubtractClamped(sinBeyond, cosBeyond, sinBounds, cosBounds);
    if (cosLeast <= node.cosEmission) return 0.0f;
    float cosIncident = 1.0f;
    if (n != vec3(0.0f)) {
        float cosNormal = abs(dot(n, toPoint));
        float sinNormal = sqrt(max(0.0f, 1.0f - cosNormal * cosNormal));
        cosIncident = cosSubtractClamped(sinNormal, cosNormal, sinBounds, cosBounds);
        if (!(cosIncident > 0.0f)) return 0.0f;
    }
    vec3 outside = max(max(node.boundsMin - p, p - node.boundsMax), vec3(0.0f));
    float closest2 = dot(outside, outside);
    float importance =
        node.power * cosLeast * cosIncident / max(closest2, max(1e-4f * radius2, 1e-20f));
    // Never 0 by underflow: only the tests above say that nothing reaches p.
    return max(importance, 1e-37f);
}

// The probability of the first child, from the children's importances i0
// and i1 (positive sum): what the walk compares its number with and what
// the trail's probability multiplies, the same float in both.
VKP_FN float lightTreeFirstChildProbability(float i0, float i1) {
    return i0 / (i0 + i1);
}

VKP_NAMESPACE_END

#ifdef __cplusplus
#define VKP_RECORD LightTreeNode
VKP_RECORD_CHECK(VKP_LIGHT_TREE_NODE_FIELDS, 4)
#undef VKP_RECORD
#endif

#endif  // VKPATH_SHARED_LIGHT_TREE_H
