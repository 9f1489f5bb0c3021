// Layer kinds `parallax` (offset mapping with offset limiting) and `pom`
// (parallax occlusion mapping): layer_parallax.glsl, Mikkelsen 2019,
// section 2.6 (listing 10; listing 11's inverse without the inverse), section
// 3 and Fig. 3(c)-(d). The two
// kinds share their math, records and emission and differ in the search
// (one tap vs a marched ray), so both entries live in this unit.
//
// What a layer does, in order (GLSL statement and CPU call alike):
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
#include "layer_kind.h"

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

// The GLSL statement (pom: occlusion search) and its CPU twin below.
std::string glslStatement(const GlslLayerContext& c, bool occlusion) {
    const P& p = c.layer().params<P>();
    const std::string uv = c.uv(), t = c.tex(0), in = c.indent + "    ";
    std::string o = "{\n";
    o += in + "SgParallaxParams p = " + c.unpack(c.layer().kind->records[0]) + ";\n";
    o += in + "SgParallaxSearch search = sgParallaxSearch(frame, " + uv +
         ", -(vRelPos + surfOffset), p.scale, " + (occlusion ? "false" : "true") + ");\n";
    if (occlusion) {
        o += in + "float depth = sgParallaxOcclusionDepth(" + uv + ", search.st, " + t +
             ", p.channel, p.steps);\n";
    } else {
        o += in + "float depth = sgParallaxOffsetDepth(" + uv + ", " + t + ", p.channel);\n";
    }
    o += in + "surfOffset += sgParallaxSurfaceOffset(frame, " + uv + ", search, depth, p.scale, " +
         t + ", p.channel);\n";
    if (p.correctNormal) {
        o += in + "frame = sgFrameWithBase(frame, sgParallaxCorrectNormal(frame, -depth * "
                  "search.scr, sgParallaxUnitNormalDeriv(frame, vNormal, SG_DFDX(vNormal)), "
                  "sgParallaxUnitNormalDeriv(frame, vNormal, SG_DFDY(vNormal))));\n";
    }
    o += in + uv + ".st -= depth * search.st;\n";
    if (p.bump) {
        o += in + "surfGrad += sgLayerHeight(frame, " + uv + ", sgUnpackHeight(" + c.rec(0) +
             "), " + t + ");\n";
    }
    return o + c.indent + "}\n";
}

void cpuCall(const CpuLayerContext& c, CpuShadeState& s, bool occlusion) {
    const P& prm = c.layer().params<P>();
    const G::SgParallaxParams p = G::sgUnpackParallax(c.rec()[0]);
    G::SgUvFrame& uv = s.uv[size_t(c.layer().uvSet)];
    const G::sampler2D t = c.tex(0);
    const G::SgParallaxSearch search =
        G::sgParallaxSearch(s.frame, uv, -(c.in.relPos + s.surfOffset), p.scale, !occlusion);
    const float depth = occlusion
                            ? G::sgParallaxOcclusionDepth(uv, search.st, t, p.channel, p.steps)
                            : G::sgParallaxOffsetDepth(uv, t, p.channel);
    s.surfOffset += G::sgParallaxSurfaceOffset(s.frame, uv, search, depth, p.scale, t, p.channel);
    if (prm.correctNormal) {
        glm::vec3 n = G::sgParallaxCorrectNormal(
            s.frame, -depth * search.scr,
            G::sgParallaxUnitNormalDeriv(s.frame, c.in.normal, c.in.dNdx),
            G::sgParallaxUnitNormalDeriv(s.frame, c.in.normal, c.in.dNdy));
        s.frame = G::sgFrameWithBase(s.frame, n);
    }
    uv.st -= depth * search.st;
    if (prm.bump) s.surfGrad += G::sgLayerHeight(s.frame, uv, G::sgUnpackHeight(c.rec()[0]), t);
}

std::string glslParallax(const GlslLayerContext& c) {
    return glslStatement(c, false);
}
std::string glslPom(const GlslLayerContext& c) {
    return glslStatement(c, true);
}
void cpuParallax(const CpuLayerContext& c, CpuShadeState& s) {
    cpuCall(c, s, false);
}
void cpuPom(const CpuLayerContext& c, CpuShadeState& s) {
    cpuCall(c, s, true);
}

// The re-prologue on the virtual surface (section 3): surfPos = vRelPos +
// surfOffset, listing 17 there with the resolved normal, and the volume
// domains and position-projected layers (decal) moved there (world space
// camera-relative, as the prologue's).
std::string reprologue(const GlslLayerContext& c) {
    const std::string in = c.indent + "    ";
    std::string o = "{\n";
    o += in + "surfPos = vRelPos + surfOffset;\n";
    o += in + "vec3 dPdxV;\n" + in + "vec3 dPdyV;\n";
    o += in + "sgScreenDerivOfPos(dPdxV, dPdyV, surfPos, nrm, " + "sgScreenMatrixMat4(" +
         c.unpack(c.layer().kind->records[1]) + "), gl_FragCoord.x, gl_FragCoord.y);\n";
    o += in + "frame = sgReprologue(frame, nrm, dPdxV, dPdyV);\n";
    if (c.plan.usesWorldVolume) {
        o += in + "volWorld = sgVolumeSpace(frame, surfPos, mat3(1.0), mat3(1.0));\n";
    }
    if (c.plan.usesObjectVolume) {
        o += in + "volObject = sgVolumeSpace(frame, vObjPos + uModelInv3 * surfOffset, uModel3, "
                  "uModelInv3);\n";
    }
    return o + c.indent + "}\n";
}

void reprologueCpu(const CpuLayerContext& c, CpuShadeState& s, glm::vec3 nrm) {
    const glm::vec4* r = c.rec();
    glm::mat4 m = G::sgScreenMatrixMat4(G::sgUnpackScreenMatrix(r[1], r[2], r[3], r[4]));
    s.surfPos = c.in.relPos + s.surfOffset;
    glm::vec3 dPdxV, dPdyV;
    G::sgScreenDerivOfPos(dPdxV, dPdyV, s.surfPos, nrm, m, c.in.fragCoord.x, c.in.fragCoord.y);
    s.frame = G::sgReprologue(s.frame, nrm, dPdxV, dPdyV);
    if (c.plan.usesWorldVolume) {
        s.volWorld = G::sgVolumeSpace(s.frame, s.surfPos, glm::mat3(1.0f), glm::mat3(1.0f));
    }
    if (c.plan.usesObjectVolume) {
        s.volObject = G::sgVolumeSpace(s.frame, c.in.objPos + c.u.modelInv3 * s.surfOffset,
                                       c.u.model3, c.u.modelInv3);
    }
}

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
        .glsl = occlusion ? glslPom : glslParallax,
        .cpu = occlusion ? cpuPom : cpuParallax,
        .movesSurface = true,
        .reprologue = reprologue,
        .reprologueCpu = reprologueCpu,
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
