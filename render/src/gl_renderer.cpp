// The OpenGL 4.5 core renderer: one draw per mesh instance with the
// program assembled for its material (plan.cpp), cached by effect
// signature; adaptive meshes one tessellated draw per patch type (their
// patch buffers uploaded once per asset, levels from the screen: the
// shared sgPatchEdgeTessLevel); meshes and textures uploaded once; an RGBA32F + 32-bit float
// depth framebuffer; draw wall time (ended by glFinish) and, where the
// driver's timer covers the draws, GPU time from GL_TIME_ELAPSED. Works on any
// current 4.5 core context (EGL surfaceless for the CLI and tests, GLFW for
// the viewer).
#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>

#include "gpu_stencils.h"
#include "layer_kind.h"
#include "render_internal.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/render.h"

namespace sg::render {

namespace {

// Images of at least this many pixels are drawn in bands of kBandRows rows
// when a progress callback is set (GlRenderer::setProgress).
constexpr int64_t kBandedPixels = int64_t(2048) * 2048;
constexpr int kBandRows = 512;

struct GpuMesh {
    GLuint vao = 0;
    GLuint vbo[10] = {};
    GLuint ebo = 0;
    GLsizei indexCount = 0;
    uint64_t layoutId = 0; // MeshAsset::layoutId of the uploaded UVs and indices
    // Adaptive meshes: shader storage buffers of sg/patch/patch_*.glsl:
    // [0] control points (binding 0), [1] per-patch records (binding 1),
    // [2] control-point indices (binding 3), [3] UV values (binding 4),
    // [4] UV patches (binding 5; meshes with UV sets). 0 for triangle meshes.
    GLuint patchBuf[5] = {};
    // Animated cages (MeshAsset::cagePositions): the stencil rows and the
    // cage, whose compute stage writes patchBuf[0].
    detail::GpuStencils stencils;
};

} // namespace

std::vector<uint32_t> detail::patchRecords(const sg::mesh::AdaptivePatches& ap) {
    std::vector<uint32_t> data;
    data.reserve(28 * ap.patchCount());
    for (const auto& arr : ap.arrays) {
        for (uint32_t k = 0; k < arr.patchCount; ++k) {
            const size_t p = size_t(arr.firstPatch) + k;
            const glm::uvec4 c = ap.cornerVertices[p], e = ap.edgeOwners[p], o = ap.cornerOwners[p];
            const glm::uvec4 lo = ap.transitionLo[p], hi = ap.transitionHi[p];
            const glm::uvec4 mid = ap.transitionMid[p];
            const uint32_t first = arr.firstIndex + k * uint32_t(arr.pointsPerPatch);
            data.insert(data.end(), {ap.params[p].y,
                                     c.x,
                                     c.y,
                                     c.z,
                                     c.w,
                                     uint32_t(arr.type),
                                     first,
                                     ap.transitionMask[p],
                                     e.x,
                                     e.y,
                                     e.z,
                                     e.w,
                                     o.x,
                                     o.y,
                                     o.z,
                                     o.w,
                                     lo.x,
                                     lo.y,
                                     lo.z,
                                     lo.w,
                                     hi.x,
                                     hi.y,
                                     hi.z,
                                     hi.w,
                                     mid.x,
                                     mid.y,
                                     mid.z,
                                     mid.w});
        }
    }
    return data;
}

namespace {

using detail::patchRecords;

// The UV sets' buffers (bindings 4 and 5; layout in sg/patch/patch_tes.glsl):
// every set's values, xy, one set after the other; per patch and set
// (patch-major), 22 words: face-varying field1, type, 20 value indices
// (offset by the set's first value).
void uvPatchBuffers(const sg::mesh::AdaptivePatches& ap, std::vector<float>& values,
                    std::vector<uint32_t>& records) {
    constexpr uint32_t kStride = 2 + sg::mesh::AdaptiveUvSet::kUvValuesPerPatch;
    const size_t sets = std::min(ap.uvSets.size(), size_t(kMaxUvSets));
    std::vector<uint32_t> firstValue(sets, 0);
    for (size_t s = 0; s < sets; ++s) {
        firstValue[s] = uint32_t(values.size() / 2);
        for (const glm::vec2& v : ap.uvSets[s].values) values.insert(values.end(), {v.x, v.y});
    }
    records.assign(ap.patchCount() * sets * kStride, 0u);
    for (size_t p = 0; p < ap.patchCount(); ++p) {
        for (size_t s = 0; s < sets; ++s) {
            const sg::mesh::AdaptiveUvSet& u = ap.uvSets[s];
            uint32_t* r = &records[(p * sets + s) * kStride];
            r[0] = u.field1[p];
            r[1] = u.types[p];
            for (uint32_t i = 0; i < sg::mesh::AdaptiveUvSet::kUvValuesPerPatch; ++i)
                r[2 + i] =
                    firstValue[s] + u.indices[p * sg::mesh::AdaptiveUvSet::kUvValuesPerPatch + i];
        }
    }
}

// Static patches upload their points; an animated cage uploads the stencil
// rows instead (its points come from the compute stage). Returns the bytes.
uint64_t uploadPatches(GpuMesh& g, const sg::mesh::AdaptivePatches& ap, bool animated) {
    if (!g.patchBuf[0]) glCreateBuffers(5, g.patchBuf);
    const std::vector<uint32_t> records = patchRecords(ap);
    uint64_t bytes = records.size() * 4 + ap.indices.size() * 4;
    if (animated) {
        bytes += g.stencils.upload(ap, g.patchBuf[0]);
    } else {
        std::vector<float> pts;
        pts.reserve(3 * ap.points.size());
        for (const glm::vec3& p : ap.points) pts.insert(pts.end(), {p.x, p.y, p.z});
        glNamedBufferData(g.patchBuf[0], GLsizeiptr(pts.size() * sizeof(float)), pts.data(),
                          GL_STATIC_DRAW);
        bytes += pts.size() * sizeof(float);
    }
    glNamedBufferData(g.patchBuf[1], GLsizeiptr(records.size() * sizeof(uint32_t)), records.data(),
                      GL_STATIC_DRAW);
    glNamedBufferData(g.patchBuf[2], GLsizeiptr(ap.indices.size() * sizeof(uint32_t)),
                      ap.indices.data(), GL_STATIC_DRAW);
    if (!ap.uvSets.empty()) {
        std::vector<float> uvValues;
        std::vector<uint32_t> uvRecords;
        uvPatchBuffers(ap, uvValues, uvRecords);
        glNamedBufferData(g.patchBuf[3], GLsizeiptr(uvValues.size() * sizeof(float)),
                          uvValues.data(), GL_STATIC_DRAW);
        glNamedBufferData(g.patchBuf[4], GLsizeiptr(uvRecords.size() * sizeof(uint32_t)),
                          uvRecords.data(), GL_STATIC_DRAW);
        bytes += uvValues.size() * sizeof(float) + uvRecords.size() * sizeof(uint32_t);
    }
    return bytes;
}

struct GpuProgram {
    sg::gl::Program program;
    std::unordered_map<std::string, GLint> locations;
    GLint loc(const char* name) {
        auto it = locations.find(name);
        if (it != locations.end()) return it->second;
        GLint l = glGetUniformLocation(program.id(), name);
        locations.emplace(name, l);
        return l;
    }
};

void deleteMesh(GpuMesh& m) {
    if (m.vao) glDeleteVertexArrays(1, &m.vao);
    glDeleteBuffers(10, m.vbo);
    if (m.ebo) glDeleteBuffers(1, &m.ebo);
    if (m.patchBuf[0]) glDeleteBuffers(5, m.patchBuf);
    m = GpuMesh{};
}

template <class T>
uint64_t uploadAttrib(GLuint vao, GLuint& vbo, GLuint location, const std::vector<T>& data,
                      int comps) {
    if (data.empty()) {
        glDisableVertexArrayAttrib(vao, location);
        return 0;
    }
    if (!vbo) glCreateBuffers(1, &vbo);
    glNamedBufferData(vbo, GLsizeiptr(data.size() * sizeof(T)), data.data(), GL_DYNAMIC_DRAW);
    glVertexArrayVertexBuffer(vao, location, vbo, 0, GLsizei(sizeof(T)));
    glVertexArrayAttribFormat(vao, location, comps, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, location, location);
    glEnableVertexArrayAttrib(vao, location);
    return data.size() * sizeof(T);
}

} // namespace

struct GlRenderer::Impl {
    std::unordered_map<std::string, GpuProgram> programs;
    std::string fragmentDefines; // "#define ...\n" lines (GlRenderer::setFragmentDefines)
    sg::shaders::Target dialect = sg::shaders::Target::Glsl450; // GlRenderer::setDialect
    uint64_t meshesFor = 0, meshVersion = 0;
    std::vector<GpuMesh> meshes;
    bool meshesDirty = true;
    std::unordered_map<uint64_t, GLuint> textures; // by TextureImage::uid
    GLuint fbo = 0, colorTex = 0, depthRb = 0;
    int fbW = 0, fbH = 0;
    GLuint query = 0;
    int timerOk = -1; // timerMeasures(), once per renderer

