// The binned SAH builder (Wald, "On fast Construction of SAH-based Bounding
// Volume Hierarchies", IEEE Symposium on Interactive Ray Tracing 2007): at each
// node the primitive centroids are sorted into equal-width bins along each
// axis, a sweep over the bins evaluates the surface area heuristic at every
// bin boundary, and the cheapest split (or a leaf) wins.
//
// Subtrees are built on other threads near the root; each builds its nodes in
// depth-first order into a vector of its own, and the parent appends it, so
// the result is the serial build's bit for bit.
#include "bvh/bvh.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <map>
#include <stdexcept>
#include <thread>

#include "bvh/traversal_nodes.h"
#include "input_error.h"

namespace vkpath::bvh {

using glm::vec3;
using shared::BvhNode;
using shared::BvhPrimitive;

namespace {

constexpr float INF = std::numeric_limits<float>::infinity();

struct Aabb {
    vec3 lo{INF};
    vec3 hi{-INF};

    void grow(const Aabb& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    void grow(vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    // Half the surface area (the SAH only uses ratios).
    float halfArea() const {
        if (empty()) return 0.0f;
        const vec3 e = hi - lo;
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
};

// One primitive as the builder sees it: where it is, and where it came from.
struct BuildPrimitive {
    Aabb bounds;
    vec3 centroid;
    uint32_t kind;    // VKP_PRIMITIVE_*
    uint32_t id;      // shared::BvhPrimitive::id
    uint32_t source;  // triangle: mesh index; sphere: unused
    uint32_t local;   // triangle: index within the mesh; sphere: index into Scene::spheres
};

// A node before flattening: interior nodes keep their second child's index
// in `offset`, relative to the start of the vector they were built into.
struct BuildNode {
    Aabb bounds;
    uint32_t offset = 0;
    uint32_t count = 0;  // 0: interior
};

uint32_t ceilLog2(size_t n) {
    return n <= 1 ? 0u : static_cast<uint32_t>(std::bit_width(n - 1));
}

float roundDown(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) > x) f = std::nextafter(f, -INF);
    return f;
}

float roundUp(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) < x) f = std::nextafter(f, INF);
    return f;
}

Aabb sphereBounds(vec3 c, float r) {
    Aabb b;
    for (int k = 0; k < 3; ++k) {
        b.lo[k] = roundDown(static_cast<double>(c[k]) - r);
        b.hi[k] = roundUp(static_cast<double>(c[k]) + r);
    }
    return b;
}

// Builds over the primitives themselves, partitioning them in place: each
// level of the tree then reads them sequentially (a permuted index array
// would make every read a cache miss on large meshes).
class Builder {
  public:
    Builder(const BvhOptions& options, std::vector<BuildPrimitive>& primitives)
        : m_options(options), m_primitives(primitives) {
        uint32_t threads = options.threads ? options.threads : std::thread::hardware_concurrency();
        threads = std::max(threads, 1u);
        // Two subtrees per thread near the root balance uneven splits a little.
        m_spawnDepth = threads > 1 ? ceilLog2(threads) + 1 : 0;
    }

    // Builds the subtree over m_primitives[begin, end) into `out`, depth-first.
    void build(uint32_t begin, uint32_t end, uint32_t depth, std::vector<BuildNode>& out) const {
        const size_t nodeIndex = out.size();
        out.emplace_back();
        Aabb bounds, centroids;
        for (uint32_t i = begin; i < end; ++i) {
            bounds.grow(m_primitives[i].bounds);
            centroids.grow(m_primitives[i].centroid);
        }
        out[nodeIndex].bounds = bounds;

        const uint32_t mid = split(begin, end, depth, bounds, centroids);
        if (mid == 0) {
            out[nodeIndex].offset = begin;
            out[nodeIndex].count = end - begin;
            return;
        }
        if (depth < m_spawnDepth && end - begin >= m_options.parallelThreshold) {
            auto second = std::async(std::launch::async, [this, mid, end, depth] {
                std::vector<BuildNode> nodes;
                build(mid, end, depth + 1, nodes);
                return nodes;
            });
            build(begin, mid, depth + 1, out);
            std::vector<BuildNode> nodes = second.get();
            const auto base = static_cast<uint32_t>(out.size());
            out[nodeIndex].offset = base;
            for (BuildNode& node : nodes) {
                if (node.count == 0) node.offset += base;
                out.push_back(node);
            }
        } else {
            build(begin, mid, depth + 1, out);
            out[nodeIndex].offset = static_cast<uint32_t>(out.size());
            build(mid, end, depth + 1, out);
        }
    }

  private:
    static constexpr uint32_t MAX_BINS = 256;

    struct Bin {
        Aabb bounds;
        uint32_t count = 0;
    };

