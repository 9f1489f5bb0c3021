// Floating-point kernels shared by the two MikkTSpace implementations
// (mikktspace_reference.cpp, the oracle, and mikktspace.cpp, the fast one).
//
// Bit compatibility with MikkTSpace is a property of the exact sequence of
// float operations, so every formula here spells out the reference's
// evaluation order (left-to-right sums, s*v scalings, 1/len then multiply,
// acos in double). These files are compiled with -ffp-contract=off so no
// multiply-add is fused (mesh/CMakeLists.txt). Everything else (welding,
// adjacency, grouping) is structure, written separately in each file.
//
// Equation numbers refer to Mikkelsen, "Simulation of Wrinkled Surfaces
// Revisited", 2008, section 4.2 (per-face first order derivatives).
#pragma once

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "surfgrad/base/contract.h"
#include "surfgrad/mesh/tangents.h"

namespace sg::mesh::mikk {

struct Vec3 {
    float x, y, z;
};

inline bool exactlyEqual(const Vec3& a, const Vec3& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
}
inline Vec3 add(const Vec3& a, const Vec3& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 sub(const Vec3& a, const Vec3& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 scale(float s, const Vec3& v) {
    return {s * v.x, s * v.y, s * v.z};
}
inline float dot(const Vec3& a, const Vec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline float lengthSquared(const Vec3& v) {
    return v.x * v.x + v.y * v.y + v.z * v.z;
}
inline float length(const Vec3& v) {
    return std::sqrt(lengthSquared(v));
}

// The reference's zero test: |x| > FLT_MIN (denormals count as zero).
inline bool notZero(float x) {
    return std::fabs(x) > FLT_MIN;
}
inline bool notZero(const Vec3& v) {
    return notZero(v.x) || notZero(v.y) || notZero(v.z);
}

// 1/len first, then a scaling (not three divisions), as the reference.
inline Vec3 normalize(const Vec3& v) {
    return scale(1.0f / length(v), v);
}

// v minus its component along n, normalized unless it vanished.
inline Vec3 projectToPlane(const Vec3& v, const Vec3& n) {
    Vec3 r = sub(v, scale(dot(n, v), n));
    if (notZero(r)) r = normalize(r);
    return r;
}

inline Vec3 toVec3(const glm::vec3& v) {
    return {v.x, v.y, v.z};
}
inline glm::vec3 toGlm(const Vec3& v) {
    return {v.x, v.y, v.z};
}

// Per-triangle first-order derivatives, eq. 18/19 (InitTriInfo):
//   vOs = t31y*d1 - t21y*d2,  vOt = -t31x*d1 + t21x*d2
// (dP/ds and dP/dt times twice the signed UV area), the orientation bit
// (signed UV area > 0), and when the UV area is not zero: vOs, vOt
// normalized and flipped for mirrored UVs (so they point along +s, +t),
// magnitudes |dP/ds|, |dP/dt|; the triangle is "good" (may seed and
// average into groups) when both magnitudes are non-zero.
struct FaceDerivatives {
    Vec3 vOs{0.0f, 0.0f, 0.0f};
    Vec3 vOt{0.0f, 0.0f, 0.0f};
    float magS = 0.0f;
    float magT = 0.0f;
    bool orientPreserving = false;
    bool groupWithAny = true; // "bad" triangle: takes the orientation of the first group meeting it
};

inline FaceDerivatives faceDerivatives(const Vec3& p1, const Vec3& p2, const Vec3& p3,
                                       const glm::vec2& t1, const glm::vec2& t2,
                                       const glm::vec2& t3) {
    FaceDerivatives d;
    const float t21x = t2.x - t1.x;
    const float t21y = t2.y - t1.y;
    const float t31x = t3.x - t1.x;
    const float t31y = t3.y - t1.y;
    const Vec3 d1 = sub(p2, p1);
    const Vec3 d2 = sub(p3, p1);
    const float signedAreaSTx2 = t21x * t31y - t21y * t31x;
    const Vec3 vOs = sub(scale(t31y, d1), scale(t21y, d2));  // eq. 18
    const Vec3 vOt = add(scale(-t31x, d1), scale(t21x, d2)); // eq. 19
    d.orientPreserving = signedAreaSTx2 > 0.0f;
    if (notZero(signedAreaSTx2)) {
        const float absArea = std::fabs(signedAreaSTx2);
        const float lenOs = length(vOs);
        const float lenOt = length(vOt);
        const float flip = d.orientPreserving ? 1.0f : -1.0f;
        if (notZero(lenOs)) d.vOs = scale(flip / lenOs, vOs);
        if (notZero(lenOt)) d.vOt = scale(flip / lenOt, vOt);
        d.magS = lenOs / absArea;
        d.magT = lenOt / absArea;
        if (notZero(d.magS) && notZero(d.magT)) d.groupWithAny = false;
    }
    return d;
}

// Twice the unsigned UV area of a triangle (CalcTexArea), used to pick the
// orientation of a quad whose two triangles disagree.
inline float uvAreaTimes2(const glm::vec2& t1, const glm::vec2& t2, const glm::vec2& t3) {
    const float t21x = t2.x - t1.x;
    const float t21y = t2.y - t1.y;
    const float t31x = t3.x - t1.x;
    const float t31y = t3.y - t1.y;
    const float a = t21x * t31y - t21y * t31x;
    return a < 0.0f ? -a : a;
}

// (float)acos((double)c) for c in [-1, 1], the reference's rounding of
// the angle, without calling acos in almost all cases (libm's double acos
// costs ~25 ns, 3 per triangle). Method: acos in double from
// asin(sqrt(z))/sqrt(z) = 1 + z Q(z), z in [0, 1/4] (z = c^2 for |c| <= 1/2,
// z = (1 - |c|)/2 otherwise; acos = pi/2 - asin(c), resp. 2 asin(sqrt z) or
// pi - 2 asin(sqrt z)), Q a degree-9 Chebyshev interpolant (absolute error
// of z Q(z) < 2^-45). The float rounding of that value is final unless it
// lies within 2^-36 (relative) of a midpoint between two floats, where libm
// decides (~0.05% of inputs).
// Since any libm acos is within an ulp of the true value (2^-52), the
// result equals (float)std::acos(c) for every float c; an exhaustive check
// over all 2^31 floats in [-1, 1] is in the benchmark
// (tangents_bench --check-acos) and a sample in the tests. The fast
// MikkTSpace path uses the two-lane SIMD copy, mikktspaceAnglesFromCos.
// Q's coefficients, highest degree first (Horner order); every copy of the
// kernel (scalar here, AVX2 and SSE2 in mikktspace.cpp) evaluates them in
// this order, so all give the same double.
inline constexpr double kAcosQ[10] = {
    0x1.c93a92d53b4f1p-6, -0x1.815314c864b09p-9, 0x1.00d47e7966d94p-6, 0x1.b02442413f6bap-7,
    0x1.1dc2ef640046fp-6, 0x1.6e72146fda29ep-6,  0x1.f1c81c59ea536p-6, 0x1.6db6d8e71341bp-5,
    0x1.33333335a9cd6p-4, 0x1.5555555554f05p-3,
};

inline float acosRoundedToFloat(float c) {
    constexpr double kPi = 3.141592653589793115997963468544185161590576171875;
    constexpr double kHalfPi = 1.5707963267948965579989817342720925807952880859375;
    const double x = c;
    const double a = std::fabs(x);
    auto q = [](double z) {
        double p = kAcosQ[0];
#pragma GCC unroll 10
        for (int k = 1; k < 10; ++k) p = p * z + kAcosQ[k];
        return p;
    };
    double y;
    if (a <= 0.5) {
        const double z = x * x;
        y = kHalfPi - (x + x * z * q(z));
    } else {
        const double z = (1.0 - a) * 0.5; // exact for float a in [1/2, 1]
        const double r = std::sqrt(z);
        const double asinR = r + r * z * q(z);
        y = x > 0.0 ? 2.0 * asinR : kPi - 2.0 * asinR;
    }
    if (y == 0.0) return 0.0f; // c == 1 exactly
    const float f = static_cast<float>(y);
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits); // f > 0: neighbours are bits -+ 1
    float below, above;
    const uint32_t bitsBelow = bits - 1, bitsAbove = bits + 1;
    std::memcpy(&below, &bitsBelow, sizeof below);
    std::memcpy(&above, &bitsAbove, sizeof above);
    const double margin = y * 0x1p-36;
    if (y - 0.5 * (double(f) + double(below)) > margin &&
        0.5 * (double(f) + double(above)) - y > margin)
        return f;
    return static_cast<float>(std::acos(x));
}

// The angle of a triangle at corner p1 (between p1->p0 and p1->p2), both
// edges projected into the plane of the vertex normal n: the weight of the
// triangle's derivatives in the vertex average. As the reference: acos in
// double, rounded to float (the oracle's expression; the fast path computes
// the same cosine four corners at a time and rounds the angle with
// mikktspaceAnglesFromCos, which gives the same bits).
inline float cornerAngle(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& n) {
    const Vec3 v1 = projectToPlane(sub(p0, p1), n);
    const Vec3 v2 = projectToPlane(sub(p2, p1), n);
    float c = dot(v1, v2);
    c = c > 1.0f ? 1.0f : (c < -1.0f ? -1.0f : c);
    return static_cast<float>(std::acos(static_cast<double>(c)));
}

// Angle-weighted sum of the projected derivatives of one subgroup
// (EvalTspace); accumulate() in the subgroup's ascending triangle order,
// then finish().
struct FrameAccumulator {
    Vec3 vOs{0.0f, 0.0f, 0.0f};
    Vec3 vOt{0.0f, 0.0f, 0.0f};
    float magS = 0.0f;
    float magT = 0.0f;
    float angleSum = 0.0f;

    void accumulate(float angle, const Vec3& projOs, const Vec3& projOt, float triMagS,
                    float triMagT) {
        vOs = add(vOs, scale(angle, projOs));
        vOt = add(vOt, scale(angle, projOt));
        magS += angle * triMagS;
        magT += angle * triMagT;
        angleSum += angle;
    }
    void finish() {
        if (notZero(vOs)) vOs = normalize(vOs);
        if (notZero(vOt)) vOt = normalize(vOt);
        if (angleSum > 0.0f) {
            magS /= angleSum;
            magT /= angleSum;
        }
    }
};

// A corner's frame while it is being built (STSpace). `count` is how many
// triangles wrote it: the two triangles of a quad share two corners.
struct CornerSpace {
    Vec3 vOs{1.0f, 0.0f, 0.0f};
    float magS = 1.0f;
    Vec3 vOt{0.0f, 1.0f, 0.0f};
    float magT = 1.0f;
    int count = 0;
    bool orient = false;
};

// Averages the frame already in a quad corner with the second triangle's
// (AvgTSpace). Identical inputs are kept as they are: averaging them would
// change the last bit and split the vertex later.
inline CornerSpace averageSpaces(const CornerSpace& a, const CornerSpace& b) {
    CornerSpace r;
    if (a.magS == b.magS && a.magT == b.magT && exactlyEqual(a.vOs, b.vOs) &&
        exactlyEqual(a.vOt, b.vOt)) {
        r.magS = a.magS;
        r.magT = a.magT;
        r.vOs = a.vOs;
        r.vOt = a.vOt;
    } else {
        r.magS = 0.5f * (a.magS + b.magS);
        r.magT = 0.5f * (a.magT + b.magT);
        r.vOs = add(a.vOs, b.vOs);
        r.vOt = add(a.vOt, b.vOt);
        if (notZero(r.vOs)) r.vOs = normalize(r.vOs);
        if (notZero(r.vOt)) r.vOt = normalize(r.vOt);
    }
    return r;
}

// Writes one subgroup frame into a corner: the first write stores it, the
// second (quads) averages. The orientation is the group's.
inline void writeCornerSpace(CornerSpace& out, const FrameAccumulator& frame, bool orient) {
    CornerSpace s;
    s.vOs = frame.vOs;
    s.magS = frame.magS;
    s.vOt = frame.vOt;
    s.magT = frame.magT;
    if (out.count == 1) {
        out = averageSpaces(out, s);
        out.count = 2;
    } else {
        out = s;
        out.count = 1;
    }
    out.orient = orient;
}

inline MikkTSpaceFrame toFrame(const CornerSpace& s) {
    MikkTSpaceFrame f;
    f.tangent = toGlm(s.vOs);
    f.magS = s.magS;
    f.bitangent = toGlm(s.vOt);
    f.magT = s.magT;
    f.sign = s.orient ? 1.0f : -1.0f;
    return f;
}

// cos(180 degrees) as the reference computes its default angular threshold
// (float pi, cos in double, rounded to float): exactly -1.0f. Two frames of a
// group are kept together unless one of the cosines is <= -1.
inline float defaultThresholdCos() {
    return static_cast<float>(std::cos(static_cast<double>((180.0f * 3.14159265358979f) / 180.0f)));
}

// The number of triangles of an input (quads count 2; other faces 0).
size_t triangleCount(const MikkTSpaceInput& input);
// MikkTSpaceInput's preconditions as a contract check (abort in checked
// builds when mikktspaceInputProblem() names one); returns triangleCount().
size_t validateInput(const MikkTSpaceInput& input);

// Bit-level key of a float for hashing/ordering where -0 and +0 must be the
// same (the reference welds with ==).
inline uint32_t weldBits(float v) {
    const float w = v + 0.0f; // -0 + +0 = +0; other values unchanged
    uint32_t b;
    std::memcpy(&b, &w, sizeof b);
    return b;
}

} // namespace sg::mesh::mikk
