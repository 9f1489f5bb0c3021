// The scene of the engine-integration sample, written once for the program
// (main.cpp builds the mesh and textures from it) and for its test
// (tests/examples/engine_integration_test.cpp derives the expected normals
// from it analytically). Plain C++ and GLM, no GL.
//
// Scene: a unit UV sphere at the origin seen from +z, a tangent-space normal
// map of dimples on UV0 (TBN style, Mikkelsen 2019 listings 4-6) and a ring
// emblem decal (listing 15), both encoded as 8-bit RGB tangent-space normal
// maps with the OpenGL green convention (green = +t, texture origin at the
// lower-left corner).
//
// Spaces: world space is right-handed, y up; the camera looks down -z.
// A "derivative" d is the slope of the conceptual height over the map's
// coordinates, TBN style (dimples: one cell spans [-1,1]^2; decal: the map
// spans [-1,1]^2); the map stores the unit normal normalize(-d.x, -d.y, 1).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace example {

constexpr float kPi = 3.14159265358979f;

// ---- camera (perspective, looking at the origin from +z)
constexpr float kCameraDistance = 3.2f;
constexpr float kFovYDeg = 40.0f;
constexpr float kNear = 0.1f, kFar = 10.0f;

// ---- light (direction TOWARD the light, world space)
inline glm::vec3 lightDirection() {
    return glm::normalize(glm::vec3(-0.5f, 0.6f, 0.65f));
}

// ---- sphere: s = longitude, t = latitude, both in [0,1]; s = 0.5 faces the
// camera (the texture seam is at the back), t = 0 is the south pole. At the
// front, +s points to +x and +t to +y, so (T, B, N) is right-handed.
constexpr int kSegmentsS = 128, kSegmentsT = 64;

inline glm::vec3 spherePoint(float s, float t) {
    float phi = 2.0f * kPi * (s - 0.5f), theta = kPi * t;
    return {std::sin(theta) * std::sin(phi), -std::cos(theta), std::sin(theta) * std::cos(phi)};
}
// Inverse of spherePoint for a unit vector p (s in [0,1), t in [0,1]).
inline glm::vec2 sphereUv(glm::vec3 p) {
    float phi = std::atan2(p.x, p.z); // in (-pi, pi], 0 at the front
    float theta = std::acos(std::clamp(-p.y, -1.0f, 1.0f));
    return {phi / (2.0f * kPi) + 0.5f, theta / kPi};
}
// Unit dP/ds and dP/dt (the sphere's parametrization is orthogonal, so
// these and the normal are the orthonormal frame listing 6 reproduces).
inline void sphereTangents(glm::vec3 p, glm::vec3& dPds, glm::vec3& dPdt) {
    glm::vec2 st = sphereUv(p);
    float phi = 2.0f * kPi * (st.x - 0.5f), theta = kPi * st.y;
    dPds = glm::vec3(std::cos(phi), 0.0f, -std::sin(phi));
    dPdt = glm::vec3(std::cos(theta) * std::sin(phi), std::sin(theta),
                     std::cos(theta) * std::cos(phi));
}

// ---- layer 1: dimples on UV0, kCellsS x kCellsT cells (square at the
// equator: both span 2 pi / 24 radians). In cell coordinates (a, b) in
// [-1,1]^2, r = |(a,b)| / kDimpleRadius, the height is
// -kDimpleDepth * q^2 with q = (1 + cos(pi r)) / 2 for r < 1, 0 elsewhere:
// its slope is C1 everywhere (no kink at the rim or the centre), so bilinear
// filtering of the baked map stays close to the exact pattern.
constexpr int kCellsS = 24, kCellsT = 12;
constexpr float kDimpleRadius = 0.8f, kDimpleDepth = 0.3f;
constexpr int kNormalMapWidth = 768, kNormalMapHeight = 384; // 32 texels per cell

// Derivative dh/d(a,b) at texture coordinate st (any real st: the pattern tiles).
inline glm::vec2 dimpleDeriv(glm::vec2 st) {
    float cs = st.x * float(kCellsS), ct = st.y * float(kCellsT);
    float a = 2.0f * (cs - std::floor(cs)) - 1.0f, b = 2.0f * (ct - std::floor(ct)) - 1.0f;
    float len = std::sqrt(a * a + b * b), r = len / kDimpleRadius;
    if (r >= 1.0f || len <= 0.0f) return glm::vec2(0.0f);
    // dh/dr = depth * pi * q * sin(pi r); dr/d(a,b) = (a,b) / (len * radius).
    float q = 0.5f * (1.0f + std::cos(kPi * r));
    float g = kDimpleDepth * kPi * q * std::sin(kPi * r) / kDimpleRadius;
    return g * glm::vec2(a, b) / len;
}

// ---- layer 2: a decal projector centred on the sphere at decalCenter(),
// projecting toward the sphere's centre. The map holds a raised ring plus a
// central boss: in map coordinates (a, b) in [-1,1]^2, r = |(a,b)|,
// h = kRingHeight exp(-((r - kRingRadius)/kRingWidth)^2)
//   + kBossHeight exp(-(r/kBossWidth)^2).
constexpr float kRingRadius = 0.62f, kRingWidth = 0.11f, kRingHeight = 0.07f;
constexpr float kBossWidth = 0.22f, kBossHeight = 0.07f;
constexpr int kDecalMapSize = 256;
constexpr float kDecalHalfSize = 0.42f; // half width/height of the projector box
constexpr float kDecalHalfDepth = 0.5f; // half depth of the box
constexpr float kDecalCosStart = 0.5f;  // angle fade: full below 60 degrees ...
constexpr float kDecalCosEnd = 0.17f;   // ... none beyond 80 degrees

inline glm::vec3 decalCenter() {
    return glm::normalize(glm::vec3(-0.42f, 0.33f, 0.85f));
}
// Projector frame: z points back toward the projector (out of the surface),
// x = up cross z, y = z cross x (right-handed).
inline void decalAxes(glm::vec3& x, glm::vec3& y, glm::vec3& z) {
    z = decalCenter();
    x = glm::normalize(glm::cross(glm::vec3(0.0f, 1.0f, 0.0f), z));
    y = glm::cross(z, x);
}

// Derivative dh/d(a,b) at map coordinate uv in [0,1]^2 (a = 2u - 1, b = 2v - 1).
inline glm::vec2 decalDeriv(glm::vec2 uv) {
    float a = 2.0f * uv.x - 1.0f, b = 2.0f * uv.y - 1.0f;
    float r = std::sqrt(a * a + b * b);
    float q = (r - kRingRadius) / kRingWidth;
    // dh/dr of both terms; the boss term is written as a multiple of r so
    // (a,b)/r below has no 0/0 at the centre.
    float ringOverR =
        r > 0.0f ? kRingHeight * std::exp(-q * q) * (-2.0f * q / kRingWidth) / r : 0.0f;
    float bossOverR = kBossHeight * std::exp(-(r * r) / (kBossWidth * kBossWidth)) *
                      (-2.0f / (kBossWidth * kBossWidth));
    return (ringOverR + bossOverR) * glm::vec2(a, b);
}

// The unit tangent-space normal a map stores for derivative d.
inline glm::vec3 derivToNormal(glm::vec2 d) {
    return glm::normalize(glm::vec3(-d.x, -d.y, 1.0f));
}

// Strengths (bump scales, listing 2) of the two layers.
constexpr float kNormalMapStrength = 1.0f, kDecalStrength = 1.0f;

} // namespace example
