// Table 11's error measure (docs/accuracy-cost.md, section 11): the
// screen-space distance of drawn triangles to a reference surface given as
// a dense mesh with unit normals at its vertices (OpenSubdiv's limit mesh of
// a high uniform level, or a displaced surface tessellated densely).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include <string>

#include "surfgrad/render.h"
#include "surfgrad/render/image.h"
#include "surfgrad/render/view.h"
#include "surfgrad/mesh/render_mesh.h"

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

// Table 11e's frame error: angles (degrees) between two images of vectors
// (tangent or shaded-normal AOVs of two tessellations of one view) at the
// pixels where both see the same sheet of the surface: both covered and
// their geometric (limit) normals, baseA and baseB (base normal AOVs;
// background 0), within kSameSheetDeg. The limit normal is continuous and
// the two tessellations' points at a pixel lie within the chord error of
// each other, so it moves by far less except where an occlusion edge moved
// and the pixel sees another part of the surface (or, at grazing angles,
// nearly so); those pixels are counted in `otherSheet`, not compared.
// Pixels with a non-finite vector in either image are counted in
// `nonFinite`. `deg` is sorted ascending. All four images have one size.
constexpr double kSameSheetDeg = 10.0;
struct DirectionDiff {
    std::vector<double> deg;
    size_t otherSheet = 0, nonFinite = 0;
};
DirectionDiff compareDirections(const sg::render::Image& a, const sg::render::Image& b,
                                const sg::render::Image& baseA, const sg::render::Image& baseB);

// ---- The tessellated-asset view (tables 11 and 13) ----------------------

// A scene of one mesh `file` (absolute path or data:) on the tessellated-
// asset example's camera at `distanceScale`, 960x540, one plain material;
// `subdivision`: the mesh's subdivision object; `extra`: more fields of
// the mesh (e.g. its displacement, starting with a comma).
std::string meshScene(const std::string& file, float distanceScale, const std::string& subdivision,
                      const std::string& extra = "");
// The scene parsed from that text (relative paths against ".").
sg::render::Scene sceneOf(const std::string& json);
// {"mode": "adaptive", "isolation": I, "pixels_per_edge": P}.
std::string adaptiveJson(int isolation, float pixelsPerEdge);

// The displaced surface of the scene's first (adaptive) mesh as the CPU
// tessellator makes it for `view` (detail::tessellatePatches with the
// scene's displacement, the evaluation stage's math), with area-weighted
// vertex normals of its triangles (the displaced surface's, for
// SurfaceReference's tangent planes). cpuMs: the tessellation's time.
sg::mesh::RenderMesh displacedMesh(const sg::render::Scene& s, const sg::render::SceneAssets& a,
                                   const sg::render::View& view, float pixelsPerEdge,
                                   double* cpuMs = nullptr);

} // namespace study
