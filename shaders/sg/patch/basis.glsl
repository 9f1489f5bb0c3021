// Basis functions of the patches of OpenSubdiv's feature-adaptive patch
// tables (Far::PatchTable built by Far::PatchTableFactory from an adaptively
// refined Catmull-Clark cage, Gregory-basis end caps), written once in the
// shared GLSL/C++ subset: the tessellation evaluation stage evaluates the
// limit surface with them on the GPU, the CPU reference renderer and the
// tests with the very same source through GLM.
//
// Math:
//  - regular patches: bicubic uniform B-spline tensor product (de Boor 1972;
//    the limit of Catmull-Clark on a regular grid, Catmull & Clark 1978),
//    with phantom points extrapolated linearly beyond boundary edges
//    (P_phantom = 2 P_1 - P_2, the boundary rule of Far): the weights of a
//    missing row or column are folded into the two rows next to it;
//  - Gregory-basis end caps: the 20-point cubic Gregory patch (Gregory 1974;
//    Loop, Schaefer, Ni & Castano, "Approximating subdivision surfaces with
//    Gregory patches for hardware tessellation", SIGGRAPH Asia 2009), each
//    interior Bezier point the rational blend of a pair of face points;
//    the derivatives differentiate the Bezier patch of the blended interior
//    points (the approximation of Loop et al. 2009 that Far and Osd use);
//  - parametrisation of a patch within its ptex face and the derivative
//    scale from its depth: Far::PatchParam (field1 bit layout below),
//    Niessner, Loop, Meyer & DeRose, "Feature-adaptive GPU rendering of
//    Catmull-Clark subdivision surfaces", ACM TOG 31(1), 2012.
//
// Point order: as in Far's patch arrays. Regular: a 4x4 grid, index
// 4 * row + column, row along +v, column along +u, the patch's domain the
// middle cell (points 5, 6, 10, 9). Gregory basis: five points per corner
// (corner point, edge point towards +-u, edge point towards +-v, the two
// face points), corners in the order (0,0), (1,0), (1,1), (0,1).
//
// Checked against Far::PatchTable::EvaluateBasis on every patch of every
// Catmull-Clark osd-shape (tests/bump/patch_basis_test.cpp).
#ifndef SG_PATCH_BASIS_GLSL
#define SG_PATCH_BASIS_GLSL

#include "sg/compat.glsl"

// Far::PatchDescriptor::Type values of the patch kinds evaluated here.
#define SG_PATCH_QUADS 3
#define SG_PATCH_REGULAR 6
#define SG_PATCH_GREGORY_BASIS 9

// Largest number of control points of a patch kind evaluated here.
#define SG_PATCH_MAX_POINTS 20

// One weight per control point (the first 4, 16 or 20 are used).
struct SgPatchRow {
    float v[SG_PATCH_MAX_POINTS];
};

// Weights of a patch's control points at one (u,v): position, and first
// derivatives with respect to the ptex face's (u,v) (not the patch's own
// sub-domain: the depth scale is applied). count: control points used.
struct SgPatchBasis {
    SgPatchRow pos;
    SgPatchRow du;
    SgPatchRow dv;
    int count;
};

// ---- Far::PatchParam, field1 (the bits the evaluation needs):
//   bits 0-3 depth, 4 non-quad root, 5 regular, 7-11 boundary mask
//   (bit 0: edge v=0, 1: u=1, 2: v=1, 3: u=0), 12-21 v, 22-31 u (the
//   patch's integer position within its ptex face at its depth).
SG_FN int sgPatchDepth(uint field1) { return int(field1 & 15u); }
SG_FN int sgPatchNonQuadRoot(uint field1) { return int((field1 >> 4u) & 1u); }
SG_FN int sgPatchBoundaryMask(uint field1) { return int((field1 >> 7u) & 31u); }
SG_FN vec2 sgPatchOrigin(uint field1) {
    return vec2(float((field1 >> 22u) & 1023u), float((field1 >> 12u) & 1023u));
}

// (u,v) of the ptex face -> (u,v) of the patch's own unit square
// (PatchParam::Normalize). The scale is a power of two: exact.
SG_FN vec2 sgPatchNormalizeUv(uint field1, vec2 faceUv) {
    float scale = float(1 << (sgPatchDepth(field1) - sgPatchNonQuadRoot(field1)));
    return faceUv * scale - sgPatchOrigin(field1);
}

