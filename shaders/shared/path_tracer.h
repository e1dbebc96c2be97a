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
//   TriangleVertices sceneTriangleVertices(uint triangle);  // by BvhPrimitive::id (shared/mesh_attributes.h)
//   vec3 sceneVertexNormal(uint vertex);
//   vec4 sceneVertexTexcoords(uint vertex);         // (TEXCOORD_0, TEXCOORD_1)
//   vec4 sceneVertexColor(uint vertex);
//   vec4 sceneVertexTangent(uint vertex);           // unit xyz, w = +-1: B = w (N x T)
//   TextureInfo sceneTexture(uint index);           // shared/texture.h
//   TextureSlot sceneTextureSlot(uint index);
//   vec4 sceneTexel(uint index);                    // linear RGBA
//   MaterialAlpha sceneMaterialAlpha(uint index);   // shared/alpha.h; read only when SceneInfo::alphaTested
//
// It defines the alpha test that shared/bvh_traverse.h asks (bvhAlphaTest).
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
// paired with the lobe choice of the materials that choose between lobes
// with a number of their own (sampleBsdf's uc) and with the component of a
// guided Lambertian vertex's mixture (sampleGuidedDiffuse), which no other
// material draws, so adding them changed no other material's numbers.
#define VKP_DIMS_PER_BOUNCE_BASE 4u  // BSDF direction (2), Russian roulette (1), lobe or component choice (1)
#define VKP_DIMS_PER_LIGHT_SAMPLE 4u  // environment texel (2 words), light choice and position (2)

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

// ---- textures and vertex colours --------------------------------------------------------

VKP_FN vec4 textureTexel(TextureInfo texture, int i, int j) VKP_SCENE_CONST {
    return sceneTexel(texture.firstTexel + uint(j) * texture.width + uint(i));
}

// The texture's value at uv (shared/texture.h has the conventions).
VKP_FN vec4 textureLookup(TextureInfo texture, vec2 uv) VKP_SCENE_CONST {
    int w = int(texture.width), h = int(texture.height);
    uint wrapU = texture.sampling & 3u, wrapV = (texture.sampling >> 2u) & 3u;
    float x = uv.x * float(w), y = uv.y * float(h);
    if ((texture.sampling & VKP_TEXTURE_NEAREST) != 0u)
        return textureTexel(texture, wrapTexelIndex(floorToInt(x), w, wrapU),
                            wrapTexelIndex(floorToInt(y), h, wrapV));
    // Bilinear: the four texels whose centres surround (x, y).
    x -= 0.5f;
    y -= 0.5f;
    int i = floorToInt(x), j = floorToInt(y);
    float fx = x - float(i), fy = y - float(j);
    int i0 = wrapTexelIndex(i, w, wrapU), i1 = wrapTexelIndex(i + 1, w, wrapU);
    int j0 = wrapTexelIndex(j, h, wrapV), j1 = wrapTexelIndex(j + 1, h, wrapV);
    vec4 top = exactMix(textureTexel(texture, i0, j0), textureTexel(texture, i1, j0), fx);
    vec4 bottom = exactMix(textureTexel(texture, i0, j1), textureTexel(texture, i1, j1), fx);
    return exactMix(top, bottom, fy);
}

// The value of texture slot `slot` at texture coordinates `texcoords`
// (TEXCOORD_0, TEXCOORD_1); 1 for an empty slot.
VKP_FN vec4 textureSlotValue(uint slot, vec4 texcoords) VKP_SCENE_CONST {
    TextureSlot s = sceneTextureSlot(slot);
    if (s.texture == VKP_NO_TEXTURE) return vec4(1.0f);
    vec3 uv1 = s.texCoord == 0u ? vec3(texcoords.x, texcoords.y, 1.0f) : vec3(texcoords.z, texcoords.w, 1.0f);
    return textureLookup(sceneTexture(s.texture), vec2(dot(s.transformU, uv1), dot(s.transformV, uv1)));
}

