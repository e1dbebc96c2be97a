// Multiple-scattering compensation of the microfacet lobes
// (shared/microfacet_albedo.h) and the sheen's albedo scaling: part of
// shared/path_tracer.h, which includes it (no include guard: once per scope,
// as path_tracer.h). It reads the
// albedo tables through the accessor
//
//   float sceneMicrofacetAlbedo(uint index);  // shared/microfacet_albedo.h's layout
//
// ---- multiple-scattering compensation and the sheen's albedo ----------------------------

// The table entry at (cos, roughness) of the block at `offset`, interpolated
// linearly on both axes.
VKP_FN float microfacetAlbedoAt(uint offset, AlbedoGridCell c, AlbedoGridCell r) VKP_SCENE_CONST {
    uint row = offset + r.index * VKP_ALBEDO_COS_COUNT + c.index;
    float lower = mix(sceneMicrofacetAlbedo(row), sceneMicrofacetAlbedo(row + 1u), c.weight);
    row += VKP_ALBEDO_COS_COUNT;
    float upper = mix(sceneMicrofacetAlbedo(row), sceneMicrofacetAlbedo(row + 1u), c.weight);
    return mix(lower, upper, r.weight);
}

// E(mu_o) of the white single-scattering lobe of `material` (a microfacet
// kind) seen from wo at cosine cosO to its shading normal (signed: glass
// tells the inside from it), interpolated from the tables. An anisotropic
// lobe reads the isotropic one of the root mean square of its two alphas,
// the simple stand-in that comes closest (against the geometric mean, the
// arithmetic mean and the alpha projected on wo's azimuth): the white
// metal's albedo E_aniso / E_iso stays within 8% of 1 at strengths up to
// 0.6 and within 30% at strength 1, at grazing angles across the direction
// (tests/kernels/anisotropy_test.cpp measures it).
VKP_FN float microfacetAlbedo(VKP_IN(Material) material, float cosO) VKP_SCENE_CONST {
    AlbedoGridCell c = albedoGridCell(albedoGridCosPosition(abs(cosO)), VKP_ALBEDO_COS_COUNT);
    float roughness = material.roughness;
    if (materialAnisotropic(material)) {
        vec2 alpha = materialAlpha(material);
        roughness = sqrt(sqrt(0.5f * (alpha.x * alpha.x + alpha.y * alpha.y)));
    }
    AlbedoGridCell r =
        albedoGridCell(albedoGridRoughnessPosition(roughness), VKP_ALBEDO_ROUGHNESS_COUNT);
    // (a thin wall's lobe is the conductor's, split between its two sides)
    if (!materialIs(material, VKP_MATERIAL_ROUGH_DIELECTRIC) || materialThinWalled(material))
        return microfacetAlbedoAt(VKP_ALBEDO_CONDUCTOR_OFFSET, c, r);
    // The rough glass: the table of wo's side, at the index of wi's side over
    // wo's (or its inverse when that is below 1, light leaving the glass).
    bool leaving = (cosO > 0.0f) == (material.ior < 1.0f);
    float eta = material.ior < 1.0f ? 1.0f / material.ior : material.ior;
    AlbedoGridCell n = albedoGridCell(albedoGridIorPosition(eta), VKP_ALBEDO_IOR_COUNT);
    uint block = (leaving ? VKP_ALBEDO_LEAVING_OFFSET : VKP_ALBEDO_ENTERING_OFFSET) +
                 n.index * VKP_ALBEDO_CONDUCTOR_SIZE;
    return mix(microfacetAlbedoAt(block, c, r),
               microfacetAlbedoAt(block + VKP_ALBEDO_CONDUCTOR_SIZE, c, r), n.weight);
}

// Material::multipleScattering of `material` for wo at cosine cosO to the
// shading normal: (1 - E) / E for a microfacet kind (the registry's
// VKP_KIND_MICROFACET) whose GGX lobe is not a delta; 0 otherwise, when its
// lobes scale by exactly 1.
VKP_FN float multipleScattering(VKP_IN(Material) material, float cosO) VKP_SCENE_CONST {
    bool microfacet = (materialKindFlags(materialKind(material)) & VKP_KIND_MICROFACET) != 0u;
    if (!microfacet || microfacetIsSmooth(materialAlpha(material)) || !hasNonDeltaLobe(material) ||
        cosO == 0.0f)
        return 0.0f;
    float albedo = microfacetAlbedo(material, cosO);
    return albedo > 0.0f ? (1.0f - albedo) / albedo : 0.0f;
}

// Material::sheenLobeAlbedo of `material` for wo at cosine cosO to the
// shading normal: E_sheen(mu_o) of its white sheen lobe, from which the
// layered material takes what the sheen reflects and the base loses
// (shared/metallic_roughness.h); 0 without a sheen.
VKP_FN float sheenLobeAlbedo(VKP_IN(Material) material, float cosO) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_SHEEN) || !materialIs(material, VKP_MATERIAL_METALLIC_ROUGHNESS) ||
        material.sheenColor == vec3(0.0f))
        return 0.0f;
    AlbedoGridCell c = albedoGridCell(albedoGridCosPosition(abs(cosO)), VKP_ALBEDO_COS_COUNT);
    AlbedoGridCell r = albedoGridCell(albedoGridRoughnessPosition(material.sheenRoughness),
                                      VKP_ALBEDO_ROUGHNESS_COUNT);
    return microfacetAlbedoAt(VKP_ALBEDO_SHEEN_OFFSET, c, r);
}
