// bench_accuracy_cost: what accuracy costs in time. Every choice the library
// offers (tangent frame source, subdivision level, blend method, feature-curve
// mode, derivative method, precision) measured as error against an
// independent ground truth (analytic, double precision) and as cost on the
// machine it runs on. docs/accuracy-cost.md explains each table and shows a
// run; bench/README.md ("Accuracy and cost") lists the options.
//
// Run (GPU tables need the llvmpipe environment):
//   LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe EGL_PLATFORM=surfaceless
//   build/bin/bench_accuracy_cost [--table NAME|all] [--markdown] [--runs N]
//                                 [--frames N] [--size N] [--quick]
//                                 [--plot-data DIR] [--image-dir DIR] [--list]
// NAME: a registered table (tables.h; --list prints them). bench/run drives
// this executable to regenerate docs/accuracy-cost.md and its plots.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <exception>
#include <string>
#include <thread>

#include "surfgrad/gl/context.h"
#include "tables.h"

namespace {

int usage() {
    std::fprintf(
        stderr,
        "usage: bench_accuracy_cost [--table NAME|all] [--markdown] [--runs N] [--frames N]\n"
        "                           [--size N] [--quick] [--plot-data DIR] [--image-dir DIR]\n"
        "                           [--list]\n"
        "NAME: one of --list\n");
    return 2;
}

bool parseInt(const char* s, int lo, int hi, int& out) {
    char* end = nullptr;
    const long v = std::strtol(s, &end, 10);
    if (end == s || *end != '\0' || v < lo || v > hi) return false;
    out = int(v);
    return true;
}

} // namespace

int main(int argc, char** argv) {
    study::Options o;
    std::string table = "all";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool hasValue = i + 1 < argc;
        if (a == "--markdown")
            o.markdown = true;
        else if (a == "--quick")
            o.quick = true;
        else if (a == "--list") {
            for (const study::TableEntry& e : study::registeredTables())
                std::printf("%s\t%s\n", e.name, e.title);
            return 0;
        } else if (a == "--plot-data" && hasValue)
            o.plotDataDir = argv[++i];
        else if (a == "--image-dir" && hasValue)
            o.imageDir = argv[++i];
        else if (a == "--table" && hasValue)
            table = argv[++i];
        else if (a == "--runs" && hasValue) {
            if (!parseInt(argv[++i], 1, 1000, o.runs)) return usage();
        } else if (a == "--frames" && hasValue) {
            if (!parseInt(argv[++i], 1, 1000, o.frames)) return usage();
        } else if (a == "--size" && hasValue) {
            if (!parseInt(argv[++i], 16, 4096, o.size)) return usage();
        } else {
            return usage();
        }
    }
    if (o.quick) {
        o.runs = std::min(o.runs, 3);
        o.frames = std::min(o.frames, 3);
        o.size = std::min(o.size, 256);
    }
    bool found = table == "all";
    for (const study::TableEntry& e : study::registeredTables()) found = found || table == e.name;
    if (!found) return usage();
    // Load average: the machine's other work shows in every timing (ratios
    // within one table are measured interleaved, so they suffer less).
    std::string load = "?";
    if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
        char buf[64] = {0};
        if (std::fgets(buf, sizeof buf, f)) load = std::string(buf, std::strcspn(buf, "\n"));
        std::fclose(f);
    }
    std::printf("bench_accuracy_cost: %u hardware threads; LP_NUM_THREADS=%s; load average %s\n",
                std::thread::hardware_concurrency(),
                std::getenv("LP_NUM_THREADS") ? std::getenv("LP_NUM_THREADS") : "(default)",
                load.c_str());
    try {
        // One context for every table (GL names are per context).
        sg::gl::HeadlessContext ctx;
        o.renderer = ctx.renderer();
        std::printf("renderer: %s, OpenGL %s\n", o.renderer.c_str(), ctx.version().c_str());
        for (const study::TableEntry& e : study::registeredTables()) {
            if (table == "all" || table == e.name) e.run(o);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_accuracy_cost: %s\n", e.what());
        return 1;
    }
    return 0;
}
