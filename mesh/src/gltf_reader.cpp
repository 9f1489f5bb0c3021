// glTF 2.0 input (.gltf/.glb) through tinygltf (surfgrad/mesh/mesh_io.h:
// parseGltf, loadScene). tinygltf parses the JSON and loads the buffers;
// everything it hands over is then checked here before use, because
// tinygltf 2.7 does not bound-check accessors against their buffers:
// every accessor read verifies component type, element type, count, stride
// and byte range; every index is checked against its array; node graphs are
// walked with cycle and depth checks.
//
// Spec references: glTF 2.0 sec. 3.6 (accessors, sparse accessors,
// normalized integers), 3.7.2 (primitives, morph targets), 3.5.3 (node
// transforms), 3.9 (materials: normalTexture, baseColorTexture), 3.11
// (animations). TEXCOORD v points down the image; RenderMesh t points up:
// t = 1 - v.
#include <tiny_gltf.h>

#include <atomic>
#include <cctype>
#include <cstring>
#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "mesh_internal.h"
#include "surfgrad/mesh/mesh_io.h"

namespace sg::mesh {

using io::InputError;

namespace {

struct FsContext {
    std::filesystem::path baseDir;
    const InputLimits* limits;
    std::string refused; // why the last external read was refused
};

// Empty when `path` may be read, else why not.
std::string outsideRule(const FsContext& ctx, const std::string& path) {
    if (ctx.baseDir.empty())
        return "external file '" + io::printable(path, 200) + "' refused (in-memory input)";
    if (!ctx.limits->allowOutsideFolder && !io::isInsideFolder(ctx.baseDir, path)) {
        return "URI resolves to '" + io::printable(path, 200) +
               "', outside the model's folder (refused; --allow-outside-uris allows it)";
    }
    return {};
}

bool fsFileExists(const std::string& path, void* user) {
    auto* ctx = static_cast<FsContext*>(user);
    if (std::string why = outsideRule(*ctx, path); !why.empty()) {
        ctx->refused = why;
        return false;
    }
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}

std::string fsExpand(const std::string& path, void*) {
    return path;
} // no ~ or $VAR expansion

bool fsRead(std::vector<unsigned char>* out, std::string* err, const std::string& path,
            void* user) {
    auto* ctx = static_cast<FsContext*>(user);
    auto refuse = [&](const std::string& why) {
        ctx->refused = why;
        if (err) *err += why + "\n";
        return false;
    };
    if (std::string why = outsideRule(*ctx, path); !why.empty()) return refuse(why);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        return refuse("external file '" + path.substr(0, 200) + "' not found");
    uint64_t size = std::filesystem::file_size(path, ec);
    if (ec || size > ctx->limits->maxFileBytes) {
        return refuse("external file '" + path.substr(0, 200) + "' is larger than the limit (" +
                      std::to_string(ctx->limits->maxFileBytes) + " bytes)");
    }
    std::string ext = meshFormat(path);
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".ktx2" || ext == ".webp") {
        // Images are never decoded (materials keep paths): skip reading
        // them, tinygltf only needs some bytes to hand to our image loader.
        out->assign(1, 0);
        return true;
    }
    std::ifstream in(path, std::ios::binary);
    out->resize(size_t(size));
    in.read(reinterpret_cast<char*>(out->data()), std::streamsize(size));
    if (uint64_t(in.gcount()) != size) return refuse("short read of '" + path.substr(0, 200) + "'");
    return true;
}

bool fsWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err = "writing refused";
    return false;
}

bool keepImageUndecoded(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                        const unsigned char*, int, void*) {
    return true;
}

uint32_t readU32(std::string_view bytes, size_t at) {
    uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
}

// GLB container check (glTF 2.0 sec. 4.4) before tinygltf sees it.
void checkGlbHeader(std::string_view bytes, const std::string& file) {
    auto u32 = [&](size_t at) { return readU32(bytes, at); };
    if (bytes.size() < 20)
        throw InputError(file, "GLB header",
                         "truncated (" + std::to_string(bytes.size()) + " bytes)");
    if (u32(4) != 2)
        throw InputError(file, "GLB header",
                         "version " + std::to_string(u32(4)) + " (only 2 is supported)");
    if (u32(8) != bytes.size()) {
        throw InputError(file, "GLB header",
                         "declares " + std::to_string(u32(8)) + " bytes but the file has " +
                             std::to_string(bytes.size()) + " (truncated?)");
    }
    uint64_t jsonLen = u32(12);
    if (u32(16) != 0x4E4F534Au) throw InputError(file, "GLB chunk 0", "is not the JSON chunk");
    if (20 + jsonLen > bytes.size())
        throw InputError(file, "GLB chunk 0", "JSON chunk runs past the end of the file");
    uint64_t at = 20 + ((jsonLen + 3) & ~uint64_t(3));
    if (at + 8 <= bytes.size()) {
        uint64_t binLen = u32(size_t(at));
        if (at + 8 + binLen > bytes.size())
            throw InputError(file, "GLB chunk 1", "BIN chunk runs past the end of the file");
    }
}

