// Layer kind `noise`: procedural volume noise with analytic gradients
// (layer_noise.glsl: Mikkelsen 2019, section 2.7, listing 12, and section
// 4: turbulence, frequency clamping, Gritz's x^k composite); with
// "antialias": "lean" the clamped octaves' slope variance widens the lobe
// (layer_noise_aa.glsl).
#include "layer_emit.h"

#include <cmath>
#include <cstdint>

namespace sg::render {

namespace {

namespace G = sg::glsl;
using P = NoiseParams;

// The noise's argument frequency * x0 + offset at the domain's reference
// point x0 (layer_noise.glsl: the camera for world space, 0 for object
// space), split in binary64 into its whole cell, wrapped to 32 bits, and
// the rest.
struct OriginSplit {
    glm::vec3 frac{0.0f};
    glm::vec3 cellLo{0.0f}, cellHi{0.0f}; // 16-bit halves of the cell's two's complement
};

OriginSplit originSplit(const PackInput& in) {
    const P& p = in.params<P>();
    OriginSplit o;
    if (p.space == Space::Object) {
        o.frac = p.offset;
        return o;
    }
    for (int i = 0; i < 3; ++i) {
        const double arg = double(p.frequency) * in.view.cameraPos[i] + double(p.offset[i]);
        if (!std::isfinite(arg)) continue;
        const double cell = std::floor(arg);
        o.frac[i] = float(arg - cell);                  // exact in binary64, then rounded once
        double wrapped = std::fmod(cell, 4294967296.0); // exact
        if (wrapped < 0.0) wrapped += 4294967296.0;
        const uint32_t bits = uint32_t(wrapped);
        o.cellLo[i] = float(bits & 0xffffu);
        o.cellHi[i] = float(bits >> 16);
    }
    return o;
}

// sgUnpackNoise(r0, r1, r2, r3, r4), layer_noise.glsl:
//   r0 = (amplitude, frequency, type SG_NOISE_*, octaves);
//   r1 = (lacunarity, gain, exponent k, antialias); r2 = (originFrac xyz, 0);
//   r3, r4 = (originCell's low, high 16 bits xyz, 0). View-dependent for
//   world space (the camera is x0).
RecordLayout records() {
    using S = G::SgNoiseParams;
    return Records<S, 5>("SgNoiseParams", "sgUnpackNoise", G::sgUnpackNoise)
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
               [](const PackInput& in) { return in.params<P>().antialias != NoiseAntialias::None; })
        .field("originFrac", &S::originFrac, "r2.xyz",
               [](const PackInput& in) { return originSplit(in).frac; })
        .field("originCellLo", &S::originCellLo, "r3.xyz",
               [](const PackInput& in) { return originSplit(in).cellLo; })
        .field("originCellHi", &S::originCellHi, "r4.xyz",
               [](const PackInput& in) { return originSplit(in).cellHi; })
        .done();
}

bool isLean(const Layer& L) {
    return L.params<P>().antialias == NoiseAntialias::Lean;
}

// sgLayerNoise(frame, volume domain, params); antialiased, its own
// function (layer_noise_aa.glsl) adding to slopeCov.
constexpr LayerEmitter kEmit = emitter([](auto& b) {
    const Space space = b.layer().template params<P>().space;
    if (isLean(b.layer())) {
        return b.addSurfgrad(
            SG_LAYER_CALL(b, sgLayerNoiseLean, b.frame(), b.vol(space), b.record(), b.slopeCov()));
    }
    b.addSurfgrad(SG_LAYER_CALL(b, sgLayerNoise, b.frame(), b.vol(space), b.record()));
});

// "antialias": true / "fade" (the default), false / "none", or "lean".
void parseAntialias(const detail::SceneNode& n, const char* key, Layer& L,
                    const detail::SceneReader&) {
    if (!n.has(key)) return;
    const nlohmann::json& v = n.value().at(key);
    NoiseAntialias& aa = L.params<P>().antialias;
    if (v.is_boolean()) {
        aa = v.get<bool>() ? NoiseAntialias::Fade : NoiseAntialias::None;
        return;
    }
    if (v.is_string()) {
        const std::string s = v.get<std::string>();
        if (s == "none")
            aa = NoiseAntialias::None;
        else if (s == "fade")
            aa = NoiseAntialias::Fade;
        else if (s == "lean")
            aa = NoiseAntialias::Lean;
        else
            n.failField(key, "expected true, false, \"none\", \"fade\" or \"lean\"");
        return;
    }
    n.failField(key, "expected true, false, \"none\", \"fade\" or \"lean\"");
}

std::vector<Layer> uberStandIns(const LayerKind& k, int) {
    std::vector<Layer> v = {uberStandIn(k), uberStandIn(k)};
    v[0].params<P>().space = Space::Object;
    v[1].params<P>().space = Space::World;
    return v;
}

// The material's "lean" or "toksvig" make the layer "lean" (the noise's
// covariance is analytic: there is no cheaper estimate); its "none" leaves
// the default fade (no lobe widening, as today).
ParamSpec antialiasParam() {
    ParamSpec s = param::custom("antialias", parseAntialias,
                                "true or \"fade\" (default): fade octaves finer than 2 pixels; "
                                "\"lean\": fade and widen the lobe by their slope variance; "
                                "false or \"none\": no fade");
    s.fromMaterial = [](const std::string& v, const Layer&) {
        return v == "none" ? std::string() : std::string("lean");
    };
    return s;
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
                antialiasParam(),
            },
        .makeParams = [] { return std::any(P{}); },
        .volume = [](const Layer& L) -> std::optional<Space> { return L.params<P>().space; },
        .glslFile = "sg/render/layer_noise.glsl",
        .glslFileOf =
            [](const Layer& L) {
                return isLean(L) ? "sg/render/layer_noise_aa.glsl" : "sg/render/layer_noise.glsl";
            },
        .antialias = isLean,
        .signature = [](const Layer& L) -> std::string { return isLean(L) ? "~lean" : ""; },
        .records = {records()},
        .emit = kEmit,
        .uberStandIns = uberStandIns,
        .imageCases =
            {
                {"noise_perlin",
                 R"({"type": "noise", "noise": "perlin", "amplitude": 0.05, "frequency": 4})"},
                {"noise_turbulence_dented",
                 R"({"type": "noise", "noise": "turbulence", "amplitude": 0.01, "frequency": 6, "exponent": 3})"},
                {"noise_fbm_world",
                 R"({"type": "noise", "noise": "fbm", "space": "world", "amplitude": 0.01, "frequency": 5})"},
            },
    };
    return kind;
}

} // namespace sg::render
