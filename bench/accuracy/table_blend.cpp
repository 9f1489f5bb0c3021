// Table 3, blend method (docs/accuracy-cost.md): two tangent-space normal
// maps of known height layers on one UV set, blended by each method of
// sg/normal_blends.glsl on the GPU; error against the normal of the summed heights
// (Mikkelsen 2019 eq. 2-3; Loviscach 2008 "Adding"), in double. Three slope
// regimes (each layer's steepest slope 0.25, 1 and 3, i.e. 14, 45 and 72
// degrees). Order dependence: the largest angle between blend(a, b) and
// blend(b, a). Cost: a 512^2 pass per method, either one blend per pixel
// (two float texel fetches, the blend, the rotation into a TBN frame given by
// uniforms, one write) or 16 blends per pixel (ALU bound), ratio to the
// surface-gradient method.
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "blend.h"
#include "tables.h"

namespace study {

namespace {

struct Layer {
    // h = amp * sum_k w_k sin(2 pi (fx_k x + fy_k y) + phase_k): periodic on [0,1]^2.
    double amp = 1.0;
    double w[2], fx[2], fy[2], ph[2];
    glm::dvec2 grad(double x, double y) const {
        glm::dvec2 g(0.0);
        for (int k = 0; k < 2; ++k) {
            const double c =
                w[k] * 2.0 * M_PI * std::cos(2.0 * M_PI * (fx[k] * x + fy[k] * y) + ph[k]);
            g += c * glm::dvec2(fx[k], fy[k]);
        }
        return amp * g;
    }
};

glm::dvec3 normalOfGrad(const glm::dvec2& g) {
    return glm::normalize(glm::dvec3(-g.x, -g.y, 1.0));
}

const char* kFragment = R"(
uniform sampler2D uA;
uniform sampler2D uB;
uniform vec3 uT;
uniform vec3 uB3;
uniform vec3 uN;
uniform vec2 uRot; // (cos, sin) of the detail's rotation step
layout(location = 0) out vec4 oColor;
vec3 blendOne(SgFrame f, vec3 a, vec3 b) {
#if METHOD == SG_NORMAL_BLEND_SURFGRAD
    return sgNormalBlendSurfgrad(f, uT, uB3, a, b);
#elif METHOD == SG_NORMAL_BLEND_LINEAR
    return sgTangentNormalToFrame(f, uT, uB3, sgNormalBlendLinear(a, b));
#elif METHOD == SG_NORMAL_BLEND_OVERLAY
    return sgTangentNormalToFrame(f, uT, uB3, sgNormalBlendOverlay(a, b));
#elif METHOD == SG_NORMAL_BLEND_UDN
    return sgTangentNormalToFrame(f, uT, uB3, sgNormalBlendUdn(a, b));
#elif METHOD == SG_NORMAL_BLEND_WHITEOUT
    return sgTangentNormalToFrame(f, uT, uB3, sgNormalBlendWhiteout(a, b));
#else
    return sgTangentNormalToFrame(f, uT, uB3, sgNormalBlendRnm(a, b));
#endif
}
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 a = texelFetch(uA, p, 0).xyz;
    vec3 b = texelFetch(uB, p, 0).xyz;
    SgFrame f;
    f.nrmBase = uN;
    f.resolveSign = 1.0;
#ifdef LOOP
    // 16 blends of a rotated detail: ALU-bound, same overhead for every method.
    vec3 acc = vec3(0.0);
    vec3 bi = b;
    for (int i = 0; i < 16; ++i) {
        acc += blendOne(f, a, bi);
        bi = vec3(bi.x * uRot.x - bi.y * uRot.y, bi.x * uRot.y + bi.y * uRot.x, bi.z);
    }
    oColor = vec4(acc, 1.0);
#else
    oColor = vec4(blendOne(f, a, b), 1.0);
#endif
}
)";

const char* kMethodNames[SG_NORMAL_BLEND_COUNT] = {
    "surface gradient (sum)", "linear", "overlay", "UDN", "whiteout", "RNM"};

} // namespace

