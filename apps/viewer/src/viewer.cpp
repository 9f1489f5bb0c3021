// The interactive viewer (see surfgrad/viewer.h): GLFW window, the shared
// GlRenderer into its float framebuffer, a display pass (tone mapping or
// vector encoding, the same sgToneMap the PNG writer uses), Dear ImGui.
#include <epoxy/gl.h>
// epoxy first: GLFW must not include its own GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/base/io.h"
#include "surfgrad/shaders/shader_files.h"
#include "surfgrad/viewer.h"

namespace sg::render {

namespace {

// Fullscreen display of the renderer's RGBA32F target: colour through the
// display transform, vectors as 0.5 v + 0.5, uv as fract(uv).
const char* kDisplayVs = "#include \"sg/render/fullscreen_vs.glsl\"\n";
const char* kDisplayFs = R"(
#include "sg/render/shading.glsl"
in vec2 vScreenUv;
uniform sampler2D uImage;
uniform int uAov;
uniform float uExposure;
layout(location = 0) out vec4 outColor;
void main() {
    vec4 v = texture(uImage, vScreenUv);
    vec3 c;
    if (uAov == SG_AOV_COLOR) c = sgToneMap(v.xyz, uExposure);
    else if (uAov == SG_AOV_UV) c = vec3(fract(v.xy), 0.0);
    else if (uAov == SG_AOV_PRIM_ID) c = vec3(fract(v.x * 0.618034), fract(v.x * 0.41421), fract(v.x * 0.7320508));
    else if (uAov == 8) { // patch AOV: a colour per patch, brighter with its level
        if (v.z == 6.0 || v.z == 9.0) {
            float lit = 1.0 / 3.0 + 2.0 / 3.0 * log2(max(v.y, 1.0)) / 6.0;
            c = vec3(fract(v.x * 0.618034), fract(v.x * 0.41421), fract(v.x * 0.7320508)) *
                (0.25 + 0.75 * lit);
        } else {
            c = sgToneMap(v.xyz, uExposure); // meshes drawn as triangles: their colour
        }
    }
    else c = 0.5 * v.xyz + 0.5;
    outColor = vec4(c, 1.0);
}
)";

struct Orbit {
    glm::dvec3 target{0.0}; // world, binary64
    float distance = 5.0f, azimuthDeg = 30.0f, elevationDeg = 20.0f, fovDeg = 35.0f;
    float radius = 1.0f; // scene radius: near/far planes
};

Orbit orbitFromScene(const Scene& scene, const SceneAssets& assets, int w, int h) {
    View v = makeView(scene, assets, w, h);
    glm::vec3 lo, hi;
    sceneBounds(scene, assets, lo, hi);
    Orbit o;
    o.radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    o.target =
        scene.camera.automatic ? 0.5 * (glm::dvec3(lo) + glm::dvec3(hi)) : scene.camera.target;
    const glm::vec3 d(v.cameraPos - o.target);
    o.distance = std::max(glm::length(d), 1e-3f);
    glm::vec3 dir = d / o.distance;
    o.elevationDeg = glm::degrees(std::asin(std::clamp(dir.y, -1.0f, 1.0f)));
    o.azimuthDeg = glm::degrees(std::atan2(dir.x, dir.z));
    o.fovDeg = scene.camera.fovDeg;
    return o;
}

View orbitView(const Orbit& o, int w, int h, Aov aov) {
    float nearP = std::max(o.distance - 2.0f * o.radius, o.distance * 1e-3f);
    float farP = o.distance + 3.0f * o.radius;
    return makeOrbitView(o.target, o.distance, o.azimuthDeg, o.elevationDeg, o.fovDeg, nearP, farP,
                         w, h, aov);
}

struct Glfw {
    GLFWwindow* window = nullptr;
    Glfw(int w, int h, const std::string& title) {
        glfwSetErrorCallback(
            [](int code, const char* msg) { std::fprintf(stderr, "glfw %d: %s\n", code, msg); });
        if (!glfwInit())
            throw sg::gl::GlError("viewer: glfwInit failed (no X display? use xvfb-run)");
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        window = glfwCreateWindow(w, h, title.c_str(), nullptr, nullptr);
        if (!window) {
            glfwTerminate();
            throw sg::gl::GlError("viewer: cannot create a window with an OpenGL 4.5 core context");
        }
        glfwMakeContextCurrent(window);
        glfwSwapInterval(1);
    }
    ~Glfw() {
        if (window) glfwDestroyWindow(window);
        glfwTerminate();
    }
};

struct ImGuiScope {
    explicit ImGuiScope(GLFWwindow* w) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr; // no imgui.ini next to the user's files
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(w, true);
        ImGui_ImplOpenGL3_Init("#version 450");
    }
    ~ImGuiScope() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
};