// `material` as it is at a hit on `primitive`: its base colour times the
// base-colour texture and the vertex colour (glTF 2.0 section 3.9.2; a
// glass's base colour tints its transmission, scene::Material), its
// emission times the emissive texture, its roughness and metalness times the
// metallic-roughness texture. Spheres have no texture coordinates.
VKP_FN Material materialAt(Material material, VKP_IN(BvhPrimitive) primitive, Hit hit) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_TEXTURES | VKP_FEATURE_VERTEX_COLORS) || isSphere(primitive)) return material;
    bool textured = hasFeature(VKP_FEATURE_TEXTURES) && material.textures != VKP_NO_TEXTURE;
    uint attributes = sceneInfo().triangleAttributes & (VKP_TRIANGLE_TEXCOORDS | VKP_TRIANGLE_COLORS);
    if (!textured && (!hasFeature(VKP_FEATURE_VERTEX_COLORS) || attributes == 0u)) return material;
    vec4 base = vec4(1.0f);
    vec4 texcoords = vec4(0.0f);
    if (attributes != 0u) {
        TriangleVertices triangle = sceneTriangleVertices(primitive.id);
        float b1 = hit.barycentrics.x, b2 = hit.barycentrics.y, b0 = 1.0f - b1 - b2;
        uvec3 v = triangle.vertex;
        if (textured && (triangle.attributes & VKP_TRIANGLE_TEXCOORDS) != 0u)
            texcoords = b0 * sceneVertexTexcoords(v.x) + b1 * sceneVertexTexcoords(v.y) +
                        b2 * sceneVertexTexcoords(v.z);
        if (hasFeature(VKP_FEATURE_VERTEX_COLORS) && (triangle.attributes & VKP_TRIANGLE_COLORS) != 0u)
            base = b0 * sceneVertexColor(v.x) + b1 * sceneVertexColor(v.y) + b2 * sceneVertexColor(v.z);
    }
    if (textured) {
        base *= textureSlotValue(material.textures + VKP_SLOT_BASE_COLOR, texcoords);
        if (material.emission != vec3(0.0f))
            material.emission *= vec3(textureSlotValue(material.textures + VKP_SLOT_EMISSIVE, texcoords));
        // glTF 2.0 section 3.9.2: roughness in G, metalness in B, each
        // multiplying its factor (an empty slot is 1).
        if (hasFeature(VKP_FEATURES_MICROFACET)) {
            vec4 metallicRoughness = textureSlotValue(material.textures + VKP_SLOT_METALLIC_ROUGHNESS, texcoords);
            material.roughness *= metallicRoughness.y;
            material.metallic *= metallicRoughness.z;
        }
    }
    if (materialIs(material, VKP_MATERIAL_DIELECTRIC) || materialIs(material, VKP_MATERIAL_ROUGH_DIELECTRIC))
        material.transmittance *= vec3(base);
    else if (!materialIs(material, VKP_MATERIAL_CONDUCTOR) || (material.flags & VKP_MATERIAL_COMPLEX_FRESNEL) == 0u)
        material.reflectance *= vec3(base);  // (a complex index is no colour)
    return material;
}

// ---- shading normals ------------------------------------------------------------------

// The normal map's normal at barycentrics (b1, b2) of `triangle`, whose
// material has a normal map and whose vertices have tangents; `n` is the
// normal it perturbs (interpolated or geometric, unit). glTF 2.0, section
// 3.9.3 (normalTexture): the texel's RGB is a tangent-space normal
// 2 x - 1, its x and y scaled by normalTexture.scale, in the frame of the
// tangent T (interpolated, made orthogonal to n: Gram-Schmidt), the
// bitangent B = w (n x T) (section 3.7.2.1; +Y up the image, since T and w
// were made for glTF's v-down coordinates) and n. `n` itself where the
// frame or the map's normal is degenerate.
VKP_FN vec3 normalMapNormal(VKP_IN(Material) material, VKP_IN(TriangleVertices) triangle, float b1,
                            float b2, vec3 n) VKP_SCENE_CONST {
    TextureSlot slot = sceneTextureSlot(material.textures + VKP_SLOT_NORMAL);
    if (slot.texture == VKP_NO_TEXTURE) return n;
    float b0 = 1.0f - b1 - b2;
    uvec3 v = triangle.vertex;
    vec4 texcoords = b0 * sceneVertexTexcoords(v.x) + b1 * sceneVertexTexcoords(v.y) + b2 * sceneVertexTexcoords(v.z);
    vec3 mapped = 2.0f * vec3(textureSlotValue(material.textures + VKP_SLOT_NORMAL, texcoords)) - 1.0f;
    vec4 tangent = b0 * sceneVertexTangent(v.x) + b1 * sceneVertexTangent(v.y) + b2 * sceneVertexTangent(v.z);
    vec3 t = vec3(tangent) - dot(n, vec3(tangent)) * n;
    float t2 = dot(t, t);
    if (!(t2 > 1e-12f)) return n;
    t /= sqrt(t2);
    vec3 b = (tangent.w < 0.0f ? -1.0f : 1.0f) * exactCross(n, t);
    vec3 world = (slot.scale * mapped.x) * t + (slot.scale * mapped.y) * b + mapped.z * n;
    float length2 = dot(world, world);
    if (!(length2 > 1e-12f)) return n;
    return world / sqrt(length2);
}

