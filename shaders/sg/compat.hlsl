// surfgrad shared-shader common subset: HLSL side (Unity, Unreal, D3D11/12,
// and glslang's or DXC's HLSL front ends to SPIR-V).
//
// The third language of the one shared source (the GLSL side is
// sg/compat.glsl, the C++ side surfgrad/shaders/glsl_cpp.h). An HLSL file includes
// sg/surfgrad.hlsl, which includes this file (defining SG_HLSL) and then the
// GLSL sources; sg/compat.glsl then leaves the spelling to the macros here. This is the arrangement of
// OpenSubdiv's osd/patchBasisCommon.h (OSD_PATCH_BASIS_HLSL): the GLSL names
// of the subset are spelled as HLSL types and built-ins by the preprocessor.
//
// What the mapping relies on (docs/engines.md, "HLSL"):
//   - matrices: the shared code builds them from columns (mat2(c0, c1),
//     mat4(c0, c1, c2, c3), outerProduct, sgMat3Diag), adds and scales
//     them and reads columns and elements back (m[i], m[i][j]); it never
//     multiplies a matrix by a vector or by a matrix. floatNxM(r0, r1, ...) takes rows and
//     m[i] returns row i, so HLSL holds the transpose of GLSL's matrix and
//     every access the subset allows means the same;
//   - no splat constructors (vec3(x)): HLSL's constructors take as many
//     components as the type has, so the subset writes sgVec3(x)
//     (sg/compat.glsl);
//   - frexp/ldexp/imulExtended/unpackHalf2x16: HLSL's frexp returns its
//     exponent as a float, and the others differ or are missing, so HLSL
//     takes the bit-pattern path of GLSL 3.30 (SG_GLSL_LEGACY);
//   - GLSL's mod is x - y floor(x/y); HLSL's fmod truncates: the subset does
//     not use mod (GlslSubset.SharedFunctionsUseNoMod checks).
#ifndef SG_COMPAT_HLSL
#define SG_COMPAT_HLSL

#define SG_HLSL 1

#define SG_GLSL_LEGACY 1

#define vec2 float2
#define vec3 float3
#define vec4 float4
#define ivec2 int2
#define ivec3 int3
#define ivec4 int4
#define uvec2 uint2
#define uvec3 uint3
#define uvec4 uint4
#define bvec2 bool2
#define bvec3 bool3
#define bvec4 bool4
#define mat2 float2x2
#define mat3 float3x3
#define mat4 float4x4

#define fract frac
#define mix lerp
#define inversesqrt rsqrt
#define dFdx ddx
#define dFdy ddy
#define dFdxFine ddx_fine
#define dFdyFine ddy_fine
#define dFdxCoarse ddx_coarse
#define dFdyCoarse ddy_coarse
#define floatBitsToInt asint
#define floatBitsToUint asuint
#define intBitsToFloat asfloat
#define uintBitsToFloat asfloat

// texelFetch and textureSize of the unsigned integer textures the shared
// code reads (the feature maps, sg/features/fetch.glsl), as GLSL spells
// them: level `lod` of an HLSL Texture2D<uint4>.
uint4 texelFetch(Texture2D<uint4> tex, int2 texel, int lod) { return tex.Load(int3(texel, lod)); }
int2 textureSize(Texture2D<uint4> tex, int lod) {
    uint width;
    uint height;
    uint levels;
    tex.GetDimensions(uint(lod), width, height, levels);
    return int2(int(width), int(height));
}

// outerProduct(c, r): GLSL's matrix with column j = c r[j], held as HLSL
// rows (see "matrices" above).
float2x2 outerProduct(float2 c, float2 r) { return float2x2(c * r.x, c * r.y); }
float3x3 outerProduct(float3 c, float3 r) { return float3x3(c * r.x, c * r.y, c * r.z); }

// sampler2D: a texture and its sampler state travel together (HLSL keeps
// them apart), and texture/textureGrad/textureLod/textureSize read them.
// `texture` is an HLSL keyword, so the GLSL name is spelled sgTexture.
struct SgSampler2D {
    Texture2D<float4> tex;
    SamplerState state;
};
#define sampler2D SgSampler2D
#define texture sgTexture
float4 sgTexture(SgSampler2D s, float2 st) { return s.tex.Sample(s.state, st); }
float4 textureGrad(SgSampler2D s, float2 st, float2 dSTdx, float2 dSTdy) {
    return s.tex.SampleGrad(s.state, st, dSTdx, dSTdy);
}
float4 textureLod(SgSampler2D s, float2 st, float lod) { return s.tex.SampleLevel(s.state, st, lod); }
int2 textureSize(SgSampler2D s, int lod) {
    uint width;
    uint height;
    uint levels;
    s.tex.GetDimensions(uint(lod), width, height, levels);
    return int2(int(width), int(height));
}

#define SG_OUT(T) out T
#define SG_INOUT(T) inout T
#define SG_FN

#endif
