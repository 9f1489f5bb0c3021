// Mesh input and output: loaders for OBJ (with OpenSubdiv tag lines), OFF,
// PLY, STL (through OpenMesh's readers) and glTF 2.0 (.gltf/.glb, through
// tinygltf); validation and repair; writers for OBJ, PLY and glTF.
//
// Every loader treats its input as untrusted (docs/architecture.md,
// "Errors"): sizes are checked against InputLimits before anything is
// allocated, and every problem throws sg::io::InputError naming the file,
// the element (line, face, vertex, accessor, ...) and the reason. A loaded
// mesh has passed validate(): no NaN/Inf, every index in range, no empty
// mesh, no degenerate face, manifold and consistently oriented.
//
// Formats:
//  - .obj  own tokenizer (OpenMesh's OBJ reader neither reads "t" tags nor
//          keeps faces at non-manifold edges: it drops them silently).
//          v, vt, vn, f (negative indices allowed), "t" tags: crease,
//          corner, hole, interpolateboundary, facevaryinginterpolateboundary,
//          creasemethod, smoothtriangles, plus our own "t scheme 0/0/1
//          catmark|loop|bilinear". Other statements (o, g, s, usemtl, mtllib,
//          l, p, ...) are ignored and counted in LoadReport::notes.
//  - .off .ply .stl  OpenMesh::IO into a recording importer that keeps every
//          face as written (OpenMesh's PolyMesh would drop faces at complex
//          edges/vertices silently; this way validate() sees and names them).
//          PLY per-vertex texture coordinates become UV set 0.
//  - .gltf .glb  tinygltf: every triangle primitive (modes 4/5/6), POSITION,
//          NORMAL, TANGENT, every TEXCOORD_n (normalized integer types
//          accepted), morph targets (POSITION/NORMAL/TANGENT deltas), default
//          weights, weight animations, node transforms, materials.
//          Images are never decoded: materials keep texture paths.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/render_mesh.h"

