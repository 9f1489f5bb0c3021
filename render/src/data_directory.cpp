// Where "data:" paths of scenes resolve (sg::render::dataDirectory(); the
// order is documented at the declaration in surfgrad/render/scene.h): the
// build tree uses the source tree's data/, an installation its own
// share/surfgrad/data found relative to the running executable, so that a
// relocated prefix and the Debian package work without configuration.
// The compile definitions come from render/CMakeLists.txt.
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "surfgrad/render/scene.h"

#ifndef SURFGRAD_DEFAULT_DATA_DIR
#define SURFGRAD_DEFAULT_DATA_DIR ""
#endif
#ifndef SURFGRAD_BUILD_BIN_DIR
#define SURFGRAD_BUILD_BIN_DIR ""
#endif
#ifndef SURFGRAD_BIN_TO_DATA_DIR
#define SURFGRAD_BIN_TO_DATA_DIR "../share/surfgrad/data"
#endif
#ifndef SURFGRAD_INSTALL_DATA_DIR
#define SURFGRAD_INSTALL_DATA_DIR ""
#endif

namespace sg::render {

namespace fs = std::filesystem;

namespace {

// The running executable with symbolic links resolved (a link to an
// installed surfgrad still finds its prefix); empty if unknown.
fs::path executablePath() {
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : exe;
}

// Whether the two paths name the same existing directory.
bool sameDirectory(const fs::path& a, const fs::path& b) {
    std::error_code ec;
    return !a.empty() && !b.empty() && fs::equivalent(a, b, ec) && !ec;
}

bool isDirectory(const fs::path& p) {
    std::error_code ec;
    return !p.empty() && fs::is_directory(p, ec);
}

} // namespace

fs::path dataDirectory() {
    if (const char* env = std::getenv("SURFGRAD_DATA_DIR"); env && *env) return fs::path(env);
    const fs::path sourceData(SURFGRAD_DEFAULT_DATA_DIR);
    const fs::path exe = executablePath();
    // Every program of the build tree is in its bin/ (an installation made
    // inside the build tree, as the install tests do, is not).
    if (sameDirectory(exe.parent_path(), fs::path(SURFGRAD_BUILD_BIN_DIR))) return sourceData;
    if (!exe.empty()) {
        fs::path installed = (exe.parent_path() / SURFGRAD_BIN_TO_DATA_DIR).lexically_normal();
        if (isDirectory(installed)) return installed;
    }
    if (const fs::path configured(SURFGRAD_INSTALL_DATA_DIR); isDirectory(configured)) {
        return configured;
    }
    return sourceData;
}

} // namespace sg::render
