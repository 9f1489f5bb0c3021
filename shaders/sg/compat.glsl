// surfgrad shared-shader common subset: GLSL side.
//
// Every file under shaders/sg/ is compiled from this one source: by the GL
// driver as GLSL, by the C++ compiler through GLM (the C++ side of these
// macros is shaders/include/surfgrad/shaders/glsl_cpp.h, which defines SG_CPP), and
// as HLSL (the HLSL side is sg/compat.hlsl, which defines SG_HLSL and which
// sg/surfgrad.hlsl includes first).
// The GLSL side compiles as GLSL 4.50, GLSL 3.30 core and GLSL ES 3.00
// (WebGL2, GLES 3), and as Vulkan GLSL to SPIR-V (docs/engines.md): what
// only 4.x has is written here once with a 3.30/ES path (SG_GLSL_LEGACY).
// The subset (checked by the build in both languages):
//   - float literals carry an f suffix (1.0f): GLM does not mix float/double;
//   - no swizzles (write vec2(v.x, v.y)), no array constructors, no globals:
//     state travels in structs (SgFrame);
//   - no splat constructors: sgVec3(x) (below), not vec3(x), which HLSL
//     rejects; matrices built from columns (sgMat3Diag(d), not mat3(d)) and
//     read by column, never multiplied by a vector; no == of vectors
//     (sgIsZero3); no mod (sg/compat.hlsl says why);
//   - out/inout parameters through SG_OUT(T)/SG_INOUT(T); every function is
//     declared `SG_FN type name(...)`;
//   - no implicit int->float promotion in vector arithmetic;
//   - identifiers avoid keywords of all three languages (sample, patch, new,
//     and HLSL's line, point, linear, triangle, vector, matrix, half, ...).
// OpenSubdiv's osd/patchBasis.h is the model for this arrangement.
#ifndef SG_COMPAT_GLSL
#define SG_COMPAT_GLSL

#if defined(SG_HLSL)
// HLSL: sg/compat.hlsl, included before this file (by sg/surfgrad.hlsl and
// the other .hlsl entries), has spelled the subset. (It is not included
// here: includes are expanded before the preprocessor runs, so every GLSL
// program would carry its text.)
#elif !defined(SG_CPP)
// GLSL before 4.00 and GLSL ES have no frexp/ldexp, imulExtended, fma or
// precise, GLSL 3.30 no unpackHalf2x16; ES 3.00 also needs default
// precisions (highp: the shared math is binary32). Sampler precisions are
// set where samplers are declared (sg/features/layout.glsl for the feature
// maps' usampler2D, which has no default) or by the program: ES's default
// lowp sampler2D returns lowp values (docs/engines.md).
#if defined(GL_ES) || __VERSION__ < 400
#define SG_GLSL_LEGACY 1
#endif
#ifdef GL_ES
precision highp float;
precision highp int;
#endif
#define SG_OUT(T) out T
#define SG_INOUT(T) inout T
// Storage class of every shared function: nothing in GLSL, `inline` in C++
// (the functions live in headers there), like OpenSubdiv's
// OSD_FUNCTION_STORAGE_CLASS.
#define SG_FN
#endif

// Smallest e with 1 + e != 1 in binary32 (Mikkelsen 2019, listing 16).
#define SG_FLT_EPSILON 1.192092896e-07f
// Smallest normal binary32. Values below it may be flushed to zero by GPUs,
// so every "is it zero?" test in the shared code uses this threshold, which
// makes CPU and GPU take the same branch.
#define SG_FLT_MIN 1.175494351e-38f
#define SG_FLT_MAX 3.402823466e+38f
// Magnitude domain of the shared functions. Inputs are expected to have
// components within +-SG_BIG (1e18: far beyond any position, derivative or
// texture size a renderer produces, and small enough that a product of two
// such values, e.g. a dot product, stays finite in binary32). Functions that
// divide (listings 7, 8, 10, 11, 17, the mikktspace rescale) keep their
// outputs within SG_BIG per component by shrinking the result along its own
// direction (sgBoundedScale3): the resolve depends only on the direction of
// such a huge gradient, so nothing a renderer sees changes. For inputs in
// the domain every shared function returns finite values.
#define SG_BIG 1.0e18f

