// Periodic bicubic B-spline limit of the Catmull-Clark torus cage (torus.h).
#include "torus.h"

#include <cmath>

namespace study {

namespace {

int wrap(int i, int n) {
    return ((i % n) + n) % n;
}

// Uniform cubic B-spline basis on one span, x in [0, 1], and its derivative.
// With control points c[k-1..k+2] for the span [k, k+1], the limit at x = 0
// is (c[k-1] + 4 c[k] + c[k+1]) / 6: the Catmull-Clark vertex limit rule.
void basis(double x, double w[4], double dw[4]) {
    const double y = 1.0 - x;
    w[0] = y * y * y / 6.0;
    w[1] = (3.0 * x * x * x - 6.0 * x * x + 4.0) / 6.0;
    w[2] = (-3.0 * x * x * x + 3.0 * x * x + 3.0 * x + 1.0) / 6.0;
    w[3] = x * x * x / 6.0;
    dw[0] = -0.5 * y * y;
    dw[1] = 1.5 * x * x - 2.0 * x;
    dw[2] = -1.5 * x * x + x + 0.5;
    dw[3] = 0.5 * x * x;
}

} // namespace

glm::dvec3 TorusCage::control(int i, int j) const {
    const double th = 2.0 * M_PI * double(wrap(i, n)) / double(n);
    const double ph = 2.0 * M_PI * double(wrap(j, m)) / double(m);
    const double rr = majorRadius + minorRadius * std::cos(ph);
    return {rr * std::cos(th), rr * std::sin(th), minorRadius * std::sin(ph)};
}

sg::mesh::PolygonMesh TorusCage::polygonMesh() const {
    sg::mesh::PolygonMesh mesh;
    mesh.name = "bspline_torus";
    for (int j = 0; j < m; ++j) {
        for (int i = 0; i < n; ++i) mesh.positions.push_back(glm::vec3(control(i, j)));
    }
    sg::mesh::FaceVaryingChannel uv;
    uv.name = "st";
    // (n+1) x (m+1) UV values: the seams carry both s = 0 and s = 1.
    for (int j = 0; j <= m; ++j) {
        for (int i = 0; i <= n; ++i)
            uv.values.push_back(glm::vec2(float(i) / float(n), float(j) / float(m)));
    }
    auto vtx = [&](int i, int j) { return uint32_t(wrap(j, m) * n + wrap(i, n)); };
    auto uvi = [&](int i, int j) { return uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < m; ++j) {
        for (int i = 0; i < n; ++i) {
            mesh.faceSizes.push_back(4);
            const int ci[4] = {i, i + 1, i + 1, i};
            const int cj[4] = {j, j, j + 1, j + 1};
            for (int k = 0; k < 4; ++k) {
                mesh.faceVertices.push_back(vtx(ci[k], cj[k]));
                uv.indices.push_back(uvi(ci[k], cj[k]));
            }
        }
    }
    mesh.uvSets.push_back(std::move(uv));
    return mesh;
}

SurfacePoint TorusCage::limit(double s, double t) const {
    const double a = s * double(n), b = t * double(m);
    const double fa = std::floor(a), fb = std::floor(b);
    const int ia = int(fa), ib = int(fb);
    double wa[4], dwa[4], wb[4], dwb[4];
    basis(a - fa, wa, dwa);
    basis(b - fb, wb, dwb);
    glm::dvec3 p(0.0), pa(0.0), pb(0.0);
    for (int k = 0; k < 4; ++k) {
        for (int l = 0; l < 4; ++l) {
            const glm::dvec3 c = control(ia - 1 + k, ib - 1 + l);
            p += wa[k] * wb[l] * c;
            pa += dwa[k] * wb[l] * c;
            pb += wa[k] * dwb[l] * c;
        }
    }
    SurfacePoint r;
    r.pos = p;
    r.dPds = pa * double(n); // da/ds = n
    r.dPdt = pb * double(m);
    r.normal = glm::normalize(glm::cross(r.dPds, r.dPdt));
    return r;
}

glm::dvec3 blinnNormal(const SurfacePoint& p, double hs, double ht) {
    const glm::dvec3& n = p.normal;
    const double det = glm::dot(n, glm::cross(p.dPds, p.dPdt));
    const glm::dvec3 grad = (hs * glm::cross(p.dPdt, n) + ht * glm::cross(n, p.dPds)) / det;
    return glm::normalize(n - grad);
}

void exactFrame(const SurfacePoint& p, glm::dvec3& tangent, glm::dvec3& bitangent) {
    tangent = glm::normalize(p.dPds - glm::dot(p.dPds, p.normal) * p.normal);
    bitangent = glm::cross(p.normal, tangent);
}

glm::dvec2 bakeDerivative(const SurfacePoint& p, const glm::dvec3& nt) {
    glm::dvec3 t, b;
    exactFrame(p, t, b);
    const double z = glm::dot(nt, p.normal);
    return {-glm::dot(nt, t) / z, -glm::dot(nt, b) / z};
}

} // namespace study
