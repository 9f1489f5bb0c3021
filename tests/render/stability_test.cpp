// The stability suite: hard cases must be stable, not only finite. Every
// case (bench/accuracy/stability_cases.cpp) is rendered as given and after a
// rounding-size change of its input, on the GPU (llvmpipe) and on the CPU
// reference renderer with the GPU's derivative and LOD rules; the normal
// images must move by a bounded amount, and the GPU must agree with the
// CPU. Three sets: the named inputs users meet, every hard-case family
// crossed with every layer kind, and generated random cases. Each set
// reports rows of docs/hard-cases.md with the perturbation it applied.
//
// Bounds (p99 angles, degrees), and why:
//  - perturbation, kPerturbed = 0.05: a stable computation moves by its own
//    rounding, measured 1e-5 to 4e-3 deg over every case (llvmpipe's
//    binary32 arithmetic on positions and derivatives that changed by an
//    ulp or two, amplified by at most the texture's slope); a decision made
//    on a rounding-size quantity (a determinant's sign, a fade on noise)
//    moves by degrees, as every input of table 12's before-columns did;
//  - GPU vs CPU, kGpuVsCpu = 0.05: the parity bound of the triangle path
//    (tests/render/image_test.cpp): the two renderers differ by llvmpipe's
//    interpolation and filtering roundings (measured 1e-5 to 6e-3 here);
//  - against the expected image, kExpected = 0.01: an exact identity (a
//    faded layer adds nothing; flip negates none exactly; a scene moved
//    with its camera renders the same), measured 0;
//  - an input that brings its own condition number (Case::inputCondition:
//    a transform A:1 anisotropic multiplies the rounding of normals,
//    object-space maps and volume gradients by A through its inverse
//    transpose) gets the bounds above times A / 1000 beyond A = 1000: the
//    defaults hold the renderer's own rounding (1e-5..4e-3 deg) times
//    amplifications up to about 1000; a flattened (1e-4) instance measured
//    up to 0.07 deg (condition 2.5e4: bound 1.25);
//  - the exceptions below, each with its reason at its entry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include <unistd.h>

#include "hardcase.h"
#include "render_test_util.h"
#include "stability.h"

