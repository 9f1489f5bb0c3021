// The layer kinds' shared functions checked by numbers through the HLSL
// round trip (issue 25; docs/engines.md, "HLSL"), not only compiled.
//
// For every registered kind's image cases (LayerKind::imageCases, the
// scenes of the image-parity test) the material's plan is built as the
// renderers build it (planMaterial, drawUniforms, the plan's textures), and
// the statements of group 0 (each PlanLayer's emit.glsl, in plan order: the
// text of the assembled fragment main()) run over kSamples random but
// reproducible pixel inputs three times:
//   - GLSL 4.50: a compute program that declares the main()'s variables
//     (frame, uv0..uv3, volWorld, volObject, surfPos, surfOffset, slopeCov,
//     surfGrad, vRelPos, vObjPos, vNormal, uNormalMat, uModel3, uModelInv3,
//     uLayerData, uTex<k>) from the inputs as plan.cpp's prologue does,
//     pastes the statements and writes out what they may change (the
//     control: the same driver runs the renderer's fragment programs);
//   - HLSL: the same body under sg/compat.hlsl (the plan's .glsl files
//     included after it, StructuredBuffers for the inputs and records, each
//     uTex<k> an SgSampler2D local built from a Texture2D and a
//     SamplerState), through glslang's HLSL front end, spirv-val and
//     SPIRV-Cross to GLSL 4.50 (tests/common/hlsl_round_trip.h), run on the
//     same context;
//   - the CPU twin: each PlanLayer's emit.cpu on a CpuShadeState built the
//     same way (the C++ build of the same source; textures through
//     planSamplers with llvmpipe's LOD rule, gpuParityOptions()).
// Screen derivatives are inputs here (no dFdx in a compute stage): the
// harness defines SG_DFDX(v) / SG_DFDY(v) as the input variables v##Dx /
// v##Dy, which the parallax statement reads for vNormal (section 2.6's
// normal correction); the prologue's dPdx/dPdy and the UV derivatives are
// inputs too.
//
// Cases: every image case, its antialiased variants (the material's
// "antialias": "lean" and "toksvig", where a layer then antialiases with
// options of its own: the *_aa.glsl functions and slopeCov; for the
// feature kind, which antialiases per layer, "antialias": "lean" on the
// first feature layer where it has no base map), and MODULATE without
// DEFORM (its identity Jacobian; no image case has it).
//
// The feature kind (LayerKind::batch) emits its layers as one loop per
// group (layer_feature.cpp's groupLoop); its body is the kind's emitter
// with GlslLayerContext::loop, which the harness instantiates once per
// feature layer as the loop's unrolled form does: a block
// `{ const int fi = <kindIndex>; int r = <record>; SgUvFrame fuv = uv<set>;
// <statement> }`. The statement calls sgLayerFeature, sgLayerFeatureNear,
// sgLayerFeatureAa or sgLayerFeatureNearAa (per plan) with the per-layer
// sampler arrays indexed by fi: uFeatCorners, uFeatEdges (and uFeatNear,
// uFeatPieces with the exact near field) are the layer's feature maps
// uploaded as feature_assets.cpp does (RGBA32UI, one level, nearest;
// read with texelFetch), uFeatBase, uFeatChainA, uFeatChainB its texture
// slots (bindGpu's choice of stand-ins); in GLSL `uniform usampler2D
// uFeatCorners[n]` etc. with a binding per array, in HLSL one global per
// layer (Texture2D<uint4>, or Texture2D<float4> with a SamplerState)
// gathered into local arrays of main() (Texture2D<uint4>, SgSampler2D)
// that the constant fi indexes (glslang's legalization resolves them).
// The CPU twin gets the kind's data as the CPU renderer builds it
// (planKindCpuData); the programs the kinds' defines (SG_FEAT_CURVED,
// SG_FEAT_NEAR).
//
// Skipped: of post_resolve scenes, the groups after the first (their
// re-prologue reads gl_FragCoord and the resolved normal of the group
// before: group 0 is checked, the later groups' layers are kinds checked
// on their own scenes). Textures: RGBA32F with the exact mip chain,
// trilinear, the wrap of the image (gl_renderer.cpp's upload).
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "hlsl_round_trip.h"
#include "layer_kind.h"
#include "layers/feature_assets.h"
#include "render_internal.h"
#include "render_test_util.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/shaders/shader_files.h"

