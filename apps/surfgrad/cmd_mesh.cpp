// `surfgrad mesh ...`: the mesh pipeline's subcommands (mesh/,
// surfgrad/mesh/mesh_io.h, surfgrad/mesh/subdivision.h, surfgrad/mesh/morph.h).
//
//   mesh info FILE [--json] [--repair]
//       counts, bounding box (object units; glTF: world space, the nodes'
//       transforms applied, as the file is loaded), face-degree histogram,
//       UV sets, creases/corners/holes, boundary loops, manifoldness
//       (non-manifold files are described, not refused).
//   mesh subdivide FILE --level N [--scheme catmark|loop|bilinear]
//       [--boundary none|edge-only|edge-and-corner] [--fvar smooth|...|all]
//       [--limit] [--max-memory SIZE] [--threads N] -o OUT [--json] [--repair]
//       OUT .obj/.ply: the refined polygons (OBJ keeps crease tags); .gltf/.glb:
//       the triangulated render mesh with normals. Flags override the file's
//       tags, tags override the defaults.
//   mesh morph FILE --weights w0,w1,... -o OUT [--normals recompute|blend]
//       [--level N [--limit]] [--max-memory SIZE] [--threads N] [--json] [--repair]
//       Level 0: the morph is applied to the file's own vertices; level N:
//       to the cage, which is then subdivided.
// A subdivision whose estimated peak memory is above --max-memory (default:
// sg::mesh::defaultSubdivisionBudget) is refused before it allocates,
// naming the level, the face count and the bytes needed. One of at least
// kProgressFaces faces (seconds: level 8 of a 180-face cage takes about 5)
// says so on stderr before it starts and again before the output is
// written. --threads N (1..1024, default all cores): the subdivision's
// threads (SubdivisionSettings::threads); the output files are the same
// bytes for every count.
//
// Other files attach more `mesh` subcommands to the group this returns
// (see commands.h). Notes about dropped or converted data go to stderr as
// "surfgrad: note: ...".
#include <CLI/CLI.hpp>
#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <optional>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/morph.h"
#include "surfgrad/mesh/subdivision.h"

