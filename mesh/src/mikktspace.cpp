// MikkTSpace, the fast implementation (Mikkelsen 2008, "Simulation of
// Wrinkled Surfaces Revisited", section 4.2; the published mikktspace.c
// algorithm with its default 180-degree threshold). Same stages as the
// oracle (mikktspace_reference.cpp, read that first) and the same float
// operations (mikktspace_common.h, or SIMD lanes doing exactly those IEEE
// operations in the same order); what changes is the data flow:
//
//  - the weld hashes INPUT VERTICES (not corners): corners that name the
//    same vertex have the same values, so V lookups instead of 3T, with the
//    table slot prefetched; welded ids are numbered densely in order of
//    first use and their values copied into one compact array;
//  - a vertex -> incident-corner table (counting sort; lists in ascending
//    triangle order; entries carry the previous and next welded vertex and
//    the triangle's flags) replaces the global edge sort AND the group
//    flood: the reference floods a group across the two edges at its
//    vertex, so pairing (step 6), groups (step 7) and frames (step 8) of a
//    vertex need only its own list. Vertices touching a group-with-any
//    triangle (whose orientation the first group reaching it sets) are
//    deferred and replayed in the reference's seed order;
//  - per-corner terms (projected derivatives, corner cosine) 4 or 8 corners
//    per SIMD step, angles 2 or 4 per step without libm's acos except near
//    float rounding boundaries (mikk::acosRoundedToFloat); the subgroup test
//    is settled in one dot product per member when every member is within
//    89 degrees of the first (the 180-degree threshold then cannot split);
//  - the per-entry gathers (the triangle's derivatives, the neighbours'
//    positions) are prefetched a few dozen entries ahead: they are the
//    scattered reads of the whole computation;
//  - a vertex whose corners all get one frame (the usual case) stores it
//    once; corner order is gathered at the end, in triangle order; all
//    buffers live in the generator and are reused between calls.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <limits>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
// x86-64 with GCC/Clang: an AVX2 copy of the SIMD kernels, chosen at run
// time when the CPU has AVX2 (same bits; see TermBatch::compute8Avx2).
#if defined(__SSE2__) && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SG_MIKK_AVX2 1
#include <immintrin.h>
#else
#define SG_MIKK_AVX2 0
#endif

#include "mikktspace_common.h"
#include "surfgrad/base/scratch_buffer.h"
#include "surfgrad/base/threads.h"

namespace sg::mesh {

std::string mikktspaceInputProblem(const MikkTSpaceInput& in) {
    const size_t vertexCount = in.positions.size();
    if (in.normals.size() != vertexCount || in.uvs.size() != vertexCount)
        return "MikkTSpace: positions (" + std::to_string(vertexCount) + "), normals (" +
               std::to_string(in.normals.size()) + ") and uvs (" + std::to_string(in.uvs.size()) +
               ") must have the same length";
    for (size_t v = 0; v < vertexCount; ++v) {
        const glm::vec3 p = in.positions[v], n = in.normals[v];
        const glm::vec2 t = in.uvs[v];
        // Bounds that keep every intermediate finite or +inf, never NaN
        // (products of two coordinate differences <= 2^122; normals are
        // meant to be unit vectors). NaN fails every comparison.
        constexpr float kMaxCoord = 0x1p60f, kMaxNormal = 16.0f;
        if (!(std::fabs(p.x) <= kMaxCoord && std::fabs(p.y) <= kMaxCoord &&
              std::fabs(p.z) <= kMaxCoord && std::fabs(t.x) <= kMaxCoord &&
              std::fabs(t.y) <= kMaxCoord && std::fabs(n.x) <= kMaxNormal &&
              std::fabs(n.y) <= kMaxNormal && std::fabs(n.z) <= kMaxNormal))
            return "MikkTSpace: vertex " + std::to_string(v) +
                   " has a non-finite or out-of-range position, normal or uv "
                   "(|position|, |uv| <= 2^60, |normal component| <= 16)";
    }
    const size_t cornerCount = in.cornerVertices.size();
    if (in.faceSizes.empty()) {
        if (cornerCount % 3 != 0)
            return "MikkTSpace: " + std::to_string(cornerCount) +
                   " corners is not a multiple of 3 (no face sizes given)";
    } else {
        size_t sum = 0;
        for (const uint32_t n : in.faceSizes) {
            sum += n;
            if (sum > cornerCount) break;
        }
        if (sum != cornerCount)
            return "MikkTSpace: face sizes do not sum to the " + std::to_string(cornerCount) +
                   " corners";
    }
    const size_t triangles = mikk::triangleCount(in);
    if (triangles >= (size_t(1) << 28))
        return "MikkTSpace: too many triangles (" + std::to_string(triangles) + ", limit 2^28)";
    for (size_t c = 0; c < cornerCount; ++c)
        if (in.cornerVertices[c] >= vertexCount)
            return "MikkTSpace: corner " + std::to_string(c) + " names vertex " +
                   std::to_string(in.cornerVertices[c]) + " of " + std::to_string(vertexCount);
    return {};
}

namespace mikk {

size_t triangleCount(const MikkTSpaceInput& in) {
    if (in.faceSizes.empty()) return in.cornerVertices.size() / 3;
    size_t triangles = 0;
    for (const uint32_t n : in.faceSizes) triangles += n == 3 ? 1 : (n == 4 ? 2 : 0);
    return triangles;
}

size_t validateInput(const MikkTSpaceInput& in) {
    SG_EXPECTS(mikktspaceInputProblem(in).empty(),
               "MikkTSpaceInput preconditions (surfgrad/mesh/tangents.h); untrusted meshes are "
               "checked with mikktspaceInputProblem() first");
    return triangleCount(in);
}

} // namespace mikk

float mikktspaceAngleFromCos(float cosine) {
    return mikk::acosRoundedToFloat(cosine);
}

// mikk::acosRoundedToFloat two values at a time (SSE2 doubles): the same
// double operations in the same order per lane, then the same margin test;
// lanes that fail it (and c == 1, whose neighbour test reads a NaN) call
// libm's acos.
namespace {

bool cpuHasAvx2() {
#if SG_MIKK_AVX2
    static const bool has = __builtin_cpu_supports("avx2");
    return has;
#else
    return false;
#endif
}

#if SG_MIKK_AVX2
// The SSE2 loop of mikktspaceAnglesFromCos four values at a time; returns
// how many values it did (a multiple of 4).
__attribute__((target("avx2"))) size_t anglesFromCosAvx2(float* values, size_t n) {
    const __m256d half = _mm256_set1_pd(0.5), one = _mm256_set1_pd(1.0), two = _mm256_set1_pd(2.0);
    const __m256d pi = _mm256_set1_pd(3.141592653589793115997963468544185161590576171875);
    const __m256d halfPi = _mm256_set1_pd(1.5707963267948965579989817342720925807952880859375);
    const __m256d signBit = _mm256_set1_pd(-0.0), zero = _mm256_setzero_pd();
    const __m256d marginScale = _mm256_set1_pd(0x1p-36);
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        float* v = values + i;
        const __m128 cf = _mm_loadu_ps(v);
        const __m256d x = _mm256_cvtps_pd(cf);
        const __m256d a = _mm256_andnot_pd(signBit, x);
        const __m256d small = _mm256_cmp_pd(a, half, _CMP_LE_OQ);
        const __m256d zBig = _mm256_mul_pd(_mm256_sub_pd(one, a), half);
        const __m256d z = _mm256_blendv_pd(zBig, _mm256_mul_pd(x, x), small);
        __m256d q = _mm256_set1_pd(mikk::kAcosQ[0]);
#pragma GCC unroll 10
        for (int k = 1; k < 10; ++k)
            q = _mm256_add_pd(_mm256_mul_pd(q, z), _mm256_set1_pd(mikk::kAcosQ[k]));
        const __m256d r = _mm256_blendv_pd(_mm256_sqrt_pd(zBig), x, small);
        const __m256d asinR = _mm256_add_pd(r, _mm256_mul_pd(_mm256_mul_pd(r, z), q));
        const __m256d twoAsin = _mm256_mul_pd(two, asinR);
        const __m256d yBig = _mm256_blendv_pd(_mm256_sub_pd(pi, twoAsin), twoAsin,
                                              _mm256_cmp_pd(x, zero, _CMP_GT_OQ));
        const __m256d y = _mm256_blendv_pd(yBig, _mm256_sub_pd(halfPi, asinR), small);
        const __m128 f = _mm256_cvtpd_ps(y);
        const __m128i bits = _mm_castps_si128(f);
        const __m256d fd = _mm256_cvtps_pd(f);
        const __m256d below =
            _mm256_cvtps_pd(_mm_castsi128_ps(_mm_sub_epi32(bits, _mm_set1_epi32(1))));
        const __m256d above =
            _mm256_cvtps_pd(_mm_castsi128_ps(_mm_add_epi32(bits, _mm_set1_epi32(1))));
        const __m256d margin = _mm256_mul_pd(y, marginScale);
        const __m256d ok = _mm256_and_pd(
            _mm256_cmp_pd(_mm256_sub_pd(y, _mm256_mul_pd(half, _mm256_add_pd(fd, below))), margin,
                          _CMP_GT_OQ),
            _mm256_cmp_pd(_mm256_sub_pd(_mm256_mul_pd(half, _mm256_add_pd(fd, above)), y), margin,
                          _CMP_GT_OQ));
        const int okBits = _mm256_movemask_pd(ok);
        alignas(16) float in[4], out[4];
        _mm_store_ps(in, cf);
        _mm_store_ps(out, f);
        for (int l = 0; l < 4; ++l)
            v[l] = (okBits >> l) & 1 ? out[l]
                                     : static_cast<float>(std::acos(static_cast<double>(in[l])));
    }
    return i;
}
#endif

} // namespace

void mikktspaceAnglesFromCos(std::span<float> values, bool allowWideSimd) {
    size_t i = 0;
#if SG_MIKK_AVX2
    if (allowWideSimd && cpuHasAvx2()) i = anglesFromCosAvx2(values.data(), values.size());
#else
    (void)allowWideSimd;
#endif
#if defined(__SSE2__)
    const __m128d half = _mm_set1_pd(0.5), one = _mm_set1_pd(1.0), two = _mm_set1_pd(2.0);
    const __m128d pi = _mm_set1_pd(3.141592653589793115997963468544185161590576171875);
    const __m128d halfPi = _mm_set1_pd(1.5707963267948965579989817342720925807952880859375);
    const __m128d signBit = _mm_set1_pd(-0.0), zero = _mm_setzero_pd();
    const __m128d marginScale = _mm_set1_pd(0x1p-36);
    auto blend = [](__m128d mask, __m128d a, __m128d b) {
        return _mm_or_pd(_mm_and_pd(mask, a), _mm_andnot_pd(mask, b));
    };
    for (; i + 2 <= values.size(); i += 2) {
        float* v = values.data() + i;
        const float c0 = v[0], c1 = v[1];
        const __m128d x = _mm_cvtps_pd(_mm_setr_ps(c0, c1, 0.0f, 0.0f));
        const __m128d a = _mm_andnot_pd(signBit, x);
        const __m128d small = _mm_cmple_pd(a, half);
        const __m128d zBig = _mm_mul_pd(_mm_sub_pd(one, a), half);
        const __m128d z = blend(small, _mm_mul_pd(x, x), zBig);
        __m128d q = _mm_set1_pd(mikk::kAcosQ[0]);
#pragma GCC unroll 10
        for (int k = 1; k < 10; ++k) q = _mm_add_pd(_mm_mul_pd(q, z), _mm_set1_pd(mikk::kAcosQ[k]));
        const __m128d r = blend(small, x, _mm_sqrt_pd(zBig));
        const __m128d asinR = _mm_add_pd(r, _mm_mul_pd(_mm_mul_pd(r, z), q));
        const __m128d twoAsin = _mm_mul_pd(two, asinR);
        const __m128d yBig = blend(_mm_cmpgt_pd(x, zero), twoAsin, _mm_sub_pd(pi, twoAsin));
        const __m128d y = blend(small, _mm_sub_pd(halfPi, asinR), yBig);
        const __m128 f = _mm_cvtpd_ps(y);
        const __m128i bits = _mm_castps_si128(f);
        const __m128d fd = _mm_cvtps_pd(f);
        const __m128d below =
            _mm_cvtps_pd(_mm_castsi128_ps(_mm_sub_epi32(bits, _mm_set1_epi32(1))));
        const __m128d above =
            _mm_cvtps_pd(_mm_castsi128_ps(_mm_add_epi32(bits, _mm_set1_epi32(1))));
        const __m128d margin = _mm_mul_pd(y, marginScale);
        const __m128d ok = _mm_and_pd(
            _mm_cmpgt_pd(_mm_sub_pd(y, _mm_mul_pd(half, _mm_add_pd(fd, below))), margin),
            _mm_cmpgt_pd(_mm_sub_pd(_mm_mul_pd(half, _mm_add_pd(fd, above)), y), margin));
        alignas(16) float out[4];
        _mm_store_ps(out, f);
        const int okBits = _mm_movemask_pd(ok);
        v[0] = (okBits & 1) ? out[0] : static_cast<float>(std::acos(static_cast<double>(c0)));
        v[1] = (okBits & 2) ? out[1] : static_cast<float>(std::acos(static_cast<double>(c1)));
    }
#endif
    for (; i < values.size(); ++i) values[i] = mikk::acosRoundedToFloat(values[i]);
}