// Width of a slider next to a checkbox in the narrow panel: the rest of
// the row less room for its label.
float sliderWidth() {
    return std::clamp(ImGui::GetContentRegionAvail().x - 80.0f, 40.0f, 140.0f);
}

// The per-layer controls: an on/off box per layer, then a slider per entry
// of the kind's parameter table that has one (the doc line as tooltip);
// groups list their layers indented. Returns true when the program set may
// change (a layer toggled), so missing textures are loaded.
bool layerControls(std::vector<Layer>& layers, const std::string& idPrefix) {
    bool toggled = false;
    for (size_t i = 0; i < layers.size(); ++i) {
        Layer& L = layers[i];
        ImGui::PushID((idPrefix + std::to_string(i)).c_str());
        toggled |= ImGui::Checkbox(layerKindName(L.kind), &L.enabled);
        if (layerIsGroup(L)) {
            ImGui::Indent();
            toggled |= layerControls(L.children, idPrefix + std::to_string(i) + "/");
            ImGui::Unindent();
        }
        bool first = true;
        for (const LayerSlider& p : layerSliders(L)) {
            if (first) ImGui::SameLine();
            first = false;
            ImGui::SetNextItemWidth(sliderWidth());
            ImGui::SliderFloat(p.name, p.value, p.lo, p.hi, p.format);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", p.doc);
        }
        ImGui::PopID();
    }
    return toggled;
}

// Orbit camera from the mouse (unless ImGui wants it): left drag orbits,
// right drag and the wheel zoom, middle drag pans.
void orbitFromMouse(Orbit& orbit, const Orbit& home, int fbw, int fbh) {
    ImGuiIO& io = ImGui::GetIO();
    if (io.WantCaptureMouse) return;
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
        orbit.azimuthDeg -= 0.3f * io.MouseDelta.x;
        orbit.elevationDeg = std::clamp(orbit.elevationDeg + 0.3f * io.MouseDelta.y, -89.0f, 89.0f);
    }
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Right))
        orbit.distance *= std::exp(0.01f * io.MouseDelta.y);
    if (io.MouseWheel != 0.0f) orbit.distance *= std::exp(-0.1f * io.MouseWheel);
    if (ImGui::IsMouseDragging(ImGuiMouseButton_Middle)) {
        View v = orbitView(orbit, fbw, fbh, Aov::Color);
        glm::vec3 right(v.view[0][0], v.view[1][0], v.view[2][0]),
            up(v.view[0][1], v.view[1][1], v.view[2][1]);
        float k = orbit.distance * 0.002f;
        orbit.target += glm::dvec3(k * (-io.MouseDelta.x * right + io.MouseDelta.y * up));
    }
    orbit.distance = std::clamp(orbit.distance, 1e-3f * home.distance, 100.0f * home.distance);
}

// The renderer's float target through the display transform.
struct DisplayPass {
    sg::gl::Program program;
    GLuint emptyVao = 0;

    DisplayPass()
        : program(
              {{sg::gl::Stage::Vertex, sg::shaders::assemble(kDisplayVs, "(viewer display vs)")},
               {sg::gl::Stage::Fragment,
                sg::shaders::assemble(kDisplayFs, "(viewer display fs)")}}) {
        glCreateVertexArrays(1, &emptyVao);
    }
    ~DisplayPass() { glDeleteVertexArrays(1, &emptyVao); }
    DisplayPass(const DisplayPass&) = delete;
    DisplayPass& operator=(const DisplayPass&) = delete;

    void draw(GLuint tex, int fbw, int fbh, int aovIndex, float exposure) const {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, fbw, fbh);
        glDisable(GL_DEPTH_TEST);
        glDisable(GL_CULL_FACE);
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        if (!tex) return;
        glUseProgram(program.id());
        glBindTextureUnit(0, tex);
        glUniform1i(program.uniform("uImage"), 0);
        glUniform1i(program.uniform("uAov"), aovIndex);
        glUniform1f(program.uniform("uExposure"), exposure);
        glBindVertexArray(emptyVao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glBindVertexArray(0);
        glUseProgram(0);
    }
};

// What the panel edits besides the scene.
struct ViewerState {
    Orbit orbit, home;
    int aovIndex = 0;
    bool playing = false;
    float time = 0.0f;
    bool morphOverride = false;
    std::vector<std::vector<float>> morphWeights;
    std::string status;
    double frameMs = 0.0;
    bool screenshotNow = false;
    bool wireframe = false; // polygon mode GL_LINE for the scene's draws
};

