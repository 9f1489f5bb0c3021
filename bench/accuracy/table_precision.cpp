// Table 6, precision (docs/accuracy-cost.md): the bump path of table 1
// (torus_bump.h) evaluated on the CPU in binary64, binary32 and emulated
// binary16 (precision_path.h) from the per-pixel inputs the GPU produced for
// the torus at level 3 (interpolated position, normal, UV, tangent, their
// fine screen derivatives, the derivative map's sample turned into a
// tangent-space normal m as a normal map would store it).
//
// Error columns: against the binary64 evaluation of the same path on the
// same inputs (what the precision alone costs), and against Blinn's normal on
// the exact surface (table 1's truth: what the user sees in total). Rows:
//   per-pixel frame (L16 + L6 + L4 + L5 + L1):
//     binary32;
//     binary16 arithmetic, inputs (normal, dPdx/dPdy, dSTdx/dSTdy, m)
//       rounded to binary16 once ("mediump" math on highp varyings and
//       derivatives);
//     binary16 varyings too: position and UV interpolated in binary16 and
//       differenced in binary16 (dPdx = h(P + dPdx) - h(P), likewise UV);
//     binary32 with positions NOT camera-relative, the object 1000 units
//       from the origin (why listing 16 subtracts the camera position);
//     binary32 with the normal map quantized to 8 bits (RG8, z
//       reconstructed by L4): the storage error the others compete with;
//   vertex tangents (section 2.2 basis + L4 + L5 + L1): binary32, binary16.
// No cost column: llvmpipe runs every float operation in binary32 (no
// float16_t in GLSL, mediump ignored by desktop GL), so there is no binary16
// speed to measure on this machine; the table says so.
#include <epoxy/gl.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "precision_path.h"
#include "surfgrad/bump/core.h"
#include "surfgrad/render/view.h"
#include "tables.h"
#include "torus_bump.h"

namespace study {

namespace {

const char* kInputs = R"(
layout(location = 0) out vec4 oPosU;  // relPos, uv.x
layout(location = 1) out vec4 oNrmV;  // interpolated normal (not normalized), uv.y
layout(location = 2) out vec4 oDx;    // dPdx, dSTdx.x
layout(location = 3) out vec4 oDy;    // dPdy, dSTdx.y
layout(location = 4) out vec4 oTan;   // interpolated tangent xyz, w
layout(location = 5) out vec4 oDerivDy; // derivative map sample, dSTdy
void main() {
    vec3 dPdx = dFdxFine(vRelPos);
    vec3 dPdy = dFdyFine(vRelPos);
    vec2 dSTdx = dFdxFine(vUv);
    vec2 dSTdy = dFdyFine(vUv);
    oPosU = vec4(vRelPos, vUv.x);
    oNrmV = vec4(vNormal, vUv.y);
    oDx = vec4(dPdx, dSTdx.x);
    oDy = vec4(dPdy, dSTdx.y);
    oTan = vTangent;
    oDerivDy = vec4(texture(uDeriv, vUv).xy, dSTdy);
}
)";

// Vertex stage of the distance study (table 6b): the torus moved `uModel`'s
// translation away from the origin with the camera, as the renderer's
// vertex program did it before (world position in binary32, then minus
// the camera) and does it now (CAMERA_RELATIVE: one object ->
// camera-relative matrix composed in double on the CPU,
// sg::render::modelToCameraRelative; shaders/sg/render/surface_vs.glsl).
const char* kFarVertex = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
layout(location = 3) in vec4 aTangent;
uniform mat4 uModel;       // object -> world
uniform vec3 uCamPos;      // world position of the camera (binary32)
uniform mat4 uModelRel;    // object -> camera-relative world
uniform mat4 uViewProjRel; // camera-relative world -> clip
out vec3 vRelPos;
out vec3 vNormal;
out vec4 vTangent;
out vec2 vUv;
void main() {
#ifdef CAMERA_RELATIVE
    vRelPos = (uModelRel * vec4(aPos, 1.0)).xyz;
#else
    vec4 worldPos = uModel * vec4(aPos, 1.0);
    vRelPos = worldPos.xyz - uCamPos;
#endif
    vNormal = aNormal;
    vTangent = aTangent;
    vUv = aUv;
    gl_Position = uViewProjRel * vec4(vRelPos, 1.0);
}
)";

