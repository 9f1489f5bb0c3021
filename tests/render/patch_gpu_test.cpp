// The adaptive-patch draw on the GPU (shaders/sg/patch/patch_{vs,tcs,tes}.glsl)
// against the CPU evaluation of the same shared source: the tessellation
// evaluation stage appends every point it evaluates (patch, domain (u,v),
// object position) to a buffer (SG_PATCH_CAPTURE), with rasterisation off.
//  - parity: each captured position equals the shared basis evaluated on
//    the CPU at the same (u,v) within a few ulp;
//  - levels: the points GL generated on each patch edge are k/n, n the
//    level the CPU computes with the shared sgPatchEdgeTessLevel from the
//    patch's corner vertices;
//  - shared edges: two patches of the same depth that share an edge put
//    the same number of points on it (no T-junctions), at positions equal
//    bit for bit from both sides (sg/patch/watertight.glsl);
//  - transition edges: a patch's edge against two patches one level
//    deeper (one per half) carries as many points as the two halves
//    together, at positions equal bit for bit to the halves' own.
// And the CPU reference's own tessellation of the quad domain
// (detail::tessellateQuadDomain) against the triangles llvmpipe emits for
// one patch (transform feedback), over a sweep of levels (QuadDomainGpu).
#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "render_internal.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

namespace g = sg::glsl;
using sg::mesh::AdaptivePatches;

std::filesystem::path dataPath(const std::string& rel) {
    const char* env = std::getenv("SURFGRAD_DATA_DIR");
    return (env && *env ? std::filesystem::path(env) : std::filesystem::path(SURFGRAD_DATA_DIR)) /
           rel;
}

sg::gl::HeadlessContext& context() {
    static sg::gl::HeadlessContext ctx;
    return ctx;
}

struct Captured {
    uint32_t patch;
    glm::vec2 uv;
    glm::vec3 pos;
};

// Camera at `eye` (camera-relative positions = object - eye), focal length
// and pixels per edge as a 1000-pixel-high view would use.
struct View {
    glm::vec3 eye{0.0f, 0.0f, 6.0f};
    float focalPx = 1000.0f;
    float pixelsPerEdge = 6.0f;
    float maxLevel = 64.0f;
    glm::mat4 modelRel() const { return glm::translate(glm::mat4(1.0f), -eye); }
};

// Where the patch's arrays put patch p.
const sg::mesh::AdaptivePatchArray& arrayOf(const AdaptivePatches& ap, uint32_t p) {
    for (const auto& a : ap.arrays)
        if (p >= a.firstPatch && p < a.firstPatch + a.patchCount) return a;
    throw std::runtime_error("patch out of range");
}

