// `surfgrad bake` end to end: the cube cage and sphere of bake_test.cpp
// written as files, every output written and read back, the counts in
// --json, and the command-line and input errors with their exit statuses.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "bake_meshes.h"
#include "cli.h"
#include "surfgrad/mesh_io.h"
#include "surfgrad/normalmap.h"

namespace sg::test {
namespace {

namespace fs = std::filesystem;

struct Files {
    fs::path dir, cage, high;
};

const Files& files() {
    static const Files f = [] {
        Files g;
        g.dir = processScratchDir("bake_cli");
        g.cage = g.dir / "cube.obj";
        g.high = g.dir / "sphere.glb";
        mesh::writePolygonMesh(g.cage, cubeCage());
        mesh::writeRenderMesh(g.high, sphereMesh(64, 0.7));
        return g;
    }();
    return f;
}

std::string q(const fs::path& p) {
    return shellQuote(p);
}

TEST(BakeCli, WritesEveryMapAndReportsCounts) {
    const Files& f = files();
    const fs::path disp = f.dir / "disp.exr", normal = f.dir / "normal.png",
                   object = f.dir / "object.png", mask = f.dir / "mask.png";
    const CommandResult r =
        runSurfgrad("bake " + q(f.high) + " " + q(f.cage) +
                    " --size 64x48 --distance 0.5 --displacement " + q(disp) + " --normal " +
                    q(normal) + " --object-normal " + q(object) + " --mask " + q(mask) + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.output();
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_GT(j["hits"].get<size_t>(), 1000u);
    EXPECT_EQ(j["misses"].get<size_t>(), 0u);
    EXPECT_EQ(j["overlap_texels"].get<size_t>(), 0u);
    const normalmap::Image d = normalmap::readImage(disp);
    EXPECT_EQ(d.width, 64);
    EXPECT_EQ(d.height, 48);
    EXPECT_EQ(d.channels, 1);
    EXPECT_TRUE(d.isFloat);
    // The cube's limit surface lies outside the sphere of radius 0.7
    // almost everywhere: displacements are inwards, within the distance.
    float lo = 0;
    for (float v : d.texels) lo = std::min(lo, v);
    EXPECT_LT(lo, -0.05f);
    EXPECT_GT(lo, -0.5f);
    const normalmap::Image m = normalmap::readImage(mask);
    size_t baked = 0;
    for (float v : m.texels) baked += v == 1.0f ? 1 : 0;
    EXPECT_EQ(baked, j["hits"].get<size_t>());
    EXPECT_EQ(normalmap::readImage(normal).channels, 3);
    EXPECT_EQ(normalmap::readImage(object).channels, 3);
}

TEST(BakeCli, WrongCommandLinesExitWithStatus2) {
    const Files& f = files();
    const std::string base = "bake " + q(f.high) + " " + q(f.cage);
    for (const std::string& args :
         {std::string(" --size 64"),                  // nothing to write
          " --size 0 --mask " + q(f.dir / "m.png"),   // bad size
          " --size 64x --mask " + q(f.dir / "m.png"), // bad size
          " --displacement " + q(f.dir / "d.png"),    // integer displacement
          " --mask " + q(f.dir / "m.png") + " --normal " + q(f.dir / "m.png"), // same output twice
          " --mask " + q(f.dir / "m.png") + " --threads 0"}) {
        const CommandResult r = runSurfgrad(base + args);
        EXPECT_EQ(r.exitCode, 2) << args << ": " << r.output();
        EXPECT_NE(r.err.find("error"), std::string::npos) << args;
    }
}

TEST(BakeCli, BadInputExitsWithStatus1NamingTheFile) {
    const Files& f = files();
    // The output over an input.
    CommandResult r = runSurfgrad("bake " + q(f.high) + " " + q(f.cage) + " --mask " + q(f.cage));
    EXPECT_EQ(r.exitCode, 1) << r.output();
    // A cage without UVs.
    const fs::path noUv = f.dir / "nouv.obj";
    mesh::PolygonMesh cage = cubeCage();
    cage.uvSets.clear();
    mesh::writePolygonMesh(noUv, cage);
    const fs::path mask = f.dir / "never.png";
    r = runSurfgrad("bake " + q(f.high) + " " + q(noUv) + " --size 32 --mask " + q(mask));
    EXPECT_EQ(r.exitCode, 1) << r.output();
    EXPECT_NE(r.err.find("nouv.obj: uv set 0"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(mask)) << "no output after an error";
    // A high mesh out of reach.
    r = runSurfgrad("bake " + q(f.high) + " " + q(f.cage) + " --size 32 --distance 0.01 --mask " +
                    q(mask));
    EXPECT_EQ(r.exitCode, 1) << r.output();
    EXPECT_NE(r.err.find("sphere.glb"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(mask));
}

} // namespace
} // namespace sg::test
