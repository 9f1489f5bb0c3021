// Table 12: numerical stability, measured (stability.h). For every case:
// how far a rounding-size change of the input moves the normal image (GPU
// and matched CPU reference), how far the GPU is from the matched CPU
// reference, and, where the case has one, from the image it must equal;
// p99 angles in degrees over the pixels the same primitive covers. The
// perturbation's relative size is about 2^-22, so an angle of x degrees is
// a measured condition number of about x * (pi / 180) / 2^-22 (output
// radians per unit of relative input change).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "stability.h"
#include "tables.h"

namespace study {

namespace {

std::string deg(const stability::AngleStats& s) {
    if (s.compared == 0) return "-";
    return fmtErr(s.p99);
}

} // namespace

void tableStability(const Options& o) {
    sg::render::GlRenderer gpu;
    const std::filesystem::path scratch =
        std::filesystem::temp_directory_path() / "surfgrad-stability-table";
    Table t;
    t.title = "Table 12a: named hard cases, p99 angle (degrees)";
    t.header = {
        "case",           "family",          "perturbation p99 GPU",  "perturbation p99 CPU",
        "GPU vs CPU p99", "vs expected p99", "GPU vs default CPU p99"};
    for (const stability::Case& c : stability::namedCases()) {
        std::fprintf(stderr, "stability: %s\n", c.id.c_str());
        const stability::Result r = stability::run(c, gpu, scratch);
        t.add({c.id, c.family, deg(r.perturbedGpu), deg(r.perturbedCpu), deg(r.gpuVsCpu),
               deg(r.expected), deg(r.gpuVsDefaultCpu)});
    }
    t.notes.push_back("Renderer: " + o.renderer + ".");
    t.print(o);

    // 12b/12c: every family input x every kind.
    std::vector<std::string> kinds;
    for (const auto& [k, l] : stability::kindLayers()) kinds.push_back(k);
    Table tp, tg;
    tp.title = "Table 12b: every family x every layer kind, perturbation p99 (degrees, GPU; CPU in "
               "parentheses where it differs by 0.1 or more)";
    tg.title = "Table 12c: every family x every layer kind, GPU vs matched CPU p99 (degrees)";
    tp.header = tg.header = {"input"};
    for (const std::string& k : kinds) {
        tp.header.push_back(k);
        tg.header.push_back(k);
    }
    std::vector<std::string> rowP, rowG;
    std::string input;
    auto flush = [&] {
        if (input.empty()) return;
        tp.add(rowP);
        tg.add(rowG);
    };
    for (const stability::Case& c : stability::familyCases()) {
        const std::string in = c.id.substr(0, c.id.find('/'));
        if (in != input) {
            flush();
            input = in;
            rowP.assign(kinds.size() + 1, "");
            rowG.assign(kinds.size() + 1, "");
            rowP[0] = rowG[0] = in;
        }
        std::fprintf(stderr, "stability: %s\n", c.id.c_str());
        const stability::Result r = stability::run(c, gpu, scratch);
        const size_t col =
            size_t(std::find(kinds.begin(), kinds.end(), c.kind) - kinds.begin()) + 1;
        std::string cell = deg(r.perturbedGpu);
        if (std::fabs(r.perturbedCpu.p99 - r.perturbedGpu.p99) >= 0.1)
            cell += " (" + deg(r.perturbedCpu) + ")";
        rowP[col] = cell;
        rowG[col] = deg(r.gpuVsCpu);
    }
    flush();
    tp.print(o);
    tg.print(o);

    // 12d: generated cases.
    Table tr;
    tr.title = "Table 12d: generated cases (random meshes, charts, transforms, cameras, kinds)";
    tr.header = {"case", "input", "perturbation p99 GPU", "perturbation p99 CPU", "GPU vs CPU p99"};
    std::vector<double> pg, pc, gc;
    for (const stability::Case& c : stability::generatedCases(1, o.quick ? 12 : 48)) {
        std::fprintf(stderr, "stability: %s\n", c.id.c_str());
        const stability::Result r = stability::run(c, gpu, scratch);
        pg.push_back(r.perturbedGpu.p99);
        pc.push_back(r.perturbedCpu.p99);
        gc.push_back(r.gpuVsCpu.p99);
        tr.add({c.id, c.input, deg(r.perturbedGpu), deg(r.perturbedCpu), deg(r.gpuVsCpu)});
    }
    tr.print(o);
    std::filesystem::remove_all(scratch);
}

} // namespace study
