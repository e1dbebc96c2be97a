// Ray/box, ray/triangle and ray/sphere intersection, and spawning secondary
// rays off a surface: the math under BVH traversal (shared/bvh_traverse.h),
// the same on GPU and CPU.
//
// Hit-or-miss decisions use only +, - and *, which Vulkan requires to be
// correctly rounded (division and sqrt may be off by ulps on a GPU), so the
// CPU and a GPU decide identically; `precise` (VKP_PRECISE) keeps GLSL
// compilers from fusing those operations into FMAs or reassociating them. The
// C++ side is built with -ffp-contract=off (CMakeLists.txt), so that no
// compiler fuses them on a CPU with FMA either.
//
// Ray interval: a ray is the segment origin + t * direction, 0 <= t < tMax
// (shared/ray.h). t = 0 is included, so a ray that starts exactly on a surface
// may report that surface at t = 0; secondary rays must leave a surface
// through spawnRay / offsetRayOrigin below, never from the bare hit point.
#ifndef VKPATH_SHARED_INTERSECT_H
#define VKPATH_SHARED_INTERSECT_H

#include "shared/bvh.h"
#include "shared/compat.h"
#include "shared/precise_math.h"
#include "shared/ray.h"

#define VKP_FLT_MAX 3.402823466e+38f

// Box distances are widened by this factor (1 + 2^-19, about 32 float ulps):
// the slab distances carry the rounding of a subtraction, a reciprocal (up to
// 2.5 ulp on Vulkan devices) and a multiplication, so an exact test could
// reject a box that the ray grazes (Ize, "Robust BVH Ray Traversal", JCGT
// 2(2), 2013, widens by 1 + 2 gamma(3) for a correctly rounded reciprocal).
#define VKP_BOX_SLACK 1.0000019073486328125f

// Offsets of spawned ray origins (see offsetRayOrigin). Waechter and Binder
// use 256 ulps, sized for hit points computed as origin + t * direction,
// whose error grows with the ray's length. vkpath recomputes hit points from
// the primitive (surfacePoint: vertex 0 plus barycentric multiples of exact
// edge vectors, or a sphere's centre plus its radius), which are within about
// one ulp of their coordinates of the true surface, and the intersection
// tests work in coordinates relative to the ray origin, so a few ulps
// suffice: 8. At 1e5 from the origin an ulp is 8 mm, and 256 of them (2 m)
// would throw a bounced ray clean out of a half-metre room. The fixed offset
// of 2^-16 within 2^-5 of zero keeps the chapter's values.
#define VKP_SPAWN_ULPS 8.0f
#define VKP_SPAWN_NEAR_ZERO 0.03125f
#define VKP_SPAWN_ABSOLUTE 1.52587890625e-05f

VKP_NAMESPACE_BEGIN

// ---------------------------------------------------------------------------
// Ray/box: the slab test on boxes whose bounds the builder rounded outward.
// ---------------------------------------------------------------------------

// 1 / direction per axis, with (near-)zero components mapped to FLT_MAX
// instead of infinity: (bound - origin) * inverse is then never 0 * inf = NaN.
// A zero product means the origin lies exactly on a slab plane; the builder
// pads every box so no geometry lies on its planes, so whichever way that
// plane is counted, no hit is lost.
VKP_FN vec3 safeInverse(vec3 d) {
    vec3 result;
    result.x = abs(d.x) >= 1e-30f ? 1.0f / d.x : VKP_FLT_MAX;
    result.y = abs(d.y) >= 1e-30f ? 1.0f / d.y : VKP_FLT_MAX;
    result.z = abs(d.z) >= 1e-30f ? 1.0f / d.z : VKP_FLT_MAX;
    return result;
}

