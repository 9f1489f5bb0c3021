// Animated cages on the GPU: the stencil rows applied to the uploaded cage
// by the compute stage shaders/sg/patch/stencils.comp.glsl (gpu_stencils.h).
// Our own compute stage rather than Osd::GLComputeEvaluator: it reads the
// stencil arrays AdaptivePatches already holds (one pass per refinement
// level, each from the level above, then the Gregory end caps' local
// points), updates the packed xyz points buffer the patch draw reads in
// place, and sums in updateAdaptivePoints' order, so the GPU's points equal
// the CPU reference's bit for bit (docs/mesh.md).
#include "gpu_stencils.h"

#include <algorithm>
#include <utility>

#include "surfgrad/base/contract.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/shaders/shader_files.h"

namespace sg::render::detail {

namespace {

constexpr uint32_t kGroupSize = 64;    // local_size_x of stencils.comp.glsl
constexpr uint32_t kMaxGroups = 65535; // GL's guaranteed work-group count per dispatch

} // namespace

sg::gl::Program makeStencilProgram() {
    const char* src = sg::shaders::find("sg/patch/stencils.comp.glsl");
    SG_ASSERT(src, "the stencil stage is embedded");
    return sg::gl::Program(
        {{sg::gl::Stage::Compute, sg::shaders::assemble(src, "sg/patch/stencils.comp.glsl")}});
}

GpuStencils::~GpuStencils() {
    if (buf_[0]) glDeleteBuffers(3, buf_);
}

GpuStencils::GpuStencils(GpuStencils&& o) noexcept {
    *this = std::move(o);
}

GpuStencils& GpuStencils::operator=(GpuStencils&& o) noexcept {
    if (this != &o) {
        if (buf_[0]) glDeleteBuffers(3, buf_);
        std::copy(o.buf_, o.buf_ + 3, buf_);
        std::fill(o.buf_, o.buf_ + 3, 0u);
        points_ = o.points_;
        passes_ = std::move(o.passes_);
        cagePointCount_ = o.cagePointCount_;
    }
    return *this;
}

uint64_t GpuStencils::upload(const sg::mesh::AdaptivePatches& ap, GLuint pointsBuffer) {
    SG_EXPECTS(ap.points.size() >= ap.cagePointCount &&
                   ap.stencilOffsets.size() == ap.points.size() - ap.cagePointCount + 1 &&
                   !ap.stencilPasses.empty() && ap.stencilPasses.front() == ap.cagePointCount &&
                   ap.stencilPasses.back() == ap.points.size(),
               "GpuStencils::upload: one stencil row per point past the cage, passes cover them");
    if (!buf_[0]) glCreateBuffers(3, buf_);
    points_ = pointsBuffer;
    cagePointCount_ = ap.cagePointCount;
    passes_ = ap.stencilPasses;
    const GLsizeiptr offBytes = GLsizeiptr(ap.stencilOffsets.size() * 4);
    const GLsizeiptr idxBytes = GLsizeiptr(std::max<size_t>(ap.stencilIndices.size(), 1) * 4);
    const GLsizeiptr wBytes = GLsizeiptr(std::max<size_t>(ap.stencilWeights.size(), 1) * 4);
    glNamedBufferData(buf_[0], offBytes, ap.stencilOffsets.data(), GL_STATIC_DRAW);
    glNamedBufferData(buf_[1], idxBytes,
                      ap.stencilIndices.empty() ? nullptr : ap.stencilIndices.data(),
                      GL_STATIC_DRAW);
    glNamedBufferData(buf_[2], wBytes,
                      ap.stencilWeights.empty() ? nullptr : ap.stencilWeights.data(),
                      GL_STATIC_DRAW);
    glNamedBufferData(points_, GLsizeiptr(std::max<size_t>(ap.points.size(), 1) * 12), nullptr,
                      GL_DYNAMIC_COPY);
    return uint64_t(offBytes + idxBytes + wBytes);
}

uint64_t GpuStencils::apply(std::span<const glm::vec3> cage, const sg::gl::Program& program) {
    SG_EXPECTS(uploaded() && cage.size() == cagePointCount_,
               "GpuStencils::apply: upload() first, one position per cage vertex");
    const GLsizeiptr cageBytes = GLsizeiptr(cage.size() * 12);
    static_assert(sizeof(glm::vec3) == 12, "packed xyz");
    // The cage is the points buffer's first cagePointCount points; the
    // buffer update is ordered before the dispatches that read it.
    if (cageBytes) glNamedBufferSubData(points_, 0, cageBytes, cage.data());
    const GLuint prog = program.id();
    glUseProgram(prog);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, points_);
    for (int k = 0; k < 3; ++k) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(5 + k), buf_[k]);
    glUniform1ui(glGetUniformLocation(prog, "uCagePointCount"), cagePointCount_);
    const GLint firstLoc = glGetUniformLocation(prog, "uFirstPoint");
    const GLint endLoc = glGetUniformLocation(prog, "uEndPoint");
    const uint32_t perDispatch = kGroupSize * kMaxGroups;
    // One pass after the other: a pass reads points earlier passes wrote,
    // hence the barrier after each (the last one also serves the patch
    // draw, which reads the points as storage buffers: patch_vs/tcs).
    for (size_t p = 0; p + 1 < passes_.size(); ++p) {
        glUniform1ui(endLoc, passes_[p + 1]);
        for (uint32_t first = passes_[p]; first < passes_[p + 1]; first += perDispatch) {
            const uint32_t n = std::min(perDispatch, passes_[p + 1] - first);
            glUniform1ui(firstLoc, first);
            glDispatchCompute((n + kGroupSize - 1) / kGroupSize, 1, 1);
        }
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    sg::gl::checkError("cage stencils");
    return uint64_t(cageBytes);
}

std::vector<glm::vec3> readPoints(GLuint pointsBuffer, size_t count) {
    std::vector<glm::vec3> out(count);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    if (count) glGetNamedBufferSubData(pointsBuffer, 0, GLsizeiptr(count * 12), out.data());
    return out;
}

} // namespace sg::render::detail
