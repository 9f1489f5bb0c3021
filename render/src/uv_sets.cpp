// UV sets of a mesh asset: the derived sets of the scene's "uv_sets" field
// and the re-centring of sets that only repeating maps read
// (render_internal.h).
//
// Re-centring. The GPU interpolates a texture coordinate in binary32 and
// takes dFdxFine as the difference of two interpolated values, so both
// carry an absolute error of about an ulp of the coordinate. World-unit
// terrain UVs around 1e4 keep only about 10 bits of their fraction there:
// the per-pixel frame (listing 6), listing 8's chain rule and the texture
// LOD then see derivatives with errors of 1e-3 per pixel, and the GPU and
// the CPU reference disagree by tens of degrees. A whole-unit shift of the
// coordinate changes nothing a repeating texture samples, so sets read only
// by repeating maps are moved, at load, by the integer part of their
// bounding box's centre (chosen in binary64): the coordinates come back
// next to 0 with every bit of their fraction. Derived sets are computed in
// binary64 from their source and shifted before they are rounded, so their
// fraction is exact to binary32 there. Shown only by the `uv` AOV (which
// then reads the shifted coordinate).
#include <algorithm>
#include <cmath>

#include "layer_kind.h"
#include "render_internal.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/base/io.h"

namespace sg::render::detail {

namespace sm = sg::mesh;

namespace {

// Clears the bit of every set a layer (and its group's children) reads
// through something other than repeating maps.
void markLayer(const Layer& L, uint32_t& repeatOnly) {
    for (const Layer& c : L.children) markLayer(c, repeatOnly);
    if (!L.kind || !L.kind->readsUv || L.uvSet < 0 || L.uvSet >= kMaxUvSets) return;
    bool repeats = !(L.kind->assets && L.kind->assets->reads(L)); // clamped (LayerKindAssets)
    for (const TextureSource& m : L.maps) repeats = repeats && m.wrap == Wrap::Repeat;
    for (const Modifier& md : L.modifiers)
        if (md.mask) repeats = repeats && md.mask->wrap == Wrap::Repeat;
    if (!repeats) repeatOnly &= ~(1u << L.uvSet);
}

// The linear part R(rotate_deg) * scale of derived UV set `d` on a mesh
// that has `count` sets at this point; an InputError naming d's field when
// its source set does not exist or the mesh is full.
glm::dmat2 derivedUvLinear(const Scene& scene, const DerivedUvSet& d, size_t count) {
    if (size_t(d.from) >= count) {
        throw io::InputError(scene.sourceName, d.fieldPath + ".from",
                             "the mesh has " + std::to_string(count) + " UV set(s) (0.." +
                                 std::to_string(int(count) - 1) + ") at this point, no set " +
                                 std::to_string(d.from));
    }
    if (count >= size_t(kMaxUvSets)) {
        throw io::InputError(scene.sourceName, d.fieldPath,
                             "a mesh can have at most " + std::to_string(kMaxUvSets) +
                                 " UV sets (it has " + std::to_string(count) + " already)");
    }
    const double a = glm::radians(double(d.rotateDeg)), c = std::cos(a), sn = std::sin(a);
    // Column-major: R = [[c, s], [-s, c]] as columns, then scale per axis.
    return glm::dmat2(c, sn, -sn, c) * glm::dmat2(double(d.scale.x), 0.0, 0.0, double(d.scale.y));
}

// The whole units (per coordinate) of the centre of the bounding box of
// values + shift, rounded toward zero; 0 for an empty or non-finite set.
glm::dvec2 wholeUnitsOfCentre(const std::vector<glm::dvec2>& values) {
    if (values.empty()) return glm::dvec2(0.0);
    glm::dvec2 lo = values[0], hi = values[0];
    for (const glm::dvec2& v : values) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
    }
    const glm::dvec2 c = 0.5 * (lo + hi);
    if (!std::isfinite(c.x) || !std::isfinite(c.y)) return glm::dvec2(0.0);
    return glm::trunc(c);
}

// One derived set's values in binary64 (source values plus the source's
// shift, mapped), shifted by their whole units when `recentre`; returns the
// shift.
glm::dvec2 derive(const std::vector<glm::vec2>& source, glm::dvec2 sourceShift,
                  const glm::dmat2& lin, glm::dvec2 offset, bool recentre,
                  std::vector<glm::vec2>& out) {
    std::vector<glm::dvec2> exact(source.size());
    for (size_t i = 0; i < source.size(); ++i)
        exact[i] = lin * (glm::dvec2(source[i]) + sourceShift) + offset;
    const glm::dvec2 shift = recentre ? wholeUnitsOfCentre(exact) : glm::dvec2(0.0);
    out.resize(exact.size());
    for (size_t i = 0; i < exact.size(); ++i) out[i] = glm::vec2(exact[i] - shift);
    return shift;
}

// Shifts set values by their whole units (recentreUvSets on one set).
glm::dvec2 recentreSet(std::vector<glm::vec2>& values) {
    std::vector<glm::dvec2> exact(values.begin(), values.end());
    const glm::dvec2 shift = wholeUnitsOfCentre(exact);
    if (shift == glm::dvec2(0.0)) return shift;
    for (size_t i = 0; i < values.size(); ++i) values[i] = glm::vec2(exact[i] - shift);
    return shift;
}

} // namespace

