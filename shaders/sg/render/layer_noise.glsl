// Bump layer: procedural volume noise (Perlin, turbulence or fBm) with
// analytic gradients, optionally composited with Gritz's x^k.
// Mikkelsen 2019, section 2.7 (volume bump map, listing 12) and section 4
// (turbulence with frequency clamping and the x^k composite, "dented").
// Height H(p) = amplitude * g(noise(frequency * p + offset)) in domain
// units, so the bumps are displacement style: amplitude and frequency are
// physical (domain length units).
#ifndef SG_RENDER_LAYER_NOISE_GLSL
#define SG_RENDER_LAYER_NOISE_GLSL

#include "sg/render/common.glsl"
#include "sg/render/noise.glsl"

// Records r0 = (amplitude, frequency, type SG_NOISE_*, octaves);
// r1 = (lacunarity, gain, exponent k (1: no composite), antialias);
// r2 = (offset xyz, 0).
struct SgNoiseParams {
    float amplitude;
    float frequency;
    int type;
    int octaves;
    float lacunarity;
    float gain;
    float exponent;
    bool antialias;
    vec3 offset;
};

SG_FN SgNoiseParams sgUnpackNoise(vec4 r0, vec4 r1, vec4 r2) {
    SgNoiseParams p;
    p.amplitude = r0.x;
    p.frequency = r0.y;
    p.type = sgRecInt(r0.z);
    p.octaves = sgRecInt(r0.w);
    p.lacunarity = r1.x;
    p.gain = r1.y;
    p.exponent = r1.z;
    p.antialias = sgRecBool(r1.w);
    p.offset = sgRecVec3(r2);
    return p;
}

// Height and domain-space gradient of the layer: vec4(H, dH/dp).
SG_FN vec4 sgNoiseLayerHeight(SgVolumeSpace vs, SgNoiseParams p) {
    float footprint = p.antialias ? sgVolumeFootprint(vs) * p.frequency : 0.0f;
    vec4 n = sgNoiseOctaves(p.type, p.frequency * vs.pos + p.offset, p.octaves, p.lacunarity,
                            p.gain, footprint);
    if (p.exponent != 1.0f) n = sgNoisePowerComposite(n, p.exponent);
    // Chain rule for the frequency scale of the argument.
    return vec4(p.amplitude * n.x, (p.amplitude * p.frequency) * vec3(n.y, n.z, n.w));
}

SG_FN vec3 sgLayerNoise(SgFrame f, SgVolumeSpace vs, SgNoiseParams p) {
    vec4 h = sgNoiseLayerHeight(vs, p);
    return sgSurfgradFromVolumeGradient(f, vs.gradToFrame * vec3(h.y, h.z, h.w));
}

#endif
