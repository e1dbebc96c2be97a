// The path tracer's per-vertex math, shared by the wavefront stages and the
// CPU reference renderer: emission with its MIS weight, one light sample
// (next-event estimation), and the BSDF sample that continues the path with
// Russian roulette. Like shared/bvh_traverse.h it reads the scene through
// accessors its includer defines:
//
//   SceneInfo sceneInfo();
//   Material sceneMaterial(uint index);
//   Light sceneLight(uint index);
//   AliasEntry sceneLightAlias(uint index);
//   uint scenePrimitiveLight(uint leafPrimitive);   // VKP_NO_LIGHT if not emissive
//   AliasEntry sceneEnvAlias(uint texel);
//   vec3 sceneEnvRadiance(uint texel);              // linear RGB, before strength
//   BvhPrimitive bvhPrimitive(uint index);          // from the BVH
//
// No include guard: include once per scope (C++: inside the reference
// renderer's scene view struct, so these become const member functions).
//
// Multiple importance sampling: light sampling (N = lightSamples samples per
// vertex) and BSDF sampling are combined with the power heuristic with
// sample counts (Veach's thesis, section 9.2): a light sample of density p_l
// (light choice times direction) is weighted (N p_l)^2 / ((N p_l)^2 + p_b^2)
// and divided by N; an emitter hit by the BSDF sample of density p_b gets
// p_b^2 / (p_b^2 + (N p_l)^2). Delta lights and delta BSDFs take weight 1.

#ifdef __cplusplus
#define VKP_SCENE_CONST const
#else
#define VKP_SCENE_CONST
#endif

// Random dimensions: after the pixel jitter, each bounce uses
// VKP_DIMS_PER_BOUNCE_BASE + VKP_DIMS_PER_LIGHT_SAMPLE * lightSamples numbers.
// Every 2-D quantity starts at an even dimension, the pairs that the Sobol'
// sampler stratifies together (shared/rng.h); roulette's single number is
// padded to a pair for that.
#define VKP_DIMS_PER_BOUNCE_BASE 4u  // BSDF direction (2), Russian roulette (1), padding (1)
#define VKP_DIMS_PER_LIGHT_SAMPLE 6u  // light choice (2 words), environment texel (2 words), position (2)

// SceneInfo::lightSamples, a constant when the kernel's features fix it.
VKP_FN uint lightSampleCount() VKP_SCENE_CONST { return featureLightSamples(sceneInfo().lightSamples); }

VKP_FN uint bounceDimension(uint bounce) VKP_SCENE_CONST {
    return 2u + bounce * (VKP_DIMS_PER_BOUNCE_BASE + VKP_DIMS_PER_LIGHT_SAMPLE * lightSampleCount());
}


// ---- the environment ---------------------------------------------------------------

// Whether the environment is a map (else a constant colour); call only where
// the scene has one.
VKP_FN bool environmentIsMap() VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_ENVIRONMENT_MAP)) return false;
    if (!hasFeature(VKP_FEATURE_ENVIRONMENT_COLOR)) return true;
    return sceneInfo().environment.width != 0u;
}

// The texel whose sampling cell holds `worldDirection` (environmentPdf).
VKP_FN uint environmentTexel(vec3 worldDirection) VKP_SCENE_CONST {
    EnvironmentInfo env = sceneInfo().environment;
    return envTexelOfUv(env, equirectUv(envWorldToMap(env, worldDirection)));
}

// The map's radiance interpolated bilinearly between texel centres
// (shared/environment_sampling.h, envBilinear).
VKP_FN vec3 environmentRadiance(vec3 worldDirection) VKP_SCENE_CONST {
    SceneInfo info = sceneInfo();
    if (!hasFeature(VKP_FEATURES_ENVIRONMENT) || info.hasEnvironment == 0u) return vec3(0.0f);
    if (!environmentIsMap()) return info.environment.color * info.environment.strength;
    EnvironmentInfo env = info.environment;
    EnvBilinear b = envBilinear(env, equirectUv(envWorldToMap(env, worldDirection)));
    vec3 radiance = envBilinearMix(b, sceneEnvRadiance(b.texel00), sceneEnvRadiance(b.texel10),
                                   sceneEnvRadiance(b.texel01), sceneEnvRadiance(b.texel11));
    return radiance * env.strength;
}

