// The inputs of the stability cases (stability_inputs.h).
#include "stability_inputs.h"

#include <algorithm>

namespace study::stability::detail {

using sg::render::Scene;

// x moved by `ulps` units in the last place of binary32 at max(|x|, 0.5):
// a change the file's reader sees (values are written to round-trip
// binary32), of the size rounding gives a coordinate of that magnitude.
double moveUlps(double x, int ulps) {
    const float xf = float(x);
    const float mag = std::max(std::fabs(xf), 0.5f);
    int e = 0;
    std::frexp(mag, &e);
    const float ulp = std::ldexp(1.0f, e - 24);
    return double(xf + float(ulps) * ulp);
}

std::string num(double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

std::string vec3Json(glm::dvec3 v) {
    return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]";
}

Scene sceneOf(const SceneSpec& s, const fs::path& dir) {
    std::string json = R"({"output": {"width": 64, "height": 48}, "materials": [{"name": "m", )" +
                       s.materialExtra + R"("layers": [)" + s.layers + R"(]}], "meshes": [{)" +
                       s.meshFields;
    if (!s.transform.empty()) json += R"(, "transform": )" + s.transform;
    json += R"(}], "camera": {"position": )" + vec3Json(s.eye) + R"(, "target": )" +
            vec3Json(s.target) + R"(, "up": [0, 1, 0], "fov_deg": )" + num(s.fovDeg) +
            R"(, "near": )" + num(s.nearPlane) + R"(, "far": )" + num(s.farPlane) + "}}";
    return sg::render::parseScene(json, (dir / "scene.json").string(), dir);
}

std::string fileField(const ObjMesh& m, const fs::path& dir, const std::string& name) {
    const fs::path f = dir / (name + ".obj");
    m.write(f);
    return R"("file": ")" + f.string() + R"(")";
}

// ---------------------------------------------------------------------------
// Meshes

// One triangle facing +z whose UVs are (s0,0), (s0,1), (s0,1): a chart
// collapsed to a segment (s is constant, t runs along one edge only).
ObjMesh collapsedTriangle(double s0) {
    ObjMesh m;
    const int n = m.addVn({0, 0, 1});
    const int a = m.addV({-1, -1, 0}), b = m.addV({1, -1, 0}), c = m.addV({0, 1, 0});
    const int ta = m.addVt({s0, 0}), tb = m.addVt({s0, 1}), tc = m.addVt({s0, 1});
    m.faces.push_back({{a, ta, n}, {b, tb, n}, {c, tc, n}});
    return m;
}

// An open cylinder (radius 0.5, y in [-0.5, 0.5], `segments` quads around,
// `rows` quads high) with a top cap, UVs projected from the top:
// (s, t) = (0.5 + x, 0.5 - z). The walls' UV chart is singular (t and s do
// not change along y); the cap's is regular. Quads (a subdivision cage),
// the cap a fan of triangles.
ObjMesh topProjectedCylinder(int segments, int rows) {
    ObjMesh m;
    const double r = 0.5, kPi = 3.14159265358979323846;
    std::vector<int> ring((size_t(rows) + 1) * size_t(segments)), uvs(ring.size());
    std::vector<int> nrm(static_cast<size_t>(segments));
    for (int i = 0; i < segments; ++i) {
        const double a = 2.0 * kPi * double(i) / double(segments);
        nrm[size_t(i)] = m.addVn({std::cos(a), 0, -std::sin(a)});
    }
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i < segments; ++i) {
            const double a = 2.0 * kPi * double(i) / double(segments);
            const double x = r * std::cos(a), z = -r * std::sin(a), y = -0.5 + double(j) / rows;
            const size_t k = size_t(j) * size_t(segments) + size_t(i);
            ring[k] = m.addV({x, y, z});
            uvs[k] = m.addVt({0.5 + x, 0.5 - z});
        }
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < segments; ++i) {
            const int i1 = (i + 1) % segments;
            auto at = [&](int jj, int ii) {
                const size_t k = size_t(jj) * size_t(segments) + size_t(ii);
                return glm::ivec3(ring[k], uvs[k], nrm[size_t(ii)]);
            };
            m.faces.push_back({at(j, i), at(j, i1), at(j + 1, i1), at(j + 1, i)});
        }
    const int up = m.addVn({0, 1, 0});
    const int centre = m.addV({0, 0.5, 0}), centreUv = m.addVt({0.5, 0.5});
    for (int i = 0; i < segments; ++i) {
        const int i1 = (i + 1) % segments;
        const size_t k0 = size_t(rows) * size_t(segments) + size_t(i),
                     k1 = size_t(rows) * size_t(segments) + size_t(i1);
        m.faces.push_back(
            {{ring[k0], uvs[k0], up}, {ring[k1], uvs[k1], up}, {centre, centreUv, up}});
    }
    return m;
}

