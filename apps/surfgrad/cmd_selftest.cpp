// `surfgrad selftest [--records N] [--seed S] [--target T] [--verbose]`: the CPU/GPU
// parity suite of every shared shader function, printed as a table
// (function, inputs, max abs error, max rel error, NaN count, ...; the
// measures are defined in parity.h). Exits 1 when any function produces a
// non-finite value, breaks an invariant of its contract, exceeds its
// tolerance or has more ill-conditioned records than its tolerance allows
// (each entry's, shaders/sg/eval/kernels.glsl; printed with its reason for a
// function that fails). --target runs the GLSL build in another dialect:
// glsl330 on an OpenGL 3.3 core context, es300 on an OpenGL ES 3.0 context
// (the kernels as a transform-feedback vertex program, docs/engines.md).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

#include "commands.h"
#include "surfgrad/parity/check.h"

namespace sg::cli {

void addSelftestCommand(CLI::App& app, int& status) {
    auto* cmd = app.add_subcommand("selftest", "CPU/GPU parity of every shared shader function");
    auto records = std::make_shared<size_t>(100000);
    auto seed = std::make_shared<uint64_t>(20261122);
    auto verbose = std::make_shared<bool>(false);
    auto only = std::make_shared<std::string>();
    auto target = std::make_shared<std::string>("glsl450");
    cmd->add_option("--records", *records, "Input records per function (default 100000)")
        ->check(CLI::Range(size_t(1), size_t(10000000)));
    cmd->add_option("--seed", *seed, "Random seed");
    cmd->add_option("--only", *only, "Run only this entry (see `surfgrad eval --list`)");
    cmd->add_option("--target", *target,
                    "Shader dialect of the GPU build: glsl450 (compute, default), glsl330 "
                    "(OpenGL 3.3 core) or es300 (OpenGL ES 3.0)")
        ->check(CLI::IsMember({"glsl450", "glsl330", "es300"}));
    cmd->add_flag("--verbose", *verbose, "Print the worst record of every function");
    cmd->callback([&status, records, seed, verbose, only, target] {
        if (!only->empty() && !eval::findEntry(*only)) {
            throw CliError("selftest: unknown entry '" + *only + "'");
        }
        shaders::Target dialect = shaders::Target::Glsl450;
        shaders::parseTarget(*target, dialect); // checked by IsMember
        auto t0 = std::chrono::steady_clock::now();
        gl::HeadlessContext ctx(gl::apiFor(dialect));
        parity::GpuEvaluator gpuEval(ctx);
        std::printf("surfgrad selftest: C++ (GLM, binary32) build vs GLSL build (%s, %s) on %s\n",
                    shaders::targetName(dialect), gpuEval.vertexStage() ? "vertex" : "compute",
                    ctx.renderer().c_str());
        std::printf("%-22s %7s %10s %10s %10s %9s %7s %8s %6s %9s %9s  %s\n", "function", "inputs",
                    "max abs", "max rel", "max mixed", "tolerance", "NaN/Inf", "ill-cond", "expl",
                    "cpu-f64", "gpu-f64", "verdict");
        bool allOk = true;
        for (const auto& e : eval::entries()) {
            if (!only->empty() && e.name != *only) continue;
            auto in = eval::generateInputs(e, *records, *seed);
            auto row = parity::compare(gpuEval, e, in, e.tolerance);
            const bool finite = row.nonFiniteCpu == 0 && row.nonFiniteGpu == 0;
            const bool illOk = double(row.illConditioned + row.backwardExplained) <=
                               e.maxIllFraction * double(row.records);
            const bool ok =
                finite && row.invariantViolations == 0 && row.maxMixedErr <= e.tolerance && illOk;
            allOk &= ok;
            std::printf(
                "%-22s %7zu %10.3g %10.3g %10.3g %9.2g %3zu/%-3zu %8zu %6zu %9.2g %9.2g  %s\n",
                row.entry.c_str(), row.records, row.maxAbsErr, row.maxRelErr, row.maxMixedErr,
                e.tolerance, row.nonFiniteCpu, row.nonFiniteGpu, row.illConditioned,
                row.backwardExplained, row.maxCpuRefErr, row.maxGpuRefErr, ok ? "ok" : "FAIL");
            if (!ok) {
                std::printf("  tolerance %.2g, ill-conditioned share %.2g: %s\n", e.tolerance,
                            e.maxIllFraction, e.toleranceReason.c_str());
            }
            if (row.invariantViolations) {
                std::printf("  %zu records break the contract; first: %s\n",
                            row.invariantViolations, row.firstViolation.c_str());
            }
            if (*verbose || !ok) {
                const size_t nin = size_t(eval::inStride()), nout = size_t(eval::outStride());
                const float* rec = &in[row.worstRecord * nin];
                std::vector<float> c(nout);
                std::vector<double> x(rec, rec + nin), ref(nout);
                eval::evalCpu(e, rec, c.data());
                eval::evalDouble(e, x.data(), ref.data());
                auto g = gpuEval.evalAll(e, std::vector<float>(rec, rec + nin));
                std::printf("  worst well-conditioned record #%zu (mixed %.3g; all records incl. "
                            "ill-conditioned: %.3g):\n%s\n",
                            row.worstRecord, row.maxMixedErr, row.maxMixedErrAll,
                            parity::describeRecord(e, rec, c.data(), g.data(), ref.data()).c_str());
            }
        }
        double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf(
            "max abs = max |gpu - cpu|; max rel = max |gpu - cpu|_inf / |cpu|_inf per output;\n"
            "max mixed = max |gpu - cpu|_inf / max(1, |cpu|_inf) per output (the toleranced "
            "measure);\nNaN/Inf = records with a non-finite output (cpu/gpu); ill-cond = records "
            "whose binary64\nresult moves by > tolerance/4 under a 2^-21 relative input "
            "perturbation; expl = CPU/GPU\ndisagreements both explained as exact results of "
            "inputs within 2^-18 (backward\nerror); both are excluded from the maxima and "
            "still checked for finiteness and\ninvariants. cpu-f64, gpu-f64 = max mixed error of "
            "each build vs the same formulas "
            "in binary64. %.1f s\n",
            secs);
        std::printf("%s\n", allOk ? "selftest: all functions agree" : "selftest: FAILED");
        status = allOk ? 0 : 1;
    });
}

} // namespace sg::cli