class GltfReader {
public:
    GltfReader(const tinygltf::Model& model, const std::string& file, const InputLimits& limits,
               LoadReport* report, const std::filesystem::path& baseDir)
        : m_(model), file_(file), limits_(limits), report_(report), baseDir_(baseDir) {}

    Scene read();

private:
    [[noreturn]] void fail(const std::string& element, const std::string& reason) const {
        throw InputError(file_, element, reason);
    }
    void note(const std::string& s) {
        if (report_) report_->notes.push_back(s);
    }
    // Reads accessor `idx` as `comps` floats per element (float or, when
    // allowed, normalized integers), applying sparse substitution.
    std::vector<float> readFloats(int idx, int comps, bool allowNormalized,
                                  const std::string& what) const;
    std::vector<uint32_t> readIndices(int idx, size_t vertexCount, const std::string& what) const;
    const unsigned char* viewData(int viewIdx, size_t byteOffset, size_t elemSize, size_t stride,
                                  size_t count, const std::string& what) const;
    // One primitive as a scene instance, in the steps below.
    void primitive(const tinygltf::Mesh& mesh, int meshIdx, int primIdx, int nodeIdx,
                   const glm::mat4& world, const std::vector<double>& nodeWeights, Scene& scene);
    // POSITION, NORMAL (unit; zero ones flagged as 0), TANGENT, TEXCOORD_n
    // (st = (u, 1 - v)); returns the vertex count.
    size_t vertexAttributes(const tinygltf::Primitive& prim, const std::string& el, RenderMesh& rm);
    // Indices (or 0..n-1) as a triangle list; strips and fans unrolled with
    // their winding kept.
    void triangleList(const tinygltf::Primitive& prim, int mode, size_t nV, const std::string& el,
                      RenderMesh& rm) const;
    // Morph targets, their names (extras.targetNames) and default weights
    // (the node's, else the mesh's).
    void morphTargets(const tinygltf::Mesh& mesh, const tinygltf::Primitive& prim,
                      const std::vector<double>& nodeWeights, size_t nV, const std::string& el,
                      RenderMesh& rm) const;
    void materials(Scene& scene);
    void animations(Scene& scene);
    std::string texturePath(int textureIdx, const std::string& what) const;

    const tinygltf::Model& m_;
    const std::string& file_;
    const InputLimits& limits_;
    LoadReport* report_;
    std::filesystem::path baseDir_;
    size_t totalVertices_ = 0;
};

const unsigned char* GltfReader::viewData(int viewIdx, size_t byteOffset, size_t elemSize,
                                          size_t stride, size_t count,
                                          const std::string& what) const {
    if (viewIdx < 0 || size_t(viewIdx) >= m_.bufferViews.size())
        fail(what, "bufferView " + std::to_string(viewIdx) + " does not exist");
    const tinygltf::BufferView& view = m_.bufferViews[size_t(viewIdx)];
    if (view.buffer < 0 || size_t(view.buffer) >= m_.buffers.size()) {
        fail(what, "bufferView " + std::to_string(viewIdx) + " names buffer " +
                       std::to_string(view.buffer) + " which does not exist");
    }
    const tinygltf::Buffer& buf = m_.buffers[size_t(view.buffer)];
    // 128-bit-safe arithmetic: every term is < 2^64 and count is limited.
    uint64_t viewEnd = uint64_t(view.byteOffset) + uint64_t(view.byteLength);
    if (view.byteOffset > buf.data.size() || viewEnd > buf.data.size()) {
        fail(what, "bufferView " + std::to_string(viewIdx) + " [" +
                       std::to_string(view.byteOffset) + ", " + std::to_string(viewEnd) +
                       ") lies outside buffer " + std::to_string(view.buffer) + " (" +
                       std::to_string(buf.data.size()) + " bytes)");
    }
    if (count == 0) return buf.data.data();
    if (byteOffset > view.byteLength) fail(what, "byteOffset past the end of its bufferView");
    long double need = (long double)(byteOffset) +
                       (long double)(count - 1) * (long double)(stride) + (long double)(elemSize);
    if (need > (long double)(view.byteLength)) {
        fail(what, std::to_string(count) + " elements (stride " + std::to_string(stride) +
                       ") need more than the " + std::to_string(view.byteLength) +
                       " bytes of bufferView " + std::to_string(viewIdx));
    }
    return buf.data.data() + view.byteOffset + byteOffset;
}

float decodeComponent(const unsigned char* p, int componentType, bool normalized) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? float(*p) / 255.0f : float(*p);
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        int8_t v;
        std::memcpy(&v, p, 1);
        return normalized ? std::max(float(v) / 127.0f, -1.0f) : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? float(v) / 65535.0f : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
    }
    default:
        return 0.0f;
    }
}

int componentBytes(int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return 4;
    default:
        return 0;
    }
}

int typeComponents(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR:
        return 1;
    case TINYGLTF_TYPE_VEC2:
        return 2;
    case TINYGLTF_TYPE_VEC3:
        return 3;
    case TINYGLTF_TYPE_VEC4:
        return 4;
    default:
        return 0;
    }
}