namespace sg::render::test {
namespace {

namespace G = sg::glsl;

constexpr size_t kSamples = 256;
constexpr uint32_t kSeed = 20250125u;

// Input record (floats): the vertex normal, the position's screen
// derivatives, the vertex normal's, the camera-relative and object
// positions, the object position's derivatives, front facing, then per UV
// set st, dSTdx, dSTdy and a vertex tangent (xyz, w sign).
constexpr int kInNormal = 0, kInDPdx = 3, kInDPdy = 6, kInDNdx = 9, kInDNdy = 12, kInRelPos = 15,
              kInObjPos = 18, kInDObjdx = 21, kInDObjdy = 24, kInFront = 27, kInUv = 28,
              kInTangent = 52, kInStride = 72;
// Output record: surfGrad, slopeCov's columns, uv<k>.st, frame.nrmBase,
// surfOffset, the resolved normal sgResolve(frame, surfGrad).
constexpr int kOutSurfGrad = 0, kOutSlopeCov = 3, kOutSt = 12, kOutNrmBase = 20,
              kOutSurfOffset = 23, kOutNrm = 26, kOutStride = 32;

// Texture units and HLSL resource bindings: records 2, draw matrices 3,
// texture slot k on unit/binding kTexBase + k (SPIRV-Cross's combined
// sampler inherits the texture's binding), its SamplerState after them.
constexpr int kTexBase = 4;

struct HarnessCase {
    std::string name;
    std::string json;
    const LayerKind* kind;
};

const LayerKind* kindNamed(const char* name) {
    for (const LayerKind* k : layerKinds())
        if (std::string(k->name) == name) return k;
    return nullptr;
}

// What the material's layers compile to: each layer's kind and its
// signature (the options that change its statement), and whether it
// antialiases.
std::string layerOptions(const std::string& json, bool& antialias) {
    const Scene scene = sceneFromJson(json);
    std::string o;
    antialias = false;
    for (const Layer& L : scene.materials[0].layers) {
        o += std::string(L.kind->name) + "(" + (L.kind->signature ? L.kind->signature(L) : "") +
             ") ";
        antialias = antialias || (L.kind->antialias && L.kind->antialias(L));
    }
    return o;
}

std::vector<HarnessCase> harnessCases() {
    std::vector<HarnessCase> cases;
    for (const LayerKind* k : layerKinds()) {
        for (const KindImageCase& c : k->imageCases) {
            const std::string mesh = c.mesh.empty() ? kSphere : c.mesh;
            cases.push_back(
                {c.name, oneMaterialScene(c.layers, mesh, "", 200, 150, c.sceneExtra), k});
            // The feature kind antialiases per layer ("antialias": "lean" on
            // the layer, not the material's): the first feature layer made
            // LEAN where it has no base map (the chain replaces it), so the
            // plan calls sgLayerFeatureAa / sgLayerFeatureNearAa.
            if (k->batch) {
                const std::string head = R"({"type": "feature", )";
                const std::string layers = c.layers;
                const size_t at = layers.find(head);
                if (at == std::string::npos) continue;
                size_t end = at; // the end of the layer's object
                for (int depth = 0; end < layers.size(); ++end) {
                    depth += layers[end] == '{' ? 1 : layers[end] == '}' ? -1 : 0;
                    if (depth == 0) break;
                }
                if (layers.substr(at, end - at).find("base_map") != std::string::npos) continue;
                std::string lean = layers;
                lean.insert(at + head.size(), R"("antialias": "lean", )");
                cases.push_back({std::string(c.name) + "_lean",
                                 oneMaterialScene(lean, mesh, "", 200, 150, c.sceneExtra), k});
                continue;
            }
            // The antialiased variants (the *_aa.glsl functions, slopeCov):
            // the same scene with the material's "antialias", kept when a
            // layer then antialiases with options no kept case has (layers
            // with modifiers keep none; noise has LEAN only).
            if (!k->antialias) continue;
            bool aaBase = false;
            std::vector<std::string> seen = {layerOptions(cases.back().json, aaBase)};
            for (const char* aa : {"lean", "toksvig"}) {
                HarnessCase v{std::string(c.name) + "_" + aa,
                              oneMaterialScene(c.layers, mesh,
                                               std::string(R"("antialias": ")") + aa + R"(",)", 200,
                                               150, c.sceneExtra),
                              k};
                bool antialias = false;
                std::string options = layerOptions(v.json, antialias);
                if (!antialias || std::find(seen.begin(), seen.end(), options) != seen.end())
                    continue;
                seen.push_back(options);
                cases.push_back(std::move(v));
            }
        }
    }
    // MODULATE without DEFORM (no image case has it): its Jacobian is the
    // identity the block spells sgModNoWarp(); HLSL's float2x2(1.0f), what
    // GLSL's mat2(1.0f) becomes under sg/compat.hlsl, is a matrix of ones.
    cases.push_back(
        {"modifiers_modulate_no_warp",
         oneMaterialScene(
             R"({"type": "uv_normal", "map": {"procedural": "bricks", "size": 256}, "height": {"channel": "a", "scale": 1}, "modifiers": [{"type": "modulate", "mask": {"procedural": "tiles", "output": "height", "size": 64}, "gain": 1}]})",
             kSphere),
         kindNamed("uv_normal")});
    return cases;
}

// gtest prints a failing case by its name.
[[maybe_unused]] void PrintTo(const HarnessCase& c, std::ostream* os) {
    *os << c.name;
}

// The files the harness includes: the common header, then the layers' files
// as the assembler includes them (layerGlslFiles, every group's).
std::vector<std::string> planFiles(const MaterialPlan& plan) {
    std::vector<std::string> files = {"sg/render/common.glsl"};
    for (const std::string& f : layerGlslFiles(plan)) files.push_back(f);
    return files;
}

// The statements of group 0, in plan order. A batched (feature) layer's
// is the body of its kind's loop (GlslLayerContext::loop: records from
// `r`, the UV frame `fuv`, its maps at `fi`) in a block of its own that
// sets them for that layer, as the loop's unrolled form does (fi its
// PlanLayer::kindIndex, a constant).
std::vector<std::string> groupStatements(const MaterialPlan& plan) {
    std::vector<std::string> s;
    for (const PlanLayer& pl : plan.groups[0]) {
        if (!pl.layer->kind->batch) {
            s.push_back(pl.layer->kind->emit.glsl(GlslLayerContext{plan, pl, "    "}));
            continue;
        }
        const std::string in = "        ";
        s.push_back("{\n" + in + "const int fi = " + std::to_string(pl.kindIndex) + ";\n" + in +
                    "int r = " + std::to_string(pl.record) + ";\n" + in + "SgUvFrame fuv = uv" +
                    std::to_string(pl.layer->uvSet) + ";\n" + in +
                    pl.layer->kind->emit.glsl(GlslLayerContext{plan, pl, in, /*loop*/ true}) +
                    "    }\n");
    }
    return s;
}

// The program defines of the plan's kinds (the feature kind's
// SG_FEAT_CURVED, SG_FEAT_NEAR: plan.cpp's assembleProgram).
std::vector<std::string> planDefines(const MaterialPlan& plan) {
    std::vector<std::string> defs;
    for (const LayerKind* k : plan.kinds)
        if (k->programDefines) k->programDefines(plan, defs);
    return defs;
}

// The feature layers' maps (feature_assets.cpp's bindGpu), per layer fi
// (PlanLayer::kindIndex, all groups) on units after the plan's textures
// and their SamplerStates: the arrays uFeatCorners, uFeatEdges, uFeatNear,
// uFeatPieces (RGBA32UI), uFeatBase, uFeatChainA, uFeatChainB (the
// layer's texture slots), each a run of featureLayers units.
enum FeatArray {
    kFeatCorners,
    kFeatEdges,
    kFeatNear,
    kFeatPieces,
    kFeatBase,
    kFeatChainA,
    kFeatChainB,
    kFeatArrays
};
const char* const kFeatArrayNames[kFeatArrays] = {"uFeatCorners", "uFeatEdges", "uFeatNear",
                                                  "uFeatPieces",  "uFeatBase",  "uFeatChainA",
                                                  "uFeatChainB"};
int featUnit(const MaterialPlan& plan, FeatArray a, int fi) {
    const int n = int(plan.textureKeys.size()), layers = featurePlan(plan).layerCount;
    return kTexBase + 2 * n + layers * int(a) + fi;
}
// The arrays the plan's program declares (layer_feature.cpp's declarations).
bool featArrayUsed(const FeaturePlan& fp, FeatArray a) {
    if (a == kFeatNear || a == kFeatPieces) return fp.near;
    if (a == kFeatChainA || a == kFeatChainB) return fp.lean;
    return true;
}
bool featArrayUnsigned(FeatArray a) {
    return a <= kFeatPieces;
}

// main()'s body after the target's opening (which defines `i`, the
// record): the same text for GLSL 4.50 and HLSL (the subset: sgVec3,
// sgMat3Diag; matrices built from columns, so HLSL holds the transpose).
std::string harnessBody(const MaterialPlan& plan, int bfaceMode,
                        const std::vector<std::string>& statements) {
    auto in3 = [](int o) { return "sgIn3(b + " + std::to_string(o) + "u)"; };
    auto in2 = [](int o) { return "sgIn2(b + " + std::to_string(o) + "u)"; };
    std::string o;
    o += "    uint b = i * " + std::to_string(kInStride) + "u;\n";
    o += "    vec3 vNormal = " + in3(kInNormal) + ";\n";
    o += "    vec3 vNormalDx = " + in3(kInDNdx) + ";\n";
    o += "    vec3 vNormalDy = " + in3(kInDNdy) + ";\n";
    o += "    vec3 vRelPos = " + in3(kInRelPos) + ";\n";
    o += "    vec3 vObjPos = " + in3(kInObjPos) + ";\n";
    o += "    mat3 uNormalMat = mat3(uDraw[0].xyz, uDraw[1].xyz, uDraw[2].xyz);\n";
    o += "    mat3 uModel3 = mat3(uDraw[3].xyz, uDraw[4].xyz, uDraw[5].xyz);\n";
    o += "    mat3 uModelInv3 = mat3(uDraw[6].xyz, uDraw[7].xyz, uDraw[8].xyz);\n";
    o += "    SgFrame frame = sgPrologue(vNormal, " + in3(kInDPdx) + ", " + in3(kInDPdy) +
         ", inData[b + " + std::to_string(kInFront) + "u] > 0.5f, " + std::to_string(bfaceMode) +
         ");\n";
    for (int k = 0; k < plan.uvCount; ++k) {
        const int u = kInUv + 6 * k;
        std::string uv = "uv" + std::to_string(k);
        if (plan.vertexTangentMask >> k & 1u) {
            o += "    SgUvFrame " + uv + " = sgUvFrameVertex(" + in2(u) + ", " + in2(u + 2) + ", " +
                 in2(u + 4) + ", vNormal, sgIn4(b + " + std::to_string(kInTangent + 4 * k) +
                 "u));\n";
        } else {
            o += "    SgUvFrame " + uv + " = sgUvFramePixel(frame, " + in2(u) + ", " + in2(u + 2) +
                 ", " + in2(u + 4) + ");\n";
        }
    }
    o += "    SgVolumeSpace volWorld = sgVolumeSpace(frame, vRelPos, sgMat3Diag(1.0f), "
         "sgMat3Diag(1.0f));\n";
    o += "    SgVolumeSpace volObject = sgVolumeSpaceDeriv(vObjPos, " + in3(kInDObjdx) + ", " +
         in3(kInDObjdy) + ", uModel3, uModelInv3);\n";
    o += "    vec3 surfGrad = sgVec3(0.0f);\n"
         "    mat3 slopeCov = sgMat3Diag(0.0f);\n"
         "    vec3 surfOffset = sgVec3(0.0f);\n"
         "    vec3 surfPos = vRelPos;\n";
    for (const std::string& s : statements) o += "    " + s;
    o += "    vec3 nrm = sgResolve(frame, surfGrad);\n";
    o += "    uint o = i * " + std::to_string(kOutStride) + "u;\n";
    auto out3 = [&](int at, const std::string& v) {
        o += "    sgOut3(o + " + std::to_string(at) + "u, " + v + ");\n";
    };
    out3(kOutSurfGrad, "surfGrad");
    for (int c = 0; c < 3; ++c) out3(kOutSlopeCov + 3 * c, "slopeCov[" + std::to_string(c) + "]");
    for (int k = 0; k < plan.uvCount; ++k) {
        const std::string at = std::to_string(kOutSt + 2 * k);
        o += "    outData[o + " + at + "u] = uv" + std::to_string(k) + ".st.x;\n";
        o += "    outData[o + " + at + "u + 1u] = uv" + std::to_string(k) + ".st.y;\n";
    }
    out3(kOutNrmBase, "frame.nrmBase");
    out3(kOutSurfOffset, "surfOffset");
    out3(kOutNrm, "nrm");
    return o + "}\n";
}

// Helpers after the buffer declarations (both targets).
const char* kHelpers = R"(
// Screen derivatives are inputs of the harness: SG_DFDX(vNormal) is vNormalDx.
#define SG_DFDX(v) v##Dx
#define SG_DFDY(v) v##Dy
vec2 sgIn2(uint o) { return vec2(inData[o], inData[o + 1u]); }
vec3 sgIn3(uint o) { return vec3(inData[o], inData[o + 1u], inData[o + 2u]); }
vec4 sgIn4(uint o) { return vec4(inData[o], inData[o + 1u], inData[o + 2u], inData[o + 3u]); }
void sgOut3(uint o, vec3 v) {
    outData[o] = v.x;
    outData[o + 1u] = v.y;
    outData[o + 2u] = v.z;
}
)";

std::string glslHarness(const MaterialPlan& plan, int bfaceMode,
                        const std::vector<std::string>& statements) {
    std::string o = "// Layer statements harness, GLSL 4.50 (tests/render/layer_hlsl_test.cpp).\n";
    for (const std::string& f : planFiles(plan)) o += "#include \"" + f + "\"\n";
    o += "layout(local_size_x = " + std::to_string(sg::gl::kComputeGroupSize) +
         ") in;\n"
         "layout(std430, binding = 0) readonly buffer InData { float inData[]; };\n"
         "layout(std430, binding = 1) writeonly buffer OutData { float outData[]; };\n"
         "layout(std430, binding = 2) readonly buffer LayerData { vec4 uLayerData[]; };\n"
         "layout(std430, binding = 3) readonly buffer DrawData { vec4 uDraw[]; };\n"
         "uniform uint uCount;\n";
    for (size_t k = 0; k < plan.textureKeys.size(); ++k) {
        o += "layout(binding = " + std::to_string(kTexBase + int(k)) + ") uniform sampler2D uTex" +
             std::to_string(k) + ";\n";
    }
    const FeaturePlan fp = featurePlan(plan);
    for (int a = 0; a < kFeatArrays && fp.layerCount > 0; ++a) {
        const FeatArray fa = FeatArray(a);
        if (!featArrayUsed(fp, fa)) continue;
        o += "layout(binding = " + std::to_string(featUnit(plan, fa, 0)) + ") uniform " +
             (featArrayUnsigned(fa) ? "usampler2D " : "sampler2D ") + kFeatArrayNames[a] + "[" +
             std::to_string(fp.layerCount) + "];\n";
    }
    o += kHelpers;
    o += "void main() {\n"
         "    uint i = gl_GlobalInvocationID.x;\n"
         "    if (i >= uCount) return;\n";
    return o + harnessBody(plan, bfaceMode, statements);
}

std::string hlslHarness(const MaterialPlan& plan, int bfaceMode,
                        const std::vector<std::string>& statements) {
    std::string o = "// Layer statements harness, HLSL (tests/render/layer_hlsl_test.cpp).\n"
                    "#include \"sg/compat.hlsl\"\n";
    for (const std::string& f : planFiles(plan)) o += "#include \"" + f + "\"\n";
    o += "[[vk::binding(0)]] StructuredBuffer<float> inData : register(t0);\n"
         "[[vk::binding(1)]] RWStructuredBuffer<float> outData : register(u1);\n"
         "[[vk::binding(2)]] StructuredBuffer<float4> uLayerData : register(t2);\n"
         "[[vk::binding(3)]] StructuredBuffer<float4> uDraw : register(t3);\n";
    const size_t n = plan.textureKeys.size();
    for (size_t k = 0; k < n; ++k) {
        const std::string t = std::to_string(kTexBase + int(k)), s = std::to_string(k);
        o += "[[vk::binding(" + t + ")]] Texture2D<float4> gTex" + s + " : register(t" + t + ");\n";
        o += "[[vk::binding(" + std::to_string(kTexBase + int(n + k)) + ")]] SamplerState gSmp" +
             s + " : register(s" + s + ");\n";
    }
    // The feature arrays: a global per layer (binding its unit), gathered
    // into local arrays in main() (constant indices; glslang's legalization
    // resolves them).
    const FeaturePlan fp = featurePlan(plan);
    for (int a = 0; a < kFeatArrays; ++a) {
        const FeatArray fa = FeatArray(a);
        if (!featArrayUsed(fp, fa)) continue;
        for (int fi = 0; fi < fp.layerCount; ++fi) {
            const std::string t = std::to_string(featUnit(plan, fa, fi));
            o += "[[vk::binding(" + t + ")]] Texture2D<" +
                 (featArrayUnsigned(fa) ? "uint4" : "float4") + "> g" +
                 std::string(kFeatArrayNames[a] + 1) + std::to_string(fi) + " : register(t" + t +
                 ");\n";
        }
    }
    if (fp.layerCount > 0) {
        const std::string b = std::to_string(featUnit(plan, kFeatArrays, 0));
        o += "[[vk::binding(" + b + ")]] SamplerState gFeatSmp : register(s" + std::to_string(n) +
             ");\n";
    }
    o += kHelpers;
    o += "[numthreads(" + std::to_string(sg::gl::kComputeGroupSize) +
         ", 1, 1)] void main(uint3 threadId : SV_DispatchThreadID) {\n"
         "    uint outFloats;\n"
         "    uint strideBytes;\n"
         "    outData.GetDimensions(outFloats, strideBytes);\n"
         "    uint i = threadId.x;\n"
         "    if (i >= outFloats / " +
         std::to_string(kOutStride) + "u) return;\n";
    for (size_t k = 0; k < n; ++k) {
        const std::string s = std::to_string(k);
        o += "    SgSampler2D uTex" + s + ";\n    uTex" + s + ".tex = gTex" + s + ";\n    uTex" +
             s + ".state = gSmp" + s + ";\n";
    }
    for (int a = 0; a < kFeatArrays && fp.layerCount > 0; ++a) {
        const FeatArray fa = FeatArray(a);
        if (!featArrayUsed(fp, fa)) continue;
        const std::string name = kFeatArrayNames[a], global = "g" + name.substr(1);
        o += std::string("    ") + (featArrayUnsigned(fa) ? "Texture2D<uint4> " : "SgSampler2D ") +
             name + "[" + std::to_string(fp.layerCount) + "];\n";
        for (int fi = 0; fi < fp.layerCount; ++fi) {
            const std::string at = name + "[" + std::to_string(fi) + "]",
                              g = global + std::to_string(fi);
            if (featArrayUnsigned(fa)) {
                o += "    " + at + " = " + g + ";\n";
            } else {
                o += "    " + at + ".tex = " + g + ";\n    " + at + ".state = gFeatSmp;\n";
            }
        }
    }
    return o + harnessBody(plan, bfaceMode, statements);
}

// Random pixel inputs: a point of the unit sphere facing the camera, its
// normal slightly off the geometric one (interpolated), screen derivatives
// of a pixel on a unit sphere at 200 x 150 (0.004 to 0.03 units, any
// direction and aspect, a small normal part), UVs in [0, 1] with
// derivatives of 1e-4 to 2e-2 (magnified to minified 256-texel maps).
struct Inputs {
    std::vector<float> data;
    std::vector<detail::PixelInputs> px;
};

Inputs randomInputs(const View& view, const detail::DrawUniforms& u) {
    std::mt19937 rng(kSeed);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f), sym(-1.0f, 1.0f);
    auto logUni = [&](float lo, float hi) { return lo * std::pow(hi / lo, uni(rng)); };
    auto unitVec = [&] {
        for (;;) {
            glm::vec3 v(sym(rng), sym(rng), sym(rng));
            float l = glm::length(v);
            if (l > 0.1f && l <= 1.0f) return v / l;
        }
    };
    const glm::vec3 cam = glm::vec3(view.cameraPos);
    const glm::vec3 toCam = glm::normalize(cam);
    const glm::mat4 modelInv = glm::inverse(u.model);
    Inputs r;
    r.data.assign(kSamples * size_t(kInStride), 0.0f);
    for (size_t i = 0; i < kSamples; ++i) {
        glm::vec3 p = unitVec();
        if (glm::dot(p, toCam) < 0.1f) p = glm::reflect(p, toCam); // the visible side
        if (glm::dot(p, toCam) < 0.1f) p = glm::normalize(p + 0.5f * toCam);
        glm::vec3 t1 = glm::normalize(glm::cross(p, unitVec())), t2 = glm::cross(p, t1);
        const float s = logUni(0.004f, 0.03f), a = 6.2831853f * uni(rng),
                    b = a + 1.5707963f + 0.4f * sym(rng);
        glm::vec3 dPdx = s * (0.5f + 1.5f * uni(rng)) *
                         (std::cos(a) * t1 + std::sin(a) * t2 + 0.2f * sym(rng) * p);
        glm::vec3 dPdy = s * (0.5f + 1.5f * uni(rng)) *
                         (std::cos(b) * t1 + std::sin(b) * t2 + 0.2f * sym(rng) * p);
        detail::PixelInputs in;
        in.normal = glm::normalize(p + 0.02f * unitVec());
        in.dPdx = dPdx;
        in.dPdy = dPdy;
        in.dNdx = dPdx + 0.1f * s * unitVec(); // unit sphere: dN = dP
        in.dNdy = dPdy + 0.1f * s * unitVec();
        in.relPos = p - cam;
        in.objPos = glm::vec3(modelInv * glm::vec4(p, 1.0f));
        in.dObjdx = u.modelInv3 * dPdx;
        in.dObjdy = u.modelInv3 * dPdy;
        in.frontFacing = true;
        for (int k = 0; k < kMaxUvSets; ++k) {
            const size_t kk = size_t(k);
            in.uv[kk] = glm::vec2(uni(rng), uni(rng));
            const float c = 6.2831853f * uni(rng), d = c + 0.6f + 1.9f * uni(rng);
            in.dUVdx[kk] = logUni(1e-4f, 2e-2f) * glm::vec2(std::cos(c), std::sin(c));
            in.dUVdy[kk] = logUni(1e-4f, 2e-2f) * glm::vec2(std::cos(d), std::sin(d));
            glm::vec3 t = glm::normalize(glm::cross(in.normal, unitVec()));
            in.tangent[kk] = glm::vec4(t, uni(rng) < 0.5f ? -1.0f : 1.0f);
        }
        float* f = &r.data[i * size_t(kInStride)];
        auto put3 = [&](int at, glm::vec3 v) {
            for (int c = 0; c < 3; ++c) f[at + c] = v[c];
        };
        put3(kInNormal, in.normal);
        put3(kInDPdx, in.dPdx);
        put3(kInDPdy, in.dPdy);
        put3(kInDNdx, in.dNdx);
        put3(kInDNdy, in.dNdy);
        put3(kInRelPos, in.relPos);
        put3(kInObjPos, in.objPos);
        put3(kInDObjdx, in.dObjdx);
        put3(kInDObjdy, in.dObjdy);
        f[kInFront] = 1.0f;
        for (int k = 0; k < kMaxUvSets; ++k) {
            const size_t kk = size_t(k);
            float* uv = f + kInUv + 6 * k;
            uv[0] = in.uv[kk].x, uv[1] = in.uv[kk].y;
            uv[2] = in.dUVdx[kk].x, uv[3] = in.dUVdx[kk].y;
            uv[4] = in.dUVdy[kk].x, uv[5] = in.dUVdy[kk].y;
            for (int c = 0; c < 4; ++c) f[kInTangent + 4 * k + c] = in.tangent[kk][c];
        }
        r.px.push_back(in);
    }
    return r;
}

// The CPU twin: the same prologue (plan.cpp, CpuShader::prologue, every
// volume built), group 0's layers, the resolve; the same output record.
std::vector<float> runCpu(const MaterialPlan& plan, const detail::DrawUniforms& u,
                          const std::vector<G::sampler2D>& smp,
                          const std::vector<std::any>& kindData, const Inputs& inputs) {
    // The layer's kind's entry of kindData (plan.cpp's CpuShader).
    auto kindDataOf = [&](const PlanLayer& pl) -> const std::any* {
        for (size_t k = 0; k < plan.kindPlans.size(); ++k)
            if (plan.kindPlans[k].kind == pl.layer->kind) return &kindData[k];
        return nullptr;
    };
    std::vector<float> out(kSamples * size_t(kOutStride), 0.0f);
    for (size_t i = 0; i < kSamples; ++i) {
        const detail::PixelInputs& in = inputs.px[i];
        CpuShadeState s;
        s.frame = G::sgPrologue(in.normal, in.dPdx, in.dPdy, in.frontFacing, u.bfaceMode);
        s.surfPos = in.relPos;
        for (int k = 0; k < plan.uvCount; ++k) {
            const size_t kk = size_t(k);
            s.uv[kk] = (plan.vertexTangentMask >> k & 1u)
                           ? G::sgUvFrameVertex(in.uv[kk], in.dUVdx[kk], in.dUVdy[kk], in.normal,
                                                in.tangent[kk])
                           : G::sgUvFramePixel(s.frame, in.uv[kk], in.dUVdx[kk], in.dUVdy[kk]);
        }
        s.volWorld = G::sgVolumeSpace(s.frame, in.relPos, glm::mat3(1.0f), glm::mat3(1.0f));
        s.volObject = G::sgVolumeSpaceDeriv(in.objPos, in.dObjdx, in.dObjdy, u.model3, u.modelInv3);
        for (const PlanLayer& pl : plan.groups[0])
            pl.layer->kind->emit.cpu(CpuLayerContext{plan, pl, u, smp, kindDataOf(pl), in}, s,
                                     glm::vec3(0.0f));
        const glm::vec3 nrm = G::sgResolve(s.frame, s.surfGrad);
        float* o = &out[i * size_t(kOutStride)];
        auto put3 = [&](int at, glm::vec3 v) {
            for (int c = 0; c < 3; ++c) o[at + c] = v[c];
        };
        put3(kOutSurfGrad, s.surfGrad);
        for (int c = 0; c < 3; ++c) put3(kOutSlopeCov + 3 * c, s.slopeCov[c]);
        for (int k = 0; k < plan.uvCount; ++k) {
            o[kOutSt + 2 * k] = s.uv[size_t(k)].st.x;
            o[kOutSt + 2 * k + 1] = s.uv[size_t(k)].st.y;
        }
        put3(kOutNrmBase, s.frame.nrmBase);
        put3(kOutSurfOffset, s.surfOffset);
        put3(kOutNrm, nrm);
    }
    return out;
}

// The plan's textures as the GL renderer uploads them (gl_renderer.cpp:
// RGBA32F, the exact chain, trilinear, the image's wrap), on units
// kTexBase + slot; deleted with the object.
class PlanTextures {
public:
    PlanTextures(const MaterialPlan& plan, const SceneAssets& assets) {
        for (size_t s = 0; s < plan.textureKeys.size(); ++s) {
            auto it = assets.textures.find(plan.textureKeys[s]);
            GLuint t = 0;
            if (it != assets.textures.end()) t = upload(*it->second);
            ids_.push_back(t);
            glBindTextureUnit(GLuint(kTexBase + int(s)), t);
        }
        sg::gl::checkError("harness textures");
    }
    ~PlanTextures() {
        for (GLuint t : ids_)
            if (t) glDeleteTextures(1, &t);
    }
    GLuint id(int slot) const { return slot >= 0 ? ids_[size_t(slot)] : 0; }
    PlanTextures(const PlanTextures&) = delete;
    PlanTextures& operator=(const PlanTextures&) = delete;

private:
    static GLuint upload(const TextureImage& img) {
        GLuint t = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &t);
        glTextureStorage2D(t, GLsizei(img.levels.size()), GL_RGBA32F, img.width(), img.height());
        for (size_t l = 0; l < img.levels.size(); ++l) {
            const TextureLevel& L = img.levels[l];
            std::vector<glm::vec4> texels(size_t(L.width) * size_t(L.height));
            L.expandRows(0, L.height, texels.data());
            glTextureSubImage2D(t, GLint(l), 0, 0, L.width, L.height, GL_RGBA, GL_FLOAT,
                                texels.data());
        }
        glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        const GLint wrap = img.wrap == Wrap::Clamp ? GL_CLAMP_TO_EDGE : GL_REPEAT;
        glTextureParameteri(t, GL_TEXTURE_WRAP_S, wrap);
        glTextureParameteri(t, GL_TEXTURE_WRAP_T, wrap);
        glTextureParameteri(t, GL_TEXTURE_MAX_LEVEL, GLint(img.levels.size()) - 1);
        return t;
    }
    std::vector<GLuint> ids_;
};

