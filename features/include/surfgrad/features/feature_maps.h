// Feature maps: normal-map features (creases, grooves, seams) that stay sharp
// at any magnification. Parilov, Rosenberg, Zorin, "Real-time rendering of
// normal maps with discontinuities" (TR2005-872: straight segments) and
// Parilov, Zorin, "Real-Time Rendering of Textures with Feature Curves"
// (TOG 2008: quadratic Bezier curves).
//
// A feature-curve network (surfgrad/features/curves.h) is baked into a small set of
// maps: the distance to the curves and its (smoothed) gradient sampled at
// texel corners, and per texel a configuration (up to two discontinuity
// segments) with a signature (where they cross the texel edges and, for
// curves, their tangent angles). At render time the shared evaluator
// (shaders/sg/features/*.glsl, compiled here as C++ too) reconstructs the
// distance d and its unit gradient at any point, exactly 0 on the curves and
// never interpolating across one; a profile h(d) turns them into a
// texture-space derivative (surfgrad composition) or a blended normal
// (the paper's Eq. 1).
//
// CONVENTIONS (used by every function here and in the shaders)
//  - Texel space: x right, y up, in texels. Texel (i, j) covers
//    [i, i+1] x [j, j+1]; a map of size N covers [0, N]^2. Grid corner
//    (i, j), 0 <= i, j <= N, is the point (i, j). A renderer with uv in
//    [0, 1]^2 (v up) passes texelPos = uv * N.
//  - Distances and widths are in texels; gradients are texel-space vectors.
//  - Input curves map to texel space by texel = scale * input + offset
//    (TexelTransform); font and SVG loaders already give y up.
//
// GPU LAYOUT (GpuFeatureMaps, read by shaders/sg/features/fetch.glsl with
// texelFetch only; GL_NEAREST, mip level 0):
//   cornerPairs RGBA32UI N x (N+1): texel (i, j) = grid corners (i, j) and
//               (i+1, j) as half floats (x: both distances, y, z: their
//               gradients) plus the configuration word of texel (i, j) (w)
//   edges       RGBA32UI N x N: edge words of edges S, E, N, W of each texel
// Row j of each array is texture row j (the first row uploaded, t = 0).
// Words are described in shaders/sg/features/layout.glsl. 32 bytes per
// texel (plus one row of corner pairs); 3 fetches per sample. Distances and
// gradients are rounded to half floats there (5e-4 texels at d < 1, 0.008
// at the 16-texel band edge), positions and angles to 16 bits. Shaders for
// maps baked in linear mode may define SG_FEAT_CURVED 0 before including
// the features files (straight segments only: cheaper, same results on such
// maps). Calling sequence and costs: docs/features.md.
//
// FILE LAYOUT (save/load, OpenEXR: written by the image writer of
// surfgrad/image/image_write.h, read by the image decoder of
// surfgrad/image/image_decode.h after the header scan): one image of
// (N+1) x (N+1) pixels, pixel (i, j) = grid corner (i, j), scanline 0 = the
// top row (j = N) so viewers show the map upright. FLOAT channels:
//   d, gx, gy   distance and gradient at the corner
//   left        1 when the corner lies left of its nearest curve, else 0
//   seg         configuration bits 0-11 of texel (i, j) (layout.glsl);
//               0 in the last row and column
//   hT, vT      point on the horizontal edge (i, j)-(i+1, j) / vertical
//               edge (i, j)-(i, j+1): position in [2^-10, 1 - 2^-10] on the
//               16-bit grid, or -1 when the edge has no point
//   hA, vA      tangent angle of the curve at that point, radians in
//               [-pi/2, pi/2] on the 16-bit grid (0 without a point); the
//               shape of curved segments and the gradient on the curve
// Metadata: surfgrad:featureMapsVersion (int), surfgrad:mode ("linear" or
// "quadratic"), surfgrad:size (int N), surfgrad:inputToTexelScaleX/Y and
// surfgrad:inputToTexelOffsetX/Y (double), surfgrad:bandTexels (double),
// surfgrad:smoothIterations (int), surfgrad:source (string),
// surfgrad:layout (a one-line description). Loading checks all of it, each
// field's type exactly (an int stored as a float or a string is refused).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/gtc/packing.hpp>
#include <glm/vec2.hpp>

#include "surfgrad/base/contract.h"
#include "surfgrad/features/curves.h"
#include "surfgrad/shaders/glsl_cpp.h"
#include "surfgrad/bump/record.h"

