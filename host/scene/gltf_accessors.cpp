#include "scene/gltf_accessors.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "input_error.h"

namespace vkpath::scene::gltf {
namespace {

constexpr size_t MAX_ACCESSOR_COUNT = size_t(1) << 25;  // elements per accessor
// An accessor without a bufferView is all zeros (or sparse substitutions):
// a few bytes of JSON must not allocate gigabytes.
constexpr size_t MAX_ZERO_ACCESSOR_COUNT = size_t(1) << 20;

const char* typeName(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return "SCALAR";
        case TINYGLTF_TYPE_VEC2:
            return "VEC2";
        case TINYGLTF_TYPE_VEC3:
            return "VEC3";
        case TINYGLTF_TYPE_VEC4:
            return "VEC4";
        case TINYGLTF_TYPE_MAT2:
            return "MAT2";
        case TINYGLTF_TYPE_MAT3:
            return "MAT3";
        case TINYGLTF_TYPE_MAT4:
            return "MAT4";
        default:
            return "unknown";
    }
}

// Bytes per component; 0 for a type glTF 2.0 does not allow.
size_t componentSize(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
    }
}

size_t componentCount(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        case TINYGLTF_TYPE_MAT2:
            return 4;
        case TINYGLTF_TYPE_MAT3:
            return 9;
        case TINYGLTF_TYPE_MAT4:
            return 16;
        default:
            return 0;
    }
}

const char* componentTypeName(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return "BYTE";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return "UNSIGNED_BYTE";
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return "SHORT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return "UNSIGNED_SHORT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return "UNSIGNED_INT";
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return "FLOAT";
        default:
            return "unknown";
    }
}

// "a", "a or b", "a, b or c".
std::string alternatives(const std::vector<std::string>& names) {
    std::string out;
    for (size_t i = 0; i < names.size(); ++i)
        out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return out;
}

// One component, little-endian as glTF stores it (and as this host is).
// Normalized integers as glTF 2.0 3.11 defines them: unsigned c / (2^n - 1),
// signed max(c / (2^(n-1) - 1), -1), so that both ends of the range are exact.
float componentValue(const uint8_t* bytes, const Encoding& encoding) {
    auto read = [&](auto value) {
        std::memcpy(&value, bytes, sizeof(value));
        return value;
    };
    const bool n = encoding.normalized;
    switch (encoding.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return read(float(0));
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const float c = read(int8_t(0));
            return n ? std::max(c / 127.0f, -1.0f) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
            const float c = read(uint8_t(0));
            return n ? c / 255.0f : c;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            const float c = read(int16_t(0));
            return n ? std::max(c / 32767.0f, -1.0f) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            const float c = read(uint16_t(0));
            return n ? c / 65535.0f : c;
        }
        default: {  // UNSIGNED_INT: no vertex attribute allows it
            const double c = read(uint32_t(0));
            return float(n ? c / 4294967295.0 : c);
        }
    }
}

}  // namespace

std::string encodingName(const Encoding& e) {
    return fmt::format("{}{}", e.normalized ? "normalized " : "",
                       componentTypeName(e.componentType));
}

std::string formatName(const AttributeFormat& format) {
    std::vector<std::string> encodings, types;
    for (const Encoding& e : format.encodings) encodings.push_back(encodingName(e));
    for (int type : format.types) types.push_back(typeName(type));
    return alternatives(encodings) + " " + alternatives(types);
}

template <typename... Args>
void Accessors::fail(fmt::format_string<Args...> format, Args&&... args) const {
    throw InputError(
        fmt::format("{}: {}", m_file, fmt::format(format, std::forward<Args>(args)...)));
}

const tinygltf::Accessor& Accessors::accessor(int index, const std::string& what) const {
    if (index < 0 || size_t(index) >= m_model.accessors.size())
        fail("{}: accessor {} does not exist", what, index);
    return m_model.accessors[size_t(index)];
}

// The accessor's elements, tightly packed (count x element size), after
// checking every offset, stride and count against the bufferView and the
// buffer, and applying sparse substitution.
std::vector<uint8_t> Accessors::elementBytes(int index, const std::string& what,
                                             size_t& elementSize) const {
    const tinygltf::Accessor& a = accessor(index, what);
    const size_t compSize = componentSize(a.componentType);
    const size_t comps = componentCount(a.type);
    if (compSize == 0)
        fail("{}: accessor {} has invalid componentType {}", what, index, a.componentType);
    if (comps == 0) fail("{}: accessor {} has an invalid type", what, index);
    elementSize = compSize * comps;
    if (a.count == 0) fail("{}: accessor {} has count 0", what, index);
    if (a.count > MAX_ACCESSOR_COUNT)
        fail("{}: accessor {} count {} exceeds the limit of {}", what, index, a.count,
             MAX_ACCESSOR_COUNT);

    if (a.bufferView < 0 && a.count > MAX_ZERO_ACCESSOR_COUNT)
        fail("{}: accessor {} has no bufferView and count {}, more than the {} allowed", what,
             index, a.count, MAX_ZERO_ACCESSOR_COUNT);
    std::vector<uint8_t> out(a.count * elementSize,
                             0);  // no bufferView: zeros (glTF 2.0, 3.6.2.1)
    if (a.bufferView >= 0) {
        size_t stride = 0;
        const std::span<const uint8_t> view = bufferView(a.bufferView, what, stride);
        if (stride == 0) stride = elementSize;
        if (stride < elementSize)
            fail("{}: accessor {} stride {} is smaller than its {}-byte elements", what, index,
                 stride, elementSize);
        const uint64_t needed =
            uint64_t(a.byteOffset) + uint64_t(a.count - 1) * stride + elementSize;
        if (a.byteOffset > view.size() || needed > view.size())
            fail(
                "{}: accessor {} (offset {}, count {}, stride {}) overruns its bufferView {} "
                "of {} bytes",
                what, index, a.byteOffset, a.count, stride, a.bufferView, view.size());
        for (size_t i = 0; i < a.count; ++i)
            std::memcpy(&out[i * elementSize], view.data() + a.byteOffset + i * stride,
                        elementSize);
    }
    if (a.sparse.isSparse) applySparse(a, index, what, elementSize, out);
    return out;
}