// The feature layers' maps as feature_assets.cpp uploads them (RGBA32UI,
// one level, nearest; read with texelFetch), on the units of featUnit:
// maps without a near field have their corner texture stand in for the
// near textures (never read; an integer sampler needs an integer texture),
// the base and chain arrays the layer's texture slots (bindGpu: base and
// chain A slot 0, chain B slot 1 or 0); deleted with the object.
class FeatureTextures {
public:
    FeatureTextures(const MaterialPlan& plan, const SceneAssets& assets,
                    const PlanTextures& planTextures) {
        const KindPlan* kp = nullptr;
        for (const KindPlan& k : plan.kindPlans)
            if (k.kind->batch) kp = &k;
        if (!kp) return;
        std::vector<std::array<GLuint, 4>> slots;
        for (const std::string& key : kp->keys) {
            std::array<GLuint, 4> t{0, 0, 0, 0};
            if (const FeatureMapsAsset* fm = findFeatureMaps(assets, key)) {
                const auto& g = fm->gpu;
                t[0] = upload(g.cornerPairsWidth(), g.cornerPairsHeight(), g.cornerPairs);
                t[1] = upload(g.size, g.size, g.edges);
                if (g.hasNearField()) {
                    t[2] = upload(g.size, g.nearHeight, g.nearLists);
                    t[3] = upload(SG_FEAT_PIECES_WIDTH, g.piecesHeight, g.pieces);
                }
            }
            for (GLuint x : t)
                if (x) ids_.push_back(x);
            if (!t[2]) t[2] = t[3] = t[0];
            slots.push_back(t);
        }
        const FeaturePlan fp = featurePlan(plan);
        for (const auto& g : plan.groups)
            for (const PlanLayer& pl : g) {
                if (pl.kindIndex < 0 || !pl.layer->kind->batch) continue;
                const auto& t = slots[size_t(pl.kindSlot)];
                auto bind = [&](FeatArray a, GLuint tex) {
                    if (featArrayUsed(fp, a))
                        glBindTextureUnit(GLuint(featUnit(plan, a, pl.kindIndex)), tex);
                };
                bind(kFeatCorners, t[0]);
                bind(kFeatEdges, t[1]);
                bind(kFeatNear, t[2]);
                bind(kFeatPieces, t[3]);
                bind(kFeatBase, planTextures.id(pl.tex[0]));
                bind(kFeatChainA, planTextures.id(pl.tex[0]));
                bind(kFeatChainB, planTextures.id(pl.tex[1] >= 0 ? pl.tex[1] : pl.tex[0]));
            }
        sg::gl::checkError("harness feature maps");
    }
    ~FeatureTextures() {
        for (GLuint t : ids_) glDeleteTextures(1, &t);
    }
    FeatureTextures(const FeatureTextures&) = delete;
    FeatureTextures& operator=(const FeatureTextures&) = delete;

private:
    static GLuint upload(int w, int h, const std::vector<uint32_t>& data) {
        GLuint x = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &x);
        glTextureStorage2D(x, 1, GL_RGBA32UI, w, h);
        glTextureSubImage2D(x, 0, 0, 0, w, h, GL_RGBA_INTEGER, GL_UNSIGNED_INT, data.data());
        glTextureParameteri(x, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(x, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        return x;
    }
    std::vector<GLuint> ids_;
};

// Shader storage buffers 2 (the layer records) and 3 (the draw matrices'
// columns), bound while the object lives.
class DrawBuffers {
public:
    explicit DrawBuffers(const detail::DrawUniforms& u) {
        glCreateBuffers(2, bufs_);
        std::vector<glm::vec4> records = u.records;
        if (records.empty()) records.emplace_back(0.0f);
        std::vector<glm::vec4> draw;
        for (const glm::mat3* m : {&u.normalMat, &u.model3, &u.modelInv3})
            for (int c = 0; c < 3; ++c) draw.emplace_back((*m)[c], 0.0f);
        glNamedBufferData(bufs_[0], GLsizeiptr(records.size() * sizeof(glm::vec4)), records.data(),
                          GL_STATIC_DRAW);
        glNamedBufferData(bufs_[1], GLsizeiptr(draw.size() * sizeof(glm::vec4)), draw.data(),
                          GL_STATIC_DRAW);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, bufs_[0]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, bufs_[1]);
        sg::gl::checkError("harness buffers");
    }
    ~DrawBuffers() { glDeleteBuffers(2, bufs_); }
    DrawBuffers(const DrawBuffers&) = delete;
    DrawBuffers& operator=(const DrawBuffers&) = delete;

private:
    GLuint bufs_[2] = {0, 0};
};

