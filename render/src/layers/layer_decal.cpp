// Layer kind `decal`: a projector, a volume bump map with fall-off
// (layer_decal.glsl: Mikkelsen 2019, section 2.9, listing 15); antialiased
// with "antialias" (layer_decal_aa.glsl: the map's slope covariance mapped
// by the projector's Jacobian).
#include "layer_emit.h"

#include <algorithm>
#include <cmath>

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = DecalParams;
using detail::kHuge;
using detail::SceneNode;

// sgUnpackDecal(r0..r5), layer_decal.glsl (frame space: world, relative to
// the camera):
//   r0 = (origin - camera, strength)
//   r1 = (unit axis x, half size x)     r2 = (unit axis y, half size y)
//   r3 = (unit axis z, half depth)      r4 = (fade width, cos start, cos end, encoding)
//   r5 = (flipV, 0, 0, 0)
RecordLayout records() {
    using S = G::SgDecalParams;
    return Records<S, 6>("SgDecalParams", "sgUnpackDecal", G::sgUnpackDecal)
        .field("origin", &S::origin, "r0.xyz",
               [](const PackInput& in) {
                   return glm::vec3(in.params<P>().position - in.view.cameraPos); // binary64
               })
        .field("strength", &S::strength, "r0.w",
               [](const PackInput& in) { return in.layer.strength; })
        .field("axisX", &S::axisX, "r1.xyz",
               [](const PackInput& in) { return in.params<P>().axisX; })
        .field("axisY", &S::axisY, "r2.xyz",
               [](const PackInput& in) { return in.params<P>().axisY; })
        .field("axisZ", &S::axisZ, "r3.xyz",
               [](const PackInput& in) { return in.params<P>().axisZ; })
        .field("halfSize", &S::halfSize, "r1.w r2.w r3.w",
               [](const PackInput& in) { return in.params<P>().halfSize; })
        .field("fadeWidth", &S::fadeWidth, "r4.x",
               [](const PackInput& in) { return in.params<P>().fade; })
        .field("cosStart", &S::cosStart, "r4.y",
               [](const PackInput& in) { return in.params<P>().cosStart; })
        .field("cosEnd", &S::cosEnd, "r4.z",
               [](const PackInput& in) { return in.params<P>().cosEnd; })
        .field("encoding", &S::encoding, "r4.w",
               [](const PackInput& in) { return int(in.params<P>().encoding); })
        .field("flipV", &S::flipV, "r5.x", [](const PackInput& in) { return in.params<P>().flipV; })
        .done();
}

// "up" (read after "direction"): the projector's frame, z against the
// projection direction, x = up x z.
void parseUp(const SceneNode& n, const char* key, Layer& L, const detail::SceneReader&) {
    P& p = L.params<P>();
    p.up = n.vec3(key, p.up, -kHuge, kHuge);
    if (glm::length(p.direction) < 1e-6f) n.failField("direction", "expected a non-zero vector");
    glm::vec3 z = -glm::normalize(p.direction);
    glm::vec3 x = glm::cross(p.up, z);
    if (glm::length(x) < 1e-6f * std::max(glm::length(p.up), 1e-30f) || glm::length(p.up) < 1e-6f)
        n.failField(key, "expected a non-zero vector not parallel to \"direction\"");
    x = glm::normalize(x);
    p.axisX = x;
    p.axisY = glm::cross(z, x);
    p.axisZ = z;
}

void parseSize(const SceneNode& n, const char* key, Layer& L, const detail::SceneReader&) {
    glm::vec3 size = n.vec3(key, glm::vec3(1.0f), 0.0, kHuge);
    if (!(size.x > 0 && size.y > 0 && size.z > 0))
        n.failField(key, "expected an array of 3 numbers > 0 (width, height, depth)");
    L.params<P>().halfSize = 0.5f * size;
}