// Solid-angle density of sampling `worldDirection` from the environment light
// (without the probability of choosing it): the probability of the cell the
// direction lies in, the one sampleDirectLight draws from, over the cell's
// solid angle. A constant environment is sampled uniformly over the sphere.
VKP_FN float environmentPdf(vec3 worldDirection) VKP_SCENE_CONST {
    EnvironmentInfo env = sceneInfo().environment;
    if (!environmentIsMap()) return uniformSpherePdf();
    return envDirectionPdf(env, sceneEnvAlias(environmentTexel(worldDirection)).probability, worldDirection);
}

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
    float lightPdf = sceneLightAlias(info.environmentLight).probability * environmentPdf(direction);
    return le * bsdfMisWeight(bsdfPdf, lightPdf);
}

// Emission at a hit: `surface` on leaf primitive `primitive`, reached along
// `direction` from `previous` (the last vertex) by a ray of BSDF density
// `bsdfPdf`. Triangles emit from their front face only.
VKP_FN vec3 emittedRadiance(Material material, uint primitive, SurfacePoint surface, vec3 direction, vec3 previous,
                            bool specular, float bsdfPdf) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_EMISSIVE_SURFACES)) return vec3(0.0f);
    vec3 le = material.emission;
    if (!isSphere(bvhPrimitive(primitive)) && dot(direction, surface.normal) >= 0.0f) return vec3(0.0f);
    SceneInfo info = sceneInfo();
    if (le == vec3(0.0f) || specular || lightSampleCount() == 0u || info.lightCount == 0u) return le;
    uint lightIndex = scenePrimitiveLight(primitive);
    if (lightIndex == VKP_NO_LIGHT) return le;
    Light light = sceneLight(lightIndex);
    float lightPdf = sceneLightAlias(lightIndex).probability * areaLightPdf(light, previous, surface.position, surface.normal);
    return le * bsdfMisWeight(bsdfPdf, lightPdf);
}

// ---- next-event estimation ---------------------------------------------------------------

struct ShadowRequest {
    Ray ray;            // toward the light; tMax stops short of it
    vec3 contribution;  // added to the path's radiance if the ray is unoccluded
    bool valid;
    // The chosen light gave a direction of density 0 (or NaN) from here, e.g.
    // an area light seen exactly edge-on: the sample is skipped instead of
    // divided by its pdf, and counted (RenderResult::rejectedLightSamples).
    bool rejected;
};

