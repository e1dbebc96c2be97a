// A hit's material after its textures and vertex colours: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

// ---- textures and vertex colours --------------------------------------------------------

VKP_FN vec4 textureTexel(TextureInfo texture, int i, int j) VKP_SCENE_CONST {
    return sceneTexel(texture.firstTexel + uint(j) * texture.width + uint(i));
}

// The texture's value at uv (shared/texture.h has the conventions).
VKP_FN vec4 textureLookup(TextureInfo texture, vec2 uv) VKP_SCENE_CONST {
    int w = int(texture.width), h = int(texture.height);
    uint wrapU = texture.sampling & 3u, wrapV = (texture.sampling >> 2u) & 3u;
    float x = uv.x * float(w), y = uv.y * float(h);
    if ((texture.sampling & VKP_TEXTURE_NEAREST) != 0u)
        return textureTexel(texture, wrapTexelIndex(floorToInt(x), w, wrapU),
                            wrapTexelIndex(floorToInt(y), h, wrapV));
    // Bilinear: the four texels whose centres surround (x, y).
    x -= 0.5f;
    y -= 0.5f;
    int i = floorToInt(x), j = floorToInt(y);
    float fx = x - float(i), fy = y - float(j);
    int i0 = wrapTexelIndex(i, w, wrapU), i1 = wrapTexelIndex(i + 1, w, wrapU);
    int j0 = wrapTexelIndex(j, h, wrapV), j1 = wrapTexelIndex(j + 1, h, wrapV);
    vec4 top = exactMix(textureTexel(texture, i0, j0), textureTexel(texture, i1, j0), fx);
    vec4 bottom = exactMix(textureTexel(texture, i0, j1), textureTexel(texture, i1, j1), fx);
    return exactMix(top, bottom, fy);
}

// The value of texture slot `slot` at texture coordinates `texcoords`
// (TEXCOORD_0, TEXCOORD_1); 1 for an empty slot.
VKP_FN vec4 textureSlotValue(uint slot, vec4 texcoords) VKP_SCENE_CONST {
    TextureSlot s = sceneTextureSlot(slot);
    if (s.texture == VKP_NO_TEXTURE) return vec4(1.0f);
    vec3 uv1 = s.texCoord == 0u ? vec3(texcoords.x, texcoords.y, 1.0f)
                                : vec3(texcoords.z, texcoords.w, 1.0f);
    return textureLookup(sceneTexture(s.texture),
                         vec2(dot(s.transformU, uv1), dot(s.transformV, uv1)));
}

