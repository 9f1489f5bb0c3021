// Blendshape frame benchmark (bench/README.md, "Mesh"): AnimatedMorphSphere
// (glTF, 2 morph targets, weight animation) welded into a cage, given a
// longitude/latitude UV set (the file has none; a normal map needs one),
// subdivided to >= 100k vertices. Per animation frame, two ways to draw it
// normal-mapped on llvmpipe (512x512, glFinish per frame):
//   vertex tangents: morph (positions + recomputed normals), MikkTSpace
//                    tangents for the morphed mesh (surfgrad/mesh/tangents.h;
//                    it splits vertices, so every attribute is re-uploaded),
//                    draw with the mikktspace basis (sgMikktsBasis);
//   per pixel:       morph (positions + normals), upload those two, draw with
//                    the frame built per pixel from screen derivatives
//                    (sgPrologue + sgGenBasisTB, Mikkelsen 2019 sec. 2.3).
// Both fragment shaders share everything else (shaders/sg/*.glsl). Prints
// medians per stage and the ratio of the totals, plus the mean difference
// of the two images as a sanity check (they should nearly agree).
//
// Usage: mesh_blendshape_bench [--frames N] [--level L] [--size S]
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "surfgrad/gl/context.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/morph.h"
#include "surfgrad/shaders/shader_files.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"

namespace {

using namespace sg::mesh;
using Clock = std::chrono::steady_clock;

double ms(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

const char* kVertex = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNrm;
layout(location = 2) in vec2 aUv;
layout(location = 3) in vec4 aTan;
uniform mat4 uModel;
uniform mat4 uViewProj;
uniform vec3 uCamera;
out vec3 vRelPos;
out vec3 vNrm;
out vec2 vUv;
out vec4 vTan;
void main() {
    vec4 world = uModel * vec4(aPos, 1.0);
    vRelPos = world.xyz - uCamera; // camera-relative (listing 16)
    mat3 n = transpose(inverse(mat3(uModel)));
    vNrm = n * aNrm;
    vTan = vec4(mat3(uModel) * aTan.xyz, aTan.w);
    vUv = aUv;
    gl_Position = uViewProj * world;
}
)";

// Shared shading: sample the normal map, turn it into a surface gradient
// with the chosen basis, resolve, light.
const char* kFragment = R"(
#include "sg/frame.glsl"
#include "sg/surfgrad.glsl"
in vec3 vRelPos;
in vec3 vNrm;
in vec2 vUv;
in vec4 vTan;
uniform sampler2D uNormalMap;
out vec4 oColor;
void main() {
    vec3 dPdx = dFdxFine(vRelPos), dPdy = dFdyFine(vRelPos);
    SgFrame f = sgPrologue(vNrm, dPdx, dPdy, gl_FrontFacing, SG_BFACE_NONE);
    vec2 m = texture(uNormalMap, vUv).xy * 2.0 - 1.0;
    vec2 d = sgTspaceNormalToDeriv(m, false);
    vec3 vT, vB;
#if VERTEX_TANGENTS
    sgMikktsBasis(vNrm, vTan, vT, vB);
#else
    sgGenBasisTB(f, vUv, dFdxFine(vUv), dFdyFine(vUv), vT, vB);
#endif
    vec3 n = sgResolve(f, sgSurfgradFromTBN(d, vT, vB));
    float lambert = max(dot(n, normalize(vec3(0.4, 0.7, 0.6))), 0.0);
    oColor = vec4(vec3(0.1 + 0.9 * lambert), 1.0);
}
)";

