// CPU/GPU parity of the feature-curve evaluator: the same GLSL source
// (shaders/sg/features/) compiled as C++ and run in a compute shader on the
// headless llvmpipe context. Three paths: the evaluation kernel on texel
// records (kernels.glsl), the texture path a renderer uses (sample.comp.glsl:
// texelFetch from RGBA32F/RGBA32UI textures), and the profile functions.
#include <epoxy/gl.h>

#include <random>

#include "hlsl_round_trip.h"
#include "maps_test_util.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/shaders/shader_files.h"

using namespace sg::features;
using namespace sgtest;

namespace {

class FeatureMapsGpu : public ::testing::Test {
protected:
    static void SetUpTestSuite() { ctx_ = new sg::gl::HeadlessContext(); }
    static void TearDownTestSuite() {
        delete ctx_;
        ctx_ = nullptr;
    }
    static sg::gl::Program kernelProgram(int kernel, bool curved = true) {
        auto defines = evalKernelGpuDefines(kernel);
        if (!curved) defines.push_back("SG_FEAT_CURVED 0");
        auto src = sg::shaders::assemble(evalKernelGpuBody(), "features-kernel", defines);
        return sg::gl::Program({{sg::gl::Stage::Compute, src}});
    }
    static sg::gl::HeadlessContext* ctx_;
};
sg::gl::HeadlessContext* FeatureMapsGpu::ctx_ = nullptr;

// Networks exercising every configuration: curves, polylines, a star, tight
// arcs (Eq. 7 repairs), curves on grid lines.
std::vector<FeatureMaps> testMaps() {
    std::vector<FeatureMaps> out;
    NetBuilder a;
    a.circle({10.3, 11.7}, 6.2, 10);
    a.circle({24.1, 22.6}, 3.1, 8, 0.4);
    a.polyline({{2.0, 2.0}, {30.0, 30.0}});
    a.polyline({{1.5, 20.0}, {30.5, 20.0}});
    dvec2 c(20.37, 8.61);
    for (int k = 0; k < 8; ++k)
        a.polyline({c, c + 6.0 * dvec2(std::cos(0.3 + 0.785 * k), std::sin(0.3 + 0.785 * k))});
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 12; ++k) {
        dvec2 cc(4.0 + 24.0 * u(rng), 4.0 + 24.0 * u(rng));
        double r = 0.4 + u(rng), a0 = 6.28 * u(rng), sw = 0.6 + 1.8 * u(rng);
        a.begin();
        a.quad(cc + r * dvec2(std::cos(a0), std::sin(a0)),
               cc + r / std::cos(sw / 2) * dvec2(std::cos(a0 + sw / 2), std::sin(a0 + sw / 2)),
               cc + r * dvec2(std::cos(a0 + sw), std::sin(a0 + sw)));
    }
    out.push_back(bake(a.net, texelSpace(32, BakeMode::Quadratic)));
    out.push_back(bake(a.net, texelSpace(32, BakeMode::Linear)));
    // The same with the exact near field, and a star of twelve rays (lists
    // overflowing their eight header slots).
    BakeOptions o = texelSpace(32, BakeMode::Quadratic);
    o.nearField = true;
    out.push_back(bake(a.net, o));
    NetBuilder star;
    for (int k = 0; k < 12; ++k) {
        double ang = 0.2 + 2 * M_PI * k / 12;
        star.polyline(
            {{16.3, 15.8}, dvec2(16.3, 15.8) + 9.0 * dvec2(std::cos(ang), std::sin(ang))});
    }
    out.push_back(bake(star.net, o));
    return out;
}

struct Diff {
    size_t records = 0, compared = 0;
    double maxDist = 0, maxAngle = 0;
    size_t sideMismatch = 0, nonFinite = 0;
};

