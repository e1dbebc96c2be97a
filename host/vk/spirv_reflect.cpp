#include "vk/spirv_reflect.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

namespace vkpath::vk {
namespace {

// Opcodes and enumerants from the SPIR-V specification (unified, 1.6).
enum Op : uint32_t {
    OpName = 5,
    OpExecutionMode = 16,
    OpCapability = 17,
    OpMemberName = 6,
    OpTypeInt = 21,
    OpTypeFloat = 22,
    OpTypeVector = 23,
    OpTypeMatrix = 24,
    OpTypeImage = 25,
    OpTypeArray = 28,
    OpTypeRuntimeArray = 29,
    OpTypeStruct = 30,
    OpTypePointer = 32,
    OpConstant = 43,
    OpVariable = 59,
    OpDecorate = 71,
    OpMemberDecorate = 72,
};
enum Decoration : uint32_t {
    ArrayStride = 6,
    MatrixStride = 7,
    Binding = 33,
    DescriptorSet = 34,
    Offset = 35
};
enum StorageClass : uint32_t {
    UniformConstant = 0,
    Uniform = 2,
    PushConstant = 9,
    StorageBuffer = 12
};
constexpr uint32_t DIM_BUFFER = 5;          // OpTypeImage's Dim operand
constexpr uint32_t SAMPLED_BY_SAMPLER = 1;  // OpTypeImage's Sampled operand: not a storage image

std::string literalString(std::span<const uint32_t> words) {
    std::string s;
    for (uint32_t w : words) {
        for (int b = 0; b < 4; ++b) {
            const char c = static_cast<char>((w >> (8 * b)) & 0xff);
            if (c == '\0') return s;
            s.push_back(c);
        }
    }
    return s;
}

struct Type {
    uint32_t op = 0;
    std::vector<uint32_t> operands;  // the instruction's words after the result id
};

}  // namespace

SpirvReflection reflectSpirv(std::span<const uint32_t> words) {
    if (words.size() < 5 || words[0] != 0x07230203u)
        throw std::runtime_error("not a SPIR-V module");

    std::unordered_map<uint32_t, std::string> names;
    std::unordered_map<uint32_t, Type> types;
    std::unordered_map<uint32_t, uint32_t> constants;
    std::unordered_map<uint32_t, uint32_t> arrayStrides;
    std::unordered_map<uint32_t, std::map<uint32_t, uint32_t>> memberOffsets;
    std::unordered_map<uint32_t, uint32_t> bindingOf, setOf;
    struct Variable {
        uint32_t id, pointerType, storage;
    };
    std::vector<Variable> variables;
    SpirvReflection result;

    for (size_t i = 5; i < words.size();) {
        const uint32_t count = words[i] >> 16;
        const uint32_t op = words[i] & 0xffff;
        if (count == 0 || i + count > words.size())
            throw std::runtime_error("truncated SPIR-V instruction");
        std::span<const uint32_t> in = words.subspan(i + 1, count - 1);
        switch (op) {
            case OpName:
                names[in[0]] = literalString(in.subspan(1));
                break;
            case OpCapability:
                result.capabilities.push_back(in[0]);
                break;
            case OpExecutionMode:
                result.executionModes.push_back(
                    {in[1], std::vector<uint32_t>(in.begin() + 2, in.end())});
                break;
            case OpTypeInt:
            case OpTypeFloat:
            case OpTypeVector:
            case OpTypeMatrix:
            case OpTypeImage:
            case OpTypeArray:
            case OpTypeRuntimeArray:
            case OpTypeStruct:
            case OpTypePointer:
                types[in[0]] = Type{op, std::vector<uint32_t>(in.begin() + 1, in.end())};
                break;
            case OpConstant:
                if (in.size() >= 3) constants[in[1]] = in[2];
                break;
            case OpVariable:
                variables.push_back({in[1], in[0], in[2]});
                break;
            case OpDecorate:
                if (in[1] == ArrayStride) arrayStrides[in[0]] = in[2];
                if (in[1] == Binding) bindingOf[in[0]] = in[2];
                if (in[1] == DescriptorSet) setOf[in[0]] = in[2];
                break;
            case OpMemberDecorate:
                if (in[2] == Offset) memberOffsets[in[0]][in[1]] = in[3];
                break;
            default:
                break;
        }
        i += count;
    }

    // Byte size of a type under the offsets the module declares.
    auto sizeOf = [&](auto&& self, uint32_t id) -> uint32_t {
        const Type& t = types.at(id);
        switch (t.op) {
            case OpTypeInt:
            case OpTypeFloat:
                return t.operands[0] / 8;
            case OpTypeVector:
                return self(self, t.operands[0]) * t.operands[1];
            case OpTypeMatrix:
                return self(self, t.operands[0]) * t.operands[1];
            case OpTypeArray:
                return arrayStrides.at(id) * constants.at(t.operands[1]);
            case OpTypeStruct: {
                if (t.operands.empty()) return 0;
                const uint32_t last = static_cast<uint32_t>(t.operands.size() - 1);
                return memberOffsets.at(id).at(last) + self(self, t.operands[last]);
            }
            default:
                throw std::runtime_error(
                    fmt::format("cannot size SPIR-V type with opcode {}", t.op));
        }
    };

    for (const Variable& v : variables) {
        if (v.storage == PushConstant) {
            const uint32_t pointee = types.at(v.pointerType).operands[1];
            result.pushConstantSize = sizeOf(sizeOf, pointee);
        } else if ((v.storage == StorageBuffer || v.storage == Uniform) &&
                   bindingOf.contains(v.id)) {
            // Storage buffers are StorageBuffer variables under SPIR-V 1.5
            // (--target-env vulkan1.2); Uniform ones are uniform buffers.
            result.bindings.push_back({setOf.contains(v.id) ? setOf[v.id] : 0, bindingOf[v.id],
                                       v.storage == Uniform ? DescriptorKind::UniformBuffer
                                                            : DescriptorKind::StorageBuffer});
        } else if (v.storage == UniformConstant && bindingOf.contains(v.id)) {
            // An image of dimension Buffer that is sampled (GLSL's
            // textureBuffer) is a uniform texel buffer; vkpath's kernels
            // declare no other opaque type.
            const Type& image = types.at(types.at(v.pointerType).operands[1]);
            const bool texelBuffer = image.op == OpTypeImage &&
                                     image.operands.at(1) == DIM_BUFFER &&
                                     image.operands.at(5) == SAMPLED_BY_SAMPLER;
            if (!texelBuffer)
                throw std::runtime_error(
                    "SPIR-V: a resource other than a buffer or a texel buffer");
            result.bindings.push_back({setOf.contains(v.id) ? setOf[v.id] : 0, bindingOf[v.id],
                                       DescriptorKind::UniformTexelBuffer});
        }
    }
    std::sort(result.bindings.begin(), result.bindings.end(), [](const auto& a, const auto& b) {
        return std::tie(a.set, a.binding) < std::tie(b.set, b.binding);
    });

    for (const auto& [id, type] : types) {
        if (type.op != OpTypeStruct || !names.contains(id)) continue;
        SpirvStructLayout layout;
        if (auto it = memberOffsets.find(id); it != memberOffsets.end())
            for (const auto& [member, offset] : it->second) layout.memberOffsets.push_back(offset);
        result.structs[names[id]] = layout;
    }
    for (const auto& [id, type] : types) {
        if (type.op != OpTypeRuntimeArray || !arrayStrides.contains(id)) continue;
        const uint32_t element = type.operands[0];
        if (names.contains(element)) result.structs[names[element]].arrayStride = arrayStrides[id];
    }
    return result;
}

}  // namespace vkpath::vk