std::vector<float> GltfReader::readFloats(int idx, int comps, bool allowNormalized,
                                          const std::string& what) const {
    if (idx < 0 || size_t(idx) >= m_.accessors.size())
        fail(what, "accessor " + std::to_string(idx) + " does not exist");
    const tinygltf::Accessor& a = m_.accessors[size_t(idx)];
    std::string el = what + " (accessor " + std::to_string(idx) + ")";
    if (typeComponents(a.type) != comps)
        fail(el, "has " + std::to_string(typeComponents(a.type)) +
                     " components per element; expected " + std::to_string(comps));
    int cbytes = componentBytes(a.componentType);
    bool isFloat = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
    bool okInt = allowNormalized && a.normalized &&
                 a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && cbytes > 0;
    if (!isFloat && !okInt)
        fail(el, "component type " + std::to_string(a.componentType) +
                     " is not allowed here (float" +
                     (allowNormalized ? " or normalized integers" : "") + ")");
    if (a.count > limits_.maxCorners)
        fail(el, "count " + std::to_string(a.count) + " exceeds the limit");
    size_t elemSize = size_t(cbytes) * size_t(comps);
    std::vector<float> out(a.count * size_t(comps), 0.0f);
    if (a.bufferView >= 0) {
        size_t stride = elemSize;
        if (size_t(a.bufferView) < m_.bufferViews.size() &&
            m_.bufferViews[size_t(a.bufferView)].byteStride != 0) {
            stride = m_.bufferViews[size_t(a.bufferView)].byteStride;
            if (stride < elemSize)
                fail(el, "byteStride " + std::to_string(stride) + " is smaller than an element");
        }
        const unsigned char* p =
            viewData(a.bufferView, a.byteOffset, elemSize, stride, a.count, el);
        for (size_t i = 0; i < a.count; ++i) {
            for (int c = 0; c < comps; ++c)
                out[i * size_t(comps) + size_t(c)] = decodeComponent(
                    p + i * stride + size_t(c * cbytes), a.componentType, a.normalized);
        }
    }
    if (a.sparse.isSparse) {
        if (a.sparse.count < 0 || size_t(a.sparse.count) > a.count)
            fail(el, "sparse count " + std::to_string(a.sparse.count) + " is out of range");
        size_t n = size_t(a.sparse.count);
        int icType = a.sparse.indices.componentType;
        int ib = componentBytes(icType);
        if (icType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            icType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            icType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
            fail(el, "sparse indices have component type " + std::to_string(icType));
        }
        if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
            fail(el, "negative sparse byteOffset");
        const unsigned char* ip =
            viewData(a.sparse.indices.bufferView, size_t(a.sparse.indices.byteOffset), size_t(ib),
                     size_t(ib), n, el + " sparse indices");
        const unsigned char* vp =
            viewData(a.sparse.values.bufferView, size_t(a.sparse.values.byteOffset), elemSize,
                     elemSize, n, el + " sparse values");
        for (size_t k = 0; k < n; ++k) {
            uint32_t target = 0;
            if (ib == 1)
                target = ip[k];
            else if (ib == 2) {
                uint16_t v;
                std::memcpy(&v, ip + 2 * k, 2);
                target = v;
            } else
                std::memcpy(&target, ip + 4 * k, 4);
            if (target >= a.count)
                fail(el, "sparse index " + std::to_string(target) + " is out of range (" +
                             std::to_string(a.count) + " elements)");
            for (int c = 0; c < comps; ++c) {
                out[size_t(target) * size_t(comps) + size_t(c)] = decodeComponent(
                    vp + k * elemSize + size_t(c * cbytes), a.componentType, a.normalized);
            }
        }
    }
    for (size_t i = 0; i < out.size(); ++i) {
        if (!std::isfinite(out[i]))
            fail(el, "element " + std::to_string(i / size_t(comps)) + " is not finite");
    }
    return out;
}

std::vector<uint32_t> GltfReader::readIndices(int idx, size_t vertexCount,
                                              const std::string& what) const {
    if (idx < 0 || size_t(idx) >= m_.accessors.size())
        fail(what, "accessor " + std::to_string(idx) + " does not exist");
    const tinygltf::Accessor& a = m_.accessors[size_t(idx)];
    std::string el = what + " (accessor " + std::to_string(idx) + ")";
    if (a.type != TINYGLTF_TYPE_SCALAR) fail(el, "indices must be scalars");
    int cb = componentBytes(a.componentType);
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        fail(el, "index component type " + std::to_string(a.componentType) +
                     " (expected an unsigned integer type)");
    }
    if (a.count > limits_.maxCorners)
        fail(el, "count " + std::to_string(a.count) + " exceeds the limit");
    if (a.sparse.isSparse) fail(el, "sparse index accessors are not supported");
    if (a.bufferView < 0) fail(el, "index accessor without bufferView");
    const unsigned char* p =
        viewData(a.bufferView, a.byteOffset, size_t(cb), size_t(cb), a.count, el);
    size_t viewStride =
        m_.bufferViews[size_t(a.bufferView)].byteStride; // index valid: viewData checked it
    if (viewStride != 0 && viewStride != size_t(cb))
        fail(el, "index bufferView with byteStride " + std::to_string(viewStride));
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i) {
        uint32_t v = 0;
        if (cb == 1)
            v = p[i];
        else if (cb == 2) {
            uint16_t s;
            std::memcpy(&s, p + 2 * i, 2);
            v = s;
        } else
            std::memcpy(&v, p + 4 * i, 4);
        if (v >= vertexCount)
            fail(el, "index " + std::to_string(v) + " at position " + std::to_string(i) +
                         " is out of range (" + std::to_string(vertexCount) + " vertices)");
        out[i] = v;
    }
    return out;
}