// Compares (d, gx, gy, side) outputs. Where d < 1e-3 texels the point lies
// within rounding of a curve (binary32 positions are ~1e-6 apart there and
// the GPU may contract multiply-adds into FMA), so the side test may go
// either way: only d is compared there.
void compare(const float* cpu, const float* gpu, int stride, size_t n, Diff& d) {
    for (size_t k = 0; k < n; ++k) {
        const float* a = cpu + k * size_t(stride);
        const float* b = gpu + k * size_t(stride);
        ++d.records;
        bool fin = true;
        for (int i = 0; i < 4; ++i) fin = fin && std::isfinite(a[i]) && std::isfinite(b[i]);
        if (!fin) {
            ++d.nonFinite;
            continue;
        }
        d.maxDist = std::max(d.maxDist, double(std::fabs(a[0] - b[0])) /
                                            std::max(1.0, double(std::fabs(a[0]))));
        if (a[0] < 1e-3f) continue;
        ++d.compared;
        double cosA = double(a[1]) * b[1] + double(a[2]) * b[2];
        double la = std::hypot(a[1], a[2]), lb = std::hypot(b[1], b[2]);
        if (la > 0.5 && lb > 0.5)
            d.maxAngle = std::max(d.maxAngle, std::acos(std::clamp(cosA / (la * lb), -1.0, 1.0)));
        if (a[3] != b[3]) ++d.sideMismatch;
    }
}

} // namespace

// Every kernel of the table (shaders/sg/features/kernels.glsl: one
// declaration per kernel), on the records its generator makes: the CPU and
// GPU builds agree within the kernel's declared tolerance (its reason is in
// the declaration), and both are finite.
TEST_F(FeatureMapsGpu, KernelParity) {
    ASSERT_EQ(kernels().size(), size_t(SG_FEAT_K_COUNT));
    for (const Kernel& k : kernels()) {
        sg::gl::Program prog = kernelProgram(k.id);
        std::vector<float> in = k.inputs(20261122u);
        size_t n = in.size() / size_t(kEvalInStride);
        ASSERT_GT(n, 1000u) << k.name;
        std::vector<float> cpu(n * size_t(kEvalOutStride));
        for (size_t r = 0; r < n; ++r)
            evalKernelCpu(k.id, &in[r * size_t(kEvalInStride)], &cpu[r * size_t(kEvalOutStride)]);
        std::vector<float> gpu = sg::gl::runCompute(prog, in, kEvalInStride, kEvalOutStride, n);
        double worst = 0, largest = 0;
        size_t nonFinite = 0;
        for (size_t i = 0; i < cpu.size(); ++i) {
            largest = std::max(largest, double(std::fabs(cpu[i])));
            if (!std::isfinite(cpu[i]) || !std::isfinite(gpu[i])) {
                ++nonFinite;
                continue;
            }
            worst = std::max(worst, double(std::fabs(cpu[i] - gpu[i])) /
                                        std::max(1.0, double(std::fabs(cpu[i]))));
        }
        std::printf("%-8s %7zu records: max difference %.2e (tolerance %.0e: %s)\n", k.name.c_str(),
                    n, worst, k.tolerance, k.reason.c_str());
        EXPECT_EQ(nonFinite, 0u) << k.name;
        EXPECT_GT(largest, 0.1) << k.name << ": the kernel computed nothing";
        EXPECT_LE(worst, k.tolerance) << k.name << ": " << k.reason;
    }
}

