// buildBvh: collects the scene's primitives' boxes, has sah_builder.cpp build
// the tree over them (and over each instanced object's), and flattens the
// trees and primitives into the arrays the kernels read.
#include "bvh/bvh.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "bvh/parallel_chunks.h"
#include "bvh/sah_builder.h"
#include "bvh/traversal_nodes.h"
#include "input_error.h"

namespace vkpath::bvh {

using glm::vec3;
using shared::BvhNode;
using shared::BvhPrimitive;

namespace {

constexpr float INF = BUILD_INF;

// Where a primitive came from: what flattening it needs. A build's origins
// are in (kind, id) order (triangles mesh by mesh, then spheres, then
// instances), so an origin's index orders ties.
struct PrimitiveOrigin {
    uint32_t kind;    // VKP_PRIMITIVE_*
    uint32_t id;      // shared::BvhPrimitive::id
    uint32_t source;  // triangle: mesh index; instance: object index
    uint32_t local;   // triangle: index within its mesh; sphere: into Scene::spheres;
                      // instance: into Scene::instances
};

// A build's primitives: the builder reorders `items` into leaf order and
// leaves `origins` as they were added.
struct BuildPrimitives {
    std::vector<BuildPrimitive> items;
    std::vector<PrimitiveOrigin> origins;