struct PixelInputs {
    glm::dvec3 relPos, normal, dPdx, dPdy, tangentXyz;
    double tangentW;
    glm::dvec2 uv, dSTdx, dSTdy, m; // m: tangent-space normal xy of the map sample
};

template <class T>
V3<T> v3(const glm::dvec3& v) {
    return {T(float(v.x)), T(float(v.y)), T(float(v.z))};
}
template <>
V3<double> v3<double>(const glm::dvec3& v) {
    return {v.x, v.y, v.z};
}
template <class T>
V2<T> v2(const glm::dvec2& v) {
    return {T(float(v.x)), T(float(v.y))};
}
template <>
V2<double> v2<double>(const glm::dvec2& v) {
    return {v.x, v.y};
}
template <class T>
glm::dvec3 back(const V3<T>& v) {
    return {toFloat(v.x), toFloat(v.y), toFloat(v.z)};
}
template <>
glm::dvec3 back<double>(const V3<double>& v) {
    return {v.x, v.y, v.z};
}

// The per-pixel-frame path in precision T, with the given position and UV
// derivatives (already in T).
template <class T>
glm::dvec3 pixelPath(const PixelInputs& in, V3<T> dPdx, V3<T> dPdy, V2<T> dSTdx, V2<T> dSTdy,
                     glm::dvec2 m) {
    const Frame<T> f = prologue(v3<T>(in.normal), dPdx, dPdy);
    V3<T> t, b;
    genBasisTB(f, dSTdx, dSTdy, t, b);
    return back(resolveTBN(f, tspaceNormalToDeriv(v2<T>(m)), t, b));
}

template <class T>
glm::dvec3 pixelPath(const PixelInputs& in) {
    return pixelPath<T>(in, v3<T>(in.dPdx), v3<T>(in.dPdy), v2<T>(in.dSTdx), v2<T>(in.dSTdy), in.m);
}

template <class T>
glm::dvec3 vertexPath(const PixelInputs& in) {
    V3<T> tang, bino, nUnit;
    mikktsBasis(v3<T>(in.normal), v3<T>(in.tangentXyz), T(float(in.tangentW)), tang, bino, nUnit);
    Frame<T> f;
    f.nrmBase = nUnit;
    f.resolveSign = T(1.0f);
    return back(resolveTBN(f, tspaceNormalToDeriv(v2<T>(in.m)), tang, bino));
}

// The shared C++ build (sg::glsl) of the per-pixel path: checks the
// transcription at T = float.
glm::dvec3 sharedPixelPath(const PixelInputs& in) {
    using namespace sg::glsl;
    const SgFrame f =
        sgPrologue(vec3(in.normal), vec3(in.dPdx), vec3(in.dPdy), true, SG_BFACE_NONE);
    vec3 t, b;
    sgGenBasisTB(f, vec2(in.uv), vec2(in.dSTdx), vec2(in.dSTdy), t, b);
    return glm::dvec3(
        sgResolve(f, sgSurfgradFromTBN(sgTspaceNormalToDeriv(vec2(in.m), false), t, b)));
}

