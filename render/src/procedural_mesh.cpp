// The procedural meshes of a scene's "procedural" field (docs/scene.md):
// planes, spheres, tori, terrain grids and the other generators, with
// their UV sets; every triangle counter-clockwise around its vertex
// normals.
#include <algorithm>
#include <cmath>

#include "render_internal.h"
#include "surfgrad/render.h"
#include "surfgrad/render/render_shaders.h" // the terrain's fBm (sg/render/noise.glsl)

namespace sg::render::detail {

namespace {

constexpr float kPi = 3.14159265358979f;

// Makes every triangle counter-clockwise around the average of its vertex
// normals (the generators below then need not track winding by hand).
void orientTriangles(sg::mesh::RenderMesh& m) {
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
        glm::vec3 n = glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
        glm::vec3 vn = m.normals[a] + m.normals[b] + m.normals[c];
        if (glm::dot(n, vn) < 0.0f) std::swap(m.indices[t + 1], m.indices[t + 2]);
    }
}

// A (nu+1) x (nv+1) vertex grid over (u, v) in [0,1]^2 from a callback
// giving position, normal and uv; two triangles per cell.
template <class F>
void addGrid(sg::mesh::RenderMesh& m, int nu, int nv, F&& f) {
    uint32_t base = uint32_t(m.positions.size());
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            glm::vec3 p, n;
            glm::vec2 uv;
            f(float(i) / float(nu), float(j) / float(nv), p, n, uv);
            m.positions.push_back(p);
            m.normals.push_back(n);
            m.uvSets[0].push_back(uv);
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            uint32_t a = base + uint32_t(j * (nu + 1) + i), b = a + 1, c = a + uint32_t(nu + 1),
                     d = c + 1;
            for (uint32_t x : {a, b, d, a, d, c}) m.indices.push_back(x);
        }
}

// Height of the procedural terrain over (x, z) in units of its edge:
// fBm (the shared noise, CPU build) with its analytic gradient.
glm::vec3 terrainHeight(float x, float z, float relief) {
    glm::vec4 n = sg::glsl::sgNoiseOctaves(SG_NOISE_FBM, glm::vec3(x * 3.0f, 0.37f, z * 3.0f), 6,
                                           2.0f, 0.5f, 0.0f);
    // n = (value, d/dx, d/dy, d/dz) w.r.t. the scaled argument.
    return glm::vec3(relief * n.x, relief * 3.0f * n.y, relief * 3.0f * n.w);
}

} // namespace

sg::mesh::RenderMesh makeProceduralMesh(const Procedural& p) {
    sg::mesh::RenderMesh m;
    m.name = p.type;
    m.uvSets.resize(1);
    const int seg = p.segments;
    if (p.type == "sphere") {
        float r = p.size;
        addGrid(m, seg, std::max(2, seg / 2),
                [&](float u, float v, glm::vec3& pos, glm::vec3& n, glm::vec2& uv) {
                    float phi = 2.0f * kPi * u, theta = kPi * v; // theta from the south pole
                    n = glm::vec3(std::sin(theta) * std::cos(phi), -std::cos(theta),
                                  -std::sin(theta) * std::sin(phi));
                    pos = r * n;
                    uv = glm::vec2(u, v);
                });
        // Pole rows are degenerate (zero-area triangles): drop them.
        std::vector<uint32_t> keep;
        for (size_t t = 0; t < m.indices.size(); t += 3) {
            glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                      c = m.positions[m.indices[t + 2]];
            if (glm::length(glm::cross(b - a, c - a)) > 1e-12f * r * r) {
                keep.insert(keep.end(), {m.indices[t], m.indices[t + 1], m.indices[t + 2]});
            }
        }
        m.indices = std::move(keep);
    } else if (p.type == "plane") {
        float s = p.size;
        addGrid(m, seg, seg, [&](float u, float v, glm::vec3& pos, glm::vec3& n, glm::vec2& uv) {
            pos = glm::vec3((u - 0.5f) * s, 0.0f, (0.5f - v) * s);
            n = glm::vec3(0, 1, 0);
            uv = glm::vec2(u, v);
        });
    } else if (p.type == "terrain") {
        float s = p.size;
        addGrid(m, seg, seg, [&](float u, float v, glm::vec3& pos, glm::vec3& n, glm::vec2& uv) {
            float x = u - 0.5f, z = 0.5f - v;
            glm::vec3 h = terrainHeight(x, z, p.terrainHeight / s);
            pos = glm::vec3(x * s, h.x * s, z * s);
            n = glm::normalize(glm::vec3(-h.y, 1.0f, -h.z));
            uv = glm::vec2(u, v);
        });
    } else if (p.type == "torus") {
        float R = p.size, r = p.minorRadius;
        addGrid(m, seg, std::max(3, seg / 2),
                [&](float u, float v, glm::vec3& pos, glm::vec3& n, glm::vec2& uv) {
                    float a = 2.0f * kPi * u, b = 2.0f * kPi * v;
                    glm::vec3 ring(std::cos(a), 0.0f, -std::sin(a));
                    n = std::cos(b) * ring + glm::vec3(0.0f, std::sin(b), 0.0f);
                    pos = R * ring + r * n;
                    uv = glm::vec2(u, v);
                });
    } else { // cube
        float h = 0.5f * p.size;
        int n = std::max(1, seg / 8);
        for (int face = 0; face < 6; ++face) {
            int axis = face / 2;
            float sgn = face % 2 ? -1.0f : 1.0f;
            glm::vec3 nrm(0.0f);
            nrm[axis] = sgn;
            // (tu, tv) span the face so that tu x tv = nrm.
            glm::vec3 tu(0.0f), tv(0.0f);
            tu[(axis + 1) % 3] = 1.0f;
            tv[(axis + 2) % 3] = 1.0f;
            if (glm::dot(glm::cross(tu, tv), nrm) < 0.0f) tu = -tu;
            addGrid(m, n, n, [&](float u, float v, glm::vec3& pos, glm::vec3& nn, glm::vec2& uv) {
                pos = h * (nrm + (2.0f * u - 1.0f) * tu + (2.0f * v - 1.0f) * tv);
                nn = nrm;
                uv = glm::vec2(u, v);
            });
        }
    }
    orientTriangles(m);
    for (int k = 1; k < p.uvSets; ++k) {
        m.uvSets.push_back(m.uvSets[0]);
        for (auto& uv : m.uvSets.back()) uv *= 4.0f;
    }
    return m;
}

} // namespace sg::render::detail