    uint32_t binOf(float c, float lo, float scale) const {
        const float x = (c - lo) * scale;
        return std::min(m_options.binCount - 1, static_cast<uint32_t>(x));
    }

    // Partitions m_primitives[begin, end) and returns where the second child
    // starts, or 0 to make a leaf.
    uint32_t split(uint32_t begin, uint32_t end, uint32_t depth, const Aabb& bounds,
                   const Aabb& centroids) const {
        const uint32_t n = end - begin;
        if (n == 1) return 0;
        const bool mustSplit = n > m_options.maxLeafSize;
        const uint32_t binCount = m_options.binCount;

        // ---- bin the centroids along all three axes in one pass ---------------
        std::array<float, 3> lo{}, scale{};
        std::array<bool, 3> usable{};
        for (int axis = 0; axis < 3; ++axis) {
            lo[axis] = centroids.lo[axis];
            const float extent = centroids.hi[axis] - lo[axis];
            scale[axis] = static_cast<float>(binCount) / extent;
            usable[axis] = extent > 0.0f && std::isfinite(scale[axis]);
        }
        if (!usable[0] && !usable[1] && !usable[2]) {
            // Every centroid in one point: no plane separates them.
            return mustSplit ? medianSplit(begin, end, centroids) : 0;
        }
        // Per-thread scratch: constructing 3 x 256 bins on every call would
        // cost more than binning the small nodes near the leaves.
        thread_local std::array<std::array<Bin, MAX_BINS>, 3> bins;
        thread_local std::array<float, MAX_BINS> secondArea;
        thread_local std::array<uint32_t, MAX_BINS> secondCount;
        thread_local std::array<uint32_t, MAX_BINS> usedBins;
        for (int axis = 0; axis < 3; ++axis)
            std::fill(bins[axis].begin(), bins[axis].begin() + binCount, Bin{});
        for (uint32_t i = begin; i < end; ++i) {
            const BuildPrimitive& p = m_primitives[i];
            for (int axis = 0; axis < 3; ++axis) {
                if (!usable[axis]) continue;
                Bin& bin = bins[axis][binOf(p.centroid[axis], lo[axis], scale[axis])];
                bin.bounds.grow(p.bounds);
                ++bin.count;
            }
        }

        // ---- the SAH sweep over each axis's bin boundaries --------------------
        const float nodeArea = bounds.halfArea();
        float bestCost = INF;
        int bestAxis = -1;
        uint32_t bestBin = 0;  // bins 0..bestBin go to the first child
        uint32_t bestFirstCount = 0;
        for (int axis = 0; axis < 3; ++axis) {
            if (!usable[axis]) continue;
            const auto& axisBins = bins[axis];
            // Only boundaries after a non-empty bin give distinct partitions, so
            // sweep over those: small nodes near the leaves fill few bins.
            uint32_t used = 0;
            for (uint32_t b = 0; b < binCount; ++b)
                if (axisBins[b].count) usedBins[used++] = b;
            Aabb acc;
            uint32_t count = 0;
            for (uint32_t k = used - 1; k > 0; --k) {
                acc.grow(axisBins[usedBins[k]].bounds);
                count += axisBins[usedBins[k]].count;
                secondArea[k - 1] = acc.halfArea();
                secondCount[k - 1] = count;
            }
            acc = Aabb{};
            count = 0;
            for (uint32_t k = 0; k + 1 < used; ++k) {
                acc.grow(axisBins[usedBins[k]].bounds);
                count += axisBins[usedBins[k]].count;
                const float areas = acc.halfArea() * static_cast<float>(count) +
                                    secondArea[k] * static_cast<float>(secondCount[k]);
                const float cost = m_options.traversalCost +
                                   (nodeArea > 0.0f ? areas / nodeArea : static_cast<float>(n));
                if (cost < bestCost) {
                    bestCost = cost;
                    bestAxis = axis;
                    bestBin = usedBins[k];
                    bestFirstCount = count;
                }
            }
        }
        if (bestAxis < 0) return mustSplit ? medianSplit(begin, end, centroids) : 0;
        if (!mustSplit && static_cast<float>(n) <= bestCost) return 0;

        // The depth guard: both children must still fit below maxDepth with
        // halving splits (which preserve depth + ceilLog2(n) <= maxDepth).
        const uint32_t larger = std::max(bestFirstCount, n - bestFirstCount);
        if (depth + 1 + ceilLog2(larger) > m_options.maxDepth)
            return medianSplit(begin, end, centroids);

        const float axisLo = lo[bestAxis], axisScale = scale[bestAxis];
        auto* first = m_primitives.data() + begin;
        auto* middle =
            std::partition(first, m_primitives.data() + end, [&](const BuildPrimitive& p) {
                return binOf(p.centroid[bestAxis], axisLo, axisScale) <= bestBin;
            });
        return begin + static_cast<uint32_t>(middle - first);
    }

