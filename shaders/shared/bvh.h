// The bounding volume hierarchy as the kernels read it: the builder's tree (a
// depth-first array of 32-byte nodes, BvhNode) packed into the records that
// traversal reads (below), and an array of 48-byte primitives in leaf order,
// all built by host/bvh/ and uploaded as two device buffers (read as texel
// buffers of 16-byte texels, shared/bvh_buffers.h), plus the hit record that
// closest-hit traversal returns.
//
// The builder's tree (depth-first preorder, root at index 0):
//   interior node i: children i + 1 and `offset`, count == 0
//   leaf:            primitives [offset, offset + count), count >= 1
//   empty BVH:       a single node with offset == 0 and count == 0 (no ray hits it)
// The builder guarantees that every leaf lies at depth <= VKP_BVH_MAX_DEPTH
// (root at depth 0), which bounds the traversal stack (shared/bvh_traverse.h).
#ifndef VKPATH_SHARED_BVH_H
#define VKPATH_SHARED_BVH_H

#include "shared/compat.h"
#include "shared/features.h"
#include "shared/precise_math.h"
#include "shared/records.h"

// The deepest a leaf may be (root at depth 0). Traversal pushes at most one
// node per level, so this is also the size of its stack.
#define VKP_BVH_MAX_DEPTH 64
// The traversal stack's entries kept in variables (shared/bvh_traverse.h); a
// tree with a leaf deeper than this sets VKP_FEATURE_DEEP_BVH, whose kernels
// keep the entries below these in an array.
#define VKP_BVH_SHALLOW_DEPTH 8u

// The node array traversal reads (shared/bvh_traverse.h), packed from the
// tree above by host/bvh (packTraversalNodes): 16-byte texels, each interior
// node one record of three texels that holds its two children's boxes, so a
// traversal step reads three texels and a pop reads none (the child's box was
// tested in its parent; leaves have no record). The twelve words are the
// boxes' floats in the order A.min.xyz A.max.xyz B.min.xyz B.max.xyz (A the
// first child). The low VKP_BVH_WORD_BITS bits of each box's six floats hold
// that child's word (bits 0-5 in A.min.x, 6-11 in A.min.y, ..., 30-31 in
// A.max.z): the floats were moved outward to the nearest values with those
// bits, up to 127 ulps (host/bvh/traversal_nodes.cpp), so every box still
// holds its subtree and is read as it is, without decoding.
//   child word: (count << 28) | index
//     count 0:      an interior node whose record starts at texel `index`
//     count 1..15:  a leaf of primitives [index, index + count)
// The root's record is at texel 0. A tree that is a single leaf has a record
// whose two children are that leaf; an empty tree's record holds two boxes
// of NaN, which no ray enters.
#define VKP_BVH_WORD_BITS 6u
#define VKP_BVH_WORD_COUNT_SHIFT 28u
#define VKP_BVH_WORD_INDEX_MASK 0x0fffffffu
#define VKP_BVH_MAX_LEAF_COUNT 15u
#define VKP_BVH_RECORD_TEXELS 3u

// BvhPrimitive::kind
#define VKP_PRIMITIVE_TRIANGLE 0u
#define VKP_PRIMITIVE_SPHERE 1u
#define VKP_PRIMITIVE_INSTANCE 2u

// Hit::primitive of a ray that hits nothing.
#define VKP_NO_HIT 0xffffffffu
// Hit::instance of a hit on a primitive of the scene's own tree.
#define VKP_NO_INSTANCE 0xffffffffu

// Instancing (scene::Instance; VKP_FEATURE_INSTANCES): a mesh that several
// nodes place is stored once, in its own space, with its own tree (a BLAS, a
// bottom-level tree), and the scene's tree (the TLAS) holds one primitive
// per placement, of kind VKP_PRIMITIVE_INSTANCE:
//   id        the first texel of its instance record in the node array
//   material  the texel of its bottom-level tree's root record
//   p0.x      its bottom-level tree's index (bvh::BvhBuild::objects), as a
//             float (exact below 2^24: the CPU's wide tree finds it by this)
//   p1, p2    its world-space box (the integrity check's; traversal reads neither)
// Every tree is in the same two arrays: the node array holds the scene's
// tree's records from texel 0, then each bottom-level tree's, then the
// instance records; the primitive array the scene's tree's leaves, then each
// bottom-level tree's. A child word indexes the whole array, so a bottom-level
// tree is traversed as the scene's tree is, from its root's texel, with the
// ray in its space (shared/bvh_traverse.h). An instance record is
// VKP_INSTANCE_RECORD_TEXELS texels of floats: the rows of the world-to-object
// matrix (x' = dot(row.xyz, x) + row.w), then those of the object-to-world
// matrix, both 3x4, the inverse computed in double by the host.
#define VKP_INSTANCE_RECORD_TEXELS 6u