// The normal the BSDF uses at a hit on `primitive` whose geometric normal is
// `geometric`, seen from wo: the triangle's vertex normals interpolated with
// the hit's barycentrics (Phong's interpolation: glTF's NORMAL attribute,
// Scotty3D's smooth meshes), or the geometric normal, perturbed by the
// material's normal map where it has one, then adapted to wo
// (shared/bsdf.h); the geometric normal itself for spheres and for flat
// triangles without a normal map.
VKP_FN vec3 shadingNormal(VKP_IN(Material) material, VKP_IN(BvhPrimitive) primitive, Hit hit,
                          vec3 geometric, vec3 wo) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_SHADING_NORMALS | VKP_FEATURE_NORMAL_MAPS) || isSphere(primitive)) return geometric;
    if ((sceneInfo().triangleAttributes & (VKP_TRIANGLE_SHADING_NORMALS | VKP_TRIANGLE_TANGENTS)) == 0u)
        return geometric;
    TriangleVertices triangle = sceneTriangleVertices(primitive.id);
    bool mapped = hasFeature(VKP_FEATURE_NORMAL_MAPS) && (triangle.attributes & VKP_TRIANGLE_TANGENTS) != 0u;
    bool interpolated =
        hasFeature(VKP_FEATURE_SHADING_NORMALS) && (triangle.attributes & VKP_TRIANGLE_SHADING_NORMALS) != 0u;
    if (!mapped && !interpolated) return geometric;
    float b1 = hit.barycentrics.x, b2 = hit.barycentrics.y;
    vec3 n = geometric;
    if (interpolated) {
        vec3 sum = (1.0f - b1 - b2) * sceneVertexNormal(triangle.vertex.x) + b1 * sceneVertexNormal(triangle.vertex.y) +
                   b2 * sceneVertexNormal(triangle.vertex.z);
        float length2 = dot(sum, sum);
        if (length2 > 1e-12f)
            n = sum / sqrt(length2);
        else if (!mapped)
            return geometric;  // vertex normals that cancel out
    }
    if (mapped) n = normalMapNormal(material, triangle, b1, b2, n);
    return adaptShadingNormal(geometric, n, wo);
}

// ---- alpha coverage: the traversal's test (shared/alpha.h) -------------------------------

// The alpha of a material with record `material` at barycentrics `b` of
// triangle `triangle` (BvhPrimitive::id): its factor x the base-colour
// texture's alpha x COLOR_0's alpha, interpolated as materialAt interpolates
// the base colour.
VKP_FN float surfaceAlpha(MaterialAlpha material, uint triangle, vec2 b) VKP_SCENE_CONST {
    float alpha = material.alpha;
    bool textured = hasFeature(VKP_FEATURE_TEXTURES) && material.baseColorSlot != VKP_NO_TEXTURE;
    uint attributes = sceneInfo().triangleAttributes & (VKP_TRIANGLE_TEXCOORDS | VKP_TRIANGLE_COLORS);
    if (!textured && (!hasFeature(VKP_FEATURE_VERTEX_COLORS) || attributes == 0u)) return alpha;
    vec4 texcoords = vec4(0.0f);
    if (attributes != 0u) {
        TriangleVertices vertices = sceneTriangleVertices(triangle);
        float b0 = 1.0f - b.x - b.y;
        uvec3 v = vertices.vertex;
        if (textured && (vertices.attributes & VKP_TRIANGLE_TEXCOORDS) != 0u)
            texcoords = b0 * sceneVertexTexcoords(v.x) + b.x * sceneVertexTexcoords(v.y) +
                        b.y * sceneVertexTexcoords(v.z);
        if (hasFeature(VKP_FEATURE_VERTEX_COLORS) && (vertices.attributes & VKP_TRIANGLE_COLORS) != 0u)
            alpha *= b0 * sceneVertexColor(v.x).w + b.x * sceneVertexColor(v.y).w + b.y * sceneVertexColor(v.z).w;
    }
    if (textured) alpha *= textureSlotValue(material.baseColorSlot, texcoords).w;
    return alpha;
}