// Whether the ray meets the box before or at tLimit; `entry` is where it
// enters (0 when the origin is inside). Conservative: widened by
// VKP_BOX_SLACK. "At" keeps a box that may hold a hit tied with the current
// one (shared/bvh_leaf.h), even at distance 0.
VKP_FN bool intersectBox(vec3 boundsMin, vec3 boundsMax, vec3 origin, vec3 inverseDirection,
                         float tLimit, VKP_OUT(float) entry) {
    vec3 t0 = (boundsMin - origin) * inverseDirection;
    vec3 t1 = (boundsMax - origin) * inverseDirection;
    vec3 tNear = min(t0, t1);
    vec3 tFar = max(t0, t1);
    entry = max(max(tNear.x, tNear.y), max(tNear.z, 0.0f));
    float exit = min(min(tFar.x, tFar.y), tFar.z) * VKP_BOX_SLACK;
    return entry <= exit && entry <= tLimit * VKP_BOX_SLACK;
}

// ---------------------------------------------------------------------------
// Ray/triangle: Woop, Benthin and Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013.
//
// The vertices are moved into a frame where the ray is the +z axis (a
// permutation that makes z the dominant direction axis, then a shear), and the
// three 2-D edge functions decide the hit. A vertex shared by two triangles is
// transformed to the same bits in both, and the edge functions of a shared
// edge are then exact negations of each other, so a ray through an edge or a
// vertex of a closed mesh hits at least one of the triangles around it.
//
// One change from the paper: the shear multiplies by d_z instead of dividing
// by it (every sheared coordinate is d_z times the paper's), so the decision
// needs no division, whose rounding may differ between CPU and GPU. The edge
// functions scale by d_z^2 > 0, which keeps their signs.
//
// Where an edge function rounds to exactly zero the paper recomputes it in
// double precision; we do the same. The products of two floats are exact in
// double, so the sign is exact. This needs shaderFloat64 (lavapipe and
// desktop GPUs have it; vk::Context enables it where present).
// ---------------------------------------------------------------------------

// What the triangle test needs of a ray, computed once per ray.
struct TriangleRay {
    vec3 origin;
    uint kx;  // the permutation: kz is the axis of the largest |direction| component,
    uint ky;  // kx and ky the two others in cyclic order
    uint kz;
    vec3 direction;  // permuted: (d[kx], d[ky], d[kz])
};

VKP_FN vec3 permuteAxes(vec3 v, uint kx, uint ky, uint kz) {
    return vec3(v[kx], v[ky], v[kz]);
}

VKP_FN TriangleRay makeTriangleRay(vec3 origin, vec3 direction) {
    TriangleRay ray;
    vec3 a = abs(direction);
    ray.kz = a.x >= a.y ? (a.x >= a.z ? 0u : 2u) : (a.y >= a.z ? 1u : 2u);
    ray.kx = ray.kz == 2u ? 0u : ray.kz + 1u;
    ray.ky = ray.kx == 2u ? 0u : ray.kx + 1u;
    ray.origin = origin;
    ray.direction = permuteAxes(direction, ray.kx, ray.ky, ray.kz);
    return ray;
}

