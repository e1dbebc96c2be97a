// What BVH traversal does at a leaf: test one primitive against the ray and
// keep it when it is the nearer hit. Both traversals include it: the binary
// tree's (shared/bvh_traverse.h, on GPU and CPU) and the CPU reference's
// eight-wide one (host/bvh/wide_bvh.h). It reads through its includer's
// accessors
//
//   BvhPrimitive bvhPrimitive(uint index);
//   bool bvhAlphaTest(BvhPrimitive triangle, vec2 barycentrics, uint alphaKey);
//
// bvhAlphaTest says whether a triangle's candidate hit stands (alpha
// coverage, shared/alpha.h; only kernels with VKP_FEATURE_ALPHA ask). A
// rejected candidate is passed through: it neither shortens the interval nor
// ends an any-hit trace. Includers without materials (the BVH test kernels,
// host/bvh/bvh_view.h) answer true.
//
// Ties: a hit at exactly the distance of the best so far replaces it when
// its leaf index is smaller (with instances: its key, shared/bvh.h
// bvhIntervalEnd). So the closest hit is the nearest candidate that
// stands, and among those at the same distance the one of smallest index,
// whatever order a traversal visits the leaves in: the binary and the wide
// tree give the same hit, bit for bit. (Before this rule the first one found
// won, which depended on the tree.)
//
// No include guard: include once per scope, before shared/bvh_traverse.h
// (C++: inside the struct whose accessors it reads, VKP_BVH_CONST).

#ifdef __cplusplus
#define VKP_BVH_CONST const
#else
#define VKP_BVH_CONST
#endif

// Tests the triangle or sphere `primitive`, at `index` in the primitive
// array, of the bottom-level tree of instance primitive `instance` (the ray
// in its space) or of the scene's tree (VKP_NO_INSTANCE); when it is hit in
// [0, hit.t), or at exactly hit.t with the smaller key
// (shared/bvh.h bvhIntervalEnd), makes it `hit` and returns true.
VKP_FN bool bvhTestPrimitiveRecord(VKP_IN(Ray) ray, VKP_IN(TriangleRay) triangleRay,
                                   VKP_IN(BvhPrimitive) primitive, uint index, uint instance,
                                   uint alphaKey, VKP_INOUT(Hit) hit) VKP_BVH_CONST {
    float tLimit = bvhIntervalEnd(hit, index, instance);
    float t;
    vec2 barycentrics = vec2(0.0f, 0.0f);
    bool found;
    if (isSphere(primitive)) {
        found = intersectSphere(ray.origin, ray.direction, primitive.p0, primitive.p1.x, tLimit, t);
    } else {
        found = intersectTriangle(triangleRay, primitive.p0, primitive.p1, primitive.p2, tLimit, t,
                                  barycentrics);
        if (found && hasFeature(VKP_FEATURE_ALPHA))
            found = bvhAlphaTest(primitive, barycentrics, alphaKey);
    }
    if (!found) return false;
    hit.t = t;
    hit.primitive = index;
    hit.barycentrics = barycentrics;
    hit.instance = instance;
    return true;
}

// Tests leaf primitive `index` (a triangle or sphere) of the tree of
// `instance` as above.
VKP_FN bool bvhTestPrimitive(VKP_IN(Ray) ray, VKP_IN(TriangleRay) triangleRay, uint index,
                             uint instance, uint alphaKey, VKP_INOUT(Hit) hit) VKP_BVH_CONST {
    return bvhTestPrimitiveRecord(ray, triangleRay, bvhPrimitive(index), index, instance, alphaKey,
                                  hit);
}
