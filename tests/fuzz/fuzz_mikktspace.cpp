// libFuzzer entry for MikkTSpace (surfgrad/mesh/tangents.h): the bytes describe a
// small polygon soup on a coarse value grid (so exact ties, welds,
// degenerate and zero-area triangles, opposite frames and non-manifold
// edges are common); the fast generator (wide and narrow SIMD, with and
// without full frames) must equal the step-by-step oracle bit for bit, and
// no output may be NaN. Layout: byte 0 -> vertex count (3..34); then per
// vertex 8 bytes (position xyz and uv on a 5-step grid, normal from a
// 26-direction table); the rest are faces: a size byte (3, 4 or 5 corners)
// and that many vertex indices.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <glm/geometric.hpp>

#include "surfgrad/mesh/mikktspace_reference.h"
#include "surfgrad/mesh/tangents.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    size_t at = 0;
    const size_t vertexCount = 3 + data[at++] % 32;
    if (size < 1 + vertexCount * 8) return 0;
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs;
    auto grid = [](uint8_t b) { return float(int(b % 5) - 2) * 0.5f; };
    for (size_t v = 0; v < vertexCount; ++v, at += 8) {
        const uint8_t* b = data + at;
        positions.push_back({grid(b[0]), grid(b[1]), grid(b[2])});
        // One of the 26 directions to the neighbours of a cube cell (unit).
        int d = b[3] % 26;
        if (d >= 13) ++d; // skip (0,0,0)
        const glm::vec3 dir(float(d % 3 - 1), float(d / 3 % 3 - 1), float(d / 9 - 1));
        normals.push_back(glm::normalize(dir));
        uvs.push_back({grid(b[4]) + float(b[6] % 3), grid(b[5]) + float(b[7] % 3)});
    }
    std::vector<uint32_t> corners, faceSizes;
    while (at < size && corners.size() < 600) {
        const uint32_t n = 3 + data[at++] % 3;
        if (at + n > size) break;
        for (uint32_t k = 0; k < n; ++k) corners.push_back(data[at++] % uint32_t(vertexCount));
        faceSizes.push_back(n);
    }
    sg::mesh::MikkTSpaceInput in;
    in.positions = positions;
    in.normals = normals;
    in.uvs = uvs;
    in.cornerVertices = corners;
    in.faceSizes = faceSizes;
    const std::vector<sg::mesh::MikkTSpaceFrame> ref = sg::mesh::mikktspaceReferenceFrames(in);
    sg::mesh::MikkTSpaceGenerator wide, narrow;
    narrow.setWideSimd(false);
    std::vector<glm::vec4> a, b;
    std::vector<sg::mesh::MikkTSpaceFrame> frames;
    wide.generate(in, a, &frames);
    narrow.generate(in, b);
    for (size_t c = 0; c < ref.size(); ++c) {
        const glm::vec4 expected(ref[c].tangent, ref[c].sign);
        if (std::memcmp(&frames[c], &ref[c], sizeof ref[c]) != 0 ||
            std::memcmp(&a[c], &expected, sizeof expected) != 0 ||
            std::memcmp(&b[c], &expected, sizeof expected) != 0) {
            std::fprintf(stderr, "fast != oracle at corner %zu\n", c);
            std::abort();
        }
        for (int i = 0; i < 4; ++i)
            if (std::isnan(expected[i])) {
                std::fprintf(stderr, "NaN at corner %zu\n", c);
                std::abort();
            }
    }
    // Triangles only: the quad-free fast path (direct output, no frames).
    faceSizes.clear();
    corners.resize(corners.size() / 3 * 3);
    in.cornerVertices = corners;
    in.faceSizes = {};
    const std::vector<sg::mesh::MikkTSpaceFrame> ref3 = sg::mesh::mikktspaceReferenceFrames(in);
    wide.generate(in, a);
    narrow.generate(in, b);
    for (size_t c = 0; c < ref3.size(); ++c) {
        const glm::vec4 expected(ref3[c].tangent, ref3[c].sign);
        if (std::memcmp(&a[c], &expected, sizeof expected) != 0 ||
            std::memcmp(&b[c], &expected, sizeof expected) != 0) {
            std::fprintf(stderr, "fast != oracle at corner %zu (triangles)\n", c);
            std::abort();
        }
    }
    return 0;
}
