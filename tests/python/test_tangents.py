# Tangent frames from Python (python/surfgrad/__init__.pyi, "Tangents"): surfgrad.mikktspace and
# MikkTSpaceGenerator (Mikkelsen 2008, section 4.2, and the published mikktspace.c; the rules are
# docs/tangents.md "MikkTSpace"), generate_tangents on a RenderMesh, limit_tangents (the chain rule
# on limit-surface derivatives) and uv_area_within_rounding.
#
# Known values, each with the C++ test it comes from:
#  - tests/mesh/tangents_mikktspace_test.cpp: the flat strip with UV = xy gives (1, 0, 0, +1);
#    mirrored UVs (-1, 0, 0, -1); seams, zero-area UV triangles, degenerate triangles and isolated
#    vertices their documented frames (the default frame is (1, 0, 0, -1)); quads split along the
#    shorter UV diagonal; agreement with the TANGENTs Blender wrote into NormalTangentMirrorTest;
#  - tests/mesh/tangents_limit_test.cpp: limitTangent's known answers and fallbacks, and the
#    exact constant tangent of an affine plane through the subdivider.
import numpy as np
import pytest

import surfgrad
from conftest import angle_deg, assert_names, gltf_primitive, normalized, plane_cage_obj, write_text

DEFAULT_FRAME = np.array([1, 0, 0, -1], np.float32)  # kMikkTSpaceDefaultFrame


def assert_frames_near(got, expected, max_deg=1e-4):
    """frameNear of tangents_mikktspace_test.cpp: same sign bit for bit, direction within
    max_deg (the exact-looking answers pass through sums of angles and one 1/len scaling, which
    can leave the last bit off 1.0), unit length to a few ulps."""
    got = np.asarray(got)
    expected = np.broadcast_to(np.asarray(expected, np.float32), got.shape)
    np.testing.assert_array_equal(got[:, 3], expected[:, 3])
    assert angle_deg(got, expected).max() <= max_deg, got
    np.testing.assert_allclose(
        np.linalg.norm(got[:, :3].astype(np.float64), axis=1), 1.0, atol=1e-6
    )


class Strip:
    """The flat strip of tangents_mikktspace_test.cpp: vertices in the xy plane, normal +z."""

    def __init__(self):
        self.positions, self.uvs, self.corners = [], [], []

    def add(self, position, uv):
        self.positions.append(position)
        self.uvs.append(uv)
        return len(self.positions) - 1

    def arrays(self):
        positions = np.array(self.positions, np.float32)
        normals = np.tile(np.array([0, 0, 1], np.float32), (len(positions), 1))
        return positions, normals, np.array(self.uvs, np.float32), np.array(self.corners, np.uint32)

    def tangents(self, **kwargs):
        return surfgrad.mikktspace(*self.arrays(), **kwargs)


def two_quad_strip(right_uvs):
    """Left quad x in [0, 1] with s = x, right quad x in [1, 2] with the given UVs at (2, 0) and
    (2, 1); the seam vertices a1, a2 are shared."""
    s = Strip()
    a0, a1 = s.add((0, 0, 0), (0, 0)), s.add((1, 0, 0), (1, 0))
    a2, a3 = s.add((1, 1, 0), (1, 1)), s.add((0, 1, 0), (0, 1))
    b1, b2 = s.add((2, 0, 0), right_uvs[0]), s.add((2, 1, 0), right_uvs[1])
    s.corners = [a0, a1, a2, a0, a2, a3, a1, b1, b2, a1, b2, a2]
    return s


