// The scene in device memory, in the layouts of shaders/shared/: the BVH,
// materials, the light list with its alias table, the map from emissive leaf
// primitives to lights, and the environment with its sampling table. Only
// what the scene uses takes memory: absent features get one 16-byte texel
// (Vulkan needs every declared binding bound, and most are texel buffers).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bvh/bvh.h"
#include "bvh/gpu_bvh.h"
#include "scene/scene.h"
#include "shared/alias.h"
#include "shared/bvh.h"
#include "shared/lights.h"
#include "shared/material.h"
#include "shared/medium.h"
#include "shared/scene_addresses.h"
#include "shared/scene_arrays.h"
#include "shared/scene_data.h"
#include "vk/buffer.h"
#include "wavefront/alpha_tables.h"
#include "wavefront/light_tree.h"
#include "wavefront/surface_tables.h"
#include "wavefront/texture_tables.h"

namespace vkpath::wavefront {

// SceneTables::materialPrimitives' bits.
constexpr uint8_t MATERIAL_ON_TRIANGLES = 1;
constexpr uint8_t MATERIAL_ON_SPHERES = 2;

// The scene flattened for the integrators, on the host: what the GPU
// buffers hold and what the CPU reference reads directly.
struct SceneTables {
    bvh::BvhBuild bvh;
    std::vector<shared::Material> materials;
    // Per material, the kinds of primitive in the BVH that wear it
    // (MATERIAL_ON_TRIANGLES, MATERIAL_ON_SPHERES): what the kernels'
    // features need to know of the primitives, before the BVH is built.
    std::vector<uint8_t> materialPrimitives;
    std::vector<shared::Light> lights;
    // The alias table over the lights' power; with a light tree, followed by
    // a second part over the tree as a whole and each light after its range
    // (shared/path/light_choice.h).
    std::vector<shared::AliasEntry> lightAlias;
    // Over the bounded lights [0, lightTree.trails.size()) (light types not
    // VKP_LIGHT_IS_INFINITE come first); empty unless two or more have power.
    LightTree lightTree;
    std::vector<uint32_t> primitiveLight;  // per leaf primitive; empty when nothing is emissive
    std::vector<shared::AliasEntry> envAlias;
    std::vector<glm::vec4> envRadiance;  // the map's texels, w 0: one 16-byte texel each
    SurfaceTables surface;   // vertex attributes for shading (empty when the scene is flat)
    TextureTables textures;  // empty when no material has a texture
    // The fog, then the inside of each material (shared/medium.h); empty
    // unless the fog is present or the inside of a transmitting material scatters
    std::vector<shared::Medium> media;
    // The grid medium (render --volume): its record, densities and majorants
    // (shared/medium.h GridMedium); empty without one
    std::vector<shared::GridMedium> gridMedium;
    std::vector<float> gridDensity;
    std::vector<float> gridMajorant;
    std::vector<shared::MaterialAlpha>
        materialAlpha;  // per material; empty unless info.alphaTested
    // shared/microfacet_albedo.h's tables (host/albedo/albedo_tables.h);
    // empty unless a material has a GGX lobe that is not a delta
    // (roughLobes) or a sheen
    std::vector<float> microfacetAlbedo;
    bool roughLobes = false;  // a material has a GGX lobe that is not a delta
    // (centre, radius) of the smooth specular spheres that diffuse samples
    // may be guided toward (shared/path_tracer.h sampleGuidedDiffuse), the
    // largest VKP_MAX_GUIDE_SPHERES of them; empty without emissive surfaces
    // and under an environment map (buildSceneTables says why).
    std::vector<glm::vec4> guideSpheres;
    shared::SceneInfo
        info{};  // settings fields (samples, depth, seed, size) filled by the renderer
    // Everything above is in render space: world space moved so that the
    // centre of the geometry's bounding box is the origin (computed in
    // double), so that float precision follows the scene's size, not its
    // distance from the world origin. `camera` is the scene's camera in render
    // space; worldOrigin is where render space's origin lies in world space.
    scene::Camera camera;
    glm::dvec3 worldOrigin{0.0};
};

// Builds the tables in render space (see SceneTables). Lights: one per emissive non-degenerate
// triangle and sphere, each punctual light, and the environment when present, chosen in proportion
// to their power in luminance: pi x area x L for surfaces (a triangle's front face; a sphere's
// outside), 4 pi I for points, the cone's solid angle x I for spots, and pi R^2 x E (directional)
// or pi R^2 x the integral of L over the sphere (environment), R the radius of a sphere around the
// geometry.
// The BVH is built last: `beforeBvh`, when given, is called with the tables
// complete but for `bvh` and `primitiveLight` (the renderer starts on its
// pipelines while the BVH builds).
SceneTables buildSceneTables(const scene::Scene& scene, const bvh::BvhOptions& bvhOptions = {},
                             const std::function<void(const SceneTables&)>& beforeBvh = {});

// Puts `world` (a camera in world space) in place of the tables' camera,
// moved into render space as buildSceneTables moves the scene's.
void placeCamera(SceneTables& tables, const scene::Camera& world);

struct GpuScene {
    bvh::GpuBvh bvh;
    // One buffer per row of shaders/shared/scene_arrays.h (materials, lights,
    // lightAlias, ...), named after it.
#define VKP_SCENE_BUFFER(index, name, Record, access, member) vk::Buffer name;
    VKP_SCENE_ARRAYS(VKP_SCENE_BUFFER)
#undef VKP_SCENE_BUFFER
    // Whether the stage kernels read the BVH and the SPANS arrays by address,
    // through `addresses` (shared/scene_addresses.h); then each of their
    // bindings gets bvh.placeholder. Pipelines take it as
    // bvh::sceneAccessConstant(byAddress).
    bool byAddress = false;
    vk::Buffer addresses;  // SceneAddresses, zeros unless byAddress (always bound)

