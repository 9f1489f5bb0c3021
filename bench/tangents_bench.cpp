// Benchmark: MikkTSpace-compatible vertex tangents (surfgrad/mesh/tangents.h) on
// a >= 1M-triangle mesh, one core. Input: blub (Keenan Crane,
// data/meshes/blub) with area-weighted vertex normals, split
// 1-to-4 at edge midpoints (positions, normals and UVs interpolated, normals
// renormalized) until it has >= 900k triangles (3 splits: 909,312).
// Loaded with sg::mesh::loadRenderMesh (normals: area-weighted, smooth across
// UV seams).
//
// Rows: the fast generator reusing its buffers (the intended use), the fast
// generator constructed per call (cold buffers: page faults included), the
// step-by-step oracle (the baseline, same run); every row's output is
// compared bit for bit with the oracle's. The C reference (mmikk/MikkTSpace)
// is not built here; its figure (0.5 Mtri/s, measured once separately on
// this kind of machine, single core, -O2) is printed as an anchor only.
//
//   bench/tangents_bench [--runs N] [--oracle-runs N] [--splits N] [--obj FILE]
//   bench/tangents_bench --check-acos
//   bench/tangents_bench --profile-runs N
//
// --check-acos instead verifies, for every one of the 2^31 floats in
// [-1, 1], that the fast angle rounding MikkTSpace uses
// (sg::mesh::mikktspaceAngleFromCos and the batch mikktspaceAnglesFromCos)
// equals (float)std::acos(double(c)), the reference's expression (a few
// minutes).
//
// --profile-runs N runs only the reused fast generator N times and prints
// the median and minimum CPU time (no oracle, no comparison), for
// `perf record`.
//
// Threads: the rows above run on one thread (setThreads(1)); then the same
// reused generator on --threads N threads (default 0: all cores), same
// run, with the wall-time ratio and the median wall time of each step at
// both thread counts. On a shared machine only ratios within one run mean
// anything.
//
// --cutover times prefixes of the input (1k to 200k triangles) at one
// thread and at --threads, for choosing kMikkTSpaceParallelCutover.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include <tbb/info.h>

#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/mikktspace_reference.h"
#include "surfgrad/mesh/tangents.h"