// bufferView `index` as bytes, checked against its buffer.
std::span<const uint8_t> Accessors::bufferView(int index, const std::string& what,
                                               size_t& stride) const {
    if (index < 0 || size_t(index) >= m_model.bufferViews.size())
        fail("{}: bufferView {} does not exist", what, index);
    const tinygltf::BufferView& v = m_model.bufferViews[size_t(index)];
    if (v.buffer < 0 || size_t(v.buffer) >= m_model.buffers.size())
        fail("{}: bufferView {} refers to buffer {}, which does not exist", what, index, v.buffer);
    const std::vector<unsigned char>& data = m_model.buffers[size_t(v.buffer)].data;
    if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset)
        fail("{}: bufferView {} (offset {}, length {}) overruns buffer {} of {} bytes", what, index,
             v.byteOffset, v.byteLength, v.buffer, data.size());
    if (v.byteStride != 0 && (v.byteStride < 4 || v.byteStride > 252 || v.byteStride % 4 != 0))
        fail("{}: bufferView {} byteStride {} is not a multiple of 4 in [4, 252]", what, index,
             v.byteStride);
    stride = v.byteStride;
    return std::span<const uint8_t>(data.data() + v.byteOffset, v.byteLength);
}

void Accessors::applySparse(const tinygltf::Accessor& a, int index, const std::string& what,
                            size_t elementSize, std::vector<uint8_t>& out) const {
    const auto& sparse = a.sparse;
    if (sparse.count < 1 || size_t(sparse.count) > a.count)
        fail("{}: accessor {} sparse count {} is not in [1, {}]", what, index, sparse.count,
             a.count);
    const size_t n = size_t(sparse.count);
    const size_t indexSize = componentSize(sparse.indices.componentType);
    if (indexSize == 0 || sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
        sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
        sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
        fail("{}: accessor {} sparse indices must be unsigned integers", what, index);
    auto range = [&](int viewIndex, int offset, size_t bytes, const char* part) {
        size_t stride = 0;
        const std::span<const uint8_t> view = bufferView(viewIndex, what, stride);
        if (offset < 0 || size_t(offset) > view.size() || bytes > view.size() - size_t(offset))
            fail("{}: accessor {} sparse {} overrun bufferView {}", what, index, part, viewIndex);
        return view.subspan(size_t(offset), bytes);
    };
    const auto targets =
        range(sparse.indices.bufferView, sparse.indices.byteOffset, n * indexSize, "indices");
    const auto values =
        range(sparse.values.bufferView, sparse.values.byteOffset, n * elementSize, "values");
    uint64_t previous = 0;
    for (size_t i = 0; i < n; ++i) {
        uint64_t target = 0;
        std::memcpy(&target, &targets[i * indexSize], indexSize);  // little-endian host
        if (target >= a.count || (i > 0 && target <= previous))
            fail("{}: accessor {} sparse index {} is out of range or not increasing", what, index,
                 target);
        std::memcpy(&out[target * elementSize], &values[i * elementSize], elementSize);
        previous = target;
    }
}

Encoding Accessors::encoding(int index, const std::string& what) const {
    const tinygltf::Accessor& a = accessor(index, what);
    return {a.componentType, a.normalized};
}

std::vector<glm::vec4> Accessors::floats(int index, const std::string& what,
                                         const AttributeFormat& format, size_t& components) const {
    const tinygltf::Accessor& a = accessor(index, what);
    const Encoding encoding{a.componentType, a.normalized};
    if (std::find(format.types.begin(), format.types.end(), a.type) == format.types.end() ||
        std::find(format.encodings.begin(), format.encodings.end(), encoding) ==
            format.encodings.end()) {
        fail("{}: accessor {} must be {}, not {} {}", what, index, formatName(format),
             encodingName(encoding), typeName(a.type));
    }
    components = componentCount(a.type);
    size_t elementSize = 0;
    const std::vector<uint8_t> bytes = elementBytes(index, what, elementSize);
    const size_t size = componentSize(a.componentType);
    std::vector<glm::vec4> out(a.count, glm::vec4(0.0f));
    for (size_t i = 0; i < a.count; ++i)
        for (size_t c = 0; c < components; ++c) {
            const float value = componentValue(&bytes[i * elementSize + c * size], encoding);
            if (!std::isfinite(value)) fail("{}: element {} is not finite", what, i);
            out[i][int(c)] = value;
        }
    return out;
}

std::vector<uint32_t> Accessors::indices(int index, const std::string& what) const {
    const tinygltf::Accessor& a = accessor(index, what);
    const int type = a.componentType;
    if (a.type != TINYGLTF_TYPE_SCALAR || (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                           type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                           type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        fail("{}: accessor {} must be an unsigned byte, short or int SCALAR", what, index);
    size_t elementSize = 0;
    const std::vector<uint8_t> bytes = elementBytes(index, what, elementSize);
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i) {
        uint32_t value = 0;
        std::memcpy(&value, &bytes[i * elementSize], elementSize);  // little-endian host
        out[i] = value;
    }
    return out;
}

}  // namespace vkpath::scene::gltf