// Adaptive meshes: their patches and the tessellation target, live (the
// levels follow it the next frame; the patch AOV shows each patch's level).
void adaptiveControls(Scene& scene, const SceneAssets& assets) {
    for (size_t i = 0; i < scene.meshes.size() && i < assets.meshes.size(); ++i) {
        const auto& patches = assets.meshes[i].patches;
        if (!patches) continue;
        MeshInstance& mi = scene.meshes[i];
        ImGui::PushID(int(1000 + i));
        ImGui::TextWrapped("%s: adaptive, %zu patches, isolation %d",
                           (mi.name.empty() ? mi.fieldPath : mi.name).c_str(),
                           patches->patchCount(), mi.subdivIsolation);
        ImGui::SliderFloat("px per edge", &mi.subdivPixelsPerEdge, 0.5f, 64.0f, "%.1f",
                           ImGuiSliderFlags_Logarithmic);
        ImGui::PopID();
    }
}

// Materials: double-sided mode, base colour, roughness, the layers.
// Returns true when a layer was toggled.
bool materialControls(Scene& scene) {
    bool toggled = false;
    for (size_t m = 0; m < scene.materials.size(); ++m) {
        Material& mat = scene.materials[m];
        ImGui::PushID(int(m));
        if (ImGui::CollapsingHeader(("material " + mat.name).c_str(),
                                    ImGuiTreeNodeFlags_DefaultOpen)) {
            int ds = int(mat.doubleSided);
            static const char* modes[] = {"off (cull)", "none", "mirror", "flip"};
            if (ImGui::Combo("double-sided", &ds, modes, IM_ARRAYSIZE(modes)))
                mat.doubleSided = DoubleSided(ds);
            ImGui::ColorEdit3("base colour", &mat.baseColor[0]);
            ImGui::SliderFloat("roughness", &mat.roughness, 0.02f, 1.0f);
            toggled |= layerControls(mat.layers, "L");
        }
        ImGui::PopID();
    }
    return toggled;
}

// Blendshapes: playback, time, weights by hand (the mesh once, then one
// slider per target, by its name).
void morphControls(Scene& scene, SceneAssets& assets, ViewerState& st) {
    bool anyMorph = false;
    for (const auto& a : assets.meshes) anyMorph |= morphTargetCount(a) > 0;
    if (!anyMorph || !ImGui::CollapsingHeader("blendshapes", ImGuiTreeNodeFlags_DefaultOpen))
        return;
    ImGui::Checkbox("play", &st.playing);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(160);
    ImGui::SliderFloat("time (s)", &st.time, 0.0f,
                       std::max(1.0f, float(scene.frameCount) / scene.fps));
    ImGui::Checkbox("set weights by hand", &st.morphOverride);
    for (size_t i = 0; i < scene.meshes.size(); ++i) {
        auto& w = st.morphWeights[i];
        if (!w.empty())
            ImGui::TextWrapped("%s", (scene.meshes[i].name.empty() ? scene.meshes[i].fieldPath
                                                                   : scene.meshes[i].name)
                                         .c_str());
        for (size_t t = 0; t < w.size(); ++t) {
            ImGui::PushID(int(i * 1000 + t));
            std::string label = morphTargetLabel(assets.meshes[i], t);
            if (ImGui::SliderFloat(label.c_str(), &w[t], 0.0f, 1.0f) && st.morphOverride) {
                scene.meshes[i].morphKeys.clear();
                scene.meshes[i].morphWeights = w;
            }
            ImGui::PopID();
        }
    }
    if (st.morphOverride) applyFrame(scene, assets, st.time);
}

// The panel, docked narrow at the right edge, full height, collapsible to
// its title bar (viewerPanelWidth: 288 px of a 960 px window); nothing when
// `show` is false (--no-ui). Returns true when a layer was toggled.
bool panel(Scene& scene, SceneAssets& assets, const GlRenderer& renderer, ViewerState& st, int fbw,
           int fbh, bool show) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const float panelW = viewerPanelWidth(fbw);
    ImGui::SetNextWindowPos(ImVec2(float(fbw) - panelW, 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(panelW, float(fbh)), ImGuiCond_Always);
    bool toggled = false;
    if (show &&
        ImGui::Begin("surfgrad", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize)) {
        ImGui::PushItemWidth(-100.0f); // room for the labels
        ImGui::TextWrapped("%s", scene.sourceName.c_str());
        ImGui::TextWrapped("%s", viewerTimingText(st.frameMs, renderer.stats()).c_str());
        ImGui::Text("%zu programs cached", renderer.cachedPrograms());
        static const char* aovs[] = {"color",      "normal", "surfgrad", "tangent", "bitangent",
                                     "basenormal", "uv",     "primid",   "patch"};
        ImGui::Combo("AOV", &st.aovIndex, aovs, IM_ARRAYSIZE(aovs));
        ImGui::SliderFloat("exposure", &scene.output.exposure, 0.05f, 8.0f, "%.2f",
                           ImGuiSliderFlags_Logarithmic);
        if (ImGui::Button("reset camera")) st.orbit = st.home;
        ImGui::SameLine();
        if (ImGui::Button("screenshot")) st.screenshotNow = true;
        ImGui::Checkbox("wireframe", &st.wireframe);
        adaptiveControls(scene, assets);
        toggled = materialControls(scene);
        morphControls(scene, assets, st);
        if (!st.status.empty()) ImGui::TextWrapped("%s", st.status.c_str());
        ImGui::PopItemWidth();
    }
    if (show) ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    return toggled;
}

