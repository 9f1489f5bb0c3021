// The feature-curve evaluation kernels' C++ side: the table expanded from the
// kernel list of shaders/sg/features/kernels.glsl (one declaration per
// kernel), the CPU evaluation of a record, and the compute-program pieces
// that run the same kernels on the GPU.
#include <cstring>

#include "kernel_inputs.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/features/feature_maps.h"

namespace sg::features {

namespace {

using namespace sg::glsl; // the field types of the field lists (vec2, uint, ...)

#define SG_FEAT_CPP_KERNEL(name, id, function, IN, OUT, tolerance, reason, inputs)                 \
    Kernel{#name, id, SG_REC_FIELDS(IN), SG_REC_FIELDS(OUT), tolerance, reason, &detail::inputs},

std::vector<Kernel> buildTable() {
    std::vector<Kernel> t{SG_FEAT_KERNELS(SG_FEAT_CPP_KERNEL)};
    for (size_t k = 0; k < t.size(); ++k) {
        // Ids are the list's order, and the records fit their strides.
        SG_ASSERT(t[k].id == int(k), "kernel ids are the list's order");
        SG_ASSERT(record::recordFloats(t[k].in) <= kEvalInStride, "input record fits its stride");
        SG_ASSERT(record::recordFloats(t[k].out) <= kEvalOutStride,
                  "output record fits its stride");
    }
    return t;
}

#undef SG_FEAT_CPP_KERNEL

} // namespace

const std::vector<Kernel>& kernels() {
    static const std::vector<Kernel> table = buildTable();
    static_assert(SG_FEAT_K_COUNT > 0);
    SG_ASSERT(table.size() == size_t(SG_FEAT_K_COUNT), "SG_FEAT_K_COUNT counts the list");
    return table;
}

const Kernel* findKernel(std::string_view name) {
    for (const Kernel& k : kernels())
        if (k.name == name) return &k;
    return nullptr;
}

void evalKernelCpu(int kernel, const float* in, float* out) {
    glsl::SgFeatEvalIn x;
    for (int k = 0; k < kEvalInStride; ++k) x.v[k] = in[k];
    glsl::SgFeatEvalOut y = glsl::sgFeatEvalKernel(kernel, x);
    for (int k = 0; k < kEvalOutStride; ++k) out[k] = y.v[k];
}

std::string evalKernelGpuBody() {
    return "#include \"sg/features/kernels.comp.glsl\"\n";
}

std::string evalKernelHlslBody() {
    return "#include \"sg/features/kernels.hlsl\"\n";
}

std::string evalKernelGpuVertexBody() {
    return "#include \"sg/features/kernels.vert.glsl\"\n";
}

std::vector<std::string> evalKernelGpuFeedback() {
    return {"vOut0", "vOut1"};
}

std::vector<std::string> evalKernelGpuDefines(int kernel) {
    return {"SG_FEAT_EVAL_KERNEL " + std::to_string(kernel)};
}

std::string sampleGpuBody() {
    return "#include \"sg/features/sample.comp.glsl\"\n";
}

void packEvalRecord(const GpuFeatureMaps& maps, int i, int j, glm::vec2 local, float* r) {
    SG_EXPECTS(i >= 0 && j >= 0 && i < maps.size && j < maps.size, "texel (i, j) inside the map");
    glsl::SgFeatTexel tx =
        glsl::sgFeatFetch(maps.cornerSampler(), maps.edgeSampler(), glsl::ivec2(i, j));
    detail::RecordWriter w(kernels()[SG_FEAT_K_EVAL].in, r);
    w.set("cornerDist", tx.dist);
    w.set("grad0", tx.grad0);
    w.set("grad1", tx.grad1);
    w.set("grad2", tx.grad2);
    w.set("grad3", tx.grad3);
    w.setWord("cfg", tx.cfg);
    w.setWord("edgeS", tx.edges.x);
    w.setWord("edgeE", tx.edges.y);
    w.setWord("edgeN", tx.edges.z);
    w.setWord("edgeW", tx.edges.w);
    w.set("local", local);
}

} // namespace sg::features