// A vector with every component x ("splat"). The shared source writes
// sgVec3(x) where GLSL and C++ would take vec3(x): HLSL's constructors take
// as many components as the type has (DXC and FXC reject float3(x)).
SG_FN vec2 sgVec2(float x) { return vec2(x, x); }
SG_FN vec3 sgVec3(float x) { return vec3(x, x, x); }
SG_FN vec4 sgVec4(float x) { return vec4(x, x, x, x); }
SG_FN ivec2 sgIvec2(int x) { return ivec2(x, x); }
SG_FN ivec3 sgIvec3(int x) { return ivec3(x, x, x); }
SG_FN uvec4 sgUvec4(uint x) { return uvec4(x, x, x, x); }

// v == vec3(0): every component exactly zero (written per component: a
// vector == is a bool in GLSL and C++ but a bool3 in HLSL).
SG_FN bool sgIsZero3(vec3 v) { return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f; }

// The diagonal matrix d I (GLSL's mat3(d); HLSL's float3x3(d) is no
// diagonal matrix).
SG_FN mat3 sgMat3Diag(float d) {
    return mat3(vec3(d, 0.0f, 0.0f), vec3(0.0f, d, 0.0f), vec3(0.0f, 0.0f, d));
}

// Normalize that survives huge and tiny inputs: dividing by the largest
// absolute component first keeps dot(s, s) in [1, 3], so it neither
// overflows (|v| ~ 1e30) nor underflows (|v| ~ 1e-30). Returns `fallback`
// when v has no direction (largest component below FLT_MIN, or not finite).
// Written as one straight path (a reciprocal, no division per component, no
// fast/slow branches): llvmpipe evaluates both sides of a divergent branch,
// and this runs twice on every pixel.
SG_FN vec3 sgSafeNormalize(vec3 v, vec3 fallback) {
    float m = max(max(abs(v.x), abs(v.y)), abs(v.z));
    vec3 s = v * (1.0f / m);
    return (m >= SG_FLT_MIN && m <= SG_FLT_MAX) ? s * inversesqrt(dot(s, s)) : fallback;
}

SG_FN vec2 sgSafeNormalize2(vec2 v, vec2 fallback) {
    float m = max(abs(v.x), abs(v.y));
    vec2 s = v * (1.0f / m);
    return (m >= SG_FLT_MIN && m <= SG_FLT_MAX) ? s * inversesqrt(dot(s, s)) : fallback;
}

// v with every component of magnitude below SG_FLT_MIN (a denormal) set to
// zero: what a GPU that flushes denormals reads. The shared functions apply
// it where such a component could decide a branch or a sign, so a GPU that
// flushes, a GPU that does not (llvmpipe's compute stage keeps denormals,
// its vertex stage flushes them) and the CPU build take the same path.
SG_FN vec3 sgFlushDenorm3(vec3 v) {
    return vec3(abs(v.x) >= SG_FLT_MIN ? v.x : 0.0f, abs(v.y) >= SG_FLT_MIN ? v.y : 0.0f,
                abs(v.z) >= SG_FLT_MIN ? v.z : 0.0f);
}
SG_FN vec2 sgFlushDenorm2(vec2 v) {
    return vec2(abs(v.x) >= SG_FLT_MIN ? v.x : 0.0f, abs(v.y) >= SG_FLT_MIN ? v.y : 0.0f);
}

// Largest absolute component.
SG_FN float sgMaxAbs2(vec2 v) { return max(abs(v.x), abs(v.y)); }
SG_FN float sgMaxAbs3(vec3 v) { return max(max(abs(v.x), abs(v.y)), abs(v.z)); }
SG_FN float sgMaxAbs4(vec4 v) { return max(max(abs(v.x), abs(v.y)), max(abs(v.z), abs(v.w))); }

// v divided by its largest absolute component (so that component is +-1), or
// the zero vector when v has none of at least SG_FLT_MIN (or is not finite).
// Products of such vectors (cross, dot) can neither overflow nor underflow,
// and their signs are those of the unscaled products.
SG_FN vec3 sgScaleToUnitMax3(vec3 v) {
    float m = sgMaxAbs3(v);
    if (!(m >= SG_FLT_MIN) || !(m <= SG_FLT_MAX)) return sgVec3(0.0f);
    return v / m;
}

