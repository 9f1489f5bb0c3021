// Layer kind `triplanar`: normal maps projected on three planes as a volume
// bump map (layer_triplanar.glsl: Mikkelsen 2019, section 2.8, listings 12,
// 13, 14); antialiased with "antialias" (layer_triplanar_aa.glsl: each
// plane's slope covariance mapped by its Jacobian, weights squared).
#include "layer_emit.h"

#include <algorithm>

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = TriplanarParams;
using detail::SceneNode;

// Whether every plane's map repeats ("wrap": "repeat", the default; a
// map's "wrap": "clamp" is kept).
bool mapsRepeat(const Layer& L) {
    return std::all_of(L.maps.begin(), L.maps.end(),
                       [](const TextureSource& m) { return m.wrap == Wrap::Repeat; });
}

// SgTriplanarParams::texShift: the texture position of the domain's
// reference point (the camera for world space) in binary64, reduced to
// [0, 1) by whole repeats when the maps repeat; with a clamped map the
// absolute scale * camera (no repeat to reduce by: the layer reads the
// absolute position, as precise as binary32 is there); 0 in object space.
glm::vec3 texShift(const PackInput& in) {
    const P& p = in.params<P>();
    if (p.space == Space::Object) return glm::vec3(0.0f);
    const glm::dvec3 s = double(p.scale) * in.view.cameraPos;
    if (!mapsRepeat(in.layer)) return glm::vec3(s);
    return glm::vec3(s - glm::floor(s));
}

// sgUnpackTriplanar(r0, r1, r2), layer_triplanar.glsl:
//   r0 = (strength, scale, sharpness k, rightHanded); r1 = (encoding, flipV, 0, 0);
//   r2 = (texShift xyz, 0), view-dependent for world space.
RecordLayout records() {
    using S = G::SgTriplanarParams;
    return Records<S, 3>("SgTriplanarParams", "sgUnpackTriplanar", G::sgUnpackTriplanar)
        .field("strength", &S::strength, "r0.x",
               [](const PackInput& in) { return in.layer.strength; })
        .field("scale", &S::scale, "r0.y", [](const PackInput& in) { return in.params<P>().scale; })
        .field("sharpness", &S::sharpness, "r0.z",
               [](const PackInput& in) { return in.params<P>().sharpness; })
        .field("rightHanded", &S::rightHanded, "r0.w",
               [](const PackInput& in) { return in.params<P>().rightHanded; })
        .field("encoding", &S::encoding, "r1.x",
               [](const PackInput& in) { return int(in.params<P>().encoding); })
        .field("flipV", &S::flipV, "r1.y", [](const PackInput& in) { return in.params<P>().flipV; })
        .field("texShift", &S::texShift, "r2.xyz", texShift)
        .done();
}

// "map" (one map for all planes) or "maps" ([x, y, z]).
void parseMaps(const SceneNode& n, const char*, Layer& L, const detail::SceneReader& reader) {
    if (n.has("map") == n.has("maps")) {
        n.fail("expected exactly one of \"map\" (one map for all planes) or \"maps\" "
               "([x, y, z] plane maps)");
    }
    if (n.has("map")) {
        L.maps.push_back(reader.texture(n.child("map"), Wrap::Repeat));
    } else {
        SceneNode ms = n.child("maps");
        if (!ms.value().is_array() || ms.value().size() != 3) {
            ms.fail("expected an array of 3 maps (x, y and z planes)");
        }
        for (size_t i = 0; i < 3; ++i) L.maps.push_back(reader.texture(ms.item(i), Wrap::Repeat));
    }
}

int antialiasOf(const Layer& L) {
    return L.params<P>().antialias;
}

// The texture slot of plane i's moment texture A (second: B): LEAN keeps
// two per plane, Toksvig one (its B is A again).
int aaSlot(int aa, int plane, bool second) {
    return aa == SG_AA_LEAN ? 2 * plane + (second ? 1 : 0) : plane;
}

