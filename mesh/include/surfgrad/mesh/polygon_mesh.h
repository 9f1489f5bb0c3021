// PolygonMesh: an indexed polygon mesh with face-varying UV sets and
// OpenSubdiv subdivision tags (creases, corners, holes, boundary rules). It is
// what the loaders produce (a control cage), what the subdivider consumes and
// produces (the refined polygons of level N) and what the OBJ/PLY writers
// take. Plain data, no behaviour beyond trivial helpers; loaders, validation
// and writers are in surfgrad/mesh/mesh_io.h, refinement in surfgrad/mesh/subdivision.h.
//
// Tag semantics follow OpenSubdiv's Sdc (docs: "Subdivision Surfaces",
// "Sharpness and creases") and its regression shapes' OBJ "t" lines
// (regression/common/far_utils.h; data/osd-shapes/README.md).
//
// Conventions (shared with surfgrad/mesh/render_mesh.h):
//  - positions in object space, right-handed, units of the source file;
//  - faces are counter-clockwise seen from the front (outside);
//  - texture coordinates (s,t): (0,0) is the LOWER-left corner of the image,
//    t up (OpenGL and OBJ convention; glTF's v is flipped on load, t = 1 - v);
//  - every index is 0-based.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace sg::mesh {

// Sharpness at or above this is "infinitely sharp"
// (OpenSubdiv Sdc::Crease::SHARPNESS_INFINITE).
inline constexpr float kInfiniteSharpness = 10.0f;

enum class Scheme : uint8_t {
    Catmark,  // Catmull-Clark: any polygons, quads after one level
    Loop,     // Loop: triangles only
    Bilinear, // bilinear: any polygons, the limit surface is the cage's bilinear patches
};

// Boundary rule for vertex data ("t interpolateboundary k": 0 None,
// 1 EdgeAndCorner, 2 EdgeOnly).
enum class BoundaryInterpolation : uint8_t {
    None,          // boundary faces are not part of the limit surface
    EdgeOnly,      // boundary edges are infinitely sharp creases
    EdgeAndCorner, // ... and boundary vertices of valence 2 are sharp corners
};

// Face-varying (UV) interpolation ("t facevaryinginterpolateboundary k",
// k = the enum's value): how UV seams and UV boundaries are refined.
enum class FVarInterpolation : uint8_t {
    Smooth = 0,       // smooth everywhere, UV boundaries included ("none")
    CornersOnly = 1,  // linear at UV corners
    CornersPlus1 = 2, // ... plus junctions of 3+ UV regions (USD's default)
    CornersPlus2 = 3, // ... plus concave corners
    Boundaries = 4,   // linear along every UV boundary
    All = 5,          // linear everywhere (UVs are not smoothed at all)
};

enum class CreaseMethod : uint8_t { Uniform, Chaikin }; // "t creasemethod normal|chaikin"
enum class TriangleRule : uint8_t { Catmark, Smooth };  // "t smoothtriangles catmark" = Smooth

struct SubdivOptions {
    Scheme scheme = Scheme::Catmark;
    BoundaryInterpolation boundary = BoundaryInterpolation::EdgeOnly;
    FVarInterpolation fvar = FVarInterpolation::CornersPlus1;
    CreaseMethod creaseMethod = CreaseMethod::Uniform;
    TriangleRule triangles = TriangleRule::Catmark;
};

// Which SubdivOptions fields the file set explicitly (bit per field); a
// command-line flag overrides a file tag, a file tag overrides the default.
enum SubdivTagBits : uint32_t {
    kTagScheme = 1u << 0,
    kTagBoundary = 1u << 1,
    kTagFVar = 1u << 2,
    kTagCreaseMethod = 1u << 3,
    kTagTriangles = 1u << 4,
};

// One UV set: values plus one value index per face corner, so a vertex may
// carry different UVs in different faces (UV seams).
struct FaceVaryingChannel {
    std::string name;              // "TEXCOORD_0", "vt", ...
    std::vector<glm::vec2> values; // (s,t), t up
    std::vector<uint32_t> indices; // faceVertices.size() entries, each < values.size()
};

// Edge between two vertices (order irrelevant); sharpness in Sdc units
// (0 smooth, each unit keeps the edge sharp for one refinement level,
// >= kInfiniteSharpness infinitely sharp).
struct EdgeCrease {
    uint32_t v0 = 0, v1 = 0;
    float sharpness = 0.0f;
};

struct VertexCorner {
    uint32_t vertex = 0;
    float sharpness = 0.0f; // same units as EdgeCrease::sharpness
};

// Morph target of a cage: per-vertex position offsets, object space.
struct CageMorphTarget {
    std::string name;
    std::vector<glm::vec3> positionDeltas; // positions.size() entries
};

struct PolygonMesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> faceSizes;    // corners per face (>= 3)
    std::vector<uint32_t> faceVertices; // sum(faceSizes) vertex indices, CCW per face
    std::vector<FaceVaryingChannel> uvSets;

    // Optional face-varying normals (OBJ vn, glTF NORMAL): unit vectors in
    // object space; normalIndices is empty or has faceVertices.size() entries.
    std::vector<glm::vec3> normals;
    std::vector<uint32_t> normalIndices;

    std::vector<EdgeCrease> creases;
    std::vector<VertexCorner> corners;
    std::vector<uint32_t> holes; // face indices, sorted, unique

    SubdivOptions options;
    uint32_t explicitTags = 0; // SubdivTagBits set by the file

    std::vector<CageMorphTarget> morphTargets;
    std::vector<float> morphWeights; // default weights, one per target

    size_t vertexCount() const { return positions.size(); }
    size_t faceCount() const { return faceSizes.size(); }
    size_t cornerCount() const { return faceVertices.size(); }
};

// Offset of each face's first corner in faceVertices (faceCount() + 1
// entries, the last one == cornerCount()).
std::vector<uint32_t> faceOffsets(const PolygonMesh& mesh);

const char* toString(Scheme scheme);              // "catmark" | "loop" | "bilinear"
const char* toString(BoundaryInterpolation rule); // "none" | "edge-only" | "edge-and-corner"
const char* toString(FVarInterpolation rule);     // "smooth" | "corners-only" | ... | "all"
// Parse the same names; return false for an unknown name.
bool parseScheme(const std::string& name, Scheme& out);
bool parseFVarInterpolation(const std::string& name, FVarInterpolation& out);
bool parseBoundaryInterpolation(const std::string& name, BoundaryInterpolation& out);

} // namespace sg::mesh
