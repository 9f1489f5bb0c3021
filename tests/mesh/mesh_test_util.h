// Helpers for the mesh/ tests: data paths, small cages as OBJ text,
// expecting an InputError with given element/reason fragments.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"

namespace sg::test {

inline std::filesystem::path dataDir() {
    const char* env = std::getenv("SURFGRAD_DATA_DIR");
    return env && *env ? std::filesystem::path(env) : std::filesystem::path(SURFGRAD_DATA_DIR);
}
inline std::filesystem::path dataPath(const std::string& rel) {
    return dataDir() / rel;
}

// A scratch directory per test, removed at the end.
class TempDir {
public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = std::filesystem::temp_directory_path() /
                ("surfgrad_mesh_" + std::string(info->test_suite_name()) + "_" + info->name() +
                 "_" + std::to_string(::getpid()));
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

inline void writeText(const std::filesystem::path& p, const std::string& text) {
    sg::io::writeFileAtomically(p, text);
}

// Unit cube, 6 quads, outward CCW faces, one UV per corner (a cross layout).
inline const char* kCubeObj = R"(v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
f 1/1 4/2 3/3 2/4
f 5/1 6/2 7/3 8/4
f 1/1 2/2 6/3 5/4
f 2/1 3/2 7/3 6/4
f 3/1 4/2 8/3 7/4
f 4/1 1/2 5/3 8/4
)";

// Calls `f` and checks that it throws InputError whose element and reason
// contain the given fragments (empty fragment: not checked).
template <class F>
void expectInputError(F&& f, const std::string& elementPart, const std::string& reasonPart) {
    try {
        f();
        ADD_FAILURE() << "expected InputError (" << elementPart << ": " << reasonPart << ")";
    } catch (const sg::io::InputError& e) {
        EXPECT_NE(e.element().find(elementPart), std::string::npos) << "element of: " << e.what();
        EXPECT_NE(e.reason().find(reasonPart), std::string::npos) << "reason of: " << e.what();
    }
}

} // namespace sg::test
