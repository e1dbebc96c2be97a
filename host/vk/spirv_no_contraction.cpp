#include "vk/spirv_no_contraction.h"

#include <stdexcept>
#include <unordered_set>

namespace vkpath::vk {
namespace {

// Opcodes and enumerants from the SPIR-V specification (unified, 1.6).
constexpr uint32_t OP_DECORATE = 71;
constexpr uint32_t DECORATION_NO_CONTRACTION = 42;
constexpr uint32_t HEADER_WORDS = 5;

bool isFloatArithmetic(uint32_t op) {
    switch (op) {
        case 129:  // OpFAdd
        case 131:  // OpFSub
        case 133:  // OpFMul
        case 136:  // OpFDiv
        case 142:  // OpVectorTimesScalar
        case 143:  // OpMatrixTimesScalar
        case 144:  // OpVectorTimesMatrix
        case 145:  // OpMatrixTimesVector
        case 146:  // OpMatrixTimesMatrix
        case 147:  // OpOuterProduct
        case 148:  // OpDot
            return true;
        default:
            return false;
    }
}

// The annotation section: OpDecorate, OpMemberDecorate, OpDecorationGroup,
// OpGroupDecorate, OpGroupMemberDecorate, OpDecorateId, OpDecorateString,
// OpMemberDecorateString.
bool isAnnotation(uint32_t op) {
    return (op >= 71 && op <= 75) || op == 332 || op == 5632 || op == 5633;
}

// Instructions of the sections before the annotations: debug information
// (OpSourceContinued to OpLine, OpModuleProcessed), OpExtension to
// OpCapability (imports, memory model, entry points, execution modes), and
// OpExecutionModeId.
bool isBeforeAnnotations(uint32_t op) {
    return (op >= 2 && op <= 8) || (op >= 10 && op <= 17) || op == 330 || op == 331;
}

}  // namespace

std::vector<uint32_t> decorateNoContraction(std::span<const uint32_t> module) {
    if (module.size() < HEADER_WORDS || module[0] != 0x07230203u)
        throw std::runtime_error("not a SPIR-V module");

    // One pass to find the results to decorate, those already decorated, and
    // where the annotations end.
    std::vector<uint32_t> results;
    std::unordered_set<uint32_t> decorated;
    size_t annotationsEnd = 0;  // word index after the last annotation; 0: none
    size_t firstLater = 0;      // word index of the first instruction after the preamble
    for (size_t i = HEADER_WORDS; i < module.size();) {
        const uint32_t count = module[i] >> 16;
        const uint32_t op = module[i] & 0xffffu;
        if (count == 0 || i + count > module.size())
            throw std::runtime_error("malformed SPIR-V module");
        if (op == OP_DECORATE && count >= 3 && module[i + 2] == DECORATION_NO_CONTRACTION)
            decorated.insert(module[i + 1]);
        if (isAnnotation(op))
            annotationsEnd = i + count;
        else if (firstLater == 0 && !isBeforeAnnotations(op))
            firstLater = i;
        if (isFloatArithmetic(op) && count >= 3) results.push_back(module[i + 2]);
        i += count;
    }
    const size_t insertAt = annotationsEnd ? annotationsEnd
                            : firstLater   ? firstLater
                                           : module.size();

    std::vector<uint32_t> out(module.begin(),
                              module.begin() + static_cast<std::ptrdiff_t>(insertAt));
    for (const uint32_t id : results) {
        if (!decorated.insert(id).second) continue;
        out.insert(out.end(), {(3u << 16) | OP_DECORATE, id, DECORATION_NO_CONTRACTION});
    }
    out.insert(out.end(), module.begin() + static_cast<std::ptrdiff_t>(insertAt), module.end());
    return out;
}

}  // namespace vkpath::vk
