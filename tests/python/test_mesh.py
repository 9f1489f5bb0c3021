# surfgrad's meshes from Python (python/surfgrad/__init__.pyi, "Meshes"): RenderMesh and
# PolygonMesh built from arrays and read from files, the zero-copy views and the checked
# assignments of their arrays, load/save round trips (OBJ, glTF, GLB), validation, description,
# welding and the conversions; every bad argument a TypeError/ValueError naming it, every
# malformed file an InputError naming file, element and reason.
#
# Known values are those of the C++ tests: tests/mesh/obj_test.cpp (OBJ errors named as the file
# numbers them, repair), tests/mesh/validate_test.cpp (the cube's topology, tag errors),
# tests/mesh/gltf_test.cpp (glTF UV sets flipped to t up, against the raw accessors) and
# tests/mesh/formats_test.cpp (writer round trips and notes). The glTF oracle is conftest's
# numpy accessor reader, not the module.
import gc
import json

import numpy as np
import pytest

import surfgrad
from conftest import CUBE_OBJ, assert_names, gltf_primitive, write_text


def quad_arrays():
    """Two triangles over the unit square in z = 0, normal +z, UV = xy (4 vertices)."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    normals = np.tile(np.array([0, 0, 1], np.float32), (4, 1))
    uvs = positions[:, :2].copy()
    indices = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
    return positions, indices, normals, uvs


def quad_mesh():
    positions, indices, normals, uvs = quad_arrays()
    return surfgrad.RenderMesh(positions, indices, normals=normals, uv_sets=[uvs], name="quad")


def cube_cage(tmp_path, tags=""):
    return surfgrad.load_cage(write_text(tmp_path / "cube.obj", CUBE_OBJ + tags))


def obj_corners(text):
    """(vertex, uv) index pairs of every face corner of an OBJ text, 0-based, in file order."""
    corners = []
    for line in text.splitlines():
        if line.startswith("f "):
            for token in line.split()[1:]:
                v, t = token.split("/")[:2]
                corners.append((int(v) - 1, int(t) - 1))
    return corners


# ---------------------------------------------------------------------------
# RenderMesh from arrays: counts, views, assignment


def test_render_mesh_from_arrays_has_the_given_counts_and_values():
    positions, indices, normals, uvs = quad_arrays()
    mesh = surfgrad.RenderMesh(positions, indices, normals=normals, uv_sets=[uvs], name="quad")
    assert mesh.vertex_count == 4
    assert mesh.triangle_count == 2
    assert mesh.name == "quad"
    assert mesh.positions.dtype == np.float32 and mesh.positions.shape == (4, 3)
    assert mesh.indices.dtype == np.uint32 and mesh.indices.shape == (2, 3)
    np.testing.assert_array_equal(mesh.positions, positions)
    np.testing.assert_array_equal(mesh.indices, indices)
    np.testing.assert_array_equal(mesh.normals, normals)
    assert len(mesh.uv_sets) == 1
    np.testing.assert_array_equal(mesh.uv_sets[0], uvs)
    # No tangents given: the documented empty (0, 4) array, no UV set named.
    assert mesh.tangents.shape == (0, 4)
    assert mesh.tangent_uv_set == -1
    assert mesh.morph_targets == []


def test_render_mesh_owns_a_copy_of_the_constructor_arrays():
    positions, indices, normals, uvs = quad_arrays()
    mesh = surfgrad.RenderMesh(positions, indices, normals=normals, uv_sets=[uvs])
    positions[0, 0] = 42.0
    assert mesh.positions[0, 0] == 0.0


def test_array_attributes_are_views_into_the_mesh():
    mesh = quad_mesh()
    first = mesh.positions
    # Two reads of the property share the mesh's memory: no copy per read.
    assert np.shares_memory(first, mesh.positions)
    first[2, 2] = 7.5
    assert mesh.positions[2, 2] == 7.5
    uv = mesh.uv_sets[0]
    uv[1, 0] = 0.25
    assert mesh.uv_sets[0][1, 0] == 0.25
    normals = mesh.normals
    normals[0] = (0, 1, 0)
    np.testing.assert_array_equal(mesh.normals[0], [0, 1, 0])


def test_uv_sets_list_is_new_but_its_arrays_are_views():
    mesh = quad_mesh()
    sets = mesh.uv_sets
    sets.append(np.zeros((4, 2), np.float32))
    assert len(mesh.uv_sets) == 1  # the list is the caller's
    assert np.shares_memory(mesh.uv_sets[0], mesh.uv_sets[0])


def test_a_view_keeps_its_mesh_alive():
    mesh = quad_mesh()
    view = mesh.positions
    expected = view.copy()
    del mesh
    gc.collect()
    # Allocate and free some memory of the mesh's size class so a freed buffer would be reused.
    junk = [np.full((4, 3), 99.0, np.float32) for _ in range(100)]
    del junk
    np.testing.assert_array_equal(view, expected)


def test_assigning_an_array_copies_it():
    mesh = quad_mesh()
    new_positions = np.arange(12, dtype=np.float32).reshape(4, 3)
    mesh.positions = new_positions
    np.testing.assert_array_equal(mesh.positions, new_positions)
    assert not np.shares_memory(mesh.positions, new_positions)
    new_positions[0, 0] = -1.0
    assert mesh.positions[0, 0] == 0.0
    tangents = np.tile(np.array([1, 0, 0, 1], np.float32), (4, 1))
    mesh.tangents = tangents
    mesh.tangent_uv_set = 0
    np.testing.assert_array_equal(mesh.tangents, tangents)
    assert mesh.tangent_uv_set == 0


def test_assignment_checks_dtype_and_shape():
    mesh = quad_mesh()
    with pytest.raises(TypeError) as e:
        mesh.positions = np.zeros((4, 3), np.float64)
    assert_names(e, "positions")
    with pytest.raises(ValueError) as e:
        mesh.positions = np.zeros((4, 2), np.float32)
    assert_names(e, "positions")
    with pytest.raises(ValueError) as e:
        mesh.normals = np.zeros((5, 3), np.float32)  # 4 vertices
    assert_names(e, "normals")
    with pytest.raises(ValueError) as e:
        mesh.tangents = np.zeros((4, 3), np.float32)  # (V, 4) or (0, 4)
    assert_names(e, "tangents")
    with pytest.raises(TypeError) as e:
        mesh.indices = np.zeros((2, 3), np.int64)
    assert_names(e, "indices")
    # Nothing was changed by the refused assignments.
    np.testing.assert_array_equal(mesh.positions, quad_arrays()[0])


def test_set_uv_set_replaces_and_appends():
    mesh = quad_mesh()
    mirrored = mesh.uv_sets[0].copy()
    mirrored[:, 0] = 1.0 - mirrored[:, 0]
    mesh.set_uv_set(1, mirrored)  # index == len(uv_sets): appends
    assert len(mesh.uv_sets) == 2
    np.testing.assert_array_equal(mesh.uv_sets[1], mirrored)
    mesh.set_uv_set(0, mirrored)
    np.testing.assert_array_equal(mesh.uv_sets[0], mirrored)
    with pytest.raises(ValueError) as e:
        mesh.set_uv_set(3, mirrored)  # neither an existing set nor the next one
    assert_names(e, "3")
    with pytest.raises(ValueError) as e:
        mesh.set_uv_set(0, np.zeros((3, 2), np.float32))
    assert_names(e, "uvs")


def test_copy_is_independent():
    mesh = quad_mesh()
    other = mesh.copy()
    other.positions[0] = (5, 5, 5)
    np.testing.assert_array_equal(mesh.positions[0], [0, 0, 0])
    assert not np.shares_memory(other.positions, mesh.positions)


# ---------------------------------------------------------------------------
# RenderMesh: every bad argument named


def bad_constructor_cases():
    positions, indices, normals, uvs = quad_arrays()
    wide = np.zeros((4, 6), np.float32)
    wide[:, ::2] = positions
    nan_positions = positions.copy()
    nan_positions[2, 1] = np.nan
    inf_uvs = uvs.copy()
    inf_uvs[1, 0] = np.inf
    out_of_range = indices.copy()
    out_of_range[1, 2] = 4  # 4 vertices: 0..3
    return [
        ("float64 positions", TypeError, "positions", (positions.astype(np.float64), indices), {}),
        ("int64 indices", TypeError, "indices", (positions, indices.astype(np.int64)), {}),
        (
            "float64 normals",
            TypeError,
            "normals",
            (positions, indices),
            {"normals": normals.astype(np.float64)},
        ),
        ("positions (4, 2)", ValueError, "positions", (positions[:, :2].copy(), indices), {}),
        ("positions (12,)", ValueError, "positions", (positions.ravel(), indices), {}),
        ("non-contiguous positions", ValueError, "positions", (wide[:, ::2], indices), {}),
        (
            "Fortran-order positions",
            ValueError,
            "positions",
            (np.asfortranarray(positions), indices),
            {},
        ),
        ("NaN position", ValueError, "positions", (nan_positions, indices), {}),
        ("index out of range", ValueError, "indices", (positions, out_of_range), {}),
        ("indices (3, 2)", ValueError, "indices", (positions, indices.reshape(3, 2)), {}),
        (
            "normals (3, 3)",
            ValueError,
            "normals",
            (positions, indices),
            {"normals": normals[:3].copy()},
        ),
        (
            "UV set (3, 2)",
            ValueError,
            "uv_sets",
            (positions, indices),
            {"uv_sets": [uvs[:3].copy()]},
        ),
        ("infinite UV", ValueError, "uv_sets", (positions, indices), {"uv_sets": [inf_uvs]}),
        (
            "tangents (4, 3)",
            ValueError,
            "tangents",
            (positions, indices),
            {"uv_sets": [uvs], "tangents": np.zeros((4, 3), np.float32), "tangent_uv_set": 0},
        ),
        (
            # A set the mesh lacks is allowed (a glTF file may carry TANGENT without its
            # TEXCOORD, and load_mesh keeps the index); below -1 is not an index at all.
            "tangent_uv_set below -1",
            ValueError,
            "tangent_uv_set",
            (positions, indices),
            {"uv_sets": [uvs], "tangents": np.zeros((4, 4), np.float32), "tangent_uv_set": -2},
        ),
    ]


@pytest.mark.parametrize(
    "what, error, named, args, kwargs",
    bad_constructor_cases(),
    ids=[case[0] for case in bad_constructor_cases()],
)
def test_render_mesh_refuses_bad_arrays(what, error, named, args, kwargs):
    with pytest.raises(error) as e:
        surfgrad.RenderMesh(*args, **kwargs)
    assert_names(e, named)


def test_render_mesh_type_errors_name_shape_and_dtype():
    positions, indices = quad_arrays()[:2]
    with pytest.raises(TypeError) as e:
        surfgrad.RenderMesh(positions.astype(np.float64), indices)
    # The conventions of __init__.pyi: the message names the argument, its shape and its dtype.
    assert_names(e, "positions", "float64", "(4, 3)")


# ---------------------------------------------------------------------------
# Loading: OBJ


def test_load_mesh_of_the_cube_splits_vertices_at_uv_seams(tmp_path):
    mesh = surfgrad.load_mesh(write_text(tmp_path / "cube.obj", CUBE_OBJ))
    corners = obj_corners(CUBE_OBJ)
    # One render vertex per distinct (position, UV) index pair of the file; polygons fanned.
    assert mesh.vertex_count == len(set(corners))
    assert mesh.triangle_count == 12
    assert len(mesh.uv_sets) == 1
    # Every corner of every fanned triangle has its file position and UV (OBJ's t is already up:
    # no flip).
    file_positions = np.array(
        [[float(x) for x in l.split()[1:]] for l in CUBE_OBJ.splitlines() if l.startswith("v ")],
        np.float32,
    )
    file_uvs = np.array(
        [[float(x) for x in l.split()[1:]] for l in CUBE_OBJ.splitlines() if l.startswith("vt ")],
        np.float32,
    )
    fanned = []
    for f in range(6):
        quad = corners[4 * f : 4 * f + 4]
        fanned += [quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]]
    v_file = np.array([c[0] for c in fanned])
    t_file = np.array([c[1] for c in fanned])
    flat = mesh.indices.ravel()
    np.testing.assert_array_equal(mesh.positions[flat], file_positions[v_file])
    np.testing.assert_array_equal(mesh.uv_sets[0][flat], file_uvs[t_file])


def test_load_cage_of_the_cube_keeps_polygons_and_face_varying_uvs(tmp_path):
    cage = cube_cage(tmp_path)
    assert (cage.vertex_count, cage.face_count, cage.corner_count) == (8, 6, 24)
    np.testing.assert_array_equal(cage.face_sizes, np.full(6, 4, np.uint32))
    corners = obj_corners(CUBE_OBJ)
    np.testing.assert_array_equal(cage.face_vertices, [c[0] for c in corners])
    assert cage.scheme == "catmark"
    ((name, values, uv_indices),) = cage.uv_sets
    assert values.shape == (4, 2) and values.dtype == np.float32
    np.testing.assert_array_equal(values, [[0, 0], [1, 0], [1, 1], [0, 1]])
    np.testing.assert_array_equal(uv_indices, [c[1] for c in corners])
    assert cage.creases == [] and cage.corners == [] and cage.holes == []


def test_describe_the_cube(tmp_path):
    # tests/mesh/validate_test.cpp, Validate.AcceptsAClosedCube: 12 edges, closed, Euler 2.
    info = surfgrad.describe(cube_cage(tmp_path))
    assert info["vertices"] == 8
    assert info["faces"] == 6
    assert info["edges"] == 12
    assert info["boundary_edges"] == 0
    assert info["boundary_loops"] == 0
    assert info["non_manifold_edges"] == 0
    assert info["manifold"] is True
    assert info["euler_characteristic"] == 2


def test_obj_tags_load_and_round_trip(tmp_path):
    # tests/mesh/formats_test.cpp, Formats.ObjRoundTripKeepsTagsAndUvs: OBJ keeps every tag.
    tags = "t crease 2/1/0 0 1 2.5\nt corner 1/1/0 6 10\nt hole 1/0/0 2\n"
    cage = cube_cage(tmp_path, tags)
    assert cage.creases == [(0, 1, 2.5)]
    assert cage.corners == [(6, 10.0)]
    assert cage.holes == [2]
    notes = surfgrad.save_mesh(tmp_path / "out.obj", cage)
    assert notes == []
    back = surfgrad.load_cage(tmp_path / "out.obj")
    np.testing.assert_array_equal(back.positions, cage.positions)
    np.testing.assert_array_equal(back.face_vertices, cage.face_vertices)
    np.testing.assert_array_equal(back.uv_sets[0][1], cage.uv_sets[0][1])
    np.testing.assert_array_equal(back.uv_sets[0][2], cage.uv_sets[0][2])
    assert back.creases == cage.creases
    assert back.corners == cage.corners
    assert back.holes == cage.holes


def test_malformed_obj_is_an_input_error_naming_file_element_and_reason(tmp_path):
    # tests/mesh/obj_test.cpp, Obj.LoadNamesTheFileAndTheFaceLine: the second face, on line 6,
    # uses vertex 1 twice; named as the file numbers them.
    path = write_text(
        tmp_path / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n# a comment\nf 1 2 3\nf 1 1 2\n"
    )
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.load_cage(path)
    assert e.value.file == str(path)
    assert e.value.element == "face 2 (line 6)"
    assert "uses vertex 1 twice" in e.value.reason
    assert str(e.value) == f"{e.value.file}: {e.value.element}: {e.value.reason}"
    assert isinstance(e.value, ValueError)
    with pytest.raises(surfgrad.InputError):
        surfgrad.load_mesh(path)
    # With repair the face is dropped and counted.
    cage = surfgrad.load_cage(path, repair=True)
    assert cage.face_count == 1
    report = surfgrad.load_report(path, repair=True)
    assert report["degenerate_faces_dropped"] == 1
    assert isinstance(report["notes"], list)


@pytest.mark.parametrize(
    "text, element, reason",
    [
        # tests/mesh/obj_test.cpp, Obj.ErrorsNameTheLine
        ("v 0 0 0\nv 1 0\n", "line 2", "fewer than 3 coordinates"),
        ("v 0 0 0\nv 0 0 nan\n", "vertex 2", "non-finite coordinate"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", "line 5", "vertex index 4 is out of range"),
        ("f 1/2/3/4\n", "line 1", "more than 3 parts"),
        # tests/mesh/obj_test.cpp, Obj.TopologyErrorsUseTheFilesNumbers
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
            "edge (1, 2)",
            "shared by 3 faces (1, 2, 3)",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n",
            "vertex 1",
            "2 separate fans",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 3 4\n",
            "edge (2, 3)",
            "faces 1 and 2 traverse it in the same direction",
        ),
    ],
)
def test_malformed_obj_files_are_named(tmp_path, text, element, reason):
    path = write_text(tmp_path / "a.obj", text)
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.load_cage(path)
    assert e.value.file == str(path)
    assert element in e.value.element
    assert reason in e.value.reason


def test_missing_and_unknown_files_are_input_errors(tmp_path):
    # tests/mesh/obj_test.cpp, Obj.LoadNamesTheFileAndTheFaceLine (last lines).
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.load_mesh(tmp_path / "missing.obj")
    assert "no such file" in e.value.reason
    write_text(tmp_path / "x.fbx", "whatever")
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.load_cage(tmp_path / "x.fbx")
    assert "unknown mesh format '.fbx'" in e.value.reason


def test_paths_may_be_str_or_pathlike(tmp_path):
    path = write_text(tmp_path / "cube.obj", CUBE_OBJ)
    assert surfgrad.load_mesh(str(path)).triangle_count == surfgrad.load_mesh(path).triangle_count


@pytest.mark.parametrize("threads", [-1, 1025, 2000])
def test_load_refuses_bad_thread_counts(tmp_path, threads):
    path = write_text(tmp_path / "cube.obj", CUBE_OBJ)
    for load in (surfgrad.load_mesh, surfgrad.load_cage):
        with pytest.raises(ValueError) as e:
            load(path, threads=threads)
        assert_names(e, "threads")


def test_load_gives_the_same_mesh_for_every_thread_count(data_dir):
    path = data_dir / "meshes/spot/spot_control_mesh.obj"
    one = surfgrad.load_cage(path, threads=1)
    two = surfgrad.load_cage(path, threads=2)
    np.testing.assert_array_equal(one.positions, two.positions)
    np.testing.assert_array_equal(one.face_vertices, two.face_vertices)


# ---------------------------------------------------------------------------
# PolygonMesh from arrays, validation and repair


def cube_arrays():
    """The cube of CUBE_OBJ as PolygonMesh arrays: positions, face sizes, face vertices and its
    one UV set (name, values, per-corner indices), parsed here without the module."""
    lines = CUBE_OBJ.splitlines()
    positions = np.array([l.split()[1:] for l in lines if l.startswith("v ")], np.float32)
    uvs = np.array([l.split()[1:] for l in lines if l.startswith("vt ")], np.float32)
    corners = obj_corners(CUBE_OBJ)
    face_vertices = np.array([c[0] for c in corners], np.uint32)
    uv_indices = np.array([c[1] for c in corners], np.uint32)
    return positions, np.full(6, 4, np.uint32), face_vertices, [("uv", uvs, uv_indices)]


def test_polygon_mesh_from_arrays_equals_the_loaded_cube(tmp_path):
    positions, face_sizes, face_vertices, uv_sets = cube_arrays()
    cage = surfgrad.PolygonMesh(positions, face_sizes, face_vertices, uv_sets, name="cube")
    loaded = cube_cage(tmp_path)
    assert (cage.vertex_count, cage.face_count, cage.corner_count) == (8, 6, 24)
    np.testing.assert_array_equal(cage.positions, loaded.positions)
    np.testing.assert_array_equal(cage.face_sizes, loaded.face_sizes)
    np.testing.assert_array_equal(cage.face_vertices, loaded.face_vertices)
    np.testing.assert_array_equal(cage.uv_sets[0][1], loaded.uv_sets[0][1])
    np.testing.assert_array_equal(cage.uv_sets[0][2], loaded.uv_sets[0][2])
    assert cage.scheme == "catmark" and cage.name == "cube"
    # Both refine to the same surface.
    a = surfgrad.Subdivider(cage, 1).refined.positions
    np.testing.assert_array_equal(a, surfgrad.Subdivider(loaded, 1).refined.positions)


def test_polygon_mesh_views(tmp_path):
    cage = cube_cage(tmp_path)
    # positions: a writable view; the topology: read-only views.
    assert np.shares_memory(cage.positions, cage.positions)
    cage.positions[0] = (-2, -2, -2)
    np.testing.assert_array_equal(cage.positions[0], [-2, -2, -2])
    assert np.shares_memory(cage.face_vertices, cage.face_vertices)
    with pytest.raises(ValueError):  # numpy: assignment destination is read-only
        cage.face_vertices[0] = 1
    with pytest.raises(ValueError):
        cage.face_sizes[0] = 3
    with pytest.raises(AttributeError):
        cage.face_sizes = np.full(6, 4, np.uint32)
    # Copies: changing them changes nothing in the cage.
    values = cage.uv_sets[0][1]
    values[:] = 7
    assert cage.uv_sets[0][1].max() == 1.0
    creases = cage.creases
    creases.append((0, 1, 1.0))
    assert cage.creases == []


def test_polygon_mesh_positions_assignment_is_checked(tmp_path):
    cage = cube_cage(tmp_path)
    with pytest.raises(TypeError) as e:
        cage.positions = np.zeros((8, 3), np.float64)
    assert_names(e, "positions")
    with pytest.raises(ValueError) as e:
        cage.positions = np.zeros((9, 3), np.float32)  # the faces use 8 vertices
    assert_names(e, "positions")
    moved = cage.positions * np.float32(2)
    cage.positions = moved
    assert not np.shares_memory(cage.positions, moved)
    np.testing.assert_array_equal(cage.positions, moved)


@pytest.mark.parametrize(
    "change, element, reason",
    [
        # tests/mesh/validate_test.cpp, Validate.BadValuesAndIndices, on the cube.
        ({"creases": [(0, 6, 1.0)]}, "crease 0 (0, 6)", "no face has an edge"),
        ({"creases": [(0, 1, -1.0)]}, "crease 0", "not a finite value >= 0"),
        ({"holes": [6]}, "hole tag (face 6)", "out of range"),
        ({"face_vertices": 99}, "face 1", "vertex index 99 is out of range (8 vertices)"),
        ({"face_sizes": 5}, "faces", "add up to 25"),
        ({"uv_index": 40}, "uv set 0 corner 2", "out of range (4 UVs)"),
        ({"nan": True}, "vertex 3", "non-finite"),
    ],
)
def test_polygon_mesh_constructor_validates_like_a_loader(change, element, reason):
    positions, face_sizes, face_vertices, uv_sets = cube_arrays()
    kwargs = {}
    if "creases" in change or "holes" in change:
        kwargs = change
    if "face_vertices" in change:
        face_vertices[5] = change["face_vertices"]
    if "face_sizes" in change:
        face_sizes[0] = change["face_sizes"]
    if "uv_index" in change:
        uv_sets[0][2][2] = change["uv_index"]
    if "nan" in change:
        positions[3, 1] = np.nan
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.PolygonMesh(positions, face_sizes, face_vertices, uv_sets, **kwargs)
    assert element in e.value.element
    assert reason in e.value.reason


def test_polygon_mesh_constructor_checks_dtypes():
    positions, face_sizes, face_vertices, uv_sets = cube_arrays()
    with pytest.raises(TypeError) as e:
        surfgrad.PolygonMesh(positions.astype(np.float64), face_sizes, face_vertices)
    assert_names(e, "positions")
    with pytest.raises(TypeError) as e:
        surfgrad.PolygonMesh(positions, face_sizes.astype(np.int32), face_vertices)
    assert_names(e, "face_sizes")
    with pytest.raises(TypeError) as e:
        surfgrad.PolygonMesh(positions, face_sizes, face_vertices.astype(np.int64))
    assert_names(e, "face_vertices")
    with pytest.raises(ValueError) as e:
        surfgrad.PolygonMesh(positions, face_sizes, face_vertices, scheme="sqrt3")
    assert_names(e, "scheme")


def test_validate_names_the_mesh(tmp_path):
    cage = cube_cage(tmp_path)
    report = surfgrad.validate(cage, name="t.obj")
    assert report["degenerate_faces_dropped"] == 0 and report["duplicate_vertices_welded"] == 0
    assert report["isolated_vertices"] == 0 and report["notes"] == []


def split_square():
    """Two triangles over the unit square with their own copies of the diagonal's two vertices:
    a valid cage (an open seam along the diagonal) until the copies are welded."""
    positions = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32
    )
    return surfgrad.PolygonMesh(
        positions, np.array([3, 3], np.uint32), np.arange(6, dtype=np.uint32), name="split"
    )


def test_repaired_welds_bitwise_equal_vertices():
    # docs/mesh.md, "Validation": repair welds vertices with exactly equal positions.
    cage = split_square()
    assert surfgrad.describe(cage)["boundary_loops"] == 2
    fixed, report = surfgrad.repaired(cage)
    assert report["duplicate_vertices_welded"] == 2
    assert fixed.vertex_count == 4 and cage.vertex_count == 6  # a copy; the input is unchanged
    info = surfgrad.describe(fixed)
    # One square with its diagonal: V - E + F = 4 - 5 + 2 = 1, one boundary loop.
    assert (info["edges"], info["boundary_loops"], info["euler_characteristic"]) == (5, 1, 1)


# ---------------------------------------------------------------------------
# Weld and conversions


def split_quad_mesh(uv_shift=0.0):
    """The two triangles of quad_arrays with their own copies of the shared diagonal (6
    vertices, 4 distinct); uv_shift moves the second triangle's UVs to another island."""
    positions, indices, normals, uvs = quad_arrays()
    split = np.array([0, 1, 2, 0, 2, 3])
    split_uvs = uvs[split].copy()
    split_uvs[3:, 0] += uv_shift
    return surfgrad.RenderMesh(
        positions[split].copy(),
        np.arange(6, dtype=np.uint32).reshape(2, 3),
        normals=normals[split].copy(),
        uv_sets=[split_uvs],
    )


