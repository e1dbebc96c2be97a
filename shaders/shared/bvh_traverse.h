// BVH traversal of the binary tree: closest hit and any hit (shadow rays),
// the same code on GPU and CPU. GLSL has neither pointers nor recursion, and
// a GLSL function cannot take a buffer, so this file reads the BVH through
// accessors that its includer defines before including it:
//
//   BvhNode bvhNode(uint index);            // shared/bvh.h layouts
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
// The traversal keeps an explicit stack of node indices. At an interior node
// both children's boxes are tested; the nearer is visited next and the other
// pushed, so the stack holds at most one node per level below the root, and
// the builder keeps every leaf at depth <= VKP_BVH_MAX_DEPTH: a stack of
// VKP_BVH_MAX_DEPTH entries cannot overflow. The loop is "while-while" (Aila
// and Laine, "Understanding the Efficiency of Ray Traversal on GPUs", HPG
// 2009): descend through interior nodes until a leaf, then test the leaf, so
// the rays of a SIMD group run the same phase together (measured ~10% faster
// for incoherent rays on lavapipe than one if/else per step).

// The stack's top eight entries live in two vectors, the top in near.x, every
// entry shifted by one on a push and a pop. lavapipe keeps a lane's stack
// array in memory and masks every access for the lanes that make it;
// variables stay in vector registers. A tree deeper than
// VKP_BVH_SHALLOW_DEPTH (VKP_FEATURE_DEEP_BVH) keeps the entries below those
// eight in an array, written and read only while the stack holds more than
// eight: on lavapipe CBspheres (shallow) renders 1.07 to 1.10x faster than
// with the whole stack in an array, CBbunny (deep) 1.02 to 1.08x; four or
// 32 entries in variables measured slower (docs/BENCHMARKS.md).
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

    BvhNode node = bvhNode(0u);
    if (node.count == 0u && node.offset == 0u) return hit;  // empty BVH
    TriangleRay triangleRay = makeTriangleRay(ray.origin, ray.direction);
    vec3 inverseDirection = safeInverse(ray.direction);
    float entry;
    if (!intersectBox(node.boundsMin, node.boundsMax, ray.origin, inverseDirection, hit.t, entry)) {
        return hit;
    }

    // The stack: its top eight entries in near and far, the rest in overflow
    // (overflow[0] the bottom entry), which a shallow tree's kernels compile out.
    uvec4 near = uvec4(0u), far = uvec4(0u);
    uint overflow[VKP_BVH_MAX_DEPTH - VKP_BVH_SHALLOW_DEPTH];
    uint stackSize = 0u;
    uint index = 0u;
    while (true) {
        // ---- interior nodes: descend to the nearer child, push the farther ----
        // (all of a SIMD group's rays descend together, then all test leaves)
        bool exhausted = false;
        while (node.count == 0u) {
            uint first = index + 1u;
            uint second = node.offset;
            BvhNode a = bvhNode(first);
            BvhNode b = bvhNode(second);
            float entryA, entryB;
            bool hitA = intersectBox(a.boundsMin, a.boundsMax, ray.origin, inverseDirection, hit.t,
                                     entryA);
            bool hitB = intersectBox(b.boundsMin, b.boundsMax, ray.origin, inverseDirection, hit.t,
                                     entryB);
            // The next node is one of the two just read, or read from the stack.
            if (hitA && hitB) {
                bool firstNearer = entryA <= entryB;
                if (hasFeature(VKP_FEATURE_DEEP_BVH) && stackSize >= VKP_BVH_SHALLOW_DEPTH)
                    overflow[stackSize - VKP_BVH_SHALLOW_DEPTH] = far.w;
                bvhStackPush(near, far, firstNearer ? second : first);
                stackSize += 1u;
                index = firstNearer ? first : second;
                node = firstNearer ? a : b;
            } else if (hitA || hitB) {
                index = hitA ? first : second;
                node = hitA ? a : b;
            } else if (stackSize > 0u) {
                index = bvhStackPop(near, far);
                stackSize -= 1u;
                if (hasFeature(VKP_FEATURE_DEEP_BVH) && stackSize >= VKP_BVH_SHALLOW_DEPTH)
                    far.w = overflow[stackSize - VKP_BVH_SHALLOW_DEPTH];
                node = bvhNode(index);
            } else {
                exhausted = true;
                break;
            }
        }
        if (exhausted) break;

        // ---- a leaf: test its primitives --------------------------------------
        uint end = node.offset + node.count;
        for (uint i = node.offset; i < end; ++i)
            if (bvhTestPrimitive(ray, triangleRay, i, alphaKey, hit) && anyHit) return hit;
        if (stackSize == 0u) break;
        index = bvhStackPop(near, far);
        stackSize -= 1u;
        if (hasFeature(VKP_FEATURE_DEEP_BVH) && stackSize >= VKP_BVH_SHALLOW_DEPTH)
            far.w = overflow[stackSize - VKP_BVH_SHALLOW_DEPTH];
        node = bvhNode(index);
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
VKP_FN Hit bvhClosestHit(VKP_IN(Ray) ray) VKP_BVH_CONST { return bvhTrace(ray, false, 0u); }
VKP_FN bool bvhOccluded(VKP_IN(Ray) ray) VKP_BVH_CONST { return bvhOccluded(ray, 0u); }
