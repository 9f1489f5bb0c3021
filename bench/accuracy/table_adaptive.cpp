// Table 11: adaptive patches (GPU tessellation of OpenSubdiv's feature-
// adaptive patches, docs/mesh.md) against the uniform CPU path, both drawn
// through the renderer at 960x540; on llvmpipe the tessellation and compute
// stages run on the CPU: only same-run ratios mean anything.
//
// 11a, equal screen-space error: per view of an asset (small, medium, full
// screen), the coarsest uniform level (limit) and the largest
// pixels_per_edge whose triangles lie within 0.5 px of the limit surface
// (p99 and max over centroids and edge midpoints; the limit from a dense
// OpenSubdiv limit mesh), and their triangles, GPU buffers, load CPU time,
// per-frame upload of an animated cage and draw time, same run.
//
// 11b, animated cages: every frame the cage moves (a wave of a few percent
// of its size); adaptive = setCagePositions, upload of the cage and the
// stencils' compute stage (sg/patch/stencils.comp.glsl); uniform = CPU
// refinement of the moved cage (Subdivider::update: positions, limit
// normals) and upload of the refined positions and normals. Per-frame
// upload bytes (RenderStats::meshUploadBytes), CPU time, upload + compute
// wall time, draw wall time, the frame's total and its ratio to uniform on
// the same cage, measured in the same run: spot's cage, bob (a triangle
// cage) and a 128k-quad cage (bob refined twice on the CPU, written to a
// scratch OBJ).
//
// 11c, static spot on the tessellated-asset example's view: load (CPU)
// time, triangles drawn, GPU buffer bytes, draw wall time and its ratio to
// uniform level 3, frames interleaved.
//
// 11d, displacement's cost: the tessellated-asset example's mesh (spot,
// adaptive, isolation 3) with and without its displacement
// (examples/data/spot_height.png, scale 0.012 on UV set 0, sg/patch/
// displace.glsl), at several pixels_per_edge: the CPU tessellator's time
// (the CPU reference's tessellation), the GPU draw time and its ratio to
// the undisplaced draw, frames interleaved; and pinholes in the GPU image
// (uncovered pixels whose four neighbours are covered: 0 when displaced
// shared edges stay closed).
//
// 11e, the tangent frame's source on adaptive patches (Mikkelsen 2019
// section 2.3): spot (isolation 3) with a tangent-space normal map on UV
// set 0 (procedural bricks), the per-pixel frame (screen-space derivatives
// of the tessellated triangle's position and UV) against "tangents":
// "limit" (sg/patch/limit_tangent.glsl in the evaluation stage, interpolated
// over the triangle), at several pixels_per_edge. Ground truth: the limit
// frame at 1 px/edge (its interpolation error is quadratic in the triangle
// size). Errors: angle of the tangent AOV and of the shaded normal to the
// ground truth's at pixels both cover; cost: draw time, frames interleaved,
// and its ratio to the per-pixel frame at the same pixels_per_edge.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <vector>

#include "render_internal.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/render.h"
#include "adaptive_error.h"
#include "surfgrad/mesh/subdivision.h"
#include "tables.h"