std::vector<Captured> drawAndCapture(const AdaptivePatches& ap, const View& view) {
    context();
    GLuint buf[4];
    glCreateBuffers(4, buf);
    std::vector<float> pts;
    for (const glm::vec3& p : ap.points) pts.insert(pts.end(), {p.x, p.y, p.z});
    glNamedBufferStorage(buf[0], GLsizeiptr(pts.size() * 4), pts.data(), 0);
    const std::vector<uint32_t> data = sg::render::detail::patchRecords(ap); // the renderer's
    glNamedBufferStorage(buf[1], GLsizeiptr(data.size() * 4), data.data(), 0);
    const uint32_t capacity = 4u << 20;
    std::vector<uint32_t> cap(2 + 6 * size_t(capacity), 0u);
    cap[1] = capacity;
    glNamedBufferStorage(buf[2], GLsizeiptr(cap.size() * 4), cap.data(), GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferStorage(buf[3], GLsizeiptr(ap.indices.size() * 4), ap.indices.data(), 0);
    GLuint vao;
    glCreateVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf[0]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buf[1]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, buf[2]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, buf[3]);
    // A surfaceless context has no default framebuffer: draws need one
    // bound even with rasterisation off.
    GLuint fbo, rb;
    glCreateRenderbuffers(1, &rb);
    glNamedRenderbufferStorage(rb, GL_RGBA8, 1, 1);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glEnable(GL_RASTERIZER_DISCARD);
    for (const auto& arr : ap.arrays) {
        const std::string n = std::to_string(arr.pointsPerPatch);
        namespace sh = sg::shaders;
        sg::gl::Program prog({
            {sg::gl::Stage::Vertex, sh::assemble("#include \"sg/patch/patch_vs.glsl\"\n", "vs")},
            {sg::gl::Stage::TessControl, sh::assemble("#include \"sg/patch/patch_tcs.glsl\"\n",
                                                      "tcs", {"SG_PATCH_POINTS " + n})},
            {sg::gl::Stage::TessEvaluation,
             sh::assemble("#include \"sg/patch/patch_tes.glsl\"\n", "tes", {"SG_PATCH_CAPTURE 1"})},
        });
        glUseProgram(prog.id());
        const glm::mat4 rel = view.modelRel(), id(1.0f);
        const glm::mat3 id3(1.0f);
        glUniform1ui(prog.uniform("uFirstPatch"), arr.firstPatch);
        glUniform1ui(prog.uniform("uFirstIndex"), arr.firstIndex);
        glUniform1i(prog.uniform("uPointsPerPatch"), arr.pointsPerPatch);
        glUniform1i(prog.uniform("uPatchType"), arr.type);
        glUniformMatrix4fv(prog.uniform("uModelRel"), 1, GL_FALSE, &rel[0][0]);
        glUniformMatrix4fv(prog.uniform("uModel"), 1, GL_FALSE, &id[0][0]);
        glUniformMatrix4fv(prog.uniform("uViewProjRel"), 1, GL_FALSE, &id[0][0]);
        glUniformMatrix3fv(prog.uniform("uNormalMat"), 1, GL_FALSE, &id3[0][0]);
        glUniform1f(prog.uniform("uFocalPx"), view.focalPx);
        glUniform1f(prog.uniform("uPixelsPerEdge"), view.pixelsPerEdge);
        glUniform1f(prog.uniform("uMaxTessLevel"), view.maxLevel);
        glPatchParameteri(GL_PATCH_VERTICES, arr.pointsPerPatch);
        // Split as the renderer splits on llvmpipe (render_internal.h).
        const uint32_t perDraw = sg::render::detail::patchesPerDraw(true);
        const uint32_t ppp = uint32_t(arr.pointsPerPatch);
        for (uint32_t first = 0, k = 0; first < arr.patchCount; first += k) {
            k = std::min(perDraw, arr.patchCount - first);
            glDrawArrays(GL_PATCHES, GLint(first * ppp), GLsizei(k * ppp));
        }
        sg::gl::checkError("patch draw");
    }
    glDisable(GL_RASTERIZER_DISCARD);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buf[2], 0, GLsizeiptr(cap.size() * 4), cap.data());
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(1, &rb);
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(4, buf);
    EXPECT_LE(cap[0], capacity) << "capture buffer too small";
    std::vector<Captured> out(std::min(cap[0], capacity));
    for (size_t i = 0; i < out.size(); ++i) {
        const uint32_t* w = &cap[2 + 6 * i];
        out[i].patch = w[0];
        std::memcpy(&out[i].uv, w + 1, 8);
        std::memcpy(&out[i].pos, w + 3, 12);
    }
    return out;
}

glm::vec3 cpuEvalSite(const AdaptivePatches& ap, uint32_t p, glm::vec2 uv) {
    const auto& arr = arrayOf(ap, p);
    const uint32_t f1 = ap.params[p].y;
    const g::SgPatchBasis b = g::sgPatchBasis(arr.type, f1, g::sgPatchUnnormalizeUv(f1, uv));
    glm::vec3 pos(0.0f);
    const uint32_t* idx =
        &ap.indices[arr.firstIndex + (p - arr.firstPatch) * uint32_t(arr.pointsPerPatch)];
    for (int i = 0; i < b.count; ++i) pos += b.pos.v[i] * ap.points[idx[i]];
    return pos;
}

constexpr int kFrom[4] = {0, 0, 1, 3}, kTo[4] = {3, 1, 2, 2}; // edge k's corners

