// Fuzz entry point: the OBJ tokenizer with OpenSubdiv tag lines
// (sg::mesh::parseObj), validation with and without repair, and, for what
// passes, subdivision with limit evaluation. Documented errors (InputError)
// are expected; a crash, a hang, a sanitizer report, another exception or a
// non-finite output is a bug, and so is a difference between the serial
// reader and the block reader of several threads (parseObjInBlocks, blocks
// of a few bytes): another mesh, other face lines or another message.
//
// Seed corpus (corpus/mesh_obj): five OpenSubdiv regression shapes copied
// from data/osd-shapes (modified Apache 2.0, see its LICENSE.txt)
// and one hand-written file with negative indices and every tag kind.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The serial reader and the block reader (2 threads, blocks of 1 + the
// last byte % 61 bytes) read `text` alike, or the process aborts.
void compareReaders(std::string_view text, const sg::mesh::InputLimits& limits) {
    using namespace sg::mesh;
    struct Outcome {
        PolygonMesh mesh;
        std::vector<uint32_t> lines;
        std::vector<std::string> notes;
        std::string error;
    } o[2];
    const size_t blockBytes = 1 + (text.empty() ? 0 : size_t(uint8_t(text.back())) % 61);
    for (int k = 0; k < 2; ++k) {
        LoadReport report;
        try {
            o[k].mesh = detail::parseObjInBlocks(text, "fuzz.obj", limits, &report, 2,
                                                 k == 0 ? 0 : blockBytes, &o[k].lines);
            o[k].notes = report.notes;
        } catch (const sg::io::InputError& e) {
            o[k].error = e.what();
        }
    }
    const PolygonMesh &a = o[0].mesh, &b = o[1].mesh;
    bool same = o[0].error == o[1].error && o[0].lines == o[1].lines && o[0].notes == o[1].notes &&
                sameBytes(a.positions, b.positions) && sameBytes(a.faceSizes, b.faceSizes) &&
                sameBytes(a.faceVertices, b.faceVertices) && sameBytes(a.normals, b.normals) &&
                sameBytes(a.normalIndices, b.normalIndices) && sameBytes(a.creases, b.creases) &&
                sameBytes(a.corners, b.corners) && sameBytes(a.holes, b.holes) &&
                a.uvSets.size() == b.uvSets.size() && a.explicitTags == b.explicitTags &&
                std::memcmp(&a.options, &b.options, sizeof a.options) == 0;
    for (size_t s = 0; same && s < a.uvSets.size(); ++s) {
        same = sameBytes(a.uvSets[s].values, b.uvSets[s].values) &&
               sameBytes(a.uvSets[s].indices, b.uvSets[s].indices);
    }
    if (!same) std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace sg::mesh;
    // Small limits keep each run fast; the limits themselves are tested.
    InputLimits limits;
    limits.maxVertices = 4096;
    limits.maxFaces = 4096;
    limits.maxCorners = 16384;
    limits.maxFaceDegree = 16;
    try {
        std::string_view text(reinterpret_cast<const char*>(data), size);
        compareReaders(text, limits);
        PolygonMesh mesh = parseObj(text, "fuzz.obj", limits);
        // The first byte picks repair or not, so both paths are reached.
        validate(mesh, "fuzz.obj", size > 0 && (data[0] & 1), nullptr, limits);
        MeshInfo info = describe(mesh);
        if (!info.manifold) std::abort(); // validate() promised manifold topology
        SubdivisionSettings s;
        s.options = mesh.options;
        s.level = 1;
        s.limit = true;
        s.maxRefinedFaces = 1 << 16;
        Subdivider sub(mesh, s, "fuzz.obj");
        for (const auto& p : sub.renderMesh().positions) {
            if (!std::isfinite(p.x + p.y + p.z)) std::abort();
        }
        for (const auto& n : sub.renderMesh().normals) {
            if (!std::isfinite(n.x + n.y + n.z)) std::abort();
        }
        for (const auto& d : sub.limitFrame().dPdu) {
            if (!std::isfinite(d.x + d.y + d.z)) std::abort();
        }
    } catch (const sg::io::InputError&) {
    }
    return 0;
}
