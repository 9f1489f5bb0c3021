// Numerical stability of the renderer, measured: every hard case is a scene
// rendered twice, once as given and once after a rounding-size change of
// its input (a UV moved by 1e-7, the camera by a few ulps, every mesh
// coordinate by a few ulps, ...), and the two normal images are compared.
// A stable renderer moves its output by a rounding-size amount; one that
// decides something on a rounding-size quantity moves it by tens of
// degrees. The same scene is also rendered by the CPU reference renderer
// with the GPU's derivative method and texture LOD rule (CpuDerivatives::
// Quad, LodRule::FastLog2: the "matched" reference, which agrees with
// llvmpipe to a few hundredths of a degree on ordinary scenes), so a case
// whose result depends on rounding shows up as GPU/CPU disagreement too.
//
// The cases come in three sets:
//  - namedCases(): inputs users meet (a top-projected cylinder, an
//    unmapped triangle, world-unit terrain UVs, a flattened instance, a
//    camera far from the origin, a thin decal, back faces in flip mode,
//    ...), each with the layer kinds it hurts;
//  - familyCases(): every hard-case family of tests/hardcase_families.txt
//    crossed with every layer kind of the registry (the kind's registry
//    example as the layer);
//  - generatedCases(seed, n): random meshes (random charts, some
//    collapsed, needles, zero-area faces, normals near the horizon) under
//    random cameras, transforms and layer kinds.
// tests/render/stability_test.cpp asserts bounds on them (ctest label
// hardcase); table 12 of docs/accuracy-cost.md prints them.
//
// Angles are in degrees, between normal AOVs, over the pixels that the same
// primitive covers in both images (coverage may move by a rounding-size
// change: those pixels are counted, not compared).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "surfgrad/render.h"

namespace study::stability {

struct AngleStats {
    size_t compared = 0;         // pixels covered by the same primitive in both images
    size_t coverageMismatch = 0; // pixels covered in one image only, or by different primitives
    size_t nonFinite = 0;        // compared pixels with a non-finite component
    double p50 = 0, p99 = 0, max = 0;
};

// One hard case. `build(perturbed, dir)` returns the scene, with the
// rounding-size change applied when `perturbed`; files it needs (meshes)
// are written under `dir`, which exists and is empty for each call.
struct Case {
    std::string id;           // unique: "<input>/<kind>"
    std::string family;       // an id of tests/hardcase_families.txt
    std::string kind;         // the layer kind under test
    std::string input;        // what makes the input hard
    std::string perturbation; // the rounding-size change of the input
    int width = 96, height = 72;
    std::function<sg::render::Scene(bool perturbed, const std::filesystem::path& dir)> build;
    // Optional: a scene this case's normal image must equal, each normal
    // multiplied by expectSign (e.g. the same mesh without the layer where
    // the layer must fade out; mode none for a flip-mode case, negated).
    std::function<sg::render::Scene(const std::filesystem::path& dir)> expected;
    float expectSign = 1.0f;
    std::string expectedWhat; // what `expected` renders
    // The condition number the input brings itself, before any rendering:
    // the anisotropy of its transform (max / min |scale|; a transform that
    // is A:1 anisotropic multiplies the rounding of normals, object-space
    // maps and volume gradients through its inverse transpose by A). 1 for
    // ordinary inputs; the tests scale their bounds by it beyond 1000.
    double inputCondition = 1.0;
    // The largest angle between a vertex normal and its face (degrees; 0
    // when they agree): parallax and POM search up to 1 / cos of it further
    // (n . g bounded at 0.05: 20x), so their results reach that much further
    // into the map.
    double normalLeanDeg = 0.0;
    // Also compare the GPU with the default CPU reference (analytic
    // derivatives, the GL specification's exact LOD): which CPU is the
    // reference (docs/scene.md, "CPU reference").
    bool withDefaultCpu = false;
};

struct Result {
    AngleStats perturbedGpu;    // GPU: input vs perturbed input
    AngleStats perturbedCpu;    // matched CPU reference: input vs perturbed input
    AngleStats gpuVsCpu;        // GPU vs matched CPU reference, the input as given
    AngleStats expected;        // GPU vs `expected` (compared == 0 when the case has none)
    AngleStats gpuVsDefaultCpu; // GPU vs the default CPU reference (Case::withDefaultCpu)
};

// The CPU reference options that follow the GPU (quad derivatives,
// llvmpipe's LOD rule).
sg::render::CpuOptions matchedCpu();

// Renders the case (normal and primitive AOVs, GPU and matched CPU) and
// compares. `gpu` needs a current GL 4.5 context. Scratch files go under
// `scratch` (created; emptied per build).
Result run(const Case& c, sg::render::GlRenderer& gpu, const std::filesystem::path& scratch);

AngleStats compare(const sg::render::Image& a, const sg::render::Image& b,
                   const sg::render::Image& primA, const sg::render::Image& primB,
                   float signB = 1.0f);

std::vector<Case> namedCases();
std::vector<Case> familyCases();
std::vector<Case> generatedCases(uint64_t seed, int count);

// Writes the case's four normal images (GPU and CPU, as given and
// perturbed) as EXR files <dir>/<id with '/' as '_'>_{gpu,cpu}{,_perturbed}.exr
// (SG_STABILITY_DUMP=<dir> in the tests and the table: what a failing case
// looks like).
void dumpImages(const Case& c, sg::render::GlRenderer& gpu, const std::filesystem::path& scratch,
                const std::filesystem::path& dir);

// Every layer kind of the registry with its registry example, as the layer
// JSON a material lists (post_resolve: a uv_normal layer, then the group).
std::vector<std::pair<std::string, std::string>> kindLayers();

} // namespace study::stability