namespace sg::render::test {
namespace {

namespace st = study::stability;
using sg::test::hardCaseNumber;
using sg::test::hardCasePerturbedAtMost;
using sg::test::reportHardCase;

constexpr double kPerturbed = 0.05;
constexpr double kGpuVsCpu = 0.05;
constexpr double kExpected = 0.01;

struct Bounds {
    double perturbed = kPerturbed;
    double gpuVsCpu = kGpuVsCpu;
    double expected = kExpected;
    bool reportOnly = false; // the reference algorithm forbids a bound (MikkTSpace)
};

// Cases whose bounds differ from the defaults, by case id.
Bounds boundsFor(const st::Case& c) {
    Bounds b;
    const double input = std::max(1.0, c.inputCondition / 1000.0);
    b.perturbed *= input;
    b.gpuVsCpu *= input;
    // MikkTSpace decides a triangle's frame on its UV area against FLT_MIN
    // (the reference algorithm, kept bit for bit with mikktspace.c): a
    // chart whose area is rounding noise gets a frame from that noise.
    // Reported, not bounded; docs/tangents.md says what to do instead.
    if (c.id.find("mikktspace") != std::string::npos) b.reportOnly = true;
    // Parallax with vertex normals 80-90 deg from their face
    // (Case::normalLeanDeg): the search reaches 1 / cos(lean) further, up to
    // 20 times the offset-limited step (n.g bounded at 0.05), so the relief
    // is sampled up to 20 pixels' worth of texture away from the pixel,
    // where the two renderers' texture filtering (llvmpipe's 8-bit weights)
    // and a rounding-size move of the inputs differ by up to 0.02 deg of
    // normal per texel of slope: 20 x 0.02 = 0.4 deg; measured 0.12-0.31
    // GPU vs CPU, 0.26 perturbed (a generated needle with normals leaning 80
    // deg, seed 25).
    if (c.normalLeanDeg >= 80.0 && (c.kind == "parallax" || c.kind == "pom")) {
        b.gpuVsCpu = std::max(b.gpuVsCpu, 1.0);
        b.perturbed = std::max(b.perturbed, 1.0);
    }
    return b;
}

std::filesystem::path scratch(const std::string& name) {
    return std::filesystem::temp_directory_path() /
           ("surfgrad-stability-" + name + "-" + std::to_string(::getpid()));
}

// The worst values of a set of cases and the largest bounds they were held to.
struct Worst {
    double perturbed = 0, gpuVsCpu = 0, expected = 0;
    double perturbedBound = 0, gpuVsCpuBound = 0;
    size_t cases = 0, covered = 0;
    std::string perturbedCase, gpuVsCpuCase;
    void add(const st::Case& c, const st::Result& r) {
        ++cases;
        const Bounds b = boundsFor(c);
        perturbedBound = std::max(perturbedBound, b.perturbed);
        gpuVsCpuBound = std::max(gpuVsCpuBound, b.gpuVsCpu);
        covered += r.gpuVsCpu.compared > 0;
        const double p = std::max(r.perturbedGpu.p99, r.perturbedCpu.p99);
        if (p > perturbed) {
            perturbed = p;
            perturbedCase = c.id;
        }
        if (r.gpuVsCpu.p99 > gpuVsCpu) {
            gpuVsCpu = r.gpuVsCpu.p99;
            gpuVsCpuCase = c.id;
        }
        expected = std::max(expected, r.expected.p99);
    }
};

// Runs one case and checks it against its bounds (EXPECT_*: every case of
// a set runs, each failure names its case). SG_STABILITY_DUMP=<dir> writes
// the normal images of every case that fails (stability.h, dumpImages).
st::Result runCase(const st::Case& c, const std::filesystem::path& dir) {
    const st::Result r = st::run(c, gpu(), dir);
    std::printf("%-52s perturbed GPU %.3g CPU %.3g | GPU vs CPU %.3g | expected %.3g | %zu px\n",
                c.id.c_str(), r.perturbedGpu.p99, r.perturbedCpu.p99, r.gpuVsCpu.p99,
                r.expected.p99, r.gpuVsCpu.compared);
    const Bounds b = boundsFor(c);
    bool ok = true;
    auto check = [&](bool holds, const std::string& what) {
        EXPECT_TRUE(holds) << c.id << ": " << what << "\n  input: " << c.input;
        ok = ok && holds;
    };
    for (const st::AngleStats* s : {&r.perturbedGpu, &r.perturbedCpu, &r.gpuVsCpu, &r.expected})
        check(s->nonFinite == 0, "non-finite normals");
    if (!b.reportOnly) {
        check(r.perturbedGpu.p99 <= b.perturbed,
              "GPU moved by " + hardCaseNumber(r.perturbedGpu.p99) + " deg > " +
                  hardCaseNumber(b.perturbed) + " under: " + c.perturbation);
        check(r.perturbedCpu.p99 <= b.perturbed,
              "CPU moved by " + hardCaseNumber(r.perturbedCpu.p99) + " deg > " +
                  hardCaseNumber(b.perturbed) + " under: " + c.perturbation);
    }
    check(r.gpuVsCpu.p99 <= b.gpuVsCpu,
          "GPU vs CPU " + hardCaseNumber(r.gpuVsCpu.p99) + " deg > " + hardCaseNumber(b.gpuVsCpu));
    if (c.expected) {
        check(r.expected.compared > 0, "nothing to compare with " + c.expectedWhat);
        check(r.expected.p99 <= b.expected, "vs " + c.expectedWhat + ": " +
                                                hardCaseNumber(r.expected.p99) + " deg > " +
                                                hardCaseNumber(b.expected));
    }
    const char* dump = std::getenv("SG_STABILITY_DUMP");
    if (!ok && dump && *dump) st::dumpImages(c, gpu(), dir, dump);
    return r;
}

TEST(Stability, NamedInputsStayStable) {
    const auto dir = scratch("named");
    for (const st::Case& c : st::namedCases()) {
        const st::Result r = runCase(c, dir);
        EXPECT_GT(r.gpuVsCpu.compared, 100u) << c.id << ": the view shows the input";
        const Bounds b = boundsFor(c);
        const std::string name = c.input + " (" + c.kind + ")";
        if (b.reportOnly) {
            reportHardCase({c.family, name,
                            "normal AOV, p99 angle between the two renders, GPU and CPU (deg)",
                            "reported (MikkTSpace's rule, docs/tangents.md)",
                            hardCaseNumber(std::max(r.perturbedGpu.p99, r.perturbedCpu.p99)), false,
                            c.perturbation});
        } else {
            hardCasePerturbedAtMost(
                c.family, name, c.perturbation,
                "normal AOV, p99 angle between the two renders, GPU and CPU (deg)",
                std::max(r.perturbedGpu.p99, r.perturbedCpu.p99), b.perturbed, false);
        }
        hardCasePerturbedAtMost(c.family, name, "",
                                "normal AOV, p99 angle GPU vs matched CPU reference (deg)",
                                r.gpuVsCpu.p99, b.gpuVsCpu, false);
        if (c.expected) {
            hardCasePerturbedAtMost(c.family, name, "",
                                    "p99 angle to " + c.expectedWhat + " (deg), GPU",
                                    r.expected.p99, b.expected, false);
        }
    }
    std::filesystem::remove_all(dir);
}

TEST(Stability, EveryFamilyWithEveryLayerKind) {
    const auto dir = scratch("family");
    std::map<std::string, Worst> byInput;
    std::map<std::string, const st::Case*> first;
    const std::vector<st::Case> cases = st::familyCases();
    for (const st::Case& c : cases) {
        const st::Result r = runCase(c, dir);
        const std::string input = c.id.substr(0, c.id.find('/'));
        byInput[input].add(c, r);
        if (!first.count(input)) first[input] = &c;
    }
    const size_t kinds = st::kindLayers().size();
    for (const auto& [input, w] : byInput) {
        const st::Case& c = *first.at(input);
        EXPECT_EQ(w.cases, kinds) << input;
        EXPECT_EQ(w.covered, w.cases) << input << ": every kind's view shows the input";
        const std::string name =
            c.input + ", each of the " + std::to_string(kinds) + " layer kinds (registry examples)";
        hardCasePerturbedAtMost(c.family, name, c.perturbation,
                                "worst kind's p99 angle between the two renders, GPU and CPU "
                                "(deg)",
                                w.perturbed, w.perturbedBound, false);
        hardCasePerturbedAtMost(c.family, name, "",
                                "worst kind's p99 angle GPU vs matched CPU reference (deg)",
                                w.gpuVsCpu, w.gpuVsCpuBound, false);
    }
    std::filesystem::remove_all(dir);
}

// Property test over generated inputs (stability_cases.cpp, generatedCases): a
// fixed seed in the test run (SG_STABILITY_SEED and SG_STABILITY_COUNT pick
// others, e.g. to search for new failures).
TEST(Stability, GeneratedCasesStayStable) {
    uint64_t seed = 1;
    int count = 48;
    if (const char* s = std::getenv("SG_STABILITY_SEED")) seed = std::strtoull(s, nullptr, 10);
    if (const char* s = std::getenv("SG_STABILITY_COUNT")) count = std::atoi(s);
    const auto dir = scratch("generated");
    Worst w;
    for (const st::Case& c : st::generatedCases(seed, count)) w.add(c, runCase(c, dir));
    std::printf("generated: %zu cases, %zu with coverage; worst perturbed %s, GPU vs CPU %s\n",
                w.cases, w.covered, w.perturbedCase.c_str(), w.gpuVsCpuCase.c_str());
    // Random cameras and double_sided "off" leave some views empty (the
    // mesh culled or outside); most must show their mesh.
    EXPECT_GE(w.covered * 4, w.cases * 3);
    const std::string name = std::to_string(count) +
                             " random meshes (height fields; conformal, anisotropic, sheared or "
                             "singular charts, conformal ones some offset by 1e4; collapsed UVs, "
                             "needles, "
                             "normals leaning to 89.9 deg) under random transforms (flattened to "
                             "1e-4, mirrored, 1e5 from the origin), cameras, double-sided modes "
                             "and layer kinds, seed " +
                             std::to_string(seed);
    hardCasePerturbedAtMost("generated", name,
                            "every coordinate of the mesh (positions, UVs, normals) moved by "
                            "-2..2 ulps",
                            "worst case's p99 angle between the two renders, GPU and CPU (deg)",
                            w.perturbed, w.perturbedBound, false);
    hardCasePerturbedAtMost("generated", name, "",
                            "worst case's p99 angle GPU vs matched CPU reference (deg)", w.gpuVsCpu,
                            w.gpuVsCpuBound, false);
    std::filesystem::remove_all(dir);
}

} // namespace
} // namespace sg::render::test
