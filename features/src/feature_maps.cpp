// Feature maps: packing for the GPU, the C++ sampling entry point and the
// named profiles (see surfgrad/features/feature_maps.h).
#include <charconv>
#include <cmath>

#include "surfgrad/base/scratch_buffer.h"
#include "bake_internal.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/base/io.h"
#include "surfgrad/base/threads.h"

namespace sg::features {

uint32_t FeatureMaps::configWord(int i, int j) const {
    SG_EXPECTS(i >= 0 && j >= 0 && i < size && j < size, "texel (i, j) inside the map");
    uint32_t w = seg[index(i, j)] & 0x0FFFu;
    // Edge flags: S, E, N, W.
    if (hPos[index(i, j)] >= 0.0f) w |= 1u << 12;
    if (vPos[index(i + 1, j)] >= 0.0f) w |= 1u << 13;
    if (hPos[index(i, j + 1)] >= 0.0f) w |= 1u << 14;
    if (vPos[index(i, j)] >= 0.0f) w |= 1u << 15;
    // Corner side bits: SW, SE, NE, NW.
    if (left[index(i, j)]) w |= 1u << 16;
    if (left[index(i + 1, j)]) w |= 1u << 17;
    if (left[index(i + 1, j + 1)]) w |= 1u << 18;
    if (left[index(i, j + 1)]) w |= 1u << 19;
    w |= 1u << 20; // edge words carry tangent angles (both modes)
    return w;
}

void FeatureMaps::edgeWords(int i, int j, uint32_t out[4]) const {
    auto word = [](float pos, float angle) {
        return pos >= 0.0f ? detail::packEdgeWord(pos, angle) : 0u;
    };
    out[0] = word(hPos[index(i, j)], hAngle[index(i, j)]);
    out[1] = word(vPos[index(i + 1, j)], vAngle[index(i + 1, j)]);
    out[2] = word(hPos[index(i, j + 1)], hAngle[index(i, j + 1)]);
    out[3] = word(vPos[index(i, j)], vAngle[index(i, j)]);
}

namespace {

// Half-float pair, with half denormals flushed to zero so GPUs that flush
// them on unpacking agree with the CPU.
uint32_t halfPair(float a, float b) {
    auto flush = [](float v) { return std::fabs(v) < 6.103515625e-05f ? 0.0f : v; };
    return glm::packHalf2x16(glm::vec2(flush(a), flush(b)));
}

} // namespace

namespace {

// packGpu's loops with the loops of `ex` (rows of texels in parallel).
GpuFeatureMaps packGpuRows(const FeatureMaps& m, const detail::Exec& ex) {
    constexpr size_t kRowsPerBlock = 16;
    const int size = m.size;
    GpuFeatureMaps g;
    g.size = size;
    sg::detail::assignWithHugePages(g.cornerPairs, size_t(size) * size_t(size + 1) * 4, 0u);
    sg::detail::assignWithHugePages(g.edges, size_t(size) * size_t(size) * 4, 0u);
    detail::forBlocks(ex, size_t(size) + 1, kRowsPerBlock, [&](size_t, size_t j0, size_t j1) {
        for (int j = int(j0); j < int(j1); ++j) {
            for (int i = 0; i < size; ++i) {
                size_t a = m.index(i, j), b = m.index(i + 1, j);
                uint32_t* c = &g.cornerPairs[(size_t(j) * size_t(size) + size_t(i)) * 4];
                c[0] = halfPair(m.dist[a], m.dist[b]);
                c[1] = halfPair(m.gradX[a], m.gradY[a]);
                c[2] = halfPair(m.gradX[b], m.gradY[b]);
                c[3] = j < size ? m.configWord(i, j) : 0u;
                if (j < size)
                    m.edgeWords(i, j, &g.edges[(size_t(j) * size_t(size) + size_t(i)) * 4]);
            }
        }
    });
    detail::packNearField(m, g, ex);
    return g;
}

} // namespace

GpuFeatureMaps FeatureMaps::packGpu(int threads) const {
    SG_EXPECTS(threads >= 0 && threads <= kMaxThreads, "threads is 0 (all cores) .. kMaxThreads");
    if (threads == 1 || size < kBakeSerialBelowSize) return packGpuRows(*this, {false});
    return runWithThreads(threads, [&] { return packGpuRows(*this, {true}); });
}

double FeatureMaps::canonicalBytesPerTexel() const {
    // d, gx, gy, seg, hT, vT, hA, vA as float, left as a byte, per corner.
    double perCorner = 8.0 * 4.0 + 1.0;
    double corners = double(size + 1) * double(size + 1);
    return perCorner * corners / (double(size) * double(size));
}

const char* toString(NearMode m) {
    return m == NearMode::Exact ? "exact" : "paper";
}

glsl::SgFeatResult sample(const GpuFeatureMaps& maps, glm::vec2 texelPos, NearMode near) {
    if (near == NearMode::Exact && maps.hasNearField()) {
        return glsl::sgFeatSampleNear(maps.cornerSampler(), maps.edgeSampler(), maps.nearSampler(),
                                      maps.pieceSampler(), texelPos);
    }
    return glsl::sgFeatSample(maps.cornerSampler(), maps.edgeSampler(), texelPos);
}

std::vector<std::string> profileNames() {
    return {"vgroove", "crease", "ridge", "step", "seam", "table:h0,h1,..."};
}

glsl::SgFeatProfile makeProfile(std::string_view name, float depth, float w0, float w) {
    glsl::SgFeatProfile p{};
    p.depth = depth;
    p.w0 = w0;
    p.w = w;
    p.tableCount = 0;
    for (float& v : p.table) v = 0.0f;
    if (!std::isfinite(depth) || !std::isfinite(w0) || !std::isfinite(w) || !(w > 0.0f) ||
        w0 < 0.0f) {
        throw io::InputError("profile", std::string(name),
                             "depth, w0 and w must be finite with w > 0 and w0 >= 0");
    }
    static const char* kNames[] = {"vgroove", "crease", "ridge", "step", "seam"};
    for (int k = 0; k < 5; ++k) {
        if (name == kNames[k]) {
            p.kind = k;
            return p;
        }
    }
    const std::string_view prefix = "table:";
    if (name.substr(0, prefix.size()) == prefix) {
        p.kind = SG_FEAT_PROFILE_TABLE;
        std::string_view rest = name.substr(prefix.size());
        int count = 0;
        while (!rest.empty()) {
            size_t comma = rest.find(',');
            std::string_view tok = rest.substr(0, comma);
            float v = 0.0f;
            auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
            if (r.ec != std::errc() || r.ptr != tok.data() + tok.size() || !std::isfinite(v) ||
                std::fabs(v) > 1e6f) {
                throw io::InputError("profile", std::string(name),
                                     "table value '" + std::string(tok) +
                                         "' is not a finite number");
            }
            if (count >= SG_FEAT_TABLE_MAX) {
                throw io::InputError("profile", std::string(name),
                                     "more than " + std::to_string(SG_FEAT_TABLE_MAX) +
                                         " table values");
            }
            p.table[count++] = v;
            if (comma == std::string_view::npos) break;
            rest = rest.substr(comma + 1);
        }
        if (count < 2)
            throw io::InputError("profile", std::string(name), "a table needs at least 2 values");
        p.tableCount = count;
        return p;
    }
    std::string names;
    for (const auto& s : profileNames()) names += (names.empty() ? "" : ", ") + s;
    throw io::InputError("profile", std::string(name), "unknown profile (one of: " + names + ")");
}

} // namespace sg::features