def test_weld_merges_bitwise_equal_vertices_into_a_new_mesh():
    mesh = split_quad_mesh()
    old_view = mesh.positions
    corners_before = mesh.positions[mesh.indices.ravel()].copy()
    welded, removed = surfgrad.weld(mesh)
    assert removed == 2
    assert welded.vertex_count == 4
    np.testing.assert_array_equal(welded.positions[welded.indices.ravel()], corners_before)
    # The input is untouched and its views stay valid.
    assert mesh.vertex_count == 6
    np.testing.assert_array_equal(old_view[mesh.indices.ravel()], corners_before)
    # Nothing left to weld.
    again, removed = surfgrad.weld(welded, threads=1)
    assert removed == 0 and again.vertex_count == 4


def test_weld_keeps_vertices_that_differ_in_any_attribute():
    welded, removed = surfgrad.weld(split_quad_mesh(uv_shift=1.0))
    assert removed == 0
    assert welded.vertex_count == 6


def test_to_render_mesh_and_back(tmp_path):
    cage = cube_cage(tmp_path)
    mesh = surfgrad.to_render_mesh(cage)
    assert mesh.triangle_count == 12
    assert mesh.vertex_count == len(set(obj_corners(CUBE_OBJ)))
    polygons = surfgrad.to_polygon_mesh(mesh)
    assert polygons.face_count == 12
    np.testing.assert_array_equal(polygons.face_sizes, np.full(12, 3, np.uint32))
    # Render vertices with bitwise-equal positions become one cage vertex
    # (mesh/include/surfgrad/mesh/mesh_io.h, toPolygonMesh): the cube's 8 corners.
    assert polygons.vertex_count == 8
    assert surfgrad.describe(polygons)["euler_characteristic"] == 2


