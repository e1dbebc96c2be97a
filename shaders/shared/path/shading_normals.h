// A hit's shading normal: interpolated vertex normals, perturbed by a normal map: part of
// shared/path_tracer.h, which includes it (no include guard: once per scope, as path_tracer.h).

// ---- shading normals ------------------------------------------------------------------

// The tangent frame at barycentrics (b1, b2) of `triangle`, whose vertices
// have tangents, about the unit normal n: the tangent T (interpolated, made
// orthogonal to n: Gram-Schmidt) and the bitangent B = w (n x T) (glTF 2.0
// section 3.7.2.1; +Y up the image, since T and w were made for glTF's v-down
// coordinates). False where T is degenerate.
VKP_FN bool tangentFrame(VKP_IN(TriangleVertices) triangle, float b1, float b2, vec3 n,
                         bool instanced, VKP_IN(InstanceTransform) x, VKP_OUT(vec3) t,
                         VKP_OUT(vec3) b) VKP_SCENE_CONST {
    uvec3 v = triangle.vertex;
    vec4 tangent = (1.0f - b1 - b2) * placedVertexTangent(v.x, instanced, x) +
                   b1 * placedVertexTangent(v.y, instanced, x) +
                   b2 * placedVertexTangent(v.z, instanced, x);
    t = vec3(tangent) - dot(n, vec3(tangent)) * n;
    float t2 = dot(t, t);
    if (!(t2 > 1e-12f)) return false;
    t /= sqrt(t2);
    b = (tangent.w < 0.0f ? -1.0f : 1.0f) * exactCross(n, t);
    return true;
}

// The normal map's normal at barycentrics (b1, b2) of `triangle`, whose
// vertices have tangents, from the material's texture slot `map`
// (VKP_SLOT_NORMAL, or the coat's VKP_SLOT_CLEARCOAT_NORMAL); `n` is the
// normal it perturbs (interpolated or geometric, unit). glTF 2.0, section
// 3.9.3 (normalTexture): the texel's RGB is a tangent-space normal 2 x - 1,
// its x and y scaled by the texture's scale, in the tangent frame about n.
// `n` itself where the material has no such map (its triangles may have
// tangents for another) or the frame or the map's normal is degenerate.
VKP_FN vec3 normalMapNormal(VKP_IN(Material) material, uint map, VKP_IN(TriangleVertices) triangle,
                            float b1, float b2, vec3 n, bool instanced,
                            VKP_IN(InstanceTransform) x) VKP_SCENE_CONST {
    if (material.textures == VKP_NO_TEXTURE) return n;
    TextureSlot slot = sceneTextureSlot(material.textures + map);
    if (slot.texture == VKP_NO_TEXTURE) return n;
    float b0 = 1.0f - b1 - b2;
    uvec3 v = triangle.vertex;
    vec4 texcoords = b0 * sceneVertexTexcoords(v.x) + b1 * sceneVertexTexcoords(v.y) +
                     b2 * sceneVertexTexcoords(v.z);
    vec3 mapped = 2.0f * vec3(textureSlotValue(material.textures + map, texcoords)) - 1.0f;
    vec3 t, b;
    if (!tangentFrame(triangle, b1, b2, n, instanced, x, t, b)) return n;
    vec3 world = (slot.scale * mapped.x) * t + (slot.scale * mapped.y) * b + mapped.z * n;
    float length2 = dot(world, world);
    if (!(length2 > 1e-12f)) return n;
    return world / sqrt(length2);
}

// The normal the BSDF uses at a hit on `primitive` (of an object: in its
// space) whose geometric normal is `geometric`, seen from wo: the triangle's vertex normals
// interpolated with the hit's barycentrics (Phong's interpolation: glTF's NORMAL attribute,
// Scotty3D's smooth meshes), or the geometric normal, perturbed by the
// material's normal map in slot `map` where it has one, then adapted to wo
// (shared/bsdf.h); the geometric normal itself for spheres and for flat
// triangles without a normal map.
VKP_FN vec3 mappedNormal(VKP_IN(Material) material, uint map, VKP_IN(BvhPrimitive) primitive,
                         Hit hit, vec3 geometric, vec3 wo) VKP_SCENE_CONST {
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
    if (mapped) n = normalMapNormal(material, map, triangle, b1, b2, n, instanced, x);
    return adaptShadingNormal(geometric, n, wo);
}

// The shading normal: mappedNormal with the material's normalTexture.
VKP_FN vec3 shadingNormal(VKP_IN(Material) material, VKP_IN(BvhPrimitive) primitive, Hit hit,
                          vec3 geometric, vec3 wo) VKP_SCENE_CONST {
    return mappedNormal(material, VKP_SLOT_NORMAL, primitive, hit, geometric, wo);
}

// Material::clearcoatNormal at a hit: mappedNormal with the coat's own map
// (KHR_materials_clearcoat's clearcoatNormalTexture perturbs the vertex
// normal, not the base's normal map), turned toward wo; vec3(0), the coat on
// the shading normal, where the material has no such map.
VKP_FN vec3 clearcoatNormalAt(VKP_IN(Material) material, VKP_IN(BvhPrimitive) primitive, Hit hit,
                              vec3 geometric, vec3 wo) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_NORMAL_MAPS) || material.textures == VKP_NO_TEXTURE ||
        sceneTextureSlot(material.textures + VKP_SLOT_CLEARCOAT_NORMAL).texture == VKP_NO_TEXTURE)
        return vec3(0.0f);
    vec3 n = mappedNormal(material, VKP_SLOT_CLEARCOAT_NORMAL, primitive, hit, geometric, wo);
    return dot(n, wo) < 0.0f ? -n : n;
}

// Material::anisotropyDirection at a hit on `primitive` (of an object: in its
// space) whose shading normal is ns: the material's direction d in the
// tangent frame (after its texture, shared/path/textures.h) as
// d.x T + d.y B in the tangent frame about ns (KHR_materials_anisotropy).
// vec3(0) where the hit has no tangent frame (spheres, and meshes without
// tangents or texture coordinates to make them from: the importer warns),
// which leaves the lobe isotropic.
VKP_FN vec3 anisotropyDirectionAt(VKP_IN(Material) material, VKP_IN(BvhPrimitive) primitive,
                                  Hit hit, vec3 ns) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_NORMAL_MAPS) || isSphere(primitive)) return vec3(0.0f);
    TriangleVertices triangle = sceneTriangleVertices(primitive.id);
    if ((triangle.attributes & VKP_TRIANGLE_TANGENTS) == 0u) return vec3(0.0f);
    bool instanced = hasFeature(VKP_FEATURE_INSTANCES) && hit.instance != VKP_NO_INSTANCE;
    InstanceTransform x;
    if (instanced) x = instanceTransform(hit.instance);
    vec3 t, b;
    if (!tangentFrame(triangle, hit.barycentrics.x, hit.barycentrics.y, ns, instanced, x, t, b))
        return vec3(0.0f);
    vec3 d = material.anisotropyDirection.x * t + material.anisotropyDirection.y * b;
    float length2 = dot(d, d);
    return length2 > 1e-12f ? d / sqrt(length2) : vec3(0.0f);
}
