// Adaptive patches (GPU tessellation) against the uniform CPU path on the
// spot cage, through the renderer at 960x540 on the example's view: load
// (CPU) time, triangles drawn, GPU buffer bytes, draw wall time (median of
// interleaved frames) and its ratio to uniform level 3 measured in the same
// run. On llvmpipe the tessellation stages run on the CPU: only the ratios
// mean anything. Not measured here: the screen-space distance to the exact
// limit surface (the adaptive levels target pixels_per_edge pixels per
// segment; the uniform levels do not follow the screen).
//
// Second table, animated cages: every frame the cage moves (a wave of a few
// percent of its size); adaptive = setCagePositions, upload of the cage and
// the stencils' compute stage (sg/patch/stencils.comp.glsl); uniform = CPU
// refinement of the moved cage (Subdivider::update: positions, limit
// normals) and upload of the refined positions and normals. Per-frame upload
// bytes (RenderStats::meshUploadBytes), CPU time, upload + compute wall
// time, draw wall time, the frame's total and its ratio to uniform on the
// same cage, measured in the same run: spot's cage, bob (a triangle cage)
// and a 128k-quad cage (bob refined twice on the CPU, written to a scratch
// OBJ).
//
// Third table, equal screen-space error: per view of an asset (small,
// medium, full screen), the coarsest uniform level (limit) and the largest
// pixels_per_edge whose triangles lie within 0.5 px of the limit surface
// (p99 and max over centroids and edge midpoints; the limit from a dense
// OpenSubdiv limit mesh), and their triangles, GPU buffers, load CPU time,
// per-frame upload of an animated cage and draw time, same run.
//
// Usage: adaptive_bench [--quick] [--only static|animated|equal]
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
#include "surfgrad/adaptive_patches.h"
#include "surfgrad/gl.h"
#include "surfgrad/mesh_io.h"
#include "surfgrad/patch_basis.h"
#include "surfgrad/render.h"
#include "surfgrad/subdivision.h"

