// OFF, PLY and STL input through OpenMesh's readers (surfgrad/mesh/mesh_io.h).
//
// OpenMesh's readers talk to a BaseImporter. Its usual importer builds a
// PolyMesh and, when a face would make an edge or vertex non-manifold,
// prints "complex edge" and DROPS the face. Here the readers feed a
// recording importer instead, which keeps every vertex and face exactly as
// written; validate() then names the faces OpenMesh would have dropped.
//
// OpenMesh's readers trust the counts in the file header (a PLY declaring
// 4e9 vertices loops 4e9 times), so the header counts are checked against
// the file size here first.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <cctype>
#include <iterator>
#include <string_view>
#include <cstring>
#include <fstream>
#include <sstream>

#include "mesh_internal.h"
#include "surfgrad/mesh/mesh_io.h"

namespace sg::mesh {

using io::InputError;
namespace OM = OpenMesh;

namespace {

// A number token as OpenMesh's readers take it: they read every value with
// `stream >> float`, which fails on "nan" and "inf" and on values beyond
// float range (and then reads zeros for the rest of the item), so those
// must be refused here with the right reason.
enum class NumberToken { Finite, NotANumber, NonFinite };
NumberToken parseNumberToken(std::string_view t) {
    double x = 0.0;
    auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
    if (t.empty() || p != t.data() + t.size() ||
        (ec != std::errc() && ec != std::errc::result_out_of_range))
        return NumberToken::NotANumber;
    if (ec == std::errc::result_out_of_range) {
        // Overflow or underflow: strtod tells which (underflow is a zero).
        x = std::strtod(std::string(t).c_str(), nullptr);
    }
    return std::isfinite(x) && std::fabs(x) <= double(std::numeric_limits<float>::max())
               ? NumberToken::Finite
               : NumberToken::NonFinite;
}

std::string nonFiniteCoordinate(std::string_view token) {
    return "non-finite coordinate '" + io::printable(token, 32) + "'";
}

class RecordingImporter final : public OM::IO::BaseImporter {
public:
    explicit RecordingImporter(const InputLimits& limits) : limits_(limits) {}

