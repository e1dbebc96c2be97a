// Owen-scrambled Sobol' points in two dimensions, for the low-discrepancy
// sampler (shared/rng.h, `--sampler sobol`). Pure uint32 arithmetic, so GLSL
// and C++ produce the same bits.
//
// The first two dimensions of Sobol's sequence form a (0,2)-sequence in base
// 2: every aligned block of 2^k consecutive points (indices m 2^k to
// (m+1) 2^k - 1) is a (0,k,2)-net, i.e. each elementary interval
// [a 2^-i, (a+1) 2^-i) x [b 2^-j, (b+1) 2^-j) with i + j = k holds exactly
// one point. Dimension 0 is the van der Corput sequence (the bit-reversed
// index). Dimension 1 has primitive polynomial x + 1 and initial direction
// number m_1 = 1 (the first row of Joe and Kuo's direction numbers,
// "Constructing Sobol sequences with better two-dimensional projections",
// SIAM J. Sci. Comput. 30(5), 2008, file new-joe-kuo-6.21201: d=2 s=1 a=0
// m=1). Bratley and Fox's recurrence m_k = 2 m_{k-1} xor m_{k-1} then gives
// the direction numbers v_k = m_k 2^(32-k), i.e. v_1 = 2^31 and
// v_k = v_{k-1} xor (v_{k-1} >> 1) (Bratley and Fox, "Algorithm 659", ACM
// TOMS 14(1), 1988).
//
// Randomisation follows Burley, "Practical Hash-based Owen Scrambling", JCGT
// 9(4), 2020: the index is shuffled by a nested uniform scramble (a block of
// 2^k indices maps onto another aligned block of 2^k, so the net property
// survives; with a different shuffle per dimension pair this is the padding
// that decorrelates pairs), and each output coordinate gets its own nested
// uniform scramble (an Owen scramble: bit i is flipped by a hash of the bits
// above it, which maps elementary intervals onto elementary intervals, keeps
// the net and makes every point uniform on [0,1)^2).
#ifndef VKPATH_SHARED_SOBOL_H
#define VKPATH_SHARED_SOBOL_H

#include "shared/compat.h"

VKP_NAMESPACE_BEGIN

// Laine and Karras' hash ("Stratified Sampling for Stochastic Transparency",
// EGSR 2011) with Burley's constants (2020, section 3): a bijection in which
// bit i of the result depends only on bits 0..i of x (adding the seed
// carries upward; x * even shifts upward), so applied to bit-reversed values
// it is a nested uniform (Owen) scramble.
VKP_FN uint laineKarrasPermutation(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// Bit i of the result depends only on bits i..31 of x and on the seed.
VKP_FN uint nestedUniformScramble(uint x, uint seed) {
    return bitfieldReverse(laineKarrasPermutation(bitfieldReverse(x), seed));
}

// Sobol' dimension 1 of `index` as a 32-bit fraction, bit-reversed: bit j
// of the result is bit 31 - j of the fraction. The fraction is the xor of
// the direction numbers v_k over the set bits k of the index, and v_k holds
// row k - 1 of Pascal's triangle mod 2 (bit 31 - j of v_{i+1} is C(i, j)
// mod 2). By Lucas' theorem C(i, j) is odd exactly when the bits of j are a
// subset of those of i, so bit j of the reversed fraction is the xor of the
// index bits i that are supersets of j: a superset (zeta) transform over
// GF(2), one masked shift-xor per bit of the bit position, five in all
// instead of a loop over 32 index bits (tests/kernels/sobol_sampler_test.cpp
// checks it against the direction numbers).
VKP_FN uint reversedSobolDimension1(uint index) {
    index ^= (index >> 1u) & 0x55555555u;
    index ^= (index >> 2u) & 0x33333333u;
    index ^= (index >> 4u) & 0x0f0f0f0fu;
    index ^= (index >> 8u) & 0x00ff00ffu;
    index ^= (index >> 16u) & 0x0000ffffu;
    return index;
}

// Coordinate `component` (0 or 1) of point `index` of a scrambled 2-D Sobol'
// sequence, as a 32-bit fraction. `shuffleSeed` permutes the indices;
// `scrambleSeed` scrambles this coordinate. Every sample index of 32 bits is
// valid.
//
// As written out: shuffled = nestedUniformScramble(index, shuffleSeed);
// the coordinate is bitfieldReverse(shuffled) (dimension 0, van der Corput)
// or the dimension-1 fraction of it, and the result is its
// nestedUniformScramble with scrambleSeed. The bit reversals that cancel
// are left out: both coordinates are scrambled in bit-reversed form
// (scrambledCoordinate).
VKP_FN uint scrambledCoordinate(uint reversedBits, uint scrambleSeed) {
    return bitfieldReverse(laineKarrasPermutation(reversedBits, scrambleSeed));
}

VKP_FN uint scrambledSobol2(uint index, uint component, uint shuffleSeed, uint scrambleSeed) {
    uint shuffled = nestedUniformScramble(index, shuffleSeed);
    return scrambledCoordinate(component == 0u ? shuffled : reversedSobolDimension1(shuffled),
                               scrambleSeed);
}

// Both coordinates of point `index`: scrambledSobol2 of components 0 and 1,
// the index shuffled once for the two.
VKP_FN uvec2 scrambledSobol2Point(uint index, uint shuffleSeed, uint scrambleSeed0,
                                  uint scrambleSeed1) {
    uint shuffled = nestedUniformScramble(index, shuffleSeed);
    return uvec2(scrambledCoordinate(shuffled, scrambleSeed0),
                 scrambledCoordinate(reversedSobolDimension1(shuffled), scrambleSeed1));
}

VKP_NAMESPACE_END

#endif  // VKPATH_SHARED_SOBOL_H
