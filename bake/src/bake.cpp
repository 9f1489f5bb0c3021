// bake(): texel centres -> limit-surface points (uv_cover, limit_patches),
// rays along +- the limit normal into the high mesh (high_mesh), the hit's
// displacement and normal in the limit frame, padding around the charts.
// See surfgrad/bake/baker.h for the contract and the papers.
#include "surfgrad/bake/baker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "high_mesh.h"
#include "base_surface.h"
#include "residual.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/base/threads.h"
#include "uv_cover.h"

namespace sg::bake {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

void checkSettings(const mesh::PolygonMesh& cage, const BakeSettings& s, const std::string& file) {
    if (const std::string why = bakeSizeProblem(s.width, s.height); !why.empty())
        throw io::InputError(file, "size", why);
    const uint64_t budget = s.memoryBudget ? s.memoryBudget : mesh::defaultSubdivisionBudget();
    const uint64_t bytes = uint64_t(s.width) * uint64_t(s.height) *
                           (kBakeBytesPerTexel + (s.residual ? kBakeResidualBytesPerTexel : 0));
    if (bytes > budget)
        throw io::InputError(file, "size",
                             std::to_string(s.width) + "x" + std::to_string(s.height) + " needs " +
                                 mesh::formatByteSize(bytes) + " of grids, above the budget of " +
                                 mesh::formatByteSize(budget));
    if (s.surface == BakeSurface::Limit && cage.options.scheme != mesh::Scheme::Catmark)
        throw io::InputError(file, "scheme",
                             std::string("the bake evaluates Catmull-Clark limit surfaces; the "
                                         "cage is ") +
                                 mesh::toString(cage.options.scheme));
    if (s.uvSet < 0 || size_t(s.uvSet) >= cage.uvSets.size())
        throw io::InputError(file, "uv set " + std::to_string(s.uvSet),
                             "the cage has " + std::to_string(cage.uvSets.size()) +
                                 " UV set(s): the maps need a UV layout");
    if (s.surface == BakeSurface::Refined &&
        (s.refinedLevel < 0 || s.refinedLevel > mesh::kMaxSubdivisionLevel))
        throw io::InputError(file, "level",
                             std::to_string(s.refinedLevel) + ": expected 0.." +
                                 std::to_string(mesh::kMaxSubdivisionLevel));
    if (s.isolation < 1 || s.isolation > 10)
        throw io::InputError(file, "isolation", std::to_string(s.isolation) + ": expected 1..10");
    if (s.padTexels < 0 || s.padTexels > 1024)
        throw io::InputError(file, "padding",
                             std::to_string(s.padTexels) + ": expected 0..1024 texels");
    if (!std::isfinite(s.maxDistance) || s.maxDistance < 0)
        throw io::InputError(file, "max distance",
                             "expected a finite distance >= 0 (0: the default)");
}

// 5 % of the cage's bounding-box diagonal (bake.h).
double defaultDistance(const mesh::PolygonMesh& cage) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::vec3& p : cage.positions) {
        lo = glm::min(lo, glm::dvec3(p));
        hi = glm::max(hi, glm::dvec3(p));
    }
    return 0.05 * glm::length(hi - lo);
}

BakeResult emptyResult(int w, int h) {
    BakeResult r;
    r.width = w;
    r.height = h;
    r.state = normalmap::Grid<uint8_t>(w, h, uint8_t(TexelState::Empty));
    r.displacement = normalmap::ScalarField(w, h, 0.0f);
    r.objectNormal = normalmap::NormalField(w, h, glm::vec3(0.0f));
    r.basePosition = normalmap::NormalField(w, h, glm::vec3(0.0f));
    r.baseNormal = normalmap::NormalField(w, h, glm::vec3(0.0f));
    r.baseTangent = normalmap::Grid<glm::vec4>(w, h, glm::vec4(0.0f));
    return r;
}

// One texel: its point and frame on the base surface, the rays.
struct TexelBaker {
    const detail::BaseSurface& base;
    const detail::HighMesh& high;
    float tFar;
    glm::vec2 texelsPerUv;

    struct Outcome {
        float residualTexels = 0.0f; // |st - texel centre| left (limit: by Newton)
        bool overlap = false;        // the runner-up primitive is elsewhere on the surface
    };