namespace sg::cli {

namespace {

using namespace sg::mesh;
using nlohmann::json;

// Refined face count from which `mesh subdivide` reports its phases.
constexpr uint64_t kProgressFaces = uint64_t(1) << 20;

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void printNotes(const std::vector<std::string>& notes) {
    for (const std::string& n : notes) std::fprintf(stderr, "surfgrad: note: %s\n", n.c_str());
}

// Scheme/boundary/fvar flags over the file's tags.
struct SchemeFlags {
    std::string scheme, boundary, fvar;
    void add(CLI::App* cmd) {
        cmd->add_option(
               "--scheme", scheme,
               "catmark | loop | bilinear (default: the file's 't scheme' tag, else catmark)")
            ->check(CLI::IsMember({"catmark", "loop", "bilinear"}));
        cmd->add_option(
               "--boundary", boundary,
               "none | edge-only | edge-and-corner (default: the file's tag, else edge-only)")
            ->check(CLI::IsMember({"none", "edge-only", "edge-and-corner"}));
        cmd->add_option("--fvar", fvar,
                        "UV interpolation: smooth | corners-only | corners-plus1 | corners-plus2 | "
                        "boundaries | all "
                        "(default: the file's tag, else corners-plus1)")
            ->check(CLI::IsMember(
                {"smooth", "corners-only", "corners-plus1", "corners-plus2", "boundaries", "all"}));
    }
    SubdivOptions resolve(const PolygonMesh& cage) const {
        SubdivOptions o = cage.options;
        if (!scheme.empty()) parseScheme(scheme, o.scheme);
        if (!boundary.empty()) parseBoundaryInterpolation(boundary, o.boundary);
        if (!fvar.empty()) parseFVarInterpolation(fvar, o.fvar);
        return o;
    }
};

// Settings of a CLI subdivision: the --max-memory budget and --threads
// (0: all cores, already capped by limitThreads).
SubdivisionSettings budgeted(uint64_t maxMemory, int threads) {
    SubdivisionSettings s;
    s.memoryBudget = maxMemory;
    s.memoryBudgetHint = kMaxMemoryHint;
    s.threads = threads;
    return s;
}

json optionsJson(const SubdivOptions& o) {
    return {{"scheme", toString(o.scheme)},
            {"boundary", toString(o.boundary)},
            {"fvar", toString(o.fvar)},
            {"crease_method", o.creaseMethod == CreaseMethod::Chaikin ? "chaikin" : "uniform"},
            {"triangles", o.triangles == TriangleRule::Smooth ? "smooth" : "catmark"}};
}

void runInfo(const std::string& file, bool asJson, bool repair) {
    LoadOptions lo;
    lo.repair = repair;
    lo.allowNonManifold = true;
    LoadReport report;
    PolygonMesh m = loadPolygonMesh(file, lo, &report);
    MeshInfo info = describe(m);
    json hist = json::object();
    for (size_t k = 0; k < info.faceDegreeHistogram.size(); ++k) {
        if (info.faceDegreeHistogram[k]) hist[std::to_string(k)] = info.faceDegreeHistogram[k];
    }
    json names = json::array();
    for (const auto& s : m.uvSets) names.push_back(s.name);
    // Bounding box of the positions as loaded (glTF: world space).
    const std::string inExt = meshFormat(file);
    const bool world = inExt == ".gltf" || inExt == ".glb";
    glm::vec3 boxMin(0.0f), boxMax(0.0f);
    if (!m.positions.empty()) {
        boxMin = boxMax = m.positions.front();
        for (const glm::vec3& p : m.positions) {
            boxMin = glm::min(boxMin, p);
            boxMax = glm::max(boxMax, p);
        }
    }
    const glm::vec3 size = boxMax - boxMin;
    json box = nullptr;
    if (!m.positions.empty()) {
        box = {{"min", {boxMin.x, boxMin.y, boxMin.z}},
               {"max", {boxMax.x, boxMax.y, boxMax.z}},
               {"size", {size.x, size.y, size.z}},
               {"space", world ? "world" : "object"}};
    }
    json j = {{"file", file},
              {"vertices", info.vertices},
              {"faces", info.faces},
              {"corners", info.corners},
              {"edges", info.edges},
              {"bounding_box", box},
              {"face_degree_histogram", hist},
              {"uv_sets", m.uvSets.size()},
              {"uv_set_names", names},
              {"has_normals", !m.normalIndices.empty()},
              {"creases", info.creases},
              {"infinitely_sharp_creases", info.infiniteCreases},
              {"corner_tags", info.cornerTags},
              {"holes", info.holes},
              {"boundary_edges", info.boundaryEdges},
              {"boundary_loops", info.boundaryLoops},
              {"manifold", info.manifold},
              {"non_manifold_edges", info.nonManifoldEdges},
              {"non_manifold_vertices", info.nonManifoldVertices},
              {"isolated_vertices", info.isolatedVertices},
              {"euler_characteristic", info.eulerCharacteristic},
              {"morph_targets", m.morphTargets.size()},
              {"options", optionsJson(m.options)},
              {"notes", report.notes}};
    if (asJson) {
        std::cout << j.dump(2) << "\n";
        return;
    }
    std::printf("%s\n", file.c_str());
    std::printf("  vertices %zu, faces %zu, edges %zu, corners %zu\n", info.vertices, info.faces,
                info.edges, info.corners);
    if (!m.positions.empty()) {
        std::printf("  bounding box min (%g, %g, %g), max (%g, %g, %g), size %g x %g x %g%s\n",
                    boxMin.x, boxMin.y, boxMin.z, boxMax.x, boxMax.y, boxMax.z, size.x, size.y,
                    size.z, world ? " (world space: node transforms applied)" : "");
    }
    std::string h;
    for (auto it = hist.begin(); it != hist.end(); ++it)
        h += " " + it.key() + ":" + std::to_string(it.value().get<size_t>());
    std::printf("  face degrees%s\n", h.c_str());
    std::string setNames;
    for (const auto& s : m.uvSets) setNames += " " + s.name;
    std::printf("  uv sets %zu%s%s\n", m.uvSets.size(), setNames.empty() ? "" : ":",
                setNames.c_str());
    std::printf("  creases %zu (%zu infinitely sharp), corners %zu, holes %zu\n", info.creases,
                info.infiniteCreases, info.cornerTags, info.holes);
    std::printf(
        "  boundary loops %zu (%zu edges), isolated vertices %zu, Euler characteristic %d\n",
        info.boundaryLoops, info.boundaryEdges, info.isolatedVertices, info.eulerCharacteristic);
    std::printf("  %s", info.manifold ? "manifold" : "NOT manifold");
    if (!info.manifold)
        std::printf(" (%zu non-manifold edges, %zu non-manifold vertices)", info.nonManifoldEdges,
                    info.nonManifoldVertices);
    std::printf("\n  scheme %s, boundary %s, fvar %s; morph targets %zu\n",
                toString(m.options.scheme), toString(m.options.boundary), toString(m.options.fvar),
                m.morphTargets.size());
    printNotes(report.notes);
}

void runSubdivide(const std::string& file, int level, const SchemeFlags& flags, bool limit,
                  const std::string& out, bool asJson, bool repair, uint64_t maxMemory,
                  int threads) {
    io::checkOutputPath(out, {file});
    const auto threadLimit = limitThreads(threads);
    auto t0 = std::chrono::steady_clock::now();
    LoadOptions lo;
    lo.repair = repair;
    LoadReport report;
    PolygonMesh cage = loadPolygonMesh(file, lo, &report);
    double loadSeconds = secondsSince(t0);
    SubdivisionSettings s = budgeted(maxMemory, threads);
    s.level = level;
    s.limit = limit;
    s.options = flags.resolve(cage);
    std::string ext = meshFormat(out);
    const bool gltf = ext == ".gltf" || ext == ".glb";
    if (!gltf && ext != ".obj" && ext != ".ply")
        throw CliError(out + ": unknown output format '" + ext +
                       "' (expected .obj, .ply, .gltf or .glb)");
    s.buildRenderMesh = gltf || limit; // limit evaluation runs on the render vertices
    const SubdivisionCost cost = estimateSubdivisionCost(cage, s);
    const bool longRun = cost.faces >= kProgressFaces;
    if (longRun) {
        std::fprintf(stderr,
                     "surfgrad: %s: subdividing to level %d%s: %llu faces, up to %s of memory "
                     "(each level ~4x the faces)\n",
                     file.c_str(), level, limit ? " with limit evaluation" : "",
                     static_cast<unsigned long long>(cost.faces),
                     formatByteSize(cost.bytes).c_str());
    }
    t0 = std::chrono::steady_clock::now();
    Subdivider sub(cage, s, file);
    double refineSeconds = secondsSince(t0);
    if (longRun) {
        std::fprintf(stderr, "surfgrad: %s: refined in %.1f s; writing %s\n", file.c_str(),
                     refineSeconds, out.c_str());
    }
    t0 = std::chrono::steady_clock::now();
    WriteOptions wo;
    wo.inputs = {file};
    const std::optional<Material> material = inputMaterial(file, gltf, report.notes);
    if (material) wo.material = &*material;
    std::vector<std::string> notes = gltf ? writeRenderMesh(out, sub.renderMesh(), wo)
                                          : writePolygonMesh(out, sub.refined(), wo);
    double writeSeconds = secondsSince(t0);
    const SubdivisionTimings& tm = sub.timings();
    json j = {{"input", file},
              {"output", out},
              {"level", level},
              {"limit", limit},
              {"options", optionsJson(s.options)},
              {"faces", sub.refined().faceCount()},
              {"vertices", sub.refined().vertexCount()},
              {"render_vertices", sub.renderMesh().vertexCount()},
              {"triangles", sub.renderMesh().triangleCount()},
              {"seconds", refineSeconds},
              {"load_seconds", loadSeconds},
              {"write_seconds", writeSeconds},
              {"timings",
               {{"convert_in", tm.convertIn},
                {"topology", tm.topology},
                {"interpolate", tm.interpolate},
                {"convert_out", tm.convertOut},
                {"limit", tm.limit},
                {"render", tm.render}}}};
    std::vector<std::string> all = report.notes;
    all.insert(all.end(), notes.begin(), notes.end());
    j["notes"] = all;
    if (asJson)
        std::cout << j.dump(2) << "\n";
    else {
        std::printf("%s: level %d %s%s: %zu faces, %zu vertices in %.3f s -> %s\n", file.c_str(),
                    level, toString(s.options.scheme), limit ? " (limit)" : "",
                    sub.refined().faceCount(), sub.refined().vertexCount(), refineSeconds,
                    out.c_str());
    }
    printNotes(all);
}

std::vector<float> parseWeights(const std::string& text) {
    std::vector<float> w;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        double d = std::strtod(item.c_str(), &end);
        if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(d) ||
            std::fabs(d) > 1e6) {
            throw CliError("--weights: '" + item + "' is not a finite number (|w| <= 1e6)");
        }
        w.push_back(float(d));
    }
    if (w.empty()) throw CliError("--weights: expected w0,w1,...");
    return w;
}

