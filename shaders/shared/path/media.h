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
    // With media: VKP_EVENT_IN_MEDIUM at a scattering event in medium
    // `medium` (an index of the media array, shared/medium.h),
    // VKP_EVENT_IN_GRID at one in the grid medium (which lies in the fog:
    // `medium` is the fog's), 0 at a surface, where `medium` is the one behind
    // its front face: a transmitting material's inside, else the fog.
    uint inMedium;
    uint medium;
};

#define VKP_EVENT_IN_MEDIUM 1u
#define VKP_EVENT_IN_GRID 2u

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
    // (a thin wall has the fog on both sides)
    return materialTransmits(material) && !materialThinWalled(material) ? 1u + materialIndex
                                                                        : VKP_FOG_MEDIUM;
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

// ---- the grid medium (render --volume) ------------------------------------------------
// A heterogeneous medium in the fog's space (outside the bodies of
// transmitting materials), besides the fog: free flights through it by delta
// tracking and shadow rays' transmittance by ratio tracking (Woodcock et al.
// 1965; Novak et al., "Residual ratio tracking", 2014; the null-scattering
// view of Miller et al. 2019 that pbrt-v4's volumetric path tracer takes,
// section 14.2), each against the majorant of the cell of the coarse grid
// the ray is in, walked cell by cell (Amanatides and Woo, 1987), so thin
// parts of a grid cost as little as they weigh. Their random numbers come
// from a stream of their own per bounce and light sample (gridRngKey), as
// many as they need.

// Whether the scene has a grid medium, a constant false in kernels without one.
VKP_FN bool gridMediumOn() VKP_SCENE_CONST {
    return hasFeature(VKP_FEATURE_GRID_MEDIUM) && sceneInfo().gridMedium != 0u;
}

// Draws past which a track gives up (a ray through more than 2^19 majorant
// mean free paths of one grid): free flight passes on, transmittance is 0.
#define VKP_GRID_MAX_DRAWS 1048576u

// The stream of the grid's numbers for bounce `bounce`: stream 0 for its
// free flight, 1 + j for light sample j's shadow ray.
VKP_FN RngKey gridRngKey(RngKey key, uint bounce, uint stream) VKP_SCENE_CONST {
    uint seed = pcg4d(uvec4(key.seed, bounce, stream, 0x67726964u)).x;  // "grid"
    return makeRngKey(key.pixel, key.sampleIndex, seed);
}

// The grid's density (before densityScale) at `u` in its index space:
// trilinear between voxel centres, 0 outside them.
VKP_FN float gridDensityAt(VKP_IN(GridMedium) g, vec3 u) VKP_SCENE_CONST {
    vec3 f = floor(u);
    if (f.x < 0.0f || f.y < 0.0f || f.z < 0.0f || f.x + 1.0f >= float(g.resolution.x) ||
        f.y + 1.0f >= float(g.resolution.y) || f.z + 1.0f >= float(g.resolution.z))
        return 0.0f;
    vec3 w = u - f;
    uint sy = g.resolution.x, sz = g.resolution.x * g.resolution.y;
    uint i = uint(f.x) + uint(f.y) * sy + uint(f.z) * sz;
    float x00 = mix(sceneGridDensity(i), sceneGridDensity(i + 1u), w.x);
    float x10 = mix(sceneGridDensity(i + sy), sceneGridDensity(i + sy + 1u), w.x);
    float x01 = mix(sceneGridDensity(i + sz), sceneGridDensity(i + sz + 1u), w.x);
    float x11 = mix(sceneGridDensity(i + sy + sz), sceneGridDensity(i + sy + sz + 1u), w.x);
    return mix(mix(x00, x10, w.y), mix(x01, x11, w.y), w.z);
}

// A ray's walk through the majorant cells, in the grid's index space (t is
// the ray's own parameter: world distance).
struct GridWalk {
    vec3 origin;
    vec3 direction;
    ivec3 cell;
    ivec3 step;   // +-1 per axis, 0 where the ray is parallel to it
    vec3 tNext;   // where the ray crosses into the next cell along each axis
    vec3 tDelta;  // the distance across one cell along each axis
    float t;      // where the walk is
    float tEnd;   // where it ends: the grid's box or the segment's end
};

