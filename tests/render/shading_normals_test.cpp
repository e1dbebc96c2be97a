// Shading normals (interpolated vertex normals, shared/bsdf.h and
// path_tracer.h) against analytic radiance under a directional light, where a
// diffuse surface of albedo rho facing the light along the shading normal n
// has outgoing radiance rho / pi x E x max(0, n . l): nothing else lights it
// (the sky is black, and neither scene can see itself), so every camera
// ray's estimate is exact up to float rounding.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "reference/reference_renderer.h"
#include "scene/camera.h"
#include "shared/camera.h"
#include "support/gpu_render.h"
#include "support/test_context.h"
#include "wavefront/renderer.h"
#include "wavefront/surface_tables.h"

namespace {

using namespace vkpath;

constexpr double PI = 3.14159265358979323846;
constexpr float ALBEDO = 0.5f;

scene::Material grey() {
    scene::Material m;
    m.reflectance = glm::vec3(ALBEDO);
    return m;
}

// The plane y = 0, [-4, 4]^2, seen straight down from y = 3 (the whole film
// sees it), lit by a directional light.
scene::Scene litPlane(const std::vector<glm::vec3>& normals, glm::vec3 lightDirection) {
    scene::Scene s;
    s.materials.push_back(grey());
    scene::Mesh plane;
    plane.positions = {{-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}};
    plane.normals = normals;
    plane.triangles = {{0, 1, 2}, {0, 2, 3}};
    s.meshes.push_back(plane);
    s.camera.position = {0.2f, 3.0f, 0.1f};
    s.camera.target = {0.2f, 0.0f, 0.1f};
    s.camera.up = {0.0f, 0.0f, -1.0f};
    s.camera.xfovDegrees = 60.0f;
    s.directionalLights.push_back({glm::normalize(lightDirection), glm::vec3(1.0f, 2.0f, 3.0f)});
    return s;
}

wavefront::RenderSettings settings(uint32_t size, uint32_t spp) {
    wavefront::RenderSettings s;
    s.width = s.height = size;
    s.samplesPerPixel = spp;
    s.maxDepth = 4;
    return s;
}

using test::renderGpu;

TEST(SurfaceTables, FlatTrianglesKeepNoNormals) {
    const glm::vec3 p0(0, 0, 0), p1(1, 0, 0), p2(0, 1, 0), up(0, 0, 1);
    EXPECT_TRUE(wavefront::isFlatShaded(p0, p1, p2, up, up, up));
    EXPECT_TRUE(wavefront::isFlatShaded(p0, p1, p2, -up, -up,
                                        -up));  // reversed: the same two-sided shading
    EXPECT_TRUE(
        wavefront::isFlatShaded(p0, p1, p2, up, glm::vec3(0), up));  // nothing to interpolate
    EXPECT_FALSE(
        wavefront::isFlatShaded(p0, p1, p2, up, -up, up));  // would cancel out: not the face normal
    const glm::vec3 tilted = glm::normalize(glm::vec3(0.01f, 0, 1));  // 0.57 degrees
    EXPECT_FALSE(wavefront::isFlatShaded(p0, p1, p2, up, up, tilted));

    // A scene of flat meshes has no attribute arrays at all.
    const scene::Scene flat = litPlane({{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}}, {0, -1, 0});
    const wavefront::SurfaceTables t = wavefront::buildSurfaceTables(flat);
    EXPECT_EQ(t.attributes, 0u);
    EXPECT_TRUE(t.triangleVertices.empty());
    EXPECT_TRUE(t.vertexNormals.empty());
}

// Vertex normals that equal the face normal, or none: the same image bit for
// bit, and the same kernels (no shading-normals feature).
TEST(ShadingNormals, FlatMeshRendersExactlyAsWithout) {
    const glm::vec3 light(0.3f, -1.0f, 0.2f);
    const scene::Scene without = litPlane({}, light);
    const scene::Scene with = litPlane({{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}}, light);
    const auto a = renderGpu(without, settings(16, 4));
    const auto b = renderGpu(with, settings(16, 4));
    ASSERT_EQ(a.image.pixels.size(), b.image.pixels.size());
    for (size_t i = 0; i < a.image.pixels.size(); ++i)
        ASSERT_EQ(a.image.pixels[i], b.image.pixels[i]) << i;
}

// Every vertex normal tilted by 25 degrees: the plane shades as if it were
// tilted, rho / pi x E x (n_s . l), everywhere (a constant, so the bound is
// float rounding alone: 1e-5 relative, as the punctual-light tests measure).
// The light is placed so the tilted and the geometric cosines differ by 2x.
TEST(ShadingNormals, TiltedVertexNormalsShadeWithTheirCosine) {
    const double tilt = 25.0 * PI / 180.0;
    const glm::dvec3 n(std::sin(tilt), std::cos(tilt), 0.0);
    const glm::dvec3 toLight = glm::normalize(glm::dvec3(0.9, 0.5, 0.1));
    const glm::vec3 nf(n);
    const scene::Scene s = litPlane({nf, nf, nf, nf}, glm::vec3(-toLight));
    const double cosShading = glm::dot(n, toLight), cosGeometric = toLight.y;
    ASSERT_GT(cosShading, 1.5 * cosGeometric);
    for (bool cpu : {false, true}) {
        SCOPED_TRACE(cpu ? "CPU reference" : "GPU");
        const auto r = cpu ? reference::ReferenceRenderer(s, settings(16, 4)).render()
                           : renderGpu(s, settings(16, 4));
        EXPECT_EQ(r.nonFiniteSamples, 0u);
        const glm::dvec3 expected = ALBEDO / PI * glm::dvec3(1, 2, 3) * cosShading;
        for (const glm::vec3& p : r.image.pixels)
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(p[c], expected[c], 1e-5 * expected[c]);
    }
}

// A UV sphere of radius 1 (`segments` around, segments / 2 from pole to
// pole), with its analytic normals as vertex normals or without normals.
scene::Mesh sphereMesh(int segments, bool smooth) {
    scene::Mesh m;
    const int rings = segments / 2;
    for (int i = 0; i <= rings; ++i) {
        const double theta = PI * i / rings;
        for (int j = 0; j <= segments; ++j) {
            const double phi = 2 * PI * j / segments;
            const glm::vec3 p(std::sin(theta) * std::cos(phi), std::cos(theta),
                              std::sin(theta) * std::sin(phi));
            m.positions.push_back(p);
            if (smooth) m.normals.push_back(p);
        }
    }
    const auto index = [&](int i, int j) { return uint32_t(i * (segments + 1) + j); };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            const uint32_t a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1),
                           d = index(i, j + 1);
            if (i > 0) m.triangles.push_back({a, d, b});
            if (i < rings - 1) m.triangles.push_back({b, d, c});
        }
    return m;
}

