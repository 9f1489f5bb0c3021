// Factored stencils (subdivision.cpp's update(), the adaptive patches'
// local points): the refined points are linear in the cage, recorded as
// one sparse matrix per refinement step from PrimvarRefiner (or the
// specialised refiner of uniform_refiner.h) and applied level by level with
// plain loops, on TBB in waves with the same bits for every thread count.
#pragma once

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "subdivision_parallel.h"
#include "uniform_refiner.h"

namespace sg::mesh::detail {

namespace Far = OpenSubdiv::Far;

// Records PrimvarRefiner's weights: each child's Clear() starts a row, the
// AddWithWeight calls that follow fill it.
struct Token {
    uint32_t index;
};
struct TokenView {
    uint32_t base;
    Token operator[](int i) const { return {base + uint32_t(i)}; }
};
struct RecordedRows {
    uint32_t dstBase = 0;           // global index of the child level's first point
    std::vector<uint32_t> rowOf;    // per recorded row: its child index
    std::vector<uint32_t> rowStart; // per recorded row: first entry
    std::vector<uint32_t> src;      // global point indices
    std::vector<float> weight;
};
struct RecorderRef {
    RecordedRows* rows;
    uint32_t child;
    void Clear() {
        rows->rowOf.push_back(child);
        rows->rowStart.push_back(uint32_t(rows->src.size()));
    }
    void AddWithWeight(const Token& t, float w) {
        rows->src.push_back(t.index);
        rows->weight.push_back(w);
    }
    // PrimvarRefiner reuses child points it computed before (face points in
    // edge and vertex points): a reference into the child level itself.
    void AddWithWeight(const RecorderRef& c, float w) {
        rows->src.push_back(rows->dstBase + c.child);
        rows->weight.push_back(w);
    }
};
struct RecorderView {
    RecordedRows* rows;
    RecorderRef operator[](int i) const { return {rows, uint32_t(i)}; }
};

// One sparse matrix per refinement step; all points of all levels (and the
// local points of a patch table) live in one array, level after level.
// Rows are kept in the order PrimvarRefiner computed them (face points
// before the edge and vertex points that reuse them), each with its
// destination.
//
// Waves (for threads): rows [waves[i], waves[i + 1]) read no point that a
// row of the same wave writes, so a wave's rows can run in any order and
// the waves run in order; each row's sum runs in its recorded order, so the
// result is the same bits as the serial loop. A PrimvarRefiner level has
// two waves (face points; edge and vertex points, which read face points).
struct StencilBlock {
    uint32_t dstBase = 0, count = 0;
    std::vector<uint32_t> dst;     // per row: destination offset from dstBase (empty: row i -> i)
    std::vector<uint32_t> offsets; // count + 1
    std::vector<uint32_t> src;     // global point indices
    std::vector<float> weight;
    std::vector<uint32_t> waves; // row boundaries, waves.front() = 0, waves.back() = count

    uint32_t dstOf(uint32_t row) const { return dst.empty() ? row : dst[row]; }
    // Splits the rows into waves (serial, O(weights)). A row that reads a
    // point this block writes only later (never seen in OpenSubdiv's
    // tables: it would read the previous apply's value) makes the whole
    // block one serial wave.
    void computeWaves() {
        constexpr uint32_t kUnwritten = UINT32_MAX, kLater = UINT32_MAX - 1;
        uint32_t span = 0;
        for (uint32_t i = 0; i < count; ++i) span = std::max(span, dstOf(i) + 1);
        std::vector<uint32_t> waveOf(span, kUnwritten);
        for (uint32_t i = 0; i < count; ++i) waveOf[dstOf(i)] = kLater;
        waves.assign(1, 0);
        uint32_t wave = 0;
        for (uint32_t i = 0; i < count; ++i) {
            bool newWave = false;
            for (uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
                if (src[k] < dstBase || src[k] - dstBase >= span) continue;
                const uint32_t w = waveOf[src[k] - dstBase];
                if (w == kLater) {
                    waves.assign({0, count}); // read before write: serial
                    serial = true;
                    return;
                }
                newWave |= w == wave;
            }
            if (newWave) {
                waves.push_back(i);
                ++wave;
            }
            waveOf[dstOf(i)] = wave;
        }
        waves.push_back(count);
        serial = false;
    }
    bool serial = false;
};

struct FactoredStencils {
    uint32_t numControl = 0, numPoints = 0;
    std::vector<StencilBlock> blocks;

