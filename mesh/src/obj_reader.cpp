// Wavefront OBJ tokenizer with OpenSubdiv's "t" tag lines
// (surfgrad/mesh_io.h: parseObj). Own code because OpenMesh's OBJ reader
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
#include <charconv>
#include <cstring>
#include <string_view>

#include "mesh_internal.h"
#include "scratch_buffer.h"
#include "surfgrad/mesh_io.h"

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

class ObjParser {
public:
    ObjParser(const std::string& file, const InputLimits& limits, LoadReport* report)
        : file_(file), limits_(limits), report_(report) {}

    PolygonMesh parse(std::string_view text, std::vector<uint32_t>* faceLines);

private:
    void reserveFor(std::string_view text);
    [[noreturn]] void fail(const std::string& reason) const {
        throw InputError(file_, "line " + std::to_string(lineNo_), reason);
    }
    void vertex(Tokenizer& t);
    void texcoord(Tokenizer& t);
    void normal(Tokenizer& t);
    void face(Tokenizer& t);
    void tag(Tokenizer& t);
    // Resolves a 1-based or negative OBJ index against `count` entries so far.
    int64_t resolve(int64_t idx, size_t count, const char* what) const {
        if (idx == 0) fail(std::string(what) + " index 0 (OBJ indices start at 1)");
        if (idx < 0) {
            if (uint64_t(-idx) > count)
                fail(std::string(what) + " index " + std::to_string(idx) +
                     " reaches before the first " + what);
            return int64_t(count) + idx;
        }
        return idx - 1;
    }

    const std::string& file_;
    const InputLimits& limits_;
    LoadReport* report_;
    size_t lineNo_ = 0;

    PolygonMesh mesh_;
    std::vector<glm::vec2> uvs_;
    std::vector<glm::vec3> normals_;
    // Per corner, 0-based (or -1 when the corner has none); resolved and
    // range-checked after the whole file is read (forward references).
    std::vector<int64_t> cornerV_, cornerT_, cornerN_;
    std::vector<uint32_t> faceLine_;
    size_t cornersWithoutUv_ = 0;
    size_t ignored_ = 0;
    std::string firstIgnored_;
    std::vector<std::string> unknownTags_;
};