# ---------------------------------------------------------------------------
# glTF


@pytest.mark.parametrize(
    "relative",
    ["gltf/MultiUVTest/glTF/MultiUVTest.gltf", "gltf/MultiUVTest/glTF-Binary/MultiUVTest.glb"],
)
def test_gltf_uv_sets_are_flipped_to_t_up(data_dir, relative):
    # tests/mesh/gltf_test.cpp, Gltf.MultiUvTestHasTwoFlippedUvSets: s as stored, t = 1 - v,
    # exactly, against the accessors read without the module (the .gltf file's; the .glb holds
    # the same model).
    raw = gltf_primitive(data_dir / "gltf/MultiUVTest/glTF/MultiUVTest.gltf")
    mesh = surfgrad.load_mesh(data_dir / relative)
    assert mesh.vertex_count == raw["POSITION"].shape[0]
    assert len(mesh.uv_sets) == 2
    np.testing.assert_array_equal(mesh.uv_sets[0], raw["TEXCOORD_0"])
    np.testing.assert_array_equal(mesh.uv_sets[1], raw["TEXCOORD_1"])
    np.testing.assert_array_equal(mesh.positions, raw["POSITION"])
    np.testing.assert_array_equal(mesh.indices.ravel(), raw["indices"])
    assert mesh.tangents.shape == (mesh.vertex_count, 4)
    assert set(np.unique(mesh.tangents[:, 3])) <= {-1.0, 1.0}


