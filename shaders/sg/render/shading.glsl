// Shading of the renderer: lights, a small physically based BRDF (Lambert
// diffuse plus GGX / Smith-Schlick specular with Schlick Fresnel, F0 = 0.04),
// the output variables (AOVs) and the display transform. Not part of the
// bump framework: it only consumes the resolved normal (Mikkelsen 2019,
// listing 1), so any other BRDF can replace it.
#ifndef SG_RENDER_SHADING_GLSL
#define SG_RENDER_SHADING_GLSL

#include "sg/compat.glsl"

#define SG_PI 3.14159265358979f

#define SG_LIGHT_DIRECTIONAL 0
#define SG_LIGHT_POINT 1

// Output variables. Vectors are in world space; COLOR is linear radiance.
#define SG_AOV_COLOR 0
#define SG_AOV_NORMAL 1      // resolved (perturbed) unit normal
#define SG_AOV_SURFGRAD 2    // total surface gradient of the first group
#define SG_AOV_TANGENT 3     // vT of the first UV set (as used by its layers)
#define SG_AOV_BITANGENT 4   // vB of the first UV set
#define SG_AOV_BASE_NORMAL 5 // nrmBase of the prologue (after double-sided flip)
#define SG_AOV_UV 6          // first UV set (s, t)
#define SG_AOV_PRIM_ID 7     // 1 + primitive index + mesh base (exact float); 0 = background

// One light from two records:
//   r0 = (direction TOWARD the light (unit) or position relative to the
//         camera, type SG_LIGHT_*);   r1 = (linear colour * intensity, 0).
// Point lights fall off with 1 / distance^2.
SG_FN vec3 sgShadeLight(vec3 nrm, vec3 relPos, vec4 r0, vec4 r1, vec3 baseColor, float roughness) {
    vec3 toLight = vec3(r0.x, r0.y, r0.z);
    vec3 radiance = vec3(r1.x, r1.y, r1.z);
    if (int(floor(r0.w + 0.5f)) == SG_LIGHT_POINT) {
        vec3 d = toLight - relPos;
        float dist2 = max(dot(d, d), SG_FLT_EPSILON);
        radiance = radiance / dist2;
        toLight = d;
    }
    vec3 l = sgSafeNormalize(toLight, vec3(0.0f, 0.0f, 1.0f));
    // The camera sits at the origin of the relative frame.
    vec3 v = sgSafeNormalize(-relPos, nrm);
    vec3 h = sgSafeNormalize(l + v, nrm);
    float nDotL = max(dot(nrm, l), 0.0f);
    float nDotV = max(dot(nrm, v), 0.0f);
    float nDotH = max(dot(nrm, h), 0.0f);
    float vDotH = max(dot(v, h), 0.0f);
    float a = max(roughness * roughness, 0.002f);
    float a2 = a * a;
    float dd = nDotH * nDotH * (a2 - 1.0f) + 1.0f;
    float ggx = a2 / (SG_PI * dd * dd);
    float k = a * 0.5f;
    float vis = 1.0f / (4.0f * (nDotL * (1.0f - k) + k) * (nDotV * (1.0f - k) + k));
    float fresnel = 0.04f + 0.96f * pow(1.0f - vDotH, 5.0f);
    vec3 diffuse = baseColor * (1.0f / SG_PI);
    return (diffuse + sgVec3(ggx * vis * fresnel)) * radiance * nDotL;
}

// Hemispherical ambient: `ambient` from above (+y), half of it from below.
SG_FN vec3 sgShadeAmbient(vec3 nrm, vec3 ambient, vec3 baseColor) {
    return ambient * baseColor * (0.75f + 0.25f * nrm.y);
}

// The value written for output variable `aov` (SG_AOV_*). Vectors are
// written raw (signed); the image writer maps them for 8-bit formats.
SG_FN vec4 sgAovValue(int aov, vec3 color, vec3 nrm, vec3 surfGrad, vec3 tangent, vec3 bitangent,
                      vec3 baseNormal, vec2 uv, float primId) {
    if (aov == SG_AOV_NORMAL) return vec4(nrm, 1.0f);
    if (aov == SG_AOV_SURFGRAD) return vec4(surfGrad, 1.0f);
    if (aov == SG_AOV_TANGENT) return vec4(tangent, 1.0f);
    if (aov == SG_AOV_BITANGENT) return vec4(bitangent, 1.0f);
    if (aov == SG_AOV_BASE_NORMAL) return vec4(baseNormal, 1.0f);
    if (aov == SG_AOV_UV) return vec4(uv.x, uv.y, 0.0f, 1.0f);
    if (aov == SG_AOV_PRIM_ID) return vec4(primId, 0.0f, 0.0f, 1.0f);
    return vec4(color, 1.0f);
}

// Display transform for PNG output and the viewer: exposure, then the
// Reinhard-Jodie tone curve, then the sRGB transfer function. Input linear
// radiance, output display-referred [0,1].
SG_FN float sgSrgbEncode(float x) {
    float c = clamp(x, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * pow(c, 1.0f / 2.4f) - 0.055f;
}
SG_FN vec3 sgToneMap(vec3 radiance, float exposure) {
    vec3 c = max(radiance * exposure, sgVec3(0.0f));
    float lum = dot(c, vec3(0.2126f, 0.7152f, 0.0722f));
    vec3 byLum = c / (1.0f + lum);
    vec3 byChannel = c / (sgVec3(1.0f) + c);
    vec3 t = mix(byLum, byChannel, byChannel);
    return vec3(sgSrgbEncode(t.x), sgSrgbEncode(t.y), sgSrgbEncode(t.z));
}

#endif
