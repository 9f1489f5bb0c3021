// Table 2, subdivision level (docs/accuracy-cost.md). Two inputs:
//
//  a) The B-spline torus (torus.h), whose Catmull-Clark limit surface is
//     known in closed form. For levels 0..5, uniformly refined points
//     ("refined") and the same topology with vertices moved to the limit
//     surface ("+limit": limit positions and normals from the mesh module's
//     limit evaluation). Error of the rendered triangle mesh against the
//     limit surface, sampled at every vertex and at the 3 edge midpoints and
//     the centroid of every triangle (the UV of a sample names its limit
//     point, torus.h): the deviation along the true normal
//     |(p - S(uv)) . n| (the geometric error a silhouette or a shadow sees)
//     and the angle of the interpolated vertex normal to the true normal
//     (the shading error).
//  b) Spot's control cage (quads, pentagons, triangles: extraordinary
//     vertices, where OpenSubdiv's limit is the reference): the distance of
//     each refined vertex from its limit position and the angle of the
//     refined mesh's area-weighted normal to the limit normal there
//     (vertices only: spot's limit surface has no closed form).
//
// Cost: the mesh module's Subdivider::build (uniform refinement of
// positions and UVs, triangulation, vertex split, normals; +limit also the
// limit evaluation), median of several builds reusing one Subdivider with
// reuseTopology off (a fresh refinement each time, buffers reused as the
// module recommends); and the llvmpipe frame time of a plain Lambert pass of
// the mesh, ratio to level 0 of the same input.
#include <epoxy/gl.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"
#include "tables.h"
#include "torus.h"

namespace study {

namespace {

const char* kVertex = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
uniform mat4 uViewProj;
out vec3 vNormal;
void main() {
    vNormal = aNormal;
    gl_Position = uViewProj * vec4(aPos, 1.0);
}
)";

const char* kFragment = R"(
in vec3 vNormal;
layout(location = 0) out vec4 oColor;
void main() {
    float l = max(dot(normalize(vNormal), normalize(vec3(0.3, -0.5, 0.8))), 0.0);
    oColor = vec4(vec3(0.05 + 0.9 * l), 1.0);
}
)";

double buildMs(sg::mesh::Subdivider& sub, const sg::mesh::PolygonMesh& cage,
               sg::mesh::SubdivisionSettings settings, int runs) {
    using Clock = std::chrono::steady_clock;
    settings.reuseTopology = false;
    sub.build(cage, settings); // warm-up: first-touch page faults
    std::vector<double> t;
    for (int r = 0; r < runs; ++r) {
        const auto t0 = Clock::now();
        sub.build(cage, settings);
        t.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
    return median(t);
}

struct TorusErrors {
    double maxDev = 0, rmsDev = 0;
    ErrorStats normal;
};

// Samples of the torus' rendered mesh against the exact limit surface.
TorusErrors torusErrors(const TorusCage& cage, const sg::mesh::RenderMesh& mesh) {
    double sumSq = 0;
    size_t count = 0;
    TorusErrors e;
    std::vector<double> normalErr;
    auto sample = [&](const glm::dvec3& p, const glm::dvec3& n, const glm::dvec2& uv) {
        const SurfacePoint s = cage.limit(uv.x, uv.y);
        const double dev = std::fabs(glm::dot(p - s.pos, s.normal));
        e.maxDev = std::max(e.maxDev, dev);
        sumSq += dev * dev;
        ++count;
        normalErr.push_back(angleDeg(n, s.normal));
    };
    const auto& uv = mesh.uvSets[0];
    for (size_t v = 0; v < mesh.vertexCount(); ++v) {
        sample(glm::dvec3(mesh.positions[v]), glm::dvec3(mesh.normals[v]), glm::dvec2(uv[v]));
    }
    const double bary[4][3] = {
        {0.5, 0.5, 0.0}, {0.0, 0.5, 0.5}, {0.5, 0.0, 0.5}, {1.0 / 3, 1.0 / 3, 1.0 / 3}};
    for (size_t tri = 0; tri < mesh.triangleCount(); ++tri) {
        const uint32_t* ix = &mesh.indices[tri * 3];
        for (const auto& b : bary) {
            glm::dvec3 p(0.0), n(0.0);
            glm::dvec2 st(0.0);
            for (int k = 0; k < 3; ++k) {
                p += b[k] * glm::dvec3(mesh.positions[ix[k]]);
                n += b[k] * glm::dvec3(mesh.normals[ix[k]]);
                st += b[k] * glm::dvec2(uv[ix[k]]);
            }
            sample(p, n, st);
        }
    }
    e.rmsDev = std::sqrt(sumSq / double(count));
    e.normal = errorStats(normalErr);
    return e;
}

} // namespace

