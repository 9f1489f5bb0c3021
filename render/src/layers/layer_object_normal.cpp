// Layer kind `object_normal`: an object- or world-space normal map
// (layer_object_normal.glsl: Mikkelsen 2019, section 2.4, listing 7).
#include "layer_emit.h"

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = ObjectNormalParams;

// sgUnpackObjectNormal(r0), layer_object_normal.glsl:
//   r0 = (strength, encoding SG_ENC_RGB or SG_ENC_FLOAT, objectSpace, 0).
RecordLayout records() {
    using S = G::SgObjectNormalParams;
    return Records<S, 1>("SgObjectNormalParams", "sgUnpackObjectNormal", G::sgUnpackObjectNormal)
        .field("strength", &S::strength, "r0.x",
               [](const PackInput& in) { return in.layer.strength; })
        .field("encoding", &S::encoding, "r0.y",
               [](const PackInput& in) { return int(in.params<P>().encoding); })
        .field("objectSpace", &S::objectSpace, "r0.z",
               [](const PackInput& in) { return in.params<P>().space == Space::Object; })
        .done();
}

// sgLayerObjectNormal(frame, uv, params, normal matrix, map).
constexpr LayerEmitter kEmit = emitter([](auto& b) {
    b.addSurfgrad(SG_LAYER_CALL(b, sgLayerObjectNormal, b.frame(), b.uv(), b.record(),
                                b.normalMat(), b.tex(0)));
});

uint32_t mapChannels(const Layer&, const char*& why) {
    why = "the normal (r, g, b)";
    return kChannelR | kChannelG | kChannelB;
}

} // namespace

const LayerKind& objectNormalLayerKind() {
    static const LayerKind kind{
        .name = "object_normal",
        .sigCode = "osn",
        .doc = "object/world-space normal map (listing 7)",
        .example = R"("map": {"procedural": "bumps", "size": 16})",
        .params =
            {
                param::map("map", Wrap::Repeat, "the normal map"),
                param::uvSet(),
                param::choice("space", &P::space,
                              {{"object", Space::Object}, {"world", Space::World}},
                              "the space the map's normals are in"),
                param::encoding(&P::encoding, false),
                param::strength(),
            },
        .makeParams = [] { return std::any(P{}); },
        .readsUv = true,
        .textureSlots = 1,
        .mapChannels = mapChannels,
        .glslFile = "sg/render/layer_object_normal.glsl",
        .records = {records()},
        .emit = kEmit,
        .uberStandIns =
            [](const LayerKind& k, int uvCount) {
                return uvCount > 0 ? std::vector<Layer>{uberStandIn(k)} : std::vector<Layer>{};
            },
        .imageCases =
            {
                {"object_normal",
                 R"({"type": "object_normal", "strength": 0.3, "map": {"procedural": "bumps", "size": 64}})"},
            },
    };
    return kind;
}

} // namespace sg::render