// (u,v) of the patch's unit square -> (u,v) of the ptex face
// (PatchParam::Unnormalize).
SG_FN vec2 sgPatchUnnormalizeUv(uint field1, vec2 patchUv) {
    float scale = float(1 << (sgPatchDepth(field1) - sgPatchNonQuadRoot(field1)));
    return (patchUv + sgPatchOrigin(field1)) * (1.0f / scale);
}

// Uniform cubic B-spline curve basis at t (value, first derivative).
SG_FN vec4 sgBSplineCurve(float t) {
    float t2 = t * t, t3 = t2 * t;
    return vec4(1.0f - 3.0f * t + 3.0f * t2 - t3, 4.0f - 6.0f * t2 + 3.0f * t3,
                1.0f + 3.0f * t + 3.0f * t2 - 3.0f * t3, t3) *
           (1.0f / 6.0f);
}
SG_FN vec4 sgBSplineCurveDeriv(float t) {
    float t2 = t * t;
    return vec4(-0.5f * t2 + t - 0.5f, 1.5f * t2 - 2.0f * t, -1.5f * t2 + t + 0.5f, 0.5f * t2);
}

// Cubic Bernstein basis at t (value, first derivative).
SG_FN vec4 sgBezierCurve(float t) {
    float c = 1.0f - t;
    return vec4(c * c * c, 3.0f * t * c * c, 3.0f * t * t * c, t * t * t);
}
SG_FN vec4 sgBezierCurveDeriv(float t) {
    float c = 1.0f - t;
    return vec4(-3.0f * c * c, 3.0f * c * c - 6.0f * t * c, 6.0f * t * c - 3.0f * t * t,
                3.0f * t * t);
}

// Tensor product w[4 row + col] = s[col] * t[row] of two curve bases.
SG_FN SgPatchRow sgPatchTensor16(vec4 s, vec4 t) {
    SgPatchRow r;
    for (int row = 0; row < 4; ++row) {
        for (int col = 0; col < 4; ++col) r.v[4 * row + col] = s[col] * t[row];
    }
    for (int i = 16; i < SG_PATCH_MAX_POINTS; ++i) r.v[i] = 0.0f;
    return r;
}

// Folds the weights of the phantom points beyond the boundary edges of
// `mask` into the points they are extrapolated from (P_-1 = 2 P_0 - P_1 on
// each missing row/column; corners: both folds in turn).
SG_FN SgPatchRow sgBSplineFoldBoundary(SgPatchRow w, int mask) {
    for (int i = 0; i < 4; ++i) {
        if ((mask & 1) != 0) { // v = 0: row 0 missing
            w.v[i + 8] -= w.v[i];
            w.v[i + 4] += 2.0f * w.v[i];
            w.v[i] = 0.0f;
        }
    }
    for (int i = 0; i < 16; i += 4) {
        if ((mask & 2) != 0) { // u = 1: column 3 missing
            w.v[i + 1] -= w.v[i + 3];
            w.v[i + 2] += 2.0f * w.v[i + 3];
            w.v[i + 3] = 0.0f;
        }
    }
    for (int i = 0; i < 4; ++i) {
        if ((mask & 4) != 0) { // v = 1: row 3 missing
            w.v[i + 4] -= w.v[i + 12];
            w.v[i + 8] += 2.0f * w.v[i + 12];
            w.v[i + 12] = 0.0f;
        }
    }
    for (int i = 0; i < 16; i += 4) {
        if ((mask & 8) != 0) { // u = 0: column 0 missing
            w.v[i + 2] -= w.v[i];
            w.v[i + 1] += 2.0f * w.v[i];
            w.v[i] = 0.0f;
        }
    }
    return w;
}

// Gregory weights from the curve bases s (along u) and t (along v) and the
// rational factors g0 = (G0..G3), g1 = (G4..G7) of the face points.
SG_FN SgPatchRow sgGregoryTensor20(vec4 s, vec4 t, vec4 g0, vec4 g1) {
    SgPatchRow r;
    // corner (0,0): P, e+, e-, f+, f-
    r.v[0] = s.x * t.x;
    r.v[1] = s.y * t.x;
    r.v[2] = s.x * t.y;
    r.v[3] = s.y * t.y * g0.x;
    r.v[4] = s.y * t.y * g0.y;
    // corner (1,0)
    r.v[5] = s.w * t.x;
    r.v[6] = s.w * t.y;
    r.v[7] = s.z * t.x;
    r.v[8] = s.z * t.y * g0.z;
    r.v[9] = s.z * t.y * g0.w;
    // corner (1,1)
    r.v[10] = s.w * t.w;
    r.v[11] = s.z * t.w;
    r.v[12] = s.w * t.z;
    r.v[13] = s.z * t.z * g1.x;
    r.v[14] = s.z * t.z * g1.y;
    // corner (0,1)
    r.v[15] = s.x * t.w;
    r.v[16] = s.x * t.z;
    r.v[17] = s.y * t.w;
    r.v[18] = s.y * t.z * g1.z;
    r.v[19] = s.y * t.z * g1.w;
    return r;
}

