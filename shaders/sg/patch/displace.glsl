// Displacement of the tessellated limit surface along its normal by a
// height map (shared GLSL/C++ subset: the tessellation evaluation stage and
// the CPU tessellator, render/src/patch_tessellation.cpp).
//
// Mikkelsen 2019, section 2.5: displacement and a bump map of the same
// height field go together; the bump layer must take dPdx/dPdy of the
// surface BEFORE displacement (the evaluation stage writes the undisplaced
// position for the fragment stage's frame and the displaced one for
// rasterisation and lighting). The height map is read with textureLod at
// the level sgDisplaceLod gives, here: the map is filtered to about one
// texel per tessellated segment, so a coarse tessellation does not alias
// the map's detail into the geometry.
#ifndef SG_PATCH_DISPLACE_GLSL
#define SG_PATCH_DISPLACE_GLSL

#include "sg/compat.glsl"

// Mip level of the height map at a tessellated point: log2 of the texels
// one tessellated segment spans. The segment is the length the control
// stage aims at (sg/patch/tess_level.glsl: pixelsPerEdge pixels at the
// point's distance from the eye, pixelsPerEdge * distance / focalPx in the
// units of dPdu, dPdv), turned into UV length by the larger of the UV-per-
// length ratios along the two parameter directions (|dUV/du| / |dP/du|,
// the same for v), times the map's size in texels. Inputs are the same on
// both sides of a shared patch edge (all from the edge's owner patch), so
// the level is too. Degenerate inputs (zero derivatives, zero-area UVs,
// the eye on the surface, non-finite values) give level 0; at most 32.
SG_FN float sgDisplaceLod(vec3 dPdu, vec3 dPdv, vec2 dUVdu, vec2 dUVdv, float distance,
                          float focalPx, float pixelsPerEdge, float texSizePx) {
    float lu = length(dPdu), lv = length(dPdv);
    float ru = lu > 0.0f ? length(dUVdu) / lu : 0.0f;
    float rv = lv > 0.0f ? length(dUVdv) / lv : 0.0f;
    float segment = pixelsPerEdge * distance / max(focalPx, 1e-30f);
    float texels = texSizePx * max(ru, rv) * segment;
    if (!(texels > 1.0f)) return 0.0f; // also NaN
    return min(log2(texels), 32.0f);
}

// The displaced point: pos moved along the unit normal by scale * height +
// offset (object units; offset lets an unsigned image, e.g. a 16-bit PNG,
// hold signed heights). A non-finite distance (a non-finite height, scale
// or offset) leaves the point where it is.
SG_FN vec3 sgDisplacePoint(vec3 pos, vec3 unitNormal, float height, float scale, float offset) {
    float d = scale * height + offset;
    if (!(abs(d) <= 3.0e38f)) d = 0.0f;
    return pos + d * unitNormal;
}

#endif // SG_PATCH_DISPLACE_GLSL