namespace sg::mesh {

// Upper bounds checked before allocating (a file that declares more is
// refused with InputError, not truncated).
// Process-wide default of InputLimits::allowOutsideFolder: false until set.
// The CLI sets it from --allow-outside-uris before it loads anything; a
// library user sets the field per call instead.
void setAllowOutsideFolderDefault(bool allow);
bool allowOutsideFolderDefault();

struct InputLimits {
    size_t maxFileBytes = size_t(1) << 30; // 1 GiB (also per glTF buffer)
    size_t maxVertices = size_t(1) << 25;  // 33.5 M
    size_t maxFaces = size_t(1) << 25;
    size_t maxCorners = size_t(1) << 27; // face-vertex entries
    uint32_t maxFaceDegree = 256;        // corners of one polygon
    size_t maxUvSets = 8;
    size_t maxMorphTargets = 64;
    // glTF buffer and image URIs must resolve inside the model's folder
    // (sg::io::isInsideFolder: no "..", absolute path or symbolic link out of
    // it), so a downloaded model cannot read or point at other files; true
    // lifts that rule (the CLI's --allow-outside-uris).
    bool allowOutsideFolder = allowOutsideFolderDefault();
};

// What a loader (or validate with repair) did besides the obvious. Nothing
// is dropped or changed silently: every change is counted here.
struct LoadReport {
    std::vector<std::string> notes;     // one human-readable line each
    size_t degenerateFacesDropped = 0;  // repair only
    size_t duplicateVerticesWelded = 0; // repair only (bitwise-equal positions)
    size_t isolatedVertices = 0;        // vertices no face uses (kept)
    bool changed() const { return degenerateFacesDropped + duplicateVerticesWelded > 0; }
};

struct LoadOptions {
    bool repair = false; // see validate()
    // Threads for reading (surfgrad/base/threads.h: 0 = all cores, 1 = the
    // calling thread only, 2..1024 an arena): an OBJ of at least
    // kObjParallelMinBytes is read and parsed in blocks on several threads.
    // The mesh, the report and every error message are the same for every
    // count. 0 <= threads <= kMaxThreads (a contract).
    int threads = 0;
    // Accept non-manifold topology (edges with 3+ faces, bowtie vertices,
    // inconsistent orientation) instead of throwing; only `mesh info` uses
    // this, to describe such files. Everything else is still checked.
    bool allowNonManifold = false;
    InputLimits limits;
};

// ---- Validation ------------------------------------------------------------

// Checks `mesh` (file = its path, for messages) and throws InputError for the
// first problem found, element naming the face/vertex/tag:
//  - empty mesh (no vertices or no faces);
//  - NaN/Inf in positions, UVs, normals, sharpness or morph deltas; negative
//    sharpness;
//  - out-of-range vertex/UV/normal indices, face sizes < 3 or above the
//    limit, array sizes that disagree;
//  - degenerate faces: a vertex repeated within one face, or a zero Newell
//    area (all corners coincident or collinear);
//  - non-manifold edges (used by more than two faces, or twice in the same
//    direction = inconsistent orientation) and non-manifold vertices (faces
//    around the vertex form more than one fan);
//  - crease tags naming a pair of vertices that is not an edge; corner or
//    hole tags out of range.
// With repair = true, first (1) welds vertices whose positions are bitwise
// equal (and whose morph deltas are equal), (2) drops degenerate faces, then
// (3) drops vertices no face uses only if welding created them, and then
// checks; changes are counted in `report`. Non-manifold topology has no
// single honest fix and is always an error. Isolated vertices (no face) are
// kept and counted: OpenSubdiv carries them through refinement unchanged.
void validate(PolygonMesh& mesh, const std::string& file, bool repair = false,
              LoadReport* report = nullptr, const InputLimits& limits = {},
              bool allowNonManifold = false);

// Topology summary for `mesh info`; works on non-manifold meshes too.
struct MeshInfo {
    size_t vertices = 0, faces = 0, corners = 0, isolatedVertices = 0;
    std::vector<size_t> faceDegreeHistogram; // [k] = faces with k corners (size maxDegree+1)
    size_t edges = 0, boundaryEdges = 0, boundaryLoops = 0;
    size_t nonManifoldEdges = 0;    // 3+ faces, or one direction used twice
    size_t nonManifoldVertices = 0; // faces around it form 2+ fans
    size_t creases = 0, infiniteCreases = 0, cornerTags = 0, holes = 0;
    bool manifold = true;        // no non-manifold edge or vertex
    int eulerCharacteristic = 0; // V - E + F (isolated vertices excluded)
};
MeshInfo describe(const PolygonMesh& mesh);

// ---- Loading ---------------------------------------------------------------

// Loads any supported file as a control cage (format from the extension,
// case-insensitive) and validates it. glTF: all triangle primitives of the
// default scene, positions transformed to world space by their nodes,
// vertices welded by bitwise-equal position (and morph deltas), UV sets
// and normals kept face-varying; morph targets are kept only when every
// primitive has the same number of targets.
PolygonMesh loadPolygonMesh(const std::filesystem::path& path, const LoadOptions& options = {},
                            LoadReport* report = nullptr);

// Loads any supported file as a triangle mesh for rendering (polygons are
// triangulated as fans from their first corner; vertices split wherever a
// UV or normal index differs). glTF: all triangle primitives of the default
// scene merged in world space (a UV set missing from one primitive is
// dropped from all, and noted); for the per-node structure use loadScene.
// Normals: from the file when it has them for every vertex, else
// area-weighted face normals (smooth across UV seams).
RenderMesh loadRenderMesh(const std::filesystem::path& path, const LoadOptions& options = {},
                          LoadReport* report = nullptr);

// glTF material subset the renderer needs. Texture paths are resolved
// against the file's directory; empty when absent or embedded (data URI,
// GLB buffer view).
struct Material {
    std::string name;
    glm::vec4 baseColorFactor{1.0f};
    std::string baseColorTexture;
    int baseColorTexCoord = 0; // TEXCOORD_n index = RenderMesh::uvSets index
    std::string normalTexture;
    int normalTexCoord = 0;
    float normalScale = 1.0f;
    // glTF material.doubleSided (sec. 3.9.5; default false): false means
    // back faces are culled; true means they are rendered with the normal
    // reversed for lighting.
    bool doubleSided = false;
};

enum class AnimInterpolation : uint8_t { Linear, Step, CubicSpline };

// glTF animation channel with path "weights": keyframes of every morph
// weight of the node's mesh.
struct MorphWeightAnimation {
    std::string name;
    int node = -1; // glTF node index the channel targets
    size_t targetCount = 0;
    AnimInterpolation interpolation = AnimInterpolation::Linear;
    std::vector<float> times; // seconds, strictly increasing, finite
    // times.size() * targetCount values; CubicSpline: 3 * that
    // (in-tangent, value, out-tangent per key, as glTF stores them).
    std::vector<float> weights;
};

// Weights at `seconds`, clamped to the first/last key outside the range
// (glTF sec. 3.11). Linear interpolation is per component.
std::vector<float> sampleWeights(const MorphWeightAnimation& anim, float seconds);

struct SceneInstance {
    RenderMesh mesh;                               // object space
    glm::mat4 objectToWorld{1.0f};                 // the node's world matrix (column-major, glm)
    int node = -1, meshIndex = -1, primitive = -1; // glTF indices (-1 for other formats)
    int material = -1;                             // index into Scene::materials
};

struct Scene {
    std::vector<SceneInstance> instances;
    std::vector<Material> materials;
    std::vector<MorphWeightAnimation> animations;
};

// Loads a whole glTF scene (default scene, or scene 0, or every root node);
// for OBJ/OFF/PLY/STL one instance with the identity transform.
Scene loadScene(const std::filesystem::path& path, const LoadOptions& options = {},
                LoadReport* report = nullptr);

// In-memory parsers (used by the loaders and the fuzz targets). `file` only
// names the input in messages. parseObj returns the unvalidated cage;
// parseGltf reads .glb when the bytes start with the GLB magic, else JSON;
// external URIs are resolved against baseDir (empty: refused).
//
// parseObj and the OBJ loaders read a text of kObjParallelMinBytes or more
// (the measured cut-over: below it the threads cost more than they save)
// in line-aligned blocks (about two per thread, at least kObjBlockBytes)
// on `threads` threads
// (surfgrad/base/threads.h; 0 <= threads <= kMaxThreads, a contract), then join
// them in file order: the mesh, the report's notes and, for a malformed
// file, the error (the first one in file order, with its line) are the
// same as one thread's for every count.
inline constexpr size_t kObjParallelMinBytes = size_t(2) << 20;
inline constexpr size_t kObjBlockBytes = size_t(1) << 20;
PolygonMesh parseObj(std::string_view text, const std::string& file, const InputLimits& limits = {},
                     LoadReport* report = nullptr, int threads = 0);
Scene parseGltf(std::string_view bytes, const std::string& file,
                const std::filesystem::path& baseDir, const InputLimits& limits = {},
                LoadReport* report = nullptr);

namespace detail {
// For tests and the fuzz target: parseObj's block reader at any size, in
// blocks of at least blockBytes (blockBytes 0: the serial reader); the
// result must equal the serial reader's, error messages included.
// faceLines (optional): the line of each face, as the loaders use it.
PolygonMesh parseObjInBlocks(std::string_view text, const std::string& file,
                             const InputLimits& limits, LoadReport* report, int threads,
                             size_t blockBytes, std::vector<uint32_t>* faceLines = nullptr);
} // namespace detail

// ---- Conversions -----------------------------------------------------------

// Triangulates (fan from corner 0; holes skipped) and splits vertices where
// any UV or normal index differs. Normals: the mesh's own when it has them,
// else area-weighted face normals accumulated per position vertex.
// Morph targets carry their position deltas. Isolated vertices are dropped.
RenderMesh toRenderMesh(const PolygonMesh& mesh);

// Welds vertices whose every attribute is bitwise equal (position,
// normal, every UV set, tangent, every morph target's deltas): files that
// give each face corner its own v/vt/vn indices (as many exporters write)
// come out with one vertex per distinct value tuple. Welded vertices are
// numbered in order of their first occurrence (by vertex index), the index
// buffer is rewritten, and a mesh without duplicates is left unchanged.
// Returns the number of vertices removed. The same result for every
// `threads` (surfgrad/base/threads.h; 0 <= threads <= kMaxThreads, a contract):
// the hashes of the attribute bit patterns are computed in parallel from
// kWeldParallelMinVertices vertices on (the measured cut-over), the
// numbering pass is serial.
inline constexpr size_t kWeldParallelMinVertices = 65536;
size_t weldVerticesByValue(RenderMesh& mesh, int threads = 0);

// The reverse for subdivision: welds render vertices with bitwise-equal
// positions (and equal morph position deltas) into cage vertices; UV sets
// and normals become face-varying channels. Triangles become triangle faces.
PolygonMesh toPolygonMesh(const RenderMesh& mesh);

// ---- Writing (atomic; never over an input) ----------------------------------

struct WriteOptions {
    std::vector<std::filesystem::path> inputs; // refused as outputs
    const Material* material = nullptr;        // glTF: written as the mesh's material
    bool writeMorphTargets = true;             // glTF
};

// .gltf (one file, buffer embedded as a base64 data URI), .glb, .obj, .ply
// (binary little-endian). Returns one note per kind of data the format
// cannot hold (empty when nothing was lost). glTF gets POSITION (with
// min/max), NORMAL, TANGENT (when present), TEXCOORD_n (t flipped back to
// glTF's v), morph targets and weights, as split vertices (glTF's own
// model; readers weld them by position). OBJ and PLY keep the topology:
// split copies of a vertex are welded back first (toPolygonMesh), so the
// file has one vertex per position and the surface stays connected; OBJ
// then holds UV set 0 and the normals per corner (vt/vn indices), PLY the
// normals and UV sets per vertex where they have no seams (else dropped,
// noted); neither holds tangents or morph targets (noted).
std::vector<std::string> writeRenderMesh(const std::filesystem::path& path, const RenderMesh& mesh,
                                         const WriteOptions& options = {});

// .obj keeps polygons, UV set 0 as vt (other sets dropped, noted), normals
// as vn, and every tag as "t" lines (readable by parseObj and OpenSubdiv's
// regression parser); .ply (binary) keeps polygons with per-vertex normals
// and UV sets as s/t, s1/t1, ... when they have no seams (per-corner data is
// dropped, noted: OpenMesh's PLY reader cannot read face lists of UVs);
// .gltf/.glb go through toRenderMesh.
std::vector<std::string> writePolygonMesh(const std::filesystem::path& path,
                                          const PolygonMesh& mesh,
                                          const WriteOptions& options = {});

// Lower-case extension with the dot (".obj"); the loaders' and writers' switch.
std::string meshFormat(const std::filesystem::path& path);

// The mesh formats the loaders read, by extension: the one list every
// command (render, view, mesh ...), scene field and document names.
inline constexpr std::string_view kMeshFormats[] = {".obj", ".off",  ".ply",
                                                    ".stl", ".gltf", ".glb"};
// The same list as text: ".obj, .off, .ply, .stl, .gltf or .glb".
inline constexpr std::string_view kMeshFormatsText = ".obj, .off, .ply, .stl, .gltf or .glb";
// Whether meshFormat(path) is one of kMeshFormats.
bool isMeshFormat(const std::filesystem::path& path);

} // namespace sg::mesh
