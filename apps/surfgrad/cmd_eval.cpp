// `surfgrad eval ENTRY [--gpu]`: evaluates one shared shader function on
// JSON records read from stdin, one object per line, and writes one JSON
// object per line to stdout. A line that cannot be evaluated (bad JSON,
// unknown or missing key, wrong type or length, a number outside the input
// domain |x| <= 1e18; surfgrad/bump/eval_line.h) gets {"error": "line N: ..."}
// in its place; the exit status is then 1.
// `surfgrad eval --list` prints the entries and their keys.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <iostream>
#include <optional>

#include "commands.h"
#include "surfgrad/parity/check.h"
#include "surfgrad/bump/eval_kernels.h"
#include "surfgrad/bump/eval_line.h"
#include "surfgrad/gl/context.h"

namespace sg::cli {

namespace {

std::string errorLine(size_t lineNo, const std::string& msg) {
    return nlohmann::json{{"error", "line " + std::to_string(lineNo) + ": " + msg}}.dump();
}

void printList() {
    for (const auto& e : eval::entries()) {
        std::cout << e.name << ": " << e.summary << "\n  in:";
        for (const auto& f : e.inputs) {
            std::cout << " " << f.key << (f.width > 1 ? "[" + std::to_string(f.width) + "]" : "")
                      << (f.optional ? "?" : "");
        }
        std::cout << "\n  out:";
        for (const auto& f : e.outputs) {
            std::cout << " " << f.key << (f.width > 1 ? "[" + std::to_string(f.width) + "]" : "");
        }
        std::cout << "\n";
    }
}

} // namespace

void addEvalCommand(CLI::App& app, int& status) {
    auto* cmd = app.add_subcommand("eval", "Evaluate a shared shader function on JSON lines "
                                           "(stdin -> stdout)");
    auto entry = std::make_shared<std::string>();
    auto gpu = std::make_shared<bool>(false);
    auto list = std::make_shared<bool>(false);
    cmd->add_option("entry", *entry, "Entry point (see --list)");
    cmd->add_flag("--gpu", *gpu, "Evaluate with the GLSL build on the headless GL context");
    cmd->add_flag("--list", *list, "List entry points and their keys");
    cmd->callback([&status, entry, gpu, list] {
        if (*list) {
            printList();
            return;
        }
        const eval::Entry* e = eval::findEntry(*entry);
        if (!e) {
            std::string names;
            for (const auto& x : eval::entries()) names += (names.empty() ? "" : ", ") + x.name;
            throw CliError("eval: unknown entry '" + *entry + "' (one of: " + names + ")");
        }
        std::string line;
        size_t lineNo = 0;
        bool anyError = false;
        if (!*gpu) {
            std::vector<float> out(size_t(eval::outStride()));
            while (std::getline(std::cin, line)) {
                ++lineNo;
                if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
                try {
                    auto rec = eval::parseLine(*e, line);
                    eval::evalCpu(*e, rec.data(), out.data());
                    std::cout << eval::formatResult(*e, out.data()) << "\n" << std::flush;
                } catch (const std::exception& ex) {
                    anyError = true;
                    std::cout << errorLine(lineNo, ex.what()) << "\n" << std::flush;
                }
            }
        } else {
            // Batch: parse every line, one GPU dispatch, print in order.
            std::vector<std::optional<std::string>> errors;
            std::vector<float> records;
            while (std::getline(std::cin, line)) {
                ++lineNo;
                if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
                try {
                    auto rec = eval::parseLine(*e, line);
                    records.insert(records.end(), rec.begin(), rec.end());
                    errors.emplace_back(std::nullopt);
                } catch (const std::exception& ex) {
                    anyError = true;
                    errors.emplace_back(errorLine(lineNo, ex.what()));
                }
            }
            std::vector<float> out;
            if (!records.empty()) {
                gl::HeadlessContext ctx;
                parity::GpuEvaluator gpuEval(ctx);
                out = gpuEval.evalAll(*e, records);
            }
            size_t r = 0;
            for (const auto& err : errors) {
                if (err) {
                    std::cout << *err << "\n";
                } else {
                    std::cout << eval::formatResult(*e, &out[r * size_t(eval::outStride())])
                              << "\n";
                    ++r;
                }
            }
        }
        status = anyError ? 1 : 0;
    });
}

} // namespace sg::cli