glm::mat4 localMatrix(const tinygltf::Node& n, const std::string& file, int nodeIdx) {
    auto finiteAll = [](const std::vector<double>& v) {
        for (double d : v) {
            if (!std::isfinite(d)) return false;
        }
        return true;
    };
    std::string el = "node " + std::to_string(nodeIdx);
    if (!n.matrix.empty()) {
        if (n.matrix.size() != 16 || !finiteAll(n.matrix))
            throw InputError(file, el, "matrix must have 16 finite numbers");
        glm::mat4 m;
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r)
                m[c][r] = float(n.matrix[size_t(c * 4 + r)]); // glTF is column-major too
        }
        return m;
    }
    glm::mat4 m(1.0f);
    if (!n.translation.empty()) {
        if (n.translation.size() != 3 || !finiteAll(n.translation))
            throw InputError(file, el, "translation must have 3 finite numbers");
        m = glm::translate(m, glm::vec3(float(n.translation[0]), float(n.translation[1]),
                                        float(n.translation[2])));
    }
    if (!n.rotation.empty()) {
        if (n.rotation.size() != 4 || !finiteAll(n.rotation))
            throw InputError(file, el, "rotation must have 4 finite numbers");
        glm::quat q(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]),
                    float(n.rotation[2])); // glTF: x,y,z,w
        float len = glm::length(q);
        if (!(len > 0.0f)) throw InputError(file, el, "rotation quaternion has zero length");
        m = m * glm::mat4_cast(q / len);
    }
    if (!n.scale.empty()) {
        if (n.scale.size() != 3 || !finiteAll(n.scale))
            throw InputError(file, el, "scale must have 3 finite numbers");
        m = glm::scale(m, glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
    }
    return m;
}

// Normals flagged as zero (absent or zero-length in the file) become the
// normalised area-weighted sum of their triangles' normals (+z when that is
// zero too).
void fillZeroNormals(RenderMesh& rm) {
    std::vector<glm::vec3> acc;
    for (size_t i = 0; i < rm.normals.size(); ++i) {
        if (rm.normals[i] != glm::vec3(0.0f)) continue;
        if (acc.empty()) {
            acc.assign(rm.normals.size(), glm::vec3(0.0f));
            for (size_t k = 0; k + 2 < rm.indices.size(); k += 3) {
                const glm::vec3 &a = rm.positions[rm.indices[k]],
                                &b = rm.positions[rm.indices[k + 1]],
                                &c = rm.positions[rm.indices[k + 2]];
                glm::vec3 n = glm::cross(b - a, c - a);
                for (int j = 0; j < 3; ++j) acc[rm.indices[k + size_t(j)]] += n;
            }
        }
        float len = glm::length(acc[i]);
        rm.normals[i] =
            len > 0.0f && std::isfinite(len) ? acc[i] / len : glm::vec3(0.0f, 0.0f, 1.0f);
    }
}

