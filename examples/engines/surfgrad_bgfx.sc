// bgfx: surfgrad's per-pixel normal mapping in a fragment shader for
// bgfx's shaderc (docs/engines.md, "bgfx"). Put share/surfgrad/shaders/flat
// on shaderc's include path (-i). For D3D backends define SG_BIT_ARITHMETIC
// before the include (frexp and ldexp from bit patterns; docs/engines.md).
$input v_relpos, v_normal, v_texcoord0

#include <bgfx_shader.sh>
#include "surfgrad.glsl"

SAMPLER2D(s_detail, 0);

void main() {
    SgFrame frame = sgPrologue(v_normal, dFdx(v_relpos), dFdy(v_relpos), gl_FrontFacing, 0);
    vec3 vT;
    vec3 vB;
    sgGenBasisTB(frame, v_texcoord0, dFdx(v_texcoord0), dFdy(v_texcoord0), vT, vB);
    vec2 m = texture2D(s_detail, v_texcoord0).xy * 2.0 - 1.0;
    vec3 nrm = sgResolve(frame, sgSurfgradFromTBN(sgTspaceNormalToDeriv(m, false), vT, vB));
    gl_FragColor = vec4(0.5 * nrm + 0.5, 1.0);
}
