// The path tracer's one loop, and the pieces it is cut into. Three
// executions run this code:
//
//   the CPU reference    tracePath, per path on CPU threads (host/reference/)
//   the GPU megakernel   traceBounce, each invocation taking its next path
//                        when one ends (stages/megakernel.comp)
//   the GPU wavefront    the loop cut at its stage boundaries: startPath in
//                        generate, bvhClosestHit in intersect, shadeHit +
//                        sampleDirectLight + scatter in shade, bvhOccluded in
//                        shadow, with PathState kept in per-path buffers
//                        between them (stages/*.comp)
//
// Each piece is the same function in all three, and the wavefront adds a
// path's radiance in the same order as the loop (emission of bounce b, then
// the sum of its unoccluded light samples, then bounce b + 1), so on one
// device the two GPU forms give the same image bit for bit
// (tests/render/all_scenes_test.cpp).
//
// Needs what shared/path_tracer.h needs plus the traversal
// (bvhClosestHit, bvhOccluded); include after it, once per scope (C++:
// inside PathTracerView). PathState and startPath, which need no scene, are
// in shared/path_state.h.

// ---- the albedo and normal AOVs (--aov albedo,normal) -----------------------------------
// Intel Open Image Denoise's definitions (github.com/RenderKit/oidn,
// doc/api.md, section "RT", subsections "Albedos" and "Normals"), with the
// choices that document leaves open:
// - the features of the first hit whose material has a non-delta lobe: a path
//   follows perfect specular (delta) bounces, mirror and smooth glass, to the
//   next hit, as that section recommends. Smooth glass picks reflection or
//   refraction by its Fresnel term, so a pixel's mean is the Fresnel blend of
//   the reflected and transmitted features that OIDN describes. A delta hit's
//   own features stand where the path ends there (depth, roulette).
// - albedo: shared/bsdf.h materialAlbedo (the kinds' choices there), not
//   multiplied by the specular tints on the way ("the reflected albedo in
//   itself can be used for mirror-like surfaces").
// - normal: the shading normal (interpolated, normal-mapped, as "Normals"
//   recommends) in world space, turned toward the ray that found it so that
//   a surface reads the same whatever its winding.
// - a path that leaves the scene before such a hit: albedo 0 and normal 0.
//   OIDN's documentation names no value for the background; 0 is inside its
//   ranges, and a null normal says that no surface is there.
VKP_FN bool aovsWanted() VKP_SCENE_CONST {
    return hasFeature(VKP_FEATURE_AOVS) && sceneInfo().aovs != 0u;
}

// The hit `shading` (the ray arriving along -wo) into the path's AOVs, unless
// a non-delta hit or the background set them before.
VKP_FN void recordAov(VKP_INOUT(PathAov) aov, VKP_IN(Shading) shading) VKP_SCENE_CONST {
    if (aov.found != 0u) return;
    aov.albedo = materialAlbedo(shading.material);
    vec3 n = shading.surface.shadingNormal;
    aov.normal = dot(n, shading.wo) < 0.0f ? -n : n;
    aov.found = hasNonDeltaLobe(shading.material) ? 1u : 0u;
}

// A ray that left the scene, into the path's AOVs unless set before.
VKP_FN void recordEscapeAov(VKP_INOUT(PathAov) aov) VKP_SCENE_CONST {
    if (aov.found != 0u) return;
    aov.albedo = vec3(0.0f);
    aov.normal = vec3(0.0f);
    aov.found = 1u;
}

// A path that scattered in a medium at `shading` (crossMedium): its AOVs
// take the medium's single-scattering albedo and no normal where no
// non-delta hit set them, and it scatters on below the maximum depth.
VKP_FN bool scattersInMedium(VKP_INOUT(PathState) path, VKP_IN(Shading) shading,
                             uint bounce) VKP_SCENE_CONST {
    if (aovsWanted() && path.aov.found == 0u) {
        Medium m = sceneMedium(shading.medium);
        vec3 extinction = m.scattering + m.absorption;
        path.aov.albedo = vec3(extinction.x > 0.0f ? m.scattering.x / extinction.x : 0.0f,
                               extinction.y > 0.0f ? m.scattering.y / extinction.y : 0.0f,
                               extinction.z > 0.0f ? m.scattering.z / extinction.z : 0.0f);
        if (hasFeature(VKP_FEATURE_GRID_MEDIUM) && shading.inMedium == VKP_EVENT_IN_GRID)
            path.aov.albedo = sceneGridMedium().albedo;
        path.aov.normal = vec3(0.0f);
        path.aov.found = 1u;
    }
    return bounce < sceneInfo().maxDepth;
}

