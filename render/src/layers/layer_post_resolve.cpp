// Layer kind `post_resolve`: a group of layers resolved on top of the
// result so far (Mikkelsen 2019, sections 2.11 and 3): the assembler
// re-prologues with the resolved normal as the base, re-derives the group's
// UV frames per pixel and resolves the group's sum. A group has no GLSL of
// its own (sgReprologue is in sg/surfgrad.glsl); this unit holds its scene
// field and its uber-shader stand-in.
#include "layer_kind.h"

namespace sg::render {

namespace {

using detail::SceneNode;

void parseLayers(const SceneNode& n, const char* key, Layer& L, const detail::SceneReader& reader) {
    if (reader.nested) n.fail("post_resolve groups cannot be nested (list them one after another)");
    if (!n.has(key)) n.fail("missing \"layers\"");
    n.requireArray(key, size_t(kMaxLayers));
    SceneNode arr = n.child(key);
    for (size_t i = 0; i < arr.value().size(); ++i)
        L.children.push_back(reader.layer(arr.item(i), true, reader.materialAntialias));
}

// A group with one layer of detail.
std::vector<Layer> uberStandIns(const LayerKind& k, int) {
    Layer g = uberStandIn(k);
    Layer child = makeLayer("noise");
    child.fieldPath = "(uber post_resolve noise)";
    child.enabled = false;
    g.children.push_back(child);
    return {g};
}

} // namespace

const LayerKind& postResolveLayerKind() {
    static const LayerKind kind{
        .name = "post_resolve",
        .sigCode = "grp",
        .doc = "group resolved on top of the previous result (section 3)",
        .example = R"("layers": [{"type": "noise"}])",
        .params = {param::custom("layers", parseLayers, "the group's layers (no nesting)")},
        .group = true,
        .uberStandIns = uberStandIns,
        .imageCases =
            {
                {"post_resolve",
                 R"({"type": "uv_normal", "map": {"procedural": "bricks", "size": 256}}, {"type": "post_resolve", "layers": [{"type": "noise", "amplitude": 0.004, "frequency": 10, "exponent": 2}, {"type": "triplanar", "strength": 0.5, "map": {"procedural": "tiles", "size": 128}}]})"},
            },
    };
    return kind;
}

} // namespace sg::render