// The same kernel parity in the dialects without compute shaders: GLSL
// 3.30 on an OpenGL 3.3 core context and GLSL ES 3.00 on an OpenGL ES 3.0
// context, the kernels as a transform-feedback vertex program
// (sg/features/kernels.vert.glsl). Same records, same tolerances: a dialect
// changes how the source is spelled, not its binary32 arithmetic (llvmpipe's
// vertex stage flushes denormals, its compute stage keeps them; the shared
// code decides nothing on a denormal).
namespace {

// The GPU results of kernel k's parity records against the C++ build:
// finite, and within the kernel's tolerance (mixed measure).
void expectKernelParity(const Kernel& k, const std::vector<float>& in,
                        const std::vector<float>& gpu, const char* dialect) {
    const size_t n = in.size() / size_t(kEvalInStride);
    std::vector<float> cpu(n * size_t(kEvalOutStride));
    for (size_t r = 0; r < n; ++r)
        evalKernelCpu(k.id, &in[r * size_t(kEvalInStride)], &cpu[r * size_t(kEvalOutStride)]);
    ASSERT_EQ(gpu.size(), cpu.size());
    double worst = 0;
    size_t nonFinite = 0;
    for (size_t i = 0; i < cpu.size(); ++i) {
        if (!std::isfinite(cpu[i]) || !std::isfinite(gpu[i])) {
            ++nonFinite;
            continue;
        }
        worst = std::max(worst, double(std::fabs(cpu[i] - gpu[i])) /
                                    std::max(1.0, double(std::fabs(cpu[i]))));
    }
    std::printf("%-8s %-7s %7zu records: max difference %.2e (tolerance %.0e)\n", k.name.c_str(),
                dialect, n, worst, k.tolerance);
    EXPECT_EQ(nonFinite, 0u) << k.name << " " << dialect;
    EXPECT_LE(worst, k.tolerance) << k.name << " " << dialect << ": " << k.reason;
}

} // namespace

TEST(FeatureKernelDialects, KernelParityOnGlsl330AndEs300) {
    for (const auto api : {sg::gl::Api::Gl33Core, sg::gl::Api::Es30}) {
        sg::gl::HeadlessContext ctx(api);
        const auto target = sg::gl::targetFor(api);
        for (const Kernel& k : kernels()) {
            const std::string name =
                std::string("features-kernel ") + sg::shaders::targetName(target);
            auto vs = sg::shaders::assemble(evalKernelGpuVertexBody(), name,
                                            evalKernelGpuDefines(k.id), target);
            sg::gl::Program prog = sg::gl::feedbackProgram(vs, target, evalKernelGpuFeedback());
            const std::vector<float> in = k.inputs(20261122u);
            const size_t n = in.size() / size_t(kEvalInStride);
            expectKernelParity(
                k, in, sg::gl::runTransformFeedback(prog, in, kEvalInStride, kEvalOutStride, n),
                sg::shaders::targetName(target));
        }
    }
}

// The HLSL spelling of the kernels (sg/features/kernels.hlsl): glslang's
// HLSL front end to SPIR-V, SPIRV-Cross to GLSL 4.50, run as a compute
// program (hlsl_round_trip.h). Same records and tolerances.
TEST(FeatureKernelDialects, KernelParityThroughHlsl) {
    sg::gl::HeadlessContext ctx(sg::gl::Api::Gl45Core);
    for (const Kernel& k : kernels()) {
        const std::string name = "features-kernel-" + std::to_string(k.id);
        sg::gl::Program prog = sg::test::hlslComputeProgram(
            sg::shaders::assemble(evalKernelHlslBody(), name, evalKernelGpuDefines(k.id),
                                  sg::shaders::Target::Hlsl),
            name);
        const std::vector<float> in = k.inputs(20261122u);
        const size_t n = in.size() / size_t(kEvalInStride);
        expectKernelParity(k, in, sg::gl::runCompute(prog, in, kEvalInStride, kEvalOutStride, n),
                           "hlsl");
    }
}

