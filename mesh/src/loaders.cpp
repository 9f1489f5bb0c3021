// File-level loaders (surfgrad/mesh/mesh_io.h): dispatch on the extension,
// read with the size limit, parse, validate; merging of glTF scenes into
// one world-space mesh; morph-weight animation sampling (glTF 2.0 sec. 3.11
// and Appendix C, cubic Hermite splines).

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <atomic>
#include <cerrno>

#if defined(__unix__)
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#endif

#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "mesh_internal.h"
#include "surfgrad/base/scratch_buffer.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/base/threads.h"

namespace sg::mesh {

using io::InputError;

std::string meshFormat(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool isMeshFormat(const std::filesystem::path& path) {
    const std::string ext = meshFormat(path);
    for (std::string_view f : kMeshFormats) {
        if (ext == f) return true;
    }
    return false;
}

namespace {

bool isGltf(const std::string& ext) {
    return ext == ".gltf" || ext == ".glb";
}

[[noreturn]] void unknownFormat(const std::filesystem::path& path, const std::string& ext) {
    throw InputError(path.string(), "",
                     "unknown mesh format '" + io::printable(ext, 16) + "' (expected " +
                         std::string(kMeshFormatsText) + ")");
}

Scene readGltf(const std::filesystem::path& path, const LoadOptions& options, LoadReport* report) {
    std::string bytes = io::readFile(path, options.limits.maxFileBytes);
    std::filesystem::path base = path.parent_path();
    if (base.empty()) base = ".";
    return parseGltf(bytes, path.string(), base, options.limits, report);
}

// "TEXCOORD_1" or "TEXCOORD_1..TEXCOORD_3" (sets first..last).
std::string uvSetRange(size_t first, size_t last) {
    std::string s = "TEXCOORD_" + std::to_string(first);
    if (last > first) s += "..TEXCOORD_" + std::to_string(last);
    return s;
}

// Why the merged mesh has only `kept` UV sets while some primitive has
// `most`: which sets are gone and the first primitive that lacks them.
std::string droppedUvSetsNote(const Scene& scene, size_t kept, size_t most) {
    std::string where;
    for (const SceneInstance& inst : scene.instances) {
        if (inst.mesh.uvSets.size() != kept) continue;
        where = "primitive " + std::to_string(inst.primitive) + " of mesh " +
                std::to_string(inst.meshIndex) +
                (inst.mesh.name.empty() ? "" : " '" + io::printable(inst.mesh.name, 40) + "'") +
                (inst.node >= 0 ? " (node " + std::to_string(inst.node) + ")" : "");
        break;
    }
    return "UV sets " + uvSetRange(kept, most - 1) + " dropped from every primitive: " + where +
           (kept == 0 ? " has no texture coordinates" : " has only " + uvSetRange(0, kept - 1)) +
           ", and a merged mesh keeps only the sets every primitive has (loadScene and "
           "`surfgrad render` keep each primitive's own)";
}

// World-space merge of every instance (see loadRenderMesh).
RenderMesh mergeScene(const Scene& scene, LoadReport* report) {
    RenderMesh out;
    size_t nSets = SIZE_MAX, nTargets = scene.instances.front().mesh.morphTargets.size();
    bool allNormals = true, allTangents = true, sameTargets = true;
    for (const SceneInstance& inst : scene.instances) {
        nSets = std::min(nSets, inst.mesh.uvSets.size());
        allNormals &= !inst.mesh.normals.empty();
        allTangents &= !inst.mesh.tangents.empty();
        sameTargets &= inst.mesh.morphTargets.size() == nTargets;
    }
    if (!sameTargets) nTargets = 0;
    if (report) {
        size_t maxSets = 0;
        for (const SceneInstance& inst : scene.instances)
            maxSets = std::max(maxSets, inst.mesh.uvSets.size());
        if (maxSets > nSets) report->notes.push_back(droppedUvSetsNote(scene, nSets, maxSets));
        if (!sameTargets)
            report->notes.push_back(
                "morph targets dropped: primitives have different numbers of targets");
    }
    out.name = scene.instances.size() == 1 ? scene.instances[0].mesh.name : "scene";
    out.uvSets.resize(nSets);
    out.morphTargets.resize(nTargets);
    if (nTargets) out.morphWeights = scene.instances.front().mesh.morphWeights;
    int tangentSet = scene.instances.front().mesh.tangentUvSet;
    for (const SceneInstance& inst : scene.instances) {
        if (inst.mesh.tangentUvSet != tangentSet) allTangents = false;
    }
    for (const SceneInstance& inst : scene.instances) {
        const RenderMesh& m = inst.mesh;
        const glm::mat4& M = inst.objectToWorld;
        glm::mat3 L(M);
        float det = glm::determinant(L);
        glm::mat3 N = std::abs(det) > 0.0f ? glm::transpose(glm::inverse(L)) : L;
        uint32_t base = uint32_t(out.positions.size());
        for (const glm::vec3& p : m.positions)
            out.positions.push_back(glm::vec3(M * glm::vec4(p, 1.0f)));
        auto unit = [](glm::vec3 v, const glm::vec3& fallback) {
            float len = glm::length(v);
            return len > 0.0f && std::isfinite(len) ? v / len : fallback;
        };
        if (allNormals) {
            for (const glm::vec3& n : m.normals) out.normals.push_back(unit(N * n, n));
        }
        if (allTangents) {
            // A mirroring transform flips the handedness of the frame.
            float flip = det < 0.0f ? -1.0f : 1.0f;
            for (const glm::vec4& t : m.tangents)
                out.tangents.push_back(glm::vec4(unit(L * glm::vec3(t), glm::vec3(t)), t.w * flip));
        }
        for (size_t s = 0; s < nSets; ++s)
            out.uvSets[s].insert(out.uvSets[s].end(), m.uvSets[s].begin(), m.uvSets[s].end());
        for (size_t k = 0; k < m.indices.size(); k += 3) {
            // A mirroring transform turns CCW into CW: swap to keep fronts.
            if (det < 0.0f)
                out.indices.insert(out.indices.end(), {base + m.indices[k], base + m.indices[k + 2],
                                                       base + m.indices[k + 1]});
            else
                out.indices.insert(out.indices.end(), {base + m.indices[k], base + m.indices[k + 1],
                                                       base + m.indices[k + 2]});
        }
        for (size_t t = 0; t < nTargets; ++t) {
            const MorphTarget& src = m.morphTargets[t];
            MorphTarget& dst = out.morphTargets[t];
            auto append = [&](const std::vector<glm::vec3>& d, std::vector<glm::vec3>& o,
                              const glm::mat3& X) {
                o.resize(base, glm::vec3(0.0f)); // earlier instances may lack the field
                if (d.empty())
                    o.resize(base + m.positions.size(), glm::vec3(0.0f));
                else
                    for (const glm::vec3& v : d) o.push_back(X * v);
            };
            append(src.positionDeltas, dst.positionDeltas, L);
            if (allNormals) append(src.normalDeltas, dst.normalDeltas, N);
            if (allTangents) append(src.tangentDeltas, dst.tangentDeltas, L);
            if (dst.name.empty()) dst.name = src.name;
        }
    }
    if (allTangents) out.tangentUvSet = tangentSet;
    if (!allNormals) {
        out.normals.clear();
        for (MorphTarget& t : out.morphTargets) t.normalDeltas.clear();
    }
    if (!allTangents) {
        out.tangents.clear();
        for (MorphTarget& t : out.morphTargets) t.tangentDeltas.clear();
    }
    // Targets that are all zero in a field collapse to empty (as if absent).
    for (MorphTarget& t : out.morphTargets) {
        for (auto* d : {&t.positionDeltas, &t.normalDeltas, &t.tangentDeltas}) {
            if (!d->empty() && std::all_of(d->begin(), d->end(), [](const glm::vec3& v) {
                    return v == glm::vec3(0.0f);
                })) {
                d->clear();
            }
        }
    }
    return out;
}

// Drops triangles with a repeated index (repair) or counts them.
void checkRenderMesh(RenderMesh& mesh, const std::string& file, bool repair, LoadReport* report) {
    if (mesh.positions.empty() || mesh.indices.empty())
        throw InputError(file, "", "empty mesh: no triangles");
    size_t bad = 0, out = 0;
    for (size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
        uint32_t a = mesh.indices[k], b = mesh.indices[k + 1], c = mesh.indices[k + 2];
        bool degenerate = a == b || b == c || a == c;
        bad += degenerate;
        if (degenerate && repair) continue;
        mesh.indices[out++] = a;
        mesh.indices[out++] = b;
        mesh.indices[out++] = c;
    }
    mesh.indices.resize(out);
    if (bad && report) {
        if (repair) {
            report->degenerateFacesDropped += bad;
            report->notes.push_back("dropped " + std::to_string(bad) + " degenerate triangles");
        } else {
            report->notes.push_back(std::to_string(bad) +
                                    " degenerate triangles (kept; --repair drops them)");
        }
    }
    if (mesh.indices.empty())
        throw InputError(file, "", "empty mesh: every triangle is degenerate");
    if (mesh.normals.empty()) computeVertexNormals(mesh);
}

// A text file's bytes, for the OBJ reader: io::readFile's checks and
// messages (it is called for every case but a plain regular file within
// the limit), read into scratch storage (no zero fill; huge pages for a
// large file) by `threads` threads, each reading its own 8 MiB pieces with
// pread (the copy from the page cache and the first touch of the pages
// are most of the time).
sg::detail::ScratchVector<char> readText(const std::filesystem::path& path, size_t maxBytes,
                                         int threads) {
    sg::detail::ScratchVector<char> text;
    auto viaReadFile = [&] {
        const std::string s = io::readFile(path, maxBytes);
        text.assign(s.begin(), s.end());
        return std::move(text);
    };
#if defined(__unix__)
    struct Fd {
        int fd;
        ~Fd() {
            if (fd >= 0) ::close(fd);
        }
    } f{::open(path.c_str(), O_RDONLY | O_CLOEXEC)};
    struct stat st {};
    if (f.fd < 0 || ::fstat(f.fd, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size < 0 ||
        uint64_t(st.st_size) > maxBytes) {
        return viaReadFile();
    }
    const size_t size = size_t(st.st_size);
    text.resize(size);
    constexpr size_t kPieceBytes = size_t(8) << 20;
    const size_t pieces = (size + kPieceBytes - 1) / kPieceBytes;
    std::atomic<bool> shortRead{false};
    auto readPiece = [&](size_t i) {
        size_t at = i * kPieceBytes;
        const size_t end = std::min(size, at + kPieceBytes);
        while (at < end) {
            const ssize_t got = ::pread(f.fd, text.data() + at, end - at, off_t(at));
            if (got <= 0) {
                if (got < 0 && errno == EINTR) continue;
                shortRead = true; // the file shrank or cannot be read
                return;
            }
            at += size_t(got);
        }
    };
    if (threads == 1 || pieces < 2) {
        for (size_t i = 0; i < pieces; ++i) readPiece(i);
    } else {
        runWithThreads(threads, [&] {
            tbb::parallel_for(size_t(0), pieces, readPiece, tbb::simple_partitioner());
        });
    }
    if (shortRead) return viaReadFile();
    return text;
#else
    (void)threads;
    return viaReadFile();
#endif
}

} // namespace

PolygonMesh loadPolygonMesh(const std::filesystem::path& path, const LoadOptions& options,
                            LoadReport* report) {
    SG_EXPECTS(options.threads >= 0 && options.threads <= kMaxThreads,
               "0 (all cores) or 1..1024 threads (surfgrad/base/threads.h)");
    const std::string file = path.string();
    const std::string ext = meshFormat(path);
    PolygonMesh mesh;
    std::vector<uint32_t> faceLines;
    if (ext == ".obj") {
        const sg::detail::ScratchVector<char> text =
            readText(path, options.limits.maxFileBytes, options.threads);
        mesh = detail::parseObjImpl(std::string_view(text.data(), text.size()), file,
                                    options.limits, report, &faceLines, options.threads);
    } else if (ext == ".off" || ext == ".ply" || ext == ".stl") {
        if (!std::filesystem::is_regular_file(path))
            io::readFile(path, 0); // throws the usual "no such file"
        mesh = detail::readWithOpenMesh(path, options.limits, report);
    } else if (isGltf(ext)) {
        mesh = toPolygonMesh(mergeScene(readGltf(path, options, report), report));
    } else {
        unknownFormat(path, ext);
    }
    if (mesh.name.empty() || ext == ".obj") mesh.name = path.stem().string();
    detail::validateImpl(mesh, file, options.repair, report, options.limits,
                         options.allowNonManifold, faceLines.empty() ? nullptr : &faceLines);
    return mesh;
}

RenderMesh loadRenderMesh(const std::filesystem::path& path, const LoadOptions& options,
                          LoadReport* report) {
    SG_EXPECTS(options.threads >= 0 && options.threads <= kMaxThreads,
               "0 (all cores) or 1..1024 threads (surfgrad/base/threads.h)");
    const std::string ext = meshFormat(path);
    if (isGltf(ext)) {
        RenderMesh mesh = mergeScene(readGltf(path, options, report), report);
        checkRenderMesh(mesh, path.string(), options.repair, report);
        return mesh;
    }
    // Rendering needs no manifold topology.
    LoadOptions o = options;
    o.allowNonManifold = true;
    return toRenderMesh(loadPolygonMesh(path, o, report));
}

Scene loadScene(const std::filesystem::path& path, const LoadOptions& options, LoadReport* report) {
    SG_EXPECTS(options.threads >= 0 && options.threads <= kMaxThreads,
               "0 (all cores) or 1..1024 threads (surfgrad/base/threads.h)");
    const std::string ext = meshFormat(path);
    if (isGltf(ext)) {
        Scene scene = readGltf(path, options, report);
        for (SceneInstance& inst : scene.instances)
            checkRenderMesh(inst.mesh, path.string(), options.repair, report);
        return scene;
    }
    Scene scene;
    SceneInstance inst;
    inst.mesh = loadRenderMesh(path, options, report);
    scene.instances.push_back(std::move(inst));
    return scene;
}

std::vector<float> sampleWeights(const MorphWeightAnimation& anim, float seconds) {
    const size_t T = anim.targetCount, K = anim.times.size();
    std::vector<float> out(T, 0.0f);
    if (K == 0 || T == 0) return out;
    const bool cubic = anim.interpolation == AnimInterpolation::CubicSpline;
    // Value of target t at key k (cubic keys store in-tangent, value, out-tangent).
    auto value = [&](size_t k, size_t t) {
        return cubic ? anim.weights[(3 * k + 1) * T + t] : anim.weights[k * T + t];
    };
    if (!(seconds > anim.times.front())) { // also NaN: the first key
        for (size_t t = 0; t < T; ++t) out[t] = value(0, t);
        return out;
    }
    if (seconds >= anim.times.back()) {
        for (size_t t = 0; t < T; ++t) out[t] = value(K - 1, t);
        return out;
    }
    size_t k = size_t(std::upper_bound(anim.times.begin(), anim.times.end(), seconds) -
                      anim.times.begin()) -
               1;
    float t0 = anim.times[k], t1 = anim.times[k + 1], dt = t1 - t0;
    float u = (seconds - t0) / dt; // dt > 0: times are strictly increasing (checked on load)
    for (size_t t = 0; t < T; ++t) {
        switch (anim.interpolation) {
        case AnimInterpolation::Step:
            out[t] = value(k, t);
            break;
        case AnimInterpolation::Linear:
            out[t] = value(k, t) + u * (value(k + 1, t) - value(k, t));
            break;
        case AnimInterpolation::CubicSpline: {
            float outTangent = anim.weights[(3 * k + 2) * T + t],
                  inTangent = anim.weights[(3 * (k + 1)) * T + t];
            float u2 = u * u, u3 = u2 * u;
            out[t] = (2 * u3 - 3 * u2 + 1) * value(k, t) + (u3 - 2 * u2 + u) * dt * outTangent +
                     (-2 * u3 + 3 * u2) * value(k + 1, t) + (u3 - u2) * dt * inTangent;
            break;
        }
        }
    }
    return out;
}

} // namespace sg::mesh
