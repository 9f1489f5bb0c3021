// HLSL entry of the surfgrad shader library (Unity, Unreal, D3D; glslang's
// and DXC's HLSL front ends): `#include "sg/surfgrad.hlsl"` gives every
// function of sg/surfgrad.glsl, with the same names, arguments and results
// as in GLSL and C++, compiled from the same source through the macro layer
// of sg/compat.hlsl (docs/engines.md, "HLSL").
#ifndef SG_SURFGRAD_HLSL
#define SG_SURFGRAD_HLSL

#include "sg/compat.hlsl"
#include "sg/surfgrad.glsl"

#endif
