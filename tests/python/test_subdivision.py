# Subdivision and blendshapes from Python (python/surfgrad/__init__.pyi, "Subdivision" and
# "Blendshapes"): OpenSubdiv refinement counts, Catmull-Clark refined and limit positions of the
# cube, stencil updates of animated cages, the cost estimate, morphing cages and render meshes.
#
# Known values:
#  - counts of tests/mesh/subdivision_test.cpp (Subdivision.FaceCountsPerLevel, HolesAreLeftOut)
#    and the growth rules of docs/mesh.md (F' = C, E' = 2E + C, V' = V + E + F);
#  - the cube [-1, 1]^3 (tests/mesh/mesh_test_util.h) by hand with Catmull-Clark's rules
#    (Catmull and Clark 1978): level-1 face points at distance 1, edge points (0, 3/4, 3/4),
#    vertex points (Q + 2R + (n - 3) P) / n = (5/9)(1, 1, 1); limit positions with the limit mask
#    (n^2 P + 4 sum e_j + sum f_j) / (n (n + 5)) of Halstead, Kass and DeRose 1993: corners
#    (1/2)(1, 1, 1), face centres (68/81) along their axis, edge midpoints (395/648)(0, 1, 1);
#  - linearity and affine invariance of subdivision (weights summing to 1), which
#    tests/mesh/subdivision_test.cpp StencilUpdateMatchesRebuild and mesh/include/surfgrad/mesh/morph.h
#    rely on: a moved cage refines to the moved surface (a doubled cage exactly, bit for bit);
#    morphing the cage or the refined mesh gives the same positions;
#  - glTF 2.0 sec. 3.7.2.2 blendshapes P0 + sum w_i dP_i and normalize(N0 + sum w_i dN_i),
#    evaluated here in double on AnimatedMorphSphere and the blendshape example's model
#    (examples/data/morph_blob.gltf, whose targets carry normal deltas).
import gc

import numpy as np
import pytest

import surfgrad
from conftest import CUBE_OBJ, REPO_DIR, angle_deg, assert_names, write_text

CORNER_LIMIT = 0.5  # (9 + 4 - 1) / 24 for a valence-3 corner of the [-1, 1] cube
FACE_LIMIT = 68.0 / 81.0  # level-1 face point: (16 + 12 + 20/9) / 36
EDGE_LIMIT = 395.0 / 648.0  # level-1 edge point: (12 + 76/9 + 3/2) / 36


@pytest.fixture
def cube(tmp_path):
    return surfgrad.load_cage(write_text(tmp_path / "cube.obj", CUBE_OBJ))


@pytest.fixture(scope="module")
def spot_path(data_dir):
    return data_dir / "meshes/spot/spot_control_mesh.obj"


def classify_cube_points(points):
    """Splits points of a cube-symmetric surface by how many coordinates are not 0: 3 (the
    corners' copies), 2 (edge midpoints), 1 (face centres). Rounding noise is below 1e-3."""
    nonzero = (np.abs(points) > 1e-3).sum(axis=1)
    return {k: np.abs(points[nonzero == k]) for k in (1, 2, 3)}


# ---------------------------------------------------------------------------
# Counts


@pytest.mark.parametrize("level", [0, 1, 2, 3])
def test_cube_face_and_vertex_counts_per_level(cube, level):
    # Subdivision.FaceCountsPerLevel: 6 * 4^level quads; closed genus 0 (V - E + F = 2 with
    # E = 2F): V = F + 2. A cube at level 1 has 26 vertices and 24 quads.
    sub = surfgrad.Subdivider(cube, level)
    faces = 6 * 4**level
    assert sub.refined.face_count == faces
    assert sub.refined.vertex_count == faces + 2
    assert sub.render_mesh.triangle_count == 2 * faces
    np.testing.assert_array_equal(sub.refined.face_sizes, np.full(faces, 4, np.uint32))


def test_spot_turns_every_corner_into_a_quad(spot_path):
    # Subdivision.FaceCountsPerLevel: one level turns an N-gon into N quads.
    cage = surfgrad.load_cage(spot_path)
    assert set(np.unique(cage.face_sizes)) >= {3, 4, 5}
    for level in (1, 2):
        sub = surfgrad.Subdivider(cage, level)
        assert sub.refined.face_count == cage.corner_count << (2 * (level - 1))
        assert len(sub.refined.uv_sets) == 1
        assert sub.refined.uv_sets[0][2].shape == (sub.refined.corner_count,)


