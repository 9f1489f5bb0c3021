// Fuzz entry point: a scene together with the files it references, as
// `surfgrad render SCENE.json` loads them: the scene parser, then every
// referenced file through its loader (meshes: OBJ with OpenSubdiv tags,
// OFF, PLY, STL, glTF with external buffers, GLB; curves: JSON, SVG, fonts;
// feature maps; textures through OpenImageIO), the mesh pipeline the scene
// asks for (subdivision, limit evaluation, vertex tangents, derived UV sets,
// morph animation) and a small CPU reference render whose pixels must all be
// finite. Documented errors (InputError) are expected; a crash, a hang, a
// sanitizer report, another exception or a NaN pixel is a bug.
//
// Input format (a tiny archive, so mutations reach both the scene and its
// files):
//   <scene JSON>
//   \n@file NAME\n<bytes of NAME>
//   \n@file NAME\n<bytes of NAME> ...
// NAME is 1..40 characters of [A-Za-z0-9._-], not starting with '.'
// (anything else: the entry is skipped); at most 8 files. They are written
// to a per-process scratch folder, the scene's base directory. The harness
// bounds what the scene may ask for (scene_fuzz_util.h: subdivision level,
// procedural sizes) and renders 24 x 16 pixels; the first byte's low bit
// picks the color or the normal output.
#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>

#include "scene_fuzz_util.h"
#include "surfgrad/base/io.h"

namespace {

bool validName(std::string_view n) {
    if (n.empty() || n.size() > 40 || n[0] == '.') return false;
    for (char c : n) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
        if (!ok) return false;
    }
    return true;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    namespace fs = std::filesystem;
    const std::string_view in(reinterpret_cast<const char*>(data), size);
    const std::string_view sep = "\n@file ";
    const fs::path dir = sgfuzz::scratchDir("scene_files");
    size_t at = in.find(sep);
    const std::string scene(in.substr(0, at));
    int files = 0;
    while (at != std::string_view::npos && files < 8) {
        const size_t nameStart = at + sep.size();
        const size_t nameEnd = in.find('\n', nameStart);
        if (nameEnd == std::string_view::npos) break;
        const size_t next = in.find(sep, nameEnd);
        const std::string_view name = in.substr(nameStart, nameEnd - nameStart);
        const std::string_view body =
            in.substr(nameEnd + 1,
                      next == std::string_view::npos ? std::string_view::npos : next - nameEnd - 1);
        if (validName(name)) {
            std::ofstream(dir / std::string(name), std::ios::binary)
                .write(body.data(), std::streamsize(body.size()));
            ++files;
        }
        at = next;
    }
    try {
        sg::render::Scene s = sg::render::parseScene(scene, "fuzz-scene.json", dir);
        sgfuzz::boundCost(s);
        sgfuzz::renderAndCheck(
            s, (size > 0 && (data[0] & 1)) ? sg::render::Aov::Normal : sg::render::Aov::Color, 24,
            16);
    } catch (const sg::io::InputError&) {
    }
    return 0;
}
