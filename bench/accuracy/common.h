// Shared pieces of bench_accuracy_cost (docs/accuracy-cost.md): error
// statistics in double, table printing (plain or markdown), and the small
// OpenGL toolkit every GPU table uses (float render targets with read-back,
// mesh upload, a full-screen pass, and the frame timer).
//
// Timing method (docs/platform.md, "Timing on llvmpipe"): llvmpipe skips draws
// that a later opaque draw covers, so each timed frame is exactly one
// clear + draw + glFinish, measured on the wall clock. Variants of one table
// are interleaved frame by frame (A, B, C, A, B, C, ...) so drift from other
// load on the machine hits all of them alike; a variant's time is the median
// over runs of the per-run median frame time, and every ratio is against a
// baseline measured in the same run.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/gl/context.h"
#include "surfgrad/mesh/render_mesh.h"

namespace study {

// ---------------------------------------------------------------------------
// Statistics

struct ErrorStats {
    size_t count = 0;
    double mean = 0, p50 = 0, p90 = 0, p99 = 0, max = 0;
};
// Percentiles by rank (nearest rank) of a sample; an empty sample gives all 0.
ErrorStats errorStats(std::vector<double> values);
double median(std::vector<double> values);

// Angle between two non-zero vectors in degrees, atan2(|a x b|, a.b): accurate
// for tiny and near-180-degree angles alike (acos of a dot product is not).
double angleDeg(const glm::dvec3& a, const glm::dvec3& b);

// ---------------------------------------------------------------------------
// Tables

struct Options;

// What bench/run plots of a table: one figure per table, error (y) against
// cost (x), one point per row whose two cells are numbers ("1.23x" and
// "**1.2**" read as numbers; empty or "(as ...)" cells drop the row), rows
// with the same series cell joined by a line. Columns are header indexes.
struct PlotSpec {
    std::string id; // data file <id>.tsv, figure docs/images/accuracy/<id>.png; empty: no plot
    int xColumn = -1, yColumn = -1;
    int seriesColumn = -1;          // -1: every row its own point, labelled
    std::vector<int> labelColumns;  // point labels (joined by a space)
    bool logX = false, logY = true; // log-log where both span decades
    std::string xLabel, yLabel;     // default: the header cells
};

struct Table {
    std::string title;
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> notes; // printed under the table
    void add(std::vector<std::string> row) { rows.push_back(std::move(row)); }
    PlotSpec plot;
    // Plain: aligned columns. Markdown: a pipe table (docs/accuracy-cost.md).
    void print(bool markdown) const;
    // print(o.markdown), and with o.plotDataDir set, the plot data of
    // `plot` as <plotDataDir>/<plot.id>.tsv (bench/run turns it into a PNG).
    void print(const Options& o) const;
    void writePlotData(const std::string& dir) const;
};

// Fixed-point or scientific, whichever reads better for error magnitudes.
std::string fmtErr(double v);
std::string fmt(double v, int decimals);
std::string fmtRatio(double v); // "1.23x"

// ---------------------------------------------------------------------------
// Options shared by the tables

struct Options {
    bool markdown = false;
    int runs = 7;            // timing runs per variant (interleaved)
    int frames = 8;          // frames per run; each = clear + draw + glFinish
    int size = 1024;         // render size for timings (square)
    bool quick = false;      // smaller sizes and fewer runs (tests, smoke runs)
    std::string renderer;    // GL_RENDERER of the context the tables run in (for the notes)
    std::string plotDataDir; // --plot-data: where Table::print(Options) writes plot data
    std::string imageDir;    // --image-dir: where tables write their pictures; empty: none
};

// ---------------------------------------------------------------------------
// OpenGL toolkit (needs a current context: sg::gl::HeadlessContext)

// An FBO with `colorCount` RGBA32F (or RGBA8) colour attachments and a depth
// buffer, all draw buffers enabled. The colour targets are cleared to
// `clearValue` by clear() so uncovered pixels are recognisable.
class Target {
public:
    Target(int width, int height, int colorCount, bool floatColor = true);
    ~Target();
    Target(const Target&) = delete;
    Target& operator=(const Target&) = delete;
    void bind() const; // binds the FBO and sets the viewport
    void clear(const glm::vec4& clearValue = glm::vec4(0.0f)) const;
    std::vector<glm::vec4> read(int attachment) const; // bottom row first
    int width() const { return width_; }
    int height() const { return height_; }

private:
    int width_, height_, colorCount_;
    unsigned fbo_ = 0, depth_ = 0;
    std::vector<unsigned> color_;
};

// Interleaved vertex buffer of a RenderMesh: location 0 position, 1 normal,
// 2 UV set 0, 3 tangent (vec4; (1,0,0,1) when the mesh has none).
class GpuMesh {
public:
    explicit GpuMesh(const sg::mesh::RenderMesh& mesh);
    ~GpuMesh();
    GpuMesh(const GpuMesh&) = delete;
    GpuMesh& operator=(const GpuMesh&) = delete;
    void draw() const;
    size_t triangles() const { return indexCount_ / 3; }

private:
    unsigned vao_ = 0, vbo_ = 0, ibo_ = 0;
    size_t indexCount_ = 0;
};

// A full-screen triangle (no attributes; the vertex shader uses gl_VertexID).
// The empty VAO it binds is created once per context: construct one
// FullscreenTriangle per context (GL object names are per context).
// fullscreenVertexShader() is the body of its vertex stage for makeProgram:
// the library's sg/render/fullscreen_vs.glsl (output vScreenUv, [0, 1]^2
// over the viewport).
const char* fullscreenVertexShader();
class FullscreenTriangle {
public:
    FullscreenTriangle();
    ~FullscreenTriangle();
    FullscreenTriangle(const FullscreenTriangle&) = delete;
    FullscreenTriangle& operator=(const FullscreenTriangle&) = delete;
    void draw() const;

private:
    unsigned vao_ = 0;
};

// Compiles a vertex + fragment program from GLSL bodies (sg::shaders::assemble:
// `#include "sg/..."` resolves against the embedded library).
sg::gl::Program makeProgram(const std::string& vertexBody, const std::string& fragmentBody,
                            const std::string& name, const std::vector<std::string>& defines = {});

// A 2D float texture (GL_RGBA32F or GL_RG32F / GL_R32F by `channels`) with
// linear filtering and no mip maps; rows bottom first. Returns the GL name.
unsigned makeFloatTexture(int width, int height, int channels, const std::vector<float>& texels,
                          bool repeatS, bool repeatT);
void deleteTexture(unsigned tex);

// Times frames of several variants, interleaved frame by frame (see the
// file comment).
// frame(i) must draw variant i completely (clear + draw); the timer adds
// glFinish. Returns per variant the median over runs of the per-run median
// frame time, in milliseconds.
std::vector<double> timeVariants(size_t variantCount, const std::function<void(size_t)>& frame,
                                 const Options& options);

} // namespace study
