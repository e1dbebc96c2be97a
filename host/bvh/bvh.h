// The bounding volume hierarchy over a scene's triangles and spheres: a binned
// SAH builder, flattened into the depth-first node array and leaf-ordered
// primitive array whose layouts shaders/shared/bvh.h defines.
//
//   bvh::BvhBuild build = bvh::buildBvh(scene);               // host arrays + stats
//   std::vector<std::string> problems = bvh::integrityCheck(build, scene);
//   bvh::GpuBvh gpu = bvh::uploadBvh(context, build);         // host/bvh/gpu_bvh.h
//   shared::BvhView view{build.traversalNodes, build.primitives};  // CPU traversal,
//   host/bvh/bvh_view.h
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "shared/bvh.h"

namespace vkpath::bvh {

struct BvhOptions {
    // Leaves hold at most this many primitives; below it the SAH decides
    // between a leaf and a split. Measured on lavapipe (docs/BENCHMARKS.md,
    // "BVH build"): 1 is slower, 2 to 8 about alike; 4 leaves the SAH room
    // without long leaves on meshes whose SAH would pack them.
    // 1 to VKP_BVH_MAX_LEAF_COUNT (15, what a traversal node word holds).
    uint32_t maxLeafSize = 4;
    // Bins per axis for the SAH sweep, 2 to 256.
    uint32_t binCount = 16;
    // SAH cost of visiting an interior node (two box tests), in units of one
    // primitive test. 0.5 to 4 measure about alike, 1 as fast as any
    // (docs/BENCHMARKS.md, "BVH build").
    float traversalCost = 1.0f;
    // Leaves lie at depth <= maxDepth (root 0). At most VKP_BVH_MAX_DEPTH, the
    // traversal stack's size; tests lower it to exercise the guard.
    uint32_t maxDepth = VKP_BVH_MAX_DEPTH;
    // Worker threads for building subtrees: 0 uses every hardware thread, 1
    // builds serially. The result is the same for any value.
    uint32_t threads = 0;
    // A subtree is handed to another thread only if it has at least this many
    // primitives (and it lies near the root).
    uint32_t parallelThreshold = 8192;
};

struct BvhStats {
    size_t triangles = 0;            // in the BVH: an instanced mesh's once
    size_t spheres = 0;              // in the BVH
    size_t instances = 0;            // instance primitives in the scene's tree
    size_t degenerateInstances = 0;  // left out: a singular or non-finite transform, or an
                                     // object of no triangle
    size_t degenerateTriangles =
        0;                         // left out: zero area or a non-finite vertex (never hit anyway)
    size_t degenerateSpheres = 0;  // left out: radius <= 0 or non-finite
    size_t nodes = 0;              // of all trees
    size_t leaves = 0;             // of all trees
    uint32_t maxDepth = 0;         // of a leaf, root at 0, in any tree
    uint32_t largestLeaf = 0;      // primitives in the fullest leaf
    double sahCost = 0;            // see sahCost(): of the scene's tree
    double buildMilliseconds = 0;  // wall clock, scene to flattened arrays
};

// A bottom-level tree (instancing, shaders/shared/bvh.h): the meshes
// [firstMesh, firstMesh + meshCount) of the scene in their own space, which
// instances place.
struct ObjectTree {
    uint32_t firstMesh = 0, meshCount = 0;
    uint32_t rootNode = 0;                            // in BvhBuild::nodes
    uint32_t rootTexel = 0;                           // in BvhBuild::traversalNodes
    uint32_t firstPrimitive = 0, primitiveCount = 0;  // in BvhBuild::primitives
};

struct BvhBuild {
    // Depth-first preorder: the scene's tree, root at 0, then each object's
    // tree (interior offsets and leaf ranges index the whole arrays).
    std::vector<shared::BvhNode> nodes;
    std::vector<shared::BvhPrimitive> primitives;  // in leaf order, the scene's tree's first
    // The nodes as traversal reads them (traversal_nodes.h), then the
    // instance records (shaders/shared/bvh.h).
    std::vector<glm::uvec4> traversalNodes;
    std::vector<ObjectTree> objects;  // the bottom-level trees, in the order of their nodes
    uint32_t sceneTreeNodes = 0;      // nodes[0, sceneTreeNodes) are the scene's tree
    BvhStats stats;