// Linear maps through the straight-only build (SG_FEAT_CURVED 0), which
// must give the full evaluator's results on them.
TEST_F(FeatureMapsGpu, StraightOnlyBuildMatchesOnLinearMaps) {
    sg::gl::Program progLinear = kernelProgram(SG_FEAT_K_EVAL, false);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const FeatureMaps m = testMaps()[1];
    ASSERT_EQ(m.mode, BakeMode::Linear);
    GpuFeatureMaps g = m.packGpu();
    std::vector<float> in;
    std::vector<float> rec(static_cast<size_t>(kEvalInStride));
    for (int j = 0; j < m.size; ++j) {
        for (int i = 0; i < m.size; ++i) {
            bool feat = (m.configWord(i, j) & 0xFFFFu) != 0;
            if (!feat && (i + j) % 7) continue;
            for (int s = 0; s < (feat ? 49 : 4); ++s) {
                glm::vec2 p = s < 9 ? glm::vec2(float(s % 3) * 0.5f, float(s / 3) * 0.5f)
                                    : glm::vec2(u(rng), u(rng));
                packEvalRecord(g, i, j, p, rec.data());
                in.insert(in.end(), rec.begin(), rec.end());
            }
        }
    }
    size_t n = in.size() / size_t(kEvalInStride);
    std::vector<float> cpu(n * size_t(kEvalOutStride));
    for (size_t k = 0; k < n; ++k)
        evalKernelCpu(SG_FEAT_K_EVAL, &in[k * size_t(kEvalInStride)],
                      &cpu[k * size_t(kEvalOutStride)]);
    std::vector<float> gpu = sg::gl::runCompute(progLinear, in, kEvalInStride, kEvalOutStride, n);
    Diff d;
    compare(cpu.data(), gpu.data(), kEvalOutStride, n, d);
    std::printf("linear maps (SG_FEAT_CURVED 0): %zu records, max |d| diff %.2e, max gradient "
                "angle %.2e rad, %zu side mismatches of %zu\n",
                d.records, d.maxDist, d.maxAngle, d.sideMismatch, d.compared);
    EXPECT_EQ(d.nonFinite, 0u);
    // As the kernel's parity tolerance (kernels.glsl): binary32 rounding
    // differences only (measured 1e-6).
    EXPECT_LT(d.maxDist, 1e-4);
    EXPECT_LT(d.maxAngle, 1e-3);
    // A side mismatch away from the curves would be a different triangle or
    // region: none is allowed.
    EXPECT_EQ(d.sideMismatch, 0u);
}

// Arbitrary texel words (every configuration bit pattern the format allows,
// random positions and angles, extreme corner values): both builds stay
// finite. Values are compared only for valid configurations (above), since
// garbage signatures can be ill-conditioned.
TEST_F(FeatureMapsGpu, EvalKernelFiniteOnArbitraryData) {
    sg::gl::Program prog = kernelProgram(SG_FEAT_K_EVAL);
    std::mt19937 rng(13);
    std::uniform_int_distribution<uint32_t> bits(0, 0xFFFFFFFFu);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const size_t n = 20000;
    std::vector<float> in(n * size_t(kEvalInStride), 0.0f);
    for (size_t k = 0; k < n; ++k) {
        float* r = &in[k * size_t(kEvalInStride)];
        float scale = std::pow(10.0f, float(int(bits(rng) % 13) - 6)); // 1e-6 .. 1e6
        for (int i = 0; i < 4; ++i) r[i] = u(rng) * scale;
        for (int i = 4; i < 12; ++i)
            r[i] = (2.0f * u(rng) - 1.0f) * (bits(rng) % 5 == 0 ? 0.0f : 1.0f);
        uint32_t cfg = bits(rng) & 0x1FFFFFu;
        if ((cfg & 3u) == 3u) cfg &= ~1u; // 3 segments does not exist
        // Slots from the kernel's declared layout.
        const auto& layout = kernels()[SG_FEAT_K_EVAL].in;
        int cfgSlot = sg::record::findField(layout, "cfg")->slot;
        r[cfgSlot] = float(cfg & 0xFFFFu);
        r[cfgSlot + 1] = float(cfg >> 16);
        for (const char* e : {"edgeS", "edgeE", "edgeN", "edgeW"}) {
            int slot = sg::record::findField(layout, e)->slot;
            r[slot] = float(bits(rng) & 0xFFFFu);
            r[slot + 1] = float(bits(rng) & 0xFFFFu);
        }
        int localSlot = sg::record::findField(layout, "local")->slot;
        r[localSlot] = u(rng);
        r[localSlot + 1] = u(rng);
    }
    std::vector<float> cpu(n * size_t(kEvalOutStride));
    for (size_t k = 0; k < n; ++k)
        evalKernelCpu(SG_FEAT_K_EVAL, &in[k * size_t(kEvalInStride)],
                      &cpu[k * size_t(kEvalOutStride)]);
    std::vector<float> gpu = sg::gl::runCompute(prog, in, kEvalInStride, kEvalOutStride, n);
    size_t bad = 0;
    for (size_t k = 0; k < n * size_t(kEvalOutStride); ++k)
        bad += !std::isfinite(cpu[k]) || !std::isfinite(gpu[k]);
    EXPECT_EQ(bad, 0u);
}

