// Layer kinds `parallax` (offset mapping with offset limiting) and `pom`
// (parallax occlusion mapping): layer_parallax.glsl, Mikkelsen 2019,
// section 2.6 (listing 10; listing 11's inverse without the inverse), section
// 3 and Fig. 3(c)-(d). The two
// kinds share their math, records and emission and differ in the search
// (one tap vs a marched ray), so both entries live in this unit.
//
// What a layer does, in order (sgLayerParallax, called by both renderers):
//  1. the search (listing 10's projection of the view direction at the
//     pixel: texture, tangent-plane and screen steps per unit of depth) and
//     the depth of the hit (offset or POM);
//  2. the virtual surface: surfOffset += the view ray's tangential travel
//     to that depth plus the relief along the normal (what listing 11's
//     inverse would give, without inverting the UV Jacobian);
//  3. section 2.6's normal correction of nrmBase (option, dFdxFine of the
//     vertex normal, moved by the screen step to that depth);
//  4. uv<k>.st += correction, keeping the uncorrected derivatives (the mip
//     level of the coordinate before correction);
//  5. the relief's own surface gradient at the corrected coordinate
//     (option "bump": layer_height.glsl's listings 8 and 9).
// Groups after the layer re-prologue on the virtual surface with listing
// 17's analytic derivatives (frame.glsl, sgScreenDerivOfPos): the inverse
// of viewport * projection * view for the camera-relative space is packed
// in the layer's records 1..4.
#include "layer_emit.h"