scene::Scene sphereUnderSun(std::optional<scene::Mesh> mesh) {
    scene::Scene s;
    s.materials.push_back(grey());
    if (mesh)
        s.meshes.push_back(*mesh);
    else
        s.spheres.push_back({"ball", glm::vec3(0.0f), 1.0f, 0});
    s.camera.position = {0.0f, 0.0f, 4.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.xfovDegrees = 40.0f;
    // From the upper right and a little behind: the terminator crosses the film.
    s.directionalLights.push_back({glm::normalize(glm::vec3(-1.0f, -0.4f, 0.3f)), glm::vec3(3.0f)});
    return s;
}

// A smooth-shaded sphere mesh against the analytic sphere: inside the
// silhouette (pixels whose every ray meets a sphere of radius 0.97, inside the
// mesh, whose facets are within cos(pi / 48) = 0.998 of the centre) the two
// differ only by the interpolation of the normals and by the mesh's flat
// positions, which at 48 segments are within 0.3% in the normal's direction;
// the flat-shaded mesh differs by the facets' angle, up to 7.5 degrees. The
// bounds, from the renders (64 x 64 pixels, 16 spp; the light is a delta, so
// only pixel jitter is noise; 1428 pixels inside): the smooth mesh's mean
// |error| measured 0.0012 of the peak and the flat one's 0.0069. Smooth must
// stay below 0.004 (3x the measured, room for the jitter of another sampler
// or seed) and below a third of flat (the interpolation is what removes the
// facets; measured a sixth).
TEST(ShadingNormals, SmoothSphereMeshMatchesTheAnalyticSphere) {
    constexpr uint32_t SIZE = 64;
    const auto sphere = renderGpu(sphereUnderSun(std::nullopt), settings(SIZE, 16));
    const auto smooth = renderGpu(sphereUnderSun(sphereMesh(48, true)), settings(SIZE, 16));
    const auto flat = renderGpu(sphereUnderSun(sphereMesh(48, false)), settings(SIZE, 16));

    const scene::Scene s = sphereUnderSun(std::nullopt);
    const shared::Camera camera = scene::makeGpuCamera(s.camera, SIZE, SIZE);
    auto inside = [&](uint32_t x, uint32_t y) {
        for (float u : {0.0f, 1.0f})
            for (float v : {0.0f, 1.0f}) {
                const shared::Ray ray =
                    shared::generateCameraRay(camera, glm::uvec2(x, y), glm::vec2(u, v));
                const glm::dvec3 o(ray.origin), d = glm::normalize(glm::dvec3(ray.direction));
                const double b = glm::dot(o, d), c = glm::dot(o, o) - 0.97 * 0.97;
                if (b * b - c <= 0) return false;
            }
        return true;
    };
    double peak = 0;
    for (const glm::vec3& p : sphere.image.pixels) peak = std::max(peak, double(p.x));
    double smoothError = 0, flatError = 0;
    int pixels = 0;
    for (uint32_t y = 0; y < SIZE; ++y)
        for (uint32_t x = 0; x < SIZE; ++x) {
            if (!inside(x, y)) continue;
            const size_t i = y * SIZE + x;
            smoothError += std::abs(smooth.image.pixels[i].x - sphere.image.pixels[i].x);
            flatError += std::abs(flat.image.pixels[i].x - sphere.image.pixels[i].x);
            ++pixels;
        }
    ASSERT_GT(pixels, 1000);
    smoothError /= pixels * peak;
    flatError /= pixels * peak;
    EXPECT_LT(smoothError, 0.004) << "flat: " << flatError;
    EXPECT_LT(smoothError, flatError / 3) << "smooth " << smoothError << ", flat " << flatError;
}

}  // namespace
