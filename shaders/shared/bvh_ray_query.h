// GLSL only: closest-hit and any-hit tracing by the device's acceleration
// structures (VK_KHR_ray_query; --traversal rayquery), in place of
// shared/bvh_traverse.h in the kernels compiled with VKP_RAY_QUERY (their
// `_rayquery` variants, cmake/shaders.cmake). It defines the same functions
// (bvhTrace, bvhClosestHit, bvhOccluded), reads the same primitive array
// through shared/bvh_buffers.h's accessors and tests what the device cannot
// with shared/intersect.h's code, so that a hit is the compute traversal's
// wherever the two find the same primitive:
//
//   - opaque triangles are the device's to find; the one it commits is
//     tested again with intersectTriangle (the ray moved into its instance's
//     space as bvhTraceInstance moves it), whose t and barycentrics the hit
//     takes. The device's own are taken only where that test misses (a
//     grazing hit the two round differently);
//   - triangles of alpha-tested materials are non-opaque geometry: each
//     candidate is tested with intersectTriangle and then bvhAlphaTest, the
//     same stochastic decision as the compute traversal's;
//   - spheres are AABB geometry, and intersectSphere finds the hit.
//
// Where two primitives are hit at the same distance the device keeps either,
// where the compute traversal keeps the one of smaller key
// (shared/bvh_leaf.h); the BVH tests count how often the two differ.
//
// host/bvh/acceleration_structures.h builds the structures and the arrays
// that map a device hit back to the primitive array (shared/bvh.h,
// RayQueryGeometry); their addresses are in VKP_BVH_ADDRESSES.
// Included by shared/bvh_buffers.h, after shared/bvh_leaf.h.

#extension GL_EXT_ray_query : require

layout(buffer_reference, scalar,
       buffer_reference_align = 16) readonly buffer RayQueryGeometryArray {
    RayQueryGeometry v[];
};
layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer RayQueryIndexArray {
    uint v[];
};

// The primitive (its index in the primitive array) and Hit::instance of the
// device's intersection: its instance's custom index, geometry and primitive.
uvec2 rayQueryLeaf(uint customIndex, uint geometry, uint primitive) {
    RayQueryGeometry g =
        RayQueryGeometryArray(VKP_BVH_ADDRESSES.rayQueryGeometries).v[customIndex + geometry];
    uint entry = RayQueryIndexArray(VKP_BVH_ADDRESSES.rayQueryIndices)
                     .v[g.firstIndex + g.stride * primitive];
    return uvec2(entry / g.stride, g.instance);
}

// `ray` in the space of instance primitive `instance` (by its world-to-object
// rows, as bvhTraceInstance moves it); `ray` itself for VKP_NO_INSTANCE.
TriangleRay rayQueryTriangleRay(Ray ray, uint instance) {
    if (instance == VKP_NO_INSTANCE) return makeTriangleRay(ray.origin, ray.direction);
    uint record = bvhPrimitive(instance).id;
    vec4 rows[3];
    for (uint k = 0u; k < 3u; ++k) rows[k] = uintBitsToFloat(bvhNodeTexel(record + k));
    return makeTriangleRay(transformPoint(rows, ray.origin),
                           transformDirection(rows, ray.direction));
}

// anyHit: stop at the first hit in [0, ray.tMax) (it need not be the closest).
// alphaKey: passed to bvhAlphaTest (shared/alpha.h alphaRayKey).
Hit bvhTrace(Ray ray, bool anyHit, uint alphaKey) {
    Hit hit;
    hit.t = ray.tMax;
    hit.primitive = VKP_NO_HIT;
    hit.barycentrics = vec2(0.0f, 0.0f);
    hit.instance = VKP_NO_INSTANCE;
    if (!(ray.tMax > 0.0f)) return hit;
    // The traversal's interval is [0, tMax), the device's closed: end it one
    // float below tMax.
    float deviceTMax = uintBitsToFloat(floatBitsToUint(ray.tMax) - 1u);
    rayQueryEXT query;
    rayQueryInitializeEXT(query, accelerationStructureEXT(VKP_BVH_ADDRESSES.accelerationStructure),
                          anyHit ? gl_RayFlagsTerminateOnFirstHitEXT : gl_RayFlagsNoneEXT, 0xffu,
                          ray.origin, 0.0f, ray.direction, deviceTMax);
    while (rayQueryProceedEXT(query)) {
        uvec2 leaf = rayQueryLeaf(rayQueryGetIntersectionInstanceCustomIndexEXT(query, false),
                                  rayQueryGetIntersectionGeometryIndexEXT(query, false),
                                  rayQueryGetIntersectionPrimitiveIndexEXT(query, false));
        BvhPrimitive primitive = bvhPrimitive(leaf.x);
        if (rayQueryGetIntersectionTypeEXT(query, false) ==
            gl_RayQueryCandidateIntersectionAABBEXT) {
            float tLimit = rayQueryGetIntersectionTypeEXT(query, true) ==
                                   gl_RayQueryCommittedIntersectionNoneEXT
                               ? ray.tMax
                               : rayQueryGetIntersectionTEXT(query, true);
            float t;
            if (intersectSphere(ray.origin, ray.direction, primitive.p0, primitive.p1.x, tLimit, t))
                rayQueryGenerateIntersectionEXT(query, t);
        } else {  // a triangle whose material is alpha-tested
            float t;
            vec2 b;
            if (intersectTriangle(rayQueryTriangleRay(ray, leaf.y), primitive.p0, primitive.p1,
                                  primitive.p2, ray.tMax, t, b) &&
                bvhAlphaTest(primitive, b, alphaKey))
                rayQueryConfirmIntersectionEXT(query);
        }
    }
    uint committed = rayQueryGetIntersectionTypeEXT(query, true);
    if (committed == gl_RayQueryCommittedIntersectionNoneEXT) return hit;
    uvec2 leaf = rayQueryLeaf(rayQueryGetIntersectionInstanceCustomIndexEXT(query, true),
                              rayQueryGetIntersectionGeometryIndexEXT(query, true),
                              rayQueryGetIntersectionPrimitiveIndexEXT(query, true));
    hit.primitive = leaf.x;
    hit.instance = leaf.y;
    hit.t = rayQueryGetIntersectionTEXT(query, true);
    // A sphere's t is intersectSphere's already; a shadow ray needs no more.
    if (committed == gl_RayQueryCommittedIntersectionGeneratedEXT || anyHit) return hit;
    BvhPrimitive primitive = bvhPrimitive(leaf.x);
    float t;
    vec2 b;
    if (intersectTriangle(rayQueryTriangleRay(ray, leaf.y), primitive.p0, primitive.p1,
                          primitive.p2, ray.tMax, t, b)) {
        hit.t = t;
        hit.barycentrics = b;
    } else {
        hit.barycentrics = rayQueryGetIntersectionBarycentricsEXT(query, true);
    }
    return hit;
}

// The nearest hit in [0, ray.tMax), or Hit::primitive == VKP_NO_HIT.
Hit bvhClosestHit(Ray ray, uint alphaKey) {
    return bvhTrace(ray, false, alphaKey);
}

// Whether anything lies in [0, ray.tMax) (a surface exactly at tMax does not occlude).
bool bvhOccluded(Ray ray, uint alphaKey) {
    return bvhTrace(ray, true, alphaKey).primitive != VKP_NO_HIT;
}

// The same for rays that belong to no path (alpha key 0).
Hit bvhClosestHit(Ray ray) {
    return bvhTrace(ray, false, 0u);
}
bool bvhOccluded(Ray ray) {
    return bvhOccluded(ray, 0u);
}