void parseAngleFade(const SceneNode& n, const char* key, Layer& L, const detail::SceneReader&) {
    std::vector<float> ang = n.floats(key, 0.0, 180.0, 2);
    if (!n.has(key)) return;
    if (ang.size() != 2 || !(ang[0] <= ang[1]))
        n.failField(key, "expected [start, end] in degrees with start <= end");
    L.params<P>().cosStart = std::cos(glm::radians(ang[0]));
    L.params<P>().cosEnd = std::cos(glm::radians(ang[1]));
}

int antialiasOf(const Layer& L) {
    return L.params<P>().antialias;
}

// sgLayerDecal(frame, surface position, params, map) at the frame's
// surface: the virtual one in a post-resolve group after parallax or POM
// (section 3, Fig. 3(d)), as the footprint (frame.dPdx). Antialiased:
// sgLayerDecalAa (layer_decal_aa.glsl) with the mode a constant, the moment
// textures (Toksvig's one twice) and slopeCov.
constexpr LayerEmitter kEmit = emitter([](auto& b) {
    const int aa = antialiasOf(b.layer());
    if (aa == 0) {
        return b.addSurfgrad(
            SG_LAYER_CALL(b, sgLayerDecal, b.frame(), b.surfPos(), b.record(), b.tex(0)));
    }
    b.addSurfgrad(SG_LAYER_CALL(b, sgLayerDecalAa, b.frame(), b.surfPos(), b.record(),
                                b.constant(aa, aaName(aa)), b.tex(0),
                                b.tex(aa == SG_AA_LEAN ? 1 : 0), b.slopeCov()));
});

uint32_t mapChannels(const Layer& L, const char*& why) {
    why = "the normal encoding";
    return normalXyChannels(L.params<DecalParams>().encoding);
}

} // namespace

const LayerKind& decalLayerKind() {
    static const LayerKind kind{
        .name = "decal",
        .sigCode = "dec",
        .doc = "decal projector (listing 15, section 2.9)",
        .example = R"("map": {"procedural": "scratches", "size": 16})",
        .params =
            {
                param::map("map", Wrap::Clamp, "the decal's normal map (clamped)"),
                param::vec3("position", &P::position, {}, "centre (world)"),
                param::vec3("direction", &P::direction, {}, "projection direction"),
                param::custom("up", parseUp, "up direction of the projected image"),
                param::custom("size", parseSize, "[width, height, depth], world units"),
                param::number("fade", &P::fade, {0.0, 1.0},
                              "depth fade, fraction of the half depth"),
                param::custom("angle_fade_deg", parseAngleFade,
                              "[start, end]: fade with the angle to the surface"),
                param::encoding(&P::encoding, true),
                param::green(&P::flipV),
                param::strength(),
                param::antialias(&P::antialias, &P::encoding, 1),
            },
        .makeParams = [] { return std::any(P{}); },
        .textureSlots = 1,
        .textureSlotsOf = [](const Layer& L) { return antialiasOf(L) == SG_AA_LEAN ? 2 : 1; },
        .mapChannels = mapChannels,
        .glslFile = "sg/render/layer_decal.glsl",
        .glslFileOf =
            [](const Layer& L) {
                return antialiasOf(L) != 0 ? "sg/render/layer_decal_aa.glsl"
                                           : "sg/render/layer_decal.glsl";
            },
        .antialias = [](const Layer& L) { return antialiasOf(L) != 0; },
        .signature = [](const Layer& L) -> std::string {
            const int aa = antialiasOf(L);
            return aa == SG_AA_LEAN ? "~lean" : aa == SG_AA_TOKSVIG ? "~toksvig" : "";
        },
        .records = {records()},
        .emit = kEmit,
        .uberStandIns = [](const LayerKind& k, int) { return std::vector<Layer>{uberStandIn(k)}; },
        .imageCases =
            {
                {"decal",
                 R"({"type": "decal", "position": [0, 0, 0.9], "direction": [0, 0, -1], "size": [1.2, 1.2, 1], "strength": 2, "map": {"procedural": "bricks", "size": 256}})"},
            },
    };
    return kind;
}

} // namespace sg::render
