// The table of evaluation entry points: JSON keys <-> record slots of
// shaders/sg/eval/kernels.glsl. Keep each entry's slots in step with the
// kernel of the same id (the parity and CLI tests exercise every entry).
#include "surfgrad/eval_kernels.h"

#include "surfgrad/bump.h"
#include "surfgrad/shader_files.h"

namespace sg::glsl {
#include "sg/eval/kernels.glsl"
}

namespace sg::eval {

int inStride() {
    return SG_EVAL_IN;
}
int outStride() {
    return SG_EVAL_OUT;
}

namespace {
Field f(const char* key, int width, int slot, const char* doc) {
    return {key, width, slot, FieldKind::Float, false, 0.0f, doc};
}
Field fopt(const char* key, int width, int slot, float def, const char* doc) {
    return {key, width, slot, FieldKind::Float, true, def, doc};
}
Field b(const char* key, int slot, bool optional, bool def, const char* doc) {
    return {key, 1, slot, FieldKind::Bool, optional, def ? 1.0f : 0.0f, doc};
}
Field iopt(const char* key, int slot, int def, const char* doc) {
    return {key, 1, slot, FieldKind::Int, true, float(def), doc};
}

std::vector<Entry> makeEntries() {
    const char* nDoc = "base normal (unit length; normalized if not)";
    const char* dpdxDoc = "d(position)/d(screen x), position units per pixel";
    const char* dpdyDoc = "d(position)/d(screen y), position units per pixel";
    const char* sgDoc = "surface gradient (tangent to the surface)";
    std::vector<Field> frameOut = {f("nrm_base", 3, 0, "base normal after the double-sided rule"),
                                   f("sigma_x", 3, 3, "dpdx projected onto the tangent plane"),
                                   f("sigma_y", 3, 6, "dpdy projected onto the tangent plane"),
                                   f("flip_sign", 1, 9, "orientation sign of (dpdx, dpdy, n)"),
                                   f("resolve_sign", 1, 10, "-1 for back faces in flip mode")};
    return {
        {"resolve",
         SG_K_RESOLVE,
         "normalize(n - resolve_sign * sg) (L1)",
         {f("n", 3, 0, nDoc), f("sg", 3, 3, sgDoc),
          fopt("resolve_sign", 1, 6, 1.0f, "+1, or -1 for back faces in flip mode")},
         {f("n", 3, 0, "perturbed unit normal")}},
        {"tspace-to-deriv",
         SG_K_TSPACE_TO_DERIV,
         "tangent-space normal xy to derivative, |d| <= 128 clamp (L4)",
         {f("m", 2, 0, "normal-map xy channels in [-1, 1]"),
          b("flip_v", 2, true, false, "green channel points down for a lower-left origin")},
         {f("d", 2, 0, "derivative dH/d(s, t) w.r.t. +s, +t")}},
        {"tbn",
         SG_K_TBN,
         "d.x * t + d.y * b (L5)",
         {f("d", 2, 0, "derivative"), f("t", 3, 2, "tangent"), f("b", 3, 5, "bitangent")},
         {f("sg", 3, 0, sgDoc)}},
        {"basis",
         SG_K_BASIS,
         "procedural tangent/bitangent from UV derivatives (L6, L16)",
         {f("n", 3, 0, nDoc), f("dpdx", 3, 3, dpdxDoc), f("dpdy", 3, 6, dpdyDoc),
          f("dstdx", 2, 9, "d(uv)/d(screen x)"), f("dstdy", 2, 11, "d(uv)/d(screen y)")},
         {f("t", 3, 0, "unit tangent (direction of +s)"),
          f("b", 3, 3, "unit bitangent (direction of +t)")}},
        {"perturbed",
         SG_K_PERTURBED,
         "surface gradient of a perturbed normal v (L7)",
         {f("n", 3, 0, nDoc), f("v", 3, 3, "perturbed normal, same space as n, any length")},
         {f("sg", 3, 0, sgDoc)}},
        {"scale-dependent",
         SG_K_SCALE_DEPENDENT,
         "scale-dependent bump (L8)",
         {f("n", 3, 0, nDoc), f("dpdx", 3, 3, dpdxDoc), f("dpdy", 3, 6, dpdyDoc),
          f("deriv", 2, 9, "dH/d(u, v), height units per texel"),
          f("dstdx", 2, 11, "d(uv)/d(screen x), normalized uv"),
          f("dstdy", 2, 13, "d(uv)/d(screen y), normalized uv"),
          f("dim", 2, 15, "texture size in texels (w, h)")},
         {f("sg", 3, 0, sgDoc)}},
        {"volume",
         SG_K_VOLUME,
         "volume gradient to surface gradient (L12)",
         {f("n", 3, 0, nDoc), f("grad", 3, 3, "volume gradient of the height")},
         {f("sg", 3, 0, sgDoc)}},
        {"triplanar-weights",
         SG_K_TRIPLANAR_WEIGHTS,
         "triplanar blend weights (L14)",
         {f("n", 3, 0, "normal"), fopt("k", 1, 3, 3.0f, "sharpness exponent, > 0")},
         {f("w", 3, 0, "weights, sum 1")}},
        {"triplanar",
         SG_K_TRIPLANAR,
         "triplanar surface gradient (L13 with L14 weights)",
         {f("n", 3, 0, nDoc), fopt("k", 1, 3, 3.0f, "sharpness exponent, > 0"),
          f("dx", 2, 4, "derivative of the x-plane map, sampled at (z, y)"),
          f("dy", 2, 6, "derivative of the y-plane map, sampled at (x, z)"),
          f("dz", 2, 8, "derivative of the z-plane map, sampled at (x, y)"),
          b("right_handed", 10, true, false, "right-handed frame: (-z, y), (x, -z)"),
          b("upper_left", 11, true, false, "texture origin upper-left")},
         {f("sg", 3, 0, sgDoc)}},
        {"decal",
         SG_K_DECAL,
         "decal projector surface gradient (L15)",
         {f("n", 3, 0, nDoc), f("d", 2, 3, "derivative of the decal map"),
          f("axis_x", 3, 5, "projector x axis (unit)"),
          f("axis_y", 3, 8, "projector y axis (unit)"),
          b("upper_left", 11, true, false, "texture origin upper-left")},
         {f("sg", 3, 0, sgDoc)}},
        {"prologue",
         SG_K_PROLOGUE,
         "pixel-shader prologue (L16, section 2.10)",
         {f("n", 3, 0, "interpolated vertex normal (any length)"), f("dpdx", 3, 3, dpdxDoc),
          f("dpdy", 3, 6, dpdyDoc), b("front_facing", 9, true, true, "gl_FrontFacing"),
          iopt("bface_mode", 10, 0, "0 none, 1 mirror, 2 flip")},
         frameOut},
        {"mikkts-basis",
         SG_K_MIKKTS_BASIS,
         "mikktspace-compliant basis scaled by 1/|n| (section 2.2, L16)",
         {f("n", 3, 0, "interpolated vertex normal, unnormalized"),
          f("tangent", 4, 3, "interpolated tangent xyz, sign w")},
         {f("t", 3, 0, "tangent * renorm"), f("b", 3, 3, "sign(w) cross(n, t) * renorm")}},
        {"screen-deriv-of-pos",
         SG_K_SCREEN_DERIV_OF_POS,
         "analytic dPdx/dPdy (L17)",
         {f("pos", 3, 0, "surface position"), f("n", 3, 3, "surface normal"),
          f("inv_view_proj_scr", 16, 6, "screen -> position space, column-major mat4"),
          f("x", 1, 22, "window x (pixel centre at .5)"),
          f("y", 1, 23, "window y (pixel centre at .5)")},
         {f("dpdx", 3, 0, dpdxDoc), f("dpdy", 3, 3, dpdyDoc)}},
        {"parallax-project",
         SG_K_PARALLAX_PROJECT,
         "direction to texture space (L10)",
         {f("n", 3, 0, nDoc), f("dpdx", 3, 3, dpdxDoc), f("dpdy", 3, 6, dpdyDoc),
          f("dir", 3, 9, "unit direction"), f("dstdx", 2, 12, "d(uv)/d(screen x)"),
          f("dstdy", 2, 14, "d(uv)/d(screen y)"),
          fopt("bump_scale", 1, 16, 1.0f, "displacement per unit height"),
          b("skip_proj", 17, true, false, "basic parallax (no projection)")},
         {f("offset", 2, 0, "texture-space offset, normalized uv")}},
        {"texoffs-to-surface",
         SG_K_TEXOFFS_TO_SURFACE,
         "texture offset to surface (L11)",
         {f("n", 3, 0, nDoc), f("dpdx", 3, 3, dpdxDoc), f("dpdy", 3, 6, dpdyDoc),
          f("dstdx", 2, 9, "d(uv)/d(screen x)"), f("dstdy", 2, 11, "d(uv)/d(screen y)"),
          f("offset", 2, 13, "texture-space offset, normalized uv")},
         {f("p", 3, 0, "offset in the tangent plane, position units")}},
        {"screen-deriv-surfgrad",
         SG_K_SCREEN_DERIV_SURFGRAD,
         "surface gradient from screen-space height derivatives (L8, isDerivScreenSpace)",
         {f("n", 3, 0, nDoc), f("dpdx", 3, 3, dpdxDoc), f("dpdy", 3, 6, dpdyDoc),
          f("dhdxy", 2, 9, "(dH/dx, dH/dy) per pixel")},
         {f("sg", 3, 0, sgDoc)}},
        {"deriv-to-tspace",
         SG_K_DERIV_TO_TSPACE,
         "derivative to unit tangent-space normal",
         {f("d", 2, 0, "derivative"), b("flip_v", 2, true, false, "see tspace-to-deriv")},
         {f("m", 3, 0, "unit tangent-space normal")}},
        {"reprologue",
         SG_K_REPROLOGUE,
         "post-resolve frame (sections 2.11, 3)",
         {f("n", 3, 0, "interpolated vertex normal"), f("dpdx", 3, 3, dpdxDoc),
          f("dpdy", 3, 6, dpdyDoc), b("front_facing", 9, true, true, "gl_FrontFacing"),
          iopt("bface_mode", 10, 0, "0 none, 1 mirror, 2 flip"),
          f("resolved", 3, 11, "normal after the first resolve")},
         frameOut},
        {"bump-scale",
         SG_K_BUMP_SCALE,
         "scale * sg (L2)",
         {f("scale", 1, 0, "bump scale"), f("sg", 3, 1, sgDoc)},
         {f("sg", 3, 0, sgDoc)}},
        {"deriv-scale",
         SG_K_DERIV_SCALE,
         "derivative of alpha * h (L3; Loviscach scaling)",
         {f("d", 2, 0, "derivative"), f("alpha", 1, 2, "height scale")},
         {f("d", 2, 0, "derivative")}},
        {"deriv-blend",
         SG_K_DERIV_BLEND,
         "sum of w_i * d_i over up to 4 layers (Loviscach)",
         {iopt("count", 0, 2, "number of layers, 0..4"), fopt("d0", 2, 1, 0.0f, "layer 0"),
          fopt("d1", 2, 3, 0.0f, "layer 1"), fopt("d2", 2, 5, 0.0f, "layer 2"),
          fopt("d3", 2, 7, 0.0f, "layer 3"), fopt("w0", 1, 9, 0.0f, "weight 0"),
          fopt("w1", 1, 10, 0.0f, "weight 1"), fopt("w2", 1, 11, 0.0f, "weight 2"),
          fopt("w3", 1, 12, 0.0f, "weight 3")},
         {f("d", 2, 0, "derivative")}},
        {"deriv-modulate",
         SG_K_DERIV_MODULATE,
         "derivative of h1 * h2 (Loviscach)",
         {f("d1", 2, 0, "derivative of h1"), f("h1", 1, 2, "height h1"),
          f("d2", 2, 3, "derivative of h2"), f("h2", 1, 5, "height h2")},
         {f("d", 2, 0, "derivative")}},
        {"deriv-curve",
         SG_K_DERIV_CURVE,
         "derivative of f(h), f'(h) = 1 / (1 + P (h - H)^2) (Loviscach)",
         {f("d", 2, 0, "derivative of h"), f("h", 1, 2, "height"),
          f("p", 1, 3, "boost width P >= 0"), f("hc", 1, 4, "boost centre H")},
         {f("d", 2, 0, "derivative of f(h)"), f("f", 1, 2, "f(h), f(H) = 0")}},
        {"deriv-deform",
         SG_K_DERIV_DEFORM,
         "derivative of h(s(u, v), t(u, v)) (Loviscach)",
         {f("d", 2, 0, "derivative sampled at (s, t)"),
          f("ds_du_dt_du", 2, 2, "Jacobian column (ds/du, dt/du)"),
          f("ds_dv_dt_dv", 2, 4, "Jacobian column (ds/dv, dt/dv)")},
         {f("d", 2, 0, "derivative w.r.t. (u, v)")}},
        {"deriv-sine-warp",
         SG_K_DERIV_SINE_WARP,
         "deform with s = u, t = v + A sin(B u) (Loviscach example)",
         {f("d", 2, 0, "derivative sampled at (s, t)"), f("u", 1, 2, "u"),
          f("a", 1, 3, "amplitude A"), f("b", 1, 4, "frequency B")},
         {f("d", 2, 0, "derivative w.r.t. (u, v)")}},
        {"decal-volume",
         SG_K_DECAL_VOLUME,
         "volume gradient of one decal (section 2.9)",
         {f("d", 2, 0, "derivative of the decal map"), f("axis_x", 3, 2, "projector x axis"),
          f("axis_y", 3, 5, "projector y axis"),
          b("upper_left", 8, true, false, "texture origin upper-left")},
         {f("grad", 3, 0, "volume gradient")}},
        {"height-3tap",
         SG_K_HEIGHT_3TAP,
         "3-tap screen-space height derivative (L9)",
         {f("hll", 1, 0, "H(st)"), f("hlr", 1, 1, "H(st + dstdx)"),
          f("hul", 1, 2, "H(st + dstdy)")},
         {f("dhdxy", 2, 0, "(dH/dx, dH/dy)")}},
        {"bounded-scale",
         SG_K_BOUNDED_SCALE,
         "v * |f.x f.y f.z f.w| kept within SG_BIG along v (overflow-free scaling, compat.glsl)",
         {f("v", 3, 0, "vector"), f("f", 4, 3, "four factors (absolute values are used)")},
         {f("v", 3, 0, "scaled vector, components within 1e18")}},
    };
}
} // namespace

const std::vector<Entry>& entries() {
    static const std::vector<Entry> table = makeEntries();
    return table;
}

const Entry* findEntry(std::string_view name) {
    for (const auto& e : entries()) {
        if (e.name == name) return &e;
    }
    return nullptr;
}

void evalCpu(const Entry& e, const float* in, float* out) {
    glsl::SgEvalIn x;
    for (int i = 0; i < SG_EVAL_IN; ++i) x.v[i] = in[i];
    glsl::SgEvalOut y = glsl::sgEvalKernel(e.kernel, x);
    for (int i = 0; i < SG_EVAL_OUT; ++i) out[i] = y.v[i];
}

std::string evalGpuBody() {
    return "#include \"sg/eval/eval.comp.glsl\"\n";
}

std::vector<std::string> evalGpuDefines(const Entry& e) {
    return {"SG_EVAL_KERNEL " + std::to_string(e.kernel)};
}

} // namespace sg::eval
