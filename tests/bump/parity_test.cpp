// CPU/GPU parity of every shared shader function: the
// C++ (GLM) build against the GLSL build on llvmpipe, >= 100,000 random and
// adversarial records per function, with the per-function tolerances each
// entry declares (shaders/sg/eval/kernels.glsl, each with its reason) and
// the conditioning classification of surfgrad/parity/check.h. Also the hard-case
// contract (finite outputs, resolve unit length, ...) on CPU and GPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <random>

#include "hardcase.h"
#include "hlsl_round_trip.h"
#include "surfgrad/parity/check.h"

namespace {

using namespace sg;

// One suite per shader dialect, each with its own context: Parity (GLSL
// 4.50, a compute program), ParityGlsl330 and ParityEs300 (GLSL 3.30 on an
// OpenGL 3.3 core context, GLSL ES 3.00 on an OpenGL ES 3.0 context: the
// same kernels as a transform-feedback vertex program; there the shared
// source takes its legacy paths, e.g. frexp/ldexp from the bit pattern,
// sg/compat.glsl). All three hold the same tolerances: a dialect changes
// how the source is spelled, not the binary32 arithmetic it asks for.
// The context and evaluator of one suite (Suite: the fixture, so that each
// suite owns its pair); the fixture's SetUpTestSuite opens them.
template <class Suite>
class ParitySuite : public ::testing::TestWithParam<std::string> {
protected:
    static void open(gl::Api api,
                     const std::function<parity::GpuEvaluator*(gl::HeadlessContext&)>& make) {
        ctx_ = new gl::HeadlessContext(api);
        gpu_ = make(*ctx_);
    }
    static void TearDownTestSuite() {
        delete gpu_;
        delete ctx_;
        gpu_ = nullptr;
        ctx_ = nullptr;
    }
    static inline gl::HeadlessContext* ctx_ = nullptr;
    static inline parity::GpuEvaluator* gpu_ = nullptr;
};

template <gl::Api A>
class ParityOn : public ParitySuite<ParityOn<A>> {
protected:
    static void SetUpTestSuite() {
        ParitySuite<ParityOn<A>>::open(A, [](gl::HeadlessContext& ctx) {
            return new parity::GpuEvaluator(ctx, std::getenv("SG_PARITY_VERTEX") != nullptr);
        });
    }
};
using Parity = ParityOn<gl::Api::Gl45Core>;
using ParityGlsl330 = ParityOn<gl::Api::Gl33Core>;
using ParityEs300 = ParityOn<gl::Api::Es30>;

// The HLSL spelling of the source (sg/eval/eval.hlsl through
// sg/compat.hlsl), checked by numbers: each entry's HLSL program goes
// through glslang's HLSL front end to SPIR-V and SPIRV-Cross back to GLSL
// 4.50 (hlsl_round_trip.h), and runs as a compute program on the 4.5
// context. Same records and tolerances as the GLSL suites.
class ParityHlsl : public ParitySuite<ParityHlsl> {
protected:
    static void SetUpTestSuite() {
        open(gl::Api::Gl45Core, [](gl::HeadlessContext& ctx) {
            return new parity::GpuEvaluator(
                ctx,
                [](const eval::Entry& e) {
                    const std::string name = "eval-" + std::to_string(e.kernel);
                    return sg::test::hlslComputeProgram(
                        shaders::assemble(eval::evalHlslBody(), name, eval::evalGpuDefines(e),
                                          shaders::Target::Hlsl),
                        name);
                },
                shaders::Target::Hlsl);
        });
    }
};

std::vector<std::string> entryNames() {
    std::vector<std::string> names;
    for (const auto& e : eval::entries()) names.push_back(e.name);
    return names;
}

void expectParity(parity::GpuEvaluator& gpu, const std::string& name) {
    const eval::Entry& e = *eval::findEntry(name);
    const auto in = eval::generateInputs(e, 100000, 20261122);
    const auto row = parity::compare(gpu, e, in, e.tolerance);
    // Three significant digits (std::to_string's fixed 6 decimals would
    // print 0 for most of them).
    auto sci = [](double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.3g", v);
        return std::string(buf);
    };
    ::testing::Test::RecordProperty("max_abs", sci(row.maxAbsErr));
    ::testing::Test::RecordProperty("max_rel", sci(row.maxRelErr));
    ::testing::Test::RecordProperty("max_mixed", sci(row.maxMixedErr));
    ::testing::Test::RecordProperty("ill_conditioned", std::to_string(row.illConditioned));
    EXPECT_EQ(row.records, 100000u);
    EXPECT_EQ(row.nonFiniteCpu, 0u);
    EXPECT_EQ(row.nonFiniteGpu, 0u);
    EXPECT_EQ(row.invariantViolations, 0u) << row.firstViolation;
    if (row.maxMixedErr > e.tolerance) {
        // The worst record, evaluated again alone, for the failure message.
        const size_t nin = size_t(eval::inStride());
        const std::vector<float> rec(in.begin() + std::ptrdiff_t(row.worstRecord * nin),
                                     in.begin() + std::ptrdiff_t((row.worstRecord + 1) * nin));
        const auto cpu = parity::evalCpuAll(e, rec);
        const auto gpuOut = gpu.evalAll(e, rec);
        std::vector<double> x(rec.begin(), rec.end()), ref(size_t(eval::outStride()));
        eval::evalDouble(e, x.data(), ref.data());
        ADD_FAILURE() << "worst record #" << row.worstRecord << ", mixed error " << row.maxMixedErr
                      << " > " << e.tolerance << "\n"
                      << parity::describeRecord(e, rec.data(), cpu.data(), gpuOut.data(),
                                                ref.data());
    }
    EXPECT_LE(double(row.illConditioned + row.backwardExplained), e.maxIllFraction * 100000.0);
    // The probe must leave most records in the comparison.
    EXPECT_GT(row.records - row.illConditioned - row.backwardExplained, 40000u);
}

// Hand-written hard cases for every entry: every input slot set to each of
// zero, +-SG_BIG (1e18), +-1e-30, a denormal, and mixtures; CPU and GPU
// outputs must satisfy the contract (finite; unit resolve; ...).
void expectHardCasesKeepTheContract(parity::GpuEvaluator& gpu, const std::string& name) {
    const eval::Entry& e = *eval::findEntry(name);
    const int nin = eval::inStride(), nout = eval::outStride();
    const float values[] = {0.0f, 1e18f, -1e18f, 1e-30f, -1e-30f, 1e-40f, 1.0f, -1.0f, 0.5f};
    std::vector<float> in;
    std::mt19937 rng(3);
    for (int r = 0; r < 4000; ++r) {
        std::vector<float> rec(size_t(nin), 0.0f);
        for (const auto& f : e.inputs) {
            for (int i = 0; i < f.width; ++i) {
                float v = values[rng() % std::size(values)];
                if (f.kind == eval::FieldKind::Bool) v = float(rng() % 2);
                if (f.kind == eval::FieldKind::Int) v = float(rng() % 3); // modes 0..2, counts
                rec[size_t(f.slot + i)] = v;
            }
        }
        in.insert(in.end(), rec.begin(), rec.end());
    }
    const auto cpu = parity::evalCpuAll(e, in);
    const auto gpuOut = gpu.evalAll(e, in);
    for (size_t r = 0; r < in.size() / size_t(nin); ++r) {
        const float* x = &in[r * size_t(nin)];
        const std::string c = parity::checkInvariants(e, x, &cpu[r * size_t(nout)]);
        const std::string g = parity::checkInvariants(e, x, &gpuOut[r * size_t(nout)]);
        ASSERT_TRUE(c.empty()) << "cpu: " << c << "\n"
                               << parity::describeRecord(e, x, &cpu[r * size_t(nout)], nullptr,
                                                         nullptr);
        ASSERT_TRUE(g.empty()) << "gpu: " << g << "\n"
                               << parity::describeRecord(e, x, nullptr, &gpuOut[r * size_t(nout)],
                                                         nullptr);
    }
    const std::string dialect = shaders::targetName(gpu.target());
    sg::test::reportHardCase({"adversarial",
                              e.name +
                                  ", every input component one of 0, +-1e18, +-1e-30, "
                                  "1e-40, +-1, 0.5 (4000 records, CPU and GPU " +
                                  dialect + ")",
                              "records breaking the contract (parity::checkInvariants)", "0", "0"});
}

TEST_P(Parity, CpuMatchesGpuWithinStatedTolerance) {
    expectParity(*gpu_, GetParam());
}
TEST_P(Parity, HardCasesKeepTheContract) {
    expectHardCasesKeepTheContract(*gpu_, GetParam());
}
TEST_P(ParityGlsl330, CpuMatchesGpuWithinStatedTolerance) {
    expectParity(*gpu_, GetParam());
}
TEST_P(ParityGlsl330, HardCasesKeepTheContract) {
    expectHardCasesKeepTheContract(*gpu_, GetParam());
}
TEST_P(ParityEs300, CpuMatchesGpuWithinStatedTolerance) {
    expectParity(*gpu_, GetParam());
}
TEST_P(ParityEs300, HardCasesKeepTheContract) {
    expectHardCasesKeepTheContract(*gpu_, GetParam());
}

TEST_P(ParityHlsl, CpuMatchesGpuWithinStatedTolerance) {
    expectParity(*gpu_, GetParam());
}
TEST_P(ParityHlsl, HardCasesKeepTheContract) {
    expectHardCasesKeepTheContract(*gpu_, GetParam());
}

std::string entryTestName(const ::testing::TestParamInfo<std::string>& p) {
    std::string n = p.param;
    for (char& c : n) c = (c == '-') ? '_' : c;
    return n;
}
INSTANTIATE_TEST_SUITE_P(AllEntries, Parity, ::testing::ValuesIn(entryNames()), entryTestName);
INSTANTIATE_TEST_SUITE_P(AllEntries, ParityGlsl330, ::testing::ValuesIn(entryNames()),
                         entryTestName);
INSTANTIATE_TEST_SUITE_P(AllEntries, ParityEs300, ::testing::ValuesIn(entryNames()), entryTestName);
INSTANTIATE_TEST_SUITE_P(AllEntries, ParityHlsl, ::testing::ValuesIn(entryNames()), entryTestName);

// The contract checks themselves can fail.
TEST(ParityContract, InvariantCheckRejectsBadOutputs) {
    const eval::Entry& resolve = *eval::findEntry("resolve");
    std::vector<float> in(size_t(eval::inStride()), 0.0f), out(size_t(eval::outStride()), 0.0f);
    out[0] = 1.0f;
    EXPECT_TRUE(parity::checkInvariants(resolve, in.data(), out.data()).empty());
    out[0] = 0.9f;
    EXPECT_FALSE(parity::checkInvariants(resolve, in.data(), out.data()).empty());
    out[0] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_FALSE(parity::checkInvariants(resolve, in.data(), out.data()).empty());
    const eval::Entry& w = *eval::findEntry("triplanar-weights");
    out = {0.5f, 0.5f, 0.1f};
    out.resize(size_t(eval::outStride()), 0.0f);
    EXPECT_FALSE(parity::checkInvariants(w, in.data(), out.data()).empty());
}

// The conditioning probe separates a singular configuration from a regular
// one: listing 10 with parallel screen derivatives (its sign(det) is
// rounding noise) vs a well-shaped frame. Listing 6 with parallel UV
// derivatives is NOT ill-conditioned: its frame fades to zero there
// (sgChartWeight), and the probe sees a stable zero.
TEST(ParityContract, ConditionProbeFlagsSingularRecords) {
    auto record = [](const eval::Entry& e,
                     std::initializer_list<std::pair<const char*, std::vector<float>>> fields) {
        std::vector<float> rec(size_t(eval::inStride()), 0.0f);
        for (const eval::Field& f : e.inputs)
            if (f.optional) rec[size_t(f.slot)] = f.defaultValue;
        for (const auto& [key, v] : fields) {
            const auto it = std::find_if(e.inputs.begin(), e.inputs.end(),
                                         [&](const eval::Field& f) { return f.key == key; });
            EXPECT_NE(it, e.inputs.end()) << key;
            for (size_t i = 0; i < v.size(); ++i) rec[size_t(it->slot) + i] = v[i];
        }
        return rec;
    };
    const eval::Entry& l10 = *eval::findEntry("parallax-project");
    const auto good = record(l10, {{"n", {0, 0, 1}},
                                   {"dpdx", {1, 0, 0}},
                                   {"dpdy", {0.2f, 1, 0}},
                                   {"dir", {0.6f, 0, 0.8f}},
                                   {"dstdx", {1, 0.2f}},
                                   {"dstdy", {-0.1f, 1}}});
    EXPECT_LT(parity::conditionProbe(l10, good.data(), parity::kPerturbationsLong), 1e-5);
    // dpdy = 2 dpdx: n . (dpdx x dpdy) = 0 up to rounding.
    auto singular = record(l10, {{"n", {0, 0, 1}},
                                 {"dpdx", {1, 0.3f, 0}},
                                 {"dpdy", {2, 0.6f, 0}},
                                 {"dir", {0.6f, 0, 0.8f}},
                                 {"dstdx", {1, 0.2f}},
                                 {"dstdy", {-0.1f, 1}}});
    EXPECT_GT(parity::conditionProbe(l10, singular.data(), parity::kPerturbationsLong), 0.1);
    const eval::Entry& basis = *eval::findEntry("basis");
    const auto parallel = record(basis, {{"n", {0, 0, 1}},
                                         {"dpdx", {1, 0, 0}},
                                         {"dpdy", {0, 1, 0}},
                                         {"st", {0.3f, 0.7f}},
                                         {"dstdx", {0.2f, 1}},
                                         {"dstdy", {0.4f, 2}}});
    EXPECT_LT(parity::conditionProbe(basis, parallel.data(), parity::kPerturbationsLong), 1e-6);
}

} // namespace