// The exact closest point on arbitrary pieces: degenerate ones (coincident
// control points, a middle point on an end, folded back), huge and tiny
// ones, points on the piece and far away: both builds stay finite and
// return a unit gradient.
TEST_F(FeatureMapsGpu, NearPieceFiniteOnArbitraryPieces) {
    sg::gl::Program prog = kernelProgram(SG_FEAT_K_NEAR_PIECE);
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const auto& layout = kernels()[SG_FEAT_K_NEAR_PIECE].in;
    auto slot = [&](const char* f) { return sg::record::findField(layout, f)->slot; };
    const size_t n = 20000;
    std::vector<float> in(n * size_t(kEvalInStride), 0.0f);
    for (size_t k = 0; k < n; ++k) {
        float* r = &in[k * size_t(kEvalInStride)];
        float scale = std::pow(10.0f, float(int(rng() % 13) - 6)); // 1e-6 .. 1e6
        glm::vec2 p[3] = {{u(rng), u(rng)}, {u(rng), u(rng)}, {u(rng), u(rng)}};
        for (auto& q : p) q *= scale;
        switch (k % 6) {
        case 0:
            p[1] = p[0];
            break; // middle point on an end
        case 1:
            p[2] = p[0];
            break; // folded back: ends coincide
        case 2:
            p[1] = p[2] = p[0];
            break; // a point
        case 3:
            p[1] = 3.0f * p[2] - 2.0f * p[0];
            break; // collinear, beyond the end
        default:
            break;
        }
        const char* names[3] = {"p0", "p1", "p2"};
        for (int c = 0; c < 3; ++c) {
            r[slot(names[c])] = p[c].x;
            r[slot(names[c]) + 1] = p[c].y;
        }
        r[slot("curved")] = (k % 5) ? 1.0f : 0.0f;
        glm::vec2 pt = (k % 7 == 0) ? p[0] : glm::vec2(u(rng), u(rng)) * scale * 2.0f;
        r[slot("query")] = pt.x;
        r[slot("query") + 1] = pt.y;
    }
    std::vector<float> cpu(n * size_t(kEvalOutStride));
    for (size_t k = 0; k < n; ++k)
        evalKernelCpu(SG_FEAT_K_NEAR_PIECE, &in[k * size_t(kEvalInStride)],
                      &cpu[k * size_t(kEvalOutStride)]);
    std::vector<float> gpu = sg::gl::runCompute(prog, in, kEvalInStride, kEvalOutStride, n);
    size_t bad = 0;
    for (const std::vector<float>* v : {&cpu, &gpu}) {
        for (size_t k = 0; k < n; ++k) {
            const float* o = &(*v)[k * size_t(kEvalOutStride)];
            float gl = std::hypot(o[1], o[2]);
            // Finite, non-negative distance, unit gradient (binary32
            // normalization: a few ulps).
            bool ok = std::isfinite(o[0]) && o[0] >= 0.0f && std::fabs(gl - 1.0f) < 1e-5f &&
                      std::fabs(o[3]) == 1.0f;
            if (!ok && bad++ < 5)
                ADD_FAILURE() << "record " << k << ": d " << o[0] << " grad " << o[1] << ", "
                              << o[2] << " side " << o[3];
        }
    }
    EXPECT_EQ(bad, 0u);
}