// At a hit on dispersive glass (Material::dispersion > 0): a path that
// follows no wavelength yet takes one (its number VKP_DIM_WAVELENGTH, the
// same at every bounce) and its throughput the weight w(lambda); the glass's
// index becomes its index at the path's wavelength (shared/spectral.h).
VKP_FN void disperse(VKP_INOUT(PathState) path, VKP_INOUT(Material) material,
                     RngKey key) VKP_SCENE_CONST {
    if (path.wavelength == 0.0f) {
        path.wavelength = wavelengthOf(rngUniform(key, VKP_DIM_WAVELENGTH));
        path.throughput *= spectralWeight(path.wavelength);
    }
    material.ior = dispersedIor(material.ior, material.dispersion, path.wavelength);
}

// Stage "shade", first part: adds what the ray of bounce `bounce` sees at
// `hit` (emission with its MIS weight, or the environment on a miss), or,
// with media, where it scatters before. Returns whether the path scatters
// there (at a surface or in a medium, below the maximum depth); then
// `shading` describes the vertex.
VKP_FN bool shadeHit(VKP_INOUT(PathState) path, Hit hit, RngKey key, uint bounce,
                     VKP_OUT(Shading) shading) VKP_SCENE_CONST {
    shading.inMedium = 0u;
    shading.medium = VKP_FOG_MEDIUM;
    if (hit.primitive == VKP_NO_HIT) {
        if (mediaOn()) {
            // A defined record in place of the surface's that an event in a medium never reads.
            shading.material = sceneMaterial(0u);
            if (crossMedium(path, VKP_FOG_MEDIUM, VKP_FLOAT_MAX, key, bounce, shading))
                return scattersInMedium(path, shading, bounce);
        }
        if (aovsWanted()) recordEscapeAov(path.aov);
        if (hasFeature(VKP_FEATURES_ENVIRONMENT))
            path.radiance +=
                path.throughput * escapedRadiance(path.ray.direction, path.specular, path.bsdfPdf);
        return false;
    }
    BvhPrimitive primitive = bvhPrimitive(hit.primitive);
    BvhPrimitive objectTriangle = primitive;
    bool instanced = hasFeature(VKP_FEATURE_INSTANCES) && hit.instance != VKP_NO_INSTANCE;
    InstanceTransform x;
    if (instanced) {
        // An object's triangle, placed (shared/path/instances.h).
        x = instanceTransform(hit.instance);
        primitive = placedTriangle(primitive, x);
    }
    // The material as it is (path regularisation widens it last, below: the
    // medium behind it, its shading normal and its compensation follow its
    // own parameters; one copy of the record, which the CPU reference pays
    // per copy).
    shading.material = materialAt(sceneMaterial(primitive.material), primitive, hit);
    shading.surface = surfacePoint(primitive, path.ray, hit);
    if (instanced) {
        shading.surface.spawnOffset =
            instanceSpawnOffset(x, shading.surface.position, objectTriangle);
        if (instanceMirrors(x)) {
            shading.surface.normal = -shading.surface.normal;
            shading.surface.shadingNormal = shading.surface.normal;
        }
    }
    shading.wo = -path.ray.direction;
    if (mediaOn()) {
        // The segment's medium: the inside of the surface it reaches from
        // behind (shared/path/media.h).
        shading.medium = mediumBehind(shading.material, primitive.material);
        uint crossed = dot(path.ray.direction, shading.surface.normal) > 0.0f ? shading.medium
                                                                              : VKP_FOG_MEDIUM;
        if (crossMedium(path, crossed, hit.t, key, bounce, shading))
            return scattersInMedium(path, shading, bounce);
    } else if (hasFeature(VKP_FEATURE_ABSORPTION)) {
        path.throughput *= mediumTransmittance(shading.material, shading.surface, path.ray, hit);
    }
    shading.surface.shadingNormal =
        shadingNormal(shading.material, primitive, hit, shading.surface.normal, shading.wo);
    if (hasFeature(VKP_FEATURE_CLEARCOAT) && shading.material.clearcoat > 0.0f)
        shading.material.clearcoatNormal =
            clearcoatNormalAt(shading.material, primitive, hit, shading.surface.normal, shading.wo);
    if (hasFeature(VKP_FEATURE_DISPERSION) && shading.material.dispersion > 0.0f)
        disperse(path, shading.material, key);
    if (hasFeature(VKP_FEATURE_ANISOTROPY) && shading.material.anisotropy > 0.0f) {
        shading.material.anisotropyDirection =
            anisotropyDirectionAt(shading.material, primitive, hit, shading.surface.shadingNormal);
        if (shading.material.anisotropyDirection == vec3(0.0f)) shading.material.anisotropy = 0.0f;
    }
    // Compensation follows the material's own roughness: a lobe that path
    // regularisation roughens keeps its own (none for a mirror or smooth glass).
    if (hasFeature(VKP_FEATURE_MICROFACET_COMPENSATION) && sceneInfo().microfacetCompensation != 0u)
        shading.material.multipleScattering =
            multipleScattering(shading.material, dot(shading.surface.shadingNormal, shading.wo));
    if (hasFeature(VKP_FEATURE_SHEEN))
        shading.material.sheenLobeAlbedo =
            sheenLobeAlbedo(shading.material, dot(shading.surface.shadingNormal, shading.wo));
    if (hasFeature(VKP_FEATURE_REGULARIZE) && path.afterNonDelta)
        shading.material = regularizedMaterial(shading.material, sceneInfo().regularizeAlpha);
    if (aovsWanted()) recordAov(path.aov, shading);
    if (hasFeature(VKP_FEATURE_EMISSIVE_SURFACES))
        path.radiance += path.throughput *
                         emittedRadiance(shading.material, primitive, hit.primitive,
                                         shading.surface, path.ray.direction, path.previousPosition,
                                         path.previousNormal, path.specular, path.bsdfPdf);
    if (bounce >= sceneInfo().maxDepth) return false;
    // A last vertex whose light samples stand alone draws no BSDF sample and
    // weighs them against none: it needs no guide spheres.
    shading.guide.mask = 0u;
    shading.guide.count = 0u;
    if (!lightSamplingAlone(shading.material, bounce))
        shading.guide = guideSpheresAt(shading.material, shading.surface, shading.wo);
    return true;
}

