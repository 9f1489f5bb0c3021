// Table 8: bump antialiasing (none, Toksvig, LEAN per layer, LEAN through
// composition) against a supersampled truth, for every layer kind that
// antialiases and for all of them composed in one material.
// Olano and Baker 2010 (LEAN), Toksvig 2005, Loviscach 2008 ("Care:
// Antialiasing"); Mikkelsen 2019, section 3 (the surface gradients add);
// the renderer's composition: shaders/sg/render/antialias.glsl.
//
// The scene: a plane whose normal is the world's diagonal (1, 1, 1)/sqrt 3
// (so a world-space triplanar layer blends its three planes equally), seen
// straight on by a perspective camera: every pixel covers the same area of
// the plane, and the minification m (map texels per pixel) is set by the
// camera's distance alone, so each variant's scene and assets load once.
// Every layer has the same density (128 map texels per world unit); one
// directional light near the mirror direction, black base colour, no
// ambient: the image is the GGX highlight (roughness 0.2), the radiance
// that aliases.
//   truth    - the CPU reference renderer at 16 x 16 samples per pixel,
//              texture level 0 (LodRule::Level0), no octave fade on noise,
//              the exact feature evaluator, box averaged;
//   variants - the GPU at one sample per pixel, mip-mapped maps:
//              no AA (maps "none": the filtered mean slope; noise "fade",
//              its frequency clamping; feature "none"), Toksvig (map
//              layers only), LEAN per layer (SG_AA_COV_UNMAPPED: each
//              layer's covariance in its own texture space, its trace
//              summed, no Jacobian) and LEAN through composition (what the
//              renderer does).
// Errors on the pixel radiance (all channels equal): RMSE, max, and the
// highlight energy (radiance sum / the truth's). Cost: frame time of each
// variant and the ratio to no AA, frames interleaved.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "surfgrad/render.h"
#include "tables.h"

