// Fragment shader of the engine-integration sample: two bump layers of
// different kinds composed with the surfgrad GLSL library (Mikkelsen,
// "Surface Gradient Based Bump Mapping Framework", 2019):
//   1. a tangent-space normal map on UV0 with a per-pixel basis
//      (listings 4, 5, 6: no vertex tangents);
//   2. a decal projector, a volume bump map (section 2.9, listing 15);
// each turned into a surface gradient, scaled, added (eq. 2-3) and resolved
// once (listing 1) after the prologue (listing 16, section 2.11).
//
// The library is pulled in with one #include; the host program resolves it
// (here with sg::shaders::assemble, in an engine with its own include
// mechanism: see README.md). Everything else is ordinary engine code.
#include "sg/surfgrad.glsl"

in vec3 vRelPos; // world position relative to the camera
in vec3 vNormal; // interpolated world normal (not normalized)
in vec2 vUv0;

uniform int uBfaceMode; // SG_BFACE_NONE / MIRROR / FLIP (section 2.10)
#ifdef EXAMPLE_ANALYTIC_DERIVS
uniform mat4 uInvViewProjScr; // window (x, y in pixels, depth in [0,1]) -> camera-relative world
#endif

uniform sampler2D uNormalMap; // RGB8 UNORM (not sRGB!): 0.5 * m + 0.5, green = +t
uniform float uNormalStrength;

uniform sampler2D uDecalMap; // same encoding, clamped at the edges
uniform vec3 uDecalOrigin;   // box centre, relative to the camera
uniform vec3 uDecalAxisX, uDecalAxisY, uDecalAxisZ; // unit; z back toward the projector
uniform vec3 uDecalHalfSize;
uniform vec2 uDecalCosFade; // (cos where the angle fade starts, cos where it ends)
uniform float uDecalStrength;

uniform vec3 uLightDir; // toward the light
uniform vec3 uBaseColor;
uniform int uOutput; // 0: linear colour, 1: perturbed world normal

out vec4 outColor;

void main() {
    // ---- Prologue (listing 16): once per pixel. The screen derivatives are
    // taken HERE, in the engine's shader; the library functions never call
    // dFdx themselves (they also compile as C++).
#ifdef EXAMPLE_ANALYTIC_DERIVS
    // No usable dFdx (deferred/compute pass, POM, ...): the derivatives of
    // the position follow from the pixel's ray and the tangent plane
    // (listing 17).
    vec3 dPdx, dPdy;
    sgScreenDerivOfPos(dPdx, dPdy, vRelPos, vNormal, uInvViewProjScr, gl_FragCoord.x, gl_FragCoord.y);
#else
    vec3 dPdx = dFdxFine(vRelPos);
    vec3 dPdy = dFdyFine(vRelPos);
#endif
    SgFrame frame = sgPrologue(vNormal, dPdx, dPdy, gl_FrontFacing, uBfaceMode);

    vec3 surfGrad = vec3(0.0);

    // ---- Layer 1: tangent-space normal map on UV0, per-pixel basis.
    vec2 dSTdx = dFdxFine(vUv0);
    vec2 dSTdy = dFdyFine(vUv0);
    vec3 vT, vB;
    sgGenBasisTB(frame, vUv0, dSTdx, dSTdy, vT, vB);                  // listing 6
    vec2 m = 2.0 * textureGrad(uNormalMap, vUv0, dSTdx, dSTdy).xy - 1.0;
    vec2 deriv = sgTspaceNormalToDeriv(m, false);                     // listing 4, green up
    surfGrad += sgBumpScale(uNormalStrength, sgSurfgradFromTBN(deriv, vT, vB)); // listings 2, 5

    // ---- Layer 2: decal projector (a volume bump map).
    vec3 r = vRelPos - uDecalOrigin;
    vec3 l = vec3(dot(r, uDecalAxisX), dot(r, uDecalAxisY), dot(r, uDecalAxisZ)) / uDecalHalfSize;
    vec2 decalST = 0.5 * l.xy + 0.5;
    // Sampled unconditionally with explicit gradients (chain rule: st moves
    // 0.5 / halfSize per unit along each axis), then faded to zero outside.
    vec2 decalDx = 0.5 * vec2(dot(dPdx, uDecalAxisX), dot(dPdx, uDecalAxisY)) / uDecalHalfSize.xy;
    vec2 decalDy = 0.5 * vec2(dot(dPdy, uDecalAxisX), dot(dPdy, uDecalAxisY)) / uDecalHalfSize.xy;
    vec2 dm = 2.0 * textureGrad(uDecalMap, decalST, decalDx, decalDy).xy - 1.0;
    vec2 decalDeriv = sgTspaceNormalToDeriv(dm, false);
    bool inBox = all(lessThanEqual(abs(l), vec3(1.0)));
    float angleFade = clamp((dot(frame.nrmBase, uDecalAxisZ) - uDecalCosFade.y) /
                            (uDecalCosFade.x - uDecalCosFade.y), 0.0, 1.0);
    float fade = inBox ? angleFade : 0.0;
    // Listing 15; the fade is a bump scale (end of section 2.9).
    surfGrad += sgBumpScale(fade * uDecalStrength,
                            sgSurfgradFromDecal(frame, decalDeriv, uDecalAxisX, uDecalAxisY, false));

    // ---- Resolve once (listing 1, eq. 1).
    vec3 n = sgResolve(frame, surfGrad);

    if (uOutput == 1) {
        outColor = vec4(n, 1.0);
        return;
    }
    // Ordinary engine shading from here on: Lambert + Blinn-Phong.
    vec3 v = normalize(-vRelPos);
    vec3 h = normalize(uLightDir + v);
    float nDotL = max(dot(n, uLightDir), 0.0);
    float spec = pow(max(dot(n, h), 0.0), 60.0) * (nDotL > 0.0 ? 0.4 : 0.0);
    vec3 sky = mix(vec3(0.05, 0.045, 0.04), vec3(0.10, 0.12, 0.16), 0.5 * n.y + 0.5);
    outColor = vec4(uBaseColor * (sky + 1.8 * nDotL) + vec3(1.8 * spec), 1.0);
}