def test_loop_scheme_gives_four_triangles_per_triangle(data_dir):
    tet = surfgrad.load_cage(data_dir / "osd-shapes/loop_tetrahedron.obj")
    sub = surfgrad.Subdivider(tet, 3, scheme="loop")
    assert sub.refined.face_count == tet.face_count * 64
    assert set(np.unique(sub.refined.face_sizes)) == {3}


@pytest.mark.parametrize("limit", [False, True])
def test_holes_are_left_out(data_dir, limit):
    # Subdivision.HolesAreLeftOut: a quad gives 16 faces at level 2, an N-gon 4 N.
    cage = surfgrad.load_cage(data_dir / "osd-shapes/catmark_hole_test1.obj")
    assert cage.holes
    sizes = cage.face_sizes
    expected = sum(
        16 if sizes[f] == 4 else 4 * int(sizes[f])
        for f in range(cage.face_count)
        if f not in cage.holes
    )
    sub = surfgrad.Subdivider(cage, 2, limit=limit)
    assert sub.refined.face_count == expected
    assert np.isfinite(sub.render_mesh.positions).all()
    used = np.zeros(sub.refined.vertex_count, bool)
    used[sub.refined.face_vertices] = True
    assert used.all()  # no isolated leftovers of the holes


def test_estimated_counts_follow_the_growth_rules(cube):
    # docs/mesh.md: F' = C, E' = 2E + C, V' = V + E + F per Catmull-Clark level. Cube: (V, E, F,
    # C) = (8, 12, 6, 24) -> level 1 (26, 48, 24, 96) -> level 2 (98, 192, 96, 384).
    cost = surfgrad.estimate_subdivision_cost(cube, 2)
    assert cost["faces"] == 96
    assert cost["vertices"] == 98
    assert cost["edges"] == 192
    assert all(isinstance(v, int) for v in cost.values())
    # The estimate is of what a build makes.
    sub = surfgrad.Subdivider(cube, 2)
    assert cost["faces"] == sub.refined.face_count and cost["vertices"] == sub.refined.vertex_count


# ---------------------------------------------------------------------------
# Positions: refined and limit


def test_cube_level_one_refined_points(cube):
    # Catmull-Clark's face, edge and vertex points of the [-1, 1] cube (values derived above).
    sub = surfgrad.Subdivider(cube, 1)
    groups = classify_cube_points(sub.refined.positions.astype(np.float64))
    assert [len(groups[k]) for k in (1, 2, 3)] == [6, 12, 8]
    # Averages of a few binary32 values of magnitude 1: rounding, 1e-6.
    np.testing.assert_allclose(groups[1].max(axis=1), 1.0, atol=1e-6)
    np.testing.assert_allclose(np.sort(groups[2], axis=1)[:, 1:], 0.75, atol=1e-6)
    np.testing.assert_allclose(groups[3], 5.0 / 9.0, atol=1e-6)


def test_cube_limit_positions_level_zero(cube):
    # The cage's own vertices pushed to the limit: (1/2)(+-1, +-1, +-1). Against OpenSubdiv's
    # limit masks the C++ test allows 1e-5 (float patch sums; measured 2.5e-7).
    sub = surfgrad.Subdivider(cube, 0, limit=True)
    positions = sub.render_mesh.positions.astype(np.float64)
    assert positions.shape[0] >= 8  # split at UV seams
    np.testing.assert_allclose(np.abs(positions), CORNER_LIMIT, atol=1e-5)


