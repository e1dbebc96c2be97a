// The scene model every other part consumes: world-space triangle meshes and
// analytic spheres, materials, punctual lights, a camera and an optional
// environment, plus an exact summary of the features the scene uses.
//
// Conventions (docs/SCENES.md): right-handed, +Y up, metres; radiance in
// linear RGB W/(m^2 sr) with no photometric conversion (a glTF candela is
// taken as W/sr, a lux as W/m^2).
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/ext/vector_uint4_sized.hpp>
#include <glm/glm.hpp>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"
#include "scene/volume_grid.h"
#include "shared/material.h"

namespace vkpath::scene {

// The material kinds: one per row of the registry
// (shaders/shared/material_kinds.h, which says what each is), with the
// kernels' numbers (VKP_MATERIAL_*).
enum class MaterialKind : uint32_t {
#define VKP_KIND_ENUMERATOR(id, NAME, Type, key, label, feature, flags, regularized) Type = id,
    VKP_MATERIAL_KINDS(VKP_KIND_ENUMERATOR)
#undef VKP_KIND_ENUMERATOR
};

// A kind's row of the registry, as the host reads it.
struct MaterialKindInfo {
    MaterialKind kind;
    const char* key;           // scene-info's JSON key and FeatureSummary's field
    const char* label;         // its name in scene-info's text and the kernels' feature list
    uint64_t feature;          // VKP_FEATURE_* (shaders/shared/features.h)
    uint32_t flags;            // VKP_KIND_*
    MaterialKind regularized;  // the kind path regularisation turns it into
};

inline constexpr MaterialKindInfo MATERIAL_KINDS[] = {
#define VKP_KIND_INFO(id, NAME, Type, key, label, feature, flags, regularized) \
    {MaterialKind::Type, #key, label, feature, flags, MaterialKind(VKP_MATERIAL_##regularized)},
    VKP_MATERIAL_KINDS(VKP_KIND_INFO)
#undef VKP_KIND_INFO
};
static_assert(std::size(MATERIAL_KINDS) == VKP_MATERIAL_KIND_COUNT);

// The row of `kind` (rows are in the order of their numbers:
// tests/kernels/material_registry_test.cpp).
inline const MaterialKindInfo& materialKindInfo(MaterialKind kind) {
    return MATERIAL_KINDS[uint32_t(kind)];
}

// How a material's alpha covers its surface (glTF 2.0 section 3.9.4 "Alpha
// Coverage", material.alphaMode); the same numbers as VKP_ALPHA_*
// (shaders/shared/alpha.h).
enum class AlphaMode : uint32_t {
    Opaque = 0,  // alpha is ignored
    Mask = 1,    // a point is there where its alpha >= alphaCutoff, else a hole
    Blend = 2,   // a point is there with probability alpha (stochastic transparency)
};

// How a texture is read outside [0, 1] (glTF sampler wrapS / wrapT); the
// same numbers as VKP_WRAP_* (shaders/shared/texture.h).
enum class TextureWrap : uint32_t { Repeat = 0, ClampToEdge = 1, MirroredRepeat = 2 };

// An image as decoded from its file: RGBA, 16-bit normalised, rows top to
// bottom (the first row is v = 0 in glTF's texture coordinates), values as
// stored (no colour decoding: each use says whether they are sRGB).
struct TextureImage {
    std::string name;
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<glm::u16vec4> texels;  // width x height, row-major
};

// A glTF texture: an image and how it is sampled.
struct Texture {
    uint32_t image = 0;  // index into Scene::images
    TextureWrap wrapU = TextureWrap::Repeat;
    TextureWrap wrapV = TextureWrap::Repeat;
    bool nearest = false;  // nearest texel, else bilinear (glTF's magFilter)
};

// A material's use of a texture (glTF textureInfo with KHR_texture_transform):
// uv' = offset + R(rotation) S(scale) uv, read at texture coordinate set
// `texCoord`. `texture` < 0: none.
struct TextureRef {
    int32_t texture = -1;   // index into Scene::textures
    uint32_t texCoord = 0;  // TEXCOORD_n
    glm::vec2 offset{0.0f};
    float rotation = 0.0f;  // radians, counter-clockwise in uv as KHR_texture_transform defines it
    glm::vec2 scale{1.0f};

    bool present() const { return texture >= 0; }
};

struct Material {
    std::string name;
    MaterialKind kind = MaterialKind::Diffuse;
    glm::vec3 reflectance{0.8f};    // albedo (diffuse), specular tint (mirror, glass), F0
                                    // (conductor), base colour (metallic-roughness)
    glm::vec3 transmittance{1.0f};  // glass, rough glass: tint of refracted light
    float ior =
        1.5f;  // glass, rough glass, metallic-roughness: index of refraction inside / outside
    glm::vec3 emission{0.0f};  // emitted radiance, W/(m^2 sr); > 0 makes the surface an area light
    // The microfacet kinds (Conductor, RoughDielectric, MetallicRoughness):
    float roughness = 0.0f;  // glTF's perceptual roughness in [0, 1]; GGX alpha = roughness^2
    float metallic = 0.0f;   // MetallicRoughness: metalness in [0, 1]
    float specular = 1.0f;   // MetallicRoughness: KHR_materials_specular specularFactor, in [0, 1]
    glm::vec3 specularColor{1.0f};  // MetallicRoughness: KHR_materials_specular specularColorFactor
    // Conductor: a complex index of refraction eta + i k per channel, relative
    // to the outside; eta all 0 (the default): Schlick's Fresnel with F0 = reflectance.
    glm::vec3 conductorEta{0.0f};
    glm::vec3 conductorK{0.0f};
    // Dielectric, RoughDielectric: the inside's attenuation coefficient per
    // metre (KHR_materials_volume: -ln(attenuationColor) / attenuationDistance),
    // light crossing a distance d inside keeps exp(-attenuation d); 0: clear.
    // The share scatteringAlbedo of it scatters (KHR_materials_volume_scatter's
    // single-scattering albedo), the rest absorbs.
    glm::vec3 attenuation{0.0f};
    glm::vec3 scatteringAlbedo{0.0f};  // in [0, 1]; 0: the inside only absorbs
    // Dielectric, RoughDielectric: a thin wall with air on both sides (glTF's
    // transmission without KHR_materials_volume), no inside and no attenuation
    bool thinWalled = false;
    float scatterAnisotropy = 0.0f;  // the inside's Henyey-Greenstein g, in (-1, 1)
    // Dielectric, RoughDielectric with an inside: KHR_materials_dispersion's
    // 20 / Abbe number (0: the index is the same at every wavelength)
    float dispersion = 0.0f;
    // MetallicRoughness: the layers over it (shaders/shared/metallic_roughness.h).
    // KHR_materials_clearcoat: the coat's weight in [0, 1] (0: none) and roughness;
    // KHR_materials_sheen: the sheen's colour (0: none) and roughness.
    float clearcoat = 0.0f;
    float clearcoatRoughness = 0.0f;
    glm::vec3 sheenColor{0.0f};
    float sheenRoughness = 0.0f;
    // KHR_materials_diffuse_transmission: the share of the diffuse lobe that
    // passes to the back (0: none) and its colour.
    float diffuseTransmission = 0.0f;
    glm::vec3 diffuseTransmissionColor{1.0f};
    // KHR_materials_iridescence: the thin film's weight (0: none), index and
    // thickness range in nm (the maximum without a thickness texture)
    float iridescence = 0.0f;
    float iridescenceIor = 1.3f;
    float iridescenceThicknessMinimum = 100.0f;
    float iridescenceThicknessMaximum = 400.0f;
    // KHR_materials_anisotropy (conductor, rough glass, metallic-roughness):
    // the strength (0: isotropic) and the direction's rotation from the
    // tangent, counter-clockwise in radians
    float anisotropy = 0.0f;
    float anisotropyRotation = 0.0f;
    // Textures (glTF): the base colour multiplies `reflectance` (or a glass's
    // `transmittance`, which the base colour tints), the emissive texture
    // `emission`; both are sRGB-encoded. The others hold linear data.
    TextureRef baseColorTexture;
    TextureRef emissiveTexture;
    TextureRef metallicRoughnessTexture;    // G: roughness, B: metalness
    TextureRef normalTexture;               // tangent-space normals
    float normalScale = 1.0f;               // glTF normalTexture.scale: scales the map's x and y
    TextureRef clearcoatTexture;            // R: multiplies clearcoat
    TextureRef clearcoatRoughnessTexture;   // G: multiplies clearcoatRoughness
    TextureRef clearcoatNormalTexture;      // the coat's own normal map, as normalTexture's
    float clearcoatNormalScale = 1.0f;      // ... and its scale
    TextureRef sheenColorTexture;           // RGB (sRGB): multiplies sheenColor
    TextureRef sheenRoughnessTexture;       // A: multiplies sheenRoughness
    TextureRef diffuseTransmissionTexture;  // A: multiplies diffuseTransmission
    TextureRef diffuseTransmissionColorTexture;  // RGB (sRGB): multiplies its colour
    TextureRef iridescenceTexture;               // R: multiplies iridescence
    TextureRef iridescenceThicknessTexture;      // G: picks the thickness between min and max
    TextureRef anisotropyTexture;  // RG: direction in the tangent frame (2 x - 1), B: strength
    // Alpha (glTF): a point's alpha is `alpha` x the base-colour texture's
    // alpha x COLOR_0's alpha. Spheres are opaque whatever the mode.
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;  // Mask only
    float alpha = 1.0f;        // baseColorFactor[3]

    bool emissive() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;  // world space
    std::vector<glm::vec3>
        normals;  // world space shading normals, per vertex; empty: use face normals
    std::vector<glm::vec2> texcoords0;  // TEXCOORD_0 per vertex, glTF's convention ((0, 0) the
                                        // image's top left); empty: none
    std::vector<glm::vec2> texcoords1;  // TEXCOORD_1 per vertex; empty: none
    std::vector<glm::vec4> colors;      // COLOR_0 per vertex, linear RGBA; empty: none (white)
    std::vector<glm::vec4> tangents;    // TANGENT per vertex: world space unit xyz, w = +-1 so that
                                        // the bitangent is w (normal x tangent); empty: none
    std::vector<glm::uvec3>
        triangles;          // indices into positions, counter-clockwise seen from the front
    uint32_t material = 0;  // index into Scene::materials
    // In object space and drawn only where Scene::instances place it (its
    // positions, normals and tangents are then the object's, not the world's).
    bool instanced = false;
};

// A placement of instanced meshes (glTF: a node whose mesh other nodes also
// place): the meshes [firstMesh, firstMesh + meshCount) of Scene::meshes, all
// `instanced`, drawn under `objectToWorld`. Instances of the same range share
// one copy of its triangles and one bottom-level tree (shaders/shared/bvh.h).
// Emissive meshes are never instanced (their triangles are lights, sampled
// in world space).
struct Instance {
    std::string name;
    uint32_t firstMesh = 0;
    uint32_t meshCount = 0;
    glm::dmat4 objectToWorld{1.0};
};

struct Sphere {
    std::string name;
    glm::vec3 center{0.0f};  // world space
    float radius = 1.0f;
    uint32_t material = 0;
};

struct PointLight {
    glm::vec3 position{0.0f};
    glm::vec3 intensity{0.0f};  // W/sr, falls off with the inverse square of distance
    // > 0: KHR_lights_punctual's range, beyond which the light reaches
    // nothing (its falloff windowed: shared/lights.h rangeWindow); 0: none
    float range = 0.0f;
};

struct SpotLight {
    glm::vec3 position{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  // unit, where the cone points
    glm::vec3 intensity{0.0f};               // W/sr on the axis
    float innerConeAngle = 0.0f;             // radians: full intensity inside
    float outerConeAngle = 0.7853982f;       // radians: zero outside, smooth in between
    float range = 0.0f;                      // as PointLight::range
};

struct DirectionalLight {
    glm::vec3 direction{0.0f, -1.0f, 0.0f};  // unit, the direction the light travels
    glm::vec3 irradiance{0.0f};              // W/m^2 on a surface facing the light
};

// Equirectangular environment: +Y is up; u = 0 at the -Z direction... see
// docs/SCENES.md for the exact mapping. A constant colour when no map is given.
struct Environment {
    std::optional<image::Image> map;  // linear RGB radiance
    glm::vec3 color{0.0f};            // constant radiance when there is no map
    float strength = 1.0f;            // multiplies map or colour
    float rotationDegrees = 0.0f;     // about +Y
};

struct Camera {
    std::string name;
    glm::vec3 position{0.0f};
    glm::vec3 target{0.0f, 0.0f, -1.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float xfovDegrees = 60.0f;  // horizontal field of view of the camera's own aspect
    float aspect = 0.0f;        // the camera's own width / height, 0 when the file gives none
};

// What a scene uses: kernels are specialised to this (later issues), so it
// must be exact: a flag is set if and only if the feature is present.
struct FeatureSummary {
    bool triangles = false;
    bool spheres = false;
    // One per material kind, named by its registry key (diffuse, mirror, glass, ...).
#define VKP_KIND_FIELD(id, NAME, Type, key, label, feature, flags, regularized) bool key = false;
    VKP_MATERIAL_KINDS(VKP_KIND_FIELD)
#undef VKP_KIND_FIELD
    bool emissiveSurfaces = false;
    bool pointLights = false;
    bool spotLights = false;
    bool directionalLights = false;
    bool environment = false;
};

// How much geometry a scene holds, as its meshes and spheres will be once
// loaded: what the size of its tables is estimated from
// (wavefront/scene_footprint.h). The importers count it from the file before
// they build any mesh (LoadOptions::admit), so that a scene too large for the
// machine is refused before its memory is spent; countGeometry counts a
// loaded scene.
struct GeometryCounts {
    uint64_t triangles = 0;
    uint64_t vertices = 0;
    // Vertices that carry each per-vertex attribute (a mesh's vertices, for
    // each mesh that has it); texture coordinates count once for both sets.
    uint64_t normals = 0;
    uint64_t texcoords = 0;
    uint64_t colors = 0;
    uint64_t tangents = 0;
    uint64_t spheres = 0;
    uint64_t instances = 0;  // placements of instanced meshes (counted once above)

    GeometryCounts& operator+=(const GeometryCounts& o) {
        triangles += o.triangles;
        vertices += o.vertices;
        normals += o.normals;
        texcoords += o.texcoords;
        colors += o.colors;
        tangents += o.tangents;
        spheres += o.spheres;
        instances += o.instances;
        return *this;
    }
};

// An axis-aligned box, world space.
struct Bounds {
    glm::vec3 lo, hi;
};

// A homogeneous participating medium, coefficients per metre
// (docs/SCENES.md, "Media").
struct Medium {
    glm::vec3 scattering{0.0f};  // sigma_s
    glm::vec3 absorption{0.0f};  // sigma_a
    float anisotropy = 0.0f;     // Henyey-Greenstein g, in (-1, 1): > 0 forward
    bool present() const { return scattering != glm::vec3(0.0f) || absorption != glm::vec3(0.0f); }
};

struct Scene {
    std::vector<Material> materials;
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;  // where the `instanced` meshes are drawn
    std::vector<Sphere> spheres;
    std::vector<TextureImage> images;
    std::vector<Texture> textures;
    std::vector<PointLight> pointLights;
    std::vector<SpotLight> spotLights;
    std::vector<DirectionalLight> directionalLights;
    std::optional<Environment> environment;
    // Fills the space outside the bodies of transmitting materials (render
    // --fog-density); absent: clear.
    Medium fog;
    // A heterogeneous medium in the same space, besides the fog (render --volume)
    std::optional<VolumeGrid> volume;
    Camera camera;
    // The files the scene file refers to that its loader read (glTF buffers,
    // images, an environment map), in the order read: with the scene file,
    // what a render's identity hashes (app::renderIdentity).
    std::vector<std::filesystem::path> referencedFiles;
    // The material variants the file declares (glTF's KHR_materials_variants;
    // LoadOptions::materialVariant chooses one)
    std::vector<std::string> materialVariants;

    FeatureSummary features() const;
    // Triangles stored: an instanced mesh's once.
    size_t triangleCount() const;
    // Triangles drawn: an instanced mesh's once per instance.
    uint64_t drawnTriangleCount() const;
    GeometryCounts countGeometry() const;
    // The box around the triangles of the meshes and the spheres (lo > hi
    // when there are none): what the importers frame a default camera on.
    Bounds geometryBounds() const;
};

}  // namespace vkpath::scene
