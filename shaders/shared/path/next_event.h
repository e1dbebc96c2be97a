// Next-event estimation: light samples and their shadow rays: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

// ---- next-event estimation ---------------------------------------------------------------

// Whether the light that the vertex of bounce `bounce` on `material` receives
// is estimated by its light samples alone, with weight 1, and its BSDF sample
// is not traced: at the path's last scattering vertex (the next hit would
// only add emission: shadeHit), on a Lambertian surface, when every emitter
// is a light. The two estimators that MIS weighs there are each unbiased,
// so one alone is too; the ray it saves is one in five of a full path's
// closest-hit rays, and on a diffuse surface light sampling alone is as good
// as the MIS pair there (docs/BENCHMARKS.md, "The last vertex"). Glossy
// lobes keep MIS: light sampling alone is noisy on them.
VKP_FN bool lightSamplingAlone(VKP_IN(Material) material, uint bounce) VKP_SCENE_CONST {
    SceneInfo info = sceneInfo();
    return bounce + 1u == info.maxDepth && lightSampleCount() > 0u &&
           info.unsampledEmitters == 0u && materialIs(material, VKP_MATERIAL_DIFFUSE);
}

struct ShadowRequest {
    Ray ray;            // toward the light; tMax stops short of it
    vec3 contribution;  // added to the path's radiance if the ray is unoccluded
    bool valid;
    // The chosen light gave a direction of density 0 (or NaN) from here, e.g.
    // an area light seen exactly edge-on: the sample is skipped instead of
    // divided by its pdf, and counted (RenderResult::rejectedLightSamples).
    bool rejected;
};

// A light chosen (chooseLight) at `p` of normal `n` and a direction toward
// it from `p` (a point on it, or the environment's direction), from the
// sampler's dimensions dim to dim + 3 of `key`. The scene has at least one
// light.
struct SceneLightSample {
    LightSample lightSample;  // pdf: of the direction given this light
    uint lightIndex;          // its index in the light array; VKP_NO_LIGHT: the light tree was
                              // chosen and none of it reaches the point (radiance 0)
    float choice;             // the probability of choosing it
};

VKP_FN SceneLightSample sampleSceneLight(vec3 p, vec3 n, RngKey key, uint dim) VKP_SCENE_CONST {
    SceneInfo info = sceneInfo();
    // One pair picks the light and the point on it: its first word chooses
    // the light and, rescaled, is the point's first coordinate
    // (aliasSampleReusing, sampleLightTree), so the pair's stratification
    // carries over to the points on each light.
    uvec2 pointBits = rngBits2(key, dim + 2u);
    // A light of tiny probability gets its first coordinate from the
    // independent sampler at the same dimension (its stratification is moot:
    // it is chosen once in 2^16 samples or less often), and so does a tree
    // walked from too coarse a part of the word, from the dimension before
    // (the environment's texel pair, which a light of the tree never reads).
    RngKey independentKey = makeRngKey(key.pixel, key.sampleIndex, key.seed);
    float fresh = lightTreeOn() ? rngUniform(independentKey, dim + 1u) : 0.0f;
    LightChoice lightChoice = chooseLight(p, n, pointBits.x, fresh);
    SceneLightSample chosen;
    chosen.lightIndex = lightChoice.light;
    chosen.choice = lightChoice.probability;
    if (lightChoice.light == VKP_NO_LIGHT) {
        // The tree, of which no light reaches p: nothing to trace.
        chosen.choice = 1.0f;
        chosen.lightSample = noLightSample();
        chosen.lightSample.pdf = 1.0f;
        return chosen;
    }
    Light light = sceneLight(chosen.lightIndex);
    float u0 = lightChoice.reusable ? lightChoice.u : rngUniform(independentKey, dim + 2u);
    vec2 u = vec2(u0, uintToUnitFloat(pointBits.y));

    LightSample ls;
    if (lightIs(light, VKP_LIGHT_ENVIRONMENT)) {
        ls = noLightSample();
        EnvironmentInfo env = info.environment;
        if (!environmentIsMap()) {
            ls.direction = sampleUniformSphere(u);
            ls.pdf = uniformSpherePdf();
        } else {
            uint texels = env.width * env.height;
            uvec2 texelChoice = rngBits2(key, dim);
            uint envBucket = aliasBucket(texelChoice.x, texels);
            uint texel = aliasResolve(sceneEnvAlias(envBucket), envBucket, texelChoice.y);
            EnvSample es = envSampleInTexel(env, texel, u);
            ls.direction = es.direction;
            ls.pdf = envDirectionPdf(env, sceneEnvAlias(es.pdfTexel).probability, es.direction);
        }
        ls.distance = VKP_FLOAT_MAX;
        ls.radiance = environmentRadiance(ls.direction);
    } else {
        ls = sampleLight(light, p, u);
    }
    chosen.lightSample = ls;
    return chosen;
}