// The shared evaluator, compiled as C++. Samplers over CPU arrays first, so
// fetch.glsl's texelFetch/textureSize calls resolve to them.
namespace sg::glsl {
// A texture of 4 x 32-bit words per texel over a CPU array: what the GLSL
// build reads as a usampler2D with texelFetch. The layout's four textures
// (corner pairs and edges; the near field's lists and pieces) are distinct
// types of this one template, so each evaluator parameter names its
// texture, with one texelFetch and one textureSize for all.
template <int Texture>
struct SgFeatU32Sampler {
    const uint32_t* rgba = nullptr; // (width x height) RGBA texels, row-major, row 0 first
    int width = 0;
    int height = 0;
};
using SgFeatCornerSampler = SgFeatU32Sampler<0>;
using SgFeatEdgeSampler = SgFeatU32Sampler<1>;
using SgFeatNearSampler = SgFeatU32Sampler<2>;  // exact near field (near.glsl)
using SgFeatPieceSampler = SgFeatU32Sampler<3>; // exact near field (near.glsl)
template <int Texture>
inline uvec4 texelFetch(const SgFeatU32Sampler<Texture>& s, ivec2 p, int /*lod*/) {
    SG_EXPECTS(p.x >= 0 && p.y >= 0 && p.x < s.width && p.y < s.height, "texel inside the map");
    const uint32_t* t = s.rgba + 4 * (size_t(p.y) * size_t(s.width) + size_t(p.x));
    return uvec4(t[0], t[1], t[2], t[3]);
}
template <int Texture>
inline ivec2 textureSize(const SgFeatU32Sampler<Texture>& s, int /*lod*/) {
    return ivec2(s.width, s.height);
}
// The C++ build always has the exact near field (the GLSL build only when a
// map has it).
#undef SG_FEAT_NEAR
#define SG_FEAT_NEAR 1
#include "sg/features/fetch.glsl"
#include "sg/features/profile.glsl"
#include "sg/features/kernels.glsl"
} // namespace sg::glsl