// The walk of `ray` over [0, tEnd] within the grid's box; false when the
// ray misses the box there.
VKP_FN bool gridWalkStart(VKP_IN(GridMedium) g, VKP_IN(Ray) ray, float tEnd,
                          VKP_OUT(GridWalk) w) VKP_SCENE_CONST {
    w.origin = (ray.origin - g.origin) * g.inverseVoxelSize;
    w.direction = ray.direction * g.inverseVoxelSize;
    vec3 hi = vec3(g.resolution) - vec3(1.0f);
    float t0 = 0.0f, t1 = tEnd;
    for (int axis = 0; axis < 3; ++axis) {
        float o = w.origin[axis], d = w.direction[axis];
        if (d == 0.0f) {
            if (o < 0.0f || o > hi[axis]) return false;
        } else {
            float ta = -o / d, tb = (hi[axis] - o) / d;
            t0 = max(t0, min(ta, tb));
            t1 = min(t1, max(ta, tb));
        }
    }
    if (!(t0 < t1)) return false;
    w.t = t0;
    w.tEnd = t1;
    float m = float(g.majorantCell);
    vec3 u = w.origin + t0 * w.direction;
    ivec3 last = ivec3(g.majorantResolution) - ivec3(1);
    w.cell = clamp(ivec3(floor(u / m)), ivec3(0), last);
    for (int axis = 0; axis < 3; ++axis) {
        float o = w.origin[axis], d = w.direction[axis];
        int c = w.cell[axis];
        w.step[axis] = d > 0.0f ? 1 : d < 0.0f ? -1 : 0;
        w.tNext[axis] = d > 0.0f   ? (float(c + 1) * m - o) / d
                        : d < 0.0f ? (float(c) * m - o) / d
                                   : VKP_FLOAT_MAX;
        w.tDelta[axis] = d != 0.0f ? m / abs(d) : VKP_FLOAT_MAX;
    }
    return true;
}

// Where the walk leaves its cell (or ends).
VKP_FN float gridCellExit(VKP_IN(GridWalk) w) VKP_SCENE_CONST {
    return min(min(w.tNext.x, w.tNext.y), min(w.tNext.z, w.tEnd));
}

// The majorant of the walk's cell, sigma_t's bound there.
VKP_FN float gridCellMajorant(VKP_IN(GridMedium) g, VKP_IN(GridWalk) w) VKP_SCENE_CONST {
    uvec3 c = uvec3(w.cell);
    return g.densityScale *
           sceneGridMajorant(c.x + g.majorantResolution.x * (c.y + g.majorantResolution.y * c.z));
}

// Into the next cell; false when the walk has ended.
VKP_FN bool gridWalkNext(VKP_INOUT(GridWalk) w, VKP_IN(GridMedium) g) VKP_SCENE_CONST {
    float exit = gridCellExit(w);
    if (exit >= w.tEnd) return false;
    w.t = exit;
    int axis = w.tNext.x <= w.tNext.y && w.tNext.x <= w.tNext.z ? 0
               : w.tNext.y <= w.tNext.z                         ? 1
                                                                : 2;
    w.cell[axis] += w.step[axis];
    w.tNext[axis] += w.tDelta[axis];
    return w.cell[axis] >= 0 && w.cell[axis] < int(g.majorantResolution[axis]);
}

// The first real collision with the grid along `ray` before tEnd (delta
// tracking), at `t`; false if the ray gets through.
VKP_FN bool gridCollision(VKP_IN(GridMedium) g, VKP_IN(Ray) ray, float tEnd, RngKey key,
                          VKP_OUT(float) t) VKP_SCENE_CONST {
    t = tEnd;
    GridWalk w;
    if (!gridWalkStart(g, ray, tEnd, w)) return false;
    uint draws = 0u;
    do {
        float majorant = gridCellMajorant(g, w);
        if (!(majorant > 0.0f)) continue;
        float exit = gridCellExit(w);
        float s = w.t;
        while (draws < VKP_GRID_MAX_DRAWS) {
            s -= log(1.0f - rngUniform(key, draws)) / majorant;
            if (s >= exit) break;
            float sigma = g.densityScale * gridDensityAt(g, w.origin + s * w.direction);
            if (rngUniform(key, draws + 1u) * majorant < sigma) {
                t = s;
                return true;
            }
            draws += 2u;
        }
        draws += 1u;
    } while (gridWalkNext(w, g));
    return false;
}