void runMorph(const std::string& file, const std::string& weightsText,
              const std::string& normalsMode, int level, bool limit, const std::string& out,
              bool asJson, bool repair, uint64_t maxMemory, int threads) {
    io::checkOutputPath(out, {file});
    const auto threadLimit = limitThreads(threads);
    std::vector<float> weights = parseWeights(weightsText);
    MorphNormals mode = normalsMode == "blend" ? MorphNormals::Blend : MorphNormals::Recompute;
    LoadOptions lo;
    lo.repair = repair;
    LoadReport report;
    auto t0 = std::chrono::steady_clock::now();
    RenderMesh result;
    size_t targets = 0;
    WriteOptions wo;
    wo.inputs = {file};
    wo.writeMorphTargets = false; // the weights are baked into the geometry
    if (level == 0 && !limit) {
        RenderMesh base = loadRenderMesh(file, lo, &report);
        targets = base.morphTargets.size();
        if (targets == 0) throw io::InputError(file, "", "has no morph targets");
        if (weights.size() != targets) {
            throw CliError(file + " has " + std::to_string(targets) +
                           " morph targets; --weights gave " + std::to_string(weights.size()));
        }
        Morpher morpher(base);
        morpher.apply(weights, mode, result);
        result.morphTargets.clear();
        result.morphWeights.clear();
    } else {
        PolygonMesh cage = loadPolygonMesh(file, lo, &report);
        targets = cage.morphTargets.size();
        if (targets == 0) throw io::InputError(file, "", "has no morph targets");
        if (weights.size() != targets) {
            throw CliError(file + " has " + std::to_string(targets) +
                           " morph targets; --weights gave " + std::to_string(weights.size()));
        }
        // Morph the cage, then subdivide (subdivision is linear: the same as
        // morphing the refined mesh with refined deltas).
        PolygonMesh morphed = cage;
        morphCagePositions(cage, weights, morphed.positions);
        morphed.morphTargets.clear();
        morphed.morphWeights.clear();
        SubdivisionSettings s = budgeted(maxMemory, threads);
        s.level = level;
        s.limit = limit;
        s.options = cage.options;
        Subdivider sub(morphed, s, file);
        result = sub.renderMesh();
        if (mode == MorphNormals::Blend)
            report.notes.push_back(
                "--normals blend needs the file's normal deltas; subdivided meshes recompute them");
    }
    double seconds = secondsSince(t0);
    const std::string outExt = meshFormat(out);
    const std::optional<Material> material =
        inputMaterial(file, outExt == ".gltf" || outExt == ".glb", report.notes);
    if (material) wo.material = &*material;
    std::vector<std::string> notes = writeRenderMesh(out, result, wo);
    std::vector<std::string> all = report.notes;
    all.insert(all.end(), notes.begin(), notes.end());
    if (asJson) {
        std::cout << json{{"input", file},
                          {"output", out},
                          {"targets", targets},
                          {"weights", weights},
                          {"vertices", result.vertexCount()},
                          {"triangles", result.triangleCount()},
                          {"seconds", seconds},
                          {"notes", all}}
                         .dump(2)
                  << "\n";
    } else {
        std::printf("%s: %zu targets morphed, %zu vertices -> %s\n", file.c_str(), targets,
                    result.vertexCount(), out.c_str());
    }
    printNotes(all);
}

} // namespace