namespace {

using mikk::Vec3;

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

// Triangle flags.
constexpr uint8_t kOrient = 1;       // orientation preserving
constexpr uint8_t kAny = 2;          // group-with-any (zero UV area or magnitude)
constexpr uint8_t kQuadOneDegen = 4; // quad whose other triangle is degenerate
constexpr uint8_t kGrouped0 = 8;     // corner 0 is in a group (then 16, 32)
constexpr uint8_t kGroupedAll = 8 | 16 | 32;
constexpr uint8_t kDegenerate = 64; // two corners at one position (steps 3-5 only)

// An entry of the vertex -> incident corners table.
struct Incidence {
    // Good triangle index << 4 | group-with-any << 3 | orientation << 2 |
    // corner (0..2) at the vertex. The two flag bits are the triangle's at
    // step 6; a deferred vertex reads the live orientation from the flags.
    uint32_t packed;
    uint32_t prev; // welded id of the previous corner of that triangle
    uint32_t next; // welded id of the next corner

    uint32_t tri() const { return packed >> 4; }
    uint32_t corner() const { return packed & 3u; }
    bool orient() const { return (packed & 4u) != 0; }
    bool any() const { return (packed & 8u) != 0; }
};

// 32 bytes, 32-aligned: the 16-byte loads of the SIMD kernels (position,
// normal) never straddle a cache line, and one prefetch brings a vertex.
struct alignas(32) WeldedVertex {
    Vec3 position;
    Vec3 normal;
    glm::vec2 uv;
};

// A good triangle's normalized first-order derivatives (eq. 18/19) and
// magnitudes, one half cache line: the term kernels load os and ot (16
// bytes each, the magnitude riding along) and the accumulation reads the
// magnitudes from the same line.
struct alignas(32) TriDerivatives {
    Vec3 os;
    float magS;
    Vec3 ot;
    float magT;
};

// A corner of one triangle range at a vertex another range owns (step 6).
struct Spill {
    uint32_t vertex;
    Incidence entry;
};

// Per-entry terms of a vertex's incidence list, structure of arrays: the
// derivatives projected into the plane of the vertex normal, and the
// corner angle (first the clamped cosine, then the angle).
struct Terms {
    float *osx, *osy, *osz, *otx, *oty, *otz, *angle;

    static Terms over(float* base, size_t capacity) {
        return {base,
                base + capacity,
                base + 2 * capacity,
                base + 3 * capacity,
                base + 4 * capacity,
                base + 5 * capacity,
                base + 6 * capacity};
    }
    Terms offset(size_t j) const {
        return {osx + j, osy + j, osz + j, otx + j, oty + j, otz + j, angle + j};
    }
    Vec3 os(size_t e) const { return {osx[e], osy[e], osz[e]}; }
    Vec3 ot(size_t e) const { return {otx[e], oty[e], otz[e]}; }
};

// Four entries' terms at once: mikk::projectToPlane and the cosine of
// mikk::cornerAngle with the same operations in the same order on each
// lane (SSE2 when available: its add/mul/div/sqrt are the same IEEE
// operations as the scalar ones, so the bits are the same).
struct TermBatch {
    static constexpr size_t kLanes = 8; // one AVX2 step or two SSE2 steps
    // Per lane: the triangle's derivatives, the vertex (normal, position)
    // and the previous and next corners' positions.
    const TriDerivatives* deriv[kLanes];
    const WeldedVertex* vertex[kLanes];
    const WeldedVertex* prev[kLanes];
    const WeldedVertex* next[kLanes];

    void set(size_t lane, const TriDerivatives* d, const WeldedVertex* w, const WeldedVertex* p,
             const WeldedVertex* n) {
        deriv[lane] = d, vertex[lane] = w, prev[lane] = p, next[lane] = n;
    }
    void copyLane(size_t to, size_t from) {
        set(to, deriv[from], vertex[from], prev[from], next[from]);
    }

#if defined(__SSE2__)
    struct V {
        __m128 x, y, z;
    };
    // Four 16-byte loads (x, y, z and the float that follows, which is in
    // bounds: TriDerivatives and WeldedVertex hold more after each Vec3),
    // transposed.
    static V gather(const float* a, const float* b, const float* c, const float* d) {
        __m128 r0 = _mm_loadu_ps(a), r1 = _mm_loadu_ps(b), r2 = _mm_loadu_ps(c),
               r3 = _mm_loadu_ps(d);
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        return {r0, r1, r2};
    }
    static __m128 dot4(const V& a, const V& b) {
        return _mm_add_ps(_mm_add_ps(_mm_mul_ps(a.x, b.x), _mm_mul_ps(a.y, b.y)),
                          _mm_mul_ps(a.z, b.z));
    }
    static V project4(const V& v, const V& n) {
        const __m128 d = dot4(n, v);
        const V r{_mm_sub_ps(v.x, _mm_mul_ps(d, n.x)), _mm_sub_ps(v.y, _mm_mul_ps(d, n.y)),
                  _mm_sub_ps(v.z, _mm_mul_ps(d, n.z))};
        const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7FFFFFFF));
        const __m128 tiny = _mm_set1_ps(FLT_MIN);
        const __m128 nonZero = _mm_or_ps(_mm_or_ps(_mm_cmpgt_ps(_mm_and_ps(r.x, absMask), tiny),
                                                   _mm_cmpgt_ps(_mm_and_ps(r.y, absMask), tiny)),
                                         _mm_cmpgt_ps(_mm_and_ps(r.z, absMask), tiny));
        // Lanes that stay unnormalized may divide by zero here; their
        // result is discarded by the select.
        const __m128 inv = _mm_div_ps(_mm_set1_ps(1.0f), _mm_sqrt_ps(dot4(r, r)));
        auto select = [&](__m128 normalized, __m128 raw) {
            return _mm_or_ps(_mm_and_ps(nonZero, normalized), _mm_andnot_ps(nonZero, raw));
        };
        return {select(_mm_mul_ps(inv, r.x), r.x), select(_mm_mul_ps(inv, r.y), r.y),
                select(_mm_mul_ps(inv, r.z), r.z)};
    }
    static V sub4(const V& a, const V& b) {
        return {_mm_sub_ps(a.x, b.x), _mm_sub_ps(a.y, b.y), _mm_sub_ps(a.z, b.z)};
    }

    // Lanes first..first+3 into out at j.
    void compute4(const Terms& out, size_t j, int first) const {
        auto rows = [&](auto field) {
            return gather(field(first), field(first + 1), field(first + 2), field(first + 3));
        };
        const V os = rows([&](int l) { return &deriv[l]->os.x; });
        const V ot = rows([&](int l) { return &deriv[l]->ot.x; });
        const V n = rows([&](int l) { return &vertex[l]->normal.x; });
        const V p = rows([&](int l) { return &vertex[l]->position.x; });
        const V pp = rows([&](int l) { return &prev[l]->position.x; });
        const V pn = rows([&](int l) { return &next[l]->position.x; });
        const V pos = project4(os, n), pot = project4(ot, n);
        const V e1 = project4(sub4(pp, p), n), e2 = project4(sub4(pn, p), n);
        const __m128 c =
            _mm_min_ps(_mm_max_ps(dot4(e1, e2), _mm_set1_ps(-1.0f)), _mm_set1_ps(1.0f));
        _mm_storeu_ps(out.osx + j, pos.x);
        _mm_storeu_ps(out.osy + j, pos.y);
        _mm_storeu_ps(out.osz + j, pos.z);
        _mm_storeu_ps(out.otx + j, pot.x);
        _mm_storeu_ps(out.oty + j, pot.y);
        _mm_storeu_ps(out.otz + j, pot.z);
        _mm_storeu_ps(out.angle + j, c);
    }
#if SG_MIKK_AVX2
    __attribute__((target("avx2"))) void compute8Avx2(const Terms& out, size_t j) const;
#endif
    // All kLanes lanes into out at j.
    void compute(const Terms& out, size_t j, bool wide) const {
#if SG_MIKK_AVX2
        if (wide) {
            compute8Avx2(out, j);
            return;
        }
#endif
        (void)wide;
        compute4(out, j, 0);
        compute4(out, j + 4, 4);
    }
#else
    void compute(const Terms& out, size_t j, bool /*wide*/) const {
        for (size_t lane = 0; lane < kLanes; ++lane) {
            const Vec3 n = vertex[lane]->normal, p = vertex[lane]->position;
            const Vec3 os = mikk::projectToPlane(deriv[lane]->os, n);
            const Vec3 ot = mikk::projectToPlane(deriv[lane]->ot, n);
            const Vec3 e1 = mikk::projectToPlane(mikk::sub(prev[lane]->position, p), n);
            const Vec3 e2 = mikk::projectToPlane(mikk::sub(next[lane]->position, p), n);
            float c = mikk::dot(e1, e2);
            c = c > 1.0f ? 1.0f : (c < -1.0f ? -1.0f : c);
            out.osx[j + lane] = os.x, out.osy[j + lane] = os.y, out.osz[j + lane] = os.z;
            out.otx[j + lane] = ot.x, out.oty[j + lane] = ot.y, out.otz[j + lane] = ot.z;
            out.angle[j + lane] = c;
        }
    }
#endif
};

#if SG_MIKK_AVX2
// The same as two compute4 calls, eight lanes per AVX2 instruction (the
// same IEEE operations per lane; no FMA: the target is "avx2" only and the
// file is compiled with -ffp-contract=off). Helpers are functions, not
// lambdas: a lambda does not inherit the target attribute.
#define SG_AVX2 __attribute__((target("avx2")))
struct W8 {
    __m256 x, y, z;
};
SG_AVX2 inline W8 gather8(const float* const* ptr) {
    const TermBatch::V lo = TermBatch::gather(ptr[0], ptr[1], ptr[2], ptr[3]);
    const TermBatch::V hi = TermBatch::gather(ptr[4], ptr[5], ptr[6], ptr[7]);
    return {_mm256_insertf128_ps(_mm256_castps128_ps256(lo.x), hi.x, 1),
            _mm256_insertf128_ps(_mm256_castps128_ps256(lo.y), hi.y, 1),
            _mm256_insertf128_ps(_mm256_castps128_ps256(lo.z), hi.z, 1)};
}
SG_AVX2 inline __m256 dot8(const W8& a, const W8& b) {
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(a.x, b.x), _mm256_mul_ps(a.y, b.y)),
                         _mm256_mul_ps(a.z, b.z));
}
SG_AVX2 inline W8 sub8(const W8& a, const W8& b) {
    return {_mm256_sub_ps(a.x, b.x), _mm256_sub_ps(a.y, b.y), _mm256_sub_ps(a.z, b.z)};
}
SG_AVX2 inline W8 project8(const W8& v, const W8& n) {
    const __m256 absMask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7FFFFFFF));
    const __m256 tiny = _mm256_set1_ps(FLT_MIN);
    const __m256 d = dot8(n, v);
    const W8 r{_mm256_sub_ps(v.x, _mm256_mul_ps(d, n.x)), _mm256_sub_ps(v.y, _mm256_mul_ps(d, n.y)),
               _mm256_sub_ps(v.z, _mm256_mul_ps(d, n.z))};
    const __m256 nonZero =
        _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(_mm256_and_ps(r.x, absMask), tiny, _CMP_GT_OQ),
                                  _mm256_cmp_ps(_mm256_and_ps(r.y, absMask), tiny, _CMP_GT_OQ)),
                     _mm256_cmp_ps(_mm256_and_ps(r.z, absMask), tiny, _CMP_GT_OQ));
    const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(dot8(r, r)));
    return {_mm256_blendv_ps(r.x, _mm256_mul_ps(inv, r.x), nonZero),
            _mm256_blendv_ps(r.y, _mm256_mul_ps(inv, r.y), nonZero),
            _mm256_blendv_ps(r.z, _mm256_mul_ps(inv, r.z), nonZero)};
}

SG_AVX2 void TermBatch::compute8Avx2(const Terms& out, size_t j) const {
    const float* ptr[6][kLanes];
    for (size_t l = 0; l < kLanes; ++l) {
        ptr[0][l] = &deriv[l]->os.x;
        ptr[1][l] = &deriv[l]->ot.x;
        ptr[2][l] = &vertex[l]->normal.x;
        ptr[3][l] = &vertex[l]->position.x;
        ptr[4][l] = &prev[l]->position.x;
        ptr[5][l] = &next[l]->position.x;
    }
    const W8 n = gather8(ptr[2]), p = gather8(ptr[3]);
    const W8 pos = project8(gather8(ptr[0]), n), pot = project8(gather8(ptr[1]), n);
    const W8 e1 = project8(sub8(gather8(ptr[4]), p), n), e2 = project8(sub8(gather8(ptr[5]), p), n);
    const __m256 c =
        _mm256_min_ps(_mm256_max_ps(dot8(e1, e2), _mm256_set1_ps(-1.0f)), _mm256_set1_ps(1.0f));
    _mm256_storeu_ps(out.osx + j, pos.x);
    _mm256_storeu_ps(out.osy + j, pos.y);
    _mm256_storeu_ps(out.osz + j, pos.z);
    _mm256_storeu_ps(out.otx + j, pot.x);
    _mm256_storeu_ps(out.oty + j, pot.y);
    _mm256_storeu_ps(out.otz + j, pot.z);
    _mm256_storeu_ps(out.angle + j, c);
}
#endif