namespace sg::features {

// Version of the feature-map format and evaluator contract.
inline constexpr int kFeatureMapsVersion = 1;
// Largest map size accepted by bake and load (texels per side).
inline constexpr int kMaxFeatureMapSize = 4096;

enum class BakeMode {
    Linear,   // straight segments between edge points (TR2005); interactive
    Quadratic // quadratic Bezier segments with tangent angles (TOG 2008)
};
const char* toString(BakeMode m);

// texel = scale * input + offset (componentwise).
struct TexelTransform {
    glm::dvec2 scale{1.0, 1.0};
    glm::dvec2 offset{0.0, 0.0};
    glm::dvec2 apply(glm::dvec2 p) const { return scale * p + offset; }
};

struct BakeOptions {
    int size = 512; // N, texels per side, 1..kMaxFeatureMapSize
    BakeMode mode = BakeMode::Linear;
    // fit: the network's control-point bounds are scaled uniformly and
    // centred into [margin, N - margin]^2 (y stays up). Otherwise
    // `transform` is used as given (tests pass texel-space networks with the
    // identity).
    bool fit = true;
    double marginTexels = 8.0;
    TexelTransform transform;
    // Distances are exact (brute force, double) up to bandTexels and clamped
    // to it beyond, where the gradient is 0 before smoothing. Profiles must
    // be narrower than the band (width <= band - 1.5 keeps the bilinear
    // interpolation of clamped corners out of the profile).
    double bandTexels = 16.0;
    // Constrained Laplacian smoothing of the gradient (TOG 2008 sec. 4).
    int smoothIterations = 10;
    // Exact near field (shaders/sg/features/near.glsl): keep the input's
    // pieces (texel space) with their per-curve profiles and widths, so the
    // runtime evaluates exact distances within the band of the largest
    // profile width in the map (curves without their own width count as
    // nearWidthTexels) plus nearMarginTexels. The band must not exceed
    // bandTexels. Per-curve profiles are CurveInfo::profile names
    // (makeProfile); at most SG_FEAT_MAX_PROFILES distinct ones.
    bool nearField = false;
    double nearWidthTexels = 3.0;
    double nearMarginTexels = 1.0;
    // Called with a phase name and its completed fraction (0..1) at most
    // every few milliseconds, always from the calling thread; may be empty.
    std::function<void(const char* phase, double fraction)> progress;
    // Threads (surfgrad/base/threads.h): 0 = all cores, 1 = the calling thread,
    // 2..kMaxThreads = that many; outside 0..kMaxThreads is a contract
    // violation. The maps are the same bits for every count: the loops over
    // texels and corners write disjoint outputs, the distance pass splits the
    // map into bands of rows that each take the pieces in input order, the
    // smoothing is a Jacobi iteration, and the signature optimisation
    // (quadratic mode) runs the invalid texels in waves of texels at least
    // three texels apart whose order among dependent texels is the serial
    // one. Scan conversion (the accumulation of crossings in stroke order)
    // stays serial. Maps smaller than kBakeSerialBelowSize run on the
    // calling thread whatever the count.
    int threads = 0;
};

// Serial cut-over of bake() and FeatureMaps::packGpu(): maps of fewer
// texels per side run on the calling thread. Measured (bench/features_bench
// threads, its cut-over table, on the idle 2-core reference machine): whole
// bakes of 500 polylines with parallel loops ran 1.61-1.77x faster than
// serial ones at every size from 32^2 to 256^2 (6.3 vs 3.6 ms at 32^2), so
// only maps below 32^2, where a bake is a millisecond or less, stay serial.
// (A first measurement on the same machine under a load of ~7 had put the
// break-even at 256^2: there the second core was taken by other work.)
inline constexpr int kBakeSerialBelowSize = 32;

// What the bake did (for --json and the tests).
struct BakeStats {
    int size = 0;
    TexelTransform inputToTexel;
    int texelsWithFeatures = 0; // texels with a segment or an edge point
    int texelsWithSegments = 0;
    int segmentsKept = 0;         // discontinuity segments stored
    int segmentsDropped = 0;      // removed by the transformation table (rule 2)
    int edgePointsMerged = 0;     // crossings merged into an existing edge point (rule 1)
    int curvedSegments = 0;       // stored as quadratic Beziers
    int straightenedThetaMin = 0; // theta < theta_min (TOG 2008 sec. 5.2)
    int straightenedFlat = 0;     // deviation from the chord below 1e-3 texels
    int straightenedCrossing = 0; // the flatter of two curves crossing one texel
    int eq7Failures = 0;          // curved segments failing the Eq. 7 safety test
    int invalidTexels = 0;        // texels whose signature needed the optimisation
    int optimizedTexels = 0;      // ... and were made valid by it
    int fallbackTexels = 0;       // ... and were made valid by straightening instead
    int nearPieces = 0;           // pieces kept for the exact near field
    double nearBandTexels = 0.0;  // its band (0: no near field)
    int threads = 1;              // threads the bake ran on (1: serial)
    double seconds = 0.0;         // wall-clock time of the whole bake
    double cpuSeconds = 0.0;      // CPU time of the process during the bake (all its threads)
    // CPU time of the process (all its threads) in the phases: scan
    // conversion and configurations, signature optimisation (quadratic
    // mode), distances, smoothing; and their wall-clock time.
    double secondsScan = 0.0, secondsOptimize = 0.0, secondsDistance = 0.0, secondsSmooth = 0.0;
    double wallSecondsScan = 0.0, wallSecondsOptimize = 0.0, wallSecondsDistance = 0.0,
           wallSecondsSmooth = 0.0;
};

struct GpuFeatureMaps;

// One input piece kept for the exact near field: a quadratic Bezier (a line
// has p1 = (p0 + p2) / 2 and curved = false) in texel space, in binary32 as
// the GPU reads it, with its curve's profile and its profile widths.
struct NearPiece {
    glm::vec2 p0{0.0f}, p1{0.0f}, p2{0.0f};
    bool curved = false;
    int profile = -1;    // index into FeatureMaps::profiles; -1: the layer's profile
    float width0 = 0.0f; // profile width at p0 / p2 (texels); 0: the layer's width
    float width1 = 0.0f;
};
// Most pieces a map with a near field may hold (15-bit list slots), and its
// widest band (texels).
inline constexpr int kMaxNearPieces = 32767;
inline constexpr double kMaxNearBandTexels = 64.0;

// The baked maps in their canonical (file) form; see the file layout above.
// Arrays over grid corners have (N+1)^2 entries, index j * (N+1) + i.
struct FeatureMaps {
    int size = 0;
    BakeMode mode = BakeMode::Linear;
    TexelTransform inputToTexel;
    double bandTexels = 16.0;
    int smoothIterations = 10;
    std::string source;

