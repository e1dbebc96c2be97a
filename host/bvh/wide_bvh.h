// The CPU reference's tree: the binary BVH (bvh.h) collapsed into nodes of up
// to eight children, whose boxes are tested against a ray in one pass of
// eight-lane vector arithmetic (AVX on x86-64), where the binary traversal
// tests two boxes per node, one after the other. The GPU kernels keep the
// binary tree: on SIMD hardware each lane is a ray already.
//
//   bvh::WideBvh wide = bvh::collapseBvh(build.nodes, build.primitives);
//   shared::Hit hit = bvh::traceWide(view, wide, ray, false, alphaKey);
//
// A leaf is a binary leaf or a whole binary subtree of at most
// LEAF_PRIMITIVES primitives (where the surface area heuristic expects
// testing them together to cost less than descending: wide_bvh.cpp), its
// primitives copied into blocks of eight of one kind in structure-of-arrays
// form, each block tested in one pass of eight-lane arithmetic, lane by lane
// the operations of shared/intersect.h intersectTriangle (and that function
// itself where an edge function is exactly zero and it recomputes in double)
// or intersectSphere. A box is culled by the same test as in the binary
// traversal (shared/intersect.h intersectBox, lane by lane the same
// operations), and a leaf that merges binary leaves only adds tests of
// primitives whose boxes the binary traversal may have culled, which cannot
// yield a nearer hit. So traceWide returns the binary traversal's hit bit for
// bit, ties included (shared/bvh_leaf.h: among equal distances the smallest
// leaf index, whatever the order of the tests).
//
// Collapsing follows Wald, Benthin and Boulos, "Getting Rid of Packets:
// Efficient SIMD Single-Ray Traversal using Multi-branching BVHs" (RT 2008):
// a wide node takes its binary node's two children, then repeatedly opens the
// interior child of largest surface area, until it has eight or only leaves.
// Traversal visits the hit children nearest first, with each one's entry
// distance on the stack so that a box entered beyond the current hit is
// skipped when popped.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#if defined(__AVX__) || defined(__SSE__)
#include <immintrin.h>
#endif

#include "shared/bvh.h"
#include "shared/intersect.h"
#include "shared/ray.h"

namespace vkpath::bvh {

struct WideBvh {
    static constexpr uint32_t WIDTH = 8;
    // The deepest a wide node can be: collapsing never deepens the tree.
    static constexpr uint32_t MAX_DEPTH = VKP_BVH_MAX_DEPTH;

    // A node's children in structure-of-arrays form: one vector load per
    // bound and axis. Slots at or past `children` are unused (zero).
    struct alignas(32) Node {
        float minX[WIDTH], minY[WIDTH], minZ[WIDTH];
        float maxX[WIDTH], maxY[WIDTH], maxZ[WIDTH];
        uint32_t child[WIDTH];  // interior: index into nodes; leaf: its first block in `blocks`
        uint32_t count[WIDTH];  // leaf: its blocks (>= 1); interior: 0
        uint32_t children;      // slots in use, 1 to WIDTH
    };

    // A wide leaf is a binary leaf, or a binary subtree of at most
    // LEAF_PRIMITIVES primitives whose primitives are tested together, a
    // block of BLOCK at a time, without the subtree's inner boxes.
    static constexpr uint32_t LEAF_PRIMITIVES = 8;
    static constexpr uint32_t BLOCK = 8;
    // Up to eight primitives of one leaf and one kind, in leaf order: lane i
    // is primitive[i], a triangle (p0, p1, p2), a sphere (centre p0, radius
    // p1x), an instance (p0x: its bottom-level tree's index as a float,
    // shared/bvh.h) or unused (no bit). A leaf's triangle blocks come first,
    // then its spheres', then its instances'.
    struct alignas(32) Block {
        float p0x[BLOCK], p0y[BLOCK], p0z[BLOCK];
        float p1x[BLOCK], p1y[BLOCK], p1z[BLOCK];
        float p2x[BLOCK], p2y[BLOCK], p2z[BLOCK];
        uint32_t primitive[BLOCK];  // index into the leaf-ordered BvhPrimitive array
        uint32_t triangles;         // bit i: lane i is a triangle
        uint32_t spheres;           // bit i: lane i is a sphere
        uint32_t instances;         // bit i: lane i is an instance
    };

