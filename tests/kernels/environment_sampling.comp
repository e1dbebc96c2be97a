// Test kernel: samples the environment's alias table and, for each sample,
// also evaluates the pdf of the sampled direction the way a BSDF-sampled ray
// that hits the environment would (direction -> map uv -> texel -> pdf), and
// the map's bilinear radiance in that direction (as environmentRadiance does,
// before strength).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require

#include "shared/environment_sampling.h"
#include "shared/rng.h"

layout(local_size_x_id = 0) in;

struct EnvTestResult {
    vec3 direction;
    float pdf;        // from sampling
    float pdfLookup;  // from evaluating the direction
    uint texel;       // the texel chosen by the alias table
    uint lookedUpTexel;  // the texel of the sampled direction, looked up
    vec3 radiance;       // the bilinear radiance in the sampled direction
};

layout(binding = 0, scalar) readonly buffer Table { AliasEntry table[]; };
layout(binding = 1, scalar) writeonly buffer Results { EnvTestResult results[]; };
layout(binding = 2, scalar) readonly buffer Texels { vec3 texels[]; };
layout(push_constant, scalar) uniform Push {
    EnvironmentInfo info;
    uint count;
    uint seed;
    uint largest;  // 1: every random word is 2^32 - 1 (the largest uniform, 1 - 2^-24)
};

uint bitsFor(RngKey key, uint dimension) { return largest != 0u ? 0xffffffffu : rngBits(key, dimension); }

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    RngKey key = makeRngKey(i, 0u, seed);
    uint texelCount = info.width * info.height;
    uint bucket = aliasBucket(bitsFor(key, 0u), texelCount);
    uint texel = aliasResolve(table[bucket], bucket, bitsFor(key, 1u));
    EnvSample s = envSampleInTexel(info, texel, vec2(uintToUnitFloat(bitsFor(key, 2u)), uintToUnitFloat(bitsFor(key, 3u))));

    // As a BSDF-sampled ray escaping in this direction would evaluate it.
    vec3 mapDirection = envWorldToMap(info, s.direction);
    uint lookedUp = envTexelOfUv(info, equirectUv(mapDirection));
    EnvTestResult r;
    r.direction = s.direction;
    r.pdf = envDirectionPdf(info, table[s.pdfTexel].probability, s.direction);
    r.pdfLookup = envDirectionPdf(info, table[lookedUp].probability, s.direction);
    r.texel = texel;
    r.lookedUpTexel = lookedUp;
    EnvBilinear b = envBilinear(info, equirectUv(mapDirection));
    r.radiance = envBilinearMix(b, texels[b.texel00], texels[b.texel10], texels[b.texel01],
                                texels[b.texel11]);
    results[i] = r;
}