double angleDeg(glm::vec3 a, glm::vec3 b) {
    const glm::dvec3 x(a), y(b);
    return glm::degrees(std::atan2(glm::length(glm::cross(x, y)), glm::dot(x, y)));
}

bool allFinite(const std::vector<float>& v) {
    return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

struct Errors {
    double maxDeg = 0.0;       // resolved normal, GPU against CPU
    double stPixels = 0.0;     // |uv.st difference| / the pixel's st footprint
    double offsetPixels = 0.0; // |surfOffset difference| / the pixel's size
    double slopeCovRel = 0.0;  // |slopeCov difference| / the case's largest |slopeCov|
};

Errors compare(const MaterialPlan& plan, const Inputs& in, const std::vector<float>& gpu,
               const std::vector<float>& cpu) {
    Errors e;
    double covScale = 0.0;
    for (size_t i = 0; i < kSamples; ++i)
        for (int c = 0; c < 9; ++c)
            covScale = std::max(covScale, double(std::abs(cpu[i * kOutStride + kOutSlopeCov + c])));
    for (size_t i = 0; i < kSamples; ++i) {
        const float* g = &gpu[i * size_t(kOutStride)];
        const float* c = &cpu[i * size_t(kOutStride)];
        auto v3 = [](const float* p) { return glm::vec3(p[0], p[1], p[2]); };
        e.maxDeg = std::max(e.maxDeg, angleDeg(v3(g + kOutNrm), v3(c + kOutNrm)));
        const detail::PixelInputs& px = in.px[i];
        for (int k = 0; k < plan.uvCount; ++k) {
            const size_t kk = size_t(k);
            const double foot = double(glm::length(px.dUVdx[kk]) + glm::length(px.dUVdy[kk]));
            const glm::vec2 d(g[kOutSt + 2 * k] - c[kOutSt + 2 * k],
                              g[kOutSt + 2 * k + 1] - c[kOutSt + 2 * k + 1]);
            e.stPixels = std::max(e.stPixels, double(glm::length(d)) / foot);
        }
        const double pixel = double(glm::length(px.dPdx) + glm::length(px.dPdy));
        e.offsetPixels =
            std::max(e.offsetPixels,
                     double(glm::length(v3(g + kOutSurfOffset) - v3(c + kOutSurfOffset))) / pixel);
        if (covScale > 0.0) {
            for (int k = 0; k < 9; ++k)
                e.slopeCovRel = std::max(
                    e.slopeCovRel,
                    std::abs(double(g[kOutSlopeCov + k] - c[kOutSlopeCov + k])) / covScale);
        }
    }
    return e;
}

class LayerHlsl : public ::testing::TestWithParam<HarnessCase> {};

// Bounds (per case and target, GPU against the CPU twin over kSamples
// pixels):
//  - the resolved normal within 0.05 degrees: the image-parity bound
//    (Kinds/LayerImage.GpuMatchesCpuReference's max), which the same
//    statements meet on the renderer's fragment programs; the HLSL
//    spelling must change nothing a rendered pixel shows;
//  - uv<k>.st (parallax and POM correct it) within 1% of the pixel's
//    footprint in st (|dSTdx| + |dSTdy|): a shift no sampled texel shows;
//  - surfOffset (the virtual surface) within 1% of the pixel's size
//    (|dPdx| + |dPdy|), for the same reason in position;
//  - slopeCov within 1e-3 of the case's largest entry (antialiasing plans:
//    a lobe widened by a thousandth of the bumps' variance).
constexpr double kMaxDeg = 0.05, kMaxStPixels = 0.01, kMaxOffsetPixels = 0.01,
                 kMaxSlopeCovRel = 1e-3;

TEST_P(LayerHlsl, GroupZeroStatementsMatchCpuInGlslAndThroughHlsl) {
    const HarnessCase& hc = GetParam();
    gpu(); // the GL 4.5 context
    Scene scene = sceneFromJson(hc.json);
    SceneAssets assets = loadAssets(scene);
    const MaterialPlan plan = planMaterial(scene, assets, 0, 0);
    const View view = makeView(scene, assets, 0, 0, Aov::Normal);
    const detail::DrawUniforms u = detail::drawUniforms(scene, assets, plan, view, 0, 0.0f);
    const std::vector<G::sampler2D> smp =
        detail::planSamplers(plan, assets, gpuParityOptions().textureLod);
    ASSERT_FALSE(plan.groups.empty());
    if (!hc.kind->group) {
        EXPECT_TRUE(std::any_of(plan.groups[0].begin(), plan.groups[0].end(),
                                [&](const PlanLayer& pl) { return pl.layer->kind == hc.kind; }))
            << hc.name << ": the kind's own layer is in group 0";
    }

    const std::vector<std::string> statements = groupStatements(plan);
    const std::vector<std::string> defines = planDefines(plan);
    const std::string glsl = glslHarness(plan, u.bfaceMode, statements);
    const shaders::Assembled hlsl =
        shaders::assemble(hlslHarness(plan, u.bfaceMode, statements), "layer-hlsl-" + hc.name,
                          defines, shaders::Target::Hlsl);
    // Not vacuous: every statement is in the HLSL and calls its kind's
    // shared function (sgLayer<Kind>, or the sampler of a modifier block).
    for (size_t j = 0; j < statements.size(); ++j) {
        const PlanLayer& pl = plan.groups[0][j];
        // A modifier block samples through sgSample<Kind>HD.
        const std::string fn = pl.hasModifiers ? "sgSample" : "sgLayer";
        EXPECT_NE(statements[j].find(fn), std::string::npos) << hc.name << ": " << statements[j];
        EXPECT_NE(hlsl.text.find(statements[j]), std::string::npos) << hc.name;
        if (pl.layer->kind->batch) { // the plan's variant of the feature function
            const FeaturePlan fp = featurePlan(plan);
            const std::string want = std::string("sgLayerFeature") + (fp.near ? "Near" : "") +
                                     (fp.lean ? "Aa" : "") + "(";
            EXPECT_NE(statements[j].find(want), std::string::npos)
                << hc.name << ": " << statements[j];
        }
    }

    const Inputs inputs = randomInputs(view, u);
    const std::vector<float> cpu =
        runCpu(plan, u, smp, detail::planKindCpuData(plan, assets), inputs);
    ASSERT_TRUE(allFinite(cpu)) << hc.name << ": the CPU twin";

    PlanTextures textures(plan, assets);
    FeatureTextures featureTextures(plan, assets, textures);
    DrawBuffers buffers(u);
    sg::gl::Program glslProg(
        {{sg::gl::Stage::Compute, shaders::assemble(glsl, "layer-glsl-" + hc.name, defines)}});
    const std::vector<float> gpuGlsl =
        sg::gl::runCompute(glslProg, inputs.data, kInStride, kOutStride, kSamples);
    std::vector<float> gpuHlsl;
    try {
        sg::gl::Program hlslProg = sg::test::hlslComputeProgram(hlsl, "layer-" + hc.name, true);
        gpuHlsl = sg::gl::runCompute(hlslProg, inputs.data, kInStride, kOutStride, kSamples);
    } catch (const std::exception& e) {
        FAIL() << hc.name << ": " << e.what();
    }

    // Not trivial: the layers bump somewhere.
    size_t bumped = 0;
    for (size_t i = 0; i < kSamples; ++i) {
        const float* c = &cpu[i * size_t(kOutStride) + kOutSurfGrad];
        bumped += glm::length(glm::vec3(c[0], c[1], c[2])) > 1e-6f;
    }
    EXPECT_GT(bumped, 0u) << hc.name << ": surfGrad is zero at every sample";

    const std::pair<const char*, const std::vector<float>*> targets[] = {{"glsl450", &gpuGlsl},
                                                                         {"hlsl", &gpuHlsl}};
    Errors err[2];
    for (int t = 0; t < 2; ++t) {
        SCOPED_TRACE(std::string(hc.name) + " " + targets[t].first);
        const std::vector<float>& g = *targets[t].second;
        ASSERT_TRUE(allFinite(g));
        err[t] = compare(plan, inputs, g, cpu);
        EXPECT_LE(err[t].maxDeg, kMaxDeg);
        EXPECT_LE(err[t].stPixels, kMaxStPixels);
        EXPECT_LE(err[t].offsetPixels, kMaxOffsetPixels);
        EXPECT_LE(err[t].slopeCovRel, kMaxSlopeCovRel);
    }
    std::printf("[layer-hlsl] %-44s worst angle glsl450 %.3g deg, hlsl %.3g deg; st %.2g/%.2g px, "
                "offset %.2g/%.2g px, slopeCov %.2g/%.2g; bumped %zu/%zu\n",
                hc.name.c_str(), err[0].maxDeg, err[1].maxDeg, err[0].stPixels, err[1].stPixels,
                err[0].offsetPixels, err[1].offsetPixels, err[0].slopeCovRel, err[1].slopeCovRel,
                bumped, kSamples);
}

INSTANTIATE_TEST_SUITE_P(Kinds, LayerHlsl, ::testing::ValuesIn(harnessCases()),
                         [](const auto& tpi) { return tpi.param.name; });

// Every registered kind, the batched (feature) kind included, is run by
// the harness.
TEST(LayerHlslCoverage, EveryKindHasACase) {
    const std::vector<HarnessCase> cases = harnessCases();
    for (const LayerKind* k : layerKinds()) {
        EXPECT_TRUE(std::any_of(cases.begin(), cases.end(), [&](const HarnessCase& c) {
            return c.kind == k;
        })) << k->name;
    }
}

} // namespace
} // namespace sg::render::test
