// CPU/GPU parity of every shared shader function: the
// C++ (GLM) build against the GLSL build on llvmpipe, >= 100,000 random and
// adversarial records per function, with the per-function tolerances each
// entry declares (shaders/sg/eval/kernels.glsl, each with its reason) and
// the conditioning classification of surfgrad/parity.h. Also the hard-case
// contract (finite outputs, resolve unit length, ...) on CPU and GPU.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "hardcase.h"
#include "surfgrad/parity.h"

namespace {

using namespace sg;

class Parity : public ::testing::TestWithParam<std::string> {
protected:
    static void SetUpTestSuite() {
        ctx_ = new gl::HeadlessContext();
        gpu_ = new parity::GpuEvaluator(*ctx_);
    }
    static void TearDownTestSuite() {
        delete gpu_;
        delete ctx_;
        gpu_ = nullptr;
        ctx_ = nullptr;
    }
    static gl::HeadlessContext* ctx_;
    static parity::GpuEvaluator* gpu_;
};
gl::HeadlessContext* Parity::ctx_ = nullptr;
parity::GpuEvaluator* Parity::gpu_ = nullptr;

std::vector<std::string> entryNames() {
    std::vector<std::string> names;
    for (const auto& e : eval::entries()) names.push_back(e.name);
    return names;
}

TEST_P(Parity, CpuMatchesGpuWithinStatedTolerance) {
    const eval::Entry& e = *eval::findEntry(GetParam());
    const auto in = eval::generateInputs(e, 100000, 20261122);
    const auto row = parity::compare(*gpu_, e, in, e.tolerance);
    RecordProperty("max_abs", std::to_string(row.maxAbsErr));
    RecordProperty("max_rel", std::to_string(row.maxRelErr));
    RecordProperty("max_mixed", std::to_string(row.maxMixedErr));
    RecordProperty("ill_conditioned", std::to_string(row.illConditioned));
    EXPECT_EQ(row.records, 100000u);
    EXPECT_EQ(row.nonFiniteCpu, 0u);
    EXPECT_EQ(row.nonFiniteGpu, 0u);
    EXPECT_EQ(row.invariantViolations, 0u) << row.firstViolation;
    EXPECT_LE(row.maxMixedErr, e.tolerance) << "worst record #" << row.worstRecord;
    EXPECT_LE(double(row.illConditioned + row.backwardExplained), e.maxIllFraction * 100000.0);
    // The probe must leave most records in the comparison.
    EXPECT_GT(row.records - row.illConditioned - row.backwardExplained, 40000u);
}

INSTANTIATE_TEST_SUITE_P(AllEntries, Parity, ::testing::ValuesIn(entryNames()), [](const auto& p) {
    std::string n = p.param;
    for (char& c : n) c = (c == '-') ? '_' : c;
    return n;
});

// Hand-written hard cases for every entry: every input slot set to each of
// zero, +-SG_BIG (1e18), +-1e-30, a denormal, and mixtures; CPU and GPU
// outputs must satisfy the contract (finite; unit resolve; ...).
TEST_P(Parity, HardCasesKeepTheContract) {
    const eval::Entry& e = *eval::findEntry(GetParam());
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
    const auto gpu = gpu_->evalAll(e, in);
    for (size_t r = 0; r < in.size() / size_t(nin); ++r) {
        const float* x = &in[r * size_t(nin)];
        const std::string c = parity::checkInvariants(e, x, &cpu[r * size_t(nout)]);
        const std::string g = parity::checkInvariants(e, x, &gpu[r * size_t(nout)]);
        ASSERT_TRUE(c.empty()) << "cpu: " << c << "\n"
                               << parity::describeRecord(e, x, &cpu[r * size_t(nout)], nullptr,
                                                         nullptr);
        ASSERT_TRUE(g.empty()) << "gpu: " << g << "\n"
                               << parity::describeRecord(e, x, nullptr, &gpu[r * size_t(nout)],
                                                         nullptr);
    }
    sg::test::reportHardCase({"adversarial",
                              e.name + ", every input component one of 0, +-1e18, +-1e-30, "
                                       "1e-40, +-1, 0.5 (4000 records, CPU and GPU)",
                              "records breaking the contract (parity::checkInvariants)", "0", "0"});
}

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
// one: GenBasisTB with parallel UV derivatives vs a well-shaped Jacobian.
TEST(ParityContract, ConditionProbeFlagsSingularRecords) {
    const eval::Entry& basis = *eval::findEntry("basis");
    std::vector<float> rec(size_t(eval::inStride()), 0.0f);
    const float good[] = {0, 0, 1, 1, 0, 0, 0, 1, 0, 1, 0.2f, -0.1f, 1};
    for (int i = 0; i < 13; ++i) rec[size_t(i)] = good[i];
    EXPECT_LT(parity::conditionProbe(basis, rec.data(), parity::kPerturbationsLong), 1e-6);
    rec[11] = 2.0f; // dstdy = 2 * dstdx: det = 0 up to rounding
    rec[12] = 0.4f;
    rec[10] = 0.2f;
    rec[9] = 1.0f;
    EXPECT_GT(parity::conditionProbe(basis, rec.data(), parity::kPerturbationsLong), 0.1);
}

} // namespace
