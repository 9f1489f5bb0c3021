// `surfgrad features ...`: feature-curve maps (Parilov, Rosenberg, Zorin 2005;
// Parilov, Zorin 2008), surfgrad/features/feature_maps.h.
//
//   features bake (--curves F | --svg F | --font F --text STR [--face I])
//                 --size N [--mode linear|quadratic] [--margin T] [--band T]
//                 [--smooth K] [--near exact|paper] [--near-width T]
//                 [--threads N] -o MAPS.exr [--json] [--progress]
//     Bakes a curve network (--curves: JSON, docs/features-input.md) into
//     feature maps (OpenEXR only). Texel space: x right, y up, texel (i, j)
//     covers [i, i+1] x [j, j+1]; the input is scaled uniformly and centred
//     into [T, N - T]^2 (T = --margin, default 8). --json prints the
//     statistics as one JSON object (size, texels_with_features, seconds,
//     input_to_texel {scale, offset}, ...). Bakes longer than a second (or
//     any, with --progress) report progress on stderr, each phase up to
//     100%. --near exact keeps the exact near field (the input pieces with
//     their per-curve profiles and widths; curves without a width count as
//     --near-width, default 3 texels); paper (default) stores the papers'
//     maps only. --threads N: worker threads (1..1024, default all cores);
//     the maps are the same bits for every count.
//   features sample MAPS.exr --points F [--near exact|paper]
//     F holds one "x y" (texel space) per line; prints the header line
//     "x y dist grad_x grad_y", then one line per point: the distance
//     (texels) and unit gradient exactly as the shader computes them (the
//     C++ build of sgFeatSample / sgFeatSampleNear; maps with a near field
//     use it unless --near paper). A point outside the map ([0, N]^2) is an
//     error naming its line.
//   features render MAPS.exr --profile NAME [--width W] [--depth D]
//                 [--blend W0] [--zoom K] [--center x,y] [--size WxH]
//                 [--composition surfgrad|paper] [--compare bilinear]
//                 [--near exact|paper] -o IMG.png
//     A lit close-up of the feature normal field on the CPU (same code as
//     the shader), K pixels per texel around the centre; with --compare
//     bilinear, side by side with a plain bilinear normal map of the same
//     resolution (the profile's normals at the map's samples). In the exact
//     near field, curves with their own profile or width use them (the
//     layer's --profile and --width are the default). IMG is 8-bit sRGB:
//     .png (or .tga, .tif); another extension is refused before rendering.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <charconv>
#include <chrono>
#include <memory>
#include <string>
#include <utility>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "surfgrad/features/curves.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/image/image_write.h"
#include "surfgrad/base/io.h"

