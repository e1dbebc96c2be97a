// Choosing a light, and the probability of the choice: part of shared/path_tracer.h, which
// includes it (no include guard: once per scope, as path_tracer.h).

// ---- choosing a light ----------------------------------------------------------------------

// Whether lights [0, SceneInfo::treeLights) are chosen through the light
// tree (shared/light_tree.h); else every light is chosen by the alias table
// over their power. With the tree the alias table's second part
// (entries from lightCount on) holds the tree as a whole, then each light
// from treeLights on (the directional lights and the environment).
VKP_FN bool lightTreeOn() VKP_SCENE_CONST {
    return hasFeature(VKP_FEATURE_LIGHT_TREE) && sceneInfo().treeLights != 0u;
}

// The alias entry of light `light` from treeLights on, with the tree.
VKP_FN AliasEntry outsideTreeAlias(uint light) VKP_SCENE_CONST {
    SceneInfo info = sceneInfo();
    return sceneLightAlias(info.lightCount + 1u + (light - info.treeLights));
}

struct LightTreeSample {
    uint light;  // VKP_NO_LIGHT: no light of the tree reaches the point
    float pmf;   // the probability of choosing it at the point
    float u;     // the walk's number, rescaled at every level to [0, 1)
};

// A light of the tree chosen at `p` of normal `n` with probability in
// proportion to its importance at every level (lightNodeImportance), from a
// number `u` in [0, 1). A child whose share rounds to 0 in float (below
// 2^-24 of its sibling's importance) is never chosen and reads probability
// 0: MIS then counts its light by BSDF samples alone, and light sampling
// alone at a last vertex (lightSamplingAlone) misses at most that share.
VKP_FN LightTreeSample sampleLightTree(vec3 p, vec3 n, float u) VKP_SCENE_CONST {
    LightTreeSample s;
    s.light = VKP_NO_LIGHT;
    s.pmf = 0.0f;
    s.u = u;
    uint index = 0u;
    LightTreeNode node = sceneLightTreeNode(0u);
    float pmf = 1.0f;
    for (uint depth = 0u; depth <= VKP_LIGHT_TREE_MAX_DEPTH; ++depth) {
        if ((node.flags & VKP_LIGHT_NODE_LEAF) != 0u) {
            s.light = node.index;
            s.pmf = pmf;
            s.u = u;
            return s;
        }
        LightTreeNode first = sceneLightTreeNode(index + 1u);
        LightTreeNode second = sceneLightTreeNode(node.index);
        float i0 = lightNodeImportance(first, p, n);
        float i1 = lightNodeImportance(second, p, n);
        if (!(i0 + i1 > 0.0f)) return s;
        float p0 = lightTreeFirstChildProbability(i0, i1);
        if (u < p0) {
            u = min(u / p0, VKP_ONE_MINUS_EPSILON);
            pmf *= p0;
            index = index + 1u;
            node = first;
        } else {
            u = min((u - p0) / (1.0f - p0), VKP_ONE_MINUS_EPSILON);
            pmf *= 1.0f - p0;
            index = node.index;
            node = second;
        }
    }
    return s;
}

// The probability that sampleLightTree(p, n, u) chooses `light` (of the
// tree), walked down its trail with the same floats as the sampling.
VKP_FN float lightTreePmf(vec3 p, vec3 n, uint light) VKP_SCENE_CONST {
    uint trail = sceneLightTreeTrail(light);
    if (trail == VKP_NO_LIGHT) return 0.0f;  // a light of no power
    uint index = 0u;
    LightTreeNode node = sceneLightTreeNode(0u);
    float pmf = 1.0f;
    for (uint depth = 0u; depth <= VKP_LIGHT_TREE_MAX_DEPTH; ++depth) {
        if ((node.flags & VKP_LIGHT_NODE_LEAF) != 0u) return pmf;
        LightTreeNode first = sceneLightTreeNode(index + 1u);
        LightTreeNode second = sceneLightTreeNode(node.index);
        float i0 = lightNodeImportance(first, p, n);
        float i1 = lightNodeImportance(second, p, n);
        if (!(i0 + i1 > 0.0f)) return 0.0f;
        float p0 = lightTreeFirstChildProbability(i0, i1);
        if ((trail & 1u) == 0u) {
            pmf *= p0;
            index = index + 1u;
            node = first;
        } else {
            pmf *= 1.0f - p0;
            index = node.index;
            node = second;
        }
        trail >>= 1u;
    }
    return 0.0f;
}

// The normal a vertex's light choice sees: its geometric normal `n` as the
// path keeps it (shared/unit_vector.h), so that the choice at the vertex and
// its probability seen from the next hit (emittedRadiance) agree.
VKP_FN vec3 lightChoiceNormal(vec3 n) VKP_SCENE_CONST {
    return decodeUnitVector(encodeUnitVector(n));
}

// The probability that a light sample at `p` of normal `n`
// (lightChoiceNormal) chooses light `light` (the alias table's, times the
// tree's where the light is in it).
VKP_FN float lightChoiceProbability(uint light, vec3 p, vec3 n) VKP_SCENE_CONST {
    if (!lightTreeOn()) return sceneLightAlias(light).probability;
    SceneInfo info = sceneInfo();
    if (light >= info.treeLights) return outsideTreeAlias(light).probability;
    return sceneLightAlias(info.lightCount).probability * lightTreePmf(p, n, light);
}

// A light chosen at `p` of normal `n` (lightChoiceNormal) and what is left of the number `u` that
// chose it (reusable: fine enough to place the point on the light); light VKP_NO_LIGHT where the
// tree was chosen and none of it reaches p.
struct LightChoice {
    uint light;
    float probability;
    float u;
    bool reusable;
};

// From the word `bits`, uniform over 32 bits, and `fresh`, a number in
// [0, 1) independent of it that walks the tree where the alias table's part
// of the word is too coarse to (a tree of a tiny share of the power).
VKP_FN LightChoice chooseLight(vec3 p, vec3 n, uint bits, float fresh) VKP_SCENE_CONST {
    SceneInfo info = sceneInfo();
    LightChoice choice;
    if (!lightTreeOn()) {
        uint bucket = aliasBucket(bits, info.lightCount);
        AliasChoice a = aliasSampleReusing(sceneLightAlias(bucket), bucket,
                                           aliasBucketFraction(bits, info.lightCount));
        choice.light = a.element;
        choice.probability = sceneLightAlias(a.element).probability;
        choice.u = a.u;
        choice.reusable = a.reusable;
        return choice;
    }
    // Element 0 of the second part is the tree, element 1 + i light treeLights + i.
    uint count = info.lightCount - info.treeLights + 1u;
    uint bucket = aliasBucket(bits, count);
    AliasChoice a = aliasSampleReusing(sceneLightAlias(info.lightCount + bucket), bucket,
                                       aliasBucketFraction(bits, count));
    float aliasProbability = sceneLightAlias(info.lightCount + a.element).probability;
    if (a.element != 0u) {
        choice.light = info.treeLights + a.element - 1u;
        choice.probability = aliasProbability;
        choice.u = a.u;
        choice.reusable = a.reusable;
        return choice;
    }
    LightTreeSample s = sampleLightTree(p, n, a.reusable ? a.u : fresh);
    choice.light = s.light;
    choice.probability = aliasProbability * s.pmf;
    choice.u = s.u;
    choice.reusable = a.reusable && s.pmf >= VKP_LIGHT_TREE_REUSE_MIN_PMF;
    return choice;
}
