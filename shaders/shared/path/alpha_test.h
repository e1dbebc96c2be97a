// Alpha coverage: the traversal's test: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

// ---- alpha coverage: the traversal's test (shared/alpha.h) -------------------------------

// The alpha of a material with record `material` at barycentrics `b` of
// triangle `triangle` (BvhPrimitive::id): its factor x the base-colour
// texture's alpha x COLOR_0's alpha, interpolated as materialAt interpolates
// the base colour.
VKP_FN float surfaceAlpha(MaterialAlpha material, uint triangle, vec2 b) VKP_SCENE_CONST {
    float alpha = material.alpha;
    bool textured = hasFeature(VKP_FEATURE_TEXTURES) && material.baseColorSlot != VKP_NO_TEXTURE;
    uint attributes =
        sceneInfo().triangleAttributes & (VKP_TRIANGLE_TEXCOORDS | VKP_TRIANGLE_COLORS);
    if (!textured && (!hasFeature(VKP_FEATURE_VERTEX_COLORS) || attributes == 0u)) return alpha;
    vec4 texcoords = vec4(0.0f);
    if (attributes != 0u) {
        TriangleVertices vertices = sceneTriangleVertices(triangle);
        float b0 = 1.0f - b.x - b.y;
        uvec3 v = vertices.vertex;
        if (textured && (vertices.attributes & VKP_TRIANGLE_TEXCOORDS) != 0u)
            texcoords = b0 * sceneVertexTexcoords(v.x) + b.x * sceneVertexTexcoords(v.y) +
                        b.y * sceneVertexTexcoords(v.z);
        if (hasFeature(VKP_FEATURE_VERTEX_COLORS) &&
            (vertices.attributes & VKP_TRIANGLE_COLORS) != 0u)
            alpha *= b0 * sceneVertexColor(v.x).w + b.x * sceneVertexColor(v.y).w +
                     b.y * sceneVertexColor(v.z).w;
    }
    if (textured) alpha *= textureSlotValue(material.baseColorSlot, texcoords).w;
    return alpha;
}

// Whether a candidate hit at barycentrics `b` of `triangle` stands for the
// ray of alpha key `alphaKey` (shared/bvh_traverse.h asks; shared/alpha.h).
VKP_FN bool bvhAlphaTest(VKP_IN(BvhPrimitive) triangle, vec2 b, uint alphaKey) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_ALPHA) || sceneInfo().alphaTested == 0u) return true;
    MaterialAlpha material = sceneMaterialAlpha(triangle.material);
    if (material.mode == VKP_ALPHA_OPAQUE) return true;
    return alphaCovers(material, surfaceAlpha(material, triangle.id, b), alphaKey, triangle.id);
}

// The alpha key of ray `ray` (alphaClosestRay, alphaShadowRay) of the path
// of `key`; 0 where nothing is alpha-tested (it is then never read).
VKP_FN uint pathAlphaKey(RngKey key, uint ray) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_ALPHA) || sceneInfo().alphaTested == 0u) return 0u;
    return alphaRayKey(key, ray);
}