    // Halves the range at the median centroid of the widest axis, ties broken
    // by (kind, id), which is unique, so the order is fully determined.
    uint32_t medianSplit(uint32_t begin, uint32_t end, const Aabb& centroids) const {
        const vec3 extent = centroids.hi - centroids.lo;
        const int axis =
            extent.x >= extent.y ? (extent.x >= extent.z ? 0 : 2) : (extent.y >= extent.z ? 1 : 2);
        const uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(m_primitives.data() + begin, m_primitives.data() + mid,
                         m_primitives.data() + end,
                         [&](const BuildPrimitive& a, const BuildPrimitive& b) {
                             const float ca = a.centroid[axis], cb = b.centroid[axis];
                             if (ca != cb) return ca < cb;
                             return a.kind != b.kind ? a.kind < b.kind : a.id < b.id;
                         });
        return mid;
    }

    const BvhOptions& m_options;
    std::vector<BuildPrimitive>& m_primitives;
    uint32_t m_spawnDepth = 0;
};

void validate(const BvhOptions& options) {
    if (options.maxLeafSize < 1 || options.maxLeafSize > VKP_BVH_MAX_LEAF_COUNT)
        throw std::invalid_argument(fmt::format("BVH: maxLeafSize must be 1 to {}, not {}",
                                                VKP_BVH_MAX_LEAF_COUNT, options.maxLeafSize));
    if (options.binCount < 2 || options.binCount > 256)
        throw std::invalid_argument(
            fmt::format("BVH: binCount must be 2 to 256, not {}", options.binCount));
    if (options.maxDepth < 1 || options.maxDepth > VKP_BVH_MAX_DEPTH)
        throw std::invalid_argument(fmt::format("BVH: maxDepth must be 1 to {}, not {}",
                                                VKP_BVH_MAX_DEPTH, options.maxDepth));
    if (!(options.traversalCost >= 0.0f))
        throw std::invalid_argument("BVH: traversalCost must be >= 0");
}

// Appends the triangles of mesh `m` (its first triangle's id `firstId`) that
// are not degenerate.
void collectTriangles(const scene::Scene& scene, uint32_t m, uint64_t firstId, BvhStats& stats,
                      std::vector<BuildPrimitive>& primitives) {
    const scene::Mesh& mesh = scene.meshes[m];
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3 tri = mesh.triangles[t];
        if (tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() ||
            tri.z >= mesh.positions.size())
            throw InputError(
                fmt::format("mesh '{}': triangle {} has a vertex index beyond its {} vertices",
                            mesh.name, t, mesh.positions.size()));
        const vec3 a = mesh.positions[tri.x], b = mesh.positions[tri.y], c = mesh.positions[tri.z];
        if (isDegenerateTriangle(a, b, c)) {
            ++stats.degenerateTriangles;
            continue;
        }
        BuildPrimitive p;
        p.bounds.grow(a);
        p.bounds.grow(b);
        p.bounds.grow(c);
        p.centroid = 0.5f * (p.bounds.lo + p.bounds.hi);
        p.kind = VKP_PRIMITIVE_TRIANGLE;
        p.id = static_cast<uint32_t>(firstId + t);
        p.source = m;
        p.local = t;
        primitives.push_back(p);
        ++stats.triangles;
    }
}

// Each mesh's first triangle id: triangles are numbered over all meshes, mesh
// by mesh in scene order.
std::vector<uint64_t> firstTriangleIds(const scene::Scene& scene) {
    std::vector<uint64_t> first(scene.meshes.size());
    uint64_t id = 0;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        first[m] = id;
        id += scene.meshes[m].triangles.size();
    }
    return first;
}

// The primitives of the scene's tree but its instances, in scene order
// (triangles of the meshes that are not instanced, mesh by mesh, then
// spheres), with the counts of those left out.
std::vector<BuildPrimitive> collectPrimitives(const scene::Scene& scene,
                                              const std::vector<uint64_t>& firstIds,
                                              BvhStats& stats) {
    std::vector<BuildPrimitive> primitives;
    primitives.reserve(scene.triangleCount() + scene.spheres.size() + scene.instances.size());
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        if (!scene.meshes[m].instanced) collectTriangles(scene, m, firstIds[m], stats, primitives);
    for (uint32_t s = 0; s < scene.spheres.size(); ++s) {
        const scene::Sphere& sphere = scene.spheres[s];
        if (isDegenerateSphere(sphere.center, sphere.radius)) {
            ++stats.degenerateSpheres;
            continue;
        }
        BuildPrimitive p;
        p.bounds = sphereBounds(sphere.center, sphere.radius);
        p.centroid = sphere.center;
        p.kind = VKP_PRIMITIVE_SPHERE;
        p.id = s;
        p.source = 0;
        p.local = s;
        primitives.push_back(p);
        ++stats.spheres;
    }
    return primitives;
}