// Stage "shade", last part: samples the BSDF (and roulette) for the next
// bounce. Returns whether the path goes on; then path.ray is its next ray.
VKP_FN bool scatter(VKP_INOUT(PathState) path, VKP_IN(Shading) shading, RngKey key,
                    uint bounce) VKP_SCENE_CONST {
    PathStep step = continuePath(shading, path.throughput, path.etaScale, key, bounce);
    if (!step.alive) return false;
    path.ray = step.ray;
    path.throughput = step.throughput;
    path.etaScale = step.etaScale;
    path.previousPosition = shading.surface.position;
    if (!lightTreeOn())
        path.previousNormal = 0u;
    else if (hasFeature(VKP_FEATURE_MEDIA) && shading.inMedium != 0u)
        path.previousNormal = VKP_NO_NORMAL;
    else
        path.previousNormal = encodeUnitVector(shading.surface.normal);
    path.bsdfPdf = step.bsdfPdf;
    path.specular = step.specular;
    path.afterNonDelta = path.afterNonDelta || !step.specular;
    return true;
}

// One bounce of the loop: traces path.ray, adds what it finds (emission or
// the environment, then the unoccluded light samples) and samples the next
// ray. Returns whether the path goes on to bounce + 1.
VKP_FN bool traceBounce(VKP_INOUT(PathState) path, RngKey key, uint bounce,
                        VKP_INOUT(PathTally) tally) VKP_SCENE_CONST {
    // ---- intersect ------------------------------------------------------------------
    Hit hit =
        bvhClosestHit(path.ray, pathAlphaKey(key, alphaClosestRay(bounce, lightSampleCount())));
    tally.closestRays += 1u;

    // ---- shade: what the ray sees ------------------------------------------------------
    Shading shading;
    if (!shadeHit(path, hit, key, bounce, shading)) return false;

    // ---- shade: next-event estimation; shadow: the unoccluded samples ------------------
    // As the shadow stage does: the sum is added once a sample was queued.
    vec3 unoccluded = vec3(0.0f);
    bool queued = false;
    for (uint j = 0u; j < lightSampleCount(); ++j) {
        ShadowRequest request = sampleDirectLight(shading, path.throughput, key, bounce, j);
        if (request.rejected) tally.rejectedLightSamples += 1u;
        queued = queued || request.valid;
        if (!request.valid || request.contribution == vec3(0.0f)) continue;
        tally.shadowRays += 1u;
        uint alphaKey = pathAlphaKey(key, alphaShadowRay(bounce, lightSampleCount(), j));
        if (!bvhOccluded(request.ray, alphaKey)) unoccluded += request.contribution;
    }
    if (queued) path.radiance += unoccluded;

    // ---- shade: the next bounce ----------------------------------------------------------
    return scatter(path, shading, key, bounce);
}

// The whole path from `path` (startPath): its radiance estimate ends in
// path.radiance (and its AOVs in path.aov).
VKP_FN void tracePath(VKP_INOUT(PathState) path, RngKey key,
                      VKP_INOUT(PathTally) tally) VKP_SCENE_CONST {
    uint bounce = 0u;
    while (traceBounce(path, key, bounce, tally)) ++bounce;
}
