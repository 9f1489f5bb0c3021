// Fuzz entry point: OFF, PLY and STL input through OpenMesh's readers and
// our recording importer (mesh/src/openmesh_reader.cpp: header counts
// checked against the file size before OpenMesh sees them), then
// validation and, for what passes, describe(). OpenMesh's readers take a
// path, so the bytes go to a per-process temporary file whose extension is
// sniffed from the content ("ply" -> .ply, "OFF"-style header -> .off,
// anything else -> .stl, ASCII or binary): mutated headers then reach the
// other readers too. Documented errors (InputError) are expected; a crash,
// a hang, a sanitizer report, another exception or a non-finite position
// in an accepted mesh is a bug.
//
// Seed corpus (corpus/mesh_openmesh): small hand-written files: OFF with a
// quad and a triangle, ASCII and binary little-endian PLY, ASCII and binary
// STL.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"

namespace {

std::string extensionFor(std::string_view bytes) {
    if (bytes.substr(0, 3) == "ply") return ".ply";
    // OFF headers: OFF, COFF, NOFF, STOFF, 4OFF, ... (a prefix then OFF).
    const size_t off = bytes.substr(0, 8).find("OFF");
    if (off != std::string_view::npos) return ".off";
    return ".stl";
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    namespace fs = std::filesystem;
    using namespace sg::mesh;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const fs::path path = fs::temp_directory_path() /
                          ("surfgrad_fuzz_" + std::to_string(::getpid()) + extensionFor(bytes));
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        if (!out) std::abort(); // the harness, not the parser, failed
    }
    // Small limits keep each run fast; the limits themselves are tested.
    LoadOptions options;
    options.limits.maxVertices = 4096;
    options.limits.maxFaces = 4096;
    options.limits.maxCorners = 16384;
    options.limits.maxFaceDegree = 16;
    options.repair = size > 0 && (data[size - 1] & 1); // both validation paths
    try {
        PolygonMesh mesh = loadPolygonMesh(path, options);
        for (const auto& p : mesh.positions) {
            if (!std::isfinite(p.x + p.y + p.z))
                std::abort(); // validation promised finite positions
        }
        if (!describe(mesh).manifold) std::abort(); // validation promised manifold topology
    } catch (const sg::io::InputError&) {
    }
    std::error_code ec;
    fs::remove(path, ec);
    return 0;
}