namespace {

using namespace sg::render;

struct Case {
    const char* name;
    std::string subdivision;
};

std::string scene(const std::string& subdivision) {
    return R"({"output": {"width": 960, "height": 540},
      "camera": {"azimuth_deg": 105, "elevation_deg": 14, "distance_scale": 0.72, "fov_deg": 32},
      "materials": [{"name": "m"}],
      "meshes": [{"file": "data:meshes/spot/spot_control_mesh.obj", "subdivision": )" +
           subdivision + "}]}";
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::filesystem::path dataDir() {
    const char* env = std::getenv("SURFGRAD_DATA_DIR");
    return env && *env ? std::filesystem::path(env) : dataDirectory();
}

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

std::string animScene(const std::filesystem::path& file, const std::string& subdivision) {
    return R"({"output": {"width": 960, "height": 540},
      "camera": {"azimuth_deg": 105, "elevation_deg": 14, "distance_scale": 0.72, "fov_deg": 32},
      "materials": [{"name": "m"}],
      "meshes": [{"file": ")" +
           file.string() + R"(", "subdivision": )" + subdivision + "}]}";
}

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
    char adaptiveJson[160], uniformJson[96];
    std::snprintf(adaptiveJson, sizeof adaptiveJson,
                  R"({"mode": "adaptive", "isolation": %d, "pixels_per_edge": %g})", isolation,
                  double(pixelsPerEdge));
    std::snprintf(uniformJson, sizeof uniformJson, R"({"level": %d, "limit": true})", uniformLevel);
    Scene sa = parseScene(animScene(c.file, adaptiveJson), "adaptive_bench.json", ".");
    Scene su = parseScene(animScene(c.file, uniformJson), "adaptive_bench.json", ".");
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
    if (moving.vertexCount() != au.meshes[0].mesh.vertexCount()) {
        std::fprintf(stderr, "adaptive_bench: uniform vertex layouts differ\n");
        std::exit(1);
    }
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
    {
        const auto& m = au.meshes[0].mesh; // positions, normals, UV sets, 32-bit indices
        U.gpuBytes = m.vertexCount() * (24 + 8 * m.uvSets.size()) + m.indices.size() * 4;
        const auto& p = *aa.meshes[0].patches; // points, indices, records, cage, stencil rows
        A.gpuBytes = p.points.size() * 12 + p.indices.size() * 4 + p.patchCount() * 112 +
                     size_t(p.cagePointCount) * 12 + p.stencilOffsets.size() * 4 +
                     p.stencilIndices.size() * 4 + p.stencilWeights.size() * 4;
    }
    std::vector<glm::vec3> moved;
    for (int f = 1; f <= frames; ++f) {
        waveCage(cage.positions, extent, f, moved);
        { // adaptive: the cage to the renderer, the GPU does the rest
            auto t0 = Clock::now();
            setCagePositions(sa, aa, 0, moved);
            A.cpuMs.push_back(msSince(t0));
            t0 = Clock::now();
            ra.renderToTexture(sa, aa, view);
            A.frameMs.push_back(A.cpuMs.back() + msSince(t0));
            A.updateMs.push_back(ra.stats().meshUpdateWallMs);
            A.drawMs.push_back(ra.stats().drawWallMs);
            A.uploadBytes = ra.stats().meshUploadBytes;
        }
        { // uniform: refine the moved cage on the CPU, upload the mesh
            auto t0 = Clock::now();
            sub.update(moved, moving, &frame);
            MeshAsset& m = au.meshes[0];
            std::memcpy(m.mesh.positions.data(), moving.positions.data(),
                        moving.positions.size() * sizeof(glm::vec3));
            std::memcpy(m.mesh.normals.data(), moving.normals.data(),
                        moving.normals.size() * sizeof(glm::vec3));
            ++au.meshVersion;
            U.cpuMs.push_back(msSince(t0));
            t0 = Clock::now();
            ru.renderToTexture(su, au, view);
            U.frameMs.push_back(U.cpuMs.back() + msSince(t0));
            U.updateMs.push_back(ru.stats().meshUpdateWallMs);
            U.drawMs.push_back(ru.stats().drawWallMs);
            U.uploadBytes = ru.stats().meshUploadBytes;
        }
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

void animatedTable(bool quick) {
    const std::filesystem::path data = dataDir();
    const std::filesystem::path scratch =
        std::filesystem::temp_directory_path() / ("adaptive_bench_" + std::to_string(getpid()));
    std::filesystem::create_directories(scratch);
    // The 128k-quad cage: bob refined twice (no limit), written as OBJ.
    {
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
    }
    const int frames = quick ? 3 : 7;
    std::vector<AnimRow> rows;
    // The larger cages cost seconds per adaptive frame on llvmpipe: fewer
    // frames, isolation 2 (a triangle cage has an extraordinary vertex at
    // every face centre of its first refinement).
    const int heavyFrames = quick ? 2 : 3;
    animatedCage({"spot", data / "meshes/spot/spot_control_mesh.obj"}, 3, 4.0f, 3, frames, rows);
    animatedCage({"bob", data / "meshes/bob/bob_tri.obj"}, 2, 4.0f, 2, heavyFrames, rows);
    animatedCage({"bob refined twice", scratch / "bob_l2.obj"}, 1, 4.0f, 2, heavyFrames, rows);
    std::filesystem::remove_all(scratch);
    std::printf("\nAnimated cages, 960x540, llvmpipe, median of %d frames (bob: %d; each frame a "
                "new cage; adaptive and uniform interleaved)\n\n",
                frames, heavyFrames);
    std::printf("| cage (faces, vertices) | mode | triangles drawn | GPU buffers MiB | upload per "
                "frame | CPU ms | upload+compute ms | draw ms | frame ms | ratio to uniform |\n"
                "|---|---|---|---|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < rows.size(); i += 2) {
        const double base = median(rows[i + 1].frameMs);
        for (size_t k = i; k < i + 2; ++k) {
            const AnimRow& r = rows[k];
            const double kib = double(r.uploadBytes) / 1024.0;
            std::printf("| %s (%zu, %zu) | %s | %zu | %.1f | %.1f KiB | %.2f | %.2f | %.1f | "
                        "%.1f | %.2fx |\n",
                        r.cage.c_str(), r.cageFaces, r.cageVerts, r.mode.c_str(), r.triangles,
                        double(r.gpuBytes) / 1048576.0, kib, median(r.cpuMs), median(r.updateMs),
                        median(r.drawMs), median(r.frameMs), median(r.frameMs) / base);
        }
    }
}

void staticTable();

// ---- Equal screen-space error ------------------------------------------

// The exact limit surface, sampled densely: a uniform limit mesh of a high
// level (OpenSubdiv's limit points and limit normals at its vertices), in a
// hash grid. The distance of a point p to the surface is taken as
// |(p - v) . n| for the nearest reference vertex v (normal n): the
// surface departs from that tangent plane by about r^2 k / 2 over the
// lateral offset r <= the reference's vertex spacing, far below the
// errors measured (the reference's spacing is < 1 px on every view).
struct LimitReference {
    std::vector<glm::vec3> pos, nrm;
    float cell = 1.0f;
    std::vector<std::pair<uint64_t, uint32_t>> grid; // (cell key, vertex), sorted

    static uint64_t key(glm::ivec3 c) {
        return (uint64_t(uint32_t(c.x) & 0x1FFFFFu) << 42) |
               (uint64_t(uint32_t(c.y) & 0x1FFFFFu) << 21) | uint64_t(uint32_t(c.z) & 0x1FFFFFu);
    }
    glm::ivec3 cellOf(glm::vec3 p) const { return glm::ivec3(glm::floor(p / cell)); }

    LimitReference(const sg::mesh::RenderMesh& m) : pos(m.positions), nrm(m.normals) {
        double edge = 0.0;
        for (size_t t = 0; t < m.indices.size(); t += 3)
            edge += glm::length(pos[m.indices[t]] - pos[m.indices[t + 1]]);
        cell = float(2.0 * edge / double(std::max<size_t>(m.indices.size() / 3, 1)));
        grid.reserve(pos.size());
        for (uint32_t v = 0; v < pos.size(); ++v) grid.push_back({key(cellOf(pos[v])), v});
        std::sort(grid.begin(), grid.end());
    }
    // Distance to the surface (object space); -1 when no vertex is near.
    float distance(glm::vec3 p) const {
        const glm::ivec3 c = cellOf(p);
        float best = INFINITY;
        uint32_t bestV = 0;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const uint64_t k = key(c + glm::ivec3(dx, dy, dz));
                    auto it = std::lower_bound(grid.begin(), grid.end(),
                                               std::pair<uint64_t, uint32_t>(k, 0));
                    for (; it != grid.end() && it->first == k; ++it) {
                        const glm::vec3 d = p - pos[it->second];
                        const float d2 = glm::dot(d, d);
                        if (d2 < best) {
                            best = d2;
                            bestV = it->second;
                        }
                    }
                }
        if (!std::isfinite(best)) return -1.0f;
        return std::fabs(glm::dot(p - pos[bestV], nrm[bestV]));
    }
};

struct ErrorStats {
    double p99 = 0.0, max = 0.0;
    size_t samples = 0, missed = 0;
};

// Screen-space distance (pixels) of the drawn triangles to the limit
// surface, sampled at every triangle's centroid and edge midpoints that lie
// in the view frustum: object distance x focal length in pixels / depth.
ErrorStats screenError(const LimitReference& ref, const sg::mesh::RenderMesh& m, const View& v,
                       float focalPx, size_t maxTriangles = 400000) {
    std::vector<double> px;
    const size_t tris = m.indices.size() / 3;
    const size_t stride = std::max<size_t>(1, tris / maxTriangles);
    ErrorStats e;
    const glm::mat4 vp = v.proj * v.view;
    for (size_t t = 0; t < tris; t += stride) {
        const glm::vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                        c = m.positions[m.indices[3 * t + 2]];
        for (const glm::vec3 p :
             {(a + b + c) / 3.0f, 0.5f * (a + b), 0.5f * (b + c), 0.5f * (c + a)}) {
            const glm::vec4 clip = vp * glm::vec4(p, 1.0f);
            if (!(clip.w > 0.0f) || std::fabs(clip.x) > clip.w || std::fabs(clip.y) > clip.w)
                continue;
            const float d = ref.distance(p);
            if (d < 0.0f) {
                ++e.missed;
                continue;
            }
            const float depth = -(v.view * glm::vec4(p, 1.0f)).z;
            px.push_back(double(d) * double(focalPx) / double(depth));
        }
    }
    e.samples = px.size();
    if (px.empty()) return e;
    std::sort(px.begin(), px.end());
    e.max = px.back();
    e.p99 = px[std::min(px.size() - 1, size_t(0.99 * double(px.size())))];
    return e;
}

std::string coverageScene(const std::filesystem::path& file, float distanceScale,
                          const std::string& subdivision) {
    char cam[160];
    std::snprintf(
        cam, sizeof cam,
        R"("camera": {"azimuth_deg": 105, "elevation_deg": 14, "distance_scale": %g, "fov_deg": 32})",
        double(distanceScale));
    return R"({"output": {"width": 960, "height": 540}, )" + std::string(cam) +
           R"(, "materials": [{"name": "m"}], "meshes": [{"file": ")" + file.string() +
           R"(", "subdivision": )" + subdivision + "}]}";
}