    // What to bind in place of `array`: itself, or the placeholder when the
    // kernels read it by address.
    const vk::Buffer& binding(const vk::Buffer& array) const {
        return byAddress ? bvh.placeholder : array;
    }
    // Device memory of the scene's arrays (not counting placeholders).
    uint64_t bytes() const;
    // What the stage kernels bind, by binding index: every scene array (a
    // placeholder for those read by address), the BVH's two and the addresses.
    std::vector<std::pair<uint32_t, const vk::Buffer*>> bindings() const;
};

// Device memory the tables take once uploaded (GpuScene::bytes of their upload).
uint64_t deviceBytes(const SceneTables& tables);

// Uploads the tables. The arrays are read by address when any of them is
// larger than one binding may span (vk::bufferLimits: 16 x the device's
// maxTexelBufferElements, or VKPATH_MAX_BINDING_BYTES when lower);
// throws InputError, naming the array, when one is larger than a buffer may be.
// With bvh::Traversal::RayQuery the device's acceleration structures are built
// too (InputError where it has no ray queries).
GpuScene uploadScene(vk::Context& context, const SceneTables& tables,
                     bvh::Traversal traversal = bvh::Traversal::Compute);

// One line for the render summary: the scene's device memory, the BVH's part
// of it, and how the kernels read it, e.g. "scene: 12.3 MiB on the device
// (BVH: 1234 nodes (38.6 KiB) + ...), bound as texel buffers".
std::string describeMemory(const GpuScene& scene, const SceneTables& tables);

// Frees what uploadScene copied to the device and the host need not keep:
// the BVH's arrays and every row of shaders/shared/scene_arrays.h that grows
// with the scene (SPANS), most of a large scene's host memory. The rest
// (materials, settings, the BVH's statistics) stays.
void releaseUploaded(SceneTables& tables);

}  // namespace vkpath::wavefront
