"""MikkTSpace tangents of Blender's active mesh through surfgrad, stored as a corner attribute.

    blender --background FILE.blend --python examples/python/blender_tangents.py -- \\
        [--uv NAME] [--name surfgrad_tangent] [--as-vector] [--threads N] [--compare] \\
        [--save [OUT.blend]]

Blender hands out a mesh as loops (face corners): each loop names a vertex and carries its own
normal (split normals) and UV. The script reads the active object's mesh with foreach_get into
float32 numpy arrays (no Python loop over the mesh), runs surfgrad.mikktspace (Mikkelsen 2008,
the published mikktspace.c, docs/tangents.md) with one surfgrad vertex per loop (MikkTSpace welds
equal values itself, so this is the same as Blender's own input) and writes one tangent per loop
back as a CORNER attribute:

  default       FLOAT_COLOR "surfgrad_tangent": (x, y, z, w), xyz unit along +U in object space,
                w = +-1 with bitangent = w * cross(normal, tangent) (MikkTSpace, glTF TANGENT);
  --as-vector   FLOAT_VECTOR "surfgrad_tangent" (x, y, z) and FLOAT "surfgrad_tangent_sign" (w).

Blender's UVs have (0, 0) at the lower left with V up, as surfgrad's (s, t): no flip. Faces must
be triangles or quads (MikkTSpace's rule; Blender's own calc_tangents refuses n-gons too): add a
Triangulate modifier and apply it first. --compare also runs Blender's calc_tangents and prints
the largest angle between the two (both implement the same reference algorithm). --save writes
the .blend (to OUT.blend, else over FILE.blend). Object mode is required (edit-mode data is not
in mesh.loops).

The numpy core (inputs_from_loops, loop_tangents, attribute_values, compute_loop_tangents) does
not import bpy: tests/python/test_blender_core.py runs it on meshes laid out as Blender does.
Run with Debian 12's Blender 3.4 (the ctest python_blender when blender is installed); the bpy
calls also follow Blender 4.x (mesh.corner_normals from 4.1, calc_normals_split before).
"""
import argparse
import sys

import numpy as np


# ---------------------------------------------------------------------------
# The numpy core (no bpy)


def inputs_from_loops(
    vertex_positions, loop_vertices, loop_normals, loop_uvs, face_loop_starts, face_loop_totals
):
    """surfgrad.mikktspace's inputs from Blender's arrays.

    vertex_positions (V, 3), loop_vertices (L,), loop_normals (L, 3), loop_uvs (L, 2),
    face_loop_starts (F,) and face_loop_totals (F,), any numeric dtype and order. One surfgrad
    vertex per loop: positions[loop] = vertex_positions[loop_vertices[loop]].

    Returns a dict with positions, normals, uvs (float32, C-contiguous), corner_vertices
    (uint32: the loops of face 0, then face 1, ...), face_sizes (uint32) and corner_loops (the
    loop of every corner, for loop_tangents). Raises ValueError for an n-gon (naming the first
    face with more than 4 corners), a face with fewer than 3, or arrays that do not fit together.
    """
    vertex_positions = np.asarray(vertex_positions, np.float32).reshape(-1, 3)
    loop_vertices = np.asarray(loop_vertices, np.int64).ravel()
    loop_normals = np.asarray(loop_normals, np.float32).reshape(-1, 3)
    loop_uvs = np.asarray(loop_uvs, np.float32).reshape(-1, 2)
    starts = np.asarray(face_loop_starts, np.int64).ravel()
    totals = np.asarray(face_loop_totals, np.int64).ravel()
    loops = loop_vertices.shape[0]
    if loop_normals.shape[0] != loops or loop_uvs.shape[0] != loops:
        raise ValueError(
            f"{loops} loops but {loop_normals.shape[0]} loop normals and "
            f"{loop_uvs.shape[0]} loop UVs"
        )
    if starts.shape != totals.shape:
        raise ValueError(
            f"{starts.shape[0]} face loop starts but {totals.shape[0]} face loop totals"
        )
    if loops and (loop_vertices.min() < 0 or loop_vertices.max() >= vertex_positions.shape[0]):
        raise ValueError(f"a loop names a vertex outside 0..{vertex_positions.shape[0] - 1}")
    bad = np.flatnonzero((totals < 3) | (totals > 4))
    if bad.size:
        f = int(bad[0])
        raise ValueError(
            f"face {f} has {int(totals[f])} corners: MikkTSpace takes triangles and quads "
            f"(apply a Triangulate modifier first; {bad.size} such faces)"
        )
    if totals.size and (starts.min() < 0 or (starts + totals).max() > loops):
        raise ValueError(f"face loop ranges outside the {loops} loops")
    # The loops of each face, face after face (Blender stores them so; starts may be in any
    # order): corner k of face f is loop starts[f] + k.
    first_corner = np.cumsum(totals) - totals
    corner_loops = np.repeat(starts - first_corner, totals) + np.arange(totals.sum())
    return {
        "positions": np.ascontiguousarray(vertex_positions[loop_vertices]),
        "normals": np.ascontiguousarray(loop_normals),
        "uvs": np.ascontiguousarray(loop_uvs),
        "corner_vertices": corner_loops.astype(np.uint32),
        "face_sizes": totals.astype(np.uint32),
        "corner_loops": corner_loops,
    }