def grid_mesh_arrays(n):
    """An n x n grid of quads split into triangles, a bumpy height field with UV = xy/n: 2 n^2
    triangles (above the 10k-triangle cut-over of the threaded path for n >= 72)."""
    y, x = np.mgrid[0 : n + 1, 0 : n + 1].astype(np.float64)
    z = 0.1 * np.sin(x * 0.37) * np.cos(y * 0.23)
    positions = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
    dzdx = 0.1 * 0.37 * np.cos(x * 0.37) * np.cos(y * 0.23)
    dzdy = -0.1 * 0.23 * np.sin(x * 0.37) * np.sin(y * 0.23)
    normals = normalized(np.stack([-dzdx, -dzdy, np.ones_like(x)], -1).reshape(-1, 3))
    uvs = (np.stack([x, y], -1).reshape(-1, 2) / n).astype(np.float32)
    v = np.arange((n + 1) * (n + 1)).reshape(n + 1, n + 1)
    a, b, c, d = v[:-1, :-1], v[:-1, 1:], v[1:, 1:], v[1:, :-1]
    tris = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3)
    return positions, normals.astype(np.float32), uvs, tris.astype(np.uint32)


# ---------------------------------------------------------------------------
# Known answers


def test_flat_strip_with_uv_xy_gives_plus_x():
    s = two_quad_strip([(2, 0), (2, 1)])  # s = x everywhere
    t = s.tangents()
    assert t.shape == (12, 4) and t.dtype == np.float32
    assert_frames_near(t, [1, 0, 0, 1])


def test_corner_vertices_as_triangles_array_gives_the_same_bits():
    positions, normals, uvs, corners = two_quad_strip([(2, 0), (2, 1)]).arrays()
    flat = surfgrad.mikktspace(positions, normals, uvs, corners)
    shaped = surfgrad.mikktspace(positions, normals, uvs, corners.reshape(-1, 3))
    np.testing.assert_array_equal(flat, shaped)


def test_mirrored_uvs_flip_the_sign():
    # MikkTSpace.MirroredUvsFlipTheSign: the right quad has s = 2 - x; +s runs toward -x and the
    # bitangent w * (n x t) = -1 * (0, -1, 0) = +y = +t.
    t = two_quad_strip([(0, 0), (0, 1)]).tangents()
    assert_frames_near(t[:6], [1, 0, 0, 1])
    assert_frames_near(t[6:], [-1, 0, 0, -1])


def test_uv_seam_sides_are_computed_separately():
    # MikkTSpace.UvSeamSidesAreComputedSeparately: the right quad on its own UV island (s = x + 4,
    # t = 2 y), sheared in position: P = (x, y + (x - 1) / 2) so dP/ds = (1, 0.5, 0).
    s = Strip()
    a0, a1 = s.add((0, 0, 0), (0, 0)), s.add((1, 0, 0), (1, 0))
    a2, a3 = s.add((1, 1, 0), (1, 1)), s.add((0, 1, 0), (0, 1))
    c1, c2 = s.add((1, 0, 0), (5, 0)), s.add((1, 1, 0), (5, 2))
    b1, b2 = s.add((2, 0.5, 0), (6, 0)), s.add((2, 1.5, 0), (6, 2))
    s.corners = [a0, a1, a2, a0, a2, a3, c1, b1, b2, c1, b2, c2]
    t = s.tangents()
    assert_frames_near(t[:6], [1, 0, 0, 1])
    right = np.array([1, 0.5, 0, 1], np.float32)
    right[:3] /= np.linalg.norm(right[:3])
    assert_frames_near(t[6:], right)  # float rounding: 1e-4 degrees


def test_zero_area_uv_triangle_takes_its_neighbours_frame():
    # MikkTSpace.ZeroAreaUvTriangleTakesItsNeighborsFrame.
    s = Strip()
    a0, a1 = s.add((0, 0, 0), (0, 0)), s.add((1, 0, 0), (1, 0))
    a2, a3 = s.add((1, 1, 0), (1, 1)), s.add((0, 1, 0), (0, 1))
    z = s.add((0.5, 2, 0), (0.5, 1))  # Z = (a3, a2, z): UVs on the line t = 1
    lone = [
        s.add((5, 0, 0), (0.5, 0.5)),
        s.add((6, 0, 0), (0.5, 0.5)),
        s.add((5, 1, 0), (0.5, 0.5)),
    ]
    s.corners = [a0, a1, a2, a0, a2, a3, a3, a2, z] + lone
    t = s.tangents()
    assert_frames_near(t[5:6], [1, 0, 0, 1])
    np.testing.assert_array_equal(t[6], t[5])  # Z's corner at a3 takes the square's frame there
    np.testing.assert_array_equal(t[7], t[2])  # ... and at a2
    np.testing.assert_array_equal(t[8], DEFAULT_FRAME)  # z meets no good triangle
    np.testing.assert_array_equal(t[9:], np.tile(DEFAULT_FRAME, (3, 1)))
    # Both triangles have exactly zero UV area: counted as within rounding
    # (mesh/include/surfgrad/mesh/tangents.h, uvAreaWithinRounding counts zero areas).
    positions, normals, uvs, corners = s.arrays()
    mesh = surfgrad.RenderMesh(positions, corners.reshape(-1, 3), normals=normals, uv_sets=[uvs])
    assert surfgrad.uv_area_within_rounding(mesh) == 2


