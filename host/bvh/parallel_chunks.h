// Runs a loop over [0, count) as contiguous chunks on several threads, for
// the BVH's per-node and per-primitive passes, whose elements are
// independent: the result is the same for any number of threads.
//
//   forEachChunk(nodes.size(), 0, [&](size_t begin, size_t end) { ... });
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <future>
#include <thread>
#include <vector>

namespace vkpath::bvh {

// Calls fn(begin, end) on chunks that cover [0, count), one per thread
// (`threads`, or every hardware thread for 0), the first on the calling
// thread; a loop under `minChunk` elements a thread stays on one. An
// exception thrown by a chunk reaches the caller once all have ended.
template <typename F>
void forEachChunk(size_t count, uint32_t threads, const F& fn, size_t minChunk = 1u << 16) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    const size_t chunks = std::clamp<size_t>(count / std::max<size_t>(minChunk, 1), 1, threads);
    if (chunks == 1) {
        fn(size_t(0), count);
        return;
    }
    std::vector<std::future<void>> others;
    const auto bound = [&](size_t c) { return count * c / chunks; };
    for (size_t c = 1; c < chunks; ++c)
        others.push_back(std::async(
            std::launch::async, [&fn, begin = bound(c), end = bound(c + 1)] { fn(begin, end); }));
    std::exception_ptr failure;
    try {
        fn(size_t(0), bound(1));
    } catch (...) {
        failure = std::current_exception();
    }
    for (std::future<void>& other : others) {
        try {
            other.get();
        } catch (...) {
            if (!failure) failure = std::current_exception();
        }
    }
    if (failure) std::rethrow_exception(failure);
}

}  // namespace vkpath::bvh