    // Whether GL_TIME_ELAPSED measures the draws: the driver has a timer (not
    // 0 counter bits) and rasterises inside the query. Mesa's software
    // rasterisers (llvmpipe, softpipe) bin the draws and rasterise them on
    // worker threads their query does not cover: 17.6 ms of a 580 ms
    // 4096^2 frame (wall time, glFinish inside the query), so no GPU time
    // is reported there (docs/platform.md).
    void bindDraw(GpuProgram& gp, const MaterialPlan& plan, const detail::DrawUniforms& u,
                  const View& view, const SceneAssets& assets);
    bool timerMeasures() {
        if (timerOk < 0) {
            GLint bits = 0;
            glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &bits);
            timerOk = bits > 0 && !mesaDrawModule() ? 1 : 0;
        }
        return timerOk == 1;
    }

    // Whether the context is one of Mesa's software rasterisers (llvmpipe,
    // softpipe), which run the vertex and tessellation stages in Mesa's
    // draw module.
    int softwareDriver = -1;
    bool mesaDrawModule() {
        if (softwareDriver < 0) {
            const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
            const std::string name = r ? r : "";
            softwareDriver = name.find("llvmpipe") != std::string::npos ||
                             name.find("softpipe") != std::string::npos;
        }
        return softwareDriver == 1;
    }

