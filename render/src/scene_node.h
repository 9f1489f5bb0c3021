// Reading a scene file's JSON: a value with its field path, read as typed,
// range-checked fields (every error names the file and the field path from
// the document root, e.g. "materials[0].layers[2].strength: expected a
// number"), and the reader of file paths, textures and nested layers that
// the scene parser (scene.cpp) and the layer kinds' parameter tables
// (layer_kind.h) share. Internal to surfgrad_render.
#pragma once

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/base/io.h"
#include "surfgrad/render/scene.h"

namespace sg::render::detail {

constexpr double kHuge = 1e6; // largest sensible coordinate/size

// A JSON value with its field path, reading typed, range-checked fields.
class SceneNode {
public:
    SceneNode(const nlohmann::json& j, std::string path, const std::string& file)
        : j_(j), path_(std::move(path)), file_(file) {}

    const nlohmann::json& value() const { return j_; }
    const std::string& path() const { return path_; }

    [[noreturn]] void fail(const std::string& reason) const {
        throw io::InputError(file_, path_.empty() ? "(root)" : path_, reason);
    }
    [[noreturn]] void failField(const std::string& key, const std::string& reason) const {
        throw io::InputError(file_, sub(key), reason);
    }
    std::string sub(const std::string& key) const {
        return path_.empty() ? key : path_ + "." + key;
    }

    void requireObject() const {
        if (!j_.is_object()) fail("expected an object");
    }
    // Every key must be in `allowed`.
    void allowOnly(const std::vector<const char*>& allowed) const {
        requireObject();
        for (auto it = j_.begin(); it != j_.end(); ++it) {
            bool ok = false;
            for (const char* a : allowed) ok = ok || it.key() == a;
            if (!ok) {
                std::string list;
                for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
                failField(it.key(), "unknown field (expected one of: " + list + ")");
            }
        }
    }
    bool has(const char* key) const { return j_.is_object() && j_.contains(key); }
    SceneNode child(const char* key) const { return SceneNode(j_.at(key), sub(key), file_); }
    SceneNode item(size_t i) const {
        return SceneNode(j_.at(i), path_ + "[" + std::to_string(i) + "]", file_);
    }

