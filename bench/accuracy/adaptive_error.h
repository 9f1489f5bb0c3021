// Table 11's error measure (docs/accuracy-cost.md, section 11): the
// screen-space distance of drawn triangles to a reference surface given as
// a dense mesh with unit normals at its vertices (OpenSubdiv's limit mesh of
// a high uniform level, or a displaced surface tessellated densely).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/render/view.h"
#include "surfgrad/render_mesh.h"

namespace study {

// The reference surface in a hash grid of its vertices (object space). The
// distance of a point p to the surface is taken as |(p - v) . n| for the
// nearest reference vertex v (unit normal n): the surface departs from
// that tangent plane by about r^2 k / 2 over the lateral offset r <= the
// reference's vertex spacing (curvature k), far below the errors measured
// when the spacing is under a pixel.
class SurfaceReference {
public:
    // `mesh`: positions, unit normals and triangles (the cell size is twice
    // the mean length of the triangles' first edges).
    explicit SurfaceReference(const sg::mesh::RenderMesh& mesh);
    // Distance to the surface (object units); -1 when no reference vertex
    // lies in the 27 cells around p (p farther than about a cell).
    float distance(glm::vec3 p) const;

private:
    static uint64_t key(glm::ivec3 c);
    glm::ivec3 cellOf(glm::vec3 p) const { return glm::ivec3(glm::floor(p / cell_)); }
    std::vector<glm::vec3> pos_, nrm_;
    float cell_ = 1.0f;
    std::vector<std::pair<uint64_t, uint32_t>> grid_; // (cell key, vertex), sorted
};

struct ScreenError {
    double p99 = 0.0, max = 0.0; // pixels
    size_t samples = 0;          // points in the view frustum measured
    size_t missed = 0;           // points with no reference vertex near
};

// Screen-space distance (pixels) of the triangles of `mesh` (object space,
// identity model transform) to `ref`, sampled at every triangle's centroid
// and edge midpoints inside the view frustum of `view`: object distance x
// focalPx (focal length in pixels) / the point's depth. At most
// `maxTriangles` triangles, evenly strided.
ScreenError screenError(const SurfaceReference& ref, const sg::mesh::RenderMesh& mesh,
                        const sg::render::View& view, float focalPx, size_t maxTriangles = 400000);

} // namespace study
