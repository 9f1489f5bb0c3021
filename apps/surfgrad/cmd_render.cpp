// `surfgrad render`, `surfgrad shader` and `surfgrad view`: the renderer's
// subcommands (render, surfgrad/render.h).
//
//   render [SCENE.json | MODEL] [-o OUT.png|.exr]   MODEL: any mesh format
//          (sg::mesh::kMeshFormats)
//          [--size WxH] [--aov NAME] [--frame F] [--tbn pixel|mikktspace|limit]
//          [--cpu] [--all-frames]
//     Without a scene: the built-in default scene to out/default.png.
//   shader SCENE.json [--mesh I] [--target T] [-o DIR]
//                                  prints (or writes) the assembled program of
//                                  every distinct material (or of mesh I) for
//                                  a shader target, validated.
//   view [SCENE.json | MODEL] [--size WxH] [--frames N] [--screenshot PNG] [--no-ui]
//                                  the interactive viewer (GLFW + Dear ImGui).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <functional>
#include <iostream>
#include <set>

#include "commands.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/image/image_format.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/render.h"
#include "surfgrad/translate/shader_target.h"
#if SURFGRAD_HAVE_VIEWER
#include "surfgrad/viewer.h"
#endif

namespace sg::cli {

namespace fs = std::filesystem;
using namespace sg::render;

namespace {

// What `render`, `shader` and `view` take: a scene, or a model in any mesh
// format the loaders read (sg::mesh::kMeshFormats).
const std::string kSceneOrModel =
    "a scene (.json) or a model (" + std::string(sg::mesh::kMeshFormatsText) + ")";

Scene sceneFromArg(const std::string& arg) {
    if (arg.empty()) return defaultScene();
    std::string ext = image::lowerExtension(arg);
    if (ext == ".json") return loadScene(arg);
    if (sg::mesh::isMeshFormat(arg)) return sceneForModel(arg);
    throw CliError(arg + ": expected " + kSceneOrModel);
}

void parseSize(const std::string& s, int& w, int& h) {
    unsigned a = 0, b = 0;
    char x = 0, extra = 0;
    if (std::sscanf(s.c_str(), "%u%c%u%c", &a, &x, &b, &extra) != 3 || (x != 'x' && x != 'X') ||
        a < 1 || b < 1 || a > unsigned(kMaxImageSize) || b > unsigned(kMaxImageSize)) {
        throw CliError("--size: expected WxH with 1 <= W, H <= " + std::to_string(kMaxImageSize) +
                       ", got \"" + s + "\"");
    }
    w = int(a);
    h = int(b);
}

// "512M", "1.5G", "2GiB", "800MB", "1073741824": bytes (binary units).
uint64_t parseBytes(const std::string& option, const std::string& s) {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    std::string unit(end ? end : "");
    for (auto& c : unit) c = char(std::toupper(static_cast<unsigned char>(c)));
    if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();
    if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();
    if (unit == "B") unit.clear();
    const std::string units = "KMGT";
    const size_t u = unit.empty() ? std::string::npos : units.find(unit);
    if (end == s.c_str() || !(v > 0.0) ||
        (!unit.empty() && (unit.size() != 1 || u == std::string::npos)))
        throw CliError(option + ": expected a size such as 512M, 1.5G or 2GiB, got \"" + s + "\"");
    const double bytes = v * std::pow(1024.0, unit.empty() ? 0.0 : double(u + 1));
    if (!(bytes >= 1.0 && bytes < 1.8e19)) throw CliError(option + ": " + s + " is out of range");
    return uint64_t(bytes);
}

constexpr const char* kBudgetHelp =
    "Memory all of the scene's textures may take together (e.g. 512M, 4G): each texture's "
    "mip chain as stored plus the decoder's buffers; a texture that would exceed it is "
    "refused before it is decoded. Default: a quarter of physical memory, at most 8G, at "
    "most half of the process's memory limit (ulimit -v)";

// --tbn: the scene field "tangents" for every UV set whose basis an
// enabled layer reads, one rule for both. "limit" is the same request as
// "tangents": "limit": it applies to meshes drawn as the limit surface
// ("subdivision": {"limit": true} or {"mode": "adaptive"}) and changes only
// their tangents (never the geometry); the other meshes keep their own
// tangents and are named in a note on stderr. A scene without such a mesh
// is an error naming its meshes. "mikktspace" on an adaptive mesh is an
// error naming it (patches have no vertex list), as the field is.
void overrideTangents(Scene& scene, const std::string& tbn) {
    if (tbn.empty()) return;
    TangentSource src = tbn == "pixel"        ? TangentSource::Pixel
                        : tbn == "mikktspace" ? TangentSource::MikkTSpace
                                              : TangentSource::Limit;
    std::string skipped;
    for (auto& m : scene.meshes) {
        if (src == TangentSource::MikkTSpace && m.drawsPatches()) {
            throw CliError("--tbn mikktspace: " + m.fieldPath +
                           " is drawn as adaptive patches, which have no vertex list for "
                           "MikkTSpace (use --tbn limit or pixel)");
        }
        if (src == TangentSource::Limit && !m.drawsLimitSurface()) {
            skipped += (skipped.empty() ? "" : ", ") + m.fieldPath;
            continue;
        }
        // Every UV set whose tangent basis an enabled layer reads gets the
        // source (pixel resets them all; vertex tangents are generated only
        // for those sets anyway).
        uint32_t sets = src == TangentSource::Pixel
                            ? 0u
                            : tangentBasisUvSets(scene.materials[size_t(m.material)]);
        m.tangents.assign(size_t(kMaxUvSets), TangentSource::Pixel);
        for (int k = 0; k < kMaxUvSets; ++k) {
            if (sets >> k & 1u) m.tangents[size_t(k)] = src;
        }
    }
    if (skipped.empty()) return;
    const char* rule =
        "limit tangents need \"subdivision\": {\"limit\": true} or {\"mode\": \"adaptive\"}";
    bool none = std::none_of(scene.meshes.begin(), scene.meshes.end(),
                             [](const MeshInstance& m) { return m.drawsLimitSurface(); });
    if (none) throw CliError("--tbn limit: " + skipped + ": " + rule);
    std::fprintf(stderr, "surfgrad: note: --tbn limit: %s keep their tangents (%s)\n",
                 skipped.c_str(), rule);
}

// Progress of long work on stderr, a line per report (stdout keeps the
// results): subdivision to high levels before the assets load, bands of
// large GPU renders (GlRenderer::setProgress), rows of CPU reference renders
// of at least 512^2 pixels, and the read-back and write of large images.
constexpr int kSubdivNoticeLevel = 4;
constexpr long kCpuProgressPixels = 512L * 512L;
constexpr long kLargeImagePixels = 2048L * 2048L;

void noteSubdivision(const Scene& scene) {
    for (const auto& m : scene.meshes) {
        if (!m.subdivide || m.subdivLevel < kSubdivNoticeLevel) continue;
        std::fprintf(stderr, "surfgrad: %s: subdividing to level %d%s (each level ~4x the faces)\n",
                     m.fieldPath.c_str(), m.subdivLevel,
                     m.subdivLimit ? " with limit evaluation" : "");
    }
}

std::function<void(int, int)> progressLine(const std::string& what, const char* unit) {
    return [what, unit](int done, int total) {
        std::fprintf(stderr, "surfgrad: %s: %d/%d %s\n", what.c_str(), done, total, unit);
    };
}

// "OpenGL, N programs compiled, draw W ms wall, GPU draw time (timer
// query) G ms": the wall time of the frame's draws (ended by glFinish) and,
// only when the driver's timer query measured them, the GPU time.
std::string glTimes(const RenderStats& st) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "OpenGL, %d program%s compiled, draw %.4g ms wall, ",
                  st.programsCompiled, st.programsCompiled == 1 ? "" : "s", st.drawWallMs);
    std::string s = buf;
    if (st.gpuMeasured) {
        std::snprintf(buf, sizeof buf, "GPU draw time (timer query) %.4g ms", st.gpuMs);
        s += buf;
    } else {
        s += "GPU draw time (timer query) not measured";
    }
    return s;
}