def test_gltf_mirrored_tangents_keep_their_sign(data_dir):
    # tests/mesh/gltf_test.cpp, Gltf.MirroredTangentsKeepTheirSign.
    mesh = surfgrad.load_mesh(
        data_dir / "gltf/NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf"
    )
    signs = mesh.tangents[:, 3]
    assert (signs < 0).any() and (signs > 0).any()
    # Unit normals after the loader's renormalization: float rounding of one division.
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-6)


def test_gltf_morph_targets_and_weights(data_dir):
    # tests/mesh/gltf_test.cpp, Gltf.MorphPrimitivesTest: one target per primitive, weight 0.5;
    # load_mesh merges the two primitives.
    mesh = surfgrad.load_mesh(data_dir / "gltf/MorphPrimitivesTest/glTF/MorphPrimitivesTest.gltf")
    assert len(mesh.morph_targets) == 1
    np.testing.assert_array_equal(mesh.morph_weights, np.array([0.5], np.float32))
    target = mesh.morph_targets[0]
    assert target.position_deltas.shape == (mesh.vertex_count, 3)
    assert target.position_deltas.dtype == np.float32


def limit_cube_mesh(tmp_path):
    cage = cube_cage(tmp_path)
    return surfgrad.Subdivider(cage, 2, limit=True).render_mesh


