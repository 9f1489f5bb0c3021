// `surfgrad mesh tangents FILE [--method mikktspace|limit] [--uv-set K]
//  [--level N] [--scheme catmark|loop|bilinear] [--threads N]
//  -o OUT.gltf|.glb [--json]`:
// writes a glTF whose TANGENT (xyz + handedness w) belongs to UV set K
// (TEXCOORD_K), computed by one of the tangent-frame methods of
// surfgrad/mesh/tangents.h:
//  - mikktspace: MikkTSpace-compatible vertex tangents of the file's
//    triangle mesh (or of its level-N uniform refinement with --level);
//    vertices whose corners get different tangents are split;
//  - limit: the exact frame of the subdivision limit surface at the
//    vertices of the level-N refinement (positions, normals and UVs on the
//    limit surface as well).
// The third method, pixel, stores nothing (the shader builds the frame),
// so it has nothing to write here. Without --level the file's vertices are
// first welded by value (mesh::weldVerticesByValue: a file giving every
// corner its own v/vt/vn indices writes only its distinct vertices).
// --threads N caps every parallel step (reading, tangents; the output is
// the same bytes for every N). Errors name the file and reason; the output
// is written atomically and never over the input. --json reports the
// seconds of each phase (read, tangents, write).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"

namespace sg::cli {

namespace {

struct TangentsOptions {
    std::string input, output, method = "mikktspace", scheme;
    int uvSet = 0;
    int level = 0;
    int threads = 0; // --threads (0: all cores)
    bool json = false;
    uint64_t maxMemory = 0; // SubdivisionSettings::memoryBudget
};

// The mesh comes from an untrusted file: what the tangent generators take
// as preconditions (values in MikkTSpace's range, ...) is checked here.
void checkTangentInput(const std::string& file, const mesh::RenderMesh& m,
                       mesh::TangentMethod method, int uvSet, const mesh::LimitFrame* frame) {
    const std::string why = mesh::tangentInputProblem(m, method, uvSet, frame);
    if (!why.empty()) throw io::InputError(file, "", why);
}

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void runTangents(const TangentsOptions& o, int& status) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto threadLimit = limitThreads(o.threads);
    const std::optional<mesh::TangentMethod> method = mesh::parseTangentMethod(o.method);
    if (!method || *method == mesh::TangentMethod::Pixel)
        throw CliError("--method " + o.method +
                       ": expected mikktspace or limit (pixel frames are built by the shader; "
                       "nothing is stored)");
    const std::string outFormat = mesh::meshFormat(o.output);
    if (outFormat != ".gltf" && outFormat != ".glb")
        throw CliError(o.output + ": TANGENT needs a glTF output (.gltf or .glb), not '" +
                       outFormat + "'");
    if (o.level < 0 || o.level > mesh::kMaxSubdivisionLevel)
        throw CliError("--level " + std::to_string(o.level) + ": expected 0.." +
                       std::to_string(mesh::kMaxSubdivisionLevel));
    io::checkOutputPath(o.output, {o.input});

    mesh::RenderMesh result;
    size_t changed = 0; // vertices split (mikktspace) or irregular (limit)
    size_t welded = 0;  // vertices removed by the weld by value
    double readSeconds = 0, tangentSeconds = 0;
    const bool subdivide = *method == mesh::TangentMethod::Limit || o.level > 0;
    if (subdivide) {
        mesh::LoadOptions load;
        load.threads = o.threads;
        const mesh::PolygonMesh cage = mesh::loadPolygonMesh(o.input, load);
        mesh::SubdivisionSettings settings;
        settings.memoryBudget = o.maxMemory;
        settings.memoryBudgetHint = kMaxMemoryHint;
        settings.level = o.level;
        settings.options = cage.options;
        if (!o.scheme.empty() && !mesh::parseScheme(o.scheme, settings.options.scheme))
            throw CliError("--scheme " + o.scheme + ": expected catmark, loop or bilinear");
        settings.limit = *method == mesh::TangentMethod::Limit;
        mesh::Subdivider subdivider(cage, settings, o.input);
        result = subdivider.renderMesh();
        readSeconds = secondsSince(t0);
        const auto t1 = std::chrono::steady_clock::now();
        if (o.uvSet < 0 || size_t(o.uvSet) >= result.uvSets.size())
            throw io::InputError(o.input, "--uv-set " + std::to_string(o.uvSet),
                                 "the mesh has " + std::to_string(result.uvSets.size()) +
                                     " UV set(s)");
        const mesh::LimitFrame* frame = settings.limit ? &subdivider.limitFrame() : nullptr;
        checkTangentInput(o.input, result, *method, o.uvSet, frame);
        changed = mesh::generateTangents(result, *method, o.uvSet, frame, o.threads);
        tangentSeconds = secondsSince(t1);
    } else {
        if (!o.scheme.empty()) throw CliError("--scheme needs --level N > 0 (or --method limit)");
        mesh::LoadOptions load;
        load.threads = o.threads;
        result = mesh::loadRenderMesh(o.input, load);
        welded = mesh::weldVerticesByValue(result, o.threads);
        readSeconds = secondsSince(t0);
        const auto t1 = std::chrono::steady_clock::now();
        if (o.uvSet < 0 || size_t(o.uvSet) >= result.uvSets.size())
            throw io::InputError(o.input, "--uv-set " + std::to_string(o.uvSet),
                                 "the mesh has " + std::to_string(result.uvSets.size()) +
                                     " UV set(s)");
        checkTangentInput(o.input, result, *method, o.uvSet, nullptr);
        changed = mesh::generateTangents(result, *method, o.uvSet, nullptr, o.threads);
        tangentSeconds = secondsSince(t1);
    }

