// Internal state of the feature-map bake (features/src/bake*.cpp), in texel
// space. Parilov, Zorin (TOG 2008) section 4; Parilov, Rosenberg, Zorin
// (TR2005-872) section 4.1.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "bake_geometry.h"
#include "bake_parallel.h"
#include "surfgrad/features/feature_maps.h"

namespace sg::features::detail {

// The six segment types of a valid configuration: a segment joins two
// different edges (TOG 2008 Fig. 5); pairs 0-3 cut a corner (the diagonals
// of the 8-triangle partition), 4-5 cross the texel through the centre.
inline constexpr int kPairCount = 6;
inline constexpr int kPairEdges[kPairCount][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}, {3, 1}};
int pairOf(int edgeA, int edgeB); // -1 when edgeA == edgeB

// Transformation table (TOG 2008 sec. 4, Fig. 6 left): for a valid
// configuration (a set of at most two segment types, as a 6-bit mask) and a
// new segment type, the resulting valid configuration. Built from one rule:
// a segment already present merges (its edge points average); with room
// (fewer than two segments) the new one is added; otherwise the two of the
// three segments that touch the most edges are kept (ties keep the old
// ones), so as many edge points as possible stay connected.
uint8_t transition(uint8_t mask, int pair);

// Quantization of edge signatures to the 16-bit grids of layout.glsl.
double quantizePos(double t); // also clamps to [SG_FEAT_EDGE_MARGIN, 1 - margin]
double quantizeAngle(double theta);
uint32_t packEdgeWord(double posQ, double angleQ);

// Accumulates the crossings of one texel edge: centre of mass of the
// positions, and the mean of the tangent angles (doubled-angle vectors, as
// tangent lines have no orientation). Rule 1 of TOG 2008 sec. 4.
struct EdgeAcc {
    double sumPos = 0.0, sumCos = 0.0, sumSin = 0.0;
    int count = 0;
};

// An input segment in texel space (a line keeps its chord midpoint as p1).
struct TexelPiece {
    Quad q;
    bool line = true;
};

// The grid being baked.
struct Grid {
    int n = 0; // texels per side
    // Edges over grid corners (index j * (n+1) + i): h = (i,j)-(i+1,j),
    // v = (i,j)-(i,j+1). The accumulators hold only the edges a curve
    // crosses (a dense array was most of the scan's time: page faults).
    std::unordered_map<size_t, EdgeAcc> hAcc, vAcc;
    std::vector<double> hPos, hAng, vPos, vAng; // final, quantized; pos < 0: no point
    // Per texel (index j * n + i).
    std::vector<uint8_t> segMask;      // segment types present
    std::vector<uint8_t> quadMask;     // ... coming from quadratic input (curve candidates)
    std::vector<uint8_t> straightMask; // ... forced straight (optimisation fallback)
    // Quadratic mode: for each (texel, segment type) with curve input, the
    // mean texel-local position of the input curve's point farthest from
    // the segment's chord (the fidelity target of the optimisation).
    struct Target {
        dvec2 sum{0.0};
        int count = 0;
    };
    std::unordered_map<uint64_t, Target> targets;
    static uint64_t targetKey(size_t texel, int pair) {
        return uint64_t(texel) * kPairCount + uint64_t(pair);
    }

    size_t ci(int i, int j) const { return size_t(j) * size_t(n + 1) + size_t(i); }
    size_t ti(int i, int j) const { return size_t(j) * size_t(n) + size_t(i); }
    // Edge e (S, E, N, W) of texel (i, j): position (< 0: none) and angle.
    double& pos(int i, int j, int e);
    double& ang(int i, int j, int e);
};

// A texel decoded for validation: its edge points and tangents from the
// 16-bit edge words through the runtime's own decode (the binary64 build of
// evaluate.glsl, shared_double.h), and its segments.
struct LocalTexel {
    uint32_t edgeWords[4] = {0, 0, 0, 0}; // S, E, N, W (layout.glsl)
    uint32_t edgeFlags = 0;               // configuration bits 12-15
    dvec2 q[4];                           // edge vertices
    dvec2 tang[4];                        // unit tangents there
    bool pt[4] = {false, false, false, false};
    int nseg = 0;
    int a[2] = {0, 0}, b[2] = {0, 0};
    int pair[2] = {0, 0};
    bool candidate[2] = {false, false}; // quadratic input, not forced straight
    bool curved[2] = {false, false};    // final (after the straightening rules)
    Quad seg[2];
    bool hasTarget[2] = {false, false};
    dvec2 target[2];
    // The configuration word the runtime reads (segments, curved bits, edge
    // flags, angles bit).
    uint32_t configWord() const;
};

LocalTexel decodeTexel(const Grid& g, int i, int j);

struct ValidationCounters {
    int thetaMin = 0, flat = 0, eq7 = 0, cross = 0;
};

// Applies the straightening rules (theta_min of sec. 5.2, flat segments, the
// flatter of two crossing curves) to
// t.curved and returns the constraint violation of the texel's signature
// (0 = valid: every curved segment has its tangent intersection inside the
// texel, a safe side test (Eq. 7 or the exact test), and the 8-triangle
// partition is well formed for the runtime schemes of sec. 5.3).
double validateTexel(LocalTexel& t, ValidationCounters* counters);

// Thin-plate energy (Eq. 3) of segment s of t as implied by its signature,
// plus (fidelity) the weighted squared distance from the input curve's
// farthest-from-chord point in the texel to the segment.
double segmentEnergy(const LocalTexel& t, int s, bool fidelity = true);