// A grid of n x n quads over [-1, 1]^2 in the plane y = 0 (UVs [0, 1]^2,
// s along +x, t along -z), every vertex normal `normal`.
ObjMesh grid(int n, glm::dvec3 normal) {
    ObjMesh m;
    const int vn = m.addVn(normal);
    std::vector<int> idx;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double s = double(i) / n, t = double(j) / n;
            m.addV({-1.0 + 2.0 * s, 0.0, 1.0 - 2.0 * t});
            m.addVt({s, t});
        }
    auto at = [&](int i, int j) {
        const int k = j * (n + 1) + i;
        return glm::ivec3(k, k, vn);
    };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            m.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    return m;
}

// The top-projected cylinder with its walls' projection tilted by `tilt`
// (t += tilt * y): 0 is singular, small values near-singular.
ObjMesh tiltedCylinder(double tilt) {
    ObjMesh m = topProjectedCylinder(24, 3);
    for (size_t i = 0; i < m.vt.size() && i < m.v.size(); ++i) m.vt[i].y += tilt * m.v[i].y;
    return m;
}

// A grid whose UVs are collinear on every triangle: (s, t) = (u, u).
ObjMesh collinearGrid() {
    ObjMesh m = grid(6, {0, 1, 0});
    for (auto& t : m.vt) t.y = t.x;
    return m;
}

// A grid whose vertex normals alternate, checkerwise, between the face
// normal and 150 degrees from it (behind the surface, leaning to +z): the
// interpolated normal turns through the horizon inside every triangle.
ObjMesh flippingNormalsGrid() {
    const int n = 6;
    ObjMesh m = grid(n, {0, 1, 0});
    const double a = 150.0 * 3.14159265358979323846 / 180.0;
    const int behind = m.addVn({0.0, std::cos(a), std::sin(a)});
    for (auto& f : m.faces)
        for (glm::ivec3& corner : f) {
            const int i = corner.x % (n + 1), j = corner.x / (n + 1);
            if ((i + j) % 2 == 1) corner.z = behind;
        }
    return m;
}

// A grid mirrored in s across x = 0 (a UV seam in the middle).
ObjMesh mirroredGrid() {
    ObjMesh m = grid(6, {0, 1, 0});
    for (size_t i = 0; i < m.vt.size(); ++i) m.vt[i].x = std::fabs(m.v[i].x);
    return m;
}

// A fan of needles: a disk of 720 triangles (0.5 degrees each) around the
// origin in the plane y = 0, UVs the planar projection.
ObjMesh needleFan() {
    ObjMesh m;
    const int n = 720, vn = m.addVn({0, 1, 0});
    const int c = m.addV({0, 0, 0});
    m.addVt({0.5, 0.5});
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * 3.14159265358979323846 * double(i) / n;
        m.addV({std::cos(a), 0, -std::sin(a)});
        m.addVt({0.5 + 0.5 * std::cos(a), 0.5 + 0.5 * std::sin(a)});
    }
    for (int i = 0; i < n; ++i) {
        const int a = 1 + i, b = 1 + (i + 1) % n;
        m.faces.push_back({{c, c, vn}, {a, a, vn}, {b, b, vn}});
    }
    return m;
}