size_t GltfReader::vertexAttributes(const tinygltf::Primitive& prim, const std::string& el,
                                    RenderMesh& rm) {
    auto attr = [&](const std::string& name) -> int {
        auto it = prim.attributes.find(name);
        return it == prim.attributes.end() ? -1 : it->second;
    };
    int posIdx = attr("POSITION");
    if (posIdx < 0) fail(el, "has no POSITION attribute");
    std::vector<float> pos = readFloats(posIdx, 3, false, el + " POSITION");
    const size_t nV = pos.size() / 3;
    totalVertices_ += nV;
    if (totalVertices_ > limits_.maxVertices)
        fail(el, "the scene has more than " + std::to_string(limits_.maxVertices) +
                     " vertices (limit)");
    rm.positions.resize(nV);
    if (nV > 0)
        std::memcpy(rm.positions.data(), pos.data(),
                    nV * sizeof(glm::vec3)); // (no null pointers into memcpy)

    auto sizeCheck = [&](const std::vector<float>& v, int comps, const std::string& what) {
        if (v.size() != nV * size_t(comps))
            fail(el, what + " has " + std::to_string(v.size() / size_t(comps)) +
                         " elements; POSITION has " + std::to_string(nV));
    };
    if (int ni = attr("NORMAL"); ni >= 0) {
        std::vector<float> n = readFloats(ni, 3, false, el + " NORMAL");
        sizeCheck(n, 3, "NORMAL");
        rm.normals.resize(nV);
        size_t zero = 0;
        for (size_t i = 0; i < nV; ++i) {
            glm::vec3 v(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
            float len = glm::length(v);
            if (!(len > 1e-20f) || !std::isfinite(len)) {
                ++zero;
                v = glm::vec3(0.0f);
            } else {
                v /= len;
            }
            rm.normals[i] = v;
        }
        if (zero) {
            // Filled from the geometry once the indices are known (fillZeroNormals).
            note(el + ": " + std::to_string(zero) +
                 " zero-length normals replaced by face normals");
        }
    }
    if (int ti = attr("TANGENT"); ti >= 0) {
        std::vector<float> t = readFloats(ti, 4, false, el + " TANGENT");
        sizeCheck(t, 4, "TANGENT");
        rm.tangents.resize(nV);
        for (size_t i = 0; i < nV; ++i) {
            glm::vec3 xyz(t[4 * i], t[4 * i + 1], t[4 * i + 2]);
            float len = glm::length(xyz);
            if (len > 1e-20f && std::isfinite(len)) xyz /= len;
            rm.tangents[i] = glm::vec4(xyz, t[4 * i + 3] < 0.0f ? -1.0f : 1.0f);
        }
        rm.tangentUvSet = 0; // glTF tangents belong to the normal texture's set; 0 unless a
                             // material says otherwise
    }
    for (int set = 0;; ++set) {
        int ui = attr("TEXCOORD_" + std::to_string(set));
        if (ui < 0) break;
        if (size_t(set) >= limits_.maxUvSets)
            fail(el, "more than " + std::to_string(limits_.maxUvSets) + " TEXCOORD sets (limit)");
        std::vector<float> uv = readFloats(ui, 2, true, el + " TEXCOORD_" + std::to_string(set));
        sizeCheck(uv, 2, "TEXCOORD_" + std::to_string(set));
        std::vector<glm::vec2> st(nV);
        for (size_t i = 0; i < nV; ++i) st[i] = glm::vec2(uv[2 * i], 1.0f - uv[2 * i + 1]);
        rm.uvSets.push_back(std::move(st));
    }
    return nV;
}

void GltfReader::triangleList(const tinygltf::Primitive& prim, int mode, size_t nV,
                              const std::string& el, RenderMesh& rm) const {
    std::vector<uint32_t> idx;
    if (prim.indices >= 0) {
        idx = readIndices(prim.indices, nV, el + " indices");
    } else {
        idx.resize(nV);
        std::iota(idx.begin(), idx.end(), 0u);
    }
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (idx.size() % 3 != 0)
            fail(el, std::to_string(idx.size()) + " indices is not a multiple of 3");
        rm.indices = std::move(idx);
    } else if (idx.size() >= 3) {
        rm.indices.reserve((idx.size() - 2) * 3);
        for (size_t i = 2; i < idx.size(); ++i) {
            if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                // Even triangles (i-2, i-1, i), odd (i-1, i-2, i): keeps CCW.
                if (i % 2 == 0)
                    rm.indices.insert(rm.indices.end(), {idx[i - 2], idx[i - 1], idx[i]});
                else
                    rm.indices.insert(rm.indices.end(), {idx[i - 1], idx[i - 2], idx[i]});
            } else {
                rm.indices.insert(rm.indices.end(), {idx[0], idx[i - 1], idx[i]});
            }
        }
    }
}

void GltfReader::morphTargets(const tinygltf::Mesh& mesh, const tinygltf::Primitive& prim,
                              const std::vector<double>& nodeWeights, size_t nV,
                              const std::string& el, RenderMesh& rm) const {
    if (prim.targets.size() > limits_.maxMorphTargets)
        fail(el, std::to_string(prim.targets.size()) + " morph targets; the limit is " +
                     std::to_string(limits_.maxMorphTargets));
    for (size_t t = 0; t < prim.targets.size(); ++t) {
        MorphTarget mt;
        std::string tel = el + " target " + std::to_string(t);
        auto read3 = [&](const char* name, std::vector<glm::vec3>& dst) {
            auto it = prim.targets[t].find(name);
            if (it == prim.targets[t].end()) return;
            std::vector<float> d = readFloats(it->second, 3, true, tel + " " + name);
            if (d.size() != nV * 3)
                fail(tel, std::string(name) + " has " + std::to_string(d.size() / 3) +
                              " elements; POSITION has " + std::to_string(nV));
            dst.resize(nV);
            if (!d.empty()) std::memcpy(dst.data(), d.data(), d.size() * sizeof(float));
        };
        read3("POSITION", mt.positionDeltas);
        read3("NORMAL", mt.normalDeltas);
        read3("TANGENT", mt.tangentDeltas);
        if (rm.normals.empty()) mt.normalDeltas.clear();
        if (rm.tangents.empty()) mt.tangentDeltas.clear();
        rm.morphTargets.push_back(std::move(mt));
    }
    if (rm.morphTargets.empty()) return;
    // Names from mesh.extras.targetNames (a common exporter convention).
    if (mesh.extras.Has("targetNames") && mesh.extras.Get("targetNames").IsArray()) {
        const tinygltf::Value& names = mesh.extras.Get("targetNames");
        for (size_t t = 0; t < rm.morphTargets.size() && t < names.ArrayLen(); ++t) {
            if (names.Get(int(t)).IsString())
                rm.morphTargets[t].name = names.Get(int(t)).Get<std::string>();
        }
    }
    const std::vector<double>& w = !nodeWeights.empty() ? nodeWeights : mesh.weights;
    if (!w.empty() && w.size() != rm.morphTargets.size()) {
        fail(el, std::to_string(w.size()) + " default weights for " +
                     std::to_string(rm.morphTargets.size()) + " morph targets");
    }
    rm.morphWeights.assign(rm.morphTargets.size(), 0.0f);
    for (size_t t = 0; t < w.size(); ++t) {
        if (!std::isfinite(w[t])) fail(el, "non-finite default morph weight");
        rm.morphWeights[t] = float(w[t]);
    }
}

