// Hits on instanced meshes (shared/bvh.h): their transforms and their
// triangles placed in world space: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).
//
// Traversal finds an instanced hit in its object's space; shading places it:
// the triangle's vertices go through the object-to-world matrix, so the hit
// point and the geometric normal are computed from world-space vertices as
// for any triangle (shared/intersect.h surfacePoint), vertex normals through
// the inverse transpose and tangents through the matrix, each normalised
// before they are interpolated, as the importer does for a flattened mesh
// (host/scene/gltf_meshes.cpp), so that an instanced scene renders as its
// flattened copy up to rounding.

// ---- instances ---------------------------------------------------------------------------

// The transforms of instance primitive `instance` (Hit::instance), from its record.
VKP_FN InstanceTransform instanceTransform(uint instance) VKP_SCENE_CONST {
    uint record = bvhPrimitive(instance).id;
    InstanceTransform x;
    for (uint k = 0u; k < 3u; ++k) {
        x.worldToObject[k] = uintBitsToFloat(bvhNodeTexel(record + k));
        x.objectToWorld[k] = uintBitsToFloat(bvhNodeTexel(record + 3u + k));
    }
    return x;
}

// Whether the transform mirrors (a negative determinant): the object's
// counter-clockwise fronts are clockwise in the world, so its geometric
// normals turn around (the importer swaps such a flattened mesh's winding).
VKP_FN bool instanceMirrors(VKP_IN(InstanceTransform) x) VKP_SCENE_CONST {
    vec3 a = vec3(x.objectToWorld[0]), b = vec3(x.objectToWorld[1]), c = vec3(x.objectToWorld[2]);
    return exactDot(a, exactCross(b, c)) < 0.0f;
}

// `triangle` of an object with its vertices in world space.
VKP_FN BvhPrimitive placedTriangle(BvhPrimitive triangle,
                                   VKP_IN(InstanceTransform) x) VKP_SCENE_CONST {
    triangle.p0 = transformPoint(x.objectToWorld, triangle.p0);
    triangle.p1 = transformPoint(x.objectToWorld, triangle.p1);
    triangle.p2 = transformPoint(x.objectToWorld, triangle.p2);
    return triangle;
}

// Vertex `vertex`'s shading normal in world space: unit, an instanced one's
// through the inverse transpose.
VKP_FN vec3 placedVertexNormal(uint vertex, bool instanced,
                               VKP_IN(InstanceTransform) x) VKP_SCENE_CONST {
    vec3 n = sceneVertexNormal(vertex);
    if (!instanced) return n;
    return normalize(transformNormal(x.worldToObject, n));
}

// Vertex `vertex`'s tangent in world space: unit xyz, an instanced one's
// through the matrix, w negated under a mirror (glTF's B = w (N x T)).
VKP_FN vec4 placedVertexTangent(uint vertex, bool instanced,
                                VKP_IN(InstanceTransform) x) VKP_SCENE_CONST {
    vec4 t = sceneVertexTangent(vertex);
    if (!instanced) return t;
    vec3 d = normalize(transformDirection(x.objectToWorld, vec3(t)));
    return vec4(d, (t.w < 0.0f) != instanceMirrors(x) ? -1.0f : 1.0f);
}