// A hit with 0 <= t < tMax; `barycentrics` are the weights of p1 and p2.
// A ray lying in a triangle's plane never hits it (the projected triangle has
// zero area, det == 0). Zero-area triangles never reach this test: the
// builder leaves them out (bvh::isDegenerateTriangle).
VKP_FN bool intersectTriangle(VKP_IN(TriangleRay) ray, vec3 p0, vec3 p1, vec3 p2, float tMax,
                              VKP_OUT(float) tHit, VKP_OUT(vec2) barycentrics) {
    // Vertices relative to the origin, in the permuted axes.
    VKP_PRECISE vec3 a = permuteAxes(p0 - ray.origin, ray.kx, ray.ky, ray.kz);
    VKP_PRECISE vec3 b = permuteAxes(p1 - ray.origin, ray.kx, ray.ky, ray.kz);
    VKP_PRECISE vec3 c = permuteAxes(p2 - ray.origin, ray.kx, ray.ky, ray.kz);
    float dx = ray.direction.x, dy = ray.direction.y, dz = ray.direction.z;

    // Shear (scaled by d_z) so the ray runs along z through the 2-D origin.
    VKP_PRECISE float ax = dz * a.x - dx * a.z;
    VKP_PRECISE float ay = dz * a.y - dy * a.z;
    VKP_PRECISE float bx = dz * b.x - dx * b.z;
    VKP_PRECISE float by = dz * b.y - dy * b.z;
    VKP_PRECISE float cx = dz * c.x - dx * c.z;
    VKP_PRECISE float cy = dz * c.y - dy * c.z;

    // Edge functions: twice the signed areas of the sub-triangles (origin, edge).
    VKP_PRECISE float u = cx * by - cy * bx;
    VKP_PRECISE float v = ax * cy - ay * cx;
    VKP_PRECISE float w = bx * ay - by * ax;
    bool negative = u < 0.0f || v < 0.0f || w < 0.0f;
    bool positive = u > 0.0f || v > 0.0f || w > 0.0f;
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        VKP_PRECISE double u64 = double(cx) * double(by) - double(cy) * double(bx);
        VKP_PRECISE double v64 = double(ax) * double(cy) - double(ay) * double(cx);
        VKP_PRECISE double w64 = double(bx) * double(ay) - double(by) * double(ax);
        negative = u64 < 0.0 || v64 < 0.0 || w64 < 0.0;
        positive = u64 > 0.0 || v64 > 0.0 || w64 > 0.0;
        u = float(u64);
        v = float(v64);
        w = float(w64);
    }
    // No back-face culling: the origin must be inside for either winding.
    if (negative && positive) return false;
    VKP_PRECISE float det = u + v + w;
    if (det == 0.0f) return false;

    // Distance: the paper's t = (U A_z + V B_z + W C_z) / det with A_z = a_z / d_z;
    // our u, v, w and det are d_z^2 times the paper's, hence the extra d_z.
    VKP_PRECISE float scaledT = u * a.z + v * b.z + w * c.z;
    VKP_PRECISE float t = scaledT / (dz * det);
    if (!(t >= 0.0f && t < tMax)) return false;
    float inverseDet = 1.0f / det;
    tHit = t;
    barycentrics = vec2(v * inverseDet, w * inverseDet);
    return true;
}

// ---------------------------------------------------------------------------
// Ray/sphere: Haines, Guenther and Akenine-Moeller, "Precision Improvements
// for Ray/Sphere Intersection", Ray Tracing Gems, chapter 7, 2019.
//
// The textbook discriminant b^2 - 4ac subtracts two numbers of the size of the
// squared distance to the centre, which leaves nothing of a small or distant
// sphere. The chapter instead measures the ray's closest approach to the
// centre, l = f - (f.d / d.d) d with f = origin - centre, and uses
// r^2 - |l|^2; the roots then come from the numerically stable pair
// t = c / q, q / a. We scale l by a = d.d (a l = a f - (f.d) d) so the
// decision needs no division; the sign of the discriminant is unchanged.
// ---------------------------------------------------------------------------

// The nearest root with 0 <= t < tMax.
VKP_FN bool intersectSphere(vec3 origin, vec3 direction, vec3 center, float radius, float tMax,
                            VKP_OUT(float) tHit) {
    VKP_PRECISE vec3 f = origin - center;
    VKP_PRECISE float a = exactDot(direction, direction);
    VKP_PRECISE float b = -exactDot(f, direction);           // -b/2 in the textbook's notation
    VKP_PRECISE vec3 scaledClosest = a * f + b * direction;  // a l: the closest approach times a
    VKP_PRECISE float scaledRadius = a * radius;
    VKP_PRECISE float discriminant =
        scaledRadius * scaledRadius - exactDot(scaledClosest, scaledClosest);
    if (discriminant < 0.0f) return false;  // = a^2 (r^2 - |l|^2)

    VKP_PRECISE float c = exactDot(f, f) - radius * radius;
    float q = b + (b >= 0.0f ? sqrt(discriminant / a) : -sqrt(discriminant / a));
    if (q == 0.0f) return false;  // tangent exactly at the origin
    float t0 = c / q;
    float t1 = q / a;
    float tNear = min(t0, t1);
    float tFar = max(t0, t1);
    if (tNear >= 0.0f && tNear < tMax) {
        tHit = tNear;
        return true;
    }
    if (tFar >= 0.0f && tFar < tMax) {
        tHit = tFar;
        return true;
    }
    return false;
}

