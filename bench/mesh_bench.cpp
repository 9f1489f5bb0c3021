// Mesh pipeline benchmarks (bench/README.md, "Mesh"): every row is the
// median of several runs, with its ratio to the baseline measured in the
// same run, single thread.
//
//  1. Refinement of spot's control cage (quads, pentagons, triangles; one UV
//     set) to levels 1..5, a NEW topology each call (reuseTopology = false:
//     nothing is cached between calls but buffer capacity):
//       - OpenMesh's CatmullClarkT (positions only; no creases, no UVs),
//       - plain Far: TopologyRefinerFactory + RefineUniform + PrimvarRefiner
//         for positions and UVs (fresh buffers each call, like a one-off user),
//       - ours: Subdivider::build (creases/corners/holes and every UV set
//         carried; buffers reused between calls) with the specialised
//         Catmull-Clark refiner (bitwise OpenSubdiv's result, see
//         mesh/src/uniform_refiner.h) and, for reference, with OpenSubdiv's
//         Far (specializedRefiner = false); plus the OpenMesh -> OpenSubdiv ->
//         polygons conversion share.
//     The candidates of one level are timed interleaved (A A B B C C ...,
//     the second call of each pair timed), so load from other processes
//     hits them alike and each is measured warm.
//  2. Animated cage at level 4: full re-refinement vs the factored stencil
//     update (positions; then + normals), and for limit frames (positions,
//     dP/du, dP/dv).
//  Sections 1 and 2 run at SubdivisionSettings::threads = 1.
//  3. Threads: each job at 1 thread and at all threads (TBB's default
//     concurrency) side by side, timed interleaved, with the speed-up and
//     the efficiency (speed-up / threads) and the process CPU time of the
//     threaded call: refinement (first call: a fresh Subdivider; warm: a
//     reused one; + the render mesh), the factored stencil update
//     (positions + normals), the limit build and the limit stencil update,
//     on spot at levels 4 and 5 and bob at levels 3 and 4 (1.03M and 4.1M
//     triangles); then the cut-over probe: refinement of spot at levels 1-4
//     with the cut-over off (serialBelowFaces = 0), where threads start to
//     pay (SubdivisionSettings::serialBelowFaces, kSerialBelowFaces).
//
// Allocation policy: by default glibc's (large freed blocks go back to the
// OS, so a call that allocates fresh buffers page-faults them in again).
// --keep-memory makes the benchmark PROCESS keep freed memory (mallopt:
// no mmap for blocks below 32 MB, no trimming): an application's explicit
// choice, applied to every row alike (OpenMesh and Far allocate per call,
// ours reuses its buffers either way); the library never changes it.
//
// Usage: mesh_bench [--runs N] [--max-level L] [--keep-memory] [--threads-only]
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/CatmullClarkT.hh>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <malloc.h>
#include <tbb/info.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/osd_primvar.h"
#include "surfgrad/mesh/polymesh.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

using namespace sg::mesh;
namespace Far = OpenSubdiv::Far;
using Clock = std::chrono::steady_clock;