def test_cube_limit_positions_and_normals_level_one(cube):
    sub = surfgrad.Subdivider(cube, 1, limit=True)
    mesh = sub.render_mesh
    groups = classify_cube_points(mesh.positions.astype(np.float64))
    assert all(len(groups[k]) > 0 for k in (1, 2, 3))
    np.testing.assert_allclose(groups[3], CORNER_LIMIT, atol=1e-5)  # as above
    np.testing.assert_allclose(groups[1].max(axis=1), FACE_LIMIT, atol=1e-5)
    np.testing.assert_allclose(np.sort(groups[2], axis=1)[:, 1:], EDGE_LIMIT, atol=1e-5)
    # By symmetry the limit normal at a face centre is its axis. That point is regular, on a
    # B-spline patch corner (isolation 5): the exact tangent plane up to the float patch sums;
    # 1e-3 degrees (1.7e-5 rad) is ten times their rounding.
    positions = mesh.positions.astype(np.float64)
    centres = (np.abs(positions) > 1e-3).sum(axis=1) == 1
    axes = np.where(np.abs(positions[centres]) > 1e-3, np.sign(positions[centres]), 0.0)
    assert angle_deg(mesh.normals[centres], axes).max() < 1e-3


def test_limit_frame_shapes_and_absence(cube):
    assert surfgrad.Subdivider(cube, 1).limit_frame is None
    sub = surfgrad.Subdivider(cube, 1, limit=True)
    frame = sub.limit_frame
    v = sub.render_mesh.vertex_count
    assert frame.dpdu.shape == (v, 3) and frame.dpdv.shape == (v, 3)
    assert len(frame.duvdu) == 1 and frame.duvdu[0].shape == (v, 2)
    assert len(frame.duvdv) == 1 and frame.duvdv[0].shape == (v, 2)
    assert frame.ptex_face.shape == (v,) and frame.ptex_face.dtype == np.uint32
    assert frame.ptex_uv.shape == (v, 2)
    assert ((frame.ptex_uv >= 0) & (frame.ptex_uv <= 1)).all()
    assert sub.render_to_refined_vertex.shape == (v,)
    assert sub.render_to_refined_vertex.max() < sub.refined.vertex_count
    # Every render vertex is a copy of its refined vertex (split at UV seams only).
    np.testing.assert_array_equal(
        sub.render_mesh.positions, sub.refined.positions[sub.render_to_refined_vertex]
    )
    assert all(isinstance(k, str) and t >= 0.0 for k, t in sub.timings.items())
    assert isinstance(sub.used_specialized_refiner, bool)


def test_refinement_is_the_same_bits_for_every_thread_count(spot_path):
    cage = surfgrad.load_cage(spot_path)
    one = surfgrad.Subdivider(cage, 2, limit=True, threads=1).render_mesh
    two = surfgrad.Subdivider(cage, 2, limit=True, threads=2).render_mesh
    np.testing.assert_array_equal(one.positions, two.positions)
    np.testing.assert_array_equal(one.normals, two.normals)
    np.testing.assert_array_equal(one.indices, two.indices)


# ---------------------------------------------------------------------------
# Animated cages


def test_update_follows_a_scaling_of_the_cage_exactly(spot_path):
    # Subdivision and the limit are linear in the cage. Doubling every control point doubles
    # every product and sum exactly in binary floating point, so positions and derivatives come
    # back exactly doubled and the unit normals bit for bit the same.
    cage = surfgrad.load_cage(spot_path)
    sub = surfgrad.Subdivider(cage, 2, limit=True, animate=True)
    assert sub.stencil_weight_count > 0
    before = sub.render_mesh.copy()
    dpdu_before = sub.limit_frame.dpdu.copy()
    moved = sub.update(2 * cage.positions)
    assert isinstance(moved, surfgrad.RenderMesh)
    assert moved.vertex_count == before.vertex_count
    np.testing.assert_array_equal(moved.positions, 2 * before.positions)
    np.testing.assert_array_equal(moved.normals, before.normals)
    # The subdivider's own limit frame stays the rest pose's (copies; update returns a mesh).
    np.testing.assert_array_equal(sub.limit_frame.dpdu, dpdu_before)


def test_update_follows_a_translation_of_the_cage(spot_path):
    # The weights sum to 1, so a translated cage gives the translated surface. The translated
    # cage is rounded to binary32 (1 + 0.3 loses bits of 0.3) and the same weights are applied
    # in another order: the C++ bound of StencilUpdateMatchesRebuild, 1e-5 relative to the size.
    cage = surfgrad.load_cage(spot_path)
    sub = surfgrad.Subdivider(cage, 2, limit=True, animate=True)
    before = sub.render_mesh.copy()
    offset = np.array([1, 2, 3], np.float32)
    out = sub.render_mesh.copy()
    moved = sub.update(cage.positions + offset, out=out)
    assert moved is out  # written in place and returned
    expected = before.positions.astype(np.float64) + offset
    assert np.abs(out.positions - expected).max() < 1e-5 * np.abs(expected).max()