namespace study {

namespace {

using namespace sg::render;

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::filesystem::path dataDir() {
    const char* env = std::getenv("SURFGRAD_DATA_DIR");
    return env && *env ? std::filesystem::path(env) : dataDirectory();
}

// Bytes the renderer's buffers hold for adaptive patches: control points
// (xyz), control-point indices and the patch records the draw uploads
// (detail::patchRecords, 28 words per patch); with `stencils`, also the
// animated path's stencil rows (offsets, indices, weights of the passes;
// the cage is uploaded into the control points' buffer).
size_t patchGpuBytes(const sg::mesh::AdaptivePatches& p, bool stencils) {
    size_t bytes = p.points.size() * 12 + p.indices.size() * 4 + detail::patchRecords(p).size() * 4;
    if (stencils)
        bytes +=
            p.stencilOffsets.size() * 4 + p.stencilIndices.size() * 4 + p.stencilWeights.size() * 4;
    return bytes;
}

// Bytes of a uniform mesh's buffers: positions, normals, UV sets, 32-bit
// indices.
size_t meshGpuBytes(const sg::mesh::RenderMesh& m) {
    return m.vertexCount() * (24 + 8 * m.uvSets.size()) + m.indices.size() * 4;
}

std::string uniformJson(int level) {
    return "{\"level\": " + std::to_string(level) + ", \"limit\": true}";
}

// ---- 11b: animated cages -------------------------------------------------

// The cage at frame f: every vertex moved along a travelling wave of 2% of
// the cage's extent (what skinning or blendshapes would hand the renderer).
void waveCage(const std::vector<glm::vec3>& rest, float extent, int f,
              std::vector<glm::vec3>& out) {
    out.resize(rest.size());
    const float t = 0.35f * float(f);
    for (size_t v = 0; v < rest.size(); ++v) {
        const glm::vec3 p = rest[v];
        const float phase = 6.0f * (p.x + p.y + p.z) / extent + t;
        out[v] = p + 0.02f * extent *
                         glm::vec3(std::sin(phase), std::cos(1.3f * phase),
                                   std::sin(0.7f * phase + 1.0f));
    }
}

struct AnimCase {
    const char* name;
    std::filesystem::path file;
};

struct AnimRow {
    std::string cage, mode;
    size_t cageFaces = 0, cageVerts = 0, triangles = 0, gpuBytes = 0;
    uint64_t uploadBytes = 0;
    std::vector<double> cpuMs, updateMs, drawMs, frameMs;
};

// Adaptive (cage upload + GPU stencils) and uniform (CPU refinement +
// upload) of one moving cage, frames interleaved.
void animatedCage(const AnimCase& c, int uniformLevel, float pixelsPerEdge, int isolation,
                  int frames, std::vector<AnimRow>& out) {
    const sg::mesh::PolygonMesh cage = sg::mesh::loadPolygonMesh(c.file);
    float extent = 0.0f;
    for (const glm::vec3& p : cage.positions)
        extent = std::max({extent, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    Scene sa = sceneOf(meshScene(c.file.string(), 0.72f, adaptiveJson(isolation, pixelsPerEdge)));
    Scene su = sceneOf(meshScene(c.file.string(), 0.72f, uniformJson(uniformLevel)));
    SceneAssets aa = loadAssets(sa), au = loadAssets(su);
    // The uniform path's animated refiner: the same settings as the asset's.
    sg::mesh::SubdivisionSettings st;
    st.level = uniformLevel;
    st.options = cage.options;
    st.limit = true;
    st.animate = true;
    sg::mesh::Subdivider sub(cage, st, c.file.string());
    sg::mesh::RenderMesh moving = sub.renderMesh();
    sg::mesh::LimitFrame frame = sub.limitFrame();
    if (moving.vertexCount() != au.meshes[0].mesh.vertexCount())
        throw std::runtime_error("table adaptive: uniform vertex layouts differ");
    const View view = makeView(su, au);
    GlRenderer ra, ru;
    ra.renderToTexture(sa, aa, view); // compile, first upload
    ru.renderToTexture(su, au, view);
    const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
    AnimRow A, U;
    A.cage = U.cage = c.name;
    A.cageFaces = U.cageFaces = cage.faceCount();
    A.cageVerts = U.cageVerts = cage.vertexCount();
    char mode[64];
    std::snprintf(mode, sizeof mode, "adaptive %g px/edge (isolation %d)", double(pixelsPerEdge),
                  isolation);
    A.mode = mode;
    std::snprintf(mode, sizeof mode, "uniform level %d (limit)", uniformLevel);
    U.mode = mode;
    U.triangles = au.meshes[0].mesh.triangleCount();
    U.gpuBytes = meshGpuBytes(au.meshes[0].mesh);
    A.gpuBytes = patchGpuBytes(*aa.meshes[0].patches, true);
    // One frame of a mode: the caller's CPU work (timed), then the render.
    auto timeFrame = [&](AnimRow& row, GlRenderer& r, const Scene& sc, const SceneAssets& as,
                         const auto& cpuWork) {
        auto t0 = Clock::now();
        cpuWork();
        row.cpuMs.push_back(msSince(t0));
        t0 = Clock::now();
        r.renderToTexture(sc, as, view);
        row.frameMs.push_back(row.cpuMs.back() + msSince(t0));
        row.updateMs.push_back(r.stats().meshUpdateWallMs);
        row.drawMs.push_back(r.stats().drawWallMs);
        row.uploadBytes = r.stats().meshUploadBytes;
    };
    std::vector<glm::vec3> moved;
    for (int f = 1; f <= frames; ++f) {
        waveCage(cage.positions, extent, f, moved);
        // Adaptive: the cage to the renderer, the GPU does the rest.
        timeFrame(A, ra, sa, aa, [&] { setCagePositions(sa, aa, 0, moved); });
        // Uniform: refine the moved cage on the CPU, upload the mesh.
        timeFrame(U, ru, su, au, [&] {
            sub.update(moved, moving, &frame);
            MeshAsset& m = au.meshes[0];
            std::memcpy(m.mesh.positions.data(), moving.positions.data(),
                        moving.positions.size() * sizeof(glm::vec3));
            std::memcpy(m.mesh.normals.data(), moving.normals.data(),
                        moving.normals.size() * sizeof(glm::vec3));
            ++au.meshVersion;
        });
    }
    // Triangles the adaptive draw makes on the last frame's cage.
    sg::mesh::AdaptivePatches ap = *aa.meshes[0].patches;
    sg::mesh::updateAdaptivePoints(ap, moved);
    A.triangles =
        detail::tessellatePatches(ap, modelToCameraRelative(sa.meshes[0].transform, view.cameraPos),
                                  focalPx, pixelsPerEdge)
            .mesh.triangleCount();
    out.push_back(std::move(A));
    out.push_back(std::move(U));
}

void animatedTable(const Options& o) {
    const std::filesystem::path data = dataDir();
    const std::filesystem::path scratch =
        std::filesystem::temp_directory_path() / ("sg_table_adaptive_" + std::to_string(getpid()));
    const int frames = o.quick ? 3 : 7;
    // The larger cages cost seconds per adaptive frame on llvmpipe: fewer
    // frames, isolation 2 (a triangle cage has an extraordinary vertex at
    // every face centre of its first refinement). --quick: spot only.
    const int heavyFrames = 3;
    std::vector<AnimRow> rows;
    animatedCage({"spot", data / "meshes/spot/spot_control_mesh.obj"}, 3, 4.0f, 3, frames, rows);
    if (!o.quick) {
        std::filesystem::create_directories(scratch);
        // The 128k-quad cage: bob refined twice (no limit), written as OBJ.
        const sg::mesh::PolygonMesh bob =
            sg::mesh::loadPolygonMesh(data / "meshes/bob/bob_tri.obj");
        sg::mesh::SubdivisionSettings st;
        st.level = 2;
        st.options = bob.options;
        st.buildRenderMesh = false;
        sg::mesh::Subdivider sub(bob, st, "bob_tri.obj");
        sg::mesh::PolygonMesh big = sub.refined();
        big.uvSets.clear();
        big.normals.clear();
        big.normalIndices.clear();
        sg::mesh::writePolygonMesh(scratch / "bob_l2.obj", big);
        animatedCage({"bob", data / "meshes/bob/bob_tri.obj"}, 2, 4.0f, 2, heavyFrames, rows);
        animatedCage({"bob refined twice", scratch / "bob_l2.obj"}, 1, 4.0f, 2, heavyFrames, rows);
        std::error_code ec;
        std::filesystem::remove_all(scratch, ec); // a failure leaves it in TMPDIR
    }
    Table t;
    t.title = "Table 11b: animated cages, 960x540, median of " + std::to_string(frames) +
              " frames" + (o.quick ? "" : " (bob: " + std::to_string(heavyFrames) + ")") +
              "; each frame a new cage; adaptive and uniform interleaved";
    t.header = {"cage (faces, vertices)",
                "mode",
                "triangles drawn",
                "GPU buffers MiB",
                "upload/frame KiB",
                "CPU ms",
                "upload+compute ms",
                "draw ms",
                "frame ms",
                "ratio to uniform"};
    for (size_t i = 0; i < rows.size(); i += 2) {
        const double base = median(rows[i + 1].frameMs);
        for (size_t k = i; k < i + 2; ++k) {
            const AnimRow& r = rows[k];
            t.add({r.cage + " (" + std::to_string(r.cageFaces) + ", " +
                       std::to_string(r.cageVerts) + ")",
                   r.mode, std::to_string(r.triangles), fmt(double(r.gpuBytes) / 1048576.0, 1),
                   fmt(double(r.uploadBytes) / 1024.0, 1), fmt(median(r.cpuMs), 2),
                   fmt(median(r.updateMs), 2), fmt(median(r.drawMs), 1), fmt(median(r.frameMs), 1),
                   fmtRatio(median(r.frameMs) / base)});
        }
    }
    t.notes.push_back(
        "GPU buffers: adaptive = control points, indices, patch records and the stencil rows "
        "(applied level by level); uniform = positions, normals, UV sets, indices. Upload: "
        "RenderStats::"
        "meshUploadBytes (exact). CPU: the caller's work per frame (adaptive: setCagePositions; "
        "uniform: Subdivider::update and the copy). Frame: CPU + renderToTexture. Ratio to "
        "uniform on the same cage, same run; renderer " +
        o.renderer + ".");
    t.print(o);
}

// ---- 11c: static spot ----------------------------------------------------

void staticTable(const Options& o) {
    struct Case {
        const char* name;
        std::string subdivision;
    };
    const std::vector<Case> cases = {
        {"uniform level 2 (limit)", uniformJson(2)},
        {"uniform level 3 (limit)", uniformJson(3)},
        {"uniform level 4 (limit)", uniformJson(4)},
        {"adaptive 8 px/edge", R"({"mode": "adaptive", "pixels_per_edge": 8})"},
        {"adaptive 4 px/edge", R"({"mode": "adaptive", "pixels_per_edge": 4})"},
        {"adaptive 2 px/edge", R"({"mode": "adaptive", "pixels_per_edge": 2})"},
    };
    struct Row {
        Scene scene;
        SceneAssets assets;
        double loadMs = 0.0;
        size_t triangles = 0, gpuBytes = 0;
        std::vector<double> drawMs;
    };
    std::vector<Row> rows;
    for (const Case& c : cases) {
        Row r;
        r.scene =
            sceneOf(meshScene("data:meshes/spot/spot_control_mesh.obj", 0.72f, c.subdivision));
        std::vector<double> loads; // median of 3 (the first also reads the file)
        for (int k = 0; k < 3; ++k) {
            const auto t0 = Clock::now();
            r.assets = loadAssets(r.scene);
            loads.push_back(msSince(t0));
        }
        r.loadMs = median(loads);
        rows.push_back(std::move(r));
    }
    std::vector<GlRenderer> renderers(rows.size());
    const View view = makeView(rows[1].scene, rows[1].assets); // one view for all
    for (size_t i = 0; i < rows.size(); ++i) {
        Row& r = rows[i];
        const MeshAsset& a = r.assets.meshes[0];
        if (a.patches) {
            const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
            r.triangles =
                detail::tessellatePatches(
                    *a.patches, modelToCameraRelative(r.scene.meshes[0].transform, view.cameraPos),
                    focalPx, r.scene.meshes[0].subdivPixelsPerEdge)
                    .mesh.triangleCount();
            r.gpuBytes = patchGpuBytes(*a.patches, false);
        } else {
            r.triangles = a.mesh.triangleCount();
            r.gpuBytes = meshGpuBytes(a.mesh);
        }
        renderers[i].render(r.scene, r.assets, view); // compile, upload
    }
    const int frames = o.quick ? 3 : 7;
    for (int f = 0; f < frames; ++f) {
        for (size_t i = 0; i < rows.size(); ++i) {
            renderers[i].render(rows[i].scene, rows[i].assets, view);
            rows[i].drawMs.push_back(renderers[i].stats().drawWallMs);
        }
    }
    const double base = median(rows[1].drawMs);
    Table t;
    t.title = "Table 11c: static spot cage on the tessellated-asset view, 960x540, median of " +
              std::to_string(frames) + " interleaved frames";
    t.header = {"mesh",    "load (CPU) ms",           "triangles drawn", "GPU buffers KiB",
                "draw ms", "ratio to uniform level 3"};
    for (size_t i = 0; i < rows.size(); ++i) {
        const double ms = median(rows[i].drawMs);
        t.add({cases[i].name, fmt(rows[i].loadMs, 1), std::to_string(rows[i].triangles),
               fmt(double(rows[i].gpuBytes) / 1024.0, 0), fmt(ms, 1), fmtRatio(ms / base)});
    }
    t.notes.push_back("GPU buffers: uniform = positions, normals, UV sets, indices; adaptive = "
                      "control points, indices, patch records (isolation 3); renderer " +
                      o.renderer + ".");
    t.print(o);
}

// ---- 11a: equal screen-space error ---------------------------------------

struct EqualRow {
    std::string asset, coverage, uniformPick, adaptivePick;
    double covered = 0.0; // fraction of the image's pixels
    ScreenError eu, ea;
    size_t triU = 0, triA = 0, gpuU = 0, gpuA = 0, uploadU = 0, uploadA = 0;
    double loadU = 0, loadA = 0, drawU = 0, drawA = 0;
};

// For each view: the coarsest uniform level and the largest pixels_per_edge
// whose drawn triangles are within `targetPx` of the limit (p99 and max),
// then their costs measured in the same run.
void equalErrorAsset(const char* name, const std::filesystem::path& file, int refLevel,
                     int maxUniform, int isolation,
                     const std::vector<std::pair<const char*, float>>& views, float targetPx,
                     int frames, std::vector<EqualRow>& out) {
    const sg::mesh::PolygonMesh cage = sg::mesh::loadPolygonMesh(file);
    sg::mesh::SubdivisionSettings rs;
    rs.level = refLevel;
    rs.options = cage.options;
    rs.limit = true;
    const SurfaceReference ref(sg::mesh::Subdivider(cage, rs, file.string()).renderMesh());
    // Uniform assets per level (view-independent), their load times.
    std::vector<SceneAssets> uni(size_t(maxUniform) + 1);
    std::vector<double> uniLoad(size_t(maxUniform) + 1);
    for (int L = 1; L <= maxUniform; ++L) {
        Scene s = sceneOf(meshScene(file.string(), 1.0f, uniformJson(L)));
        const auto t0 = Clock::now();
        uni[size_t(L)] = loadAssets(s);
        uniLoad[size_t(L)] = msSince(t0);
    }
    Scene sa0 = sceneOf(
        meshScene(file.string(), 1.0f,
                  R"({"mode": "adaptive", "isolation": )" + std::to_string(isolation) + "}"));
    auto t0 = Clock::now();
    SceneAssets adaptive = loadAssets(sa0);
    const double adaptiveLoad = msSince(t0);
    const sg::mesh::AdaptivePatches& ap = *adaptive.meshes[0].patches;
    const float ppes[] = {32, 24, 16, 12, 8, 6, 4, 3, 2, 1.5f, 1};
    for (const auto& [coverage, distanceScale] : views) {
        EqualRow r;
        r.asset = name;
        r.coverage = coverage;
        Scene su = sceneOf(meshScene(file.string(), distanceScale, uniformJson(1)));
        const View view = makeView(su, uni[1]);
        const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
        int level = maxUniform;
        for (int L = 1; L <= maxUniform; ++L) {
            r.eu = screenError(ref, uni[size_t(L)].meshes[0].mesh, view, focalPx);
            level = L;
            if (r.eu.p99 < targetPx && r.eu.max < targetPx) break;
        }
        float ppe = ppes[std::size(ppes) - 1];
        const glm::mat4 rel = modelToCameraRelative(glm::dmat4(1.0), view.cameraPos);
        for (float p : ppes) {
            sg::mesh::RenderMesh t = detail::tessellatePatches(ap, rel, focalPx, p).mesh;
            r.ea = screenError(ref, t, view, focalPx);
            r.triA = t.triangleCount();
            ppe = p;
            if (r.ea.p99 < targetPx && r.ea.max < targetPx) break;
        }
        char buf[96];
        std::snprintf(buf, sizeof buf, "level %d", level);
        r.uniformPick = buf;
        std::snprintf(buf, sizeof buf, "%g px/edge (isolation %d)", double(ppe), isolation);
        r.adaptivePick = buf;
        const SceneAssets& au = uni[size_t(level)];
        const auto& m = au.meshes[0].mesh;
        r.triU = m.triangleCount();
        r.gpuU = meshGpuBytes(m);
        r.gpuA = patchGpuBytes(ap, false);
        r.uploadU = m.vertexCount() * 24;           // animated: positions + normals
        r.uploadA = size_t(ap.cagePointCount) * 12; // animated: the cage
        r.loadU = uniLoad[size_t(level)];
        r.loadA = adaptiveLoad;
        // Frame time, interleaved.
        Scene sa = sceneOf(meshScene(file.string(), distanceScale, adaptiveJson(isolation, ppe)));
        GlRenderer gu, ga;
        Image img = gu.render(su, au,
                              View{view.width, view.height, view.cameraPos, view.viewProjRel,
                                   view.view, view.proj, Aov::Normal});
        size_t covered = 0;
        for (size_t i = 0; i < img.texelCount(); ++i) {
            const glm::vec3 q(img.rgba(i));
            covered += glm::dot(q, q) > 0.25f;
        }
        r.covered = double(covered) / double(img.texelCount());
        ga.renderToTexture(sa, adaptive, view);
        std::vector<double> du, da;
        for (int f = 0; f < frames; ++f) {
            gu.renderToTexture(su, au, view);
            du.push_back(gu.stats().drawWallMs);
            ga.renderToTexture(sa, adaptive, view);
            da.push_back(ga.stats().drawWallMs);
        }
        r.drawU = median(du);
        r.drawA = median(da);
        out.push_back(r);
    }
}

void equalErrorTable(const Options& o) {
    const std::filesystem::path data = dataDir();
    const float target = 0.5f;
    const int frames = o.quick ? 3 : 5;
    std::vector<EqualRow> rows;
    const std::vector<std::pair<const char*, float>> views = {
        {"small", 4.0f}, {"medium", 1.2f}, {"full screen", 0.45f}};
    equalErrorAsset("spot", data / "meshes/spot/spot_control_mesh.obj", o.quick ? 5 : 6, 5, 3,
                    views, target, frames, rows);
    if (!o.quick)
        equalErrorAsset("bob", data / "meshes/bob/bob_tri.obj", 4, 3, 2,
                        {{"small", 4.0f}, {"medium", 1.2f}}, target, 3, rows);
    Table t;
    t.title = "Table 11a: equal screen-space error (p99 and max < " + fmt(target, 1) +
              " px to the limit surface), 960x540, draw: median of " + std::to_string(frames) +
              " interleaved frames (bob: 3)";
    t.header = {"asset, view (coverage)",
                "uniform pick: err p99/max px",
                "adaptive pick: err p99/max px",
                "triangles U / A",
                "GPU MiB U / A",
                "load (CPU) ms U / A",
                "upload per animated frame KiB U / A",
                "draw ms U / A",
                "draw ratio A/U"};
    for (const EqualRow& r : rows) {
        t.add({r.asset + ", " + r.coverage + " (" + fmt(100.0 * r.covered, 0) + "%)",
               r.uniformPick + ": " + fmt(r.eu.p99, 2) + "/" + fmt(r.eu.max, 2),
               r.adaptivePick + ": " + fmt(r.ea.p99, 2) + "/" + fmt(r.ea.max, 2),
               std::to_string(r.triU) + " / " + std::to_string(r.triA),
               fmt(double(r.gpuU) / 1048576.0, 2) + " / " + fmt(double(r.gpuA) / 1048576.0, 2),
               fmt(r.loadU, 0) + " / " + fmt(r.loadA, 0),
               fmt(double(r.uploadU) / 1024.0, 1) + " / " + fmt(double(r.uploadA) / 1024.0, 1),
               fmt(r.drawU, 1) + " / " + fmt(r.drawA, 1), fmtRatio(r.drawA / r.drawU)});
    }
    t.notes.push_back(
        "U: uniform (limit), A: adaptive. Errors: distance to OpenSubdiv's dense limit mesh "
        "(spot level " +
        std::to_string(o.quick ? 5 : 6) +
        ", bob level 4) in pixels. GPU MiB: uniform positions, normals, UV sets, indices; "
        "adaptive control points, indices, patch records (the animated path's stencil rows: "
        "table 11b). Upload: computed (refined positions + normals vs the cage). Draw ratio in "
        "the same run; renderer " +
        o.renderer + ".");
    t.print(o);
}

// ---- 11d: displacement's cost --------------------------------------------

// Uncovered pixels whose four neighbours are covered (a normal AOV image:
// background 0).
size_t pinholes(const Image& img) {
    auto covered = [&](int x, int y) {
        return glm::length(glm::vec3(img.rgba(size_t(y) * size_t(img.width) + size_t(x)))) > 0.5f;
    };
    size_t holes = 0;
    for (int y = 1; y + 1 < img.height; ++y)
        for (int x = 1; x + 1 < img.width; ++x)
            holes += !covered(x, y) && covered(x - 1, y) && covered(x + 1, y) &&
                     covered(x, y - 1) && covered(x, y + 1);
    return holes;
}

void displacementTable(const Options& o) {
    const std::string spot = "data:meshes/spot/spot_control_mesh.obj";
    const std::string height =
        (std::filesystem::path(SURFGRAD_EXAMPLE_DATA_DIR) / "spot_height.png").string();
    const std::string dispJson =
        R"(, "displacement": {"map": ")" + height + R"(", "scale": 0.012, "uv_set": 0})";
    const std::vector<float> ppes = o.quick ? std::vector<float>{4} : std::vector<float>{8, 4, 2};
    const float refPpe = o.quick ? 1.0f : 0.5f; // the dense displaced reference
    const int frames = o.quick ? 3 : 7;
    struct Variant {
        float ppe = 0.0f;
        bool displaced = false;
        Scene scene;
        SceneAssets assets;
        size_t triangles = 0, holes = 0;
        double tessMs = 0.0;
        ScreenError err;
        std::vector<double> drawMs;
    };
    std::vector<Variant> vs;
    for (float p : ppes)
        for (bool d : {false, true}) {
            Variant v;
            v.ppe = p;
            v.displaced = d;
            v.scene = sceneOf(meshScene(spot, 0.72f, adaptiveJson(3, p), d ? dispJson : ""));
            v.assets = loadAssets(v.scene);
            vs.push_back(std::move(v));
        }
    const View view = makeView(vs[0].scene, vs[0].assets);
    const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
    // Accuracy: distance of the displaced triangles to the displaced surface
    // tessellated densely (refPpe px per segment, the map read near level 0).
    const SurfaceReference ref(displacedMesh(vs[1].scene, vs[1].assets, view, refPpe));
    std::vector<GlRenderer> gl(vs.size());
    for (size_t i = 0; i < vs.size(); ++i) {
        Variant& v = vs[i];
        std::vector<double> tess;
        for (int k = 0; k < (o.quick ? 1 : 3); ++k) {
            double ms = 0.0;
            const sg::mesh::RenderMesh m = displacedMesh(v.scene, v.assets, view, v.ppe, &ms);
            tess.push_back(ms);
            if (k == 0) {
                v.triangles = m.triangleCount();
                v.err = screenError(ref, m, view, focalPx);
            }
        }
        v.tessMs = median(tess);
        View nv = view;
        nv.aov = Aov::Normal;
        v.holes = pinholes(gl[i].render(v.scene, v.assets, nv)); // also compiles, uploads
        gl[i].renderToTexture(v.scene, v.assets, view);
    }
    for (int f = 0; f < frames; ++f)
        for (size_t i = 0; i < vs.size(); ++i) {
            gl[i].renderToTexture(vs[i].scene, vs[i].assets, view);
            vs[i].drawMs.push_back(gl[i].stats().drawWallMs);
        }
    Table t;
    t.title =
        "Table 11d: displacement's cost, spot adaptive (isolation 3) on the tessellated-asset "
        "view, 960x540, spot_height.png x 0.012; draw: median of " +
        std::to_string(frames) + " interleaved frames";
    t.header = {"px/edge", "displacement",      "triangles",      "CPU tessellator ms",
                "draw ms", "draw ratio to off", "pinholes (GPU)", "err to displaced p99/max px"};
    for (size_t i = 0; i < vs.size(); ++i) {
        const Variant& v = vs[i];
        const Variant& off = vs[i & ~size_t(1)];
        t.add({fmt(v.ppe, 0), v.displaced ? "on" : "off", std::to_string(v.triangles),
               fmt(v.tessMs, 1), fmt(median(v.drawMs), 1),
               fmtRatio(median(v.drawMs) / median(off.drawMs)), std::to_string(v.holes),
               fmt(v.err.p99, 2) + "/" + fmt(v.err.max, 2)});
    }
    t.notes.push_back(
        "CPU tessellator: detail::tessellatePatches, the CPU reference renderer's tessellation "
        "(median of " +
        std::to_string(o.quick ? 1 : 3) +
        "). Pinholes: uncovered pixels with four covered neighbours in the GPU's normal AOV. "
        "err: screen-space distance of the drawn triangles (centroids, edge midpoints) to the "
        "displaced surface tessellated at " +
        fmt(refPpe, 1) +
        " px/edge (nearest vertex's tangent plane; off: how far the displacement moves the "
        "surface); it includes the height detail a coarser tessellation reads from a coarser mip "
        "level. Ratio to off at the same px/edge, same run; "
        "renderer " +
        o.renderer + ".");
    t.print(o);
}

// ---- 11e: tangent frame source -------------------------------------------

void frameSourceTable(const Options& o) {
    const std::string spot = "data:meshes/spot/spot_control_mesh.obj";
    const std::string layer =
        R"({"type": "uv_normal", "uv_set": 0, "map": {"procedural": "bricks", "size": 256}, )"
        R"("strength": 1.0})";
    const std::vector<float> ppes = o.quick ? std::vector<float>{4} : std::vector<float>{8, 4, 2};
    const float refPpe = 1.0f;
    const int frames = o.quick ? 3 : 7;
    auto sceneFor = [&](float ppe, const char* tangents) {
        const std::string mesh = R"({"file": ")" + spot +
                                 R"(", "material": "bumped", "subdivision": )" +
                                 adaptiveJson(3, ppe) + R"(, "tangents": [")" + tangents + R"("]})";
        return sceneOf(
            R"({"output": {"width": 960, "height": 540}, "camera": {"azimuth_deg": 105, )"
            R"("elevation_deg": 14, "distance_scale": 0.72, "fov_deg": 32}, "materials": [)"
            R"({"name": "bumped", "layers": [)" +
            layer + "]}], \"meshes\": [" + mesh + "]}");
    };
    struct Variant {
        float ppe = 0.0f;
        const char* source = "";
        Scene scene;
        SceneAssets assets;
        DirectionDiff tangent, normal;
        std::vector<double> drawMs;
    };
    std::vector<Variant> vs;
    for (float p : ppes)
        for (const char* src : {"pixel", "limit"}) {
            Variant v;
            v.ppe = p;
            v.source = src;
            v.scene = sceneFor(p, src);
            v.assets = loadAssets(v.scene);
            vs.push_back(std::move(v));
        }
    Scene refScene = sceneFor(refPpe, "limit");
    SceneAssets refAssets = loadAssets(refScene);
    const View view = makeView(refScene, refAssets);
    auto aovView = [&](Aov aov) {
        View v = view;
        v.aov = aov;
        return v;
    };
    GlRenderer refGl;
    const Image refT = refGl.render(refScene, refAssets, aovView(Aov::Tangent));
    const Image refN = refGl.render(refScene, refAssets, aovView(Aov::Normal));
    const Image refBase = refGl.render(refScene, refAssets, aovView(Aov::BaseNormal));
    std::vector<GlRenderer> gl(vs.size());
    for (size_t i = 0; i < vs.size(); ++i) {
        Variant& v = vs[i];
        const Image base = gl[i].render(v.scene, v.assets, aovView(Aov::BaseNormal));
        v.tangent = compareDirections(gl[i].render(v.scene, v.assets, aovView(Aov::Tangent)), refT,
                                      base, refBase);
        v.normal = compareDirections(gl[i].render(v.scene, v.assets, aovView(Aov::Normal)), refN,
                                     base, refBase);
        gl[i].renderToTexture(v.scene, v.assets, view); // the timed program
    }
    for (int f = 0; f < frames; ++f)
        for (size_t i = 0; i < vs.size(); ++i) {
            gl[i].renderToTexture(vs[i].scene, vs[i].assets, view);
            vs[i].drawMs.push_back(gl[i].stats().drawWallMs);
        }
    Table t;
    t.title = "Table 11e: tangent frame source on adaptive patches, spot (isolation 3) with a "
              "bricks normal map on the tessellated-asset view, 960x540; ground truth: limit "
              "frame at " +
              fmt(refPpe, 0) + " px/edge; draw: median of " + std::to_string(frames) +
              " interleaved frames";
    t.header = {"px/edge",
                "frame",
                "tangent err p50 deg",
                "tangent err p99 deg",
                "shaded normal err p50 deg",
                "shaded normal err p99 deg",
                "pixels compared / other sheet",
                "draw ms",
                "draw ratio to per-pixel"};
    for (size_t i = 0; i < vs.size(); ++i) {
        const Variant& v = vs[i];
        if (v.tangent.nonFinite + v.normal.nonFinite)
            throw std::runtime_error("table adaptive: non-finite frame in the " +
                                     std::string(v.source) + " variant");
        const double ms = median(v.drawMs);
        const ErrorStats te = errorStats(v.tangent.deg), ne = errorStats(v.normal.deg);
        t.add({fmt(v.ppe, 0), std::string(v.source) == "pixel" ? "per-pixel" : "limit",
               fmtErr(te.p50), fmtErr(te.p99), fmtErr(ne.p50), fmtErr(ne.p99),
               std::to_string(ne.count) + " / " + std::to_string(v.normal.otherSheet), fmt(ms, 1),
               fmtRatio(ms / median(vs[i & ~size_t(1)].drawMs))});
    }
    t.notes.push_back(
        "Errors: angle to the ground truth's tangent AOV (vT of set 0) and shaded normal at "
        "pixels where both images see the same sheet of the surface (both covered, base "
        "normals within " +
        fmt(kSameSheetDeg, 0) +
        " deg); the tessellations differ, so each pixel's surface point differs by the chord "
        "error (table 11a); pixels where an occlusion edge moved are counted (other sheet), "
        "not compared. Ratio to the "
        "per-pixel frame at the same px/edge, same run; renderer " +
        o.renderer + ".");
    t.plot.id = "adaptive-frames";
    t.plot.xColumn = 7;
    t.plot.yColumn = 5;
    t.plot.seriesColumn = 1;
    t.plot.labelColumns = {0};
    t.plot.xLabel = "draw ms (llvmpipe, 960x540)";
    t.plot.yLabel = "shaded normal error p99 (deg)";
    t.print(o);
}

} // namespace

void tableAdaptive(const Options& o) {
    equalErrorTable(o);
    animatedTable(o);
    staticTable(o);
    displacementTable(o);
    frameSourceTable(o);
}

} // namespace study
