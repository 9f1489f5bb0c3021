#!/usr/bin/env python3
"""MikkTSpace (or limit-surface) tangents for a glTF model, written back as a .glb.

    gltf_tangents.py [IN.gltf|.glb|.obj] OUT.glb [--uv-set K] [--method mikktspace|limit]
                     [--level N] [--threads N]

Default input: data/gltf/NormalTangentTest/glTF/NormalTangentTest.gltf (a Khronos sample that
ships no tangents, so an engine has to make them).

"mikktspace" (default) runs the reference algorithm of Mikkelsen 2008 (section 4.2, the published
mikktspace.c; docs/tangents.md) on the file's triangles: the tangents agree with what Blender,
Unity and Unreal compute, and vertices whose corners disagree (mirror seams) are split. "limit"
loads the file as a control cage, refines it to --level with limit evaluation and stores the exact
tangent of the Catmull-Clark limit surface at every vertex (docs/tangents.md, "limit").

The output holds POSITION, NORMAL, TEXCOORD_n (glTF's v = 1 - t, flipped back on save) and TANGENT
(xyz unit along +s, w = +-1 with bitangent = w cross(normal, tangent): glTF's convention). It prints
the vertices added, the tangents' unit length and orthogonality to the normals, and how many
triangles have a UV area within rounding (their frame follows the file's rounding).
"""
import argparse
import os
import sys
from pathlib import Path

import numpy as np

import surfgrad

DATA_DIR = Path(os.environ.get("SURFGRAD_DATA_DIR", Path(__file__).resolve().parents[2] / "data"))
DEFAULT_INPUT = DATA_DIR / "gltf/NormalTangentTest/glTF/NormalTangentTest.gltf"


def tangents_for_file(path, uv_set=0, method="mikktspace", level=2, threads=0):
    """The mesh of `path` with tangents for UV set `uv_set`, and the count generate_tangents
    returned (vertices added by MikkTSpace, irregular limit points for "limit")."""
    if method == "mikktspace":
        mesh = surfgrad.load_mesh(path, threads=threads)
        return surfgrad.generate_tangents(mesh, "mikktspace", uv_set, threads=threads)
    cage = surfgrad.load_cage(path, threads=threads)
    subdivider = surfgrad.Subdivider(cage, level, limit=True, threads=threads)
    return surfgrad.generate_tangents(
        subdivider.render_mesh, "limit", uv_set, subdivider.limit_frame, threads=threads
    )


def frame_checks(mesh):
    """Largest | |t| - 1 | and largest |t . n| over the vertices, in double."""
    t = mesh.tangents[:, :3].astype(np.float64)
    n = mesh.normals.astype(np.float64)
    return np.abs(np.linalg.norm(t, axis=1) - 1).max(), np.abs(np.sum(t * n, axis=1)).max()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("paths", nargs="+", metavar="PATH", help="[IN] OUT.glb")
    parser.add_argument("--uv-set", type=int, default=0)
    parser.add_argument("--method", choices=["mikktspace", "limit"], default="mikktspace")
    parser.add_argument("--level", type=int, default=2, help="refinement level for --method limit")
    parser.add_argument("--threads", type=int, default=0, help="0: all cores")
    args = parser.parse_args(argv)
    if len(args.paths) > 2:
        parser.error("expected [IN] OUT.glb")
    source = Path(args.paths[0]) if len(args.paths) == 2 else DEFAULT_INPUT
    output = Path(args.paths[-1])
    try:
        mesh, count = tangents_for_file(source, args.uv_set, args.method, args.level, args.threads)
        notes = surfgrad.save_mesh(output, mesh)
    except surfgrad.InputError as e:  # names the file, the element and the reason
        print(f"gltf_tangents: error: {e}", file=sys.stderr)
        return 1
    length_error, dot = frame_checks(mesh)
    added = (
        "vertices added where corners disagree"
        if args.method == "mikktspace"
        else "irregular points"
    )
    print(f"{source.name}: {mesh.vertex_count} vertices, {mesh.triangle_count} triangles")
    print(f"  {args.method} tangents on UV set {args.uv_set}: {count} {added}")
    print(f"  max | |t| - 1 | = {length_error:.2e}, max |t . n| = {dot:.2e}")
    print(f"  mirrored vertices (w = -1): {int((mesh.tangents[:, 3] < 0).sum())}")
    within = surfgrad.uv_area_within_rounding(mesh, args.uv_set)
    print(f"  triangles with a UV area within rounding: {within}")
    for note in notes:
        print(f"  note: {note}")
    print(f"wrote {output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
