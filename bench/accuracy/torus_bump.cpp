// The torus bump experiment (torus_bump.h).
#include "torus_bump.h"

#include <cmath>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>

#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"

namespace study {

double HeightField::h(double s, double t) const {
    return amplitude * std::sin(2.0 * M_PI * kS * s) * std::sin(2.0 * M_PI * kT * t);
}

glm::dvec2 HeightField::grad(double s, double t) const {
    const double as = 2.0 * M_PI * kS, at = 2.0 * M_PI * kT;
    return {amplitude * as * std::cos(as * s) * std::sin(at * t),
            amplitude * at * std::sin(as * s) * std::cos(at * t)};
}

TorusBump::TorusBump(int lvl, bool quick) : level(lvl) {
    if (quick) {
        texW = 1024;
        texH = 512;
    }
    sg::mesh::PolygonMesh poly = cage.polygonMesh();
    sg::mesh::validate(poly, "bspline_torus");
    sg::mesh::SubdivisionSettings settings;
    settings.level = level;
    settings.options = poly.options;
    settings.limit = true;
    sg::mesh::Subdivider sub(poly, settings, "bspline_torus");
    pixelMesh = sub.renderMesh();
    // Independence check: OpenSubdiv's limit positions against the B-spline
    // at the vertex UVs (see torus.h): ~1e-7 when both are right.
    for (size_t v = 0; v < pixelMesh.vertexCount(); ++v) {
        const glm::vec2 uv = pixelMesh.uvSets[0][v];
        const glm::dvec3 p = cage.limit(uv.x, uv.y).pos;
        limitCheckMaxDist =
            std::max(limitCheckMaxDist, glm::length(p - glm::dvec3(pixelMesh.positions[v])));
    }
    if (limitCheckMaxDist > 1e-4) {
        throw std::runtime_error("torus: OpenSubdiv limit positions differ from the B-spline by " +
                                 std::to_string(limitCheckMaxDist) + " (ground truth invalid)");
    }
    mikkMesh = pixelMesh;
    sg::mesh::generateTangents(mikkMesh, sg::mesh::TangentMethod::MikkTSpace, 0);
    limitMesh = pixelMesh;
    sg::mesh::generateTangents(limitMesh, sg::mesh::TangentMethod::Limit, 0, &sub.limitFrame());

    derivTexels.resize(size_t(texW) * size_t(texH) * 2);
    for (int j = 0; j < texH; ++j) {
        for (int i = 0; i < texW; ++i) {
            const double s = (i + 0.5) / texW, t = (j + 0.5) / texH;
            const glm::dvec2 d = bakeDerivative(cage.limit(s, t), truthNormal(s, t));
            derivTexels[(size_t(j) * size_t(texW) + size_t(i)) * 2 + 0] = float(d.x);
            derivTexels[(size_t(j) * size_t(texW) + size_t(i)) * 2 + 1] = float(d.y);
        }
    }
    // Looking down at the torus from 40 degrees of elevation: the inner
    // ring, the outer flank and grazing silhouettes are all on screen.
    camPos = glm::vec3(0.35f, -2.3f, 1.95f);
    viewProj = glm::perspective(glm::radians(50.0f), 1.0f, 0.1f, 10.0f) *
               glm::lookAt(camPos, glm::vec3(0.0f, 0.05f, -0.15f), glm::vec3(0, 0, 1));
}

glm::dvec3 TorusBump::truthNormal(double s, double t) const {
    const glm::dvec2 g = height.grad(s, t);
    return blinnNormal(cage.limit(s, t), g.x, g.y);
}

glm::dvec2 TorusBump::sampleDeriv(double s, double t) const {
    // GL_LINEAR with GL_REPEAT: texel centres at (i + 0.5) / W.
    const double x = s * texW - 0.5, y = t * texH - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    auto texel = [&](int i, int j) {
        i = ((i % texW) + texW) % texW;
        j = ((j % texH) + texH) % texH;
        const size_t k = (size_t(j) * size_t(texW) + size_t(i)) * 2;
        return glm::dvec2(derivTexels[k], derivTexels[k + 1]);
    };
    const int i0 = int(fx), j0 = int(fy);
    return (1 - ax) * (1 - ay) * texel(i0, j0) + ax * (1 - ay) * texel(i0 + 1, j0) +
           (1 - ax) * ay * texel(i0, j0 + 1) + ax * ay * texel(i0 + 1, j0 + 1);
}

std::vector<double> TorusBump::vertexTangentErrors(const sg::mesh::RenderMesh& mesh,
                                                   glm::dvec2* worstUv) const {
    std::vector<double> err;
    double worst = -1;
    for (size_t v = 0; v < mesh.vertexCount(); ++v) {
        const glm::dvec2 uv(mesh.uvSets[0][v]);
        glm::dvec3 t, b;
        exactFrame(cage.limit(uv.x, uv.y), t, b);
        err.push_back(angleDeg(glm::dvec3(mesh.tangents[v]), t));
        if (err.back() > worst) {
            worst = err.back();
            if (worstUv) *worstUv = uv;
        }
    }
    return err;
}

const char* torusVertexShader() {
    return R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
layout(location = 3) in vec4 aTangent;
uniform mat4 uViewProj;
uniform vec3 uCamPos;
out vec3 vRelPos;
out vec3 vNormal;
out vec4 vTangent;
out vec2 vUv;
void main() {
    vRelPos = aPos - uCamPos; // camera-relative world position (listing 16)
    vNormal = aNormal;
    vTangent = aTangent;
    vUv = aUv;
    gl_Position = uViewProj * vec4(aPos, 1.0);
}
)";
}

const char* torusFragmentHead() {
    return R"(
#include "sg/surfgrad.glsl"
in vec3 vRelPos;
in vec3 vNormal;
in vec4 vTangent;
in vec2 vUv;
uniform sampler2D uDeriv;
)";
}

} // namespace study
