// Scene schema validation (docs/scene.md): every kind of bad field is
// rejected with an error naming the field path and the reason; valid scenes
// (the built-in default included) parse into what they say.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "render_test_util.h"
#include "surfgrad/base/io.h"

namespace sg::render::test {
namespace {

struct BadCase {
    const char* what;
    std::string json;
    const char* element; // expected InputError::element()
    const char* reason;  // substring of InputError::reason()
};

std::string mat(const std::string& layers, const std::string& extra = "") {
    return R"({"meshes": [{"procedural": {"type": "sphere"}}], "materials": [{"name": "m", )" +
           extra + R"("layers": [)" + layers + "]}]}";
}
const std::string kMap = R"("map": {"procedural": "bumps"})";

std::vector<BadCase> badCases() {
    return {
        {"invalid JSON", R"({"meshes": [)", "", "invalid JSON"},
        {"number too large for a double", R"({"output": {"width": 1e999}})", "", "number overflow"},
        {"root not an object", "[1, 2]", "(root)", "expected an object"},
        {"unknown top-level field",
         R"({"meshes": [{"procedural": {"type": "sphere"}}], "mehses": []})", "mehses",
         "unknown field"},
        {"no meshes", R"({"materials": []})", "(root)", "missing \"meshes\""},
        {"empty meshes", R"({"meshes": []})", "meshes", "at least one mesh"},
        {"mesh without geometry", R"({"meshes": [{"name": "x"}]})", "meshes[0]",
         "exactly one of \"file\" or \"procedural\""},
        {"unknown procedural type", R"({"meshes": [{"procedural": {"type": "teapot"}}]})",
         "meshes[0].procedural.type", "expected one of"},
        {"segments out of range",
         R"({"meshes": [{"procedural": {"type": "sphere", "segments": 1}}]})",
         "meshes[0].procedural.segments", "expected an integer in [2, 2048]"},
        {"strength not a number",
         mat(R"({"type": "uv_normal", )" + kMap + R"(, "strength": "high"})"),
         "materials[0].layers[0].strength", "expected a number"},
        {"layer type unknown", mat(R"({"type": "bump"})"), "materials[0].layers[0].type",
         "expected one of"},
        {"layer type missing", mat(R"({"map": "x.png"})"), "materials[0].layers[0]",
         "missing \"type\""},
        {"unknown layer field", mat(R"({"type": "uv_normal", )" + kMap + R"(, "strenght": 1})"),
         "materials[0].layers[0].strenght", "unknown field"},
        {"uv_set out of range", mat(R"({"type": "uv_normal", )" + kMap + R"(, "uv_set": 4})"),
         "materials[0].layers[0].uv_set", "expected an integer in [0, 3]"},
        {"missing map", mat(R"({"type": "height"})"), "materials[0].layers[0]", "missing \"map\""},
        {"bad encoding", mat(R"({"type": "uv_normal", )" + kMap + R"(, "encoding": "bc5"})"),
         "materials[0].layers[0].encoding", "expected one of"},
        {"two-channel encoding for object normals",
         mat(R"({"type": "object_normal", )" + kMap + R"(, "encoding": "rg"})"),
         "materials[0].layers[0].encoding", "needs all three components"},
        {"green convention", mat(R"({"type": "uv_normal", )" + kMap + R"(, "green": "up"})"),
         "materials[0].layers[0].green", "expected one of \"gl\", \"dx\""},
        {"texture both file and procedural",
         mat(R"({"type": "uv_normal", "map": {"file": "a.png", "procedural": "bumps"}})"),
         "materials[0].layers[0].map", "exactly one of"},
        {"procedural texture size",
         mat(R"({"type": "uv_normal", "map": {"procedural": "bumps", "size": 2}})"),
         "materials[0].layers[0].map.size", "expected an integer in [4, 4096]"},
        {"triplanar map and maps",
         mat(R"({"type": "triplanar", )" + kMap + R"(, "maps": ["a", "b", "c"]})"),
         "materials[0].layers[0]", "exactly one of \"map\""},
        {"triplanar two maps", mat(R"({"type": "triplanar", "maps": ["a.png", "b.png"]})"),
         "materials[0].layers[0].maps", "array of 3 maps"},
        {"triplanar sharpness zero",
         mat(R"({"type": "triplanar", )" + kMap + R"(, "sharpness": 0})"),
         "materials[0].layers[0].sharpness", "expected a number in (0, 64]"},
        {"decal zero direction",
         mat(R"({"type": "decal", )" + kMap + R"(, "direction": [0, 0, 0]})"),
         "materials[0].layers[0].direction", "non-zero"},
        {"decal up parallel to direction",
         mat(R"({"type": "decal", )" + kMap + R"(, "direction": [0, 1, 0], "up": [0, 2, 0]})"),
         "materials[0].layers[0].up", "not parallel"},
        {"decal size", mat(R"({"type": "decal", )" + kMap + R"(, "size": [1, 0, 1]})"),
         "materials[0].layers[0].size", "> 0"},
        {"decal angle fade order",
         mat(R"({"type": "decal", )" + kMap + R"(, "angle_fade_deg": [80, 20]})"),
         "materials[0].layers[0].angle_fade_deg", "start <= end"},
        {"noise octaves", mat(R"({"type": "noise", "octaves": 0})"),
         "materials[0].layers[0].octaves", "expected an integer in [1, 12]"},
        {"noise exponent below 1", mat(R"({"type": "noise", "exponent": 0.5})"),
         "materials[0].layers[0].exponent", "expected a number in [1, 16]"},
        {"noise frequency zero", mat(R"({"type": "noise", "frequency": 0})"),
         "materials[0].layers[0].frequency", "> 0"},
        {"deform not first",
         mat(R"({"type": "uv_normal", )" + kMap +
             R"(, "modifiers": [{"type": "scale"}, {"type": "deform"}]})"),
         "materials[0].layers[0].modifiers[1]", "must come first"},
        {"modulate without mask",
         mat(R"({"type": "uv_normal", )" + kMap + R"(, "modifiers": [{"type": "modulate"}]})"),
         "materials[0].layers[0].modifiers[0]", "missing \"mask\""},
        {"too many modifiers",
         mat(R"({"type": "uv_normal", )" + kMap +
             R"(, "modifiers": [{"type": "scale"}, {"type": "scale"}, {"type": "scale"}, {"type": "scale"}, {"type": "scale"}]})"),
         "materials[0].layers[0].modifiers", "at most 4"},
        {"curve boost negative",
         mat(R"({"type": "uv_normal", )" + kMap +
             R"(, "modifiers": [{"type": "curve", "boost": -1}]})"),
         "materials[0].layers[0].modifiers[0].boost", ">= 0"},
        {"nested post_resolve",
         mat(R"({"type": "post_resolve", "layers": [{"type": "post_resolve", "layers": []}]})"),
         "materials[0].layers[0].layers[0]", "cannot be nested"},
        {"layer after post_resolve",
         mat(R"({"type": "post_resolve", "layers": []}, {"type": "noise"})"),
         "materials[0].layers[1]", "after a post_resolve group"},
        {"roughness out of range", mat("", R"("roughness": 2, )"), "materials[0].roughness",
         "expected a number in [0, 1]"},
        {"double-sided mode", mat("", R"("double_sided": "both", )"), "materials[0].double_sided",
         "expected one of"},
        {"base colour components", mat("", R"("base_color": [1, 0.5], )"),
         "materials[0].base_color", "expected an array of 3 numbers"},
        {"unknown material name",
         R"({"meshes": [{"procedural": {"type": "sphere"}, "material": "gold"}]})",
         "meshes[0].material", "no material named \"gold\""},
        {"material index out of range",
         R"({"meshes": [{"procedural": {"type": "sphere"}, "material": 3}]})", "meshes[0].material",
         "no material with index 3"},
        {"tangent source",
         R"({"meshes": [{"procedural": {"type": "sphere"}, "tangents": ["mikkt"]}]})",
         "meshes[0].tangents[0]", "expected \"pixel\", \"mikktspace\" or \"limit\""},
        {"derived UV set source", R"({"meshes": [{"file": "m.obj", "uv_sets": [{"from": 4}]}]})",
         "meshes[0].uv_sets[0].from", "expected an integer in [0, 3]"},
        {"derived UV set zero scale",
         R"({"meshes": [{"file": "m.obj", "uv_sets": [{"scale": [8, 0]}]}]})",
         "meshes[0].uv_sets[0].scale", "non-zero"},
        {"derived UV set scale shape",
         R"({"meshes": [{"file": "m.obj", "uv_sets": [{"scale": [1, 2, 3]}]}]})",
         "meshes[0].uv_sets[0].scale", "a number or an array of 2 numbers"},
        {"derived UV set offset",
         R"({"meshes": [{"file": "m.obj", "uv_sets": [{"offset": 0.5}]}]})",
         "meshes[0].uv_sets[0].offset", "an array of 2 numbers"},
        {"derived UV set rotation",
         R"({"meshes": [{"file": "m.obj", "uv_sets": [{"rotate_deg": "30"}]}]})",
         "meshes[0].uv_sets[0].rotate_deg", "expected a number"},
        {"derived UV set unknown field",
         R"({"meshes": [{"file": "m.obj", "uv_sets": [{"from": 0, "rotate": 30}]}]})",
         "meshes[0].uv_sets[0].rotate", "unknown field"},
        {"too many derived UV sets",
         R"({"meshes": [{"file": "m.obj", "uv_sets": [{}, {}, {}, {}, {}]}]})", "meshes[0].uv_sets",
         "at most 4"},
        {"limit tangents without limit",
         R"({"meshes": [{"file": "m.obj", "tangents": ["limit"]}]})", "meshes[0].tangents",
         "\"limit\": true"},
        {"subdivision of a procedural mesh",
         R"({"meshes": [{"procedural": {"type": "sphere"}, "subdivision": {"level": 2}}]})",
         "meshes[0].subdivision", "mesh files only"},
        {"subdivision level", R"({"meshes": [{"file": "m.obj", "subdivision": {"level": 9}}]})",
         "meshes[0].subdivision.level", "expected an integer in [0, 6]"},
        {"subdivision memory limit",
         R"({"meshes": [{"file": "m.obj", "subdivision": {"level": 2, "max_memory_mib": 0}}]})",
         "meshes[0].subdivision.max_memory_mib", "expected an integer in [1, 16777216]"},
        {"morph key times",
         R"({"meshes": [{"file": "m.gltf", "morph": {"animation": {"keys": [{"time": 1, "weights": [0]}, {"time": 0.5, "weights": [1]}]}}}]})",
         "meshes[0].morph.animation.keys[1].time", "must increase"},
        {"singular transform",
         R"({"meshes": [{"procedural": {"type": "sphere"}, "transform": {"scale": [1, 0, 1]}}]})",
         "meshes[0].transform.scale", "non-zero"},
        {"output width",
         R"({"meshes": [{"procedural": {"type": "sphere"}}], "output": {"width": 0}})",
         "output.width", "expected an integer in [1, 8192]"},
        {"camera target equals position",
         R"({"meshes": [{"procedural": {"type": "sphere"}}], "camera": {"position": [1, 2, 3], "target": [1, 2, 3]}})",
         "camera.target", "must differ"},
        {"light type",
         R"({"meshes": [{"procedural": {"type": "sphere"}}], "lights": [{"type": "spot"}]})",
         "lights[0].type", "expected one of"},
        {"too many lights",
         R"({"meshes": [{"procedural": {"type": "sphere"}}], "lights": [{"type": "point"}, {"type": "point"}, {"type": "point"}, {"type": "point"}, {"type": "point"}, {"type": "point"}, {"type": "point"}, {"type": "point"}, {"type": "point"}]})",
         "lights", "at most 8"},
        {"NaN-like value", R"({"meshes": [{"procedural": {"type": "sphere", "size": -1}}]})",
         "meshes[0].procedural.size", "> 0"},
        {"frames fps", R"({"meshes": [{"procedural": {"type": "sphere"}}], "frames": {"fps": 0}})",
         "frames.fps", "in (0, 1000]"},
    };
}

TEST(SceneValidation, EveryBadFieldIsNamed) {
    for (const BadCase& c : badCases()) {
        SCOPED_TRACE(c.what);
        try {
            parseScene(c.json, "scene.json", ".");
            ADD_FAILURE() << "accepted: " << c.json;
        } catch (const io::InputError& e) {
            EXPECT_EQ(e.file(), "scene.json");
            EXPECT_EQ(e.element(), c.element) << e.what();
            EXPECT_NE(e.reason().find(c.reason), std::string::npos) << e.what();
            // The message a user sees: "scene.json: <field>: <reason>".
            if (*c.element) {
                EXPECT_EQ(
                    std::string(e.what()).rfind(std::string("scene.json: ") + c.element + ": ", 0),
                    0u);
            }
        }
    }
}

TEST(SceneValidation, ErrorsFoundWhenLoadingAssetsNameTheField) {
    // A layer reading a UV set the mesh does not have (procedural meshes
    // have the number of UV sets they are asked for).
    Scene s = sceneFromJson(R"({"meshes": [{"procedural": {"type": "plane", "uv_sets": 1}}],
        "materials": [{"layers": [{"type": "uv_normal", "uv_set": 2, "map": {"procedural": "tiles"}}]}]})");
    SceneAssets a = loadAssets(s);
    try {
        planMaterial(s, a, 0, 0);
        ADD_FAILURE() << "missing UV set accepted";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.element(), "materials[0].layers[0].uv_set");
        EXPECT_NE(e.reason().find("has 1 UV set"), std::string::npos) << e.what();
    }
    // A texture file that does not exist.
    Scene s2 = sceneFromJson(R"({"meshes": [{"procedural": {"type": "plane"}}],
        "materials": [{"layers": [{"type": "uv_normal", "map": "no/such/file.png"}]}]})");
    try {
        loadAssets(s2);
        ADD_FAILURE() << "missing texture accepted";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.element(), "materials[0].layers[0].map");
        EXPECT_NE(e.reason().find("does not exist"), std::string::npos) << e.what();
    }
    // Derived UV sets: the source must exist when the set is added (a
    // file's set count is known only then), and a mesh has at most 4 sets.
    auto loadError = [](const std::string& json, const std::string& element,
                        const std::string& reason) {
        Scene sc = sceneFromJson(json);
        try {
            loadAssets(sc);
            ADD_FAILURE() << "accepted: " << json;
        } catch (const io::InputError& e) {
            EXPECT_EQ(e.element(), element) << e.what();
            EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
        }
    };
    loadError(
        R"({"meshes": [{"procedural": {"type": "plane", "uv_sets": 1}, "uv_sets": [{"from": 1}]}]})",
        "meshes[0].uv_sets[0].from", "has 1 UV set(s)");
    loadError(
        R"({"meshes": [{"procedural": {"type": "plane", "uv_sets": 3}, "uv_sets": [{"from": 0}, {"from": 1}]}]})",
        "meshes[0].uv_sets[1]", "at most 4 UV sets");
    loadError(
        R"({"meshes": [{"procedural": {"type": "plane", "uv_sets": 2}, "tangents": ["pixel", "pixel", "mikktspace"]}]})",
        "meshes[0].tangents[2]", "no UV set 2");
    // A mesh file that does not exist is reported by the mesh loader with the path.
    Scene s3 = sceneFromJson(R"({"meshes": [{"file": "no/such/mesh.obj"}]})");
    EXPECT_THROW(loadAssets(s3), io::InputError);
    // A mesh file whose values MikkTSpace cannot take (a coordinate beyond
    // 2^60), asked for MikkTSpace tangents a layer reads: the tangents field.
    const std::filesystem::path huge =
        std::filesystem::path(SURFGRAD_BINARY_DIR) / "tests/render/huge_coordinate.obj";
    std::filesystem::create_directories(huge.parent_path());
    std::ofstream(huge) << "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                           "f 1/1 2/2 3/3\n";
    loadError(R"({"meshes": [{"file": ")" + huge.string() + R"(", "tangents": ["mikktspace"]}],
        "materials": [{"layers": [{"type": "uv_normal", "map": {"procedural": "bumps"}}]}]})",
              "meshes[0].tangents[0]", "MikkTSpace failed: MikkTSpace: vertex 1");
}