    OM::VertexHandle add_vertex(const OM::Vec3f& p) override {
        if (positions.size() >= limits_.maxVertices) {
            overflow = "more than " + std::to_string(limits_.maxVertices) + " vertices (limit)";
            return OM::VertexHandle();
        }
        positions.push_back(glm::vec3(p[0], p[1], p[2]));
        return OM::VertexHandle(int(positions.size() - 1));
    }
    OM::VertexHandle add_vertex() override { return add_vertex(OM::Vec3f(0, 0, 0)); }
    OM::HalfedgeHandle add_edge(OM::VertexHandle, OM::VertexHandle) override {
        return OM::HalfedgeHandle();
    }
    OM::FaceHandle add_face(const VHandles& vs) override {
        if (faceSizes.size() >= limits_.maxFaces ||
            faceVertices.size() + vs.size() > limits_.maxCorners) {
            overflow = "more faces or corners than the limits allow";
            return OM::FaceHandle();
        }
        for (const OM::VertexHandle& v : vs) {
            // Negative handles (the reader's "invalid") become an out-of-range
            // index that validation reports.
            faceVertices.push_back(v.idx() < 0 ? UINT32_MAX : uint32_t(v.idx()));
        }
        faceSizes.push_back(uint32_t(vs.size()));
        return OM::FaceHandle(int(faceSizes.size() - 1));
    }
    OM::FaceHandle add_face(OM::HalfedgeHandle) override { return OM::FaceHandle(); }
    void add_face_texcoords(OM::FaceHandle, OM::VertexHandle,
                            const std::vector<OM::Vec2f>&) override {
        ++ignoredFaceTexcoords;
    }
    void add_face_texcoords(OM::FaceHandle, OM::VertexHandle,
                            const std::vector<OM::Vec3f>&) override {
        ++ignoredFaceTexcoords;
    }
    void set_face_texindex(OM::FaceHandle, int) override {}
    void set_point(OM::VertexHandle v, const OM::Vec3f& p) override {
        if (valid(v)) positions[size_t(v.idx())] = glm::vec3(p[0], p[1], p[2]);
    }
    void set_halfedge(OM::VertexHandle, OM::HalfedgeHandle) override {}
    void set_normal(OM::VertexHandle v, const OM::Vec3f& n) override {
        if (!valid(v)) return;
        if (normals.size() < positions.size()) normals.resize(positions.size(), glm::vec3(0.0f));
        normals[size_t(v.idx())] = glm::vec3(n[0], n[1], n[2]);
        hasNormal.resize(positions.size(), 0);
        hasNormal[size_t(v.idx())] = 1;
    }
    void set_normal(OM::VertexHandle v, const OM::Vec3d& n) override {
        set_normal(v, OM::Vec3f(n));
    }
    void set_color(OM::VertexHandle, const OM::Vec3uc&) override {}
    void set_color(OM::VertexHandle, const OM::Vec4uc&) override {}
    void set_color(OM::VertexHandle, const OM::Vec3f&) override {}
    void set_color(OM::VertexHandle, const OM::Vec4f&) override {}
    void set_texcoord(OM::VertexHandle v, const OM::Vec2f& t) override {
        if (!valid(v)) return;
        if (uvs.size() < positions.size()) uvs.resize(positions.size(), glm::vec2(0.0f));
        uvs[size_t(v.idx())] = glm::vec2(t[0], t[1]);
        hasUv.resize(positions.size(), 0);
        hasUv[size_t(v.idx())] = 1;
    }
    void set_status(OM::VertexHandle, const OM::Attributes::StatusInfo&) override {}
    void set_next(OM::HalfedgeHandle, OM::HalfedgeHandle) override {}
    void set_face(OM::HalfedgeHandle, OM::FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(OM::HalfedgeHandle, const OM::Vec2f&) override { ++ignoredFaceTexcoords; }
    void set_texcoord(OM::VertexHandle v, const OM::Vec3f& t) override {
        set_texcoord(v, OM::Vec2f(t[0], t[1]));
    }
    void set_texcoord(OM::HalfedgeHandle, const OM::Vec3f&) override { ++ignoredFaceTexcoords; }
    void set_status(OM::HalfedgeHandle, const OM::Attributes::StatusInfo&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec3uc&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec4uc&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec3f&) override {}
    void set_color(OM::EdgeHandle, const OM::Vec4f&) override {}
    void set_status(OM::EdgeHandle, const OM::Attributes::StatusInfo&) override {}
    void set_normal(OM::FaceHandle, const OM::Vec3f&) override {}
    void set_normal(OM::FaceHandle, const OM::Vec3d&) override {}
    void set_color(OM::FaceHandle, const OM::Vec3uc&) override {}
    void set_color(OM::FaceHandle, const OM::Vec4uc&) override {}
    void set_color(OM::FaceHandle, const OM::Vec3f&) override {}
    void set_color(OM::FaceHandle, const OM::Vec4f&) override {}
    void set_status(OM::FaceHandle, const OM::Attributes::StatusInfo&) override {}
    void add_texture_information(int, std::string) override {}
    size_t n_vertices() const override { return positions.size(); }
    size_t n_faces() const override { return faceSizes.size(); }
    size_t n_edges() const override { return 0; }

    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs;
    std::vector<uint8_t> hasNormal, hasUv;
    std::vector<uint32_t> faceSizes, faceVertices;
    size_t ignoredFaceTexcoords = 0;
    std::string overflow;

private:
    bool valid(OM::VertexHandle v) const {
        return v.idx() >= 0 && size_t(v.idx()) < positions.size();
    }
    const InputLimits& limits_;
};

// PLY header grammar (Turk's format as OpenMesh reads it), checked in full
// before OpenMesh's reader sees the file: that reader indexes its element
// list without checking it (a `property` line before any `element` line
// crashes it). Lines: `ply`, one `format ascii|binary_little_endian|
// binary_big_endian 1.0` before any element, `comment ...`, `obj_info ...`,
// `element NAME COUNT`, `property TYPE NAME` or `property list TYPE TYPE
// NAME` after an element, `end_header`. Anything else is an error naming
// the header line. Also checks each element's count against the file size
// (every element takes at least one byte per property).
// Bytes of a PLY scalar type (checked by isType first).
int plyTypeBytes(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "double" || t == "float64") return 8;
    return 4;
}

struct PlyProperty {
    bool list = false;
    std::string countType, itemType; // itemType: the scalar type of non-lists
    std::string name;
};
struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> props;
};

void checkPlyBody(std::istream& in, const std::string& file, uint64_t fileSize,
                  const std::string& format, const std::vector<PlyElement>& elements,
                  const InputLimits& limits);

void checkPlyHeader(std::istream& in, const std::string& file, uint64_t fileSize,
                    const InputLimits& limits) {
    auto fail = [&](size_t lineNo, const std::string& reason) {
        throw InputError(file, "header line " + std::to_string(lineNo), reason);
    };
    auto isType = [](const std::string& t) {
        static const char* kTypes[] = {"char",  "uchar",  "short",   "ushort", "int",   "uint",
                                       "float", "double", "int8",    "uint8",  "int16", "uint16",
                                       "int32", "uint32", "float32", "float64"};
        for (const char* k : kTypes) {
            if (t == k) return true;
        }
        return false;
    };
    std::string line;
    if (!std::getline(in, line) || (line != "ply" && line != "ply\r"))
        fail(1, "not a PLY file (first line is not 'ply')");
    std::string element;
    uint64_t count = 0, props = 0;
    bool format = false;
    std::string formatName;
    std::vector<PlyElement> elements;
    auto checkCount = [&]() {
        if (!element.empty() && count > fileSize / std::max<uint64_t>(props, 1)) {
            throw InputError(file, "header",
                             "declares " + std::to_string(count) + " " + element +
                                 " elements but the file has only " + std::to_string(fileSize) +
                                 " bytes");
        }
    };
    // A header longer than this is not a mesh header (OpenMesh reads it
    // line by line; a multi-megabyte "header" is a malformed file).
    constexpr size_t kMaxHeaderLines = 10000;
    for (size_t lineNo = 2; lineNo <= kMaxHeaderLines && std::getline(in, line); ++lineNo) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream ls(line);
        std::string kw;
        ls >> kw;
        std::vector<std::string> rest;
        for (std::string w; ls >> w;) rest.push_back(w);
        if (kw == "comment" || kw == "obj_info") continue;
        if (kw == "format") {
            if (format) fail(lineNo, "a second format line");
            if (!element.empty()) fail(lineNo, "format after an element");
            if (rest.size() != 2 ||
                (rest[0] != "ascii" && rest[0] != "binary_little_endian" &&
                 rest[0] != "binary_big_endian") ||
                rest[1] != "1.0") {
                fail(lineNo, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
            }
            format = true;
            formatName = rest[0];
        } else if (kw == "element") {
            if (!format) fail(lineNo, "element before the format line");
            checkCount();
            if (rest.size() != 2 || rest[1].empty() || rest[1].size() > 18 ||
                rest[1].find_first_not_of("0123456789") != std::string::npos) {
                fail(lineNo, "expected 'element NAME COUNT' with a non-negative integer count");
            }
            element = rest[0];
            count = std::stoull(rest[1]);
            props = 0;
            elements.push_back({element, count, {}});
        } else if (kw == "property") {
            if (element.empty()) fail(lineNo, "property before any element");
            const bool list = !rest.empty() && rest[0] == "list";
            const bool ok = list ? (rest.size() == 4 && isType(rest[1]) && isType(rest[2]))
                                 : (rest.size() == 2 && isType(rest[0]));
            if (!ok)
                fail(lineNo, "expected 'property TYPE NAME' or 'property list TYPE TYPE NAME' with "
                             "PLY types");
            if (list && (rest[1] == "float" || rest[1] == "double" || rest[1] == "float32" ||
                         rest[1] == "float64")) {
                fail(lineNo, "a list count must have an integer type");
            }
            ++props;
            elements.back().props.push_back(list ? PlyProperty{true, rest[1], rest[2], rest[3]}
                                                 : PlyProperty{false, "", rest[0], rest[1]});
        } else if (kw == "end_header") {
            if (!format) fail(lineNo, "no format line");
            checkCount();
            checkPlyBody(in, file, fileSize, formatName, elements, limits);
            return;
        } else {
            fail(lineNo, "unknown header keyword '" + io::printable(kw, 32) + "'");
        }
    }
    throw InputError(file, "header",
                     "no end_header within " + std::to_string(kMaxHeaderLines) + " lines");
}

// PLY body, checked item by item before OpenMesh's reader sees it: that
// reader reads a list's count and then resizes a vector to it, so a count
// of -30 read as unsigned asked for 2^31 handles (found by
// fuzz_mesh_openmesh). Every list count must be an integer in [0,
// maxFaceDegree]; every value must be present (ASCII: each item on its
// own line with exactly its values, numbers only; binary: the bytes fit in
// the file). The element/property order is the header's.
void checkPlyBody(std::istream& in, const std::string& file, uint64_t fileSize,
                  const std::string& format, const std::vector<PlyElement>& elements,
                  const InputLimits& limits) {
    const std::streamoff start = in.tellg();
    if (start < 0) throw InputError(file, "header", "cannot read the data after end_header");
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    (void)fileSize; // data.size() is what is left of it
    const uint64_t maxList = limits.maxFaceDegree;
    auto where = [&](const PlyElement& e, uint64_t i) {
        return io::printable(e.name, 32) + " " + std::to_string(i);
    };
    // A vertex's x, y, z are its coordinates; anything else is named.
    auto nonFiniteValue = [](const PlyElement& e, const PlyProperty& pr, std::string_view value) {
        if (e.name == "vertex" && (pr.name == "x" || pr.name == "y" || pr.name == "z"))
            return "non-finite coordinate " + pr.name + " = '" + io::printable(value, 32) + "'";
        return "non-finite value '" + io::printable(value, 32) + "' of property '" +
               io::printable(pr.name, 32) + "'";
    };
    if (format == "ascii") {
        size_t at = 0;
        for (const PlyElement& e : elements) {
            for (uint64_t i = 0; i < e.count; ++i) {
                if (at >= data.size())
                    throw InputError(file, where(e, i),
                                     "the file ends before " + e.name + " " + std::to_string(i) +
                                         " of " + std::to_string(e.count));
                size_t eol = data.find('\n', at);
                if (eol == std::string::npos) eol = data.size();
                std::string_view lineText(data.data() + at, eol - at);
                at = eol + 1;
                std::vector<std::string_view> tok;
                for (size_t p = 0; p < lineText.size();) {
                    while (p < lineText.size() &&
                           std::isspace(static_cast<unsigned char>(lineText[p])))
                        ++p;
                    const size_t q = p;
                    while (p < lineText.size() &&
                           !std::isspace(static_cast<unsigned char>(lineText[p])))
                        ++p;
                    if (p > q) tok.push_back(lineText.substr(q, p - q));
                }
                size_t k = 0;
                const PlyProperty* property = nullptr;
                auto number = [&](bool integerOnly, uint64_t* value) {
                    if (k >= tok.size())
                        throw InputError(file, where(e, i), "too few values on its line");
                    const std::string_view t = tok[k++];
                    if (integerOnly) {
                        long long v = 0;
                        auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
                        if (ec != std::errc() || p != t.data() + t.size() || v < 0 ||
                            uint64_t(v) > maxList) {
                            throw InputError(file, where(e, i),
                                             "list size '" + io::printable(t, 32) +
                                                 "' is not an integer in [0, " +
                                                 std::to_string(maxList) + "]");
                        }
                        *value = uint64_t(v);
                        return;
                    }
                    switch (parseNumberToken(t)) {
                    case NumberToken::Finite:
                        return;
                    case NumberToken::NotANumber:
                        throw InputError(file, where(e, i),
                                         "expected a number, found '" + io::printable(t, 32) + "'");
                    case NumberToken::NonFinite:
                        throw InputError(file, where(e, i), nonFiniteValue(e, *property, t));
                    }
                };
                for (const PlyProperty& pr : e.props) {
                    property = &pr;
                    uint64_t n = 1;
                    if (pr.list) number(true, &n);
                    for (uint64_t j = 0; j < n; ++j) number(false, nullptr);
                }
                if (k != tok.size())
                    throw InputError(file, where(e, i),
                                     "more values on its line than its properties");
            }
        }
        return;
    }
    const bool bigEndian = format == "binary_big_endian";
    size_t at = 0;
    for (const PlyElement& e : elements) {
        for (uint64_t i = 0; i < e.count; ++i) {
            for (const PlyProperty& pr : e.props) {
                uint64_t n = 1;
                if (pr.list) {
                    const int bytes = plyTypeBytes(pr.countType);
                    if (data.size() - at < size_t(bytes))
                        throw InputError(file, where(e, i), "the file ends inside the item");
                    uint64_t raw = 0;
                    for (int b = 0; b < bytes; ++b) {
                        const uint64_t byte = static_cast<unsigned char>(
                            data[at + size_t(bigEndian ? b : bytes - 1 - b)]);
                        raw = raw << 8 | byte;
                    }
                    at += size_t(bytes);
                    const bool isSigned = pr.countType[0] != 'u';
                    if (isSigned && (raw >> (8 * bytes - 1)) != 0) {
                        throw InputError(file, where(e, i), "negative list size");
                    }
                    if (raw > maxList) {
                        throw InputError(file, where(e, i),
                                         "list size " + std::to_string(raw) + " is above " +
                                             std::to_string(maxList));
                    }
                    n = raw;
                }
                const int itemBytes = plyTypeBytes(pr.itemType);
                const uint64_t bytes = n * uint64_t(itemBytes);
                if (data.size() - at < bytes)
                    throw InputError(file, where(e, i), "the file ends inside the item");
                const bool real = pr.itemType == "float" || pr.itemType == "float32" ||
                                  pr.itemType == "double" || pr.itemType == "float64";
                for (uint64_t j = 0; real && j < n; ++j) {
                    unsigned char raw[8];
                    for (int b = 0; b < itemBytes; ++b)
                        raw[b] = static_cast<unsigned char>(
                            data[at + size_t(j) * size_t(itemBytes) +
                                 size_t(bigEndian ? itemBytes - 1 - b : b)]);
                    double x = 0.0;
                    if (itemBytes == 4) {
                        float f;
                        std::memcpy(&f, raw, 4);
                        x = f;
                    } else {
                        std::memcpy(&x, raw, 8);
                    }
                    if (!std::isfinite(x) ||
                        std::fabs(x) > double(std::numeric_limits<float>::max())) {
                        char text[32];
                        auto r = std::to_chars(text, text + sizeof text, x);
                        throw InputError(
                            file, where(e, i),
                            nonFiniteValue(e, pr, std::string_view(text, size_t(r.ptr - text))));
                    }
                }
                at += size_t(bytes);
            }
        }
    }
}

// ASCII OFF, checked token by token the way OpenMesh's reader consumes it,
// before that reader sees the file. Its face loop reads each face's vertex
// count into an unsigned int and then reads that many indices without
// checking the stream: a count of "-10" (4294967286 as unsigned) or a
// stale count after a failed read spins for billions of iterations (found
// by fuzz_mesh_openmesh). So every token that reader will take as a count
// is checked here. Layout: line 1 the keyword [ST][C][N]OFF alone; then nV
// nF nE; then per vertex 3 coordinates (6 with N) read as tokens, the rest
// of that line skipped (colours, texture coordinates); then per face a
// vertex count k in [1, maxFaceDegree] and k integer indices (anything
// after them on the line is left to the next token read, as OpenMesh
// does). 4OFF/nOFF (other dimensions) and BINARY OFF are refused by name.
void checkOff(const std::filesystem::path& path, const std::string& file, uint64_t fileSize,
              const InputLimits& limits) {
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    size_t at = 0, line = 1;
    auto fail = [&](const std::string& element, const std::string& reason) {
        throw InputError(file, element, reason);
    };
    auto lineName = [&]() { return "line " + std::to_string(line); };
    // Next whitespace-separated token (empty at the end of the file).
    auto token = [&]() {
        while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) {
            if (text[at] == '\n') ++line;
            ++at;
        }
        const size_t start = at;
        while (at < text.size() && !std::isspace(static_cast<unsigned char>(text[at]))) ++at;
        return std::string_view(text).substr(start, at - start);
    };
    auto skipLine = [&]() {
        while (at < text.size() && text[at] != '\n') ++at;
    };
    auto integer = [&](std::string_view t, uint64_t maxValue, const std::string& element,
                       const std::string& what) {
        uint64_t v = 0;
        auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (t.empty() || ec != std::errc() || p != t.data() + t.size() || v > maxValue) {
            fail(element, "expected " + what + ", found '" + io::printable(t, 32) + "'");
        }
        return v;
    };
    // Keyword line.
    const std::string_view magic = token();
    const size_t offAt = magic.find("OFF");
    if (offAt == std::string_view::npos || offAt + 3 != magic.size())
        fail("header", "not an OFF file (no OFF keyword)");
    std::string_view prefix = magic.substr(0, offAt);
    bool normals = false;
    for (std::string_view known : {"ST", "C", "N"}) {
        if (prefix.substr(0, known.size()) == known) {
            normals |= known == "N";
            prefix.remove_prefix(known.size());
        }
    }
    if (prefix == "4" || prefix == "n" || prefix == "4n")
        fail("header",
             "OFF of dimension other than 3 (" + std::string(magic) + ") is not supported");
    if (!prefix.empty()) fail("header", "unknown OFF keyword '" + io::printable(magic, 32) + "'");
    {
        // The rest of the keyword line: nothing, or BINARY.
        const size_t eol = text.find('\n', at);
        std::istringstream rest(
            text.substr(at, eol == std::string::npos ? std::string::npos : eol - at));
        std::string word;
        if (rest >> word) {
            if (word == "BINARY")
                fail("header", "binary OFF is not supported (use ASCII OFF or PLY)");
            fail("header", "expected the OFF keyword alone on line 1, found '" +
                               io::printable(word, 32) + "'");
        }
        skipLine();
    }
    const uint64_t nV = integer(token(), UINT32_MAX, "header", "a vertex count");
    const uint64_t nF = integer(token(), UINT32_MAX, "header", "a face count");
    integer(token(), UINT32_MAX, "header", "an edge count");
    // Every vertex and face takes at least a few bytes.
    if (nV > fileSize / 6)
        fail("header", "declares " + std::to_string(nV) + " vertices but the file has only " +
                           std::to_string(fileSize) + " bytes");
    if (nF > fileSize / 4)
        fail("header", "declares " + std::to_string(nF) + " faces but the file has only " +
                           std::to_string(fileSize) + " bytes");
    if (nV > limits.maxVertices)
        fail("header",
             std::to_string(nV) + " vertices; the limit is " + std::to_string(limits.maxVertices));
    if (nF > limits.maxFaces)
        fail("header",
             std::to_string(nF) + " faces; the limit is " + std::to_string(limits.maxFaces));
    const int coords = normals ? 6 : 3;
    for (uint64_t v = 0; v < nV; ++v) {
        for (int k = 0; k < coords; ++k) {
            const std::string_view t = token();
            switch (parseNumberToken(t)) {
            case NumberToken::Finite:
                break;
            case NumberToken::NotANumber:
                fail("vertex " + std::to_string(v),
                     lineName() + ": expected a number, found '" + io::printable(t, 32) + "'");
                break;
            case NumberToken::NonFinite:
                fail("vertex " + std::to_string(v),
                     (k < 3 ? nonFiniteCoordinate(t)
                            : "non-finite normal component '" + io::printable(t, 32) + "'") +
                         " (" + lineName() + ")");
                break;
            }
        }
        skipLine();
    }
    for (uint64_t f = 0; f < nF; ++f) {
        const std::string element = "face " + std::to_string(f);
        const std::string_view t = token();
        if (t.empty())
            fail(element,
                 "the file ends before face " + std::to_string(f) + " of " + std::to_string(nF));
        const uint64_t k = integer(t, limits.maxFaceDegree, element,
                                   lineName() + ": a vertex count in [1, " +
                                       std::to_string(limits.maxFaceDegree) + "]");
        if (k == 0) fail(element, lineName() + ": a face needs at least one vertex");
        for (uint64_t j = 0; j < k; ++j) {
            const std::string_view idx = token();
            if (idx.empty())
                fail(element, "the file ends inside the face (" + std::to_string(j) + " of " +
                                  std::to_string(k) + " indices)");
            long long value = 0;
            auto [p, ec] = std::from_chars(idx.data(), idx.data() + idx.size(), value);
            if (idx.empty() || ec != std::errc() || p != idx.data() + idx.size()) {
                fail(element, lineName() + ": expected " + std::to_string(k) +
                                  " vertex indices, found '" + io::printable(idx, 32) + "'");
            }
        }
    }
}

