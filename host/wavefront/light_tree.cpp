#include "wavefront/light_tree.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <glm/glm.hpp>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace vkpath::wavefront {
namespace {

constexpr double PI = std::numbers::pi;
constexpr int BINS = 12;

// A cone of directions: unit axis and the cosine of its half-angle.
struct Cone {
    glm::dvec3 axis{0, 0, 1};
    double cosTheta = 1;
};

Cone entireSphere() {
    return {{0, 0, 1}, -1};
}

// The angle between unit vectors, accurate near 0 and pi.
double angleBetween(glm::dvec3 a, glm::dvec3 b) {
    if (glm::dot(a, b) < 0) return PI - 2 * std::asin(std::min(1.0, glm::length(a + b) / 2));
    return 2 * std::asin(std::min(1.0, glm::length(b - a) / 2));
}

// v rotated by `angle` about the unit axis k (Rodrigues).
glm::dvec3 rotate(glm::dvec3 v, glm::dvec3 k, double angle) {
    return v * std::cos(angle) + glm::cross(k, v) * std::sin(angle) +
           k * glm::dot(k, v) * (1 - std::cos(angle));
}

// The least cone holding both (pbrt-v4, section 3.8.4, "Bounding directions").
Cone unite(const Cone& a, const Cone& b) {
    const double thetaA = std::acos(std::clamp(a.cosTheta, -1.0, 1.0));
    const double thetaB = std::acos(std::clamp(b.cosTheta, -1.0, 1.0));
    const double thetaD = angleBetween(a.axis, b.axis);
    if (std::min(thetaD + thetaB, PI) <= thetaA) return a;
    if (std::min(thetaD + thetaA, PI) <= thetaB) return b;
    const double theta = (thetaA + thetaD + thetaB) / 2;
    if (theta >= PI) return entireSphere();
    const glm::dvec3 k = glm::cross(a.axis, b.axis);
    if (glm::dot(k, k) == 0) return entireSphere();
    return {glm::normalize(rotate(a.axis, glm::normalize(k), theta - thetaA)), std::cos(theta)};
}

// What a node bounds, in double.
struct Bounds {
    glm::dvec3 lo{std::numeric_limits<double>::infinity()};
    glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
    double power = 0;
    Cone normals;
    double cosEmission = 1;
    bool twoSided = false;
    // Triangles of one normal (normals.axis, exactly): their least dot(x, axis).
    bool planar = false;
    double frontPlane = 0;
    bool empty = true;