def test_degenerate_triangles_copy_from_good_corners():
    # MikkTSpace.DegenerateTrianglesCopyFromGoodCorners.
    s = Strip()
    a0, a1 = s.add((0, 0, 0), (0, 0)), s.add((1, 0, 0), (1, 0))
    a2, a3 = s.add((1, 1, 0), (1, 1)), s.add((0, 1, 0), (0, 1))
    d = s.add((0, 1, 0), (0.2, 0.9))  # at a3's position, another UV
    e = [s.add((9, 9, 0), (0, 0)), s.add((9, 9, 0), (1, 0)), s.add((8, 9, 0), (0, 1))]
    s.corners = [a0, a1, a2, a0, a2, a3, a2, d, a3] + e
    t = s.tangents()
    np.testing.assert_array_equal(t[6], t[2])  # a2: copies the first good corner at a2
    np.testing.assert_array_equal(t[8], t[5])  # a3
    np.testing.assert_array_equal(t[7], DEFAULT_FRAME)  # d welds with nothing good
    np.testing.assert_array_equal(t[9:], np.tile(DEFAULT_FRAME, (3, 1)))


def test_opposite_frames_in_one_group_are_kept_apart():
    # MikkTSpace.OppositeFramesInOneGroupAreKeptApart: a strip folded back over itself at x = 1.
    s = Strip()
    a0, a1 = s.add((0, 0, 0), (0, 0)), s.add((1, 0, 0), (1, 0))
    a2, a3 = s.add((1, 1, 0), (1, 1)), s.add((0, 1, 0), (0, 1))
    b1, b2 = s.add((0, 0, 0.5), (2, 0)), s.add((0, 1, 0.5), (2, 1))
    s.corners = [a0, a1, a2, a0, a2, a3, a1, b1, b2, a1, b2, a2]
    t = s.tangents()
    assert_frames_near(t[[1, 2]], [1, 0, 0, 1])
    assert_frames_near(t[[6, 9, 11]], [-1, 0, 0, 1])


def test_quads_split_along_the_shorter_uv_diagonal():
    # MikkTSpace.QuadsSplitAlongTheShorterUvDiagonal: UV diagonal 1-3 is the shorter, so the
    # quad is triangles (0, 1, 3) and (1, 2, 3); dP/ds of each in double.
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    normals = np.tile(np.array([0, 0, 1], np.float32), (4, 1))
    uvs = np.array([[0, 0], [1, 0.5], [1.2, 2.6], [0.1, 1]], np.float32)
    corners = np.arange(4, dtype=np.uint32)

    def dp_ds(i0, i1, i2):
        p, t = positions.astype(np.float64), uvs.astype(np.float64)
        d1, d2 = p[i1] - p[i0], p[i2] - p[i0]
        e1, e2 = t[i1] - t[i0], t[i2] - t[i0]
        return normalized(e2[1] * d1 - e1[1] * d2)

    t013, t123, t012 = dp_ds(0, 1, 3), dp_ds(1, 2, 3), dp_ds(0, 1, 2)
    assert angle_deg(t013, t123) > 5 and angle_deg(t013, t012) > 5  # distinguishable choices
    t = surfgrad.mikktspace(positions, normals, uvs, corners, np.array([4], np.uint32))
    assert t.shape == (4, 4)
    assert angle_deg(t[0], t013) < 1e-4  # float rounding
    assert angle_deg(t[2], t123) < 1e-4
    np.testing.assert_array_equal(t[:, 3], np.ones(4, np.float32))
    # As two explicit triangles, corners 0 and 2 agree bit for bit.
    tt = surfgrad.mikktspace(positions, normals, uvs, np.array([0, 1, 3, 1, 2, 3], np.uint32))
    np.testing.assert_array_equal(t[0], tt[0])
    np.testing.assert_array_equal(t[2], tt[4])


