// surfgrad_flatten: writes the shader library as single files for engines
// without an #include of their own (sg::shaders::flatLibrary,
// docs/engines.md "One file per language"). A build tool: the build runs it
// into <build>/shaders/flat and installs the result in
// share/surfgrad/shaders/flat.
//
//   surfgrad_flatten OUT_DIR
//
// Each file is written to a temporary name and renamed, so a reader never
// sees a partial file.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "surfgrad/shaders/shader_files.h"

namespace {

void writeAtomically(const std::filesystem::path& path, const std::string& text) {
    const std::filesystem::path tmp = path.string() + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.close();
        if (!out) throw std::runtime_error("cannot write " + tmp.string());
    }
    std::filesystem::rename(tmp, path);
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: surfgrad_flatten OUT_DIR\n");
        return 2;
    }
    try {
        const std::filesystem::path dir = argv[1];
        std::filesystem::create_directories(dir);
        for (const auto& f : sg::shaders::flatLibrary()) writeAtomically(dir / f.name, f.text);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "surfgrad_flatten: %s\n", e.what());
        return 1;
    }
    return 0;
}
