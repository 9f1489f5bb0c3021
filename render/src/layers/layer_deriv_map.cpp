// Layer kind `deriv_map`: a derivative map, TBN style (listing 5) or in
// texel space (listing 8) (layer_deriv_map.glsl: Mikkelsen 2019, section
// 2.1). Takes derivative-space modifiers (layer_deriv_map_mods.glsl).
#include "layer_emit.h"

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = DerivMapParams;

// sgUnpackDerivMap(r0, r1), layer_deriv_map.glsl:
//   r0 = (strength, signedTexels, range, texelSpace);
//   r1 = (flipV, heightChannel, heightScale, 0).
RecordLayout records() {
    using S = G::SgDerivMapParams;
    return Records<S, 2>("SgDerivMapParams", "sgUnpackDerivMap", G::sgUnpackDerivMap)
        .field("strength", &S::strength, "r0.x",
               [](const PackInput& in) { return in.layer.strength; })
        .field("signedTexels", &S::signedTexels, "r0.y",
               [](const PackInput& in) { return in.params<P>().signedTexels; })
        .field("range", &S::range, "r0.z", [](const PackInput& in) { return in.params<P>().range; })
        .field("texelSpace", &S::texelSpace, "r0.w",
               [](const PackInput& in) { return in.params<P>().texelSpace; })
        .field("flipV", &S::flipV, "r1.x", [](const PackInput& in) { return in.params<P>().flipV; })
        .field("heightChannel", &S::heightChannel, "r1.y",
               [](const PackInput& in) { return in.params<P>().heightChannel; })
        .field("heightScale", &S::heightScale, "r1.z",
               [](const PackInput& in) { return in.params<P>().heightScale; })
        .done();
}

// With modifiers: sample as height and derivative, edit, then listing 5 or 8.
const DerivModTarget kModifiers = {"sg/render/layer_deriv_map_mods.glsl"};

// sgLayerDerivMap(frame, uv, params, map); with modifiers, their chain.
constexpr LayerEmitter kEmit = emitter([](auto& b) {
    if (b.hasModifiers()) {
        return addDerivModSurfgrad(
            b, "SgDerivMapParams",
            [](auto& bb, const auto& p, const auto& st, const auto& dx, const auto& dy) {
                return SG_LAYER_CALL(bb, sgSampleDerivMapHD, bb.tex(0), st, dx, dy, p);
            },
            [](auto& bb, const auto& p, const auto& hd) {
                return SG_LAYER_CALL(bb, sgDerivMapSurfgradHD, bb.frame(), bb.uv(), p, hd,
                                     bb.tex(0));
            });
    }
    b.addSurfgrad(SG_LAYER_CALL(b, sgLayerDerivMap, b.frame(), b.uv(), b.record(), b.tex(0)));
});

std::vector<Layer> uberStandIns(const LayerKind& k, int uvCount) {
    if (uvCount == 0) return {};
    Layer withMods = uberStandIn(k);
    Modifier scale;
    scale.kind = findModifierKind("scale");
    withMods.modifiers.push_back(scale);
    return {uberStandIn(k), withMods};
}

uint32_t mapChannels(const Layer& L, const char*& why) {
    const int heightChannel = L.params<DerivMapParams>().heightChannel;
    why = heightChannel >= 0 ? "the derivative (r, g) and the height channel"
                             : "the derivative (r, g)";
    return kChannelR | kChannelG | channelBit(heightChannel);
}

} // namespace

const LayerKind& derivMapLayerKind() {
    static const LayerKind kind{
        .name = "deriv_map",
        .sigCode = "drv",
        .doc = "derivative map, TBN style or texel space (section 2.1)",
        .example = R"("map": {"procedural": "weave", "output": "derivative", "size": 16})",
        .params =
            {
                param::map("map", Wrap::Repeat, "the derivative map"),
                param::uvSet(),
                param::choice("encoding", &P::signedTexels, {{"float", true}, {"unorm", false}},
                              "signed float texels, or unorm: (2 rg - 1) * range"),
                param::number("range", &P::range, {0.0, detail::kHuge, true},
                              "unorm encoding: the derivative at texel value 1"),
                param::choice("space", &P::texelSpace, {{"tbn", false}, {"texel", true}},
                              "per unit of st (listing 5) or height units per texel (listing 8)"),
                param::green(&P::flipV),
                param::strength(),
                param::heightChannel(&P::heightChannel, &P::heightScale),
                param::modifiers(),
            },
        .makeParams = [] { return std::any(P{}); },
        .readsUv = true,
        .readsTangentBasis = [](const Layer& L) { return !L.params<P>().texelSpace; },
        .textureSlots = 1,
        .mapChannels = mapChannels,
        .glslFile = "sg/render/layer_deriv_map.glsl",
        .modifiers = &kModifiers,
        .records = {records()},
        .emit = kEmit,
        .uberStandIns = uberStandIns,
        .imageCases =
            {
                {"deriv_map_tbn",
                 R"({"type": "deriv_map", "map": {"procedural": "weave", "output": "derivative", "size": 128}})"},
                {"deriv_map_texel",
                 R"({"type": "deriv_map", "space": "texel", "strength": 0.02, "map": {"procedural": "weave", "output": "derivative", "size": 128}})"},
                {"deriv_map_modifiers",
                 R"({"type": "deriv_map", "map": {"procedural": "weave", "output": "derivative", "size": 128}, "modifiers": [{"type": "scale", "alpha": 0.5}]})"},
            },
    };
    return kind;
}

} // namespace sg::render
