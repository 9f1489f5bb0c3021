// The three.js example (examples/web, docs/engines.md "three.js") in a real
// browser: Debian's Chromium, headless, WebGL2 on SwiftShader, driven by
// puppeteer-core through the DevTools protocol (examples/web/capture.mjs).
// The page must load with no console error, page error or failed request,
// and its normal view (the model's normal map on UV set 0 with per-pixel
// frames, drawn by three.js with the GLSL ES 3.00 library) must agree with
// surfgrad's own renderer drawing the same glTF model from the same camera
// at the same size (the normal AOV of `surfgrad render`, here in process).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "cli.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/render/assets.h"
#include "surfgrad/render/renderer.h"
#include "surfgrad/render/scene.h"

namespace {

namespace fs = std::filesystem;
using namespace sg::render;

const fs::path kSource = SURFGRAD_SOURCE_DIR;

struct Capture {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba; // top row first
};

// Runs the page with URL parameters `query`; fails the test (and returns
// an empty capture) when the page reports a problem.
Capture capturePage(const std::string& query) {
    const fs::path web = kSource / "examples" / "web";
    if (!fs::exists(web / "node_modules" / "puppeteer-core")) {
        ADD_FAILURE() << "examples/web/node_modules is missing: run scripts/setup-deps "
                         "(npm ci in examples/web)";
        return {};
    }
    const fs::path out = sg::test::processScratchDir("surfgrad_web") / "page.rgba";
    const auto r = sg::test::runCommand(
        sg::test::shellQuote(std::string(SURFGRAD_NODE)) + " " +
        sg::test::shellQuote(web / "capture.mjs") + " --chromium " +
        sg::test::shellQuote(std::string(SURFGRAD_CHROMIUM)) + " --shaders " +
        sg::test::shellQuote(fs::path(SURFGRAD_BINARY_DIR) / "shaders" / "flat") + " --query " +
        sg::test::shellQuote(query) + " --out " + sg::test::shellQuote(out));
    EXPECT_EQ(r.exitCode, 0) << r.output();
    Capture c;
    std::ifstream in(out, std::ios::binary);
    if (r.exitCode != 0 || !in) return c;
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    if (bytes.size() < 8) return c;
    auto u32 = [&](size_t at) {
        return uint32_t(bytes[at]) | uint32_t(bytes[at + 1]) << 8 | uint32_t(bytes[at + 2]) << 16 |
               uint32_t(bytes[at + 3]) << 24;
    };
    c.width = int(u32(0));
    c.height = int(u32(4));
    c.rgba.assign(bytes.begin() + 8, bytes.end());
    EXPECT_EQ(c.rgba.size(), size_t(c.width) * size_t(c.height) * 4);
    return c;
}

// The page's default layers, blends and views all draw without an error.
TEST(WebPage, LoadsWithoutErrorsInEveryMode) {
    for (const char* query : {"size=160x120&panel=0", "size=160x120&blend=whiteout",
                              "size=160x120&blend=udn", "size=160x120&blend=rnm&view=normal"}) {
        SCOPED_TRACE(query);
        const Capture c = capturePage(query);
        ASSERT_EQ(c.width, 160);
        ASSERT_EQ(c.height, 120);
        // The model covers part of the canvas (alpha 255), the rest is clear.
        size_t covered = 0;
        for (size_t i = 3; i < c.rgba.size(); i += 4) covered += c.rgba[i] == 255;
        EXPECT_GT(covered, 1000u);
        EXPECT_LT(covered, size_t(160 * 120));
    }
}

// Normal view of NormalTangentTest (its normal map on UV set 0, per-pixel
// frames, mirror mode for its double-sided material) in the browser against
// the renderer's normal AOV, same camera and size.
TEST(WebPage, NormalViewAgreesWithTheRenderer) {
    const int w = 320, h = 240;
    const glm::dvec3 eye(0.45, 0.35, 2.7), target(0.0, -0.1, 0.0);
    const float fov = 45.0f, nearP = 0.5f, farP = 10.0f;
    std::ostringstream query;
    query << "size=" << w << "x" << h << "&panel=0&view=normal&layers=base&camera=" << eye.x << ","
          << eye.y << "," << eye.z << "," << target.x << "," << target.y << "," << target.z << ","
          << fov << "," << nearP << "," << farP;
    const Capture page = capturePage(query.str());
    ASSERT_EQ(page.width, w);
    ASSERT_EQ(page.height, h);

    Scene s = sceneForModel(kSource / "data/gltf/NormalTangentTest/glTF/NormalTangentTest.gltf");
    s.camera.automatic = false;
    s.camera.position = eye;
    s.camera.target = target;
    s.camera.fovDeg = fov;
    s.camera.nearPlane = nearP;
    s.camera.farPlane = farP;
    sg::gl::HeadlessContext ctx;
    const SceneAssets assets = loadAssets(s);
    GlRenderer gpu;
    const Image ours = gpu.render(s, assets, makeView(s, assets, w, h, Aov::Normal));

    std::vector<double> angles;
    size_t onlyOne = 0, farOff = 0; // farOff: pixels more than 20 degrees apart
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const uint8_t* p = &page.rgba[(size_t(y) * size_t(w) + size_t(x)) * 4];
            const glm::vec4 o = ours.rgba(x, h - 1 - y); // ours: bottom row first
            const bool inPage = p[3] == 255;
            const bool inOurs = glm::length(glm::vec3(o)) > 0.5f;
            if (inPage != inOurs) {
                ++onlyOne;
                continue;
            }
            if (!inPage) continue;
            const glm::dvec3 a = glm::normalize(glm::dvec3(p[0], p[1], p[2]) / 127.5 - 1.0);
            const glm::dvec3 b = glm::normalize(glm::dvec3(o));
            angles.push_back(glm::degrees(std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0))));
            if (angles.back() > 20.0 && ++farOff <= 8) {
                std::printf("  (%d, %d): page %d %d %d, renderer %.3f %.3f %.3f\n", x, y, p[0],
                            p[1], p[2], o.x, o.y, o.z);
            }
        }
    }
    if (const char* dump = std::getenv("SG_WEB_DUMP")) {
        // Both normal views side by side (page left), 0.5 n + 0.5, as a PPM.
        std::ofstream ppm(dump, std::ios::binary);
        ppm << "P6\n" << 2 * w << " " << h << "\n255\n";
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x)
                ppm.write(reinterpret_cast<const char*>(
                              &page.rgba[(size_t(y) * size_t(w) + size_t(x)) * 4]),
                          3);
            for (int x = 0; x < w; ++x) {
                const glm::vec4 o = ours.rgba(x, h - 1 - y);
                for (int k = 0; k < 3; ++k)
                    ppm.put(
                        char(std::clamp(int(std::lround((0.5f * o[k] + 0.5f) * 255.0f)), 0, 255)));
            }
        }
    }
    ASSERT_GT(angles.size(), size_t(w * h / 10));
    std::sort(angles.begin(), angles.end());
    const double p50 = angles[angles.size() / 2], p99 = angles[angles.size() * 99 / 100];
    std::printf("normal view vs renderer: %zu pixels, p50 %.3f deg, p99 %.3f deg, max %.3f deg; "
                "%zu pixels over 20 deg; %zu pixels covered by one only\n",
                angles.size(), p50, p99, angles.back(), farOff, onlyOne);
    RecordProperty("p50_deg", std::to_string(p50));
    RecordProperty("p99_deg", std::to_string(p99));
    RecordProperty("far_off_pixels", std::to_string(farOff));
    // Silhouette pixels may be covered by one rasterizer only (positions
    // rounded differently: camera-relative in the renderer, world then view
    // in three.js): under 1% of the covered pixels.
    EXPECT_LT(double(onlyOne), 0.01 * double(angles.size()));
    // Pixels where the two rasterizers pick a different primitive (the
    // thin side faces of the tiles seen almost edge-on, where one draws a
    // back face the other does not): 4 of 30,563 measured, some with the
    // mirrored normal (179 degrees). Under 0.1%.
    EXPECT_LT(double(farOff), 0.001 * double(angles.size()));
    // The page's normal is written as 8-bit 0.5 n + 0.5: up to ~0.4 degrees
    // of quantization. Beyond it the two draws differ in the normal map's
    // mip chain (the browser's generateMipmap vs the renderer's own) and in
    // the level each picks (texture() with SwiftShader's implicit
    // derivatives vs textureGrad with llvmpipe's dFdxFine). Measured on
    // Chromium 156 / SwiftShader against Mesa 22.3 llvmpipe: p50 0.17, p99
    // 0.87 degrees. The bounds leave room for another SwiftShader's
    // derivatives and mip filter; a wrong frame, UV convention or
    // back-face mode moves whole regions by 5 to 180 degrees.
    EXPECT_LT(p50, 0.5);
    EXPECT_LT(p99, 2.0);
}

} // namespace
