// Diffuse samples guided toward smooth specular spheres: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

// ---- diffuse samples guided toward smooth specular spheres ------------------------------
// Light that reaches a diffuse surface from a small emitter through a mirror
// or glass sphere (a caustic) is found by BSDF samples only: a light sample
// cannot aim through a delta lobe. Cosine sampling rarely hits the emitter's
// image in the sphere, and each hit is a firefly: on CBspheres a few pixels
// hold most of the error (docs/TRADEOFFS.md, "Light samples"). So a
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
    if (!hasFeature(VKP_FEATURE_SPHERE_GUIDING) || !materialIs(material, VKP_MATERIAL_DIFFUSE))
        return g;
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
VKP_FN BsdfSample sampleGuidedDiffuse(VKP_IN(Material) material, VKP_IN(SurfacePoint) surface,
                                      vec3 wo, GuideSpheres g, vec2 u, float uc) VKP_SCENE_CONST {
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
VKP_FN float scatterPdf(VKP_IN(Material) material, VKP_IN(SurfacePoint) surface, vec3 wo,
                        GuideSpheres guide, vec3 wi) VKP_SCENE_CONST {
    float pdf = bsdfPdf(material, surface.normal, surface.shadingNormal, wo, wi);
    if (guide.count == 0u || pdf == 0.0f) return pdf;
    return guidedDiffusePdf(surface.position, faceForward(surface.shadingNormal, wo), wi, guide);
}
