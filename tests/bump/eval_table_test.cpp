// The evaluation table as expanded from the one declaration per function in
// shaders/sg/eval/kernels.glsl: what the expansion must guarantee for the
// JSON format, the GPU dispatch and the parity suite to agree (ids are list
// positions, keys unique, records fit, integers have a range holding their
// default, every entry states a tolerance with its reason and has a
// generator), and records from the generators that respect the declared
// types and ranges.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "surfgrad/bump/eval_kernels.h"

namespace {

using namespace sg::eval;

int recordFloats(const std::vector<Field>& fields) {
    int at = 0;
    for (const Field& f : fields) {
        EXPECT_EQ(f.slot, at) << f.key << ": slots follow the declaration order";
        at += f.width;
    }
    return at;
}

TEST(EvalTable, DeclarationsAreConsistent) {
    const auto& table = entries();
    ASSERT_FALSE(table.empty());
    std::set<std::string> names;
    for (size_t k = 0; k < table.size(); ++k) {
        const Entry& e = table[k];
        SCOPED_TRACE(e.name);
        EXPECT_EQ(e.kernel, int(k)) << "kernel ids are the list positions";
        EXPECT_TRUE(names.insert(e.name).second) << "names are unique";
        EXPECT_EQ(findEntry(e.name), &e);
        EXPECT_FALSE(e.summary.empty());
        EXPECT_LE(recordFloats(e.inputs), inStride());
        EXPECT_LE(recordFloats(e.outputs), outStride());
        EXPECT_FALSE(e.outputs.empty());
        // Tolerances are positive, shares in (0, 1), each with its reason.
        EXPECT_GT(e.tolerance, 0.0);
        EXPECT_GT(e.maxIllFraction, 0.0);
        EXPECT_LT(e.maxIllFraction, 1.0);
        EXPECT_GT(e.toleranceReason.size(), 20u);
        EXPECT_NE(e.generator, nullptr);
        for (const auto* fields : {&e.inputs, &e.outputs}) {
            std::set<std::string> keys;
            for (const Field& f : *fields) {
                EXPECT_TRUE(keys.insert(f.key).second) << f.key << " twice";
                EXPECT_FALSE(f.doc.empty()) << f.key;
                EXPECT_TRUE(f.width == 1 || f.width == 2 || f.width == 3 || f.width == 4 ||
                            f.width == 16)
                    << f.key;
            }
        }
        for (const Field& f : e.inputs) {
            if (f.kind == FieldKind::Int) {
                EXPECT_LE(f.minValue, f.maxValue) << f.key << " needs sgRange";
                if (f.optional) {
                    EXPECT_GE(f.defaultValue, float(f.minValue)) << f.key;
                    EXPECT_LE(f.defaultValue, float(f.maxValue)) << f.key;
                }
            }
            if (f.kind == FieldKind::Bool && f.optional) {
                EXPECT_TRUE(f.defaultValue == 0.0f || f.defaultValue == 1.0f) << f.key;
            }
            if (f.kind != FieldKind::Float) {
                EXPECT_EQ(f.width, 1) << f.key;
            }
        }
    }
}

TEST(EvalTable, GeneratedRecordsRespectTheDeclaredFields) {
    const size_t n = size_t(inStride());
    for (const Entry& e : entries()) {
        SCOPED_TRACE(e.name);
        const std::vector<float> in = generateInputs(e, 2000, 7);
        ASSERT_EQ(in.size(), 2000 * n);
        EXPECT_EQ(in, generateInputs(e, 2000, 7)) << "deterministic in the seed";
        EXPECT_NE(in, generateInputs(e, 2000, 8));
        const int used = e.inputs.empty() ? 0 : e.inputs.back().slot + e.inputs.back().width;
        for (size_t r = 0; r < 2000; ++r) {
            const float* rec = &in[r * n];
            for (int i = used; i < int(n); ++i) ASSERT_EQ(rec[i], 0.0f) << "slot " << i;
            for (const Field& f : e.inputs) {
                for (int i = 0; i < f.width; ++i) ASSERT_TRUE(std::isfinite(rec[f.slot + i]));
                const float v = rec[f.slot];
                if (f.kind == FieldKind::Bool) {
                    ASSERT_TRUE(v == 0.0f || v == 1.0f) << f.key;
                }
                if (f.kind == FieldKind::Int) {
                    ASSERT_EQ(v, std::floor(v)) << f.key;
                    ASSERT_GE(v, float(f.minValue)) << f.key;
                    ASSERT_LE(v, float(f.maxValue)) << f.key;
                }
                // Magnitudes up to the input domain |x| <= 1e18 (SG_BIG), times
                // up to 2 where an adversarial relation scales one field
                // into another (dpdy = c dpdx, dpdx = c n, |c| at most 2).
                for (int i = 0; i < f.width; ++i)
                    ASSERT_LE(std::fabs(rec[f.slot + i]), 2e18f) << f.key;
            }
        }
    }
}

} // namespace
