// Procedural volume noise with analytic gradients, for volume bump maps:
// Mikkelsen 2019, section 2.7 (listing 12 turns the gradient into a surface
// gradient) and section 4 (turbulence with frequency clamping, composited
// with Gritz's g(x) = x^k, "dented.sl" 1994, differentiated by the chain rule
// (g o f)' = g'(f) f').
//
//  - Perlin, "Improving Noise" (2002): gradient noise on the integer lattice
//    with the quintic fade 6t^5 - 15t^4 + 10t^3 and the twelve cube-edge
//    gradients (padded to sixteen). The permutation table is replaced by an
//    integer hash so the code needs no arrays (shared GLSL/C++ subset) and
//    uint arithmetic wraps identically on both sides.
//  - Perlin, "An Image Synthesizer" (1985): turbulence = sum |noise(2^i p)| / 2^i.
//  - fBm: sum gain^i noise(lacunarity^i p).
// Every function returns vec4(value, d/dx, d/dy, d/dz): the gradient is exact
// (not finite differences), so bumps follow the true derivative everywhere.
//
// Filtering: procedural noise has no mip maps, so octaves whose frequency
// exceeds a quarter cycle per pixel fade out (weight 1 - smoothstep(0.25,
// 0.5, cycles per pixel)), as the paper's frequency clamping suggests.
#ifndef SG_RENDER_NOISE_GLSL
#define SG_RENDER_NOISE_GLSL

#include "sg/compat.glsl"

#define SG_NOISE_MAX_OCTAVES 12

#define SG_NOISE_PERLIN 0
#define SG_NOISE_TURBULENCE 1
#define SG_NOISE_FBM 2

// Integer hash of a lattice point (a multiply-xorshift mix); any bit pattern
// of the three coordinates maps to a well-distributed 32-bit value.
SG_FN uint sgNoiseHash(ivec3 c) {
    uint h = uint(c.x) * 0x8da6b343u;
    h ^= uint(c.y) * 0xd8163841u;
    h ^= uint(c.z) * 0xcb1ab31fu;
    h ^= h >> 16u;
    h *= 0x7feb352du;
    h ^= h >> 15u;
    h *= 0x846ca68bu;
    h ^= h >> 16u;
    return h;
}

// Perlin 2002's gradient set: the twelve edge midpoints of the cube, plus
// (1,1,0), (-1,1,0), (0,-1,1), (0,-1,-1) to fill sixteen slots.
SG_FN vec3 sgNoiseLatticeGradient(uint h) {
    uint k = h & 15u;
    float s0 = (k & 1u) != 0u ? -1.0f : 1.0f;
    float s1 = (k & 2u) != 0u ? -1.0f : 1.0f;
    if (k < 4u) return vec3(s0, s1, 0.0f);
    if (k < 8u) return vec3(s0, 0.0f, s1);
    if (k < 12u) return vec3(0.0f, s0, s1);
    if (k < 14u) return vec3(s0, 1.0f, 0.0f);
    return vec3(0.0f, -1.0f, s0);
}

