// `surfgrad eval ENTRY [--gpu]`: evaluates one shared shader function on
// JSON records read from stdin, one object per line, and writes one JSON
// object per line to stdout. A line that cannot be evaluated (bad JSON,
// unknown or missing key, wrong type or length, a number outside float
// range) gets {"error": "..."} in its place; the exit status is then 1.
// `surfgrad eval --list` prints the entries and their keys.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>

#include "commands.h"
#include "parity.h"
#include "surfgrad/eval_kernels.h"
#include "surfgrad/gl.h"

namespace sg::cli {

namespace {

std::string fmtFloat(float v) {
    if (!std::isfinite(v)) return "null";
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v); // shortest round-trip
    return std::string(buf, r.ptr);
}

float toFloat(const nlohmann::json& j, const std::string& key) {
    if (!j.is_number()) throw std::runtime_error("key '" + key + "': expected a number");
    double d = j.get<double>();
    if (!std::isfinite(d) || std::fabs(d) > double(std::numeric_limits<float>::max())) {
        throw std::runtime_error("key '" + key + "': " + j.dump() + " is outside float range");
    }
    return float(d);
}

// Parses one line into a record; throws with a message naming the key.
std::vector<float> parseRecord(const eval::Entry& e, const std::string& line) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::parse_error& ex) {
        throw std::runtime_error(std::string("invalid JSON: ") + ex.what());
    }
    if (!j.is_object()) throw std::runtime_error("expected a JSON object");
    std::vector<float> rec(size_t(eval::inStride()), 0.0f);
    for (auto it = j.begin(); it != j.end(); ++it) {
        bool known = false;
        for (const auto& f : e.inputs) known |= f.key == it.key();
        if (!known) {
            std::string keys;
            for (const auto& f : e.inputs) keys += (keys.empty() ? "" : ", ") + f.key;
            throw std::runtime_error("unknown key '" + it.key() + "' (" + e.name +
                                     " takes " + keys + ")");
        }
    }
    for (const auto& f : e.inputs) {
        auto it = j.find(f.key);
        if (it == j.end()) {
            if (!f.optional) {
                throw std::runtime_error("missing key '" + f.key + "' (" + f.doc + ")");
            }
            for (int i = 0; i < f.width; ++i) rec[size_t(f.slot + i)] = f.defaultValue;
            continue;
        }
        if (f.kind == eval::FieldKind::Bool) {
            if (!it->is_boolean()) throw std::runtime_error("key '" + f.key + "': expected true or false");
            rec[size_t(f.slot)] = it->get<bool>() ? 1.0f : 0.0f;
        } else if (f.kind == eval::FieldKind::Int) {
            if (!it->is_number_integer()) throw std::runtime_error("key '" + f.key + "': expected an integer");
            rec[size_t(f.slot)] = float(it->get<long long>());
        } else if (f.width == 1) {
            rec[size_t(f.slot)] = toFloat(*it, f.key);
        } else {
            if (!it->is_array() || int(it->size()) != f.width) {
                throw std::runtime_error("key '" + f.key + "': expected an array of " +
                                         std::to_string(f.width) + " numbers");
            }
            for (int i = 0; i < f.width; ++i) rec[size_t(f.slot + i)] = toFloat((*it)[size_t(i)], f.key);
        }
    }
    // Validate enumerations and counts here, so the kernel sees only valid ones.
    for (const auto& f : e.inputs) {
        float v = rec[size_t(f.slot)];
        if (f.key == "bface_mode" && (v < 0 || v > 2)) {
            throw std::runtime_error("key 'bface_mode': must be 0 (none), 1 (mirror) or 2 (flip)");
        }
        if (f.key == "count" && (v < 0 || v > 4)) {
            throw std::runtime_error("key 'count': must be 0..4");
        }
    }
    return rec;
}

std::string formatResult(const eval::Entry& e, const float* out) {
    std::string s = "{";
    bool first = true;
    for (const auto& f : e.outputs) {
        s += first ? "\"" : ",\"";
        first = false;
        s += f.key + "\":";
        if (f.width == 1) {
            s += fmtFloat(out[f.slot]);
        } else {
            s += "[";
            for (int i = 0; i < f.width; ++i) s += (i ? "," : "") + fmtFloat(out[f.slot + i]);
            s += "]";
        }
    }
    return s + "}";
}

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
                    auto rec = parseRecord(*e, line);
                    eval::evalCpu(*e, rec.data(), out.data());
                    std::cout << formatResult(*e, out.data()) << "\n" << std::flush;
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
                    auto rec = parseRecord(*e, line);
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
                    std::cout << formatResult(*e, &out[r * size_t(eval::outStride())]) << "\n";
                    ++r;
                }
            }
        }
        status = anyError ? 1 : 0;
    });
}

} // namespace sg::cli
