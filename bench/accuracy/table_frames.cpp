// Table 1, tangent frame source (docs/accuracy-cost.md): the same
// tangent-space derivative map rendered on the same limit mesh with three
// frame sources,
//   pixel      - no stored tangents: prologue (Mikkelsen 2019 listing 16)
//                + GenBasisTB (listing 6) from dFdxFine of position and UV;
//   mikktspace - MikkTSpace vertex tangents of the limit mesh (mesh module),
//                mikktspace-compliant basis (section 2.2);
//   limit      - the exact limit-surface tangents at the vertices (mesh
//                module, generateLimitTangents), same shader as mikktspace;
// then listing 5 + listing 1. Error: angle between the rendered normal and
// Blinn's perturbed normal on the exact limit surface at the pixel's UV
// (torus_bump.h: the map is baked against the exact frame, so only the
// frame and the interpolated base normal can make a difference). Cost: the
// frame time of the same pass on llvmpipe, ratio to mikktspace.
#include <epoxy/gl.h>

#include <cstdio>
#include <memory>

#include "tables.h"
#include "torus_bump.h"

namespace study {

namespace {

const char* kFragment = R"(
#ifdef ACCURACY
layout(location = 0) out vec4 oNormalU; // resolved normal, uv.x
layout(location = 1) out vec4 oBaseV;   // base normal, uv.y
#else
layout(location = 0) out vec4 oColor;
#endif
void main() {
    vec2 deriv = texture(uDeriv, vUv).xy;
    SgFrame f;
    vec3 t;
    vec3 b;
#ifdef FRAME_PIXEL
    f = sgPrologue(vNormal, dFdxFine(vRelPos), dFdyFine(vRelPos), gl_FrontFacing, SG_BFACE_NONE);
    sgGenBasisTB(f, vUv, dFdxFine(vUv), dFdyFine(vUv), t, b);
#else
    f.nrmBase = vNormal * sgRenormFactor(vNormal);
    f.resolveSign = 1.0;
    sgMikktsBasis(vNormal, vTangent, t, b);
#endif
    vec3 n = sgResolve(f, sgSurfgradFromTBN(deriv, t, b));
#ifdef ACCURACY
    oNormalU = vec4(n, vUv.x);
    oBaseV = vec4(f.nrmBase, vUv.y);
#else
    oColor = vec4(n * 0.5 + 0.5, 1.0);
#endif
}
)";

struct Source {
    const char* name;
    const sg::mesh::RenderMesh* mesh;
    bool pixel;
};

std::vector<Source> sourcesOf(const TorusBump& scene) {
    return {{"mikktspace", &scene.mikkMesh, false},
            {"limit", &scene.limitMesh, false},
            {"pixel (L16+L6)", &scene.pixelMesh, true}};
}

sg::gl::Program frameProgram(bool pixel, bool accuracy) {
    std::vector<std::string> defs = {pixel ? "FRAME_PIXEL" : "FRAME_VERTEX"};
    if (accuracy) defs.push_back("ACCURACY");
    return makeProgram(torusVertexShader(), std::string(torusFragmentHead()) + kFragment, "frames",
                       defs);
}

void useFrameProgram(const sg::gl::Program& p, const TorusBump& scene) {
    glUseProgram(p.id());
    glUniformMatrix4fv(p.uniform("uViewProj"), 1, GL_FALSE, &scene.viewProj[0][0]);
    glUniform3fv(p.uniform("uCamPos"), 1, &scene.camPos[0]);
    glUniform1i(p.uniform("uDeriv"), 0);
}

} // namespace

FrameSourceErrors measureFrameSources(const TorusBump& scene, int size) {
    const unsigned tex = makeFloatTexture(scene.texW, scene.texH, 2, scene.derivTexels, true, true);
    glBindTextureUnit(0, tex);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    Target acc(size, size, 2);
    FrameSourceErrors fe;
    const auto sources = sourcesOf(scene);
    for (size_t k = 0; k < 3; ++k) {
        GpuMesh mesh(*sources[k].mesh);
        const sg::gl::Program prog = frameProgram(sources[k].pixel, true);
        acc.clear(glm::vec4(0.0f, 0.0f, 0.0f, -1.0f));
        useFrameProgram(prog, scene);
        mesh.draw();
        const auto nu = acc.read(0), bv = acc.read(1);
        for (size_t i = 0; i < nu.size(); ++i) {
            if (bv[i].w < 0.0f) continue; // not covered
            const double s = nu[i].w, tt = bv[i].w;
            const glm::dvec3 truth = scene.truthNormal(s, tt);
            fe.err[k].push_back(angleDeg(glm::dvec3(nu[i]), truth));
            if (k == 0) {
                ++fe.covered;
                const SurfacePoint p = scene.truthPoint(s, tt);
                fe.baseErr.push_back(angleDeg(glm::dvec3(bv[i]), p.normal));
                // The map's own reconstruction error: its bilinear sample
                // resolved with the exact frame and normal.
                glm::dvec3 tx, bx;
                exactFrame(p, tx, bx);
                const glm::dvec2 d = scene.sampleDeriv(s, tt);
                fe.floorErr.push_back(
                    angleDeg(glm::normalize(p.normal - d.x * tx - d.y * bx), truth));
            }
        }
    }
    deleteTexture(tex);
    return fe;
}

