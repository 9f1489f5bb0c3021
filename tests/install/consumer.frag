// A fragment shader as an engine writes it against the installed GLSL
// library: the only include path is <prefix>/share/surfgrad/shaders, and
// glslang resolves the #include lines (GL_GOOGLE_include_directive).
// tests/install/install_test.sh validates it with `glslangValidator -l -I`.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "sg/surfgrad.glsl"

in vec3 vRelPos; // position relative to the camera
in vec3 vNormal; // interpolated vertex normal
in vec2 vUv0;
uniform sampler2D uNormalMap; // tangent-space normal map, UNORM
out vec4 outColor;

void main() {
    // Prologue (listing 16), a per-pixel basis (listing 6), the normal map
    // as a surface gradient (listings 4, 5), one resolve (listing 1).
    SgFrame f = sgPrologue(vNormal, dFdxFine(vRelPos), dFdyFine(vRelPos), gl_FrontFacing,
                           SG_BFACE_NONE);
    vec3 vT, vB;
    sgGenBasisTB(f, vUv0, dFdxFine(vUv0), dFdyFine(vUv0), vT, vB);
    vec2 m = 2.0 * texture(uNormalMap, vUv0).xy - 1.0;
    vec3 n = sgResolve(f, sgSurfgradFromTBN(sgTspaceNormalToDeriv(m, false), vT, vB));
    outColor = vec4(0.5 * n + 0.5, 1.0);
}