    std::vector<float> dist, gradX, gradY;
    std::vector<uint8_t> left;
    std::vector<uint16_t> seg;                     // configuration bits 0-11 of texel (i, j)
    std::vector<float> hPos, hAngle, vPos, vAngle; // edge points (see file layout)

    // Exact near field (BakeOptions::nearField); nearBandTexels == 0: none.
    // The GPU lists are derived from the pieces (packGpu), never stored.
    double nearBandTexels = 0.0;
    std::vector<NearPiece> pieces;
    std::vector<std::string> profiles; // profile table: makeProfile names
    bool hasNearField() const { return nearBandTexels > 0.0; }

    int gridSize() const { return size + 1; }
    size_t index(int i, int j) const { return size_t(j) * size_t(size + 1) + size_t(i); }
    // Full configuration word of texel (i, j) (0 <= i, j < N): segments,
    // edge flags and corner side bits (layout.glsl).
    uint32_t configWord(int i, int j) const;
    // Edge words of texel (i, j): S, E, N, W.
    void edgeWords(int i, int j, uint32_t out[4]) const;
    // The GPU layout (and the exact near field's lists). `threads` as
    // BakeOptions::threads (0 = all cores; the same bits for every count;
    // maps below kBakeSerialBelowSize on the calling thread).
    GpuFeatureMaps packGpu(int threads = 0) const;

    // Bytes per texel of the GPU layout and of the in-memory canonical form.
    static constexpr double kGpuBytesPerTexel = 32.0;
    double canonicalBytesPerTexel() const;
};

// The two textures of the GPU layout (see above), ready for glTexImage2D:
//   glTextureStorage2D(t, 1, GL_RGBA32UI, width, height);
//   glTextureSubImage2D(t, 0, 0, 0, width, height, GL_RGBA_INTEGER,
//                       GL_UNSIGNED_INT, data);
// with GL_NEAREST filters, bound to usampler2D uniforms.
struct GpuFeatureMaps {
    int size = 0;                      // N
    std::vector<uint32_t> cornerPairs; // N x (N+1) texels * 4 words
    std::vector<uint32_t> edges;       // N x N texels * 4 words
    int cornerPairsWidth() const { return size; }
    int cornerPairsHeight() const { return size + 1; }
    glsl::SgFeatCornerSampler cornerSampler() const { return {cornerPairs.data(), size, size + 1}; }
    glsl::SgFeatEdgeSampler edgeSampler() const { return {edges.data(), size, size}; }

