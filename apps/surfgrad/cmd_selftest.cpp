// `surfgrad selftest [--records N] [--seed S]`: the CPU/GPU parity suite of
// every shared shader function, printed as a table (function, inputs, max
// abs error, max rel error, NaN count). Exits 1 when any function produces
// a non-finite value or exceeds its tolerance (parity_tolerances.h).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

#include "commands.h"
#include "parity.h"
#include "parity_tolerances.h"

namespace sg::cli {

void addSelftestCommand(CLI::App& app, int& status) {
    auto* cmd = app.add_subcommand("selftest", "CPU/GPU parity of every shared shader function");
    auto records = std::make_shared<size_t>(100000);
    auto seed = std::make_shared<uint64_t>(20261122);
    cmd->add_option("--records", *records, "Input records per function (default 100000)")
        ->check(CLI::Range(size_t(1), size_t(10000000)));
    cmd->add_option("--seed", *seed, "Random seed");
    cmd->callback([&status, records, seed] {
        auto t0 = std::chrono::steady_clock::now();
        gl::HeadlessContext ctx;
        parity::GpuEvaluator gpuEval(ctx);
        std::printf("surfgrad selftest: C++ (GLM) build vs GLSL build on %s\n",
                    ctx.renderer().c_str());
        std::printf("%-22s %9s %12s %12s %12s %9s  %s\n", "function", "inputs", "max abs err",
                    "max rel err", "max mixed", "NaN/Inf", "verdict");
        bool allOk = true;
        for (const auto& e : eval::entries()) {
            auto in = parity::generateInputs(e, *records, *seed);
            auto row = parity::compare(gpuEval, e, in);
            const double tol = parity::mixedTolerance(e.name);
            const bool ok = row.nonFiniteCpu == 0 && row.nonFiniteGpu == 0 && row.maxMixedErr <= tol;
            allOk &= ok;
            std::printf("%-22s %9zu %12.3g %12.3g %12.3g %4zu/%-4zu  %s\n", row.entry.c_str(),
                        row.records, row.maxAbsErr, row.maxRelErr, row.maxMixedErr, row.nonFiniteCpu,
                        row.nonFiniteGpu, ok ? "ok" : "FAIL");
        }
        double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("mixed error = |gpu - cpu|_inf / max(1, |cpu|_inf) per output; NaN/Inf = "
                    "records with a non-finite output (cpu/gpu). %.1f s\n",
                    secs);
        std::printf("%s\n", allOk ? "selftest: all functions agree" : "selftest: FAILED");
        status = allOk ? 0 : 1;
    });
}

} // namespace sg::cli
