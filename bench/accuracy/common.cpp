// Statistics, tables and the GL toolkit of bench_accuracy_cost (common.h).
#include "common.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstddef>
#include <cstdlib>
#include <stdexcept>

#include "surfgrad/shaders/shader_files.h"

namespace study {

ErrorStats errorStats(std::vector<double> v) {
    ErrorStats s;
    s.count = v.size();
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    double sum = 0;
    for (double x : v) sum += x;
    s.mean = sum / double(v.size());
    auto rank = [&](double q) {
        // Nearest rank: the smallest value with at least q of the sample at or below it.
        size_t k = size_t(std::ceil(q * double(v.size())));
        return v[std::min(v.size() - 1, k == 0 ? 0 : k - 1)];
    };
    s.p50 = rank(0.50);
    s.p90 = rank(0.90);
    s.p99 = rank(0.99);
    s.max = v.back();
    return s;
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * (180.0 / M_PI);
}

std::string fmt(double v, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

std::string fmtErr(double v) {
    char buf[64];
    if (v == 0.0) return "0";
    if (std::fabs(v) >= 100.0)
        std::snprintf(buf, sizeof buf, "%.0f", v);
    else if (std::fabs(v) >= 0.1)
        std::snprintf(buf, sizeof buf, "%.3g", v);
    else
        std::snprintf(buf, sizeof buf, "%.2e", v);
    return buf;
}

std::string fmtRatio(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2fx", v);
    return buf;
}

void Table::print(bool markdown) const {
    std::vector<size_t> width(header.size(), 0);
    for (size_t c = 0; c < header.size(); ++c) width[c] = header[c].size();
    for (const auto& r : rows) {
        for (size_t c = 0; c < r.size() && c < width.size(); ++c)
            width[c] = std::max(width[c], r[c].size());
    }
    auto line = [&](const std::vector<std::string>& cells) {
        std::string s = markdown ? "|" : "";
        for (size_t c = 0; c < width.size(); ++c) {
            const std::string cell = c < cells.size() ? cells[c] : "";
            if (markdown) {
                s += " " + cell + std::string(width[c] - cell.size(), ' ') + " |";
            } else {
                // First column left-aligned, numbers right-aligned.
                if (c == 0)
                    s += cell + std::string(width[c] - cell.size(), ' ');
                else
                    s += "  " + std::string(width[c] - cell.size(), ' ') + cell;
            }
        }
        std::printf("%s\n", s.c_str());
    };
    std::printf("\n%s%s\n\n", markdown ? "#### " : "== ", title.c_str());
    line(header);
    if (markdown) {
        std::string s = "|";
        for (size_t c = 0; c < width.size(); ++c)
            s += (c == 0 ? " :" : " ") + std::string(width[c] - 1, '-') + (c == 0 ? " |" : ": |");
        std::printf("%s\n", s.c_str());
    } else {
        size_t total = 0;
        for (size_t c = 0; c < width.size(); ++c) total += width[c] + (c ? 2 : 0);
        std::printf("%s\n", std::string(total, '-').c_str());
    }
    for (const auto& r : rows) line(r);
    if (!notes.empty()) std::printf("\n");
    // Markdown: one list item per note (consecutive lines would merge).
    for (const auto& n : notes) std::printf("%s%s\n", markdown ? "- " : "  ", n.c_str());
    std::fflush(stdout);
}

void Table::print(const Options& o) const {
    print(o.markdown);
    if (!o.plotDataDir.empty()) writePlotData(o.plotDataDir);
}

namespace {

// A table cell as a number: "1.23x", "**3.03x**", "1.5e-03"; false for
// anything else (empty, "(same)", "n/a").
bool cellNumber(std::string cell, double& out) {
    std::string s;
    for (char c : cell)
        if (c != '*' && c != ' ') s += c;
    if (!s.empty() && s.back() == 'x') s.pop_back();
    if (s.empty()) return false;
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size() && std::isfinite(out);
}

std::string tsvCell(std::string s) {
    for (char& c : s)
        if (c == '\t' || c == '\n') c = ' ';
    std::string t;
    for (char c : s)
        if (c != '*') t += c;
    return t;
}

} // namespace

void Table::writePlotData(const std::string& dir) const {
    if (plot.id.empty() || plot.xColumn < 0 || plot.yColumn < 0) return;
    const std::string path = dir + "/" + plot.id + ".tsv";
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + path);
    auto head = [&](int c) { return c >= 0 && size_t(c) < header.size() ? header[size_t(c)] : ""; };
    std::fprintf(f, "#title\t%s\n", tsvCell(title).c_str());
    std::fprintf(f, "#x\t%s\n",
                 tsvCell(plot.xLabel.empty() ? head(plot.xColumn) : plot.xLabel).c_str());
    std::fprintf(f, "#y\t%s\n",
                 tsvCell(plot.yLabel.empty() ? head(plot.yColumn) : plot.yLabel).c_str());
    std::fprintf(f, "#log\t%d\t%d\n", plot.logX ? 1 : 0, plot.logY ? 1 : 0);
    std::fprintf(f, "#series\t%d\n", plot.seriesColumn >= 0 ? 1 : 0);
    for (const auto& r : rows) {
        auto cell = [&](int c) { return c >= 0 && size_t(c) < r.size() ? r[size_t(c)] : ""; };
        double x = 0, y = 0;
        if (!cellNumber(cell(plot.xColumn), x) || !cellNumber(cell(plot.yColumn), y)) continue;
        if ((plot.logX && x <= 0) || (plot.logY && y <= 0)) continue;
        std::string label;
        for (int c : plot.labelColumns) {
            // A label column of numbers reads "level 3"; of words, just the word.
            double unused = 0;
            const std::string v = cellNumber(cell(c), unused) ? head(c) + " " + cell(c) : cell(c);
            label += (label.empty() ? "" : ", ") + v;
        }
        std::fprintf(f, "%s\t%s\t%.9g\t%.9g\n", tsvCell(cell(plot.seriesColumn)).c_str(),
                     tsvCell(label).c_str(), x, y);
    }
    if (std::fclose(f) != 0) throw std::runtime_error("cannot write " + path);
}

// ---------------------------------------------------------------------------

Target::Target(int width, int height, int colorCount, bool floatColor)
    : width_(width), height_(height), colorCount_(colorCount) {
    glCreateFramebuffers(1, &fbo_);
    color_.resize(size_t(colorCount));
    std::vector<GLenum> bufs;
    for (int i = 0; i < colorCount; ++i) {
        glCreateRenderbuffers(1, &color_[size_t(i)]);
        glNamedRenderbufferStorage(color_[size_t(i)], floatColor ? GL_RGBA32F : GL_RGBA8, width,
                                   height);
        glNamedFramebufferRenderbuffer(fbo_, GLenum(GL_COLOR_ATTACHMENT0 + i), GL_RENDERBUFFER,
                                       color_[size_t(i)]);
        bufs.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
    }
    glNamedFramebufferDrawBuffers(fbo_, GLsizei(bufs.size()), bufs.data());
    glCreateRenderbuffers(1, &depth_);
    glNamedRenderbufferStorage(depth_, GL_DEPTH_COMPONENT24, width, height);
    glNamedFramebufferRenderbuffer(fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
    if (glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw sg::gl::GlError("bench_accuracy_cost: framebuffer incomplete");
    }
}

Target::~Target() {
    if (!color_.empty()) glDeleteRenderbuffers(GLsizei(color_.size()), color_.data());
    glDeleteRenderbuffers(1, &depth_);
    glDeleteFramebuffers(1, &fbo_);
}

void Target::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, width_, height_);
}

