// Animated cages on the GPU (internal to surfgrad_render): the stencil rows
// of sg::mesh::AdaptivePatches uploaded once, then per frame the cage
// positions uploaded (cagePointCount x 12 bytes, into the first points of
// the points buffer the patch draw reads) and the other control points
// recomputed in that buffer, pass after pass (one dispatch per stencil
// pass, a storage barrier between), by the compute stage
// shaders/sg/patch/stencils.comp.glsl (bit for bit what
// sg::mesh::updateAdaptivePoints computes on the CPU).
//
// Needs a current GL 4.3+ context (compute shaders) on the calling thread;
// the object owns its buffers except the points buffer, which belongs to the
// caller (the patch draw's binding 0) and is (re)sized by upload().
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/gl/context.h"

namespace sg::render::detail {

// The compute program of stencils.comp.glsl (one per context).
sg::gl::Program makeStencilProgram();

class GpuStencils {
public:
    GpuStencils() = default;
    ~GpuStencils();
    GpuStencils(const GpuStencils&) = delete;
    GpuStencils& operator=(const GpuStencils&) = delete;
    GpuStencils(GpuStencils&& o) noexcept;
    GpuStencils& operator=(GpuStencils&& o) noexcept;

    // Uploads the stencil rows of `patches` (offsets, indices, weights) and
    // sizes `pointsBuffer` (a buffer name the caller created) for
    // patches.points.size() points (xyz floats). Returns the bytes uploaded.
    uint64_t upload(const sg::mesh::AdaptivePatches& patches, GLuint pointsBuffer);
    // Uploads `cagePositions` (cagePointCount entries, object space) into
    // the points buffer and dispatches the compute stage (`program`:
    // makeStencilProgram()) once per stencil pass, in order, with a storage
    // barrier after each (the next pass and the patch draw's storage-buffer
    // reads see its points). Returns the bytes uploaded (the cage).
    uint64_t apply(std::span<const glm::vec3> cagePositions, const sg::gl::Program& program);

    bool uploaded() const { return buf_[0] != 0; }
    GLuint pointsBuffer() const { return points_; }
    uint32_t cagePointCount() const { return cagePointCount_; }

private:
    GLuint buf_[3] = {}; // offsets (binding 5), indices (6), weights (7)
    GLuint points_ = 0;  // not owned
    uint32_t cagePointCount_ = 0;
    std::vector<uint32_t> passes_; // AdaptivePatches::stencilPasses
};

// Reads `count` points (xyz floats) back from a points buffer (tests, the
// bench's check).
std::vector<glm::vec3> readPoints(GLuint pointsBuffer, size_t count);

} // namespace sg::render::detail
