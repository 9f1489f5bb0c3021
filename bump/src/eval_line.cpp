// `surfgrad eval` line format (see surfgrad/bump/eval_line.h).
#include "surfgrad/bump/eval_line.h"

#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>

#include "surfgrad/base/io.h"

namespace sg::eval {

namespace {

constexpr size_t kMaxLineBytes = size_t(1) << 20;

std::string fmtFloat(float v) {
    if (!std::isfinite(v)) return "null";
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v); // shortest round-trip
    return std::string(buf, r.ptr);
}

float toFloat(const nlohmann::json& j, const std::string& key) {
    if (!j.is_number()) throw LineError("key '" + key + "': expected a number");
    const double d = j.get<double>();
    if (!std::isfinite(d) || std::fabs(d) > kMaxInputMagnitude) {
        throw LineError("key '" + key + "': " + j.dump() +
                        " is outside the input domain |x| <= 1e18");
    }
    return float(d);
}

} // namespace

std::vector<float> parseLine(const Entry& e, std::string_view line) {
    if (line.size() > kMaxLineBytes) throw LineError("line longer than 1 MiB");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception& ex) {
        throw LineError("invalid JSON: " + io::printable(ex.what(), 256));
    }
    try {
        io::checkJsonKeysUnique(line, "");
    } catch (const io::InputError& ex) {
        throw LineError(ex.reason()); // `duplicate key "k"` (records are flat objects)
    }
    if (!j.is_object()) throw LineError("expected a JSON object");
    std::vector<float> rec(size_t(inStride()), 0.0f);
    for (auto it = j.begin(); it != j.end(); ++it) {
        bool known = false;
        for (const auto& f : e.inputs) known |= f.key == it.key();
        if (!known) {
            std::string keys;
            for (const auto& f : e.inputs) keys += (keys.empty() ? "" : ", ") + f.key;
            throw LineError("unknown key '" + io::printable(it.key(), 64) + "' (" + e.name +
                            " takes " + keys + ")");
        }
    }
    for (const auto& f : e.inputs) {
        auto it = j.find(f.key);
        if (it == j.end()) {
            if (!f.optional) throw LineError("missing key '" + f.key + "' (" + f.doc + ")");
            for (int i = 0; i < f.width; ++i) rec[size_t(f.slot + i)] = f.defaultValue;
            continue;
        }
        if (f.kind == FieldKind::Bool) {
            if (!it->is_boolean()) throw LineError("key '" + f.key + "': expected true or false");
            rec[size_t(f.slot)] = it->get<bool>() ? 1.0f : 0.0f;
        } else if (f.kind == FieldKind::Int) {
            if (!it->is_number_integer())
                throw LineError("key '" + f.key + "': expected an integer");
            // Range-checked below; clamp first so the conversion is defined.
            const long long v =
                it->is_number_unsigned()
                    ? static_cast<long long>(
                          std::min<unsigned long long>(it->get<unsigned long long>(), 1u << 20))
                    : std::clamp<long long>(it->get<long long>(), -(1 << 20), 1 << 20);
            rec[size_t(f.slot)] = float(v);
        } else if (f.width == 1) {
            rec[size_t(f.slot)] = toFloat(*it, f.key);
        } else {
            if (!it->is_array() || int(it->size()) != f.width) {
                throw LineError("key '" + f.key + "': expected an array of " +
                                std::to_string(f.width) + " numbers");
            }
            for (int i = 0; i < f.width; ++i) {
                rec[size_t(f.slot + i)] = toFloat((*it)[size_t(i)], f.key);
            }
        }
    }
    // Integers (enumerations, counts) are checked against their range here,
    // so kernels see valid ones.
    for (const auto& f : e.inputs) {
        if (f.kind != FieldKind::Int) continue;
        const float v = rec[size_t(f.slot)];
        if (v < float(f.minValue) || v > float(f.maxValue)) {
            throw LineError("key '" + f.key + "': must be " + std::to_string(f.minValue) + ".." +
                            std::to_string(f.maxValue) + " (" + f.doc + ")");
        }
    }
    return rec;
}

std::string formatResult(const Entry& e, const float* out) {
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

} // namespace sg::eval
