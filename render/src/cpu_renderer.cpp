// The CPU reference renderer (see renderCpu in surfgrad/render.h).
//
// Rasterisation follows the OpenGL pipeline the GPU runs: vertices to clip
// space with the same matrices, clipping against the near plane (z >= -w)
// in homogeneous coordinates (Sutherland-Hodgman), the viewport transform,
// coverage at pixel centres (x + 0.5, y + 0.5) with a top-left tie rule,
// depth interpolated linearly in screen space and tested with GL_LESS,
// back faces culled for single-sided materials. Adaptive meshes are first
// tessellated as the GPU's tessellation stages do (patch_tessellation.cpp).
//
// Shading inputs are interpolated perspective-correctly and differentiated
// ANALYTICALLY: with screen-space barycentrics b_i (affine in x, y) and
// clip w_i, the perspective-correct weights are lambda_i = (b_i / w_i) /
// sum_j (b_j / w_j), a quotient of affine functions, whose exact derivative
// is (q_i' D - q_i D') / D^2. Every attribute (position, UVs, ...) and its
// d/dx, d/dy follow linearly. The GPU's dFdxFine is the difference of the
// same interpolant between the two pixels of a 2x2 quad, so the two agree to
// second order in the pixel size (the image tests state by how much).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <cmath>
#include <limits>

#include "render_internal.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/render.h"

namespace sg::render {

namespace {

struct ClipVert {
    glm::vec4 clip;
    glm::vec3 bary; // weights of the original triangle's three vertices
};

// A screen-space triangle after clipping.
struct ScreenTri {
    int mesh = 0;
    uint32_t prim = 0;    // original triangle index (gl_PrimitiveID)
    uint32_t vtx[3] = {}; // original triangle's vertex indices
    glm::dvec2 win[3];    // window coordinates
    double invW[3] = {};  // 1 / clip w
    glm::vec3 bary[3];    // clipped vertex -> original barycentrics
    double area = 0.0;    // signed area (twice), window space
    bool front = true;
};

// Clips a polygon against z + w >= 0 (the near plane).
std::vector<ClipVert> clipNear(const std::vector<ClipVert>& in) {
    std::vector<ClipVert> out;
    for (size_t i = 0; i < in.size(); ++i) {
        const ClipVert& a = in[i];
        const ClipVert& b = in[(i + 1) % in.size()];
        float da = a.clip.z + a.clip.w, db = b.clip.z + b.clip.w;
        if (da >= 0.0f) out.push_back(a);
        if ((da >= 0.0f) != (db >= 0.0f)) {
            float t = da / (da - db);
            out.push_back(ClipVert{a.clip + t * (b.clip - a.clip), a.bary + t * (b.bary - a.bary)});
        }
    }
    return out;
}

// Top-left rule for an edge a -> b of a counter-clockwise (area > 0)
// triangle in y-up window coordinates: pixels exactly on a "top" edge
// (horizontal, interior below: running right to left) or a "left" edge
// (running downwards) are inside.
bool topLeft(glm::dvec2 a, glm::dvec2 b) {
    glm::dvec2 e = b - a;
    return (e.y == 0.0 && e.x < 0.0) || e.y < 0.0;
}

// Vertex data of one mesh instance (camera-relative and object space),
// exactly as the vertex program computes it.
struct MeshData {
    std::vector<glm::vec3> rel, obj, normal;
    // Displaced adaptive meshes: rel, obj are the undisplaced
    // positions (the frame's, vRelPos), relLit the displaced ones
    // (vRelPosLit, lighting; clip comes from them). Empty otherwise.
    std::vector<glm::vec3> relLit;
    std::vector<glm::vec4> tangent[kMaxUvSets];
    std::vector<glm::vec4> clip;
    const sg::mesh::RenderMesh* mesh = nullptr;
    const std::vector<glm::vec4>* patchAov = nullptr; // adaptive meshes (vPatchAov)
    float detSign = 1.0f;
};

MeshData vertexStage(const MeshInstance& inst, const MeshAsset& a, const View& view,
                     const std::vector<glm::vec3>* framePositions = nullptr) {
    const auto& m = a.mesh;
    MeshData d;
    d.mesh = &m;
    const glm::mat4 M(inst.transform); // uModel (tangents)
    const glm::mat4 rel = modelToCameraRelative(inst.transform, view.cameraPos);
    glm::mat3 nm = detail::normalMatrix(inst.transform);
    d.detSign = glm::determinant(glm::dmat3(inst.transform)) < 0.0 ? -1.0f : 1.0f;
    size_t nv = m.vertexCount();
    d.rel.resize(nv);
    const std::vector<glm::vec3>& base = framePositions ? *framePositions : m.positions;
    d.obj = base;
    d.normal.resize(nv);
    d.clip.resize(nv);
    if (framePositions) d.relLit.resize(nv);
    for (size_t v = 0; v < nv; ++v) {
        d.rel[v] = glm::vec3(rel * glm::vec4(base[v], 1.0f));
        d.normal[v] = m.normals.empty() ? glm::vec3(0.0f) : nm * m.normals[v];
        if (framePositions) {
            d.relLit[v] = glm::vec3(rel * glm::vec4(m.positions[v], 1.0f));
            d.clip[v] = view.viewProjRel * glm::vec4(d.relLit[v], 1.0f);
        } else {
            d.clip[v] = view.viewProjRel * glm::vec4(d.rel[v], 1.0f);
        }
    }
    for (int k = 0; k < kMaxUvSets && size_t(k) < a.vertexTangents.size(); ++k) {
        const auto& t = a.vertexTangents[size_t(k)];
        d.tangent[k].resize(t.size());
        for (size_t v = 0; v < t.size(); ++v) {
            d.tangent[k][v] = glm::vec4(glm::mat3(M) * glm::vec3(t[v]), t[v].w * d.detSign);
        }
    }
    return d;
}

// Depth-tested visibility: which screen triangle covers each pixel.
struct Raster {
    int W = 0, H = 0;
    std::vector<float> depth;
    std::vector<int32_t> visible;
    std::vector<ScreenTri> tris;

