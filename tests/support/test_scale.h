// How many samples, rays or repetitions a test uses: the CI count by default,
// the count its issue asks for under `make test-long` (VKPATH_TEST_LONG=1).
// Every test with two counts lists both, and why the CI one still has power,
// in docs/ACCURACY.md.
#pragma once

#include <cstdlib>
#include <string_view>

namespace vkpath::test {

inline bool longTests() {
    const char* value = std::getenv("VKPATH_TEST_LONG");
    return value != nullptr && std::string_view(value) != "" && std::string_view(value) != "0";
}

template <typename T>
T ciOrLong(T ciCount, T longCount) {
    return longTests() ? longCount : ciCount;
}

}  // namespace vkpath::test
