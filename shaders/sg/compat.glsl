// surfgrad shared-shader common subset: GLSL side.
//
// Every file under shaders/sg/ is compiled twice from this one source: by the
// GL driver as GLSL 4.50, and by the C++ compiler through GLM (the C++ side of
// these macros is bump/include/surfgrad/glsl_cpp.h, which defines SG_CPP).
// The subset (checked by the build in both languages):
//   - float literals carry an f suffix (1.0f): GLM does not mix float/double;
//   - no swizzles (write vec2(v.x, v.y)), no array constructors, no globals:
//     state travels in structs (SgFrame);
//   - out/inout parameters through SG_OUT(T)/SG_INOUT(T); every function is
//     declared `SG_FN type name(...)`;
//   - no implicit int->float promotion in vector arithmetic;
//   - identifiers avoid keywords of both languages (sample, patch, new, ...).
// OpenSubdiv's osd/patchBasis.h is the model for this arrangement.
#ifndef SG_COMPAT_GLSL
#define SG_COMPAT_GLSL

#ifndef SG_CPP
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

// Normalize that survives huge and tiny inputs: dividing by the largest
// absolute component first keeps dot(s, s) in [1, 3], so it neither
// overflows (|v| ~ 1e30) nor underflows (|v| ~ 1e-30). Returns `fallback`
// when v has no direction (largest component below FLT_MIN, or not finite).
SG_FN vec3 sgSafeNormalize(vec3 v, vec3 fallback) {
    float m = max(max(abs(v.x), abs(v.y)), abs(v.z));
    if (!(m >= SG_FLT_MIN) || !(m <= SG_FLT_MAX)) return fallback;
    vec3 s = v / m;
    return s * inversesqrt(dot(s, s));
}

SG_FN vec2 sgSafeNormalize2(vec2 v, vec2 fallback) {
    float m = max(abs(v.x), abs(v.y));
    if (!(m >= SG_FLT_MIN) || !(m <= SG_FLT_MAX)) return fallback;
    vec2 s = v / m;
    return s * inversesqrt(dot(s, s));
}

// 1/x with the sign of x kept and |x| clamped below by FLT_EPSILON: the
// guarded reciprocal used throughout Mikkelsen 2019 (listings 7, 8, 10, 11).
SG_FN float sgSignedRcp(float x) {
    float sgn = x < 0.0f ? -1.0f : 1.0f;
    return sgn / max(SG_FLT_EPSILON, abs(x));
}

#endif