    ~Impl() {
        for (auto& m : meshes) deleteMesh(m);
        for (auto& [img, t] : textures) glDeleteTextures(1, &t);
        kindGpu.clear(); // the kinds' GL objects, while the context is current
        if (fbo) glDeleteFramebuffers(1, &fbo);
        if (colorTex) glDeleteTextures(1, &colorTex);
        if (depthRb) glDeleteRenderbuffers(1, &depthRb);
        if (query) glDeleteQueries(1, &query);
    }

    void ensureFramebuffer(int w, int h) {
        if (fbo && w == fbW && h == fbH) return;
        if (fbo) glDeleteFramebuffers(1, &fbo);
        if (colorTex) glDeleteTextures(1, &colorTex);
        if (depthRb) glDeleteRenderbuffers(1, &depthRb);
        glCreateTextures(GL_TEXTURE_2D, 1, &colorTex);
        glTextureStorage2D(colorTex, 1, GL_RGBA32F, w, h);
        glTextureParameteri(colorTex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(colorTex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glCreateRenderbuffers(1, &depthRb);
        glNamedRenderbufferStorage(depthRb, GL_DEPTH_COMPONENT32F, w, h);
        glCreateFramebuffers(1, &fbo);
        glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, colorTex, 0);
        glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depthRb);
        if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            // Almost always memory: name the size and the option that sets it.
            const double mib = double(w) * double(h) * (16.0 + 4.0) / (1024.0 * 1024.0);
            char buf[200];
            std::snprintf(buf, sizeof buf,
                          "renderer: the GL driver cannot make a %dx%d framebuffer (RGBA32F + "
                          "DEPTH32F, %.0f MiB): render a smaller --size",
                          w, h, mib);
            throw sg::gl::GlError(buf);
        }
        fbW = w;
        fbH = h;
    }

    sg::gl::Program stencilProgram; // stencils.comp.glsl, compiled at the first animated cage

    // Returns the bytes uploaded.
    uint64_t uploadMeshes(const SceneAssets& assets) {
        if (meshesFor != assets.uid || meshes.size() != assets.meshes.size()) {
            for (auto& m : meshes) deleteMesh(m);
            meshes.clear();
            meshes.resize(assets.meshes.size());
            meshesFor = assets.uid;
            meshesDirty = true;
        }
        if (meshVersion != assets.meshVersion) meshesDirty = true;
        meshVersion = assets.meshVersion;
        if (!meshesDirty) return 0;
        uint64_t bytes = 0;
        for (size_t i = 0; i < assets.meshes.size(); ++i) {
            const MeshAsset& a = assets.meshes[i];
            GpuMesh& g = meshes[i];
            bool fresh = !g.vao;
            if (fresh) glCreateVertexArrays(1, &g.vao);
            if (a.patches) {
                // The draw reads the patch buffers only (the VAO stays empty);
                // an animated cage: only the cage per frame, the points from
                // the stencils' compute stage.
                const bool animated = !a.cagePositions.empty();
                if (fresh || g.layoutId != a.layoutId || animated != g.stencils.uploaded())
                    bytes += uploadPatches(g, *a.patches, animated);
                if (animated) {
                    if (!stencilProgram.id()) stencilProgram = detail::makeStencilProgram();
                    bytes += g.stencils.apply(a.cagePositions, stencilProgram);
                }
                g.layoutId = a.layoutId;
                continue;
            }
            bytes += uploadAttrib(g.vao, g.vbo[0], 0, a.mesh.positions, 3);
            bytes += uploadAttrib(g.vao, g.vbo[1], 1, a.mesh.normals, 3);
            static const std::vector<glm::vec2> none2;
            static const std::vector<glm::vec4> none4;
            // Tangents move with morphing; UVs and indices never change.
            for (int k = 0; k < kMaxUvSets; ++k) {
                size_t kk = size_t(k);
                bytes +=
                    uploadAttrib(g.vao, g.vbo[6 + k], GLuint(6 + k),
                                 kk < a.vertexTangents.size() ? a.vertexTangents[kk] : none4, 4);
            }
            if (fresh || g.layoutId != a.layoutId) {
                for (int k = 0; k < kMaxUvSets; ++k) {
                    size_t kk = size_t(k);
                    bytes += uploadAttrib(g.vao, g.vbo[2 + k], GLuint(2 + k),
                                          kk < a.mesh.uvSets.size() ? a.mesh.uvSets[kk] : none2, 2);
                }
                bytes += a.mesh.indices.size() * sizeof(uint32_t);
                if (!g.ebo) glCreateBuffers(1, &g.ebo);
                glNamedBufferData(g.ebo, GLsizeiptr(a.mesh.indices.size() * sizeof(uint32_t)),
                                  a.mesh.indices.data(), GL_STATIC_DRAW);
                glVertexArrayElementBuffer(g.vao, g.ebo);
                g.indexCount = GLsizei(a.mesh.indices.size());
                g.layoutId = a.layoutId;
            }
        }
        meshesDirty = false;
        sg::gl::checkError("mesh upload");
        return bytes;
    }

    GLuint texture(const TextureImage* img) {
        auto it = textures.find(img->uid);
        if (it != textures.end()) return it->second;
        GLuint t = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &t);
        glTextureStorage2D(t, GLsizei(img->levels.size()), GL_RGBA32F, img->width(), img->height());
        // The exact mip chain the CPU reference filters (no glGenerateMipmap),
        // expanded to RGBA float a band of rows at a time (at most 4 MiB).
        std::vector<glm::vec4> band;
        for (size_t l = 0; l < img->levels.size(); ++l) {
            const auto& L = img->levels[l];
            const int rows = std::clamp(
                int((size_t(4) << 20) / (sizeof(glm::vec4) * size_t(L.width))), 1, L.height);
            band.resize(size_t(rows) * size_t(L.width));
            for (int y = 0; y < L.height; y += rows) {
                const int n = std::min(rows, L.height - y);
                L.expandRows(y, n, band.data());
                glTextureSubImage2D(t, GLint(l), 0, y, L.width, n, GL_RGBA, GL_FLOAT, band.data());
            }
        }
        glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        GLint wrap = img->wrap == Wrap::Clamp ? GL_CLAMP_TO_EDGE : GL_REPEAT;
        glTextureParameteri(t, GL_TEXTURE_WRAP_S, wrap);
        glTextureParameteri(t, GL_TEXTURE_WRAP_T, wrap);
        glTextureParameteri(t, GL_TEXTURE_MAX_LEVEL, GLint(img->levels.size()) - 1);
        textures.emplace(img->uid, t);
        sg::gl::checkError("texture upload");
        return t;
    }

    // The layer kinds' own GL objects (LayerKindAssets::bindGpu's cache).
    std::unordered_map<const LayerKind*, std::shared_ptr<void>> kindGpu;

    // Uploads (uniform empty) or binds (uniform set) the kinds' own assets of
    // `plan` on the units after its regular textures, kind after kind.
    void bindKindAssets(const MaterialPlan& plan, const SceneAssets& assets,
                        const std::function<int(const char*)>& uniform) {
        int unit = int(plan.textureKeys.size());
        for (const KindPlan& kp : plan.kindPlans) {
            const LayerKindAssets& ka = *kp.kind->assets;
            if (ka.bindGpu)
                ka.bindGpu(KindGpuContext{plan, kp, assets, kindGpu[kp.kind], unit, uniform});
            if (ka.gpuUnits) unit += ka.gpuUnits(kp);
        }
    }
    // The first texture unit after the plan's regular textures and the units
    // of its kinds' own assets.
    static GLuint unitAfterKindAssets(const MaterialPlan& plan) {
        GLuint unit = GLuint(plan.textureKeys.size());
        for (const KindPlan& kp : plan.kindPlans)
            if (kp.kind->assets->gpuUnits) unit += GLuint(kp.kind->assets->gpuUnits(kp));
        return unit;
    }

    // The plan's program; adaptive plans: the one for patches of
    // `patchPoints` control points (one per patch type).
    GpuProgram& program(const MaterialPlan& plan, RenderStats& stats, int patchPoints = 0) {
        const std::string key =
            (plan.adaptive ? plan.signature + "#p" + std::to_string(patchPoints) : plan.signature) +
            fragmentDefines + sg::shaders::targetName(dialect);
        auto it = programs.find(key);
        if (it != programs.end()) return it->second;
        ProgramSource src = assembleProgram(plan);
        if (!fragmentDefines.empty()) { // after the #version line
            const size_t eol = src.fragment.find('\n');
            src.fragment.insert(eol == std::string::npos ? src.fragment.size() : eol + 1,
                                fragmentDefines);
        }
        if (dialect != sg::shaders::Target::Glsl450) {
            SG_EXPECTS(!plan.adaptive, "GlRenderer::setDialect: adaptive patches need GLSL 4.50");
            src.vertex = sg::shaders::inDialect(src.vertex, dialect);
            src.fragment = sg::shaders::inDialect(src.fragment, dialect);
        }
        std::vector<std::pair<sg::gl::Stage, sg::shaders::Assembled>> stages;
        stages.push_back(
            {sg::gl::Stage::Vertex, sg::shaders::Assembled{src.vertex, src.vertexFiles}});
        if (plan.adaptive) {
            stages.push_back({sg::gl::Stage::TessControl, assemblePatchControl(patchPoints)});
            stages.push_back({sg::gl::Stage::TessEvaluation,
                              sg::shaders::Assembled{src.tessEval, src.tessEvalFiles}});
        }
        stages.push_back(
            {sg::gl::Stage::Fragment, sg::shaders::Assembled{src.fragment, src.fragmentFiles}});
        GpuProgram gp;
        gp.program = sg::gl::Program(stages);
        ++stats.programsCompiled;
        return programs.emplace(key, std::move(gp)).first->second;
    }

    // The tessellated draws of one adaptive mesh, one per patch type, after
    // bindDraw's uniforms on each type's program: levels from the shared
    // sgPatchEdgeTessLevel at `pixelsPerEdge` for this view.
    void drawPatches(const MaterialPlan& plan, const detail::DrawUniforms& u, const View& view,
                     const SceneAssets& assets, const GpuMesh& g,
                     const sg::mesh::AdaptivePatches& ap, const MeshInstance& mi,
                     RenderStats& stats) {
        const float pixelsPerEdge = mi.subdivPixelsPerEdge;
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.patchBuf[0]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.patchBuf[1]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, g.patchBuf[2]);
        if (!ap.uvSets.empty()) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, g.patchBuf[3]);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, g.patchBuf[4]);
        }
        const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
        for (const auto& arr : ap.arrays) {
            if (arr.patchCount == 0) continue;
            GpuProgram& gp = program(plan, stats, arr.pointsPerPatch);
            bindDraw(gp, plan, u, view, assets);
            glUniform1ui(gp.loc("uFirstIndex"), arr.firstIndex);
            glUniform1ui(gp.loc("uFirstPatch"), arr.firstPatch);
            glUniform1i(gp.loc("uPointsPerPatch"), arr.pointsPerPatch);
            glUniform1f(gp.loc("uFocalPx"), focalPx);
            glUniform1f(gp.loc("uPixelsPerEdge"), pixelsPerEdge);
            glUniform1f(gp.loc("uMaxTessLevel"), SG_TESS_MAX_LEVEL);
            if (plan.displacementUvSet >= 0 && mi.displacement) {
                // The height map on the unit after the fragment stage's
                // textures and kinds' own assets.
                const GLuint unit = unitAfterKindAssets(plan);
                auto it = assets.textures.find(mi.displacement->map.key());
                glBindTextureUnit(unit,
                                  it != assets.textures.end() ? texture(it->second.get()) : 0);
                glUniform1i(gp.loc("uDispMap"), GLint(unit));
                glUniform1f(gp.loc("uDispScale"), mi.displacement->scale);
                glUniform1f(gp.loc("uDispOffset"), mi.displacement->offset);
            }
            glPatchParameteri(GL_PATCH_VERTICES, arr.pointsPerPatch);
            // gl_VertexID counts from `first`: the vertex stage's patch
            // index and control points stay those of the whole array.
            const uint32_t perDraw = detail::patchesPerDraw(mesaDrawModule()),
                           ppp = uint32_t(arr.pointsPerPatch);
            for (uint32_t first = 0, n = 0; first < arr.patchCount; first += n) {
                n = std::min(perDraw, arr.patchCount - first);
                glDrawArrays(GL_PATCHES, GLint(first * ppp), GLsizei(n * ppp));
                ++stats.drawCalls;
            }
        }
    }
};

