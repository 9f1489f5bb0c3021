// SPIRV-Cross as the back end of the hlsl and msl shader targets
// (compilers.h), through its C API: HLSL shader model 5.0 (D3D11, Unity,
// Unreal), MSL 2.2 for macOS (10.15 and later: the primitive id of
// the primid AOV needs 2.2). The options are SPIRV-Cross's defaults
// otherwise, as `spirv-cross --hlsl --shader-model 50` and `--msl` use them.
#include <spirv_cross/spirv_cross_c.h>

#include <memory>

#include "compilers.h"

namespace sg::translate::detail {

namespace {

struct ContextDeleter {
    void operator()(spvc_context_s* c) const { spvc_context_destroy(c); }
};

} // namespace

std::string spirvCross(const std::vector<uint32_t>& spirv, CrossLanguage language,
                       const std::string& what) {
    spvc_context raw = nullptr;
    if (spvc_context_create(&raw) != SPVC_SUCCESS)
        throw TranslateError(what + ": SPIRV-Cross: no context");
    std::unique_ptr<spvc_context_s, ContextDeleter> context(raw);
    const auto fail = [&](const char* step) {
        return TranslateError(what + ": SPIRV-Cross (" + step +
                              "): " + spvc_context_get_last_error_string(context.get()));
    };
    spvc_parsed_ir ir = nullptr;
    if (spvc_context_parse_spirv(context.get(), spirv.data(), spirv.size(), &ir) != SPVC_SUCCESS)
        throw fail("parse");
    const bool hlsl = language == CrossLanguage::Hlsl;
    spvc_compiler compiler = nullptr;
    if (spvc_context_create_compiler(context.get(), hlsl ? SPVC_BACKEND_HLSL : SPVC_BACKEND_MSL, ir,
                                     SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &compiler) != SPVC_SUCCESS)
        throw fail("compiler");
    spvc_compiler_options options = nullptr;
    if (spvc_compiler_create_compiler_options(compiler, &options) != SPVC_SUCCESS)
        throw fail("options");
    if (hlsl) {
        spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_HLSL_SHADER_MODEL, 50);
    } else {
        spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_MSL_VERSION,
                                       SPVC_MAKE_MSL_VERSION(2, 2, 0));
    }
    if (spvc_compiler_install_compiler_options(compiler, options) != SPVC_SUCCESS)
        throw fail("options");
    const char* source = nullptr;
    if (spvc_compiler_compile(compiler, &source) != SPVC_SUCCESS) throw fail("compile");
    return source ? std::string(source) : std::string();
}

} // namespace sg::translate::detail