// v / k for a common scale k >= max(|v|) of several vectors, with a vector
// whose largest component is below SG_FLT_MIN treated as zero (a GPU flushes
// such denormals; the CPU would carry them into products): both builds then
// see the same zero vector.
SG_FN vec3 sgDivScale3(vec3 v, float k) { return sgMaxAbs3(v) >= SG_FLT_MIN ? v / k : sgVec3(0.0f); }
SG_FN vec2 sgDivScale2(vec2 v, float k) { return sgMaxAbs2(v) >= SG_FLT_MIN ? v / k : sgVec2(0.0f); }

// frexp and ldexp of normal binary32 values, written with the bit pattern
// (floatBitsToInt exists in GLSL 3.30 and ES 3.00) where the language lacks
// them. Same results as the built-ins on the domain the shared code uses:
//   sgFrexp: x normal (SG_FLT_MIN <= |x| <= SG_FLT_MAX): x = m 2^e with
//            0.5 <= |m| < 1; exact (only the exponent field changes);
//   sgLdexp: m 2^e for -252 <= e <= 252 and m 2^(e/2) a normal number
//            or m = 0 (the callers: m in [2^-5, 2^24) or 0, e in [-120, 64]). The power of
//            two is applied as two exact factors, 2^(e/2) first, so only
//            the second product rounds: one rounding, like ldexp (a result
//            in the denormal range is then flushed by a GPU as its ldexp's
//            is).
//   sgIMulExtended: the 64-bit product a * b of two signed 32-bit integers
//            as its high and low words (imulExtended); exact. The legacy
//            path multiplies 16-bit halves as unsigned integers and then
//            corrects the high word for the signs (two's complement).
//   sgUnpackHalf2x16: the two binary16 halves of a 32-bit word as floats
//            (low half first), unpackHalf2x16; exact (every binary16 value,
//            denormals, infinities and NaNs included, is a binary32 value).
#if defined(SG_CPP) || !defined(SG_GLSL_LEGACY) || defined(GL_ES)
SG_FN vec2 sgUnpackHalf2x16(uint w) { return unpackHalf2x16(w); }
#else
SG_FN float sgHalfToFloat(uint h) {
    uint e = (h >> 10u) & 0x1fu;
    uint m = h & 0x3ffu;
    // Denormal halves: m 2^-24, exact. Else rebias the exponent (15 -> 127;
    // the all-ones exponent of infinities and NaNs stays all ones).
    float v = e == 0u ? float(m) * 5.9604644775390625e-8f
                      : uintBitsToFloat(((e == 31u ? 255u : e + 112u) << 23u) | (m << 13u));
    return (h & 0x8000u) != 0u ? -v : v;
}
SG_FN vec2 sgUnpackHalf2x16(uint w) {
    return vec2(sgHalfToFloat(w & 0xffffu), sgHalfToFloat(w >> 16u));
}
#endif
// SG_BIT_ARITHMETIC: frexp, ldexp and imulExtended from bit patterns and
// 16-bit halves, as the legacy dialects need; also defined for GLSL 4.x
// programs carried to HLSL through SPIR-V (surfgrad/translate/shader_target.h):
// SPIRV-Cross writes HLSL's frexp with an int exponent, which HLSL's frexp
// (float exponent) does not take, and no HLSL for OpSMulExtended.
#if defined(SG_GLSL_LEGACY) && !defined(SG_BIT_ARITHMETIC)
#define SG_BIT_ARITHMETIC 1
#endif
#if defined(SG_CPP) || !defined(SG_BIT_ARITHMETIC)
SG_FN float sgFrexp(float x, SG_OUT(int) e) { return frexp(x, e); }
SG_FN float sgLdexp(float m, int e) { return ldexp(m, e); }
SG_FN void sgIMulExtended(int a, int b, SG_OUT(int) hi, SG_OUT(int) lo) {
    imulExtended(a, b, hi, lo);
}
#else
SG_FN float sgFrexp(float x, SG_OUT(int) e) {
    int bits = floatBitsToInt(x);
    e = ((bits >> 23) & 0xff) - 126;
    return intBitsToFloat((bits & int(0x807fffffu)) | (126 << 23));
}
SG_FN float sgLdexp(float m, int e) {
    int e1 = e / 2;
    int e2 = e - e1;
    return (m * intBitsToFloat((e1 + 127) << 23)) * intBitsToFloat((e2 + 127) << 23);
}
SG_FN void sgIMulExtended(int a, int b, SG_OUT(int) hi, SG_OUT(int) lo) {
    uint ua = uint(a);
    uint ub = uint(b);
    uint a0 = ua & 0xffffu;
    uint a1 = ua >> 16u;
    uint b0 = ub & 0xffffu;
    uint b1 = ub >> 16u;
    uint p00 = a0 * b0;
    uint p01 = a0 * b1;
    uint p10 = a1 * b0;
    uint mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu); // < 3 * 2^16
    uint uhi = a1 * b1 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u);
    // Unsigned to signed product: subtract b 2^32 when a < 0, a 2^32 when b < 0.
    if (a < 0) uhi -= ub;
    if (b < 0) uhi -= ua;
    lo = int((p00 & 0xffffu) | (mid << 16u));
    hi = int(uhi);
}
#endif

