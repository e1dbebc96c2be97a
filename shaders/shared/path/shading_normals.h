// A hit's shading normal: interpolated vertex normals, perturbed by a normal map: part of
// shared/path_tracer.h, which includes it (no include guard: once per scope, as path_tracer.h).

// ---- shading normals ------------------------------------------------------------------

// The normal map's normal at barycentrics (b1, b2) of `triangle`, whose
// material has a normal map and whose vertices have tangents; `n` is the
// normal it perturbs (interpolated or geometric, unit). glTF 2.0, section
// 3.9.3 (normalTexture): the texel's RGB is a tangent-space normal
// 2 x - 1, its x and y scaled by normalTexture.scale, in the frame of the
// tangent T (interpolated, made orthogonal to n: Gram-Schmidt), the
// bitangent B = w (n x T) (section 3.7.2.1; +Y up the image, since T and w
// were made for glTF's v-down coordinates) and n. `n` itself where the
// frame or the map's normal is degenerate.
VKP_FN vec3 normalMapNormal(VKP_IN(Material) material, VKP_IN(TriangleVertices) triangle, float b1,
                            float b2, vec3 n, bool instanced,
                            VKP_IN(InstanceTransform) x) VKP_SCENE_CONST {
    TextureSlot slot = sceneTextureSlot(material.textures + VKP_SLOT_NORMAL);
    if (slot.texture == VKP_NO_TEXTURE) return n;
    float b0 = 1.0f - b1 - b2;
    uvec3 v = triangle.vertex;
    vec4 texcoords = b0 * sceneVertexTexcoords(v.x) + b1 * sceneVertexTexcoords(v.y) +
                     b2 * sceneVertexTexcoords(v.z);
    vec3 mapped =
        2.0f * vec3(textureSlotValue(material.textures + VKP_SLOT_NORMAL, texcoords)) - 1.0f;
    vec4 tangent = b0 * placedVertexTangent(v.x, instanced, x) +
                   b1 * placedVertexTangent(v.y, instanced, x) +
                   b2 * placedVertexTangent(v.z, instanced, x);
    vec3 t = vec3(tangent) - dot(n, vec3(tangent)) * n;
    float t2 = dot(t, t);
    if (!(t2 > 1e-12f)) return n;
    t /= sqrt(t2);
    vec3 b = (tangent.w < 0.0f ? -1.0f : 1.0f) * exactCross(n, t);
    vec3 world = (slot.scale * mapped.x) * t + (slot.scale * mapped.y) * b + mapped.z * n;
    float length2 = dot(world, world);
    if (!(length2 > 1e-12f)) return n;
    return world / sqrt(length2);
}

// The normal the BSDF uses at a hit on `primitive` (of an object: in its
// space) whose geometric normal is `geometric`, seen from wo: the triangle's vertex normals
// interpolated with the hit's barycentrics (Phong's interpolation: glTF's NORMAL attribute,
// Scotty3D's smooth meshes), or the geometric normal, perturbed by the
// material's normal map where it has one, then adapted to wo
// (shared/bsdf.h); the geometric normal itself for spheres and for flat
// triangles without a normal map.
VKP_FN vec3 shadingNormal(VKP_IN(Material) material, VKP_IN(BvhPrimitive) primitive, Hit hit,
                          vec3 geometric, vec3 wo) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_SHADING_NORMALS | VKP_FEATURE_NORMAL_MAPS) || isSphere(primitive))
        return geometric;
    if ((sceneInfo().triangleAttributes & (VKP_TRIANGLE_SHADING_NORMALS | VKP_TRIANGLE_TANGENTS)) ==
        0u)
        return geometric;
    TriangleVertices triangle = sceneTriangleVertices(primitive.id);
    bool mapped =
        hasFeature(VKP_FEATURE_NORMAL_MAPS) && (triangle.attributes & VKP_TRIANGLE_TANGENTS) != 0u;
    bool interpolated = hasFeature(VKP_FEATURE_SHADING_NORMALS) &&
                        (triangle.attributes & VKP_TRIANGLE_SHADING_NORMALS) != 0u;
    if (!mapped && !interpolated) return geometric;
    float b1 = hit.barycentrics.x, b2 = hit.barycentrics.y;
    bool instanced = hasFeature(VKP_FEATURE_INSTANCES) && hit.instance != VKP_NO_INSTANCE;
    InstanceTransform x;
    if (instanced) x = instanceTransform(hit.instance);
    vec3 n = geometric;
    if (interpolated) {
        vec3 sum = (1.0f - b1 - b2) * placedVertexNormal(triangle.vertex.x, instanced, x) +
                   b1 * placedVertexNormal(triangle.vertex.y, instanced, x) +
                   b2 * placedVertexNormal(triangle.vertex.z, instanced, x);
        float length2 = dot(sum, sum);
        if (length2 > 1e-12f)
            n = sum / sqrt(length2);
        else if (!mapped)
            return geometric;  // vertex normals that cancel out
    }
    if (mapped) n = normalMapNormal(material, triangle, b1, b2, n, instanced, x);
    return adaptShadingNormal(geometric, n, wo);
}