// Improved Perlin noise in the lattice cell whose lower corner is `cell`
// (the corner's integer coordinates modulo 2^32, as the hash reads them) at
// f in [0, 1]^3 within it, and its exact gradient: vec4(n, dn/dp).
// Corners are cell + (0 or 1) in wrapped uint arithmetic, which both builds
// share.
SG_FN vec4 sgPerlinNoiseCell(uvec3 cell, vec3 f) {
    // Quintic fade and its derivative (C2 continuous noise).
    vec3 u = f * f * f * (f * (f * 6.0f - sgVec3(15.0f)) + sgVec3(10.0f));
    vec3 du = 30.0f * f * f * (f * (f - sgVec3(2.0f)) + sgVec3(1.0f));

    vec3 g000 = sgNoiseLatticeGradient(sgNoiseHash(ivec3(cell)));
    vec3 g100 = sgNoiseLatticeGradient(sgNoiseHash(ivec3(cell + uvec3(1u, 0u, 0u))));
    vec3 g010 = sgNoiseLatticeGradient(sgNoiseHash(ivec3(cell + uvec3(0u, 1u, 0u))));
    vec3 g110 = sgNoiseLatticeGradient(sgNoiseHash(ivec3(cell + uvec3(1u, 1u, 0u))));
    vec3 g001 = sgNoiseLatticeGradient(sgNoiseHash(ivec3(cell + uvec3(0u, 0u, 1u))));
    vec3 g101 = sgNoiseLatticeGradient(sgNoiseHash(ivec3(cell + uvec3(1u, 0u, 1u))));
    vec3 g011 = sgNoiseLatticeGradient(sgNoiseHash(ivec3(cell + uvec3(0u, 1u, 1u))));
    vec3 g111 = sgNoiseLatticeGradient(sgNoiseHash(ivec3(cell + uvec3(1u, 1u, 1u))));

    float v000 = dot(g000, f);
    float v100 = dot(g100, f - vec3(1.0f, 0.0f, 0.0f));
    float v010 = dot(g010, f - vec3(0.0f, 1.0f, 0.0f));
    float v110 = dot(g110, f - vec3(1.0f, 1.0f, 0.0f));
    float v001 = dot(g001, f - vec3(0.0f, 0.0f, 1.0f));
    float v101 = dot(g101, f - vec3(1.0f, 0.0f, 1.0f));
    float v011 = dot(g011, f - vec3(0.0f, 1.0f, 1.0f));
    float v111 = dot(g111, f - vec3(1.0f, 1.0f, 1.0f));

    // Trilinear interpolation written as a polynomial in u:
    // n = k0 + k1 ux + k2 uy + k3 uz + k4 ux uy + k5 uy uz + k6 uz ux + k7 ux uy uz.
    float k0 = v000;
    float k1 = v100 - v000;
    float k2 = v010 - v000;
    float k3 = v001 - v000;
    float k4 = v000 - v100 - v010 + v110;
    float k5 = v000 - v010 - v001 + v011;
    float k6 = v000 - v100 - v001 + v101;
    float k7 = -v000 + v100 + v010 - v110 + v001 - v101 - v011 + v111;
    // The same polynomial over the lattice gradients (d v_abc / dp = g_abc).
    vec3 h0 = g000;
    vec3 h1 = g100 - g000;
    vec3 h2 = g010 - g000;
    vec3 h3 = g001 - g000;
    vec3 h4 = g000 - g100 - g010 + g110;
    vec3 h5 = g000 - g010 - g001 + g011;
    vec3 h6 = g000 - g100 - g001 + g101;
    vec3 h7 = -g000 + g100 + g010 - g110 + g001 - g101 - g011 + g111;

    float n = k0 + k1 * u.x + k2 * u.y + k3 * u.z + k4 * u.x * u.y + k5 * u.y * u.z +
              k6 * u.z * u.x + k7 * u.x * u.y * u.z;
    vec3 grad = h0 + h1 * u.x + h2 * u.y + h3 * u.z + h4 * (u.x * u.y) + h5 * (u.y * u.z) +
                h6 * (u.z * u.x) + h7 * (u.x * u.y * u.z);
    grad += du * vec3(k1 + k4 * u.y + k6 * u.z + k7 * u.y * u.z,
                      k2 + k5 * u.z + k4 * u.x + k7 * u.z * u.x,
                      k3 + k6 * u.x + k5 * u.y + k7 * u.x * u.y);
    return vec4(n, grad.x, grad.y, grad.z);
}

// Improved Perlin noise at p and its exact gradient: vec4(n, dn/dp).
// n is in about [-1, 1]; n = 0 at every lattice point.
SG_FN vec4 sgPerlinNoise(vec3 p) {
    vec3 pf = floor(p);
    return sgPerlinNoiseCell(uvec3(ivec3(pf)), p - pf);
}

// freq * cell exactly, as its whole part modulo 2^32 (`whole`) and its
// fraction in [0, 1) (`fraction`), for a binary32 freq in [1, SG_FLT_MAX] and a
// 32-bit lattice coordinate `cell`: freq = m 2^(e - 24) with m a 24-bit
// integer (frexp), so freq * cell is the 56-bit product m * cell
// (sgIMulExtended) times 2^(e - 24); its fraction has at most 23 bits and is
// exact in binary32. Integer arithmetic only: both builds agree bit for
// bit. Other freq (never made by lacunarities >= 1): 0, 0.
SG_FN void sgNoiseScaleCell(int cell, float freq, SG_OUT(uint) whole, SG_OUT(float) fraction) {
    whole = 0u;
    fraction = 0.0f;
    if (!(freq >= 1.0f) || !(freq <= SG_FLT_MAX)) return;
    int e;
    float mant = sgFrexp(freq, e);
    int m = int(mant * 16777216.0f); // in [2^23, 2^24): exact
    int hi;
    int lo;
    sgIMulExtended(m, cell, hi, lo);
    int shift = 24 - e; // freq * cell = (hi 2^32 + lo) 2^-shift, shift <= 23
    if (shift <= -32) return; // a multiple of 2^32
    if (shift <= 0) {
        whole = uint(lo) << uint(-shift);
        return;
    }
    whole = (uint(lo) >> uint(shift)) | (uint(hi) << uint(32 - shift));
    fraction = sgLdexp(float(uint(lo) & ((1u << uint(shift)) - 1u)), -shift);
}