// `surfgrad render`'s options.
struct RenderOpts {
    std::string scene, out, size, aov = "color", tbn, cpuDeriv = "analytic", cpuLod = "exact",
                                  budget;
    double frame = 0.0;
    bool cpu = false, allFrames = false, verbose = false, compare = false;
};

// `surfgrad render`: loads the scene, renders each requested frame (OpenGL
// or the CPU reference) and writes it; --compare-cpu prints the normal AOV's
// differences between the two.
void runRender(const RenderOpts& ro) {
    auto aov = parseAov(ro.aov);
    if (!aov) throw CliError("--aov: unknown output \"" + ro.aov + "\"");
    Scene scene = sceneFromArg(ro.scene);
    overrideTangents(scene, ro.tbn);
    fs::path out = ro.out;
    if (out.empty()) {
        std::string stem = ro.scene.empty() ? "default" : fs::path(ro.scene).stem().string();
        if (stem == "scene" && !ro.scene.empty()) {
            stem = fs::absolute(ro.scene).parent_path().filename().string();
        }
        fs::create_directories("out");
        out = fs::path("out") / (stem + (*aov == Aov::Color ? "" : "_" + ro.aov) + ".png");
    }
    std::string outExt = image::lowerExtension(out);
    if (outExt != ".png" && outExt != ".exr") {
        throw CliError(out.string() + ": unsupported image format \"" + outExt +
                       "\" (expected .png or .exr)");
    }
    io::checkOutputPath(out, {fs::path(ro.scene)});
    int w = 0, h = 0;
    if (!ro.size.empty()) parseSize(ro.size, w, h);
    AssetOptions assetOptions;
    if (!ro.budget.empty())
        assetOptions.textureBudgetBytes = parseBytes("--texture-budget", ro.budget);
    auto t0 = std::chrono::steady_clock::now();
    noteSubdivision(scene);
    SceneAssets assets = loadAssets(scene, assetOptions);
    if (ro.verbose) {
        for (const auto& l : assets.log) std::printf("%s\n", l.c_str());
    }
    std::unique_ptr<sg::gl::HeadlessContext> ctx;
    std::unique_ptr<GlRenderer> gl;
    if (!ro.cpu) {
        ctx = std::make_unique<sg::gl::HeadlessContext>();
        gl = std::make_unique<GlRenderer>();
    }
    CpuOptions cpuOpt;
    cpuOpt.derivatives = ro.cpuDeriv == "quad" ? CpuDerivatives::Quad : CpuDerivatives::Analytic;
    cpuOpt.textureLod =
        ro.cpuLod == "llvmpipe" ? sg::glsl::LodRule::FastLog2 : sg::glsl::LodRule::Exact;
    int first = int(ro.frame), count = 1;
    if (ro.allFrames) {
        first = 0;
        count = scene.frameCount;
    }
    for (int f = 0; f < count; ++f) {
        float frame = ro.allFrames ? float(first + f) : float(ro.frame);
        applyFrame(scene, assets, frame / scene.fps);
        if (gl) gl->invalidateMeshes();
        View view = makeView(scene, assets, w, h, *aov);
        const std::string size = std::to_string(view.width) + "x" + std::to_string(view.height);
        const long pixels = long(view.width) * long(view.height);
        if (gl) gl->setProgress(progressLine("drawing " + size, "bands"));
        cpuOpt.progress =
            pixels >= kCpuProgressPixels ? progressLine("CPU reference " + size, "rows") : nullptr;
        Image img;
        try {
            img = gl ? gl->render(scene, assets, view) : renderCpu(scene, assets, view, cpuOpt);
        } catch (const std::bad_alloc&) {
            throw std::runtime_error("out of memory rendering " + size + " pixels (" +
                                     (gl ? "OpenGL" : "CPU reference") +
                                     "): render a smaller --size");
        }
        fs::path target = out;
        if (ro.allFrames) {
            char suffix[16];
            std::snprintf(suffix, sizeof suffix, "_%04d", first + f);
            target = out.parent_path() / (out.stem().string() + suffix + out.extension().string());
        }
        if (pixels >= kLargeImagePixels)
            std::fprintf(stderr, "surfgrad: writing %s\n", target.string().c_str());
        writeImage(target, img, *aov, scene.output.exposure);
        if (ro.compare && gl) {
            gl->setProgress(nullptr);
            cpuOpt.progress = nullptr;
            View nv = view, pv = view;
            nv.aov = Aov::Normal;
            pv.aov = Aov::PrimId;
            Image gn = gl->render(scene, assets, nv), gp = gl->render(scene, assets, pv);
            Image cn = renderCpu(scene, assets, nv, cpuOpt),
                  cp = renderCpu(scene, assets, pv, cpuOpt);
            VectorImageDiff d = compareVectorImages(gn, cn, gp, cp);
            std::printf("normal AOV, OpenGL vs CPU reference: %zu pixels compared, %zu coverage "
                        "mismatches, %zu non-finite\n  angle (deg): mean %.4g  p50 %.4g  p90 %.4g  "
                        "p99 %.4g  p99.9 %.4g  max %.4g at (%d, %d)\n",
                        d.compared, d.coverageMismatch, d.nonFinite, d.meanDeg, d.p50Deg, d.p90Deg,
                        d.p99Deg, d.p999Deg, d.maxDeg, d.maxX, d.maxY);
        }
        double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("wrote %s (%dx%d, %s, %s, %.2f s elapsed)\n", target.string().c_str(),
                    img.width, img.height, aovName(*aov),
                    gl ? glTimes(gl->stats()).c_str() : "CPU reference", secs);
    }
}