// Whether a candidate hit at barycentrics `b` of `triangle` stands for the
// ray of alpha key `alphaKey` (shared/bvh_traverse.h asks; shared/alpha.h).
VKP_FN bool bvhAlphaTest(VKP_IN(BvhPrimitive) triangle, vec2 b, uint alphaKey) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_ALPHA) || sceneInfo().alphaTested == 0u) return true;
    MaterialAlpha material = sceneMaterialAlpha(triangle.material);
    if (material.mode == VKP_ALPHA_OPAQUE) return true;
    return alphaCovers(material, surfaceAlpha(material, triangle.id, b), alphaKey, triangle.id);
}

// The alpha key of ray `ray` (alphaClosestRay, alphaShadowRay) of the path
// of `key`; 0 where nothing is alpha-tested (it is then never read).
VKP_FN uint pathAlphaKey(RngKey key, uint ray) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_ALPHA) || sceneInfo().alphaTested == 0u) return 0u;
    return alphaRayKey(key, ray);
}

// ---- absorption inside glass ------------------------------------------------------------

// What is left of light that crossed the inside of `material` to reach
// `surface` from behind along `ray` (Beer-Lambert: exp(-attenuation d)), 1
// for a hit from the front or on a clear material. A ray that meets a glass
// surface from behind travelled inside that glass, as long as glass bodies
// are closed and do not overlap or nest (docs/SCENES.md).
VKP_FN vec3 mediumTransmittance(VKP_IN(Material) material, VKP_IN(SurfacePoint) surface,
                                VKP_IN(Ray) ray, Hit hit) VKP_SCENE_CONST {
    bool glass = materialIs(material, VKP_MATERIAL_DIELECTRIC) || materialIs(material, VKP_MATERIAL_ROUGH_DIELECTRIC);
    if (!glass || material.attenuation == vec3(0.0f) || dot(ray.direction, surface.normal) <= 0.0f) return vec3(1.0f);
    return exp(-material.attenuation * hit.t);  // (ray.direction is unit)
}

// ---- diffuse samples guided toward smooth specular spheres ------------------------------
// Light that reaches a diffuse surface from a small emitter through a mirror
// or glass sphere (a caustic) is found by BSDF samples only: a light sample
// cannot aim through a delta lobe. Cosine sampling rarely hits the emitter's
// image in the sphere, and each hit is a firefly: on CBspheres the top 5% of
// pixels held 84% of the relMSE at 64 spp (docs/BENCHMARKS.md). So a
// Lambertian vertex that sees guide spheres (SceneInfo::guideSphereCount:
// the smooth specular spheres, listed where emissive surfaces can be seen
// through them, host/wavefront/gpu_scene.cpp) draws its direction from a
// one-sample mixture (Veach's thesis, 1997, section 9.2.4; Hesterberg's
// defensive mixtures, 1995): with probability 1 - guideFraction the cosine
// lobe, else uniformly in the cone subtended by one of its candidate spheres
// (chosen uniformly; shared/sampling.h sampleSphereCone). The sample's
// weight and its MIS with light samples both use the mixture's density, so
// the estimator stays unbiased for any sphere list and fraction; only its
// variance depends on them (--guide-spheres, docs/TRADEOFFS.md).

// The guide spheres a vertex may sample toward: bit k of `mask` for sphere k.
struct GuideSpheres {
    uint mask;
    uint count;
};

// The candidates of a vertex on `material`: none unless it is Lambertian and
// the kernel guides; else the spheres it is outside of that reach above its
// tangent plane (their centre lies less than a radius below it).
VKP_FN GuideSpheres guideSpheresAt(VKP_IN(Material) material, VKP_IN(SurfacePoint) surface,
                                   vec3 wo) VKP_SCENE_CONST {
    GuideSpheres g;
    g.mask = 0u;
    g.count = 0u;
    if (!hasFeature(VKP_FEATURE_SPHERE_GUIDING) || !materialIs(material, VKP_MATERIAL_DIFFUSE)) return g;
    vec3 n = faceForward(surface.shadingNormal, wo);
    uint total = sceneInfo().guideSphereCount;
    for (uint k = 0u; k < total; ++k) {
        vec4 sphere = sceneGuideSphere(k);
        vec3 d = vec3(sphere) - surface.position;
        if (dot(d, d) > sphere.w * sphere.w && dot(d, n) > -sphere.w) {
            g.mask |= 1u << k;
            g.count += 1u;
        }
    }
    return g;
}