// A triangle or sphere as the kernels read it (instances are made by buildBvh).
BvhPrimitive flattenPrimitive(const scene::Scene& scene, const BuildPrimitive& p) {
    BvhPrimitive out{};
    out.kind = p.kind;
    out.id = p.id;
    if (p.kind == VKP_PRIMITIVE_SPHERE) {
        const scene::Sphere& s = scene.spheres[p.local];
        out.p0 = s.center;
        out.p1 = vec3(s.radius, 0.0f, 0.0f);
        out.p2 = vec3(0.0f);
        out.material = s.material;
    } else {
        const scene::Mesh& mesh = scene.meshes[p.source];
        const glm::uvec3 tri = mesh.triangles[p.local];
        out.p0 = mesh.positions[tri.x];
        out.p1 = mesh.positions[tri.y];
        out.p2 = mesh.positions[tri.z];
        out.material = mesh.material;
    }
    return out;
}

// A tree over `primitives`, reordering them into leaf order: its nodes in
// depth-first order, interior offsets relative to the vector, leaf ranges to
// `primitives`. Empty for no primitives.
std::vector<BuildNode> buildTree(const BvhOptions& options,
                                 std::vector<BuildPrimitive>& primitives) {
    std::vector<BuildNode> nodes;
    if (primitives.empty()) return nodes;
    if (ceilLog2(primitives.size()) > options.maxDepth)
        throw std::invalid_argument(fmt::format("BVH: {} primitives cannot fit below maxDepth {}",
                                                primitives.size(), options.maxDepth));
    nodes.reserve(2 * primitives.size());
    Builder(options, primitives).build(0, static_cast<uint32_t>(primitives.size()), 0, nodes);
    return nodes;
}

// Appends `nodes` to `out` with padded boxes, interior offsets moved by
// `nodeBase` and leaf ranges by `primitiveBase`; adds to the statistics.
void appendNodes(const std::vector<BuildNode>& nodes, uint32_t nodeBase, uint32_t primitiveBase,
                 std::vector<BvhNode>& out, BvhStats& stats) {
    std::vector<uint32_t> depth(nodes.size(), 0);
    for (size_t i = 0; i < nodes.size(); ++i) {
        const BuildNode& n = nodes[i];
        BvhNode node;
        node.boundsMin =
            vec3(padBelow(n.bounds.lo.x), padBelow(n.bounds.lo.y), padBelow(n.bounds.lo.z));
        node.boundsMax =
            vec3(padAbove(n.bounds.hi.x), padAbove(n.bounds.hi.y), padAbove(n.bounds.hi.z));
        node.count = n.count;
        node.offset = n.count == 0 ? n.offset + nodeBase : n.offset + primitiveBase;
        out.push_back(node);
        // Depth and leaf statistics: nodes are in preorder, so a node's depth
        // is known when it is reached.
        if (n.count == 0) {
            depth[i + 1] = depth[i] + 1;
            depth[n.offset] = depth[i] + 1;
        } else {
            ++stats.leaves;
            stats.maxDepth = std::max(stats.maxDepth, depth[i]);
            stats.largestLeaf = std::max(stats.largestLeaf, n.count);
        }
    }
    stats.nodes += nodes.size();
}

// An instance's world-space box: the corners of its object's box (the
// root's, unpadded) placed in double, rounded outward. Empty when the
// transform is singular or a corner is not finite.
Aabb instanceBounds(const Aabb& object, const glm::dmat4& objectToWorld) {
    Aabb box;
    const double det = glm::determinant(glm::dmat3(objectToWorld));
    if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return box;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p((corner & 1) ? object.hi.x : object.lo.x,
                           (corner & 2) ? object.hi.y : object.lo.y,
                           (corner & 4) ? object.hi.z : object.lo.z);
        const glm::dvec3 w(objectToWorld * glm::dvec4(p, 1.0));
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(w[k]) || std::abs(w[k]) > 0x1p100) return Aabb{};
            box.lo[k] = std::min(box.lo[k], roundDown(w[k]));
            box.hi[k] = std::max(box.hi[k], roundUp(w[k]));
        }
    }
    return box;
}

// The rows of a 3x4 affine matrix, as an instance record holds them.
void appendRows(const glm::dmat4& m, std::vector<glm::uvec4>& texels) {
    for (int row = 0; row < 3; ++row)
        texels.push_back(glm::floatBitsToUint(
            glm::vec4(float(m[0][row]), float(m[1][row]), float(m[2][row]), float(m[3][row]))));
}

}  // namespace