// sgLayerTriplanar(frame, volume domain, params, three maps); antialiased:
// sgLayerTriplanarAa (layer_triplanar_aa.glsl) with the mode a constant,
// each plane's moment textures (aaSlot) and slopeCov.
constexpr LayerEmitter kEmit = emitter([](auto& b) {
    const Space space = b.layer().template params<P>().space;
    const int aa = antialiasOf(b.layer());
    if (aa == 0) {
        return b.addSurfgrad(SG_LAYER_CALL(b, sgLayerTriplanar, b.frame(), b.vol(space), b.record(),
                                           b.tex(0), b.tex(1), b.tex(2)));
    }
    auto t = [&b, aa](int plane, bool second) { return b.tex(aaSlot(aa, plane, second)); };
    b.addSurfgrad(SG_LAYER_CALL(b, sgLayerTriplanarAa, b.frame(), b.vol(space), b.record(),
                                b.constant(aa, aaName(aa)), t(0, false), t(0, true), t(1, false),
                                t(1, true), t(2, false), t(2, true), b.slopeCov()));
});

std::vector<Layer> uberStandIns(const LayerKind& k, int) {
    std::vector<Layer> v = {uberStandIn(k), uberStandIn(k)};
    v[0].params<P>().space = Space::World;
    v[1].params<P>().space = Space::Object;
    return v;
}

uint32_t mapChannels(const Layer& L, const char*& why) {
    why = "the normal encoding";
    return normalXyChannels(L.params<TriplanarParams>().encoding);
}

} // namespace

const LayerKind& triplanarLayerKind() {
    static const LayerKind kind{
        .name = "triplanar",
        .sigCode = "tri",
        .doc = "triplanar projection (listings 13, 14, section 2.8)",
        .example = R"("map": {"procedural": "tiles", "size": 16})",
        .params =
            {
                param::custom("map", parseMaps, "one map for all three planes"),
                param::custom("maps", nullptr, "[x, y, z]: one map per plane"),
                param::number("scale", &P::scale, {0.0, detail::kHuge, true},
                              "texture repeats per domain unit"),
                param::number("sharpness", &P::sharpness, {0.0, 64.0, true},
                              "listing 14's k: blend weight sharpness"),
                param::choice("handedness", &P::rightHanded, {{"right", true}, {"left", false}},
                              "the domain's handedness (section 2.8)"),
                param::choice("space", &P::space,
                              {{"object", Space::Object}, {"world", Space::World}},
                              "the projection's domain"),
                param::encoding(&P::encoding, true),
                param::green(&P::flipV),
                param::strength(),
                param::antialias(&P::antialias, &P::encoding, 3),
            },
        .makeParams = [] { return std::any(P{}); },
        .textureSlots = 3,
        .textureSlotsOf = [](const Layer& L) { return antialiasOf(L) == SG_AA_LEAN ? 6 : 3; },
        .mapChannels = mapChannels,
        .volume = [](const Layer& L) -> std::optional<Space> { return L.params<P>().space; },
        .glslFile = "sg/render/layer_triplanar.glsl",
        .glslFileOf =
            [](const Layer& L) {
                return antialiasOf(L) != 0 ? "sg/render/layer_triplanar_aa.glsl"
                                           : "sg/render/layer_triplanar.glsl";
            },
        .antialias = [](const Layer& L) { return antialiasOf(L) != 0; },
        .signature = [](const Layer& L) -> std::string {
            const int aa = antialiasOf(L);
            return aa == SG_AA_LEAN ? "~lean" : aa == SG_AA_TOKSVIG ? "~toksvig" : "";
        },
        .records = {records()},
        .emit = kEmit,
        .uberStandIns = uberStandIns,
        .imageCases =
            {
                {"triplanar_world",
                 R"({"type": "triplanar", "space": "world", "scale": 2, "map": {"procedural": "tiles", "size": 128}})"},
                {"triplanar_object_three_maps_left",
                 R"({"type": "triplanar", "space": "object", "handedness": "left", "maps": [{"procedural": "tiles", "size": 128}, {"procedural": "bricks", "size": 256}, {"procedural": "weave", "size": 128}]})"},
            },
    };
    return kind;
}

} // namespace sg::render