// Longitude/latitude UVs: one value per vertex, plus a second value (u + 1)
// for the corners of faces that cross the u = 0/1 seam, so the UV layout is
// continuous everywhere except along that seam.
void addSphericalUvs(PolygonMesh& cage) {
    glm::vec3 centre(0.0f);
    for (const auto& p : cage.positions) centre += p;
    centre /= float(cage.positions.size());
    std::vector<glm::vec2> perVertex(cage.positions.size());
    for (size_t v = 0; v < cage.positions.size(); ++v) {
        glm::vec3 d = glm::normalize(cage.positions[v] - centre);
        perVertex[v] = glm::vec2(0.5f + std::atan2(d.x, d.z) / (2.0f * float(M_PI)),
                                 0.5f + std::asin(std::clamp(d.y, -1.0f, 1.0f)) / float(M_PI));
    }
    FaceVaryingChannel ch;
    ch.name = "lonlat";
    ch.values = perVertex;
    std::vector<uint32_t> wrapped(cage.positions.size(), UINT32_MAX);
    size_t c = 0;
    for (uint32_t k : cage.faceSizes) {
        float lo = 1, hi = 0;
        for (uint32_t j = 0; j < k; ++j) {
            lo = std::min(lo, perVertex[cage.faceVertices[c + j]].x);
            hi = std::max(hi, perVertex[cage.faceVertices[c + j]].x);
        }
        for (uint32_t j = 0; j < k; ++j) {
            uint32_t v = cage.faceVertices[c + j];
            if (hi - lo > 0.5f && perVertex[v].x < 0.5f) { // this face crosses the seam
                if (wrapped[v] == UINT32_MAX) {
                    wrapped[v] = uint32_t(ch.values.size());
                    ch.values.push_back(perVertex[v] + glm::vec2(1.0f, 0.0f));
                }
                ch.indices.push_back(wrapped[v]);
            } else {
                ch.indices.push_back(v);
            }
        }
        c += k;
    }
    cage.uvSets.push_back(std::move(ch));
}

struct GpuMesh {
    GLuint vao = 0, vbo[4] = {0, 0, 0, 0}, ebo = 0;
    size_t vertexCapacity = 0, indexCapacity = 0;
    GLsizei indexCount = 0;
    void create() {
        glCreateVertexArrays(1, &vao);
        glCreateBuffers(4, vbo);
        glCreateBuffers(1, &ebo);
        const GLint comps[4] = {3, 3, 2, 4};
        for (GLuint a = 0; a < 4; ++a) {
            glVertexArrayVertexBuffer(vao, a, vbo[a], 0, GLsizei(comps[a] * sizeof(float)));
            glVertexArrayAttribFormat(vao, a, comps[a], GL_FLOAT, GL_FALSE, 0);
            glVertexArrayAttribBinding(vao, a, a);
            glEnableVertexArrayAttrib(vao, a);
        }
        glVertexArrayElementBuffer(vao, ebo);
    }
    // Uploads the attributes named in `mask` (bit a = attribute a) and,
    // with indices = true, the index buffer; grows storage when needed.
    void upload(const RenderMesh& m, unsigned mask, bool indices) {
        const size_t n = m.vertexCount();
        if (n > vertexCapacity) {
            vertexCapacity = n;
            const size_t bytes[4] = {12, 12, 8, 16};
            for (int a = 0; a < 4; ++a)
                glNamedBufferData(vbo[a], GLsizeiptr(n * bytes[a]), nullptr, GL_DYNAMIC_DRAW);
            mask = 0xf;
        }
        if (mask & 1) glNamedBufferSubData(vbo[0], 0, GLsizeiptr(n * 12), m.positions.data());
        if (mask & 2) glNamedBufferSubData(vbo[1], 0, GLsizeiptr(n * 12), m.normals.data());
        if ((mask & 4) && !m.uvSets.empty())
            glNamedBufferSubData(vbo[2], 0, GLsizeiptr(n * 8), m.uvSets[0].data());
        if ((mask & 8) && !m.tangents.empty())
            glNamedBufferSubData(vbo[3], 0, GLsizeiptr(n * 16), m.tangents.data());
        if (indices) {
            if (m.indices.size() > indexCapacity) {
                indexCapacity = m.indices.size();
                glNamedBufferData(ebo, GLsizeiptr(indexCapacity * 4), nullptr, GL_DYNAMIC_DRAW);
            }
            glNamedBufferSubData(ebo, 0, GLsizeiptr(m.indices.size() * 4), m.indices.data());
            indexCount = GLsizei(m.indices.size());
        }
    }
};

} // namespace