// A grid with every third quad collapsed to a segment (two corners moved
// onto the other two): zero-area triangles amid ordinary ones.
ObjMesh zeroAreaGrid() {
    ObjMesh m = grid(6, {0, 1, 0});
    std::vector<std::vector<glm::ivec3>> faces;
    int k = 0;
    for (auto f : m.faces) {
        if (k++ % 3 == 0) {
            faces.push_back({f[0], f[1], f[1]});
            faces.push_back({f[0], f[1], f[0]});
            faces.push_back({f[1], f[2], f[3]});
        } else {
            faces.push_back({f[0], f[1], f[2]});
            faces.push_back({f[0], f[2], f[3]});
        }
    }
    m.faces.clear();
    for (auto& f : faces)
        if (f[0].x != f[1].x && f[1].x != f[2].x && f[0].x != f[2].x) m.faces.push_back(f);
    // Zero area by position: the middle vertex of a row moved onto the segment.
    return m;
}

// A closed cage with two poles of valence `valence` (a sphere of `valence`
// segments and 4 rings, triangle fans at the poles), UVs the sphere's.
ObjMesh poleCage(int valence) {
    ObjMesh m;
    const double kPi = 3.14159265358979323846;
    const int rings = 4;
    std::vector<int> idx;
    const int north = m.addV({0, 1, 0}), south = m.addV({0, -1, 0});
    const int tn = m.addVt({0.5, 1.0}), ts = m.addVt({0.5, 0.0});
    std::vector<int> ring((size_t(rings) - 1) * size_t(valence + 1));
    std::vector<int> ringV((size_t(rings) - 1) * size_t(valence));
    for (int r = 1; r < rings; ++r) {
        const double th = kPi * double(r) / rings;
        for (int i = 0; i <= valence; ++i) {
            const double ph = 2.0 * kPi * double(i) / valence;
            if (i < valence)
                ringV[size_t(r - 1) * size_t(valence) + size_t(i)] = m.addV(
                    {std::sin(th) * std::cos(ph), std::cos(th), -std::sin(th) * std::sin(ph)});
            ring[size_t(r - 1) * size_t(valence + 1) + size_t(i)] =
                m.addVt({double(i) / valence, 1.0 - double(r) / rings});
        }
    }
    auto V = [&](int r, int i) {
        return ringV[size_t(r - 1) * size_t(valence) + size_t(i % valence)];
    };
    auto T = [&](int r, int i) { return ring[size_t(r - 1) * size_t(valence + 1) + size_t(i)]; };
    for (int i = 0; i < valence; ++i) {
        m.faces.push_back(
            {{north, tn, -1}, {V(1, i), T(1, i), -1}, {V(1, i + 1), T(1, i + 1), -1}});
        for (int r = 1; r + 1 < rings; ++r)
            m.faces.push_back({{V(r, i), T(r, i), -1},
                               {V(r + 1, i), T(r + 1, i), -1},
                               {V(r + 1, i + 1), T(r + 1, i + 1), -1},
                               {V(r, i + 1), T(r, i + 1), -1}});
        m.faces.push_back({{south, ts, -1},
                           {V(rings - 1, i + 1), T(rings - 1, i + 1), -1},
                           {V(rings - 1, i), T(rings - 1, i), -1}});
    }
    return m;
}

