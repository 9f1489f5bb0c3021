// `surfgrad bake HIGH CAGE [--size N|WxH] [--uv-set K] [--isolation N]
//  [--surface limit|refined [--level N]] [--distance D] [--pad N] [--threads N] [--displacement
//  OUT.exr
//  [--displacement-bits half|float|16]]
//  [--normal OUT.png] [--residual-normal OUT.png] [--encoding E] [--green gl|dx]
//  [--bits B] [--object-normal OUT.png] [--mask OUT.png] [--json] [--progress]`:
// bakes the high-resolution mesh HIGH onto the Catmull-Clark limit surface
// of CAGE (or, --surface refined, onto CAGE refined to level N and
// triangulated, with MikkTSpace frames) in the layout of its UV set K
// (bake, surfgrad/bake/baker.h). Each
// output is optional, at least one is required:
//  - displacement: one channel, object units along the limit normal
//    (positive outwards): float in .exr/.tif (the scene's "displacement"
//    reads it with "scale": 1), or a 16-bit .png of (height - offset) /
//    scale with the scale and offset printed (and in --json and the file's
//    metadata), read with "scale" and "offset";
//  - normal: the tangent-space normal map in the limit frame (the frame of
//    "tangents": "limit" and of the per-pixel frame on that surface), in
//    the encodings of `surfgrad normalmap` (default rgb, +green up);
//  - residual-normal: the same frame and encodings, the residual after
//    displacement (BakeResult::residualSlopes): the map to pair with a
//    height layer of the displacement map (scale 1) so the two together
//    give the high mesh's normal;
//  - object-normal: the high mesh's normal in object space, 0.5 n + 0.5
//    (what an object_normal layer with "space": "object" reads);
//  - mask: one channel, 1 baked, 0.5 miss (its ray found no high mesh
//    within the distance), 0.25 padding, 0 empty.
// Every output path is checked before the bake starts; files are written
// atomically and never over an input. Misses and overlapping UVs are
// counted on stderr and in --json, never silently filled.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>

#include "commands.h"
#include "surfgrad/bake/baker.h"
#include "surfgrad/image/image_format.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/normalmap/operations.h"

