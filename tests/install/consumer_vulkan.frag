// consumer.frag as a Vulkan engine writes it: explicit locations and a
// descriptor binding, compiled to SPIR-V by install_test.sh with
// `glslangValidator -V -I<prefix>/share/surfgrad/shaders` and checked by
// spirv-val.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "sg/surfgrad.glsl"

layout(location = 0) in vec3 vRelPos; // position relative to the camera
layout(location = 1) in vec3 vNormal; // interpolated vertex normal
layout(location = 2) in vec2 vUv0;
layout(set = 0, binding = 0) uniform sampler2D uNormalMap; // tangent-space normal map, UNORM
layout(location = 0) out vec4 outColor;

void main() {
    SgFrame f = sgPrologue(vNormal, dFdxFine(vRelPos), dFdyFine(vRelPos), gl_FrontFacing,
                           SG_BFACE_NONE);
    vec3 vT, vB;
    sgGenBasisTB(f, vUv0, dFdxFine(vUv0), dFdyFine(vUv0), vT, vB);
    vec2 m = 2.0 * texture(uNormalMap, vUv0).xy - 1.0;
    vec3 n = sgResolve(f, sgSurfgradFromTBN(sgTspaceNormalToDeriv(m, false), vT, vB));
    outColor = vec4(0.5 * n + 0.5, 1.0);
}
