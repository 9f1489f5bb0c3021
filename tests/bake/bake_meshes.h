// Meshes with known answers for the bake tests: a flat quad-grid cage whose
// limit surface is its own plane (with UVs equal to x, y), a cube cage with
// one UV chart per face (seams on every edge), height-field and sphere high
// meshes with analytic normals.
#pragma once

#include <cmath>
#include <functional>
#include <numbers>

#include <glm/geometric.hpp>

#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/render_mesh.h"

namespace sg::test {

// n x n quads over [0,1]^2 at z = 0, UV = (x, y), boundary edge-and-corner:
// a uniform B-spline grid with linear boundary rules reproduces linear data
// (linear precision), so the limit surface is the square itself and its
// limit UV at (x, y, 0) is (x, y).
inline mesh::PolygonMesh planeCage(int n) {
    mesh::PolygonMesh m;
    m.options.boundary = mesh::BoundaryInterpolation::EdgeAndCorner;
    mesh::FaceVaryingChannel uv;
    uv.name = "uv";
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const glm::vec2 p(float(i) / float(n), float(j) / float(n));
            m.positions.emplace_back(p.x, p.y, 0.0f);
            uv.values.push_back(p);
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t v0 = uint32_t(j * (n + 1) + i);
            for (uint32_t v : {v0, v0 + 1, v0 + uint32_t(n) + 2, v0 + uint32_t(n) + 1}) {
                m.faceVertices.push_back(v);
                uv.indices.push_back(v);
            }
            m.faceSizes.push_back(4);
        }
    m.uvSets.push_back(std::move(uv));
    return m;
}

// The cube [-1,1]^3 as 6 quads (counter-clockwise from outside), face f's
// UV chart the square [0.05 + 0.32 (f % 3), +0.28] x [0.05 + 0.5 (f / 3),
// +0.4] of a 3 x 2 atlas: every cube edge is a UV seam.
inline mesh::PolygonMesh cubeCage() {
    mesh::PolygonMesh m;
    for (int k = 0; k < 8; ++k)
        m.positions.emplace_back(k & 1 ? 1.0f : -1.0f, k & 2 ? 1.0f : -1.0f, k & 4 ? 1.0f : -1.0f);
    const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    mesh::FaceVaryingChannel uv;
    uv.name = "uv";
    for (int f = 0; f < 6; ++f) {
        const glm::vec2 lo(0.05f + 0.32f * float(f % 3), 0.05f + 0.5f * float(f / 3));
        const glm::vec2 size(0.28f, 0.4f);
        const glm::vec2 corner[4] = {lo, lo + glm::vec2(size.x, 0), lo + size,
                                     lo + glm::vec2(0, size.y)};
        for (int c = 0; c < 4; ++c) {
            m.faceVertices.push_back(faces[f][c]);
            uv.indices.push_back(uint32_t(uv.values.size()));
            uv.values.push_back(corner[c]);
        }
        m.faceSizes.push_back(4);
    }
    m.uvSets.push_back(std::move(uv));
    return m;
}

// z = h(x, y) on an (n + 1)^2 grid over [lo, hi]^2, split along one
// diagonal, with the analytic unit normals normalize(-dh/dx, -dh/dy, 1).
inline mesh::RenderMesh heightFieldMesh(int n, float lo, float hi,
                                        const std::function<double(double, double)>& h,
                                        const std::function<glm::dvec2(double, double)>& grad) {
    mesh::RenderMesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = lo + (hi - lo) * double(i) / n, y = lo + (hi - lo) * double(j) / n;
            m.positions.emplace_back(float(x), float(y), float(h(x, y)));
            const glm::dvec2 g = grad(x, y);
            m.normals.push_back(glm::vec3(glm::normalize(glm::dvec3(-g.x, -g.y, 1.0))));
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t v0 = uint32_t(j * (n + 1) + i), v1 = v0 + 1, v2 = v0 + uint32_t(n) + 2,
                           v3 = v0 + uint32_t(n) + 1;
            for (uint32_t v : {v0, v1, v2, v0, v2, v3}) m.indices.push_back(v);
        }
    return m;
}

// A UV sphere of radius r about the origin: `rings` x 2 `rings` quads split
// into triangles, analytic normals (the unit position).
inline mesh::RenderMesh sphereMesh(int rings, double r) {
    mesh::RenderMesh m;
    const int seg = 2 * rings;
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i <= seg; ++i) {
            const double th = std::numbers::pi * j / rings, ph = 2 * std::numbers::pi * i / seg;
            const glm::dvec3 n(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                               std::cos(th));
            m.positions.push_back(glm::vec3(r * n));
            m.normals.push_back(glm::vec3(n));
        }
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < seg; ++i) {
            const uint32_t v0 = uint32_t(j * (seg + 1) + i), v1 = v0 + 1,
                           v2 = v0 + uint32_t(seg) + 2, v3 = v0 + uint32_t(seg) + 1;
            // Counter-clockwise seen from outside: theta grows downwards.
            for (uint32_t v : {v0, v3, v2, v0, v2, v1}) m.indices.push_back(v);
        }
    return m;
}

} // namespace sg::test