void GltfReader::primitive(const tinygltf::Mesh& mesh, int meshIdx, int primIdx, int nodeIdx,
                           const glm::mat4& world, const std::vector<double>& nodeWeights,
                           Scene& scene) {
    const tinygltf::Primitive& prim = mesh.primitives[size_t(primIdx)];
    std::string el = "mesh " + std::to_string(meshIdx) + " primitive " + std::to_string(primIdx);
    int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        note(el + ": mode " + std::to_string(mode) + " (points/lines) skipped");
        return;
    }
    if (prim.attributes.find("POSITION") == prim.attributes.end())
        fail(el, "has no POSITION attribute");
    SceneInstance inst;
    inst.node = nodeIdx;
    inst.meshIndex = meshIdx;
    inst.primitive = primIdx;
    inst.objectToWorld = world;
    inst.material = prim.material;
    if (prim.material >= 0 && size_t(prim.material) >= m_.materials.size())
        fail(el, "material " + std::to_string(prim.material) + " does not exist");
    RenderMesh& rm = inst.mesh;
    rm.name = mesh.name.empty() ? "mesh" + std::to_string(meshIdx) : mesh.name;
    if (mesh.primitives.size() > 1) rm.name += "#" + std::to_string(primIdx);

    const size_t nV = vertexAttributes(prim, el, rm);
    triangleList(prim, mode, nV, el, rm);
    if (rm.indices.empty()) {
        note(el + ": no triangles; skipped");
        return;
    }
    morphTargets(mesh, prim, nodeWeights, nV, el, rm);
    // Material: tangents belong to the normal texture's UV set.
    if (prim.material >= 0 && !rm.tangents.empty()) {
        const tinygltf::Material& mat = m_.materials[size_t(prim.material)];
        if (mat.normalTexture.index >= 0) rm.tangentUvSet = mat.normalTexture.texCoord;
    }
    fillZeroNormals(rm);
    scene.instances.push_back(std::move(inst));
}