// Hash of a vertex's weld key (position, normal, uv with -0 as +0): four
// independent 64-bit products (short dependency chain), then one final
// mix. Only equal keys must hash equal; quality only affects speed.
inline uint64_t weldHash(const glm::vec3& p, const glm::vec3& n, const glm::vec2& uv) {
    auto pair = [](float a, float b) {
        return uint64_t(mikk::weldBits(a)) | uint64_t(mikk::weldBits(b)) << 32;
    };
    uint64_t h = pair(p.x, p.y) * 0x9E3779B97F4A7C15ull;
    h ^= pair(p.z, n.x) * 0xC2B2AE3D27D4EB4Full;
    h ^= pair(n.y, n.z) * 0x165667B19E3779F9ull;
    h ^= pair(uv.x, uv.y) * 0xD6E8FEB86659FD93ull;
    h ^= h >> 32;
    h *= 0x94D049BB133111EBull;
    return h ^ (h >> 29);
}

#if defined(__SSE2__)
// mikk::faceDerivatives for four triangles at once (welded ids tri[0..11]):
// the same IEEE operations per lane; lanes whose UV area or lengths are
// zero compute garbage that the masks discard, exactly as the scalar
// branches skip it. Writes deriv[0..3] (two 16-byte stores each: os with
// magS, ot with magT), ORs the orientation, group-with-any and degenerate
// (two corners at one position, mikk::exactlyEqual) bits into flags[0..3]
// and returns how many of the four are degenerate.
size_t faceDerivatives4(const WeldedVertex* wv, const uint32_t* tri, TriDerivatives* deriv,
                        uint8_t* flags) {
    auto positions = [&](int corner) {
        __m128 r0 = _mm_loadu_ps(&wv[tri[corner]].position.x);
        __m128 r1 = _mm_loadu_ps(&wv[tri[3 + corner]].position.x);
        __m128 r2 = _mm_loadu_ps(&wv[tri[6 + corner]].position.x);
        __m128 r3 = _mm_loadu_ps(&wv[tri[9 + corner]].position.x);
        _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
        return TermBatch::V{r0, r1, r2};
    };
    auto uvs = [&](int corner, __m128& u, __m128& v) {
        auto load = [&](int lane) {
            return _mm_castpd_ps(
                _mm_load_sd(reinterpret_cast<const double*>(&wv[tri[3 * lane + corner]].uv.x)));
        };
        const __m128 lo = _mm_unpacklo_ps(load(0), load(1)); // u0 u1 v0 v1
        const __m128 hi = _mm_unpacklo_ps(load(2), load(3)); // u2 u3 v2 v3
        u = _mm_movelh_ps(lo, hi);
        v = _mm_movehl_ps(hi, lo);
    };
    const TermBatch::V p1 = positions(0), p2 = positions(1), p3 = positions(2);
    __m128 u1, v1, u2, v2, u3, v3;
    uvs(0, u1, v1);
    uvs(1, u2, v2);
    uvs(2, u3, v3);
    const __m128 t21x = _mm_sub_ps(u2, u1), t21y = _mm_sub_ps(v2, v1);
    const __m128 t31x = _mm_sub_ps(u3, u1), t31y = _mm_sub_ps(v3, v1);
    const TermBatch::V d1 = TermBatch::sub4(p2, p1), d2 = TermBatch::sub4(p3, p1);
    const __m128 area = _mm_sub_ps(_mm_mul_ps(t21x, t31y), _mm_mul_ps(t21y, t31x));
    const __m128 signBit = _mm_set1_ps(-0.0f);
    const __m128 negT31x = _mm_xor_ps(t31x, signBit);
    const TermBatch::V os{_mm_sub_ps(_mm_mul_ps(t31y, d1.x), _mm_mul_ps(t21y, d2.x)),
                          _mm_sub_ps(_mm_mul_ps(t31y, d1.y), _mm_mul_ps(t21y, d2.y)),
                          _mm_sub_ps(_mm_mul_ps(t31y, d1.z), _mm_mul_ps(t21y, d2.z))};
    const TermBatch::V ot{_mm_add_ps(_mm_mul_ps(negT31x, d1.x), _mm_mul_ps(t21x, d2.x)),
                          _mm_add_ps(_mm_mul_ps(negT31x, d1.y), _mm_mul_ps(t21x, d2.y)),
                          _mm_add_ps(_mm_mul_ps(negT31x, d1.z), _mm_mul_ps(t21x, d2.z))};
    const __m128 zero = _mm_setzero_ps(), tiny = _mm_set1_ps(FLT_MIN);
    const __m128 orient = _mm_cmpgt_ps(area, zero);
    const __m128 absArea = _mm_andnot_ps(signBit, area);
    const __m128 areaOk = _mm_cmpgt_ps(absArea, tiny);
    const __m128 lenOs = _mm_sqrt_ps(TermBatch::dot4(os, os));
    const __m128 lenOt = _mm_sqrt_ps(TermBatch::dot4(ot, ot));
    const __m128 flip =
        _mm_or_ps(_mm_and_ps(orient, _mm_set1_ps(1.0f)), _mm_andnot_ps(orient, _mm_set1_ps(-1.0f)));
    const __m128 osOk = _mm_and_ps(areaOk, _mm_cmpgt_ps(lenOs, tiny));
    const __m128 otOk = _mm_and_ps(areaOk, _mm_cmpgt_ps(lenOt, tiny));
    const __m128 sOs = _mm_div_ps(flip, lenOs), sOt = _mm_div_ps(flip, lenOt);
    auto keep = [](__m128 mask, __m128 v) { return _mm_and_ps(mask, v); };
    __m128 ox = keep(osOk, _mm_mul_ps(sOs, os.x)), oy = keep(osOk, _mm_mul_ps(sOs, os.y));
    __m128 oz = keep(osOk, _mm_mul_ps(sOs, os.z));
    __m128 tx = keep(otOk, _mm_mul_ps(sOt, ot.x)), ty = keep(otOk, _mm_mul_ps(sOt, ot.y));
    __m128 tz = keep(otOk, _mm_mul_ps(sOt, ot.z));
    const __m128 mS = keep(areaOk, _mm_div_ps(lenOs, absArea));
    const __m128 mT = keep(areaOk, _mm_div_ps(lenOt, absArea));
    __m128 o4 = mS, t4 = mT; // transposed: {os, magS}, {ot, magT} per triangle
    const __m128 good =
        _mm_and_ps(areaOk, _mm_and_ps(_mm_cmpgt_ps(_mm_andnot_ps(signBit, mS), tiny),
                                      _mm_cmpgt_ps(_mm_andnot_ps(signBit, mT), tiny)));
    _MM_TRANSPOSE4_PS(ox, oy, oz, o4);
    _MM_TRANSPOSE4_PS(tx, ty, tz, t4);
    const __m128 osLane[4] = {ox, oy, oz, o4}, otLane[4] = {tx, ty, tz, t4};
    for (int l = 0; l < 4; ++l) {
        _mm_store_ps(&deriv[l].os.x, osLane[l]);
        _mm_store_ps(&deriv[l].ot.x, otLane[l]);
    }
    auto same = [](const TermBatch::V& a, const TermBatch::V& b) {
        return _mm_and_ps(_mm_and_ps(_mm_cmpeq_ps(a.x, b.x), _mm_cmpeq_ps(a.y, b.y)),
                          _mm_cmpeq_ps(a.z, b.z));
    };
    const int degenerateBits =
        _mm_movemask_ps(_mm_or_ps(_mm_or_ps(same(p1, p2), same(p1, p3)), same(p2, p3)));
    const int orientBits = _mm_movemask_ps(orient), goodBits = _mm_movemask_ps(good);
    for (int l = 0; l < 4; ++l)
        flags[l] |=
            uint8_t(((orientBits >> l) & 1 ? kOrient : 0) | ((goodBits >> l) & 1 ? 0 : kAny) |
                    ((degenerateBits >> l) & 1 ? kDegenerate : 0));
    return size_t(__builtin_popcount(unsigned(degenerateBits)));
}
#endif

} // namespace

namespace {

using sg::detail::ScratchVector;

// Steps 7-8 scratch, one per thread.
struct FrameScratch {
    // Terms of a chunk of vertices' entries (Terms layout).
    std::vector<float> terms;
    std::vector<int32_t> outNbr, inNbr, component;
    std::vector<uint64_t> halfEdges;
    std::vector<uint8_t> paired;
    std::vector<uint32_t> members;             // also the flood stack (clean vertices)
    std::vector<uint32_t> stack, groupMembers; // deferred vertices
};

// The generator's buffers, reused between calls.
struct Buffers {
    // Triangulation (only filled when faceSizes is given).
    ScratchVector<uint32_t> triVertex; // input vertex per triangle corner
    ScratchVector<uint32_t> triCorner; // output corner per triangle corner
    ScratchVector<uint32_t> triFace;   // original face per triangle
    ScratchVector<uint8_t> triVertInFace;
    // Welding.
    ScratchVector<uint32_t> vertexClass; // input vertex -> welded id
    ScratchVector<uint32_t> firstUse;    // input vertices in order of first use
    ScratchVector<uint64_t> hashes;      // of firstUse's values
    ScratchVector<WeldedVertex> staged;  // firstUse's values (becomes `welded` without duplicates)
    ScratchVector<uint32_t> stagedId;    // firstUse index -> welded id
    ScratchVector<uint64_t> hashTable;   // hash bits 32..63 | welded id; ~0 = empty
    ScratchVector<WeldedVertex> welded;
    ScratchVector<uint32_t> triWelded; // welded id per triangle corner (all triangles)
    // Degenerate handling and the good-first order.
    ScratchVector<uint8_t> quadOneDegen; // only with quads and degenerates
    ScratchVector<uint32_t> order; // good triangles then degenerate ones (only if any degenerate)
    ScratchVector<uint32_t> goodWelded, goodCorner, goodFace;
    ScratchVector<uint8_t> goodVertInFace;
    // Per good triangle.
    ScratchVector<TriDerivatives> deriv;
    ScratchVector<uint8_t> flags;
    // Vertex -> incident corners.
    ScratchVector<uint32_t> incidenceStart;
    ScratchVector<Incidence> incidence;
    ScratchVector<glm::vec4> vertexOut; // one frame per welded vertex, or w = 0: see entryOut
    ScratchVector<glm::vec4> entryOut;  // results in incidence order (vertices with w = 0)
    // Vertices touching group-with-any triangles (1 per welded vertex).
    ScratchVector<uint8_t> isDeferred;
    // Output stage.
    ScratchVector<mikk::CornerSpace> spaces; // quads or full frames requested
    ScratchVector<uint32_t> firstGoodCorner;
    // Parallel steps only: per-block counts, the incidence fill cursors,
    // the weld's table slot then class representative per staged vertex.
    ScratchVector<size_t> blockCounts;
    ScratchVector<uint32_t> cursor, repOf;
    // Step 6 in parallel: the owner ranges' first welded ids, and each
    // triangle range's corners at other ranges' vertices.
    std::vector<uint32_t> ownStart;
    std::vector<std::vector<Spill>> spills;
    std::vector<MikkTSpaceStepTime> stepTimes;
    // Steps 7-8 scratch: the calling thread's, and each worker's.
    FrameScratch frameScratch;
    tbb::enumerable_thread_specific<FrameScratch> threadScratch;
};

// Parallel loops split [0, n) into fixed blocks: the boundaries depend on n
// only, never on the thread count or the scheduling, and every step is
// written so that its result does not depend on them either (per-element
// work, or per-block counts combined in block order).
struct Blocks {
    size_t size = 0, count = 0;
};
constexpr size_t kBlocksPerLoop = 256;
constexpr size_t kMinBlock = 8;

// Blocks of a multiple of `align` elements.
Blocks blocksOf(size_t n, size_t align) {
    size_t size = std::max((n + kBlocksPerLoop - 1) / kBlocksPerLoop, kMinBlock);
    size = (size + align - 1) / align * align;
    return {size, (n + size - 1) / size};
}

// One generate() call: its input and buffers, and what each step hands on
// to the next (the steps are numbered as in docs/tangents.md).
struct Pass {
    Pass(const MikkTSpaceInput& input, Buffers& buffers, std::vector<MikkTSpaceFrame>* f)
        : in(input), s(buffers), frames(f) {}

    const MikkTSpaceInput& in;
    Buffers& s;
    // Inside a task arena: loops run as parallel blocks; otherwise one block.
    bool parallel = false;