void addRenderCommand(CLI::App& app, int& status) {
    auto* render =
        app.add_subcommand("render", "Render a scene (or the built-in default scene) to an image");
    auto ro = std::make_shared<RenderOpts>();
    render->add_option("scene", ro->scene,
                       "SCENE.json, or a model to frame automatically (" +
                           std::string(sg::mesh::kMeshFormatsText) +
                           "); default: the built-in scene");
    render->add_option("-o,--output", ro->out,
                       "Output image (.png tone-mapped, .exr linear); default out/<name>.png");
    render->add_option("--size", ro->size, "Image size WxH (default: the scene's output size)");
    render->add_option(
        "--aov", ro->aov,
        "Output variable: color, normal, surfgrad, tangent, bitangent, basenormal, uv, primid, "
        "patch");
    render->add_option("--frame", ro->frame, "Frame number (time = frame / fps)")
        ->check(CLI::Range(0.0, 1e7));
    render
        ->add_option("--tbn", ro->tbn,
                     "Tangent frame for normal-mapped UV sets: pixel, mikktspace or limit "
                     "(the scene field \"tangents\" on every mesh; limit applies to meshes "
                     "drawn as the limit surface, \"subdivision\": {\"limit\": true} or "
                     "{\"mode\": \"adaptive\"}, and never changes the geometry, other meshes "
                     "keep their tangents; mikktspace is refused on adaptive meshes)")
        ->check(CLI::IsMember({"pixel", "mikktspace", "limit"}));
    render->add_flag("--cpu", ro->cpu, "Use the CPU reference renderer instead of OpenGL");
    render
        ->add_option(
            "--cpu-derivatives", ro->cpuDeriv,
            "CPU reference screen derivatives: analytic (exact) or quad (emulates dFdxFine)")
        ->check(CLI::IsMember({"analytic", "quad"}));
    render
        ->add_option("--cpu-lod", ro->cpuLod,
                     "CPU reference texture LOD: exact (GL spec log2) or llvmpipe (its fast log2)")
        ->check(CLI::IsMember({"exact", "llvmpipe"}));
    render->add_flag("--all-frames", ro->allFrames,
                     "Render every frame of the scene to OUT_NNNN.ext");
    render->add_option("--texture-budget", ro->budget, kBudgetHelp);
    render->add_flag("-v,--verbose", ro->verbose, "Print what was loaded and compiled");
    render->add_flag(
        "--compare-cpu", ro->compare,
        "Also render the normal AOV with the CPU reference and print the per-pixel angle "
        "differences (pixels covered by the same primitive in both)");
    render->callback([ro, &status] {
        runRender(*ro);
        status = 0;
    });
}