    // Records refinement step `level` (1-based) of `refiner` as a block
    // reading the previous level at srcBase and writing at dstBase.
    // fvarChannel >= 0 records InterpolateFaceVarying of that channel.
    void recordLevel(const Far::TopologyRefiner& refiner, int level, uint32_t srcBase,
                     uint32_t dstBase, int fvarChannel = -1) {
        const int nChild = fvarChannel < 0 ? refiner.GetLevel(level).GetNumVertices()
                                           : refiner.GetLevel(level).GetNumFVarValues(fvarChannel);
        record(uint32_t(nChild), srcBase, dstBase, [&](const TokenView& src, RecorderView& dst) {
            Far::PrimvarRefiner primvar(refiner);
            if (fvarChannel < 0)
                primvar.Interpolate(level, src, dst);
            else
                primvar.InterpolateFaceVarying(level, src, dst, fvarChannel);
        });
    }
    // The same from the specialised refiner (uniform_refiner.h), through
    // its writer protocol.
    void recordLevel(const UniformRefiner& refiner, int level, uint32_t srcBase, uint32_t dstBase,
                     int fvarChannel = -1) {
        const uint32_t nChild = fvarChannel < 0 ? refiner.level(level).numVerts
                                                : refiner.numFVarValues(level, fvarChannel);
        record(nChild, srcBase, dstBase, [&](const TokenView& src, RecorderView& dst) {
            struct Writer {
                RecordedRows* rows;
                uint32_t srcBase;
                void begin(uint32_t child) {
                    rows->rowOf.push_back(child);
                    rows->rowStart.push_back(uint32_t(rows->src.size()));
                }
                void add(uint32_t parent, float w) {
                    rows->src.push_back(srcBase + parent);
                    rows->weight.push_back(w);
                }
                void addChild(uint32_t child, float w) {
                    rows->src.push_back(rows->dstBase + child);
                    rows->weight.push_back(w);
                }
                void end() {}
            } writer{dst.rows, src.base};
            if (fvarChannel < 0)
                refiner.interpolate(level, writer);
            else
                refiner.interpolateFaceVarying(level, writer, fvarChannel);
        });
    }
    template <class Interpolate>
    void record(uint32_t nChild, uint32_t srcBase, uint32_t dstBase, Interpolate&& interpolate) {
        RecordedRows rows;
        rows.dstBase = dstBase;
        rows.rowOf.reserve(size_t(nChild));
        rows.rowStart.reserve(size_t(nChild));
        TokenView src{srcBase};
        RecorderView dst{&rows};
        interpolate(src, dst);
        StencilBlock b;
        b.dstBase = dstBase;
        b.count = uint32_t(rows.rowOf.size());
        b.dst = std::move(rows.rowOf);
        b.offsets = std::move(rows.rowStart);
        b.offsets.push_back(uint32_t(rows.src.size()));
        b.src = std::move(rows.src);
        b.weight = std::move(rows.weight);
        b.computeWaves();
        blocks.push_back(std::move(b));
    }

    // A Far stencil table whose control indices are global point indices.
    // (StencilTableReal<float>, not StencilTable: PatchTable creates its
    // local-point tables as the former, and its non-template getters
    // static_cast them to the latter, a downcast UBSan rejects.)
    void appendTable(const Far::StencilTableReal<float>& table, uint32_t dstBase) {
        StencilBlock b;
        b.dstBase = dstBase;
        b.count = uint32_t(table.GetNumStencils());
        const auto& sizes = table.GetSizes();
        const auto& idx = table.GetControlIndices();
        const auto& w = table.GetWeights();
        b.offsets.resize(size_t(b.count) + 1);
        uint32_t at = 0;
        for (uint32_t s = 0; s < b.count; ++s) {
            b.offsets[s] = at;
            at += uint32_t(sizes[s]);
        }
        b.offsets[b.count] = at;
        b.src.assign(idx.begin(), idx.begin() + at);
        b.weight.assign(w.begin(), w.begin() + at);
        b.computeWaves();
        blocks.push_back(std::move(b));
    }

    size_t weightCount() const {
        size_t n = 0;
        for (const StencilBlock& b : blocks) n += b.src.size();
        return n;
    }

    // points[0, numControl) must hold the control values. Blocks in order,
    // each block's waves in order, a wave's rows on TBB with par.on (each
    // row's sum in its recorded order: the same bits for any thread count).
    template <class V>
    void apply(V* points, const Parallel& par = {}) const {
        for (const StencilBlock& b : blocks) {
            const uint32_t* off = b.offsets.data();
            const uint32_t* src = b.src.data();
            const float* w = b.weight.data();
            V* dst = points + b.dstBase;
            const uint32_t* row = b.dst.empty() ? nullptr : b.dst.data();
            auto rows = [&](size_t begin, size_t end) {
                for (size_t i = begin; i < end; ++i) {
                    V acc(0.0f);
                    for (uint32_t k = off[i]; k < off[i + 1]; ++k) acc += w[k] * points[src[k]];
                    dst[row ? row[i] : i] = acc;
                }
            };
            for (size_t v = 0; v + 1 < b.waves.size(); ++v) {
                const uint32_t first = b.waves[v];
                (b.serial ? Parallel{} : par)
                    .blocks(b.waves[v + 1] - first,
                            [&](size_t lo, size_t hi) { rows(first + lo, first + hi); });
            }
        }
    }
};

} // namespace sg::mesh::detail