    Blocks blocks(size_t n, size_t align = 1) const {
        if (!parallel) return {n, n == 0 ? size_t(0) : size_t(1)};
        return blocksOf(n, align);
    }
    // f(block, begin, end) for every block of b over [0, n).
    template <typename F>
    void forBlocks(const Blocks& b, size_t n, F&& f) const {
        if (b.count == 1) {
            f(size_t(0), size_t(0), n);
            return;
        }
        tbb::parallel_for(
            size_t(0), b.count, [&](size_t k) { f(k, k * b.size, std::min(n, (k + 1) * b.size)); },
            tbb::simple_partitioner());
    }
    template <typename F>
    void forBlocks(size_t n, size_t align, F&& f) const {
        forBlocks(blocks(n, align), n, f);
    }
    // Exclusive prefix sum of s.blockCounts[0..count) in place; returns the total.
    size_t prefixBlockCounts(size_t count) const {
        size_t total = 0;
        for (size_t k = 0; k < count; ++k) {
            const size_t c = s.blockCounts[k];
            s.blockCounts[k] = total;
            total += c;
        }
        return total;
    }
    std::vector<MikkTSpaceFrame>* frames; // complete frames requested, or nullptr
    size_t triCount = 0, cornerCount = 0;
    bool trianglesOnly = true; // no faceSizes, or every face a triangle
    bool hasQuads = false;     // faces are given and not all triangles
    // Results go to per-corner spaces (s.spaces: quads average two frames,
    // frames need the magnitudes) instead of straight to the tangents.
    bool fullSpaces = false;
    glm::vec4* tangentsOut = nullptr;
    // Step 1: the input vertex of each triangle corner.
    const uint32_t* triVertex = nullptr;
    // Step 2: the welded vertices.
    const WeldedVertex* wv = nullptr;
    size_t weldedCount = 0;
    // Steps 3-5.
    size_t degenerateCount = 0, goodCount = 0;
    // Triangles in the good-first order: welded ids per corner, output
    // corner per corner (null: corner j is output corner j), face per
    // triangle (null: triangle t is face t) and each corner's position in
    // its face (quads only).
    const uint32_t* gWelded = nullptr;
    const uint32_t* gCorner = nullptr;
    const uint32_t* gFace = nullptr;
    const uint8_t* gVertInFace = nullptr;

    uint32_t cornerOut(size_t j) const { return gCorner ? gCorner[j] : uint32_t(j); }
    uint32_t faceOf(size_t t) const { return gFace ? gFace[t] : uint32_t(t); }
};

// --- Step 1: triangles ---------------------------------------------------------------

// Whether a quad (its four input vertices fv) splits along 0-2: the shorter
// UV diagonal; on a tie the shorter position diagonal; on a second tie 0-2.
bool quadSplitsAlong02(const MikkTSpaceInput& in, const uint32_t* fv) {
    auto uvDist2 = [&](int a, int b) {
        const glm::vec2 ta = in.uvs[fv[a]], tb = in.uvs[fv[b]];
        const float dx = tb.x - ta.x, dy = tb.y - ta.y;
        return dx * dx + dy * dy;
    };
    const float uv02 = uvDist2(0, 2), uv13 = uvDist2(1, 3);
    if (uv02 < uv13) return true;
    if (uv13 < uv02) return false;
    auto posDist2 = [&](int a, int b) {
        return mikk::lengthSquared(
            mikk::sub(mikk::toVec3(in.positions[fv[b]]), mikk::toVec3(in.positions[fv[a]])));
    };
    return !(posDist2(1, 3) < posDist2(0, 2));
}

// The triangle list. Without quads a triangle's corners are the input
// corners 3t..3t+2 and nothing is copied.
void triangulate(Pass& p) {
    const MikkTSpaceInput& in = p.in;
    Buffers& s = p.s;
    p.triVertex = in.cornerVertices.data();
    if (p.trianglesOnly) return;
    s.triVertex.resize(p.triCount * 3);
    s.triCorner.resize(p.triCount * 3);
    s.triFace.resize(p.triCount);
    s.triVertInFace.resize(p.triCount * 3);
    size_t t = 0, first = 0;
    for (size_t f = 0; f < in.faceSizes.size(); first += in.faceSizes[f], ++f) {
        const uint32_t n = in.faceSizes[f];
        if (n != 3 && n != 4) continue;
        const uint32_t* fv = in.cornerVertices.data() + first;
        auto emit = [&](int a, int b, int c) {
            const int k[3] = {a, b, c};
            for (int i = 0; i < 3; ++i) {
                s.triVertex[t * 3 + size_t(i)] = fv[k[i]];
                s.triCorner[t * 3 + size_t(i)] = uint32_t(first) + uint32_t(k[i]);
                s.triVertInFace[t * 3 + size_t(i)] = uint8_t(k[i]);
            }
            s.triFace[t] = uint32_t(f);
            ++t;
        };
        if (n == 3) {
            emit(0, 1, 2);
        } else if (quadSplitsAlong02(in, fv)) {
            emit(0, 1, 2);
            emit(0, 2, 3);
        } else {
            emit(0, 1, 3);
            emit(1, 2, 3);
        }
    }
    p.triVertex = s.triVertex.data();
}

// --- Step 2: weld --------------------------------------------------------------------

constexpr uint32_t kSeen = kNone - 1;

// Pass 1: the input vertices in order of first use (marked kSeen).
void listVerticesByFirstUse(Pass& p) {
    Buffers& s = p.s;
    s.vertexClass.assign(p.in.positions.size(), kNone);
    s.firstUse.clear();
    for (size_t c = 0; c < p.triCount * 3; ++c) {
        const uint32_t v = p.triVertex[c];
        if (s.vertexClass[v] == kNone) {
            s.vertexClass[v] = kSeen;
            s.firstUse.push_back(v);
        }
    }
}

// Pass 2: their values, in order of first use, into `staged`, hashed.
void stageVertexValues(Pass& p) {
    Buffers& s = p.s;
    const size_t used = s.firstUse.size();
    s.hashes.resize(used);
    s.staged.resize(used);
    p.forBlocks(used, 1, [&](size_t, size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
            const uint32_t v = s.firstUse[i];
            const glm::vec3 pos = p.in.positions[v], n = p.in.normals[v];
            const glm::vec2 uv = p.in.uvs[v];
            s.staged[i] = {mikk::toVec3(pos), mikk::toVec3(n), uv};
            s.hashes[i] = weldHash(pos, n, uv);
        }
    });
}

// Pass 3: each staged vertex looked up in an open-addressing table (slot =
// staged index of the class's first vertex and 32 hash bits, so a probe
// rarely reads the candidate's values), prefetching the slot a few
// vertices ahead; the values compared are read from `staged`
// (sequentially), not from the input. Returns the number of classes.
uint32_t classifyStagedVertices(Buffers& s) {
    const size_t used = s.firstUse.size();
    size_t tableSize = 64;
    while (tableSize < 2 * used) tableSize *= 2;
    const size_t mask = tableSize - 1;
    constexpr uint64_t kEmpty = ~uint64_t(0);
    s.hashTable.assign(tableSize, kEmpty);
    s.stagedId.resize(used);
    const WeldedVertex* const staged = s.staged.data();
    uint32_t* const stagedId = s.stagedId.data();
    uint32_t classCount = 0;
    constexpr size_t kAhead = 16;
    for (size_t i = 0; i < used; ++i) {
        if (i + kAhead < used) __builtin_prefetch(&s.hashTable[s.hashes[i + kAhead] & mask]);
        const uint64_t h = s.hashes[i];
        const uint64_t tag = h & 0xFFFFFFFF00000000ull;
        const WeldedVertex& x = staged[i];
        uint32_t id;
        for (size_t slot = size_t(h) & mask;; slot = (slot + 1) & mask) {
            const uint64_t entry = s.hashTable[slot];
            if (entry == kEmpty) {
                id = classCount++;
                s.hashTable[slot] = tag | i;
                break;
            }
            if ((entry & 0xFFFFFFFF00000000ull) != tag) continue;
            const WeldedVertex& y = staged[uint32_t(entry)];
            if (mikk::exactlyEqual(x.position, y.position) &&
                mikk::exactlyEqual(x.normal, y.normal) && x.uv.x == y.uv.x && x.uv.y == y.uv.y) {
                id = stagedId[uint32_t(entry)];
                break;
            }
        }
        stagedId[i] = id;
        s.vertexClass[s.firstUse[i]] = id;
    }
    return classCount;
}

// Relaxed atomic minimum (the result does not depend on the order of the
// calls).
inline void atomicMin(uint32_t& target, uint32_t value) {
    std::atomic_ref<uint32_t> a(target);
    uint32_t current = a.load(std::memory_order_relaxed);
    while (value < current && !a.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
    }
}
inline void atomicMin(uint64_t& target, uint64_t value) {
    std::atomic_ref<uint64_t> a(target);
    uint64_t current = a.load(std::memory_order_relaxed);
    while (value < current && !a.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
    }
}

// weld() in parallel, with the same result: the first use of an input
// vertex is the smallest corner naming it (atomic minimum), firstUse the
// corners that are their vertex's first use, compacted in corner order; a
// class's id is the rank of its smallest staged index among those
// smallest indices (the order the serial loop meets classes in), found
// through a lock-free table whose slot keeps the smallest staged index of
// its class (atomic minimum on tag | index: equal tags, so the index
// decides).
void weldParallel(Pass& p) {
    Buffers& s = p.s;
    const size_t cornerCount = p.triCount * 3;
    const uint32_t* const tv = p.triVertex;
    s.vertexClass.resize(p.in.positions.size());
    p.forBlocks(s.vertexClass.size(), 1, [&](size_t, size_t b, size_t e) {
        std::fill(s.vertexClass.begin() + ptrdiff_t(b), s.vertexClass.begin() + ptrdiff_t(e),
                  kNone);
    });
    // First corner of each vertex (fewer than 2^30 corners: never kNone).
    p.forBlocks(cornerCount, 1, [&](size_t, size_t b, size_t e) {
        for (size_t c = b; c < e; ++c) atomicMin(s.vertexClass[tv[c]], uint32_t(c));
    });
    const Blocks cb = p.blocks(cornerCount);
    s.blockCounts.resize(cb.count);
    p.forBlocks(cb, cornerCount, [&](size_t k, size_t b, size_t e) {
        size_t n = 0;
        for (size_t c = b; c < e; ++c) n += s.vertexClass[tv[c]] == c;
        s.blockCounts[k] = n;
    });
    const size_t used = p.prefixBlockCounts(cb.count);
    s.firstUse.resize(used);
    s.hashes.resize(used);
    s.staged.resize(used);
    p.forBlocks(cb, cornerCount, [&](size_t k, size_t b, size_t e) {
        size_t i = s.blockCounts[k];
        for (size_t c = b; c < e; ++c) {
            const uint32_t v = tv[c];
            if (s.vertexClass[v] != c) continue;
            s.firstUse[i] = v;
            const glm::vec3 pos = p.in.positions[v], n = p.in.normals[v];
            const glm::vec2 uv = p.in.uvs[v];
            s.staged[i] = {mikk::toVec3(pos), mikk::toVec3(n), uv};
            s.hashes[i] = weldHash(pos, n, uv);
            ++i;
        }
    });
    // The table: each staged vertex inserted or merged into its class's
    // slot; repOf[i] = that slot.
    size_t tableSize = 64;
    while (tableSize < 2 * used) tableSize *= 2;
    const size_t mask = tableSize - 1;
    constexpr uint64_t kEmpty = ~uint64_t(0);
    s.hashTable.resize(tableSize);
    p.forBlocks(tableSize, 1, [&](size_t, size_t b, size_t e) {
        std::fill(s.hashTable.begin() + ptrdiff_t(b), s.hashTable.begin() + ptrdiff_t(e), kEmpty);
    });
    s.repOf.resize(used);
    s.stagedId.resize(used);
    const WeldedVertex* const staged = s.staged.data();
    const Blocks ub = p.blocks(used);
    p.forBlocks(ub, used, [&](size_t, size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
            const uint64_t h = s.hashes[i];
            const uint64_t tag = h & 0xFFFFFFFF00000000ull;
            const uint64_t mine = tag | i;
            const WeldedVertex& x = staged[i];
            for (size_t slot = size_t(h) & mask;; slot = (slot + 1) & mask) {
                std::atomic_ref<uint64_t> cell(s.hashTable[slot]);
                uint64_t entry = cell.load(std::memory_order_relaxed);
                if (entry == kEmpty) {
                    if (cell.compare_exchange_strong(entry, mine, std::memory_order_relaxed)) {
                        s.repOf[i] = uint32_t(slot);
                        break;
                    }
                    // Taken meanwhile: `entry` is what took it.
                }
                if ((entry & 0xFFFFFFFF00000000ull) != tag) continue;
                const WeldedVertex& y = staged[uint32_t(entry)];
                if (mikk::exactlyEqual(x.position, y.position) &&
                    mikk::exactlyEqual(x.normal, y.normal) && x.uv.x == y.uv.x &&
                    x.uv.y == y.uv.y) {
                    atomicMin(s.hashTable[slot], mine);
                    s.repOf[i] = uint32_t(slot);
                    break;
                }
            }
        }
    });
    // Representatives (the smallest staged index of each class) numbered
    // in staged order.
    s.blockCounts.resize(ub.count);
    p.forBlocks(ub, used, [&](size_t k, size_t b, size_t e) {
        size_t n = 0;
        for (size_t i = b; i < e; ++i) {
            s.repOf[i] = uint32_t(s.hashTable[s.repOf[i]]);
            n += s.repOf[i] == i;
        }
        s.blockCounts[k] = n;
    });
    const size_t classCount = p.prefixBlockCounts(ub.count);
    const bool noDuplicates = classCount == used;
    if (noDuplicates)
        s.welded.swap(s.staged);
    else
        s.welded.resize(classCount);
    p.forBlocks(ub, used, [&](size_t k, size_t b, size_t e) {
        uint32_t id = uint32_t(s.blockCounts[k]);
        for (size_t i = b; i < e; ++i)
            if (s.repOf[i] == i) {
                if (!noDuplicates) s.welded[id] = s.staged[i];
                s.stagedId[i] = id++;
            }
    });
    p.forBlocks(ub, used, [&](size_t, size_t b, size_t e) {
        for (size_t i = b; i < e; ++i) {
            if (s.repOf[i] != i) s.stagedId[i] = s.stagedId[s.repOf[i]]; // rep < i: set above
            s.vertexClass[s.firstUse[i]] = s.stagedId[i];
        }
    });
    s.triWelded.resize(cornerCount);
    p.forBlocks(cb, cornerCount, [&](size_t, size_t b, size_t e) {
        for (size_t c = b; c < e; ++c) s.triWelded[c] = s.vertexClass[tv[c]];
    });
    p.wv = s.welded.data();
    p.weldedCount = s.welded.size();
}

