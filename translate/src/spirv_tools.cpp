// SPIR-V checks of the shader targets (compilers.h): the validator and the
// disassembler of SPIRV-Tools (what `spirv-val --target-env vulkan1.1` and
// `spirv-dis` run), Vulkan 1.1 environment.
#include <spirv-tools/libspirv.hpp>

#include "compilers.h"

namespace sg::translate::detail {

void validateSpirv(const std::vector<uint32_t>& spirv, const std::string& what) {
    spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_1);
    std::string log;
    tools.SetMessageConsumer(
        [&log](spv_message_level_t, const char*, const spv_position_t& at, const char* message) {
            log += "word " + std::to_string(at.index) + ": " + message + "\n";
        });
    if (!tools.Validate(spirv)) {
        if (!log.empty()) log.pop_back();
        throw TranslateError(what + ": SPIR-V validator: " + (log.empty() ? "invalid" : log));
    }
}

std::string disassembleSpirv(const std::vector<uint32_t>& spirv) {
    spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_1);
    std::string text;
    if (!tools.Disassemble(spirv, &text,
                           SPV_BINARY_TO_TEXT_OPTION_FRIENDLY_NAMES |
                               SPV_BINARY_TO_TEXT_OPTION_INDENT))
        throw TranslateError("SPIR-V disassembler: the module does not disassemble");
    return text;
}

} // namespace sg::translate::detail