// The mixture's density of the unit direction wi at `p` (normal n faced
// toward wo) with candidates g (count > 0). wi lies in the cone of the
// sphere at distance-vector d exactly when dot(wi, d) >= |d| cos theta_max
// = sqrt(|d|^2 - r^2): tested squared, so only the cones that hold wi (few,
// for a light sample's direction) cost a square root.
VKP_FN float guidedDiffusePdf(vec3 p, vec3 n, vec3 wi, GuideSpheres g) VKP_SCENE_CONST {
    float cones = 0.0f;
    uint total = sceneInfo().guideSphereCount;
    for (uint k = 0u; k < total; ++k) {
        if ((g.mask & (1u << k)) == 0u) continue;
        vec4 sphere = sceneGuideSphere(k);
        vec3 d = vec3(sphere) - p;
        float along = dot(wi, d);
        if (along > 0.0f && along * along >= dot(d, d) - sphere.w * sphere.w)
            cones += sphereConePdf(sphereCone(vec3(sphere), sphere.w, p));
    }
    float fraction = sceneInfo().guideFraction;
    return (1.0f - fraction) * cosineHemispherePdf(dot(n, wi)) + fraction * cones / float(g.count);
}

// Index of the (pick + 1)-th set bit of mask (pick < bitCount(mask)).
VKP_FN uint nthSetBit(uint mask, uint pick) VKP_SCENE_CONST {
    uint k = 0u;
    for (; k < 31u; ++k) {
        if ((mask & (1u << k)) == 0u) continue;
        if (pick == 0u) break;
        pick -= 1u;
    }
    return k;
}

// A direction from the mixture at a Lambertian vertex with candidates g
// (count > 0): u picks the direction, uc the component (and the sphere).
VKP_FN BsdfSample sampleGuidedDiffuse(VKP_IN(Material) material, VKP_IN(SurfacePoint) surface, vec3 wo,
                                      GuideSpheres g, vec2 u, float uc) VKP_SCENE_CONST {
    vec3 n = faceForward(surface.shadingNormal, wo);
    float fraction = sceneInfo().guideFraction;
    vec3 wi;
    if (uc < fraction) {
        uint pick = min(uint(uc / fraction * float(g.count)), g.count - 1u);
        vec4 sphere = sceneGuideSphere(nthSetBit(g.mask, pick));
        SphereCone cone = sphereCone(vec3(sphere), sphere.w, surface.position);
        wi = normalize(sampleSphereCone(cone, normalize(vec3(sphere) - surface.position), u));
    } else {
        wi = normalize(frameToWorld(makeFrame(n), sampleCosineHemisphere(u)));
    }
    BsdfSample s = invalidBsdfSample();
    // f is zero below the horizon (a cone sample may fall there): the path ends.
    vec3 f = evalBsdf(material, surface.normal, surface.shadingNormal, wo, wi);
    float pdf = guidedDiffusePdf(surface.position, n, wi, g);
    if (f == vec3(0.0f) || !(pdf > 0.0f)) return s;
    s.direction = wi;
    s.pdf = pdf;
    s.weight = f / pdf;
    s.valid = true;
    return s;
}

