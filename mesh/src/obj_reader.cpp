// Wavefront OBJ tokenizer with OpenSubdiv's "t" tag lines
// (surfgrad/mesh/mesh_io.h: parseObj). Own code because OpenMesh's OBJ reader
// ignores tags and drops faces at non-manifold edges without a word; this
// one keeps every face as written so validation can name what is wrong.
//
// Tag syntax (OpenSubdiv regression/common/shape_utils, Hbr heritage):
//   t <name> <nInts>/<nFloats>/<nStrings> <ints...> <floats...> <strings...>
// crease: the ints are a chain of vertices (2 for one edge), with one
// sharpness for the whole chain or one per edge; corner: vertices with one
// sharpness or one each; hole: face indices; interpolateboundary k;
// facevaryinginterpolateboundary k; creasemethod normal|chaikin;
// smoothtriangles catmark; and our own "scheme catmark|loop|bilinear".
// Indices in tags are 0-based; in v/vt/vn/f statements 1-based or negative
// (relative to the end of the list so far), as OBJ defines. Messages name
// vertices and faces as the file numbers them: v statements and faces from
// 1 (the face with its line), tag indices as written.
//
// Untrusted input: every count is bounded by InputLimits, every number is
// parsed with std::from_chars (no locale, no exceptions), and every error
// names the line.
#include <algorithm>
#include <charconv>
#include <cstring>
#include <string_view>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "mesh_internal.h"
#include "surfgrad/base/scratch_buffer.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/base/threads.h"