@pytest.mark.parametrize("name", ["out.gltf", "out.glb"])
def test_gltf_writer_round_trip(tmp_path, name):
    # tests/mesh/formats_test.cpp, Formats.PlyAndGltfWritersRoundTrip.
    mesh = limit_cube_mesh(tmp_path)
    mesh.tangents = np.tile(np.array([1, 0, 0, -1], np.float32), (mesh.vertex_count, 1))
    mesh.tangent_uv_set = 0
    notes = surfgrad.save_mesh(tmp_path / name, mesh)
    assert notes == []
    back = surfgrad.load_mesh(tmp_path / name)
    assert back.vertex_count == mesh.vertex_count
    np.testing.assert_array_equal(back.indices, mesh.indices)
    np.testing.assert_array_equal(back.positions, mesh.positions)  # float32 in, float32 out
    # t -> 1 - t -> 1 - (1 - t): exact on a 2^-k grid, one ulp of 1 otherwise.
    np.testing.assert_allclose(back.uv_sets[0], mesh.uv_sets[0], rtol=0, atol=1e-7)
    # Normals are renormalized on load: an ulp or two.
    assert np.linalg.norm(back.normals - mesh.normals, axis=1).max() < 1e-6
    np.testing.assert_array_equal(back.tangents[0], [1, 0, 0, -1])
    assert back.tangent_uv_set == 0