void tableFrames(const Options& o) {
    const std::vector<int> levels = o.quick ? std::vector<int>{1} : std::vector<int>{1, 3};
    Table t;
    t.title = "Table 1: tangent frame source (B-spline torus, limit mesh, derivative map baked "
              "against the exact frame)";
    t.header = {"level",   "source",  "tris",     "p50 deg",      "p90 deg",
                "p99 deg", "max deg", "frame ms", "vs mikktspace"};
    for (int level : levels) {
        TorusBump scene(level, o.quick);
        const auto sources = sourcesOf(scene);
        const int accSize = o.quick ? 384 : 1024;
        const FrameSourceErrors fe = measureFrameSources(scene, accSize);
        const auto& err = fe.err;

        const unsigned tex =
            makeFloatTexture(scene.texW, scene.texH, 2, scene.derivTexels, true, true);
        glBindTextureUnit(0, tex);
        std::vector<std::unique_ptr<GpuMesh>> meshes;
        std::vector<sg::gl::Program> timing;
        for (const Source& s : sources) {
            meshes.push_back(std::make_unique<GpuMesh>(*s.mesh));
            timing.push_back(frameProgram(s.pixel, false));
        }

        // Timing pass.
        Target tim(o.size, o.size, 1, false);
        const auto ms = timeVariants(
            3,
            [&](size_t k) {
                tim.clear();
                useFrameProgram(timing[k], scene);
                meshes[k]->draw();
            },
            o);
        for (int k = 0; k < 3; ++k) {
            const ErrorStats e = errorStats(err[size_t(k)]);
            t.add({std::to_string(level), sources[k].name,
                   std::to_string(meshes[size_t(k)]->triangles()), fmtErr(e.p50), fmtErr(e.p90),
                   fmtErr(e.p99), fmtErr(e.max), fmt(ms[size_t(k)], 2),
                   fmtRatio(ms[size_t(k)] / ms[0])});
        }
        const ErrorStats b = errorStats(fe.baseErr), fl = errorStats(fe.floorErr);
        t.add({std::to_string(level), "(interpolated base normal vs limit normal)", "",
               fmtErr(b.p50), fmtErr(b.p90), fmtErr(b.p99), fmtErr(b.max), "", ""});
        t.add({std::to_string(level), "(map reconstruction floor, exact frame)", "", fmtErr(fl.p50),
               fmtErr(fl.p90), fmtErr(fl.p99), fmtErr(fl.max), "", ""});
        t.notes.push_back(
            "level " + std::to_string(level) + ": " + std::to_string(fe.covered) + " pixels at " +
            std::to_string(accSize) + "^2; OpenSubdiv limit vs analytic B-spline max " +
            fmtErr(scene.limitCheckMaxDist) + " object units; MikkTSpace split the mesh to " +
            std::to_string(scene.mikkMesh.vertexCount()) + " vertices (" +
            std::to_string(scene.pixelMesh.vertexCount()) + " without tangents)");
        glm::dvec2 mikkWorst(0.0), limitWorst(0.0);
        const ErrorStats vm = errorStats(scene.vertexTangentErrors(scene.mikkMesh, &mikkWorst));
        const ErrorStats vl = errorStats(scene.vertexTangentErrors(scene.limitMesh, &limitWorst));
        t.notes.push_back("level " + std::to_string(level) +
                          " vertex tangents vs the exact tangent at the vertex: "
                          "MikkTSpace p50 " +
                          fmtErr(vm.p50) + ", max " + fmtErr(vm.max) + " deg (at uv " +
                          fmt(mikkWorst.x, 3) + ", " + fmt(mikkWorst.y, 3) + "); limit p50 " +
                          fmtErr(vl.p50) + ", max " + fmtErr(vl.max) + " deg");
        deleteTexture(tex);
    }
    t.notes.push_back(
        "Error: angle between the rendered normal and Blinn's perturbed normal of h(s,t) = " +
        fmt(HeightField().amplitude, 3) +
        " sin(16 pi s) sin(8 pi t) on the exact B-spline limit "
        "surface at the pixel's UV (double). Timing: " +
        std::to_string(o.size) + "^2, RGBA8 target, " + std::to_string(o.runs) + " runs x " +
        std::to_string(o.frames) + " frames, medians; same vertex buffer layout for all sources.");
    t.plot = {"frames",
              8,
              5,
              1,
              {0},
              false,
              true,
              "frame time, ratio to MikkTSpace (same run)",
              "normal error p99, degrees"};
    t.print(o);
}

} // namespace study