namespace sg::mesh {

using io::InputError;

namespace {

struct Tokenizer {
    std::string_view line;
    size_t pos = 0;
    bool next(std::string_view& tok) {
        while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t')) ++pos;
        if (pos >= line.size()) return false;
        size_t b = pos;
        while (pos < line.size() && line[pos] != ' ' && line[pos] != '\t') ++pos;
        tok = line.substr(b, pos - b);
        return true;
    }
};

bool parseFloat(std::string_view tok, float& out) {
    if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
    auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

bool parseInt(std::string_view tok, int64_t& out) {
    if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
    auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

// One run of statements: the whole text (the serial reader, exact mode)
// or one line-aligned block of it (block mode). In block mode everything
// the file before the block decides is left for the assembly: line numbers
// and the v/vt/vn counts are local, a negative (relative) index is stored
// as local count + index and listed in rel*, and any InputError only marks
// the block (the serial reader then names the first error of the file).
struct ObjBlock {
    ObjBlock(const std::string& file, const InputLimits& limits, bool blockMode)
        : file_(file), limits_(limits), blockMode_(blockMode) {}

    void reserveFor(std::string_view text);
    // The statements of `text`; throws InputError at the first bad one.
    void parseLines(std::string_view text);

    [[noreturn]] void fail(const std::string& reason) const {
        throw InputError(file_, "line " + std::to_string(lineNo_), reason);
    }
    void vertex(Tokenizer& t);
    void texcoord(Tokenizer& t);
    void normal(Tokenizer& t);
    void face(Tokenizer& t);
    void tag(Tokenizer& t);
    // Resolves a 1-based or negative OBJ index against `count` entries so
    // far (block mode: a negative one is resolved later, see rel*).
    int64_t resolve(int64_t idx, size_t count, const char* what, std::vector<uint32_t>& rel) {
        if (idx == 0) fail(std::string(what) + " index 0 (OBJ indices start at 1)");
        if (idx < 0) {
            if (blockMode_) {
                rel.push_back(uint32_t(cornerV_.size()));
                return int64_t(count) + idx;
            }
            if (uint64_t(-idx) > count)
                fail(std::string(what) + " index " + std::to_string(idx) +
                     " reaches before the first " + what);
            return int64_t(count) + idx;
        }
        return idx - 1;
    }

    const std::string& file_;
    const InputLimits& limits_;
    bool blockMode_;
    size_t lineNo_ = 0; // lines read (block mode: within the block)

    PolygonMesh mesh_; // positions, faceSizes, tags, options, explicitTags
    std::vector<glm::vec2> uvs_;
    std::vector<glm::vec3> normals_;
    // Per corner, 0-based (or -1 when the corner has none); range-checked
    // after the whole file is read (forward references).
    std::vector<int64_t> cornerV_, cornerT_, cornerN_;
    // Block mode: corners (local numbers) whose v, vt or vn index was
    // negative, stored relative to the block's first v, vt or vn.
    std::vector<uint32_t> relV_, relT_, relN_;
    std::vector<uint32_t> faceLine_; // block mode: line within the block
    size_t ignored_ = 0;
    std::string firstIgnored_;
    std::vector<std::string> unknownTags_;
};

void ObjBlock::vertex(Tokenizer& t) {
    glm::vec3 p;
    std::string_view tok;
    for (int i = 0; i < 3; ++i) {
        if (!t.next(tok)) fail("vertex with fewer than 3 coordinates");
        if (!parseFloat(tok, p[i])) fail("bad number '" + io::printable(tok, 32) + "'");
    }
    if (!detail::finite(p)) {
        // Named as the file numbers it (v statements count from 1).
        throw InputError(file_, "vertex " + std::to_string(mesh_.positions.size() + 1),
                         "non-finite coordinate " + detail::vecString(p) + " (line " +
                             std::to_string(lineNo_) + ")");
    }
    if (mesh_.positions.size() >= limits_.maxVertices) {
        fail("more than " + std::to_string(limits_.maxVertices) + " vertices (limit)");
    }
    mesh_.positions.push_back(p); // a 4th (w) or colour values are ignored
}

void ObjBlock::texcoord(Tokenizer& t) {
    glm::vec2 uv(0.0f);
    std::string_view tok;
    if (!t.next(tok)) fail("vt without coordinates");
    if (!parseFloat(tok, uv.x)) fail("bad number '" + io::printable(tok, 32) + "'");
    if (t.next(tok) && !parseFloat(tok, uv.y)) fail("bad number '" + io::printable(tok, 32) + "'");
    if (!detail::finite(uv)) fail("non-finite texture coordinate");
    if (uvs_.size() >= limits_.maxCorners)
        fail("more than " + std::to_string(limits_.maxCorners) + " texture coordinates (limit)");
    uvs_.push_back(uv);
}

void ObjBlock::normal(Tokenizer& t) {
    glm::vec3 n;
    std::string_view tok;
    for (int i = 0; i < 3; ++i) {
        if (!t.next(tok)) fail("vn with fewer than 3 coordinates");
        if (!parseFloat(tok, n[i])) fail("bad number '" + io::printable(tok, 32) + "'");
    }
    if (!detail::finite(n)) fail("non-finite normal");
    if (normals_.size() >= limits_.maxCorners)
        fail("more than " + std::to_string(limits_.maxCorners) + " normals (limit)");
    normals_.push_back(n);
}

void ObjBlock::face(Tokenizer& t) {
    std::string_view tok;
    uint32_t degree = 0;
    while (t.next(tok)) {
        if (degree >= limits_.maxFaceDegree)
            fail("face with more than " + std::to_string(limits_.maxFaceDegree) +
                 " corners (limit)");
        if (cornerV_.size() >= limits_.maxCorners)
            fail("more than " + std::to_string(limits_.maxCorners) + " face corners (limit)");
        // v, v/vt, v//vn, v/vt/vn
        std::string_view parts[3];
        int nParts = 0;
        size_t b = 0;
        for (size_t i = 0; i <= tok.size(); ++i) {
            if (i == tok.size() || tok[i] == '/') {
                if (nParts == 3)
                    fail("corner '" + io::printable(tok, 32) + "' has more than 3 parts");
                parts[nParts++] = tok.substr(b, i - b);
                b = i + 1;
            }
        }
        int64_t v = 0, vt = -1, vn = -1;
        if (!parseInt(parts[0], v)) fail("bad vertex index '" + io::printable(tok, 32) + "'");
        v = resolve(v, mesh_.positions.size(), "vertex", relV_);
        if (nParts > 1 && !parts[1].empty()) {
            if (!parseInt(parts[1], vt)) fail("bad texture index '" + io::printable(tok, 32) + "'");
            vt = resolve(vt, uvs_.size(), "texture coordinate", relT_);
        }
        if (nParts > 2 && !parts[2].empty()) {
            if (!parseInt(parts[2], vn)) fail("bad normal index '" + io::printable(tok, 32) + "'");
            vn = resolve(vn, normals_.size(), "normal", relN_);
        }
        cornerV_.push_back(v);
        cornerT_.push_back(vt);
        cornerN_.push_back(vn);
        ++degree;
    }
    if (mesh_.faceSizes.size() >= limits_.maxFaces)
        fail("more than " + std::to_string(limits_.maxFaces) + " faces (limit)");
    // Faces with fewer than 3 corners are kept: validation names them
    // (degenerate; --repair drops them).
    mesh_.faceSizes.push_back(degree);
    faceLine_.push_back(uint32_t(std::min<size_t>(lineNo_, UINT32_MAX)));
}

void ObjBlock::tag(Tokenizer& t) {
    std::string_view name, counts, tok;
    if (!t.next(name)) fail("'t' without a tag name");
    if (!t.next(counts))
        fail("tag '" + io::printable(name, 32) +
             "' without counts (expected nInts/nFloats/nStrings)");
    int64_t n[3] = {0, 0, 0};
    {
        size_t b = 0;
        int k = 0;
        for (size_t i = 0; i <= counts.size(); ++i) {
            if (i == counts.size() || counts[i] == '/') {
                if (k == 3 || !parseInt(counts.substr(b, i - b), n[k]) || n[k] < 0) {
                    fail("tag counts '" + io::printable(counts, 32) +
                         "' are not nInts/nFloats/nStrings");
                }
                ++k;
                b = i + 1;
            }
        }
        if (k != 3)
            fail("tag counts '" + io::printable(counts, 32) + "' are not nInts/nFloats/nStrings");
    }
    // Every value is one token on this line, so the counts are bounded by
    // the line length; check before reserving anything.
    if (uint64_t(n[0]) + uint64_t(n[1]) + uint64_t(n[2]) > t.line.size()) {
        fail("tag declares " + std::to_string(n[0] + n[1] + n[2]) +
             " values but the line is shorter");
    }
    std::vector<int64_t> ints(static_cast<size_t>(n[0]));
    std::vector<float> floats(static_cast<size_t>(n[1]));
    std::vector<std::string> strings(static_cast<size_t>(n[2]));
    for (auto& v : ints) {
        if (!t.next(tok) || !parseInt(tok, v))
            fail("tag '" + std::string(name) + "': missing or bad integer");
    }
    for (auto& v : floats) {
        if (!t.next(tok) || !parseFloat(tok, v))
            fail("tag '" + std::string(name) + "': missing or bad number");
        if (!std::isfinite(v)) fail("tag '" + std::string(name) + "': non-finite number");
    }
    for (auto& v : strings) {
        if (!t.next(tok)) fail("tag '" + std::string(name) + "': missing string");
        v = std::string(tok);
    }
    auto index = [&](int64_t v) -> uint32_t {
        if (v < 0 || v > int64_t(UINT32_MAX - 1))
            fail("tag '" + std::string(name) + "': index " + std::to_string(v) + " out of range");
        return uint32_t(v);
    };
    auto oneInt = [&]() -> int64_t {
        if (ints.size() != 1) fail("tag '" + std::string(name) + "' takes 1 integer");
        return ints[0];
    };
    auto oneString = [&]() -> const std::string& {
        if (strings.size() != 1) fail("tag '" + std::string(name) + "' takes 1 string");
        return strings[0];
    };
    if (name == "crease") {
        if (ints.size() < 2) fail("crease needs at least 2 vertices");
        if (floats.size() != 1 && floats.size() != ints.size() - 1) {
            fail("crease with " + std::to_string(ints.size()) + " vertices needs 1 or " +
                 std::to_string(ints.size() - 1) + " sharpness values");
        }
        for (size_t i = 0; i + 1 < ints.size(); ++i) {
            mesh_.creases.push_back(
                {index(ints[i]), index(ints[i + 1]), floats.size() == 1 ? floats[0] : floats[i]});
        }
    } else if (name == "corner") {
        if (ints.empty()) fail("corner needs at least 1 vertex");
        if (floats.size() != 1 && floats.size() != ints.size())
            fail("corner needs 1 sharpness or one per vertex");
        for (size_t i = 0; i < ints.size(); ++i) {
            mesh_.corners.push_back({index(ints[i]), floats.size() == 1 ? floats[0] : floats[i]});
        }
    } else if (name == "hole") {
        for (int64_t f : ints) mesh_.holes.push_back(index(f));
    } else if (name == "interpolateboundary") {
        int64_t k = oneInt();
        if (k < 0 || k > 2)
            fail("interpolateboundary " + std::to_string(k) + " (expected 0, 1 or 2)");
        static constexpr BoundaryInterpolation kMap[3] = {BoundaryInterpolation::None,
                                                          BoundaryInterpolation::EdgeAndCorner,
                                                          BoundaryInterpolation::EdgeOnly};
        mesh_.options.boundary = kMap[k];
        mesh_.explicitTags |= kTagBoundary;
    } else if (name == "facevaryinginterpolateboundary") {
        int64_t k = oneInt();
        if (k < 0 || k > 5)
            fail("facevaryinginterpolateboundary " + std::to_string(k) + " (expected 0..5)");
        mesh_.options.fvar = FVarInterpolation(k);
        mesh_.explicitTags |= kTagFVar;
    } else if (name == "creasemethod") {
        const std::string& s = oneString();
        if (s == "normal")
            mesh_.options.creaseMethod = CreaseMethod::Uniform;
        else if (s == "chaikin")
            mesh_.options.creaseMethod = CreaseMethod::Chaikin;
        else
            fail("creasemethod '" + s.substr(0, 32) + "' (expected normal or chaikin)");
        mesh_.explicitTags |= kTagCreaseMethod;
    } else if (name == "smoothtriangles") {
        const std::string& s = oneString();
        if (s != "catmark") fail("smoothtriangles '" + s.substr(0, 32) + "' (expected catmark)");
        mesh_.options.triangles = TriangleRule::Smooth;
        mesh_.explicitTags |= kTagTriangles;
    } else if (name == "scheme") {
        const std::string& s = oneString();
        if (!parseScheme(s, mesh_.options.scheme))
            fail("scheme '" + s.substr(0, 32) + "' (expected catmark, loop or bilinear)");
        mesh_.explicitTags |= kTagScheme;
    } else {
        std::string tagName = io::printable(name, 40);
        if (std::find(unknownTags_.begin(), unknownTags_.end(), tagName) == unknownTags_.end() &&
            unknownTags_.size() < 16) {
            unknownTags_.push_back(tagName);
        }
    }
}

// Storage for the statements a quick scan of the line starts counts (each
// within its limit), reserved before parsing: no reallocation copies, and
// fresh blocks get huge pages before they are filled (scratch_buffer.h: on
// a VM the first touch of 4 KiB pages is most of the cost of a large file).
void ObjBlock::reserveFor(std::string_view text) {
    size_t v = 0, vt = 0, vn = 0, f = 0;
    for (size_t pos = 0; pos < text.size();) {
        const char* p = text.data() + pos;
        if (p[0] == 'v' && pos + 1 < text.size()) {
            v += p[1] == ' ' || p[1] == '\t';
            vt += p[1] == 't';
            vn += p[1] == 'n';
        }
        f += p[0] == 'f';
        const void* eol = std::memchr(p, '\n', text.size() - pos);
        pos = eol ? size_t(static_cast<const char*>(eol) - text.data()) + 1 : text.size();
    }
    auto reserve = [](auto& vec, size_t n, size_t limit) {
        sg::detail::reserveWithHugePages(vec, std::min(n, limit));
    };
    reserve(mesh_.positions, v, limits_.maxVertices);
    reserve(uvs_, vt, limits_.maxCorners);
    reserve(normals_, vn, limits_.maxCorners);
    reserve(mesh_.faceSizes, f, limits_.maxFaces);
    reserve(faceLine_, f, limits_.maxFaces);
    // Triangles are the common case; larger faces grow the vectors.
    for (auto* c : {&cornerV_, &cornerT_, &cornerN_}) reserve(*c, 3 * f, limits_.maxCorners);
}

void ObjBlock::parseLines(std::string_view text) {
    size_t pos = 0;
    while (pos < text.size()) {
        size_t eol = text.find('\n', pos);
        if (eol == std::string_view::npos) eol = text.size();
        std::string_view line = text.substr(pos, eol - pos);
        pos = eol + 1;
        ++lineNo_;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        Tokenizer t{line};
        std::string_view kw;
        if (!t.next(kw) || kw.front() == '#') continue;
        if (kw == "v")
            vertex(t);
        else if (kw == "vt")
            texcoord(t);
        else if (kw == "vn")
            normal(t);
        else if (kw == "f")
            face(t);
        else if (kw == "t")
            tag(t);
        else {
            if (ignored_++ == 0) firstIgnored_ = io::printable(kw, 16);
        }
    }
}

// Where a block's items start in the file's arrays (and, for the sum over
// every block, how many there are).
struct BlockBase {
    size_t positions = 0, uvs = 0, normals = 0, corners = 0, faces = 0, lines = 0;
    void add(const ObjBlock& b) {
        positions += b.mesh_.positions.size();
        uvs += b.uvs_.size();
        normals += b.normals_.size();
        corners += b.cornerV_.size();
        faces += b.mesh_.faceSizes.size();
        lines += b.lineNo_;
    }
};

// f(b) for every block: on this thread for one block, else in parallel
// (each call writes only block b's own data or its own slice of an output).
template <class F>
void forEachBlock(size_t count, F&& f) {
    if (count == 1) {
        f(size_t(0));
        return;
    }
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, count, 1),
        [&](const tbb::blocked_range<size_t>& r) {
            for (size_t b = r.begin(); b != r.end(); ++b) f(b);
        },
        tbb::simple_partitioner());
}

// out = the blocks' vectors get(block) one after another (moved for one block).
template <class T, class Get>
void concatenate(std::vector<T>& out, std::vector<ObjBlock>& blocks,
                 const std::vector<BlockBase>& bases, size_t BlockBase::*base, size_t total,
                 Get get) {
    if (blocks.size() == 1) {
        out = std::move(get(blocks[0]));
        return;
    }
    sg::detail::reserveWithHugePages(out, total);
    out.resize(total);
    forEachBlock(blocks.size(), [&](size_t b) {
        const std::vector<T>& v = get(blocks[b]);
        std::copy(v.begin(), v.end(), out.begin() + ptrdiff_t(bases[b].*base));
    });
}

// Per block, what the corners' resolution needs to know.
struct CornerSummary {
    bool anyUv = false, allUv = true, anyN = false, allN = true;
    size_t withoutUv = 0;
    // First corner (local number) whose index is out of range, per kind.
    size_t badV = SIZE_MAX, badT = SIZE_MAX, badN = SIZE_MAX;
    // The count the serial reader names with a bad vt index (the vt values
    // plus the (0,0) fallback once a corner without vt came before).
    size_t badTBound = 0;
};

// The line of a block's corner c (for messages).
uint32_t cornerLine(const ObjBlock& block, const BlockBase& base, size_t c) {
    size_t f = 0;
    for (size_t first = 0; f < block.mesh_.faceSizes.size(); ++f) {
        first += block.mesh_.faceSizes[f];
        if (c < first) break;
    }
    f = std::min(f, block.faceLine_.size() - 1);
    return uint32_t(std::min<size_t>(base.lines + block.faceLine_[f], UINT32_MAX));
}

// The tags of every block in file order (creases, corners and holes
// appended; an option set by a later tag replaces an earlier one, as the
// serial reader does) and the report's notes.
void applyTagsAndNotes(PolygonMesh& mesh, std::vector<ObjBlock>& blocks, LoadReport* report,
                       size_t withoutUv, bool anyUv, bool allUv, bool anyN, bool allN) {
    size_t ignored = 0;
    std::string firstIgnored;
    std::vector<std::string> unknownTags;
    for (ObjBlock& k : blocks) {
        const PolygonMesh& m = k.mesh_;
        mesh.creases.insert(mesh.creases.end(), m.creases.begin(), m.creases.end());
        mesh.corners.insert(mesh.corners.end(), m.corners.begin(), m.corners.end());
        mesh.holes.insert(mesh.holes.end(), m.holes.begin(), m.holes.end());
        if (m.explicitTags & kTagBoundary) mesh.options.boundary = m.options.boundary;
        if (m.explicitTags & kTagFVar) mesh.options.fvar = m.options.fvar;
        if (m.explicitTags & kTagCreaseMethod) mesh.options.creaseMethod = m.options.creaseMethod;
        if (m.explicitTags & kTagTriangles) mesh.options.triangles = m.options.triangles;
        if (m.explicitTags & kTagScheme) mesh.options.scheme = m.options.scheme;
        mesh.explicitTags |= m.explicitTags;
        if (ignored == 0 && k.ignored_ > 0) firstIgnored = k.firstIgnored_;
        ignored += k.ignored_;
        // A block keeps its first 16 distinct names: every name among the
        // file's first 16 is among its block's first 16.
        for (const std::string& tag : k.unknownTags_) {
            if (std::find(unknownTags.begin(), unknownTags.end(), tag) == unknownTags.end() &&
                unknownTags.size() < 16) {
                unknownTags.push_back(tag);
            }
        }
    }
    if (!report) return;
    if (anyUv && withoutUv && !allUv) {
        report->notes.push_back(std::to_string(withoutUv) +
                                " face corners without vt got UV (0,0)");
    }
    if (anyN && !allN)
        report->notes.push_back("vn on some corners only: normals ignored (recomputed)");
    if (ignored) {
        report->notes.push_back("ignored " + std::to_string(ignored) + " statements (first: '" +
                                firstIgnored + "')");
    }
    for (const std::string& tag : unknownTags)
        report->notes.push_back("ignored unknown tag '" + tag + "'");
}

// The mesh from parsed blocks in file order (one block: the serial reader),
// their relative indices already resolved: corner indices range-checked
// (the first bad one in file order throws, v before vt before vn, as the
// serial reader checks them), arrays concatenated, tags applied in order.
PolygonMesh assemble(std::vector<ObjBlock>& blocks, const std::vector<BlockBase>& bases,
                     const BlockBase& total, const std::string& file, LoadReport* report,
                     std::vector<uint32_t>* faceLines) {
    const size_t nB = blocks.size();
    std::vector<CornerSummary> sum(nB);
    forEachBlock(nB, [&](size_t b) {
        const ObjBlock& k = blocks[b];
        CornerSummary& s = sum[b];
        for (size_t c = 0; c < k.cornerV_.size(); ++c) {
            s.anyUv |= k.cornerT_[c] >= 0;
            s.allUv &= k.cornerT_[c] >= 0;
            s.anyN |= k.cornerN_[c] >= 0;
            s.allN &= k.cornerN_[c] >= 0;
            s.withoutUv += k.cornerT_[c] < 0;
        }
    });
    bool anyUv = false, allUv = true, anyN = false, allN = true;
    size_t withoutUv = 0;
    std::vector<size_t> withoutUvBefore(nB);
    for (size_t b = 0; b < nB; ++b) {
        anyUv |= sum[b].anyUv;
        allUv &= sum[b].allUv;
        anyN |= sum[b].anyN;
        allN &= sum[b].allN;
        withoutUvBefore[b] = withoutUv;
        withoutUv += sum[b].withoutUv;
    }
    const bool keepNormals = anyN && allN;

    PolygonMesh mesh;
    concatenate(
        mesh.positions, blocks, bases, &BlockBase::positions, total.positions,
        [](ObjBlock & k) -> auto& { return k.mesh_.positions; });
    // Zero-filled on this thread, then written in parallel, block by block.
    std::vector<uint32_t> uvIndices;
    for (auto* v : {&mesh.faceVertices, &uvIndices, &mesh.normalIndices}) {
        if (v == &uvIndices && !anyUv) continue;
        if (v == &mesh.normalIndices && !keepNormals) continue;
        sg::detail::reserveWithHugePages(*v, total.corners);
        v->resize(total.corners);
    }
    const size_t nUv = total.uvs, nN = total.normals, nV = total.positions;
    forEachBlock(nB, [&](size_t b) {
        const ObjBlock& k = blocks[b];
        CornerSummary& s = sum[b];
        const size_t c0 = bases[b].corners;
        for (size_t c = 0; c < k.cornerV_.size(); ++c) {
            if (uint64_t(k.cornerV_[c]) >= nV && s.badV == SIZE_MAX) s.badV = c;
            mesh.faceVertices[c0 + c] = uint32_t(k.cornerV_[c]);
        }
        if (anyUv) {
            bool fallbackBefore = withoutUvBefore[b] > 0;
            for (size_t c = 0; c < k.cornerT_.size(); ++c) {
                if (k.cornerT_[c] < 0) {
                    fallbackBefore = true;
                    uvIndices[c0 + c] = uint32_t(nUv);
                    continue;
                }
                if (uint64_t(k.cornerT_[c]) >= nUv + fallbackBefore && s.badT == SIZE_MAX) {
                    s.badT = c;
                    s.badTBound = nUv + fallbackBefore;
                }
                uvIndices[c0 + c] = uint32_t(k.cornerT_[c]);
            }
        }
        if (keepNormals) {
            for (size_t c = 0; c < k.cornerN_.size(); ++c) {
                if (uint64_t(k.cornerN_[c]) >= nN && s.badN == SIZE_MAX) s.badN = c;
                mesh.normalIndices[c0 + c] = uint32_t(k.cornerN_[c]);
            }
        }
    });
    auto firstBad = [&](size_t CornerSummary::*bad) -> size_t {
        for (size_t b = 0; b < nB; ++b)
            if (sum[b].*bad != SIZE_MAX) return b;
        return SIZE_MAX;
    };
    auto lineOf = [&](size_t b, size_t c) {
        return "line " + std::to_string(cornerLine(blocks[b], bases[b], c));
    };
    if (size_t b = firstBad(&CornerSummary::badV); b != SIZE_MAX) {
        const size_t c = sum[b].badV;
        throw InputError(file, lineOf(b, c),
                         "vertex index " + std::to_string(blocks[b].cornerV_[c] + 1) +
                             " is out of range (" + std::to_string(nV) + " vertices)");
    }
    if (size_t b = firstBad(&CornerSummary::badT); anyUv && b != SIZE_MAX) {
        const size_t c = sum[b].badT;
        throw InputError(file, lineOf(b, c),
                         "texture coordinate index " + std::to_string(blocks[b].cornerT_[c] + 1) +
                             " is out of range (" + std::to_string(sum[b].badTBound) + " vt)");
    }
    if (size_t b = firstBad(&CornerSummary::badN); keepNormals && b != SIZE_MAX) {
        const size_t c = sum[b].badN;
        throw InputError(file, lineOf(b, c),
                         "normal index " + std::to_string(blocks[b].cornerN_[c] + 1) +
                             " is out of range (" + std::to_string(nN) + " vn)");
    }
    if (anyUv) {
        FaceVaryingChannel ch;
        ch.name = "vt";
        concatenate(
            ch.values, blocks, bases, &BlockBase::uvs, total.uvs,
            [](ObjBlock & k) -> auto& { return k.uvs_; });
        if (withoutUv > 0) ch.values.push_back(glm::vec2(0.0f));
        ch.indices = std::move(uvIndices);
        mesh.uvSets.push_back(std::move(ch));
    }
    if (keepNormals) {
        concatenate(
            mesh.normals, blocks, bases, &BlockBase::normals, total.normals,
            [](ObjBlock & k) -> auto& { return k.normals_; });
    }
    concatenate(
        mesh.faceSizes, blocks, bases, &BlockBase::faces, total.faces,
        [](ObjBlock & k) -> auto& { return k.mesh_.faceSizes; });
    if (faceLines) {
        concatenate(
            *faceLines, blocks, bases, &BlockBase::faces, total.faces,
            [](ObjBlock & k) -> auto& { return k.faceLine_; });
        if (nB > 1) {
            forEachBlock(nB, [&](size_t b) {
                uint32_t* out = faceLines->data() + bases[b].faces;
                for (size_t f = 0; f < blocks[b].faceLine_.size(); ++f)
                    out[f] = uint32_t(std::min<size_t>(bases[b].lines + out[f], UINT32_MAX));
            });
        }
    }
    applyTagsAndNotes(mesh, blocks, report, withoutUv, anyUv, allUv, anyN, allN);
    return mesh;
}

// The serial reader: the whole text as one block.
PolygonMesh parseSerial(std::string_view text, const std::string& file, const InputLimits& limits,
                        LoadReport* report, std::vector<uint32_t>* faceLines) {
    std::vector<ObjBlock> blocks;
    blocks.emplace_back(file, limits, false);
    blocks[0].reserveFor(text);
    blocks[0].parseLines(text);
    BlockBase total;
    total.add(blocks[0]);
    return assemble(blocks, {BlockBase{}}, total, file, report, faceLines);
}

// Line-aligned blocks of at least blockBytes (the last one may be shorter).
std::vector<std::string_view> splitLines(std::string_view text, size_t blockBytes) {
    std::vector<std::string_view> pieces;
    for (size_t pos = 0; pos < text.size();) {
        size_t end = text.size();
        if (text.size() - pos > blockBytes) {
            const void* eol = std::memchr(text.data() + pos + blockBytes - 1, '\n',
                                          text.size() - (pos + blockBytes - 1));
            if (eol) end = size_t(static_cast<const char*>(eol) - text.data()) + 1;
        }
        pieces.push_back(text.substr(pos, end - pos));
        pos = end;
    }
    return pieces;
}

// The block reader, on the current arena's threads. Whenever the file
// holds an error (a bad statement in any block, a count above its limit,
// a relative index before the first element) the serial reader reads it
// again, so the message is the serial one: the first error in file order.
PolygonMesh parseBlocks(std::string_view text, const std::string& file, const InputLimits& limits,
                        LoadReport* report, std::vector<uint32_t>* faceLines, size_t blockBytes) {
    const std::vector<std::string_view> pieces = splitLines(text, std::max<size_t>(blockBytes, 1));
    const size_t nB = pieces.size();
    std::vector<ObjBlock> blocks;
    blocks.reserve(nB);
    for (size_t b = 0; b < nB; ++b) blocks.emplace_back(file, limits, true);
    std::vector<char> failed(nB, 0);
    forEachBlock(nB, [&](size_t b) {
        try {
            blocks[b].reserveFor(pieces[b]);
            blocks[b].parseLines(pieces[b]);
        } catch (const InputError&) {
            failed[b] = 1;
        }
    });
    auto serial = [&] { return parseSerial(text, file, limits, report, faceLines); };
    if (std::find(failed.begin(), failed.end(), 1) != failed.end()) return serial();
    std::vector<BlockBase> bases(nB);
    BlockBase total;
    for (size_t b = 0; b < nB; ++b) {
        bases[b] = total;
        total.add(blocks[b]);
    }
    if (total.positions > limits.maxVertices || total.uvs > limits.maxCorners ||
        total.normals > limits.maxCorners || total.corners > limits.maxCorners ||
        total.faces > limits.maxFaces) {
        return serial();
    }
    // Relative indices: add the counts of the blocks before.
    forEachBlock(nB, [&](size_t b) {
        ObjBlock& k = blocks[b];
        auto shift = [&](const std::vector<uint32_t>& rel, std::vector<int64_t>& idx, size_t n) {
            for (uint32_t c : rel) {
                idx[c] += int64_t(n);
                if (idx[c] < 0) failed[b] = 1; // reaches before the first
            }
        };
        shift(k.relV_, k.cornerV_, bases[b].positions);
        shift(k.relT_, k.cornerT_, bases[b].uvs);
        shift(k.relN_, k.cornerN_, bases[b].normals);
    });
    if (std::find(failed.begin(), failed.end(), 1) != failed.end()) return serial();
    return assemble(blocks, bases, total, file, report, faceLines);
}

} // namespace

namespace detail {
PolygonMesh parseObjImpl(std::string_view text, const std::string& file, const InputLimits& limits,
                         LoadReport* report, std::vector<uint32_t>* faceLines, int threads) {
    SG_EXPECTS(threads >= 0 && threads <= kMaxThreads,
               "0 (all cores) or 1..1024 threads (surfgrad/base/threads.h)");
    if (threads == 1 || text.size() < kObjParallelMinBytes)
        return parseSerial(text, file, limits, report, faceLines);
    return runWithThreads(threads, [&] {
        // About two blocks per thread (at least kObjBlockBytes): a block's
        // arrays are then large enough for huge pages (scratch_buffer.h; on
        // a VM the page faults of many small blocks cost more than the
        // parse). The result does not depend on the blocks.
        const size_t perThread =
            text.size() / (2 * size_t(std::max(1, tbb::this_task_arena::max_concurrency())));
        return parseBlocks(text, file, limits, report, faceLines,
                           std::max(kObjBlockBytes, perThread));
    });
}

PolygonMesh parseObjInBlocks(std::string_view text, const std::string& file,
                             const InputLimits& limits, LoadReport* report, int threads,
                             size_t blockBytes, std::vector<uint32_t>* faceLines) {
    SG_EXPECTS(threads >= 0 && threads <= kMaxThreads,
               "0 (all cores) or 1..1024 threads (surfgrad/base/threads.h)");
    if (blockBytes == 0) return parseSerial(text, file, limits, report, faceLines);
    return runWithThreads(
        threads, [&] { return parseBlocks(text, file, limits, report, faceLines, blockBytes); });
}
} // namespace detail

PolygonMesh parseObj(std::string_view text, const std::string& file, const InputLimits& limits,
                     LoadReport* report, int threads) {
    return detail::parseObjImpl(text, file, limits, report, nullptr, threads);
}

} // namespace sg::mesh