    // Exact near field (near.glsl), empty without one: the list texture
    // (N x nearHeight: headers of the N x N texels, then overflow rows) and
    // the piece texture (SG_FEAT_PIECES_WIDTH x piecesHeight: the profile
    // table, then two texels per piece). Both RGBA32UI, GL_NEAREST.
    int nearHeight = 0;
    std::vector<uint32_t> nearLists;
    int piecesHeight = 0;
    std::vector<uint32_t> pieces;
    bool hasNearField() const { return nearHeight > 0; }
    glsl::SgFeatNearSampler nearSampler() const { return {nearLists.data(), size, nearHeight}; }
    glsl::SgFeatPieceSampler pieceSampler() const {
        return {pieces.data(), SG_FEAT_PIECES_WIDTH, piecesHeight};
    }
    // What the lists hold: texels in the band, pieces per listed texel (mean
    // and max), texels whose list overflows its 8 header slots.
    struct NearStats {
        int bandTexels = 0;
        double meanPieces = 0.0;
        int maxPieces = 0;
        int overflowTexels = 0;
    } nearStats;
    // Bytes of the near-field textures per map texel (N^2).
    double nearBytesPerTexel() const;
};

// How the evaluator treats a map with an exact near field.
enum class NearMode {
    Exact, // within the band, the exact distance to the input curves (near.glsl)
    Paper  // the papers' interpolation everywhere
};
const char* toString(NearMode m);

// Exactly what the shader computes at texel-space texelPos (the C++ build of
// sgFeatSample, or sgFeatSampleNear for maps with a near field in Exact
// mode): distance (texels), unit gradient, side, and in the near field the
// nearest curve's profile and width.
glsl::SgFeatResult sample(const GpuFeatureMaps& maps, glm::vec2 texelPos,
                          NearMode near = NearMode::Exact);

// Bakes a network. Throws sg::io::InputError for bad input: non-finite or
// absurd coordinates, coincident control points (a zero-length segment, a
// quadratic whose middle point coincides with an end), a quadratic that
// folds back on itself, a size outside 1..kMaxFeatureMapSize.
FeatureMaps bake(const CurveNetwork& net, const BakeOptions& options, BakeStats* stats = nullptr);

// Point files of `surfgrad features sample`: one "x y" per line (texel
// space), separated by spaces or tabs; blank lines are skipped, a trailing
// CR is ignored. Throws sg::io::InputError naming the file and the line for
// anything else: not exactly two numbers, a number that is not finite
// (after from_chars: "nan", "inf", overflow) or beyond +-1e30.
// parseSamplePoints takes the text (fuzzing; `name` appears in messages),
// loadSamplePoints reads a file of at most 1 GiB. `lineNumbers`, when given,
// receives each point's line in the file (from 1), for messages about a
// point.
std::vector<glm::vec2> parseSamplePoints(std::string_view text, const std::string& name,
                                         std::vector<size_t>* lineNumbers = nullptr);
std::vector<glm::vec2> loadSamplePoints(const std::filesystem::path& path,
                                        std::vector<size_t>* lineNumbers = nullptr);

// OpenEXR storage (atomic write; load validates every channel, value and
// metadata field and throws sg::io::InputError naming what is wrong).
void save(const FeatureMaps& maps, const std::filesystem::path& path);
FeatureMaps load(const std::filesystem::path& path);
// Same checks on an in-memory file (fuzzing); `name` appears in messages.
FeatureMaps loadFromMemory(const std::string& bytes, const std::string& name);

// Evaluation kernels (shaders/sg/features/kernels.glsl) for CPU/GPU
// parity. The table is expanded from the kernel list there (one
// declaration per kernel: name, id, record layouts, parity tolerance with
// its reason, input generator).
inline constexpr int kEvalInStride = SG_FEAT_EVAL_IN;
inline constexpr int kEvalOutStride = SG_FEAT_EVAL_OUT;
struct Kernel {
    std::string name;               // e.g. "eval"
    int id = 0;                     // SG_FEAT_K_*
    std::vector<record::Field> in;  // input record layout (kEvalInStride floats)
    std::vector<record::Field> out; // output record layout (kEvalOutStride floats)
    double tolerance = 0.0;         // max over outputs of |cpu - gpu| / max(1, |cpu|)
    std::string reason;             // why that tolerance
    std::vector<float> (*inputs)(uint32_t seed) = nullptr; // parity records, kEvalInStride each
};
const std::vector<Kernel>& kernels(); // in id order
const Kernel* findKernel(std::string_view name);
// The C++ build of sgFeatEvalKernel: in kEvalInStride floats, out
// kEvalOutStride floats.
void evalKernelCpu(int kernel, const float* in, float* out);
// The compute-program body and defines that run the same kernel on the GPU
// (assemble with sg::shaders::assemble, run with sg::gl::runCompute).
std::string evalKernelGpuBody(); // includes sg/features/kernels.comp.glsl
std::vector<std::string> evalKernelGpuDefines(int kernel);
// The same kernels as a vertex program for dialects without compute shaders
// (GLSL 3.30, ES 3.00; run with sg::gl::runTransformFeedback), and the names
// of its captured outputs in record order.
std::string evalKernelGpuVertexBody(); // includes sg/features/kernels.vert.glsl
std::vector<std::string> evalKernelGpuFeedback();
// The same kernels as an HLSL compute program (sg/features/kernels.hlsl;
// assemble with Target::Hlsl and evalKernelGpuDefines): records in buffer
// 0, results in buffer 1, their count the result buffer's.
std::string evalKernelHlslBody();
// Body of the texture-path compute program (sg/features/sample.comp.glsl):
// samplers uFeatCorners / uFeatEdges, records of 2 floats -> 4 floats.
std::string sampleGpuBody();
// The "eval" record of texel (i, j) of `maps` at local point `local`.
void packEvalRecord(const GpuFeatureMaps& maps, int i, int j, glm::vec2 local, float* record);

// Named profiles: "vgroove", "crease", "ridge", "step", "seam", or
// "table:h0,h1,...,hk" (2..16 heights in units of depth, at d = w * i / k).
// depth, w0, w in texels. Throws sg::io::InputError (file "profile") for an
// unknown name, a bad table, or w <= 0, w0 < 0, non-finite values.
glsl::SgFeatProfile makeProfile(std::string_view name, float depth, float w0, float w);
// Names of the built-in profiles, for messages and --help.
std::vector<std::string> profileNames();

} // namespace sg::features