// `material` as it is at a hit on `primitive`: its base colour times the
// base-colour texture and the vertex colour (glTF 2.0 section 3.9.2; a
// glass's base colour tints its transmission, scene::Material), its
// emission times the emissive texture, its roughness and metalness times the
// metallic-roughness texture, its clear coat, sheen, diffuse transmission,
// thin film and anisotropy times theirs. Spheres have no texture coordinates.
VKP_FN Material materialAt(Material material, VKP_IN(BvhPrimitive) primitive,
                           Hit hit) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_TEXTURES | VKP_FEATURE_VERTEX_COLORS) || isSphere(primitive))
        return material;
    bool textured = hasFeature(VKP_FEATURE_TEXTURES) && material.textures != VKP_NO_TEXTURE;
    uint attributes =
        sceneInfo().triangleAttributes & (VKP_TRIANGLE_TEXCOORDS | VKP_TRIANGLE_COLORS);
    if (!textured && (!hasFeature(VKP_FEATURE_VERTEX_COLORS) || attributes == 0u)) return material;
    vec4 base = vec4(1.0f);
    vec4 texcoords = vec4(0.0f);
    if (attributes != 0u) {
        TriangleVertices triangle = sceneTriangleVertices(primitive.id);
        float b1 = hit.barycentrics.x, b2 = hit.barycentrics.y, b0 = 1.0f - b1 - b2;
        uvec3 v = triangle.vertex;
        if (textured && (triangle.attributes & VKP_TRIANGLE_TEXCOORDS) != 0u)
            texcoords = b0 * sceneVertexTexcoords(v.x) + b1 * sceneVertexTexcoords(v.y) +
                        b2 * sceneVertexTexcoords(v.z);
        if (hasFeature(VKP_FEATURE_VERTEX_COLORS) &&
            (triangle.attributes & VKP_TRIANGLE_COLORS) != 0u)
            base = b0 * sceneVertexColor(v.x) + b1 * sceneVertexColor(v.y) +
                   b2 * sceneVertexColor(v.z);
    }
    if (textured) {
        base *= textureSlotValue(material.textures + VKP_SLOT_BASE_COLOR, texcoords);
        if (material.emission != vec3(0.0f))
            material.emission *=
                vec3(textureSlotValue(material.textures + VKP_SLOT_EMISSIVE, texcoords));
        // glTF 2.0 section 3.9.2: roughness in G, metalness in B, each
        // multiplying its factor (an empty slot is 1).
        if (hasFeature(VKP_FEATURES_MICROFACET)) {
            vec4 metallicRoughness =
                textureSlotValue(material.textures + VKP_SLOT_METALLIC_ROUGHNESS, texcoords);
            material.roughness *= metallicRoughness.y;
            material.metallic *= metallicRoughness.z;
        }
        // KHR_materials_clearcoat: the weight in R, the roughness in G;
        // KHR_materials_sheen: the colour in RGB (sRGB), the roughness in A;
        // KHR_materials_diffuse_transmission: the share in A, the colour in
        // RGB (sRGB); KHR_materials_iridescence: the weight in R, the
        // thickness between the minimum (0) and the maximum (1) in G.
        if (hasFeature(VKP_FEATURE_CLEARCOAT) && material.clearcoat > 0.0f) {
            material.clearcoat *=
                textureSlotValue(material.textures + VKP_SLOT_CLEARCOAT, texcoords).x;
            material.clearcoatRoughness *=
                textureSlotValue(material.textures + VKP_SLOT_CLEARCOAT_ROUGHNESS, texcoords).y;
        }
        if (hasFeature(VKP_FEATURE_DIFFUSE_TRANSMISSION) && material.diffuseTransmission > 0.0f) {
            material.diffuseTransmission *=
                textureSlotValue(material.textures + VKP_SLOT_DIFFUSE_TRANSMISSION, texcoords).w;
            material.diffuseTransmissionColor *= vec3(textureSlotValue(
                material.textures + VKP_SLOT_DIFFUSE_TRANSMISSION_COLOR, texcoords));
        }
        if (hasFeature(VKP_FEATURE_IRIDESCENCE) && material.iridescence > 0.0f) {
            material.iridescence *=
                textureSlotValue(material.textures + VKP_SLOT_IRIDESCENCE, texcoords).x;
            material.iridescenceThickness = mix(
                material.iridescenceThicknessMinimum, material.iridescenceThickness,
                textureSlotValue(material.textures + VKP_SLOT_IRIDESCENCE_THICKNESS, texcoords).y);
        }
        // KHR_materials_anisotropy: the direction in RG (2 x - 1 in the
        // tangent frame, turned by the rotation), the strength's factor in B;
        // without the texture the direction is the tangent, turned.
        if (hasFeature(VKP_FEATURE_ANISOTROPY) && material.anisotropy > 0.0f &&
            sceneTextureSlot(material.textures + VKP_SLOT_ANISOTROPY).texture != VKP_NO_TEXTURE) {
            vec3 texel = vec3(textureSlotValue(material.textures + VKP_SLOT_ANISOTROPY, texcoords));
            vec2 d = 2.0f * vec2(texel) - 1.0f;
            vec2 turn = vec2(material.anisotropyDirection);  // (cos, sin) of the rotation
            material.anisotropyDirection =
                vec3(turn.x * d.x - turn.y * d.y, turn.y * d.x + turn.x * d.y, 0.0f);
            material.anisotropy *= texel.z;
        }
        if (hasFeature(VKP_FEATURE_SHEEN) && material.sheenColor != vec3(0.0f)) {
            material.sheenColor *=
                vec3(textureSlotValue(material.textures + VKP_SLOT_SHEEN_COLOR, texcoords));
            material.sheenRoughness *=
                textureSlotValue(material.textures + VKP_SLOT_SHEEN_ROUGHNESS, texcoords).w;
        }
    }
    if (materialTransmits(material))
        material.transmittance *= vec3(base);
    else if (!materialIs(material, VKP_MATERIAL_CONDUCTOR) ||
             (material.flags & VKP_MATERIAL_COMPLEX_FRESNEL) == 0u)
        material.reflectance *= vec3(base);  // (a complex index is no colour)
    return material;
}
