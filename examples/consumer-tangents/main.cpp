// consumer-tangents: loads a mesh file with surfgrad::mesh, gives it
// MikkTSpace tangents (Mikkelsen 2008, the published mikktspace.c
// algorithm) and bump-maps every vertex with surfgrad::bump, the shader
// math of Mikkelsen, "Surface Gradient Based Bump Mapping Framework"
// (2019), compiled as C++: a tangent-space normal-map texel becomes a
// derivative (listing 4), a surface gradient in the vertex frame (listing
// 5, with the mikktspace basis of section 2.2) and a normal (listing 1).
// Built against an installed surfgrad with find_package (CMakeLists.txt).
//
//   example_consumer_tangents MESH [--uv-set K]
//
// Prints the mesh after tangent generation and two checks that hold for a
// correct frame: the tangents are unit and orthogonal to the normals, and
// the surface-gradient normal equals the classic TBN-matrix normal
// normalize(m.x T + m.y B + m.z N) of the same texel (section 2.1: the two
// agree exactly for an orthonormal frame). Exit status 1 on bad input.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "surfgrad/bump/core.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/tangents.h"

int main(int argc, char** argv) {
    if (argc != 2 && !(argc == 4 && std::string(argv[2]) == "--uv-set")) {
        std::fprintf(stderr, "usage: %s MESH [--uv-set K]\n", argv[0]);
        return 1;
    }
    const int uvSet = argc == 4 ? std::atoi(argv[3]) : 0;
    try {
        sg::mesh::RenderMesh mesh = sg::mesh::loadRenderMesh(argv[1]);
        // A file's mesh may lack the UV set or hold values MikkTSpace does
        // not allow: the library names the problem before generating.
        std::string problem =
            sg::mesh::tangentInputProblem(mesh, sg::mesh::TangentMethod::MikkTSpace, uvSet);
        if (!problem.empty()) throw std::runtime_error(std::string(argv[1]) + ": " + problem);
        sg::mesh::generateMikkTSpaceTangents(mesh, uvSet);

        // One tilted normal-map texel (unit, tilted 30 degrees toward +s and
        // 20 toward -t), applied at every vertex.
        const glm::vec3 texel =
            glm::normalize(glm::vec3(std::tan(0.5236f), -std::tan(0.3491f), 1.0f));
        double maxLengthError = 0.0, maxDotTN = 0.0, maxAngleDeg = 0.0;
        for (size_t v = 0; v < mesh.vertexCount(); ++v) {
            const glm::vec3 n = mesh.normals[v];
            const glm::vec4 t = mesh.tangents[v];
            const glm::vec3 t3(t.x, t.y, t.z);
            maxLengthError = std::max(maxLengthError, double(std::abs(glm::length(t3) - 1.0f)));
            maxDotTN = std::max(maxDotTN, double(std::abs(glm::dot(t3, n))));

            // Surface-gradient path: basis, derivative, gradient, resolve.
            glm::vec3 vT, vB;
            sg::glsl::sgMikktsBasis(n, t, vT, vB);
            glm::vec2 deriv = sg::glsl::sgTspaceNormalToDeriv(glm::vec2(texel.x, texel.y), false);
            sg::glsl::SgFrame frame = sg::glsl::sgPrologue(n, vT, vB, true, SG_BFACE_NONE);
            glm::vec3 bumped =
                sg::glsl::sgResolve(frame, sg::glsl::sgSurfgradFromTBN(deriv, vT, vB));

            // Classic path: the TBN matrix times the texel.
            glm::vec3 b = t.w * glm::cross(n, t3);
            glm::vec3 classic = glm::normalize(texel.x * t3 + texel.y * b + texel.z * n);
            // atan2(|a x b|, a . b) in double: acos of a float dot product
            // cannot resolve angles below ~0.03 degrees.
            glm::dvec3 a(bumped), c(classic);
            double angle = std::atan2(glm::length(glm::cross(a, c)), glm::dot(a, c));
            maxAngleDeg = std::max(maxAngleDeg, angle * 180.0 / 3.14159265358979);
        }
        std::printf("mesh %s\n", argv[1]);
        std::printf("vertices %zu triangles %zu uv_set %d\n", mesh.vertexCount(),
                    mesh.triangleCount(), uvSet);
        std::printf("tangent max_length_error %.3g max_dot_normal %.3g\n", maxLengthError,
                    maxDotTN);
        std::printf("bump max_angle_deg_vs_tbn %.3g\n", maxAngleDeg);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "example_consumer_tangents: error: %s\n", e.what());
        return 1;
    }
}