// Weld by exact (position, normal, uv), through the input vertices. Welded
// ids in order of first use; their values are those of the first corner
// using them (as the oracle's representative).
void weld(Pass& p) {
    // The parallel weld does ~2.3x the serial weld's work (extra passes over
    // the corners, atomics; tangents_bench per-step times with the parallel
    // steps on one effective core), so it only pays with more threads.
    // Below that, passes 1 and 3 (first use, classes: sequential by nature)
    // run on this thread and passes 2 and 4 (per vertex, per corner) in
    // parallel blocks.
    constexpr int kParallelWeldThreads = 4;
    if (p.parallel && tbb::this_task_arena::max_concurrency() >= kParallelWeldThreads) {
        weldParallel(p);
        return;
    }
    Buffers& s = p.s;
    listVerticesByFirstUse(p);
    stageVertexValues(p);
    const uint32_t classCount = classifyStagedVertices(s);
    // Welded values: each class's first vertex (new ids appear in
    // increasing order); without duplicates that is `staged` itself.
    const size_t used = s.firstUse.size();
    if (classCount == used) {
        s.welded.swap(s.staged);
    } else {
        s.welded.resize(classCount);
        uint32_t nextId = 0;
        for (size_t i = 0; i < used; ++i)
            if (s.stagedId[i] == nextId) s.welded[nextId++] = s.staged[i];
    }
    // Pass 4: welded id per triangle corner.
    const size_t cornerCount = p.triCount * 3;
    s.triWelded.resize(cornerCount);
    p.forBlocks(cornerCount, 1, [&](size_t, size_t b, size_t e) {
        for (size_t c = b; c < e; ++c) s.triWelded[c] = s.vertexClass[p.triVertex[c]];
    });
    p.wv = s.welded.data();
    p.weldedCount = s.welded.size();
}

// --- Steps 3-5: degenerate triangles, derivatives, orientation -----------------------

size_t faceDerivativesRange(const WeldedVertex* wv, const uint32_t* tw, TriDerivatives* deriv,
                            uint8_t* flags, size_t first, size_t last);

// Per-triangle derivatives and orientation (eq. 18/19) of every triangle
// in input order, with the degenerate test (two corners at one position)
// in the same pass: both read the same positions. A degenerate triangle's
// derivatives are computed and dropped in step 4.
void faceDerivativesAndDegenerates(Pass& p) {
    Buffers& s = p.s;
    const size_t triCount = p.triCount;
    const WeldedVertex* const wv = p.wv;
    s.deriv.resize(triCount);
    s.flags.resize(triCount); // indexed in the good-first order after step 4
    const uint32_t* const tw = s.triWelded.data();
    // Blocks of a multiple of 4 triangles: each triangle goes through the
    // same kernel (4-wide or scalar tail; the same bits either way).
    const Blocks tb = p.blocks(triCount, 4);
    s.blockCounts.resize(tb.count);
    p.forBlocks(tb, triCount, [&](size_t k, size_t b, size_t e) {
        std::fill(s.flags.begin() + ptrdiff_t(b), s.flags.begin() + ptrdiff_t(e), uint8_t(0));
        s.blockCounts[k] = faceDerivativesRange(wv, tw, s.deriv.data(), s.flags.data(), b, e);
    });
    size_t degenerateCount = 0;
    for (size_t k = 0; k < tb.count; ++k) degenerateCount += s.blockCounts[k];
    p.degenerateCount = degenerateCount;
    p.goodCount = triCount - degenerateCount;
}

// Derivatives, flags and the degenerate test of triangles [b, e); returns
// the number of degenerate ones.
size_t faceDerivativesRange(const WeldedVertex* wv, const uint32_t* tw, TriDerivatives* deriv,
                            uint8_t* flags, size_t first, size_t last) {
    size_t degenerateCount = 0;
    size_t firstScalar = first;
#if defined(__SSE2__)
    for (; firstScalar + 4 <= last; firstScalar += 4)
        degenerateCount +=
            faceDerivatives4(wv, tw + firstScalar * 3, deriv + firstScalar, flags + firstScalar);
#endif
    for (size_t t = firstScalar; t < last; ++t) {
        const WeldedVertex& a = wv[tw[t * 3]];
        const WeldedVertex& b = wv[tw[t * 3 + 1]];
        const WeldedVertex& c = wv[tw[t * 3 + 2]];
        const mikk::FaceDerivatives d =
            mikk::faceDerivatives(a.position, b.position, c.position, a.uv, b.uv, c.uv);
        deriv[t] = {d.vOs, d.magS, d.vOt, d.magT};
        const bool degenerate = mikk::exactlyEqual(a.position, b.position) ||
                                mikk::exactlyEqual(a.position, c.position) ||
                                mikk::exactlyEqual(b.position, c.position);
        flags[t] |= uint8_t((d.orientPreserving ? kOrient : 0) | (d.groupWithAny ? kAny : 0) |
                            (degenerate ? kDegenerate : 0));
        degenerateCount += degenerate;
    }
    return degenerateCount;
}

// Step 4: quads with exactly one degenerate triangle are marked (fixed up in
// step 9); then degenerate triangles go last (the good ones keep their
// order; their derivatives and flags move to the front).
void moveDegeneratesLast(Pass& p) {
    Buffers& s = p.s;
    const size_t triCount = p.triCount;
    const bool hasQuads = p.hasQuads;
    auto isDegenerate = [&](size_t t) { return (s.flags[t] & kDegenerate) != 0; };
    if (hasQuads) {
        s.quadOneDegen.assign(triCount, 0);
        for (size_t t = 0; t + 1 < triCount;) {
            if (s.triFace[t] == s.triFace[t + 1]) {
                if (isDegenerate(t) != isDegenerate(t + 1))
                    s.quadOneDegen[t] = s.quadOneDegen[t + 1] = 1;
                t += 2;
            } else {
                ++t;
            }
        }
    }
    s.order.clear();
    for (size_t t = 0; t < triCount; ++t)
        if (!isDegenerate(t)) s.order.push_back(uint32_t(t));
    for (size_t t = 0; t < triCount; ++t)
        if (isDegenerate(t)) s.order.push_back(uint32_t(t));
    s.goodWelded.resize(triCount * 3);
    s.goodCorner.resize(triCount * 3);
    if (hasQuads) {
        s.goodFace.resize(triCount);
        s.goodVertInFace.resize(triCount * 3);
    }
    for (size_t t = 0; t < triCount; ++t) {
        const size_t src = s.order[t];
        for (size_t i = 0; i < 3; ++i) {
            s.goodWelded[t * 3 + i] = s.triWelded[src * 3 + i];
            s.goodCorner[t * 3 + i] = hasQuads ? s.triCorner[src * 3 + i] : uint32_t(src * 3 + i);
            if (hasQuads) s.goodVertInFace[t * 3 + i] = s.triVertInFace[src * 3 + i];
        }
        if (hasQuads) s.goodFace[t] = s.triFace[src];
        // In place: order[t] >= t for the good prefix, and a degenerate
        // triangle keeps no derivative bits.
        const uint8_t quadBit = hasQuads && s.quadOneDegen[src] ? kQuadOneDegen : 0;
        if (t < p.goodCount) {
            s.deriv[t] = s.deriv[src];
            s.flags[t] = uint8_t((s.flags[src] & (kOrient | kAny)) | quadBit);
        } else {
            s.flags[t] = quadBit;
        }
    }
    p.gWelded = s.goodWelded.data();
    p.gCorner = s.goodCorner.data();
    p.gFace = hasQuads ? s.goodFace.data() : nullptr;
    p.gVertInFace = hasQuads ? s.goodVertInFace.data() : nullptr;
}

// Step 5, quads: the two good triangles of a quad get one orientation, the
// one of the good ("not group-with-any") triangle, else of the larger UV
// area.
void oneOrientationPerQuad(Pass& p) {
    const WeldedVertex* const wv = p.wv;
    for (size_t t = 0; t + 1 < p.goodCount;) {
        if (p.faceOf(t) != p.faceOf(t + 1)) {
            ++t;
            continue;
        }
        uint8_t& fa = p.s.flags[t];
        uint8_t& fb = p.s.flags[t + 1];
        if ((fa & kOrient) != (fb & kOrient)) {
            const uint32_t* wa = p.gWelded + t * 3;
            const uint32_t* wb = p.gWelded + (t + 1) * 3;
            const bool keepFirst = (fb & kAny) != 0 ||
                                   mikk::uvAreaTimes2(wv[wa[0]].uv, wv[wa[1]].uv, wv[wa[2]].uv) >=
                                       mikk::uvAreaTimes2(wv[wb[0]].uv, wv[wb[1]].uv, wv[wb[2]].uv);
            if (keepFirst)
                fb = uint8_t((fb & ~kOrient) | (fa & kOrient));
            else
                fa = uint8_t((fa & ~kOrient) | (fb & kOrient));
        }
        t += 2;
    }
}

// --- Step 6: adjacency, as a vertex -> incident corners table -------------------------

// Incidence::packed of good triangle t without the corner bits: the index
// and the triangle's group-with-any and orientation flags.
inline uint32_t packedTriangle(const uint8_t* flags, size_t t) {
    return uint32_t(t) << 4 | ((flags[t] & kAny) ? 8u : 0u) | ((flags[t] & kOrient) ? 4u : 0u);
}

// Each welded vertex's incident corners of good triangles, each list in
// ascending triangle order (the order of the reference's sorted edge list
// and of its sorted subgroups).
//
// In parallel: the triangles are split into one contiguous range per
// thread of the arena, and the welded ids into as many owner ranges, range
// k owning the ids first used in triangle range k (ids are numbered by
// first use, so its boundary is estimated from the last triangles of the
// range before). Each task counts, then places, the corners of its own
// triangles at vertices it owns; a corner at another range's vertex is
// kept in the task's spill list. A list is then, in ascending triangle
// order: the spills of earlier ranges (placed first, serially, in range
// order), the owner's own corners (in parallel: owners are disjoint), the
// spills of later ranges (serially, in range order). The result is the
// unique sorted table, whatever the split; the split only decides how
// much is spilled (vertices shared across range boundaries: a small part
// on meshes whose triangle order has locality, all of it at worst). Every
// corner is read twice, as in the serial loop, whatever the thread count.
void buildIncidenceParallel(Pass& p) {
    Buffers& s = p.s;
    const size_t weldedCount = p.weldedCount, goodCount = p.goodCount;
    const uint32_t* const gWelded = p.gWelded;
    const size_t ranges = std::clamp<size_t>(size_t(tbb::this_task_arena::max_concurrency()), 1,
                                             std::min<size_t>(64, std::max<size_t>(goodCount, 1)));
    auto triStart = [&](size_t k) { return goodCount * k / ranges; };
    // Owner boundaries: 1 + the largest id among the last few triangles of
    // the range before (the next new id when they introduced one), kept
    // non-decreasing.
    std::vector<uint32_t>& ownStart = s.ownStart;
    ownStart.assign(ranges + 1, 0);
    for (size_t k = 1; k < ranges; ++k) {
        const size_t end = triStart(k),
                     begin = std::max(triStart(k - 1), end - std::min<size_t>(end, 8));
        uint32_t next = ownStart[k - 1];
        for (size_t j = begin * 3; j < end * 3; ++j) next = std::max(next, gWelded[j] + 1);
        ownStart[k] = uint32_t(std::min<size_t>(next, weldedCount));
    }
    ownStart[ranges] = uint32_t(weldedCount);
    s.incidenceStart.resize(weldedCount + 1);
    s.cursor.resize(weldedCount);
    s.spills.resize(std::max(s.spills.size(), ranges));
    // Own corners counted into incidenceStart[w + 1]; the others spilled.
    tbb::parallel_for(
        size_t(0), ranges,
        [&](size_t k) {
            const uint32_t lo = ownStart[k], hi = ownStart[k + 1];
            std::fill(s.incidenceStart.begin() + ptrdiff_t(lo) + 1,
                      s.incidenceStart.begin() + ptrdiff_t(hi) + 1, 0u);
            std::vector<Spill>& spill = s.spills[k];
            spill.clear();
            for (size_t t = triStart(k); t < triStart(k + 1); ++t) {
                const uint32_t* w = gWelded + t * 3;
                for (uint32_t i = 0; i < 3; ++i) {
                    if (w[i] >= lo && w[i] < hi) {
                        ++s.incidenceStart[w[i] + 1];
                    } else {
                        spill.push_back({w[i],
                                         {packedTriangle(s.flags.data(), t) | i, w[(i + 2) % 3],
                                          w[(i + 1) % 3]}});
                    }
                }
            }
        },
        tbb::simple_partitioner());
    for (size_t k = 0; k < ranges; ++k)
        for (const Spill& x : s.spills[k]) ++s.incidenceStart[x.vertex + 1];
    s.incidenceStart[0] = 0;
    for (size_t w = 0; w < weldedCount; ++w) {
        s.incidenceStart[w + 1] += s.incidenceStart[w];
        s.cursor[w] = s.incidenceStart[w];
    }
    s.incidence.resize(goodCount * 3);
    // Spills at vertices owned by a later range come before the owner's own
    // corners.
    for (size_t k = 0; k < ranges; ++k)
        for (const Spill& x : s.spills[k])
            if (x.vertex >= ownStart[k + 1]) s.incidence[s.cursor[x.vertex]++] = x.entry;
    tbb::parallel_for(
        size_t(0), ranges,
        [&](size_t k) {
            const uint32_t lo = ownStart[k], hi = ownStart[k + 1];
            for (size_t t = triStart(k); t < triStart(k + 1); ++t) {
                const uint32_t* w = gWelded + t * 3;
                const uint32_t tc = packedTriangle(s.flags.data(), t);
                if (w[0] >= lo && w[0] < hi) s.incidence[s.cursor[w[0]]++] = {tc | 0u, w[2], w[1]};
                if (w[1] >= lo && w[1] < hi) s.incidence[s.cursor[w[1]]++] = {tc | 1u, w[0], w[2]};
                if (w[2] >= lo && w[2] < hi) s.incidence[s.cursor[w[2]]++] = {tc | 2u, w[1], w[0]};
            }
        },
        tbb::simple_partitioner());
    // Spills at vertices owned by an earlier range come after.
    for (size_t k = 0; k < ranges; ++k)
        for (const Spill& x : s.spills[k])
            if (x.vertex < ownStart[k]) s.incidence[s.cursor[x.vertex]++] = x.entry;
}

