// An analytic ground truth for subdivision surfaces: a Catmull-Clark torus
// cage whose every vertex has valence 4 and which has no boundary. Away from
// extraordinary vertices the Catmull-Clark limit surface is the uniform
// bicubic B-spline surface of the control points (Catmull & Clark 1978;
// Stam 1998 evaluates the same patches), so here the limit surface is a
// periodic tensor-product cubic B-spline that this file evaluates in double
// precision without OpenSubdiv: an independent reference for the mesh
// module's refinement, limit frames and tangents, and for the renderer.
//
// Parametrization: cage vertex (i, j), i mod n around the major circle,
// j mod m around the minor circle; face (i, j) has corners (i, j), (i+1, j),
// (i+1, j+1), (i, j+1), counter-clockwise seen from outside, and covers the
// patch a in [i, i+1], b in [j, j+1]. Its one UV set is s = a / n,
// t = b / m (seams at s = 0|1 and t = 0|1), orientation preserving.
// Catmull-Clark refinement and the face-varying rules reproduce linear data,
// so refined and limit UVs stay exactly (s, t) = (a / n, b / m): a point's
// UV names its parameter on the limit surface. bench_accuracy_cost checks
// this against OpenSubdiv's limit positions before trusting it.
#pragma once

#include <glm/glm.hpp>

#include "surfgrad/mesh/polygon_mesh.h"

namespace study {

struct SurfacePoint {
    glm::dvec3 pos;  // object space
    glm::dvec3 dPds; // d(pos)/ds, object units per UV unit
    glm::dvec3 dPdt;
    glm::dvec3 normal; // unit, normalize(dPds x dPdt): outward
};

struct TorusCage {
    int n = 16, m = 8;        // faces around the major / minor circle
    double majorRadius = 1.0; // cage, object units
    double minorRadius = 0.45;

    // Control point (i, j), indices taken modulo n and m. The torus lies in
    // the xy plane, z up.
    glm::dvec3 control(int i, int j) const;
    // The cage: n * m quads, one UV set "st", Catmull-Clark, default rules.
    sg::mesh::PolygonMesh polygonMesh() const;
    // The limit surface at UV (s, t) (any real values: periodic).
    SurfacePoint limit(double s, double t) const;
};

// The Blinn (1978) perturbed normal of a height field h(s, t) displacing
// the surface along its normal, first order in h (curvature terms dropped,
// as Blinn does and as every bump-mapping method assumes): with the surface
// gradient (Mikkelsen 2010, eq. 3)
//   grad_S h = (h_s (dPdt x n) + h_t (n x dPds)) / (n . (dPds x dPdt)),
// the normal is normalize(n - grad_S h). hs, ht: dh/ds, dh/dt in object
// units per UV unit.
glm::dvec3 blinnNormal(const SurfacePoint& p, double hs, double ht);

// The exact orthonormal TBN frame of a parametrized surface point: T along
// dPds (made orthogonal to n), B = n x T (the +t side for an orientation-
// preserving chart). A tangent-space derivative d is "baked against the
// exact frame" from a target normal nt as d = -(nt.T, nt.B) / (nt.n); the
// TBN-style reconstruction normalize(n - d.x T - d.y B) with that exact
// frame then gives nt back exactly (Mikkelsen 2019, eq. 6).
void exactFrame(const SurfacePoint& p, glm::dvec3& tangent, glm::dvec3& bitangent);
glm::dvec2 bakeDerivative(const SurfacePoint& p, const glm::dvec3& targetNormal);

} // namespace study
