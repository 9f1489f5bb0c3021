#!/usr/bin/env python3
"""What the Python binding adds to the C++ calls, on a >= 1M-triangle mesh.

Input (--mesh): spot (data/meshes/spot/spot_control_mesh.obj) refined by
surfgrad.Subdivider to Catmull-Clark level 6, the render mesh split at UV
seams: 1,499,136 triangles (default); or the mesh of bench/tangents_bench.cpp
built the same way in numpy: blub (load_mesh: area-weighted normals, split at
UV seams) split 1-to-4 at edge midpoints (positions, normals and UVs
interpolated, normals renormalised) three times: 909,312 triangles.

Rows (medians of --runs, one process, so the ratios are same-run figures):
  mikktspace()          surfgrad.mikktspace(...): argument checks, the input
                        scan (mikktspaceInputProblem), a new generator (cold
                        buffers), the output moved into numpy;
  generate (warm)       MikkTSpaceGenerator.generate(): the same checks, the
                        generator's buffers reused, output moved;
  generate (out=)       the same, written into a caller's array (one copy);
  C++ generate()        the C++ call inside the last generate(), timed by the
                        binding (last_generate_ms): the baseline;
  overhead              binding wall time minus the C++ call, and the ratio.
Also Subdivider (spot, Catmull-Clark level 4) against its own stage timings,
and to_height on a 1024^2 slope grid (a copy in, the result moved out).

  PYTHONPATH=build/python python3 bench/python_binding_bench.py [--runs N] [--threads N]
      [--mesh spot|blub]
"""
import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import surfgrad


def split4(positions, normals, uvs, tris):
    """One 1-to-4 split at edge midpoints (shared midpoints per edge)."""
    v = len(positions)
    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    keys = np.sort(edges, axis=1).astype(np.uint64)
    key = keys[:, 0] * np.uint64(v) + keys[:, 1]
    uniq, inverse = np.unique(key, return_inverse=True)
    a = (uniq // np.uint64(v)).astype(np.int64)
    b = (uniq % np.uint64(v)).astype(np.int64)
    mid = lambda x: (x[a] + x[b]) * np.float32(0.5)
    n_mid = mid(normals)
    n_mid /= np.linalg.norm(n_mid, axis=1, keepdims=True)
    p2 = np.concatenate([positions, mid(positions)]).astype(np.float32)
    n2 = np.concatenate([normals, n_mid]).astype(np.float32)
    uv2 = np.concatenate([uvs, mid(uvs)]).astype(np.float32)
    t = len(tris)
    m = (inverse.reshape(3, t).T + v).astype(np.uint32)  # midpoints of edges 01, 12, 20
    t0, t1, t2 = tris[:, 0], tris[:, 1], tris[:, 2]
    out = np.concatenate([
        np.stack([t0, m[:, 0], m[:, 2]], 1),
        np.stack([m[:, 0], t1, m[:, 1]], 1),
        np.stack([m[:, 2], m[:, 1], t2], 1),
        np.stack([m[:, 0], m[:, 1], m[:, 2]], 1),
    ]).astype(np.uint32)
    return p2, n2, uv2, np.ascontiguousarray(out)


def median_ms(fn, runs):
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        fn()
        times.append((time.perf_counter() - t0) * 1e3)
    return statistics.median(times), times


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=9)
    ap.add_argument("--threads", type=int, default=1, help="generator threads (default 1)")
    ap.add_argument("--mesh", choices=["spot", "blub"], default="spot",
                    help="spot: Catmull-Clark level 6, 1.5M triangles (default); blub: split x3")
    ap.add_argument("--data", default=os.environ.get("SURFGRAD_DATA_DIR",
                                                     str(Path(__file__).resolve().parents[1] / "data")))
    args = ap.parse_args()
    data = Path(args.data)

    if args.mesh == "blub":
        mesh = surfgrad.load_mesh(data / "meshes/blub/blub_triangulated.obj")
        p, n = mesh.positions.copy(), mesh.normals.copy()
        uv, t = mesh.uv_sets[0].copy(), mesh.indices.copy()
        for _ in range(3):
            p, n, uv, t = split4(p, n, uv, t)
        what = "blub split 1-to-4 x3"
    else:
        cage = surfgrad.load_cage(data / "meshes/spot/spot_control_mesh.obj")
        mesh = surfgrad.Subdivider(cage, 6).render_mesh
        p, n, uv, t = mesh.positions, mesh.normals, mesh.uv_sets[0], mesh.indices
        what = "spot Catmull-Clark level 6 (split at UV seams)"
    print(f"input: {what}: {len(t)} triangles, {len(p)} vertices; "
          f"threads {args.threads}; {args.runs} runs; surfgrad {surfgrad.__version__}")

    rows = []
    ms, _ = median_ms(lambda: surfgrad.mikktspace(p, n, uv, t, threads=args.threads), args.runs)
    rows.append(("mikktspace() (new generator)", ms))
    gen = surfgrad.MikkTSpaceGenerator(threads=args.threads)
    gen.generate(p, n, uv, t)  # warm the buffers
    cpp = []

    def warm():
        gen.generate(p, n, uv, t)
        cpp.append(gen.last_generate_ms())

    ms_warm, _ = median_ms(warm, args.runs)
    rows.append(("generate (warm, result moved)", ms_warm))
    out = np.empty((t.size, 4), np.float32)
    cpp_out = []

    def warm_out():
        gen.generate(p, n, uv, t, out=out)
        cpp_out.append(gen.last_generate_ms())

    ms_out, _ = median_ms(warm_out, args.runs)
    rows.append(("generate (warm, out=)", ms_out))
    cpp_ms = statistics.median(cpp + cpp_out)
    rows.append(("C++ generate() inside (baseline)", cpp_ms))
    print(f"{'row':36s} {'median ms':>10s} {'/ C++':>7s}")
    for name, v in rows:
        print(f"{name:36s} {v:10.2f} {v / cpp_ms:7.3f}")
    print(f"overhead of generate (warm): {ms_warm - statistics.median(cpp):.2f} ms "
          f"({(ms_warm / statistics.median(cpp) - 1) * 100:.1f}%); with out=: "
          f"{ms_out - statistics.median(cpp_out):.2f} ms")

    cage = surfgrad.load_cage(data / "meshes/spot/spot_control_mesh.obj")

    def build():
        build.sub = surfgrad.Subdivider(cage, 4, threads=args.threads)

    ms_sub, _ = median_ms(build, max(3, args.runs // 2))
    stages = sum(build.sub.timings.values()) * 1e3
    print(f"Subdivider(spot, level 4): {ms_sub:.2f} ms wall, C++ stages {stages:.2f} ms "
          f"({build.sub.render_mesh.triangle_count} triangles; ratio {ms_sub / stages:.3f})")

    rng = np.random.default_rng(1)
    height = rng.standard_normal((1024, 1024)).astype(np.float32)
    slopes = surfgrad.normalmap.from_height(height, 1.0)
    ms_h, _ = median_ms(lambda: surfgrad.normalmap.to_height(slopes), 3)
    print(f"normalmap.to_height 1024^2: {ms_h:.2f} ms (input copy of {slopes.nbytes / 2**20:.0f} MiB "
          f"included)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