def loop_tangents(corner_tangents, corner_loops, loop_count):
    """(L, 4) float32 tangents per loop from surfgrad's per-corner result (C, 4); loops no face
    uses keep MikkTSpace's default frame (1, 0, 0, -1)."""
    out = np.tile(np.array([1, 0, 0, -1], np.float32), (loop_count, 1))
    out[np.asarray(corner_loops)] = corner_tangents
    return out


def attribute_values(tangents, as_vector=False):
    """Flat float32 arrays for attribute.data.foreach_set: {"color": (L*4,)} for a FLOAT_COLOR
    attribute, or {"vector": (L*3,), "value": (L,)} for FLOAT_VECTOR plus the FLOAT sign."""
    tangents = np.asarray(tangents, np.float32)
    if as_vector:
        return {
            "vector": np.ascontiguousarray(tangents[:, :3]).ravel(),
            "value": tangents[:, 3].copy(),
        }
    return {"color": np.ascontiguousarray(tangents).ravel()}


def compute_loop_tangents(
    vertex_positions,
    loop_vertices,
    loop_normals,
    loop_uvs,
    face_loop_starts,
    face_loop_totals,
    threads=0,
):
    """MikkTSpace tangents per loop (L, 4) through surfgrad.mikktspace."""
    import surfgrad

    inputs = inputs_from_loops(
        vertex_positions, loop_vertices, loop_normals, loop_uvs, face_loop_starts, face_loop_totals
    )
    corner = surfgrad.mikktspace(
        inputs["positions"],
        inputs["normals"],
        inputs["uvs"],
        inputs["corner_vertices"],
        inputs["face_sizes"],
        threads=threads,
    )
    return loop_tangents(corner, inputs["corner_loops"], np.asarray(loop_vertices).size)


# ---------------------------------------------------------------------------
# Blender (bpy) side


def read_mesh(mesh, uv_name=None):
    """The arrays compute_loop_tangents takes, read with foreach_get (object mode)."""
    vertices, loops, faces = len(mesh.vertices), len(mesh.loops), len(mesh.polygons)
    positions = np.empty(vertices * 3, np.float32)
    mesh.vertices.foreach_get("co", positions)
    loop_vertices = np.empty(loops, np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vertices)
    normals = np.empty(loops * 3, np.float32)
    if hasattr(mesh, "corner_normals"):  # Blender 4.1 and later
        mesh.corner_normals.foreach_get("vector", normals)
    else:
        mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", normals)
    layer = mesh.uv_layers.get(uv_name) if uv_name else mesh.uv_layers.active
    if layer is None:
        raise ValueError(f"mesh {mesh.name!r} has no UV map {uv_name or '(active)'}")
    uvs = np.empty(loops * 2, np.float32)
    layer.data.foreach_get("uv", uvs)
    starts = np.empty(faces, np.int32)
    totals = np.empty(faces, np.int32)
    mesh.polygons.foreach_get("loop_start", starts)
    mesh.polygons.foreach_get("loop_total", totals)
    return positions, loop_vertices, normals, uvs, starts, totals, layer.name