void buildIncidence(Pass& p) {
    if (p.parallel) {
        buildIncidenceParallel(p);
        return;
    }
    Buffers& s = p.s;
    const size_t weldedCount = p.weldedCount, goodCount = p.goodCount;
    const uint32_t* const gWelded = p.gWelded;
    s.incidenceStart.assign(weldedCount + 1, 0);
    for (size_t j = 0; j < goodCount * 3; ++j) ++s.incidenceStart[gWelded[j] + 1];
    for (size_t w = 0; w < weldedCount; ++w) s.incidenceStart[w + 1] += s.incidenceStart[w];
    s.incidence.resize(goodCount * 3);
    // The next list's start serves as the cursor, shifted back after.
    uint32_t* cursor = s.incidenceStart.data();
    constexpr size_t kAheadT = 16; // triangles
    for (size_t t = 0; t < goodCount; ++t) {
        const uint32_t* w = gWelded + t * 3;
        if (t + kAheadT < goodCount) {
            const uint32_t* wa = w + kAheadT * 3;
            __builtin_prefetch(s.incidence.data() + cursor[wa[0]], 1);
            __builtin_prefetch(s.incidence.data() + cursor[wa[1]], 1);
            __builtin_prefetch(s.incidence.data() + cursor[wa[2]], 1);
        }
        const uint32_t tc = packedTriangle(s.flags.data(), t);
        s.incidence[cursor[w[0]]++] = {tc | 0u, w[2], w[1]};
        s.incidence[cursor[w[1]]++] = {tc | 1u, w[0], w[2]};
        s.incidence[cursor[w[2]]++] = {tc | 2u, w[1], w[0]};
    }
    for (size_t w = weldedCount; w > 0; --w) s.incidenceStart[w] = s.incidenceStart[w - 1];
    s.incidenceStart[0] = 0;
}

// --- Steps 7-8: groups and frames ------------------------------------------------------

// Steps 7-8, vertex by vertex. The reference floods groups across the two
// edges at a vertex, so everything a vertex needs is in its incidence list:
// which corners pair across each edge (step 6 of the oracle, restricted to
// the edges at this vertex), its groups (step 7) and their frames (step 8).
// Groups only interact through group-with-any triangles, whose orientation
// the first group meeting them sets in the reference's seed order; vertices
// touching such a triangle are therefore deferred and done afterwards in
// that order.
//
// Without quads or full frames, the usual vertex (one group, one subgroup:
// every corner at it gets the same frame) stores that frame once in
// vertexOut; other vertices store w = 0 there (a real w is +-1) and their
// entries' results in entryOut, in incidence order. Corner order is
// gathered afterwards (gatherCornerOrder): writing each corner straight
// into the corner-ordered output scatters 16-byte stores over the whole
// array and costs more.
//
// Vertices are independent here: each writes only its own vertexOut and
// entryOut entries (or, with full spaces, the spaces of its own corners:
// the corners two triangles of a quad share name one input vertex, so one
// welded vertex) and its own isDeferred flag. The clean vertices therefore
// run as parallel blocks (frameSteps), each thread with its own
// FrameScratch; the deferred ones stay serial, in seed order.
class VertexFrames {
public:
    VertexFrames(Pass& p, bool wide, FrameScratch& scratch, size_t maxDegree);
    // Steps 7-8 of the vertices [w0, w1), deferring those that touch a
    // group-with-any triangle.
    void cleanVertices(uint32_t w0, uint32_t w1);
    void deferredVertices();

private:
    // What the 8-lane test made of a vertex.
    enum class Fan { Done, Deferred, General };

    void computeTerms(uint32_t w0, uint32_t w1, const Terms& out);
    bool pairManifoldEdges(const Incidence* list, size_t k);
    void pairEdgesGreedy(const Incidence* list, size_t k);
    void pairEdges(const Incidence* list, size_t k) {
        if (!pairManifoldEdges(list, k)) pairEdgesGreedy(list, k);
    }
    bool together(const Incidence* list, const Terms& terms, uint32_t x, uint32_t y) const {
        return list[x].any() || list[y].any() ||
               p_.faceOf(list[x].tri()) == p_.faceOf(list[y].tri()) ||
               (mikk::dot(terms.os(x), terms.os(y)) > thresholdCos_ &&
                mikk::dot(terms.ot(x), terms.ot(y)) > thresholdCos_);
    }
    void accumulateOver(mikk::FrameAccumulator& fr, const Incidence* list, const Terms& terms,
                        uint32_t e) const {
        if (list[e].any()) return; // bad triangles contribute nothing
        const uint32_t t = list[e].tri();
        fr.accumulate(terms.angle[e], terms.os(e), terms.ot(e), triDeriv_[t].magS,
                      triDeriv_[t].magT);
    }
    void writeEntry(const Incidence* entry, const mikk::FrameAccumulator& fr, bool orient) {
        if (fullSpaces_)
            mikk::writeCornerSpace(
                s_.spaces[p_.cornerOut(size_t(entry->tri()) * 3 + entry->corner())], fr, orient);
        else
            entryOut_[entry - incidence_] =
                glm::vec4(fr.vOs.x, fr.vOs.y, fr.vOs.z, orient ? 1.0f : -1.0f);
    }
    void emitGroup(uint32_t w, const Incidence* list, const Terms& terms, const uint32_t* members,
                   size_t m, bool orient, bool wholeVertex);
#if defined(__SSE2__)
    Fan smallFan(uint32_t w, const Incidence* list, size_t k, const Terms& terms);
#endif
    bool oneFan(size_t k) const;
    void vertex(uint32_t w, const Incidence* list, size_t k, const Terms& terms);
    void components(uint32_t w, const Incidence* list, size_t k, const Terms& terms);
    void deferredGroup(size_t f, uint32_t i);

    // Vertices are processed in chunks of about kChunk entries whose terms
    // are computed together (4 or 8 entries per SIMD step).
    static constexpr size_t kChunk = 1024;
    static constexpr size_t kPrefetchAhead = 32; // entries; 16..96 measure the same

    Pass& p_;
    Buffers& s_;
    FrameScratch& f_;
    const bool wide_;
    const bool fullSpaces_;
    const float thresholdCos_;
    const WeldedVertex* const wv_;
    const TriDerivatives* const triDeriv_;
    const Incidence* const incidence_;
    const uint32_t* const incidenceStart_;
    const size_t entryCount_;
    glm::vec4* vertexOut_ = nullptr;
    glm::vec4* entryOut_ = nullptr;
    Terms chunkTerms_{};
    int32_t* outNbr_ = nullptr;
    int32_t* inNbr_ = nullptr;
};

// Output buffers and the deferred flags for steps 7-8; returns the largest
// incidence list.
size_t prepareFrames(Pass& p) {
    Buffers& s = p.s;
    if (p.fullSpaces) s.spaces.assign(p.cornerCount, mikk::CornerSpace{});
    if (!p.fullSpaces) {
        s.vertexOut.resize(p.weldedCount);
        s.entryOut.resize(p.goodCount * 3);
    }
    s.isDeferred.resize(p.weldedCount);
    const Blocks vb = p.blocks(p.weldedCount);
    s.blockCounts.resize(vb.count);
    p.forBlocks(vb, p.weldedCount, [&](size_t k, size_t b, size_t e) {
        std::fill(s.isDeferred.begin() + ptrdiff_t(b), s.isDeferred.begin() + ptrdiff_t(e),
                  uint8_t(0));
        size_t maxDegree = 0;
        for (size_t w = b; w < e; ++w)
            maxDegree = std::max<size_t>(maxDegree, s.incidenceStart[w + 1] - s.incidenceStart[w]);
        s.blockCounts[k] = maxDegree;
    });
    return vb.count == 0 ? 0 : *std::max_element(s.blockCounts.begin(), s.blockCounts.end());
}

VertexFrames::VertexFrames(Pass& p, bool wide, FrameScratch& scratch, size_t maxDegree)
    : p_(p), s_(p.s), f_(scratch), wide_(wide), fullSpaces_(p.fullSpaces),
      thresholdCos_(mikk::defaultThresholdCos()), wv_(p.wv), triDeriv_(p.s.deriv.data()),
      incidence_(p.s.incidence.data()), incidenceStart_(p.s.incidenceStart.data()),
      entryCount_(p.goodCount * 3) {
    vertexOut_ = s_.vertexOut.data();
    entryOut_ = s_.entryOut.data();
    const size_t termCapacity = std::max(kChunk, maxDegree) + TermBatch::kLanes;
    if (f_.terms.size() < 7 * termCapacity) f_.terms.resize(7 * termCapacity);
    chunkTerms_ = Terms::over(f_.terms.data(), termCapacity);
    const size_t localSize = std::max<size_t>(maxDegree, 8); // the 8-lane path writes 8
    if (f_.outNbr.size() < localSize) {
        f_.outNbr.resize(localSize);
        f_.inNbr.resize(localSize);
        f_.component.resize(localSize);
        f_.members.resize(localSize);
    }
    outNbr_ = f_.outNbr.data();
    inNbr_ = f_.inNbr.data();
}

// Terms of the entries of vertices [w0, w1) (consecutive in the incidence
// array), entry j at index j - incidenceStart[w0].
void VertexFrames::computeTerms(uint32_t w0, uint32_t w1, const Terms& out) {
    TermBatch batch;
    size_t filled = 0, first = 0;
    for (uint32_t w = w0; w < w1; ++w) {
        const Incidence* list = incidence_ + incidenceStart_[w];
        const size_t k = incidenceStart_[w + 1] - incidenceStart_[w];
        for (size_t e = 0; e < k; ++e) {
            const size_t ahead = incidenceStart_[w] + e + kPrefetchAhead;
            if (ahead < entryCount_) {
                const Incidence& a = incidence_[ahead];
                __builtin_prefetch(triDeriv_ + a.tri());
                __builtin_prefetch(wv_ + a.prev);
                __builtin_prefetch(wv_ + a.next);
            }
            batch.set(filled, triDeriv_ + list[e].tri(), wv_ + w, wv_ + list[e].prev,
                      wv_ + list[e].next);
            if (++filled == TermBatch::kLanes) {
                batch.compute(out, first, wide_);
                first += TermBatch::kLanes;
                filled = 0;
            }
        }
    }
    if (filled > 0) {
        for (size_t lane = filled; lane < TermBatch::kLanes; ++lane) batch.copyLane(lane, 0);
        batch.compute(out, first, wide_); // writes up to 7 entries past the end: capacity has room
        first += filled;
    }
    mikktspaceAnglesFromCos({out.angle, first}, wide_);
}

// Which entries pair across each edge at the vertex: entry e's edge
// vertex->next ("out", the reference's left neighbour) and prev->vertex
// ("in", its right neighbour). The half-edges on one edge {vertex, x}, in
// ascending triangle order: each unpaired one takes the first later
// unpaired one running the other way (the reference's pairing of its
// sorted edge list). This is the fast path: when every x is some entry's
// next at most once and some entry's prev at most once (a manifold fan), a
// pair is simply next == prev. Returns false when that does not hold.
bool VertexFrames::pairManifoldEdges(const Incidence* list, size_t k) {
    int32_t* const outNbr = outNbr_;
    int32_t* const inNbr = inNbr_;
    for (size_t e = 0; e < k; ++e) outNbr[e] = inNbr[e] = -1;
#if defined(__SSE2__)
    if (k <= 8) {
        // All nexts and prevs in two registers each; one compare per
        // register finds every entry whose next/prev equals x.
        alignas(16) uint32_t nexts[8], prevs[8];
        for (size_t e = 0; e < 8; ++e) {
            nexts[e] = e < k ? list[e].next : kNone; // kNone is never a welded id
            prevs[e] = e < k ? list[e].prev : kNone;
        }
        const __m128i n0 = _mm_load_si128(reinterpret_cast<const __m128i*>(nexts));
        const __m128i n1 = _mm_load_si128(reinterpret_cast<const __m128i*>(nexts + 4));
        const __m128i p0 = _mm_load_si128(reinterpret_cast<const __m128i*>(prevs));
        const __m128i p1 = _mm_load_si128(reinterpret_cast<const __m128i*>(prevs + 4));
        auto matches = [](__m128i a, __m128i b, __m128i x) {
            return unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(a, x)))) |
                   unsigned(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(b, x)))) << 4;
        };
        for (size_t e = 0; e < k; ++e) {
            const __m128i x = _mm_set1_epi32(int(nexts[e]));
            const unsigned sameNext = matches(n0, n1, x), prevIsX = matches(p0, p1, x);
            if ((sameNext & (sameNext - 1)) != 0 || (prevIsX & (prevIsX - 1)) != 0)
                return false; // two half-edges one way on one edge
            if (prevIsX != 0) {
                const int32_t f = int32_t(__builtin_ctz(prevIsX));
                outNbr[e] = f;
                inNbr[size_t(f)] = int32_t(e);
            }
        }
        return true;
    }
