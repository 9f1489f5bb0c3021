// Hard-case reports: every numerical-stability test (ctest label
// `hardcase`, given by surfgrad_add_test's HARDCASE pattern in
// tests/CMakeLists.txt) states what it checks as rows of docs/hard-cases.md:
// the hard case, the quantity checked, the bound the test asserts and the
// worst value it measured. Each row goes
//   - to stdout as `[hardcase] {json}`,
//   - into the test's XML properties (RecordProperty, ctest --output-junit),
//   - to <build>/hardcases/<test name>.jsonl ($SURFGRAD_HARDCASE_DIR
//     overrides the folder), which cmake/HardCases.cmake reads to write
//     docs/hard-cases.md (scripts/hard-cases) and to check it (the ctest
//     hard_cases_doc).
// A row's family is one of tests/hardcase_families.txt (the list of
// hard cases); a test may report several rows. Reporting does not assert:
// the test keeps its own checks, or uses hardCaseAtMost, which does both.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

namespace sg::test {

struct HardCaseRow {
    std::string family;   // id of tests/hardcase_families.txt
    std::string caseName; // what makes the input hard, e.g. "v 1e-6 below the horizon"
    std::string quantity; // what is measured, with its unit
    std::string bound;    // what the test asserts, e.g. "<= 5e-06", "0", "rejected"
    std::string worst;    // the worst value measured over the test's inputs
    // false when the measured value depends on the machine (llvmpipe's
    // arithmetic follows the CPU's vector width and LLVM version): the doc
    // check then compares everything but this value.
    bool deterministic = true;
    // Stability rows: the rounding-size change of the input whose effect
    // the quantity measures (e.g. "every UV coordinate moved by -2..2
    // ulps"); empty for rows that check a value on one input.
    std::string perturbation;
};

// The largest of the values added; NaN sticks (any NaN makes the result
// NaN, so a bound check on it fails).
struct Worst {
    double value = 0.0;
    void add(double x) {
        if (!(x <= value) && !std::isnan(value)) value = x;
    }
};

// %.3g, the precision of the table (and of the doc check).
inline std::string hardCaseNumber(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

namespace detail {

inline std::string jsonString(const std::string& s) {
    std::string o = "\"";
    for (char c : s) {
        if (c == ';') {
            o += "\\u003b"; // cmake/HardCases.cmake reads the lines as a CMake list
        } else if (c == '"' || c == '\\') {
            o += '\\';
            o += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            o += buf;
        } else {
            o += c;
        }
    }
    return o + "\"";
}

inline std::filesystem::path hardCaseDir() {
    if (const char* d = std::getenv("SURFGRAD_HARDCASE_DIR")) return d;
#ifdef SURFGRAD_BINARY_DIR
    return std::filesystem::path(SURFGRAD_BINARY_DIR) / "hardcases";
#else
    return std::filesystem::temp_directory_path() / "surfgrad-hardcases";
#endif
}

} // namespace detail

// Reports one row for the running test (see the file comment).
inline void reportHardCase(const HardCaseRow& row) {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string test = info ? std::string(info->test_suite_name()) + "." + info->name() : "";
    const std::string json = "{\"test\":" + detail::jsonString(test) +
                             ",\"family\":" + detail::jsonString(row.family) +
                             ",\"case\":" + detail::jsonString(row.caseName) +
                             ",\"quantity\":" + detail::jsonString(row.quantity) +
                             ",\"bound\":" + detail::jsonString(row.bound) +
                             ",\"worst\":" + detail::jsonString(row.worst) +
                             ",\"deterministic\":" + (row.deterministic ? "true" : "false") +
                             ",\"perturbation\":" + detail::jsonString(row.perturbation) + "}";
    std::printf("[hardcase] %s\n", json.c_str());
    std::fflush(stdout);
    static int count = 0;
    ::testing::Test::RecordProperty("hardcase_" + std::to_string(count++), json);
    // One file per test; the first row of this process truncates it.
    std::string file = test;
    for (char& c : file)
        if (c == '/') c = '~';
    static std::set<std::string> started;
    std::error_code ec;
    const std::filesystem::path dir = detail::hardCaseDir();
    std::filesystem::create_directories(dir, ec);
    const bool first = started.insert(file).second;
    std::ofstream out(dir / (file + ".jsonl"), first ? std::ios::trunc : std::ios::app);
    out << json << "\n";
    EXPECT_TRUE(out.good()) << "cannot write the hard-case report to " << dir;
}

// Asserts worst <= bound (EXPECT_LE; NaN fails) and reports the row with
// the bound as "<= bound" and the worst value to 3 digits.
inline void hardCaseAtMost(const std::string& family, const std::string& caseName,
                           const std::string& quantity, double worst, double bound,
                           bool deterministic = true) {
    EXPECT_LE(worst, bound) << family << ": " << caseName << ": " << quantity;
    reportHardCase({family, caseName, quantity, "<= " + hardCaseNumber(bound),
                    hardCaseNumber(worst), deterministic});
}

// A stability row (docs/hard-cases.md's perturbation column): asserts
// worst <= bound like hardCaseAtMost and names the rounding-size change of
// the input the quantity responds to.
inline void hardCasePerturbedAtMost(const std::string& family, const std::string& caseName,
                                    const std::string& perturbation, const std::string& quantity,
                                    double worst, double bound, bool deterministic = true) {
    EXPECT_LE(worst, bound) << family << ": " << caseName << ": " << quantity;
    reportHardCase({family, caseName, quantity, "<= " + hardCaseNumber(bound),
                    hardCaseNumber(worst), deterministic, perturbation});
}

// For checks without a measured number (a known answer bit for bit, an
// input rejected with a named error): reports `holds` as the worst value if
// the running test has no failure so far, "fails" otherwise.
inline void reportHardCaseHolds(const std::string& family, const std::string& caseName,
                                const std::string& quantity, const std::string& bound,
                                const std::string& holds) {
    reportHardCase(
        {family, caseName, quantity, bound, ::testing::Test::HasFailure() ? "fails" : holds, true});
}

} // namespace sg::test
