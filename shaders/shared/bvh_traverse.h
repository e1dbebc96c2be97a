// BVH traversal of the binary tree: closest hit and any hit (shadow rays),
// the same code on GPU and CPU. GLSL has neither pointers nor recursion, and
// a GLSL function cannot take a buffer, so this file reads the BVH through
// accessors that its includer defines before including it:
//
//   uvec4 bvhNodeTexel(uint texel);         // shared/bvh.h layouts
//   BvhPrimitive bvhPrimitive(uint index);
//   bool bvhAlphaTest(BvhPrimitive triangle, vec2 barycentrics, uint alphaKey);
//
// and tests leaves with shared/bvh_leaf.h (the alpha test and the rule for
// ties), which the includer includes first.
//
// GLSL: a kernel declares its two buffer bindings and the accessors over them
//   (shared/bvh_buffers.h does all of it) and declares bvhAlphaTest (a
//   prototype will do), then includes this file at global scope.
// C++: host/bvh/bvh_view.h includes it inside the body of struct BvhView,
//   whose member accessors read std::spans; the functions below become const
//   member functions (VKP_BVH_CONST). The CPU reference traces an eight-wide
//   tree built from this one instead (host/bvh/wide_bvh.h), with the same
//   leaf test and so the same hits.
//
// There is no include guard: include it exactly once per scope. The loop
// itself is in shared/bvh_traverse_loop.h, which this file includes once for
// the scene's tree and once for the bottom-level trees of instances
// (shared/bvh.h): at an instance primitive the scene's loop moves the ray
// into the instance's space and runs the other loop from its tree's root.
//
// The traversal reads the node records of shared/bvh.h: a record holds both
// children's boxes and words, so a step reads three texels and a pop or a
// leaf none (the two-texel nodes it replaced cost four texels a step and two
// more a pop: docs/BENCHMARKS.md, "On lavapipe: what a ray reads, and the
// node records"). It keeps an explicit stack of child words. At an
// interior node both children's boxes are tested; the nearer is visited next
// and the other pushed, so the stack holds at most one node per level below
// the root, and the builder keeps every leaf at depth <= VKP_BVH_MAX_DEPTH: a stack of
// VKP_BVH_MAX_DEPTH entries cannot overflow. The loop is "while-while" (Aila
// and Laine, "Understanding the Efficiency of Ray Traversal on GPUs", HPG
// 2009): descend through interior nodes until a leaf, then test the leaf, so
// the rays of a SIMD group run the same phase together.

// The stack's top eight entries live in two vectors, the top in near.x, every
// entry shifted by one on a push and a pop. lavapipe keeps a lane's stack
// array in memory and masks every access for the lanes that make it;
// variables stay in vector registers. A tree deeper than
// VKP_BVH_SHALLOW_DEPTH (VKP_FEATURE_DEEP_BVH) keeps the entries below those
// eight in an array, written and read only while the stack holds more than
// eight: faster on lavapipe than the whole stack in an array, for shallow
// and deep trees alike (docs/BENCHMARKS.md, "The traversal stack in
// variables", which also has the four and 32 entries measured).
VKP_FN void bvhStackPush(VKP_INOUT(uvec4) near, VKP_INOUT(uvec4) far, uint index) VKP_BVH_CONST {
    far = uvec4(near.w, far.x, far.y, far.z);
    near = uvec4(index, near.x, near.y, near.z);
}

VKP_FN uint bvhStackPop(VKP_INOUT(uvec4) near, VKP_INOUT(uvec4) far) VKP_BVH_CONST {
    uint top = near.x;
    near = uvec4(near.y, near.z, near.w, far.x);
    far = uvec4(far.y, far.z, far.w, 0u);
    return top;
}

// ---- the bottom-level trees (instancing) ----------------------------------------
// Compiled in C++ and in the kernels built with VKP_INSTANCING (their
// `_instanced` variants, cmake/shaders.cmake), which the host picks for
// kernels whose features include VKP_FEATURE_INSTANCES: a kernel of a scene
// without instances carries none of this code, not even code its
// specialisation would remove, whose compilation costs time and memory.
#if defined(__cplusplus) || defined(VKP_INSTANCING)
// Their loop tests triangles only: a bottom-level tree holds a mesh.
#define VKP_TRAVERSE_FUNCTION bvhTraverseObject
#define VKP_TRAVERSE_LEAF(i) bvhTestPrimitive(ray, triangleRay, i, instance, alphaKey, hit)
#include "shared/bvh_traverse_loop.h"
#undef VKP_TRAVERSE_FUNCTION
#undef VKP_TRAVERSE_LEAF