void ObjParser::vertex(Tokenizer& t) {
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

void ObjParser::texcoord(Tokenizer& t) {
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

void ObjParser::normal(Tokenizer& t) {
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

void ObjParser::face(Tokenizer& t) {
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
        v = resolve(v, mesh_.positions.size(), "vertex");
        if (nParts > 1 && !parts[1].empty()) {
            if (!parseInt(parts[1], vt)) fail("bad texture index '" + io::printable(tok, 32) + "'");
            vt = resolve(vt, uvs_.size(), "texture coordinate");
        }
        if (nParts > 2 && !parts[2].empty()) {
            if (!parseInt(parts[2], vn)) fail("bad normal index '" + io::printable(tok, 32) + "'");
            vn = resolve(vn, normals_.size(), "normal");
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

void ObjParser::tag(Tokenizer& t) {
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
void ObjParser::reserveFor(std::string_view text) {
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
        detail::reserveWithHugePages(vec, std::min(n, limit));
    };
    reserve(mesh_.positions, v, limits_.maxVertices);
    reserve(uvs_, vt, limits_.maxCorners);
    reserve(normals_, vn, limits_.maxCorners);
    reserve(mesh_.faceSizes, f, limits_.maxFaces);
    reserve(faceLine_, f, limits_.maxFaces);
    // Triangles are the common case; larger faces grow the vectors.
    for (auto* c : {&cornerV_, &cornerT_, &cornerN_}) reserve(*c, 3 * f, limits_.maxCorners);
}

PolygonMesh ObjParser::parse(std::string_view text, std::vector<uint32_t>* faceLines) {
    reserveFor(text);
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
    // Resolve corners now that every list is complete.
    const size_t nC = cornerV_.size();
    mesh_.faceVertices.resize(nC);
    bool anyUv = false, allUv = true, anyN = false, allN = true;
    for (size_t c = 0; c < nC; ++c) {
        anyUv |= cornerT_[c] >= 0;
        allUv &= cornerT_[c] >= 0;
        anyN |= cornerN_[c] >= 0;
        allN &= cornerN_[c] >= 0;
    }
    // Which line a corner came from, for messages.
    std::vector<uint32_t> offsets = faceOffsets(mesh_);
    auto cornerLine = [&](size_t c) {
        size_t f = size_t(std::upper_bound(offsets.begin(), offsets.end(), uint32_t(c)) -
                          offsets.begin()) -
                   1;
        return faceLine_[std::min(f, faceLine_.size() - 1)];
    };
    for (size_t c = 0; c < nC; ++c) {
        if (uint64_t(cornerV_[c]) >= mesh_.positions.size()) {
            throw InputError(file_, "line " + std::to_string(cornerLine(c)),
                             "vertex index " + std::to_string(cornerV_[c] + 1) +
                                 " is out of range (" + std::to_string(mesh_.positions.size()) +
                                 " vertices)");
        }
        mesh_.faceVertices[c] = uint32_t(cornerV_[c]);
    }
    if (anyUv) {
        FaceVaryingChannel ch;
        ch.name = "vt";
        ch.values = std::move(uvs_);
        ch.indices.resize(nC);
        uint32_t fallback = UINT32_MAX;
        for (size_t c = 0; c < nC; ++c) {
            if (cornerT_[c] < 0) {
                if (fallback == UINT32_MAX) {
                    fallback = uint32_t(ch.values.size());
                    ch.values.push_back(glm::vec2(0.0f));
                }
                ch.indices[c] = fallback;
                ++cornersWithoutUv_;
                continue;
            }
            if (uint64_t(cornerT_[c]) >= ch.values.size()) {
                throw InputError(file_, "line " + std::to_string(cornerLine(c)),
                                 "texture coordinate index " + std::to_string(cornerT_[c] + 1) +
                                     " is out of range (" + std::to_string(ch.values.size()) +
                                     " vt)");
            }
            ch.indices[c] = uint32_t(cornerT_[c]);
        }
        mesh_.uvSets.push_back(std::move(ch));
    }
    if (anyN && allN) {
        mesh_.normalIndices.resize(nC);
        for (size_t c = 0; c < nC; ++c) {
            if (uint64_t(cornerN_[c]) >= normals_.size()) {
                throw InputError(file_, "line " + std::to_string(cornerLine(c)),
                                 "normal index " + std::to_string(cornerN_[c] + 1) +
                                     " is out of range (" + std::to_string(normals_.size()) +
                                     " vn)");
            }
            mesh_.normalIndices[c] = uint32_t(cornerN_[c]);
        }
        mesh_.normals = std::move(normals_);
    }
    if (report_) {
        if (cornersWithoutUv_ && !allUv) {
            report_->notes.push_back(std::to_string(cornersWithoutUv_) +
                                     " face corners without vt got UV (0,0)");
        }
        if (anyN && !allN)
            report_->notes.push_back("vn on some corners only: normals ignored (recomputed)");
        if (ignored_) {
            report_->notes.push_back("ignored " + std::to_string(ignored_) +
                                     " statements (first: '" + firstIgnored_ + "')");
        }
        for (const std::string& tag : unknownTags_)
            report_->notes.push_back("ignored unknown tag '" + tag + "'");
    }
    if (faceLines) *faceLines = std::move(faceLine_);
    return std::move(mesh_);
}

} // namespace

namespace detail {
PolygonMesh parseObjImpl(std::string_view text, const std::string& file, const InputLimits& limits,
                         LoadReport* report, std::vector<uint32_t>* faceLines) {
    ObjParser parser(file, limits, report);
    return parser.parse(text, faceLines);
}
} // namespace detail

PolygonMesh parseObj(std::string_view text, const std::string& file, const InputLimits& limits,
                     LoadReport* report) {
    return detail::parseObjImpl(text, file, limits, report, nullptr);
}

} // namespace sg::mesh
