// Table 13's anchor: Blender's Cycles baker through blender_bake.py (the
// script's header says what each bake is and why its settings are what
// they are).
#include "blender_anchor.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>

#include <nlohmann/json.hpp>

namespace study {

namespace nm = sg::normalmap;

namespace {

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// Runs `command` through the shell; returns its combined output and exit
// status.
std::pair<std::string, int> runCaptured(const std::string& command) {
    FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (!pipe) throw std::runtime_error("blender: cannot start: " + command);
    std::string out;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
    const int status = pclose(pipe);
    return {out, status};
}

std::vector<float> readFloats(const std::filesystem::path& path, size_t count) {
    std::ifstream in(path, std::ios::binary);
    std::vector<float> v(count);
    in.read(reinterpret_cast<char*>(v.data()), std::streamsize(count * sizeof(float)));
    if (!in || in.peek() != EOF)
        throw std::runtime_error("blender: " + path.string() + ": expected " +
                                 std::to_string(count) + " float32 values");
    return v;
}

} // namespace

std::string findBlender() {
    if (const char* env = std::getenv("SURFGRAD_BLENDER"); env && *env) return env;
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "";
    size_t start = 0;
    while (start <= dirs.size()) {
        const size_t end = std::min(dirs.find(':', start), dirs.size());
        const std::filesystem::path candidate =
            std::filesystem::path(dirs.substr(start, end - start)) / "blender";
        std::error_code ec;
        if (end > start && std::filesystem::is_regular_file(candidate, ec)) return candidate;
        start = end + 1;
    }
    return {};
}

BlenderBake blenderBake(const std::string& blender, const std::filesystem::path& low,
                        const std::filesystem::path& high, const std::filesystem::path& dir,
                        int size, float extrusion, int padTexels) {
    const std::filesystem::path prefix = dir / ("blender_" + std::to_string(size));
    const std::string command = quoted(blender) + " --background --factory-startup --python " +
                                quoted(SURFGRAD_BLENDER_SCRIPT) + " -- " + quoted(low.string()) +
                                " " + quoted(high.string()) + " " + quoted(prefix.string()) + " " +
                                std::to_string(size) + " " + std::to_string(extrusion) + " " +
                                std::to_string(2.0f * extrusion) + " " + std::to_string(padTexels);
    const auto t0 = std::chrono::steady_clock::now();
    const auto [out, status] = runCaptured(command);
    BlenderBake b;
    b.processMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const size_t at = out.rfind("BLENDER_BAKE ");
    if (status != 0 || at == std::string::npos)
        throw std::runtime_error("blender: the bake failed (status " + std::to_string(status) +
                                 "):\n" + out.substr(out.size() > 2000 ? out.size() - 2000 : 0));
    const nlohmann::json j =
        nlohmann::json::parse(out.substr(at + 13, out.find('\n', at) - (at + 13)));
    const nlohmann::json& s = j.at("seconds");
    b.normalMs = 1e3 * s.at("normal").get<double>();
    b.bakeMs =
        b.normalMs + 1e3 * (s.at("high_position").get<double>() +
                            s.at("low_position").get<double>() + s.at("low_normal").get<double>());
    b.version = j.at("version").get<std::string>();

    // The four RGBA passes (blender_bake.py): tangent-space normal, HIGH's
    // and LOW's positions + offset, LOW's object-space normal.
    const size_t texels = size_t(size) * size_t(size);
    const auto pass = [&](const char* name) {
        return readFloats(prefix.string() + "." + name + ".f32", 4 * texels);
    };
    const std::vector<float> tangentNormal = pass("normal"), highPos = pass("high_position"),
                             lowPos = pass("low_position"), lowNormal = pass("low_normal");
    const auto rgb = [](const std::vector<float>& v, size_t k) {
        return glm::vec3(v[4 * k], v[4 * k + 1], v[4 * k + 2]);
    };
    const auto unit = [](glm::vec3 encoded) {
        const glm::vec3 n = 2.0f * encoded - 1.0f;
        const float len = glm::length(n);
        return len > 0.0f ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
    };
    nm::NormalField normals(size, size);
    b.height = nm::ScalarField(size, size);
    for (size_t k = 0; k < texels; ++k) {
        normals.v[k] = unit(rgb(tangentNormal, k));
        // The offset cancels in the difference of the two positions.
        b.height.v[k] = glm::dot(rgb(highPos, k) - rgb(lowPos, k), unit(rgb(lowNormal, k)));
    }
    b.slopes = nm::slopesFromNormals(normals);
    return b;
}

} // namespace study
