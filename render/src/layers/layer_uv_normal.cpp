// Layer kind `uv_normal`: a tangent-space normal map on a UV set
// (layer_uv_normal.glsl: Mikkelsen 2019, listings 4, 5, 6; the vertex or
// limit basis of section 2.2 when the UV set has vertex tangents). Takes
// derivative-space modifiers (layer_uv_normal_mods.glsl).
#include <cstring>

#include "layer_emit.h"

namespace sg::render {

// NormalEncoding (surfgrad/render/scene.h) is the record value the shader
// compares with SG_ENC_* (sg/render/common.glsl): one list, checked here.
static_assert(int(NormalEncoding::Rgb) == SG_ENC_RGB && int(NormalEncoding::Rg) == SG_ENC_RG &&
                  int(NormalEncoding::Ag) == SG_ENC_AG &&
                  int(NormalEncoding::Float) == SG_ENC_FLOAT,
              "NormalEncoding and SG_ENC_* agree");

namespace detail {

TextureImage normalMomentTexture(const TextureImage& map, TexMoments moments,
                                 NormalEncoding encoding) {
    SG_EXPECTS(moments != TexMoments::None && !map.levels.empty(), "a moment texture of a map");
    const TextureLevel& L0 = map.levels[0];
    const int mode = moments == TexMoments::Toksvig ? SG_AA_TOKSVIG : SG_AA_LEAN;
    std::vector<glm::vec4> texels(size_t(L0.width) * size_t(L0.height));
    std::vector<glm::vec4> row(size_t(L0.width));
    for (int y = 0; y < L0.height; ++y) {
        L0.expandRows(y, 1, row.data());
        for (int x = 0; x < L0.width; ++x) {
            glm::vec4 a, b;
            sg::glsl::sgUvNormalMomentTexel(row[size_t(x)], int(encoding), mode, a, b);
            texels[size_t(y) * size_t(L0.width) + size_t(x)] = moments == TexMoments::LeanB ? b : a;
        }
    }
    TextureImage img = makeTexture(L0.width, L0.height, std::move(texels), map.wrap);
    img.channelMask = map.channelMask;
    img.sourceChannels = map.sourceChannels;
    return img;
}

} // namespace detail

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
const DerivModTarget kModifiers = {"sg/render/layer_uv_normal_mods.glsl"};

int antialiasOf(const Layer& L) {
    return L.params<P>().antialias;
}

// sgLayerUvNormal(uv, params, map); antialiased (layer_uv_normal_aa.glsl),
// the mode's own function (a program carries only the one it uses) with
// the moment textures in slots 0 (and 1 for LEAN) and slopeCov; with
// modifiers, their chain.
constexpr LayerEmitter kEmit = emitter([](auto& b) {
    if (b.hasModifiers()) {
        return addDerivModSurfgrad(
            b, "SgUvNormalParams",
            [](auto& bb, const auto& p, const auto& st, const auto& dx, const auto& dy) {
                return SG_LAYER_CALL(bb, sgSampleUvNormalHD, bb.tex(0), st, dx, dy, p);
            },
            [](auto& bb, const auto& p, const auto& hd) {
                return SG_LAYER_CALL(bb, sgUvNormalSurfgrad, bb.uv(), p, hd);
            });
    }
    const int aa = antialiasOf(b.layer());
    if (aa == SG_AA_LEAN) {
        return b.addSurfgrad(SG_LAYER_CALL(b, sgLayerUvNormalLean, b.uv(), b.record(), b.tex(0),
                                           b.tex(1), b.slopeCov()));
    }
    if (aa == SG_AA_TOKSVIG) {
        return b.addSurfgrad(
            SG_LAYER_CALL(b, sgLayerUvNormalToksvig, b.uv(), b.record(), b.tex(0), b.slopeCov()));
    }
    b.addSurfgrad(SG_LAYER_CALL(b, sgLayerUvNormal, b.uv(), b.record(), b.tex(0)));
});

// "antialias": reads the choice and puts the map's moment textures in
// place of the map (read after "map", "encoding" and "modifiers").
ParamSpec antialiasParam() {
    ParamSpec s = param::custom(
        "antialias",
        [](const detail::SceneNode& n, const char* key, Layer& L, const detail::SceneReader&) {
            if (!n.has(key)) return;
            P& p = L.params<P>();
            p.antialias = n.choice(key, 0, {"none", "lean", "toksvig"});
            if (p.antialias == 0) return;
            if (!L.modifiers.empty()) {
                n.failField(key, "antialiasing does not combine with modifiers: expected "
                                 "\"none\" or no modifiers");
            }
            param::useMomentMaps(L, p.antialias, p.encoding, 1);
        },
        "bump antialiasing: \"none\" (default), \"lean\" or \"toksvig\" (slope covariance "
        "of the footprint widens the lobe; default: the material's)");
    // The material's value, except on layers with modifiers (which do not
    // antialias).
    s.fromMaterial = [](const std::string& v, const Layer& L) {
        return L.modifiers.empty() ? v : std::string();
    };
    return s;
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
                antialiasParam(),
            },
        .makeParams = [] { return std::any(P{}); },
        .readsUv = true,
        .readsTangentBasis = [](const Layer&) { return true; },
        .textureSlots = 1,
        .textureSlotsOf = [](const Layer& L) { return antialiasOf(L) == SG_AA_LEAN ? 2 : 1; },
        .mapChannels = mapChannels,
        .glslFile = "sg/render/layer_uv_normal.glsl",
        .glslFileOf =
            [](const Layer& L) {
                return antialiasOf(L) != 0 ? "sg/render/layer_uv_normal_aa.glsl"
                                           : "sg/render/layer_uv_normal.glsl";
            },
        .antialias = [](const Layer& L) { return antialiasOf(L) != 0; },
        .signature = [](const Layer& L) -> std::string {
            const int aa = antialiasOf(L);
            return aa == SG_AA_LEAN ? "~lean" : aa == SG_AA_TOKSVIG ? "~toksvig" : "";
        },
        .modifiers = &kModifiers,
        .records = {records()},
        .emit = kEmit,
        .uberStandIns = uberStandIns,
        .imageCases =
            {
                {"uv_normal",
                 R"({"type": "uv_normal", "map": {"procedural": "bricks", "size": 256}})"},
                {"uv_normal_second_set_dx_green",
                 R"({"type": "uv_normal", "uv_set": 1, "green": "dx", "strength": 0.7, "map": {"procedural": "tiles", "size": 128}})"},
                {"modifiers_scale_curve",
                 R"({"type": "uv_normal", "map": {"procedural": "bumps", "size": 128}, "height": {"channel": "a", "scale": 1}, "modifiers": [{"type": "curve", "boost": 4000, "center": 0.02}, {"type": "scale", "alpha": -1.5}]})"},
                {"modifiers_deform_modulate",
                 R"({"type": "uv_normal", "map": {"procedural": "bricks", "size": 256}, "height": {"channel": "a", "scale": 1}, "modifiers": [{"type": "deform", "amplitude": 0.03, "frequency": 25}, {"type": "modulate", "mask": {"procedural": "tiles", "output": "height", "size": 64}, "gain": 1}]})"},
            },
    };
    return kind;
}

} // namespace sg::render