bool isDegenerateTriangle(vec3 p0, vec3 p1, vec3 p2) {
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(p0[k]) || !std::isfinite(p1[k]) || !std::isfinite(p2[k])) return true;
    // The edge vectors and their cross product in double: differences of floats
    // of similar size are exact there, and their products are, so exactly
    // collinear vertices give exactly zero.
    const glm::dvec3 e1 = glm::dvec3(p1) - glm::dvec3(p0);
    const glm::dvec3 e2 = glm::dvec3(p2) - glm::dvec3(p0);
    const glm::dvec3 n = glm::cross(e1, e2);
    return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
}

bool isDegenerateSphere(vec3 center, float radius) {
    return !(radius > 0.0f) || !std::isfinite(radius) || !std::isfinite(center.x) ||
           !std::isfinite(center.y) || !std::isfinite(center.z);
}

float padBelow(float x) {
    const double d = x;
    return roundDown(d - (std::abs(d) * 0x1p-21 + 0x1p-100));
}

float padAbove(float x) {
    const double d = x;
    return roundUp(d + (std::abs(d) * 0x1p-21 + 0x1p-100));
}

BvhBuild buildBvh(const scene::Scene& scene, const BvhOptions& options) {
    validate(options);
    const auto start = std::chrono::steady_clock::now();
    BvhBuild result;
    const std::vector<uint64_t> firstIds = firstTriangleIds(scene);
    std::vector<BuildPrimitive> primitives = collectPrimitives(scene, firstIds, result.stats);

    // ---- the objects: one tree per distinct range of instanced meshes ------------
    struct Object {
        std::vector<BuildPrimitive> primitives;
        std::vector<BuildNode> nodes;
    };
    std::vector<Object> objects;
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> objectOf;  // (firstMesh, meshCount)
    std::vector<uint32_t> instances;  // the scene's instances that are drawn
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const scene::Instance& instance = scene.instances[i];
        if (uint64_t(instance.firstMesh) + instance.meshCount > scene.meshes.size())
            throw InputError(fmt::format("instance '{}': meshes [{}, {}) beyond the scene's {}",
                                         instance.name, instance.firstMesh,
                                         uint64_t(instance.firstMesh) + instance.meshCount,
                                         scene.meshes.size()));
        const auto key = std::pair(instance.firstMesh, instance.meshCount);
        auto [it, added] = objectOf.emplace(key, uint32_t(objects.size()));
        if (added) {
            Object object;
            for (uint32_t m = instance.firstMesh; m < instance.firstMesh + instance.meshCount;
                 ++m) {
                if (!scene.meshes[m].instanced)
                    throw InputError(fmt::format("instance '{}': mesh '{}' is not instanced",
                                                 instance.name, scene.meshes[m].name));
                collectTriangles(scene, m, firstIds[m], result.stats, object.primitives);
            }
            object.nodes = buildTree(options, object.primitives);
            objects.push_back(std::move(object));
        }
        const Object& object = objects[it->second];
        const Aabb box = object.nodes.empty()
                             ? Aabb{}
                             : instanceBounds(object.nodes[0].bounds, instance.objectToWorld);
        if (box.empty()) {
            ++result.stats.degenerateInstances;
            continue;
        }
        BuildPrimitive p;
        p.bounds = box;
        p.centroid = 0.5f * (box.lo + box.hi);
        p.kind = VKP_PRIMITIVE_INSTANCE;
        p.id = uint32_t(instances.size());
        p.source = it->second;
        p.local = i;
        primitives.push_back(p);
        instances.push_back(i);
        ++result.stats.instances;
    }
    if (objects.size() > (1u << 24))
        throw std::length_error(
            fmt::format("BVH: {} instanced objects, more than 2^24", objects.size()));
    size_t total = primitives.size();
    for (const Object& o : objects) total += o.primitives.size();
    if (total >= std::numeric_limits<uint32_t>::max() - 1)
        throw std::length_error(fmt::format("BVH: {} primitives, more than 2^32 - 2", total));

    // ---- the scene's tree, then each object's -------------------------------------
    const std::vector<BuildNode> sceneNodes = buildTree(options, primitives);
    if (sceneNodes.empty()) {
        result.nodes.push_back(BvhNode{vec3(0.0f), 0u, vec3(0.0f), 0u});  // the empty tree
        result.stats.nodes = 1;
    } else {
        appendNodes(sceneNodes, 0, 0, result.nodes, result.stats);
    }
    result.sceneTreeNodes = uint32_t(result.nodes.size());
    result.traversalNodes = packTraversalNodes(result.nodes);
    uint32_t nextPrimitive = uint32_t(primitives.size());
    for (const Object& object : objects) {
        ObjectTree tree;
        tree.rootNode = uint32_t(result.nodes.size());
        tree.firstPrimitive = nextPrimitive;
        tree.primitiveCount = uint32_t(object.primitives.size());
        if (!object.nodes.empty()) {
            // Packed with leaf ranges in the whole array and interior offsets in its own.
            std::vector<BvhNode> local;
            BvhStats ignored;
            appendNodes(object.nodes, 0, nextPrimitive, local, ignored);
            tree.rootTexel = uint32_t(result.traversalNodes.size());
            const std::vector<glm::uvec4> texels = packTraversalNodes(local, tree.rootTexel);
            result.traversalNodes.insert(result.traversalNodes.end(), texels.begin(), texels.end());
            appendNodes(object.nodes, tree.rootNode, nextPrimitive, result.nodes, result.stats);
        }
        nextPrimitive += tree.primitiveCount;
        result.objects.push_back(tree);
    }
    for (const auto& [key, index] : objectOf) {
        result.objects[index].firstMesh = key.first;
        result.objects[index].meshCount = key.second;
    }

    // ---- the primitives, and the instance records after the nodes -------------------
    const auto firstRecord = uint32_t(result.traversalNodes.size());
    result.primitives.resize(total);
    for (size_t i = 0; i < primitives.size(); ++i) {
        const BuildPrimitive& p = primitives[i];
        if (p.kind != VKP_PRIMITIVE_INSTANCE) {
            result.primitives[i] = flattenPrimitive(scene, p);
            continue;
        }
        BvhPrimitive& out = result.primitives[i];
        out = BvhPrimitive{};
        out.kind = VKP_PRIMITIVE_INSTANCE;
        out.id = firstRecord + VKP_INSTANCE_RECORD_TEXELS * p.id;
        out.material = result.objects[p.source].rootTexel;
        out.p0 = vec3(float(p.source), 0.0f, 0.0f);
        out.p1 = p.bounds.lo;
        out.p2 = p.bounds.hi;
    }
    size_t next = primitives.size();
    for (const Object& object : objects)
        for (const BuildPrimitive& p : object.primitives)
            result.primitives[next++] = flattenPrimitive(scene, p);
    for (const uint32_t i : instances) {
        const glm::dmat4& objectToWorld = scene.instances[i].objectToWorld;
        appendRows(glm::inverse(objectToWorld), result.traversalNodes);
        appendRows(objectToWorld, result.traversalNodes);
    }
    if (result.traversalNodes.size() > VKP_BVH_WORD_INDEX_MASK)
        throw std::length_error("BVH: more node texels than the 2^28 a node word indexes");

    result.stats.sahCost =
        sahCost(std::span(result.nodes).first(result.sceneTreeNodes), options.traversalCost);
    result.stats.buildMilliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

