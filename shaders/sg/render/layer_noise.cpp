// Layer kind `noise`: procedural volume noise with analytic gradients
// (layer_noise.glsl: Mikkelsen 2019, section 2.7, listing 12, and section
// 4: turbulence, frequency clamping, Gritz's x^k composite).
#include "layer_kind.h"

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = NoiseParams;

// sgUnpackNoise(r0, r1, r2), layer_noise.glsl:
//   r0 = (amplitude, frequency, type SG_NOISE_*, octaves);
//   r1 = (lacunarity, gain, exponent k, antialias); r2 = (offset xyz, 0).
RecordLayout records() {
    using S = G::SgNoiseParams;
    return Records<S, 3>("SgNoiseParams", "sgUnpackNoise", G::sgUnpackNoise)
        .field("amplitude", &S::amplitude, "r0.x",
               [](const PackInput& in) { return in.params<P>().amplitude; })
        .field("frequency", &S::frequency, "r0.y",
               [](const PackInput& in) { return in.params<P>().frequency; })
        .field("type", &S::type, "r0.z",
               [](const PackInput& in) { return int(in.params<P>().type); })
        .field("octaves", &S::octaves, "r0.w",
               [](const PackInput& in) { return in.params<P>().octaves; })
        .field("lacunarity", &S::lacunarity, "r1.x",
               [](const PackInput& in) { return in.params<P>().lacunarity; })
        .field("gain", &S::gain, "r1.y", [](const PackInput& in) { return in.params<P>().gain; })
        .field("exponent", &S::exponent, "r1.z",
               [](const PackInput& in) { return in.params<P>().exponent; })
        .field("antialias", &S::antialias, "r1.w",
               [](const PackInput& in) { return in.params<P>().antialias; })
        .field("offset", &S::offset, "r2.xyz",
               [](const PackInput& in) { return in.params<P>().offset; })
        .done();
}

std::string glsl(const GlslLayerContext& c) {
    return "surfGrad += sgLayerNoise(frame, " + c.vol(c.layer().params<P>().space) + ", " +
           c.unpack(c.layer().kind->records[0]) + ");\n";
}

void cpu(const CpuLayerContext& c, CpuShadeState& s) {
    const glm::vec4* r = c.rec();
    s.surfGrad += G::sgLayerNoise(s.frame, s.vol(c.layer().params<P>().space),
                                  G::sgUnpackNoise(r[0], r[1], r[2]));
}

std::vector<Layer> uberStandIns(const LayerKind& k, int) {
    std::vector<Layer> v = {uberStandIn(k), uberStandIn(k)};
    v[0].params<P>().space = Space::Object;
    v[1].params<P>().space = Space::World;
    return v;
}

} // namespace

const LayerKind& noiseLayerKind() {
    static const LayerKind kind{
        .name = "noise",
        .sigCode = "noi",
        .doc = "volume noise with analytic gradients (listing 12, section 4)",
        .params =
            {
                param::choice("noise", &P::type,
                              {{"perlin", NoiseType::Perlin},
                               {"turbulence", NoiseType::Turbulence},
                               {"fbm", NoiseType::Fbm}},
                              "the noise function"),
                param::slider(param::number("amplitude", &P::amplitude, {}, "height, domain units"),
                              -0.1f, 0.1f, "%.4f"),
                param::slider(param::number("frequency", &P::frequency, {0.0, detail::kHuge, true},
                                            "per domain unit"),
                              0.1f, 50.0f),
                param::integer("octaves", &P::octaves, 1, 12, "octaves summed"),
                param::number("lacunarity", &P::lacunarity, {1.0, 8.0},
                              "frequency ratio of successive octaves"),
                param::number("gain", &P::gain, {0.0, 1.0},
                              "amplitude ratio of successive octaves"),
                param::number("exponent", &P::exponent, {1.0, 16.0}, "Gritz's x^k composite"),
                param::vec3("offset", &P::offset, {}, "added to the scaled domain position"),
                param::choice("space", &P::space,
                              {{"object", Space::Object}, {"world", Space::World}},
                              "the noise's domain"),
                param::boolean("antialias", &P::antialias, "fade octaves finer than 2 pixels"),
            },
        .makeParams = [] { return std::any(P{}); },
        .volume = [](const Layer& L) -> std::optional<Space> { return L.params<P>().space; },
        .glslFile = "sg/render/layer_noise.glsl",
        .records = {records()},
        .glsl = glsl,
        .cpu = cpu,
        .uberStandIns = uberStandIns,
    };
    return kind;
}

} // namespace sg::render