CLI::App* addMeshCommands(CLI::App& app, int& status) {
    // The description names the subcommands: describeMeshGroup, once all
    // are attached.
    CLI::App* mesh = app.add_subcommand("mesh");
    mesh->require_subcommand(1);

    {
        auto* cmd = mesh->add_subcommand(
            "info", "vertices, faces, face degrees, UV sets, tags, boundary loops, manifoldness");
        auto file = std::make_shared<std::string>();
        auto asJson = std::make_shared<bool>(false);
        auto repair = std::make_shared<bool>(false);
        cmd->add_option("FILE", *file, "mesh file (" + std::string(kMeshFormatsText) + ")")
            ->required();
        cmd->add_flag("--json", *asJson, "print JSON");
        cmd->add_flag("--repair", *repair,
                      "drop degenerate faces and weld exact duplicate vertices first");
        cmd->callback([file, asJson, repair, &status] {
            runInfo(*file, *asJson, *repair);
            status = 0;
        });
    }
    {
        auto* cmd = mesh->add_subcommand(
            "subdivide", "refine with OpenSubdiv (uniform, optional limit surface)");
        auto file = std::make_shared<std::string>();
        auto out = std::make_shared<std::string>();
        auto level = std::make_shared<int>(2);
        auto limit = std::make_shared<bool>(false);
        auto asJson = std::make_shared<bool>(false);
        auto repair = std::make_shared<bool>(false);
        auto flags = std::make_shared<SchemeFlags>();
        auto maxMemory = std::make_shared<uint64_t>(0);
        auto threads = std::make_shared<int>(0);
        cmd->add_option("FILE", *file, "control cage (" + std::string(kMeshFormatsText) + ")")
            ->required();
        cmd->add_option("--level", *level, "uniform refinement level")
            ->required()
            ->check(CLI::Range(0, kMaxSubdivisionLevel));
        flags->add(cmd);
        cmd->add_flag("--limit", *limit, "positions, normals and UVs on the limit surface");
        addMaxMemoryOption(cmd, *maxMemory);
        addThreadsOption(cmd, *threads);
        cmd->add_option("-o,--output", *out,
                        "output .obj/.ply (polygons) or .gltf/.glb (triangles with normals)")
            ->required();
        cmd->add_flag("--json", *asJson,
                      "print statistics as JSON (faces, vertices, seconds, ...)");
        cmd->add_flag("--repair", *repair,
                      "drop degenerate faces and weld exact duplicate vertices first");
        cmd->callback([=, &status] {
            runSubdivide(*file, *level, *flags, *limit, *out, *asJson, *repair, *maxMemory,
                         *threads);
            status = 0;
        });
    }
    {
        auto* cmd =
            mesh->add_subcommand("morph", "apply morph-target weights and write the result");
        auto file = std::make_shared<std::string>();
        auto out = std::make_shared<std::string>();
        auto weights = std::make_shared<std::string>();
        auto normals = std::make_shared<std::string>("recompute");
        auto level = std::make_shared<int>(0);
        auto limit = std::make_shared<bool>(false);
        auto asJson = std::make_shared<bool>(false);
        auto repair = std::make_shared<bool>(false);
        auto maxMemory = std::make_shared<uint64_t>(0);
        auto threads = std::make_shared<int>(0);
        cmd->add_option("FILE", *file,
                        "mesh with morph targets (" + std::string(kMeshFormatsText) +
                            "; only glTF files carry morph targets)")
            ->required();
        cmd->add_option("--weights", *weights, "one weight per target: w0,w1,...")->required();
        cmd->add_option("-o,--output", *out, "output .gltf/.glb/.obj/.ply")->required();
        cmd->add_option(
               "--normals", *normals,
               "recompute (from the morphed surface) or blend (the targets' normal deltas)")
            ->check(CLI::IsMember({"recompute", "blend"}));
        cmd->add_option("--level", *level, "subdivide the morphed cage to this level")
            ->check(CLI::Range(0, kMaxSubdivisionLevel));
        cmd->add_flag("--limit", *limit, "evaluate the limit surface of the morphed cage");
        addMaxMemoryOption(cmd, *maxMemory);
        addThreadsOption(cmd, *threads);
        cmd->add_flag("--json", *asJson, "print JSON");
        cmd->add_flag("--repair", *repair,
                      "drop degenerate faces and weld exact duplicate vertices first");
        cmd->callback([=, &status] {
            runMorph(*file, *weights, *normals, *level, *limit, *out, *asJson, *repair, *maxMemory,
                     *threads);
            status = 0;
        });
    }
    return mesh;
}