// ---- the test-level trace kernels (tests/kernels/bvh_closest.comp, bvh_anyhit.comp)
#define VKP_TRACE_BINDING_NODES 0       // BvhNode[], read (a placeholder when read by address)
#define VKP_TRACE_BINDING_PRIMITIVES 1  // BvhPrimitive[], read (a placeholder when read by address)
#define VKP_TRACE_BINDING_RAYS 2        // Ray[count], read
#define VKP_TRACE_BINDING_RESULTS \
    3  // bvh_closest: Hit[count]; bvh_anyhit: uint[count], 1 = occluded

VKP_NAMESPACE_BEGIN

struct BvhNode {
    vec3 boundsMin;  // world space, padded outward so it strictly contains its subtree (host/bvh)
    uint offset;  // interior: index of the second child (the first is this node + 1); leaf: first
                  // primitive
    vec3 boundsMax;  // world space, rounded outward
    uint count;      // leaf: number of primitives (>= 1); interior: 0
};

// One triangle or sphere in leaf order. Triangles keep their three world-space
// vertices here so a leaf is one contiguous read; the original ids tell
// shading where the rest of the data lives.
// BvhPrimitive's fields (type, name, first 32-bit word; shared/records.h): the
// struct, its layout check and its texel decoding come from this list.
#define VKP_BVH_PRIMITIVE_FIELDS(F)                                                            \
    /* world space. triangle: vertex 0; sphere: centre */                                      \
    F(vec3, p0, 0)                                                                             \
    /* VKP_PRIMITIVE_TRIANGLE or VKP_PRIMITIVE_SPHERE */                                       \
    F(uint, kind, 3)                                                                           \
    /* world space. triangle: vertex 1; sphere: (radius, 0, 0) */                              \
    F(vec3, p1, 4)                                                                             \
    /* triangle: index over all scene triangles, mesh by mesh in scene order; sphere: index */ \
    /* into Scene::spheres */                                                                  \
    F(uint, id, 7)                                                                             \
    /* world space. triangle: vertex 2; sphere: unused (0) */                                  \
    F(vec3, p2, 8)                                                                             \
    /* index into Scene::materials */                                                          \
    F(uint, material, 11)
struct BvhPrimitive {
    VKP_BVH_PRIMITIVE_FIELDS(VKP_FIELD_DECLARE)
};

// The result of closest-hit traversal.
struct Hit {
    float t;         // ray parameter of the hit, 0 <= t < ray.tMax; ray.tMax when nothing was hit
    uint primitive;  // index into the leaf-ordered BvhPrimitive array; VKP_NO_HIT when nothing was
                     // hit
    vec2 barycentrics;  // triangle: weights of p1 and p2 (p0's is 1 - x - y); sphere: (0, 0)
    uint instance;      // the instance primitive (its index in the array) whose bottom-level tree
                        // holds `primitive`; VKP_NO_INSTANCE for the scene tree's own primitives
};

// An instance's two transforms (the rows of its record, above).
struct InstanceTransform {
    vec4 worldToObject[3];
    vec4 objectToWorld[3];
};

// Row-major 3x4 `rows` applied to the point p, each row's dot product in
// glm's order (shared/precise_math.h says why it is written out).
VKP_FN vec3 transformPoint(const vec4 rows[3], vec3 p) {
    VKP_PRECISE vec3 r = vec3(rows[0].x * p.x + rows[0].y * p.y + rows[0].z * p.z + rows[0].w,
                              rows[1].x * p.x + rows[1].y * p.y + rows[1].z * p.z + rows[1].w,
                              rows[2].x * p.x + rows[2].y * p.y + rows[2].z * p.z + rows[2].w);
    return r;
}

// The same for the direction v (no translation).
VKP_FN vec3 transformDirection(const vec4 rows[3], vec3 v) {
    VKP_PRECISE vec3 r = vec3(rows[0].x * v.x + rows[0].y * v.y + rows[0].z * v.z,
                              rows[1].x * v.x + rows[1].y * v.y + rows[1].z * v.z,
                              rows[2].x * v.x + rows[2].y * v.y + rows[2].z * v.z);
    return r;
}

// The transpose of the 3x3 part of `rows` applied to v: with the
// world-to-object rows, an object-space normal's world-space direction (the
// inverse transpose of the object-to-world matrix).
VKP_FN vec3 transformNormal(const vec4 rows[3], vec3 n) {
    VKP_PRECISE vec3 r = vec3(rows[0].x * n.x + rows[1].x * n.y + rows[2].x * n.z,
                              rows[0].y * n.x + rows[1].y * n.y + rows[2].y * n.z,
                              rows[0].z * n.x + rows[1].z * n.y + rows[2].z * n.z);
    return r;
}

