// The traversal loop of shared/bvh_traverse.h, as a function whose name and
// leaf test its includer defines, once for the scene's tree and, with
// instances, once more for the bottom-level trees (GLSL has no recursion, so
// the scene's loop cannot call itself to enter an instance):
//
//   #define VKP_TRAVERSE_FUNCTION name
//   #define VKP_TRAVERSE_LEAF(i) a bool expression: leaf primitive i was tested and took the hit
//   #include "shared/bvh_traverse_loop.h"
//
// The function traverses the tree whose root record is at texel `root` with
// `ray` (and its triangleRay and inverseDirection) and updates `hit`. It
// returns whether it took a hit; with anyHit it stops at the first.
// No include guard: included twice by shared/bvh_traverse.h, which undefines
// the two macros after each.

VKP_FN bool VKP_TRAVERSE_FUNCTION(VKP_IN(Ray) ray, VKP_IN(TriangleRay) triangleRay,
                                  vec3 inverseDirection, uint root, uint instance, bool anyHit,
                                  uint alphaKey, VKP_INOUT(Hit) hit) VKP_BVH_CONST {
    // The stack: its top eight entries in near and far, the rest in overflow
    // (overflow[0] the bottom entry), which a shallow tree's kernels compile
    // out. Entries and `node` are child words (shared/bvh.h).
    uvec4 near = uvec4(0u), far = uvec4(0u);
    uint overflow[VKP_BVH_MAX_DEPTH - VKP_BVH_SHALLOW_DEPTH];
    uint stackSize = 0u;
    uint node = root;
    bool took = false;
    while (true) {
        // ---- interior nodes: descend to the nearer child, push the farther ----
        // (all of a SIMD group's rays descend together, then all test leaves)
        bool exhausted = false;
        while ((node >> VKP_BVH_WORD_COUNT_SHIFT) == 0u) {
            uvec4 t0 = bvhNodeTexel(node);
            uvec4 t1 = bvhNodeTexel(node + 1u);
            uvec4 t2 = bvhNodeTexel(node + 2u);
            uvec3 minA = uvec3(t0.x, t0.y, t0.z), maxA = uvec3(t0.w, t1.x, t1.y);
            uvec3 minB = uvec3(t1.z, t1.w, t2.x), maxB = uvec3(t2.y, t2.z, t2.w);
            float entryA, entryB;
            bool hitA = intersectBox(uintBitsToFloat(minA), uintBitsToFloat(maxA), ray.origin,
                                     inverseDirection, hit.t, entryA);
            bool hitB = intersectBox(uintBitsToFloat(minB), uintBitsToFloat(maxB), ray.origin,
                                     inverseDirection, hit.t, entryB);
            uint first = bvhChildWord(minA, maxA);
            uint second = bvhChildWord(minB, maxB);
            // The next node is one of the two just tested, or from the stack.
            if (hitA && hitB) {
                bool firstNearer = entryA <= entryB;
                if (hasFeature(VKP_FEATURE_DEEP_BVH) && stackSize >= VKP_BVH_SHALLOW_DEPTH)
                    overflow[stackSize - VKP_BVH_SHALLOW_DEPTH] = far.w;
                bvhStackPush(near, far, firstNearer ? second : first);
                stackSize += 1u;
                node = firstNearer ? first : second;
            } else if (hitA || hitB) {
                node = hitA ? first : second;
            } else if (stackSize > 0u) {
                node = bvhStackPop(near, far);
                stackSize -= 1u;
                if (hasFeature(VKP_FEATURE_DEEP_BVH) && stackSize >= VKP_BVH_SHALLOW_DEPTH)
                    far.w = overflow[stackSize - VKP_BVH_SHALLOW_DEPTH];
            } else {
                exhausted = true;
                break;
            }
        }
        if (exhausted) break;

        // ---- a leaf: test its primitives --------------------------------------
        uint begin = node & VKP_BVH_WORD_INDEX_MASK;
        uint end = begin + (node >> VKP_BVH_WORD_COUNT_SHIFT);
        for (uint i = begin; i < end; ++i) {
            if (VKP_TRAVERSE_LEAF(i)) {
                if (anyHit) return true;
                took = true;
            }
        }
        if (stackSize == 0u) break;
        node = bvhStackPop(near, far);
        stackSize -= 1u;
        if (hasFeature(VKP_FEATURE_DEEP_BVH) && stackSize >= VKP_BVH_SHALLOW_DEPTH)
            far.w = overflow[stackSize - VKP_BVH_SHALLOW_DEPTH];
    }
    return took;
}
