// Layer kind `uv_normal`: a tangent-space normal map on a UV set
// (layer_uv_normal.glsl: Mikkelsen 2019, listings 4, 5, 6; the vertex or
// limit basis of section 2.2 when the UV set has vertex tangents). Takes
// derivative-space modifiers (layer_uv_normal_mods.glsl).
#include "layer_kind.h"

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = UvNormalParams;

// sgUnpackUvNormal(r0, r1), layer_uv_normal.glsl:
//   r0 = (strength, encoding SG_ENC_*, flipV, heightChannel); r1 = (heightScale, 0, 0, 0).
RecordLayout records() {
    using S = G::SgUvNormalParams;
    return Records<S, 2>("SgUvNormalParams", "sgUnpackUvNormal", G::sgUnpackUvNormal)
        .field("strength", &S::strength, "r0.x",
               [](const PackInput& in) { return in.layer.strength; })
        .field("encoding", &S::encoding, "r0.y",
               [](const PackInput& in) { return int(in.params<P>().encoding); })
        .field("flipV", &S::flipV, "r0.z", [](const PackInput& in) { return in.params<P>().flipV; })
        .field("heightChannel", &S::heightChannel, "r0.w",
               [](const PackInput& in) { return in.params<P>().heightChannel; })
        .field("heightScale", &S::heightScale, "r1.x",
               [](const PackInput& in) { return in.params<P>().heightScale; })
        .done();
}

// With modifiers: sample as height and derivative, edit, then listing 5.
const DerivModTarget kModifiers = {
    "sg/render/layer_uv_normal_mods.glsl",
    [](const GlslLayerContext& c) {
        return "SgUvNormalParams p = " + c.unpack(c.layer().kind->records[0]) + ";";
    },
    "sgSampleUvNormalHD",
    [](const GlslLayerContext& c) { return "sgUvNormalSurfgrad(" + c.uv() + ", p, hd)"; },
    [](const CpuLayerContext& c, glm::vec2 st, glm::vec2 dx, glm::vec2 dy) {
        const glm::vec4* r = c.rec();
        return G::sgSampleUvNormalHD(c.tex(0), st, dx, dy, G::sgUnpackUvNormal(r[0], r[1]));
    },
    [](const CpuLayerContext& c, const CpuShadeState& s, const G::SgHeightDeriv& hd) {
        const glm::vec4* r = c.rec();
        return G::sgUvNormalSurfgrad(c.uv(s), G::sgUnpackUvNormal(r[0], r[1]), hd);
    },
};

std::string glsl(const GlslLayerContext& c) {
    if (c.pl.hasModifiers) return derivModBlock(c, kModifiers);
    return "surfGrad += sgLayerUvNormal(" + c.uv() + ", " + c.unpack(c.layer().kind->records[0]) +
           ", " + c.tex(0) + ");\n";
}

void cpu(const CpuLayerContext& c, CpuShadeState& s) {
    if (c.pl.hasModifiers) {
        s.surfGrad += derivModCpu(c, s, kModifiers);
        return;
    }
    const glm::vec4* r = c.rec();
    s.surfGrad += G::sgLayerUvNormal(c.uv(s), G::sgUnpackUvNormal(r[0], r[1]), c.tex(0));
}

std::vector<Layer> uberStandIns(const LayerKind& k, int uvCount) {
    if (uvCount == 0) return {};
    Layer withMods = uberStandIn(k);
    Modifier scale;
    scale.kind = findModifierKind("scale");
    withMods.modifiers.push_back(scale);
    return {uberStandIn(k), withMods};
}

uint32_t mapChannels(const Layer& L, const char*& why) {
    const P& p = L.params<P>();
    why =
        p.heightChannel >= 0 ? "the normal encoding and the height channel" : "the normal encoding";
    return normalXyChannels(p.encoding) | channelBit(p.heightChannel);
}

} // namespace

const LayerKind& uvNormalLayerKind() {
    static const LayerKind kind{
        .name = "uv_normal",
        .sigCode = "uvn",
        .doc = "tangent-space normal map on a UV set (listings 4, 5, 6)",
        .example = R"("map": {"procedural": "bumps", "size": 16})",
        .params =
            {
                param::map("map", Wrap::Repeat, "the normal map"),
                param::uvSet(),
                param::encoding(&P::encoding, true),
                param::green(&P::flipV),
                param::strength(),
                param::heightChannel(&P::heightChannel, &P::heightScale),
                param::modifiers(),
            },
        .makeParams = [] { return std::any(P{}); },
        .readsUv = true,
        .readsTangentBasis = [](const Layer&) { return true; },
        .textureSlots = 1,
        .mapChannels = mapChannels,
        .glslFile = "sg/render/layer_uv_normal.glsl",
        .modifiers = &kModifiers,
        .records = {records()},
        .glsl = glsl,
        .cpu = cpu,
        .uberStandIns = uberStandIns,
    };
    return kind;
}

} // namespace sg::render
