# The numpy core of examples/python/blender_tangents.py (the part that does not need Blender):
# Blender's loop arrays (one vertex index, split normal and UV per loop; faces as loop start and
# loop count) turned into surfgrad.mikktspace's inputs, and the per-corner result back into one
# tangent per loop. Blender is not needed: the meshes below are laid out as Blender's
# foreach_get hands them out (flat float32 arrays, int32 indices).
#
# Known values: tests/mesh/tangents_mikktspace_test.cpp, the two-quad strip with UV = xy gives
# (1, 0, 0, +1) at every corner, and with the right quad mirrored (s = 2 - x) (-1, 0, 0, -1) there
# (MikkTSpace.MirroredUvsFlipTheSign); MikkTSpace's default frame is (1, 0, 0, -1).
import importlib.util
import sys

import numpy as np
import pytest

import surfgrad
from conftest import REPO_DIR, angle_deg


@pytest.fixture(scope="module")
def core():
    path = REPO_DIR / "examples/python/blender_tangents.py"
    spec = importlib.util.spec_from_file_location("blender_tangents", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def strip_loops(mirrored=False):
    """Two quads side by side, x in [0, 2], y in [0, 1], normal +z, as Blender stores them:
    6 shared vertices, 8 loops (4 per face, counter-clockwise), loop UVs s = x on the left
    and s = x or 2 - x on the right, t = y."""
    vertices = np.array(
        [[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], np.float32
    ).ravel()
    loop_vertices = np.array([0, 1, 4, 3, 1, 2, 5, 4], np.int32)
    xy = vertices.reshape(-1, 3)[loop_vertices, :2].astype(np.float64)
    s = xy[:, 0].copy()
    if mirrored:
        s[4:] = 2.0 - s[4:]
    uvs = np.stack([s, xy[:, 1]], axis=1).astype(np.float32).ravel()
    normals = np.tile(np.array([0, 0, 1], np.float32), 8)
    starts = np.array([0, 4], np.int32)
    totals = np.array([4, 4], np.int32)
    return vertices, loop_vertices, normals, uvs, starts, totals


def assert_frames(tangents, expected):
    expected = np.broadcast_to(np.asarray(expected, np.float32), tangents.shape)
    np.testing.assert_array_equal(tangents[:, 3], expected[:, 3])
    # frameNear of the C++ test: sums of angles and one 1/len scaling leave the last bit.
    assert angle_deg(tangents, expected).max() <= 1e-4


def test_importing_the_core_does_not_need_bpy(core):
    assert "bpy" not in sys.modules
    assert callable(core.compute_loop_tangents)


def test_inputs_from_loops_gives_one_vertex_per_loop(core):
    vertices, loop_vertices, normals, uvs, starts, totals = strip_loops()
    inputs = core.inputs_from_loops(vertices, loop_vertices, normals, uvs, starts, totals)
    assert inputs["positions"].shape == (8, 3) and inputs["positions"].dtype == np.float32
    assert inputs["normals"].shape == (8, 3) and inputs["uvs"].shape == (8, 2)
    assert inputs["corner_vertices"].dtype == np.uint32 and inputs["face_sizes"].dtype == np.uint32
    np.testing.assert_array_equal(inputs["corner_vertices"], np.arange(8))
    np.testing.assert_array_equal(inputs["face_sizes"], [4, 4])
    np.testing.assert_array_equal(inputs["positions"], vertices.reshape(-1, 3)[loop_vertices])
    for key in ("positions", "normals", "uvs"):
        assert inputs[key].flags.c_contiguous


def test_strip_with_uv_xy_gives_plus_x(core):
    tangents = core.compute_loop_tangents(*strip_loops(), threads=1)
    assert tangents.shape == (8, 4) and tangents.dtype == np.float32
    assert_frames(tangents, [1, 0, 0, 1])


def test_mirrored_strip_flips_the_sign(core):
    tangents = core.compute_loop_tangents(*strip_loops(mirrored=True))
    assert_frames(tangents[:4], [1, 0, 0, 1])
    assert_frames(tangents[4:], [-1, 0, 0, -1])


def test_the_core_gives_surfgrads_own_corner_result(core):
    # With loops in face order, loop k is corner k: the result is mikktspace's, bit for bit.
    vertices, loop_vertices, normals, uvs, starts, totals = strip_loops(mirrored=True)
    direct = surfgrad.mikktspace(
        vertices.reshape(-1, 3)[loop_vertices],
        normals.reshape(-1, 3),
        uvs.reshape(-1, 2),
        np.arange(8, dtype=np.uint32),
        np.array([4, 4], np.uint32),
    )
    np.testing.assert_array_equal(core.compute_loop_tangents(*strip_loops(mirrored=True)), direct)


def test_faces_whose_loops_are_stored_out_of_order(core):
    # Face 0 on loops 4..7 and face 1 on loops 0..3: every loop still gets its own tangent.
    vertices, loop_vertices, normals, uvs, starts, totals = strip_loops(mirrored=True)
    in_order = core.compute_loop_tangents(vertices, loop_vertices, normals, uvs, starts, totals)
    swap = np.r_[4:8, 0:4]
    swapped = core.compute_loop_tangents(
        vertices,
        loop_vertices[swap],
        normals.reshape(-1, 3)[swap],
        uvs.reshape(-1, 2)[swap],
        np.array([4, 0], np.int32),
        totals,
    )
    np.testing.assert_array_equal(swapped, in_order[swap])


def test_triangles_and_quads_mix(core):
    # The right quad as two triangles (loops 4..6 and 7..9): same directions, same signs.
    vertices, _, _, _, _, _ = strip_loops()
    loop_vertices = np.array([0, 1, 4, 3, 1, 2, 5, 1, 5, 4], np.int32)
    xy = vertices.reshape(-1, 3)[loop_vertices, :2]
    tangents = core.compute_loop_tangents(
        vertices,
        loop_vertices,
        np.tile(np.array([0, 0, 1], np.float32), 10),
        np.ascontiguousarray(xy, np.float32),
        np.array([0, 4, 7], np.int32),
        np.array([4, 3, 3], np.int32),
    )
    assert_frames(tangents, [1, 0, 0, 1])


def test_ngons_are_refused_naming_the_face(core):
    vertices = np.zeros((5, 3), np.float32)
    vertices[:, :2] = [[0, 0], [1, 0], [1.5, 1], [0.5, 1.5], [-0.5, 1]]
    loops = np.arange(8, dtype=np.int32) % 5
    with pytest.raises(ValueError, match="face 1 has 5 corners"):
        core.inputs_from_loops(vertices, loops, np.zeros((8, 3)), np.zeros((8, 2)), [0, 3], [3, 5])


def test_mismatched_arrays_are_refused(core):
    vertices, loop_vertices, normals, uvs, starts, totals = strip_loops()
    with pytest.raises(ValueError, match="loop UVs"):
        core.inputs_from_loops(vertices, loop_vertices, normals, uvs[:-2], starts, totals)
    with pytest.raises(ValueError, match="vertex"):
        core.inputs_from_loops(vertices, loop_vertices + 3, normals, uvs, starts, totals)


def test_loops_no_face_uses_keep_the_default_frame(core):
    corner = np.tile(np.array([1, 0, 0, 1], np.float32), (3, 1))
    tangents = core.loop_tangents(corner, np.array([0, 1, 2]), 5)
    np.testing.assert_array_equal(tangents[3:], [[1, 0, 0, -1]] * 2)


def test_attribute_values_for_foreach_set(core):
    tangents = core.compute_loop_tangents(*strip_loops(mirrored=True))
    color = core.attribute_values(tangents)
    assert set(color) == {"color"} and color["color"].shape == (32,)
    np.testing.assert_array_equal(color["color"].reshape(8, 4), tangents)
    split = core.attribute_values(tangents, as_vector=True)
    assert split["vector"].shape == (24,) and split["value"].shape == (8,)
    np.testing.assert_array_equal(split["vector"].reshape(8, 3), tangents[:, :3])
    np.testing.assert_array_equal(split["value"], tangents[:, 3])
    assert all(v.dtype == np.float32 for v in (*color.values(), *split.values()))