TEST(SceneValidation, ValidSceneParsesAsWritten) {
    Scene s = sceneFromJson(R"({
      "output": {"width": 320, "height": 200, "exposure": 2},
      "materials": [{"name": "a", "double_sided": "flip", "roughness": 0.2, "layers": [
        {"type": "uv_normal", "uv_set": 1, "green": "dx", "encoding": "ag", "strength": 0.5, "map": {"procedural": "weave"}},
        {"type": "decal", "position": [1, 2, 3], "direction": [0, -1, 0], "up": [0, 0, -1], "size": [2, 4, 6], "map": "d.png"},
        {"type": "post_resolve", "layers": [{"type": "noise", "noise": "fbm", "octaves": 3, "exponent": 2}]}]}],
      "meshes": [{"procedural": {"type": "torus"}, "material": "a", "transform": {"translate": [1, 0, 0], "scale": 2},
                  "uv_sets": [{"from": 1, "scale": 8, "rotate_deg": 30, "offset": [0.25, -1]}, {"scale": [2, -3]}],
                  "tangents": ["mikktspace", "pixel", "mikktspace"]}],
      "lights": [{"type": "point", "position": [0, 5, 0], "intensity": 10}]})");
    ASSERT_EQ(s.materials.size(), 1u);
    const Material& m = s.materials[0];
    EXPECT_EQ(m.doubleSided, DoubleSided::Flip);
    ASSERT_EQ(m.layers.size(), 3u);
    EXPECT_EQ(m.layers[0].uvSet, 1);
    EXPECT_TRUE(m.layers[0].params<UvNormalParams>().flipV);
    EXPECT_EQ(m.layers[0].params<UvNormalParams>().encoding, NormalEncoding::Ag);
    EXPECT_FLOAT_EQ(m.layers[0].strength, 0.5f);
    // Decal frame: z points against the projection direction, x = up x z.
    const DecalParams& decal = m.layers[1].params<DecalParams>();
    EXPECT_NEAR(glm::length(decal.axisZ - glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(decal.axisY - glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(decal.halfSize - glm::vec3(1, 2, 3)), 0.0f, 1e-6f);
    EXPECT_EQ(m.layers[1].maps[0].wrap, Wrap::Clamp); // decals do not repeat
    EXPECT_EQ(m.layers[2].kind, findLayerKind("post_resolve"));
    ASSERT_EQ(m.layers[2].children.size(), 1u);
    EXPECT_EQ(m.layers[2].children[0].params<NoiseParams>().type, NoiseType::Fbm);
    EXPECT_EQ(s.meshes[0].material, 0);
    const auto& uvs = s.meshes[0].derivedUvSets;
    ASSERT_EQ(uvs.size(), 2u);
    EXPECT_EQ(uvs[0].from, 1);
    EXPECT_EQ(uvs[0].scale, glm::vec2(8.0f));
    EXPECT_FLOAT_EQ(uvs[0].rotateDeg, 30.0f);
    EXPECT_EQ(uvs[0].offset, glm::vec2(0.25f, -1.0f));
    EXPECT_EQ(uvs[1].from, 0);
    EXPECT_EQ(uvs[1].scale, glm::vec2(2.0f, -3.0f));
    EXPECT_EQ(uvs[1].fieldPath, "meshes[0].uv_sets[1]");
    // Any number of UV sets may carry vertex tangents, each its own source.
    EXPECT_EQ(s.meshes[0].tangents,
              (std::vector<TangentSource>{TangentSource::MikkTSpace, TangentSource::Pixel,
                                          TangentSource::MikkTSpace}));
    EXPECT_NEAR(s.meshes[0].transform[0][0], 2.0f, 1e-6f);
    EXPECT_NEAR(s.meshes[0].transform[3][0], 1.0f, 1e-6f);
    EXPECT_TRUE(s.lights[0].point);
    EXPECT_EQ(s.output.width, 320);
}

TEST(SceneValidation, DefaultSceneIsValidAndUsesManyLayerKinds) {
    Scene s = defaultScene();
    EXPECT_GE(s.meshes.size(), 3u);
    std::set<const LayerKind*> kinds;
    for (const auto& m : s.materials)
        for (const auto& L : m.layers) {
            kinds.insert(L.kind);
            for (const auto& c : L.children) kinds.insert(c.kind);
        }
    EXPECT_GE(kinds.size(), 6u) << "the default scene should show most layer kinds";
}

// A scene whose subdivision would need more memory than its limit (the
// default budget, or subdivision.max_memory_mib): refused before the
// refinement allocates, naming the level, the faces, the bytes needed and
// the field that raises the limit; as every error of a referenced file it
// keeps the scene context (field meshes[0].file, then the mesh file and its
// element); within a raised limit the same mesh loads.
TEST(SceneAssets, SubdivisionAboveTheMemoryLimitIsRefused) {
    const std::string spot = std::string(SURFGRAD_DATA_DIR) + "/meshes/spot/spot_control_mesh.obj";
    auto scene = [&](int level, int mib) {
        return sceneFromJson(R"({"meshes": [{"file": ")" + spot +
                             R"(", "subdivision": {"level": )" + std::to_string(level) +
                             R"(, "max_memory_mib": )" + std::to_string(mib) + "}}]}");
    };
    try {
        loadAssets(scene(5, 16));
        ADD_FAILURE() << "expected InputError";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.element(), "meshes[0].file");
        EXPECT_NE(std::string(e.reason())
                      .find("spot_control_mesh.obj: level 5: would make 187392 "
                            "faces and need about "),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.reason())
                      .find("the limit is 16.0 MiB (raise it with the scene field "
                            "meshes[0].subdivision.max_memory_mib)"),
                  std::string::npos)
            << e.what();
    }
    const SceneAssets a = loadAssets(scene(1, 64));
    ASSERT_EQ(a.meshes.size(), 1u);
    EXPECT_EQ(a.meshes[0].mesh.triangleCount(), 732u * 2);
}

} // namespace
} // namespace sg::render::test