// Instance primitive `primitive` (at `index`): `ray` moved into its space by
// its world-to-object rows, then its bottom-level tree traversed. A ray
// parameter means the same point in both spaces (the direction is
// transformed, not normalised), so hit.t needs no conversion.
VKP_FN bool bvhTraceInstance(VKP_IN(Ray) ray, VKP_IN(BvhPrimitive) primitive, uint index,
                             bool anyHit, uint alphaKey, VKP_INOUT(Hit) hit) VKP_BVH_CONST {
    vec4 rows[3];
    for (uint k = 0u; k < 3u; ++k) rows[k] = uintBitsToFloat(bvhNodeTexel(primitive.id + k));
    Ray objectRay;
    objectRay.origin = transformPoint(rows, ray.origin);
    objectRay.direction = transformDirection(rows, ray.direction);
    objectRay.tMax = ray.tMax;
    objectRay.pixel = ray.pixel;
    TriangleRay objectTriangleRay = makeTriangleRay(objectRay.origin, objectRay.direction);
    return bvhTraverseObject(objectRay, objectTriangleRay, safeInverse(objectRay.direction),
                             primitive.material, index, anyHit, alphaKey, hit);
}

#endif

// A leaf primitive of the scene's tree (`instance` is VKP_NO_INSTANCE): an
// instance, a triangle or a sphere.
VKP_FN bool bvhTestSceneLeaf(VKP_IN(Ray) ray, VKP_IN(TriangleRay) triangleRay, uint index,
                             uint instance, bool anyHit, uint alphaKey,
                             VKP_INOUT(Hit) hit) VKP_BVH_CONST {
    BvhPrimitive primitive = bvhPrimitive(index);
#if defined(__cplusplus) || defined(VKP_INSTANCING)
    if (isInstance(primitive))
        return bvhTraceInstance(ray, primitive, index, anyHit, alphaKey, hit);
#endif
    return bvhTestPrimitiveRecord(ray, triangleRay, primitive, index, instance, alphaKey, hit);
}

// ---- the scene's tree ----------------------------------------------------------------
#define VKP_TRAVERSE_FUNCTION bvhTraverseScene
#define VKP_TRAVERSE_LEAF(i) bvhTestSceneLeaf(ray, triangleRay, i, instance, anyHit, alphaKey, hit)
#include "shared/bvh_traverse_loop.h"
#undef VKP_TRAVERSE_FUNCTION
#undef VKP_TRAVERSE_LEAF

// anyHit: stop at the first hit in [0, ray.tMax) (it need not be the closest).
// alphaKey: passed to bvhAlphaTest (shared/alpha.h alphaRayKey).
VKP_FN Hit bvhTrace(VKP_IN(Ray) ray, bool anyHit, uint alphaKey) VKP_BVH_CONST {
    Hit hit;
    hit.t = ray.tMax;
    hit.primitive = VKP_NO_HIT;
    hit.barycentrics = vec2(0.0f, 0.0f);
    hit.instance = VKP_NO_INSTANCE;
    bvhTraverseScene(ray, makeTriangleRay(ray.origin, ray.direction), safeInverse(ray.direction),
                     0u, VKP_NO_INSTANCE, anyHit, alphaKey, hit);
    return hit;
}

// The nearest hit in [0, ray.tMax), or Hit::primitive == VKP_NO_HIT.
VKP_FN Hit bvhClosestHit(VKP_IN(Ray) ray, uint alphaKey) VKP_BVH_CONST {
    return bvhTrace(ray, false, alphaKey);
}

// Whether anything lies in [0, ray.tMax): for shadow rays, whose tMax is the
// distance to the light (a surface exactly at tMax does not occlude).
VKP_FN bool bvhOccluded(VKP_IN(Ray) ray, uint alphaKey) VKP_BVH_CONST {
    return bvhTrace(ray, true, alphaKey).primitive != VKP_NO_HIT;
}

// The same for rays that belong to no path (the BVH tests and benchmarks,
// whose geometry is opaque): alpha key 0.
VKP_FN Hit bvhClosestHit(VKP_IN(Ray) ray) VKP_BVH_CONST {
    return bvhTrace(ray, false, 0u);
}
VKP_FN bool bvhOccluded(VKP_IN(Ray) ray) VKP_BVH_CONST {
    return bvhOccluded(ray, 0u);
}