    mesh::WriteOptions write;
    write.inputs = {o.input};
    std::vector<std::string> notes;
    // MikkTSpace's frames of charts with no frame follow the file's rounding
    // (kept bit for bit with the reference: say so, and what to do).
    size_t roundingArea = 0;
    if (*method == mesh::TangentMethod::MikkTSpace) {
        roundingArea = mesh::uvAreaWithinRounding(result, o.uvSet);
        if (roundingArea > 0) {
            notes.push_back(std::to_string(roundingArea) + " triangle(s) of TEXCOORD_" +
                            std::to_string(o.uvSet) +
                            " have a UV area within the rounding of their coordinates "
                            "(collapsed or collinear UVs): MikkTSpace gives them the frame of "
                            "that rounding, which a rounding-size change of one UV turns by up to "
                            "90 degrees; give them UV area, or render that set with per-pixel "
                            "frames (\"tangents\": \"pixel\", which fade such charts out) or "
                            "limit tangents (docs/tangents.md, \"Charts with no frame\")");
        }
    }
    if (welded > 0)
        notes.push_back(std::to_string(welded) +
                        " vertices welded into equal ones (every attribute bitwise equal)");
    const auto t2 = std::chrono::steady_clock::now();
    const std::optional<mesh::Material> material = inputMaterial(o.input, true, notes);
    if (material) write.material = &*material;
    const std::vector<std::string> written = mesh::writeRenderMesh(o.output, result, write);
    notes.insert(notes.end(), written.begin(), written.end());
    const double writeSeconds = secondsSince(t2);
    const double seconds = secondsSince(t0);

    const char* changedKey =
        *method == mesh::TangentMethod::Limit ? "irregular_vertices" : "split_vertices";
    if (o.json) {
        nlohmann::json j;
        j["method"] = std::string(mesh::tangentMethodName(*method));
        j["uv_set"] = o.uvSet;
        j["level"] = o.level;
        j["vertices"] = result.vertexCount();
        j["triangles"] = result.triangleCount();
        j[changedKey] = changed;
        j["welded_vertices"] = welded;
        if (*method == mesh::TangentMethod::MikkTSpace) j["rounding_area_triangles"] = roundingArea;
        j["output"] = o.output;
        j["notes"] = notes;
        j["seconds"] = seconds;
        // Where the time went: loading (and refining or welding), the
        // input check and the tangent method, writing.
        j["seconds_read"] = readSeconds;
        j["seconds_tangents"] = tangentSeconds;
        j["seconds_write"] = writeSeconds;
        std::cout << j.dump() << "\n";
    } else {
        std::printf("%s: %s tangents for TEXCOORD_%d%s: %zu vertices, %zu triangles, %zu %s -> %s "
                    "(%.3f s)\n",
                    o.input.c_str(), std::string(mesh::tangentMethodName(*method)).c_str(), o.uvSet,
                    subdivide ? (" at level " + std::to_string(o.level)).c_str() : "",
                    result.vertexCount(), result.triangleCount(), changed,
                    *method == mesh::TangentMethod::Limit
                        ? "irregular vertices (neighbour fallback)"
                        : "vertices split",
                    o.output.c_str(), seconds);
        for (const std::string& n : notes) std::printf("note: %s\n", n.c_str());
    }
    status = 0;
}

} // namespace

void addMeshTangentsCommand(CLI::App& meshGroup, int& status) {
    auto opts = std::make_shared<TangentsOptions>();
    CLI::App* cmd = meshGroup.add_subcommand(
        "tangents", "Write a glTF with TANGENT (xyz + handedness w) for one UV set");
    cmd->add_option("file", opts->input, "Input mesh (" + std::string(mesh::kMeshFormatsText) + ")")
        ->required();
    cmd->add_option("--method", opts->method,
                    "mikktspace (MikkTSpace-compatible vertex tangents) or limit (exact frame "
                    "of the subdivision limit surface)")
        ->capture_default_str();
    cmd->add_option("--uv-set", opts->uvSet, "UV set K (TEXCOORD_K) the tangents belong to")
        ->capture_default_str();
    cmd->add_option("--level", opts->level,
                    "Uniform subdivision level first (limit: the level whose vertices get limit "
                    "frames; 0 = the cage's own vertices)")
        ->capture_default_str();
    addMaxMemoryOption(cmd, opts->maxMemory);
    cmd->add_option("--scheme", opts->scheme,
                    "catmark, loop or bilinear (default: the file's tag)");
    cmd->add_option("-o,--output", opts->output, "Output .gltf or .glb")->required();
    addThreadsOption(cmd, opts->threads);
    cmd->add_flag("--json", opts->json, "Print a JSON summary");
    cmd->callback([opts, &status] { runTangents(*opts, status); });
}

} // namespace sg::cli
