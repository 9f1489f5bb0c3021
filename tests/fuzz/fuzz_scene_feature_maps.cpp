// Fuzz entry point: a feature-map file (OpenEXR) through the full loader,
// as a scene loads it: the input is written to a file that a fixed scene's
// feature layer names ("maps"), then parseScene, loadAssets (the render
// module's feature-map asset: sg::features::load, its EXR header pre-check,
// the image decoder, the validation of every channel and signature, packing for
// the GPU) and a CPU reference render of a plane covered by the map, whose
// pixels must all be finite (the normal output; the first byte's low bit
// picks linear or quadratic evaluation by the profile's mode). Documented
// errors (InputError) are expected; a crash, a hang, a sanitizer report,
// another exception or a NaN pixel is a bug.
#include <cstdint>
#include <fstream>
#include <string>

#include "scene_fuzz_util.h"
#include "surfgrad/base/io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::filesystem::path dir = sgfuzz::scratchDir("scene_feature_maps");
    std::ofstream(dir / "maps.exr", std::ios::binary)
        .write(reinterpret_cast<const char*>(data), std::streamsize(size));
    // A plane filling the view, UVs 0..1 over it, the map tiled twice and
    // offset so texel borders, corners and the map's edges are all seen.
    const std::string mode = (size > 0 && (data[0] & 1)) ? "paper" : "surfgrad";
    const std::string scene =
        R"({"output": {"width": 32, "height": 32},
            "camera": {"position": [0, 2, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_deg": 60},
            "materials": [{"layers": [{"type": "feature", "maps": "maps.exr", "profile": "ridge",
                                       "width": 3, "w0": 0.5, "depth": 1, "tiling": 2,
                                       "offset": [0.1, -0.2], "mode": ")" +
        mode + R"("}]}],
            "meshes": [{"procedural": {"type": "plane", "size": 2, "segments": 2}}]})";
    try {
        sg::render::Scene s = sg::render::parseScene(scene, "fuzz-scene.json", dir);
        sgfuzz::renderAndCheck(s, sg::render::Aov::Normal, 32, 32);
    } catch (const sg::io::InputError&) {
    }
    return 0;
}
