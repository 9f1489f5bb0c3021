// Table 13, baking (docs/accuracy-cost.md): maps baked onto the limit
// surface against maps baked onto the cage refined to level 1-3 and
// triangulated (what triangle-mesh bakers measure from), both drawn the way
// the renderer draws an adaptive mesh: the limit surface displaced along
// its limit normal by the displacement map and shaded with the normal map
// in the limit frame (examples/tessellated-asset).
//
// Input: a known high-resolution surface. Spot's limit surface at level 6
// (1.5M triangles) with every vertex moved along its limit normal by
// 0.012 x examples/data/spot_height.png (the sculpt of the example's
// bake_maps.sh), vertex normals recomputed from the moved mesh.
//
// Error, at 100,000 random points of the limit surface (uniform in each
// adaptive patch's square, isolation 3 as the example): the ray from the
// point along +- its limit normal into the high mesh gives the true
// displacement t and the true normal n; the drawn surface there has
// displacement h = the map sampled bilinearly at the point's UV (the
// renderer's CPU texture sampling, surfgrad/render/glsl_texture.h), and the shading
// normal from the normal map (slopes sampled bilinearly, then
// sgMikktsBasis in the limit frame, sgSurfgradFromTBN, sgResolve: the
// renderer's path). Columns: |h - t| as a fraction of the sculpt's depth
// (0.012) and the angle between the shading normal and n, p50 and p99.
//
// Cost: bake() on all cores, median of 3 runs, and per million texels on
// the charts.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <random>
#include <unistd.h>
#include <thread>

#include <glm/geometric.hpp>

#include "adaptive_error.h"
#include "blender_anchor.h"
#include "high_mesh.h"
#include "limit_patches.h"
#include "surfgrad/bake/baker.h"
#include "surfgrad/bump/core.h"
#include "surfgrad/render/glsl_texture.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/normalmap/operations.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/mesh/subdivision.h"
#include "tables.h"