namespace sg::cli {

namespace fs = std::filesystem;
using namespace sg::features;

namespace {

struct BakeArgs {
    std::string json, svg, font, text, out;
    int face = 0;
    int size = 0;
    std::string mode = "linear";
    double margin = 8.0;
    double band = 16.0;
    int smooth = 10;
    std::string near = "paper";
    double nearWidth = 3.0;
    bool printJson = false;
    bool progress = false; // report progress however short the bake
    int threads = 0;       // 0: all cores
};

// Progress lines "features bake: PHASE NN%" on stderr; every phase that
// was reported ends with its 100% line (the bake reports phases at
// intervals, the last one before the end).
class BakeProgress {
public:
    explicit BakeProgress(bool always) : always_(always) {}
    void report(const char* phase, double fraction) {
        if (!always_ && std::chrono::steady_clock::now() - start_ < std::chrono::seconds(1)) return;
        if (phase_ != phase) finishPhase();
        phase_ = phase;
        fraction_ = fraction;
        std::fprintf(stderr, "features bake: %s %3.0f%%\n", phase, 100.0 * fraction);
    }
    // The last phase reported, at 100% (call when the bake returned).
    void finishPhase() {
        if (!phase_.empty() && fraction_ < 1.0)
            std::fprintf(stderr, "features bake: %s 100%%\n", phase_.c_str());
        phase_.clear();
    }

private:
    bool always_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    std::string phase_;
    double fraction_ = 0;
};

NearMode parseNear(const std::string& cmd, const std::string& v) {
    if (v == "exact") return NearMode::Exact;
    if (v == "paper") return NearMode::Paper;
    throw CliError("features " + cmd + ": --near must be exact or paper, got '" + v + "'");
}

void runBake(const BakeArgs& a) {
    int inputs = int(!a.json.empty()) + int(!a.svg.empty()) + int(!a.font.empty());
    if (inputs != 1) throw CliError("features bake: give exactly one of --curves, --svg, --font");
    if (image::lowerExtension(a.out) != ".exr") {
        throw CliError("features bake: -o " + a.out +
                       ": feature maps are .exr (OpenEXR keeps their 8 float channels)");
    }
    if (!a.font.empty() && a.text.empty()) throw CliError("features bake: --font needs --text");
    if (a.font.empty() && (!a.text.empty() || a.face != 0)) {
        throw CliError("features bake: --text and --face apply to --font only");
    }
    if (a.mode != "linear" && a.mode != "quadratic") {
        throw CliError("features bake: --mode must be linear or quadratic, got '" + a.mode + "'");
    }
    const fs::path in = !a.json.empty() ? a.json : !a.svg.empty() ? a.svg : a.font;
    io::checkOutputPath(a.out, {in});
    const auto threadLimit = limitThreads(a.threads);
    CurveNetwork net;
    if (!a.json.empty()) {
        net = loadCurvesJson(a.json);
    } else if (!a.svg.empty()) {
        net = loadSvg(a.svg);
    } else {
        FontOptions fo;
        fo.faceIndex = a.face;
        net = loadFont(a.font, a.text, fo);
    }
    BakeOptions opt;
    opt.size = a.size;
    opt.mode = a.mode == "linear" ? BakeMode::Linear : BakeMode::Quadratic;
    opt.marginTexels = a.margin;
    opt.bandTexels = a.band;
    opt.smoothIterations = a.smooth;
    opt.nearField = parseNear("bake", a.near) == NearMode::Exact;
    opt.nearWidthTexels = a.nearWidth;
    opt.threads = a.threads;
    auto progress = std::make_shared<BakeProgress>(a.progress);
    opt.progress = [progress](const char* phase, double fraction) {
        progress->report(phase, fraction);
    };
    BakeStats st;
    FeatureMaps maps = bake(net, opt, &st);
    progress->finishPhase();
    save(maps, a.out);
    std::error_code ec;
    double fileBytes = double(fs::file_size(a.out, ec));
    double texels = double(maps.size) * double(maps.size);
    if (a.printJson) {
        nlohmann::json j;
        j["size"] = maps.size;
        j["mode"] = toString(maps.mode);
        j["segments_in"] = net.segments.size();
        j["texels_with_features"] = st.texelsWithFeatures;
        j["texels_with_segments"] = st.texelsWithSegments;
        j["segments_kept"] = st.segmentsKept;
        j["segments_dropped"] = st.segmentsDropped;
        j["edge_points_merged"] = st.edgePointsMerged;
        j["curved_segments"] = st.curvedSegments;
        j["straightened_theta_min"] = st.straightenedThetaMin;
        j["straightened_flat"] = st.straightenedFlat;
        j["straightened_crossing"] = st.straightenedCrossing;
        j["eq7_failures"] = st.eq7Failures;
        j["invalid_texels"] = st.invalidTexels;
        j["optimized_texels"] = st.optimizedTexels;
        j["fallback_texels"] = st.fallbackTexels;
        j["seconds"] = st.seconds;
        j["threads"] = st.threads;
        j["cpu_seconds"] = st.cpuSeconds;
        j["cpu_seconds_phases"] = {{"scan", st.secondsScan},
                                   {"optimize", st.secondsOptimize},
                                   {"distance", st.secondsDistance},
                                   {"smooth", st.secondsSmooth}};
        j["seconds_phases"] = {{"scan", st.wallSecondsScan},
                               {"optimize", st.wallSecondsOptimize},
                               {"distance", st.wallSecondsDistance},
                               {"smooth", st.wallSecondsSmooth}};
        j["input_to_texel"] = {{"scale", {st.inputToTexel.scale.x, st.inputToTexel.scale.y}},
                               {"offset", {st.inputToTexel.offset.x, st.inputToTexel.offset.y}}};
        j["memory"] = {{"gpu_bytes_per_texel", FeatureMaps::kGpuBytesPerTexel},
                       {"canonical_bytes_per_texel", maps.canonicalBytesPerTexel()},
                       {"file_bytes", fileBytes},
                       {"file_bytes_per_texel", fileBytes / texels}};
        if (maps.hasNearField()) {
            GpuFeatureMaps gpu = maps.packGpu(a.threads);
            j["near"] = {{"pieces", st.nearPieces},
                         {"band_texels", st.nearBandTexels},
                         {"profiles", maps.profiles},
                         {"band_texel_count", gpu.nearStats.bandTexels},
                         {"pieces_per_band_texel_mean", gpu.nearStats.meanPieces},
                         {"pieces_per_band_texel_max", gpu.nearStats.maxPieces},
                         {"overflow_texels", gpu.nearStats.overflowTexels},
                         {"gpu_bytes_per_texel", gpu.nearBytesPerTexel()}};
        }
        j["output"] = a.out;
        std::cout << j.dump() << "\n";
    } else {
        std::printf("%s: %dx%d %s maps, %d texels with features, %d segments (%d curved), %.3f s; "
                    "texel = (%.9g, %.9g) * input + (%.9g, %.9g)\n",
                    a.out.c_str(), maps.size, maps.size, toString(maps.mode), st.texelsWithFeatures,
                    st.segmentsKept, st.curvedSegments, st.seconds, st.inputToTexel.scale.x,
                    st.inputToTexel.scale.y, st.inputToTexel.offset.x, st.inputToTexel.offset.y);
    }
}

bool parseNumber(std::string_view tok, double& v) {
    auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    return r.ec == std::errc() && r.ptr == tok.data() + tok.size() && std::isfinite(v);
}

std::string fmt(float v) {
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

void runSample(const std::string& mapsFile, const std::string& pointsFile,
               const std::string& nearArg) {
    const NearMode near = parseNear("sample", nearArg);
    FeatureMaps maps = load(mapsFile);
    GpuFeatureMaps gpu = maps.packGpu();
    std::vector<size_t> lines;
    std::vector<glm::vec2> pts = loadSamplePoints(pointsFile, &lines);
    // Outside the map the reconstruction extrapolates the border texels:
    // plausible-looking values that mean nothing.
    const float extent = float(maps.size);
    for (size_t i = 0; i < pts.size(); ++i) {
        const glm::vec2 p = pts[i];
        if (!(p.x >= 0.0f && p.x <= extent && p.y >= 0.0f && p.y <= extent)) {
            throw io::InputError(pointsFile, "line " + std::to_string(lines[i]),
                                 "point (" + fmt(p.x) + ", " + fmt(p.y) +
                                     ") is outside the map (texel space [0, " + fmt(extent) +
                                     "]^2)");
        }
    }
    std::string out = "x y dist grad_x grad_y\n";
    for (const auto& p : pts) {
        glsl::SgFeatResult r = sample(gpu, p, near);
        out += fmt(p.x) + " " + fmt(p.y) + " " + fmt(r.dist) + " " + fmt(r.grad.x) + " " +
               fmt(r.grad.y) + "\n";
    }
    std::fwrite(out.data(), 1, out.size(), stdout);
}

struct RenderArgs {
    std::string maps, profile, out, center, size = "512x512", composition = "surfgrad", compare;
    std::string near = "exact";
    float width = 3.0f, depth = 1.0f, blend = 0.0f, zoom = 16.0f;
};

// Shading of a tangent-space normal on a flat, unit-scaled plane seen from
// above: a key light from the upper left, Lambert plus Blinn-Phong.
glm::vec3 shade(glm::vec3 n) {
    const glm::vec3 l = glm::normalize(glm::vec3(-0.55f, 0.65f, 0.52f));
    const glm::vec3 v(0.0f, 0.0f, 1.0f);
    const glm::vec3 h = glm::normalize(l + v);
    float diff = std::max(glm::dot(n, l), 0.0f);
    float spec = std::pow(std::max(glm::dot(n, h), 0.0f), 48.0f) * (diff > 0.0f ? 1.0f : 0.0f);
    glm::vec3 albedo(0.72f, 0.70f, 0.66f);
    return albedo * (0.12f + 0.88f * diff) + glm::vec3(0.35f * spec);
}

float toSrgb(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

void runRender(const RenderArgs& a) {
    try {
        image::checkWritable(a.out, image::SampleType::Unorm8);
    } catch (const io::InputError& e) {
        throw CliError("features render: -o " + a.out + ": " + e.reason());
    }
    io::checkOutputPath(a.out, {a.maps});
    glsl::SgFeatProfile prof = makeProfile(a.profile, a.depth, a.blend, a.width);
    FeatureMaps maps = load(a.maps);
    GpuFeatureMaps gpu = maps.packGpu();
    if (a.width > float(maps.bandTexels) - 1.5f) {
        throw CliError("features render: --width " + fmt(a.width) +
                       " exceeds the maps' distance band " + fmt(float(maps.bandTexels)) +
                       " minus 1.5 texels (bake with a larger --band)");
    }
    const NearMode near = parseNear("render", a.near);
    if (near == NearMode::Exact && maps.hasNearField() && a.width > float(maps.nearBandTexels)) {
        throw CliError("features render: --width " + fmt(a.width) +
                       " exceeds the near field's band " + fmt(float(maps.nearBandTexels)) +
                       " texels (bake with a larger --near-width, or render --near paper)");
    }
    if (!(a.zoom > 0.0f && a.zoom <= 4096.0f))
        throw CliError("features render: --zoom must be in (0, 4096]");
    if (a.composition != "surfgrad" && a.composition != "paper") {
        throw CliError("features render: --composition must be surfgrad or paper");
    }
    if (!a.compare.empty() && a.compare != "bilinear")
        throw CliError("features render: --compare takes 'bilinear'");
    unsigned w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(a.size.c_str(), "%u%c%u%c", &w, &x, &h, &extra) != 3 ||
        (x != 'x' && x != 'X') || w < 1 || h < 1 || w > 4096 || h > 4096) {
        throw CliError("features render: --size must be WxH with 1 <= W, H <= 4096");
    }
    glm::vec2 centre(0.5f * float(maps.size));
    if (!a.center.empty()) {
        size_t comma = a.center.find(',');
        double cx = 0, cy = 0;
        if (comma == std::string::npos ||
            !parseNumber(std::string_view(a.center).substr(0, comma), cx) ||
            !parseNumber(std::string_view(a.center).substr(comma + 1), cy)) {
            throw CliError("features render: --center must be x,y in texel space");
        }
        centre = glm::vec2(float(cx), float(cy));
    }
    const bool compare = a.compare == "bilinear";
    const unsigned panels = compare ? 2 : 1;
    const unsigned gap = compare ? 4 : 0;
    const unsigned W = w * panels + gap * (panels - 1);
    std::vector<float> img(size_t(W) * h * 3, 1.0f);
    const glm::vec3 flat(0.0f, 0.0f, 1.0f);
    auto featureNormal = [&](glm::vec2 p) {
        glsl::SgFeatResult r = sample(gpu, p, near);
        // Per-curve profiles and widths (exact near field only).
        const glsl::SgFeatProfile pr =
            gpu.hasNearField() ? glsl::sgFeatCurveProfile(gpu.pieceSampler(), prof, r) : prof;
        if (a.composition == "paper") return glsl::sgFeatNormalPaper(r, pr, flat);
        return glsl::sgFeatNormalFromDeriv(glsl::sgFeatDeriv(r, pr, glm::vec2(0.0f)));
    };
    // The bilinear reference: the profile's normal at every grid sample
    // (distance and unit gradient of the sample), interpolated bilinearly.
    std::vector<glm::vec3> sampleNormals;
    if (compare) {
        const int m = maps.size + 1;
        sampleNormals.resize(size_t(m) * size_t(m));
        for (int j = 0; j < m; ++j) {
            for (int i = 0; i < m; ++i) {
                size_t k = maps.index(i, j);
                glsl::SgFeatResult r;
                r.dist = maps.dist[k];
                r.grad = glsl::sgSafeNormalize2(glm::vec2(maps.gradX[k], maps.gradY[k]),
                                                glm::vec2(0.0f));
                r.side = maps.left[k] ? 1.0f : -1.0f;
                r.profile = -1;
                r.width = 0.0f;
                sampleNormals[k] =
                    a.composition == "paper"
                        ? glsl::sgFeatNormalPaper(r, prof, flat)
                        : glsl::sgFeatNormalFromDeriv(glsl::sgFeatDeriv(r, prof, glm::vec2(0.0f)));
            }
        }
    }
    auto bilinearNormal = [&](glm::vec2 p) {
        const int m = maps.size + 1;
        glm::vec2 pc = glm::clamp(p, glm::vec2(0.0f), glm::vec2(float(maps.size)));
        int i = std::min(int(std::floor(pc.x)), maps.size - 1),
            j = std::min(int(std::floor(pc.y)), maps.size - 1);
        float fx = pc.x - float(i), fy = pc.y - float(j);
        auto at = [&](int ci, int cj) {
            return sampleNormals[size_t(cj) * size_t(m) + size_t(ci)];
        };
        glm::vec3 n = glm::mix(glm::mix(at(i, j), at(i + 1, j), fx),
                               glm::mix(at(i, j + 1), at(i + 1, j + 1), fx), fy);
        return glsl::sgSafeNormalize(n, flat);
    };
    // 3x3 supersampling per pixel keeps the close-up's creases free of
    // pixel staircase so the comparison shows the normal field itself.
    const int ss = 3;
    for (unsigned panel = 0; panel < panels; ++panel) {
        for (unsigned py = 0; py < h; ++py) {
            for (unsigned px = 0; px < w; ++px) {
                glm::vec3 c(0.0f);
                for (int sy = 0; sy < ss; ++sy) {
                    for (int sx = 0; sx < ss; ++sx) {
                        float ox = (float(px) + (float(sx) + 0.5f) / float(ss)) - 0.5f * float(w);
                        float oy = 0.5f * float(h) - (float(py) + (float(sy) + 0.5f) / float(ss));
                        glm::vec2 p = centre + glm::vec2(ox, oy) / a.zoom;
                        c += shade(panel == 0 ? featureNormal(p) : bilinearNormal(p));
                    }
                }
                c /= float(ss * ss);
                // Rows bottom first (the image writer's order): py = 0 is the top.
                float* o = &img[(size_t(h - 1 - py) * W + panel * (w + gap) + px) * 3];
                o[0] = toSrgb(c.x);
                o[1] = toSrgb(c.y);
                o[2] = toSrgb(c.z);
            }
        }
    }
    image::WriteOptions options;
    options.type = image::SampleType::Unorm8;
    options.colorSpace = "sRGB";
    image::writeImageFile(a.out, {img.data(), int(W), int(h), 3}, options);
}

} // namespace

void addFeaturesCommands(CLI::App& app, int& status) {
    auto* features = app.add_subcommand("features", "Feature-curve maps: bake, sample, render");
    features->require_subcommand(1);

    auto bakeArgs = std::make_shared<BakeArgs>();
    auto* bakeCmd =
        features->add_subcommand("bake", "Bake a curve network into feature maps (OpenEXR)");
    bakeCmd->add_option("--curves", bakeArgs->json,
                        "Curve network as JSON (docs/features-input.md)");
    bakeCmd->add_flag("--json", bakeArgs->printJson, "Print the statistics as JSON");
    bakeCmd->add_flag("--progress", bakeArgs->progress,
                      "Report progress on stderr however short the bake (default: after 1 s)");
    bakeCmd->add_option("--svg", bakeArgs->svg, "SVG drawing");
    bakeCmd->add_option("--font", bakeArgs->font, "TrueType/OpenType font");
    bakeCmd->add_option("--text", bakeArgs->text, "UTF-8 text to take from the font");
    bakeCmd->add_option("--face", bakeArgs->face, "Face index in a font collection");
    bakeCmd->add_option("--size", bakeArgs->size, "Texels per side N")
        ->required()
        ->check(CLI::Range(1, sg::features::kMaxFeatureMapSize));
    bakeCmd->add_option("--mode", bakeArgs->mode,
                        "linear (straight segments) or quadratic (Bezier curves)");
    bakeCmd->add_option("--margin", bakeArgs->margin,
                        "Texels kept free around the drawing (default 8)");
    bakeCmd->add_option("--band", bakeArgs->band,
                        "Distances are exact up to this many texels (default 16)");
    bakeCmd->add_option("--smooth", bakeArgs->smooth, "Gradient smoothing iterations (default 10)");
    bakeCmd->add_option("--near", bakeArgs->near,
                        "exact: keep the exact near field (input pieces, per-curve profiles and "
                        "widths); paper (default): the papers' maps only");
    bakeCmd->add_option("--near-width", bakeArgs->nearWidth,
                        "Profile width (texels) of curves without their own, for the near "
                        "field's band (default 3)");
    addThreadsOption(bakeCmd, bakeArgs->threads);
    bakeCmd->add_option("-o,--output", bakeArgs->out, "Output maps (.exr)")->required();
    bakeCmd->callback([bakeArgs] { runBake(*bakeArgs); });

    auto sampleMaps = std::make_shared<std::string>();
    auto samplePoints = std::make_shared<std::string>();
    auto* sampleCmd =
        features->add_subcommand("sample", "Reconstructed distance and gradient at points");
    sampleCmd->add_option("maps", *sampleMaps, "Feature maps (.exr)")->required();
    sampleCmd->add_option("--points", *samplePoints, "File of \"x y\" lines in texel space")
        ->required();
    auto sampleNear = std::make_shared<std::string>("exact");
    sampleCmd->add_option("--near", *sampleNear,
                          "exact (default: the near field when the maps have one) or paper");
    sampleCmd->callback([sampleMaps, samplePoints, sampleNear] {
        runSample(*sampleMaps, *samplePoints, *sampleNear);
    });

    auto renderArgs = std::make_shared<RenderArgs>();
    auto* renderCmd =
        features->add_subcommand("render", "Lit close-up of the feature normal field (PNG)");
    renderCmd->add_option("maps", renderArgs->maps, "Feature maps (.exr)")->required();
    renderCmd
        ->add_option("--profile", renderArgs->profile,
                     "vgroove, crease, ridge, step, seam or table:h0,h1,...")
        ->required();
    renderCmd->add_option("--width", renderArgs->width, "Profile half-width w, texels (default 3)");
    renderCmd->add_option("--depth", renderArgs->depth, "Profile depth, texels (default 1)");
    renderCmd->add_option("--blend", renderArgs->blend,
                          "w0: band where only the profile acts, texels (default 0)");
    renderCmd->add_option("--zoom", renderArgs->zoom, "Pixels per texel (default 16)");
    renderCmd->add_option("--center", renderArgs->center,
                          "Centre x,y in texel space (default: map centre)");
    renderCmd->add_option("--size", renderArgs->size, "Image size WxH per panel (default 512x512)");
    renderCmd->add_option("--composition", renderArgs->composition,
                          "surfgrad (default) or paper (Eq. 1)");
    renderCmd->add_option("--compare", renderArgs->compare,
                          "bilinear: add a plain bilinear normal map panel");
    renderCmd->add_option("--near", renderArgs->near,
                          "exact (default: the near field when the maps have one) or paper");
    renderCmd->add_option("-o,--output", renderArgs->out, "Output image (.png)")->required();
    renderCmd->callback([renderArgs] { runRender(*renderArgs); });
    (void)status;
}

} // namespace sg::cli