// The density with which continuePath draws wi at this vertex (guide: its
// guideSpheresAt): the BSDF's, or the guided mixture's. Light samples weigh
// themselves against it.
VKP_FN float scatterPdf(VKP_IN(Material) material, VKP_IN(SurfacePoint) surface, vec3 wo, GuideSpheres guide,
                        vec3 wi) VKP_SCENE_CONST {
    float pdf = bsdfPdf(material, surface.normal, surface.shadingNormal, wo, wi);
    if (guide.count == 0u || pdf == 0.0f) return pdf;
    return guidedDiffusePdf(surface.position, faceForward(surface.shadingNormal, wo), wi, guide);
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

// Emission at a hit: `surface` on `primitive`, leaf primitive `index`,
// reached along `direction` from `previous` (the last vertex) by a ray of
// BSDF density `bsdfPdf`. Triangles emit from their front face only.
VKP_FN vec3 emittedRadiance(VKP_IN(Material) material, VKP_IN(BvhPrimitive) primitive, uint index,
                            VKP_IN(SurfacePoint) surface, vec3 direction, vec3 previous, bool specular,
                            float bsdfPdf) VKP_SCENE_CONST {
    if (!hasFeature(VKP_FEATURE_EMISSIVE_SURFACES)) return vec3(0.0f);
    vec3 le = material.emission;
    if (!isSphere(primitive) && dot(direction, surface.normal) >= 0.0f) return vec3(0.0f);
    SceneInfo info = sceneInfo();
    if (le == vec3(0.0f) || specular || lightSampleCount() == 0u || info.lightCount == 0u) return le;
    uint lightIndex = scenePrimitiveLight(index);
    if (lightIndex == VKP_NO_LIGHT) return le;
    Light light = sceneLight(lightIndex);
    float lightPdf = sceneLightAlias(lightIndex).probability * areaLightPdf(light, previous, surface.position, surface.normal);
    return le * bsdfMisWeight(bsdfPdf, lightPdf);
}

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
    return bounce + 1u == info.maxDepth && lightSampleCount() > 0u && info.unsampledEmitters == 0u &&
           materialIs(material, VKP_MATERIAL_DIFFUSE);
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

// Light sample `index` (of lightSamples) at a diffuse vertex whose guide
// spheres (guideSpheresAt) are `guide`.
VKP_FN ShadowRequest sampleDirectLight(VKP_IN(Material) material, VKP_IN(SurfacePoint) surface,
                                       vec3 wo, GuideSpheres guide, vec3 throughput, RngKey key, uint bounce,
                                       uint index) VKP_SCENE_CONST {
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
    // One pair picks the light and the point on it: its first word chooses
    // the light and, rescaled, is the point's first coordinate
    // (aliasSampleReusing), so the pair's stratification carries over to the
    // points on each light.
    uvec2 pointBits = rngBits2(key, dim + 2u);
    uint bucket = aliasBucket(pointBits.x, info.lightCount);
    AliasChoice lightChoice =
        aliasSampleReusing(sceneLightAlias(bucket), bucket, aliasBucketFraction(pointBits.x, info.lightCount));
    uint lightIndex = lightChoice.element;
    float choice = sceneLightAlias(lightIndex).probability;
    Light light = sceneLight(lightIndex);
    // A light of tiny probability gets its first coordinate from the
    // independent sampler at the same dimension (its stratification is moot:
    // it is chosen once in 2^16 samples or less often).
    RngKey independentKey = makeRngKey(key.pixel, key.sampleIndex, key.seed);
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
        ls = sampleLight(light, surface.position, u);
    }
    if (!(ls.pdf > 0.0f)) {
        request.rejected = true;
        return request;
    }
    if (ls.radiance == vec3(0.0f)) return request;

    vec3 f = evalBsdf(material, surface.normal, surface.shadingNormal, wo, ls.direction);
    if (f == vec3(0.0f)) return request;
    float n = float(lightSampleCount());
    float lightPdf = choice * ls.pdf;
    float weight = ls.delta || lightSamplingAlone(material, bounce)
                       ? 1.0f
                       : powerHeuristic(n * lightPdf, scatterPdf(material, surface, wo, guide, ls.direction));
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

// The next bounce from a vertex whose guide spheres (guideSpheresAt) are `guide`.
VKP_FN PathStep continuePath(VKP_IN(Material) material, VKP_IN(SurfacePoint) surface, vec3 wo,
                             GuideSpheres guide, vec3 throughput, float etaScale, RngKey key,
                             uint bounce) VKP_SCENE_CONST {
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

    if (lightSamplingAlone(material, bounce)) return step;
    uint dim = bounceDimension(bounce);
    // A guided Lambertian vertex draws its mixture's component where a
    // material with lobes draws its lobe (no Lambertian does).
    float lobeChoice = bsdfNeedsLobeChoice(material) || guide.count > 0u ? rngUniform(key, dim + 3u) : 0.0f;
    BsdfSample s = guide.count > 0u
                       ? sampleGuidedDiffuse(material, surface, wo, guide, rngUniform2(key, dim), lobeChoice)
                       : sampleBsdf(material, surface.normal, surface.shadingNormal, wo, rngUniform2(key, dim),
                                    lobeChoice);
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