void tableSubdivision(const Options& o) {
    const int maxLevel = o.quick ? 2 : 5;
    const int buildRuns = o.quick ? 1 : 5;
    sg::gl::Program program = makeProgram(kVertex, kFragment, "subdiv");
    Target tim(o.size, o.size, 1, false);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);

    // Renders each mesh of a list, interleaved, and returns the medians.
    auto renderMs = [&](const std::vector<std::unique_ptr<GpuMesh>>& meshes,
                        const glm::mat4& viewProj) {
        return timeVariants(
            meshes.size(),
            [&](size_t k) {
                tim.clear(glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
                glUseProgram(program.id());
                glUniformMatrix4fv(program.uniform("uViewProj"), 1, GL_FALSE, &viewProj[0][0]);
                meshes[k]->draw();
            },
            o);
    };

    // a) Torus.
    TorusCage torus;
    sg::mesh::PolygonMesh cage = torus.polygonMesh();
    sg::mesh::validate(cage, "bspline_torus");
    Table t;
    t.title = "Table 2a: subdivision level, B-spline torus (exact limit surface known; major "
              "radius 1, minor 0.45)";
    t.header = {"level",      "mesh",       "tris",     "max dev",   "rms dev",     "normal p50",
                "normal p99", "normal max", "build ms", "render ms", "render ratio"};
    std::vector<std::unique_ptr<GpuMesh>> gpu;
    struct Row {
        int level;
        bool limit;
        size_t tris;
        TorusErrors e;
        double ms;
    };
    std::vector<Row> rows;
    sg::mesh::Subdivider sub;
    for (int level = 0; level <= maxLevel; ++level) {
        for (int limit = 0; limit < 2; ++limit) {
            sg::mesh::SubdivisionSettings s;
            s.level = level;
            s.options = cage.options;
            s.limit = limit != 0;
            const double ms = buildMs(sub, cage, s, buildRuns);
            const sg::mesh::RenderMesh& mesh = sub.renderMesh();
            rows.push_back({level, limit != 0, mesh.triangleCount(), torusErrors(torus, mesh), ms});
            if (!limit) gpu.push_back(std::make_unique<GpuMesh>(mesh));
        }
    }
    const glm::vec3 eye(0.35f, -2.3f, 1.95f);
    const glm::mat4 torusView =
        glm::perspective(glm::radians(50.0f), 1.0f, 0.1f, 10.0f) *
        glm::lookAt(eye, glm::vec3(0.0f, 0.05f, -0.15f), glm::vec3(0, 0, 1));
    const auto torusMs = renderMs(gpu, torusView);
    for (const Row& r : rows) {
        const size_t k = size_t(r.level);
        t.add({std::to_string(r.level), r.limit ? "+limit" : "refined", std::to_string(r.tris),
               fmtErr(r.e.maxDev), fmtErr(r.e.rmsDev), fmtErr(r.e.normal.p50),
               fmtErr(r.e.normal.p99), fmtErr(r.e.normal.max), fmt(r.ms, 3),
               r.limit ? "" : fmt(torusMs[k], 2),
               r.limit ? "" : fmtRatio(torusMs[k] / torusMs[0])});
    }
    t.notes.push_back("Deviations in object units along the true normal; normal errors in degrees "
                      "(interpolated vertex "
                      "normal vs the limit normal at the same UV); samples: every vertex, 3 edge "
                      "midpoints and the "
                      "centroid of every triangle.");
    t.notes.push_back("build ms: Subdivider::build median of " + std::to_string(buildRuns) +
                      " (render mesh included; +limit adds limit evaluation). render: " +
                      std::to_string(o.size) + "^2 Lambert pass on " + o.renderer + ", " +
                      std::to_string(o.runs) + " runs x " + std::to_string(o.frames) +
                      " frames, ratio to level 0 (limit meshes have the same triangles).");
    t.plot = {"subdiv-torus",
              8,
              6,
              1,
              {0},
              true,
              true,
              "Subdivider::build ms (levels 0-5)",
              "normal error p99, degrees"};
    t.print(o);

    // b) Spot.
    const std::filesystem::path spotFile =
        std::filesystem::path(SURFGRAD_DATA_DIR) / "meshes" / "spot" / "spot_control_mesh.obj";
    sg::mesh::PolygonMesh spot = sg::mesh::loadPolygonMesh(spotFile);
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& p : spot.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    const double diag = glm::length(glm::dvec3(hi - lo));
    Table u;
    u.title = "Table 2b: subdivision level, spot's control cage (extraordinary vertices; "
              "OpenSubdiv limit as reference)";
    u.header = {"level",           "tris",       "vertex dist max", "vertex dist rms",
                "normal p50",      "normal p99", "normal max",      "build ms",
                "+limit build ms", "render ms",  "render ratio"};
    std::vector<std::unique_ptr<GpuMesh>> spotGpu;
    struct SpotRow {
        int level;
        size_t tris;
        double maxDist, rmsDist;
        ErrorStats normal;
        double ms, msLimit;
    };
    std::vector<SpotRow> spotRows;
    sg::mesh::Subdivider subLimit;
    for (int level = 0; level <= maxLevel; ++level) {
        sg::mesh::SubdivisionSettings s;
        s.level = level;
        s.options = spot.options;
        const double ms = buildMs(sub, spot, s, buildRuns);
        s.limit = true;
        const double msLimit = buildMs(subLimit, spot, s, buildRuns);
        const sg::mesh::RenderMesh& a = sub.renderMesh();
        const sg::mesh::RenderMesh& b = subLimit.renderMesh();
        if (a.vertexCount() != b.vertexCount() ||
            sub.renderToRefinedVertex() != subLimit.renderToRefinedVertex()) {
            throw std::runtime_error("spot: refined and limit builds do not share their vertices");
        }
        double maxDist = 0, sumSq = 0;
        std::vector<double> nerr;
        for (size_t v = 0; v < a.vertexCount(); ++v) {
            const double d =
                glm::length(glm::dvec3(a.positions[v]) - glm::dvec3(b.positions[v])) / diag;
            maxDist = std::max(maxDist, d);
            sumSq += d * d;
            nerr.push_back(angleDeg(glm::dvec3(a.normals[v]), glm::dvec3(b.normals[v])));
        }
        spotRows.push_back({level, a.triangleCount(), maxDist,
                            std::sqrt(sumSq / double(a.vertexCount())), errorStats(nerr), ms,
                            msLimit});
        spotGpu.push_back(std::make_unique<GpuMesh>(a));
    }
    const glm::vec3 c = 0.5f * (lo + hi);
    const float r = 0.5f * float(diag);
    const glm::mat4 spotView =
        glm::perspective(glm::radians(40.0f), 1.0f, 0.05f * r, 10.0f * r) *
        glm::lookAt(c + r * glm::vec3(1.6f, 0.9f, 2.2f), c, glm::vec3(0, 1, 0));
    const auto spotMs = renderMs(spotGpu, spotView);
    for (const SpotRow& s : spotRows) {
        const size_t k = size_t(s.level);
        u.add({std::to_string(s.level), std::to_string(s.tris), fmtErr(s.maxDist),
               fmtErr(s.rmsDist), fmtErr(s.normal.p50), fmtErr(s.normal.p99), fmtErr(s.normal.max),
               fmt(s.ms, 3), fmt(s.msLimit, 3), fmt(spotMs[k], 2),
               fmtRatio(spotMs[k] / spotMs[0])});
    }
    u.notes.push_back("Vertex distances relative to the bounding-box diagonal; normal errors in "
                      "degrees (area-weighted "
                      "normal of the refined mesh vs the limit normal, at the vertices).");
    u.plot = {"subdiv-spot",
              7,
              5,
              -1,
              {0},
              true,
              true,
              "Subdivider::build ms (levels 0-5)",
              "normal error p99 vs OpenSubdiv limit, degrees"};
    u.print(o);
}

} // namespace study
