// Primvar adaptors for OpenSubdiv: what Far::PrimvarRefiner (Interpolate,
// InterpolateFaceVarying, Limit) and Far::StencilTable::UpdateValues take as
// source and destination buffers, over plain arrays of glm vectors (or any
// V with V(0.0f), += and scalar *). Element i of a PrimvarView is
// base[i]; Clear() zeroes it and AddWithWeight(src, w) adds w * src, the
// two operations OpenSubdiv applies per refined or limit point.
//
//   sg::mesh::PrimvarView<const glm::vec3> src{cagePositions.data()};
//   sg::mesh::PrimvarView<glm::vec3> dst{refinedPositions.data()};
//   primvarRefiner.Interpolate(1, src, dst);
//
// Header-only and needs no OpenSubdiv header (OpenSubdiv's templates call
// these members by name).
#pragma once

namespace sg::mesh {

template <class V>
struct PrimvarRef {
    V* v;
    void Clear() { *v = V(0.0f); }
    template <class S>
    void AddWithWeight(const S& src, float w) {
        *v += w * *src.v;
    }
};

template <class V>
struct PrimvarView {
    V* base;
    PrimvarRef<V> operator[](int i) const { return {base + i}; }
};

} // namespace sg::mesh
