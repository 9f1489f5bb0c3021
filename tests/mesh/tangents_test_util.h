// Helpers shared by the tangent-frame tests: reading one glTF primitive with
// tinygltf (used directly so the tests do not depend on the mesh loaders'
// welding or normal fallbacks: the values MikkTSpace sees are the file's),
// and seeded generators of adversarial meshes for the oracle-vs-fast tests.
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "surfgrad/mesh/tangents.h"

namespace sg::test {

struct GltfPrimitive {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs; // (s, t) with t = 1 - v (surfgrad's t-up convention)
    std::vector<glm::vec4> tangents;
    std::vector<uint32_t> indices;
};

namespace detail {
template <typename T>
std::vector<T> readFloats(const tinygltf::Model& m, int accessorIndex) {
    const tinygltf::Accessor& a = m.accessors.at(size_t(accessorIndex));
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        throw std::runtime_error("accessor " + std::to_string(accessorIndex) + " is not float");
    const tinygltf::BufferView& bv = m.bufferViews.at(size_t(a.bufferView));
    const tinygltf::Buffer& b = m.buffers.at(size_t(bv.buffer));
    const size_t stride = bv.byteStride ? bv.byteStride : sizeof(T);
    std::vector<T> out(a.count);
    for (size_t i = 0; i < a.count; ++i)
        std::memcpy(&out[i], b.data.data() + bv.byteOffset + a.byteOffset + i * stride, sizeof(T));
    return out;
}
} // namespace detail

// Primitive `primitive` of mesh `mesh` of a .gltf file.
inline GltfPrimitive readGltfPrimitive(const std::string& path, int mesh = 0, int primitive = 0) {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    if (!loader.LoadASCIIFromFile(&model, &err, &warn, path))
        throw std::runtime_error(path + ": " + err);
    const tinygltf::Primitive& p = model.meshes.at(size_t(mesh)).primitives.at(size_t(primitive));
    GltfPrimitive out;
    auto attr = [&](const char* name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    };
    out.positions = detail::readFloats<glm::vec3>(model, attr("POSITION"));
    out.normals = detail::readFloats<glm::vec3>(model, attr("NORMAL"));
    out.uvs = detail::readFloats<glm::vec2>(model, attr("TEXCOORD_0"));
    for (glm::vec2& t : out.uvs) t.y = 1.0f - t.y;
    if (attr("TANGENT") >= 0) out.tangents = detail::readFloats<glm::vec4>(model, attr("TANGENT"));
    const tinygltf::Accessor& ia = model.accessors.at(size_t(p.indices));
    const tinygltf::BufferView& bv = model.bufferViews.at(size_t(ia.bufferView));
    const unsigned char* base =
        model.buffers.at(size_t(bv.buffer)).data.data() + bv.byteOffset + ia.byteOffset;
    out.indices.resize(ia.count);
    for (size_t i = 0; i < ia.count; ++i) {
        switch (ia.componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t v;
            std::memcpy(&v, base + 2 * i, 2);
            out.indices[i] = v;
            break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            std::memcpy(&out.indices[i], base + 4 * i, 4);
            break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            out.indices[i] = base[i];
            break;
        default:
            throw std::runtime_error("unsupported index type");
        }
    }
    return out;
}

// A polygon soup for MikkTSpaceInput, owning its arrays.
struct SoupMesh {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs;
    std::vector<uint32_t> corners;
    std::vector<uint32_t> faceSizes; // empty: triangles
};

// The generator's view of a soup or a glTF primitive (spans into it: the
// mesh must outlive the input).
inline sg::mesh::MikkTSpaceInput inputOf(const SoupMesh& m) {
    sg::mesh::MikkTSpaceInput in;
    in.positions = m.positions;
    in.normals = m.normals;
    in.uvs = m.uvs;
    in.cornerVertices = m.corners;
    in.faceSizes = m.faceSizes;
    return in;
}
inline sg::mesh::MikkTSpaceInput inputOf(const GltfPrimitive& p) {
    sg::mesh::MikkTSpaceInput in;
    in.positions = p.positions;
    in.normals = p.normals;
    in.uvs = p.uvs;
    in.cornerVertices = p.indices;
    return in;
}

// What the adversarial generator puts in.
struct SoupOptions {
    int gridX = 8, gridY = 6;          // vertex grid (a bumpy height field)
    float quadFraction = 0.0f;         // cells kept as quads instead of 2 triangles
    float mirrorFraction = 0.1f;       // cells whose UVs are mirrored in s
    float seamFraction = 0.1f;         // cells with their own (split) UV copies
    float degenerateFraction = 0.05f;  // cells with a corner moved onto another
    float zeroUvFraction = 0.05f;      // cells whose UVs collapse (zero area)
    float flipFraction = 0.0f;         // cells with reversed winding (inconsistent orientation)
    float duplicateFraction = 0.0f;    // cells emitted twice (3+ faces per edge)
    float otherPolygonFraction = 0.0f; // pentagons (ignored by MikkTSpace)
    int quantize = 4;                  // UV/position grid steps: many exact ties
    int isolatedVertices = 3;          // vertices no face uses
};

// A seeded random height field with the requested defects. Values are
// quantized so equal values (welding, ties in the quad diagonal rule,
// exactly opposite frames) happen often.
inline SoupMesh randomSoup(uint32_t seed, const SoupOptions& o) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    auto q = [&](float v) { return std::round(v * float(o.quantize)) / float(o.quantize); };
    SoupMesh m;
    const int nx = o.gridX, ny = o.gridY;
    auto vid = [&](int x, int y) { return uint32_t(y * nx + x); };
    for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
            m.positions.push_back({float(x), float(y), q(u01(rng) * 0.75f)});
            const glm::vec3 n = glm::normalize(
                glm::vec3(q(u01(rng) - 0.5f) * 0.5f, q(u01(rng) - 0.5f) * 0.5f, 1.0f));
            m.normals.push_back(n);
            m.uvs.push_back({q(float(x) * 0.25f), q(float(y) * 0.25f)});
        }
    auto copyVertex = [&](uint32_t v) {
        m.positions.push_back(m.positions[v]);
        m.normals.push_back(m.normals[v]);
        m.uvs.push_back(m.uvs[v]);
        return uint32_t(m.positions.size() - 1);
    };
    for (int y = 0; y + 1 < ny; ++y)
        for (int x = 0; x + 1 < nx; ++x) {
            uint32_t c[4] = {vid(x, y), vid(x + 1, y), vid(x + 1, y + 1), vid(x, y + 1)};
            const float pick = u01(rng);
            if (pick < o.mirrorFraction + o.seamFraction + o.zeroUvFraction) {
                // Own copies (a UV seam around the cell), then alter their UVs.
                for (uint32_t& v : c) v = copyVertex(v);
                if (pick < o.mirrorFraction) {
                    for (uint32_t v : c) m.uvs[v].x = q(3.0f - m.uvs[v].x); // mirrored in s
                } else if (pick < o.mirrorFraction + o.seamFraction) {
                    const glm::vec2 shift(q(u01(rng)), 0.25f); // another island
                    for (uint32_t v : c) m.uvs[v] += shift;
                } else if (u01(rng) < 0.5f) {
                    for (uint32_t v : c) m.uvs[v] = m.uvs[c[0]]; // zero UV area
                } else {
                    for (uint32_t v : c) m.uvs[v].y = m.uvs[c[0]].y; // collapsed to a line
                }
            }
            if (u01(rng) < o.degenerateFraction) {
                const uint32_t moved = copyVertex(c[1]);
                m.positions[moved] = m.positions[c[0]];
                c[1] = moved;
            }
            if (u01(rng) < o.flipFraction) std::swap(c[1], c[3]);
            const int copies = u01(rng) < o.duplicateFraction ? 2 : 1;
            for (int k = 0; k < copies; ++k) {
                if (u01(rng) < o.otherPolygonFraction) {
                    const uint32_t extra = copyVertex(c[0]);
                    m.positions[extra] += glm::vec3(-0.25f, -0.25f, 0.0f);
                    m.corners.insert(m.corners.end(), {c[0], extra, c[1], c[2], c[3]});
                    m.faceSizes.push_back(5);
                } else if (u01(rng) < o.quadFraction) {
                    m.corners.insert(m.corners.end(), {c[0], c[1], c[2], c[3]});
                    m.faceSizes.push_back(4);
                } else {
                    const bool diag = u01(rng) < 0.5f;
                    if (diag) {
                        m.corners.insert(m.corners.end(), {c[0], c[1], c[2], c[0], c[2], c[3]});
                    } else {
                        m.corners.insert(m.corners.end(), {c[0], c[1], c[3], c[1], c[2], c[3]});
                    }
                    m.faceSizes.push_back(3);
                    m.faceSizes.push_back(3);
                }
            }
        }
    for (int i = 0; i < o.isolatedVertices; ++i)
        m.positions.push_back({-1.0f, float(i), 0.0f}), m.normals.push_back({0, 0, 1}),
            m.uvs.push_back({0.0f, 0.0f});
    // Triangle-only soups drop the face sizes (the triangles-only fast path).
    bool allTriangles = true;
    for (uint32_t n : m.faceSizes) allTriangles &= n == 3;
    if (allTriangles) m.faceSizes.clear();
    return m;
}

} // namespace sg::test
