// CPU/GPU parity of every shared shader function: the
// C++ (GLM) build against the GLSL build on llvmpipe, >= 100,000 random and
// adversarial records per function, with the per-function tolerances each
// entry declares (shaders/sg/eval/kernels.glsl, each with its reason) and
// the conditioning classification of surfgrad/parity.h. Also the hard-case
// contract (finite outputs, resolve unit length, ...) on CPU and GPU.
#include <gtest/gtest.h>

#include <algorithm>
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
