// The OBJ reader on several threads (parseObj's block reader,
// surfgrad/mesh/mesh_io.h): at 1, 2, 3 and 7 threads and with blocks of a few
// bytes (so block boundaries fall on every kind of line), the mesh, the
// face lines, the report's notes and, for malformed text, the error message
// are the serial reader's exactly (memcmp of every array; string equality
// of messages). Inputs: the repository's OBJ files and random OBJ texts
// (rapidcheck, fixed seed) of valid and malformed statements, negative
// indices, tags, CRLF endings and small limits. Seeds: a fixed one
// (kDefaultParams); to run more cases or another seed:
//   RC_PARAMS="max_success=20000 seed=1" build/bin/mesh_tests --gtest_filter='ObjThreads.*'
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"

namespace {

using namespace sg::mesh;

// The fixed seed of the CI run (rapidcheck reads RC_PARAMS once, at its
// first property).
constexpr const char* kDefaultParams = "seed=20261206 max_success=1000";
[[maybe_unused]] const bool kSeeded = [] {
    if (!std::getenv("RC_PARAMS")) setenv("RC_PARAMS", kDefaultParams, 0);
    return true;
}();

template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool sameMesh(const PolygonMesh& a, const PolygonMesh& b) {
    if (!sameBytes(a.positions, b.positions) || !sameBytes(a.faceSizes, b.faceSizes) ||
        !sameBytes(a.faceVertices, b.faceVertices) || !sameBytes(a.normals, b.normals) ||
        !sameBytes(a.normalIndices, b.normalIndices) || !sameBytes(a.creases, b.creases) ||
        !sameBytes(a.corners, b.corners) || !sameBytes(a.holes, b.holes) ||
        a.uvSets.size() != b.uvSets.size() || a.explicitTags != b.explicitTags ||
        std::memcmp(&a.options, &b.options, sizeof a.options) != 0 || a.name != b.name) {
        return false;
    }
    for (size_t s = 0; s < a.uvSets.size(); ++s) {
        if (a.uvSets[s].name != b.uvSets[s].name ||
            !sameBytes(a.uvSets[s].values, b.uvSets[s].values) ||
            !sameBytes(a.uvSets[s].indices, b.uvSets[s].indices)) {
            return false;
        }
    }
    return true;
}

// What one reader makes of a text: the mesh, face lines and notes, or the
// error message.
struct Outcome {
    PolygonMesh mesh;
    std::vector<uint32_t> faceLines;
    std::vector<std::string> notes;
    std::string error;
};

Outcome readWith(const std::string& text, const InputLimits& limits, int threads,
                 size_t blockBytes) {
    Outcome o;
    LoadReport report;
    try {
        o.mesh = detail::parseObjInBlocks(text, "t.obj", limits, &report, threads, blockBytes,
                                          &o.faceLines);
        o.notes = report.notes;
    } catch (const sg::io::InputError& e) {
        o.error = e.what();
    }
    return o;
}

// Empty when equal, else what differs.
std::string difference(const Outcome& serial, const Outcome& blocks) {
    if (serial.error != blocks.error)
        return "error '" + serial.error + "' vs '" + blocks.error + "'";
    if (!serial.error.empty()) return {};
    if (!sameMesh(serial.mesh, blocks.mesh)) return "meshes differ";
    if (serial.faceLines != blocks.faceLines) return "face lines differ";
    if (serial.notes != blocks.notes) return "notes differ";
    return {};
}

TEST(ObjThreads, BlockReaderEqualsSerialOnDataFiles) {
    const std::filesystem::path data = SURFGRAD_DATA_DIR;
    size_t files = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(data)) {
        if (entry.path().extension() != ".obj") continue;
        const std::string text = sg::io::readFile(entry.path());
        const Outcome serial = readWith(text, {}, 1, 0);
        ASSERT_TRUE(serial.error.empty()) << entry.path() << ": " << serial.error;
        for (int threads : {1, 2, 3, 7}) {
            for (size_t blockBytes : {size_t(1), size_t(97), size_t(4096), text.size()}) {
                EXPECT_EQ(difference(serial, readWith(text, {}, threads, blockBytes)), "")
                    << entry.path() << " threads " << threads << " blocks of " << blockBytes;
            }
        }
        ++files;
    }
    EXPECT_GT(files, 20u);
}