double sahCost(std::span<const BvhNode> nodes, float traversalCost) {
    if (nodes.empty() || (nodes[0].count == 0 && nodes[0].offset == 0)) return 0.0;
    auto halfArea = [](const BvhNode& n) {
        const glm::dvec3 e = glm::dvec3(n.boundsMax) - glm::dvec3(n.boundsMin);
        return e.x * e.y + e.y * e.z + e.z * e.x;
    };
    const double root = halfArea(nodes[0]);
    if (!(root > 0.0)) return 0.0;
    double cost = 0.0;
    for (const BvhNode& n : nodes)
        cost += halfArea(n) / root * (n.count == 0 ? traversalCost : static_cast<double>(n.count));
    return cost;
}

std::vector<std::string> integrityCheck(const BvhBuild& bvh, const scene::Scene& scene) {
    constexpr size_t MAX_PROBLEMS = 20;
    constexpr uint32_t NONE = std::numeric_limits<uint32_t>::max();
    std::vector<std::string> problems;
    auto report = [&](std::string message) {
        if (problems.size() < MAX_PROBLEMS) problems.push_back(std::move(message));
    };
    const auto& nodes = bvh.nodes;
    const auto& prims = bvh.primitives;

    // What the BVH must hold: every non-degenerate triangle and sphere of the
    // scene, an instanced mesh's once per object, and an instance primitive
    // per instance not left out.
    std::vector<std::pair<uint32_t, uint32_t>> triangleSource;  // global id -> (mesh, triangle)
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        for (uint32_t t = 0; t < scene.meshes[m].triangles.size(); ++t)
            triangleSource.emplace_back(m, t);
    const size_t triangleTotal = triangleSource.size();
    std::vector<uint32_t> triangleSeen(triangleTotal, 0);
    std::vector<uint8_t> sphereSeen(scene.spheres.size(), 0);
    auto validTriangle = [&](uint32_t m, uint32_t t) {
        const scene::Mesh& mesh = scene.meshes[m];
        const glm::uvec3 tri = mesh.triangles[t];
        return tri.x < mesh.positions.size() && tri.y < mesh.positions.size() &&
               tri.z < mesh.positions.size() &&
               !isDegenerateTriangle(mesh.positions[tri.x], mesh.positions[tri.y],
                                     mesh.positions[tri.z]);
    };
    // An instanced mesh's triangles are in each object's tree that holds it
    // (objects may share meshes); the others' in the scene's tree once.
    size_t expected = 0;
    std::vector<uint32_t> objectsOfMesh(scene.meshes.size(), 0);
    for (const ObjectTree& o : bvh.objects)
        for (uint32_t m = o.firstMesh; m < o.firstMesh + o.meshCount && m < scene.meshes.size();
             ++m)
            ++objectsOfMesh[m];
    for (const auto& [m, t] : triangleSource)
        if (validTriangle(m, t)) expected += scene.meshes[m].instanced ? objectsOfMesh[m] : 1;
    for (const scene::Sphere& s : scene.spheres)
        if (!isDegenerateSphere(s.center, s.radius)) ++expected;
    size_t instancePrimitives = 0;
    for (const BvhPrimitive& p : prims) instancePrimitives += p.kind == VKP_PRIMITIVE_INSTANCE;
    expected += instancePrimitives;
    if (instancePrimitives + bvh.stats.degenerateInstances != scene.instances.size())
        report(fmt::format("{} instance primitives and {} left out, the scene has {} instances",
                           instancePrimitives, bvh.stats.degenerateInstances,
                           scene.instances.size()));
    if (prims.size() != expected)
        report(fmt::format("{} primitives in the BVH, the scene has {} non-degenerate ones",
                           prims.size(), expected));

    if (nodes.empty()) {
        report("no nodes (an empty BVH has one empty root)");
        return problems;
    }
    if (nodes[0].count == 0 && nodes[0].offset == 0) {
        if (bvh.sceneTreeNodes != 1 || instancePrimitives != 0 ||
            (bvh.objects.empty() && !prims.empty()))
            report("an empty root with other nodes or primitives");
        return problems;
    }

    auto inside = [](const BvhNode& inner, const BvhNode& outer) {
        return glm::all(glm::greaterThanEqual(inner.boundsMin, outer.boundsMin)) &&
               glm::all(glm::lessThanEqual(inner.boundsMax, outer.boundsMax));
    };
    auto finiteBox = [](const BvhNode& n) {
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(n.boundsMin[k]) || !std::isfinite(n.boundsMax[k]) ||
                !(n.boundsMin[k] <= n.boundsMax[k]))
                return false;
        return true;
    };

    // Walk each tree from its root: every node of [begin, end) must be
    // reached exactly once, in preorder (so the walk visits begin, begin + 1,
    // ...), its leaves within the primitives [firstPrimitive, endPrimitive).
    std::vector<uint32_t> primitiveLeaf(prims.size(), NONE);
    auto walk = [&](uint32_t begin, uint32_t end, uint32_t firstPrimitive, uint32_t endPrimitive) {
        struct Item {
            uint32_t node;
            uint32_t depth;
            uint32_t parent;
        };
        std::vector<Item> stack{{begin, 0u, NONE}};
        uint32_t visited = begin;
        while (!stack.empty()) {
            const Item item = stack.back();
            stack.pop_back();
            if (item.node != visited) {
                report(fmt::format("node {} reached as the {}th node of a depth-first walk",
                                   item.node, visited));
                return;
            }
            ++visited;
            const BvhNode& node = nodes[item.node];
            if (!finiteBox(node))
                report(fmt::format("node {}: box is not finite and ordered", item.node));
            if (item.parent != NONE && !inside(node, nodes[item.parent]))
                report(fmt::format("node {}: box is not inside its parent {}'s", item.node,
                                   item.parent));
            if (node.count == 0) {
                if (item.depth + 1 > VKP_BVH_MAX_DEPTH)
                    report(fmt::format(
                        "node {}: interior node at depth {} has children below the limit {}",
                        item.node, item.depth, VKP_BVH_MAX_DEPTH));
                if (node.offset <= item.node + 1 || node.offset >= end) {
                    report(fmt::format("node {}: second child {} out of order or range", item.node,
                                       node.offset));
                    return;
                }
                stack.push_back({node.offset, item.depth + 1, item.node});
                stack.push_back({item.node + 1, item.depth + 1, item.node});
                continue;
            }
            if (item.depth > VKP_BVH_MAX_DEPTH)
                report(fmt::format("leaf {} at depth {} beyond the limit {}", item.node, item.depth,
                                   VKP_BVH_MAX_DEPTH));
            if (node.offset < firstPrimitive ||
                static_cast<uint64_t>(node.offset) + node.count > endPrimitive) {
                report(fmt::format("leaf {}: primitives [{}, {}) beyond its tree's [{}, {})",
                                   item.node, node.offset,
                                   static_cast<uint64_t>(node.offset) + node.count, firstPrimitive,
                                   endPrimitive));
                continue;
            }
            for (uint32_t i = node.offset; i < node.offset + node.count; ++i) {
                if (primitiveLeaf[i] != NONE)
                    report(fmt::format("primitive {} is in leaves {} and {}", i, primitiveLeaf[i],
                                       item.node));
                primitiveLeaf[i] = item.node;
                const BvhPrimitive& p = prims[i];
                glm::vec3 lo, hi;
                if (p.kind == VKP_PRIMITIVE_SPHERE) {
                    lo = p.p0 - p.p1.x;
                    hi = p.p0 + p.p1.x;
                } else if (p.kind == VKP_PRIMITIVE_INSTANCE) {
                    lo = p.p1;
                    hi = p.p2;
                } else {
                    lo = glm::min(glm::min(p.p0, p.p1), p.p2);
                    hi = glm::max(glm::max(p.p0, p.p1), p.p2);
                }
                if (!glm::all(glm::lessThan(node.boundsMin, lo)) ||
                    !glm::all(glm::lessThan(hi, node.boundsMax)))
                    report(fmt::format("primitive {} is not strictly inside leaf {}'s box", i,
                                       item.node));
            }
        }
        if (visited != end)
            report(fmt::format("nodes [{}, {}), {} reachable from the root", begin, end,
                               visited - begin));
    };
    const uint32_t scenePrimitives =
        bvh.objects.empty() ? uint32_t(prims.size()) : bvh.objects[0].firstPrimitive;
    walk(0, bvh.sceneTreeNodes, 0, scenePrimitives);
    for (size_t k = 0; k < bvh.objects.size(); ++k) {
        const ObjectTree& o = bvh.objects[k];
        const uint32_t end =
            k + 1 < bvh.objects.size() ? bvh.objects[k + 1].rootNode : uint32_t(nodes.size());
        if (o.primitiveCount > 0)
            walk(o.rootNode, end, o.firstPrimitive, o.firstPrimitive + o.primitiveCount);
    }
    for (size_t i = 0; i < prims.size(); ++i)
        if (primitiveLeaf[i] == NONE) report(fmt::format("primitive {} is in no leaf", i));

    // Every primitive carries its scene data, and each scene primitive appears once.
    for (size_t i = 0; i < prims.size(); ++i) {
        const BvhPrimitive& p = prims[i];
        const bool inSceneTree = i < scenePrimitives;
        if (p.kind == VKP_PRIMITIVE_SPHERE) {
            if (p.id >= scene.spheres.size() || !inSceneTree) {
                report(fmt::format("primitive {}: sphere id {} out of range", i, p.id));
                continue;
            }
            const scene::Sphere& s = scene.spheres[p.id];
            if (sphereSeen[p.id]++) report(fmt::format("sphere {} appears twice", p.id));
            if (p.p0 != s.center || p.p1.x != s.radius || p.material != s.material)
                report(fmt::format("primitive {}: data differs from sphere {}", i, p.id));
        } else if (p.kind == VKP_PRIMITIVE_TRIANGLE) {
            if (p.id >= triangleTotal) {
                report(fmt::format("primitive {}: triangle id {} out of range", i, p.id));
                continue;
            }
            const auto [m, t] = triangleSource[p.id];
            const scene::Mesh& mesh = scene.meshes[m];
            if (mesh.instanced == inSceneTree)
                report(fmt::format("primitive {}: triangle {} of mesh '{}' in the wrong tree", i,
                                   p.id, mesh.name));
            const glm::uvec3 tri = mesh.triangles[t];
            if (++triangleSeen[p.id] > (mesh.instanced ? objectsOfMesh[m] : 1u))
                report(fmt::format("triangle {} appears more often than the trees that hold it",
                                   p.id));
            if (p.p0 != mesh.positions[tri.x] || p.p1 != mesh.positions[tri.y] ||
                p.p2 != mesh.positions[tri.z] || p.material != mesh.material)
                report(fmt::format("primitive {}: data differs from triangle {}", i, p.id));
        } else if (p.kind == VKP_PRIMITIVE_INSTANCE) {
            const auto object = uint32_t(p.p0.x);
            if (!inSceneTree || object >= bvh.objects.size() ||
                p.material != bvh.objects[object].rootTexel ||
                uint64_t(p.id) + VKP_INSTANCE_RECORD_TEXELS > bvh.traversalNodes.size())
                report(fmt::format("primitive {}: an instance whose tree or record is wrong", i));
        } else {
            report(fmt::format("primitive {}: unknown kind {}", i, p.kind));
        }
    }
    return problems;
}

}  // namespace vkpath::bvh
