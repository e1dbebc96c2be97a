// At each node the primitive centroids are sorted into equal-width bins along
// each axis, a sweep over the bins evaluates the surface area heuristic at
// every bin boundary, and the cheapest split (or a leaf) wins; a node of a
// few primitives is swept at every position instead.
//
// Subtrees are built on other threads near the root; each builds its nodes in
// depth-first order into a vector of its own, and the parent appends it, so
// the result is the serial build's bit for bit.
#include "bvh/sah_builder.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <future>
#include <stdexcept>
#include <thread>

namespace vkpath::bvh {

namespace {

Float4 min4(Float4 a, Float4 b) {
    return a < b ? a : b;
}

Float4 max4(Float4 a, Float4 b) {
    return a > b ? a : b;
}

// The lower corner without the origin's bits, so that lane is 0 like the
// upper corner's.
Float4 lowerCorner(const BuildPrimitive& p) {
    const Int4 xyz{-1, -1, -1, 0};
    return std::bit_cast<Float4>(std::bit_cast<Int4>(p.lo) & xyz);
}

Aabb toAabb(Float4 lo, Float4 hi) {
    return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
}

uint32_t ceilLog2(size_t n) {
    return n <= 1 ? 0u : static_cast<uint32_t>(std::bit_width(n - 1));
}

// A range of primitives' box and the box of their centroids.
struct RangeBounds {
    Float4 lo{BUILD_INF, BUILD_INF, BUILD_INF, 0.0f};
    Float4 hi{-BUILD_INF, -BUILD_INF, -BUILD_INF, 0.0f};
    Float4 centroidLo{BUILD_INF, BUILD_INF, BUILD_INF, 0.0f};
    Float4 centroidHi{-BUILD_INF, -BUILD_INF, -BUILD_INF, 0.0f};

    void grow(const BuildPrimitive& p) {
        const Float4 lower = lowerCorner(p);
        lo = min4(lo, lower);
        hi = max4(hi, p.hi);
        const Float4 c = (lower + p.hi) * 0.5f;
        centroidLo = min4(centroidLo, c);
        centroidHi = max4(centroidHi, c);
    }
    Aabb bounds() const { return toAabb(lo, hi); }
    Aabb centroids() const { return toAabb(centroidLo, centroidHi); }
};

RangeBounds boundsOf(const BuildPrimitive* first, const BuildPrimitive* last) {
    RangeBounds r;
    for (const BuildPrimitive* p = first; p != last; ++p) r.grow(*p);
    return r;
}

// Builds over the primitives themselves, partitioning them in place: each
// level of the tree then reads them sequentially (a permuted index array
// would make every read a cache miss on large meshes). A level reads each
// primitive twice, to bin it and to partition it; the partition also bounds
// both children, so no level reads them a third time.
class Builder {
  public:
    Builder(const BvhOptions& options, std::vector<BuildPrimitive>& primitives)
        : m_options(options), m_primitives(primitives) {
        uint32_t threads = options.threads ? options.threads : std::thread::hardware_concurrency();
        threads = std::max(threads, 1u);
        // Two subtrees per thread near the root balance uneven splits a little.
        m_spawnDepth = threads > 1 ? ceilLog2(threads) + 1 : 0;
    }

    // Builds the subtree over m_primitives[begin, end), whose bounds are
    // `range`, into `out`, depth-first.
    void build(uint32_t begin, uint32_t end, uint32_t depth, const RangeBounds& range,
               std::vector<BuildNode>& out) const {
        const size_t nodeIndex = out.size();
        out.push_back(BuildNode{range.bounds()});

        RangeBounds children[2];
        const uint32_t mid = split(begin, end, depth, range, children);
        if (mid == 0) {
            out[nodeIndex].offset = begin;
            out[nodeIndex].count = end - begin;
            return;
        }
        if (depth < m_spawnDepth && end - begin >= m_options.parallelThreshold) {
            auto second = std::async(std::launch::async, [this, mid, end, depth, &children] {
                std::vector<BuildNode> nodes;
                build(mid, end, depth + 1, children[1], nodes);
                return nodes;
            });
            build(begin, mid, depth + 1, children[0], out);
            std::vector<BuildNode> nodes = second.get();
            const auto base = static_cast<uint32_t>(out.size());
            out[nodeIndex].offset = base;
            for (BuildNode& node : nodes) {
                if (node.count == 0) node.offset += base;
                out.push_back(node);
            }
        } else {
            build(begin, mid, depth + 1, children[0], out);
            out[nodeIndex].offset = static_cast<uint32_t>(out.size());
            build(mid, end, depth + 1, children[1], out);
        }
    }