std::string GltfReader::texturePath(int textureIdx, const std::string& what) const {
    if (textureIdx < 0) return {};
    if (size_t(textureIdx) >= m_.textures.size())
        fail(what, "texture " + std::to_string(textureIdx) + " does not exist");
    int src = m_.textures[size_t(textureIdx)].source;
    if (src < 0) return {};
    if (size_t(src) >= m_.images.size())
        fail(what, "image " + std::to_string(src) + " does not exist");
    const tinygltf::Image& img = m_.images[size_t(src)];
    if (img.uri.empty() || img.uri.rfind("data:", 0) == 0) return {};
    // Percent-decode the URI (glTF URIs are RFC 3986).
    std::string path;
    for (size_t i = 0; i < img.uri.size(); ++i) {
        if (img.uri[i] == '%' && i + 2 < img.uri.size() &&
            std::isxdigit((unsigned char)img.uri[i + 1]) &&
            std::isxdigit((unsigned char)img.uri[i + 2])) {
            path += char(std::stoi(img.uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            path += img.uri[i];
        }
    }
    if (baseDir_.empty()) return path;
    std::string full = (baseDir_ / path).lexically_normal().string();
    if (!limits_.allowOutsideFolder && !io::isInsideFolder(baseDir_, full)) {
        fail(what, "image URI '" + io::printable(img.uri, 200) +
                       "' is outside the model's folder (refused; --allow-outside-uris allows it)");
    }
    return full;
}

void GltfReader::materials(Scene& scene) {
    for (size_t i = 0; i < m_.materials.size(); ++i) {
        const tinygltf::Material& src = m_.materials[i];
        std::string el = "material " + std::to_string(i);
        Material mat;
        mat.name = src.name;
        const auto& f = src.pbrMetallicRoughness.baseColorFactor;
        if (f.size() == 4) {
            for (int c = 0; c < 4; ++c) {
                if (!std::isfinite(f[size_t(c)])) fail(el, "non-finite baseColorFactor");
                mat.baseColorFactor[c] = float(f[size_t(c)]);
            }
        }
        mat.baseColorTexture =
            texturePath(src.pbrMetallicRoughness.baseColorTexture.index, el + " baseColorTexture");
        mat.baseColorTexCoord = src.pbrMetallicRoughness.baseColorTexture.texCoord;
        mat.normalTexture = texturePath(src.normalTexture.index, el + " normalTexture");
        mat.normalTexCoord = src.normalTexture.texCoord;
        if (!std::isfinite(src.normalTexture.scale)) fail(el, "non-finite normalTexture.scale");
        mat.normalScale = float(src.normalTexture.scale);
        mat.doubleSided = src.doubleSided;
        if (mat.baseColorTexCoord < 0 || mat.normalTexCoord < 0 ||
            size_t(mat.baseColorTexCoord) >= limits_.maxUvSets ||
            size_t(mat.normalTexCoord) >= limits_.maxUvSets) {
            fail(el, "texCoord index out of range");
        }
        scene.materials.push_back(std::move(mat));
    }
}

void GltfReader::animations(Scene& scene) {
    for (size_t ai = 0; ai < m_.animations.size(); ++ai) {
        const tinygltf::Animation& anim = m_.animations[ai];
        for (size_t ci = 0; ci < anim.channels.size(); ++ci) {
            const tinygltf::AnimationChannel& ch = anim.channels[ci];
            if (ch.target_path != "weights") continue;
            std::string el = "animation " + std::to_string(ai) + " channel " + std::to_string(ci);
            if (ch.sampler < 0 || size_t(ch.sampler) >= anim.samplers.size())
                fail(el, "sampler " + std::to_string(ch.sampler) + " does not exist");
            if (ch.target_node < 0 || size_t(ch.target_node) >= m_.nodes.size())
                fail(el, "target node " + std::to_string(ch.target_node) + " does not exist");
            const tinygltf::Node& node = m_.nodes[size_t(ch.target_node)];
            if (node.mesh < 0 || size_t(node.mesh) >= m_.meshes.size())
                fail(el, "target node has no mesh to morph");
            const tinygltf::Mesh& mesh = m_.meshes[size_t(node.mesh)];
            size_t targets = mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
            if (targets == 0) fail(el, "target node's mesh has no morph targets");
            const tinygltf::AnimationSampler& s = anim.samplers[size_t(ch.sampler)];
            MorphWeightAnimation out;
            out.name = anim.name.empty() ? "animation" + std::to_string(ai) : anim.name;
            out.node = ch.target_node;
            out.targetCount = targets;
            if (s.interpolation == "STEP")
                out.interpolation = AnimInterpolation::Step;
            else if (s.interpolation == "CUBICSPLINE")
                out.interpolation = AnimInterpolation::CubicSpline;
            else if (s.interpolation.empty() || s.interpolation == "LINEAR")
                out.interpolation = AnimInterpolation::Linear;
            else
                fail(el, "interpolation '" + s.interpolation.substr(0, 32) + "'");
            out.times = readFloats(s.input, 1, false, el + " input");
            out.weights = readFloats(s.output, 1, true, el + " output");
            if (out.times.empty()) fail(el, "no keyframes");
            for (size_t k = 1; k < out.times.size(); ++k) {
                if (!(out.times[k] > out.times[k - 1]))
                    fail(el, "key times are not strictly increasing at key " + std::to_string(k));
            }
            size_t per = out.interpolation == AnimInterpolation::CubicSpline ? 3 : 1;
            if (out.weights.size() != out.times.size() * targets * per) {
                fail(el, std::to_string(out.weights.size()) + " output values for " +
                             std::to_string(out.times.size()) + " keys x " +
                             std::to_string(targets) + " targets" +
                             (per == 3 ? " x 3 (cubic spline)" : ""));
            }
            scene.animations.push_back(std::move(out));
        }
    }
}

Scene GltfReader::read() {
    Scene scene;
    materials(scene);
    // Roots: the default scene, else scene 0, else every node that is nobody's child.
    std::vector<int> roots;
    if (!m_.scenes.empty()) {
        int si = m_.defaultScene >= 0 ? m_.defaultScene : 0;
        if (size_t(si) >= m_.scenes.size())
            fail("scene", "default scene " + std::to_string(si) + " does not exist");
        roots = m_.scenes[size_t(si)].nodes;
    } else {
        std::vector<uint8_t> isChild(m_.nodes.size(), 0);
        for (const tinygltf::Node& n : m_.nodes) {
            for (int c : n.children) {
                if (c >= 0 && size_t(c) < m_.nodes.size()) isChild[size_t(c)] = 1;
            }
        }
        for (size_t i = 0; i < m_.nodes.size(); ++i) {
            if (!isChild[i]) roots.push_back(int(i));
        }
    }
    std::vector<uint8_t> onPath(m_.nodes.size(), 0);
    size_t visits = 0;
    std::function<void(int, const glm::mat4&, int)> visit = [&](int ni, const glm::mat4& parent,
                                                                int depth) {
        std::string el = "node " + std::to_string(ni);
        if (ni < 0 || size_t(ni) >= m_.nodes.size()) fail(el, "does not exist");
        if (onPath[size_t(ni)]) fail(el, "is its own ancestor (cycle in the node graph)");
        if (depth > 64) fail(el, "node hierarchy deeper than 64");
        if (++visits > 100000) fail(el, "more than 100000 node instances (limit)");
        const tinygltf::Node& n = m_.nodes[size_t(ni)];
        glm::mat4 world = parent * localMatrix(n, file_, ni);
        if (n.mesh >= 0) {
            if (size_t(n.mesh) >= m_.meshes.size())
                fail(el, "mesh " + std::to_string(n.mesh) + " does not exist");
            const tinygltf::Mesh& mesh = m_.meshes[size_t(n.mesh)];
            for (size_t p = 0; p < mesh.primitives.size(); ++p)
                primitive(mesh, n.mesh, int(p), ni, world, n.weights, scene);
        }
        onPath[size_t(ni)] = 1;
        for (int c : n.children) visit(c, world, depth + 1);
        onPath[size_t(ni)] = 0;
    };
    for (int r : roots) visit(r, glm::mat4(1.0f), 0);
    if (roots.empty() && m_.nodes.empty()) {
        // No nodes at all: every mesh once, untransformed.
        for (size_t mi = 0; mi < m_.meshes.size(); ++mi) {
            for (size_t p = 0; p < m_.meshes[mi].primitives.size(); ++p)
                primitive(m_.meshes[mi], int(mi), int(p), -1, glm::mat4(1.0f), {}, scene);
        }
        if (!m_.meshes.empty()) note("no nodes: every mesh placed once at the origin");
    }
    if (scene.instances.empty()) fail("", "no triangle primitives in the scene");
    animations(scene);
    return scene;
}

// Why a buffer's data URI failed (tinygltf says only "Failed to decode
// 'uri'" and quotes the whole URI): the first buffer whose base64 payload is
// malformed or decodes to fewer bytes than its byteLength (glTF 2.0 sec.
// 3.6.1.1); empty when none is found. `jsonText` is the glTF JSON.
std::string dataUriProblem(std::string_view jsonText) {
    const nlohmann::json j = nlohmann::json::parse(jsonText, nullptr, false);
    if (!j.is_object() || !j.contains("buffers") || !j["buffers"].is_array()) return {};
    const std::string marker = ";base64,";
    for (size_t i = 0; i < j["buffers"].size(); ++i) {
        const nlohmann::json& b = j["buffers"][i];
        if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string()) continue;
        const std::string& uri = b["uri"].get_ref<const std::string&>();
        if (uri.rfind("data:", 0) != 0) continue;
        const std::string el = "buffer " + std::to_string(i);
        const size_t at = uri.find(marker);
        if (at == std::string::npos)
            return el + ": its data URI is not base64 (\"data:...;base64,...\" expected)";
        const std::string_view payload = std::string_view(uri).substr(at + marker.size());
        size_t chars = 0, pad = 0;
        for (char c : payload) {
            if (std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '/') {
                if (pad) return el + ": its data URI has base64 characters after the '=' padding";
                ++chars;
            } else if (c == '=') {
                ++pad;
            } else {
                return el + ": its data URI holds a character that is not base64";
            }
        }
        const uint64_t bytes = uint64_t(chars) * 3 / 4;
        const uint64_t declared = b.contains("byteLength") && b["byteLength"].is_number_unsigned()
                                      ? b["byteLength"].get<uint64_t>()
                                      : 0;
        if (bytes < declared) {
            return el + ": its data URI decodes to " + std::to_string(bytes) +
                   " bytes, but byteLength is " + std::to_string(declared) + " (truncated?)";
        }
    }
    return {};
}

std::atomic<bool> g_allowOutsideFolder{false};

} // namespace