// Outer levels (u=0, v=0, u=1, v=1 edges) the CPU computes for patch p, as
// the control stage does (patch_tcs.glsl), and its transitions with the
// lower halves' levels.
glm::vec4 cpuLevels(const AdaptivePatches& ap, uint32_t p, const View& v,
                    g::SgPatchTransitions* trOut = nullptr) {
    const glm::mat4 rel = v.modelRel();
    auto c = [&](uint32_t patch, int i) {
        return glm::vec3(rel * glm::vec4(ap.points[ap.cornerVertices[patch][i]], 1.0f));
    };
    const float halfMax = g::sgPatchHalfMaxLevel(v.maxLevel);
    auto l = [&](uint32_t patch, int k, float maxLevel) {
        return g::sgPatchEdgeTessLevel(c(patch, kFrom[k]), c(patch, kTo[k]), v.focalPx,
                                       v.pixelsPerEdge, maxLevel);
    };
    g::SgPatchTransitions tr = g::sgPatchNoTransitions();
    tr.lo = ap.transitionLo[p];
    tr.hi = ap.transitionHi[p];
    tr.mid = ap.transitionMid[p];
    glm::vec4 out;
    const uint32_t mask = ap.transitionMask[p];
    for (int k = 0; k < 4; ++k) {
        if ((mask >> k) & 1u) {
            tr.loLevel[k] = l(tr.lo[k] >> 3, int((tr.lo[k] >> 1) & 3u), halfMax);
            out[k] = tr.loLevel[k] + l(tr.hi[k] >> 3, int((tr.hi[k] >> 1) & 3u), halfMax);
        } else {
            out[k] = l(p, k, (mask >> (4 + k)) & 1u ? halfMax : v.maxLevel);
        }
    }
    if (trOut) *trOut = tr;
    return out;
}

// The CPU side of the TES: boundary points at their owner's site, with the
// patch's levels and transitions (cpuLevels).
glm::vec3 cpuEval(const AdaptivePatches& ap, uint32_t p, glm::vec2 uv, glm::vec4 outer,
                  const g::SgPatchTransitions& tr) {
    const g::SgPatchSite s =
        g::sgPatchEvalSite(p, ap.edgeOwners[p], ap.cornerOwners[p], tr, outer, uv);
    return cpuEvalSite(ap, s.patchIndex, s.uv);
}

class PatchGpu : public ::testing::TestWithParam<const char*> {};

struct CrackFigures {
    size_t shared = 0, transitions = 0;
};

CrackFigures checkTessellation(const std::string& name, const AdaptivePatches& ap,
                               const View& view);

TEST_P(PatchGpu, TessellatedPointsMatchTheCpuAndShareEdges) {
    const std::string name = GetParam();
    sg::mesh::PolygonMesh cage = sg::mesh::loadPolygonMesh(dataPath("osd-shapes/" + name + ".obj"));
    const AdaptivePatches ap = sg::mesh::buildAdaptivePatches(cage, cage.options, 3, name);
    const CrackFigures f = checkTessellation(name, ap, View{});
    EXPECT_GT(f.shared, 0u);
}

// Transition edges on spot and on osd-shapes with creases and extraordinary
// vertices (isolation 2 and 3), from several views: near and far (levels
// from 1 to the cap, so the halves' levels differ from each other and from
// the same-depth edges), and one so close that the halves reach the cap
// (sgPatchHalfMaxLevel) and the coarse side the maximum.
TEST(PatchGpuTransitions, TransitionEdgesAreBitwiseEqualFromBothSides) {
    struct Case {
        std::string file;
        int isolation;
    };
    const Case cases[] = {{"meshes/spot/spot_control_mesh.obj", 2},
                          {"osd-shapes/catmark_cube_creases1.obj", 3},
                          {"osd-shapes/catmark_pole8.obj", 2},
                          {"osd-shapes/catmark_xord_interior.obj", 3}};
    View views[3];
    views[0].eye = glm::vec3(0.3f, 0.4f, 4.0f);
    views[1].eye = glm::vec3(-2.0f, 1.0f, 30.0f);
    views[1].pixelsPerEdge = 3.0f;
    views[2].eye = glm::vec3(0.2f, 0.1f, 2.5f);
    views[2].pixelsPerEdge = 1.0f;
    size_t transitions = 0;
    for (const Case& c : cases) {
        sg::mesh::PolygonMesh cage = sg::mesh::loadPolygonMesh(dataPath(c.file));
        const AdaptivePatches ap =
            sg::mesh::buildAdaptivePatches(cage, cage.options, c.isolation, c.file);
        for (const View& v : views) transitions += checkTessellation(c.file, ap, v).transitions;
    }
    EXPECT_GT(transitions, 100u);
}