// A random height-field grid with a random chart, normals and damage (see
// generatedCases); `what` describes it.
ObjMesh randomMesh(Rng& rng, std::string& what, bool& uvsOffset, double& leanDeg) {
    const int n = rng.integer(2, 6);
    ObjMesh m;
    const double amp = rng.range(0.0, 0.4), freq = rng.range(0.5, 3.0);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double jx = (i > 0 && i < n) ? rng.range(-0.3, 0.3) : 0.0;
            const double jz = (j > 0 && j < n) ? rng.range(-0.3, 0.3) : 0.0;
            const double x = -1.0 + 2.0 * (double(i) + jx) / n,
                         z = -1.0 + 2.0 * (double(j) + jz) / n;
            m.addV({x, amp * std::sin(freq * x) * std::cos(freq * z), z});
        }
    // Chart: st = A (x, z) + offset, A conformal, anisotropic, sheared or
    // singular.
    const int chart = rng.integer(0, 3);
    const double a = rng.range(0.0, 6.283185307179586), sc = std::pow(10.0, rng.range(-1.0, 1.0));
    glm::dmat2 A(std::cos(a) * sc, std::sin(a) * sc, -std::sin(a) * sc, std::cos(a) * sc);
    const char* chartName[] = {"conformal", "anisotropic", "sheared", "singular"};
    if (chart == 1) A[1] *= std::pow(10.0, rng.range(-3.0, 0.0));
    if (chart == 2)
        A[1] = A[0] * rng.range(0.95, 1.05) + A[1] * std::pow(10.0, rng.range(-4.0, -1.0));
    if (chart == 3) A[1] = A[0] * rng.range(-2.0, 2.0);
    // World-unit offsets (~1e4) only on conformal charts: a file's
    // coordinates there carry 1e-3 of rounding, which leaves a thin chart's
    // frame undetermined in the data itself (not a property of the renderer).
    glm::dvec2 offset(0.0);
    if (rng.uniform() < 0.25) {
        const glm::dvec2 o(std::floor(rng.range(-2e4, 2e4)), std::floor(rng.range(-2e4, 2e4)));
        if (chart == 0) offset = o;
    }
    for (const auto& p : m.v) m.addVt(A * glm::dvec2(p.x, p.z) + offset);
    what = std::string(chartName[chart]) + " chart";
    uvsOffset = offset != glm::dvec2(0.0);
    if (uvsOffset) what += " offset by ~1e4";
    // Collapsed UVs: a few vertices take a neighbour's UV; not on charts
    // offset by 1e4, whose coordinates carry 1e-3 of rounding: a pair
    // collapsed there is collapsed only to that precision, and a
    // rounding-size change of it (2e-3) is a change of the chart by a few
    // percent, not a rounding-size change of the frame (the draws stay, so
    // the cases are the same as without this rule).
    const int collapse = rng.integer(0, 3);
    for (int k = 0; k < collapse; ++k) {
        const int v = rng.integer(0, int(m.vt.size()) - 2);
        if (offset == glm::dvec2(0.0)) m.vt[size_t(v)] = m.vt[size_t(v + 1)];
    }
    if (collapse && offset == glm::dvec2(0.0))
        what += ", " + std::to_string(collapse) + " UVs collapsed onto a neighbour";
    // Needles: a vertex moved almost onto its neighbour.
    if (rng.uniform() < 0.3) {
        const int v = rng.integer(0, int(m.v.size()) - 2);
        m.v[size_t(v)] = m.v[size_t(v + 1)] + glm::dvec3(1e-4, 0.0, 0.0);
        what += ", a needle";
    }
    // Normals: the height field's, some leaning towards the horizon.
    const double lean = rng.uniform() < 0.3 ? rng.range(80.0, 89.9) : 0.0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const glm::dvec3 p = m.v[size_t(j * (n + 1) + i)];
            glm::dvec3 nrm = glm::normalize(
                glm::dvec3(-amp * freq * std::cos(freq * p.x) * std::cos(freq * p.z), 1.0,
                           amp * freq * std::sin(freq * p.x) * std::sin(freq * p.z)));
            if (lean > 0.0 && rng.uniform() < 0.5) {
                const double t = lean * 3.14159265358979323846 / 180.0,
                             b = rng.range(0.0, 6.283185307179586);
                nrm = glm::dvec3(std::sin(t) * std::cos(b), std::cos(t), std::sin(t) * std::sin(b));
            }
            m.addVn(nrm);
        }
    leanDeg = lean;
    if (lean > 0.0) {
        char buf[64];
        std::snprintf(buf, sizeof buf, ", normals leaning up to %.1f deg", lean);
        what += buf;
    }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            auto at = [&](int ii, int jj) {
                const int k = jj * (n + 1) + ii;
                return glm::ivec3(k, k, k);
            };
            m.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return m;
}

} // namespace study::stability::detail