uint32_t repeatOnlyUvSets(const Scene& scene, const MeshInstance& mi) {
    uint32_t repeatOnly = (1u << kMaxUvSets) - 1u;
    if (mi.material < 0 || size_t(mi.material) >= scene.materials.size()) return 0u;
    const Material& m = scene.materials[size_t(mi.material)];
    for (const Layer& L : m.layers) markLayer(L, repeatOnly);
    if (m.baseColorMap && m.baseColorMap->wrap != Wrap::Repeat)
        repeatOnly &= ~(1u << m.baseColorUvSet);
    if (mi.displacement && mi.displacement->map.wrap != Wrap::Repeat)
        repeatOnly &= ~(1u << mi.displacement->uvSet);
    return repeatOnly;
}

void recentreUvSets(uint32_t sets, std::vector<std::vector<glm::vec2>>& uvSets) {
    for (size_t k = 0; k < uvSets.size() && k < size_t(kMaxUvSets); ++k)
        if (sets >> k & 1u) recentreSet(uvSets[k]);
}

void addDerivedUvSets(const Scene& scene, const MeshInstance& mi, uint32_t repeatOnly,
                      sm::RenderMesh& mesh, sm::LimitFrame& limit) {
    // The mesh's own sets are still as loaded (shift 0); derived sets record
    // theirs so a set derived from a derived one starts from exact values.
    std::vector<glm::dvec2> shift(mesh.uvSets.size(), glm::dvec2(0.0));
    for (const DerivedUvSet& d : mi.derivedUvSets) {
        const size_t count = mesh.uvSets.size();
        const glm::dmat2 lin = derivedUvLinear(scene, d, count);
        std::vector<glm::vec2> uv;
        shift.push_back(derive(mesh.uvSets[size_t(d.from)], shift[size_t(d.from)], lin,
                               glm::dvec2(d.offset), (repeatOnly >> count) & 1u, uv));
        mesh.uvSets.push_back(std::move(uv));
        if (!limit.empty() && limit.dUVdu.size() == count && limit.dUVdv.size() == count) {
            const glm::mat2 linF(lin);
            std::vector<glm::vec2> du(limit.dUVdu[size_t(d.from)]), dv(limit.dUVdv[size_t(d.from)]);
            for (auto& x : du) x = linF * x;
            for (auto& x : dv) x = linF * x;
            limit.dUVdu.push_back(std::move(du));
            limit.dUVdv.push_back(std::move(dv));
        }
    }
}

void addDerivedPatchUvSets(const Scene& scene, const MeshInstance& mi, uint32_t repeatOnly,
                           sm::AdaptivePatches& ap) {
    const size_t own = ap.uvSets.size();
    std::vector<glm::dvec2> shift(own, glm::dvec2(0.0));
    for (const DerivedUvSet& d : mi.derivedUvSets) {
        const size_t count = ap.uvSets.size();
        const glm::dmat2 lin = derivedUvLinear(scene, d, count);
        sm::AdaptiveUvSet set = ap.uvSets[size_t(d.from)];
        shift.push_back(derive(ap.uvSets[size_t(d.from)].values, shift[size_t(d.from)], lin,
                               glm::dvec2(d.offset), (repeatOnly >> count) & 1u, set.values));
        ap.uvSets.push_back(std::move(set));
    }
    for (size_t k = 0; k < own && k < size_t(kMaxUvSets); ++k)
        if (repeatOnly >> k & 1u) recentreSet(ap.uvSets[k].values);
}

} // namespace sg::render::detail
