// Absorption inside glass: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

// ---- absorption inside glass ------------------------------------------------------------

// What is left of light that crossed the inside of `material` to reach
// `surface` from behind along `ray` (Beer-Lambert: exp(-attenuation d)), 1
// for a hit from the front or on a clear material. A ray that meets a glass
// surface from behind travelled inside that glass, as long as glass bodies
// are closed and do not overlap or nest (docs/SCENES.md).
VKP_FN vec3 mediumTransmittance(VKP_IN(Material) material, VKP_IN(SurfacePoint) surface,
                                VKP_IN(Ray) ray, Hit hit) VKP_SCENE_CONST {
    if (!materialTransmits(material) || material.attenuation == vec3(0.0f) ||
        dot(ray.direction, surface.normal) <= 0.0f)
        return vec3(1.0f);
    return exp(-material.attenuation * hit.t);  // (ray.direction is unit)
}