    void reserve(size_t n) {
        items.reserve(n);
        origins.reserve(n);
    }
    void add(const Aabb& bounds, const PrimitiveOrigin& origin) {
        items.emplace_back(bounds, uint32_t(origins.size()));
        origins.push_back(origin);
    }
    size_t size() const { return items.size(); }
    bool empty() const { return items.empty(); }
    const PrimitiveOrigin& origin(size_t i) const { return origins[items[i].origin()]; }
};

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
                      BuildPrimitives& primitives) {
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
        Aabb bounds;
        bounds.grow(a);
        bounds.grow(b);
        bounds.grow(c);
        primitives.add(bounds, {VKP_PRIMITIVE_TRIANGLE, static_cast<uint32_t>(firstId + t), m, t});
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
BuildPrimitives collectPrimitives(const scene::Scene& scene, const std::vector<uint64_t>& firstIds,
                                  BvhStats& stats) {
    BuildPrimitives primitives;
    primitives.reserve(scene.triangleCount() + scene.spheres.size() + scene.instances.size());
    for (uint32_t m = 0; m < scene.meshes.size(); ++m)
        if (!scene.meshes[m].instanced) collectTriangles(scene, m, firstIds[m], stats, primitives);
    for (uint32_t s = 0; s < scene.spheres.size(); ++s) {
        const scene::Sphere& sphere = scene.spheres[s];
        if (isDegenerateSphere(sphere.center, sphere.radius)) {
            ++stats.degenerateSpheres;
            continue;
        }
        primitives.add(sphereBounds(sphere.center, sphere.radius), {VKP_PRIMITIVE_SPHERE, s, 0, s});
        ++stats.spheres;
    }
    return primitives;
}

// A triangle or sphere as the kernels read it (instances are made by buildBvh).
BvhPrimitive flattenPrimitive(const scene::Scene& scene, const PrimitiveOrigin& p) {
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

// Appends `nodes` to `out` with padded boxes, interior offsets moved by
// `nodeBase` and leaf ranges by `primitiveBase`; adds to the statistics.
void appendNodes(const std::vector<BuildNode>& nodes, uint32_t nodeBase, uint32_t primitiveBase,
                 std::vector<BvhNode>& out, BvhStats& stats, uint32_t threads) {
    const size_t first = out.size();
    out.resize(first + nodes.size());
    forEachChunk(nodes.size(), threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const BuildNode& n = nodes[i];
            BvhNode& node = out[first + i];
            node.boundsMin =
                vec3(padBelow(n.bounds.lo.x), padBelow(n.bounds.lo.y), padBelow(n.bounds.lo.z));
            node.boundsMax =
                vec3(padAbove(n.bounds.hi.x), padAbove(n.bounds.hi.y), padAbove(n.bounds.hi.z));
            node.count = n.count;
            node.offset = n.count == 0 ? n.offset + nodeBase : n.offset + primitiveBase;
        }
    });
    // Depth and leaf statistics: nodes are in preorder, so a node's depth is
    // known when it is reached.
    std::vector<uint32_t> depth(nodes.size(), 0);
    for (size_t i = 0; i < nodes.size(); ++i) {
        const BuildNode& n = nodes[i];
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

std::optional<uint64_t> predictedTraversalFeatures(const scene::Scene& scene,
                                                   const BvhOptions& options) {
    // The scene's tree holds the meshes that are not instanced, the spheres
    // and an instance primitive per instance; an object's tree at least its
    // largest mesh.
    uint64_t sceneTree = scene.spheres.size() + scene.instances.size(), largestObject = 0;
    for (const scene::Mesh& mesh : scene.meshes)
        if (mesh.instanced)
            largestObject = std::max<uint64_t>(largestObject, mesh.triangles.size());
        else
            sceneTree += mesh.triangles.size();
    const uint64_t shallowMost = uint64_t(options.maxLeafSize) << VKP_BVH_SHALLOW_DEPTH;
    if (std::max(sceneTree, largestObject) <= shallowMost) return std::nullopt;
    return VKP_FEATURE_DEEP_BVH | (scene.instances.empty() ? 0u : VKP_FEATURE_INSTANCES);
}

BvhBuild buildBvh(const scene::Scene& scene, const BvhOptions& options) {
    validate(options);
    const auto start = std::chrono::steady_clock::now();
    BvhBuild result;
    const std::vector<uint64_t> firstIds = firstTriangleIds(scene);
    BuildPrimitives primitives = collectPrimitives(scene, firstIds, result.stats);

    // ---- the objects: one tree per distinct range of instanced meshes ------------
    struct Object {
        BuildPrimitives primitives;
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
            object.nodes = buildTree(options, object.primitives.items);
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
        primitives.add(box, {VKP_PRIMITIVE_INSTANCE, uint32_t(instances.size()), it->second, i});
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
    std::vector<BuildNode> sceneNodes = buildTree(options, primitives.items);
    if (sceneNodes.empty()) {
        result.nodes.push_back(BvhNode{vec3(0.0f), 0u, vec3(0.0f), 0u});  // the empty tree
        result.stats.nodes = 1;
    } else {
        appendNodes(sceneNodes, 0, 0, result.nodes, result.stats, options.threads);
    }
    std::vector<BuildNode>().swap(sceneNodes);
    result.sceneTreeNodes = uint32_t(result.nodes.size());

    // ---- the primitives, before the nodes are packed: the builder's arrays go first,
    // since a large scene's peak memory is near --------------------------------------
    result.primitives.resize(total);
    forEachChunk(primitives.size(), options.threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i)
            if (primitives.origin(i).kind != VKP_PRIMITIVE_INSTANCE)
                result.primitives[i] = flattenPrimitive(scene, primitives.origin(i));
    });
    struct Placement {
        size_t primitive;  // its index in the scene's tree
        PrimitiveOrigin origin;
        Aabb bounds;
    };
    std::vector<Placement> placements;
    for (size_t i = 0; i < primitives.size(); ++i)
        if (primitives.origin(i).kind == VKP_PRIMITIVE_INSTANCE)
            placements.push_back({i, primitives.origin(i), primitives.items[i].bounds()});
    const auto sceneTreePrimitives = uint32_t(primitives.size());
    primitives = BuildPrimitives{};
    std::vector<uint32_t> objectPrimitives;
    size_t next = sceneTreePrimitives;
    for (Object& object : objects) {
        objectPrimitives.push_back(uint32_t(object.primitives.size()));
        for (size_t i = 0; i < object.primitives.size(); ++i)
            result.primitives[next++] = flattenPrimitive(scene, object.primitives.origin(i));
        object.primitives = BuildPrimitives{};
    }

    // ---- the nodes, packed: the scene's tree, then each object's ------------------------
    result.traversalNodes = packTraversalNodes(result.nodes);
    uint32_t nextPrimitive = sceneTreePrimitives;
    for (size_t o = 0; o < objects.size(); ++o) {
        const Object& object = objects[o];
        ObjectTree tree;
        tree.rootNode = uint32_t(result.nodes.size());
        tree.firstPrimitive = nextPrimitive;
        tree.primitiveCount = objectPrimitives[o];
        if (!object.nodes.empty()) {
            // Packed with leaf ranges in the whole array and interior offsets in its own.
            std::vector<BvhNode> local;
            BvhStats ignored;
            appendNodes(object.nodes, 0, nextPrimitive, local, ignored, options.threads);
            tree.rootTexel = uint32_t(result.traversalNodes.size());
            const std::vector<glm::uvec4> texels = packTraversalNodes(local, tree.rootTexel);
            result.traversalNodes.insert(result.traversalNodes.end(), texels.begin(), texels.end());
            appendNodes(object.nodes, tree.rootNode, nextPrimitive, result.nodes, result.stats,
                        options.threads);
        }
        nextPrimitive += tree.primitiveCount;
        result.objects.push_back(tree);
    }
    for (const auto& [key, index] : objectOf) {
        result.objects[index].firstMesh = key.first;
        result.objects[index].meshCount = key.second;
    }

    // ---- the instance primitives, and their records after the nodes ---------------------
    const auto firstRecord = uint32_t(result.traversalNodes.size());
    for (const Placement& placement : placements) {
        const PrimitiveOrigin& p = placement.origin;
        BvhPrimitive& out = result.primitives[placement.primitive];
        out = BvhPrimitive{};
        out.kind = VKP_PRIMITIVE_INSTANCE;
        out.id = firstRecord + VKP_INSTANCE_RECORD_TEXELS * p.id;
        out.material = result.objects[p.source].rootTexel;
        out.p0 = vec3(float(p.source), 0.0f, 0.0f);
        out.p1 = placement.bounds.lo;
        out.p2 = placement.bounds.hi;
    }
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
