// The table of evaluation entry points, expanded from the one declaration
// per shared function in shaders/sg/eval/kernels.glsl (SG_EVAL_KERNELS):
// names, kernel ids, record layouts (keys, widths, slots in declaration
// order, docs, JSON defaults and ranges, how parity records fill them),
// tolerances with their reasons and input generators.
#include "surfgrad/bump/eval_kernels.h"

#include <type_traits>

#include "eval_inputs.h"
#include "surfgrad/bump/core.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/bump/record.h"
#include "surfgrad/shaders/shader_files.h"

namespace sg::glsl {
#include "sg/eval/kernels.glsl"
}

namespace sg::eval {

int inStride() {
    return SG_EVAL_IN;
}
int outStride() {
    return SG_EVAL_OUT;
}

namespace {

// The options that may follow a field's doc string in kernels.glsl.
struct DefaultOption {
    float value;
};
struct RangeOption {
    int lo, hi;
};
constexpr DefaultOption sgDefault(float value) {
    return {value};
}
constexpr RangeOption sgRange(int lo, int hi) {
    return {lo, hi};
}
constexpr Generate sgGenNormal = Generate::Normal;
constexpr Generate sgGenDirection = Generate::Direction;
constexpr Generate sgGenNormalMapXY = Generate::NormalMapXY;
constexpr Generate sgGenExponent = Generate::Exponent;
constexpr Generate sgGenTexSize = Generate::TexSize;
constexpr Generate sgGenTangent = Generate::Tangent;
constexpr Generate sgGenSymmetric = Generate::Symmetric;
constexpr Generate sgGenPositive = Generate::Positive;
constexpr Generate sgGenSign = Generate::Sign;
constexpr Generate sgGenScreenDerivX = Generate::ScreenDerivX;
constexpr Generate sgGenScreenDerivY = Generate::ScreenDerivY;
constexpr Generate sgGenUvDerivX = Generate::UvDerivX;
constexpr Generate sgGenUvDerivY = Generate::UvDerivY;

// A field's third argument: its doc string, then its options.
struct FieldInfo {
    template <class... Options>
    explicit FieldInfo(const char* text, Options... options) : doc(text) {
        (apply(options), ...);
    }
    void apply(DefaultOption d) {
        optional = true;
        defaultValue = d.value;
    }
    void apply(RangeOption r) {
        minValue = r.lo;
        maxValue = r.hi;
    }
    void apply(Generate g) { generate = g; }

    std::string doc;
    bool optional = false;
    float defaultValue = 0.0f;
    int minValue = 0, maxValue = 0;
    Generate generate = Generate::Any;
};

// JSON kind of a field type: bool, int, or numbers.
template <class T>
constexpr FieldKind kindOf() {
    if constexpr (std::is_same_v<T, bool>)
        return FieldKind::Bool;
    else if constexpr (std::is_same_v<T, int>)
        return FieldKind::Int;
    else
        return FieldKind::Float;
}

template <class T>
Field field(const char* key, const FieldInfo& info) {
    Field f{key, record::floatsOf<T>(), 0, kindOf<T>(), info.optional, info.defaultValue, info.doc};
    f.minValue = info.minValue;
    f.maxValue = info.maxValue;
    f.generate = info.generate;
    return f;
}

// Slots in declaration order.
std::vector<Field> withSlots(std::vector<Field> fields) {
    int at = 0;
    for (Field& f : fields) {
        f.slot = at;
        at += f.width;
    }
    return fields;
}

int recordFloats(const std::vector<Field>& fields) {
    return fields.empty() ? 0 : fields.back().slot + fields.back().width;
}

using namespace sg::glsl; // the GLSL type names of the field lists (vec2, mat4, ...)

#define SG_EVAL_CPP_FIELD(T, key, info) field<T>(#key, FieldInfo info),
#define SG_EVAL_CPP_ENTRY(name, id, kernel, IN, OUT, summary, measure, tolerance, illShare,        \
                          reason, inputs)                                                          \
    Entry{name,                                                                                    \
          id,                                                                                      \
          summary,                                                                                 \
          withSlots({IN(SG_EVAL_CPP_FIELD)}),                                                      \
          withSlots({OUT(SG_EVAL_CPP_FIELD)}),                                                     \
          ErrorMeasure::measure,                                                                   \
          tolerance,                                                                               \
          illShare,                                                                                \
          reason,                                                                                  \
          &inputs},

std::vector<Entry> makeEntries() {
    std::vector<Entry> table{SG_EVAL_KERNELS(SG_EVAL_CPP_ENTRY)};
    for (size_t k = 0; k < table.size(); ++k) {
        SG_ASSERT(table[k].kernel == int(k), "kernel ids are the list positions");
        SG_ASSERT(recordFloats(table[k].inputs) <= SG_EVAL_IN, "inputs fit the record");
        SG_ASSERT(recordFloats(table[k].outputs) <= SG_EVAL_OUT, "outputs fit the record");
    }
    return table;
}

#undef SG_EVAL_CPP_ENTRY
#undef SG_EVAL_CPP_FIELD

} // namespace

const std::vector<Entry>& entries() {
    static const std::vector<Entry> table = makeEntries();
    return table;
}

const Entry* findEntry(std::string_view name) {
    for (const auto& e : entries()) {
        if (e.name == name) return &e;
    }
    return nullptr;
}

void evalCpu(const Entry& e, const float* in, float* out) {
    glsl::SgEvalIn x;
    for (int i = 0; i < SG_EVAL_IN; ++i) x.v[i] = in[i];
    glsl::SgEvalOut y = glsl::sgEvalKernel(e.kernel, x);
    for (int i = 0; i < SG_EVAL_OUT; ++i) out[i] = y.v[i];
}

std::string evalGpuBody() {
    return "#include \"sg/eval/eval.comp.glsl\"\n";
}

std::string evalHlslBody() {
    return "#include \"sg/eval/eval.hlsl\"\n";
}

std::string evalGpuVertexBody() {
    return "#include \"sg/eval/eval.vert.glsl\"\n";
}

std::vector<std::string> evalGpuFeedback() {
    return {"vOut0", "vOut1", "vOut2"};
}

std::vector<std::string> evalGpuDefines(const Entry& e) {
    return {"SG_EVAL_KERNEL " + std::to_string(e.kernel)};
}

} // namespace sg::eval