#endif
    for (size_t e = 0; e < k; ++e) {
        const uint32_t x = list[e].next;
        int32_t found = -1;
        int dupNext = 0, dupPrev = 0;
        for (size_t f = 0; f < k; ++f) {
            dupNext += list[f].next == x;
            if (list[f].prev == x) {
                ++dupPrev;
                found = int32_t(f);
            }
        }
        if (dupNext > 1 || dupPrev > 1) return false;
        if (found >= 0) {
            outNbr[e] = found;
            inNbr[size_t(found)] = int32_t(e);
        }
    }
    return true;
}

// Non-manifold edges at this vertex: the general greedy. Half-edges sorted
// by (x, entry); within a run each direction's candidate pointer only moves
// forward (linear in the run length).
void VertexFrames::pairEdgesGreedy(const Incidence* list, size_t k) {
    int32_t* const outNbr = outNbr_;
    int32_t* const inNbr = inNbr_;
    for (size_t e = 0; e < k; ++e) outNbr[e] = inNbr[e] = -1;
    f_.halfEdges.resize(2 * k);
    uint64_t* h = f_.halfEdges.data();
    for (size_t e = 0; e < k; ++e) {
        h[2 * e] = (uint64_t(list[e].next) << 32) | (uint64_t(e) << 1) | 1u; // out
        h[2 * e + 1] = (uint64_t(list[e].prev) << 32) | (uint64_t(e) << 1);  // in
    }
    const size_t n = 2 * k;
    std::sort(h, h + n);
    for (size_t r = 0; r < n;) {
        size_t end = r + 1;
        while (end < n && (h[end] >> 32) == (h[r] >> 32)) ++end;
        f_.paired.assign(end - r, 0);
        size_t next[2] = {r, r};
        for (size_t i = r; i < end; ++i) {
            if (f_.paired[i - r]) continue;
            const unsigned dir = unsigned(h[i] & 1), other = dir ^ 1u;
            size_t& q = next[other];
            if (q <= i) q = i + 1;
            while (q < end && (unsigned(h[q] & 1) != other || f_.paired[q - r])) ++q;
            if (q == end) continue;
            f_.paired[i - r] = f_.paired[q - r] = 1;
            const int32_t a = int32_t((h[i] & 0xFFFFFFFFu) >> 1);
            const int32_t b = int32_t((h[q] & 0xFFFFFFFFu) >> 1);
            (dir ? outNbr : inNbr)[size_t(a)] = b;
            (other ? outNbr : inNbr)[size_t(b)] = a;
        }
        r = end;
    }
}

// Step 8 for one group (entries `members` of `list`, the incidence list of
// vertex w, ascending) into its corners; `terms` holds the list's terms
// from index 0. wholeVertex: the group is every entry of w.
//
// Every pair passes the 180-degree threshold (dot products > -1) when every
// member's unit vectors are within ~89 degrees of the first member's
// (computed dots >= 0.02): any two are then at most ~178 degrees apart, dot
// >= -0.9993, far from -1 for float rounding (~1e-6). Checked while
// accumulating; otherwise every pair is tested, as the reference.
void VertexFrames::emitGroup(uint32_t w, const Incidence* list, const Terms& terms,
                             const uint32_t* members, size_t m, bool orient, bool wholeVertex) {
    mikk::FrameAccumulator fr;
    bool oneSubgroup = true;
    {
        const Vec3 rs = terms.os(members[0]), rt = terms.ot(members[0]);
        accumulateOver(fr, list, terms, members[0]);
        for (size_t x = 1; x < m; ++x) {
            const uint32_t e = members[x];
            oneSubgroup &=
                mikk::dot(terms.os(e), rs) >= 0.02f && mikk::dot(terms.ot(e), rt) >= 0.02f;
            accumulateOver(fr, list, terms, e);
        }
    }
    if (!oneSubgroup) {
        oneSubgroup = true;
        for (size_t x = 0; x < m && oneSubgroup; ++x)
            for (size_t y = x + 1; y < m; ++y)
                if (!together(list, terms, members[x], members[y])) {
                    oneSubgroup = false;
                    break;
                }
    }
    if (oneSubgroup) {
        fr.finish();
        if (!fullSpaces_ && wholeVertex) {
            vertexOut_[w] = glm::vec4(fr.vOs.x, fr.vOs.y, fr.vOs.z, orient ? 1.0f : -1.0f);
            return;
        }
    }
    if (!fullSpaces_) vertexOut_[w].w = 0.0f; // per entry
    if (oneSubgroup) {
        for (size_t x = 0; x < m; ++x) writeEntry(list + members[x], fr, orient);
        return;
    }
    // Rare: the group splits. Member x's subgroup is every member together
    // with it (x included: same face), ascending.
    for (size_t x = 0; x < m; ++x) {
        mikk::FrameAccumulator sub;
        for (size_t y = 0; y < m; ++y)
            if (together(list, terms, members[x], members[y]))
                accumulateOver(sub, list, terms, members[y]);
        sub.finish();
        writeEntry(list + members[x], sub, orient);
    }
}

#if defined(__SSE2__)
// The usual vertex (k <= 8 entries), without data-dependent loops (their
// exits are what costs here): flags, pairing and the single-group test on
// all 8 lanes at once; lanes >= k hold ids no welded vertex has, distinct
// per lane. Done: one group with every entry, emitted. Deferred: it
// touches a group-with-any triangle. General: anything else.
VertexFrames::Fan VertexFrames::smallFan(uint32_t w, const Incidence* list, size_t k,
                                         const Terms& terms) {
    int32_t* const outNbr = outNbr_;
    alignas(16) uint32_t packed[8], nexts[8], prevs[8];
    alignas(16) int32_t inLinks[8];
    for (uint32_t e = 0; e < 8; ++e) {
        const bool used = e < k;
        packed[e] = used ? list[e].packed : 0u;
        nexts[e] = used ? list[e].next : 0xFFFFFF00u + e;
        prevs[e] = used ? list[e].prev : 0xFFFFFE00u + e;
        outNbr[e] = -1;
        inLinks[e] = -1;
    }
    auto load = [](const void* q) { return _mm_load_si128(static_cast<const __m128i*>(q)); };
    auto bits8 = [](__m128i lo, __m128i hi) {
        return unsigned(_mm_movemask_ps(_mm_castsi128_ps(lo))) |
               unsigned(_mm_movemask_ps(_mm_castsi128_ps(hi))) << 4;
    };
    const __m128i pk0 = load(packed), pk1 = load(packed + 4);
    const __m128i anyBit = _mm_set1_epi32(8), orientBit = _mm_set1_epi32(4);
    const unsigned valid = (1u << k) - 1u;
    const unsigned anyBits = bits8(_mm_cmpeq_epi32(_mm_and_si128(pk0, anyBit), anyBit),
                                   _mm_cmpeq_epi32(_mm_and_si128(pk1, anyBit), anyBit)) &
                             valid;
    if (anyBits != 0) return Fan::Deferred;
    const unsigned orientBits = bits8(_mm_cmpeq_epi32(_mm_and_si128(pk0, orientBit), orientBit),
                                      _mm_cmpeq_epi32(_mm_and_si128(pk1, orientBit), orientBit)) &
                                valid;
    const __m128i n0 = load(nexts), n1 = load(nexts + 4), p0 = load(prevs), p1 = load(prevs + 4);
    bool simple = true;
    for (uint32_t e = 0; e < 8; ++e) {
        const __m128i x = _mm_set1_epi32(int(nexts[e]));
        const unsigned sameNext = bits8(_mm_cmpeq_epi32(n0, x), _mm_cmpeq_epi32(n1, x));
        const unsigned prevIsX = bits8(_mm_cmpeq_epi32(p0, x), _mm_cmpeq_epi32(p1, x));
        simple &= (sameNext & (sameNext - 1)) == 0 && (prevIsX & (prevIsX - 1)) == 0;
        if (prevIsX != 0) {
            const int32_t f = int32_t(__builtin_ctz(prevIsX));
            outNbr[e] = f;
            inLinks[f] = int32_t(e);
        }
    }
    if (!simple || (orientBits != 0 && orientBits != valid)) return Fan::General;
    // One orientation: one group iff the out-links chain all entries, from
    // the entry without an in-link (open fan) or from entry 0 (closed fan).
    const unsigned noIn = bits8(_mm_cmplt_epi32(load(inLinks), _mm_setzero_si128()),
                                _mm_cmplt_epi32(load(inLinks + 4), _mm_setzero_si128())) &
                          valid;
    const int32_t start = noIn != 0 ? int32_t(__builtin_ctz(noIn)) : 0;
    size_t reached = 1;
    for (int32_t e = outNbr[start]; e >= 0 && e != start && reached <= k; e = outNbr[e]) ++reached;
    if (reached != k) return Fan::General;
    uint32_t* const members = f_.members.data();
    for (uint32_t e = 0; e < 8; ++e) members[e] = e;
    emitGroup(w, list, terms, members, k, orientBits != 0, true);
    return Fan::Done;
}
#endif

// After pairEdges on k entries of one orientation: whether the pairing
// links all entries into one chain (open fan, from the entry without an
// in-link) or cycle (closed fan, from entry 0).
bool VertexFrames::oneFan(size_t k) const {
    int32_t start = 0;
    for (size_t e = 0; e < k; ++e)
        if (inNbr_[e] < 0) {
            start = int32_t(e);
            break;
        }
    size_t reached = 1;
    for (int32_t e = outNbr_[start]; e >= 0 && e != start && reached <= k; e = outNbr_[e])
        ++reached;
    return reached == k;
}

// Steps 7-8 for one vertex w (its k entries `list`, their terms), or its
// deferral when it touches a group-with-any triangle.
void VertexFrames::vertex(uint32_t w, const Incidence* list, size_t k, const Terms& terms) {
#if defined(__SSE2__)
    if (k <= 8) {
        const Fan fan = smallFan(w, list, k, terms);
        if (fan == Fan::Done) return;
        if (fan == Fan::Deferred) {
            s_.isDeferred[w] = 1;
            return;
        }
    } else
#endif
    {
        bool touchesAny = false;
        for (size_t e = 0; e < k; ++e) touchesAny |= list[e].any();
        if (touchesAny) {
            s_.isDeferred[w] = 1;
            return;
        }
    }
    uint32_t* const members = f_.members.data();
    if (k == 1) {
        members[0] = 0;
        emitGroup(w, list, terms, members, 1, list[0].orient(), true);
        return;
    }
    pairEdges(list, k);
    // Usual case: one orientation, and the pairing links all entries into
    // one chain or cycle: one group with every entry, already ascending.
    const bool orient0 = list[0].orient();
    bool oneOrientation = true;
    for (size_t e = 1; e < k; ++e) oneOrientation &= list[e].orient() == orient0;
    if (oneOrientation && oneFan(k)) {
        for (size_t e = 0; e < k; ++e) members[e] = uint32_t(e);
        emitGroup(w, list, terms, members, k, orient0, true);
        return;
    }
    components(w, list, k, terms);
}

// Step 7 for a vertex without group-with-any triangles: its groups are the
// connected components of same-orientation entries (any flood order gives
// the same components), each emitted in ascending entry order.
void VertexFrames::components(uint32_t w, const Incidence* list, size_t k, const Terms& terms) {
    int32_t* const comp = f_.component.data();
    uint32_t* const members = f_.members.data();
    for (size_t e = 0; e < k; ++e) comp[e] = -1;
    for (size_t seed = 0; seed < k; ++seed) {
        if (comp[seed] >= 0) continue;
        const bool orientBit = list[seed].orient();
        // Flood (members[] doubles as the stack), then list the component
        // in ascending entry order.
        comp[seed] = int32_t(seed);
        size_t top = 0;
        members[top++] = uint32_t(seed);
        while (top > 0) {
            const uint32_t e = members[--top];
            for (const int32_t nb : {outNbr_[e], inNbr_[e]}) {
                if (nb < 0 || comp[nb] >= 0 || list[nb].orient() != orientBit) continue;
                comp[nb] = int32_t(seed);
                members[top++] = uint32_t(nb);
            }
        }
        size_t m = 0;
        for (size_t e = seed; e < k; ++e)
            if (comp[e] == int32_t(seed)) members[m++] = uint32_t(e);
        emitGroup(w, list, terms, members, m, orientBit, false);
    }
}