uint32_t detail::patchesPerDraw(bool mesaDrawModule) {
    if (!mesaDrawModule) return UINT32_MAX;
    const uint32_t side = uint32_t(SG_TESS_MAX_LEVEL) + 1u;
    return std::max(65535u / (side * side), 1u);
}

GlRenderer::GlRenderer() : impl_(std::make_unique<Impl>()) {}
GlRenderer::~GlRenderer() = default;

void GlRenderer::invalidateMeshes() {
    impl_->meshesDirty = true;
}
void GlRenderer::setDialect(sg::shaders::Target dialect) {
    SG_EXPECTS(dialect != sg::shaders::Target::Hlsl, "GlRenderer::setDialect: a GLSL dialect");
    impl_->dialect = dialect;
}

void GlRenderer::setFragmentDefines(const std::vector<std::string>& defines) {
    impl_->fragmentDefines.clear();
    for (const std::string& d : defines) impl_->fragmentDefines += "#define " + d + "\n";
}

size_t GlRenderer::cachedPrograms() const {
    return impl_->programs.size();
}

// One draw's state: the program, its uniforms (transforms, material,
// lights, layer records), the regular textures and the layer kinds' own
// assets on the units after them.
void GlRenderer::Impl::bindDraw(GpuProgram& gp, const MaterialPlan& plan,
                                const detail::DrawUniforms& u, const View& view,
                                const SceneAssets& assets) {
    Impl& I = *this;
    GLuint id = gp.program.id();
    glUseProgram(id);
    glUniformMatrix4fv(gp.loc("uModel"), 1, GL_FALSE, &u.model[0][0]);
    glUniformMatrix4fv(gp.loc("uModelRel"), 1, GL_FALSE, &u.modelRel[0][0]);
    glUniformMatrix3fv(gp.loc("uNormalMat"), 1, GL_FALSE, &u.normalMat[0][0]);
    glUniform1f(gp.loc("uDetSign"), u.detSign);
    glUniformMatrix4fv(gp.loc("uViewProjRel"), 1, GL_FALSE, &view.viewProjRel[0][0]);
    glUniform1i(gp.loc("uBfaceMode"), u.bfaceMode);
    glUniform1i(gp.loc("uAov"), u.aov);
    glUniform1f(gp.loc("uPrimBase"), u.primBase);
    glUniform3fv(gp.loc("uBaseColor"), 1, &u.baseColor[0]);
    glUniform1f(gp.loc("uRoughness"), u.roughness);
    glUniform3fv(gp.loc("uAmbient"), 1, &u.ambient[0]);
    glUniformMatrix3fv(gp.loc("uModel3"), 1, GL_FALSE, &u.model3[0][0]);
    glUniformMatrix3fv(gp.loc("uModelInv3"), 1, GL_FALSE, &u.modelInv3[0][0]);
    glUniform4fv(gp.loc("uLights[0]"), GLsizei(u.lights.size()), &u.lights[0][0]);
    glUniform4fv(gp.loc("uLayerData[0]"), GLsizei(u.records.size()), &u.records[0][0]);
    if (plan.uber)
        glUniform1fv(gp.loc("uLayerOn[0]"), GLsizei(u.uberFlags.size()), u.uberFlags.data());
    for (size_t s = 0; s < plan.textureKeys.size(); ++s) {
        auto it = assets.textures.find(plan.textureKeys[s]);
        GLuint t = it != assets.textures.end() ? I.texture(it->second.get()) : 0;
        glBindTextureUnit(GLuint(s), t);
        std::string name = "uTex" + std::to_string(s);
        glUniform1i(gp.loc(name.c_str()), GLint(s));
    }
    // The layer kinds' own assets on the units after them.
    I.bindKindAssets(plan, assets, [&gp](const char* name) { return int(gp.loc(name)); });
}