// Eq. 7 safety test for a curved segment (true = the implicit side test
// cannot be fooled by the parabola's second branch).
bool eq7Safe(const Quad& c);

// The local problem of one invalid texel (TOG 2008 sec. 4, Eq. 2), in
// signature variables (bake_optimize.cpp): x holds (t, theta) of the
// texel's edge points that touch a curve candidate here or across the edge.
// The paper's equality constraints (G1 continuity, points on edges) hold by
// construction; the rest is "every affected texel valid": violation(x) is
// this texel's violation plus any increase of its edge neighbours'.
class TexelProblem {
public:
    enum class Energy {
        Ours, // Eq. 3 of the affected segments + fidelity + 0.25 (t - t0)^2
        Paper // Eq. 3 alone
    };
    TexelProblem(Grid& g, int i, int j, Energy energy = Energy::Ours);
    size_t size() const { return 2 * vars_.size(); } // 0: nothing to optimise
    const std::vector<double>& initial() const { return saved_; }
    // The search's starts: the current signature, the paper's Eq. 7 remedy
    // (middle point onto the chord's bisector), Catmull-Rom tangents.
    std::vector<std::vector<double>> starts() const;
    // Each writes x (quantized) into the grid first.
    double violation(const std::vector<double>& x);
    double energy(const std::vector<double>& x);
    // Extreme barrier: energy when feasible, else 1e9 + violation.
    double merit(const std::vector<double>& x);
    // Natural step of coordinate k (positions 1/128 texel, angles 1/32 rad).
    double scale(size_t k) const { return k % 2 == 0 ? 1.0 / 128.0 : 1.0 / 32.0; }
    void write(const std::vector<double>& x);
    int evaluations = 0;

private:
    struct Var {
        int e;      // edge of the texel
        int ni, nj; // the texel across it
        double t0;  // initial position
    };
    Grid& g_;
    int i_, j_;
    Energy kind_;
    std::vector<Var> vars_;
    std::vector<double> saved_;
    double neighbours0_ = 0.0; // the neighbours' violation before
};

// Compass (pattern) search with the extreme-barrier merit from the best of
// the problem's starts; x: the result. True when it ends feasible.
bool compassSearch(TexelProblem& p, std::vector<double>& x);

// Runs the signature optimisation of TOG 2008 sec. 4 on every texel whose
// signature is invalid, straightening what it cannot repair.
// Texels whose optimisations may depend on each other (one reads what the
// other writes: the edge points of a texel and of its four neighbours) are
// at most this far apart in x and in y; the parallel schedule keeps their
// serial order.
inline constexpr int kOptimizeReach = 2;
// In parallel (ex), texels farther apart than kOptimizeReach run at once,
// in waves that keep the serial order of dependent texels: the result is
// the serial one.
void optimizeSignatures(Grid& g, BakeStats& stats,
                        const std::function<void(const char*, double)>& progress,
                        const Exec& ex = {});

// Steps 1-6 of the bake (bake.cpp) with the loops of `ex`, whatever the
// map size (bake() applies the serial cut-over and the thread count; the
// bench measures the cut-over with this).
FeatureMaps bakeSteps(const CurveNetwork& net, const BakeOptions& opt, const Exec& ex,
                      BakeStats& st);

// Steps 1-3 of the bake (bake.cpp): the grid after scan conversion, as the
// optimisation of step 4 starts from it (the optimiser's bench uses it).
Grid scanGrid(const CurveNetwork& net, const BakeOptions& opt, BakeStats& st);

// Step 5 (bake_distance.cpp): distance and gradient at every grid corner
// within `band` texels of a piece, exact in double (TOG 2008 sec. 4,
// "Rasterization of distance field"); fills maps.dist, gradX, gradY, left.
// In parallel (ex), bands of corner rows each take the pieces in input
// order: the result is the serial one.
void computeDistances(const std::vector<TexelPiece>& pieces, double band, FeatureMaps& maps,
                      const std::function<void(const char*, double)>& progress,
                      const Exec& ex = {});

// Step 6 (bake_distance.cpp): constrained Laplacian smoothing of the
// gradient (TOG 2008 sec. 4); needs maps.hPos/vPos (the edges it does not
// smooth across) and the distances.
// (A Jacobi iteration: rows in parallel with ex give the serial result.)
void smoothGradients(double band, int iterations, FeatureMaps& maps, const Exec& ex = {});

// The exact near field (near_field.cpp): the bake keeps the pieces with
// their profiles and widths (throws InputError for unknown profiles, too
// many pieces or profiles, widths beyond the band) ...
void keepNearPieces(const CurveNetwork& net, const std::vector<TexelPiece>& segs,
                    const BakeOptions& opt, const TexelTransform& xf, FeatureMaps& maps,
                    BakeStats& st);
// ... and packing derives the GPU lists and piece texture from them.
// (Texels in parallel with ex; overflow slots assigned in texel order.)
void packNearField(const FeatureMaps& m, GpuFeatureMaps& g, const Exec& ex = {});
// Bounds the work of building the lists (pieces times the texels their
// boxes grown by the band cover, at most kNearWorkBudget): InputError
// naming `source` beyond it, so untrusted maps cannot make packing hang.
inline constexpr double kNearWorkBudget = 3.0e7;
void checkNearFieldWork(const FeatureMaps& m, const std::string& source);

} // namespace sg::features::detail