// --screenshot with --frames: the whole window as shown (render, display
// pass and, unless --no-ui, the panel), read from the back buffer.
void windowScreenshot(const std::filesystem::path& file, int fbw, int fbh) {
    Image img(fbw, fbh, 4);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, fbw, fbh, GL_RGBA, GL_FLOAT, img.samples.data());
    writeDisplayImage(file, img);
}

} // namespace

int runViewer(Scene scene, const ViewerOptions& opt) {
    Glfw glfw(opt.width, opt.height, opt.title);
    AssetOptions assetOptions;
    assetOptions.textureBudgetBytes = opt.textureBudgetBytes;
    SceneAssets assets = loadAssets(scene, assetOptions);
    GlRenderer renderer;
    ImGuiScope imgui(glfw.window);
    DisplayPass display;

    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(glfw.window, &fbw, &fbh);
    ViewerState st;
    st.orbit = orbitFromScene(scene, assets, std::max(fbw, 1), std::max(fbh, 1));
    st.home = st.orbit;
    st.playing = scene.frameCount > 1;
    st.morphWeights.resize(scene.meshes.size());
    for (size_t i = 0; i < scene.meshes.size(); ++i)
        st.morphWeights[i] = assets.meshes[i].appliedWeights;
    auto last = std::chrono::steady_clock::now();
    std::filesystem::path screenshotPath =
        opt.screenshot.empty() ? std::filesystem::path("out/view.png") : opt.screenshot;

    for (int frame = 0; !glfwWindowShouldClose(glfw.window); ++frame) {
        if (opt.maxFrames > 0 && frame >= opt.maxFrames) break;
        glfwPollEvents();
        auto now = std::chrono::steady_clock::now();
        float dt = std::chrono::duration<float>(now - last).count();
        st.frameMs = 1000.0 * double(dt);
        last = now;
        glfwGetFramebufferSize(glfw.window, &fbw, &fbh);
        if (fbw < 1 || fbh < 1) continue; // minimised
        orbitFromMouse(st.orbit, st.home, fbw, fbh);

        // Animation.
        if (st.playing) st.time += dt;
        if (!st.morphOverride) {
            applyFrame(scene, assets, st.time);
            for (size_t i = 0; i < scene.meshes.size(); ++i)
                st.morphWeights[i] = assets.meshes[i].appliedWeights;
        }

        View view = orbitView(st.orbit, fbw, fbh, Aov(st.aovIndex));
        GLuint tex = 0;
        glPolygonMode(GL_FRONT_AND_BACK, st.wireframe ? GL_LINE : GL_FILL);
        try {
            tex = renderer.renderToTexture(scene, assets, view);
        } catch (const std::exception& e) {
            st.status = e.what();
        }
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        if (st.screenshotNow) { // the panel's button: the render, without the panel
            Image img = renderer.render(scene, assets, view);
            writeImage(screenshotPath, img, view.aov, scene.output.exposure);
            st.status = "wrote " + screenshotPath.string();
            st.screenshotNow = false;
        }
        display.draw(tex, fbw, fbh, st.aovIndex, scene.output.exposure);
        bool toggled = panel(scene, assets, renderer, st, fbw, fbh, opt.panel);
        if (frame + 1 == opt.maxFrames && !opt.screenshot.empty())
            windowScreenshot(opt.screenshot, fbw, fbh);
        glfwSwapBuffers(glfw.window);

        if (toggled) {
            try {
                loadMissingAssets(scene, assets);
            } catch (const std::exception& e) {
                st.status = e.what();
            }
        }
    }
    if (!opt.screenshot.empty() && opt.maxFrames == 0) {
        // Closed by the user: the last view goes to the screenshot file.
        glfwGetFramebufferSize(glfw.window, &fbw, &fbh);
        if (fbw > 0 && fbh > 0) {
            View view = orbitView(st.orbit, fbw, fbh, Aov(st.aovIndex));
            writeImage(opt.screenshot, renderer.render(scene, assets, view), view.aov,
                       scene.output.exposure);
        }
    }
    return 0;
}

} // namespace sg::render
