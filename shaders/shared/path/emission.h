// Emission seen by a path, with its MIS weight: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

// ---- emission seen by a path ----------------------------------------------------------

// The weight of emission reached by a BSDF sample of density `bsdfPdf` whose
// light-sampling density (choice x direction) would have been `lightPdf`.
VKP_FN float bsdfMisWeight(float bsdfPdf, float lightPdf) VKP_SCENE_CONST {
    return powerHeuristic(bsdfPdf, float(lightSampleCount()) * lightPdf);
}

// What a path sees when its ray escapes. `specular`: the ray came from the
// camera or a delta BSDF (no light sample could have found this direction).
VKP_FN vec3 escapedRadiance(vec3 direction, bool specular, float bsdfPdf) VKP_SCENE_CONST {
    SceneInfo info = sceneInfo();
    vec3 le = environmentRadiance(direction);
    if (specular || lightSampleCount() == 0u || info.environmentLight == VKP_NO_LIGHT) return le;
    float lightPdf = lightChoiceProbability(info.environmentLight, vec3(0.0f), vec3(0.0f)) *
                     environmentPdf(direction);
    return le * bsdfMisWeight(bsdfPdf, lightPdf);
}

// Emission at a hit: `surface` on `primitive`, leaf primitive `index`,
// reached along `direction` from `previous` (the last vertex, its normal
// `previousNormal` as the path keeps it) by a ray of BSDF density `bsdfPdf`.
// Triangles emit from their front face only. A clear coat lies over the
// emission (KHR_materials_clearcoat) and dims it by the share it reflects,
// clearcoat F_c(n.v) at the shading normal; the host does not light-sample
// such emitters (host/wavefront/gpu_scene.cpp), whose record could not say it.
VKP_FN vec3 emittedRadiance(VKP_IN(Material) material, VKP_IN(BvhPrimitive) primitive, uint index,
                            VKP_IN(SurfacePoint) surface, vec3 direction, vec3 previous,
                            uint previousNormal, bool specular, float bsdfPdf) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_EMISSIVE_SURFACES)) return vec3(0.0f);
    vec3 le = material.emission;
    if (!isSphere(primitive) && dot(direction, surface.normal) >= 0.0f) return vec3(0.0f);
    if (hasFeature(VKP_FEATURE_CLEARCOAT) && material.clearcoat > 0.0f)
        le *=
            1.0f - clearcoatFresnel(material.clearcoat, abs(dot(surface.shadingNormal, direction)));
    SceneInfo info = sceneInfo();
    if (le == vec3(0.0f) || specular || lightSampleCount() == 0u || info.lightCount == 0u)
        return le;
    uint lightIndex = scenePrimitiveLight(index);
    if (lightIndex == VKP_NO_LIGHT) return le;
    Light light = sceneLight(lightIndex);
    vec3 n = lightTreeOn() && previousNormal != VKP_NO_NORMAL ? decodeUnitVector(previousNormal)
                                                              : vec3(0.0f);
    float lightPdf = lightChoiceProbability(lightIndex, previous, n) *
                     areaLightPdf(light, previous, surface.position, surface.normal);
    return le * bsdfMisWeight(bsdfPdf, lightPdf);
}