// The texture path: RGBA32UI corner pairs and edges read with texelFetch,
// sampled on a dense grid covering the map and its surroundings.
TEST_F(FeatureMapsGpu, TexturePathParity) {
    auto src = sg::shaders::assemble(sampleGpuBody(), "features-sample");
    sg::gl::Program progPaper({{sg::gl::Stage::Compute, src}});
    auto srcNear =
        sg::shaders::assemble(sampleGpuBody(), "features-sample-near", {"SG_FEAT_NEAR 1"});
    sg::gl::Program progNear({{sg::gl::Stage::Compute, srcNear}});
    for (const FeatureMaps& m : testMaps()) {
        GpuFeatureMaps g = m.packGpu();
        const bool near = g.hasNearField();
        const sg::gl::Program& prog = near ? progNear : progPaper;
        GLuint tex[4] = {0, 0, 0, 0};
        auto upload = [](GLuint& t, int w, int h, const std::vector<uint32_t>& data) {
            glCreateTextures(GL_TEXTURE_2D, 1, &t);
            glTextureStorage2D(t, 1, GL_RGBA32UI, w, h);
            glTextureSubImage2D(t, 0, 0, 0, w, h, GL_RGBA_INTEGER, GL_UNSIGNED_INT, data.data());
            glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        };
        upload(tex[0], g.cornerPairsWidth(), g.cornerPairsHeight(), g.cornerPairs);
        upload(tex[1], g.size, g.size, g.edges);
        if (near) {
            upload(tex[2], g.size, g.nearHeight, g.nearLists);
            upload(tex[3], SG_FEAT_PIECES_WIDTH, g.piecesHeight, g.pieces);
        }
        for (int k = 0; k < (near ? 4 : 2); ++k) glBindTextureUnit(GLuint(k), tex[k]);
        glProgramUniform1i(prog.id(), prog.uniform("uFeatCorners"), 0);
        glProgramUniform1i(prog.id(), prog.uniform("uFeatEdges"), 1);
        if (near) {
            glProgramUniform1i(prog.id(), prog.uniform("uFeatNear"), 2);
            glProgramUniform1i(prog.id(), prog.uniform("uFeatPieces"), 3);
        }
        std::vector<float> in;
        const int per = 13; // not a divisor of the texel: covers texel interiors and edges
        for (int j = -per; j <= (g.size + 1) * per; ++j) {
            for (int i = -per; i <= (g.size + 1) * per; ++i) {
                in.push_back(float(i) / float(per));
                in.push_back(float(j) / float(per));
            }
        }
        size_t n = in.size() / 2;
        std::vector<float> gpu = sg::gl::runCompute(prog, in, 2, 4, n);
        std::vector<float> cpu(n * 4);
        for (size_t k = 0; k < n; ++k) {
            auto r = sample(g, glm::vec2(in[2 * k], in[2 * k + 1]));
            cpu[4 * k] = r.dist;
            cpu[4 * k + 1] = r.grad.x;
            cpu[4 * k + 2] = r.grad.y;
            cpu[4 * k + 3] = r.side;
        }
        glDeleteTextures(near ? 4 : 2, tex);
        sg::gl::checkError("texture path");
        Diff d;
        compare(cpu.data(), gpu.data(), 4, n, d);
        std::printf("%s maps%s, texture path: %zu points, max |d| diff %.2e, max angle %.2e rad, "
                    "%zu side mismatches\n",
                    toString(m.mode), near ? " with the exact near field" : "", d.records,
                    d.maxDist, d.maxAngle, d.sideMismatch);
        EXPECT_EQ(d.nonFinite, 0u);
        EXPECT_LT(d.maxDist, 5e-5); // as in EvalKernelParity
        EXPECT_LT(d.maxAngle, 1e-3);
        EXPECT_EQ(d.sideMismatch, 0u);
    }
}