def test_obj_writer_round_trip_per_corner(tmp_path):
    # tests/mesh/formats_test.cpp, Formats.PlyAndGltfWritersRoundTrip (OBJ part): every corner has
    # its position and UV back exactly (shortest round-trip text); the tangents are noted as
    # dropped.
    mesh = limit_cube_mesh(tmp_path)
    mesh.tangents = np.tile(np.array([1, 0, 0, 1], np.float32), (mesh.vertex_count, 1))
    mesh.tangent_uv_set = 0
    notes = surfgrad.save_mesh(tmp_path / "out.obj", mesh)
    assert any("no tangents" in note for note in notes), notes
    back = surfgrad.load_mesh(tmp_path / "out.obj")
    assert back.triangle_count == mesh.triangle_count
    a, b = mesh.indices.ravel(), back.indices.ravel()
    np.testing.assert_array_equal(back.positions[b], mesh.positions[a])
    np.testing.assert_array_equal(back.uv_sets[0][b], mesh.uv_sets[0][a])
    cage = surfgrad.load_cage(tmp_path / "out.obj")
    info = surfgrad.describe(cage)
    assert info["boundary_edges"] == 0 and info["euler_characteristic"] == 2


def test_save_mesh_refuses_unknown_formats_and_missing_folders(tmp_path):
    # tests/mesh/formats_test.cpp, Formats.WritersRefuseInputsAndUnknownFormats.
    mesh = quad_mesh()
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.save_mesh(tmp_path / "out.fbx", mesh)
    assert "unknown output format '.fbx'" in e.value.reason
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.save_mesh(tmp_path / "no_such_dir" / "out.obj", mesh)
    assert "does not exist" in e.value.reason
    # Nothing half-written is left behind.
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(TypeError):
        surfgrad.save_mesh(tmp_path / "out.obj", "not a mesh")