def test_polygons_other_than_triangles_and_quads_are_ignored():
    # docs/tangents.md, step 1, and MikkTSpaceInput::faceSizes in surfgrad/mesh/tangents.h: as by the
    # reference, their corners get vec4(0); the other faces are unaffected.
    positions, normals, uvs, corners = two_quad_strip([(2, 0), (2, 1)]).arrays()
    pentagon = np.array([0, 1, 4, 5, 3], np.uint32)  # (0,0) (1,0) (2,0) (2,1) (0,1)
    t = surfgrad.mikktspace(
        positions,
        normals,
        uvs,
        np.concatenate([pentagon, corners[:3]]),
        np.array([5, 3], np.uint32),
    )
    np.testing.assert_array_equal(t[:5], np.zeros((5, 4), np.float32))
    assert_frames_near(t[5:], [1, 0, 0, 1])


def test_frames_dict_carries_the_same_tangents():
    # For P = xy with UV = xy: |dP/ds| = |dP/dt| = 1 and the bitangent is +y.
    s = two_quad_strip([(2, 0), (2, 1)])
    frames = s.tangents(frames=True)
    assert set(frames) == {"tangent", "mag_s", "bitangent", "mag_t", "sign"}
    assert frames["tangent"].shape == (12, 3) and frames["bitangent"].shape == (12, 3)
    for key in ("mag_s", "mag_t", "sign"):
        assert frames[key].shape == (12,) and frames[key].dtype == np.float32
    t = s.tangents()
    # The frame path and the direct path write the same bits (countOracleMismatches).
    np.testing.assert_array_equal(frames["tangent"], t[:, :3])
    np.testing.assert_array_equal(frames["sign"], t[:, 3])
    assert angle_deg(frames["bitangent"], [0, 1, 0]).max() < 1e-4  # float rounding
    # Magnitudes: sums of angle-weighted unit-scale values, a few ulps off 1.
    np.testing.assert_allclose(frames["mag_s"], 1.0, atol=1e-6)
    np.testing.assert_allclose(frames["mag_t"], 1.0, atol=1e-6)


def test_empty_input_gives_an_empty_result():
    empty3 = np.zeros((0, 3), np.float32)
    t = surfgrad.mikktspace(empty3, empty3, np.zeros((0, 2), np.float32), np.zeros(0, np.uint32))
    assert t.shape == (0, 4) and t.dtype == np.float32


# ---------------------------------------------------------------------------
# glTF samples, read without the module


def test_agrees_with_the_tangents_blender_wrote(data_dir):
    # MikkTSpace.AgreesWithNormalTangentMirrorTest: Blender's exporter ran MikkTSpace on its own
    # data and wrote rounded copies; measured max 0.0029 deg, and every sign agrees. 0.01 deg
    # bounds the file's rounding with a 3x margin; an algorithmic difference shows as degrees.
    p = gltf_primitive(data_dir / "gltf/NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf")
    t = surfgrad.mikktspace(p["POSITION"], p["NORMAL"], p["TEXCOORD_0"], p["indices"])
    file_t = p["TANGENT"][p["indices"]]
    assert (file_t[:, 3] < 0).sum() >= 100  # the mirrored half is exercised (measured 120)
    np.testing.assert_array_equal(t[:, 3], file_t[:, 3])
    assert angle_deg(t, file_t).max() < 0.01