namespace study {

namespace {

using namespace sg::render;

constexpr int kSuper = 16;             // truth samples per pixel along each axis (full run)
constexpr double kFovDeg = 60.0;       // vertical, square images
constexpr double kTexelsPerUnit = 128; // every layer's map texels per world unit
constexpr int kMapTexels = 128;        // tiled and triplanar maps
constexpr int kDecalTexels = 256;      // the decal's map (2 x 2 world units)
constexpr int kFeatureTexels = 256;    // the feature bake
constexpr double kDecalHalfSize = 1.0; // world units
constexpr double kMaxM = 64.0;         // the plane covers the view up to this minification

enum Variant { kNone, kToksvig, kPerLayer, kComposed, kVariantCount, kTruth = kVariantCount };
const char* const kVariantNames[kVariantCount] = {"no AA", "Toksvig", "LEAN per layer",
                                                  "LEAN through composition"};

struct SceneSpec {
    const char* name;
    bool tiled, triplanar, decal, noise, feature;
    bool hasMaps() const { return tiled || triplanar || decal; }
    // Only the decal or the feature map, both 2 x 2 world units at the
    // centre: errors are measured on the pixels inside that square.
    bool centreOnly() const { return (decal || feature) && !tiled && !triplanar && !noise; }
};

const std::vector<SceneSpec>& sceneSpecs() {
    static const std::vector<SceneSpec> s = {
        {"tiled normal map", true, false, false, false, false},
        {"triplanar", false, true, false, false, false},
        {"decal", false, false, true, false, false},
        {"noise", false, false, false, true, false},
        {"feature curves", false, false, false, false, true},
        {"all composed", true, true, true, true, true},
    };
    return s;
}

// A smooth periodic height field (sums of sines, st units) written as a
// float tangent-space normal map of n^2 texels: n = normalize(-dh/ds,
// -dh/dt, 1). `phase` varies the pattern between layers.
std::string writeSineMap(const std::string& path, int n, double amplitude, double phase) {
    const double tau = 6.283185307179586;
    Image img(n, n, 4);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double s = (i + 0.5) / n, t = (j + 0.5) / n;
            // h = sin(3 tau s) sin(5 tau t) + 0.5 sin(tau (7s + 4t) + phase)
            //     + 0.3 sin(tau (13s - 11t) + 2 phase), times amplitude.
            const double a = 3 * tau * s, b = 5 * tau * t;
            const double c = tau * (7 * s + 4 * t) + phase, e = tau * (13 * s - 11 * t) + 2 * phase;
            const double ds = 3 * tau * std::cos(a) * std::sin(b) + 0.5 * 7 * tau * std::cos(c) +
                              0.3 * 13 * tau * std::cos(e);
            const double dt = 5 * tau * std::sin(a) * std::cos(b) + 0.5 * 4 * tau * std::cos(c) -
                              0.3 * 11 * tau * std::cos(e);
            const glm::dvec3 m = glm::normalize(glm::dvec3(-amplitude * ds, -amplitude * dt, 1.0));
            img.setRgba(i, j, glm::vec4(glm::vec3(m), 1.0f));
        }
    writeImage(path, img, Aov::Normal, 1.0f);
    return path;
}

struct Maps {
    std::string tiled, triplanar, decal;
};

// The plane's frame: local y (its normal) on the world diagonal, local x
// and z in the plane (right-handed).
struct Frame {
    glm::dvec3 x, n, z;
};
Frame planeFrame() {
    const glm::dvec3 n = glm::normalize(glm::dvec3(1.0, 1.0, 1.0));
    const glm::dvec3 x = glm::normalize(glm::dvec3(1.0, -1.0, 0.0));
    return {x, n, glm::cross(x, n)};
}

std::string vec(const glm::dvec3& v) {
    char b[96];
    std::snprintf(b, sizeof b, "[%.9g, %.9g, %.9g]", v.x, v.y, v.z);
    return b;
}

// The "antialias" value of a layer kind in a variant (maps: uv_normal,
// triplanar, decal).
std::string aaValue(Variant v, bool map, bool noise) {
    if (v == kPerLayer || v == kComposed) return "lean";
    if (v == kToksvig && map) return "toksvig";
    if (noise) return v == kTruth ? "none" : "fade";
    return "none";
}

std::string layersJson(const SceneSpec& spec, Variant v, const Maps& maps, double planeSize) {
    std::vector<std::string> l;
    const std::string mapAa = "\"antialias\": \"" + aaValue(v, true, false) + "\"";
    if (spec.tiled)
        l.push_back(R"({"type": "uv_normal", "uv_set": 1, "encoding": "float", "map": {"file": ")" +
                    maps.tiled + "\"}, " + mapAa + "}");
    if (spec.triplanar)
        l.push_back(R"({"type": "triplanar", "space": "world", "scale": )" +
                    fmt(kTexelsPerUnit / kMapTexels, 6) +
                    R"(, "encoding": "float", "map": {"file": ")" + maps.triplanar + "\"}, " +
                    mapAa + "}");
    if (spec.decal) {
        const Frame f = planeFrame();
        const std::string size = fmt(2.0 * kDecalHalfSize, 6);
        l.push_back(R"({"type": "decal", "position": [0, 0, 0], "direction": )" + vec(-f.n) +
                    ", \"up\": " + vec(f.z) + ", \"size\": [" + size + ", " + size +
                    R"(, 1], "encoding": "float", "map": {"file": ")" + maps.decal + "\"}, " +
                    mapAa + "}");
    }
    if (spec.noise)
        l.push_back(R"({"type": "noise", "noise": "turbulence", "amplitude": 0.03, )"
                    R"("frequency": 4, "octaves": 6, "lacunarity": 2, "gain": 0.5, )"
                    R"("antialias": ")" +
                    aaValue(v, false, true) + "\"}");
    if (spec.feature) {
        // The map is clamped at its border: centred on the plane, 2 x 2
        // world units (as the decal), st * tiling + offset in [0, 1] there.
        // The curves keep 64 texels from the border, so the chain's levels
        // up to 6 (64 texels per texel, m = 64) read zeros when clamped.
        const double tiling = planeSize * kTexelsPerUnit / kFeatureTexels;
        const std::string offset = fmt(0.5 - 0.5 * tiling, 6);
        l.push_back(
            R"({"type": "feature", "curves": {"svg": "data:svg/flame.svg", "size": )" +
            std::to_string(kFeatureTexels) +
            R"(, "margin": 64}, "profile": "crease", "depth": 1.5, "width": 3, "uv_set": 0, "tiling": )" +
            fmt(tiling, 6) + ", \"offset\": [" + offset + ", " + offset + R"(], "antialias": ")" +
            aaValue(v, false, false) + "\"}");
    }
    std::string out;
    for (size_t i = 0; i < l.size(); ++i) out += (i ? ", " : "") + l[i];
    return out;
}

