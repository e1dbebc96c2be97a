// shared/spectral.h, the wavelengths of dispersion (KHR_materials_dispersion):
// the colour-matching fit against the CIE 1931 table, the weights a path
// takes averaging 1 in every channel over the range drawn (so white stays
// white), and the index at a wavelength keeping the extension's Abbe number.
#include "shared/spectral.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using namespace vkpath;

// CIE 1931 2-degree observer, 5 nm table (CIE 015:2018, table 1): x, y, z at
// a few wavelengths across the range.
struct CieRow {
    float lambda;
    glm::vec3 xyz;
};
constexpr CieRow CIE_1931[] = {
    {450, {0.3362f, 0.0380f, 1.7721f}}, {500, {0.0049f, 0.3230f, 0.2720f}},
    {555, {0.5121f, 1.0000f, 0.0057f}}, {600, {1.0622f, 0.6310f, 0.0008f}},
    {650, {0.2835f, 0.1070f, 0.0000f}},
};

// Wyman, Sloan and Shirley's multi-lobe fit stays within 0.03 of the table
// at each of its points here (their paper reports errors of that order at
// the peaks).
TEST(Spectral, FitFollowsTheCieTable) {
    for (const CieRow& row : CIE_1931) {
        SCOPED_TRACE(row.lambda);
        const glm::vec3 fit = shared::cieXyz(row.lambda);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit[c], row.xyz[c], 0.03f);
    }
}

// E[w] over the uniform draw is (1, 1, 1): the midpoint rule in double over
// the range (10^5 points) of the weights as the kernels compute them, within
// 1e-5 (the hard-coded scales' 7 digits); the weights are never negative.
TEST(Spectral, WeightsAverageOneOverTheRange) {
    const int n = 100000;
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i) {
        const float u = float((i + 0.5) / n);
        const glm::vec3 w = shared::spectralWeight(shared::wavelengthOf(u));
        for (int c = 0; c < 3; ++c) EXPECT_GE(w[c], 0.0f);
        sum += glm::dvec3(w);
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c] / n, 1.0, 1e-5) << "channel " << c;
    // Each channel peaks where its colour lies.
    EXPECT_GT(shared::spectralWeight(450).z, shared::spectralWeight(450).x);
    EXPECT_GT(shared::spectralWeight(540).y, shared::spectralWeight(540).x);
    EXPECT_GT(shared::spectralWeight(620).x, shared::spectralWeight(620).y);
}

// The index at the helium d line is the material's; the Abbe number
// (n_d - 1) / (n_F - n_C), from the hydrogen F and C lines, is 20 /
// dispersion to 1e-4 (the extension's formula is Cauchy's two-term fit).
TEST(Spectral, DispersedIndexKeepsTheAbbeNumber) {
    for (const float dispersion : {0.5f, 1.0f, 2.5f}) {
        SCOPED_TRACE(dispersion);
        const float ior = 1.6f;
        EXPECT_NEAR(shared::dispersedIor(ior, dispersion, 587.56f), ior, 1e-5f);
        const double nF = shared::dispersedIor(ior, dispersion, 486.13f);
        const double nC = shared::dispersedIor(ior, dispersion, 656.27f);
        EXPECT_NEAR((ior - 1.0) / (nF - nC) / (20.0 / dispersion), 1.0, 1e-4);
        EXPECT_GT(nF, nC);  // blue bends more
    }
    EXPECT_EQ(shared::dispersedIor(1.5f, 0.0f, 450.0f), 1.5f);
}

}  // namespace