    // Each object's root in `nodes` (for bvh::collapseBvh).
    std::vector<uint32_t> objectRootNodes() const {
        std::vector<uint32_t> roots;
        for (const ObjectTree& o : objects) roots.push_back(o.rootNode);
        return roots;
    }

    size_t nodeBytes() const { return nodes.size() * sizeof(shared::BvhNode); }
    size_t traversalNodeBytes() const { return traversalNodes.size() * sizeof(glm::uvec4); }
    size_t primitiveBytes() const { return primitives.size() * sizeof(shared::BvhPrimitive); }
    // What the device holds: the traversal's nodes and the primitives.
    size_t bytes() const { return traversalNodeBytes() + primitiveBytes(); }
};

// The kernel feature bits the tree's traversal needs (shared/features.h):
// VKP_FEATURE_DEEP_BVH when a leaf lies below VKP_BVH_SHALLOW_DEPTH, so that
// the kernels' stack can spill to an array (shared/bvh_traverse.h), and
// VKP_FEATURE_INSTANCES when the scene's tree places instances.
inline uint64_t traversalFeatures(const BvhBuild& bvh) {
    return (bvh.stats.maxDepth > VKP_BVH_SHALLOW_DEPTH ? VKP_FEATURE_DEEP_BVH : 0u) |
           (bvh.stats.instances > 0 ? VKP_FEATURE_INSTANCES : 0u);
}

// traversalFeatures of the BVH that buildBvh(scene, options) will build,
// where its primitive counts alone decide them: a tree of more than
// maxLeafSize << VKP_BVH_SHALLOW_DEPTH primitives has a leaf below the
// shallow depth. nullopt where none is that large. (The instances bit
// assumes an instance is drawn: wrong only for a scene of singular ones.)
std::optional<uint64_t> predictedTraversalFeatures(const scene::Scene& scene,
                                                   const BvhOptions& options = {});

// Builds the BVH of every non-degenerate triangle and sphere of `scene`: a
// tree over the triangles of its meshes that are not instanced, its spheres
// and its instances, and one tree per distinct range of instanced meshes.
// Deterministic: the same scene and options give the same arrays bit for bit,
// whatever the number of threads. Throws InputError for a triangle whose
// vertex index is out of range, std::invalid_argument for bad options, and
// std::length_error for more than 2^32 - 2 primitives.
BvhBuild buildBvh(const scene::Scene& scene, const BvhOptions& options = {});

// Checks everything traversal relies on: the node array is one tree in
// depth-first order, every leaf is at depth <= VKP_BVH_MAX_DEPTH, every
// non-degenerate primitive of `scene` is in exactly one leaf with its scene
// data, every child box lies inside its parent's and every primitive strictly
// inside its leaf's. Returns the problems found, one line each (at most 20);
// empty when the BVH is sound.
std::vector<std::string> integrityCheck(const BvhBuild& bvh, const scene::Scene& scene);

// The surface area heuristic cost of a tree: traversalCost times the summed
// areas of interior nodes plus the summed area times primitive count of the
// leaves, all relative to the root's area. The expected number of node visits
// and primitive tests for a ray that crosses the root box.
double sahCost(std::span<const shared::BvhNode> nodes, float traversalCost = 1.0f);

// What the builder leaves out (exposed for tests and integrityCheck).
bool isDegenerateTriangle(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2);
bool isDegenerateSphere(glm::vec3 center, float radius);

// Outward padding of a bound (monotone, so a child inside its parent stays
// inside after padding): a relative 2^-21 plus 2^-100, rounded outward. Boxes
// strictly contain their primitives, which traversal relies on (see
// shared/intersect.h: safeInverse).
float padBelow(float x);
float padAbove(float x);

}  // namespace vkpath::bvh