// One octave, frequency freq, at the lattice argument cell + q (cell a
// 32-bit lattice offset, q small): the noise at freq * (cell + q), with
// freq * cell split exactly (sgNoiseScaleCell), so only freq * q is rounded
// and a far cell costs no precision. cell = 0 is sgPerlinNoise(q * freq)
// bit for bit.
SG_FN vec4 sgPerlinNoiseShifted(ivec3 cell, vec3 q, float freq) {
    uint wx;
    uint wy;
    uint wz;
    float fx;
    float fy;
    float fz;
    sgNoiseScaleCell(cell.x, freq, wx, fx);
    sgNoiseScaleCell(cell.y, freq, wy, fy);
    sgNoiseScaleCell(cell.z, freq, wz, fz);
    vec3 p = q * freq + vec3(fx, fy, fz);
    vec3 pf = floor(p);
    return sgPerlinNoiseCell(uvec3(ivec3(pf)) + uvec3(wx, wy, wz), p - pf);
}

// Weight of an octave of `cyclesPerPixel` (frequency times footprint):
// 1 below a quarter cycle per pixel, 0 from half a cycle (Nyquist) up.
SG_FN float sgNoiseOctaveWeight(float cyclesPerPixel) {
    return 1.0f - smoothstep(0.25f, 0.5f, cyclesPerPixel);
}

// Sum of octaves of noise at the lattice argument p = cell + q (lattice
// units: cell a 32-bit integer offset, q the rest), vec4(value, gradient):
//   type SG_NOISE_PERLIN     - one octave of noise (octaves ignored);
//   type SG_NOISE_TURBULENCE - sum_i gain^i |noise(lacunarity^i p)|  (>= 0);
//   type SG_NOISE_FBM        - sum_i gain^i noise(lacunarity^i p).
// lacunarity^i is the binary32 product of i lacunarities, and octave i
// reads the noise at lacunarity^i cell + lacunarity^i q with the first
// product exact (sgPerlinNoiseShifted): a large argument is passed as a
// cell and a small q without losing precision, for any lacunarity >= 1,
// as long as the argument's whole part fits 32 bits (|p| < 2^31). For an
// integer lacunarity the cell may also be wrapped modulo 2^32 (the hash
// reads corners modulo 2^32, and lacunarity^i is then an integer); for a
// non-integer one a wrapped cell moves octaves i >= 1 by lacunarity^i *
// 2^32 mod 2^32, a different lattice. footprint is the pixel size in the
// units of q (0 disables the frequency clamp). |noise| has a crease where
// noise = 0; its gradient there is taken as 0 (sign(0) = 0) so the result
// stays finite.
SG_FN vec4 sgNoiseOctavesAt(int type, ivec3 cell, vec3 q, int octaves, float lacunarity,
                            float gain, float footprint) {
    int count = type == SG_NOISE_PERLIN ? 1 : clamp(octaves, 1, SG_NOISE_MAX_OCTAVES);
    float value = 0.0f;
    vec3 grad = sgVec3(0.0f);
    float freq = 1.0f;
    float amp = 1.0f;
    for (int o = 0; o < SG_NOISE_MAX_OCTAVES; ++o) {
        if (o >= count) break;
        float w = sgNoiseOctaveWeight(freq * footprint);
        if (!(w > 0.0f)) break; // higher octaves are finer still
        vec4 n = sgPerlinNoiseShifted(cell, q, freq);
        vec3 gn = vec3(n.y, n.z, n.w);
        if (type == SG_NOISE_TURBULENCE) {
            value += w * amp * abs(n.x);
            grad += (w * amp * freq * sign(n.x)) * gn;
        } else {
            value += w * amp * n.x;
            grad += (w * amp * freq) * gn;
        }
        freq *= lacunarity;
        amp *= gain;
    }
    return vec4(value, grad.x, grad.y, grad.z);
}

// The same at p (domain units, no cell): sgNoiseOctavesAt with cell 0.
SG_FN vec4 sgNoiseOctaves(int type, vec3 p, int octaves, float lacunarity, float gain,
                          float footprint) {
    return sgNoiseOctavesAt(type, sgIvec3(0), p, octaves, lacunarity, gain, footprint);
}

// Gritz's composite g(f) = sign(f) |f|^k (k >= 1) and its gradient
// g'(f) grad f = k |f|^(k-1) grad f. k < 1 is clamped to 1: below it the
// gradient is unbounded at f = 0.
SG_FN vec4 sgNoisePowerComposite(vec4 f, float k) {
    float kk = max(k, 1.0f);
    float a = max(abs(f.x), SG_FLT_MIN);
    float g = sign(f.x) * pow(a, kk);
    float dg = kk * pow(a, kk - 1.0f);
    return vec4(g, dg * f.y, dg * f.z, dg * f.w);
}

#endif