def test_normal_tangent_test_invariants(data_dir):
    # MikkTSpace.NormalTangentTestInvariants: unit length (one float normalization: a few ulps),
    # orthogonal to the file's normals (|n| - 1 is up to ~1e-6 there: 1e-5), and w the sign of
    # each corner's triangle's UV area.
    p = gltf_primitive(data_dir / "gltf/NormalTangentTest/glTF/NormalTangentTest.gltf")
    t = surfgrad.mikktspace(p["POSITION"], p["NORMAL"], p["TEXCOORD_0"], p["indices"])
    tri = p["indices"].reshape(-1, 3)
    uv = p["TEXCOORD_0"].astype(np.float64)[tri]
    e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    area = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    good = np.abs(area) >= 1e-8  # triangles with a UV orientation to compare with
    assert good.mean() > 0.9
    t3 = t.reshape(-1, 3, 4)
    n3 = p["NORMAL"][tri].astype(np.float64)
    np.testing.assert_allclose(
        np.linalg.norm(t3[..., :3].astype(np.float64), axis=-1), 1, atol=1e-6
    )
    assert np.abs(np.sum(t3[..., :3] * n3, axis=-1)).max() < 1e-5
    expected_w = np.where(area > 0, 1.0, -1.0)[good]
    np.testing.assert_array_equal(t3[good, :, 3], np.repeat(expected_w[:, None], 3, axis=1))


# ---------------------------------------------------------------------------
# The generator object


def test_generator_fills_out_in_place_and_returns_it():
    positions, normals, uvs, corners = two_quad_strip([(0, 0), (0, 1)]).arrays()
    generator = surfgrad.MikkTSpaceGenerator(threads=1)
    out = np.full((12, 4), np.nan, np.float32)
    result = generator.generate(positions, normals, uvs, corners, out=out)
    assert result is out
    np.testing.assert_array_equal(out, surfgrad.mikktspace(positions, normals, uvs, corners))
    fresh = generator.generate(positions, normals, uvs, corners)
    assert fresh.shape == (12, 4) and not np.shares_memory(fresh, out)
    steps = generator.last_step_times()
    assert steps and all(isinstance(name, str) and ms >= 0.0 for name, ms in steps)
    assert generator.last_generate_ms() >= 0.0


def test_generator_reuse_does_not_leak_state():
    # MikkTSpace.GeneratorReuseDoesNotLeakState: buffers are reused between calls.
    a = two_quad_strip([(0, 0), (0, 1)]).arrays()
    b = grid_mesh_arrays(8)
    generator = surfgrad.MikkTSpaceGenerator()
    first = generator.generate(*a).copy()
    generator.generate(*b)
    np.testing.assert_array_equal(generator.generate(*a), first)


def test_generator_checks_out():
    positions, normals, uvs, corners = two_quad_strip([(2, 0), (2, 1)]).arrays()
    generator = surfgrad.MikkTSpaceGenerator()
    with pytest.raises(TypeError) as e:
        generator.generate(positions, normals, uvs, corners, out=np.zeros((12, 4), np.float64))
    assert_names(e, "out")
    with pytest.raises(ValueError) as e:
        generator.generate(positions, normals, uvs, corners, out=np.zeros((11, 4), np.float32))
    assert_names(e, "out")
    with pytest.raises(ValueError) as e:
        generator.generate(positions, normals, uvs, corners, out=np.zeros((4, 12), np.float32).T)
    assert_names(e, "out")


def test_results_are_the_same_bits_for_every_thread_count():
    arrays = grid_mesh_arrays(80)  # 12800 triangles: above the 10k cut-over of the threaded path
    one = surfgrad.mikktspace(*arrays, threads=1)
    for threads in (2, 3, 0):
        np.testing.assert_array_equal(surfgrad.mikktspace(*arrays, threads=threads), one)
    np.testing.assert_array_equal(surfgrad.MikkTSpaceGenerator(threads=2).generate(*arrays), one)


# ---------------------------------------------------------------------------
# Bad input: named, never a crash (tests/mesh/tangents_mikktspace_test.cpp, RejectsInvalidInput)