  private:
    static constexpr uint32_t MAX_BINS = 256;
    // Nodes of at most this many primitives are split by sweepSplit
    // (docs/BENCHMARKS.md, "BVH build").
    static constexpr uint32_t SWEEP_MAX = 8;

    // Plain data, so that a call initialises only the bins it uses.
    struct Bin {
        Float4 lo, hi;
    };

    // Partitions m_primitives[begin, end), returns where the second child
    // starts and sets both children's bounds, or returns 0 to make a leaf.
    uint32_t split(uint32_t begin, uint32_t end, uint32_t depth, const RangeBounds& range,
                   RangeBounds children[2]) const {
        const uint32_t n = end - begin;
        if (n == 1) return 0;
        const bool mustSplit = n > m_options.maxLeafSize;
        const uint32_t binCount = m_options.binCount;

        // An axis along which the centroids do not spread is not split
        // along: it bins them all into bin 0 (scale 0), and its sweep is
        // skipped.
        const Float4 extent = range.centroidHi - range.centroidLo;
        Float4 scale{};
        std::array<bool, 3> usable{};
        for (int axis = 0; axis < 3; ++axis) {
            scale[axis] = static_cast<float>(binCount) / extent[axis];
            usable[axis] = extent[axis] > 0.0f && std::isfinite(scale[axis]);
            if (!usable[axis]) scale[axis] = 0.0f;
        }
        if (!usable[0] && !usable[1] && !usable[2]) {
            // Every centroid in one point: no plane separates them.
            return mustSplit ? medianSplit(begin, end, range, children) : 0;
        }
        if (n <= SWEEP_MAX) return sweepSplit(begin, end, depth, range, usable, children);

        // ---- bin the centroids along all three axes in one pass ---------------
        Bin bins[3][MAX_BINS];
        uint32_t counts[3][MAX_BINS];
        const Float4 empty = RangeBounds{}.lo;
        for (int axis = 0; axis < 3; ++axis)
            for (uint32_t b = 0; b < binCount; ++b) {
                bins[axis][b] = Bin{empty, -empty};
                counts[axis][b] = 0;
            }
        const Int4 lastBin = Int4{} + int32_t(binCount - 1);
        const BuildPrimitive* const first = m_primitives.data() + begin;
        const BuildPrimitive* const last = m_primitives.data() + end;
        for (const BuildPrimitive* p = first; p != last; ++p) {
            const Float4 lower = lowerCorner(*p);
            const Float4 c = (lower + p->hi) * 0.5f;
            const Int4 raw = __builtin_convertvector((c - range.centroidLo) * scale, Int4);
            const Int4 bin = raw < lastBin ? raw : lastBin;
            for (int axis = 0; axis < 3; ++axis) {
                Bin& b = bins[axis][bin[axis]];
                b.lo = min4(b.lo, lower);
                b.hi = max4(b.hi, p->hi);
                ++counts[axis][bin[axis]];
            }
        }

        // ---- the SAH sweep over each axis's bin boundaries --------------------
        const float nodeArea = range.bounds().halfArea();
        float bestCost = BUILD_INF;
        int bestAxis = -1;
        uint32_t bestBin = 0;  // bins 0..bestBin go to the first child
        uint32_t bestFirstCount = 0;
        std::array<float, MAX_BINS> secondArea;
        std::array<uint32_t, MAX_BINS> secondCount;
        std::array<uint32_t, MAX_BINS> usedBins;
        for (int axis = 0; axis < 3; ++axis) {
            if (!usable[axis]) continue;
            // Only boundaries after a non-empty bin give distinct partitions, so
            // sweep over those.
            uint32_t used = 0;
            for (uint32_t b = 0; b < binCount; ++b)
                if (counts[axis][b]) usedBins[used++] = b;
            Float4 lo = empty, hi = -empty;
            uint32_t count = 0;
            for (uint32_t k = used - 1; k > 0; --k) {
                lo = min4(lo, bins[axis][usedBins[k]].lo);
                hi = max4(hi, bins[axis][usedBins[k]].hi);
                count += counts[axis][usedBins[k]];
                secondArea[k - 1] = toAabb(lo, hi).halfArea();
                secondCount[k - 1] = count;
            }
            lo = empty;
            hi = -empty;
            count = 0;
            for (uint32_t k = 0; k + 1 < used; ++k) {
                lo = min4(lo, bins[axis][usedBins[k]].lo);
                hi = max4(hi, bins[axis][usedBins[k]].hi);
                count += counts[axis][usedBins[k]];
                const float areas = toAabb(lo, hi).halfArea() * static_cast<float>(count) +
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
        if (bestAxis < 0) return mustSplit ? medianSplit(begin, end, range, children) : 0;
        if (!mustSplit && static_cast<float>(n) <= bestCost) return 0;
        if (!withinDepth(depth, n, bestFirstCount)) return medianSplit(begin, end, range, children);

        // The same bin as above, computed the same way, for the chosen axis.
        const float axisLo = range.centroidLo[bestAxis], axisScale = scale[bestAxis];
        const int32_t lastBinIndex = int32_t(binCount - 1);
        const auto inFirst = [&](const BuildPrimitive& p) {
            const float c = (lowerCorner(p)[bestAxis] + p.hi[bestAxis]) * 0.5f;
            const int32_t raw = static_cast<int32_t>((c - axisLo) * axisScale);
            return std::min(raw, lastBinIndex) <= int32_t(bestBin);
        };
        return begin + partition(begin, end, inFirst, children);
    }

    // The depth guard: both children must still fit below maxDepth with
    // halving splits (which preserve depth + ceilLog2(n) <= maxDepth).
    bool withinDepth(uint32_t depth, uint32_t n, uint32_t firstCount) const {
        const uint32_t larger = std::max(firstCount, n - firstCount);
        return depth + 1 + ceilLog2(larger) <= m_options.maxDepth;
    }

    // A small node's split: the SAH at every position of its primitives'
    // order by centroid along each axis (ties by origin), which costs less
    // than initialising and sweeping bins and finds the best object split.
    uint32_t sweepSplit(uint32_t begin, uint32_t end, uint32_t depth, const RangeBounds& range,
                        const std::array<bool, 3>& usable, RangeBounds children[2]) const {
        const uint32_t n = end - begin;
        BuildPrimitive* const first = m_primitives.data() + begin;
        const float nodeArea = range.bounds().halfArea();
        std::array<std::array<uint8_t, SWEEP_MAX>, 3> order;
        std::array<float, SWEEP_MAX> secondArea;
        std::array<Float4, SWEEP_MAX> centroid;
        for (uint32_t i = 0; i < n; ++i) centroid[i] = first[i].centroid();
        float bestCost = BUILD_INF;
        int bestAxis = -1;
        uint32_t bestCount = 0;  // the first child's primitives
        for (int axis = 0; axis < 3; ++axis) {
            if (!usable[axis]) continue;
            auto& o = order[axis];
            const auto before = [&](uint8_t a, uint8_t b) {
                const float ca = centroid[a][axis], cb = centroid[b][axis];
                return ca != cb ? ca < cb : first[a].origin() < first[b].origin();
            };
            for (uint32_t i = 0; i < n; ++i) {  // insertion sort: n is small
                uint32_t j = i;
                for (; j > 0 && before(uint8_t(i), o[j - 1]); --j) o[j] = o[j - 1];
                o[j] = uint8_t(i);
            }
            Float4 lo = RangeBounds{}.lo, hi = -lo;
            for (uint32_t k = n - 1; k > 0; --k) {
                lo = min4(lo, lowerCorner(first[o[k]]));
                hi = max4(hi, first[o[k]].hi);
                secondArea[k] = toAabb(lo, hi).halfArea();  // of o[k..n)
            }
            lo = RangeBounds{}.lo;
            hi = -lo;
            for (uint32_t k = 1; k < n; ++k) {
                lo = min4(lo, lowerCorner(first[o[k - 1]]));
                hi = max4(hi, first[o[k - 1]].hi);
                const float areas = toAabb(lo, hi).halfArea() * static_cast<float>(k) +
                                    secondArea[k] * static_cast<float>(n - k);
                const float cost = m_options.traversalCost +
                                   (nodeArea > 0.0f ? areas / nodeArea : static_cast<float>(n));
                if (cost < bestCost) {
                    bestCost = cost;
                    bestAxis = axis;
                    bestCount = k;
                }
            }
        }
        if (n <= m_options.maxLeafSize && static_cast<float>(n) <= bestCost) return 0;
        if (!withinDepth(depth, n, bestCount)) return medianSplit(begin, end, range, children);

        std::array<BuildPrimitive, SWEEP_MAX> sorted;
        for (uint32_t i = 0; i < n; ++i) sorted[i] = first[order[bestAxis][i]];
        std::copy_n(sorted.begin(), n, first);
        children[0] = boundsOf(first, first + bestCount);
        children[1] = boundsOf(first + bestCount, first + n);
        return begin + bestCount;
    }

    // Moves the primitives of [begin, end) for which `inFirst` holds before
    // the others (Hoare's scheme: each is read once and moved at most once)
    // and bounds both sides; returns the first side's size.
    template <typename Predicate>
    uint32_t partition(uint32_t begin, uint32_t end, const Predicate& inFirst,
                       RangeBounds children[2]) const {
        BuildPrimitive* i = m_primitives.data() + begin;
        BuildPrimitive* j = m_primitives.data() + end;
        RangeBounds firstSide, secondSide;
        for (;;) {
            while (i != j && inFirst(*i)) firstSide.grow(*i++);
            while (i != j && !inFirst(*(j - 1))) secondSide.grow(*--j);
            if (i == j) break;
            // *i belongs second, *(j - 1) first.
            std::swap(*i, *--j);
            firstSide.grow(*i++);
            secondSide.grow(*j);
        }
        children[0] = firstSide;
        children[1] = secondSide;
        return static_cast<uint32_t>(i - (m_primitives.data() + begin));
    }

    // Halves the range at the median centroid of the widest axis, ties broken
    // by origin, which is unique, so the order is fully determined.
    uint32_t medianSplit(uint32_t begin, uint32_t end, const RangeBounds& range,
                         RangeBounds children[2]) const {
        const Float4 extent = range.centroidHi - range.centroidLo;
        const int axis = extent[0] >= extent[1] ? (extent[0] >= extent[2] ? 0 : 2)
                                                : (extent[1] >= extent[2] ? 1 : 2);
        BuildPrimitive* const first = m_primitives.data() + begin;
        BuildPrimitive* const last = m_primitives.data() + end;
        BuildPrimitive* const mid = first + (end - begin) / 2;
        std::nth_element(first, mid, last, [&](const BuildPrimitive& a, const BuildPrimitive& b) {
            const float ca = a.centroid()[axis], cb = b.centroid()[axis];
            return ca != cb ? ca < cb : a.origin() < b.origin();
        });
        children[0] = boundsOf(first, mid);
        children[1] = boundsOf(mid, last);
        return static_cast<uint32_t>(mid - m_primitives.data());
    }

    const BvhOptions& m_options;
    std::vector<BuildPrimitive>& m_primitives;
    uint32_t m_spawnDepth = 0;
};

}  // namespace

std::vector<BuildNode> buildTree(const BvhOptions& options,
                                 std::vector<BuildPrimitive>& primitives) {
    std::vector<BuildNode> nodes;
    if (primitives.empty()) return nodes;
    if (ceilLog2(primitives.size()) > options.maxDepth)
        throw std::invalid_argument(fmt::format("BVH: {} primitives cannot fit below maxDepth {}",
                                                primitives.size(), options.maxDepth));
    nodes.reserve(2 * primitives.size());
    Builder(options, primitives)
        .build(0, static_cast<uint32_t>(primitives.size()), 0,
               boundsOf(primitives.data(), primitives.data() + primitives.size()), nodes);
    return nodes;
}

}  // namespace vkpath::bvh