// One program stage carried to the target: printed, or written to
// DIR/<program>.<target>.<stage><extension> (atomically) when an output
// folder is given. SPIR-V is printed as its disassembly and written as the
// module.
void emitStage(const std::string& glsl450, sg::translate::ShaderStage stage,
               sg::translate::ShaderTarget target, const std::string& label,
               const std::string& fileStem, const std::string& outDir) {
    namespace st = sg::translate;
    const st::TranslatedShader out = st::translateShader(glsl450, stage, target, label);
    const st::ShaderTargetInfo& info = st::shaderTargetInfo(target);
    const std::string validated = out.validatedBy.empty()
                                      ? std::string(", not validated (no validator here)")
                                      : ", validated by " + out.validatedBy;
    const char* stageName = st::shaderStageName(stage);
    if (outDir.empty()) {
        std::printf("// ==== %s: %s program, %s%s\n", label.c_str(),
                    stage == st::ShaderStage::Vertex     ? "vertex"
                    : stage == st::ShaderStage::Fragment ? "fragment"
                                                         : stageName,
                    info.language, validated.c_str());
        std::fputs(out.text.c_str(), stdout);
        return;
    }
    const fs::path file =
        fs::path(outDir) / (fileStem + "." + info.name + "." + stageName + info.extension);
    if (out.spirv.empty()) {
        sg::io::writeFileAtomically(file, out.text);
    } else {
        sg::io::writeFileAtomically(file,
                                    std::string(reinterpret_cast<const char*>(out.spirv.data()),
                                                out.spirv.size() * sizeof(uint32_t)));
    }
    std::printf("wrote %s (%s%s)\n", file.string().c_str(), info.language, validated.c_str());
}

