// `surfgrad eval` from outside: runs the built binary
// (SURFGRAD_BINARY_DIR/bin/surfgrad) with JSON lines on stdin, checks the
// answers, the error lines and exit status for bad lines, and that --gpu
// (GLSL build on llvmpipe) agrees with the CPU build. Also the line parser
// (surfgrad/bump/eval_line.h) directly.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

#include "cli.h"
#include "surfgrad/bump/eval_line.h"

namespace {

using CliRun = sg::test::CommandResult;

CliRun surfgrad(const std::string& args, const std::string& stdinText) {
    return sg::test::runSurfgrad(args, {.stdinText = stdinText});
}

std::vector<nlohmann::json> lines(const std::string& out) {
    std::vector<nlohmann::json> v;
    std::istringstream in(out);
    std::string line;
    while (std::getline(in, line)) v.push_back(nlohmann::json::parse(line));
    return v;
}

TEST(CliEval, GoodLinesGiveKnownAnswers) {
    const CliRun r =
        surfgrad("eval resolve", "{\"n\":[0,0,1],\"sg\":[0.5,0,0]}\n"
                                 "{\"n\":[0,0,2],\"sg\":[0,0.75,0],\"resolve_sign\":-1}\n");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto v = lines(r.out);
    ASSERT_EQ(v.size(), 2u);
    // normalize((0,0,1) - (0.5,0,0)) = (-1, 0, 2)/sqrt(5); float output to 1e-6.
    EXPECT_NEAR(v[0]["n"][0].get<double>(), -1 / std::sqrt(5.0), 1e-6);
    EXPECT_NEAR(v[0]["n"][2].get<double>(), 2 / std::sqrt(5.0), 1e-6);
    // resolve_sign -1 (flip mode: the front side's result negated):
    // -normalize(n - sg) = -(0, -0.6, 0.8) = (0, 0.6, -0.8).
    EXPECT_NEAR(v[1]["n"][1].get<double>(), 0.6, 1e-6);
    EXPECT_NEAR(v[1]["n"][2].get<double>(), -0.8, 1e-6);

    const CliRun t =
        surfgrad("eval tspace-to-deriv", "{\"m\":[0.6,0]}\n{\"m\":[0,0.6],\"flip_v\":true}\n");
    ASSERT_EQ(t.exitCode, 0) << t.err;
    const auto d = lines(t.out);
    EXPECT_NEAR(d[0]["d"][0].get<double>(), -0.75, 1e-6); // -m.x / m.z, m.z = 0.8
    EXPECT_NEAR(d[1]["d"][1].get<double>(), 0.75, 1e-6);  // flipped green
}

TEST(CliEval, BadLinesGetErrorLinesAndExitOne) {
    const std::string input = "{\"n\":[0,0,1],\"sg\":[0,0,0]}\n"         // 1 good
                              "{\"n\":[0,0,1],\"sg\":[0,0]}\n"           // 2 wrong length
                              "not json\n"                               // 3
                              "{\"n\":[0,0,1]}\n"                        // 4 missing sg
                              "{\"n\":[0,0,1],\"sg\":[0,0,0],\"x\":1}\n" // 5 unknown key
                              "{\"n\":[0,0,1e19],\"sg\":[0,0,0]}\n"      // 6 outside the domain
                              "[1,2,3]\n"                                // 7 not an object
                              "\n"                                       // blank: skipped
                              "{\"n\":[1,0,0],\"sg\":[0,0,0]}\n";        // 9 good
    const CliRun r = surfgrad("eval resolve", input);
    EXPECT_EQ(r.exitCode, 1);
    const auto v = lines(r.out);
    ASSERT_EQ(v.size(), 8u);
    EXPECT_TRUE(v[0].contains("n"));
    const char* expect[] = {"line 2: key 'sg'",         "line 3: invalid JSON",
                            "line 4: missing key 'sg'", "line 5: unknown key 'x'",
                            "line 6: key 'n'",          "line 7: expected a JSON object"};
    for (int i = 0; i < 6; ++i) {
        ASSERT_TRUE(v[size_t(i + 1)].contains("error")) << v[size_t(i + 1)].dump();
        EXPECT_NE(v[size_t(i + 1)]["error"].get<std::string>().find(expect[i]), std::string::npos)
            << v[size_t(i + 1)].dump();
    }
    EXPECT_NEAR(v[7]["n"][0].get<double>(), 1.0, 1e-7);

    const CliRun p = surfgrad(
        "eval prologue", "{\"n\":[0,0,1],\"dpdx\":[1,0,0],\"dpdy\":[0,1,0],\"bface_mode\":3}\n");
    EXPECT_EQ(p.exitCode, 1);
    EXPECT_NE(p.out.find("bface_mode"), std::string::npos);

    const CliRun u = surfgrad("eval no-such-entry", "");
    EXPECT_EQ(u.exitCode, 2); // a wrong command line
    EXPECT_NE(u.err.find("unknown entry 'no-such-entry'"), std::string::npos) << u.err;
}

TEST(CliEval, GpuAgreesWithCpu) {
    const std::string input =
        "{\"n\":[0.2,0.3,0.9],\"dpdx\":[0.01,0.002,-0.001],\"dpdy\":[-0.001,0.012,0.003],"
        "\"dstdx\":[0.002,0.0005],\"dstdy\":[-0.0004,0.0021]}\n"
        "{\"n\":[0,0,-1],\"dpdx\":[1,0,0],\"dpdy\":[0,1,0],\"dstdx\":[1,0],\"dstdy\":[0,-1]}\n"
        "{\"n\":[0,0,1],\"dpdx\":[0,0,0],\"dpdy\":[0,0,0],\"dstdx\":[0,0],\"dstdy\":[0,0]}\n"
        "{\"n\":[0,0,1],\"dpdx\":[1,0,0],\"dpdy\":[0,1,0],\"dstdx\":[1,2],\"dstdy\":[2,4]}\n";
    const CliRun c = surfgrad("eval basis", input);
    const CliRun g = surfgrad("eval basis --gpu", input);
    ASSERT_EQ(c.exitCode, 0) << c.err;
    ASSERT_EQ(g.exitCode, 0) << g.err;
    const auto vc = lines(c.out), vg = lines(g.out);
    ASSERT_EQ(vc.size(), 4u);
    ASSERT_EQ(vg.size(), 4u);
    for (size_t i = 0; i < 4; ++i) {
        for (const char* k : {"t", "b"}) {
            for (int j = 0; j < 3; ++j) {
                // Well-conditioned unit vectors: the basis tolerance (1e-5).
                EXPECT_NEAR(vc[i][k][size_t(j)].get<double>(), vg[i][k][size_t(j)].get<double>(),
                            1e-5)
                    << "line " << i + 1 << " " << k;
            }
        }
    }
    // Degenerate lines (zero derivatives, parallel UV derivatives): zero frame.
    EXPECT_EQ(vc[2]["t"][0].get<double>(), 0.0);
    EXPECT_EQ(vc[3]["b"][2].get<double>(), 0.0);
}

TEST(CliEval, ListNamesEveryEntry) {
    const CliRun r = surfgrad("eval --list", "");
    ASSERT_EQ(r.exitCode, 0);
    for (const auto& e : sg::eval::entries()) {
        EXPECT_NE(r.out.find(e.name + ":"), std::string::npos) << e.name;
    }
}

TEST(EvalLine, ParserAcceptsAndRejects) {
    const auto& e = *sg::eval::findEntry("triplanar");
    const auto rec = sg::eval::parseLine(
        e, R"({"n":[0,0,1],"dx":[1,2],"dy":[3,4],"dz":[5,6],"upper_left":true})");
    EXPECT_EQ(rec[3], 3.0f);  // k defaults to 3
    EXPECT_EQ(rec[8], 5.0f);  // dz.x
    EXPECT_EQ(rec[11], 1.0f); // upper_left
    for (const char* bad : {R"({"n":[0,0,1],"dx":[1,2],"dy":[3,4]})",
                            R"({"n":[0,0,"x"],"dx":[1,2],"dy":[3,4],"dz":[5,6]})",
                            R"({"n":[0,0,1],"dx":[1,2],"dy":[3,4],"dz":[5,6],"upper_left":1})", "{",
                            "", R"({"n":[0,0,1],"dx":[1,2],"dy":[3,4],"dz":[5,6],"k":1e300})"}) {
        EXPECT_THROW(sg::eval::parseLine(e, bad), sg::eval::LineError) << bad;
    }
}

} // namespace