def triangle_gltf(folder, buffer_uri, buffer_path):
    """One triangle as a .gltf whose buffer (positions, then uint16 indices) lives in its own
    file at buffer_path, named by buffer_uri; written without the module."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32).tobytes()
    indices = np.array([0, 1, 2, 0], np.uint16).tobytes()  # padded to 4 bytes
    buffer_path.parent.mkdir(parents=True, exist_ok=True)
    buffer_path.write_bytes(positions + indices)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"uri": buffer_uri, "byteLength": len(positions) + len(indices)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(positions)},
            {"buffer": 0, "byteOffset": len(positions), "byteLength": 6},
        ],
        "accessors": [
            {
                "bufferView": 0,
                "componentType": 5126,
                "count": 3,
                "type": "VEC3",
                "min": [0, 0, 0],
                "max": [1, 1, 0],
            },
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
    }
    folder.mkdir(parents=True, exist_ok=True)
    return write_text(folder / "m.gltf", json.dumps(doc))


def test_gltf_uris_outside_the_models_folder_are_refused_unless_allowed(tmp_path):
    # tests/mesh/gltf_test.cpp, Gltf.UrisThatLeaveTheModelsFolderAreRefused.
    inside = triangle_gltf(tmp_path / "a", "bin/t.bin", tmp_path / "a/bin/t.bin")
    assert surfgrad.load_mesh(inside).triangle_count == 1
    outside = triangle_gltf(tmp_path / "b", "../elsewhere/t.bin", tmp_path / "elsewhere/t.bin")
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.load_mesh(outside)
    assert "outside the model's folder (refused" in e.value.reason
    assert e.value.file == str(outside)
    assert surfgrad.load_mesh(outside, allow_outside_folder=True).triangle_count == 1


GLTF_SAMPLES = [
    "AnimatedMorphSphere",
    "BoxTextured",
    "MorphPrimitivesTest",
    "MultiUVTest",
    "NormalTangentMirrorTest",
    "NormalTangentTest",
    "TextureCoordinateTest",
]


@pytest.mark.parametrize("sample", GLTF_SAMPLES)
def test_every_gltf_sample_saves_and_reloads(data_dir, tmp_path, sample):
    # Whatever load_mesh returns, save_mesh writes: the glTF writer keeps float32 positions and
    # the triangles (tests/mesh/formats_test.cpp, Formats.PlyAndGltfWritersRoundTrip).
    mesh = surfgrad.load_mesh(data_dir / f"gltf/{sample}/glTF/{sample}.gltf")
    surfgrad.save_mesh(tmp_path / "out.glb", mesh)
    back = surfgrad.load_mesh(tmp_path / "out.glb")
    np.testing.assert_array_equal(back.positions, mesh.positions)
    np.testing.assert_array_equal(back.indices, mesh.indices)
    assert back.tangents.shape == mesh.tangents.shape
    assert len(back.morph_targets) == len(mesh.morph_targets)