struct EqualRow {
    std::string asset, coverage, uniformPick, adaptivePick;
    double covered = 0.0; // fraction of the image's pixels
    ErrorStats eu, ea;
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
    const LimitReference ref(sg::mesh::Subdivider(cage, rs, file.string()).renderMesh());
    // Uniform assets per level (view-independent), their load times.
    std::vector<SceneAssets> uni(size_t(maxUniform) + 1);
    std::vector<double> uniLoad(size_t(maxUniform) + 1);
    for (int L = 1; L <= maxUniform; ++L) {
        Scene s = parseScene(
            coverageScene(file, 1.0f, "{\"level\": " + std::to_string(L) + ", \"limit\": true}"),
            "adaptive_bench.json", ".");
        const auto t0 = Clock::now();
        uni[size_t(L)] = loadAssets(s);
        uniLoad[size_t(L)] = msSince(t0);
    }
    const std::string iso = std::to_string(isolation);
    Scene sa0 =
        parseScene(coverageScene(file, 1.0f, R"({"mode": "adaptive", "isolation": )" + iso + "}"),
                   "adaptive_bench.json", ".");
    auto t0 = Clock::now();
    SceneAssets adaptive = loadAssets(sa0);
    const double adaptiveLoad = msSince(t0);
    const sg::mesh::AdaptivePatches& ap = *adaptive.meshes[0].patches;
    const float ppes[] = {32, 24, 16, 12, 8, 6, 4, 3, 2, 1.5f, 1};
    for (const auto& [coverage, distanceScale] : views) {
        EqualRow r;
        r.asset = name;
        r.coverage = coverage;
        Scene su = parseScene(coverageScene(file, distanceScale, R"({"level": 1, "limit": true})"),
                              "adaptive_bench.json", ".");
        const View view = makeView(su, uni[1]);
        const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
        int level = maxUniform;
        for (int L = 1; L <= maxUniform; ++L) {
            r.eu = screenError(ref, uni[size_t(L)].meshes[0].mesh, view, focalPx);
            level = L;
            if (r.eu.p99 < targetPx && r.eu.max < targetPx) break;
        }
        float ppe = ppes[std::size(ppes) - 1];
        const glm::mat4 rel = modelToCameraRelative(glm::mat4(1.0f), view.cameraPos);
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
        r.gpuU = m.vertexCount() * (24 + 8 * m.uvSets.size()) + m.indices.size() * 4;
        r.gpuA = ap.points.size() * 12 + ap.indices.size() * 4 + ap.patchCount() * 64;
        r.uploadU = m.vertexCount() * 24;           // animated: positions + normals
        r.uploadA = size_t(ap.cagePointCount) * 12; // animated: the cage
        r.loadU = uniLoad[size_t(level)];
        r.loadA = adaptiveLoad;
        // Frame time, interleaved.
        char sub[96];
        std::snprintf(sub, sizeof sub,
                      R"({"mode": "adaptive", "isolation": %d, "pixels_per_edge": %g})", isolation,
                      double(ppe));
        Scene sa = parseScene(coverageScene(file, distanceScale, sub), "adaptive_bench.json", ".");
        GlRenderer gu, ga;
        Image img = gu.render(su, au,
                              View{view.width, view.height, view.cameraPos, view.viewProjRel,
                                   view.view, view.proj, Aov::Normal});
        size_t covered = 0;
        for (const glm::vec4& q : img.pixels)
            covered += glm::dot(glm::vec3(q), glm::vec3(q)) > 0.25f;
        r.covered = double(covered) / double(img.pixels.size());
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

void equalErrorTable(bool quick) {
    const std::filesystem::path data = dataDir();
    const float target = 0.5f;
    std::vector<EqualRow> rows;
    const std::vector<std::pair<const char*, float>> views = {
        {"small", 4.0f}, {"medium", 1.2f}, {"full screen", 0.45f}};
    equalErrorAsset("spot", data / "meshes/spot/spot_control_mesh.obj", quick ? 5 : 6, 5, 3, views,
                    target, quick ? 3 : 5, rows);
    if (!quick)
        equalErrorAsset("bob", data / "meshes/bob/bob_tri.obj", 4, 3, 2,
                        {{"small", 4.0f}, {"medium", 1.2f}}, target, 3, rows);
    std::printf("\nEqual screen-space error (p99 and max < %.1f px to the limit surface), 960x540, "
                "llvmpipe, draw: median of %d interleaved frames\n\n",
                double(target), quick ? 3 : 5);
    std::printf("| asset, view (coverage) | uniform pick: err p99/max px | adaptive pick: err "
                "p99/max px | triangles U / A | GPU MiB U / A | load (CPU) ms U / A | upload per "
                "animated frame KiB U / A | draw ms U / A | draw ratio A/U |\n"
                "|---|---|---|---|---|---|---|---|---|\n");
    for (const EqualRow& r : rows) {
        std::printf("| %s, %s (%.0f%%) | %s: %.2f/%.2f | %s: %.2f/%.2f | %zu / %zu | %.2f / %.2f | "
                    "%.0f / %.0f | %.1f / %.1f | %.1f / %.1f | %.2fx |\n",
                    r.asset.c_str(), r.coverage.c_str(), 100.0 * r.covered, r.uniformPick.c_str(),
                    r.eu.p99, r.eu.max, r.adaptivePick.c_str(), r.ea.p99, r.ea.max, r.triU, r.triA,
                    double(r.gpuU) / 1048576.0, double(r.gpuA) / 1048576.0, r.loadU, r.loadA,
                    double(r.uploadU) / 1024.0, double(r.uploadA) / 1024.0, r.drawU, r.drawA,
                    r.drawA / r.drawU);
    }
}

} // namespace

int main(int argc, char** argv) {
    bool quick = false;
    std::string only;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--quick")) {
            quick = true;
        } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
            only = argv[++i];
        } else {
            std::fprintf(stderr,
                         "usage: adaptive_bench [--quick] [--only static|animated|equal]\n");
            return 1;
        }
    }
    sg::gl::HeadlessContext ctx;
    if (only.empty() || only == "static") staticTable();
    if (only.empty() || only == "animated") animatedTable(quick);
    if (only.empty() || only == "equal") equalErrorTable(quick);
    return 0;
}

