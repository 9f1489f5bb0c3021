// The inputs of the stability cases (stability.h): a deterministic random
// source, meshes written as OBJ files (so the renderer reads them as it
// reads a user's file), rounding-size perturbations in binary32 ulps, and
// the scene JSON around one mesh. Internal to bench/accuracy/stability*.cpp.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/render.h"

namespace study::stability::detail {

namespace fs = std::filesystem;

// x moved by `ulps` units in the last place of binary32 at max(|x|, 0.5):
// a change the file's reader sees (values are written to round-trip
// binary32), of the size rounding gives a coordinate of that magnitude.
double moveUlps(double x, int ulps);

// A small deterministic generator (splitmix64): the same cases on every
// platform and standard library.
struct Rng {
    uint64_t s;
    uint64_t next() {
        uint64_t z = (s += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
    double range(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    int integer(int lo, int hi) { return lo + int(next() % uint64_t(hi - lo + 1)); }
};

struct ObjMesh {
    std::vector<glm::dvec3> v, vn;
    std::vector<glm::dvec2> vt;
    // Faces: per corner (position, uv, normal) indices, -1 for none.
    std::vector<std::vector<glm::ivec3>> faces;

    int addV(glm::dvec3 p) {
        v.push_back(p);
        return int(v.size()) - 1;
    }
    int addVt(glm::dvec2 t) {
        vt.push_back(t);
        return int(vt.size()) - 1;
    }
    int addVn(glm::dvec3 n) {
        vn.push_back(n);
        return int(vn.size()) - 1;
    }
    // Every coordinate of the chosen arrays moved by -2..2 ulps (seeded).
    void perturb(uint64_t seed, bool positions, bool uvs, bool normals) {
        Rng rng{seed};
        if (positions)
            for (auto& p : v)
                for (int c = 0; c < 3; ++c) p[c] = moveUlps(p[c], rng.integer(-2, 2));
        if (uvs)
            for (auto& t : vt)
                for (int c = 0; c < 2; ++c) t[c] = moveUlps(t[c], rng.integer(-2, 2));
        if (normals)
            for (auto& n : vn)
                for (int c = 0; c < 3; ++c) n[c] = moveUlps(n[c], rng.integer(-2, 2));
    }
    void write(const fs::path& file) const {
        std::ofstream o(file);
        char buf[128];
        for (const auto& p : v) {
            std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\n", float(p.x), float(p.y),
                          float(p.z));
            o << buf;
        }
        for (const auto& t : vt) {
            std::snprintf(buf, sizeof buf, "vt %.9g %.9g\n", float(t.x), float(t.y));
            o << buf;
        }
        for (const auto& n : vn) {
            std::snprintf(buf, sizeof buf, "vn %.9g %.9g %.9g\n", float(n.x), float(n.y),
                          float(n.z));
            o << buf;
        }
        for (const auto& f : faces) {
            o << "f";
            for (const auto& c : f) {
                o << " " << c.x + 1;
                if (c.y >= 0 || c.z >= 0) o << "/";
                if (c.y >= 0) o << c.y + 1;
                if (c.z >= 0) o << "/" << c.z + 1;
            }
            o << "\n";
        }
        if (!o.good()) throw std::runtime_error("cannot write " + file.string());
    }
};

// A scene of one mesh (its JSON fields) under one material of `layers`,
// seen from `eye` towards `target`.
struct SceneSpec {
    std::string meshFields;    // e.g. "\"file\": \"...\""
    std::string layers;        // the material's layers array content
    std::string materialExtra; // more material fields, each with a trailing comma
    glm::dvec3 eye{0.0, 0.0, 3.0};
    glm::dvec3 target{0.0};
    double fovDeg = 40.0;
    double nearPlane = 0.05, farPlane = 50.0;
    std::string transform; // the mesh's "transform" object, or empty
};

// x with 17 significant digits (JSON).
std::string num(double x);
// A JSON array of three numbers.
std::string vec3Json(glm::dvec3 v);

// The scene of `s`, parsed as if read from dir/scene.json.
sg::render::Scene sceneOf(const SceneSpec& s, const fs::path& dir);

// Writes m as dir/<name>.obj and returns the scene's "file" field for it.
std::string fileField(const ObjMesh& m, const fs::path& dir, const std::string& name);

// One triangle facing +z whose UVs are (s0,0), (s0,1), (s0,1): a chart
// collapsed to a segment (s is constant, t runs along one edge only).
ObjMesh collapsedTriangle(double s0);

// An open cylinder (radius 0.5, y in [-0.5, 0.5], `segments` quads around,
// `rows` quads high) with a top cap, UVs projected from the top:
// (s, t) = (0.5 + x, 0.5 - z). The walls' UV chart is singular (t and s do
// not change along y); the cap's is regular. Quads (a subdivision cage),
// the cap a fan of triangles.
ObjMesh topProjectedCylinder(int segments, int rows);

// A grid of n x n quads over [-1, 1]^2 in the plane y = 0 (UVs [0, 1]^2,
// s along +x, t along -z), every vertex normal `normal`.
ObjMesh grid(int n, glm::dvec3 normal);

// The top-projected cylinder with its walls' projection tilted by `tilt`
// (t += tilt * y): 0 is singular, small values near-singular.
ObjMesh tiltedCylinder(double tilt);

// A grid whose UVs are collinear on every triangle: (s, t) = (u, u).
ObjMesh collinearGrid();

// A grid whose vertex normals alternate, checkerwise, between the face
// normal and 150 degrees from it (behind the surface): normals that flip.
ObjMesh flippingNormalsGrid();

// A grid mirrored in s across x = 0 (a UV seam in the middle).
ObjMesh mirroredGrid();

// A fan of needles: a disk of 720 triangles (0.5 degrees each) around the
// origin in the plane y = 0, UVs the planar projection.
ObjMesh needleFan();

// A grid with every third quad collapsed to a segment (two corners moved
// onto the other two): zero-area triangles amid ordinary ones.
ObjMesh zeroAreaGrid();

// A closed cage with two poles of valence `valence` (a sphere of `valence`
// segments and 4 rings, triangle fans at the poles), UVs the sphere's.
ObjMesh poleCage(int valence);

// A random height-field grid with a random chart, normals and damage (see
// generatedCases); `what` describes it.
// `uvsOffset`: its UVs were offset by about 1e4 (stored to 1e-3 there);
// `leanDeg`: how far some vertex normals lean from the surface (0: none).
ObjMesh randomMesh(Rng& rng, std::string& what, bool& uvsOffset, double& leanDeg);

} // namespace study::stability::detail