void setAllowOutsideFolderDefault(bool allow) {
    g_allowOutsideFolder = allow;
}
bool allowOutsideFolderDefault() {
    return g_allowOutsideFolder;
}

Scene parseGltf(std::string_view bytes, const std::string& file,
                const std::filesystem::path& baseDir, const InputLimits& limits,
                LoadReport* report) {
    if (bytes.size() > limits.maxFileBytes) {
        throw InputError(file, "",
                         "file is " + std::to_string(bytes.size()) + " bytes; the limit is " +
                             std::to_string(limits.maxFileBytes));
    }
    bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    if (binary) checkGlbHeader(bytes, file);
    if (bytes.empty()) throw InputError(file, "", "empty file");
    // tinygltf keeps one of two equal keys silently.
    io::checkJsonKeysUnique(binary ? bytes.substr(20, size_t(readU32(bytes, 12))) : bytes, file);
    tinygltf::TinyGLTF loader;
    FsContext ctx{baseDir, &limits, {}};
    tinygltf::FsCallbacks fs{&fsFileExists, &fsExpand, &fsRead, &fsWrite, &ctx};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(&keepImageUndecoded, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    std::string base = baseDir.empty() ? std::string() : baseDir.string();
    bool ok =
        binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                             reinterpret_cast<const unsigned char*>(bytes.data()),
                                             unsigned(bytes.size()), base)
               : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                            unsigned(bytes.size()), base);
    if (!ok) {
        if (ctx.refused.empty() && err.find("'uri'") != std::string::npos) {
            const std::string why =
                dataUriProblem(binary ? bytes.substr(20, size_t(readU32(bytes, 12))) : bytes);
            if (!why.empty())
                throw InputError(file, why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
        }
        std::string msg = !ctx.refused.empty() ? ctx.refused : err;
        while (!msg.empty() && (msg.back() == '\n' || msg.back() == ' ')) msg.pop_back();
        if (msg.size() > 300) msg = msg.substr(0, 300) + "...";
        throw InputError(file, "",
                         "glTF parse error: " + (msg.empty() ? std::string("unknown") : msg));
    }
    if (report && !warn.empty()) {
        std::string w = warn.substr(0, 200);
        while (!w.empty() && w.back() == '\n') w.pop_back();
        report->notes.push_back("tinygltf: " + w);
    }
    GltfReader reader(model, file, limits, report, baseDir);
    return reader.read();
}

} // namespace sg::mesh