def bad_mikktspace_cases():
    positions, normals, uvs, corners = two_quad_strip([(2, 0), (2, 1)]).arrays()
    nan = positions.copy()
    nan[1, 0] = np.nan
    huge = positions.copy()
    huge[2, 0] = 1e30  # beyond 2^60: products could overflow to NaN
    long_normal = normals.copy()
    long_normal[0] = (0, 0, 1e5)  # not a unit normal (|component| <= 16)
    out_of_range = corners.copy()
    out_of_range[2] = 6
    return [
        (
            "float64 positions",
            TypeError,
            "positions",
            (positions.astype(np.float64), normals, uvs, corners),
            {},
        ),
        (
            "float64 uvs",
            TypeError,
            "uvs",
            (positions, normals, uvs.astype(np.float64), corners),
            {},
        ),
        (
            "int32 corners",
            TypeError,
            "corner_vertices",
            (positions, normals, uvs, corners.astype(np.int32)),
            {},
        ),
        (
            "normals (V, 2)",
            ValueError,
            "normals",
            (positions, normals[:, :2].copy(), uvs, corners),
            {},
        ),
        (
            "uvs with fewer rows",
            ValueError,
            "uvs",
            (positions, normals, uvs[:5].copy(), corners),
            {},
        ),
        (
            "non-contiguous normals",
            ValueError,
            "normals",
            (positions, np.repeat(normals, 2, 0)[::2], uvs, corners),
            {},
        ),
        ("NaN position", ValueError, "positions", (nan, normals, uvs, corners), {}),
        ("position beyond 2^60", ValueError, "positions", (huge, normals, uvs, corners), {}),
        ("normal of length 1e5", ValueError, "normals", (positions, long_normal, uvs, corners), {}),
        (
            "corner index out of range",
            ValueError,
            "corner_vertices",
            (positions, normals, uvs, out_of_range),
            {},
        ),
        (
            "corners not a multiple of 3",
            ValueError,
            "corner_vertices",
            (positions, normals, uvs, corners[:11].copy()),
            {},
        ),
        (
            "face sizes not adding up",
            ValueError,
            ("face_sizes", "face sizes"),
            (positions, normals, uvs, corners, np.array([4], np.uint32)),
            {},
        ),
        ("threads -1", ValueError, "threads", (positions, normals, uvs, corners), {"threads": -1}),
        (
            "threads 2000",
            ValueError,
            "threads",
            (positions, normals, uvs, corners),
            {"threads": 2000},
        ),
    ]


@pytest.mark.parametrize(
    "what, error, named, args, kwargs",
    bad_mikktspace_cases(),
    ids=[case[0] for case in bad_mikktspace_cases()],
)
def test_mikktspace_refuses_bad_input(what, error, named, args, kwargs):
    with pytest.raises(error) as e:
        surfgrad.mikktspace(*args, **kwargs)
    assert_names(e, named)


@pytest.mark.parametrize("threads", [-1, 1025])
def test_generator_refuses_bad_thread_counts(threads):
    with pytest.raises(ValueError) as e:
        surfgrad.MikkTSpaceGenerator(threads=threads)
    assert_names(e, "threads")


# ---------------------------------------------------------------------------
# generate_tangents on a RenderMesh


def strip_mesh(strip, uv_sets=1):
    positions, normals, uvs, corners = strip.arrays()
    return surfgrad.RenderMesh(
        positions, corners.reshape(-1, 3), normals=normals, uv_sets=[uvs] * uv_sets
    )


def test_generate_tangents_splits_the_mirror_seam():
    # MikkTSpace.MirroredUvsFlipTheSign (RenderMesh part): the seam vertices a1, a2 get one copy
    # per handedness, and every corner's vertex holds that corner's tangent bit for bit.
    strip = two_quad_strip([(0, 0), (0, 1)])
    per_corner = strip.tangents()
    mesh = strip_mesh(strip)
    out, added = surfgrad.generate_tangents(mesh)
    assert added == 2
    assert out.vertex_count == 8
    assert out.tangent_uv_set == 0
    np.testing.assert_array_equal(out.tangents[out.indices.ravel()], per_corner)
    # Positions, normals and UVs of every corner are those of the input.
    np.testing.assert_array_equal(
        out.positions[out.indices.ravel()], mesh.positions[mesh.indices.ravel()]
    )
    # A copy: the input keeps its 6 vertices and no tangents.
    assert mesh.vertex_count == 6 and mesh.tangents.shape == (0, 4)