    std::vector<Node> nodes;    // the scene's tree's root at 0; empty for an empty tree
    std::vector<Block> blocks;  // the leaves' primitives, leaf after leaf
    // Each bottom-level tree's root in `nodes` (instancing: bvh::BvhBuild::objects).
    std::vector<uint32_t> objectRoots;

    size_t bytes() const { return nodes.size() * sizeof(Node) + blocks.size() * sizeof(Block); }
};

struct BvhBuild;

// The wide tree over a BvhBuild's depth-first node array and its
// leaf-ordered primitives: the scene's tree from node 0, and each
// bottom-level tree from its root node in `objectRoots` (BvhBuild::objects).
WideBvh collapseBvh(std::span<const shared::BvhNode> binary,
                    std::span<const shared::BvhPrimitive> primitives,
                    std::span<const uint32_t> objectRoots = {});
// The same for a whole build.
WideBvh collapseBvh(const BvhBuild& build);

namespace wide_detail {

// Eight lanes: a node's boxes, or a block's primitives.
static_assert(WideBvh::BLOCK == WideBvh::WIDTH, "a block's lanes are a node's");
using Floats = float __attribute__((vector_size(4 * WideBvh::WIDTH)));
using Ints = int32_t __attribute__((vector_size(4 * WideBvh::WIDTH)));
using Uints = uint32_t __attribute__((vector_size(4 * WideBvh::WIDTH)));

// A vector of the values at `values`.
template <typename Vector, typename Value>
inline Vector load(const Value* values) {
    Vector v;
    std::memcpy(&v, values, sizeof v);
    return v;
}
// glm's min and max, lane by lane: the binary traversal's operations.
inline Floats minOf(Floats a, Floats b) {
    return b < a ? b : a;
}
inline Floats maxOf(Floats a, Floats b) {
    return a < b ? b : a;
}

// Bit i set where lane i of `mask` is true (all ones).
inline uint32_t laneBits(Ints mask) {
#ifdef __AVX__
    return uint32_t(_mm256_movemask_ps(__m256(mask)));
#else
    uint32_t bits = 0;
    for (uint32_t i = 0; i < WideBvh::WIDTH; ++i) bits |= uint32_t(mask[i] != 0) << i;
    return bits;
#endif
}

// shared/intersect.h intersectBox for the node's eight boxes: bit i of the
// result says whether the ray meets child i before or at tLimit; entries[i] is
// where it enters.
inline uint32_t intersectBoxes(const WideBvh::Node& node, const glm::vec3& origin,
                               const glm::vec3& inverseDirection, float tLimit,
                               float entries[WideBvh::WIDTH]) {
    const Floats t0x = (load<Floats>(node.minX) - origin.x) * inverseDirection.x;
    const Floats t0y = (load<Floats>(node.minY) - origin.y) * inverseDirection.y;
    const Floats t0z = (load<Floats>(node.minZ) - origin.z) * inverseDirection.z;
    const Floats t1x = (load<Floats>(node.maxX) - origin.x) * inverseDirection.x;
    const Floats t1y = (load<Floats>(node.maxY) - origin.y) * inverseDirection.y;
    const Floats t1z = (load<Floats>(node.maxZ) - origin.z) * inverseDirection.z;
    const Floats zero = {};
    const Floats entry =
        maxOf(maxOf(minOf(t0x, t1x), minOf(t0y, t1y)), maxOf(minOf(t0z, t1z), zero));
    const Floats exit =
        minOf(minOf(maxOf(t0x, t1x), maxOf(t0y, t1y)), maxOf(t0z, t1z)) * VKP_BOX_SLACK;
    const Ints hit = (entry <= exit) & (entry <= tLimit * VKP_BOX_SLACK);
    std::memcpy(entries, &entry, sizeof entry);
    return laneBits(hit) & ((1u << node.children) - 1u);
}

// shared::bvhIntervalEnd for each lane's primitive (of the bottom-level tree
// of `instance`, or of the scene's tree): hit.t, or one ulp beyond it where
// the lane's primitive would win a tie.
inline Floats intervalEnds(const WideBvh::Block& block, const shared::Hit& hit, uint32_t instance) {
    const Uints primitives = load<Uints>(block.primitive);
    Ints winsTie{};
    if (hit.primitive != VKP_NO_HIT) {
        const uint32_t hitTop = hit.instance != VKP_NO_INSTANCE ? hit.instance : hit.primitive;
        if (instance == VKP_NO_INSTANCE)
            winsTie = Ints(primitives < hitTop);  // a lane's key is (its index, its index)
        else if (instance != hitTop)
            winsTie = instance < hitTop ? ~Ints{} : Ints{};
        else
            winsTie = Ints(primitives < hit.primitive);
    }
    Uints bits = Uints{} + glm::floatBitsToUint(hit.t);
    bits -= Uints(winsTie);  // true lanes are all ones: minus -1 adds one
    Floats ends;
    std::memcpy(&ends, &bits, sizeof ends);
    return ends;
}

// The square root of each lane, correctly rounded as std::sqrt is, without
// std::sqrt's call into libm to set errno for a lane below zero (such lanes,
// which callers mask, give NaN, or 0 without AVX).
inline Floats squareRoot(Floats x) {
#ifdef __AVX__
    return Floats(_mm256_sqrt_ps(__m256(x)));
#else
    for (uint32_t i = 0; i < WideBvh::WIDTH; ++i) x[i] = x[i] >= 0.0f ? std::sqrt(x[i]) : 0.0f;
    return x;
#endif
}

// shared/intersect.h intersectSphere for a block of spheres, lane by lane the
// same operations (glm's dot is (x + y) + z): bit i of the result says
// whether sphere i is hit in [0, limit[i]), t[i] is where.
inline uint32_t intersectSpheres(const WideBvh::Block& block, const shared::Ray& ray, Floats limit,
                                 Floats& t) {
    const glm::vec3 o = ray.origin, d = ray.direction;
    const Floats fx = o.x - load<Floats>(block.p0x), fy = o.y - load<Floats>(block.p0y),
                 fz = o.z - load<Floats>(block.p0z);
    const Floats radius = load<Floats>(block.p1x);
    const float a = glm::dot(d, d);
    const Floats b = -((fx * d.x + fy * d.y) + fz * d.z);
    const Floats closestX = a * fx + b * d.x, closestY = a * fy + b * d.y,
                 closestZ = a * fz + b * d.z;
    const Floats scaledRadius = a * radius;
    const Floats discriminant = scaledRadius * scaledRadius -
                                ((closestX * closestX + closestY * closestY) + closestZ * closestZ);
    const Floats zero = {};
    uint32_t hit = laneBits(discriminant >= zero) & block.spheres;
    if (hit == 0) return 0;
    const Floats c = ((fx * fx + fy * fy) + fz * fz) - radius * radius;
    const Floats root = squareRoot(discriminant / a);
    const Floats q = b + (b >= zero ? root : -root);
    hit &= laneBits(q != zero);
    const Floats t0 = c / q, t1 = q / a;
    const Floats tNear = t1 < t0 ? t1 : t0, tFar = t0 < t1 ? t1 : t0;
    const Ints nearIn = (tNear >= zero) & (tNear < limit);
    t = nearIn ? tNear : tFar;
    return hit & laneBits(nearIn | ((tFar >= zero) & (tFar < limit)));
}

// shared/intersect.h intersectTriangle for a block of triangles, lane by lane
// the same operations: bit i of the result says whether triangle i is hit in
// [0, limit[i]), t[i] and (v[i], w[i]) / det[i] are where. Returns
// `fallback` true, and nothing else, when an edge function of a lane rounds
// to zero: there intersectTriangle decides in double.
inline uint32_t intersectTriangles(const WideBvh::Block& block,
                                   const shared::TriangleRay& triangleRay, Floats limit, Floats& t,
                                   Floats& v, Floats& w, Floats& det, bool& fallback) {
    // Vertices relative to the origin in the permuted axes, the shear, the edge functions.
    const glm::vec3 o = triangleRay.origin;
    const Floats p0[3] = {load<Floats>(block.p0x) - o.x, load<Floats>(block.p0y) - o.y,
                          load<Floats>(block.p0z) - o.z};
    const Floats p1[3] = {load<Floats>(block.p1x) - o.x, load<Floats>(block.p1y) - o.y,
                          load<Floats>(block.p1z) - o.z};
    const Floats p2[3] = {load<Floats>(block.p2x) - o.x, load<Floats>(block.p2y) - o.y,
                          load<Floats>(block.p2z) - o.z};
    const uint32_t kx = triangleRay.kx, ky = triangleRay.ky, kz = triangleRay.kz;
    const float dx = triangleRay.direction.x, dy = triangleRay.direction.y,
                dz = triangleRay.direction.z;
    const Floats ax = dz * p0[kx] - dx * p0[kz], ay = dz * p0[ky] - dy * p0[kz];
    const Floats bx = dz * p1[kx] - dx * p1[kz], by = dz * p1[ky] - dy * p1[kz];
    const Floats cx = dz * p2[kx] - dx * p2[kz], cy = dz * p2[ky] - dy * p2[kz];
    const Floats u = cx * by - cy * bx;
    v = ax * cy - ay * cx;
    w = bx * ay - by * ax;
    const Floats zero = {};
    fallback = (laneBits((u == zero) | (v == zero) | (w == zero)) & block.triangles) != 0;
    if (fallback) return 0;
    const Ints negative = (u < zero) | (v < zero) | (w < zero);
    const Ints positive = (u > zero) | (v > zero) | (w > zero);
    det = u + v + w;
    const Floats scaledT = u * p0[kz] + v * p1[kz] + w * p2[kz];
    t = scaledT / (dz * det);
    return laneBits(~(negative & positive) & (det != zero) & (t >= zero) & (t < limit)) &
           block.triangles;
}

template <typename View>
bool traceFrom(const View& view, const WideBvh& wide, const shared::Ray& ray, uint32_t root,
               uint32_t instance, bool anyHit, uint32_t alphaKey, shared::Hit& hit);

// A block of instances: each lane's bottom-level tree traced with the ray in
// its space, as shared/bvh_traverse.h bvhTraceInstance does (the same
// operations, so the same object-space ray). Returns whether it took a hit.
template <typename View>
bool testInstances(const View& view, const WideBvh& wide, const WideBvh::Block& block,
                   const shared::Ray& ray, uint32_t alphaKey, bool anyHit, shared::Hit& hit) {
    bool took = false;
    for (uint32_t bits = block.instances; bits != 0; bits &= bits - 1) {
        const uint32_t lane = uint32_t(__builtin_ctz(bits));
        const uint32_t index = block.primitive[lane];
        const shared::BvhPrimitive instance = view.bvhPrimitive(index);
        glm::vec4 rows[3];
        for (uint32_t k = 0; k < 3; ++k)
            rows[k] = glm::uintBitsToFloat(view.bvhNodeTexel(instance.id + k));
        shared::Ray objectRay;
        objectRay.origin = shared::transformPoint(rows, ray.origin);
        objectRay.direction = shared::transformDirection(rows, ray.direction);
        objectRay.tMax = ray.tMax;
        objectRay.pixel = ray.pixel;
        const auto object = uint32_t(block.p0x[lane]);  // its tree's index, as a float
        if (traceFrom(view, wide, objectRay, wide.objectRoots[object], index, anyHit, alphaKey,
                      hit)) {
            if (anyHit) return true;
            took = true;
        }
    }
    return took;
}

// Tests a block's primitives (of the bottom-level tree of `instance`, or of
// the scene's tree) as shared/bvh_leaf.h bvhTestPrimitive would, each in
// turn, and updates `hit` alike. Returns whether it took a hit.
template <typename View>
bool testBlock(const View& view, const WideBvh& wide, const WideBvh::Block& block,
               const shared::Ray& ray, const shared::TriangleRay& triangleRay, uint32_t instance,
               uint32_t alphaKey, bool anyHit, shared::Hit& hit) {
    if (shared::hasFeature(VKP_FEATURE_INSTANCES) && block.instances != 0)
        return testInstances(view, wide, block, ray, alphaKey, anyHit, hit);
    const Floats limit = intervalEnds(block, hit, instance);
    Floats t, v, w, det;
    uint32_t candidates;
    if (block.spheres != 0) {
        candidates = intersectSpheres(block, ray, limit, t);
    } else {
        bool fallback;
        candidates = intersectTriangles(block, triangleRay, limit, t, v, w, det, fallback);
        if (fallback) {
            bool took = false;
            for (uint32_t bits = block.triangles; bits != 0; bits &= bits - 1) {
                if (view.bvhTestPrimitive(ray, triangleRay, block.primitive[__builtin_ctz(bits)],
                                          instance, alphaKey, hit)) {
                    if (anyHit) return true;
                    took = true;
                }
            }
            return took;
        }
    }

    // The candidates nearest first (the smaller index on equal distances)
    // until one passes the alpha test: the one the tests in turn would keep.
    while (candidates != 0) {
        uint32_t best = uint32_t(__builtin_ctz(candidates));
        for (uint32_t bits = candidates & (candidates - 1); bits != 0; bits &= bits - 1) {
            const uint32_t lane = uint32_t(__builtin_ctz(bits));
            if (t[lane] < t[best] ||
                (t[lane] == t[best] && block.primitive[lane] < block.primitive[best]))
                best = lane;
        }
        candidates &= ~(1u << best);
        const uint32_t index = block.primitive[best];
        glm::vec2 barycentrics(0.0f);
        if (block.spheres == 0) {
            const float inverseDet = 1.0f / det[best];
            barycentrics = glm::vec2(v[best] * inverseDet, w[best] * inverseDet);
            if (shared::hasFeature(VKP_FEATURE_ALPHA) &&
                !view.bvhAlphaTest(view.bvhPrimitive(index), barycentrics, alphaKey))
                continue;
        }
        hit = shared::Hit{t[best], index, barycentrics, instance};
        return true;
    }
    return false;
}

// The traversal of the tree whose root is wide node `root`, for the
// bottom-level tree of `instance` or the scene's tree (VKP_NO_INSTANCE):
// updates `hit`, returns whether it took a hit (with anyHit, stops at the first).
template <typename View>
bool traceFrom(const View& view, const WideBvh& wide, const shared::Ray& ray, uint32_t root,
               uint32_t instance, bool anyHit, uint32_t alphaKey, shared::Hit& hit) {
    const shared::TriangleRay triangleRay = shared::makeTriangleRay(ray.origin, ray.direction);
    const glm::vec3 inverseDirection = shared::safeInverse(ray.direction);
    // No test of the tree's box first, as the binary traversal makes: the
    // root's boxes take one vector pass, what that one box takes in scalar
    // code, and nearly every ray of a path starts inside the scene's box.

    struct Entry {
        uint32_t child, count;  // as in WideBvh::Node; the root is (root, 0)
        float entry;            // where the ray enters its box
    };
    // Each interior node pops one entry and pushes at most WIDTH.
    Entry stack[(WideBvh::WIDTH - 1) * WideBvh::MAX_DEPTH + 1];
    uint32_t size = 0;
    stack[size++] = Entry{root, 0, 0.0f};
    bool took = false;
    while (size > 0) {
        const Entry top = stack[--size];
        if (!(top.entry <= hit.t * VKP_BOX_SLACK))
            continue;  // the box lies beyond the hit found since
        if (top.count > 0) {
            for (uint32_t b = top.child; b < top.child + top.count; ++b) {
                if (testBlock(view, wide, wide.blocks[b], ray, triangleRay, instance, alphaKey,
                              anyHit, hit)) {
                    if (anyHit) return true;
                    took = true;
                }
            }
            continue;
        }
        const WideBvh::Node& node = wide.nodes[top.child];
        float entries[WideBvh::WIDTH];
        uint32_t bits = intersectBoxes(node, ray.origin, inverseDirection, hit.t, entries);
        // Push the hit children farthest first, so the nearest is popped next.
        const uint32_t first = size;
        for (; bits != 0; bits &= bits - 1) {
            const uint32_t slot = uint32_t(__builtin_ctz(bits));
            Entry e{node.child[slot], node.count[slot], entries[slot]};
            uint32_t j = size++;
            for (; j > first && stack[j - 1].entry < e.entry; --j) stack[j] = stack[j - 1];
            stack[j] = e;
        }
    }
    return took;
}

}  // namespace wide_detail

// Closest hit (anyHit false) or any hit in [0, ray.tMax) of the tree `wide`
// collapsed from the BVH that `view` reads: the hit `view.bvhTrace` returns.
// `view` provides bvhTestPrimitive (shared/bvh_leaf.h included in it), which
// asks its alpha test with `alphaKey`, bvhPrimitive and bvhNodeTexel.
template <typename View>
shared::Hit traceWide(const View& view, const WideBvh& wide, const shared::Ray& ray, bool anyHit,
                      uint32_t alphaKey) {
    shared::Hit hit{ray.tMax, VKP_NO_HIT, glm::vec2(0.0f), VKP_NO_INSTANCE};
    if (wide.nodes.empty()) return hit;
    wide_detail::traceFrom(view, wide, ray, 0, VKP_NO_INSTANCE, anyHit, alphaKey, hit);
    return hit;
}

}  // namespace vkpath::bvh