// One line of a random OBJ text from a random word: mostly valid
// statements, some malformed ones.
std::string randomLine(uint32_t r) {
    const int kind = int(r % 23);
    r /= 23;
    auto pick = [&r](int n) {
        const int v = int(r % uint32_t(n));
        r /= uint32_t(n);
        return v;
    };
    static const char* kNumbers[] = {"0", "1", "-1", "0.5", "2e-3", "+3", "nan", "1e39", "x", "-0"};
    auto number = [&] { return std::string(kNumbers[pick(8) < 7 ? pick(6) : 6 + pick(4)]); };
    auto index = [&] { return std::to_string(pick(13) - 4); }; // -4..8, 0 is an error
    auto corner = [&] {
        switch (pick(5)) {
        case 0:
            return index();
        case 1:
            return index() + "/" + index();
        case 2:
            return index() + "//" + index();
        case 3:
            return index() + "/" + index() + "/" + index();
        default:
            return std::string(pick(4) == 0 ? "1/2/3/4" : "1/x");
        }
    };
    switch (kind) {
    case 0:
    case 1:
    case 2:
    case 3:
        return "v " + number() + " " + number() + " " + number();
    case 4:
        return "v 1 2";
    case 5:
    case 6:
        return "vt " + number() + " " + number();
    case 7:
    case 8:
        return "vn " + number() + " " + number() + " " + number();
    case 9:
    case 10:
    case 11:
    case 12: {
        std::string f = "f";
        const int n = 3 + pick(3) - (pick(8) == 0 ? 2 : 0);
        for (int i = 0; i < n; ++i)
            f += " " + (pick(3) == 0 ? corner() : std::to_string(1 + pick(6)));
        return f;
    }
    case 13:
        return "t crease 2/1/0 " + index() + " " + index() + " 2.5";
    case 14:
        return "t corner 1/1/0 " + index() + " 3";
    case 15:
        return "t hole 1/0/0 " + index();
    case 16:
        return "t interpolateboundary 1/0/0 " + std::to_string(pick(4));
    case 17:
        return std::string("t scheme 0/0/1 ") + (pick(2) ? "loop" : "bilinear");
    case 18:
        return "t unknown" + std::to_string(pick(20)) + " 0/0/0";
    case 19:
        return "# comment " + number();
    case 20:
        return pick(2) ? "" : "   \t";
    case 21:
        return std::string(pick(2) ? "o name" : "usemtl m") + std::to_string(pick(3));
    default:
        return "t creasemethod 0/0/1 " + std::string(pick(2) ? "chaikin" : "normal");
    }
}

RC_GTEST_PROP(ObjThreads, RandomTextsReadTheSameAtEveryThreadCount,
              (const std::vector<uint32_t>& words, bool crlf, bool smallLimits, bool lastNewline)) {
    std::string text;
    for (size_t i = 0; i < words.size(); ++i) {
        text += randomLine(words[i]);
        if (i + 1 < words.size() || lastNewline) text += crlf ? "\r\n" : "\n";
    }
    InputLimits limits;
    if (smallLimits) {
        limits.maxVertices = 12;
        limits.maxFaces = 6;
        limits.maxCorners = 20;
        limits.maxFaceDegree = 4;
    }
    const Outcome serial = readWith(text, limits, 1, 0);
    RC_CLASSIFY(serial.error.empty(), "read");
    RC_CLASSIFY(!serial.error.empty(), "error");
    const size_t blockBytes = *rc::gen::inRange<size_t>(1, 64);
    for (int threads : {1, 2, 3, 7}) {
        const std::string why = difference(serial, readWith(text, limits, threads, blockBytes));
        RC_ASSERT(why == "");
    }
}

