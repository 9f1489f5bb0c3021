// Table 13's anchor: Blender's Cycles baker through blender_bake.py (the
// script's header says what each bake is and why its settings are what
// they are).
#include "blender_anchor.h"

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>

#include <nlohmann/json.hpp>

#include "cli.h" // runCommand, shellQuote (tests/common)

namespace study {

namespace nm = sg::normalmap;

namespace {

using sg::test::runCommand;
using sg::test::shellQuote;

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
    const std::string command = shellQuote(blender) + " --background --factory-startup --python " +
                                shellQuote(std::string(SURFGRAD_BLENDER_SCRIPT)) + " -- " +
                                shellQuote(low) + " " + shellQuote(high) + " " +
                                shellQuote(prefix) + " " + std::to_string(size) + " " +
                                std::to_string(extrusion) + " " + std::to_string(2.0f * extrusion) +
                                " " + std::to_string(padTexels);
    const auto t0 = std::chrono::steady_clock::now();
    const sg::test::CommandResult run = runCommand(command);
    BlenderBake b;
    b.processMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    // Blender exits 0 even when the script fails: the result line decides.
    const std::string& out = run.out;
    const size_t at = out.rfind("BLENDER_BAKE ");
    if (run.exitCode != 0 || at == std::string::npos) {
        const std::string all = run.output();
        throw std::runtime_error("blender: the bake failed (exit " + std::to_string(run.exitCode) +
                                 "):\n" + all.substr(all.size() > 2000 ? all.size() - 2000 : 0));
    }
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
