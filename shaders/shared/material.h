// Materials as the kernels see them: one record per scene material.
#ifndef VKPATH_SHARED_MATERIAL_H
#define VKPATH_SHARED_MATERIAL_H

#include "shared/compat.h"

// Values of Material::kind; the same numbers as scene::MaterialKind.
#define VKP_MATERIAL_DIFFUSE 0u
#define VKP_MATERIAL_MIRROR 1u
#define VKP_MATERIAL_DIELECTRIC 2u

VKP_NAMESPACE_BEGIN

struct Material {
    vec3 reflectance;    // diffuse albedo, or the specular tint of mirror and glass reflection
    uint kind;           // VKP_MATERIAL_*
    vec3 transmittance;  // glass: tint of refracted light
    float ior;           // glass: index of refraction of the inside relative to the outside
    vec3 emission;       // emitted radiance, W/(m^2 sr), from the front face
};

VKP_NAMESPACE_END

#ifdef __cplusplus
static_assert(sizeof(vkpath::shared::Material) == 44);
#endif

#endif  // VKPATH_SHARED_MATERIAL_H
