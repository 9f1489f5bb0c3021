// Layer kind `height`: a height map, displacement style (layer_height.glsl:
// Mikkelsen 2019, section 2.5, listings 8 and 9).
#include "layer_emit.h"

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = HeightParams;

// sgUnpackHeight(r0), layer_height.glsl: r0 = (scale, channel, 0, 0).
RecordLayout records() {
    using S = G::SgHeightParams;
    return Records<S, 1>("SgHeightParams", "sgUnpackHeight", G::sgUnpackHeight)
        .field("scale", &S::scale, "r0.x", [](const PackInput& in) { return in.params<P>().scale; })
        .field("channel", &S::channel, "r0.y",
               [](const PackInput& in) { return in.params<P>().channel; })
        .done();
}

// sgLayerHeight(frame, uv, params, map).
constexpr LayerEmitter kEmit = emitter([](auto& b) {
    b.addSurfgrad(SG_LAYER_CALL(b, sgLayerHeight, b.frame(), b.uv(), b.record(), b.tex(0)));
});

uint32_t mapChannels(const Layer& L, const char*& why) {
    why = "the height channel";
    return channelBit(L.params<HeightParams>().channel);
}

} // namespace

const LayerKind& heightLayerKind() {
    static const LayerKind kind{
        .name = "height",
        .sigCode = "hgt",
        .doc = "height map, displacement style (listings 8, 9)",
        .example = R"("map": {"procedural": "bumps", "output": "height", "size": 16})",
        .params =
            {
                param::map("map", Wrap::Repeat, "the height map"),
                param::uvSet(),
                param::channel("channel", &P::channel, "the channel holding the height"),
                param::slider(
                    param::number("scale", &P::scale, {}, "world units per unit of the channel"),
                    -0.1f, 0.1f, "%.4f"),
            },
        .makeParams = [] { return std::any(P{}); },
        .readsUv = true,
        .textureSlots = 1,
        .mapChannels = mapChannels,
        .glslFile = "sg/render/layer_height.glsl",
        .records = {records()},
        .emit = kEmit,
        .uberStandIns =
            [](const LayerKind& k, int uvCount) {
                return uvCount > 0 ? std::vector<Layer>{uberStandIn(k)} : std::vector<Layer>{};
            },
        .imageCases =
            {
                {"height",
                 R"({"type": "height", "scale": 0.01, "map": {"procedural": "bumps", "output": "height", "size": 256}})"},
            },
    };
    return kind;
}

} // namespace sg::render
