// The thin film's Fresnel reflectance (shaders/shared/thin_film.h,
// KHR_materials_iridescence) in its limits, computed in C++ (the same code
// the kernels run): a film of the outside's index is no film; a film far
// thicker than light's coherence adds its reflections incoherently (the
// Airy sum's mean, written here in double); a thin one colours what it
// reflects; every value is finite and in [0, 1].
#include "shared/thin_film.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace {

using namespace vkpath;

double schlick(double f0, double c) {
    return f0 + (1 - f0) * std::pow(1 - c, 5.0);
}

// A film of index 1 in air near normal incidence: the first interface
// reflects nothing (Schlick's approximation, which the extension takes for
// it, gives an index-matched interface (1 - cos)^5 of its own: 1e-5 at cos
// 0.9, 0.59 at 0.1, so the limit holds near the normal only), and what
// remains is the base's Schlick reflectance, up to the harmonics that the
// extension's clamp of R12 R23 at 1e-5 leaves (sqrt(1e-5) times the
// sensitivities, which reach a few units in linear Rec. 709): measured 0.0061
// over base F0 0.04 to 0.9, cos 0.9 and 1, 100 to 400 nm; bound 0.01.
TEST(ThinFilm, AFilmOfTheOutsidesIndexIsNoFilm) {
    double worst = 0;
    for (float f0 : {0.04f, 0.5f, 0.9f})
        for (float c : {0.9f, 1.0f})
            for (float d : {100.0f, 400.0f}) {
                const glm::vec3 f = shared::thinFilmFresnel(1.0f, 1.0f, d, c, glm::vec3(f0));
                for (int k = 0; k < 3; ++k)
                    worst = std::max(worst, std::abs(f[k] - schlick(f0, c)));
            }
    std::printf("  largest difference from the bare base: %.4f\n", worst);
    EXPECT_LT(worst, 0.01);
}

// 20 micrometres of film (optical path ~50 um, far beyond the coherence the
// sensitivities' Gaussians give): the harmonics vanish and the reflectance
// is the incoherent sum R12 + T^2 R23 / (1 - R12 R23), each interface's
// Schlick reflectance at its own angle (Snell's law into the film), to 1e-5.
TEST(ThinFilm, AThickFilmAddsItsReflectionsIncoherently) {
    for (float c : {0.2f, 0.7f, 1.0f})
        for (float f0 : {0.04f, 0.6f}) {
            const double filmIor = 1.3;
            const double r12 = schlick(std::pow((filmIor - 1) / (filmIor + 1), 2), c);
            const double cos2 = std::sqrt(1 - (1 - double(c) * c) / (filmIor * filmIor));
            const double baseIor = (1 + std::sqrt(f0 + 1e-4)) / (1 - std::sqrt(f0 + 1e-4));
            const double r23 =
                schlick(std::pow((baseIor - filmIor) / (baseIor + filmIor), 2), cos2);
            const double expected = r12 + (1 - r12) * (1 - r12) * r23 / (1 - r12 * r23);
            const glm::vec3 f = shared::thinFilmFresnel(1.0f, 1.3f, 20000.0f, c, glm::vec3(f0));
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(f[k], expected, 1e-5) << c << " " << f0;
        }
}

// A soap-bubble-like film (index 1.3, 300 nm) over glass (F0 0.04) at normal
// incidence reflects its colours unevenly (the channels spread by more than
// 0.02); over a sweep of thickness, angle, base and film index every value
// is finite and in [0, 1].
TEST(ThinFilm, AThinFilmColoursWhatItReflects) {
    const glm::vec3 f = shared::thinFilmFresnel(1.0f, 1.3f, 300.0f, 1.0f, glm::vec3(0.04f));
    EXPECT_GT(std::max({f.x, f.y, f.z}) - std::min({f.x, f.y, f.z}), 0.02f)
        << f.x << " " << f.y << " " << f.z;
    for (float d = 0; d <= 1000; d += 50)
        for (float c = 0; c <= 1.0f; c += 0.125f)
            for (float f0 : {0.0f, 0.04f, 0.5f, 1.0f})
                for (float ior : {1.0f, 1.3f, 2.5f}) {
                    const glm::vec3 r = shared::thinFilmFresnel(1.0f, ior, d, c, glm::vec3(f0));
                    for (int k = 0; k < 3; ++k) {
                        ASSERT_TRUE(std::isfinite(r[k]));
                        ASSERT_GE(r[k], 0.0f);
                        ASSERT_LE(r[k], 1.0f);
                    }
                }
}

}  // namespace