def test_update_needs_an_animated_subdivider(cube):
    sub = surfgrad.Subdivider(cube, 1)
    with pytest.raises((ValueError, RuntimeError)) as e:
        sub.update(cube.positions)
    assert_names(e, "animate")


def test_update_checks_its_array(cube):
    sub = surfgrad.Subdivider(cube, 1, animate=True)
    with pytest.raises(ValueError) as e:
        sub.update(np.zeros((9, 3), np.float32))  # the cage has 8 vertices
    assert_names(e, "cage_positions")
    with pytest.raises(TypeError) as e:
        sub.update(cube.positions.astype(np.float64))
    assert_names(e, "cage_positions")
    nan = cube.positions.copy()
    nan[3, 1] = np.nan
    with pytest.raises(ValueError) as e:
        sub.update(nan)
    assert_names(e, "cage_positions")


@pytest.mark.parametrize(
    "kwargs, named",
    [
        ({"level": -1}, "level"),
        ({"scheme": "sqrt3"}, "scheme"),
        ({"boundary": "sideways"}, "boundary"),
        ({"fvar": "wobbly"}, "fvar"),
        ({"threads": -1}, "threads"),
        ({"threads": 2000}, "threads"),
    ],
)
def test_subdivider_refuses_bad_arguments(cube, kwargs, named):
    args = {"level": 1, **kwargs}
    level = args.pop("level")
    with pytest.raises(ValueError) as e:
        surfgrad.Subdivider(cube, level, **args)
    assert_names(e, named)


def test_a_level_over_the_memory_budget_is_refused_before_it_starts(cube):
    # docs/mesh.md, "Subdivision": an InputError naming the level, the faces and the bytes.
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.Subdivider(cube, 6, memory_budget=4096)
    assert_names(e, "level 6")


# ---------------------------------------------------------------------------
# Blendshapes


def test_morph_cage_positions_is_the_weighted_sum(data_dir):
    # glTF 2.0 sec. 3.7.2.2, mesh/include/surfgrad/mesh/morph.h: P = P0 + sum w_i dP_i.
    cage = surfgrad.load_cage(data_dir / "gltf/AnimatedMorphSphere/glTF/AnimatedMorphSphere.gltf")
    targets = cage.morph_targets
    assert len(targets) == 2
    weights = np.array([0.3, -0.7], np.float32)
    got = surfgrad.morph_cage_positions(cage, weights)
    expected = cage.positions.astype(np.float64)
    for w, (_, deltas) in zip(weights, targets):
        expected = expected + np.float64(w) * deltas
    # One multiply-add per target in binary32: two roundings of values up to ~100 (the node's
    # scale), 2^-23 relative each.
    assert np.abs(got - expected).max() < 4 * 2.0**-23 * np.abs(expected).max()
    with pytest.raises(ValueError) as e:
        surfgrad.morph_cage_positions(cage, np.array([0.5], np.float32))  # 2 targets
    assert_names(e, "weights")
    with pytest.raises(ValueError) as e:
        surfgrad.morph_cage_positions(cage, np.array([0.5, np.nan], np.float32))
    assert_names(e, "weights")


SPHERE = "gltf/AnimatedMorphSphere/glTF/AnimatedMorphSphere.gltf"


def test_morpher_takes_every_loaded_mesh(data_dir):
    # The sphere's file has TANGENTs but no TEXCOORD: load_mesh keeps the tangents (UV set 0).
    mesh = surfgrad.load_mesh(data_dir / SPHERE)
    morpher = surfgrad.Morpher(mesh)
    out = morpher.apply(np.array([0.6, 0.25], np.float32), normals="recompute")
    # Recompute clears the tangents: they belong to the rest shape (surfgrad/mesh/morph.h).
    assert out.tangents.shape == (0, 4)
    blended = morpher.apply(np.array([0.6, 0.25], np.float32), normals="blend")
    assert blended.tangents.shape == mesh.tangents.shape  # blended, w kept (morph.h)
    np.testing.assert_array_equal(blended.tangents[:, 3], mesh.tangents[:, 3])


