// Antialiased volume noise (layer kind noise with "antialias": "lean"): the
// octaves above the pixel's Nyquist frequency are faded out as today
// (sgNoiseOctaveWeight, Mikkelsen 2019 section 4's frequency clamping) and
// the slope energy they lose moves into the slope covariance that widens
// the lobe (sg/render/antialias.glsl), so the faded detail still roughens
// the highlight instead of vanishing.
//
// The variance of the removed octaves, derived from the noise's spectrum:
// octave o of sgNoiseOctavesAt is amp_o n(freq_o q) (amp_o = gain^o,
// freq_o = lacunarity^o, q = frequency p + offset, layer_noise.glsl's
// argument, passed as a lattice cell and a small rest; turbulence takes
// |n|, whose gradient sign(n) grad n has the same second moments). Its domain
// gradient is A F amp_o freq_o grad n (A amplitude, F frequency), so over
// the domain its covariance is (A F amp_o freq_o)^2 D, D the covariance of
// the gradient of one unit noise n (below). Octaves are taken as
// uncorrelated (their lattices hash different integer points). The faded
// octave keeps w_o grad n (variance w_o^2 V_o), so the energy moved into
// the covariance is (1 - w_o^2) V_o: the kept and moved parts add up to the
// full-detail variance sum_o V_o at every footprint (tested against a
// measured variance in tests/render/antialias_compose_test.cpp).
//
// D for sgPerlinNoise: n(u) = sum over the cell's corners c of
// (g_c . (u - c)) S_c(u), S_c the product of quintic fades, g_c drawn from
// the sixteen gradients of sgNoiseLatticeGradient, independent and of mean
// 0, E[g g^T] = diag(10, 12, 10) / 16 (the four padding gradients add to
// y). Then E[d_i n d_j n] = sum_c v_ci^T E[g g^T] v_cj with
// v_ci = S_c e_i + (u - c) d_i S_c, averaged over the unit cell (exact
// rational integration of the polynomials): D = diag(77205550, 84125180,
// 77205550) / 160243083 = diag(0.48180, 0.52498, 0.48180), off-diagonals 0.
//
// Gritz's composite x^k multiplies the gradient by k |f|^(k-1); the moved
// variance is scaled by its square at the pixel's filtered value f (an
// approximation: the factor varies within the footprint).
#ifndef SG_RENDER_LAYER_NOISE_AA_GLSL
#define SG_RENDER_LAYER_NOISE_AA_GLSL

#include "sg/render/antialias.glsl"
#include "sg/render/layer_noise.glsl"

// Per-axis gradient variance of one unit sgPerlinNoise (see above).
SG_FN vec3 sgPerlinGradientVariance() {
    return vec3(0.48180270f, 0.52498478f, 0.48180270f);
}

// sum over the octaves of (1 - w_o^2) amp_o^2 freq_o^2: the removed
// octaves' gradient variance in units of D (A = F = 1); footprint in the
// units of q (as sgNoiseOctaves). Finite for any footprint (0 ... Inf):
// at most sum amp_o^2 freq_o^2 over the octaves.
SG_FN float sgNoiseRemovedEnergy(int type, int octaves, float lacunarity, float gain,
                                 float footprint) {
    int count = type == SG_NOISE_PERLIN ? 1 : clamp(octaves, 1, SG_NOISE_MAX_OCTAVES);
    float e = 0.0f;
    float freq = 1.0f;
    float amp = 1.0f;
    for (int o = 0; o < SG_NOISE_MAX_OCTAVES; ++o) {
        if (o >= count) break;
        float w = sgNoiseOctaveWeight(freq * footprint);
        e += (1.0f - w * w) * (amp * freq) * (amp * freq);
        freq *= lacunarity;
        amp *= gain;
    }
    return e;
}

// Frame-space covariance of a domain gradient of per-axis variances var:
// sum_k var_k (P G e_k)(P G e_k)^T (G gradToFrame, P listing 12's
// projection).
// Under SG_AA_COV_UNMAPPED (sg/render/antialias.glsl) the domain variances'
// sum, untransformed.
SG_FN mat3 sgDomainCovToFrame(SgFrame f, SgVolumeSpace vs, vec3 var) {
#ifdef SG_AA_COV_UNMAPPED
    return sgSlopeCovUnmapped(var.x + var.y + var.z);
#else
    vec3 cx = sgSurfgradFromVolumeGradient(f, vs.gradToFrame * vec3(1.0f, 0.0f, 0.0f));
    vec3 cy = sgSurfgradFromVolumeGradient(f, vs.gradToFrame * vec3(0.0f, 1.0f, 0.0f));
    vec3 cz = sgSurfgradFromVolumeGradient(f, vs.gradToFrame * vec3(0.0f, 0.0f, 1.0f));
    return var.x * outerProduct(cx, cx) + var.y * outerProduct(cy, cy) +
           var.z * outerProduct(cz, cz);
#endif
}

// The layer's surface gradient (sgLayerNoise with the fade, whatever
// p.antialias says) and, added to slopeCov, the removed octaves' covariance.
SG_FN vec3 sgLayerNoiseLean(SgFrame f, SgVolumeSpace vs, SgNoiseParams p,
                            SG_INOUT(mat3) slopeCov) {
    float footprint = sgVolumeFootprint(vs) * p.frequency;
    vec4 n = sgNoiseLayerOctaves(vs, p, footprint);
    float k = 1.0f; // the composite's gradient factor
    if (p.exponent != 1.0f) {
        float kk = max(p.exponent, 1.0f);
        k = kk * pow(max(abs(n.x), SG_FLT_MIN), kk - 1.0f);
        n = sgNoisePowerComposite(n, p.exponent);
    }
    float af = p.amplitude * p.frequency;
    float e = sgNoiseRemovedEnergy(p.type, p.octaves, p.lacunarity, p.gain, footprint);
    // min: an overflowing product stays a finite (flat-lobe) variance; no
    // removed energy is none (not Inf * 0).
    float s = e > 0.0f ? min((af * k) * (af * k) * e, 1e30f) : 0.0f;
    slopeCov = slopeCov + sgDomainCovToFrame(f, vs, s * sgPerlinGradientVariance());
    return sgSurfgradFromVolumeGradient(f, vs.gradToFrame * (af * vec3(n.y, n.z, n.w)));
}

#endif