namespace {

using Clock = std::chrono::steady_clock;

struct Mesh {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec2> uvs;
    std::vector<uint32_t> indices;
};

Mesh loadMesh(const std::string& path) {
    const sg::mesh::RenderMesh rm = sg::mesh::loadRenderMesh(path);
    if (rm.uvSets.empty()) throw std::runtime_error(path + ": no UV set");
    return {rm.positions, rm.normals, rm.uvSets[0], rm.indices};
}

// 1-to-4 split: one new vertex per (vertex pair) edge, shared by the two
// triangles on it (UV seams have split vertices, hence separate midpoints).
Mesh split4(const Mesh& m) {
    Mesh r = m;
    r.indices.clear();
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
        const auto key = std::minmax(a, b);
        auto [it, added] = mid.emplace(key, uint32_t(r.positions.size()));
        if (added) {
            r.positions.push_back(0.5f * (m.positions[a] + m.positions[b]));
            r.normals.push_back(glm::normalize(m.normals[a] + m.normals[b]));
            r.uvs.push_back(0.5f * (m.uvs[a] + m.uvs[b]));
        }
        return it->second;
    };
    for (size_t t = 0; t < m.indices.size(); t += 3) {
        const uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
        const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
        r.indices.insert(r.indices.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    return r;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// Thread CPU time: on a shared machine wall time includes the time other
// processes run; the CPU time of this thread is what one core spent.
double threadCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

struct Timings {
    std::vector<double> wallMs, cpuMs;
};

template <typename F>
Timings timeRuns(int runs, F&& f) {
    Timings t;
    for (int i = 0; i < runs; ++i) {
        const double c0 = threadCpuMs();
        const auto t0 = Clock::now();
        f();
        t.wallMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        t.cpuMs.push_back(threadCpuMs() - c0);
    }
    return t;
}

} // namespace

// Every float in [-1, 1]: fast angle rounding (scalar, and the batch the
// generator uses, AVX2 and SSE2) == (float)acos(double).
int checkAcos() {
    uint64_t checked = 0, mismatches = 0;
    const auto t0 = Clock::now();
    std::vector<float> block, batch, narrowBatch;
    auto flush = [&] {
        batch = block;
        narrowBatch = block;
        sg::mesh::mikktspaceAnglesFromCos(batch);
        sg::mesh::mikktspaceAnglesFromCos(narrowBatch, false);
        for (size_t i = 0; i < block.size(); ++i) {
            const float ref = static_cast<float>(std::acos(static_cast<double>(block[i])));
            const float scalar = sg::mesh::mikktspaceAngleFromCos(block[i]);
            const bool bad = std::memcmp(&scalar, &ref, sizeof ref) != 0 ||
                             std::memcmp(&batch[i], &ref, sizeof ref) != 0 ||
                             std::memcmp(&narrowBatch[i], &ref, sizeof ref) != 0;
            if (bad && mismatches < 10)
                std::printf("mismatch: cos %a: scalar %a, batch %a, reference %a\n",
                            double(block[i]), double(scalar), double(batch[i]), double(ref));
            mismatches += bad;
            ++checked;
        }
        block.clear();
    };
    for (const uint32_t sign : {0u, 0x80000000u}) {
        for (uint32_t bits = 0; bits <= 0x3F800000u; ++bits) { // 0 .. 1.0f
            const uint32_t b = bits | sign;
            float c;
            std::memcpy(&c, &b, sizeof c);
            block.push_back(c);
            if (block.size() == 4095) flush(); // odd: the batch's scalar tail runs too
        }
    }
    flush();
    std::printf("acos check: %llu floats in [-1, 1], %llu mismatches (%.0f s)\n",
                static_cast<unsigned long long>(checked),
                static_cast<unsigned long long>(mismatches),
                std::chrono::duration<double>(Clock::now() - t0).count());
    return mismatches == 0 ? 0 : 1;
}

// Median wall time per step (MikkTSpaceGenerator::lastStepTimes) over runs.
struct StepMedians {
    std::vector<const char*> names;
    std::vector<std::vector<double>> ms;
    void add(std::span<const sg::mesh::MikkTSpaceStepTime> steps) {
        if (names.empty())
            for (const auto& st : steps) names.push_back(st.step), ms.emplace_back();
        for (size_t i = 0; i < steps.size() && i < ms.size(); ++i) ms[i].push_back(steps[i].ms);
    }
};

// Wall time of `runs` calls of a reused generator, per-step times recorded.
Timings timeThreads(sg::mesh::MikkTSpaceGenerator& g, const sg::mesh::MikkTSpaceInput& in,
                    std::vector<glm::vec4>& out, int runs, StepMedians* steps) {
    g.generate(in, out); // sizes the buffers
    Timings t;
    for (int i = 0; i < runs; ++i) {
        const Timings one = timeRuns(1, [&] { g.generate(in, out); });
        t.wallMs.push_back(one.wallMs[0]);
        t.cpuMs.push_back(one.cpuMs[0]);
        if (steps) steps->add(g.lastStepTimes());
    }
    return t;
}

int cutover(const sg::mesh::MikkTSpaceInput& full, int threads, int runs) {
    std::printf("cut-over: prefixes of the input, median wall ms of %d runs, 1 thread vs %d "
                "(0 = all cores: %d)\n",
                runs, threads, tbb::info::default_concurrency());
    std::printf("%10s %12s %12s %8s\n", "triangles", "1 thread", "threads", "ratio");
    for (size_t tris : {1000, 2000, 5000, 10000, 20000, 50000, 100000, 200000}) {
        if (tris * 3 > full.cornerVertices.size()) break;
        sg::mesh::MikkTSpaceInput in = full;
        in.cornerVertices = full.cornerVertices.subspan(0, tris * 3);
        sg::mesh::MikkTSpaceGenerator one, many;
        one.setThreads(1);
        many.setThreads(threads);
        many.setParallelCutover(0);
        std::vector<glm::vec4> a, b;
        const double t1 = median(timeThreads(one, in, a, runs, nullptr).wallMs);
        const double tn = median(timeThreads(many, in, b, runs, nullptr).wallMs);
        const bool same = a.size() == b.size() &&
                          std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec4)) == 0;
        std::printf("%10zu %12.3f %12.3f %7.2fx %s\n", tris, t1, tn, t1 / tn,
                    same ? "" : "OUTPUT DIFFERS");
        if (!same) return 1;
    }
    return 0;
}

