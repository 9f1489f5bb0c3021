// The shaders of the three.js example: the page's own GLSL ES 3.00 around
// the surfgrad library (shaders/flat/surfgrad.glsl, fetched and placed
// before fragmentBody by main.js). Every bump layer is a surface gradient
// (Mikkelsen 2019): a normal map on UV set 0 and a detail map on UV set 1
// (listings 4-6, each set with its own per-pixel frame), triplanar
// (listings 13-14), a decal (listing 15), volume noise (section 2.7); they
// add, and sgResolve makes the normal once. The common tangent-space blends
// of two normal maps (whiteout, UDN, RNM; the library's sg/normal_blends.glsl)
// are offered for comparison: they assume that both maps share one tangent
// frame, which two UV sets do not.

export const layerNames = ['base', 'detail', 'triplanar', 'decal', 'noise'];
export const blendNames = ['surfgrad', 'whiteout', 'udn', 'rnm'];

export const vertexShader = /* glsl */ `
precision highp float;
uniform mat4 modelMatrix;
uniform mat4 viewMatrix;
uniform mat4 projectionMatrix;
uniform vec3 cameraPosition;
in vec3 position;
in vec3 normal;
in vec2 uv;
in vec2 uv1;
out vec3 vRelPos;   // world position relative to the camera (listing 16)
out vec3 vWorldPos; // world position (triplanar, decal, noise)
out vec3 vNormal;   // world vertex normal
out vec2 vUv0;
out vec2 vUv1;
void main() {
    vec4 world = modelMatrix * vec4(position, 1.0);
    vWorldPos = world.xyz;
    vRelPos = world.xyz - cameraPosition;
    vNormal = transpose(inverse(mat3(modelMatrix))) * normal;
    vUv0 = uv;
    vUv1 = uv1;
    gl_Position = projectionMatrix * viewMatrix * world;
}
`;

