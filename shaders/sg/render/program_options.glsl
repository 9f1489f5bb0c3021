// The options of the renderer's surface programs (sg/render/surface_vs.glsl,
// sg/render/surface_fs.glsl, sg/patch/patch_tes.glsl), defaulted once:
//   SG_UV_COUNT            number of texture coordinate sets (0..4);
//   SG_VTX_TANGENT_k (0/1) whether UV set k has vertex tangents
//                          (mikktspace or limit frames) as an attribute.
// The renderer defines all of them (render/src/plan.cpp); the defaults let
// each file compile alone, and GLSL ES 3.00 rejects an undefined macro in
// `#if`.
#ifndef SG_RENDER_PROGRAM_OPTIONS_GLSL
#define SG_RENDER_PROGRAM_OPTIONS_GLSL

#ifndef SG_UV_COUNT
#define SG_UV_COUNT 0
#endif
#ifndef SG_VTX_TANGENT_0
#define SG_VTX_TANGENT_0 0
#endif
#ifndef SG_VTX_TANGENT_1
#define SG_VTX_TANGENT_1 0
#endif
#ifndef SG_VTX_TANGENT_2
#define SG_VTX_TANGENT_2 0
#endif
#ifndef SG_VTX_TANGENT_3
#define SG_VTX_TANGENT_3 0
#endif

#endif