// Table 6b: the per-pixel path (binary32) on the torus moved `distance`
// units from the origin along (1, 1, 1) / sqrt 3 together with the camera,
// its inputs produced by the two vertex stages of kFarVertex; error against
// table 1's truth (the same at every distance: the view is the same).
void tableFarFromOrigin(const TorusBump& scene, const GpuMesh& mesh, unsigned tex, int size,
                        const Options& o) {
    const std::string fs = std::string(torusFragmentHead()) + kInputs;
    const sg::gl::Program before = makeProgram(kFarVertex, fs, "precision_far_world");
    const sg::gl::Program after =
        makeProgram(kFarVertex, fs, "precision_far_relative", {"CAMERA_RELATIVE"});
    // Table 1's projection and view rotation (its camera is within 0.2 of
    // the snapped one below).
    const glm::mat4 viewProjRel = scene.viewProj * glm::translate(glm::mat4(1.0f), scene.camPos);
    Table t;
    t.title = "Table 6b: far from the origin (table 1's torus, level " +
              std::string(o.quick ? "1" : "3") +
              ", and its camera moved away from the world origin; per-pixel frame, binary32)";
    t.header = {"distance", "vertex stage", "pixels", "p50 deg", "p99 deg", "max deg"};
    Target target(size, size, 6);
    glBindTextureUnit(0, tex);
    // The camera snapped to multiples of 0.5 and the offsets to integers:
    // object and camera positions are then exact in binary32 up to 1e7
    // (components below 2^23), so every distance renders the same view and
    // only the vertex stage's rounding differs.
    const glm::dvec3 cam = glm::round(glm::dvec3(scene.camPos) * 2.0) * 0.5;
    for (double distance : {1.0, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7}) {
        const glm::dvec3 offset = glm::round(distance * glm::normalize(glm::dvec3(1.0)));
        const glm::mat4 model = glm::translate(glm::mat4(1.0f), glm::vec3(offset));
        const glm::vec3 camWorld(cam + offset);
        const glm::mat4 modelRel = sg::render::modelToCameraRelative(model, camWorld);
        for (int relative = 0; relative < 2; ++relative) {
            const sg::gl::Program& p = relative ? after : before;
            target.bind();
            target.clear(glm::vec4(0.0f, 0.0f, 0.0f, -1.0f));
            glEnable(GL_DEPTH_TEST);
            glEnable(GL_CULL_FACE);
            glUseProgram(p.id());
            glUniformMatrix4fv(p.uniform("uViewProjRel"), 1, GL_FALSE, &viewProjRel[0][0]);
            if (relative) {
                glUniformMatrix4fv(p.uniform("uModelRel"), 1, GL_FALSE, &modelRel[0][0]);
            } else {
                glUniformMatrix4fv(p.uniform("uModel"), 1, GL_FALSE, &model[0][0]);
                glUniform3fv(p.uniform("uCamPos"), 1, &camWorld[0]);
            }
            glUniform1i(p.uniform("uDeriv"), 0);
            mesh.draw();
            std::vector<std::vector<glm::vec4>> out;
            for (int i = 0; i < 6; ++i) out.push_back(target.read(i));
            std::vector<double> err;
            for (size_t i = 0; i < out[0].size(); ++i) {
                if (out[1][i].w < 0.0f) continue; // not covered
                PixelInputs in;
                in.relPos = glm::dvec3(out[0][i]);
                in.uv = {out[0][i].w, out[1][i].w};
                in.normal = glm::dvec3(out[1][i]);
                in.dPdx = glm::dvec3(out[2][i]);
                in.dSTdx = {out[2][i].w, out[3][i].w};
                in.dPdy = glm::dvec3(out[3][i]);
                in.dSTdy = {out[5][i].z, out[5][i].w};
                const glm::dvec3 mn = glm::normalize(glm::dvec3(-out[5][i].x, -out[5][i].y, 1.0));
                in.m = {mn.x, mn.y};
                err.push_back(angleDeg(pixelPath<float>(in), scene.truthNormal(in.uv.x, in.uv.y)));
            }
            const ErrorStats e = errorStats(err);
            char d[32];
            std::snprintf(d, sizeof d, "%.0e", distance);
            t.add({d, relative ? "camera-relative (double on the CPU)" : "world, then minus camera",
                   std::to_string(e.count), e.count ? fmtErr(e.p50) : "-",
                   e.count ? fmtErr(e.p99) : "-", e.count ? fmtErr(e.max) : "-"});
        }
    }
    t.notes.push_back(
        "'world, then minus camera': the vertex stage as the renderer had it (world position in "
        "binary32, camera subtracted after); 'camera-relative': the renderer's vertex stage now "
        "(object -> camera-relative matrix with the camera subtracted in binary64, "
        "sg::render::modelToCameraRelative). Object and camera positions exact in binary32 (the "
        "camera snapped to multiples of 0.5), so the view is the same at every distance; error "
        "against table 1's truth (Blinn's normal on the exact surface), " +
        std::to_string(size) + "^2.");
    t.plot = {"precision-far",
              0,
              4,
              1,
              {},
              true,
              true,
              "distance from the world origin",
              "normal error p99, degrees"};
    t.print(o);
}

} // namespace

