// The scene's buffers and the accessors shared/path_tracer.h reads them
// through, then the path tracer itself (shade stage only).
#include "shared/bsdf.h"
#include "shared/lights.h"
#include "shared/material.h"
#include "shared/rng.h"
#include "shared/scene_data.h"

#define VKP_BVH_NODES_BINDING VKP_WF_BVH_NODES
#define VKP_BVH_PRIMITIVES_BINDING VKP_WF_BVH_PRIMITIVES
#include "shared/bvh_buffers.h"

layout(binding = VKP_WF_SCENE_INFO, scalar) readonly buffer SceneInfoBuffer { SceneInfo sceneInfoData; };
layout(binding = VKP_WF_MATERIALS, scalar) readonly buffer MaterialBuffer { Material materials[]; };
layout(binding = VKP_WF_LIGHTS, scalar) readonly buffer LightBuffer { Light lights[]; };
layout(binding = VKP_WF_LIGHT_ALIAS, scalar) readonly buffer LightAliasBuffer { AliasEntry lightAlias[]; };
layout(binding = VKP_WF_PRIMITIVE_LIGHT, scalar) readonly buffer PrimitiveLightBuffer { uint primitiveLight[]; };
layout(binding = VKP_WF_ENV_ALIAS, scalar) readonly buffer EnvAliasBuffer { AliasEntry envAlias[]; };
layout(binding = VKP_WF_ENV_RADIANCE, scalar) readonly buffer EnvRadianceBuffer { vec3 envRadiance[]; };

SceneInfo sceneInfo() { return sceneInfoData; }
Material sceneMaterial(uint i) { return materials[i]; }
Light sceneLight(uint i) { return lights[i]; }
AliasEntry sceneLightAlias(uint i) { return lightAlias[i]; }
uint scenePrimitiveLight(uint i) { return primitiveLight[i]; }
AliasEntry sceneEnvAlias(uint i) { return envAlias[i]; }
vec3 sceneEnvRadiance(uint i) { return envRadiance[i]; }

#include "shared/path_tracer.h"
