// Exact near field of the feature maps (shaders/sg/features/near.glsl): the
// bake keeps the input's pieces with their per-curve profiles and widths;
// packing for the GPU lists, for every texel within the band, the pieces
// that can be nearest anywhere in it. Ours, on top of Parilov, Zorin (TOG
// 2008): the papers interpolate d and its gradient from corner samples
// everywhere (sec. 5), which smooths the gradient near corners and medial
// axes.
//
// Candidate lists are conservative. Split texel T into four sub-squares
// with centres s_k and half-diagonal r = sqrt(2) / 4. The distance field
// F is 1-Lipschitz, so max over T of F <= U = max_k F(s_k) + r, and the
// distance from a piece P to T is at least L(P) = min_k |P - s_k| - r. A
// piece with L(P) > U is farther from every point of T than some other
// piece: it is never nearest in T and is left out; every other piece is
// listed. T is in the band when min_k F(s_k) - r < band. Distances are
// exact, in double, on the binary32 pieces the GPU reads.
//
// Threads: the texels' lists are built in blocks of rows in parallel; the
// lists longer than the 8 header slots get their overflow slots afterwards,
// in texel order, as one pass would.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "surfgrad/base/scratch_buffer.h"
#include "bake_internal.h"
#include "surfgrad/base/io.h"