    Raster(int w, int h)
        : W(w), H(h), depth(size_t(w) * size_t(h), 1.0f), visible(size_t(w) * size_t(h), -1) {}

    // Window coordinates, depth and orientation of a clipped triangle;
    // false when it is degenerate, behind the eye or culled.
    bool setup(const ClipVert* const cv[3], bool cull, float detSign, ScreenTri& st,
               double zw[3]) const {
        for (int i = 0; i < 3; ++i) {
            glm::dvec4 c(cv[i]->clip);
            if (!(c.w > 0.0)) return false;
            st.invW[i] = 1.0 / c.w;
            st.win[i] =
                glm::dvec2((c.x * st.invW[i] * 0.5 + 0.5) * W, (c.y * st.invW[i] * 0.5 + 0.5) * H);
            zw[i] = c.z * st.invW[i] * 0.5 + 0.5;
            st.bary[i] = cv[i]->bary;
        }
        const auto& p = st.win;
        st.area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
        if (st.area == 0.0 || !std::isfinite(st.area)) return false;
        st.front = (st.area > 0.0) == (detSign > 0.0f);
        return !(cull && !st.front);
    }

    // Coverage at pixel centres (top-left rule) and the depth test; the
    // triangle is kept when it wins some pixel.
    void cover(const ScreenTri& st, const double zw[3]) {
        const auto& p = st.win;
        // Orient counter-clockwise for the coverage test.
        double s = st.area > 0.0 ? 1.0 : -1.0;
        int32_t triIndex = int32_t(tris.size());
        int x0 = std::max(0, int(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
        int x1 = std::min(W - 1, int(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
        int y0 = std::max(0, int(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
        int y1 = std::min(H - 1, int(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
        bool any = false;
        // Edge e_i is opposite vertex i: (i+1) -> (i+2).
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                glm::dvec2 c(x + 0.5, y + 0.5);
                double b[3];
                bool inside = true;
                for (int i = 0; i < 3 && inside; ++i) {
                    glm::dvec2 a0 = p[(i + 1) % 3], a1 = p[(i + 2) % 3];
                    double e = s * ((a1.x - a0.x) * (c.y - a0.y) - (a1.y - a0.y) * (c.x - a0.x));
                    b[i] = e;
                    glm::dvec2 from = s > 0 ? a0 : a1, to = s > 0 ? a1 : a0;
                    inside = e > 0.0 || (e == 0.0 && topLeft(from, to));
                }
                if (!inside) continue;
                double sum = b[0] + b[1] + b[2];
                double z = (b[0] * zw[0] + b[1] * zw[1] + b[2] * zw[2]) / sum;
                if (!(z <= 1.0) || !(z >= 0.0)) continue; // outside the depth range (far plane)
                size_t pix = size_t(y) * size_t(W) + size_t(x);
                if (!(float(z) < depth[pix])) continue;
                depth[pix] = float(z);
                visible[pix] = triIndex;
                any = true;
            }
        }
        if (any) tris.push_back(st);
    }

    // Every triangle of one mesh: near clipping, setup, coverage.
    void mesh(int meshIndex, const MeshData& d, bool cull) {
        const auto& m = *d.mesh;
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            uint32_t idx[3] = {m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]};
            std::vector<ClipVert> poly = {{d.clip[idx[0]], {1, 0, 0}},
                                          {d.clip[idx[1]], {0, 1, 0}},
                                          {d.clip[idx[2]], {0, 0, 1}}};
            poly = clipNear(poly);
            for (size_t f = 1; f + 1 < poly.size(); ++f) {
                const ClipVert* cv[3] = {&poly[0], &poly[f], &poly[f + 1]};
                ScreenTri st;
                st.mesh = meshIndex;
                st.prim = uint32_t(t);
                std::copy(idx, idx + 3, st.vtx);
                double zw[3];
                if (setup(cv, cull, d.detSign, st, zw)) cover(st, zw);
            }
        }
    }
};

// Perspective-correct weights of the original triangle's vertices at
// window position c: screen barycentrics b_i (affine in c), q_i = b_i / w_i,
// lambda_i = q_i / sum q; their exact d/dx, d/dy by the quotient rule.
glm::dvec3 perspectiveWeights(const ScreenTri& st, glm::dvec2 c, glm::dvec3* dx, glm::dvec3* dy) {
    const auto& p = st.win;
    double b[3], bx[3], by[3];
    for (int i = 0; i < 3; ++i) {
        glm::dvec2 a0 = p[(i + 1) % 3], a1 = p[(i + 2) % 3];
        b[i] = ((a1.x - a0.x) * (c.y - a0.y) - (a1.y - a0.y) * (c.x - a0.x)) / st.area;
        bx[i] = -(a1.y - a0.y) / st.area;
        by[i] = (a1.x - a0.x) / st.area;
    }
    double q[3], qx[3], qy[3], D = 0, Dx = 0, Dy = 0;
    for (int i = 0; i < 3; ++i) {
        q[i] = b[i] * st.invW[i];
        qx[i] = bx[i] * st.invW[i];
        qy[i] = by[i] * st.invW[i];
        D += q[i];
        Dx += qx[i];
        Dy += qy[i];
    }
    glm::dvec3 mu(0.0), mux(0.0), muy(0.0);
    for (int i = 0; i < 3; ++i) {
        glm::dvec3 B(st.bary[i]);
        mu += (q[i] / D) * B;
        mux += ((qx[i] * D - q[i] * Dx) / (D * D)) * B;
        muy += ((qy[i] * D - q[i] * Dy) / (D * D)) * B;
    }
    if (dx) *dx = mux;
    if (dy) *dy = muy;
    return mu;
}

// The fragment program's inputs at pixel (x, y) of a visible triangle.
detail::PixelInputs pixelInputs(const ScreenTri& st, const MeshData& d, int x, int y,
                                CpuDerivatives derivatives) {
    glm::dvec3 mux, muy;
    glm::dvec3 mu = perspectiveWeights(st, glm::dvec2(x + 0.5, y + 0.5), &mux, &muy);
    if (derivatives == CpuDerivatives::Quad) {
        // dFdxFine/dFdyFine: differences across the pixel's 2x2 quad,
        // the triangle's interpolants extrapolated to helper pixels.
        int qx0 = x & ~1, qy0 = y & ~1;
        mux = perspectiveWeights(st, glm::dvec2(qx0 + 1.5, y + 0.5), nullptr, nullptr) -
              perspectiveWeights(st, glm::dvec2(qx0 + 0.5, y + 0.5), nullptr, nullptr);
        muy = perspectiveWeights(st, glm::dvec2(x + 0.5, qy0 + 1.5), nullptr, nullptr) -
              perspectiveWeights(st, glm::dvec2(x + 0.5, qy0 + 0.5), nullptr, nullptr);
    }
    auto interp = [&](const auto& arr, glm::dvec3 w) {
        using T = std::decay_t<decltype(arr[0])>;
        return T(float(w.x) * arr[st.vtx[0]] + float(w.y) * arr[st.vtx[1]] +
                 float(w.z) * arr[st.vtx[2]]);
    };
    detail::PixelInputs in;
    in.relPos = interp(d.rel, mu);
    in.relPosLit = d.relLit.empty() ? in.relPos : interp(d.relLit, mu);
    in.dPdx = interp(d.rel, mux);
    in.dPdy = interp(d.rel, muy);
    in.objPos = interp(d.obj, mu);
    in.dObjdx = interp(d.obj, mux);
    in.dObjdy = interp(d.obj, muy);
    in.normal = interp(d.normal, mu);
    in.dNdx = interp(d.normal, mux);
    in.dNdy = interp(d.normal, muy);
    in.fragCoord = glm::vec2(float(x) + 0.5f, float(y) + 0.5f);
    for (size_t k = 0; k < d.mesh->uvSets.size() && k < size_t(kMaxUvSets); ++k) {
        in.uv[k] = interp(d.mesh->uvSets[k], mu);
        in.dUVdx[k] = interp(d.mesh->uvSets[k], mux);
        in.dUVdy[k] = interp(d.mesh->uvSets[k], muy);
        if (!d.tangent[k].empty()) in.tangent[k] = interp(d.tangent[k], mu);
    }
    in.frontFacing = st.front;
    in.primId = float(st.prim);
    if (d.patchAov) in.patchAov = (*d.patchAov)[st.vtx[0]]; // flat: one patch per triangle
    return in;
}

// Plans, uniforms and samplers of one draw (the GPU's per-draw state).
struct DrawState {
    MaterialPlan plan;
    detail::DrawUniforms uniforms;
    std::vector<sg::glsl::sampler2D> samplers;
    std::vector<std::any> kindData; // the kinds' own (planKindCpuData)
};

std::vector<DrawState> drawStates(const Scene& scene, const SceneAssets& assets, const View& view,
                                  const CpuOptions& options) {
    std::vector<DrawState> draws;
    float primBase = 0.0f;
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        DrawState d;
        d.plan = planMaterial(scene, assets, int(mi), scene.meshes[mi].material);
        d.uniforms = detail::drawUniforms(scene, assets, d.plan, view, int(mi), primBase);
        d.kindData = detail::planKindCpuData(d.plan, assets);
        d.samplers = detail::planSamplers(d.plan, assets, options.textureLod);
        draws.push_back(std::move(d));
        primBase += float(assets.meshes[mi].mesh.triangleCount());
    }
    return draws;
}

// One more row shaded: calls options.progress after every 1/16 of the rows
// and at the last, one call at a time.
void reportRow(const CpuOptions& options, std::atomic<int>& rowsDone, std::mutex& lock, int rows) {
    const int done = ++rowsDone;
    if (!options.progress) return;
    const int step = std::max(rows / 16, 1);
    if (done % step != 0 && done != rows) return;
    std::lock_guard<std::mutex> guard(lock);
    options.progress(done, rows);
}

} // namespace

Image renderCpu(const Scene& scene, const SceneAssets& assets, const View& view,
                const CpuOptions& options) {
    const int W = view.width, H = view.height;
    glm::vec4 bg =
        view.aov == Aov::Color ? glm::vec4(scene.output.background, 1.0f) : glm::vec4(0.0f);
    Image img(W, H, bg);

    // Vertex stage and rasterisation, mesh by mesh in draw order.
    // Adaptive meshes: their patches tessellated for this view first, at the
    // levels the GPU's control stage computes (patch_tessellation.cpp).
    Raster raster(W, H);
    std::vector<MeshData> md(scene.meshes.size());
    std::vector<MeshAsset> tessellated(scene.meshes.size());
    std::vector<std::vector<glm::vec4>> patchAov(scene.meshes.size());
    std::vector<std::vector<glm::vec3>> framePositions(scene.meshes.size());
    const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
    for (size_t mi = 0; mi < scene.meshes.size(); ++mi) {
        const MeshInstance& inst = scene.meshes[mi];
        const MeshAsset* asset = &assets.meshes[mi];
        if (asset->patches) {
            // An animated cage: the points of its cage through the same
            // stencils the GPU's compute stage applies.
            const sg::mesh::AdaptivePatches* ap = asset->patches.get();
            sg::mesh::AdaptivePatches moved;
            if (!asset->cagePositions.empty()) {
                moved = *ap;
                sg::mesh::updateAdaptivePoints(moved, asset->cagePositions);
                ap = &moved;
            }
            detail::PatchDisplacement disp;
            const bool displaced = inst.displacement.has_value();
            if (displaced) {
                auto it = assets.textures.find(inst.displacement->map.key());
                SG_ASSERT(it != assets.textures.end(), "displacement maps load with the assets");
                disp.map.image = it->second.get();
                disp.scale = inst.displacement->scale;
                disp.offset = inst.displacement->offset;
                disp.uvSet = inst.displacement->uvSet;
            }
            detail::TessellatedPatches t = detail::tessellatePatches(
                *ap, modelToCameraRelative(inst.transform, view.cameraPos), focalPx,
                inst.subdivPixelsPerEdge, displaced ? &disp : nullptr,
                patchTangentMask(*asset, scene.materials[size_t(inst.material)]));
            tessellated[mi].mesh = std::move(t.mesh);
            tessellated[mi].vertexTangents = std::move(t.vertexTangents);
            patchAov[mi] = std::move(t.patchAov);
            framePositions[mi] = std::move(t.framePositions);
            asset = &tessellated[mi];
        }
        md[mi] = vertexStage(inst, *asset, view,
                             framePositions[mi].empty() ? nullptr : &framePositions[mi]);
        if (!patchAov[mi].empty()) md[mi].patchAov = &patchAov[mi];
        const bool cull = scene.materials[size_t(inst.material)].doubleSided == DoubleSided::Off;
        raster.mesh(int(mi), md[mi], cull);
    }
    const std::vector<DrawState> draws = drawStates(scene, assets, view, options);

    // Fragment stage: the visible triangle's inputs at each pixel, shaded;
    // rows done go to options.progress.
    std::atomic<int> rowsDone{0};
    std::mutex progressLock;
    tbb::parallel_for(0, H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            size_t pix = size_t(y) * size_t(W) + size_t(x);
            int32_t ti = raster.visible[pix];
            if (ti < 0) continue;
            const ScreenTri& st = raster.tris[size_t(ti)];
            const DrawState& d = draws[size_t(st.mesh)];
            detail::PixelInputs in =
                pixelInputs(st, md[size_t(st.mesh)], x, y, options.derivatives);
            img.setRgba(pix, detail::shadePixelCpu(d.plan, d.uniforms, d.samplers, d.kindData, in));
        }
        reportRow(options, rowsDone, progressLock, H);
    });
    return img;
}

} // namespace sg::render