    glm::dvec3 centroid() const { return (lo + hi) / 2.0; }
    glm::dvec3 diagonal() const { return hi - lo; }
    double surfaceArea() const {
        const glm::dvec3 d = diagonal();
        return 2 * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
};

Bounds unite(const Bounds& a, const Bounds& b) {
    if (a.empty) return b;
    if (b.empty) return a;
    Bounds u;
    u.lo = glm::min(a.lo, b.lo);
    u.hi = glm::max(a.hi, b.hi);
    u.power = a.power + b.power;
    u.normals = unite(a.normals, b.normals);
    u.cosEmission = std::min(a.cosEmission, b.cosEmission);
    u.twoSided = a.twoSided || b.twoSided;
    u.planar = a.planar && b.planar && a.normals.axis == b.normals.axis;
    u.frontPlane = std::min(a.frontPlane, b.frontPlane);
    u.empty = false;
    return u;
}

// A bounded light's box, normals and reach (shared/lights.h's records).
Bounds lightBounds(const shared::Light& light, double power) {
    Bounds b;
    b.empty = false;
    b.power = power;
    const glm::dvec3 p0(light.p0);
    switch (light.type) {
        case VKP_LIGHT_TRIANGLE:  // front face only, cosine falloff to pi/2
            b.lo = glm::min(p0, glm::min(glm::dvec3(light.p1), glm::dvec3(light.p2)));
            b.hi = glm::max(p0, glm::max(glm::dvec3(light.p1), glm::dvec3(light.p2)));
            // (the host's unit normal: the same float vector for every
            // triangle of a plane whose cross products agree)
            b.normals = {glm::dvec3(light.normal), 1};
            b.cosEmission = 0;
            b.planar = true;
            b.frontPlane = std::min({glm::dot(p0, b.normals.axis),
                                     glm::dot(glm::dvec3(light.p1), b.normals.axis),
                                     glm::dot(glm::dvec3(light.p2), b.normals.axis)});
            break;
        case VKP_LIGHT_SPHERE:  // normals every way
            b.lo = p0 - double(light.radius);
            b.hi = p0 + double(light.radius);
            b.normals = entireSphere();
            b.cosEmission = 0;
            break;
        case VKP_LIGHT_POINT:
            b.lo = b.hi = p0;
            b.normals = entireSphere();
            b.cosEmission = 0;
            break;
        case VKP_LIGHT_SPOT: {  // full inside the inner cone, nothing past the outer one
            b.lo = b.hi = p0;
            const double inner = std::acos(std::clamp(double(light.cosInner), -1.0, 1.0));
            const double outer = std::acos(std::clamp(double(light.cosOuter), -1.0, 1.0));
            b.normals = {glm::normalize(glm::dvec3(light.p1)), std::cos(inner)};
            b.cosEmission = std::cos(std::max(outer - inner, 0.0));
            break;
        }
        default:
            throw std::logic_error("buildLightTree: a light at infinity has no bounds");
    }
    return b;
}

// Conty Estevez and Kulla's cost of a node (HPG 2018, equations 1 and 2):
// power x the measure of its emission's directions x its box's surface
// area, with the box's aspect ratio along the split axis `axis`.
double cost(const Bounds& b, int axis) {
    const double thetaO = std::acos(std::clamp(b.normals.cosTheta, -1.0, 1.0));
    const double thetaE = std::acos(std::clamp(b.cosEmission, -1.0, 1.0));
    const double thetaW = std::min(thetaO + thetaE, PI);
    const double sinO = std::sin(thetaO);
    const double mOmega =
        2 * PI * (1 - std::cos(thetaO)) + PI / 2 *
                                              (2 * thetaW * sinO - std::cos(thetaO - 2 * thetaW) -
                                               2 * thetaO * sinO + std::cos(thetaO));
    const glm::dvec3 d = b.diagonal();
    const double longest = std::max({d.x, d.y, d.z});
    const double aspect = d[axis] > 0 ? longest / d[axis] : 1.0;
    return b.power * mOmega * aspect * b.surfaceArea();
}

// Floats that hold the double: rounded outward.
float below(double x) {
    float f = float(x);
    return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float above(double x) {
    float f = float(x);
    return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

shared::LightTreeNode toNode(const Bounds& b) {
    shared::LightTreeNode n{};
    n.boundsMin = glm::vec3(below(b.lo.x), below(b.lo.y), below(b.lo.z));
    n.boundsMax = glm::vec3(above(b.hi.x), above(b.hi.y), above(b.hi.z));
    n.power = float(b.power);
    n.axis = glm::vec3(b.normals.axis);
    // Widened by 1e-6 beyond the float rounding of the kernels' angles,
    // so that a light is never judged unable to reach a point it reaches.
    n.cosNormals = float(std::max(-1.0, b.normals.cosTheta - 1e-6));
    n.cosEmission = float(std::max(-1.0, b.cosEmission - 1e-6));
    n.flags = b.twoSided ? VKP_LIGHT_NODE_TWO_SIDED : 0u;
    if (b.planar) {
        n.flags |= VKP_LIGHT_NODE_PLANAR;
        n.frontPlane = below(b.frontPlane);
    }
    return n;
}

struct Item {
    uint32_t light;
    Bounds bounds;
};

class Builder {
  public:
    explicit Builder(LightTree& tree) : m_tree(tree) {}

    // Appends the subtree of items [first, last) at `depth`, whose path is `trail`.
    void build(Item* first, Item* last, uint32_t depth, uint32_t trail) {
        m_tree.depth = std::max(m_tree.depth, depth);
        Bounds all;
        for (const Item* i = first; i != last; ++i) all = unite(all, i->bounds);
        const size_t at = m_tree.nodes.size();
        m_tree.nodes.push_back(toNode(all));
        const size_t count = size_t(last - first);
        if (count == 1) {
            m_tree.nodes[at].index = first->light;
            m_tree.nodes[at].flags |= VKP_LIGHT_NODE_LEAF;
            m_tree.trails[first->light] = trail;
            return;
        }
        Item* middle = split(first, last, depth);
        build(first, middle, depth + 1, trail);
        m_tree.nodes[at].index = uint32_t(m_tree.nodes.size());
        build(middle, last, depth + 1, trail | (1u << depth));
    }

  private:
    // Where [first, last) splits: the least cost over each axis' bins, or by
    // count where the centroids coincide or the depth left is short.
    Item* split(Item* first, Item* last, uint32_t depth) {
        const size_t count = size_t(last - first);
        Bounds centroids;
        for (const Item* i = first; i != last; ++i) {
            const glm::dvec3 c = i->bounds.centroid();
            centroids.lo = glm::min(centroids.lo, c);
            centroids.hi = glm::max(centroids.hi, c);
        }
        const glm::dvec3 extent = centroids.hi - centroids.lo;
        const int widest = extent.x >= extent.y && extent.x >= extent.z ? 0
                           : extent.y >= extent.z                       ? 1
                                                                        : 2;
        const auto byCount = [&] {
            Item* middle = first + count / 2;
            std::nth_element(first, middle, last, [&](const Item& a, const Item& b) {
                return a.bounds.centroid()[widest] < b.bounds.centroid()[widest];
            });
            return middle;
        };
        // Leaves at depth <= VKP_LIGHT_TREE_MAX_DEPTH: halving from here reaches it.
        const uint32_t halvings = uint32_t(std::bit_width(count - 1));
        if (depth + halvings >= VKP_LIGHT_TREE_MAX_DEPTH || !(extent[widest] > 0)) return byCount();

        double best = std::numeric_limits<double>::infinity();
        int bestAxis = -1, bestBin = 0;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > 0)) continue;
            std::array<Bounds, BINS> bins;
            for (const Item* i = first; i != last; ++i)
                bins[binOf(*i, centroids, axis)] =
                    unite(bins[binOf(*i, centroids, axis)], i->bounds);
            for (int b = 1; b < BINS; ++b) {
                Bounds lower, upper;
                for (int j = 0; j < b; ++j) lower = unite(lower, bins[j]);
                for (int j = b; j < BINS; ++j) upper = unite(upper, bins[j]);
                if (lower.empty || upper.empty) continue;
                const double c = cost(lower, axis) + cost(upper, axis);
                if (c < best) {
                    best = c;
                    bestAxis = axis;
                    bestBin = b;
                }
            }
        }
        if (bestAxis < 0) return byCount();
        Item* middle = std::partition(
            first, last, [&](const Item& i) { return binOf(i, centroids, bestAxis) < bestBin; });
        return middle == first || middle == last ? byCount() : middle;
    }

    static int binOf(const Item& item, const Bounds& centroids, int axis) {
        const double t = (item.bounds.centroid()[axis] - centroids.lo[axis]) /
                         (centroids.hi[axis] - centroids.lo[axis]);
        return std::clamp(int(t * BINS), 0, BINS - 1);
    }

    LightTree& m_tree;
};

}  // namespace

LightTree buildLightTree(std::span<const shared::Light> lights, std::span<const double> power) {
    LightTree tree;
    std::vector<Item> items;
    for (uint32_t i = 0; i < lights.size(); ++i)
        if (power[i] > 0 && std::isfinite(power[i]))
            items.push_back({i, lightBounds(lights[i], power[i])});
    if (items.size() < 2) return tree;
    tree.trails.assign(lights.size(), VKP_NO_LIGHT);
    tree.nodes.reserve(2 * items.size() - 1);
    Builder(tree).build(items.data(), items.data() + items.size(), 0, 0);
    return tree;
}

}  // namespace vkpath::wavefront