// Every stage of one material's program for one target: fragment, vertex
// (printed with --vertex, always written), and for adaptive patches the
// evaluation stage and the control stage of each patch size (16 points
// regular, 20 Gregory), which the program's file names carry (_p16, _p20).
void emitProgram(const ProgramSource& src, sg::translate::ShaderTarget target,
                 const std::string& label, const std::string& stem, bool vertex,
                 const std::string& outDir) {
    namespace st = sg::translate;
    emitStage(src.fragment, st::ShaderStage::Fragment, target, label, stem, outDir);
    if (!vertex && outDir.empty()) return;
    emitStage(src.vertex, st::ShaderStage::Vertex, target, label, stem, outDir);
    if (src.tessEval.empty()) return;
    emitStage(src.tessEval, st::ShaderStage::TessEval, target, label, stem, outDir);
    for (int points : {16, 20}) {
        emitStage(assemblePatchControl(points).text, st::ShaderStage::TessControl, target,
                  label + ", " + std::to_string(points) + "-point patches",
                  stem + "_p" + std::to_string(points), outDir);
    }
}

// "--target": one name, a comma-separated list, or "all".
std::vector<sg::translate::ShaderTarget> parseTargets(const std::string& list) {
    namespace st = sg::translate;
    std::vector<st::ShaderTarget> targets;
    if (list == "all") {
        for (const st::ShaderTargetInfo& t : st::shaderTargets()) targets.push_back(t.target);
        return targets;
    }
    size_t at = 0;
    while (at <= list.size()) {
        const size_t comma = std::min(list.find(',', at), list.size());
        const std::string name = list.substr(at, comma - at);
        const std::optional<st::ShaderTarget> t = st::findShaderTarget(name);
        if (!t) {
            throw CliError("--target: '" + name + "' is not a shader target (expected " +
                           st::shaderTargetNames() + ", a comma-separated list, or all)");
        }
        if (std::find(targets.begin(), targets.end(), *t) == targets.end()) targets.push_back(*t);
        at = comma + 1;
    }
    return targets;
}