    // A finite number in [lo, hi] ((lo, hi] when loOpen). Bounds at or
    // beyond +-kHuge (1e6) mean "no bound" in messages.
    double number(const char* key, double def, double lo, double hi, bool loOpen = false) const {
        if (!has(key)) return def;
        const nlohmann::json& v = j_.at(key);
        const bool hugeLo = lo <= -1e6, hugeHi = hi >= 1e6;
        std::string range = rangeText(hugeLo ? -1e300 : lo, hugeHi ? 1e300 : hi, loOpen);
        if (!v.is_number()) failField(key, "expected a number" + range);
        double x = v.get<double>();
        if (!std::isfinite(x) || x < lo || x > hi || (loOpen && x == lo)) {
            bool tooBig = (x > hi && hugeHi) || (x < lo && hugeLo);
            failField(key,
                      "expected a number" + range + (tooBig ? " of magnitude at most 1e6" : ""));
        }
        return x;
    }
    float num(const char* key, double def, double lo, double hi, bool loOpen = false) const {
        return float(number(key, def, lo, hi, loOpen));
    }
    int integer(const char* key, int def, int lo, int hi) const {
        if (!has(key)) return def;
        const nlohmann::json& v = j_.at(key);
        std::string range = " in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
        if (!v.is_number_integer() &&
            !(v.is_number() && std::floor(v.get<double>()) == v.get<double>())) {
            failField(key, "expected an integer" + range);
        }
        double x = v.get<double>();
        if (!(x >= lo && x <= hi)) failField(key, "expected an integer" + range);
        return int(x);
    }
    bool boolean(const char* key, bool def) const {
        if (!has(key)) return def;
        if (!j_.at(key).is_boolean()) failField(key, "expected true or false");
        return j_.at(key).get<bool>();
    }
    std::string string(const char* key, const std::string& def) const {
        if (!has(key)) return def;
        if (!j_.at(key).is_string()) failField(key, "expected a string");
        return j_.at(key).get<std::string>();
    }
    // One of `choices`; returns its index.
    int choice(const char* key, int def, const std::vector<const char*>& choices) const {
        if (!has(key)) return def;
        const nlohmann::json& v = j_.at(key);
        std::string list;
        for (const char* c : choices)
            list += std::string(list.empty() ? "" : ", ") + "\"" + c + "\"";
        if (!v.is_string()) failField(key, "expected one of " + list);
        int i = 0;
        for (const char* c : choices) {
            if (v.get<std::string>() == c) return i;
            ++i;
        }
        failField(key, "expected one of " + list + ", got \"" + v.get<std::string>() + "\"");
    }
    glm::vec3 vec3(const char* key, glm::vec3 def, double lo = -1e9, double hi = 1e9) const {
        return glm::vec3(dvec3(key, glm::dvec3(def), lo, hi));
    }
    // The same in binary64 (positions and transforms: kept in binary64 until
    // the camera-relative composition, render/view.h).
    glm::dvec3 dvec3(const char* key, glm::dvec3 def, double lo = -1e9, double hi = 1e9) const {
        if (!has(key)) return def;
        const nlohmann::json& v = j_.at(key);
        std::string what = "expected an array of 3 numbers" + rangeText(lo, hi, false);
        if (!v.is_array() || v.size() != 3) failField(key, what);
        glm::dvec3 r;
        for (int i = 0; i < 3; ++i) {
            if (!v[size_t(i)].is_number()) failField(key, what);
            double x = v[size_t(i)].get<double>();
            if (!std::isfinite(x) || x < lo || x > hi) failField(key, what);
            r[i] = x;
        }
        return r;
    }
    std::vector<float> floats(const char* key, double lo, double hi, size_t maxCount) const {
        const std::vector<double> d = doubles(key, lo, hi, maxCount);
        return std::vector<float>(d.begin(), d.end());
    }
    std::vector<double> doubles(const char* key, double lo, double hi, size_t maxCount) const {
        std::vector<double> out;
        if (!has(key)) return out;
        const nlohmann::json& v = j_.at(key);
        std::string what = "expected an array of numbers" + rangeText(lo, hi, false);
        if (!v.is_array() || v.size() > maxCount) {
            failField(key, what + " (at most " + std::to_string(maxCount) + ")");
        }
        for (const auto& x : v) {
            if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < lo ||
                x.get<double>() > hi) {
                failField(key, what);
            }
            out.push_back(x.get<double>());
        }
        return out;
    }
    void requireArray(const char* key, size_t maxCount) const {
        if (!j_.at(key).is_array()) failField(key, "expected an array");
        if (j_.at(key).size() > maxCount) {
            failField(key, "too many entries (at most " + std::to_string(maxCount) + ")");
        }
    }

private:
    static std::string fmt(double x) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", x);
        return buf;
    }
    static std::string rangeText(double lo, double hi, bool loOpen) {
        bool hasLo = lo > -1e8, hasHi = hi < 1e8;
        if (hasLo && hasHi)
            return std::string(" in ") + (loOpen ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "]";
        if (hasLo) return std::string(loOpen ? " > " : " >= ") + fmt(lo);
        if (hasHi) return " <= " + fmt(hi);
        return "";
    }

    const nlohmann::json& j_;
    std::string path_;
    const std::string& file_;
};

// What the layer kinds' parsers need besides the node: paths, textures,
// and (for groups) the parser of a nested layer.
struct SceneReader {
    std::string file;              // the scene file, for messages
    std::filesystem::path baseDir; // relative paths resolve here
    // Reads a layer (nested: inside a group; the material's "antialias").
    std::function<Layer(const SceneNode&, bool nested, const std::string& materialAa)> layer;
    bool nested = false; // reading a layer inside a group
    // The material's "antialias" ("" when it has none): the default of the
    // layers' own (ParamSpec::fromMaterial).
    std::string materialAntialias;

    std::filesystem::path resolvePath(const SceneNode& n, const std::string& p) const;
    TextureSource texture(const SceneNode& n, Wrap defaultWrap) const;
};

} // namespace sg::render::detail