    Outcome operator()(const detail::TexelClaim& c, int i, int j, BakeResult& r) const {
        Outcome o;
        const glm::vec2 target = (glm::vec2(float(i), float(j)) + 0.5f) / texelsPerUv;
        const detail::BaseSample b = base.at(c.patch, c.patchUv, target);
        o.residualTexels = b.residualTexels;
        // The runner-up claim's point with the same UV more than half a
        // texel of surface length away: two charts on one texel, not the two
        // sides of a shared edge (those meet within the claim tolerance, a
        // thousandth of a texel).
        if (c.otherPatch != UINT32_MAX)
            o.overlap = glm::length(base.at(c.otherPatch, c.otherUv, target).pos - b.pos) >
                        0.5f * b.texelLength;
        r.basePosition.at(i, j) = b.pos;
        r.baseNormal.at(i, j) = b.normal;
        r.baseTangent.at(i, j) = b.tangent;
        const detail::RayHit up = high.cast(b.pos, b.normal, tFar);
        const detail::RayHit down = high.cast(b.pos, -b.normal, tFar);
        // The hit nearest the base point; outwards on a tie.
        const bool useDown = down.hit && (!up.hit || down.t < up.t);
        if (!up.hit && !down.hit) {
            r.state.at(i, j) = uint8_t(TexelState::Miss);
        } else {
            r.state.at(i, j) = uint8_t(TexelState::Hit);
            r.displacement.at(i, j) = useDown ? -down.t : up.t;
            r.objectNormal.at(i, j) = useDown ? down.normal : up.normal;
        }
        return o;
    }
};

// Every texel of the cover, in blocks of rows (progress between blocks);
// sets the residual and overlap statistics.
void bakeTexels(const detail::UvCover& cover, const TexelBaker& baker, BakeResult& r,
                const BakeProgress& progress) {
    const int blockRows = std::max(1, (1 << 16) / r.width);
    std::vector<float> rowResidual(size_t(r.height), 0.0f);
    std::vector<size_t> rowOverlaps(size_t(r.height), 0);
    for (int j0 = 0; j0 < r.height; j0 += blockRows) {
        const int j1 = std::min(r.height, j0 + blockRows);
        tbb::parallel_for(tbb::blocked_range<int>(j0, j1), [&](const tbb::blocked_range<int>& rr) {
            for (int j = rr.begin(); j != rr.end(); ++j)
                for (int i = 0; i < r.width; ++i) {
                    const detail::TexelClaim& c =
                        cover.claims[size_t(j) * size_t(r.width) + size_t(i)];
                    if (c.patch == UINT32_MAX) continue;
                    const TexelBaker::Outcome o = baker(c, i, j, r);
                    rowResidual[size_t(j)] = std::max(rowResidual[size_t(j)], o.residualTexels);
                    rowOverlaps[size_t(j)] += o.overlap ? 1 : 0;
                }
        });
        if (progress) progress("texels", double(j1) / double(r.height));
    }
    r.stats.maxUvResidualTexels = *std::max_element(rowResidual.begin(), rowResidual.end());
    for (size_t n : rowOverlaps) r.stats.overlapTexels += n;
}

// Texels that take the values of the nearest hit (breadth first over the
// 8-neighbourhood from every hit, in row-major order, neighbours in a fixed
// order): misses at any distance, empty texels up to padTexels rings.
void pad(BakeResult& r, int padTexels) {
    const int w = r.width, h = r.height;
    std::vector<int> ring(size_t(w) * size_t(h), -1);
    std::vector<uint32_t> source(ring.size(), UINT32_MAX);
    // First in, first out: a vector read from `head` (each texel enters once).
    std::vector<uint32_t> queue;
    for (uint32_t t = 0; t < ring.size(); ++t)
        if (r.state.v[t] == uint8_t(TexelState::Hit)) {
            ring[t] = 0;
            source[t] = t;
            queue.push_back(t);
        }
    static constexpr int kDi[8] = {1, -1, 0, 0, 1, -1, 1, -1};
    static constexpr int kDj[8] = {0, 0, 1, -1, 1, 1, -1, -1};
    for (size_t head = 0; head < queue.size(); ++head) {
        const uint32_t t = queue[head];
        const int i = int(t % uint32_t(w)), j = int(t / uint32_t(w));
        for (int k = 0; k < 8; ++k) {
            const int ni = i + kDi[k], nj = j + kDj[k];
            if (ni < 0 || nj < 0 || ni >= w || nj >= h) continue;
            const uint32_t n = uint32_t(nj) * uint32_t(w) + uint32_t(ni);
            if (ring[n] >= 0) continue;
            const bool miss = r.state.v[n] == uint8_t(TexelState::Miss);
            if (!miss && ring[t] + 1 > padTexels) continue;
            ring[n] = ring[t] + 1;
            source[n] = source[t];
            queue.push_back(n);
        }
    }
    for (uint32_t t = 0; t < ring.size(); ++t) {
        if (ring[t] <= 0) continue;
        const uint32_t s = source[t];
        if (r.state.v[t] == uint8_t(TexelState::Empty)) {
            r.state.v[t] = uint8_t(TexelState::Padded);
            ++r.stats.padded;
        }
        r.displacement.v[t] = r.displacement.v[s];
        r.objectNormal.v[t] = r.objectNormal.v[s];
        r.tangentSlopes.v[t] = r.tangentSlopes.v[s];
        if (!r.residualSlopes.v.empty()) r.residualSlopes.v[t] = r.residualSlopes.v[s];
    }
}