namespace sg::cli {

namespace {

namespace nm = sg::normalmap;
namespace fs = std::filesystem;

struct BakeArgs {
    std::string high, cage, size = "1024";
    std::string displacement, normal, residualNormal, objectNormal, mask;
    std::string encoding = "rgb", green = "gl", bits, displacementBits;
    std::string surface = "limit";
    bake::BakeSettings settings;
    bool json = false, progress = false;
};

void parseSize(const std::string& text, bake::BakeSettings& s) {
    const size_t x = text.find('x');
    try {
        size_t used = 0;
        s.width = std::stoi(text.substr(0, x), &used);
        if (used != (x == std::string::npos ? text.size() : x)) throw std::invalid_argument("");
        s.height = s.width;
        if (x != std::string::npos) {
            s.height = std::stoi(text.substr(x + 1), &used);
            if (used != text.size() - x - 1) throw std::invalid_argument("");
        }
    } catch (const std::exception&) {
        throw CliError("bake: --size " + text + ": expected N or WxH (texels)");
    }
    if (const std::string why = bake::bakeSizeProblem(s.width, s.height); !why.empty())
        throw CliError("bake: --size " + text + ": " + why);
}

// How each image output is written: decided and checked against its file
// type by checkOutputs, before any work.
struct OutputTypes {
    nm::MapFormat normalFormat;
    nm::SampleType normal = nm::SampleType::U8, residualNormal = nm::SampleType::U8,
                   objectNormal = nm::SampleType::U8, mask = nm::SampleType::U8;
};

// The outputs, checked before any work: extensions that can hold the data,
// distinct paths, writable folders, never an input.
OutputTypes checkOutputs(const BakeArgs& a) {
    std::vector<std::string> outs;
    for (const std::string* o :
         {&a.displacement, &a.normal, &a.residualNormal, &a.objectNormal, &a.mask})
        if (!o->empty()) outs.push_back(*o);
    if (outs.empty())
        throw CliError("bake: nothing to write: give --displacement, --normal, "
                       "--residual-normal, --object-normal or --mask");
    std::set<fs::path> seen;
    for (const std::string& o : outs) {
        if (!seen.insert(fs::weakly_canonical(o)).second)
            throw CliError("bake: " + o + " is given for two outputs");
        io::checkOutputPath(o, {a.high, a.cage});
    }
    if (!a.displacement.empty()) {
        const std::string ext = image::lowerExtension(a.displacement);
        const bool png = ext == ".png";
        if (!png && ext != ".exr" && ext != ".tif" && ext != ".tiff")
            throw CliError("bake: --displacement " + a.displacement +
                           ": expected .exr or .tif (float heights) or .png (16-bit, with a "
                           "scale and an offset)");
        const std::string& b = a.displacementBits;
        if (png ? !(b.empty() || b == "16") : !(b.empty() || b == "half" || b == "float"))
            throw CliError("bake: --displacement-bits " + b + ": " + ext +
                           (png ? " holds 16-bit samples" : " holds half or float samples"));
    }
    OutputTypes t;
    t.normalFormat.encoding = nm::parseEncoding(a.encoding);
    t.normalFormat.green = nm::parseGreen(a.green);
    if (!a.normal.empty()) t.normal = nm::mapSampleType(a.normal, t.normalFormat, a.bits);
    if (!a.residualNormal.empty())
        t.residualNormal = nm::mapSampleType(a.residualNormal, t.normalFormat, a.bits);
    if (!a.objectNormal.empty()) {
        t.objectNormal = a.bits.empty() ? nm::defaultSampleType(a.objectNormal, false)
                                        : nm::parseSampleType(a.bits);
        nm::checkWritable(a.objectNormal, t.objectNormal);
    }
    if (!a.mask.empty()) {
        t.mask = nm::defaultSampleType(a.mask, false);
        nm::checkWritable(a.mask, t.mask);
    }
    return t;
}

// A 16-bit PNG holds (h - offset) / scale in [0, 1]: offset the lowest
// displacement, scale the range (1 where all are equal). A scene reads it
// back with "scale" and "offset" (docs/scene.md), to within half a step of
// 1 / 65535 of the range.
struct UnsignedHeights {
    float scale = 1.0f, offset = 0.0f;
};
UnsignedHeights unsignedHeights(const bake::BakeResult& r) {
    float lo = INFINITY, hi = -INFINITY;
    for (size_t k = 0; k < r.state.v.size(); ++k)
        if (r.state.v[k] != uint8_t(bake::TexelState::Empty)) {
            lo = std::min(lo, r.displacement.v[k]);
            hi = std::max(hi, r.displacement.v[k]);
        }
    UnsignedHeights u;
    if (!(lo <= hi)) return u;
    u.offset = lo;
    u.scale = hi > lo ? hi - lo : 1.0f;
    return u;
}

std::vector<std::pair<std::string, std::string>> attrs(const std::string& what, const BakeArgs& a) {
    return {{"surfgrad:op", "bake " + what},
            {"surfgrad:frame", a.surface == "limit" ? "limit" : "mikktspace"},
            {"surfgrad:surface",
             a.surface == "limit" ? "limit" : "refined " + std::to_string(a.settings.refinedLevel)},
            {"surfgrad:uvSet", std::to_string(a.settings.uvSet)}};
}

void writeDisplacement(const BakeArgs& a, const bake::BakeResult& r, nlohmann::json& report) {
    auto at = attrs("displacement", a);
    if (image::lowerExtension(a.displacement) != ".png") {
        nm::writeImage(a.displacement, nm::imageFromScalar(r.displacement, 0.0f, 1.0f, true),
                       a.displacementBits == "half" ? nm::SampleType::Half : nm::SampleType::Float,
                       at);
        report["displacement_scale"] = 1.0;
        report["displacement_offset"] = 0.0;
        return;
    }
    const UnsignedHeights u = unsignedHeights(r);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", double(u.scale));
    at.emplace_back("surfgrad:scale", buf);
    const std::string scale = buf;
    std::snprintf(buf, sizeof buf, "%.9g", double(u.offset));
    at.emplace_back("surfgrad:offset", buf);
    nm::ScalarField unit = r.displacement;
    for (size_t k = 0; k < unit.v.size(); ++k)
        unit.v[k] = r.state.v[k] == uint8_t(bake::TexelState::Empty)
                        ? 0.0f
                        : std::clamp((unit.v[k] - u.offset) / u.scale, 0.0f, 1.0f);
    nm::writeImage(a.displacement, nm::imageFromScalar(unit, 0.0f, 1.0f, false),
                   nm::SampleType::U16, at);
    report["displacement_scale"] = u.scale;
    report["displacement_offset"] = u.offset;
    std::fprintf(stderr,
                 "surfgrad: note: bake: %s holds (height - offset) / scale: read it with "
                 "\"displacement\": {\"map\": \"%s\", \"scale\": %s, \"offset\": %s}\n",
                 a.displacement.c_str(), a.displacement.c_str(), scale.c_str(), buf);
}

void writeOutputs(const BakeArgs& a, const OutputTypes& t, const bake::BakeResult& r,
                  nlohmann::json& report) {
    if (!a.displacement.empty()) writeDisplacement(a, r, report);
    const auto writeSlopes = [&](const std::string& path, const char* what,
                                 const nm::DerivField& slopes, nm::SampleType type) {
        const bool isFloat = type == nm::SampleType::Half || type == nm::SampleType::Float;
        auto at = attrs(what, a);
        at.emplace_back("surfgrad:encoding",
                        std::string(nm::encodingName(t.normalFormat.encoding)));
        at.emplace_back("surfgrad:green", a.green);
        nm::writeImage(path, nm::encodeSlopes(slopes, t.normalFormat, isFloat), type, at);
    };
    if (!a.normal.empty()) writeSlopes(a.normal, "normal", r.tangentSlopes, t.normal);
    if (!a.residualNormal.empty())
        writeSlopes(a.residualNormal, "residual-normal", r.residualSlopes, t.residualNormal);
    if (!a.objectNormal.empty()) {
        nm::Image img(r.width, r.height, 3);
        for (size_t k = 0; k < r.objectNormal.v.size(); ++k)
            for (int c = 0; c < 3; ++c)
                img.samples[k * 3 + size_t(c)] = 0.5f * r.objectNormal.v[k][c] + 0.5f;
        nm::writeImage(a.objectNormal, img, t.objectNormal, attrs("object-normal", a));
    }
    if (!a.mask.empty()) {
        nm::ScalarField m(r.width, r.height);
        static constexpr float kLevel[4] = {0.0f, 1.0f, 0.5f, 0.25f}; // by TexelState
        for (size_t k = 0; k < m.v.size(); ++k) m.v[k] = kLevel[r.state.v[k] & 3u];
        nm::writeImage(a.mask, nm::imageFromScalar(m, 0.0f, 1.0f, false), t.mask, attrs("mask", a));
    }
}

nlohmann::json statsJson(const bake::BakeStats& s) {
    return {{"chart_texels", s.chartTexels},
            {"hits", s.hits},
            {"misses", s.misses},
            {"padded", s.padded},
            {"overlap_texels", s.overlapTexels},
            {"patches", s.patches},
            {"max_uv_residual_texels", s.maxUvResidualTexels},
            {"max_distance", s.maxDistance},
            {"max_abs_displacement", s.maxAbsDisplacement},
            {"seconds",
             {{"patches", s.secondsPatches},
              {"high_mesh", s.secondsHighMesh},
              {"cover", s.secondsCover},
              {"texels", s.secondsTexels},
              {"pad", s.secondsPad}}}};
}

void runBake(BakeArgs a) {
    parseSize(a.size, a.settings);
    a.settings.residual = !a.residualNormal.empty();
    if (a.surface == "limit")
        a.settings.surface = bake::BakeSurface::Limit;
    else if (a.surface == "refined")
        a.settings.surface = bake::BakeSurface::Refined;
    else
        throw CliError("bake: --surface " + a.surface + ": expected limit or refined");
    // Encodings and sample types are checked before the bake, so a typo
    // costs no time.
    const OutputTypes types = checkOutputs(a);
    const auto threadLimit = limitThreads(a.settings.threads);
    const auto t0 = std::chrono::steady_clock::now();
    mesh::PolygonMesh cage = mesh::loadPolygonMesh(a.cage);
    mesh::RenderMesh high = mesh::loadRenderMesh(a.high);
    const double readSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto start = std::chrono::steady_clock::now();
    bake::BakeProgress progress;
    std::string lastStage;
    int lastPercent = -1;
    progress = [&](const char* stage, double f) {
        const bool show =
            a.progress || std::chrono::steady_clock::now() - start > std::chrono::seconds(1);
        const int pct = int(100.0 * f);
        if (!show || (stage == lastStage && pct / 10 == lastPercent / 10 && pct != 100)) return;
        lastStage = stage;
        lastPercent = pct;
        std::fprintf(stderr, "bake: %s %3d%%\n", stage, pct);
    };
    const bake::BakeResult r = bake::bake(cage, high, a.settings, a.cage, a.high, progress);
    nlohmann::json report = nlohmann::json::object(); // what the outputs add to --json
    writeOutputs(a, types, r, report);
    const bake::BakeStats& s = r.stats;
    if (s.misses > 0)
        std::fprintf(stderr,
                     "surfgrad: note: bake: %zu of %zu texels missed the high mesh within %g "
                     "(filled from the nearest hit; 0.5 in --mask)\n",
                     s.misses, s.chartTexels, s.maxDistance);
    if (s.overlapTexels > 0)
        std::fprintf(stderr,
                     "surfgrad: note: bake: %zu texels lie on overlapping UV charts of uv set %d "
                     "(the first patch keeps each)\n",
                     s.overlapTexels, a.settings.uvSet);
    if (a.json) {
        nlohmann::json j = statsJson(s);
        j.update(report);
        j["seconds"]["read"] = readSeconds;
        std::cout << j.dump(2) << "\n";
    } else {
        std::printf("baked %dx%d: %zu chart texels, %zu hits, %zu misses, %zu overlapping\n",
                    r.width, r.height, s.chartTexels, s.hits, s.misses, s.overlapTexels);
    }
}

} // namespace

void addBakeCommand(CLI::App& app, int& status) {
    auto a = std::make_shared<BakeArgs>();
    CLI::App* c = app.add_subcommand(
        "bake", "Bake a high-resolution mesh onto a Catmull-Clark cage's limit surface: "
                "displacement, tangent- and object-space normal maps in the cage's UV layout");
    c->add_option("high", a->high, "High-resolution mesh (any mesh format)")->required();
    c->add_option("cage", a->cage, "Control cage with a UV set (Catmull-Clark)")->required();
    c->add_option("--size", a->size, "Map size: N or WxH texels (default 1024)");
    c->add_option("--uv-set", a->settings.uvSet, "The cage's UV set of the layout (default 0)");
    c->add_option("--surface", a->surface,
                  "Surface measured from: limit (the Catmull-Clark limit surface, its limit "
                  "frame; default) or refined (the cage refined to --level and triangulated, "
                  "MikkTSpace frames: what triangle-mesh bakers do)");
    c->add_option("--level", a->settings.refinedLevel,
                  "--surface refined: uniform subdivision level (default 2)");
    c->add_option("--isolation", a->settings.isolation,
                  "Adaptive isolation of the limit patches, 1..10 (default 4)");
    c->add_option("--distance", a->settings.maxDistance,
                  "How far rays look along +- the limit normal, object units (default 5% of the "
                  "cage's bounding-box diagonal)");
    c->add_option("--pad", a->settings.padTexels, "Texels of padding around charts (default 8)");
    c->add_option("--displacement", a->displacement,
                  "Displacement map (.exr/.tif, object units along the limit normal)");
    c->add_option("--displacement-bits", a->displacementBits,
                  "Samples of the displacement map: float (default) or half for .exr/.tif; "
                  "16 for .png (written as (height - offset) / scale, both printed)");
    c->add_option("--normal", a->normal, "Tangent-space normal map in the limit frame");
    c->add_option("--residual-normal", a->residualNormal,
                  "Tangent-space normal map of the residual after displacement (pair it with a "
                  "height layer of the displacement map, scale 1)");
    c->add_option("--encoding", a->encoding,
                  "Encoding of the tangent-space maps: rgb, rg, ag, signed, deriv");
    c->add_option("--green", a->green,
                  "Green of the tangent-space maps: gl (+v up, default) or dx");
    c->add_option("--bits", a->bits, "Samples of the normal maps: 8, 16, half, float");
    c->add_option("--object-normal", a->objectNormal, "Object-space normal map (0.5 n + 0.5)");
    c->add_option("--mask", a->mask, "Texel states: 1 baked, 0.5 miss, 0.25 padding, 0 empty");
    c->add_flag("--json", a->json, "Print the counts and stage times as JSON");
    c->add_flag("--progress", a->progress, "Report progress on stderr however short the bake");
    addThreadsOption(c, a->settings.threads);
    addMaxMemoryOption(c, a->settings.memoryBudget);
    c->callback([a, &status] {
        runBake(*a);
        status = 0;
    });
}

} // namespace sg::cli