namespace study {

namespace {

namespace nm = sg::normalmap;
namespace G = sg::glsl;
using Clock = std::chrono::steady_clock;

constexpr float kDepth = 0.012f; // the sculpt's displacement scale (object units)
constexpr int kIsolation = 3;    // as examples/tessellated-asset

// A grid (float or vec2) or one channel of an image as a texture with
// clamped edges, sampled by the renderer's own GL rules (textureLod at
// level 0: bilinear, texel centres at (i + 0.5) / size, row 0 at t = 0).
sg::render::TextureImage texture(const nm::Grid<float>& g) {
    std::vector<glm::vec4> t(g.v.size());
    for (size_t k = 0; k < t.size(); ++k) t[k] = glm::vec4(g.v[k], 0.0f, 0.0f, 1.0f);
    return sg::render::makeTexture(g.width, g.height, std::move(t), sg::render::Wrap::Clamp);
}
sg::render::TextureImage texture(const nm::Grid<glm::vec2>& g) {
    std::vector<glm::vec4> t(g.v.size());
    for (size_t k = 0; k < t.size(); ++k) t[k] = glm::vec4(g.v[k], 0.0f, 1.0f);
    return sg::render::makeTexture(g.width, g.height, std::move(t), sg::render::Wrap::Clamp);
}
glm::vec4 bilinear(const sg::render::TextureImage& tex, glm::vec2 st) {
    return G::textureLod(G::sampler2D{&tex}, st, 0.0f);
}

// Spot's limit surface at `level`, each refined vertex moved once along
// its limit normal by kDepth x the height at its first render vertex's UV.
sg::mesh::RenderMesh sculpt(const sg::mesh::PolygonMesh& cage, int level) {
    sg::mesh::SubdivisionSettings s;
    s.level = level;
    s.limit = true;
    s.options = cage.options;
    sg::mesh::Subdivider sub(cage, s);
    sg::mesh::RenderMesh m = sub.renderMesh();
    const std::vector<uint32_t>& toRefined = sub.renderToRefinedVertex();
    const nm::Image image =
        nm::readImage(std::filesystem::path(SURFGRAD_EXAMPLE_DATA_DIR) / "spot_height.png");
    const sg::render::TextureImage height =
        texture(nm::scalarFromImage(image, 0, 1.0f, "spot_height.png"));
    std::vector<float> moveOf(sub.refined().vertexCount(), NAN);
    for (size_t v = 0; v < m.vertexCount(); ++v)
        if (std::isnan(moveOf[toRefined[v]]))
            moveOf[toRefined[v]] = kDepth * bilinear(height, m.uvSets[0][v]).x;
    for (size_t v = 0; v < m.vertexCount(); ++v)
        m.positions[v] += moveOf[toRefined[v]] * m.normals[v];
    m.normals.clear();
    sg::mesh::computeVertexNormals(m, toRefined);
    m.uvSets.clear();
    return m;
}

// Table 13's anchor: Blender bakes onto the refined L3 rows' mesh.
constexpr int kBlenderLevel = 3;
const std::string kBlenderName = "Blender Cycles, refined L3";

struct BlenderInputs {
    std::string blender;       // empty: no Blender rows
    std::filesystem::path dir; // temporary; removed after the table
    std::filesystem::path low, high;
};

// The meshes Blender reads, as OBJ: the cage refined to kBlenderLevel and
// triangulated exactly as the refined bake's base (Subdivider::renderMesh,
// its normals and UV set 0) and the high mesh.
BlenderInputs blenderInputs(const Options& o, const sg::mesh::PolygonMesh& cage,
                            const sg::mesh::RenderMesh& high) {
    BlenderInputs in;
    if (o.quick) return in;
    in.blender = findBlender();
    if (in.blender.empty()) return in;
    in.dir = std::filesystem::temp_directory_path() /
             ("surfgrad_table_bake_blender_" + std::to_string(getpid()));
    std::filesystem::create_directories(in.dir);
    sg::mesh::SubdivisionSettings s;
    s.level = kBlenderLevel;
    s.options = cage.options;
    in.low = in.dir / "low.obj";
    in.high = in.dir / "high.obj";
    sg::mesh::writeRenderMesh(in.low, sg::mesh::Subdivider(cage, s).renderMesh());
    sg::mesh::writeRenderMesh(in.high, high);
    return in;
}

struct Sample {
    glm::vec3 normal;  // unit limit normal
    glm::vec4 tangent; // limit tangent (sg/patch/limit_tangent.glsl)
    glm::vec2 st;
    float trueT;
    glm::vec3 trueNormal;
};

// Random points of the limit surface with the high mesh's answer there.
std::vector<Sample> samples(const sg::bake::detail::LimitPatches& lp,
                            const sg::bake::detail::HighMesh& high, int count, float tFar) {
    std::mt19937 rng(20261207u);
    std::uniform_int_distribution<uint32_t> patch(0, lp.patchCount() - 1);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<Sample> out;
    out.reserve(size_t(count));
    while (int(out.size()) < count) {
        const uint32_t p = patch(rng);
        const glm::vec2 uv(unit(rng), unit(rng));
        const sg::bake::detail::SurfaceSample s = lp.sample(p, uv);
        Sample x;
        x.normal = G::sgSafeNormalize(glm::cross(s.dPdu, s.dPdv), glm::vec3(0, 0, 1));
        int resolved = 0;
        x.tangent = G::sgPatchLimitTangent(s.dPdu, s.dPdv, s.dSTdu, s.dSTdv, x.normal, resolved);
        x.st = s.st;
        const auto up = high.cast(s.pos, x.normal, tFar), down = high.cast(s.pos, -x.normal, tFar);
        if (!up.hit && !down.hit) continue;
        const bool useDown = down.hit && (!up.hit || down.t < up.t);
        x.trueT = useDown ? -down.t : up.t;
        x.trueNormal = useDown ? down.normal : up.normal;
        out.push_back(x);
    }
    return out;
}

struct Row {
    std::string method;
    int size = 0;
    size_t chartTexels = 0;
    ErrorStats height, normal;
    double ms = 0;
};

// A bake's two maps drawn at every sample: `displacementMap` in object
// units along the limit normal, `slopeMap` tangent-space slopes read in the
// limit frame.
Row measure(const std::string& method, const nm::ScalarField& displacementMap,
            const nm::DerivField& slopeGrid, size_t chartTexels, const std::vector<Sample>& xs,
            double ms) {
    const sg::render::TextureImage displacement = texture(displacementMap),
                                   slopeMap = texture(slopeGrid);
    Row row;
    row.method = method;
    row.size = displacementMap.width;
    row.chartTexels = chartTexels;
    row.ms = ms;
    std::vector<double> he, ne;
    he.reserve(xs.size());
    ne.reserve(xs.size());
    for (const Sample& x : xs) {
        const float h = bilinear(displacement, x.st).x;
        he.push_back(std::abs(double(h) - double(x.trueT)) / kDepth);
        const glm::vec4 sl = bilinear(slopeMap, x.st);
        const glm::vec2 slopes(sl.x, sl.y);
        glm::vec3 tang, bino;
        G::sgMikktsBasis(x.normal, x.tangent, tang, bino);
        const G::SgFrame f =
            G::sgPrologue(x.normal, glm::vec3(0.0f), glm::vec3(0.0f), true, SG_BFACE_NONE);
        const glm::vec3 n = G::sgResolve(f, G::sgSurfgradFromTBN(slopes, tang, bino));
        ne.push_back(angleDeg(glm::dvec3(n), glm::dvec3(x.trueNormal)));
    }
    row.height = errorStats(he);
    row.normal = errorStats(ne);
    return row;
}

// 13b: the displaced geometry the renderer draws from each bake's
// displacement map (the CPU tessellator of the tessellated-asset view,
// the evaluation stage's math), against the high mesh, at several
// tessellation densities.
void tessellationTable(const Options& o, const sg::mesh::RenderMesh& high, int highLevel,
                       const std::vector<std::pair<std::string, nm::ScalarField>>& bakes) {
    const SurfaceReference ref(high);
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("surfgrad_table_bake_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    const std::vector<float> ppes =
        o.quick ? std::vector<float>{4} : std::vector<float>{8, 4, 2, 1};
    Table t;
    t.title = "Table 13b: the displaced limit surface drawn from each bake's displacement map, "
              "screen-space distance to the high mesh on the tessellated-asset view, 960x540 (px)";
    t.header = {"bake surface", "map", "px/edge", "triangles", "p99 (px)", "max (px)"};
    for (const auto& [name, displacement] : bakes) {
        const std::filesystem::path map = dir / "height.exr";
        nm::writeImage(map, nm::imageFromScalar(displacement, 0.0f, 1.0f, true),
                       nm::SampleType::Float);
        for (float ppe : ppes) {
            const sg::render::Scene scene = sceneOf(meshScene(
                "data:meshes/spot/spot_control_mesh.obj", 0.72f, adaptiveJson(kIsolation, ppe),
                R"(, "displacement": {"map": ")" + map.string() +
                    R"(", "scale": 1.0, "uv_set": 0})"));
            const sg::render::SceneAssets assets = sg::render::loadAssets(scene);
            const sg::render::View view = sg::render::makeView(scene, assets);
            const float focalPx = G::sgPatchFocalPx(view.proj[1][1], float(view.height));
            const sg::mesh::RenderMesh m = displacedMesh(scene, assets, view, ppe);
            const ScreenError e = screenError(ref, m, view, focalPx);
            t.add({name, std::to_string(displacement.width) + "^2", fmt(double(ppe), 0),
                   std::to_string(m.triangleCount()), fmtErr(e.p99), fmtErr(e.max)});
        }
    }
    std::filesystem::remove_all(dir);
    t.notes.push_back("each bake's displacement map (float) on the example's mesh (adaptive, "
                      "isolation 3, scale 1), tessellated by the CPU tessellator at the px/edge "
                      "given; distance of every drawn triangle's centroid and edge midpoints to "
                      "the high mesh (Spot's limit surface at level " +
                      std::to_string(highLevel) +
                      ", displaced), in pixels at the point's depth (table 11's measure).");
    t.print(o);
}

} // namespace

void tableBake(const Options& o) {
    const sg::mesh::PolygonMesh cage = sg::mesh::loadPolygonMesh(
        std::filesystem::path(SURFGRAD_DATA_DIR) / "meshes" / "spot" / "spot_control_mesh.obj");
    const int highLevel = o.quick ? 4 : 6;
    const sg::mesh::RenderMesh high = sculpt(cage, highLevel);
    const sg::bake::detail::LimitPatches lp(cage, kIsolation, 0, "spot", 0);
    const sg::bake::detail::HighMesh highRays(high, "sculpt");
    const float tFar = 0.1f;
    const std::vector<Sample> xs = samples(lp, highRays, o.quick ? 5000 : 100000, tFar);

    struct Method {
        std::string name;
        sg::bake::BakeSurface surface;
        int level;
    };
    const std::vector<Method> methods = {{"limit surface", sg::bake::BakeSurface::Limit, 0},
                                         {"refined L1", sg::bake::BakeSurface::Refined, 1},
                                         {"refined L2", sg::bake::BakeSurface::Refined, 2},
                                         {"refined L3", sg::bake::BakeSurface::Refined, 3}};
    const std::vector<int> sizes =
        o.quick ? std::vector<int>{128} : std::vector<int>{256, 512, 1024};
    const int runs = o.quick ? 1 : 3;
    std::vector<Row> rows;
    std::vector<std::pair<std::string, nm::ScalarField>> largest; // for 13b
    const BlenderInputs anchor = blenderInputs(o, cage, high);
    std::string anchorNotes, blenderVersion;
    for (int size : sizes) {
        size_t refinedL3Texels = 0; // Blender bakes the same layout
        for (const Method& m : methods) {
            sg::bake::BakeSettings s;
            s.width = s.height = size;
            s.surface = m.surface;
            s.refinedLevel = m.level;
            s.isolation = kIsolation;
            s.maxDistance = tFar;
            std::vector<double> ms;
            sg::bake::BakeResult r;
            for (int k = 0; k < runs; ++k) {
                const auto t0 = Clock::now();
                r = sg::bake::bake(cage, high, s);
                ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
            }
            rows.push_back(measure(m.name, r.displacement, r.tangentSlopes, r.stats.chartTexels, xs,
                                   median(ms)));
            if (m.level == kBlenderLevel) refinedL3Texels = r.stats.chartTexels;
            if (size == sizes.back() && m.level != 2)
                largest.emplace_back(m.name, std::move(r.displacement));
        }
        if (anchor.blender.empty()) continue;
        std::vector<BlenderBake> bs;
        for (int k = 0; k < runs; ++k)
            bs.push_back(blenderBake(anchor.blender, anchor.low, anchor.high, anchor.dir, size,
                                     tFar, sg::bake::BakeSettings{}.padTexels));
        std::vector<double> bakeMs, normalMs, processMs;
        for (const BlenderBake& b : bs) {
            bakeMs.push_back(b.bakeMs);
            normalMs.push_back(b.normalMs);
            processMs.push_back(b.processMs);
        }
        rows.push_back(measure(kBlenderName, bs.back().height, bs.back().slopes, refinedL3Texels,
                               xs, median(bakeMs)));
        anchorNotes += (anchorNotes.empty() ? "" : "; ") + std::to_string(size) +
                       "^2: normal bake alone " + fmt(median(normalMs), 1) +
                       " ms, whole blender process " + fmt(median(processMs), 1) + " ms";
        blenderVersion = bs.back().version;
        if (size == sizes.back()) largest.emplace_back(kBlenderName, std::move(bs.back().height));
    }
    if (!anchor.dir.empty()) std::filesystem::remove_all(anchor.dir);

    Table t;
    t.title = "Table 13: baking onto the limit surface vs onto the refined triangle mesh, Spot "
              "sculpt, drawn on the limit surface";
    t.header = {"bake surface",         "map",        "chart texels",
                "height p50 (% depth)", "height p99", "normal p50 (deg)",
                "normal p99",           "bake ms",    "ms / Mtexel"};
    for (const Row& r : rows) {
        t.add({r.method, std::to_string(r.size) + "^2", std::to_string(r.chartTexels),
               fmtErr(100.0 * r.height.p50), fmtErr(100.0 * r.height.p99), fmtErr(r.normal.p50),
               fmtErr(r.normal.p99), fmt(r.ms, 1), fmt(r.ms / (double(r.chartTexels) * 1e-6), 1)});
    }
    t.notes.push_back(
        "high mesh: Spot's limit surface at level " + std::to_string(highLevel) + " (" +
        std::to_string(high.triangleCount()) +
        " triangles) moved along the limit normal by 0.012 x spot_height.png; " +
        std::to_string(xs.size()) +
        " random points of the limit surface (adaptive patches, isolation 3); height: |map - "
        "true displacement| / 0.012; normal: shading normal from the map in the limit frame vs "
        "the high mesh's normal.");
    t.notes.push_back("bake ms: surfgrad::bake::bake on all cores (" +
                      std::to_string(std::max(1u, std::thread::hardware_concurrency())) +
                      " here), median of " + std::to_string(runs) +
                      " runs; ms / Mtexel: per million chart texels.");
    if (anchor.blender.empty())
        t.notes.push_back(o.quick ? "Blender's rows are left out in quick mode."
                                  : "Blender was not found (set SURFGRAD_BLENDER or put blender "
                                    "on PATH): its rows are absent.");
    else
        t.notes.push_back(
            kBlenderName + " (Blender " + blenderVersion +
            ", bench/accuracy/blender_bake.py): Cycles \"Selected to Active\" onto the cage "
            "refined to level 3 and triangulated (the refined L3 rows' mesh, written as OBJ), "
            "cage extrusion " +
            fmt(double(tFar), 2) + ", max ray distance " + fmt(2.0 * double(tFar), 2) +
            ", 1 sample, margin 8; its normal map is in that mesh's MikkTSpace frames, its "
            "displacement is dot(P_high - P_low, N_low) from two position bakes (emission) and "
            "an object-space normal bake, as Cycles has no displacement pass for selected to "
            "active; bake ms: the four bake calls (BVH build included, start-up and OBJ "
            "reading excluded), median of " +
            std::to_string(runs) + " runs; " + anchorNotes + ".");
    t.plot = {"bake", 7, 6, 0, {1}, true, true, "bake ms", "normal error p99, degrees"};
    t.print(o);
    tessellationTable(o, high, highLevel, largest);
}

} // namespace study
