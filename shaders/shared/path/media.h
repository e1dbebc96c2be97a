// Path vertices at surfaces and in media: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

// ---- path vertices: at a surface or in a medium -------------------------------------------
// A vertex as the rest of its bounce needs it: a surface hit, or (with
// VKP_FEATURE_MEDIA) a scattering event in a medium, where the medium's
// phase function (shared/phase.h) stands for the BSDF.
struct Shading {
    Material material;     // at a surface
    SurfacePoint surface;  // in a medium: the event's position; normal and shadingNormal 0
    vec3 wo;               // toward the previous vertex
    GuideSpheres
        guide;  // the spheres its BSDF samples may be drawn toward (guideSpheresAt), found once
    // With media: 1 at a scattering event in medium `medium` (an index of the
    // media array, shared/medium.h), 0 at a surface, where `medium` is the
    // one behind its front face: a transmitting material's inside, else the fog.
    uint inMedium;
    uint medium;
};

// ---- which medium a ray crosses ---------------------------------------------------------
// No medium is tracked along a path: a segment's medium is read off its end.
// A ray that meets a transmitting material's surface from behind travelled
// inside that material; every other segment, and a ray that leaves the
// scene, is in the fog. That holds as long as the bodies of transmitting
// materials are closed and neither overlap nor nest (the assumption of
// absorption inside glass, docs/SCENES.md), and it costs no state, so a
// wavefront path carries nothing more than without media.

// The medium behind the front face of a surface of scene material
// `materialIndex` (`material` its record).
VKP_FN uint mediumBehind(VKP_IN(Material) material, uint materialIndex) VKP_SCENE_CONST {
    return materialTransmits(material) ? 1u + materialIndex : VKP_FOG_MEDIUM;
}

// The medium that a ray along `direction` from a surface vertex crosses.
VKP_FN uint mediumToward(VKP_IN(Shading) shading, vec3 direction) VKP_SCENE_CONST {
    if (shading.inMedium != 0u) return shading.medium;
    return dot(direction, shading.surface.normal) < 0.0f ? shading.medium : VKP_FOG_MEDIUM;
}

// Whether medium `index` scatters or absorbs anything.
VKP_FN bool mediumPresent(VKP_IN(Medium) m) VKP_SCENE_CONST {
    return m.scattering != vec3(0.0f) || m.absorption != vec3(0.0f);
}

// The free flight through medium `index` of the segment of bounce `bounce`,
// which ends at distance tEnd: the path's throughput takes its weight;
// true if the path scattered in it, then `shading` is that event.
// (inout, not out: in GLSL an out parameter's fields that the function does
// not write are undefined after it, and a path that reaches the surface keeps
// the surface's.)
VKP_FN bool crossMedium(VKP_INOUT(PathState) path, uint index, float tEnd, RngKey key, uint bounce,
                        VKP_INOUT(Shading) shading) VKP_SCENE_CONST {
    Medium m = sceneMedium(index);
    if (!mediumPresent(m)) return false;
    FreeFlight flight =
        sampleFreeFlight(m, tEnd, rngUniform2(key, bounceDimension(bounce) + VKP_DIM_FREE_FLIGHT));
    path.throughput *= flight.weight;
    if (!flight.scattered) return false;
    shading.inMedium = 1u;
    shading.medium = index;
    shading.wo = -path.ray.direction;
    shading.surface.position = path.ray.origin + flight.t * path.ray.direction;
    shading.surface.magnitude = maxComponent(abs(shading.surface.position));
    shading.surface.spawnOffset = 0.0f;
    shading.surface.normal = vec3(0.0f);
    shading.surface.shadingNormal = vec3(0.0f);
    shading.guide.mask = 0u;
    shading.guide.count = 0u;
    return true;
}

// The transmittance of a shadow ray of length `distance` (VKP_FLT_MAX: to
// a light at infinity) leaving `shading` along `direction`.
VKP_FN vec3 shadowTransmittance(VKP_IN(Shading) shading, vec3 direction,
                                float distance) VKP_SCENE_CONST {
    return mediumTransmittanceAlong(sceneMedium(mediumToward(shading, direction)), distance);
}