CrackFigures checkTessellation(const std::string& name, const AdaptivePatches& ap,
                               const View& view) {
    CrackFigures figures;
    const std::vector<Captured> pts = drawAndCapture(ap, view);
    EXPECT_GT(pts.size(), ap.patchCount() * 4);
    float extent = 0.0f;
    for (const glm::vec3& p : ap.points) extent = std::max(extent, g::sgMaxAbs3(p));

    // Parity. Up to 20 products summed in the same order on both sides;
    // the GPU may fuse multiply-adds: a few ulp of the largest term
    // (weights <= 1 times coordinates <= extent).
    std::vector<glm::vec4> levels(ap.patchCount());
    std::vector<g::SgPatchTransitions> trans(ap.patchCount());
    for (uint32_t p = 0; p < ap.patchCount(); ++p) levels[p] = cpuLevels(ap, p, view, &trans[p]);
    float worst = 0.0f;
    for (const Captured& c : pts) {
        if (c.patch >= ap.patchCount()) {
            ADD_FAILURE() << "captured patch index out of range";
            return figures;
        }
        worst = std::max(worst, g::sgMaxAbs3(c.pos - cpuEval(ap, c.patch, c.uv, levels[c.patch],
                                                             trans[c.patch])));
    }
    EXPECT_LE(worst, 4e-6f * extent);
    ::testing::Test::RecordProperty("max_gpu_cpu_difference", std::to_string(worst));

    // Edge points are k/n with the CPU's level n.
    using EdgePoints = std::vector<std::pair<float, glm::vec3>>; // (param along the edge, position)
    std::map<uint32_t, std::array<EdgePoints, 4>> edges;         // patch -> its four edges
    for (const Captured& c : pts) {
        auto& e = edges[c.patch];
        if (c.uv.x == 0.0f) e[0].push_back({c.uv.y, c.pos});
        if (c.uv.y == 0.0f) e[1].push_back({c.uv.x, c.pos});
        if (c.uv.x == 1.0f) e[2].push_back({c.uv.y, c.pos});
        if (c.uv.y == 1.0f) e[3].push_back({c.uv.x, c.pos});
    }
    EXPECT_EQ(edges.size(), ap.patchCount()); // every patch was tessellated
    for (auto& [p, e] : edges) {
        const glm::vec4 lv = levels[p];
        for (int k = 0; k < 4; ++k) {
            auto& ek = e[size_t(k)];
            std::sort(ek.begin(), ek.end(),
                      [](const auto& x, const auto& y) { return x.first < y.first; });
            ek.erase(std::unique(ek.begin(), ek.end(),
                                 [](const auto& x, const auto& y) { return x.first == y.first; }),
                     ek.end());
            const int n = int(lv[k]);
            EXPECT_EQ(int(e[size_t(k)].size()), n + 1) << "patch " << p << " edge " << k;
            if (int(e[size_t(k)].size()) != n + 1) return figures;
            // GL's i/n, computed its own way: llvmpipe's tessellator works
            // in 16-bit fixed point (i times 2^16 / n rounded, so the
            // rounding accumulates along the edge: at most 1.9e-4, at
            // n = 53; QuadDomainGpu checks the exact values); a quarter
            // step tells the points apart and keeps them in order.
            for (int i = 0; i <= n; ++i)
                EXPECT_NEAR(e[size_t(k)][size_t(i)].first, float(i) / float(n), 0.25f / float(n))
                    << "patch " << p << " edge " << k;
        }
    }

    // Shared edges between patches of the same depth: same vertex pair.
    std::map<std::pair<uint32_t, uint32_t>, std::vector<std::pair<uint32_t, int>>> byEdge;
    for (uint32_t p = 0; p < ap.patchCount(); ++p) {
        const glm::uvec4 c = ap.cornerVertices[p];
        const uint32_t ends[4][2] = {{c.x, c.w}, {c.x, c.y}, {c.y, c.z}, {c.w, c.z}};
        for (int k = 0; k < 4; ++k)
            byEdge[{std::min(ends[k][0], ends[k][1]), std::max(ends[k][0], ends[k][1])}].push_back(
                {p, k});
    }
    size_t& shared = figures.shared;
    size_t bitwise = 0, edgePoints = 0;
    float gap = 0.0f;
    for (const auto& [key, sides] : byEdge) {
        if (sides.size() != 2) continue;
        ++shared;
        const auto& a = edges[sides[0].first][size_t(sides[0].second)];
        const auto& b = edges[sides[1].first][size_t(sides[1].second)];
        EXPECT_EQ(a.size(), b.size()) << "T-junction on a shared edge";
        // GPU positions along the edge from both sides, matched by nearest
        // point (the two sides may run the edge in opposite directions).
        for (const auto& pa : a) {
            float best = INFINITY;
            for (const auto& pb : b) best = std::min(best, glm::length(pa.second - pb.second));
            gap = std::max(gap, best);
            bitwise += best == 0.0f;
            ++edgePoints;
        }
    }
    // Crack-free by construction: every point of a shared edge is evaluated
    // from the edge's owner at the same integer parameter on both sides.
    EXPECT_EQ(gap, 0.0f);
    EXPECT_EQ(bitwise, edgePoints);

    // Transition edges: the coarse side's points (sorted along its edge)
    // against the two halves' points from the fine side, each half in the
    // coarse edge's direction, the midpoint once: the same count and, in
    // order, the same bits.
    size_t tBitwise = 0, tPoints = 0, tMismatch = 0;
    int tLevelMin = 1 << 30, tLevelMax = 0;
    auto halfPoints = [&](uint32_t code) {
        EdgePoints h = edges[code >> 3][size_t((code >> 1) & 3u)];
        if (code & 1u) std::reverse(h.begin(), h.end()); // now from the coarse side's start
        return h;
    };
    for (uint32_t p = 0; p < ap.patchCount(); ++p) {
        for (int k = 0; k < 4; ++k) {
            if (!((ap.transitionMask[p] >> k) & 1u)) continue;
            ++figures.transitions;
            const EdgePoints& coarse = edges[p][size_t(k)];
            const EdgePoints lo = halfPoints(ap.transitionLo[p][k]);
            const EdgePoints hi = halfPoints(ap.transitionHi[p][k]);
            tLevelMin = std::min(tLevelMin, int(coarse.size()) - 1);
            tLevelMax = std::max(tLevelMax, int(coarse.size()) - 1);
            EdgePoints fine = lo;
            fine.insert(fine.end(), hi.begin() + (hi.empty() ? 0 : 1), hi.end());
            if (fine.size() != coarse.size()) {
                ++tMismatch;
                continue;
            }
            for (size_t i = 0; i < fine.size(); ++i) {
                tBitwise += std::memcmp(&fine[i].second, &coarse[i].second, sizeof(glm::vec3)) == 0;
                ++tPoints;
            }
        }
    }
    EXPECT_EQ(tMismatch, 0u) << "T-junctions on transition edges";
    EXPECT_EQ(tBitwise, tPoints);
    std::printf("%s (eye %.1f %.1f %.1f, %.1f px/edge): %zu patches, %zu points, %zu shared "
                "same-depth edges, gpu-cpu %.3g, edge gap %.3g (extent %.3g), %zu of %zu edge "
                "points bitwise equal; %zu transition edges (levels %d..%d), %zu of %zu points "
                "bitwise equal\n",
                name.c_str(), double(view.eye.x), double(view.eye.y), double(view.eye.z),
                double(view.pixelsPerEdge), ap.patchCount(), pts.size(), shared, double(worst),
                double(gap), double(extent), bitwise, edgePoints, figures.transitions,
                figures.transitions ? tLevelMin : 0, tLevelMax, tBitwise, tPoints);
    return figures;
}

