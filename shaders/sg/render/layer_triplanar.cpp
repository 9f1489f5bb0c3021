// Layer kind `triplanar`: normal maps projected on three planes as a volume
// bump map (layer_triplanar.glsl: Mikkelsen 2019, section 2.8, listings 12,
// 13, 14).
#include "layer_kind.h"

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = TriplanarParams;
using detail::SceneNode;

// sgUnpackTriplanar(r0, r1), layer_triplanar.glsl:
//   r0 = (strength, scale, sharpness k, rightHanded); r1 = (encoding, flipV, 0, 0).
RecordLayout records() {
    using S = G::SgTriplanarParams;
    return Records<S, 2>("SgTriplanarParams", "sgUnpackTriplanar", G::sgUnpackTriplanar)
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

std::string glsl(const GlslLayerContext& c) {
    return "surfGrad += sgLayerTriplanar(frame, " + c.vol(c.layer().params<P>().space) + ", " +
           c.unpack(c.layer().kind->records[0]) + ", " + c.tex(0) + ", " + c.tex(1) + ", " +
           c.tex(2) + ");\n";
}

void cpu(const CpuLayerContext& c, CpuShadeState& s) {
    const glm::vec4* r = c.rec();
    s.surfGrad +=
        G::sgLayerTriplanar(s.frame, s.vol(c.layer().params<P>().space),
                            G::sgUnpackTriplanar(r[0], r[1]), c.tex(0), c.tex(1), c.tex(2));
}

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
            },
        .makeParams = [] { return std::any(P{}); },
        .textureSlots = 3,
        .mapChannels = mapChannels,
        .volume = [](const Layer& L) -> std::optional<Space> { return L.params<P>().space; },
        .glslFile = "sg/render/layer_triplanar.glsl",
        .records = {records()},
        .glsl = glsl,
        .cpu = cpu,
        .uberStandIns = uberStandIns,
    };
    return kind;
}

} // namespace sg::render