def write_attributes(mesh, tangents, name, as_vector):
    """Replaces the CORNER attribute(s) `name` (and `name`_sign) with the tangents."""
    values = attribute_values(tangents, as_vector)
    kinds = (
        [(name, "FLOAT_VECTOR", "vector"), (name + "_sign", "FLOAT", "value")]
        if as_vector
        else [(name, "FLOAT_COLOR", "color")]
    )
    for attr_name, attr_type, key in kinds:
        old = mesh.attributes.get(attr_name)
        if old is not None:
            mesh.attributes.remove(old)
        mesh.attributes.new(attr_name, attr_type, "CORNER").data.foreach_set(key, values[key])
    mesh.update()


def blender_tangents(mesh, uv_name):
    """Blender's own MikkTSpace (calc_tangents) per loop, (L, 4)."""
    mesh.calc_tangents(uvmap=uv_name)
    loops = len(mesh.loops)
    tangents = np.empty(loops * 3, np.float32)
    signs = np.empty(loops, np.float32)
    mesh.loops.foreach_get("tangent", tangents)
    mesh.loops.foreach_get("bitangent_sign", signs)
    return np.concatenate([tangents.reshape(-1, 3), signs[:, None]], axis=1)


def main(argv):
    import bpy

    parser = argparse.ArgumentParser(
        prog="blender_tangents.py", description=__doc__.splitlines()[0]
    )
    parser.add_argument("--uv", help="UV map name (default: the active one)")
    parser.add_argument("--name", default="surfgrad_tangent", help="attribute name")
    parser.add_argument("--as-vector", action="store_true", help="FLOAT_VECTOR + FLOAT sign")
    parser.add_argument("--threads", type=int, default=0, help="0: all cores")
    parser.add_argument("--compare", action="store_true", help="against Blender's calc_tangents")
    parser.add_argument(
        "--max-angle",
        type=float,
        metavar="DEG",
        help="with --compare: exit 1 when an angle exceeds DEG or a sign differs",
    )
    parser.add_argument("--save", nargs="?", const="", metavar="OUT.blend", help="write the .blend")
    args = parser.parse_args(argv)

    obj = bpy.context.view_layer.objects.active
    if obj is None or obj.type != "MESH":
        raise SystemExit("blender_tangents.py: the active object is not a mesh")
    if obj.mode != "OBJECT":
        bpy.ops.object.mode_set(mode="OBJECT")
    mesh = obj.data
    *arrays, uv_name = read_mesh(mesh, args.uv)
    tangents = compute_loop_tangents(*arrays, threads=args.threads)
    write_attributes(mesh, tangents, args.name, args.as_vector)
    mirrored = int((tangents[:, 3] < 0).sum())
    print(
        f"{obj.name}: {len(mesh.loops)} loops, UV map {uv_name!r}, {mirrored} mirrored; "
        f"wrote corner attribute {args.name!r}"
    )
    if args.compare:
        theirs = blender_tangents(mesh, uv_name)
        cross = np.linalg.norm(np.cross(tangents[:, :3], theirs[:, :3]).astype(np.float64), axis=1)
        dot = np.sum(tangents[:, :3].astype(np.float64) * theirs[:, :3], axis=1)
        worst = float(np.degrees(np.arctan2(cross, dot)).max()) if len(dot) else 0.0
        signs = int((tangents[:, 3] == theirs[:, 3]).sum())
        print(f"  against calc_tangents: max angle {worst:.2e} deg, signs agree {signs}/{len(dot)}")
        if args.max_angle is not None and (worst > args.max_angle or signs != len(dot)):
            print(f"blender_tangents.py: differs from calc_tangents beyond {args.max_angle} deg")
            sys.exit(1)
    if args.save is not None:
        if args.save:
            bpy.ops.wm.save_as_mainfile(filepath=args.save, copy=True)
        else:
            bpy.ops.wm.save_mainfile()


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else [])