int main(int argc, char** argv) {
    int frames = 12, level = 4, size = 512;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--frames") && i + 1 < argc)
            frames = std::max(3, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--level") && i + 1 < argc)
            level = std::clamp(std::atoi(argv[++i]), 1, 5);
        else if (!std::strcmp(argv[i], "--size") && i + 1 < argc)
            size = std::clamp(std::atoi(argv[++i]), 64, 2048);
    }
    const std::string file =
        std::string(SURFGRAD_DATA_DIR) + "/gltf/AnimatedMorphSphere/glTF/AnimatedMorphSphere.gltf";
    Scene scene = loadScene(file);
    PolygonMesh cage = loadPolygonMesh(file);
    addSphericalUvs(cage);
    SubdivisionSettings s;
    s.level = level;
    Subdivider sub(cage, s, file);
    const RenderMesh& base = sub.renderMesh();
    std::printf("AnimatedMorphSphere: cage %zu vertices / %zu faces, level %d: %zu render "
                "vertices, %zu triangles, %zu targets; %dx%d, "
                "%d frames (medians)\n\n",
                cage.vertexCount(), cage.faceCount(), level, base.vertexCount(),
                base.triangleCount(), base.morphTargets.size(), size, size, frames);

    sg::gl::HeadlessContext ctx;
    std::printf("GL: %s\n\n", ctx.renderer().c_str());
    auto program = [&](bool vertexTangents) {
        std::vector<std::string> defs = {std::string("VERTEX_TANGENTS ") +
                                         (vertexTangents ? "1" : "0")};
        return sg::gl::Program(
            {{sg::gl::Stage::Vertex, sg::shaders::assemble(kVertex, "blendshape.vert")},
             {sg::gl::Stage::Fragment, sg::shaders::assemble(kFragment, "blendshape.frag", defs)}});
    };
    sg::gl::Program progVertex = program(true), progPixel = program(false);

    GLuint fbo, color, depth;
    glCreateFramebuffers(1, &fbo);
    glCreateRenderbuffers(1, &color);
    glCreateRenderbuffers(1, &depth);
    glNamedRenderbufferStorage(color, GL_RGBA8, size, size);
    glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT24, size, size);
    glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, size, size);
    glEnable(GL_DEPTH_TEST);

    // Procedural normal map: bumps on a 16x8 grid over the lon/lat chart.
    const int texSize = 512;
    std::vector<uint8_t> texels(size_t(texSize) * texSize * 4);
    for (int y = 0; y < texSize; ++y) {
        for (int x = 0; x < texSize; ++x) {
            float u = float(x) / texSize * 16.0f * 2.0f * float(M_PI),
                  v = float(y) / texSize * 8.0f * 2.0f * float(M_PI);
            glm::vec3 n = glm::normalize(glm::vec3(-0.6f * std::cos(u) * std::sin(v),
                                                   -0.6f * std::sin(u) * std::cos(v), 1.0f));
            uint8_t* t = &texels[(size_t(y) * texSize + size_t(x)) * 4];
            t[0] = uint8_t(std::lround((n.x * 0.5f + 0.5f) * 255));
            t[1] = uint8_t(std::lround((n.y * 0.5f + 0.5f) * 255));
            t[2] = uint8_t(std::lround((n.z * 0.5f + 0.5f) * 255));
            t[3] = 255;
        }
    }
    GLuint tex;
    glCreateTextures(GL_TEXTURE_2D, 1, &tex);
    glTextureStorage2D(tex, 10, GL_RGBA8, texSize, texSize);
    glTextureSubImage2D(tex, 0, 0, 0, texSize, texSize, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
    glGenerateTextureMipmap(tex);
    glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glBindTextureUnit(0, tex);

    // Camera: the whole sphere (world space of the file: the node scales it
    // by 100) seen from the front.
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const auto& p : base.positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    glm::vec3 centre = 0.5f * (lo + hi);
    float radius = 0.5f * glm::length(hi - lo);
    glm::mat4 model(1.0f);
    glm::vec3 camera = centre + radius * glm::vec3(0.0f, 0.4f, 3.2f);
    glm::mat4 viewProj =
        glm::perspective(glm::radians(40.0f), 1.0f, 0.1f * radius, 10.0f * radius) *
        glm::lookAt(camera, centre, glm::vec3(0, 1, 0));
    auto setUniforms = [&](const sg::gl::Program& p) {
        glUseProgram(p.id());
        glUniformMatrix4fv(p.uniform("uModel"), 1, GL_FALSE, glm::value_ptr(model));
        glUniformMatrix4fv(p.uniform("uViewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
        glUniform3fv(p.uniform("uCamera"), 1, glm::value_ptr(camera));
        glUniform1i(p.uniform("uNormalMap"), 0);
    };

    Morpher morpher(base);
    const MorphWeightAnimation* anim = scene.animations.empty() ? nullptr : &scene.animations[0];
    auto weightsAt = [&](int f) {
        if (!anim) return std::vector<float>(base.morphTargets.size(), 0.5f);
        float t = anim->times.front() +
                  (anim->times.back() - anim->times.front()) * float(f) / float(frames);
        return sampleWeights(*anim, t);
    };
    std::vector<uint8_t> imgVertex(size_t(size) * size * 4), imgPixel(imgVertex.size());

    // Vertex-tangent path.
    GpuMesh gv;
    gv.create();
    RenderMesh morphed, work;
    std::vector<double> vMorph, vTangent, vDraw, vTotal;
    for (int f = -1; f < frames; ++f) { // f = -1: warm-up
        std::vector<float> w = weightsAt(std::max(f, 0));
        auto t0 = Clock::now();
        morpher.apply(w, MorphNormals::Recompute, morphed);
        auto t1 = Clock::now();
        work.positions.assign(morphed.positions.begin(), morphed.positions.end());
        work.normals.assign(morphed.normals.begin(), morphed.normals.end());
        work.uvSets.resize(1);
        work.uvSets[0].assign(morphed.uvSets[0].begin(), morphed.uvSets[0].end());
        work.indices.assign(morphed.indices.begin(), morphed.indices.end());
        generateMikkTSpaceTangents(work, 0);
        auto t2 = Clock::now();
        gv.upload(work, 0xf, true);
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        setUniforms(progVertex);
        glBindVertexArray(gv.vao);
        glDrawElements(GL_TRIANGLES, gv.indexCount, GL_UNSIGNED_INT, nullptr);
        glFinish();
        auto t3 = Clock::now();
        if (f < 0) continue;
        vMorph.push_back(ms(t0, t1));
        vTangent.push_back(ms(t1, t2));
        vDraw.push_back(ms(t2, t3));
        vTotal.push_back(ms(t0, t3));
    }
    glReadPixels(0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, imgVertex.data());
    size_t splitVertices = work.vertexCount() - morphed.vertexCount();

    // Per-pixel path: UVs and indices never change; upload them once.
    GpuMesh gp;
    gp.create();
    morpher.apply(weightsAt(0), MorphNormals::Recompute, morphed);
    gp.upload(morphed, 0x7, true);
    std::vector<double> pMorph, pDraw, pTotal;
    for (int f = -1; f < frames; ++f) {
        std::vector<float> w = weightsAt(std::max(f, 0));
        auto t0 = Clock::now();
        morpher.apply(w, MorphNormals::Recompute, morphed);
        auto t1 = Clock::now();
        gp.upload(morphed, 0x3, false);
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        setUniforms(progPixel);
        glBindVertexArray(gp.vao);
        glDrawElements(GL_TRIANGLES, gp.indexCount, GL_UNSIGNED_INT, nullptr);
        glFinish();
        auto t2 = Clock::now();
        if (f < 0) continue;
        pMorph.push_back(ms(t0, t1));
        pDraw.push_back(ms(t1, t2));
        pTotal.push_back(ms(t0, t2));
    }
    glReadPixels(0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, imgPixel.data());
    sg::gl::checkError("blendshape bench");

    double diff = 0;
    size_t covered = 0;
    for (size_t i = 0; i < imgVertex.size(); i += 4) {
        if (imgVertex[i] == 0 && imgPixel[i] == 0) continue; // background
        diff += std::abs(int(imgVertex[i]) - int(imgPixel[i]));
        ++covered;
    }
    std::printf("| %-40s | %9s | %9s | %9s | %9s |\n", "blendshape frame (ms, median)", "morph",
                "tangents", "upload+draw", "total");
    std::printf("|%s|%s|%s|%s|%s|\n", std::string(42, '-').c_str(), std::string(11, '-').c_str(),
                std::string(11, '-').c_str(), std::string(11, '-').c_str(),
                std::string(11, '-').c_str());
    std::printf("| %-40s | %9.2f | %9.2f | %9.2f | %9.2f |\n",
                "vertex tangents (MikkTSpace per frame)", median(vMorph), median(vTangent),
                median(vDraw), median(vTotal));
    std::printf("| %-40s | %9.2f | %9s | %9.2f | %9.2f |\n", "per-pixel frame (no tangents)",
                median(pMorph), "-", median(pDraw), median(pTotal));
    std::printf("\nper-pixel total is %.2fx lower than the vertex-tangent total (goal >= 5x); "
                "MikkTSpace split %zu vertices; mean |image "
                "difference| %.2f / 255 over %zu covered pixels\n",
                median(vTotal) / median(pTotal), splitVertices,
                covered ? diff / double(covered) : 0.0, covered);
    return 0;
}