INSTANTIATE_TEST_SUITE_P(Shapes, PatchGpu,
                         ::testing::Values("catmark_torus", "catmark_pole8",
                                           "catmark_xord_boundary", "catmark_hole_test1",
                                           "catmark_cube_creases1"));

// ---- The quad domain's triangles, llvmpipe's tessellator as the oracle ----
//
// The CPU reference tessellates every patch itself (patch_tessellation.cpp,
// detail::tessellateQuadDomain). Its triangles must be the GPU's, or the
// two images differ inside triangles by the interpolated attributes'
// second difference across a cell. Oracle: what llvmpipe emits for one
// patch with a minimal evaluation stage (layout(quads, equal_spacing, ccw),
// gl_TessCoord out) through transform feedback, at levels set by a control
// stage as the renderer's sets them (floats holding integers). Compared as
// sets of triangles, each a counter-clockwise triple of domain points:
//  - triangles: points named by lattice indices (their index on the edge
//    they lie on, or (i, j) of the inner grid), so the comparison does not
//    depend on how either side rounds i / n;
//  - points: every point's (u, v) bit for bit.

// One patch's triangles as llvmpipe emits them (three (u, v) each, in
// emission order).
class DomainCapture {
public:
    DomainCapture() {
        context();
        const char* vs = "#version 450 core\nvoid main() { gl_Position = vec4(0.0); }\n";
        const char* tcs = "#version 450 core\nlayout(vertices = 1) out;\n"
                          "uniform vec4 uOuter;\nuniform vec2 uInner;\n"
                          "void main() {\n"
                          "    gl_out[gl_InvocationID].gl_Position = vec4(0.0);\n"
                          "    for (int k = 0; k < 4; ++k) gl_TessLevelOuter[k] = uOuter[k];\n"
                          "    gl_TessLevelInner[0] = uInner.x;\n"
                          "    gl_TessLevelInner[1] = uInner.y;\n"
                          "}\n";
        const char* tes = "#version 450 core\nlayout(quads, equal_spacing, ccw) in;\n"
                          "out vec2 tc;\n"
                          "void main() {\n"
                          "    tc = gl_TessCoord.xy;\n"
                          "    gl_Position = vec4(gl_TessCoord.xy, 0.0, 1.0);\n"
                          "}\n";
        prog_ = glCreateProgram();
        const std::pair<GLenum, const char*> stages[] = {{GL_VERTEX_SHADER, vs},
                                                         {GL_TESS_CONTROL_SHADER, tcs},
                                                         {GL_TESS_EVALUATION_SHADER, tes}};
        for (const auto& [type, src] : stages) {
            const GLuint s = glCreateShader(type);
            glShaderSource(s, 1, &src, nullptr);
            glCompileShader(s);
            GLint ok = 0;
            glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
            EXPECT_TRUE(ok) << src;
            glAttachShader(prog_, s);
            glDeleteShader(s);
        }
        const char* varyings[] = {"tc"};
        glTransformFeedbackVaryings(prog_, 1, varyings, GL_INTERLEAVED_ATTRIBS);
        glLinkProgram(prog_);
        GLint linked = 0;
        glGetProgramiv(prog_, GL_LINK_STATUS, &linked);
        EXPECT_TRUE(linked);
        glCreateVertexArrays(1, &vao_);
        glCreateBuffers(1, &buf_);
        // The largest patch (every level 64): 2 * 64 * 64 triangles.
        glNamedBufferStorage(buf_, GLsizeiptr(kMaxTriangles * 6 * sizeof(float)), nullptr, 0);
        glCreateQueries(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, 1, &query_);
        // Draws need a framebuffer even with rasterisation off (surfaceless).
        glCreateRenderbuffers(1, &rb_);
        glNamedRenderbufferStorage(rb_, GL_RGBA8, 1, 1);
        glCreateFramebuffers(1, &fbo_);
        glNamedFramebufferRenderbuffer(fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb_);
    }
    ~DomainCapture() {
        glDeleteFramebuffers(1, &fbo_);
        glDeleteRenderbuffers(1, &rb_);
        glDeleteQueries(1, &query_);
        glDeleteBuffers(1, &buf_);
        glDeleteVertexArrays(1, &vao_);
        glDeleteProgram(prog_);
    }
    DomainCapture(const DomainCapture&) = delete;
    DomainCapture& operator=(const DomainCapture&) = delete;