void tablePrecision(const Options& o) {
    const int level = o.quick ? 1 : 3;
    TorusBump scene(level, o.quick);
    const unsigned tex = makeFloatTexture(scene.texW, scene.texH, 2, scene.derivTexels, true, true);
    glBindTextureUnit(0, tex);
    GpuMesh mesh(scene.mikkMesh);
    sg::gl::Program prog =
        makeProgram(torusVertexShader(), std::string(torusFragmentHead()) + kInputs, "precision");
    const int size = o.quick ? 256 : 768;
    Target target(size, size, 6);
    target.clear(glm::vec4(0.0f, 0.0f, 0.0f, -1.0f));
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glUseProgram(prog.id());
    glUniformMatrix4fv(prog.uniform("uViewProj"), 1, GL_FALSE, &scene.viewProj[0][0]);
    glUniform3fv(prog.uniform("uCamPos"), 1, &scene.camPos[0]);
    glUniform1i(prog.uniform("uDeriv"), 0);
    mesh.draw();
    std::vector<std::vector<glm::vec4>> out;
    for (int i = 0; i < 6; ++i) out.push_back(target.read(i));

    enum Row { PixF32, PixF16, PixF16Vary, PixF32Abs, PixF32Rg8, VtxF32, VtxF16, RowCount };
    const char* names[RowCount] = {
        "per-pixel frame, binary32",
        "per-pixel frame, binary16 math (highp varyings and derivatives)",
        "per-pixel frame, binary16 math and varyings (position, UV)",
        "per-pixel frame, binary32, world positions 1000 units out",
        "per-pixel frame, binary32, 8-bit normal map",
        "vertex tangents, binary32",
        "vertex tangents, binary16 math and varyings"};
    std::vector<std::vector<double>> vs64(RowCount), vsTruth(RowCount);
    double mirrorMax = 0;
    const glm::dvec3 farOffset(1000.0, 0.0, 0.0);
    for (size_t i = 0; i < out[0].size(); ++i) {
        if (out[1][i].w < 0.0f) continue; // not covered
        PixelInputs in;
        in.relPos = glm::dvec3(out[0][i]);
        in.uv = {out[0][i].w, out[1][i].w};
        in.normal = glm::dvec3(out[1][i]);
        in.dPdx = glm::dvec3(out[2][i]);
        in.dSTdx = {out[2][i].w, out[3][i].w};
        in.dPdy = glm::dvec3(out[3][i]);
        in.tangentXyz = glm::dvec3(out[4][i]);
        in.tangentW = out[4][i].w;
        in.dSTdy = {out[5][i].z, out[5][i].w};
        // The map sample as a unit tangent-space normal (what a normal map
        // stores), so the path includes listing 4.
        const glm::dvec3 mn = glm::normalize(glm::dvec3(-out[5][i].x, -out[5][i].y, 1.0));
        in.m = {mn.x, mn.y};
        const glm::dvec3 truth = scene.truthNormal(in.uv.x, in.uv.y);

        const glm::dvec3 pix64 = pixelPath<double>(in), vtx64 = vertexPath<double>(in);
        glm::dvec3 n[RowCount];
        n[PixF32] = pixelPath<float>(in);
        mirrorMax = std::max(mirrorMax, angleDeg(n[PixF32], sharedPixelPath(in)));
        n[PixF16] = pixelPath<Half>(in);
        {
            // binary16 varyings: this pixel's and its neighbours' interpolated
            // position and UV rounded to binary16, differenced in binary16.
            auto h3 = [](const glm::dvec3& v) { return v3<Half>(v); };
            auto h2 = [](const glm::dvec2& v) { return v2<Half>(v); };
            const V3<Half> p0 = h3(in.relPos), px = h3(in.relPos + in.dPdx),
                           py = h3(in.relPos + in.dPdy);
            const V2<Half> s0 = h2(in.uv), sx = h2(in.uv + in.dSTdx), sy = h2(in.uv + in.dSTdy);
            n[PixF16Vary] =
                pixelPath<Half>(in, px - p0, py - p0, V2<Half>{sx.x - s0.x, sx.y - s0.y},
                                V2<Half>{sy.x - s0.x, sy.y - s0.y}, in.m);
        }
        {
            // Absolute world positions far from the origin, differenced in binary32.
            const glm::vec3 pw(in.relPos + glm::dvec3(scene.camPos) + farOffset);
            const glm::vec3 pwx = pw + glm::vec3(in.dPdx), pwy = pw + glm::vec3(in.dPdy);
            n[PixF32Abs] = pixelPath<float>(in, v3<float>(glm::dvec3(pwx - pw)),
                                            v3<float>(glm::dvec3(pwy - pw)), v2<float>(in.dSTdx),
                                            v2<float>(in.dSTdy), in.m);
        }
        {
            auto q8 = [](double c) {
                return std::round((c * 0.5 + 0.5) * 255.0) / 255.0 * 2.0 - 1.0;
            };
            n[PixF32Rg8] =
                pixelPath<float>(in, v3<float>(in.dPdx), v3<float>(in.dPdy), v2<float>(in.dSTdx),
                                 v2<float>(in.dSTdy), glm::dvec2(q8(in.m.x), q8(in.m.y)));
        }
        n[VtxF32] = vertexPath<float>(in);
        n[VtxF16] = vertexPath<Half>(in);
        for (int r = 0; r < RowCount; ++r) {
            const glm::dvec3& ref = r >= VtxF32 ? vtx64 : pix64;
            vs64[size_t(r)].push_back(angleDeg(n[r], ref));
            vsTruth[size_t(r)].push_back(angleDeg(n[r], truth));
        }
    }

    Table t;
    t.title = "Table 6: precision (torus level " + std::to_string(level) +
              ", table 1's path evaluated on the GPU's per-pixel inputs)";
    t.header = {"path and precision",
                "vs binary64 p50",
                "p99",
                "max",
                "vs truth p50",
                "p99",
                "max",
                "cost"};
    for (int r = 0; r < RowCount; ++r) {
        const ErrorStats a = errorStats(vs64[size_t(r)]), b = errorStats(vsTruth[size_t(r)]);
        t.add({names[r], fmtErr(a.p50), fmtErr(a.p99), fmtErr(a.max), fmtErr(b.p50), fmtErr(b.p99),
               fmtErr(b.max), "n/a"});
    }
    t.notes.push_back("Degrees over " + std::to_string(vs64[0].size()) + " pixels (" +
                      std::to_string(size) +
                      "^2). 'vs binary64': the same path on the same inputs in double; 'vs truth': "
                      "Blinn's normal "
                      "on the exact surface (table 1).");
    t.notes.push_back("binary16 is emulated (every operation rounded to binary16, "
                      "precision_path.h); the binary32 "
                      "transcription differs from the shared C++ build (sg::glsl) by at most " +
                      fmtErr(mirrorMax) + " degrees.");
    t.notes.push_back(
        "cost n/a: " + o.renderer +
        " exposes no 16-bit float arithmetic to GLSL (no float16_t "
        "extension) and desktop GLSL ignores mediump, so binary16 runs at binary32 speed here; on "
        "GPUs with double-rate fp16 the ALU part of this path could run up to 2x faster.");
    // No cost on llvmpipe (see the notes): precision alone against the whole error.
    t.plot = {"precision",
              2,
              5,
              -1,
              {0},
              true,
              true,
              "error vs binary64 p99, degrees (precision alone)",
              "error vs truth p99, degrees"};
    t.print(o);
    tableFarFromOrigin(scene, mesh, tex, size, o);
    deleteTexture(tex);
}

} // namespace study
