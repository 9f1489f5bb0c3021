// Fuzz entry point: the OBJ tokenizer with OpenSubdiv tag lines
// (sg::mesh::parseObj), validation with and without repair, and, for what
// passes, subdivision with limit evaluation. Documented errors (InputError)
// are expected; a crash, a hang, a sanitizer report, another exception or a
// non-finite output is a bug.
//
// Seed corpus (corpus/mesh_obj): five OpenSubdiv regression shapes copied
// from data/osd-shapes (modified Apache 2.0, see its LICENSE.txt)
// and one hand-written file with negative indices and every tag kind.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "surfgrad/io.h"
#include "surfgrad/mesh_io.h"
#include "surfgrad/subdivision.h"

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