    std::vector<std::array<glm::vec2, 3>> triangles(const std::array<int, 4>& outer, int innerU,
                                                    int innerV) {
        glUseProgram(prog_);
        glUniform4f(glGetUniformLocation(prog_, "uOuter"), float(outer[0]), float(outer[1]),
                    float(outer[2]), float(outer[3]));
        glUniform2f(glGetUniformLocation(prog_, "uInner"), float(innerU), float(innerV));
        glBindVertexArray(vao_);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
        glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, buf_);
        glPatchParameteri(GL_PATCH_VERTICES, 1);
        glEnable(GL_RASTERIZER_DISCARD);
        glBeginQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN, query_);
        glBeginTransformFeedback(GL_TRIANGLES);
        glDrawArrays(GL_PATCHES, 0, 1);
        glEndTransformFeedback();
        glEndQuery(GL_TRANSFORM_FEEDBACK_PRIMITIVES_WRITTEN);
        glDisable(GL_RASTERIZER_DISCARD);
        sg::gl::checkError("domain capture");
        GLuint written = 0;
        glGetQueryObjectuiv(query_, GL_QUERY_RESULT, &written);
        std::vector<std::array<glm::vec2, 3>> out(std::min<size_t>(written, kMaxTriangles));
        if (!out.empty())
            glGetNamedBufferSubData(buf_, 0, GLsizeiptr(out.size() * sizeof(out[0])), out.data());
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glBindVertexArray(0);
        return out;
    }