// STL, checked the way OpenMesh's reader takes it, before that reader sees
// the file. Binary when the size is exactly 84 + 50 n for the count n at
// byte 80 (OpenMesh's own test), else ASCII, where a line containing
// "outer" (or "OUTER") starts a facet and each of the next three lines is
// a vertex: a keyword and three numbers. That reader welds equal corners
// through a std::map and drops the facets whose corners then coincide, so
// a NaN (which it reads as NaN in binary and as 0 in ASCII) turns into a
// silently dropped face; every coordinate is checked here instead.
// Vertices are numbered in file order (3 per facet, from 0); the error
// names that number and the facet. Returns the number of facets.
uint64_t checkStl(const std::filesystem::path& path, const std::string& file, uint64_t fileSize) {
    std::ifstream in(path, std::ios::binary);
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto vertexName = [](uint64_t facet, int corner) {
        return "vertex " + std::to_string(3 * facet + uint64_t(corner));
    };
    uint32_t n = 0;
    if (data.size() >= 84) std::memcpy(&n, data.data() + 80, 4);
    if (data.size() >= 84 && 84 + 50 * uint64_t(n) == fileSize) {
        for (uint64_t f = 0; f < n; ++f) {
            for (int corner = 0; corner < 3; ++corner) {
                for (int k = 0; k < 3; ++k) {
                    float x = 0.0f;
                    std::memcpy(&x, data.data() + 84 + 50 * f + 12 * (1 + corner) + 4 * k, 4);
                    if (!std::isfinite(x)) {
                        char text[32];
                        auto r = std::to_chars(text, text + sizeof text, x);
                        throw InputError(
                            file, vertexName(f, corner),
                            nonFiniteCoordinate(std::string_view(text, size_t(r.ptr - text))) +
                                " (facet " + std::to_string(f) + ")");
                    }
                }
            }
        }
        return n;
    }
    if (data.size() >= 84 && std::string_view(data.data(), 5) != "solid") {
        // Neither a binary file of the declared size nor ASCII.
        throw InputError(file, "header",
                         "declares " + std::to_string(n) + " triangles (" +
                             std::to_string(84 + 50 * uint64_t(n)) + " bytes) but the file has " +
                             std::to_string(fileSize) + " bytes");
    }
    uint64_t facets = 0;
    size_t at = 0, lineNo = 0;
    auto nextLine = [&](std::string_view& line) {
        if (at >= data.size()) return false;
        size_t eol = data.find('\n', at);
        if (eol == std::string::npos) eol = data.size();
        line = std::string_view(data).substr(at, eol - at);
        at = eol + 1;
        ++lineNo;
        return true;
    };
    std::string_view line;
    while (nextLine(line)) {
        if (line.find("outer") == std::string_view::npos &&
            line.find("OUTER") == std::string_view::npos)
            continue;
        for (int corner = 0; corner < 3; ++corner) {
            const std::string element = vertexName(facets, corner);
            if (!nextLine(line))
                throw InputError(file, element,
                                 "the file ends inside facet " + std::to_string(facets));
            std::vector<std::string_view> tok;
            for (size_t p = 0; p < line.size();) {
                while (p < line.size() && std::isspace(static_cast<unsigned char>(line[p]))) ++p;
                const size_t q = p;
                while (p < line.size() && !std::isspace(static_cast<unsigned char>(line[p]))) ++p;
                if (p > q) tok.push_back(line.substr(q, p - q));
            }
            const std::string where =
                " (facet " + std::to_string(facets) + ", line " + std::to_string(lineNo) + ")";
            if (tok.size() < 4) throw InputError(file, element, "expected 'vertex x y z'" + where);
            for (int k = 1; k <= 3; ++k) {
                switch (parseNumberToken(tok[size_t(k)])) {
                case NumberToken::Finite:
                    break;
                case NumberToken::NotANumber:
                    throw InputError(file, element,
                                     "expected a number, found '" +
                                         io::printable(tok[size_t(k)], 32) + "'" + where);
                case NumberToken::NonFinite:
                    throw InputError(file, element, nonFiniteCoordinate(tok[size_t(k)]) + where);
                }
            }
        }
        ++facets;
    }
    return facets;
}