def test_generate_tangents_gives_isolated_vertices_the_default_frame():
    # MikkTSpace.IsolatedAndUnusedVerticesGetTheDefaultFrame, on UV set 1.
    s = Strip()
    s.add((0, 0, 0), (0, 0)), s.add((1, 0, 0), (1, 0)), s.add((1, 1, 0), (1, 1))
    s.add((7, 7, 7), (0.5, 0.5))  # isolated
    s.corners = [0, 1, 2]
    mesh, added = surfgrad.generate_tangents(strip_mesh(s, uv_sets=2), "mikktspace", uv_set=1)
    assert added == 0
    assert mesh.tangents.shape == (4, 4)
    np.testing.assert_array_equal(mesh.tangents[3], DEFAULT_FRAME)
    assert_frames_near(mesh.tangents[:1], [1, 0, 0, 1])
    assert mesh.tangent_uv_set == 1


def test_pixel_method_clears_the_tangents():
    mesh, _ = surfgrad.generate_tangents(strip_mesh(two_quad_strip([(2, 0), (2, 1)])))
    assert mesh.tangents.shape[0] == mesh.vertex_count
    cleared, _ = surfgrad.generate_tangents(mesh, "pixel")
    assert cleared.tangents.shape == (0, 4)
    assert cleared.tangent_uv_set == -1
    assert mesh.tangents.shape[0] == mesh.vertex_count  # the input keeps them


def test_generate_tangents_refuses_bad_arguments():
    mesh = strip_mesh(two_quad_strip([(2, 0), (2, 1)]))
    with pytest.raises(ValueError) as e:
        surfgrad.generate_tangents(mesh, "MikkTSpace")  # names are lower case
    assert_names(e, "method")
    with pytest.raises(ValueError) as e:
        surfgrad.generate_tangents(mesh, uv_set=1)
    assert_names(e, ("uv_set", "UV set 1"))
    with pytest.raises(ValueError) as e:
        surfgrad.generate_tangents(mesh, "limit")  # needs the subdivider's limit frame
    assert_names(e, "frame")
    with pytest.raises(ValueError) as e:
        surfgrad.generate_tangents(mesh, threads=-1)
    assert_names(e, "threads")
    positions, _, uvs, corners = two_quad_strip([(2, 0), (2, 1)]).arrays()
    no_normals = surfgrad.RenderMesh(positions, corners.reshape(-1, 3), uv_sets=[uvs])
    with pytest.raises(ValueError) as e:
        surfgrad.generate_tangents(no_normals)
    assert_names(e, "normals")
    with pytest.raises(ValueError) as e:
        surfgrad.uv_area_within_rounding(mesh, 1)
    assert_names(e, ("uv_set", "UV set 1"))


# ---------------------------------------------------------------------------
# Limit-surface tangents


