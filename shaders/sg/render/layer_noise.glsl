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

// The noise's argument (lattice units) at the absolute domain position x is
// frequency * x + offset. The domain position arrives as vs.pos = x - x0,
// relative to a reference point x0 (SgVolumeSpace: the camera for world
// space, the object origin for object space), and the argument is split as
//   frequency * x + offset = originCell + (originFrac + frequency * vs.pos),
// originCell = floor(frequency * x0 + offset), an integer (32 bits, wrapped
// modulo 2^32), and originFrac the rest, both computed in binary64 on the
// CPU (layer_noise.cpp): originFrac is in [0, 1] and vs.pos small (the
// camera is near what it sees), so nothing is large in binary32, and
// sgNoiseOctavesAt keeps the cell exact in every octave (noise.glsl): for
// any lacunarity while the argument stays within 2^31 cells of 0; beyond,
// the cell wraps modulo 2^32, exact for integer lacunarities only (octaves
// with a non-integer lacunarity^k then see a seam where it wraps).
// Object space keeps x0 = 0: originCell 0 and originFrac = offset (the
// argument as it always was).
//
// Records r0 = (amplitude, frequency, type SG_NOISE_*, octaves);
// r1 = (lacunarity, gain, exponent k (1: no composite), antialias);
// r2 = (originFrac xyz, 0); r3 = (originCell's low 16 bits xyz, 0);
// r4 = (originCell's high 16 bits xyz, 0): each half an integer in
// [0, 65535], exact in binary32 (a 32-bit integer is not), of the cell's
// two's complement bits.
struct SgNoiseParams {
    float amplitude;
    float frequency;
    int type;
    int octaves;
    float lacunarity;
    float gain;
    float exponent;
    bool antialias;
    vec3 originFrac;
    vec3 originCellLo;
    vec3 originCellHi;
};

SG_FN SgNoiseParams sgUnpackNoise(vec4 r0, vec4 r1, vec4 r2, vec4 r3, vec4 r4) {
    SgNoiseParams p;
    p.amplitude = r0.x;
    p.frequency = r0.y;
    p.type = sgRecInt(r0.z);
    p.octaves = sgRecInt(r0.w);
    p.lacunarity = r1.x;
    p.gain = r1.y;
    p.exponent = r1.z;
    p.antialias = sgRecBool(r1.w);
    p.originFrac = sgRecVec3(r2);
    p.originCellLo = sgRecVec3(r3);
    p.originCellHi = sgRecVec3(r4);
    return p;
}

// One 16-bit half of the packed cell (clamped: records hold [0, 65535]).
SG_FN uvec3 sgNoiseCellHalf(vec3 h) {
    return uvec3(clamp(floor(h + sgVec3(0.5f)), sgVec3(0.0f), sgVec3(65535.0f)));
}

// originCell from its halves: hi 2^16 + lo, as the 32-bit two's complement
// integer.
SG_FN ivec3 sgNoiseOriginCell(SgNoiseParams p) {
    return ivec3(sgNoiseCellHalf(p.originCellHi) * 65536u + sgNoiseCellHalf(p.originCellLo));
}

// The layer's octaves (sgNoiseOctavesAt) at the pixel's argument, footprint
// in lattice units.
SG_FN vec4 sgNoiseLayerOctaves(SgVolumeSpace vs, SgNoiseParams p, float footprint) {
    return sgNoiseOctavesAt(p.type, sgNoiseOriginCell(p), p.frequency * vs.pos + p.originFrac,
                            p.octaves, p.lacunarity, p.gain, footprint);
}

// Height and domain-space gradient of the layer: vec4(H, dH/dp).
SG_FN vec4 sgNoiseLayerHeight(SgVolumeSpace vs, SgNoiseParams p) {
    float footprint = p.antialias ? sgVolumeFootprint(vs) * p.frequency : 0.0f;
    vec4 n = sgNoiseLayerOctaves(vs, p, footprint);
    if (p.exponent != 1.0f) n = sgNoisePowerComposite(n, p.exponent);
    // Chain rule for the frequency scale of the argument.
    return vec4(p.amplitude * n.x, (p.amplitude * p.frequency) * vec3(n.y, n.z, n.w));
}

SG_FN vec3 sgLayerNoise(SgFrame f, SgVolumeSpace vs, SgNoiseParams p) {
    vec4 h = sgNoiseLayerHeight(vs, p);
    return sgSurfgradFromVolumeGradient(f, vs.gradToFrame * vec3(h.y, h.z, h.w));
}

#endif