void addShaderCommand(CLI::App& app, int& status) {
    auto* shader = app.add_subcommand(
        "shader", "Print (or write) the assembled programs of a scene for shader targets");
    struct ShaderOpts {
        std::string scene, budget, target = "glsl450", outDir;
        int mesh = -1;
        bool vertex = false, body = false;
    };
    auto so = std::make_shared<ShaderOpts>();
    shader->add_option("scene", so->scene,
                       "SCENE.json or a model (" + std::string(sg::mesh::kMeshFormatsText) +
                           "); default: the built-in scene");
    shader->add_option("--mesh", so->mesh, "Only the program of mesh I (0-based)")
        ->check(CLI::NonNegativeNumber);
    shader->add_flag("--vertex", so->vertex, "Print the vertex programs too");
    shader->add_flag("--body", so->body,
                     "Print the generated body before #include expansion (glsl450 only)");
    shader->add_option("--target", so->target,
                       "Shader targets: " + sg::translate::shaderTargetNames() +
                           ", a comma-separated list of them, or all (default glsl450; all "
                           "skips the targets a program cannot reach: adaptive patches need "
                           "tessellation stages); every program is validated where a "
                           "validator exists (all but msl)");
    shader->add_option("-o,--output-dir", so->outDir,
                       "Write every program to DIR/program<N>.<target>.<stage><ext> "
                       "(stage: frag, vert; tese, tesc of adaptive patches) instead of "
                       "printing it (SPIR-V as the binary module)");
    shader->add_option("--texture-budget", so->budget, kBudgetHelp);
    shader->callback([so, &status] {
        namespace st = sg::translate;
        // Options first, before the scene's assets load.
        const std::vector<st::ShaderTarget> targets = parseTargets(so->target);
        if (so->body && (targets.size() != 1 || targets[0] != st::ShaderTarget::Glsl450))
            throw CliError("--body prints the GLSL 4.50 body; it takes no --target " + so->target);
        if (!so->outDir.empty() && !fs::is_directory(so->outDir))
            throw CliError("--output-dir " + so->outDir + ": not an existing folder");
        if (so->outDir.empty() && targets.size() > 1)
            throw CliError("--target " + so->target + ": several targets need --output-dir");
        Scene scene = sceneFromArg(so->scene);
        if (so->mesh >= 0 && size_t(so->mesh) >= scene.meshes.size()) {
            throw CliError("--mesh " + std::to_string(so->mesh) + ": the scene has " +
                           std::to_string(scene.meshes.size()) + " meshes");
        }
        AssetOptions assetOptions;
        if (!so->budget.empty())
            assetOptions.textureBudgetBytes = parseBytes("--texture-budget", so->budget);
        SceneAssets assets = loadAssets(scene, assetOptions);
        std::set<std::string> seen;
        for (size_t i = 0; i < scene.meshes.size(); ++i) {
            if (so->mesh >= 0 && size_t(so->mesh) != i) continue;
            MaterialPlan plan = planMaterial(scene, assets, int(i), scene.meshes[i].material);
            if (!seen.insert(plan.signature).second) continue;
            const std::string label = scene.meshes[i].fieldPath + " (material " +
                                      scene.materials[size_t(plan.materialIndex)].name + ")";
            if (so->body) {
                std::printf("// ==== %s: fragment program body\n", label.c_str());
                std::fputs(fragmentBody(plan).c_str(), stdout);
                continue;
            }
            ProgramSource src = assembleProgram(plan);
            const std::string stem = "program" + std::to_string(seen.size() - 1);
            for (st::ShaderTarget t : targets) {
                const st::ShaderTargetInfo& info = st::shaderTargetInfo(t);
                if (!src.tessEval.empty() && !info.tessellation) {
                    // Adaptive patches: tessellation stages and std430
                    // buffers (shader_target.h says which targets lack them).
                    const std::string why = label +
                                            ": adaptive patches (tessellation stages) are not "
                                            "carried to " +
                                            info.language;
                    if (so->target != "all") throw CliError("--target " + so->target + ": " + why);
                    std::printf("skipped %s: %s\n", info.name, why.c_str());
                    continue;
                }
                emitProgram(src, t, label, stem, so->vertex, so->outDir);
            }
        }
        status = 0;
    });
}