namespace sg::render {

namespace {

namespace G = sg::glsl;

struct ParallaxParams {
    int channel = 0;     // the channel holding the relief height H in [0, 1]
    float scale = 0.02f; // world units of relief depth (H = 0 lies scale below the mesh)
    int steps = 16;      // pom: linear search steps
    bool correctNormal = true;
    bool bump = true;
};
using P = ParallaxParams;

// screen (x in [0, w], y in [0, h], depth in [0, 1]) -> camera-relative world.
glm::mat4 invViewProjScreen(const View& v) {
    glm::dmat4 vp(1.0);
    vp[0][0] = 0.5 * double(v.width);
    vp[1][1] = 0.5 * double(v.height);
    vp[2][2] = 0.5;
    vp[3] = glm::dvec4(0.5 * double(v.width), 0.5 * double(v.height), 0.5, 1.0);
    return glm::mat4(glm::inverse(vp * glm::dmat4(v.viewProjRel)));
}

// sgUnpackParallax(r0), layer_parallax.glsl: r0 = (scale, channel, steps, 0).
RecordLayout records() {
    using S = G::SgParallaxParams;
    return Records<S, 1>("SgParallaxParams", "sgUnpackParallax", G::sgUnpackParallax)
        .field("scale", &S::scale, "r0.x", [](const PackInput& in) { return in.params<P>().scale; })
        .field("channel", &S::channel, "r0.y",
               [](const PackInput& in) { return in.params<P>().channel; })
        .field("steps", &S::steps, "r0.z", [](const PackInput& in) { return in.params<P>().steps; })
        .done();
}

// sgUnpackScreenMatrix(r1, r2, r3, r4): column i = (ci xyz, ciw).
RecordLayout matrixRecords() {
    using S = G::SgScreenMatrix;
    auto col = [](int i) {
        return [i](const PackInput& in) {
            glm::vec4 c = invViewProjScreen(in.view)[i];
            return glm::vec3(c);
        };
    };
    auto colW = [](int i) {
        return [i](const PackInput& in) { return invViewProjScreen(in.view)[i].w; };
    };
    return Records<S, 4>("SgScreenMatrix", "sgUnpackScreenMatrix", G::sgUnpackScreenMatrix, 1)
        .field("c0", &S::c0, "r0.xyz", col(0))
        .field("c0w", &S::c0w, "r0.w", colW(0))
        .field("c1", &S::c1, "r1.xyz", col(1))
        .field("c1w", &S::c1w, "r1.w", colW(1))
        .field("c2", &S::c2, "r2.xyz", col(2))
        .field("c2w", &S::c2w, "r2.w", colW(2))
        .field("c3", &S::c3, "r3.xyz", col(3))
        .field("c3w", &S::c3w, "r3.w", colW(3))
        .done();
}

// sgLayerParallax(frame, uv, surfOffset, toEye, vertex normal and its
// derivatives, params, map, occlusion, normal correction, bump): the
// search and the options compile-time constants.
template <bool Occlusion>
constexpr LayerEmitter layerEmitter() {
    return emitter([](auto& b) {
        const P& p = b.layer().template params<P>();
        b.addSurfgrad(SG_LAYER_CALL(
            b, sgLayerParallax, b.frame(), b.uv(), b.surfOffset(), -(b.relPos() + b.surfOffset()),
            b.vertexNormal(), b.vertexNormalDx(), b.vertexNormalDy(), b.record(), b.tex(0),
            b.constant(Occlusion), b.constant(p.correctNormal), b.constant(p.bump)));
    });
}

// The re-prologue on the virtual surface (section 3): surfPos = vRelPos +
// surfOffset, listing 17 there with the resolved normal, and the volume
// domains and position-projected layers (decal) moved there (world space
// camera-relative, as the prologue's).
constexpr LayerEmitter kReprologue = emitter([](auto& b) {
    b.assign(b.surfPos(), b.relPos() + b.surfOffset());
    auto dPdx = b.declare("vec3", "dPdxV", glm::vec3(0.0f));
    auto dPdy = b.declare("vec3", "dPdyV", glm::vec3(0.0f));
    SG_LAYER_RUN(b, sgScreenDerivOfPos, dPdx, dPdy, b.surfPos(), b.resolvedNormal(),
                 SG_LAYER_CALL(b, sgScreenMatrixMat4, b.record(1)), b.fragCoordX(), b.fragCoordY());
    b.assign(b.frame(), SG_LAYER_CALL(b, sgReprologue, b.frame(), b.resolvedNormal(), dPdx, dPdy));
    if (b.plan().usesWorldVolume) {
        b.assign(b.vol(Space::World), SG_LAYER_CALL(b, sgVolumeSpace, b.frame(), b.surfPos(),
                                                    b.identity3(), b.identity3()));
    }
    if (b.plan().usesObjectVolume) {
        b.assign(b.vol(Space::Object), SG_LAYER_CALL(b, sgVolumeSpace, b.frame(),
                                                     b.objPos() + b.modelInv3() * b.surfOffset(),
                                                     b.model3(), b.modelInv3()));
    }
});

uint32_t mapChannels(const Layer& L, const char*& why) {
    why = "the relief height channel";
    return channelBit(L.params<P>().channel);
}

std::string signature(const Layer& L) {
    const P& p = L.params<P>();
    return std::string(p.correctNormal ? "n" : "") + (p.bump ? "b" : "");
}

std::vector<ParamSpec> params(bool occlusion) {
    std::vector<ParamSpec> v = {
        param::map("map", Wrap::Repeat, "the relief height map (H in [0, 1], 1 at the surface)"),
        param::uvSet(),
        param::channel("channel", &P::channel, "the channel holding the relief height"),
        param::slider(param::number("scale", &P::scale, {},
                                    "world units of relief depth (H = 0 lies scale below)"),
                      -0.1f, 0.1f, "%.4f"),
    };
    if (occlusion) {
        v.push_back(param::integer("steps", &P::steps, 1, 1024, "linear search steps of the ray"));
    }
    v.push_back(param::boolean("normal_correction", &P::correctNormal,
                               "section 2.6: move the base normal with the correction"));
    v.push_back(param::boolean("bump", &P::bump,
                               "add the relief's surface gradient at the corrected coordinate"));
    return v;
}

// Image-parity scenes. The corrected coordinate feeds the later layers of
// its UV set and keeps the uncorrected derivatives, so the mip level cannot
// jump at POM's occlusion edges. The comparison cannot check that: both
// renderers run sgLayerParallax (GLSL and its C++ build), so a mip level
// taken from the corrected coordinate would be taken by both and they would
// still agree. It shows agreement only; which coordinate the level comes
// from is fixed by sgLayerParallax (uv.st changes, uv.dSTdx and dSTdy do
// not) and no test compares it with an independent expectation. The
// post-resolve case re-prologues on the virtual surface with listing 17 and
// evaluates its noise there. POM's occlusion edges are discontinuities of
// the normal: where a ray grazes an edge, the half-pixel difference between
// exact and quad derivatives (they set the search vector) moves the hit to
// the other face, up to 180 degrees apart, on about 1% of the pixels of a
// deep relief (the plane's reference p99 bound: 10 degrees, measured 4.0).
std::vector<KindImageCase> imageCases(bool occlusion) {
    if (!occlusion) {
        return {
            {"parallax_offset_limited",
             R"({"type": "parallax", "scale": 0.03, "map": {"procedural": "bricks", "output": "height", "size": 256}},
                    {"type": "uv_normal", "uv_set": 1, "strength": 0.3, "map": {"procedural": "tiles", "size": 128}})"}};
    }
    return {
        {"pom_step_edges_plane",
         R"({"type": "pom", "scale": 0.08, "steps": 24, "map": {"procedural": "bricks", "output": "height", "size": 256}})",
         R"({"procedural": {"type": "plane", "segments": 4}})",
         R"(, "camera": {"position": [0.3, 0.8, 1.3], "target": [0, 0, 0]})", 10.0},
        {"pom_then_post_resolve_turbulence",
         R"({"type": "pom", "scale": 0.04, "steps": 16, "map": {"procedural": "tiles", "output": "height", "size": 128}},
            {"type": "post_resolve", "layers": [{"type": "noise", "noise": "turbulence", "amplitude": 0.004, "frequency": 12, "exponent": 2}]})"},
    };
}

LayerKind makeKind(bool occlusion) {
    return LayerKind{
        .name = occlusion ? "pom" : "parallax",
        .sigCode = occlusion ? "pom" : "plx",
        .doc = occlusion ? "parallax occlusion mapping on a height map (section 2.6, L10, L11)"
                         : "offset mapping with offset limiting (section 2.6, L10, L11)",
        .example = R"("map": {"procedural": "bricks", "output": "height", "size": 16})",
        .params = params(occlusion),
        .makeParams = [] { return std::any(P{}); },
        .readsUv = true,
        .textureSlots = 1,
        .mapChannels = mapChannels,
        .glslFile = "sg/render/layer_parallax.glsl",
        .signature = signature,
        .records = {records(), matrixRecords()},
        .emit = occlusion ? layerEmitter<true>() : layerEmitter<false>(),
        .movesSurface = true,
        .reprologue = kReprologue,
        .imageCases = imageCases(occlusion),
    };
}

} // namespace

const LayerKind& parallaxLayerKind() {
    static const LayerKind kind = makeKind(false);
    return kind;
}

const LayerKind& pomLayerKind() {
    static const LayerKind kind = makeKind(true);
    return kind;
}

} // namespace sg::render