// Light sample `index` (of lightSamples) at vertex `shading`, whose path
// throughput is `throughput`.
VKP_FN ShadowRequest sampleDirectLight(VKP_IN(Shading) shading, vec3 throughput, RngKey key,
                                       uint bounce, uint index) VKP_SCENE_CONST {
    SurfacePoint surface = shading.surface;
    ShadowRequest request;
    request.valid = false;
    request.rejected = false;
    request.contribution = vec3(0.0f);
    request.ray.origin = surface.position;
    request.ray.direction = vec3(0.0f, 0.0f, 1.0f);
    request.ray.tMax = 0.0f;
    request.ray.pixel = key.pixel;
    SceneInfo info = sceneInfo();
    bool inMedium = hasFeature(VKP_FEATURE_MEDIA) && shading.inMedium != 0u;
    if (lightSampleCount() == 0u || info.lightCount == 0u ||
        (!inMedium && !hasNonDeltaLobe(shading.material)))
        return request;

    uint dim =
        bounceDimension(bounce) + VKP_DIMS_PER_BOUNCE_BASE + index * VKP_DIMS_PER_LIGHT_SAMPLE;
    // A scattering event in a medium has no normal: the tree's importance
    // then bounds no cosine (shared/light_tree.h).
    vec3 choiceNormal = lightTreeOn() && !inMedium ? lightChoiceNormal(surface.normal) : vec3(0.0f);
    SceneLightSample chosen = sampleSceneLight(surface.position, choiceNormal, key, dim);
    LightSample ls = chosen.lightSample;
    float choice = chosen.choice;
    if (!(ls.pdf > 0.0f)) {
        request.rejected = true;
        return request;
    }
    if (ls.radiance == vec3(0.0f)) return request;

    vec3 f;
    float scatterDensity;  // of the vertex's own sample in this direction (MIS)
    if (inMedium) {
        float phase = henyeyGreenstein(dot(shading.wo, ls.direction), eventAnisotropy(shading));
        f = vec3(phase);
        scatterDensity = phase;
    } else {
        f = evalBsdf(shading.material, surface.normal, surface.shadingNormal, shading.wo,
                     ls.direction);
        scatterDensity = 0.0f;  // found below only where MIS needs it
    }
    if (f == vec3(0.0f)) return request;
    float n = float(lightSampleCount());
    float lightPdf = choice * ls.pdf;
    float weight = 1.0f;
    if (!ls.delta && (inMedium || !lightSamplingAlone(shading.material, bounce))) {
        if (!inMedium)
            scatterDensity =
                scatterPdf(shading.material, surface, shading.wo, shading.guide, ls.direction);
        weight = powerHeuristic(n * lightPdf, scatterDensity);
    }
    request.contribution = throughput * f * ls.radiance * (weight / (n * lightPdf));
    // Through a medium the shadow ray carries its transmittance, exact for a
    // homogeneous one (an occluder ends it: a transmitting body's surface
    // blocks light samples, as without media).
    if (mediaOn())
        request.contribution *=
            shadowTransmittance(shading, ls.direction, ls.distance, key, bounce, index);

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
