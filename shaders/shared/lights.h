// Lights as the kernels see them, and sampling them from a surface point.
// Emissive triangles and spheres are area lights (their emission comes from
// their material; a triangle emits from its front face, as pbrt's and
// Scotty3D's area lights do, a sphere to both sides); point, spot and directional lights are delta
// lights; the environment is one light whose directions come from its own alias table. One alias
// table over all lights picks a light in proportion to its power.
#ifndef VKPATH_SHARED_LIGHTS_H
#define VKPATH_SHARED_LIGHTS_H

#include "shared/compat.h"
#include "shared/constants.h"
#include "shared/features.h"
#include "shared/light_types.h"
#include "shared/records.h"
#include "shared/sampling.h"

// Values of Light::type, one per row of the registry (shared/light_types.h):
// VKP_LIGHT_TRIANGLE, VKP_LIGHT_SPHERE, ...
#define VKP_LIGHT_CONSTANT(id, NAME, Type, label, feature, shape, flags) \
    VKP_CONSTANT(VKP_LIGHT_##NAME, id)
VKP_LIGHT_TYPES(VKP_LIGHT_CONSTANT)
#undef VKP_LIGHT_CONSTANT

VKP_NAMESPACE_BEGIN

// Light's fields (type, name, first 32-bit word; shared/records.h): the
// struct, its layout check and its texel decoding come from this list.
#define VKP_LIGHT_FIELDS(F)                                                                   \
    /* triangle: vertex 0; sphere: centre; point, spot: position (world space) */             \
    F(vec3, p0, 0)                                                                            \
    /* VKP_LIGHT_* */                                                                         \
    F(uint, type, 3)                                                                          \
    /* triangle: vertex 1; spot: unit axis; directional: unit direction of travel */          \
    F(vec3, p1, 4)                                                                            \
    /* sphere: radius; point, spot: KHR_lights_punctual's range (0: none; rangeWindow) */     \
    F(float, radius, 7)                                                                       \
    /* triangle: vertex 2 */                                                                  \
    F(vec3, p2, 8)                                                                            \
    /* spot: cosine of the inner cone angle (full intensity inside) */                        \
    F(float, cosInner, 11)                                                                    \
    /* triangle, sphere: radiance W/(m^2 sr), from a triangle's front face only (counter- */  \
    /* clockwise seen from the front), from both sides of a sphere; point, spot: intensity */ \
    /* W/sr; directional: irradiance W/m^2 */                                                 \
    F(vec3, emission, 12)                                                                     \
    /* spot: cosine of the outer cone angle (dark outside) */                                 \
    F(float, cosOuter, 15)                                                                    \
    /* triangle: unit normal of the front face, normalize((p1 - p0) x (p2 - p0)) */           \
    F(vec3, normal, 16)                                                                       \
    /* triangle: length(triangleArea3(p0, p1, p2)); both computed once by the host */         \
    /* (wavefront/gpu_scene.cpp), not at every light sample */                                \
    F(float, area, 19)
struct Light {
    VKP_LIGHT_FIELDS(VKP_FIELD_DECLARE)
};

// What a light sample brings to a point.
struct LightSample {
    vec3 direction;  // unit, from the point toward the light
    float distance;  // to the sampled point on the light; VKP_FLOAT_MAX for directional and
                     // environment
    vec3 radiance;   // incident radiance (area), or intensity / distance^2 (point, spot), or
                     // irradiance
    float pdf;       // solid-angle density of `direction` for area lights; 1 for delta lights
                     // (neither includes the probability of choosing the light)
    vec3 normal;     // area lights: unit surface normal at the sampled point (else 0)
    bool delta;      // point, spot, directional: no MIS
};

// The light types a kernel may meet, one bit (1 << VKP_LIGHT_*) each, from
// its features: surfaces light only where they emit.
VKP_FN uint possibleLightTypes() {
    uint types = 0u;
#define VKP_LIGHT_POSSIBLE(id, NAME, Type, label, feature, shape, flags)          \
    if (hasFeature(feature) && ((shape) == VKP_NO_FEATURES || hasFeature(shape))) \
        types |= 1u << (id);
    VKP_LIGHT_TYPES(VKP_LIGHT_POSSIBLE)
#undef VKP_LIGHT_POSSIBLE
    return types;
}

// The feature bits under which a kernel may meet light type `type`.
VKP_FN FeatureMask lightTypeFeature(uint type) {
    switch (type) {
#define VKP_LIGHT_CASE(id, NAME, Type, label, feature, shape, flags) \
    case id:                                                         \
        return feature;
        VKP_LIGHT_TYPES(VKP_LIGHT_CASE)
#undef VKP_LIGHT_CASE
        default:
            return VKP_NO_FEATURES;
    }
}

// The VKP_LIGHT_IS_* flags of light type `type`.
VKP_FN uint lightTypeFlags(uint type) {
    switch (type) {
#define VKP_LIGHT_CASE(id, NAME, Type, label, feature, shape, flags) \
    case id:                                                         \
        return flags;
        VKP_LIGHT_TYPES(VKP_LIGHT_CASE)
#undef VKP_LIGHT_CASE
        default:
            return 0u;
    }
}

// light.type, or the constant type when the kernel meets only one (so a
// switch over it folds to that case).
VKP_FN uint lightType(VKP_IN(Light) light) {
    uint types = possibleLightTypes();
    for (uint type = 0u; type < VKP_LIGHT_TYPE_COUNT; ++type)
        if (types == (1u << type)) return type;
    return light.type;
}

// Whether `light` is of type `type`; known without reading it when the kernel
// meets no light of that type, or no other.
VKP_FN bool lightIs(VKP_IN(Light) light, uint type) {
    uint types = possibleLightTypes();
    if ((types & (1u << type)) == 0u) return false;
    if (types == (1u << type)) return true;
    return light.type == type;
}

VKP_FN LightSample noLightSample() {
    LightSample s;
    s.direction = vec3(0.0f, 0.0f, 1.0f);
    s.distance = 0.0f;
    s.radiance = vec3(0.0f);
    s.pdf = 0.0f;
    s.normal = vec3(0.0f);
    s.delta = false;
    return s;
}

// Spot falloff of KHR_lights_punctual (the extension's recommended
// implementation): (clamp((cos - cosOuter) / (cosInner - cosOuter), 0, 1))^2.
VKP_FN float spotFalloff(VKP_IN(Light) light, float cosAngle) {
    float scale = 1.0f / max(1e-4f, light.cosInner - light.cosOuter);
    float t = clamp((cosAngle - light.cosOuter) * scale, 0.0f, 1.0f);
    return t * t;
}

// Density in solid angle, seen from `p`, of sampling `light` toward a point
// `x` on it with unit normal `n` (area lights only).
VKP_FN float areaLightPdf(VKP_IN(Light) light, vec3 p, vec3 x, vec3 n) {
    vec3 d = x - p;
    float dist2 = dot(d, d);
    if (lightIs(light, VKP_LIGHT_SPHERE)) {
        SphereCone cone = sphereCone(light.p0, light.radius, p);
        if (!cone.inside) return sphereConePdf(cone);
        // From inside: uniform by area over the whole sphere.
        return areaToSolidAnglePdf(4.0f * VKP_PI * light.radius * light.radius, dist2,
                                   dot(n, d) / sqrt(dist2));
    }
    return areaToSolidAnglePdf(light.area, dist2, dot(n, d) / sqrt(dist2));
}

// A sample of a point `x` on an area light of area `area` with unit normal
// `n`, seen from `p` (direction, distance, solid-angle pdf); pdf 0 if x = p.
VKP_FN LightSample areaLightSample(vec3 p, vec3 x, vec3 n, float area) {
    LightSample s = noLightSample();
    vec3 d = x - p;
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return s;
    float dist = sqrt(dist2);
    s.direction = d / dist;
    s.distance = dist;
    s.pdf = areaToSolidAnglePdf(area, dist2, dot(n, s.direction));
    s.normal = n;
    return s;
}

// ---- sampling a light: one function per type ---------------------------------------
// sampleTypeLight(light, p, u) samples a direction from `p` toward `light`;
// `u` uniform in [0, 1)^2.

// A point on the triangle, uniform by area; only its front face emits.
VKP_FN LightSample sampleTriangleLight(VKP_IN(Light) light, vec3 p, vec2 u) {
    vec2 b = sampleTriangleBarycentrics(u);
    vec3 x = b.x * light.p0 + b.y * light.p1 + (1.0f - b.x - b.y) * light.p2;
    vec3 n = light.normal;
    LightSample s = areaLightSample(p, x, n, light.area);
    // Only the front face emits: the point must see it (n points back at p).
    s.radiance = s.pdf > 0.0f && dot(n, s.direction) < 0.0f ? light.emission : vec3(0.0f);
    return s;
}

// From outside, a direction in the sphere's cone, the distance from
// intersecting it with the sphere; from inside, a point uniform by area.
VKP_FN LightSample sampleSphereLight(VKP_IN(Light) light, vec3 p, vec2 u) {
    LightSample s = noLightSample();
    SphereCone cone = sphereCone(light.p0, light.radius, p);
    if (cone.inside) {
        vec3 n = sampleUniformSphere(u);
        s = areaLightSample(p, light.p0 + light.radius * n, n,
                            4.0f * VKP_PI * light.radius * light.radius);
    } else {
        vec3 toCenter = light.p0 - p;
        float centerDistance = length(toCenter);
        s.direction = sampleSphereCone(cone, toCenter / centerDistance, u);
        // Distance to the near surface along the direction; tangent
        // directions (rounding) fall back to the point of closest approach.
        float along = dot(toCenter, s.direction);
        float miss2 = max(0.0f, dot(toCenter, toCenter) - along * along);
        float halfChord = sqrt(max(0.0f, light.radius * light.radius - miss2));
        s.distance = max(0.0f, along - halfChord);
        s.pdf = sphereConePdf(cone);
        s.normal = normalize(p + s.distance * s.direction - light.p0);
    }
    s.radiance = s.pdf > 0.0f ? light.emission : vec3(0.0f);
    return s;
}

// KHR_lights_punctual's window on the inverse square beyond a point or spot
// light's range r (the extension's recommended attenuation, its 1 / d^2
// apart): clamp(1 - (d / r)^4, 0, 1); 1 where the light has none.
VKP_FN float rangeWindow(VKP_IN(Light) light, float distance) {
    if (!hasFeature(VKP_FEATURE_LIGHT_RANGE) || !(light.radius > 0.0f)) return 1.0f;
    float x = distance / light.radius;
    float x2 = x * x;
    return clamp(1.0f - x2 * x2, 0.0f, 1.0f);
}

VKP_FN LightSample samplePointLight(VKP_IN(Light) light, vec3 p, vec2 /*u*/) {
    LightSample s = noLightSample();
    vec3 d = light.p0 - p;
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return s;
    float dist = sqrt(dist2);
    s.direction = d / dist;
    s.distance = dist;
    s.pdf = 1.0f;
    s.delta = true;
    s.radiance = light.emission * (rangeWindow(light, dist) / dist2);
    return s;
}

// A point light within its cone, falling off toward the cone's edge.
VKP_FN LightSample sampleSpotLight(VKP_IN(Light) light, vec3 p, vec2 u) {
    LightSample s = samplePointLight(light, p, u);
    if (s.delta) s.radiance *= spotFalloff(light, dot(-s.direction, light.p1));
    return s;
}

VKP_FN LightSample sampleDirectionalLight(VKP_IN(Light) light, vec3 /*p*/, vec2 /*u*/) {
    LightSample s = noLightSample();
    s.direction = -light.p1;
    s.distance = VKP_FLOAT_MAX;
    s.pdf = 1.0f;
    s.delta = true;
    s.radiance = light.emission;
    return s;
}

// The environment is sampled by the caller, which holds its table.
VKP_FN LightSample sampleEnvironmentLight(VKP_IN(Light) /*light*/, vec3 /*p*/, vec2 /*u*/) {
    return noLightSample();
}

// Samples a direction toward `light` of any type but the environment (see
// above), one switch over the types made from the registry, each case
// guarded by its features.
VKP_FN LightSample sampleLight(VKP_IN(Light) light, vec3 p, vec2 u) {
    uint types = possibleLightTypes();
    switch (lightType(light)) {
#define VKP_LIGHT_CASE(id, NAME, Type, label, feature, shape, flags)               \
    case id:                                                                       \
        if ((types & (1u << (id))) != 0u) return sample##Type##Light(light, p, u); \
        break;
        VKP_LIGHT_TYPES(VKP_LIGHT_CASE)
#undef VKP_LIGHT_CASE
        default:
            break;
    }
    return noLightSample();
}

VKP_NAMESPACE_END

#ifdef __cplusplus
#define VKP_RECORD Light
VKP_RECORD_CHECK(VKP_LIGHT_FIELDS, 5)
#undef VKP_RECORD
#endif

#endif  // VKPATH_SHARED_LIGHTS_H
