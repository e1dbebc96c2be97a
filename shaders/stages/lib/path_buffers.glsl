// The wavefront's per-path state (shared/integrator.h PathState) as
// structure-of-arrays over the wave's path slots, and its load and store.
// The host sizes and binds the same buffers from one table
// (host/wavefront/renderer.cpp, PATH_BUFFERS).
layout(binding = VKP_WF_RAYS, scalar) buffer RayBuffer { Ray rays[]; };
layout(binding = VKP_WF_THROUGHPUT, scalar) buffer ThroughputBuffer { vec3 throughput[]; };
layout(binding = VKP_WF_RADIANCE, scalar) buffer RadianceBuffer { vec3 radiance[]; };
layout(binding = VKP_WF_VERTEX, scalar) buffer VertexBuffer { PathVertex vertices[]; };
layout(binding = VKP_WF_PATH_WAVELENGTH, scalar) buffer WavelengthBuffer { float wavelengths[]; };

PathState loadPath(uint slot) {
    PathState path;
    path.ray = rays[slot];
    path.throughput = throughput[slot];
    path.radiance = radiance[slot];
    PathVertex v = vertices[slot];
    path.previousPosition = v.position;
    path.previousNormal = v.normal;
    path.bsdfPdf = abs(v.bsdfPdf);
    path.afterNonDelta = (floatBitsToUint(v.bsdfPdf) & 0x80000000u) != 0u;
    path.etaScale = abs(v.specularEtaScale);
    path.specular = v.specularEtaScale < 0.0;
    path.wavelength = hasFeature(VKP_FEATURE_DISPERSION) ? wavelengths[slot] : 0.0;
    return path;
}

// Everything but the radiance (stored on its own: shade adds to it even when
// the path ends).
void storePathVertex(uint slot, PathState path) {
    rays[slot] = path.ray;
    throughput[slot] = path.throughput;
    PathVertex v;
    v.position = path.previousPosition;
    v.normal = path.previousNormal;
    v.bsdfPdf = path.afterNonDelta ? -path.bsdfPdf : path.bsdfPdf;  // (-0.0 keeps the sign bit)
    v.specularEtaScale = path.specular ? -path.etaScale : path.etaScale;
    vertices[slot] = v;
    if (hasFeature(VKP_FEATURE_DISPERSION)) wavelengths[slot] = path.wavelength;
}

// The AOVs (SceneInfo::aovs, with VKP_FEATURE_AOVS): set by generate, carried
// and updated by shade (stored whether or not the path goes on: accumulate
// reads the last), left by the megakernel at each path's end.
layout(binding = VKP_WF_PATH_AOV, scalar) buffer PathAovBuffer { PathAov pathAovs[]; };
