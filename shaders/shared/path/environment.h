// The environment seen by escaping rays and sampled as a light: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

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
    return envDirectionPdf(env, sceneEnvAlias(environmentTexel(worldDirection)).probability,
                           worldDirection);
}
