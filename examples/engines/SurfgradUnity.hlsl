// Unity: surfgrad's per-pixel normal mapping as a Shader Graph Custom
// Function node (Type: File, Name: SurfgradNormalMap) or a function an HDRP
// or URP shader calls. Copy share/surfgrad/shaders/flat/surfgrad.hlsl next
// to this file (or put share/surfgrad/shaders on the include path and
// include "sg/surfgrad.hlsl"). docs/engines.md, "Unity".
//
// Inputs, all in one space (world or camera-relative world, as HDRP gives
// them): PositionWS the surface position, NormalWS the interpolated vertex
// normal, UV the texture coordinate of the normal map's UV set (any set:
// the frame is built per pixel from its screen derivatives, no tangent
// attribute is read), NormalTS the normal map's sample (x, y in [-1, 1],
// UnpackNormal's result), IsFrontFace the facing. Out: the bumped unit
// normal in the same space. Several bump layers add their surface
// gradients before one resolve (docs/engines.md).
#ifndef SURFGRAD_UNITY_HLSL
#define SURFGRAD_UNITY_HLSL

#include "surfgrad.hlsl"

void SurfgradNormalMap_float(float3 PositionWS, float3 NormalWS, float2 UV, float3 NormalTS,
                             bool IsFrontFace, out float3 Out) {
    SgFrame f = sgPrologue(NormalWS, ddx_fine(PositionWS), ddy_fine(PositionWS), IsFrontFace,
                           SG_BFACE_FLIP);
    float3 vT;
    float3 vB;
    sgGenBasisTB(f, UV, ddx_fine(UV), ddy_fine(UV), vT, vB);
    float2 deriv = sgTspaceNormalToDeriv(float2(NormalTS.x, NormalTS.y), false);
    Out = sgResolve(f, sgSurfgradFromTBN(deriv, vT, vB));
}

// Shader Graph's half-precision variant calls the same float code.
void SurfgradNormalMap_half(float3 PositionWS, float3 NormalWS, float2 UV, float3 NormalTS,
                            bool IsFrontFace, out float3 Out) {
    SurfgradNormalMap_float(PositionWS, NormalWS, UV, NormalTS, IsFrontFace, Out);
}

#endif