private:
    static constexpr size_t kMaxTriangles = 2 * 64 * 64;
    GLuint prog_ = 0, vao_ = 0, buf_ = 0, query_ = 0, fbo_ = 0, rb_ = 0;
};

// One tessellation case: outer levels (GL's order) and inner levels.
struct DomainLevels {
    std::array<int, 4> outer;
    int innerU, innerV;
};

// Inner levels as patch_tcs.glsl sets them: the larger opposite outer level.
DomainLevels withTcsInner(std::array<int, 4> o) {
    return {o, std::max(o[1], o[3]), std::max(o[0], o[2])};
}

// A domain point named by integers: (edge, index along it) on an edge
// (GL's edge order; corners on the first edge that holds them), (4, i, j)
// in the inner lattice (inner levels below 2 count as 2).
using PointKey = std::array<int, 3>;
PointKey pointKey(glm::vec2 p, const DomainLevels& l) {
    const int m = std::max(l.innerU, 2), n = std::max(l.innerV, 2);
    auto index = [](float t, int level) { return int(std::lround(double(t) * level)); };
    if (p.x == 0.0f) return {0, index(p.y, l.outer[0]), 0};
    if (p.y == 0.0f) return {1, index(p.x, l.outer[1]), 0};
    if (p.x == 1.0f) return {2, index(p.y, l.outer[2]), 0};
    if (p.y == 1.0f) return {3, index(p.x, l.outer[3]), 0};
    return {4, index(p.x, m), index(p.y, n)};
}

// A triangle as its three keys from the smallest, in its own (rotated) order.
using TriangleKey = std::array<PointKey, 3>;
TriangleKey triangleKey(const std::array<PointKey, 3>& t) {
    const size_t k = size_t(std::min_element(t.begin(), t.end()) - t.begin());
    return {t[k], t[(k + 1) % 3], t[(k + 2) % 3]};
}

float signedArea(const std::array<glm::vec2, 3>& t) {
    const glm::vec2 e1 = t[1] - t[0], e2 = t[2] - t[0];
    return e1.x * e2.y - e1.y * e2.x;
}

struct DomainComparison {
    size_t gpuTriangles = 0, cpuTriangles = 0;
    size_t onlyGpu = 0, onlyCpu = 0; // triangles of one side only
    size_t clockwise = 0;            // GPU triangles not counter-clockwise
    size_t pointsDiffer = 0;         // points whose (u, v) differ in some bit
};

DomainComparison compareDomain(DomainCapture& capture, const DomainLevels& l) {
    DomainComparison c;
    const auto gpuTris = capture.triangles(l.outer, l.innerU, l.innerV);
    const sg::render::detail::QuadTessellation cpu =
        sg::render::detail::tessellateQuadDomain(l.outer, l.innerU, l.innerV);
    std::map<PointKey, glm::vec2> gpuPoint, cpuPoint;
    std::multiset<TriangleKey> gpuSet, cpuSet;
    for (const auto& t : gpuTris) {
        c.clockwise += signedArea(t) <= 0.0f;
        std::array<PointKey, 3> k;
        for (size_t i = 0; i < 3; ++i) {
            k[i] = pointKey(t[i], l);
            gpuPoint[k[i]] = t[i];
        }
        gpuSet.insert(triangleKey(k));
    }
    for (size_t f = 0; f + 2 < cpu.triangles.size(); f += 3) {
        std::array<PointKey, 3> k;
        for (size_t i = 0; i < 3; ++i) {
            const glm::vec2 p = cpu.uv[cpu.triangles[f + i]];
            k[i] = pointKey(p, l);
            cpuPoint[k[i]] = p;
        }
        cpuSet.insert(triangleKey(k));
    }
    c.gpuTriangles = gpuSet.size();
    c.cpuTriangles = cpuSet.size();
    for (const TriangleKey& t : gpuSet) c.onlyGpu += cpuSet.count(t) == 0;
    for (const TriangleKey& t : cpuSet) c.onlyCpu += gpuSet.count(t) == 0;
    for (const auto& [key, p] : gpuPoint) {
        const auto it = cpuPoint.find(key);
        c.pointsDiffer += it == cpuPoint.end() || std::memcmp(&it->second, &p, sizeof(p)) != 0;
    }
    return c;
}