def test_limit_tangents_known_answers():
    # LimitTangent.ScaledAndRotatedCharts and DegenerateJacobiansFallBackFinitely, exactly.
    rows = [
        # dP/du, dP/dv, d(s,t)/du, d(s,t)/dv -> tangent, case
        ((1, 0, 0), (0, 1, 0), (2, 0), (0, 3), (1, 0, 0, 1), 0),  # s = 2u, t = 3v
        ((1, 0, 0), (0, 1, 0), (0, -1), (1, 0), (0, 1, 0, 1), 0),  # a rotation by -90 degrees
        ((1, 0, 0), (0, 1, 0), (0, 1), (1, 0), (0, 1, 0, -1), 0),  # s = v, t = u: mirrored
        ((1, 0, 0), (0, 1, 0), (-1, 0), (0, 1), (-1, 0, 0, -1), 0),  # s = -u: mirrored in s
        ((2, 0, 0), (0, 1, 0), (0, 0), (0, 0), (1, 0, 0, 1), 1),  # zero-area UVs: dP/du
        ((2, 0, 0), (0, 1, 0), (1, 1), (2, 2), (1, 0, 0, 1), 1),  # UVs collapsed to a line
        ((0, 0, 0), (0, 3, 0), (0, 0), (0, 0), (0, 1, 0, 1), 2),  # dP/du = 0 as well: dP/dv
        ((1, 0, 0), (2, 0, 0), (1, 0), (0, 1), (1, 0, 0, 1), 2),  # collapsed surface point
    ]
    columns = list(zip(*rows))
    dpdu, dpdv = (np.array(c, np.float32) for c in columns[:2])
    dstdu, dstdv = (np.array(c, np.float32) for c in columns[2:4])
    tangents, cases = surfgrad.limit_tangents(dpdu, dpdv, dstdu, dstdv)
    assert tangents.shape == (8, 4) and tangents.dtype == np.float32
    assert cases.shape == (8,) and cases.dtype == np.uint8
    np.testing.assert_array_equal(tangents, np.array(columns[4], np.float32))
    np.testing.assert_array_equal(cases, np.array(columns[5], np.uint8))


def test_limit_tangents_refuse_mismatched_arrays():
    a3, a2 = np.zeros((4, 3), np.float32), np.zeros((4, 2), np.float32)
    with pytest.raises(ValueError) as e:
        surfgrad.limit_tangents(a3, a3[:3].copy(), a2, a2)
    assert_names(e, "dpdv")
    with pytest.raises(ValueError) as e:
        surfgrad.limit_tangents(a3, a3, a3, a2)
    assert_names(e, "dstdu")
    with pytest.raises(TypeError) as e:
        surfgrad.limit_tangents(a3.astype(np.float64), a3, a2, a2)
    assert_names(e, "dpdu")
    nan = a3.copy()
    nan[0, 0] = np.nan
    with pytest.raises(ValueError) as e:
        surfgrad.limit_tangents(nan, a3, a2, a2)
    assert_names(e, "dpdu")


@pytest.mark.parametrize("scheme, irregular", [("bilinear", 0), ("catmark", 4)])
@pytest.mark.parametrize(
    "chart", [((0.5, -0.1), (0.2, 0.7)), ((-0.4, 0.3), (0.0, 0.25))], ids=["det>0", "mirrored"]
)
def test_affine_plane_gives_the_exact_constant_limit_tangent(tmp_path, scheme, irregular, chart):
    # LimitTangents.AffinePlaneGivesTheExactConstantTangent: P = (x, y, 0), (s, t) = A (x, y) + b
    # gives dP/ds = first column of A^-1, w = sign(det A) at every limit point. Catmull-Clark has
    # 4 irregular points: the smooth boundary corners, where the parameterization collapses.
    # Smooth face-varying interpolation keeps an affine UV map affine on the limit surface.
    a = np.array(chart, np.float64)
    cage = surfgrad.load_cage(
        write_text(tmp_path / "plane.obj", plane_cage_obj(4, 3, a, (0.1, 0.2)))
    )
    sub = surfgrad.Subdivider(cage, 2, limit=True, scheme=scheme, fvar="smooth")
    assert sub.render_mesh.vertex_count > 50
    mesh, count = surfgrad.generate_tangents(sub.render_mesh, "limit", 0, sub.limit_frame)
    assert count == irregular
    assert mesh.vertex_count == sub.render_mesh.vertex_count
    inv = np.linalg.inv(a)
    expected = np.array([inv[0, 0], inv[1, 0], 0.0])
    w = 1.0 if np.linalg.det(a) > 0 else -1.0
    np.testing.assert_array_equal(mesh.tangents[:, 3], np.full(mesh.vertex_count, w, np.float32))
    # Limit derivatives in float divided by the chart sines: measured 4.3e-3 deg next to the
    # collapsed corners, ~1e-5 deg elsewhere; 0.01 deg bounds it, a wrong chain rule is degrees.
    assert angle_deg(mesh.tangents, expected).max() < 1e-2