double medianMs(int runs, const std::function<void()>& f) {
    f(); // warm-up (first-touch page faults, caches)
    std::vector<double> t;
    for (int i = 0; i < runs; ++i) {
        auto t0 = Clock::now();
        f();
        t.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

// Median of each callable over `runs` rounds, interleaved so that load
// from other processes, which changes within seconds on the shared
// machine, hits all of them alike. In each round every callable runs
// twice in a row and only the second call is timed: each is measured warm
// (its own buffers and allocator state from its previous call), not after
// another candidate has flushed the cache.
std::vector<double> interleavedMediansMs(int runs, const std::vector<std::function<void()>>& fs) {
    std::vector<std::vector<double>> t(fs.size());
    for (int i = 0; i < runs; ++i) {
        for (size_t k = 0; k < fs.size(); ++k) {
            fs[k]();
            auto t0 = Clock::now();
            fs[k]();
            t[k].push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        }
    }
    std::vector<double> med;
    for (auto& v : t) {
        std::sort(v.begin(), v.end());
        med.push_back(v[v.size() / 2]);
    }
    return med;
}

void row(const char* what, const char* input, double ms, double baselineMs, const char* baseline) {
    std::printf("| %-44s | %-14s | %9.3f | %6.2fx vs %s |\n", what, input, ms, baselineMs / ms,
                baseline);
}

// Plain Far, the way a one-off user writes it.
void plainFar(const PolygonMesh& cage, int level, std::vector<glm::vec3>& outPos,
              std::vector<glm::vec2>& outUv) {
    Far::TopologyDescriptor d;
    d.numVertices = int(cage.positions.size());
    d.numFaces = int(cage.faceSizes.size());
    d.numVertsPerFace = reinterpret_cast<const int*>(cage.faceSizes.data());
    d.vertIndicesPerFace = reinterpret_cast<const int*>(cage.faceVertices.data());
    Far::TopologyDescriptor::FVarChannel ch;
    ch.numValues = int(cage.uvSets[0].values.size());
    ch.valueIndices = reinterpret_cast<const int*>(cage.uvSets[0].indices.data());
    d.numFVarChannels = 1;
    d.fvarChannels = &ch;
    OpenSubdiv::Sdc::Options so;
    so.SetVtxBoundaryInterpolation(OpenSubdiv::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    so.SetFVarLinearInterpolation(OpenSubdiv::Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> r(
        Factory::Create(d, Factory::Options(OpenSubdiv::Sdc::SCHEME_CATMARK, so)));
    r->RefineUniform(Far::TopologyRefiner::UniformOptions(level));
    Far::PrimvarRefiner pr(*r);
    std::vector<glm::vec3> src = cage.positions, dst;
    std::vector<glm::vec2> usrc = cage.uvSets[0].values, udst;
    for (int l = 1; l <= level; ++l) {
        dst.assign(size_t(r->GetLevel(l).GetNumVertices()), glm::vec3(0.0f));
        PrimvarView<glm::vec3> s{src.data()}, t{dst.data()};
        pr.Interpolate(l, s, t);
        src.swap(dst);
        udst.assign(size_t(r->GetLevel(l).GetNumFVarValues(0)), glm::vec2(0.0f));
        PrimvarView<glm::vec2> us{usrc.data()}, ut{udst.data()};
        pr.InterpolateFaceVarying(l, us, ut, 0);
        usrc.swap(udst);
    }
    outPos.swap(src);
    outUv.swap(usrc);
}

struct OmTraits : OpenMesh::DefaultTraits {};
using OmMesh = OpenMesh::PolyMesh_ArrayKernelT<OmTraits>;

double processCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

// One job at 1 thread and at `threads` (0: all cores), interleaved as
// interleavedMediansMs does; job(threads) runs it once. Prints the row:
// medians, speed-up, efficiency, and the median process CPU time of the
// threaded call (above its wall time: the threads were busy).
void threadRow(const char* what, const char* input, int runs, int allThreads,
               const std::function<void(int)>& job) {
    std::vector<double> wall1, wallN, cpuN;
    for (int i = 0; i < runs; ++i) {
        job(1);
        auto t0 = Clock::now();
        job(1);
        wall1.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        job(0);
        const double c0 = processCpuMs();
        t0 = Clock::now();
        job(0);
        wallN.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        cpuN.push_back(processCpuMs() - c0);
    }
    auto med = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    };
    const double one = med(wall1), many = med(wallN), cpu = med(cpuN);
    std::printf("| %-40s | %-16s | %9.3f | %9.3f | %6.2fx | %5.2f | %9.3f |\n", what, input, one,
                many, one / many, one / many / double(allThreads), cpu);
}

void threadHeader(const char* title, int allThreads) {
    std::printf("\n| %-40s | %-16s | %9s | %6s ms | %7s | %5s | %9s |\n", title, "input",
                "1 thr ms", (std::to_string(allThreads) + " thr").c_str(), "speedup", "eff.",
                "CPU ms N");
    std::printf("|%s|%s|%s|%s|%s|%s|%s|\n", std::string(42, '-').c_str(),
                std::string(18, '-').c_str(), std::string(11, '-').c_str(),
                std::string(11, '-').c_str(), std::string(9, '-').c_str(),
                std::string(7, '-').c_str(), std::string(11, '-').c_str());
}

// Section 3 (see the top of the file).
void threadsSection(const PolygonMesh& spot, const PolygonMesh& bob, int runs) {
    const int all = tbb::info::default_concurrency();
    std::printf("\n## Threads: 1 thread vs all %d (TBB default concurrency), medians of %d "
                "interleaved runs; efficiency = speed-up / %d\n",
                all, runs, all);
    struct Input {
        const char* name;
        const PolygonMesh* cage;
        int level;
    };
    const Input inputs[] = {{"spot L4 (94k tri)", &spot, 4},
                            {"spot L5 (375k tri)", &spot, 5},
                            {"bob L3 (1.03M tri)", &bob, 3},
                            {"bob L4 (4.1M tri)", &bob, 4}};
    threadHeader("refinement (pos+UV), new topology", all);
    for (const Input& in : inputs) {
        SubdivisionSettings s;
        s.level = in.level;
        s.buildRenderMesh = false;
        s.reuseTopology = false;
        Subdivider warm[2];
        threadRow("warm (reused Subdivider)", in.name, runs, all, [&](int threads) {
            s.threads = threads;
            warm[threads == 1 ? 0 : 1].build(*in.cage, s);
        });
        threadRow("first call (fresh Subdivider)", in.name, runs, all, [&](int threads) {
            s.threads = threads;
            Subdivider fresh(*in.cage, s);
        });
        s.buildRenderMesh = true;
        threadRow("warm + render mesh (normals)", in.name, runs, all, [&](int threads) {
            s.threads = threads;
            warm[threads == 1 ? 0 : 1].build(*in.cage, s);
        });
    }
    threadHeader("factored stencils, per frame", all);
    for (const Input& in : inputs) {
        SubdivisionSettings s;
        s.level = in.level;
        s.animate = true;
        s.threads = 0;
        Subdivider anim(*in.cage, s);
        RenderMesh out = anim.renderMesh();
        std::vector<glm::vec3> moved = in.cage->positions;
        size_t k = 0;
        // update() runs at its build's count: a one-thread build beside it.
        s.threads = 1;
        Subdivider anim1(*in.cage, s);
        RenderMesh out1 = anim1.renderMesh();
        threadRow("update: positions + normals", in.name, runs, all, [&](int threads) {
            moved[k++ % moved.size()].x += 1e-4f;
            if (threads == 1)
                anim1.update(moved, out1, nullptr, true);
            else
                anim.update(moved, out, nullptr, true);
        });
        s.threads = 0;
        s.reuseTopology = true;
        s.animate = false;
        s.buildRenderMesh = false;
        Subdivider same[2];
        PolygonMesh cage = *in.cage;
        threadRow("rebuild, same topology (stencils)", in.name, runs, all, [&](int threads) {
            s.threads = threads;
            cage.positions[k++ % cage.positions.size()].x += 1e-4f;
            same[threads == 1 ? 0 : 1].build(cage, s);
        });
    }
    const Input limitInputs[] = {{"spot L3", &spot, 3}, {"spot L4", &spot, 4}, {"bob L2", &bob, 2}};
    threadHeader("limit evaluation", all);
    for (const Input& in : limitInputs) {
        SubdivisionSettings s;
        s.level = in.level;
        s.limit = true;
        Subdivider full[2];
        threadRow("limit build (P, N, UV, frame)", in.name, std::max(3, runs / 3), all,
                  [&](int threads) {
                      s.threads = threads;
                      full[threads == 1 ? 0 : 1].build(*in.cage, s);
                  });
        s.animate = true;
        s.threads = 1;
        Subdivider a1(*in.cage, s);
        s.threads = 0;
        Subdivider aN(*in.cage, s);
        RenderMesh o1 = a1.renderMesh(), oN = aN.renderMesh();
        LimitFrame f1 = a1.limitFrame(), fN = aN.limitFrame();
        std::vector<glm::vec3> moved = in.cage->positions;
        size_t k = 0;
        threadRow("limit stencil update (P, dP, N)", in.name, runs, all, [&](int threads) {
            moved[k++ % moved.size()].y += 1e-4f;
            if (threads == 1)
                a1.update(moved, o1, &f1);
            else
                aN.update(moved, oN, &fN);
        });
    }
    // Cut-over probe: the loops on TBB at every size.
    threadHeader("cut-over probe (serialBelowFaces 0)", all);
    for (int level = 1; level <= 4; ++level) {
        SubdivisionSettings s;
        s.level = level;
        s.buildRenderMesh = false;
        s.reuseTopology = false;
        s.serialBelowFaces = 0;
        Subdivider warm[2];
        char name[48];
        std::snprintf(name, sizeof name, "spot L%d (%d quads)", level, 180 << (2 * level));
        threadRow("refinement, warm", name, runs, all, [&](int threads) {
            s.threads = threads;
            warm[threads == 1 ? 0 : 1].build(spot, s);
        });
    }
}

} // namespace

int main(int argc, char** argv) {
    int runs = 15, maxLevel = 5;
    bool keepMemory = false, threadsOnly = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--runs") && i + 1 < argc)
            runs = std::max(3, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--max-level") && i + 1 < argc)
            maxLevel = std::clamp(std::atoi(argv[++i]), 1, 6);
        else if (!std::strcmp(argv[i], "--keep-memory"))
            keepMemory = true;
        else if (!std::strcmp(argv[i], "--threads-only"))
            threadsOnly = true;
    }
    if (keepMemory) {
        // 32 MB is glibc's largest mmap threshold on 64-bit; every buffer
        // of these benchmarks is smaller, so all come from the heap, which
        // is never trimmed.
        if (!mallopt(M_MMAP_THRESHOLD, 32 << 20) || !mallopt(M_TRIM_THRESHOLD, INT32_MAX)) {
            std::fprintf(stderr, "mesh_bench: mallopt refused the keep-memory policy\n");
            return 1;
        }
    }
    const std::string spotPath =
        std::string(SURFGRAD_DATA_DIR) + "/meshes/spot/spot_control_mesh.obj";
    PolygonMesh spot = loadPolygonMesh(spotPath);
    if (threadsOnly) {
        const PolygonMesh bob =
            loadPolygonMesh(std::string(SURFGRAD_DATA_DIR) + "/meshes/bob/bob_tri.obj");
        threadsSection(spot, bob, runs);
        return 0;
    }
    std::printf("spot control cage: %zu vertices, %zu faces, 1 UV set; %d runs per row (median, "
                "candidates interleaved, each warm), single "
                "thread; allocator: %s\n\n",
                spot.vertexCount(), spot.faceCount(), runs,
                keepMemory ? "--keep-memory (freed memory stays in the process)"
                           : "glibc default (large blocks returned to the OS)");

    // --- 1. Refinement ---------------------------------------------------------
    std::printf("| %-44s | %-14s | %9s | %-22s |\n", "refinement", "input", "median ms", "ratio");
    std::printf("|%s|%s|%s|%s|\n", std::string(46, '-').c_str(), std::string(16, '-').c_str(),
                std::string(11, '-').c_str(), std::string(24, '-').c_str());
    // OpenMesh input for the baseline (plain PolyMesh, no custom properties).
    OmMesh omCage;
    {
        std::vector<OmMesh::VertexHandle> vh;
        for (const auto& p : spot.positions)
            vh.push_back(omCage.add_vertex(OmMesh::Point(p.x, p.y, p.z)));
        size_t c = 0;
        for (uint32_t k : spot.faceSizes) {
            std::vector<OmMesh::VertexHandle> f;
            for (uint32_t j = 0; j < k; ++j) f.push_back(vh[spot.faceVertices[c + j]]);
            omCage.add_face(f);
            c += k;
        }
    }
    PolyMeshProperties props;
    PolyMesh spotOm = toPolyMesh(spot, props, spotPath); // ours, with UVs as halfedge properties
    Subdivider sub;
    for (int level = 1; level <= maxLevel; ++level) {
        char in[32];
        std::snprintf(in, sizeof in, "spot L%d", level);
        std::vector<glm::vec3> fp;
        std::vector<glm::vec2> fu;
        SubdivisionSettings s;
        s.level = level;
        s.threads = 1;
        s.buildRenderMesh = false;
        s.reuseTopology = false; // a new topology each call: nothing but buffer capacity is kept
        SubdivisionSettings sFar = s;
        sFar.specializedRefiner = false;
        Subdivider viaFar;
        std::vector<double> stIn, stTopo, stInterp, stOut;
        const std::vector<double> med =
            interleavedMediansMs(runs, {[&] {
                                            OmMesh m = omCage;
                                            OpenMesh::Subdivider::Uniform::CatmullClarkT<OmMesh> cc;
                                            cc.attach(m);
                                            cc(size_t(level));
                                            cc.detach();
                                        },
                                        [&] { plainFar(spot, level, fp, fu); },
                                        [&] {
                                            sub.build(spot, s);
                                            stIn.push_back(sub.timings().convertIn);
                                            stTopo.push_back(sub.timings().topology);
                                            stInterp.push_back(sub.timings().interpolate);
                                            stOut.push_back(sub.timings().convertOut);
                                        },
                                        [&] { viaFar.build(spot, sFar); },
                                        [&] {
                                            Subdivider fresh(spot, s);
                                            if (fresh.refined().faceCount() == 0) std::abort();
                                        }});
        const double om = med[0], far = med[1], ours = med[2], oursFar = med[3], cold = med[4];
        if (!sub.usedSpecializedRefiner())
            std::printf("|   (specialised refiner declined: %s)\n",
                        sub.specializedRefinerDeclined().c_str());
        auto medOf = [](std::vector<double> v) {
            std::sort(v.begin(), v.end());
            return v[v.size() / 2];
        };
        SubdivisionTimings tm;
        tm.convertIn = medOf(stIn);
        tm.topology = medOf(stTopo);
        tm.interpolate = medOf(stInterp);
        tm.convertOut = medOf(stOut);
        s.reuseTopology = true;
        sub.build(spot, s); // keeps the refiner; the next build records the stencils
        PolygonMesh moved = spot;
        size_t flip = 0;
        double cached = medianMs(runs, [&] {
            // New positions and UVs every call, same topology.
            moved.positions[flip % moved.positions.size()].x += 1e-4f;
            moved.uvSets[0].values[flip++ % moved.uvSets[0].values.size()].x += 1e-4f;
            sub.build(moved, s);
        });
        s.reuseTopology = false;
        double fromOm = medianMs(runs, [&] {
            PolygonMesh c = fromPolyMesh(spotOm, props);
            if (c.faceCount() != spot.faceCount()) std::abort();
        });
        row("OpenMesh CatmullClarkT (no creases, no UVs)", in, om, om, "OpenMesh");
        row("plain Far create+refine+primvar (pos+UV)", in, far, om, "OpenMesh");
        row("ours build: new topology (pos+UV)", in, ours, om, "OpenMesh");
        row("ours build, OpenSubdiv Far path", in, oursFar, om, "OpenMesh");
        row("ours build: fresh Subdivider per call", in, cold, om, "OpenMesh");
        row("ours build: same topology, new values", in, cached, om, "OpenMesh");
        std::printf("|   ours vs plain Far: %.2fx, vs our Far path %.2fx; stage medians ms: "
                    "convert-in %.3f, topology %.3f, interpolate %.3f, "
                    "convert-out %.3f\n",
                    far / ours, oursFar / ours, 1e3 * tm.convertIn, 1e3 * tm.topology,
                    1e3 * tm.interpolate, 1e3 * tm.convertOut);
        double conv = fromOm + 1e3 * (tm.convertIn + tm.convertOut);
        std::printf("|   OpenMesh<->OpenSubdiv conversion (PolyMesh->cage %.3f + descriptor + "
                    "level-N polygons) = %.3f ms = %.0f%% of the "
                    "refine time\n",
                    fromOm, conv, 100.0 * conv / ours);
    }

    // --- 2. Animated cage at level 4 -------------------------------------------
    std::printf("\n| %-44s | %-14s | %9s | %-22s |\n", "animated cage, per frame", "input",
                "median ms", "ratio");
    std::printf("|%s|%s|%s|%s|\n", std::string(46, '-').c_str(), std::string(16, '-').c_str(),
                std::string(11, '-').c_str(), std::string(24, '-').c_str());
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> jitter(-0.01f, 0.01f);
    std::vector<std::vector<glm::vec3>> frames(8, spot.positions);
    for (auto& f : frames) {
        for (auto& p : f) p += glm::vec3(jitter(rng), jitter(rng), jitter(rng));
    }
    size_t frame = 0;
    PolygonMesh moving = spot;
    const char* in = "spot L4";
    {
        SubdivisionSettings s;
        s.level = 4;
        s.threads = 1;
        s.buildRenderMesh = false;
        s.reuseTopology = false; // a full re-refinement, as a user without stencils does
        Subdivider full, fullPositions;
        PolygonMesh movingNoUv = spot; // what an animated cage needs per frame: positions only
        movingNoUv.uvSets.clear();
        std::vector<glm::vec3> fp;
        std::vector<glm::vec2> fu;
        // Far's flattened stencil table with its own UpdateValues.
        double farStencilBuild = 0;
        std::unique_ptr<const Far::StencilTable> table;
        std::vector<glm::vec3> farOut;
        {
            auto t0 = Clock::now();
            Far::TopologyDescriptor d;
            d.numVertices = int(spot.positions.size());
            d.numFaces = int(spot.faceSizes.size());
            d.numVertsPerFace = reinterpret_cast<const int*>(spot.faceSizes.data());
            d.vertIndicesPerFace = reinterpret_cast<const int*>(spot.faceVertices.data());
            using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
            std::unique_ptr<Far::TopologyRefiner> r(Factory::Create(
                d, Factory::Options(OpenSubdiv::Sdc::SCHEME_CATMARK, OpenSubdiv::Sdc::Options())));
            r->RefineUniform(Far::TopologyRefiner::UniformOptions(4));
            Far::StencilTableFactory::Options so;
            so.generateIntermediateLevels = false;
            so.generateOffsets = true;
            table.reset(Far::StencilTableFactory::Create(*r, so));
            farStencilBuild = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            farOut.resize(size_t(table->GetNumStencils()));
        }
        SubdivisionSettings a = s;
        a.animate = true;
        a.buildRenderMesh = true;
        auto t0 = Clock::now();
        Subdivider anim(spot, a);
        double ourBuild = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        RenderMesh out = anim.renderMesh();
        const std::vector<double> med = interleavedMediansMs(
            runs, {[&] {
                       moving.positions = frames[frame++ % frames.size()];
                       plainFar(moving, 4, fp, fu);
                   },
                   [&] {
                       moving.positions = frames[frame % frames.size()];
                       full.build(moving, s);
                   },
                   [&] {
                       movingNoUv.positions = frames[frame % frames.size()];
                       fullPositions.build(movingNoUv, s);
                   },
                   [&] {
                       const auto& f = frames[frame % frames.size()];
                       PrimvarView<const glm::vec3> src{f.data()};
                       PrimvarView<glm::vec3> dst{farOut.data()};
                       table->UpdateValues(src, dst);
                   },
                   [&] { anim.update(frames[frame % frames.size()], out, nullptr, false); },
                   [&] { anim.update(frames[frame % frames.size()], out, nullptr, true); }});
        const double far = med[0], rebuild = med[1], rebuildPositions = med[2], farStencil = med[3],
                     update = med[4], updateN = med[5];
        // Baseline: OpenSubdiv's full re-refinement (the "full
        // re-refinement, measured 2.4 ms" anchor of the goal is Far's).
        row("full re-refinement: plain Far (pos+UV)", in, far, far, "Far re-refine");
        row("full re-refinement: ours (pos+UV)", in, rebuild, far, "Far re-refine");
        row("full re-refinement: ours, positions only", in, rebuildPositions, far, "Far re-refine");
        row("Far StencilTable::UpdateValues (flattened)", in, farStencil, far, "Far re-refine");
        row("ours factored stencils: positions", in, update, far, "Far re-refine");
        row("ours factored stencils: positions + normals", in, updateN, far, "Far re-refine");
        std::printf("|   vs our own positions-only re-refinement (%.3f ms): factored stencils "
                    "%.2fx, + normals %.2fx, Far UpdateValues %.2fx\n",
                    rebuildPositions, rebuildPositions / update, rebuildPositions / updateN,
                    rebuildPositions / farStencil);
        std::printf("|   one-time setup: Far StencilTableFactory %.1f ms (%zu weights); ours build "
                    "with stencils %.1f ms (%zu weights)\n",
                    farStencilBuild, table->GetControlIndices().size(), ourBuild,
                    anim.stencilWeightCount());
    }
    {
        SubdivisionSettings s;
        s.level = 4;
        s.threads = 1;
        s.limit = true;
        Subdivider full;
        double rebuild = medianMs(std::max(3, runs / 3), [&] {
            moving.positions = frames[frame++ % frames.size()];
            full.build(moving, s);
        });
        s.animate = true;
        Subdivider anim(spot, s);
        RenderMesh out = anim.renderMesh();
        LimitFrame lf = anim.limitFrame();
        double update =
            medianMs(runs, [&] { anim.update(frames[frame++ % frames.size()], out, &lf); });
        row("limit: full rebuild (P, dP/du, dP/dv, N, UV)", in, rebuild, rebuild, "limit rebuild");
        row("limit: stencil update (P, dP/du, dP/dv, N)", in, update, rebuild, "limit rebuild");
        std::printf("|   limit update weights: %zu (adaptive points, local points, %zu samples)\n",
                    anim.stencilWeightCount(), anim.renderMesh().vertexCount());
    }
    const PolygonMesh bob =
        loadPolygonMesh(std::string(SURFGRAD_DATA_DIR) + "/meshes/bob/bob_tri.obj");
    threadsSection(spot, bob, runs);
    return 0;
}