// The public entry point and the loader at the cut-over and above it: a
// file of more than kObjParallelMinBytes (blub, welded copies side by
// side) gives the same mesh at 1 and 3 threads.
TEST(ObjThreads, LoaderAboveTheCutOverEqualsOneThread) {
    const std::string one =
        sg::io::readFile(std::filesystem::path(SURFGRAD_DATA_DIR) / "meshes/bob/bob_tri.obj");
    std::string text;
    while (text.size() < kObjParallelMinBytes + kObjBlockBytes) text += one;
    const PolygonMesh a = parseObj(text, "big.obj", {}, nullptr, 1);
    for (int threads : {0, 2, 3, 7}) {
        EXPECT_TRUE(sameMesh(a, parseObj(text, "big.obj", {}, nullptr, threads)))
            << threads << " threads";
    }
    // An error in the last block is named as the serial reader names it.
    const std::string bad = text + "f 1 2 0\n";
    std::string serialError, threadedError;
    try {
        parseObj(bad, "big.obj", {}, nullptr, 1);
    } catch (const sg::io::InputError& e) {
        serialError = e.what();
    }
    try {
        parseObj(bad, "big.obj", {}, nullptr, 3);
    } catch (const sg::io::InputError& e) {
        threadedError = e.what();
    }
    EXPECT_NE(serialError.find("index 0"), std::string::npos) << serialError;
    EXPECT_EQ(serialError, threadedError);
}

} // namespace

namespace {

// weldVerticesByValue at 1, 2, 3 and 7 threads on a mesh above its cut-over
// (random values from a small pool, so most vertices have equal copies):
// the same arrays bit for bit, numbered by first occurrence.
TEST(WeldByValue, SameAtEveryThreadCountAndNumberedByFirstOccurrence) {
    RenderMesh m;
    const size_t n = kWeldParallelMinVertices + 4097;
    uint32_t state = 12345;
    auto next = [&state] { return state = state * 1664525u + 1013904223u; };
    for (size_t v = 0; v < n; ++v) {
        const float a = float(next() >> 28), b = float(next() >> 29);
        m.positions.push_back({a, b, 1.0f});
        m.normals.push_back({0.0f, 0.0f, 1.0f});
        m.uvSets.resize(1);
        m.uvSets[0].push_back({b, float(next() >> 30)});
    }
    for (size_t i = 0; i < 3 * n; ++i) m.indices.push_back(uint32_t(next() % n));
    RenderMesh one = m;
    const size_t removed = weldVerticesByValue(one, 1);
    ASSERT_GT(removed, n / 2);
    // First occurrence: numbering m's vertices by their first equal one in
    // vertex order (a map of the values) gives the result's arrays.
    std::map<std::array<float, 5>, uint32_t> idOf;
    std::vector<uint32_t> expectedId(n);
    for (size_t v = 0; v < n; ++v) {
        const std::array<float, 5> key{m.positions[v].x, m.positions[v].y, m.positions[v].z,
                                       m.uvSets[0][v].x, m.uvSets[0][v].y};
        expectedId[v] = idOf.emplace(key, uint32_t(idOf.size())).first->second;
    }
    ASSERT_EQ(one.positions.size(), idOf.size());
    for (size_t v = 0; v < n; ++v) {
        ASSERT_EQ(one.positions[expectedId[v]], m.positions[v]);
        ASSERT_EQ(one.uvSets[0][expectedId[v]], m.uvSets[0][v]);
    }
    for (size_t i = 0; i < m.indices.size(); ++i)
        ASSERT_EQ(one.indices[i], expectedId[m.indices[i]]);
    for (int threads : {0, 2, 3, 7}) {
        RenderMesh t = m;
        EXPECT_EQ(weldVerticesByValue(t, threads), removed);
        EXPECT_TRUE(sameBytes(t.positions, one.positions) && sameBytes(t.normals, one.normals) &&
                    sameBytes(t.uvSets[0], one.uvSets[0]) && sameBytes(t.indices, one.indices))
            << threads << " threads";
    }
}

} // namespace