// Header counts against the file size: every vertex and face takes at
// least a few bytes (3 coordinates of >= 2 characters in ASCII, 4 bytes in
// binary; a face at least 4 numbers), so a count beyond that is a lie.
// Returns the number of faces the file declares (STL: facets), or 0 when
// the format does not say.
uint64_t checkHeaderCounts(const std::filesystem::path& path, const std::string& ext,
                           uint64_t fileSize, const InputLimits& limits) {
    std::string file = path.string();
    if (ext == ".stl") return checkStl(path, file, fileSize);
    if (ext == ".off") {
        checkOff(path, file, fileSize, limits);
        return 0;
    }
    std::ifstream in(path, std::ios::binary);
    if (ext == ".ply") checkPlyHeader(in, file, fileSize, limits);
    return 0;
}

} // namespace

namespace detail {

PolygonMesh readWithOpenMesh(const std::filesystem::path& path, const InputLimits& limits,
                             LoadReport* report) {
    const std::string file = path.string();
    std::error_code ec;
    uint64_t size = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(file, "", "cannot read: " + ec.message());
    if (size > limits.maxFileBytes) {
        throw InputError(file, "",
                         "file is " + std::to_string(size) + " bytes; the limit is " +
                             std::to_string(limits.maxFileBytes));
    }
    std::string ext = meshFormat(path);
    const uint64_t declaredFaces = checkHeaderCounts(path, ext, size, limits);

    RecordingImporter importer(limits);
    OM::IO::Options opt = OM::IO::Options::VertexTexCoord | OM::IO::Options::VertexNormal;
    // OpenMesh reports problems on its own error stream; ours are InputErrors.
    bool errWasEnabled = ::omerr().is_enabled(), logWasEnabled = ::omlog().is_enabled();
    ::omerr().disable();
    ::omlog().disable();
    bool ok = OM::IO::IOManager().read(file, importer, opt);
    if (errWasEnabled) ::omerr().enable();
    if (logWasEnabled) ::omlog().enable();
    if (!importer.overflow.empty()) throw InputError(file, "", importer.overflow);
    if (!ok)
        throw InputError(file, "",
                         "OpenMesh's " + ext.substr(1) + " reader could not parse the file");

    PolygonMesh mesh;
    mesh.name = path.stem().string();
    mesh.positions = std::move(importer.positions);
    mesh.faceSizes = std::move(importer.faceSizes);
    mesh.faceVertices = std::move(importer.faceVertices);
    const size_t nV = mesh.positions.size();
    if (!importer.uvs.empty()) {
        importer.hasUv.resize(nV, 0);
        size_t missing =
            size_t(std::count(importer.hasUv.begin(), importer.hasUv.end(), uint8_t(0)));
        FaceVaryingChannel ch;
        ch.name = "texcoord";
        ch.values = std::move(importer.uvs);
        ch.values.resize(nV, glm::vec2(0.0f));
        ch.indices = mesh.faceVertices; // per-vertex UVs: one value per vertex
        mesh.uvSets.push_back(std::move(ch));
        if (missing && report)
            report->notes.push_back(std::to_string(missing) +
                                    " vertices without texture coordinates got (0,0)");
    }
    if (!importer.normals.empty()) {
        importer.hasNormal.resize(nV, 0);
        if (std::count(importer.hasNormal.begin(), importer.hasNormal.end(), uint8_t(0)) == 0) {
            mesh.normals = std::move(importer.normals);
            mesh.normalIndices = mesh.faceVertices;
        } else if (report) {
            report->notes.push_back("normals on some vertices only: ignored (recomputed)");
        }
    }
    if (ext == ".stl" && declaredFaces > mesh.faceSizes.size() && report) {
        report->notes.push_back(std::to_string(declaredFaces - mesh.faceSizes.size()) +
                                " degenerate facets (two equal corners) dropped by the STL reader");
    }
    if (importer.ignoredFaceTexcoords && report) {
        report->notes.push_back(
            "ignored per-face texture coordinates (OpenMesh passes them only to a PolyMesh)");
    }
    return mesh;
}

} // namespace detail

} // namespace sg::mesh