BakeResult bakeImpl(const mesh::PolygonMesh& cage, const mesh::RenderMesh& high,
                    const BakeSettings& s, const std::string& cageFile, const std::string& highFile,
                    const BakeProgress& progress) {
    BakeResult r = emptyResult(s.width, s.height);
    BakeStats& st = r.stats;
    st.maxDistance = s.maxDistance > 0 ? s.maxDistance : defaultDistance(cage);
    auto t = Clock::now();
    const glm::vec2 texelsPerUv(float(s.width), float(s.height));
    const std::unique_ptr<detail::BaseSurface> base =
        s.surface == BakeSurface::Limit
            ? detail::limitBase(cage, s.isolation, s.uvSet, cageFile, s.threads, texelsPerUv)
            : detail::triangleBase(cage, s.refinedLevel, s.uvSet, cageFile, s.threads, texelsPerUv);
    st.patches = base->primitiveCount();
    st.secondsPatches = secondsSince(t);
    t = Clock::now();
    const detail::HighMesh hm(high, highFile);
    st.secondsHighMesh = secondsSince(t);
    t = Clock::now();
    if (progress) progress("cover", 0.0);
    const detail::UvCover cover = base->cover(s.width, s.height);
    if (progress) progress("cover", 1.0);
    st.secondsCover = secondsSince(t);
    st.chartTexels = cover.chartTexels;
    if (cover.chartTexels == 0)
        throw io::InputError(cageFile, "uv set " + std::to_string(s.uvSet),
                             "no texel centre of the " + std::to_string(s.width) + "x" +
                                 std::to_string(s.height) +
                                 " map lies on the cage's UV layout inside [0, 1]^2");
    t = Clock::now();
    const TexelBaker baker{*base, hm, float(st.maxDistance), texelsPerUv};
    bakeTexels(cover, baker, r, progress);
    st.secondsTexels = secondsSince(t);
    for (size_t k = 0; k < r.state.v.size(); ++k) {
        if (r.state.v[k] == uint8_t(TexelState::Hit)) {
            ++st.hits;
            st.maxAbsDisplacement =
                std::max(st.maxAbsDisplacement, double(std::abs(r.displacement.v[k])));
        } else if (r.state.v[k] == uint8_t(TexelState::Miss)) {
            ++st.misses;
        }
    }
    if (st.hits == 0)
        throw io::InputError(
            highFile, "",
            "no ray from the cage's limit surface (" + std::to_string(st.chartTexels) +
                " texels) hit the high mesh within " + std::to_string(st.maxDistance) +
                " object units: are both meshes in the same space and scale?");
    t = Clock::now();
    // The limit frame's grids lend themselves to the conversion (moved,
    // not copied: hundreds of MB at 4096^2) and come back after it.
    normalmap::TexelFrames frames;
    frames.normal = std::move(r.baseNormal);
    frames.tangent = std::move(r.baseTangent);
    frames.covered = normalmap::Grid<uint8_t>(s.width, s.height, 0);
    for (size_t k = 0; k < r.state.v.size(); ++k)
        frames.covered.v[k] = r.state.v[k] == uint8_t(TexelState::Hit) ? 1 : 0;
    r.tangentSlopes = normalmap::tangentFromObject(r.objectNormal, frames);
    if (s.residual)
        r.residualSlopes = normalmap::tangentFromObject(
            detail::residualNormals(r.state, r.basePosition, frames.normal, r.displacement,
                                    r.objectNormal),
            frames);
    r.baseNormal = std::move(frames.normal);
    r.baseTangent = std::move(frames.tangent);
    pad(r, s.padTexels);
    st.secondsPad = secondsSince(t);
    return r;
}

} // namespace

std::string bakeSizeProblem(int width, int height) {
    if (width >= 1 && height >= 1 && width <= kMaxBakeSide && height <= kMaxBakeSide &&
        size_t(width) * size_t(height) <= kMaxBakeTexels)
        return {};
    return std::to_string(width) + "x" + std::to_string(height) + ": expected sides 1.." +
           std::to_string(kMaxBakeSide) + " and at most " + std::to_string(kMaxBakeTexels) +
           " texels";
}

BakeResult bake(const mesh::PolygonMesh& cage, const mesh::RenderMesh& high,
                const BakeSettings& settings, const std::string& cageFile,
                const std::string& highFile, const BakeProgress& progress) {
    SG_EXPECTS(threadCountProblem(settings.threads).empty(), "bake: threads outside 0..1024");
    checkSettings(cage, settings, cageFile);
    return runWithThreads(settings.threads, [&] {
        return bakeImpl(cage, high, settings, cageFile, highFile, progress);
    });
}

} // namespace sg::bake