namespace sg::features {

namespace detail {

namespace {

constexpr double kSubRadius = 0.35355339059327373; // sqrt(2) / 4
constexpr int kBinTexels = 8;                      // spatial bins of the list builder

Quad toQuad(const NearPiece& p) {
    return {dvec2(p.p0), dvec2(p.p1), dvec2(p.p2)};
}

double pieceDistance(const Quad& q, bool curved, dvec2 p) {
    double u;
    return std::sqrt(closestParam(q, !curved, p, u));
}

// Distance from point p to the axis-aligned box [lo, hi] (0 inside).
double boxDistance(dvec2 lo, dvec2 hi, dvec2 p) {
    dvec2 d = glm::max(glm::max(lo - p, p - hi), dvec2(0.0));
    return glm::length(d);
}

// Pieces that may matter for each bin of kBinTexels^2 texels: those whose
// control-point box, grown by `reach`, touches the bin.
std::vector<std::vector<int>> binPieces(const std::vector<NearPiece>& pieces, int n, double reach) {
    const int bins = (n + kBinTexels - 1) / kBinTexels;
    std::vector<std::vector<int>> out(size_t(bins) * size_t(bins));
    for (size_t k = 0; k < pieces.size(); ++k) {
        const Quad q = toQuad(pieces[k]);
        dvec2 lo = glm::min(glm::min(q.p0, q.p1), q.p2) - reach;
        dvec2 hi = glm::max(glm::max(q.p0, q.p1), q.p2) + reach;
        int bx0 = std::max(0, int(std::floor(lo.x / kBinTexels)));
        int by0 = std::max(0, int(std::floor(lo.y / kBinTexels)));
        int bx1 = std::min(bins - 1, int(std::floor(hi.x / kBinTexels)));
        int by1 = std::min(bins - 1, int(std::floor(hi.y / kBinTexels)));
        // Only bins the piece comes within `reach` of (bin centre distance
        // minus the bin's half diagonal).
        const double halfDiagonal = 0.5 * std::sqrt(2.0) * kBinTexels;
        for (int by = by0; by <= by1; ++by) {
            for (int bx = bx0; bx <= bx1; ++bx) {
                dvec2 centre((bx + 0.5) * kBinTexels, (by + 0.5) * kBinTexels);
                if (pieceDistance(q, pieces[k].curved, centre) - halfDiagonal > reach) continue;
                out[size_t(by) * size_t(bins) + size_t(bx)].push_back(int(k));
            }
        }
    }
    return out;
}

// The list of texel (i, j) (piece indices, increasing), empty outside the band.
std::vector<int> texelList(const std::vector<NearPiece>& pieces, const std::vector<int>& bin, int i,
                           int j, double band, double reach) {
    const dvec2 lo(i, j), hi(i + 1, j + 1);
    const dvec2 sub[4] = {
        {i + 0.25, j + 0.25}, {i + 0.75, j + 0.25}, {i + 0.75, j + 0.75}, {i + 0.25, j + 0.75}};
    struct Near {
        int piece;
        double minSub; // min_k |P - s_k|
    };
    std::vector<Near> near;
    double field[4] = {1e300, 1e300, 1e300, 1e300};
    for (int k : bin) {
        const NearPiece& p = pieces[size_t(k)];
        const Quad q = toQuad(p);
        dvec2 qlo = glm::min(glm::min(q.p0, q.p1), q.p2),
              qhi = glm::max(glm::max(q.p0, q.p1), q.p2);
        if (boxDistance(qlo, qhi, 0.5 * (lo + hi)) > reach) continue;
        double m = 1e300;
        for (int s = 0; s < 4; ++s) {
            double d = pieceDistance(q, p.curved, sub[s]);
            field[s] = std::min(field[s], d);
            m = std::min(m, d);
        }
        near.push_back({k, m});
    }
    std::vector<int> list;
    double fmin = std::min({field[0], field[1], field[2], field[3]});
    if (near.empty() || !(fmin - kSubRadius < band)) return list;
    double upper = std::max({field[0], field[1], field[2], field[3]}) + kSubRadius;
    for (const Near& c : near)
        if (c.minSub - kSubRadius <= upper) list.push_back(c.piece);
    return list;
}

uint32_t floatBits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}

// The piece texture: profile table, then two texels per piece (near.glsl).
void packPieces(const FeatureMaps& m, GpuFeatureMaps& g) {
    const int texels = SG_FEAT_PIECE_BASE + 2 * int(m.pieces.size());
    g.piecesHeight = (texels + SG_FEAT_PIECES_WIDTH - 1) / SG_FEAT_PIECES_WIDTH;
    sg::detail::assignWithHugePages(g.pieces, size_t(g.piecesHeight) * SG_FEAT_PIECES_WIDTH * 4,
                                    0u);
    auto texel = [&](int at) { return &g.pieces[size_t(at) * 4]; };
    for (size_t e = 0; e < m.profiles.size(); ++e) {
        glsl::SgFeatProfile pr = makeProfile(m.profiles[e], 1.0f, 0.0f, 1.0f);
        uint32_t* t = texel(int(e) * SG_FEAT_PROFILE_TEXELS);
        t[0] = floatBits(float(pr.kind));
        t[1] = floatBits(float(pr.tableCount));
        for (int k = 0; k < SG_FEAT_TABLE_MAX; ++k) t[4 + k] = floatBits(pr.table[k]);
    }
    for (size_t k = 0; k < m.pieces.size(); ++k) {
        const NearPiece& p = m.pieces[k];
        uint32_t* t = texel(SG_FEAT_PIECE_BASE + 2 * int(k));
        t[0] = floatBits(p.p0.x);
        t[1] = floatBits(p.p0.y);
        t[2] = floatBits(p.p1.x);
        t[3] = floatBits(p.p1.y);
        t[4] = floatBits(p.p2.x);
        t[5] = floatBits(p.p2.y);
        t[6] = glm::packHalf2x16(glm::vec2(p.width0, p.width1));
        t[7] = (p.curved ? 1u : 0u) | (uint32_t(p.profile + 1) << 8);
    }
}

} // namespace

void packNearField(const FeatureMaps& m, GpuFeatureMaps& g, const Exec& ex) {
    g.nearHeight = 0;
    g.nearLists.clear();
    g.pieces.clear();
    g.piecesHeight = 0;
    g.nearStats = {};
    if (!m.hasNearField()) return;
    const int n = m.size;
    const double band = m.nearBandTexels;
    // A piece can be listed in a texel only within band + the texel's
    // diameter of it (and the field's upper bound there).
    const double reach = band + 2.0;
    const int bins = (n + kBinTexels - 1) / kBinTexels;
    const std::vector<std::vector<int>> binned = binPieces(m.pieces, n, reach);
    std::vector<uint32_t> headers(size_t(n) * size_t(n) * 4, 0u);
    auto put = [](uint32_t* t, size_t slot, int piece) {
        t[slot / 2] |= uint32_t(piece + 1) << (16 * (slot % 2));
    };
    // Per block of rows: its statistics and its long lists (texel, pieces).
    struct Block {
        int bandTexels = 0, maxPieces = 0;
        long long total = 0;
        std::vector<std::pair<size_t, std::vector<int>>> longLists;
    };
    constexpr size_t kRowsPerBlock = 8;
    std::vector<Block> blocks(blockCount(size_t(n), kRowsPerBlock));
    forBlocks(ex, size_t(n), kRowsPerBlock, [&](size_t b, size_t j0, size_t j1) {
        Block& blk = blocks[b];
        for (int j = int(j0); j < int(j1); ++j) {
            for (int i = 0; i < n; ++i) {
                const auto& bin =
                    binned[size_t(j / kBinTexels) * size_t(bins) + size_t(i / kBinTexels)];
                std::vector<int> list = texelList(m.pieces, bin, i, j, band, reach);
                if (list.empty()) continue;
                ++blk.bandTexels;
                blk.total += (long long)list.size();
                blk.maxPieces = std::max(blk.maxPieces, int(list.size()));
                const size_t texel = size_t(j) * size_t(n) + size_t(i);
                if (list.size() <= 8) {
                    for (size_t k = 0; k < list.size(); ++k) put(&headers[texel * 4], k, list[k]);
                    continue;
                }
                blk.longLists.emplace_back(texel, std::move(list));
            }
        }
    });
    std::vector<uint32_t> overflow; // 4 words per texel, 8 slots
    long long total = 0;
    for (Block& blk : blocks) {
        g.nearStats.bandTexels += blk.bandTexels;
        total += blk.total;
        g.nearStats.maxPieces = std::max(g.nearStats.maxPieces, blk.maxPieces);
        for (const auto& [texel, list] : blk.longLists) {
            ++g.nearStats.overflowTexels;
            const size_t start = overflow.size() / 4;
            overflow.resize(overflow.size() + 4 * ((list.size() + 7) / 8), 0u);
            for (size_t k = 0; k < list.size(); ++k) put(&overflow[start * 4], k, list[k]);
            uint32_t* h = &headers[texel * 4];
            h[0] = uint32_t(list.size());
            h[1] = uint32_t(start);
            h[3] = 0x80000000u;
        }
        blk.longLists = {};
    }
    g.nearStats.meanPieces =
        g.nearStats.bandTexels ? double(total) / double(g.nearStats.bandTexels) : 0.0;
    const size_t overflowTexels = overflow.size() / 4;
    const int overflowRows = int((overflowTexels + size_t(n) - 1) / size_t(n));
    g.nearHeight = n + overflowRows;
    g.nearLists = std::move(headers);
    g.nearLists.resize(size_t(n) * size_t(g.nearHeight) * 4, 0u);
    std::copy(overflow.begin(), overflow.end(),
              g.nearLists.begin() + std::ptrdiff_t(size_t(n) * size_t(n) * 4));
    packPieces(m, g);
}

void checkNearFieldWork(const FeatureMaps& m, const std::string& source) {
    // Per piece: the texels of the bins within reach of it, at most its
    // length (bounded by its control polygon) plus the reach and a bin on
    // each side, times twice that across; and the bins of its box it tests.
    const double reach = m.nearBandTexels + 2.0, n = m.size;
    double work = 0.0;
    for (const NearPiece& p : m.pieces) {
        double len = double(glm::length(p.p1 - p.p0) + glm::length(p.p2 - p.p1));
        double across = 2.0 * (reach + kBinTexels);
        // (The box clipped to the map: binning visits only the map's bins.)
        const dvec2 lo = glm::clamp(dvec2(glm::min(glm::min(p.p0, p.p1), p.p2)), 0.0, n);
        const dvec2 hi = glm::clamp(dvec2(glm::max(glm::max(p.p0, p.p1), p.p2)), 0.0, n);
        const dvec2 ext = hi - lo;
        double boxBins = (ext.x + across) * (ext.y + across) / (kBinTexels * kBinTexels);
        work += (std::min(len, 4.0 * n) + across) * across + boxBins;
    }
    if (work > kNearWorkBudget) {
        throw io::InputError(source, "near field",
                             "its pieces cover " + std::to_string(static_cast<long long>(work)) +
                                 " texels of list work (the limit is " +
                                 std::to_string(static_cast<long long>(kNearWorkBudget)) +
                                 "): fewer or shorter pieces, or a narrower band");
    }
}

void keepNearPieces(const CurveNetwork& net, const std::vector<TexelPiece>& segs,
                    const BakeOptions& opt, const TexelTransform& xf, FeatureMaps& maps,
                    BakeStats& st) {
    const std::string file = net.source.empty() ? "(curve network)" : net.source;
    if (!(opt.nearWidthTexels > 0.0 && opt.nearWidthTexels <= 1024.0) ||
        !(opt.nearMarginTexels >= 0.0 && opt.nearMarginTexels <= 1024.0)) {
        throw io::InputError("(options)", "near",
                             "the default profile width must be in (0, 1024] texels and the "
                             "margin in [0, 1024]");
    }
    if (segs.size() > size_t(kMaxNearPieces)) {
        throw io::InputError(file, "",
                             "the exact near field holds at most " +
                                 std::to_string(kMaxNearPieces) + " pieces, the network has " +
                                 std::to_string(segs.size()));
    }
    // Widths scale like lengths; with an anisotropic transform, by the
    // geometric mean of the two scales.
    const double scale = std::sqrt(std::fabs(xf.scale.x * xf.scale.y));
    std::vector<int> profileOf(net.curves.size(), -1);
    for (size_t c = 0; c < net.curves.size(); ++c) {
        const std::string& name = net.curves[c].profile;
        if (name.empty()) continue;
        const std::string element = "curves[" + std::to_string(c) + "].profile";
        try {
            (void)makeProfile(name, 1.0f, 0.0f, 1.0f);
        } catch (const io::InputError& e) {
            throw io::InputError(file, element, e.reason());
        }
        auto it = std::find(maps.profiles.begin(), maps.profiles.end(), name);
        if (it == maps.profiles.end()) {
            if (maps.profiles.size() >= size_t(SG_FEAT_MAX_PROFILES)) {
                throw io::InputError(file, element,
                                     "more than " + std::to_string(SG_FEAT_MAX_PROFILES) +
                                         " distinct profiles in one map");
            }
            it = maps.profiles.insert(maps.profiles.end(), name);
        }
        profileOf[c] = int(it - maps.profiles.begin());
    }
    double widest = opt.nearWidthTexels;
    maps.pieces.resize(segs.size());
    for (size_t k = 0; k < segs.size(); ++k) {
        const Segment& in = net.segments[k];
        const CurveInfo* curve = in.curve >= 0 && size_t(in.curve) < net.curves.size()
                                     ? &net.curves[size_t(in.curve)]
                                     : nullptr;
        auto width = [&](double w) {
            double v = w >= 0.0 ? w : (curve && curve->width >= 0.0 ? curve->width : -1.0);
            return v >= 0.0 ? v * scale : 0.0;
        };
        NearPiece& p = maps.pieces[k];
        p.p0 = glm::vec2(segs[k].q.p0);
        p.p2 = glm::vec2(segs[k].q.p2);
        p.curved = !segs[k].line;
        p.p1 = p.curved ? glm::vec2(segs[k].q.p1) : 0.5f * (p.p0 + p.p2);
        p.profile = curve ? profileOf[size_t(in.curve)] : -1;
        const double w0 = width(in.width0), w1 = width(in.width1);
        if (!std::isfinite(w0) || !std::isfinite(w1) || w0 > 1024.0 || w1 > 1024.0) {
            throw io::InputError(file, "segment " + std::to_string(k),
                                 "profile width outside [0, 1024] texels at this map size");
        }
        p.width0 = float(w0);
        p.width1 = float(w1);
        widest = std::max({widest, double(p.width0), double(p.width1)});
    }
    maps.nearBandTexels = widest + opt.nearMarginTexels;
    if (maps.nearBandTexels > opt.bandTexels) {
        throw io::InputError("(options)", "near",
                             "the widest profile (" + std::to_string(widest) +
                                 " texels) plus the margin exceeds the band of exact corner "
                                 "distances (" +
                                 std::to_string(opt.bandTexels) + " texels): raise --band");
    }
    if (maps.nearBandTexels > kMaxNearBandTexels) {
        throw io::InputError("(options)", "near",
                             "the near band may be at most " +
                                 std::to_string(int(kMaxNearBandTexels)) + " texels");
    }
    checkNearFieldWork(maps, file);
    st.nearPieces = int(maps.pieces.size());
    st.nearBandTexels = maps.nearBandTexels;
}

} // namespace detail

double GpuFeatureMaps::nearBytesPerTexel() const {
    if (!hasNearField()) return 0.0;
    return 16.0 *
           (double(size) * double(nearHeight) + double(SG_FEAT_PIECES_WIDTH) * piecesHeight) /
           (double(size) * double(size));
}

} // namespace sg::features