void addViewCommand(CLI::App& app, int& status) {
    auto* view = app.add_subcommand("view", "Interactive viewer (GLFW window + Dear ImGui)");
    struct ViewOpts {
        std::string scene, screenshot, size, budget;
        int frames = 0;
        bool noUi = false;
    };
    auto vo = std::make_shared<ViewOpts>();
    view->add_option("scene", vo->scene,
                     "SCENE.json or a model (" + std::string(sg::mesh::kMeshFormatsText) +
                         "); default: the built-in scene");
    view->add_option("--frames", vo->frames, "Quit after N frames (0: run until closed)")
        ->check(CLI::Range(0, 1000000));
    view->add_option("--screenshot", vo->screenshot,
                     "Write a PNG of the window after the first complete frame and quit (with "
                     "--frames N: after frame N)");
    view->add_option("--size", vo->size, "Window size WxH (default 1280x720)");
    view->add_option("--texture-budget", vo->budget, kBudgetHelp);
    view->add_flag("--no-ui", vo->noUi,
                   "No panel: the window shows the render alone, and so does --screenshot "
                   "(else the panel, docked at the right edge, is in the screenshot)");
    view->callback([vo, &status] {
#if SURFGRAD_HAVE_VIEWER
        ViewerOptions opt;
        opt.maxFrames = vo->frames;
        // A screenshot without --frames: the first complete frame, then quit
        // (nobody closes a window under a virtual X server). With the panel
        // that is frame 2: Dear ImGui hides an auto-sized window on the
        // frame it first measures it.
        if (!vo->screenshot.empty() && opt.maxFrames == 0) opt.maxFrames = vo->noUi ? 1 : 2;
        opt.screenshot = vo->screenshot;
        opt.panel = !vo->noUi;
        if (!vo->size.empty()) parseSize(vo->size, opt.width, opt.height);
        if (!vo->budget.empty())
            opt.textureBudgetBytes = parseBytes("--texture-budget", vo->budget);
        if (!opt.screenshot.empty()) io::checkOutputPath(opt.screenshot, {fs::path(vo->scene)});
        Scene scene = sceneFromArg(vo->scene);
        noteSubdivision(scene);
        status = runViewer(std::move(scene), opt);
#else
        (void)vo;
        (void)status;
        throw CliError(
            "view: this build has no viewer (configure with -DSURFGRAD_BUILD_VIEWER=ON)");
#endif
    });
}

} // namespace

void addRenderCommands(CLI::App& app, int& status) {
    addRenderCommand(app, status);
    addShaderCommand(app, status);
    addViewCommand(app, status);
}

} // namespace sg::cli
