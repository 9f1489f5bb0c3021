// Trivial helpers of PolygonMesh (surfgrad/mesh/polygon_mesh.h): face offsets and
// the names of the subdivision options (as the CLI and the OBJ tags spell
// them).
#include "surfgrad/mesh/polygon_mesh.h"

#include <array>
#include <cstring>

namespace sg::mesh {

std::vector<uint32_t> faceOffsets(const PolygonMesh& mesh) {
    std::vector<uint32_t> offsets(mesh.faceSizes.size() + 1);
    uint32_t sum = 0;
    for (size_t f = 0; f < mesh.faceSizes.size(); ++f) {
        offsets[f] = sum;
        sum += mesh.faceSizes[f];
    }
    offsets.back() = sum;
    return offsets;
}

namespace {
constexpr std::array<const char*, 3> kSchemeNames{"catmark", "loop", "bilinear"};
constexpr std::array<const char*, 3> kBoundaryNames{"none", "edge-only", "edge-and-corner"};
constexpr std::array<const char*, 6> kFVarNames{"smooth",        "corners-only", "corners-plus1",
                                                "corners-plus2", "boundaries",   "all"};

template <class E, size_t N>
bool parseName(const std::array<const char*, N>& names, const std::string& name, E& out) {
    for (size_t i = 0; i < N; ++i) {
        if (name == names[i]) {
            out = E(i);
            return true;
        }
    }
    return false;
}
} // namespace

const char* toString(Scheme scheme) {
    return kSchemeNames[size_t(scheme)];
}
const char* toString(BoundaryInterpolation rule) {
    return kBoundaryNames[size_t(rule)];
}
const char* toString(FVarInterpolation rule) {
    return kFVarNames[size_t(rule)];
}

bool parseScheme(const std::string& name, Scheme& out) {
    return parseName(kSchemeNames, name, out);
}
bool parseFVarInterpolation(const std::string& name, FVarInterpolation& out) {
    return parseName(kFVarNames, name, out);
}
bool parseBoundaryInterpolation(const std::string& name, BoundaryInterpolation& out) {
    return parseName(kBoundaryNames, name, out);
}

} // namespace sg::mesh
