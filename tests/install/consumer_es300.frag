#version 300 es
// (ES wants #version before anything, comments included.)
// consumer.frag as a WebGL2 / GLES 3 engine writes it: GLSL ES 3.00, so
// dFdx/dFdy instead of dFdxFine (coarse on many GPUs: docs/engines.md says
// what that costs) and a sampler precision. Validated by install_test.sh
// with only -I<prefix>/share/surfgrad/shaders.
#extension GL_GOOGLE_include_directive : require
precision highp float;
precision highp sampler2D;
#include "sg/surfgrad.glsl"

in vec3 vRelPos; // position relative to the camera
in vec3 vNormal; // interpolated vertex normal
in vec2 vUv0;
uniform sampler2D uNormalMap; // tangent-space normal map, UNORM
out vec4 outColor;

void main() {
    SgFrame f = sgPrologue(vNormal, dFdx(vRelPos), dFdy(vRelPos), gl_FrontFacing, SG_BFACE_NONE);
    vec3 vT, vB;
    sgGenBasisTB(f, vUv0, dFdx(vUv0), dFdy(vUv0), vT, vB);
    vec2 m = 2.0 * texture(uNormalMap, vUv0).xy - 1.0;
    vec3 n = sgResolve(f, sgSurfgradFromTBN(sgTspaceNormalToDeriv(m, false), vT, vB));
    outColor = vec4(0.5 * n + 0.5, 1.0);
}