// The scene of one variant; the camera is placed by placeCamera.
Scene makeScene(const SceneSpec& spec, Variant v, const Maps& maps, int w) {
    const Frame f = planeFrame();
    // The view is w * m / kTexelsPerUnit world units wide.
    const double planeSize = 1.1 * w * kMaxM / kTexelsPerUnit;
    // Column-major model matrix: local x, y, z -> f.x, f.n, f.z.
    std::string m;
    for (const glm::dvec3& c : {f.x, f.n, f.z})
        m += fmt(c.x, 9) + ", " + fmt(c.y, 9) + ", " + fmt(c.z, 9) + ", 0, ";
    m += "0, 0, 0, 1";
    const std::string json =
        R"({"output": {"width": 64, "height": 64}, "ambient": [0, 0, 0],
      "camera": {"position": )" +
        vec(f.n) + R"(, "target": [0, 0, 0], "up": )" + vec(-f.z) + R"(, "fov_deg": )" +
        fmt(kFovDeg, 3) + R"(},
      "lights": [{"type": "directional", "direction": )" +
        vec(-f.n - 0.25 * f.x - 0.15 * f.z) + R"(, "intensity": 3}],
      "materials": [{"name": "m", "base_color": [0, 0, 0], "roughness": 0.2, "layers": [)" +
        layersJson(spec, v, maps, planeSize) + R"(]}],
      "meshes": [{"procedural": {"type": "plane", "size": )" +
        fmt(planeSize, 6) + R"(, "segments": 2, "uv_sets": 1},
                  "transform": {"matrix": [)" +
        m + R"(]},
                  "uv_sets": [{"from": 0, "scale": )" +
        fmt(planeSize * kTexelsPerUnit / kMapTexels, 6) + "}]}]}";
    return parseScene(json, "antialias-table.json", ".");
}

// The camera distance for m texels per pixel of a w-pixel image:
// world units per pixel 2 H tan(fov/2) / w = m / kTexelsPerUnit.
void placeCamera(Scene& s, double m, int w) {
    const double h = m * w / (kTexelsPerUnit * 2.0 * std::tan(kFovDeg * 3.141592653589793 / 360.0));
    s.camera.position = glm::dvec3(planeFrame().n * h);
    s.camera.nearPlane = float(0.5 * h);
    s.camera.farPlane = float(2.0 * h);
}

struct VariantScene {
    Scene scene;
    SceneAssets assets;
};

// The truth: kSuper x kSuper samples per pixel at level 0, box averaged.
Image truthImage(VariantScene& t, double m, int w, int super) {
    placeCamera(t.scene, m, w);
    View v = makeView(t.scene, t.assets, w * super, w * super, Aov::Color);
    CpuOptions o;
    o.textureLod = sg::glsl::LodRule::Level0;
    const Image big = renderCpu(t.scene, t.assets, v, o);
    Image img(w, w, 4);
    for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 sum(0.0);
            for (int j = 0; j < super; ++j)
                for (int i = 0; i < super; ++i)
                    sum += glm::dvec3(big.rgba(x * super + i, y * super + j));
            img.setRgba(x, y, glm::vec4(glm::vec3(sum / double(super * super)), 1.0f));
        }
    return img;
}

// Pixels measured: all, or on the decal and feature scenes those whose
// footprint lies inside the map's square (the rest is the flat plane).
std::vector<char> pixelMask(const SceneSpec& spec, double m, int w) {
    std::vector<char> mask(size_t(w) * size_t(w), 1);
    if (!spec.centreOnly()) return mask;
    const double wpp = m / kTexelsPerUnit;
    for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x) {
            const double u = std::abs((x + 0.5 - 0.5 * w) * wpp) + 0.5 * wpp;
            const double v = std::abs((y + 0.5 - 0.5 * w) * wpp) + 0.5 * wpp;
            mask[size_t(y) * size_t(w) + size_t(x)] =
                u <= kDecalHalfSize + 1e-9 && v <= kDecalHalfSize + 1e-9;
        }
    return mask;
}

struct Errors {
    double rmse = 0, max = 0, energy = 0;
};

Errors compare(const Image& a, const Image& truth, const std::vector<char>& mask) {
    Errors e;
    double sumA = 0, sumT = 0, sq = 0;
    size_t n = 0;
    for (size_t i = 0; i < a.texelCount(); ++i) {
        if (!mask[i]) continue;
        const double va = a.rgba(i).y, vt = truth.rgba(i).y; // green: all channels equal
        sq += (va - vt) * (va - vt);
        e.max = std::max(e.max, std::abs(va - vt));
        sumA += va;
        sumT += vt;
        ++n;
    }
    e.rmse = n ? std::sqrt(sq / double(n)) : 0.0;
    e.energy = sumT > 0 ? sumA / sumT : 0.0;
    return e;
}

double maskedMean(const Image& img, const std::vector<char>& mask) {
    double s = 0;
    size_t n = 0;
    for (size_t i = 0; i < img.texelCount(); ++i)
        if (mask[i]) {
            s += img.rgba(i).y;
            ++n;
        }
    return n ? s / double(n) : 0.0;
}

bool exists(const SceneSpec& spec, int v) {
    return v != kToksvig || spec.hasMaps();
}

// One variant's image on the GPU (LEAN per layer with SG_AA_COV_UNMAPPED).
Image gpuImage(GlRenderer& gl, VariantScene& vs, int v, double m, int w) {
    placeCamera(vs.scene, m, w);
    gl.setFragmentDefines(v == kPerLayer ? std::vector<std::string>{"SG_AA_COV_UNMAPPED"}
                                         : std::vector<std::string>{});
    Image img = gl.render(vs.scene, vs.assets, makeView(vs.scene, vs.assets, w, w, Aov::Color));
    gl.setFragmentDefines({});
    return img;
}

std::string cell(const Errors& e) {
    return fmt(e.rmse, 4) + " / " + fmt(e.max, 3) + " / " + fmt(e.energy, 3);
}

struct SceneSet {
    std::vector<VariantScene> v; // kVariantCount variants, then the truth's
};

SceneSet loadScenes(const SceneSpec& spec, const Maps& maps, int w) {
    SceneSet s;
    for (int v = 0; v <= kTruth; ++v) {
        Scene sc = makeScene(spec, Variant(v), maps, w);
        SceneAssets a = loadAssets(sc);
        s.v.push_back({std::move(sc), std::move(a)});
    }
    return s;
}

// Accuracy rows of one scene; the RMSE and energy of each variant at
// m = costM go to atCost.
void accuracyRows(Table& t, GlRenderer& gl, const SceneSpec& spec, SceneSet& s,
                  const std::vector<double>& ms, int w, int super, double costM,
                  std::vector<Errors>& atCost) {
    atCost.assign(kVariantCount, Errors{});
    for (double m : ms) {
        const Image truth = truthImage(s.v[kTruth], m, w, super);
        const std::vector<char> mask = pixelMask(spec, m, w);
        std::vector<std::string> row = {spec.name, fmt(m, 0), fmt(maskedMean(truth, mask), 4)};
        for (int v = 0; v < kVariantCount; ++v) {
            if (!exists(spec, v)) {
                row.push_back("n/a");
                continue;
            }
            const Errors e = compare(gpuImage(gl, s.v[size_t(v)], v, m, w), truth, mask);
            row.push_back(cell(e));
            if (m == costM) atCost[size_t(v)] = e;
        }
        t.add(row);
        std::fflush(stdout);
    }
}

// Frame times of the variants at m = costM, size x size pixels, interleaved.
std::vector<double> costs(GlRenderer& gl, const SceneSpec& spec, SceneSet& s, double costM,
                          int size, const Options& o) {
    std::vector<int> vars;
    for (int v = 0; v < kVariantCount; ++v)
        if (exists(spec, v)) vars.push_back(v);
    std::vector<View> views;
    for (int v : vars) {
        placeCamera(s.v[size_t(v)].scene, costM, size);
        views.push_back(
            makeView(s.v[size_t(v)].scene, s.v[size_t(v)].assets, size, size, Aov::Color));
    }
    auto draw = [&](size_t i) {
        const int v = vars[i];
        gl.setFragmentDefines(v == kPerLayer ? std::vector<std::string>{"SG_AA_COV_UNMAPPED"}
                                             : std::vector<std::string>{});
        gl.renderToTexture(s.v[size_t(v)].scene, s.v[size_t(v)].assets, views[i]);
    };
    for (size_t i = 0; i < vars.size(); ++i) draw(i); // compile, upload
    const std::vector<double> t = timeVariants(vars.size(), draw, o);
    gl.setFragmentDefines({});
    std::vector<double> out(kVariantCount, -1.0);
    for (size_t i = 0; i < vars.size(); ++i) out[size_t(vars[i])] = t[i];
    return out;
}

// no AA | LEAN through composition | truth, side by side, PNG.
void picture(GlRenderer& gl, SceneSet& s, double m, int w, int super, const std::string& path) {
    const Image panels[3] = {gpuImage(gl, s.v[kNone], kNone, m, w),
                             gpuImage(gl, s.v[kComposed], kComposed, m, w),
                             truthImage(s.v[kTruth], m, w, super)};
    const int gap = 4;
    Image out(3 * w + 2 * gap, w, glm::vec4(1.0f));
    for (int k = 0; k < 3; ++k)
        for (int y = 0; y < w; ++y)
            for (int x = 0; x < w; ++x) out.setRgba(k * (w + gap) + x, y, panels[k].rgba(x, y));
    writeImage(path, out, Aov::Color, 2.0f); // exposure 2: the highlight is dim
}

} // namespace

void tableAntialias(const Options& o) {
    const int w = o.quick ? 24 : 64, super = o.quick ? 8 : kSuper;
    const std::vector<double> ms =
        o.quick ? std::vector<double>{2, 16} : std::vector<double>{1, 2, 4, 8, 16, 32, 64};
    const double costM = o.quick ? 16 : 8;
    // Cost: 256^2 frames (the composed scene costs ~0.1 s a frame on
    // llvmpipe), at most 5 runs of 5 frames, to keep the table near 2 min.
    const int costSize = std::max(64, o.size / 4);
    Options co = o;
    co.runs = std::min(o.runs, 5);
    co.frames = std::min(o.frames, 5);
    const std::string dir = std::filesystem::temp_directory_path().string();
    Maps maps;
    maps.tiled = writeSineMap(dir + "/sg_aa_table_a.exr", kMapTexels, 0.012, 0.0);
    maps.triplanar = writeSineMap(dir + "/sg_aa_table_b.exr", kMapTexels, 0.010, 1.3);
    maps.decal = writeSineMap(dir + "/sg_aa_table_c.exr", kDecalTexels, 0.006, 2.1);

    Table t;
    t.title = "Table 8a: bump antialiasing, radiance error against the " + std::to_string(super) +
              "x" + std::to_string(super) + "-supersampled truth (" + std::to_string(w) + "x" +
              std::to_string(w) + " pixels; cells: RMSE / max / energy)";
    t.header = {"scene", "m", "truth mean"};
    for (const char* n : kVariantNames) t.header.push_back(n);
    Table c;
    c.title = "Table 8b: bump antialiasing cost (" + std::to_string(costSize) +
              "^2, m = " + fmt(costM, 0) + ", median of " + std::to_string(co.runs) + " runs x " +
              std::to_string(co.frames) + " frames; error columns from table 8a at that m)";
    c.header = {"scene", "variant", "frame ms", "ratio", "RMSE", "energy"};
    GlRenderer gl;
    for (const SceneSpec& spec : sceneSpecs()) {
        SceneSet s = loadScenes(spec, maps, w);
        std::vector<Errors> atCost;
        accuracyRows(t, gl, spec, s, ms, w, super, costM, atCost);
        const std::vector<double> ms8 = costs(gl, spec, s, costM, costSize, co);
        for (int v = 0; v < kVariantCount; ++v) {
            if (ms8[size_t(v)] < 0) {
                c.add({spec.name, kVariantNames[v], "n/a", "n/a", "n/a", "n/a"});
                continue;
            }
            c.add({spec.name, kVariantNames[v], fmt(ms8[size_t(v)], 2),
                   fmtRatio(ms8[size_t(v)] / ms8[kNone]), fmtErr(atCost[size_t(v)].rmse),
                   fmt(atCost[size_t(v)].energy, 3)});
        }
        if (!o.imageDir.empty() && spec.tiled && spec.feature) {
            const std::string path = o.imageDir + "/antialias.png";
            picture(gl, s, 16.0, 128, kSuper, path);
            t.notes.push_back("Picture written: antialias.png (all composed, m = 16, 128^2 per "
                              "panel: no AA | LEAN through composition | truth).");
        }
    }
    for (const std::string* f : {&maps.tiled, &maps.triplanar, &maps.decal}) {
        std::error_code ec;
        std::filesystem::remove(*f, ec); // scratch files; a failure leaves them in TMPDIR
    }
    t.notes.push_back("m: map texels per pixel (every layer 128 texels per world unit). Energy: "
                      "image radiance sum / the truth's (1 is right). n/a: no Toksvig for noise "
                      "(analytic variance) or feature curves (lean or none only).");
    t.print(o);
    c.plot.id = "antialias";
    c.plot.xColumn = 3;
    c.plot.yColumn = 4;
    c.plot.seriesColumn = 0;
    c.plot.labelColumns = {1};
    c.notes.push_back("Frames interleaved; median over runs of the per-run median; ratio to no AA "
                      "of the same scene in the same run; renderer " +
                      o.renderer + ".");
    c.print(o);
}

} // namespace study
