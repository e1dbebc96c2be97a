// What the textured-model tests share: an image file's texels read with
// OpenImageIO and decoded by the sRGB rule written out here (not the
// renderer's decoder), where a world point lands on the film, a `vkpath
// render` with its variance AOV, and the mean radiance of a face seen
// head-on against a white sky, with its standard error.
#pragma once

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "image/image.h"
#include "image/statistics.h"
#include "shared/camera.h"
#include "support/run_vkpath.h"

namespace vkpath::test {

// IEC 61966-2-1, in double: the rule glTF 2.0 gives for base colour textures.
inline double srgbToLinear(double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// An image file's texels as 8-bit RGB, rows from the top.
struct Texels {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
};

inline Texels readTexels(const std::filesystem::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) throw std::runtime_error(path.string() + ": " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    Texels t;
    t.width = spec.width;
    t.height = spec.height;
    std::vector<uint8_t> all(size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, all.data()))
        throw std::runtime_error(path.string() + ": " + in->geterror());
    for (size_t i = 0; i < size_t(spec.width) * spec.height; ++i)
        for (int c = 0; c < 3; ++c)
            t.rgb.push_back(all[i * spec.nchannels + std::min(c, spec.nchannels - 1)]);
    return t;
}

// The mean texel over [x0, x1) x [y0, y1), per channel, each texel decoded
// by `decode` (sRGB to linear, or not, for power checks).
inline glm::dvec3 meanTexel(const Texels& t, int x0, int y0, int x1, int y1,
                            double (*decode)(double)) {
    glm::dvec3 sum(0.0);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < 3; ++c)
                sum[c] += decode(t.rgb[(size_t(y) * t.width + x) * 3 + c] / 255.0);
    return sum / double(size_t(x1 - x0) * size_t(y1 - y0));
}

inline glm::dvec3 meanTexel(const Texels& t, double (*decode)(double)) {
    return meanTexel(t, 0, 0, t.width, t.height, decode);
}

// Where a world point lands on the film, in pixels from the top-left corner
// (shared/camera.h's generateCameraRay inverted).
inline glm::dvec2 project(const shared::Camera& c, glm::dvec3 p) {
    const glm::dvec3 d = p - glm::dvec3(c.origin);
    const glm::dvec3 forward(c.forward), right(c.right), up(c.up);
    const double t = glm::dot(d, forward);
    const double ndcX = glm::dot(d, right) / (t * glm::dot(right, right));
    const double ndcY = glm::dot(d, up) / (t * glm::dot(up, up));
    return {(ndcX + 1.0) * 0.5 * c.width, (1.0 - ndcY) * 0.5 * c.height};
}

struct Render {
    image::Image image, variance;  // variance: of each pixel's mean
};

// `vkpath --validation render` under a constant white sky with the variance
// AOV, the EXR in `outputDir`; anything but exit 0 without a validation
// message fails the test and returns empty images.
inline Render renderOnWhiteSky(const std::filesystem::path& scene, uint32_t width, uint32_t height,
                               int spp, const std::filesystem::path& outputDir) {
    const std::filesystem::path exr = outputDir / (scene.stem().string() + ".exr");
    const CommandResult r =
        runVkpath("--validation render '" + scene.string() + "' -d " + std::to_string(width) + "x" +
                      std::to_string(height) + " -s " + std::to_string(spp) +
                      " --env-color 1,1,1 --aov variance -o '" + exr.string() + "'",
                  120);
    Render out;
    EXPECT_EQ(r.exitCode, 0) << scene << ":\n" << r.err;
    EXPECT_EQ(r.err.find("validation"), std::string::npos) << r.err;
    if (r.exitCode != 0) return out;
    out.image = image::readImage(exr);
    out.variance = image::readImage(image::aovPath(exr, "variance"));
    return out;
}

// The mean radiance, per channel, of a rectangle [lo, hi] of the film (in
// pixels, fractional) that a flat face seen head-on covers exactly, against
// a sky of radiance 1 seen directly around it: over the whole pixels that the
// face touches and a 2-pixel margin of sky, sum = area x face mean + (the
// rest) x 1. The standard error comes from the variance AOV. `inside` is
// false when the margin does not fit on the film.
struct FaceMean {
    bool inside = false;
    double area = 0;  // pixels
    glm::dvec3 mean{0.0}, standardError{0.0};
};

inline FaceMean faceMeanOnWhiteSky(const Render& r, glm::dvec2 lo, glm::dvec2 hi) {
    FaceMean f;
    const int x0 = int(std::floor(lo.x)) - 2, x1 = int(std::ceil(hi.x)) + 2;
    const int y0 = int(std::floor(lo.y)) - 2, y1 = int(std::ceil(hi.y)) + 2;
    if (x0 < 0 || y0 < 0 || x1 > int(r.image.width) || y1 > int(r.image.height) ||
        r.variance.width != r.image.width)
        return f;
    glm::dvec3 sum(0.0), variance(0.0);
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            sum += glm::dvec3(r.image.at(uint32_t(x), uint32_t(y)));
            variance += glm::dvec3(r.variance.at(uint32_t(x), uint32_t(y)));
        }
    f.inside = true;
    f.area = (hi.x - lo.x) * (hi.y - lo.y);
    f.mean = (sum - (double(x1 - x0) * double(y1 - y0) - f.area)) / f.area;
    f.standardError = glm::sqrt(variance) / f.area;
    return f;
}

}  // namespace vkpath::test
