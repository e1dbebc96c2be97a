// Continuing the path: the BSDF sample and Russian roulette: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

// ---- continuing the path --------------------------------------------------------------------

struct PathStep {
    Ray ray;          // the next ray
    vec3 throughput;  // the path throughput after this vertex (and roulette)
    float etaScale;   // the product of eta'^2 over the path's refractions (PathState::etaScale)
    float bsdfPdf;    // density of the sampled direction (for MIS at the next hit)
    bool specular;    // the sample came from a delta BSDF
    bool alive;       // false: the path ends here
};

// The next bounce from vertex `shading`.
VKP_FN PathStep continuePath(VKP_IN(Shading) shading, vec3 throughput, float etaScale, RngKey key,
                             uint bounce) VKP_SCENE_CONST {
    PathStep step;
    step.alive = false;
    step.throughput = throughput;
    step.etaScale = etaScale;
    step.bsdfPdf = 0.0f;
    step.specular = false;
    step.ray.origin = shading.surface.position;
    step.ray.direction = vec3(0.0f, 0.0f, 1.0f);
    step.ray.tMax = 0.0f;
    step.ray.pixel = key.pixel;

    uint dim = bounceDimension(bounce);
    BsdfSample s;
    if (hasFeature(VKP_FEATURE_MEDIA) && shading.inMedium != 0u) {
        // The phase function samples itself exactly: weight 1.
        float g = eventAnisotropy(shading);
        s.direction = sampleHenyeyGreenstein(shading.wo, g, rngUniform2(key, dim));
        s.pdf = henyeyGreenstein(dot(shading.wo, s.direction), g);
        s.weight = vec3(1.0f);
        s.delta = false;
        s.valid = true;
        s.etaSquared = 1.0f;
    } else {
        if (lightSamplingAlone(shading.material, bounce)) return step;
        // A guided Lambertian vertex draws its mixture's component where a
        // material with lobes draws its lobe (no Lambertian does).
        float lobeChoice = bsdfNeedsLobeChoice(shading.material) || shading.guide.count > 0u
                               ? rngUniform(key, dim + 3u)
                               : 0.0f;
        s = shading.guide.count > 0u
                ? sampleGuidedDiffuse(shading.material, shading.surface, shading.wo, shading.guide,
                                      rngUniform2(key, dim), lobeChoice)
                : sampleBsdf(shading.material, shading.surface.normal,
                             shading.surface.shadingNormal, shading.wo, rngUniform2(key, dim),
                             lobeChoice);
    }
    if (!s.valid) return step;
    vec3 beta = throughput * s.weight;
    // Kept within [2^-100, 2^100]: never 0 or infinite, so its sign can be
    // packed (PathVertex) and the survival probability stays defined.
    float eta2 = clamp(etaScale * s.etaSquared, 7.88860905e-31f, 1.26765060e30f);

    // Russian roulette (from rouletteDepth on): survive with probability
    // min(1, max component of the throughput x etaScale), reweighted to stay
    // unbiased. etaScale undoes the 1 / eta'^2 by which refraction scales
    // radiance (a ray inside glass is not a dimmer path, only a compressed
    // one: the roulette of pbrt-v4's PathIntegrator, section 13.4, and of
    // Mitsuba 3's path integrator). Depth counts as theirs do: the vertex of
    // bounce b (0 = the first hit) is the (b + 1)-th, and roulette follows its
    // BSDF sample from the rouletteDepth-th vertex on.
    if (hasFeature(VKP_FEATURE_ROULETTE) && bounce + 1u >= sceneInfo().rouletteDepth) {
        float survive = min(1.0f, max(max(beta.x, beta.y), beta.z) * eta2);
        if (!(rngUniform(key, dim + 2u) < survive)) return step;
        beta /= survive;
    }
    if (beta == vec3(0.0f)) return step;
    step.ray = spawnRay(shading.surface, s.direction, VKP_FLOAT_MAX, key.pixel);
    step.throughput = beta;
    step.etaScale = eta2;
    step.bsdfPdf = s.pdf;
    step.specular = s.delta;
    step.alive = true;
    return step;
}