// The vertices in chunks: terms for the chunk, then each vertex's groups.
// (A vertex's terms do not depend on the chunk it is computed in.)
void VertexFrames::cleanVertices(uint32_t first, uint32_t last) {
    for (uint32_t w0 = first; w0 < last;) {
        uint32_t w1 = w0 + 1;
        while (w1 < last && incidenceStart_[w1 + 1] - incidenceStart_[w0] <= kChunk) ++w1;
        computeTerms(w0, w1, chunkTerms_);
        for (uint32_t w = w0; w < w1; ++w) {
            const size_t k = incidenceStart_[w + 1] - incidenceStart_[w];
            if (k == 0) continue;
            vertex(w, incidence_ + incidenceStart_[w], k,
                   chunkTerms_.offset(incidenceStart_[w] - incidenceStart_[w0]));
        }
        w0 = w1;
    }
}

// The group seeded at corner i of good triangle f (at deferred vertex w):
// flooded from it, left edge first as the reference's recursion; a
// group-with-any triangle met with no corner in any group adopts the
// group's orientation.
void VertexFrames::deferredGroup(size_t f, uint32_t i) {
    uint8_t* const fl = s_.flags.data();
    const uint32_t w = p_.gWelded[f * 3 + i];
    const Incidence* list = incidence_ + incidenceStart_[w];
    const size_t k = incidenceStart_[w + 1] - incidenceStart_[w];
    computeTerms(w, w + 1, chunkTerms_);
    pairEdges(list, k);
    uint32_t seed = 0;
    while (list[seed].tri() != f) ++seed;
    const bool orient = (fl[f] & kOrient) != 0;
    fl[f] |= uint8_t(kGrouped0 << i);
    f_.groupMembers.assign(1, seed);
    f_.stack.clear();
    if (inNbr_[seed] >= 0) f_.stack.push_back(uint32_t(inNbr_[seed]));   // right
    if (outNbr_[seed] >= 0) f_.stack.push_back(uint32_t(outNbr_[seed])); // left first
    while (!f_.stack.empty()) {
        const uint32_t e = f_.stack.back();
        f_.stack.pop_back();
        const uint32_t t = list[e].tri(), c = list[e].corner();
        if (fl[t] & (kGrouped0 << c)) continue;
        if ((fl[t] & kAny) && (fl[t] & kGroupedAll) == 0)
            fl[t] = uint8_t((fl[t] & ~kOrient) | (orient ? kOrient : 0));
        if (((fl[t] & kOrient) != 0) != orient) continue;
        fl[t] |= uint8_t(kGrouped0 << c);
        f_.groupMembers.push_back(e);
        if (inNbr_[e] >= 0) f_.stack.push_back(uint32_t(inNbr_[e]));
        if (outNbr_[e] >= 0) f_.stack.push_back(uint32_t(outNbr_[e]));
    }
    std::sort(f_.groupMembers.begin(), f_.groupMembers.end());
    emitGroup(w, list, chunkTerms_, f_.groupMembers.data(), f_.groupMembers.size(), orient, false);
}

// Steps 7-8 for the deferred vertices, in the reference's seed order
// (triangle, then corner): a group from each good triangle corner at a
// deferred vertex not yet in a group. Their entries get the reference's
// default first (some may never be reached).
void VertexFrames::deferredVertices() {
    for (uint32_t w = 0; w < p_.weldedCount && !fullSpaces_; ++w) { // spaces start as the default
        if (!s_.isDeferred[w]) continue;
        vertexOut_[w].w = 0.0f;
        for (uint32_t j = incidenceStart_[w]; j < incidenceStart_[w + 1]; ++j)
            entryOut_[j] = glm::vec4(1, 0, 0, -1);
    }
    const uint8_t* const fl = s_.flags.data();
    for (size_t f = 0; f < p_.goodCount; ++f) {
        for (uint32_t i = 0; i < 3; ++i) {
            const uint32_t w = p_.gWelded[f * 3 + i];
            if (!s_.isDeferred[w] || (fl[f] & kAny) || (fl[f] & (kGrouped0 << i))) continue;
            deferredGroup(f, i);
        }
    }
}

// Steps 7-8: the clean vertices in blocks (in parallel inside an arena),
// then the deferred ones in seed order on this thread.
void frameSteps(Pass& p, bool wide) {
    Buffers& s = p.s;
    const size_t maxDegree = prepareFrames(p);
    p.forBlocks(p.weldedCount, 1, [&](size_t, size_t b, size_t e) {
        FrameScratch& scratch = p.parallel ? s.threadScratch.local() : s.frameScratch;
        VertexFrames(p, wide, scratch, maxDegree).cleanVertices(uint32_t(b), uint32_t(e));
    });
    if (std::find(s.isDeferred.begin(), s.isDeferred.end(), uint8_t(1)) != s.isDeferred.end())
        VertexFrames(p, wide, s.frameScratch, maxDegree).deferredVertices();
}

// --- Output ------------------------------------------------------------------------------

// Per-vertex and per-entry results (steps 7-8 without full spaces) into
// corner order, in triangle order.
void gatherCornerOrder(Pass& p) {
    const Buffers& s = p.s;
    const glm::vec4* const vertexOut = s.vertexOut.data();
    p.forBlocks(p.goodCount, 1, [&](size_t, size_t b, size_t e) {
        for (size_t t = b; t < e; ++t) {
            for (size_t i = 0; i < 3; ++i) {
                const uint32_t w = p.gWelded[t * 3 + i];
                glm::vec4 v = vertexOut[w];
                if (v.w == 0.0f) { // this corner's entry (a good triangle meets w once)
                    uint32_t j = s.incidenceStart[w];
                    while (s.incidence[j].tri() != t) ++j;
                    v = s.entryOut[j];
                }
                p.tangentsOut[p.cornerOut(t * 3 + i)] = v;
            }
        }
    });
}

void copyCorner(Pass& p, uint32_t dst, uint32_t src) {
    if (p.fullSpaces)
        p.s.spaces[dst] = p.s.spaces[src];
    else
        p.tangentsOut[dst] = p.tangentsOut[src];
}

// Step 9, whole degenerate triangles: each corner copies the frame of the
// first good corner with the same welded vertex (or gets the default).
void copyFromFirstGoodCorner(Pass& p) {
    Buffers& s = p.s;
    s.firstGoodCorner.assign(p.weldedCount, kNone);
    for (size_t j = p.goodCount * 3; j-- > 0;) s.firstGoodCorner[p.gWelded[j]] = uint32_t(j);
    for (size_t t = p.goodCount; t < p.triCount; ++t) {
        if (s.flags[t] & kQuadOneDegen) continue;
        for (size_t i = 0; i < 3; ++i) {
            const uint32_t j = s.firstGoodCorner[p.gWelded[t * 3 + i]];
            if (j != kNone)
                copyCorner(p, p.cornerOut(t * 3 + i), p.cornerOut(j));
            else if (!p.fullSpaces)
                p.tangentsOut[p.cornerOut(t * 3 + i)] = glm::vec4(1, 0, 0, -1);
        }
    }
}

// Step 9, quads with one degenerate half: the face corner missing from the
// good half copies the good half's corner at the same position.
void completeQuadsWithOneDegenerateHalf(Pass& p) {
    const MikkTSpaceInput& in = p.in;
    for (size_t t = 0; t < p.goodCount; ++t) {
        if (!(p.s.flags[t] & kQuadOneDegen)) continue;
        const uint8_t* vf = p.gVertInFace + t * 3;
        const int present = (1 << vf[0]) | (1 << vf[1]) | (1 << vf[2]);
        const int missing =
            (present & 2) == 0 ? 1 : ((present & 4) == 0 ? 2 : ((present & 8) == 0 ? 3 : 0));
        // Face corner k of this triangle's face: output corner (first
        // corner of the face) + k.
        const uint32_t faceFirst = p.cornerOut(t * 3) - vf[0];
        const Vec3 missingPos =
            mikk::toVec3(in.positions[in.cornerVertices[faceFirst + uint32_t(missing)]]);
        for (size_t i = 0; i < 3; ++i) {
            const Vec3 q = mikk::toVec3(in.positions[in.cornerVertices[faceFirst + vf[i]]]);
            if (mikk::exactlyEqual(q, missingPos)) {
                copyCorner(p, faceFirst + uint32_t(missing), faceFirst + vf[i]);
                break;
            }
        }
    }
}

// Step 10 with full spaces: tangents (and frames) of the corners of
// triangles and quads; others stay zero.
void writeFrames(Pass& p) {
    auto emitCorner = [&](size_t c) {
        const MikkTSpaceFrame fr = mikk::toFrame(p.s.spaces[c]);
        p.tangentsOut[c] = glm::vec4(fr.tangent, fr.sign);
        if (p.frames) (*p.frames)[c] = fr;
    };
    if (p.in.faceSizes.empty()) {
        p.forBlocks(p.cornerCount, 1, [&](size_t, size_t b, size_t e) {
            for (size_t c = b; c < e; ++c) emitCorner(c);
        });
        return;
    }
    size_t first = 0;
    for (const uint32_t n : p.in.faceSizes) {
        if (n == 3 || n == 4)
            for (size_t k = 0; k < n; ++k) emitCorner(first + k);
        first += n;
    }
}

} // namespace

struct MikkTSpaceGenerator::Scratch : Buffers {};

MikkTSpaceGenerator::MikkTSpaceGenerator() : scratch_(new Scratch) {}
void MikkTSpaceGenerator::setWideSimd(bool enabled) {
    wideSimd_ = enabled;
}
void MikkTSpaceGenerator::setThreads(int threads) {
    SG_EXPECTS(threads >= 0 && threads <= kMaxThreads,
               "0 (all cores) or 1..1024 threads (surfgrad/base/threads.h)");
    threads_ = threads;
}
void MikkTSpaceGenerator::setParallelCutover(size_t triangles) {
    parallelCutover_ = triangles;
}
std::span<const MikkTSpaceStepTime> MikkTSpaceGenerator::lastStepTimes() const {
    return scratch_->stepTimes;
}
MikkTSpaceGenerator::~MikkTSpaceGenerator() {
    delete scratch_;
}

void MikkTSpaceGenerator::generate(const MikkTSpaceInput& in,
                                   std::vector<glm::vec4>& cornerTangents,
                                   std::vector<MikkTSpaceFrame>* frames) {
    Pass p(in, *scratch_, frames);
    std::vector<MikkTSpaceStepTime>& times = scratch_->stepTimes;
    times.clear();
    auto clock = std::chrono::steady_clock::now();
    auto lap = [&](const char* step) {
        const auto now = std::chrono::steady_clock::now();
        times.push_back({step, std::chrono::duration<double, std::milli>(now - clock).count()});
        clock = now;
    };
    p.triCount = mikk::validateInput(in);
    lap("validate input");
    p.cornerCount = in.cornerVertices.size();
    p.trianglesOnly = in.faceSizes.empty() || std::all_of(in.faceSizes.begin(), in.faceSizes.end(),
                                                          [](uint32_t n) { return n == 3; });
    p.hasQuads = !p.trianglesOnly;
    p.fullSpaces = p.hasQuads || frames != nullptr;
    // Corners of faces that are neither triangles nor quads stay zero. With
    // triangles only every corner is written below (a good corner by its
    // group or the default frame, a degenerate one by step 9), so the
    // buffer needs no clearing.
    // Fresh output storage gets huge pages before the fill touches it
    // (scratch_buffer.h: the first call's page faults).
    sg::detail::reserveWithHugePages(cornerTangents, p.cornerCount);
    if (frames) sg::detail::reserveWithHugePages(*frames, p.cornerCount);
    if (p.trianglesOnly && !frames)
        cornerTangents.resize(p.cornerCount);
    else
        cornerTangents.assign(p.cornerCount, glm::vec4(0.0f));
    if (frames) frames->assign(p.cornerCount, MikkTSpaceFrame{{0, 0, 0}, 0, {0, 0, 0}, 0, 0});
    lap("output buffers");
    if (p.triCount == 0) return;
    p.tangentsOut = cornerTangents.data();

    const bool wide = wideSimd_ && cpuHasAvx2();
    auto steps = [&] {
        triangulate(p); // step 1
        lap("1 triangulate");
        weld(p); // step 2
        lap("2 weld");
        faceDerivativesAndDegenerates(p); // steps 3 and 5
        lap("3 derivatives");
        p.gWelded = p.s.triWelded.data();
        p.gCorner = p.hasQuads ? p.s.triCorner.data() : nullptr;
        p.gFace = p.hasQuads ? p.s.triFace.data() : nullptr;
        p.gVertInFace = p.hasQuads ? p.s.triVertInFace.data() : nullptr;
        if (p.degenerateCount > 0) moveDegeneratesLast(p); // step 4
        if (p.hasQuads) oneOrientationPerQuad(p);          // step 5, quads
        lap("4-5 degenerates, quads");
        buildIncidence(p); // step 6
        lap("6 incidence");
        frameSteps(p, wide); // steps 7-8
        lap("7-8 groups, frames");
        if (!p.fullSpaces) gatherCornerOrder(p);
        if (p.degenerateCount > 0) { // step 9
            copyFromFirstGoodCorner(p);
            if (p.hasQuads) completeQuadsWithOneDegenerateHalf(p);
        }
        if (p.fullSpaces) writeFrames(p); // step 10
        lap("9-10 output");
    };
    // Steps in parallel blocks inside an arena of the requested size; small
    // inputs and one thread run the serial loops on this thread.
    p.parallel = threads_ != 1 && p.triCount >= parallelCutover_;
    if (!p.parallel) {
        steps();
        return;
    }
    runWithThreads(threads_, steps);
}

} // namespace sg::mesh