# The blendshape example's model (examples/tools/make_morph_blob.py): a UV sphere whose two
# targets carry position and normal deltas (the Khronos sphere's normal deltas are all zero).
BLOB = REPO_DIR / "examples/data/morph_blob.gltf"


def test_morpher_blends_positions_and_normals():
    # glTF 2.0 sec. 3.7.2.2 (mesh/include/surfgrad/mesh/morph.h): P = P0 + sum w_i dP_i, and with
    # "blend" N = normalize(N0 + sum w_i dN_i), here in double.
    mesh = surfgrad.load_mesh(BLOB)
    assert len(mesh.morph_targets) == 2
    assert all(t.normal_deltas.shape == (mesh.vertex_count, 3) for t in mesh.morph_targets)
    morpher = surfgrad.Morpher(mesh)
    weights = np.array([0.6, 0.25], np.float32)
    out = morpher.apply(weights, normals="blend")
    p = mesh.positions.astype(np.float64)
    n = mesh.normals.astype(np.float64)
    for w, target in zip(weights, mesh.morph_targets):
        p = p + np.float64(w) * target.position_deltas
        n = n + np.float64(w) * target.normal_deltas
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    # Binary32 multiply-adds (two roundings per target, 2^-23 relative each); blended normals:
    # sums of O(1) values and one float normalization (1e-5).
    assert np.abs(out.positions - p).max() < 4 * 2.0**-23 * np.abs(p).max()
    assert np.linalg.norm(out.normals - n, axis=1).max() < 1e-5
    recomputed = morpher.apply(weights, normals="recompute")
    np.testing.assert_array_equal(recomputed.positions, out.positions)
    np.testing.assert_allclose(np.linalg.norm(recomputed.normals, axis=1), 1.0, atol=1e-6)
    # Recomputed from the morphed geometry (area-weighted triangle normals of 64 x 32 segments)
    # against the targets' exact normals (make_morph_blob.py): a discretization difference,
    # bounded here by 10 degrees.
    assert np.degrees(np.arccos(np.clip(np.sum(recomputed.normals * n, axis=1), -1, 1))).max() < 10
    with pytest.raises(ValueError) as e:
        morpher.apply(weights, normals="average")
    assert_names(e, "normals")
    with pytest.raises(ValueError) as e:
        morpher.apply(np.array([1.0], np.float32))
    assert_names(e, "weights")
    with pytest.raises(ValueError) as e:
        morpher.apply(np.array([1.0, np.inf], np.float32))
    assert_names(e, "weights")


def test_morpher_keeps_its_mesh_alive():
    mesh = surfgrad.load_mesh(BLOB)
    rest = mesh.positions.copy()
    morpher = surfgrad.Morpher(mesh)
    del mesh
    gc.collect()
    out = morpher.apply(np.zeros(2, np.float32), normals="blend")
    np.testing.assert_array_equal(out.positions, rest)


def test_morphing_the_cage_or_the_refined_mesh_gives_the_same_positions(data_dir):
    # mesh/include/surfgrad/mesh/morph.h: subdivision and limit evaluation are linear in the control
    # points, so the cage morphed then refined through the stencils equals the refined mesh
    # morphed with its refined deltas. Float rounding of one linear map in two orders, relative
    # to the model's size (~100 units): the stencil bound 1e-5 of StencilUpdateMatchesRebuild.
    cage = surfgrad.load_cage(data_dir / "gltf/AnimatedMorphSphere/glTF/AnimatedMorphSphere.gltf")
    sub = surfgrad.Subdivider(cage, 1, limit=True, animate=True)
    refined = sub.render_mesh.copy()
    assert len(refined.morph_targets) == 2
    weights = np.array([0.8, 0.4], np.float32)
    via_mesh = surfgrad.Morpher(refined).apply(weights)
    via_cage = sub.update(surfgrad.morph_cage_positions(cage, weights))
    scale = np.abs(via_cage.positions).max()
    assert np.abs(via_mesh.positions - via_cage.positions).max() < 1e-5 * scale
