// consumer.frag as a D3D / Unity / Unreal pixel shader writes it: HLSL
// (Shader Model 5), the library through sg/surfgrad.hlsl, ddx_fine/ddy_fine
// for the per-pixel frame, SV_IsFrontFace for the back-face mode.
// Validated by install_test.sh with only -I<prefix>/share/surfgrad/shaders
// (glslangValidator's HLSL front end, then spirv-val on its SPIR-V).
#include "sg/surfgrad.hlsl"

Texture2D<float4> gNormalMap : register(t0); // tangent-space normal map, UNORM
SamplerState gLinear : register(s0);

struct PixelIn {
    float4 position : SV_Position;
    float3 relPos : TEXCOORD0; // position relative to the camera
    float3 normal : TEXCOORD1; // interpolated vertex normal
    float2 uv0 : TEXCOORD2;
};

float4 main(PixelIn i, bool isFrontFace : SV_IsFrontFace) : SV_Target {
    SgFrame f = sgPrologue(i.normal, ddx_fine(i.relPos), ddy_fine(i.relPos), isFrontFace,
                           SG_BFACE_NONE);
    float3 vT;
    float3 vB;
    sgGenBasisTB(f, i.uv0, ddx_fine(i.uv0), ddy_fine(i.uv0), vT, vB);
    float2 m = 2.0f * gNormalMap.Sample(gLinear, i.uv0).xy - 1.0f;
    float3 n = sgResolve(f, sgSurfgradFromTBN(sgTspaceNormalToDeriv(m, false), vT, vB));
    return float4(0.5f * n + 0.5f, 1.0f);
}