// ---------------------------------------------------------------------------
// Spawning rays off a surface: Waechter and Binder, "A Fast and Robust Method
// for Avoiding Self-Intersection", Ray Tracing Gems, chapter 6, 2019.
//
// A hit point computed in floating point lies off the true surface by a few
// ulps of the coordinates it was computed from. Rather than a fixed epsilon
// (too small far from the origin, too large near it), the origin moves along
// the geometric normal by a number of ulps of each coordinate, done as an
// integer add on the float's bits. Near zero the ulps become tiny while the
// error stays that of the larger inputs, so there a fixed offset is used.
//
// The chapter's constants assume inputs of magnitude ~1. We scale the
// near-zero threshold and the fixed offset by `magnitude`, the largest
// absolute coordinate the point was computed from (SurfacePoint::magnitude),
// so a scene behaves the same at any scale.
// ---------------------------------------------------------------------------

VKP_FN float offsetCoordinate(float p, float n, float nearZero, float absoluteOffset) {
    if (abs(p) < nearZero) return p + absoluteOffset * n;
    int ulps = int(VKP_SPAWN_ULPS * n);
    // Adding to the bits grows the magnitude; for negative p that moves towards -inf.
    return intBitsToFloat(floatBitsToInt(p) + (p < 0.0f ? -ulps : ulps));
}

// `p` moved off its surface to the side `n` points to (n: unit geometric
// normal, flipped by the caller to the side the new ray leaves on).
VKP_FN vec3 offsetRayOrigin(vec3 p, vec3 n, float magnitude) {
    float scale = max(magnitude, 1e-30f);
    float nearZero = VKP_SPAWN_NEAR_ZERO * scale;
    float absoluteOffset = VKP_SPAWN_ABSOLUTE * scale;
    return vec3(offsetCoordinate(p.x, n.x, nearZero, absoluteOffset),
                offsetCoordinate(p.y, n.y, nearZero, absoluteOffset),
                offsetCoordinate(p.z, n.z, nearZero, absoluteOffset));
}

// A hit as shading needs it, recomputed from the primitive so its error is
// that of the primitive's coordinates, not of the ray's origin and length.
struct SurfacePoint {
    vec3 position;    // world space
    float magnitude;  // largest absolute coordinate the position was computed from
    // World distance a spawned ray moves off the surface beyond offsetRayOrigin's: 0 but on an
    // instanced triangle, where traversal moves the ray into the object's space and rounds it
    // again (instanceSpawnOffset)
    float spawnOffset;
    vec3 normal;  // world space, unit, geometric: triangles (p1 - p0) x (p2 - p0), spheres outward
    vec3
        shadingNormal;  // world space, unit, oriented like `normal`: the BSDF's frame. surfacePoint
                        // sets it to `normal`; the path tracer interpolates vertex normals into it
};

VKP_FN float maxComponent(vec3 v) {
    return max(max(v.x, v.y), v.z);
}

// The largest absolute row sum of the 3x3 part of `rows`: the factor by which
// the matrix can grow a vector, in the maximum norm.
VKP_FN float rowSumNorm(const vec4 rows[3]) {
    return max(max(abs(rows[0].x) + abs(rows[0].y) + abs(rows[0].z),
                   abs(rows[1].x) + abs(rows[1].y) + abs(rows[1].z)),
               abs(rows[2].x) + abs(rows[2].y) + abs(rows[2].z));
}