unsigned GlRenderer::renderToTexture(const Scene& scene, const SceneAssets& assets,
                                     const View& view) {
    Impl& I = *impl_;
    stats_ = RenderStats{};
    I.ensureFramebuffer(view.width, view.height);
    const auto updateStart = std::chrono::steady_clock::now();
    stats_.meshUploadBytes = I.uploadMeshes(assets);
    glBindFramebuffer(GL_FRAMEBUFFER, I.fbo);
    glViewport(0, 0, view.width, view.height);
    glm::vec3 bg = view.aov == Aov::Color ? scene.output.background : glm::vec3(0.0f);
    glClearColor(bg.x, bg.y, bg.z, view.aov == Aov::Color ? 1.0f : 0.0f);
    glClearDepth(1.0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    // Plans, program compiles and texture uploads first: the timed span
    // holds the draws only.
    std::vector<MaterialPlan> plans;
    std::vector<GpuProgram*> progs;
    for (size_t i = 0; i < scene.meshes.size(); ++i) {
        const MeshInstance& mi = scene.meshes[i];
        plans.push_back(uber_ ? planUberMaterial(scene, assets, int(i), mi.material)
                              : planMaterial(scene, assets, int(i), mi.material));
        const MeshAsset& ma = assets.meshes[i];
        if (ma.patches) {
            for (const auto& arr : ma.patches->arrays)
                if (arr.patchCount) I.program(plans.back(), stats_, arr.pointsPerPatch);
            progs.push_back(nullptr); // one program per patch type (Impl::drawPatches)
        } else {
            progs.push_back(&I.program(plans.back(), stats_));
        }
        for (const auto& key : plans.back().textureKeys) {
            auto it = assets.textures.find(key);
            if (it != assets.textures.end()) I.texture(it->second.get());
        }
        I.bindKindAssets(plans.back(), assets, nullptr); // upload only
    }
    if (!I.query) glCreateQueries(GL_TIME_ELAPSED, 1, &I.query);
    glFinish(); // uploads done: the wall time starts with an idle GPU
    const auto wallStart = std::chrono::steady_clock::now();
    stats_.meshUpdateWallMs =
        std::chrono::duration<double, std::milli>(wallStart - updateStart).count();
    glBeginQuery(GL_TIME_ELAPSED, I.query);
    // Large images with a progress callback: drawn in horizontal bands
    // (scissored, so every pixel is shaded exactly as in one pass), each
    // finished and reported.
    const int bands = progress_ && int64_t(view.width) * view.height >= kBandedPixels
                          ? (view.height + kBandRows - 1) / kBandRows
                          : 1;
    if (bands > 1) glEnable(GL_SCISSOR_TEST);
    for (int band = 0; band < bands; ++band) {
        if (bands > 1)
            glScissor(0, band * kBandRows, view.width,
                      std::min(kBandRows, view.height - band * kBandRows));
        float primBase = 0.0f;
        for (size_t i = 0; i < scene.meshes.size(); ++i) {
            const MeshInstance& mi = scene.meshes[i];
            const MaterialPlan& plan = plans[i];
            detail::DrawUniforms u =
                detail::drawUniforms(scene, assets, plan, view, int(i), primBase);
            const Material& mat = scene.materials[size_t(mi.material)];
            if (mat.doubleSided == DoubleSided::Off) {
                glEnable(GL_CULL_FACE);
                glCullFace(GL_BACK);
            } else {
                glDisable(GL_CULL_FACE);
            }
            glFrontFace(u.detSign < 0.0f ? GL_CW : GL_CCW); // mirroring transforms flip the winding
            glBindVertexArray(I.meshes[i].vao);
            if (const auto& patches = assets.meshes[i].patches) {
                I.drawPatches(plan, u, view, assets, I.meshes[i], *patches, mi, stats_);
            } else {
                I.bindDraw(*progs[i], plan, u, view, assets);
                glDrawElements(GL_TRIANGLES, I.meshes[i].indexCount, GL_UNSIGNED_INT, nullptr);
                ++stats_.drawCalls;
            }
            primBase += float(assets.meshes[i].mesh.triangleCount());
        }
        if (bands > 1) {
            glFinish();
            progress_(band + 1, bands);
        }
    }
    glDisable(GL_SCISSOR_TEST);
    // glFinish inside the bracket: drivers that rasterise at the flush
    // (llvmpipe) do the frame's work before the query ends, so the query and
    // the wall time both cover the whole frame.
    glFinish();
    glEndQuery(GL_TIME_ELAPSED);
    stats_.drawWallMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wallStart)
            .count();
    // The result of the query that bracketed this frame's draws (waits for
    // it), when the driver's timer measures the frame (Impl::timerMeasures).
    GLuint64 ns = 0;
    glGetQueryObjectui64v(I.query, GL_QUERY_RESULT, &ns);
    stats_.gpuMeasured = I.timerMeasures() && ns > 0;
    stats_.gpuMs = stats_.gpuMeasured ? double(ns) * 1e-6 : 0.0;
    glBindVertexArray(0);
    glUseProgram(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    sg::gl::checkError("render");
    return I.colorTex;
}

Image GlRenderer::render(const Scene& scene, const SceneAssets& assets, const View& view) {
    renderToTexture(scene, assets, view);
    Image img(view.width, view.height, 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, view.width, view.height, GL_RGBA, GL_FLOAT, img.samples.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    sg::gl::checkError("readback");
    return img;
}

} // namespace sg::render