void Target::clear(const glm::vec4& c) const {
    bind();
    for (int i = 0; i < colorCount_; ++i) glClearNamedFramebufferfv(fbo_, GL_COLOR, i, &c[0]);
    const float one = 1.0f;
    glClearNamedFramebufferfv(fbo_, GL_DEPTH, 0, &one);
}

std::vector<glm::vec4> Target::read(int attachment) const {
    std::vector<glm::vec4> px(size_t(width_) * size_t(height_));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    glReadBuffer(GLenum(GL_COLOR_ATTACHMENT0 + attachment));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, px.data());
    sg::gl::checkError("Target::read");
    return px;
}

// ---------------------------------------------------------------------------

namespace {
struct PackedVertex {
    float pos[3], nrm[3], uv[2], tan[4];
};
} // namespace

GpuMesh::GpuMesh(const sg::mesh::RenderMesh& mesh) {
    std::vector<PackedVertex> v(mesh.vertexCount());
    for (size_t i = 0; i < v.size(); ++i) {
        const glm::vec3 p = mesh.positions[i];
        const glm::vec3 n = mesh.normals.empty() ? glm::vec3(0, 0, 1) : mesh.normals[i];
        const glm::vec2 uv = mesh.uvSets.empty() ? glm::vec2(0) : mesh.uvSets[0][i];
        const glm::vec4 t = mesh.tangents.empty() ? glm::vec4(1, 0, 0, 1) : mesh.tangents[i];
        v[i] = {{p.x, p.y, p.z}, {n.x, n.y, n.z}, {uv.x, uv.y}, {t.x, t.y, t.z, t.w}};
    }
    indexCount_ = mesh.indices.size();
    glCreateVertexArrays(1, &vao_);
    glCreateBuffers(1, &vbo_);
    glCreateBuffers(1, &ibo_);
    glNamedBufferData(vbo_, GLsizeiptr(v.size() * sizeof(PackedVertex)), v.data(), GL_STATIC_DRAW);
    glNamedBufferData(ibo_, GLsizeiptr(mesh.indices.size() * sizeof(uint32_t)), mesh.indices.data(),
                      GL_STATIC_DRAW);
    glVertexArrayVertexBuffer(vao_, 0, vbo_, 0, sizeof(PackedVertex));
    glVertexArrayElementBuffer(vao_, ibo_);
    const GLuint offsets[] = {offsetof(PackedVertex, pos), offsetof(PackedVertex, nrm),
                              offsetof(PackedVertex, uv), offsetof(PackedVertex, tan)};
    const GLint sizes[] = {3, 3, 2, 4};
    for (GLuint a = 0; a < 4; ++a) {
        glEnableVertexArrayAttrib(vao_, a);
        glVertexArrayAttribFormat(vao_, a, sizes[a], GL_FLOAT, GL_FALSE, offsets[a]);
        glVertexArrayAttribBinding(vao_, a, 0);
    }
}