namespace {

void staticTable() {
    const std::vector<Case> cases = {
        {"uniform level 2 (limit)", R"({"level": 2, "limit": true})"},
        {"uniform level 3 (limit)", R"({"level": 3, "limit": true})"},
        {"uniform level 4 (limit)", R"({"level": 4, "limit": true})"},
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
        r.scene = parseScene(scene(c.subdivision), "adaptive_bench.json", ".");
        std::vector<double> loads; // median of 3 (the first also reads the file)
        for (int k = 0; k < 3; ++k) {
            const auto t0 = std::chrono::steady_clock::now();
            r.assets = loadAssets(r.scene);
            loads.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count());
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
            const auto& ap = *a.patches;
            const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
            r.triangles =
                detail::tessellatePatches(
                    ap, modelToCameraRelative(r.scene.meshes[0].transform, view.cameraPos), focalPx,
                    r.scene.meshes[0].subdivPixelsPerEdge)
                    .mesh.triangleCount();
            // Points (xyz), control-point indices, 28-word patch records.
            r.gpuBytes = ap.points.size() * 12 + ap.indices.size() * 4 + ap.patchCount() * 112;
        } else {
            r.triangles = a.mesh.triangleCount();
            // Positions, normals, UV sets, 32-bit indices.
            r.gpuBytes =
                a.mesh.vertexCount() * (24 + 8 * a.mesh.uvSets.size()) + a.mesh.indices.size() * 4;
        }
        renderers[i].render(r.scene, r.assets, view); // compile, upload
    }
    const int frames = 7;
    for (int f = 0; f < frames; ++f) {
        for (size_t i = 0; i < rows.size(); ++i) {
            renderers[i].render(rows[i].scene, rows[i].assets, view);
            rows[i].drawMs.push_back(renderers[i].stats().drawWallMs);
        }
    }
    const double base = median(rows[1].drawMs);
    std::printf("Adaptive patches vs uniform refinement, spot cage, 960x540, llvmpipe, median of "
                "%d interleaved frames\n\n",
                frames);
    std::printf("| mesh | load (CPU) ms | triangles drawn | GPU buffer KiB | draw ms | ratio to "
                "uniform level 3 |\n|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < rows.size(); ++i) {
        const double ms = median(rows[i].drawMs);
        std::printf("| %s | %.1f | %zu | %.0f | %.1f | %.2fx |\n", cases[i].name, rows[i].loadMs,
                    rows[i].triangles, double(rows[i].gpuBytes) / 1024.0, ms, ms / base);
    }
}

} // namespace