// The product vMax * f.x * f.y * f.z * f.w of non-negative factors, clamped to
// SG_BIG, computed on exponents and mantissas (frexp/ldexp) so that no
// intermediate product overflows or underflows whatever the order of
// magnitude of the factors (e.g. 1e18 * 1e18 * 1e-30). A factor below
// SG_FLT_MIN (zero, or a denormal that a GPU would flush) gives 0, a result
// below 2^-120 gives 0. Continuous at the SG_BIG clamp.
SG_FN float sgBoundedGain(float vMax, vec4 f) {
    float lo = min(min(vMax, f.x), min(min(f.y, f.z), f.w));
    float hi = max(max(vMax, f.x), max(max(f.y, f.z), f.w));
    if (!(lo >= SG_FLT_MIN)) return 0.0f;
    if (!(hi <= SG_FLT_MAX)) return SG_BIG;
    int ev;
    int ex;
    int ey;
    int ez;
    int ew;
    float mv = sgFrexp(vMax, ev);
    float mx = sgFrexp(f.x, ex);
    float my = sgFrexp(f.y, ey);
    float mz = sgFrexp(f.z, ez);
    float mw = sgFrexp(f.w, ew);
    int expSum = ev + ex + ey + ez + ew;
    // Each mantissa is in [0.5, 1): the product is in [1/32, 1).
    float mant = mv * ((mx * my) * (mz * mw));
    if (expSum > 64) return SG_BIG; // >= 2^59 > SG_BIG: same as the clamp below
    if (expSum < -120) return 0.0f;
    return min(sgLdexp(mant, expSum), SG_BIG);
}

// v * f.x * f.y * f.z * f.w (non-negative factors; pass 1.0f for unused
// ones) with every component of the result within SG_BIG: the direction of v
// is kept and its length shrunk if needed. Zero when v has no component of
// at least SG_FLT_MIN.
SG_FN vec3 sgBoundedScale3(vec3 v, vec4 f) {
    float m = sgMaxAbs3(v);
    if (!(m >= SG_FLT_MIN) || !(m <= SG_FLT_MAX)) return sgVec3(0.0f);
    return (v / m) * sgBoundedGain(m, f);
}
SG_FN vec2 sgBoundedScale2(vec2 v, vec4 f) {
    float m = sgMaxAbs2(v);
    if (!(m >= SG_FLT_MIN) || !(m <= SG_FLT_MAX)) return sgVec2(0.0f);
    return (v / m) * sgBoundedGain(m, f);
}

// 1/x with the sign of x kept and |x| clamped below by FLT_EPSILON: the
// guarded reciprocal used throughout Mikkelsen 2019 (listings 7, 8, 10, 11).
SG_FN float sgSignedRcp(float x) {
    float sgn = x < 0.0f ? -1.0f : 1.0f;
    return sgn / max(SG_FLT_EPSILON, abs(x));
}

#endif
