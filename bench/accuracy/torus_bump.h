// The tangent-frame experiment shared by the "frames" and "precision"
// tables: the B-spline torus (torus.h) refined by the mesh module to level L
// with limit evaluation, a known height field on its UV set, and a
// tangent-space derivative map of that height baked against the EXACT frame
// of the limit surface, so that a renderer with the exact frame would
// reproduce Blinn's perturbed normal exactly (torus.h, bakeDerivative).
// Every frame source then starts from the same map and the same vertices,
// and its error against Blinn's normal is the error of its frame (plus the
// tessellation error of the interpolated base normal, common to all).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common.h"
#include "surfgrad/mesh/render_mesh.h"
#include "torus.h"

namespace study {

struct HeightField {
    // h(s, t) = amplitude sin(2 pi kS s) sin(2 pi kT t), object units;
    // periodic on the torus' UV square.
    double amplitude = 0.045;
    int kS = 8, kT = 4;
    double h(double s, double t) const;
    glm::dvec2 grad(double s, double t) const; // (dh/ds, dh/dt)
};

struct TorusBump {
    TorusCage cage;
    HeightField height;
    int level = 0;
    // Limit mesh of the level (positions, normals and UVs on the limit
    // surface) without tangents, with MikkTSpace tangents, with limit tangents.
    sg::mesh::RenderMesh pixelMesh, mikkMesh, limitMesh;
    double limitCheckMaxDist = 0; // max |OpenSubdiv limit position - B-spline(uv)|
    // Derivative map (RG32F, texW x texH over the UV square, texel centres
    // at (i + 0.5) / texW).
    int texW = 2048, texH = 1024;
    std::vector<float> derivTexels;
    // Camera: world = object space.
    glm::vec3 camPos{0.0f};
    glm::mat4 viewProj{1.0f};

    explicit TorusBump(int level, bool quick);
    SurfacePoint truthPoint(double s, double t) const { return cage.limit(s, t); }
    glm::dvec3 truthNormal(double s, double t) const; // Blinn on the exact limit surface
    // The map's bilinear reconstruction at (s, t) (GL_LINEAR, repeat), in double.
    glm::dvec2 sampleDeriv(double s, double t) const;
    // Angle (degrees) between each vertex tangent of `mesh` (mikkMesh or
    // limitMesh) and the exact tangent of the limit surface at the vertex's
    // UV; worstUv receives the UV of the largest.
    std::vector<double> vertexTangentErrors(const sg::mesh::RenderMesh& mesh,
                                            glm::dvec2* worstUv) const;
};

// Table 1's accuracy pass (table_frames.cpp): renders the scene at
// size x size with each frame source and returns, per covered pixel, the
// angle (degrees) between the resolved normal and truthNormal at the pixel's
// UV. Index 0: MikkTSpace vertex tangents, 1: limit tangents, 2: per-pixel
// frame (L16 + L6). Needs a current GL context.
struct FrameSourceErrors {
    std::vector<double> err[3];
    std::vector<double> baseErr;  // interpolated base normal vs the limit normal
    std::vector<double> floorErr; // the map's bilinear sample with the exact frame
    size_t covered = 0;
};
FrameSourceErrors measureFrameSources(const TorusBump& scene, int size);

// GLSL shared by the torus programs: the vertex shader, and the fragment
// head declaring the inputs and uDeriv (the derivative map).
const char* torusVertexShader();
const char* torusFragmentHead();

} // namespace study