// Rational factor a / (a + b) of a face-point pair, 1 where a + b = 0 (the
// patch corner, where the interior points have zero weight anyway): the
// pair's factors always sum to 1.
SG_FN float sgGregoryFactor(float a, float b) {
    float d = a + b;
    return d <= 0.0f ? a : a / d;
}

// Weights at (u,v) of the patch's own unit square (no depth scale).
SG_FN SgPatchBasis sgPatchBasisNormalized(int patchType, uint field1, vec2 uv) {
    SgPatchBasis b;
    if (patchType == SG_PATCH_GREGORY_BASIS) {
        vec4 s = sgBezierCurve(uv.x), t = sgBezierCurve(uv.y);
        vec4 sd = sgBezierCurveDeriv(uv.x), td = sgBezierCurveDeriv(uv.y);
        float su = uv.x, sv = uv.y, cu = 1.0f - uv.x, cv = 1.0f - uv.y;
        float g0 = sgGregoryFactor(su, sv), g2 = sgGregoryFactor(sv, cu);
        float g4 = sgGregoryFactor(cu, cv), g6 = sgGregoryFactor(cv, su);
        vec4 gA = vec4(g0, 1.0f - g0, g2, 1.0f - g2), gB = vec4(g4, 1.0f - g4, g6, 1.0f - g6);
        b.pos = sgGregoryTensor20(s, t, gA, gB);
        b.du = sgGregoryTensor20(sd, t, gA, gB);
        b.dv = sgGregoryTensor20(s, td, gA, gB);
        b.count = 20;
    } else if (patchType == SG_PATCH_REGULAR) {
        vec4 s = sgBSplineCurve(uv.x), t = sgBSplineCurve(uv.y);
        vec4 sd = sgBSplineCurveDeriv(uv.x), td = sgBSplineCurveDeriv(uv.y);
        int mask = sgPatchBoundaryMask(field1);
        b.pos = sgBSplineFoldBoundary(sgPatchTensor16(s, t), mask);
        b.du = sgBSplineFoldBoundary(sgPatchTensor16(sd, t), mask);
        b.dv = sgBSplineFoldBoundary(sgPatchTensor16(s, td), mask);
        b.count = 16;
    } else { // SG_PATCH_QUADS (bilinear): corners (0,0), (1,0), (1,1), (0,1)
        vec4 s = vec4(1.0f - uv.x, uv.x, uv.x, 1.0f - uv.x);
        vec4 t = vec4(1.0f - uv.y, 1.0f - uv.y, uv.y, uv.y);
        b.pos = sgPatchTensor16(sgVec4(0.0f), sgVec4(0.0f));
        b.du = b.pos;
        b.dv = b.pos;
        for (int i = 0; i < 4; ++i) {
            b.pos.v[i] = s[i] * t[i];
            b.du.v[i] = (i == 0 || i == 3 ? -1.0f : 1.0f) * t[i];
            b.dv.v[i] = (i < 2 ? -1.0f : 1.0f) * s[i];
        }
        b.count = 4;
    }
    return b;
}

// Weights at (u,v) of the patch's ptex face (what Far::PatchTable::
// EvaluateBasis takes): normalised into the patch's square, evaluated, and
// the derivatives scaled by 2^depth so that they are d/du, d/dv of the ptex
// face. (u,v) must lie within the patch's part of the face; values outside
// [0,1] of the patch's square are clamped to it (no extrapolation: the
// Gregory factors and boundary folds are only meant for the square).
SG_FN SgPatchBasis sgPatchBasis(int patchType, uint field1, vec2 faceUv) {
    vec2 uv = clamp(sgPatchNormalizeUv(field1, faceUv), sgVec2(0.0f), sgVec2(1.0f));
    SgPatchBasis b = sgPatchBasisNormalized(patchType, field1, uv);
    float scale = float(1 << sgPatchDepth(field1));
    for (int i = 0; i < SG_PATCH_MAX_POINTS; ++i) {
        b.du.v[i] *= scale;
        b.dv.v[i] *= scale;
    }
    return b;
}

#endif // SG_PATCH_BASIS_GLSL
