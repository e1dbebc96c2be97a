// Comparing two renders made with the same seed pixel by pixel.
#pragma once

#include <cmath>
#include <cstddef>

#include "image/image.h"

namespace vkpath::test {

// The fraction of pixels whose channels agree to 1e-3 relative (or 1e-6
// absolute): those where every sample followed the same path in both.
inline double matchingPixelFraction(const image::Image& a, const image::Image& b) {
    size_t same = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        bool ok = true;
        for (int c = 0; c < 3; ++c)
            ok = ok && std::abs(a.pixels[i][c] - b.pixels[i][c]) <=
                           1e-3f * std::abs(b.pixels[i][c]) + 1e-6f;
        same += ok;
    }
    return double(same) / double(a.pixels.size());
}

}  // namespace vkpath::test