int main(int argc, char** argv) {
    std::string obj = std::string(SURFGRAD_DATA_DIR) + "/meshes/blub/blub_triangulated.obj";
    int runs = 9, oracleRuns = 3, splits = 3, profileRuns = 0, threads = 0;
    bool cutoverOnly = false, firstCallProfile = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
            return argv[++i];
        };
        if (a == "--runs")
            runs = std::max(1, std::stoi(next()));
        else if (a == "--oracle-runs")
            oracleRuns = std::max(1, std::stoi(next()));
        else if (a == "--splits")
            splits = std::max(0, std::stoi(next()));
        else if (a == "--obj")
            obj = next();
        else if (a == "--check-acos")
            return checkAcos();
        else if (a == "--profile-runs")
            profileRuns = std::max(1, std::stoi(next()));
        else if (a == "--threads")
            threads = std::clamp(std::stoi(next()), 0, 1024);
        else if (a == "--first-call")
            firstCallProfile = true;
        else if (a == "--cutover")
            cutoverOnly = true;
        else {
            std::fprintf(stderr,
                         "usage: %s [--runs N] [--oracle-runs N] [--splits N] [--obj FILE] "
                         "[--threads N] [--profile-runs N] [--cutover] | --check-acos\n",
                         argv[0]);
            return 2;
        }
    }
    Mesh m = loadMesh(obj);
    for (int s = 0; s < splits; ++s) m = split4(m);
    const double triangles = double(m.indices.size() / 3);
    std::printf("input: %s split 1-to-4 x%d: %zu triangles, %zu vertices\n", obj.c_str(), splits,
                m.indices.size() / 3, m.positions.size());

    sg::mesh::MikkTSpaceInput in;
    in.positions = m.positions;
    in.normals = m.normals;
    in.uvs = m.uvs;
    in.cornerVertices = m.indices;

    if (cutoverOnly) return cutover(in, threads, runs);

    if (profileRuns > 0 && firstCallProfile) {
        const Timings t = timeRuns(profileRuns, [&] {
            sg::mesh::MikkTSpaceGenerator fresh;
            fresh.setThreads(1);
            std::vector<glm::vec4> out;
            fresh.generate(in, out);
        });
        std::printf("fast, first call: median %.1f ms cpu, %.1f ms wall (%d runs)\n",
                    median(t.cpuMs), median(t.wallMs), profileRuns);
        return 0;
    }
    if (profileRuns > 0) {
        sg::mesh::MikkTSpaceGenerator generator;
        generator.setThreads(1);
        std::vector<glm::vec4> out;
        generator.generate(in, out);
        const Timings t = timeRuns(profileRuns, [&] { generator.generate(in, out); });
        std::printf("fast, generator reused: median %.1f ms cpu (min %.1f), %.2f Mtri/s (%d runs, "
                    "no oracle)\n",
                    median(t.cpuMs), *std::min_element(t.cpuMs.begin(), t.cpuMs.end()),
                    triangles / (median(t.cpuMs) * 1e3), profileRuns);
        return 0;
    }

    std::vector<sg::mesh::MikkTSpaceFrame> oracle;
    const Timings oracleT =
        timeRuns(oracleRuns, [&] { oracle = sg::mesh::mikktspaceReferenceFrames(in); });
    std::vector<glm::vec4> expected(oracle.size());
    for (size_t c = 0; c < oracle.size(); ++c)
        expected[c] = glm::vec4(oracle[c].tangent, oracle[c].sign);

    sg::mesh::MikkTSpaceGenerator generator;
    generator.setThreads(1);
    std::vector<glm::vec4> warm;
    StepMedians steps1, stepsN, stepsCold;
    const Timings warmT = timeThreads(generator, in, warm, runs, &steps1);
    sg::mesh::MikkTSpaceGenerator narrowGen;
    narrowGen.setThreads(1);
    narrowGen.setWideSimd(false);
    std::vector<glm::vec4> narrow;
    narrowGen.generate(in, narrow);
    const Timings narrowT = timeRuns(runs, [&] { narrowGen.generate(in, narrow); });
    std::vector<glm::vec4> cold;
    const Timings coldT = timeRuns(runs, [&] {
        sg::mesh::MikkTSpaceGenerator fresh;
        fresh.setThreads(1);
        std::vector<glm::vec4> out;
        fresh.generate(in, out);
        stepsCold.add(fresh.lastStepTimes());
        cold.swap(out);
    });
    sg::mesh::MikkTSpaceGenerator threaded;
    threaded.setThreads(threads);
    std::vector<glm::vec4> many;
    const Timings manyT = timeThreads(threaded, in, many, runs, &stepsN);
    auto identical = [&](const std::vector<glm::vec4>& t) {
        return t.size() == expected.size() &&
               std::memcmp(t.data(), expected.data(), t.size() * sizeof(glm::vec4)) == 0;
    };

    const double oracleCpu = median(oracleT.cpuMs), oracleWall = median(oracleT.wallMs);
    std::printf(
        "\nMikkTSpace tangents, one thread, median of N runs. cpu = thread CPU time (what one\n"
        "core spent), wall = elapsed; Mtri/s from cpu; ratio = oracle / row, cpu (wall)\n");
    std::printf("%-44s %3s %9s %9s %8s %15s %9s\n", "what", "N", "cpu ms", "wall ms", "Mtri/s",
                "ratio cpu(wall)", "identical");
    auto row = [&](const char* what, const Timings& t, const char* same) {
        const double cpu = median(t.cpuMs), wall = median(t.wallMs);
        std::printf("%-44s %3zu %9.1f %9.1f %8.2f %7.2fx (%4.2fx) %9s\n", what, t.cpuMs.size(), cpu,
                    wall, triangles / (cpu * 1e3), oracleCpu / cpu, oracleWall / wall, same);
    };
    row("oracle (step-by-step reference, baseline)", oracleT, "-");
    row("fast, generator reused (buffers kept)", warmT, identical(warm) ? "yes" : "NO");
    row("fast, SSE2 kernels only (no AVX2)", narrowT, identical(narrow) ? "yes" : "NO");
    row("fast, new generator per call (cold buffers)", coldT, identical(cold) ? "yes" : "NO");
    std::printf("%-44s %3s %9s %9s %8.2f %15s %9s\n", "anchor: C reference mmikk/MikkTSpace", "-",
                "-", "-", 0.5, "-", "(docs/tangents.md)");

    const int cores = threads == 0 ? tbb::info::default_concurrency() : threads;
    const double wall1 = median(warmT.wallMs), wallN = median(manyT.wallMs);
    std::printf("\nThreads, same run, median wall ms of %d runs (a shared machine: compare the "
                "ratio only)\n",
                runs);
    std::printf("%-44s %9s %8s %9s %9s\n", "what", "wall ms", "Mtri/s", "ratio", "identical");
    std::printf("%-44s %9.1f %8.2f %8.2fx %9s\n", "fast, 1 thread", wall1,
                triangles / (wall1 * 1e3), 1.0, identical(warm) ? "yes" : "NO");
    char label[64];
    std::snprintf(label, sizeof label, "fast, %d threads (--threads %d)", cores, threads);
    std::printf("%-44s %9.1f %8.2f %8.2fx %9s\n", label, wallN, triangles / (wallN * 1e3),
                wall1 / wallN, identical(many) ? "yes" : "NO");
    std::printf("\nPer step, median wall ms (1 thread | %d threads | ratio)\n", cores);
    for (size_t i = 0; i < steps1.names.size() && i < stepsN.names.size(); ++i) {
        const double a = median(steps1.ms[i]), b = median(stepsN.ms[i]);
        std::printf("  %-28s %9.2f %9.2f %7.2fx  cold %9.2f\n", steps1.names[i], a, b,
                    b > 0 ? a / b : 0.0, median(stepsCold.ms[i]));
    }
    return identical(warm) && identical(narrow) && identical(cold) && identical(many) ? 0 : 1;
}
