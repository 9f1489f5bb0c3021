// Mesh writers (surfgrad/mesh/mesh_io.h): glTF 2.0 (.gltf with the buffer
// embedded as a base64 data URI, .glb), OBJ with OpenSubdiv tags, binary
// PLY. Each file is built in memory and written atomically
// (sg::io::writeFileAtomically); an output naming an input is refused.
//
// glTF 2.0 references: sec. 3.6 (accessors; POSITION needs min/max, also
// in morph targets), 3.7.2.1 (NORMAL unit, TANGENT xyzw with w = +-1),
// 4.4 (GLB container: 12-byte header, 4-byte aligned JSON and BIN chunks).
// TEXCOORD v = 1 - t (RenderMesh has t up, glTF v down).
#include <nlohmann/json.hpp>

#include <charconv>
#include <cstring>

#include "mesh_internal.h"
#include "surfgrad/base/scratch_buffer.h"
#include "surfgrad/mesh/mesh_io.h"

namespace sg::mesh {

using io::InputError;
using nlohmann::json;

namespace {

void appendFloat(std::string& out, float v) {
    char buf[32];
    auto r = std::to_chars(buf, buf + sizeof buf, v); // shortest round-trip form
    out.append(buf, r.ptr);
}

std::string base64(const std::string& bytes) {
    static const char* kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        uint32_t n = (uint32_t(uint8_t(bytes[i])) << 16) | (uint32_t(uint8_t(bytes[i + 1])) << 8) |
                     uint8_t(bytes[i + 2]);
        for (int k = 3; k >= 0; --k) out += kAlphabet[(n >> (6 * k)) & 63];
    }
    if (i < bytes.size()) {
        uint32_t n = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        out += kAlphabet[(n >> 18) & 63];
        out += kAlphabet[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? kAlphabet[(n >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

class GltfBuilder {
public:
    // Appends data as a new bufferView + accessor; returns the accessor index.
    int accessor(const void* data, size_t count, int comps, int componentType, int target,
                 bool minMax = false, const float* values = nullptr) {
        size_t compBytes = componentType == 5123 ? 2 : 4;
        size_t bytes = count * size_t(comps) * compBytes;
        while (bin.size() % 4) bin.push_back('\0');
        json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (target) view["target"] = target;
        bin.append(static_cast<const char*>(data), bytes);
        views.push_back(view);
        static const char* kTypes[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
        json acc = {{"bufferView", views.size() - 1},
                    {"componentType", componentType},
                    {"count", count},
                    {"type", kTypes[comps]}};
        if (minMax && count > 0) {
            std::vector<float> lo(size_t(comps), std::numeric_limits<float>::max()),
                hi(size_t(comps), -std::numeric_limits<float>::max());
            for (size_t i = 0; i < count; ++i) {
                for (int c = 0; c < comps; ++c) {
                    lo[size_t(c)] = std::min(lo[size_t(c)], values[i * size_t(comps) + size_t(c)]);
                    hi[size_t(c)] = std::max(hi[size_t(c)], values[i * size_t(comps) + size_t(c)]);
                }
            }
            acc["min"] = lo;
            acc["max"] = hi;
        }
        accessors.push_back(acc);
        return int(accessors.size() - 1);
    }
    // Room for `bytes` of buffer data, reserved at once (no reallocation
    // copies), huge pages requested before the first touch.
    void reserve(size_t bytes) {
        bin.reserve(bytes);
        sg::detail::adviseHugePages(bin.data(), bin.capacity());
    }
    int vec3(const std::vector<glm::vec3>& v, bool minMax) {
        return accessor(v.data(), v.size(), 3, 5126, 34962, minMax,
                        reinterpret_cast<const float*>(v.data()));
    }
    std::string bin;
    json views = json::array(), accessors = json::array();
};

std::string relativeUri(const std::string& texture, const std::filesystem::path& out) {
    std::filesystem::path dir = out.parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    std::filesystem::path rel = std::filesystem::proximate(texture, dir, ec);
    std::string s = (ec ? std::filesystem::path(texture) : rel).generic_string();
    std::string uri;
    for (char c : s) {
        if (c == ' ')
            uri += "%20";
        else
            uri += c;
    }
    return uri;
}

std::string gltfBytes(const std::filesystem::path& path, const RenderMesh& mesh,
                      const WriteOptions& options, bool binary) {
    GltfBuilder b;
    const size_t nV = mesh.positions.size();
    {
        // Every accessor below, plus up to 3 bytes of padding each.
        size_t bytes = nV * (12 + 12 + 16 + 8 * mesh.uvSets.size()) + mesh.indices.size() * 4;
        bytes += mesh.morphTargets.size() * 3 * nV * 12;
        const size_t accessors = 5 + mesh.uvSets.size() + 3 * mesh.morphTargets.size();
        b.reserve(bytes + 4 * accessors);
    }
    json attributes;
    attributes["POSITION"] = b.vec3(mesh.positions, true);
    if (!mesh.normals.empty()) attributes["NORMAL"] = b.vec3(mesh.normals, false);
    if (!mesh.tangents.empty()) {
        attributes["TANGENT"] = b.accessor(mesh.tangents.data(), nV, 4, 5126, 34962);
    }
    for (size_t s = 0; s < mesh.uvSets.size(); ++s) {
        std::vector<glm::vec2> uv(mesh.uvSets[s].size());
        for (size_t i = 0; i < uv.size(); ++i)
            uv[i] = glm::vec2(mesh.uvSets[s][i].x, 1.0f - mesh.uvSets[s][i].y);
        attributes["TEXCOORD_" + std::to_string(s)] =
            b.accessor(uv.data(), uv.size(), 2, 5126, 34962);
    }
    json prim = {{"attributes", attributes}, {"mode", 4}};
    if (nV <= 65535) {
        std::vector<uint16_t> idx(mesh.indices.begin(), mesh.indices.end());
        prim["indices"] = b.accessor(idx.data(), idx.size(), 1, 5123, 34963);
    } else {
        prim["indices"] = b.accessor(mesh.indices.data(), mesh.indices.size(), 1, 5125, 34963);
    }
    json jmesh = {{"name", mesh.name.empty() ? "mesh" : mesh.name}};
    if (options.writeMorphTargets && !mesh.morphTargets.empty()) {
        json targets = json::array(), names = json::array();
        for (const MorphTarget& t : mesh.morphTargets) {
            json jt = json::object();
            if (!t.positionDeltas.empty()) jt["POSITION"] = b.vec3(t.positionDeltas, true);
            if (!t.normalDeltas.empty() && !mesh.normals.empty())
                jt["NORMAL"] = b.vec3(t.normalDeltas, false);
            if (!t.tangentDeltas.empty() && !mesh.tangents.empty())
                jt["TANGENT"] = b.vec3(t.tangentDeltas, false);
            if (jt.empty())
                jt["POSITION"] = b.vec3(std::vector<glm::vec3>(nV, glm::vec3(0.0f)),
                                        true); // a target needs one attribute
            targets.push_back(jt);
            names.push_back(t.name);
        }
        prim["targets"] = targets;
        std::vector<float> w = mesh.morphWeights;
        w.resize(mesh.morphTargets.size(), 0.0f);
        jmesh["weights"] = w;
        jmesh["extras"] = {{"targetNames", names}};
    }
    json doc = {{"asset", {{"version", "2.0"}, {"generator", "surfgrad"}}},
                {"scene", 0},
                {"scenes", json::array({{{"nodes", {0}}}})},
                {"nodes", json::array({{{"mesh", 0}}})}};
    if (const Material* mat = options.material) {
        json images = json::array(), textures = json::array();
        auto texture = [&](const std::string& file, int texCoord) {
            images.push_back({{"uri", relativeUri(file, path)}});
            textures.push_back({{"source", images.size() - 1}});
            return json{{"index", textures.size() - 1}, {"texCoord", texCoord}};
        };
        json jm = {{"name", mat->name.empty() ? "material" : mat->name}};
        json pbr = {{"baseColorFactor",
                     {mat->baseColorFactor.x, mat->baseColorFactor.y, mat->baseColorFactor.z,
                      mat->baseColorFactor.w}}};
        if (!mat->baseColorTexture.empty())
            pbr["baseColorTexture"] = texture(mat->baseColorTexture, mat->baseColorTexCoord);
        jm["pbrMetallicRoughness"] = pbr;
        if (!mat->normalTexture.empty()) {
            json nt = texture(mat->normalTexture, mat->normalTexCoord);
            nt["scale"] = mat->normalScale;
            jm["normalTexture"] = nt;
        }
        doc["materials"] = json::array({jm});
        if (!images.empty()) {
            doc["images"] = images;
            doc["textures"] = textures;
        }
        prim["material"] = 0;
    }
    jmesh["primitives"] = json::array({prim});
    doc["meshes"] = json::array({jmesh});
    doc["bufferViews"] = b.views;
    doc["accessors"] = b.accessors;
    while (b.bin.size() % 4) b.bin.push_back('\0');
    json buffer = {{"byteLength", b.bin.size()}};
    if (!binary) buffer["uri"] = "data:application/octet-stream;base64," + base64(b.bin);
    doc["buffers"] = json::array({buffer});
    if (!binary) return doc.dump(1) + "\n";
    std::string js = doc.dump();
    while (js.size() % 4) js.push_back(' ');
    std::string out;
    auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    uint64_t total = 12 + 8 + js.size() + 8 + b.bin.size();
    if (total > UINT32_MAX)
        throw InputError(path.string(), "", "mesh too large for a GLB file (4 GiB)");
    out.reserve(size_t(total));
    sg::detail::adviseHugePages(out.data(), out.capacity());
    u32(0x46546C67u); // "glTF"
    u32(2);
    u32(uint32_t(total));
    u32(uint32_t(js.size()));
    u32(0x4E4F534Au); // "JSON"
    out += js;
    u32(uint32_t(b.bin.size()));
    u32(0x004E4942u); // "BIN\0"
    out += b.bin;
    return out;
}

// tags = false for a render mesh (triangles to display, not a cage): no
// subdivision options are written.
std::string objBytes(const PolygonMesh& mesh, std::vector<std::string>& notes, bool tags = true) {
    std::string out = "# written by surfgrad\n";
    for (const glm::vec3& p : mesh.positions) {
        out += 'v';
        for (int i = 0; i < 3; ++i) {
            out += ' ';
            appendFloat(out, p[i]);
        }
        out += '\n';
    }
    const bool hasUv = !mesh.uvSets.empty(), hasN = !mesh.normalIndices.empty();
    if (hasUv) {
        for (const glm::vec2& t : mesh.uvSets[0].values) {
            out += "vt ";
            appendFloat(out, t.x);
            out += ' ';
            appendFloat(out, t.y);
            out += '\n';
        }
    }
    if (hasN) {
        for (const glm::vec3& n : mesh.normals) {
            out += "vn";
            for (int i = 0; i < 3; ++i) {
                out += ' ';
                appendFloat(out, n[i]);
            }
            out += '\n';
        }
    }
    size_t c = 0;
    for (uint32_t k : mesh.faceSizes) {
        out += 'f';
        for (uint32_t j = 0; j < k; ++j, ++c) {
            out += ' ' + std::to_string(mesh.faceVertices[c] + 1);
            if (hasUv || hasN)
                out +=
                    '/' + (hasUv ? std::to_string(mesh.uvSets[0].indices[c] + 1) : std::string());
            if (hasN) out += '/' + std::to_string(mesh.normalIndices[c] + 1);
        }
        out += '\n';
    }
    if (!tags) {
        if (mesh.uvSets.size() > 1)
            notes.push_back("OBJ holds one UV set: " + std::to_string(mesh.uvSets.size() - 1) +
                            " dropped");
        if (!mesh.morphTargets.empty()) notes.push_back("OBJ has no morph targets: dropped");
        return out;
    }
    // Tags: every option explicitly, so a round trip is exact.
    static const int kBoundaryTag[3] = {0, 2, 1}; // None, EdgeOnly, EdgeAndCorner
    out += "t scheme 0/0/1 " + std::string(toString(mesh.options.scheme)) + "\n";
    out += "t interpolateboundary 1/0/0 " +
           std::to_string(kBoundaryTag[int(mesh.options.boundary)]) + "\n";
    out +=
        "t facevaryinginterpolateboundary 1/0/0 " + std::to_string(int(mesh.options.fvar)) + "\n";
    out += std::string("t creasemethod 0/0/1 ") +
           (mesh.options.creaseMethod == CreaseMethod::Chaikin ? "chaikin" : "normal") + "\n";
    if (mesh.options.triangles == TriangleRule::Smooth) out += "t smoothtriangles 0/0/1 catmark\n";
    for (const EdgeCrease& e : mesh.creases) {
        out += "t crease 2/1/0 " + std::to_string(e.v0) + " " + std::to_string(e.v1) + " ";
        appendFloat(out, e.sharpness);
        out += '\n';
    }
    for (const VertexCorner& k : mesh.corners) {
        out += "t corner 1/1/0 " + std::to_string(k.vertex) + " ";
        appendFloat(out, k.sharpness);
        out += '\n';
    }
    if (!mesh.holes.empty()) {
        out += "t hole " + std::to_string(mesh.holes.size()) + "/0/0";
        for (uint32_t h : mesh.holes) out += " " + std::to_string(h);
        out += '\n';
    }
    if (mesh.uvSets.size() > 1)
        notes.push_back("OBJ holds one UV set: " + std::to_string(mesh.uvSets.size() - 1) +
                        " dropped");
    if (!mesh.morphTargets.empty()) notes.push_back("OBJ has no morph targets: dropped");
    return out;
}

struct PlyBuilder {
    std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by surfgrad\n",
                body;
    template <class T>
    void put(T v) {
        body.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
};

// Per-vertex values of a face-varying channel when every vertex has one
// value (no seams); empty otherwise.
template <class V>
std::vector<V> perVertex(const PolygonMesh& mesh, const std::vector<V>& values,
                         const std::vector<uint32_t>& indices) {
    std::vector<V> out(mesh.positions.size(), V(0.0f));
    std::vector<uint32_t> seen(mesh.positions.size(), UINT32_MAX);
    for (size_t c = 0; c < indices.size(); ++c) {
        uint32_t v = mesh.faceVertices[c];
        if (seen[v] == UINT32_MAX) {
            seen[v] = indices[c];
            out[v] = values[indices[c]];
        } else if (seen[v] != indices[c] && values[seen[v]] != values[indices[c]]) {
            return {};
        }
    }
    return out;
}

// Polygons with per-vertex attributes only: OpenMesh's PLY reader (and
// most others) do not read per-corner lists, so a UV set with seams cannot
// be written here (noted; .obj keeps it).
std::string plyBytes(const std::filesystem::path& path, const PolygonMesh& mesh,
                     std::vector<std::string>& notes) {
    PlyBuilder b;
    std::vector<glm::vec3> normals;
    if (!mesh.normalIndices.empty()) {
        normals = perVertex(mesh, mesh.normals, mesh.normalIndices);
        if (normals.empty())
            notes.push_back("PLY holds per-vertex normals; these are per corner: dropped");
    }
    std::vector<std::vector<glm::vec2>> uvs;
    for (size_t s = 0; s < mesh.uvSets.size(); ++s) {
        std::vector<glm::vec2> uv = perVertex(mesh, mesh.uvSets[s].values, mesh.uvSets[s].indices);
        if (uv.empty()) {
            notes.push_back("PLY holds per-vertex UVs; UV set " + std::to_string(s) +
                            " has seams: dropped (write .obj to keep it)");
            break; // later sets would shift names
        }
        uvs.push_back(std::move(uv));
    }
    b.header += "element vertex " + std::to_string(mesh.positions.size()) +
                "\nproperty float x\nproperty float y\nproperty float z\n";
    if (!normals.empty()) b.header += "property float nx\nproperty float ny\nproperty float nz\n";
    for (size_t s = 0; s < uvs.size(); ++s) {
        std::string suffix = s == 0 ? "" : std::to_string(s);
        b.header += "property float s" + suffix + "\nproperty float t" + suffix + "\n";
    }
    b.header += "element face " + std::to_string(mesh.faceSizes.size()) +
                "\nproperty list uchar int vertex_indices\nend_header\n";
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        for (int i = 0; i < 3; ++i) b.put(mesh.positions[v][i]);
        if (!normals.empty()) {
            for (int i = 0; i < 3; ++i) b.put(normals[v][i]);
        }
        for (const auto& uv : uvs) {
            b.put(uv[v].x);
            b.put(uv[v].y);
        }
    }
    size_t c0 = 0;
    for (uint32_t k : mesh.faceSizes) {
        if (k > 255) {
            throw InputError(path.string(), "",
                             "a face has " + std::to_string(k) +
                                 " corners; PLY lists hold at most 255");
        }
        b.put(uint8_t(k));
        for (uint32_t j = 0; j < k; ++j) b.put(int32_t(mesh.faceVertices[c0 + j]));
        c0 += k;
    }
    if (!mesh.creases.empty() || !mesh.corners.empty() || !mesh.holes.empty()) {
        notes.push_back("PLY has no crease/corner/hole tags: dropped (write .obj to keep them)");
    }
    if (!mesh.morphTargets.empty()) notes.push_back("PLY has no morph targets: dropped");
    return b.header + b.body;
}

void checkOutput(const std::filesystem::path& path, const WriteOptions& options) {
    for (const auto& in : options.inputs) io::checkNotInput(path, {in});
}

} // namespace

std::vector<std::string> writeRenderMesh(const std::filesystem::path& path, const RenderMesh& mesh,
                                         const WriteOptions& options) {
    checkOutput(path, options);
    std::vector<std::string> notes;
    const std::string ext = meshFormat(path);
    std::string bytes;
    if (ext == ".gltf" || ext == ".glb")
        bytes = gltfBytes(path, mesh, options, ext == ".glb");
    else if (ext == ".obj" || ext == ".ply") {
        // The render mesh's vertices are split at UV seams and hard edges;
        // OBJ and PLY have their own means (per-corner vt/vn indices, or
        // nothing), so the split copies are welded back first
        // (toPolygonMesh: equal positions and morph deltas): a cube stays
        // one closed surface instead of six separate squares.
        const PolygonMesh welded = toPolygonMesh(mesh);
        bytes =
            ext == ".obj" ? objBytes(welded, notes, /*tags=*/false) : plyBytes(path, welded, notes);
        if (!mesh.tangents.empty())
            notes.push_back(std::string(ext == ".obj" ? "OBJ" : "PLY") +
                            " has no tangents: dropped (write .gltf/.glb to keep them)");
    } else
        throw InputError(path.string(), "",
                         "unknown output format '" + ext +
                             "' (expected .gltf, .glb, .obj or .ply)");
    io::writeFileAtomically(path, bytes);
    return notes;
}

std::vector<std::string> writePolygonMesh(const std::filesystem::path& path,
                                          const PolygonMesh& mesh, const WriteOptions& options) {
    checkOutput(path, options);
    const std::string ext = meshFormat(path);
    if (ext == ".gltf" || ext == ".glb") return writeRenderMesh(path, toRenderMesh(mesh), options);
    std::vector<std::string> notes;
    std::string bytes;
    if (ext == ".obj")
        bytes = objBytes(mesh, notes);
    else if (ext == ".ply")
        bytes = plyBytes(path, mesh, notes);
    else
        throw InputError(path.string(), "",
                         "unknown output format '" + ext +
                             "' (expected .gltf, .glb, .obj or .ply)");
    io::writeFileAtomically(path, bytes);
    return notes;
}

} // namespace sg::mesh