export const fragmentBody = /* glsl */ `
in vec3 vRelPos;
in vec3 vWorldPos;
in vec3 vNormal;
in vec2 vUv0;
in vec2 vUv1;
uniform sampler2D uNormalMap;    // the model's normal map, UV set 0
uniform float uNormalScale;      // glTF normalTexture.scale
uniform sampler2D uDetailMap;
uniform float uDetailTiling;
uniform float uDetailStrength;
uniform bool uHasUv1;            // else UV set 1 is UV set 0 rotated by 30 degrees
uniform sampler2D uTriplanarMap;
uniform float uTriplanarScale;   // cycles per world unit
uniform float uTriplanarStrength;
uniform sampler2D uDecalMap;
uniform vec3 uDecalCenter;
uniform float uDecalHalfSize;    // world units
uniform float uNoiseFrequency;   // cycles per world unit
uniform float uNoiseAmplitude;   // world units
uniform int uLayerMask;          // bit i: layerNames[i]
uniform int uBlend;              // blendNames
uniform int uView;               // 0 shaded, 1 normal
uniform bool uDoubleSided;       // glTF doubleSided: mirror mode (section 2.10)
uniform vec3 uLightDir;
out vec4 outColor;

bool layerOn(int i) { return (uLayerMask & (1 << i)) != 0; }

// A texture coordinate (glTF: v down the image) in the convention of the
// library and of surfgrad's renderer: t = 1 - v (up the image, where a
// glTF normal map's green points), with its screen derivatives and the
// per-pixel frame of that set (listing 6).
struct UvSet {
    vec2 st;
    vec3 vT;
    vec3 vB;
};
UvSet uvSet(SgFrame f, vec2 uv) {
    UvSet s;
    s.st = vec2(uv.x, 1.0 - uv.y);
    sgGenBasisTB(f, s.st, dFdx(s.st), dFdy(s.st), s.vT, s.vB);
    return s;
}

// Tangent-space normal of an RGB normal-map texel, xy scaled by strength.
vec3 unpackScaled(vec4 texel, float strength) {
    vec2 xy = strength * (2.0 * texel.xy - 1.0);
    return vec3(xy, sqrt(max(1.0 - dot(xy, xy), 0.0)));
}

void main() {
    SgFrame f = sgPrologue(vNormal, dFdx(vRelPos), dFdy(vRelPos), gl_FrontFacing,
                           uDoubleSided ? SG_BFACE_MIRROR : SG_BFACE_NONE);
    vec3 grad = vec3(0.0);

    // Base (UV set 0) and detail (UV set 1): surface gradients, or a blend.
    UvSet set0 = uvSet(f, vUv0);
    vec2 uv1 = uHasUv1 ? vUv1 : mat2(0.8660254, 0.5, -0.5, 0.8660254) * vUv0;
    uv1 *= uDetailTiling;
    UvSet set1 = uvSet(f, uv1);
    vec4 baseTexel = texture(uNormalMap, vUv0);
    vec4 detailTexel = texture(uDetailMap, uv1);
    if (uBlend == 0) {
        if (layerOn(0)) {
            vec2 d = sgTspaceNormalToDeriv(2.0 * baseTexel.xy - 1.0, false);
            grad += sgSurfgradFromTBN(sgBumpScale(uNormalScale, d), set0.vT, set0.vB);
        }
        if (layerOn(1)) {
            vec2 d = sgTspaceNormalToDeriv(2.0 * detailTexel.xy - 1.0, false);
            grad += sgSurfgradFromTBN(sgBumpScale(uDetailStrength, d), set1.vT, set1.vB);
        }
    } else if (layerOn(0) || layerOn(1)) {
        vec3 a = layerOn(0) ? unpackScaled(baseTexel, uNormalScale) : vec3(0.0, 0.0, 1.0);
        vec3 b = layerOn(1) ? unpackScaled(detailTexel, uDetailStrength) : vec3(0.0, 0.0, 1.0);
        // The library's versions of the common blends (sg/normal_blends.glsl).
        vec3 n = uBlend == 1 ? sgNormalBlendWhiteout(a, b)
               : uBlend == 2 ? sgNormalBlendUdn(a, b) : sgNormalBlendRnm(a, b);
        // Both in UV set 0's frame: the blends' assumption.
        vec3 t = sgSafeNormalize(set0.vT, vec3(1.0, 0.0, 0.0));
        vec3 bt = sgSafeNormalize(set0.vB, vec3(0.0, 1.0, 0.0));
        grad += sgSurfgradFromPerturbedNormal(f, sgTangentNormalToFrame(f, t, bt, n));
    }

    // Triplanar (listings 13, 14): maps sampled with (z, y), (x, z), (x, y).
    if (layerOn(2)) {
        vec3 p = vWorldPos * uTriplanarScale;
        vec3 w = sgTriplanarWeights(f.nrmBase, 4.0);
        vec2 dX = sgTspaceNormalToDeriv(2.0 * texture(uTriplanarMap, vec2(p.z, p.y)).xy - 1.0, false);
        vec2 dY = sgTspaceNormalToDeriv(2.0 * texture(uTriplanarMap, vec2(p.x, p.z)).xy - 1.0, false);
        vec2 dZ = sgTspaceNormalToDeriv(2.0 * texture(uTriplanarMap, vec2(p.x, p.y)).xy - 1.0, false);
        grad += uTriplanarStrength * sgSurfgradFromTriplanar(f, w, dX, dY, dZ, false, true);
    }

    // A decal projected along -z onto the model (listing 15), faded at its edges.
    if (layerOn(3)) {
        vec3 local = (vWorldPos - uDecalCenter) / (2.0 * uDecalHalfSize);
        vec2 s = vec2(local.x, local.y) + 0.5;
        float fade = (1.0 - smoothstep(0.4, 0.5, max(abs(local.x), abs(local.y)))) *
                     step(0.0, f.nrmBase.z);
        if (fade > 0.0) {
            vec2 d = sgTspaceNormalToDeriv(2.0 * texture(uDecalMap, s).xy - 1.0, false);
            grad += fade * sgSurfgradFromDecal(f, d, vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), true);
        }
    }

    // Volume noise (section 2.7): fBm of world position, its exact gradient,
    // octaves faded by the pixel footprint.
    if (layerOn(4)) {
        float footprint = max(length(dFdx(vRelPos)), length(dFdy(vRelPos))) * uNoiseFrequency;
        vec4 n = sgNoiseOctaves(SG_NOISE_FBM, vWorldPos * uNoiseFrequency, 6, 2.0, 0.5, footprint);
        grad += sgSurfgradFromVolumeGradient(f, (uNoiseAmplitude * uNoiseFrequency) * vec3(n.y, n.z, n.w));
    }

    vec3 n = sgResolve(f, grad);
    if (uView == 1) {
        outColor = vec4(0.5 * n + 0.5, 1.0);
        return;
    }
    float diffuse = max(dot(n, uLightDir), 0.0);
    vec3 h = normalize(uLightDir - normalize(vRelPos));
    float spec = pow(max(dot(n, h), 0.0), 48.0);
    vec3 c = vec3(0.62, 0.6, 0.57) * (0.12 + 0.88 * diffuse) + 0.25 * spec;
    outColor = vec4(pow(c, vec3(1.0 / 2.2)), 1.0);
}
`;