std::optional<Material> inputMaterial(const std::string& file, bool gltfOutput,
                                      std::vector<std::string>& notes) {
    const std::string ext = meshFormat(file);
    if (ext != ".gltf" && ext != ".glb") return std::nullopt;
    const Scene scene = loadScene(file);
    std::vector<int> used;
    for (const SceneInstance& inst : scene.instances) {
        if (inst.material >= 0 && std::find(used.begin(), used.end(), inst.material) == used.end())
            used.push_back(inst.material);
    }
    if (used.empty()) return std::nullopt;
    const Material& m = scene.materials[size_t(used[0])];
    const std::string name = "'" + io::printable(m.name.empty() ? "material" : m.name) + "'";
    if (!gltfOutput) {
        notes.push_back("the material " + name + " of " + file +
                        " is not written: OBJ and PLY outputs keep no material (write .gltf or "
                        ".glb to keep it)");
        return std::nullopt;
    }
    if (used.size() > 1) {
        notes.push_back(file + " has " + std::to_string(used.size()) +
                        " materials on the merged mesh; the output keeps the first, " + name);
    }
    return m;
}

void addMaxMemoryOption(CLI::App* cmd, uint64_t& bytes) {
    cmd->add_option("--max-memory", bytes,
                    "refuse a subdivision whose estimated peak memory is above SIZE (e.g. 12G, "
                    "800MiB; default: half the physical memory, at most 3/4 of ulimit -v)")
        ->transform(CLI::AsSizeValue(false));
}

void describeMeshGroup(CLI::App& mesh) {
    std::string names;
    for (const CLI::App* sub : mesh.get_subcommands([](CLI::App*) { return true; }))
        names += (names.empty() ? "" : ", ") + sub->get_name();
    mesh.description("mesh pipeline: " + names + " (reads " + std::string(kMeshFormatsText) + ")");
}

} // namespace sg::cli