// The grid's transmittance along `ray` over [0, tEnd], estimated by ratio
// tracking (unbiased; Russian roulette below 0.1 keeps long tracks short).
VKP_FN float gridTransmittance(VKP_IN(GridMedium) g, VKP_IN(Ray) ray, float tEnd,
                               RngKey key) VKP_SCENE_CONST {
    GridWalk w;
    if (!gridWalkStart(g, ray, tEnd, w)) return 1.0f;
    float transmittance = 1.0f;
    uint draws = 0u;
    do {
        float majorant = gridCellMajorant(g, w);
        if (!(majorant > 0.0f)) continue;
        float exit = gridCellExit(w);
        float s = w.t;
        for (;;) {
            if (draws >= VKP_GRID_MAX_DRAWS) return 0.0f;
            s -= log(1.0f - rngUniform(key, draws)) / majorant;
            draws += 1u;
            if (s >= exit) break;
            float sigma = g.densityScale * gridDensityAt(g, w.origin + s * w.direction);
            transmittance *= max(0.0f, 1.0f - sigma / majorant);
            if (transmittance < 0.1f) {
                if (rngUniform(key, draws) >= 0.5f) return 0.0f;
                transmittance *= 2.0f;
                draws += 1u;
            }
        }
    } while (gridWalkNext(w, g));
    return transmittance;
}

// The Henyey-Greenstein g of the medium an event lies in.
VKP_FN float eventAnisotropy(VKP_IN(Shading) shading) VKP_SCENE_CONST {
    if (hasFeature(VKP_FEATURE_GRID_MEDIUM) && shading.inMedium == VKP_EVENT_IN_GRID)
        return sceneGridMedium().anisotropy;
    return sceneMedium(shading.medium).anisotropy;
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
    bool homogeneous = mediumPresent(m);
    bool grid = gridMediumOn() && index == VKP_FOG_MEDIUM;
    if (!homogeneous && !grid) return false;
    FreeFlight flight;
    flight.scattered = false;
    flight.t = tEnd;
    flight.weight = vec3(1.0f);
    if (homogeneous)
        flight = sampleFreeFlight(m, tEnd,
                                  rngUniform2(key, bounceDimension(bounce) + VKP_DIM_FREE_FLIGHT));
    uint event = VKP_EVENT_IN_MEDIUM;
    if (grid) {
        // The fog's and the grid's first events race (the first of two
        // independent processes is that of their sum): the grid's, tracked
        // up to the fog's, wins when it comes first, and the fog's weight is
        // then that of passing to it. At the grid's event the path keeps the
        // share albedo of sigma_t that scatters.
        GridMedium g = sceneGridMedium();
        float t;
        if (gridCollision(g, path.ray, flight.t, gridRngKey(key, bounce, 0u), t)) {
            flight.weight = homogeneous ? freeFlightPassWeight(m, t) : vec3(1.0f);
            flight.weight *= g.albedo;
            flight.scattered = true;
            flight.t = t;
            event = VKP_EVENT_IN_GRID;
        }
    }
    path.throughput *= flight.weight;
    if (!flight.scattered) return false;
    shading.inMedium = event;
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

// The transmittance of light sample `lightSample`'s shadow ray of length
// `distance` (VKP_FLT_MAX: to a light at infinity) leaving `shading` along
// `direction` at bounce `bounce`: exact for a homogeneous medium, estimated
// for the grid's.
VKP_FN vec3 shadowTransmittance(VKP_IN(Shading) shading, vec3 direction, float distance, RngKey key,
                                uint bounce, uint lightSample) VKP_SCENE_CONST {
    uint index = mediumToward(shading, direction);
    vec3 transmittance = mediumTransmittanceAlong(sceneMedium(index), distance);
    if (gridMediumOn() && index == VKP_FOG_MEDIUM && transmittance != vec3(0.0f)) {
        Ray ray;
        ray.origin = shading.surface.position;
        ray.direction = direction;
        ray.tMax = distance;
        ray.pixel = key.pixel;
        transmittance *= gridTransmittance(sceneGridMedium(), ray, distance,
                                           gridRngKey(key, bounce, 1u + lightSample));
    }
    return transmittance;
}