// The child word held in the low bits of a box's six floats (as bits:
// minimum, then maximum), as packed by host/bvh/traversal_nodes.cpp.
VKP_FN uint bvhChildWord(uvec3 boxMin, uvec3 boxMax) {
    const uint m = (1u << VKP_BVH_WORD_BITS) - 1u;
    return (boxMin.x & m) | ((boxMin.y & m) << 6u) | ((boxMin.z & m) << 12u) |
           ((boxMax.x & m) << 18u) | ((boxMax.y & m) << 24u) | ((boxMax.z & 3u) << 30u);
}

// Hardware ray tracing (--traversal rayquery; host/bvh/acceleration_structures.h
// builds them, shared/bvh_ray_query.h traces): the device's acceleration
// structures hold the same primitives, and a hit's (instance custom index,
// geometry index, primitive index) leads back to its place in the primitive
// array through two arrays. A TLAS instance's custom index is its first
// RayQueryGeometry, one per geometry of its BLAS in geometry order; the
// geometry's primitive k has the entry at firstIndex + stride x k of the
// index array. A triangle geometry's entries are vertex indices (stride 3):
// the device reads a triangle's corners from the primitive array itself, as
// 16-byte vertices (p0, p1 and p2 of primitive i are vertices 3i, 3i + 1 and
// 3i + 2), so its primitive is its first entry / 3. A sphere geometry (AABBs,
// tested by the kernel) has one entry per sphere (stride 1): its primitive.
struct RayQueryGeometry {
    uint firstIndex;
    uint stride;    // 3: triangles; 1: spheres
    uint instance;  // Hit::instance of its hits: the instance primitive, or VKP_NO_INSTANCE
    uint padding;
};

// Where the BVH's arrays lie in device memory: VkDeviceAddress as (low, high)
// words, GL_EXT_buffer_reference_uvec2. The first two for kernels that read
// the tree by address (VKP_SPEC_SCENE_BY_ADDRESS), zero when it is bound
// instead; the other three for kernels that trace by ray queries, zero without.
struct BvhAddresses {
    uvec2 nodes;                  // the traversal's node texels (uvec4[], above)
    uvec2 primitives;             // BvhPrimitive[]
    uvec2 accelerationStructure;  // the TLAS
    uvec2 rayQueryGeometries;     // RayQueryGeometry[]
    uvec2 rayQueryIndices;        // uint[]
};

struct TracePush {
    uint count;        // number of rays
    BvhAddresses bvh;  // read only by address (VKP_SPEC_SCENE_BY_ADDRESS)
};

// Whether `primitive` is a sphere (else a triangle or an instance); known
// without reading it when the kernel meets only one kind (shared/features.h).
VKP_FN bool isSphere(VKP_IN(BvhPrimitive) primitive) {
    if (!hasFeature(VKP_FEATURE_SPHERES)) return false;
    if (onlyFeature(VKP_FEATURES_PRIMITIVES, VKP_FEATURE_SPHERES)) return true;
    return primitive.kind == VKP_PRIMITIVE_SPHERE;
}

// Whether `primitive` of the scene's tree places a bottom-level tree.
VKP_FN bool isInstance(VKP_IN(BvhPrimitive) primitive) {
    return hasFeature(VKP_FEATURE_INSTANCES) && primitive.kind == VKP_PRIMITIVE_INSTANCE;
}

// The end of the half-open interval [0, end) in which primitive `index`
// (of the bottom-level tree of instance primitive `instance`, or of the
// scene's tree for VKP_NO_INSTANCE) may still become `hit`
// (shared/bvh_leaf.h has the rule for ties): hit.t, or one ulp beyond it
// when it would win a tie at exactly hit.t. hit.t of a found hit is finite
// and >= 0, so the next float up is its bits plus one. A hit's key is its
// scene-tree primitive (the instance's for an instanced hit), then its
// primitive: the smaller key wins.
VKP_FN float bvhIntervalEnd(VKP_IN(Hit) hit, uint index, uint instance) {
    bool winsTie;
    if (hasFeature(VKP_FEATURE_INSTANCES)) {
        uint top = instance != VKP_NO_INSTANCE ? instance : index;
        uint hitTop = hit.instance != VKP_NO_INSTANCE ? hit.instance : hit.primitive;
        winsTie = hit.primitive != VKP_NO_HIT &&
                  (top < hitTop || (top == hitTop && index < hit.primitive));
    } else {
        winsTie = hit.primitive != VKP_NO_HIT && index < hit.primitive;
    }
    return winsTie ? uintBitsToFloat(floatBitsToUint(hit.t) + 1u) : hit.t;
}

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::BvhNode) == 32);
#define VKP_RECORD BvhPrimitive
VKP_RECORD_CHECK(VKP_BVH_PRIMITIVE_FIELDS, 3)
#undef VKP_RECORD
static_assert(sizeof(vkpath::shared::Hit) == 20);
static_assert(sizeof(vkpath::shared::RayQueryGeometry) == 16);
static_assert(sizeof(vkpath::shared::BvhAddresses) == 40);
static_assert(sizeof(vkpath::shared::TracePush) == 44);
#endif

#endif  // VKPATH_SHARED_BVH_H
