// Reduced-precision emulation for table 6 of bench_accuracy_cost
// (docs/accuracy-cost.md): what the bump path loses when a shader runs it in
// binary16 ("mediump", GLSL float16_t).
//
// llvmpipe exposes no 16-bit float arithmetic to GLSL (no
// GL_AMD_gpu_shader_half_float, no float16_t), and desktop GLSL ignores
// precision qualifiers, so binary16 is emulated on the CPU: `Half` rounds
// the result of every operation to binary16 (round to nearest even,
// subnormals, overflow to infinity). Each operation is computed in binary32
// and then rounded; for + - * / and sqrt this equals direct rounding because
// binary32 carries more than 2 * 11 + 2 significand bits (double rounding is
// innocuous). Comparisons against the library's binary32 thresholds
// (SG_FLT_MIN, SG_FLT_EPSILON) are made in binary32, as a GPU compares a
// mediump value with a highp constant.
//
// The path is the one a per-pixel-frame or vertex-tangent fragment shader
// runs (Mikkelsen 2019 listings 16, 6, 4, 5, 1 and section 2.2). It is a
// transcription of shaders/sg/frame.glsl and shaders/sg/surfgrad.glsl,
// templated on the scalar type because GLSL source cannot be compiled with a
// custom scalar; the transcription is checked against the shared C++ build
// (sg::glsl) at T = float by the table itself, which prints the largest
// difference. Only what the path needs is transcribed (degenerate-input
// fallbacks included, so the branches are the same).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace study {

// binary32 -> nearest binary16 value (as binary32).
inline float roundToHalf(float x) {
    if (!std::isfinite(x) || x == 0.0f) return x;
    const float ax = std::fabs(x);
    if (ax >= 65520.0f) return std::copysign(INFINITY, x); // rounds past 65504
    // Quantum of binary16 at |x|: 2^(e - 10) for normals, 2^-24 below 2^-14.
    int e = 0;
    std::frexp(ax, &e); // ax = m 2^e, m in [0.5, 1)
    const int exp2 = std::max(e - 1, -14);
    const float q = std::ldexp(1.0f, exp2 - 10);
    // ax / q is exact (power of two); nearbyint rounds to nearest even.
    return std::copysign(std::nearbyint(ax / q) * q, x);
}

struct Half {
    float v = 0.0f; // always a binary16 value
    Half() = default;
    Half(float x) : v(roundToHalf(x)) {} // NOLINT: implicit, like a GLSL conversion
    explicit operator float() const { return v; }
    friend Half operator+(Half a, Half b) { return Half(a.v + b.v); }
    friend Half operator-(Half a, Half b) { return Half(a.v - b.v); }
    friend Half operator*(Half a, Half b) { return Half(a.v * b.v); }
    friend Half operator/(Half a, Half b) { return Half(a.v / b.v); }
    friend Half operator-(Half a) { return Half(-a.v); }
    friend bool operator<(Half a, Half b) { return a.v < b.v; }
};

inline float toFloat(float x) {
    return x;
}
inline float toFloat(double x) {
    return float(x);
}
inline float toFloat(Half x) {
    return x.v;
}
inline float sabs(float x) {
    return std::fabs(x);
}
inline double sabs(double x) {
    return std::fabs(x);
}
inline Half sabs(Half x) {
    return Half(std::fabs(x.v));
}
inline float srsqrt(float x) {
    return 1.0f / std::sqrt(x);
}
inline double srsqrt(double x) {
    return 1.0 / std::sqrt(x);
}
inline Half srsqrt(Half x) {
    return Half(1.0f / std::sqrt(x.v));
} // one rounding, like a hardware rsqrt
template <class T>
T smax(T a, T b) {
    return a < b ? b : a;
}