// Light sample `index` (of lightSamples) at a diffuse vertex.
VKP_FN ShadowRequest sampleDirectLight(Material material, SurfacePoint surface, vec3 wo, vec3 throughput,
                                       RngKey key, uint bounce, uint index) VKP_SCENE_CONST {
    ShadowRequest request;
    request.valid = false;
    request.rejected = false;
    request.contribution = vec3(0.0f);
    request.ray.origin = surface.position;
    request.ray.direction = vec3(0.0f, 0.0f, 1.0f);
    request.ray.tMax = 0.0f;
    request.ray.pixel = key.pixel;
    SceneInfo info = sceneInfo();
    if (lightSampleCount() == 0u || info.lightCount == 0u || !hasNonDeltaLobe(material)) return request;

    uint dim = bounceDimension(bounce) + VKP_DIMS_PER_BOUNCE_BASE + index * VKP_DIMS_PER_LIGHT_SAMPLE;
    uint bucket = aliasBucket(rngBits(key, dim), info.lightCount);
    uint lightIndex = aliasResolve(sceneLightAlias(bucket), bucket, rngBits(key, dim + 1u));
    float choice = sceneLightAlias(lightIndex).probability;
    Light light = sceneLight(lightIndex);

    LightSample ls;
    if (lightIs(light, VKP_LIGHT_ENVIRONMENT)) {
        ls = noLightSample();
        EnvironmentInfo env = info.environment;
        if (!environmentIsMap()) {
            ls.direction = sampleUniformSphere(rngUniform2(key, dim + 4u));
            ls.pdf = uniformSpherePdf();
        } else {
            uint texels = env.width * env.height;
            uint envBucket = aliasBucket(rngBits(key, dim + 2u), texels);
            uint texel = aliasResolve(sceneEnvAlias(envBucket), envBucket, rngBits(key, dim + 3u));
            EnvSample es = envSampleInTexel(env, texel, rngUniform2(key, dim + 4u));
            ls.direction = es.direction;
            ls.pdf = envDirectionPdf(env, sceneEnvAlias(es.pdfTexel).probability, es.direction);
        }
        ls.distance = VKP_FLOAT_MAX;
        ls.radiance = environmentRadiance(ls.direction);
    } else {
        ls = sampleLight(light, surface.position, rngUniform2(key, dim + 4u));
    }
    if (!(ls.pdf > 0.0f)) {
        request.rejected = true;
        return request;
    }
    if (ls.radiance == vec3(0.0f)) return request;

    vec3 f = evalBsdf(material, surface.normal, wo, ls.direction);
    if (f == vec3(0.0f)) return request;
    float n = float(lightSampleCount());
    float lightPdf = choice * ls.pdf;
    float weight = ls.delta ? 1.0f : powerHeuristic(n * lightPdf, bsdfPdf(material, surface.normal, wo, ls.direction));
    request.contribution = throughput * f * ls.radiance * (weight / (n * lightPdf));

    request.ray = spawnRay(surface, ls.direction, VKP_FLOAT_MAX, key.pixel);
    if (ls.distance < VKP_FLOAT_MAX) {
        // The shadow ray asks whether anything lies strictly between the two
        // surfaces. Its far end is pulled off the light's surface twice over:
        // by the ulp-scaled offset that lifts origins off surfaces
        // (shared/intersect.h), which covers coordinate rounding far from the
        // origin, and by 2^-12 of the distance, which covers the larger error
        // of intersecting the light itself at a grazing angle.
        vec3 target = surface.position + ls.distance * ls.direction;
        if (ls.normal != vec3(0.0f)) {
            vec3 toward = dot(ls.normal, ls.direction) < 0.0f ? ls.normal : -ls.normal;
            target = offsetRayOrigin(target, toward, maxComponent(abs(target)));
        }
        request.ray.tMax = dot(target - request.ray.origin, ls.direction) * (1.0f - 2.44140625e-4f);
    }
    request.valid = true;
    return request;
}

// ---- continuing the path --------------------------------------------------------------------

struct PathStep {
    Ray ray;           // the next ray
    vec3 throughput;   // the path throughput after this vertex (and roulette)
    float etaScale;    // the product of eta'^2 over the path's refractions (PathState::etaScale)
    float bsdfPdf;     // density of the sampled direction (for MIS at the next hit)
    bool specular;     // the sample came from a delta BSDF
    bool alive;        // false: the path ends here
};

VKP_FN PathStep continuePath(Material material, SurfacePoint surface, vec3 wo, vec3 throughput, float etaScale,
                             RngKey key, uint bounce) VKP_SCENE_CONST {
    PathStep step;
    step.alive = false;
    step.throughput = throughput;
    step.etaScale = etaScale;
    step.bsdfPdf = 0.0f;
    step.specular = false;
    step.ray.origin = surface.position;
    step.ray.direction = vec3(0.0f, 0.0f, 1.0f);
    step.ray.tMax = 0.0f;
    step.ray.pixel = key.pixel;

    uint dim = bounceDimension(bounce);
    BsdfSample s = sampleBsdf(material, surface.normal, wo, rngUniform2(key, dim));
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
    step.ray = spawnRay(surface, s.direction, VKP_FLOAT_MAX, key.pixel);
    step.throughput = beta;
    step.etaScale = eta2;
    step.bsdfPdf = s.pdf;
    step.specular = s.delta;
    step.alive = true;
    return step;
}
