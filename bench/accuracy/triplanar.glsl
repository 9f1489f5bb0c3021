// Triplanar normal mapping methods compared in the triplanar table of
// bench_accuracy_cost (docs/accuracy-cost.md), written once in the GLSL/C++
// common subset (shaders/sg/compat.glsl) so the GPU timing pass and the
// C++ error evaluation run the same code. These are comparison baselines
// of the study, not library features: the library's triplanar layer is
// sg/render/layer_triplanar.glsl.
//
// Every method gets the unit base normal n, the blend weights w (listing
// 14, sgTriplanarWeights), and the three tangent-space normals tnX, tnY,
// tnZ sampled from the maps of the x, y and z planes, and returns the
// perturbed unit normal. A plane's map coordinates (s, t) run along the
// world axes studyTriAxisS/T: (z, y), (x, z), (x, y) in the left-handed
// convention; (-z, y), (x, -z) for the x and y planes in the right-handed
// one (Mikkelsen 2019 section 2.8); with an upper-left texture origin the
// maps are sampled at (s, 1 - t), which negates the t axis. The engine
// methods are from Golus, "Normal Mapping for a Triplanar Shader" (2017),
// written for arbitrary axes so they are right in both conventions:
//   naive     - the three samples blended with fixed swizzles (each
//               sample's z along its plane's axis, signed by the side);
//   UDN       - per plane, the sample's xy added to the base normal seen in
//               that plane's frame, whose z is kept;
//   whiteout  - the same with the z's multiplied;
//   RNM       - per plane, the sample re-oriented to the base normal seen in
//               that plane's frame (Barre-Brisebois & Hill 2012);
//   volume    - Perlin 1985: the triplanar volume gradient (eq. 7) added to
//               the normal without the projection onto the tangent plane;
//   surfgrad  - Mikkelsen 2019 listings 13 + 12 + 1 (sgSurfgradFromTriplanar).
#ifndef STUDY_TRIPLANAR_GLSL
#define STUDY_TRIPLANAR_GLSL

#include "sg/surfgrad.glsl"

// World axis of plane p's map coordinate s (p = 0, 1, 2 for x, y, z).
SG_FN vec3 studyTriAxisS(int p, bool rightHanded) {
    float zs = rightHanded ? -1.0f : 1.0f;
    if (p == 0) return vec3(0.0f, 0.0f, zs);
    return vec3(1.0f, 0.0f, 0.0f);
}
SG_FN vec3 studyTriAxisT(int p, bool rightHanded, bool upperLeftOrigin) {
    float zs = rightHanded ? -1.0f : 1.0f;
    float v = upperLeftOrigin ? -1.0f : 1.0f;
    if (p == 1) return vec3(0.0f, 0.0f, v * zs);
    return vec3(0.0f, v, 0.0f);
}
SG_FN vec3 studyTriAxis(int p) {
    if (p == 0) return vec3(1.0f, 0.0f, 0.0f);
    if (p == 1) return vec3(0.0f, 1.0f, 0.0f);
    return vec3(0.0f, 0.0f, 1.0f);
}

// A sample of plane p to world space: x along S, y along T, z along the
// plane's axis on the side n faces.
SG_FN vec3 studyTriToWorld(int p, vec3 tn, vec3 n, bool rh, bool ul) {
    vec3 a = studyTriAxis(p);
    float side = dot(n, a) < 0.0f ? -1.0f : 1.0f;
    return tn.x * studyTriAxisS(p, rh) + tn.y * studyTriAxisT(p, rh, ul) + (side * tn.z) * a;
}

// The base normal in plane p's frame (S, T, axis).
SG_FN vec3 studyTriNormalInPlane(int p, vec3 n, bool rh, bool ul) {
    return vec3(dot(n, studyTriAxisS(p, rh)), dot(n, studyTriAxisT(p, rh, ul)), dot(n, studyTriAxis(p)));
}
SG_FN vec3 studyTriPlaneToWorld(int p, vec3 v, bool rh, bool ul) {
    return v.x * studyTriAxisS(p, rh) + v.y * studyTriAxisT(p, rh, ul) + v.z * studyTriAxis(p);
}

#define STUDY_TRI_SURFGRAD 0
#define STUDY_TRI_VOLUME 1
#define STUDY_TRI_NAIVE 2
#define STUDY_TRI_UDN 3
#define STUDY_TRI_WHITEOUT 4
#define STUDY_TRI_RNM 5
#define STUDY_TRI_COUNT 6

// One plane's contribution in world space for the engine methods.
SG_FN vec3 studyTriPlane(int method, int p, vec3 tn, vec3 n, bool rh, bool ul) {
    if (method == STUDY_TRI_NAIVE) return studyTriToWorld(p, tn, n, rh, ul);
    vec3 np = studyTriNormalInPlane(p, n, rh, ul);
    vec3 r = vec3(tn.x + np.x, tn.y + np.y, np.z); // UDN
    if (method == STUDY_TRI_WHITEOUT) r.z = abs(tn.z) * np.z;
    if (method == STUDY_TRI_RNM) {
        // RNM of the sample onto (np.xy, |np.z|), then z back to n's side.
        vec3 t = vec3(np.x, np.y, abs(np.z) + 1.0f);
        vec3 u = tn * vec3(-1.0f, -1.0f, 1.0f);
        r = t * (dot(t, u) / t.z) - u;
        r.z = np.z < 0.0f ? -r.z : r.z;
    }
    return studyTriPlaneToWorld(p, r, rh, ul);
}

SG_FN vec3 studyTriplanar(int method, vec3 n, vec3 w, vec3 tnX, vec3 tnY, vec3 tnZ, bool rh, bool ul) {
    if (method == STUDY_TRI_SURFGRAD || method == STUDY_TRI_VOLUME) {
        vec2 dX = sgTspaceNormalToDeriv(vec2(tnX.x, tnX.y), false);
        vec2 dY = sgTspaceNormalToDeriv(vec2(tnY.x, tnY.y), false);
        vec2 dZ = sgTspaceNormalToDeriv(vec2(tnZ.x, tnZ.y), false);
        SgFrame f;
        f.nrmBase = n;
        f.resolveSign = 1.0f;
        if (method == STUDY_TRI_SURFGRAD) return sgResolve(f, sgSurfgradFromTriplanar(f, w, dX, dY, dZ, rh, ul));
        return sgSafeNormalize(n - sgTriplanarVolumeGradient(w, dX, dY, dZ, rh, ul), n);
    }
    vec3 sum = w.x * studyTriPlane(method, 0, tnX, n, rh, ul) + w.y * studyTriPlane(method, 1, tnY, n, rh, ul) +
               w.z * studyTriPlane(method, 2, tnZ, n, rh, ul);
    return sgSafeNormalize(sum, n);
}

#endif