// How much farther than offsetRayOrigin's offset a ray
// spawned at `point` on object triangle `triangle` (placed by `x`) must start
// from the surface. offsetRayOrigin covers the rounding of a point computed
// from world-space vertices; here two more roundings stand between the ray's
// origin and the surface the traversal tests it against (shared/bvh_traverse.h
// moves the ray into the object's space by the world-to-object rows, and
// shading placed the object's vertices by the object-to-world rows), each
// bounded per coordinate by gamma(3) (|rows| |p| + |translation|) (the error
// of a transformed point: Pharr, Jakob and Humphreys, "Physically Based
// Rendering", 4th ed., section 6.8.6), the first carried back into the world
// by the object-to-world matrix. 2^-21 is gamma(3) ~ 3 x 2^-24 with a margin
// for the projection onto the normal (up to sqrt 3) and the hit point's own
// interpolation. Without it, some rays spawned off instances started behind
// their surface (assets/instances.gltf: 9 of 14 272 spawned rays hit the
// triangle they left; tests/bvh/ray_query_test.cpp).
VKP_FN float instanceSpawnOffset(VKP_IN(InstanceTransform) x, vec3 point,
                                 VKP_IN(BvhPrimitive) triangle) {
    float toObject =
        rowSumNorm(x.worldToObject) * maxComponent(abs(point)) +
        maxComponent(abs(vec3(x.worldToObject[0].w, x.worldToObject[1].w, x.worldToObject[2].w)));
    float objectSize = maxComponent(max(max(abs(triangle.p0), abs(triangle.p1)), abs(triangle.p2)));
    float toWorld = rowSumNorm(x.objectToWorld);
    float placing =
        toWorld * objectSize +
        maxComponent(abs(vec3(x.objectToWorld[0].w, x.objectToWorld[1].w, x.objectToWorld[2].w)));
    return 4.76837158203125e-07f * (toWorld * toObject + placing);  // 2^-21
}

VKP_FN SurfacePoint surfacePoint(VKP_IN(BvhPrimitive) primitive, VKP_IN(Ray) ray, Hit hit) {
    SurfacePoint s;
    if (isSphere(primitive)) {
        float radius = primitive.p1.x;
        vec3 outward = normalize(ray.origin + hit.t * ray.direction - primitive.p0);
        s.position = primitive.p0 + radius * outward;  // projected back onto the sphere
        s.normal = outward;
        s.shadingNormal = outward;
        s.magnitude = maxComponent(abs(primitive.p0)) + radius;
        s.spawnOffset = 0.0f;
    } else {
        float b1 = hit.barycentrics.x, b2 = hit.barycentrics.y;
        // p0 plus multiples of the edges: edges of nearby float vertices are
        // exact, so the only rounding of note is the final addition.
        s.position = primitive.p0 +
                     (b1 * (primitive.p1 - primitive.p0) + b2 * (primitive.p2 - primitive.p0));
        s.normal = normalize(cross(primitive.p1 - primitive.p0, primitive.p2 - primitive.p0));
        s.shadingNormal = s.normal;
        s.magnitude =
            maxComponent(max(max(abs(primitive.p0), abs(primitive.p1)), abs(primitive.p2)));
        s.spawnOffset = 0.0f;
    }
    return s;
}

// A ray leaving `surface` along `direction` (either side), offset so it does
// not hit the surface it starts on.
VKP_FN Ray spawnRay(VKP_IN(SurfacePoint) surface, vec3 direction, float tMax, uint pixel) {
    vec3 n = dot(direction, surface.normal) >= 0.0f ? surface.normal : -surface.normal;
    Ray ray;
    ray.origin = offsetRayOrigin(surface.position, n, surface.magnitude);
    if (hasFeature(VKP_FEATURE_INSTANCES) && surface.spawnOffset > 0.0f)
        ray.origin += surface.spawnOffset * n;
    ray.direction = direction;
    ray.tMax = tMax;
    ray.pixel = pixel;
    return ray;
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_INTERSECT_H
