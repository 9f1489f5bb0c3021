// Shared inputs of the renderer's bump layers: the per-UV-set tangent frame,
// the volume domain of projected layers (triplanar, decals, noise), texture
// decoding and the packing of layer parameters into vec4 records.
//
// Mikkelsen, "Surface Gradient Based Bump Mapping Framework" (2019):
// listing 6 (procedural TB basis per UV set), section 2.2 / listing 16
// (mikktspace-compliant vertex basis), listing 4 (tangent-space normal to
// derivative), section 2.7 (volume bump maps).
//
// Written in the shared GLSL/C++ subset (sg/compat.glsl). Textures are read
// only with textureGrad / textureLod / texelFetch / textureSize and explicit
// screen derivatives, which the C++ build emulates
// (render/include/surfgrad/render/glsl_texture.h), so the CPU reference
// renderer samples exactly like the GPU does, up to filtering precision.
//
// Texture convention (all layers): texture coordinate (0,0) is the LOWER-left
// corner of the image and t points up (images are flipped on load); a
// derivative is dH/ds, dH/dt w.r.t. the positive s and t axes.
#ifndef SG_RENDER_COMMON_GLSL
#define SG_RENDER_COMMON_GLSL

#include "sg/surfgrad.glsl"

// Normal-map encodings (the `encoding` field of the scene schema):
//   RGB   - xyz in [0,1] as 0.5 * n + 0.5 (8-bit PNG normal maps);
//   RG    - only xy stored as 0.5 * n + 0.5 (BC5-style two-channel maps);
//   AG    - x in alpha, y in green (DXT5nm);
//   FLOAT - xyz stored signed as is (floating-point EXR maps).
// The derivative of listing 4 needs only x and y, so z is never read.
#define SG_ENC_RGB 0
#define SG_ENC_RG 1
#define SG_ENC_AG 2
#define SG_ENC_FLOAT 3

// A texture coordinate set at the pixel, with its screen derivatives and the
// basis TBN-style layers use (listing 5):
//   pixel frames  - vT, vB orthogonal, generated per pixel (listing 6), of
//                   the chart's weight in length (1 on ordinary charts);
//   vertex frames - vT, vB the mikktspace basis scaled by 1/|n| (section 2.2,
//                   listing 16), from interpolated vertex (or limit) tangents.
struct SgUvFrame {
    vec2 st;    // normalized texture coordinate, t up
    vec2 dSTdx; // d(st)/d(screen x), st units per pixel
    vec2 dSTdy; // d(st)/d(screen y), st units per pixel
    vec3 vT;    // d(position)/ds direction (frame space)
    vec3 vB;    // d(position)/dt direction (frame space)
};

// Per-pixel basis for any texture coordinate set (listing 6). vT and vB
// carry the chart's weight (sgGenBasisTB): a zero-area or collapsed UV
// Jacobian gives zero vectors, and TBN-style layers fade out with them.
SG_FN SgUvFrame sgUvFramePixel(SgFrame f, vec2 st, vec2 dSTdx, vec2 dSTdy) {
    SgUvFrame u;
    u.st = st;
    u.dSTdx = dSTdx;
    u.dSTdy = dSTdy;
    vec3 t;
    vec3 b;
    sgGenBasisTB(f, st, dSTdx, dSTdy, t, b);
    u.vT = t;
    u.vB = b;
    return u;
}

// Vertex-tangent basis (mikktspace or limit tangents) for the UV set the
// tangents were generated for: vtxNormal/vtxTangent are the interpolated,
// UNNORMALIZED vertex normal and tangent (xyz, sign in w), in frame space.
// As in the paper, the basis does not change on back faces (section 2.10).
SG_FN SgUvFrame sgUvFrameVertex(vec2 st, vec2 dSTdx, vec2 dSTdy, vec3 vtxNormal, vec4 vtxTangent) {
    SgUvFrame u;
    u.st = st;
    u.dSTdx = dSTdx;
    u.dSTdy = dSTdy;
    vec3 t;
    vec3 b;
    sgMikktsBasis(vtxNormal, vtxTangent, t, b);
    u.vT = t;
    u.vB = b;
    return u;
}

// The domain of a volume layer (triplanar, decal, noise): positions and
// screen derivatives in the layer's space (object or world), and the linear
// maps between that space and the frame's (world, relative to the camera).
// The position is relative to a reference point x0 of the domain: object
// space the object position (x0 = 0), world space the camera-relative
// position vRelPos (x0 = the camera, which binary32 cannot place precisely
// far from the origin while vRelPos stays small there). Layers add their
// pattern's value at x0, packed per layer in binary64 and reduced by the
// pattern's period or lattice (layer_triplanar.glsl's texShift,
// layer_noise.glsl's originCell and originFrac), so patterns stay put in
// the domain as the camera moves.
//   gradToFrame   - maps a domain-space GRADIENT to frame space: the inverse
//                   transpose of the domain-to-world linear map (identity for
//                   world space);
//   normalToDomain - maps a frame-space normal to the domain (the transpose
//                   of the domain-to-world linear map); result unnormalized.
struct SgVolumeSpace {
    vec3 pos;  // position in the domain minus the reference point x0 (above)
    vec3 dPdx; // d(pos)/d(screen x)
    vec3 dPdy; // d(pos)/d(screen y)
    mat3 gradToFrame;
    mat3 normalToDomain;
};