template <class T>
struct V2 {
    T x, y;
};
template <class T>
struct V3 {
    T x, y, z;
};
template <class T>
V3<T> operator+(V3<T> a, V3<T> b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
V3<T> operator-(V3<T> a, V3<T> b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
V3<T> operator*(T s, V3<T> a) {
    return {s * a.x, s * a.y, s * a.z};
}
template <class T>
V3<T> operator/(V3<T> a, T s) {
    return {a.x / s, a.y / s, a.z / s};
}
template <class T>
T dot(V3<T> a, V3<T> b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
V3<T> cross(V3<T> a, V3<T> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
T maxAbs(V3<T> v) {
    return smax(smax(sabs(v.x), sabs(v.y)), sabs(v.z));
}
template <class T>
T maxAbs(V2<T> v) {
    return smax(sabs(v.x), sabs(v.y));
}

constexpr float kFltMin = 1.175494351e-38f; // SG_FLT_MIN
constexpr float kFltMax = 3.402823466e+38f; // SG_FLT_MAX
constexpr float kFltEps = 1.192092896e-07f; // SG_FLT_EPSILON

// sgSafeNormalize.
template <class T>
V3<T> safeNormalize(V3<T> v, V3<T> fallback) {
    const T m = maxAbs(v);
    if (!(toFloat(m) >= kFltMin) || !(toFloat(m) <= kFltMax)) return fallback;
    const V3<T> s = v / m;
    return srsqrt(dot(s, s)) * s;
}

// sgScaleToUnitMax3.
template <class T>
V3<T> scaleToUnitMax(V3<T> v) {
    const T m = maxAbs(v);
    if (!(toFloat(m) >= kFltMin) || !(toFloat(m) <= kFltMax)) return {T(0.0f), T(0.0f), T(0.0f)};
    return v / m;
}

template <class T>
struct Frame {
    V3<T> nrmBase, dPdx, dPdy, sigmaX, sigmaY;
    T flipSign, resolveSign;
};

// sgPrologue for a front face, double-sided mode NONE (the vertex normal
// is never degenerate on the test mesh; the geometric fallback is kept).
template <class T>
Frame<T> prologue(V3<T> vtxNormal, V3<T> dPdx, V3<T> dPdy) {
    Frame<T> f;
    const V3<T> z{T(0.0f), T(0.0f), T(1.0f)};
    const V3<T> c = cross(scaleToUnitMax(dPdx), scaleToUnitMax(dPdy));
    const V3<T> geo = toFloat(maxAbs(c)) >= 8.0f * kFltEps ? safeNormalize(c, z) : z;
    f.nrmBase = safeNormalize(vtxNormal, geo);
    f.resolveSign = T(1.0f);
    f.dPdx = dPdx;
    f.dPdy = dPdy;
    f.sigmaX = dPdx - dot(dPdx, f.nrmBase) * f.nrmBase;
    f.sigmaY = dPdy - dot(dPdy, f.nrmBase) * f.nrmBase;
    const V3<T> ax = scaleToUnitMax(dPdx), ay = scaleToUnitMax(dPdy);
    f.flipSign = toFloat(dot(ay, cross(f.nrmBase, ax))) < 0.0f ? T(-1.0f) : T(1.0f);
    return f;
}

// sgGenBasisTB on a well-conditioned chart (the torus: its chart weight is 1).
template <class T>
void genBasisTB(const Frame<T>& f, V2<T> dSTdx, V2<T> dSTdy, V3<T>& vT, V3<T>& vB) {
    const V3<T> zero{T(0.0f), T(0.0f), T(0.0f)};
    vT = zero;
    vB = zero;
    const T k = smax(maxAbs(dSTdx), maxAbs(dSTdy));
    if (!(toFloat(k) >= kFltMin) || !(toFloat(k) <= kFltMax)) return;
    auto divScale = [&](V2<T> v) {
        return toFloat(maxAbs(v)) >= kFltMin ? V2<T>{v.x / k, v.y / k} : V2<T>{T(0.0f), T(0.0f)};
    };
    const V2<T> sx = divScale(dSTdx), sy = divScale(dSTdy);
    const T det = sx.x * sy.y - sx.y * sy.x;
    if (!(std::fabs(toFloat(det)) >= kFltEps)) return;
    const T signDet = toFloat(det) < 0.0f ? T(-1.0f) : T(1.0f);
    const V2<T> invCO{signDet * sy.y, -(signDet * sx.y)};
    const V3<T> tRaw = invCO.x * f.sigmaX + invCO.y * f.sigmaY;
    const V3<T> t1 = tRaw - dot(tRaw, f.nrmBase) * f.nrmBase;
    const V3<T> t2 = t1 - dot(t1, f.nrmBase) * f.nrmBase;
    if (!(toFloat(maxAbs(t2)) >= 8.0f * kFltEps * toFloat(maxAbs(tRaw)))) return;
    const V3<T> t = safeNormalize(t2, zero);
    if (toFloat(maxAbs(t)) == 0.0f) return;
    vT = t;
    vB = (signDet * f.flipSign) * cross(f.nrmBase, t);
}

// sgTspaceNormalToDeriv (flipV = false).
template <class T>
V2<T> tspaceNormalToDeriv(V2<T> m) {
    const T fS = T(1.0f / (128.0f * 128.0f));
    const V2<T> mSq{m.x * m.x, m.y * m.y};
    const T mzSq = T(1.0f) - mSq.x - mSq.y;
    const T maxCompXySq = fS * smax(mSq.x, mSq.y);
    // max(..., FLT_MIN) guards m == 0 (binary16 has no FLT_MIN: its
    // smallest subnormal plays that role).
    T zSq = smax(mzSq, maxCompXySq);
    if (!(toFloat(zSq) > 0.0f)) zSq = T(std::is_same_v<T, Half> ? 5.9604645e-8f : kFltMin);
    const T zInv = srsqrt(zSq);
    return {-(zInv * m.x), -(zInv * m.y)};
}

// sgRenormFactor + sgMikktsBasis (no huge-value branch: inputs are unit-scale).
template <class T>
void mikktsBasis(V3<T> vtxNormal, V3<T> t, T w, V3<T>& tang, V3<T>& bino, V3<T>& nUnit) {
    const T m = maxAbs(vtxNormal);
    const V3<T> s = vtxNormal / m;
    const T renorm = srsqrt(dot(s, s)) / m;
    nUnit = renorm * vtxNormal;
    tang = renorm * t;
    const T signW = toFloat(w) > 0.0f ? T(1.0f) : T(-1.0f);
    bino = signW * cross(nUnit, t);
}

// sgSurfgradFromTBN + sgResolve.
template <class T>
V3<T> resolveTBN(const Frame<T>& f, V2<T> deriv, V3<T> vT, V3<T> vB) {
    const V3<T> sg = deriv.x * vT + deriv.y * vB;
    return safeNormalize(f.nrmBase - f.resolveSign * sg, f.nrmBase);
}

} // namespace study