// The sweep: every equal level 1..64; every outer combination of 1..5
// (both parities, the smallest and degenerate rings); outer levels drawn
// at random in 1..64 (asymmetric patches); transition edges (the sum of
// two halves' levels in 1..32, sgPatchHalfMaxLevel of the cap 64) against
// random other edges, all with the control stage's inner levels; and
// arbitrary inner levels (every pair in 1..20, random pairs in 1..64)
// with random outer levels.
std::vector<DomainLevels> domainSweep() {
    std::vector<DomainLevels> cases;
    for (int l = 1; l <= 64; ++l) cases.push_back({{l, l, l, l}, l, l});
    for (int a = 1; a <= 5; ++a)
        for (int b = 1; b <= 5; ++b)
            for (int c = 1; c <= 5; ++c)
                for (int d = 1; d <= 5; ++d) cases.push_back(withTcsInner({a, b, c, d}));
    std::mt19937 rng(20240611u);
    auto level = [&](int hi) { return int(rng() % uint32_t(hi)) + 1; };
    for (int k = 0; k < 400; ++k)
        cases.push_back(withTcsInner({level(64), level(64), level(64), level(64)}));
    for (int lo = 1; lo <= 32; lo += 1)
        for (int hi : {lo, level(32), level(32)}) {
            std::array<int, 4> o = {level(64), level(64), level(64), level(64)};
            o[size_t(lo + hi) % 4] = lo + hi;
            cases.push_back(withTcsInner(o));
        }
    for (int m = 1; m <= 20; ++m)
        for (int n = 1; n <= 20; ++n)
            cases.push_back({{level(64), level(64), level(64), level(64)}, m, n});
    for (int k = 0; k < 200; ++k)
        cases.push_back({{level(64), level(64), level(64), level(64)}, level(64), level(64)});
    return cases;
}

std::string describe(const DomainLevels& l) {
    return "outer " + std::to_string(l.outer[0]) + " " + std::to_string(l.outer[1]) + " " +
           std::to_string(l.outer[2]) + " " + std::to_string(l.outer[3]) + ", inner " +
           std::to_string(l.innerU) + " " + std::to_string(l.innerV);
}

// Every case of the sweep: the CPU's triangles are llvmpipe's, all
// counter-clockwise in (u, v), and none is missing or extra; every domain
// point has llvmpipe's (u, v) bit for bit (16-bit fixed point, not the
// float quotient i / n: 1/3 is 21845 / 2^16).
TEST(QuadDomainGpu, TrianglesAndPointsAreLlvmpipes) {
    DomainCapture capture;
    const std::vector<DomainLevels> cases = domainSweep();
    size_t differing = 0, triangles = 0, pointsDiffer = 0;
    for (const DomainLevels& l : cases) {
        const DomainComparison c = compareDomain(capture, l);
        triangles += c.gpuTriangles;
        pointsDiffer += c.pointsDiffer;
        const bool same = c.onlyGpu == 0 && c.onlyCpu == 0 && c.clockwise == 0 &&
                          c.gpuTriangles == c.cpuTriangles && c.gpuTriangles > 0;
        differing += !same;
        if (!same && differing <= 5)
            ADD_FAILURE() << describe(l) << ": " << c.gpuTriangles << " GPU triangles ("
                          << c.onlyGpu << " not the CPU's, " << c.clockwise << " clockwise), "
                          << c.cpuTriangles << " CPU triangles (" << c.onlyCpu << " not the GPU's)";
    }
    std::printf("quad domain: %zu level combinations, %zu triangles, %zu combinations differ, "
                "%zu points differ\n",
                cases.size(), triangles, differing, pointsDiffer);
    EXPECT_EQ(differing, 0u);
    EXPECT_EQ(pointsDiffer, 0u);
}

} // namespace