// worldFromDomain is the domain-to-world linear map (the model matrix's
// 3x3 part for object space, identity for world space) and domainFromWorld
// its inverse; dPdx/dPdy come from the frame. H_world(p) = H_domain(D p)
// gives grad_world = D^T grad_domain, and normals map by the inverse
// transpose, n_domain ~ (worldFromDomain)^T n_world.
SG_FN SgVolumeSpace sgVolumeSpace(SgFrame f, vec3 domainPos, mat3 worldFromDomain,
                                  mat3 domainFromWorld) {
    SgVolumeSpace v;
    v.pos = domainPos;
    v.dPdx = domainFromWorld * f.dPdx;
    v.dPdy = domainFromWorld * f.dPdy;
    v.gradToFrame = transpose(domainFromWorld);
    v.normalToDomain = transpose(worldFromDomain);
    return v;
}

// The same with the domain position's own screen derivatives (dDomdx,
// dDomdy: dFdxFine of the object position, for object space). For a
// transform that shrinks an axis (an instance flattened to 1e-6), mapping
// the frame's dPdx to the domain multiplies the rounding of the
// camera-relative position (an ulp of its distance from the camera) by the
// inverse scale, and the footprint, the texture LOD and the noise's octave
// fade follow that noise; the object position's own derivatives carry only
// their own rounding.
SG_FN SgVolumeSpace sgVolumeSpaceDeriv(vec3 domainPos, vec3 dDomdx, vec3 dDomdy,
                                       mat3 worldFromDomain, mat3 domainFromWorld) {
    SgVolumeSpace v;
    v.pos = domainPos;
    v.dPdx = dDomdx;
    v.dPdy = dDomdy;
    v.gradToFrame = transpose(domainFromWorld);
    v.normalToDomain = transpose(worldFromDomain);
    return v;
}

// Pixel footprint in the domain: the longer screen derivative (domain units
// per pixel), used to fade out procedural detail finer than two pixels.
SG_FN float sgVolumeFootprint(SgVolumeSpace v) { return max(length(v.dPdx), length(v.dPdy)); }

// Tangent-space xy in [-1,1] from a texel in the given encoding.
SG_FN vec2 sgDecodeNormalXY(vec4 texel, int encoding) {
    if (encoding == SG_ENC_FLOAT) return vec2(texel.x, texel.y);
    if (encoding == SG_ENC_AG) return vec2(2.0f * texel.w - 1.0f, 2.0f * texel.y - 1.0f);
    return vec2(2.0f * texel.x - 1.0f, 2.0f * texel.y - 1.0f);
}

// Full vector of an object/world-space normal map (not normalized).
SG_FN vec3 sgDecodeNormalXYZ(vec4 texel, int encoding) {
    if (encoding == SG_ENC_FLOAT) return vec3(texel.x, texel.y, texel.z);
    return vec3(2.0f * texel.x - 1.0f, 2.0f * texel.y - 1.0f, 2.0f * texel.z - 1.0f);
}

// One channel of a texel (0 r, 1 g, 2 b, 3 a).
SG_FN float sgTexelChannel(vec4 texel, int channel) {
    if (channel == 1) return texel.y;
    if (channel == 2) return texel.z;
    if (channel == 3) return texel.w;
    return texel.x;
}

// Listing 4 on a filtered texel: derivative w.r.t. +s, +t.
SG_FN vec2 sgSampleTspaceDeriv(sampler2D tex, vec2 st, vec2 dSTdx, vec2 dSTdy, int encoding,
                               bool flipV) {
    vec4 texel = textureGrad(tex, st, dSTdx, dSTdy);
    return sgTspaceNormalToDeriv(sgDecodeNormalXY(texel, encoding), flipV);
}

// Layer parameters travel in uniform vec4 records (GPU) or the same records
// in memory (CPU); each layer kind's unpack function reads its records.
// Integers and booleans are stored as small exact floats.
SG_FN int sgRecInt(float x) { return int(floor(x + 0.5f)); }
SG_FN bool sgRecBool(float x) { return x > 0.5f; }
SG_FN vec3 sgRecVec3(vec4 r) { return vec3(r.x, r.y, r.z); }

#endif
