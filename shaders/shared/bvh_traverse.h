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
// There is no include guard: include it exactly once per scope.
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

// anyHit: stop at the first hit in [0, ray.tMax) (it need not be the closest).
// alphaKey: passed to bvhAlphaTest (shared/alpha.h alphaRayKey).
VKP_FN Hit bvhTrace(VKP_IN(Ray) ray, bool anyHit, uint alphaKey) VKP_BVH_CONST {
    Hit hit;
    hit.t = ray.tMax;
    hit.primitive = VKP_NO_HIT;
    hit.barycentrics = vec2(0.0f, 0.0f);

    TriangleRay triangleRay = makeTriangleRay(ray.origin, ray.direction);
    vec3 inverseDirection = safeInverse(ray.direction);

    // The stack: its top eight entries in near and far, the rest in overflow
    // (overflow[0] the bottom entry), which a shallow tree's kernels compile
    // out. Entries and `node` are child words (shared/bvh.h).
    uvec4 near = uvec4(0u), far = uvec4(0u);
    uint overflow[VKP_BVH_MAX_DEPTH - VKP_BVH_SHALLOW_DEPTH];
    uint stackSize = 0u;
    uint node = 0u;  // the root's record
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
        for (uint i = begin; i < end; ++i)
            if (bvhTestPrimitive(ray, triangleRay, i, alphaKey, hit) && anyHit) return hit;
        if (stackSize == 0u) break;
        node = bvhStackPop(near, far);
        stackSize -= 1u;
        if (hasFeature(VKP_FEATURE_DEEP_BVH) && stackSize >= VKP_BVH_SHALLOW_DEPTH)
            far.w = overflow[stackSize - VKP_BVH_SHALLOW_DEPTH];
    }
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