GpuMesh::~GpuMesh() {
    glDeleteVertexArrays(1, &vao_);
    glDeleteBuffers(1, &vbo_);
    glDeleteBuffers(1, &ibo_);
}

void GpuMesh::draw() const {
    glBindVertexArray(vao_);
    glDrawElements(GL_TRIANGLES, GLsizei(indexCount_), GL_UNSIGNED_INT, nullptr);
}

const char* fullscreenVertexShader() {
    return "#include \"sg/render/fullscreen_vs.glsl\"\n";
}

FullscreenTriangle::FullscreenTriangle() {
    glCreateVertexArrays(1, &vao_);
}
FullscreenTriangle::~FullscreenTriangle() {
    glDeleteVertexArrays(1, &vao_);
}
void FullscreenTriangle::draw() const {
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

sg::gl::Program makeProgram(const std::string& vertexBody, const std::string& fragmentBody,
                            const std::string& name, const std::vector<std::string>& defines) {
    using sg::gl::Stage;
    return sg::gl::Program(
        {{Stage::Vertex, sg::shaders::assemble(vertexBody, name + "_vs", defines)},
         {Stage::Fragment, sg::shaders::assemble(fragmentBody, name + "_fs", defines)}});
}

unsigned makeFloatTexture(int width, int height, int channels, const std::vector<float>& texels,
                          bool repeatS, bool repeatT) {
    const GLenum internal = channels == 1 ? GL_R32F : channels == 2 ? GL_RG32F : GL_RGBA32F;
    const GLenum format = channels == 1 ? GL_RED : channels == 2 ? GL_RG : GL_RGBA;
    GLuint tex = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &tex);
    glTextureStorage2D(tex, 1, internal, width, height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(tex, 0, 0, 0, width, height, format, GL_FLOAT, texels.data());
    glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_S, repeatS ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_T, repeatT ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    sg::gl::checkError("makeFloatTexture");
    return tex;
}

void deleteTexture(unsigned tex) {
    GLuint t = tex;
    glDeleteTextures(1, &t);
}

std::vector<double> timeVariants(size_t count, const std::function<void(size_t)>& frame,
                                 const Options& o) {
    using Clock = std::chrono::steady_clock;
    // Warm-up: shader JIT, first texture/buffer use.
    for (size_t v = 0; v < count; ++v) {
        frame(v);
        glFinish();
    }
    std::vector<std::vector<double>> perRun(count);
    for (int r = 0; r < o.runs; ++r) {
        // Frame-level interleaving (A B C A B C ...): load from other
        // processes changes within a second on a shared machine, so every
        // variant samples the same moments.
        std::vector<std::vector<double>> t(count);
        for (int f = 0; f < o.frames; ++f) {
            for (size_t v = 0; v < count; ++v) {
                const auto t0 = Clock::now();
                frame(v);
                glFinish();
                t[v].push_back(
                    std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
            }
        }
        for (size_t v = 0; v < count; ++v) perRun[v].push_back(median(t[v]));
    }
    std::vector<double> out;
    for (auto& v : perRun) out.push_back(median(v));
    return out;
}

} // namespace study