void tableBlend(const Options& o) {
    const FullscreenTriangle fullscreen;
    const int w = o.quick ? 128 : 512;
    Layer base{1.0, {1.0, 0.6}, {2, 3}, {1, -4}, {0.0, 1.3}};
    Layer detail{1.0, {1.0, 0.7}, {13, -9}, {7, 16}, {0.4, 2.1}};
    // Steepest slope of each unit-amplitude layer on the grid, to scale them.
    double maxBase = 0, maxDetail = 0;
    auto at = [&](int i) { return (i + 0.5) / w; };
    for (int j = 0; j < w; ++j) {
        for (int i = 0; i < w; ++i) {
            maxBase = std::max(maxBase, glm::length(base.grad(at(i), at(j))));
            maxDetail = std::max(maxDetail, glm::length(detail.grad(at(i), at(j))));
        }
    }
    const double slopes[3] = {0.25, 1.0, 3.0};

    std::vector<sg::gl::Program> one, loop;
    const std::string fs = std::string("#include \"sg/normal_blends.glsl\"\n") + kFragment;
    for (int m = 0; m < SG_NORMAL_BLEND_COUNT; ++m) {
        const std::string def = "METHOD " + std::to_string(m);
        one.push_back(makeProgram(fullscreenVertexShader(), fs, "blend", {def}));
        loop.push_back(makeProgram(fullscreenVertexShader(), fs, "blend_loop", {def, "LOOP"}));
    }
    // Identity frame for accuracy; a rotated orthonormal frame for timing
    // (uniforms either way, so the compiler cannot fold the frame away).
    auto setUniforms = [&](const sg::gl::Program& p, bool identity) {
        glUseProgram(p.id());
        const float c = identity ? 1.0f : std::cos(0.3f), s = identity ? 0.0f : std::sin(0.3f);
        const glm::vec3 t(c, s, 0), b(-s, c, 0), n(0, 0, 1);
        glUniform3fv(p.uniform("uT"), 1, &t[0]);
        glUniform3fv(p.uniform("uB3"), 1, &b[0]);
        glUniform3fv(p.uniform("uN"), 1, &n[0]);
        glUniform1i(p.uniform("uA"), 0);
        glUniform1i(p.uniform("uB"), 1);
        if (p.uniform("uRot") >= 0)
            glUniform2f(p.uniform("uRot"), std::cos(0.39f), std::sin(0.39f));
    };

    // errors[method][regime], order dependence (steep) per method.
    std::vector<std::vector<ErrorStats>> stats(SG_NORMAL_BLEND_COUNT, std::vector<ErrorStats>(3));
    std::vector<double> orderMax(SG_NORMAL_BLEND_COUNT, 0.0);
    Target target(w, w, 1);
    glDisable(GL_DEPTH_TEST);
    for (int r = 0; r < 3; ++r) {
        base.amp = slopes[r] / maxBase;
        detail.amp = slopes[r] / maxDetail;
        std::vector<float> ta(size_t(w) * size_t(w) * 4), tb(ta.size());
        std::vector<glm::dvec3> truth(size_t(w) * size_t(w));
        for (int j = 0; j < w; ++j) {
            for (int i = 0; i < w; ++i) {
                const size_t k = size_t(j) * size_t(w) + size_t(i);
                const glm::dvec2 ga = base.grad(at(i), at(j)), gb = detail.grad(at(i), at(j));
                const glm::dvec3 na = normalOfGrad(ga), nb = normalOfGrad(gb);
                for (int c = 0; c < 3; ++c) {
                    ta[k * 4 + size_t(c)] = float(na[c]);
                    tb[k * 4 + size_t(c)] = float(nb[c]);
                }
                truth[k] = normalOfGrad(ga + gb);
            }
        }
        const unsigned texA = makeFloatTexture(w, w, 4, ta, true, true);
        const unsigned texB = makeFloatTexture(w, w, 4, tb, true, true);
        for (int m = 0; m < SG_NORMAL_BLEND_COUNT; ++m) {
            std::vector<glm::vec4> ab, ba;
            for (int order = 0; order < 2; ++order) {
                glBindTextureUnit(0, order == 0 ? texA : texB);
                glBindTextureUnit(1, order == 0 ? texB : texA);
                target.clear();
                setUniforms(one[size_t(m)], true);
                fullscreen.draw();
                (order == 0 ? ab : ba) = target.read(0);
            }
            std::vector<double> err;
            for (size_t k = 0; k < ab.size(); ++k) {
                err.push_back(angleDeg(glm::dvec3(ab[k]), truth[k]));
                if (r == 2)
                    orderMax[size_t(m)] = std::max(orderMax[size_t(m)],
                                                   angleDeg(glm::dvec3(ab[k]), glm::dvec3(ba[k])));
            }
            stats[size_t(m)][size_t(r)] = errorStats(err);
        }
        deleteTexture(texA);
        deleteTexture(texB);
    }

    // Timing on textures of the moderate regime's size class (values do not
    // change the work of any method).
    // 512^2 at most: a 1024^2 pass of 16 blends takes ~0.5 s per frame on
    // two llvmpipe threads, and the ratios do not change with the size.
    const int tw = std::min(o.size, 512);
    std::vector<float> ta(size_t(tw) * size_t(tw) * 4), tb(ta.size());
    base.amp = 1.0 / maxBase;
    detail.amp = 1.0 / maxDetail;
    for (int j = 0; j < tw; ++j) {
        for (int i = 0; i < tw; ++i) {
            const size_t k = size_t(j) * size_t(tw) + size_t(i);
            const glm::dvec3 na = normalOfGrad(base.grad((i + 0.5) / tw, (j + 0.5) / tw));
            const glm::dvec3 nb = normalOfGrad(detail.grad((i + 0.5) / tw, (j + 0.5) / tw));
            for (int c = 0; c < 3; ++c) {
                ta[k * 4 + size_t(c)] = float(na[c]);
                tb[k * 4 + size_t(c)] = float(nb[c]);
            }
        }
    }
    const unsigned texA = makeFloatTexture(tw, tw, 4, ta, true, true);
    const unsigned texB = makeFloatTexture(tw, tw, 4, tb, true, true);
    glBindTextureUnit(0, texA);
    glBindTextureUnit(1, texB);
    Target tim(tw, tw, 1, false);
    const auto msOne = timeVariants(
        SG_NORMAL_BLEND_COUNT,
        [&](size_t m) {
            tim.clear();
            setUniforms(one[m], false);
            fullscreen.draw();
        },
        o);
    const auto msLoop = timeVariants(
        SG_NORMAL_BLEND_COUNT,
        [&](size_t m) {
            tim.clear();
            setUniforms(loop[m], false);
            fullscreen.draw();
        },
        o);
    deleteTexture(texA);
    deleteTexture(texB);

    Table t;
    t.title = "Table 3: blend method (two height layers, same UV set; truth = normal of the summed "
              "heights)";
    t.header = {"method",       "gentle p50", "gentle max",   "moderate p50",
                "moderate max", "steep p50",  "steep max",    "order max",
                "1 blend ms",   "ratio",      "16 blends ms", "ratio"};
    for (int m = 0; m < SG_NORMAL_BLEND_COUNT; ++m) {
        const auto& s = stats[size_t(m)];
        t.add({kMethodNames[m], fmtErr(s[0].p50), fmtErr(s[0].max), fmtErr(s[1].p50),
               fmtErr(s[1].max), fmtErr(s[2].p50), fmtErr(s[2].max), fmtErr(orderMax[size_t(m)]),
               fmt(msOne[size_t(m)], 2), fmtRatio(msOne[size_t(m)] / msOne[0]),
               fmt(msLoop[size_t(m)], 2), fmtRatio(msLoop[size_t(m)] / msLoop[0])});
    }
    t.notes.push_back(
        "Errors in degrees over " + std::to_string(w) +
        "^2 texel centres (GPU output, RGBA32F maps and "
        "target; truth in double). Regimes: each layer's steepest slope 0.25 / 1 / 3 (14 / 45 / 72 "
        "degrees). 'order max': largest angle between blend(a,b) and blend(b,a), steep regime.");
    t.notes.push_back("Cost: " + std::to_string(tw) + "^2 full-screen pass on " + o.renderer +
                      ", " + std::to_string(o.runs) + " runs x " + std::to_string(o.frames) +
                      " frames, medians; ratios to the surface-gradient method in the same run.");
    t.plot = {"blend",
              9,
              4,
              -1,
              {0},
              false,
              true,
              "1 blend per pixel, ratio to surface gradient",
              "max error, moderate slopes, degrees"};
    t.print(o);
}

} // namespace study
