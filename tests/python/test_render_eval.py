# Rendering and the shared shader functions from Python (python/surfgrad/__init__.pyi, "Rendering
# and the shared functions"): surfgrad.render on the CPU reference renderer and, marked `gl`, on
# OpenGL through EGL; surfgrad.eval over numpy arrays.
#
# Known values:
#  - a unit plane y = 0 (procedural "plane": P = ((u - 0.5) size, 0, (0.5 - v) size), UV = (u, v),
#    render/src/assets.cpp) seen from straight above: the normal AOV is (0, 1, 0); the uv
#    AOV follows from intersecting each pixel centre's ray with the plane (pinhole camera of
#    docs/scene.md, vertical fov, row 0 at the bottom);
#  - tests/render/shading_test.cpp, Layers.UvNormalTiltResolvesToTheMapsNormal: a constant
#    tangent-space normal m on that plane (T = +x, B = -z) resolves to m in (T, B, N);
#  - tests/render/scene_test.cpp: scene errors name the field;
#  - tests/bump/cli_eval_test.cpp, CliEval.GoodLinesGiveKnownAnswers: resolve and
#    tspace-to-deriv; shaders/sg/eval/kernels.glsl: tbn = d.x t + d.y b.
import json
import math

import numpy as np
import pytest

import surfgrad
from surfgrad import normalmap
from conftest import CUBE_OBJ, angle_deg, assert_names

SIZE = 64
FOV_DEG = 40.0
HEIGHT = 1.5  # camera above the unit plane: it fills most of the view, the corners are empty


def plane_scene(layers=None):
    scene = {
        "camera": {
            "position": [0, HEIGHT, 0],
            "target": [0, 0, 0],
            "up": [0, 0, -1],
            "fov_deg": FOV_DEG,
        },
        "meshes": [{"procedural": {"type": "plane", "size": 1, "segments": 2}}],
    }
    if layers is not None:
        scene["materials"] = [{"name": "m", "layers": layers}]
    return scene


def expected_plane_uv():
    """(H, W, 2) UV at every pixel centre: the ray through the centre of pixel (x, y), row 0 at
    the bottom, meets the plane at x_world = HEIGHT tan(fov/2) ndc_x, z_world = -HEIGHT
    tan(fov/2) ndc_y (screen right +x, screen up -z), where u = x_world + 0.5, v = 0.5 - z."""
    ndc = (np.arange(SIZE) + 0.5) / SIZE * 2.0 - 1.0
    reach = HEIGHT * math.tan(math.radians(FOV_DEG) / 2)
    u = 0.5 + reach * ndc[None, :] * np.ones((SIZE, 1))
    v = 0.5 + reach * ndc[:, None] * np.ones((1, SIZE))
    return np.stack([u, v], axis=-1)


def constant_normal_map(tmp_path, m):
    path = tmp_path / "constant_normal.exr"
    normalmap.write_image(path, np.tile((0.5 * m + 0.5).astype(np.float32), (4, 4, 1)), "float")
    return path


TILT = np.array([0.3, -0.2, 0.9]) / np.linalg.norm([0.3, -0.2, 0.9])
# m in (T, B, N) = (+x, -z, +y) of the plane.
TILTED_NORMAL = (
    TILT[0] * np.array([1, 0, 0]) + TILT[1] * np.array([0, 0, -1]) + TILT[2] * np.array([0, 1, 0])
)


def check_plane_renders(renderer, tmp_path):
    normal = surfgrad.render(
        plane_scene(), width=SIZE, height=SIZE, aov="normal", renderer=renderer
    )
    assert normal.shape == (SIZE, SIZE, 4) and normal.dtype == np.float32
    covered = normal[..., 3] == 1.0
    # The plane fills the middle, the background (alpha 0) the corners.
    assert covered[SIZE // 2, SIZE // 2] and not covered[0, 0] and 0.5 < covered.mean() < 1.0
    np.testing.assert_array_equal(normal[~covered], 0.0)
    # normalize(n) of an exact (0, 1, 0): binary32 rounding only.
    np.testing.assert_allclose(
        normal[covered, :3], np.broadcast_to([0, 1, 0], (covered.sum(), 3)), atol=1e-6
    )

    uv = surfgrad.render(plane_scene(), width=SIZE, height=SIZE, aov="uv", renderer=renderer)
    inside = covered & (uv[..., 3] == 1.0)
    # Perspective-correct interpolation in binary32 (~1e-6), and on the GPU pixel centres on
    # llvmpipe's 1/256-pixel grid (7e-5 of UV here): 2e-4.
    np.testing.assert_allclose(uv[inside, :2], expected_plane_uv()[inside], atol=2e-4)

    path = constant_normal_map(tmp_path, TILT)
    tilted = surfgrad.render(
        plane_scene([{"type": "uv_normal", "map": str(path)}]),
        width=SIZE,
        height=SIZE,
        aov="normal",
        renderer=renderer,
    )
    lit = tilted[..., 3] == 1.0
    # The per-pixel frame from screen derivatives of binary32 positions and UVs (~3e-6 rad of
    # rounding); 0.01 degrees (1.7e-4 rad) leaves a margin of 50, while a swapped or flipped
    # tangent or bitangent is tens of degrees off.
    assert angle_deg(tilted[lit, :3], TILTED_NORMAL).max() < 0.01
    return normal, uv, tilted


def test_cpu_renders_of_a_plane_have_the_known_values(tmp_path):
    check_plane_renders("cpu", tmp_path)


@pytest.mark.gl
def test_gl_renders_of_a_plane_have_the_known_values_and_match_the_cpu(tmp_path):
    gl_tilted = check_plane_renders("gl", tmp_path)[2]
    cpu_tilted = check_plane_renders("cpu", tmp_path)[2]
    # docs/hard-cases.md: the normal AOV of the GPU against the CPU reference within 0.05
    # degrees (p99) where both cover the pixel.
    both = (gl_tilted[..., 3] == 1.0) & (cpu_tilted[..., 3] == 1.0)
    assert both.mean() > 0.5
    assert np.percentile(angle_deg(gl_tilted[both, :3], cpu_tilted[both, :3]), 99) <= 0.05


def test_scene_as_dict_json_text_and_file_give_the_same_image(tmp_path):
    scene = plane_scene()
    from_dict = surfgrad.render(scene, width=32, height=32, aov="color")
    from_text = surfgrad.render(json.dumps(scene), width=32, height=32, aov="color")
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    from_file = surfgrad.render(path, width=32, height=32, aov="color")
    from_str_path = surfgrad.render(str(path), width=32, height=32, aov="color")
    # The CPU reference renderer is deterministic: the same bits.
    np.testing.assert_array_equal(from_text, from_dict)
    np.testing.assert_array_equal(from_file, from_dict)
    np.testing.assert_array_equal(from_str_path, from_dict)
    assert np.isfinite(from_dict).all()


def test_a_model_file_renders_with_a_default_camera(tmp_path):
    # docs/scene.md / README: a MODEL is framed with a default camera and light. The cube's
    # normal AOV holds unit normals where it is drawn (float rounding of a normalization).
    path = tmp_path / "cube.obj"
    path.write_text(CUBE_OBJ)
    image = surfgrad.render(path, width=32, height=32, aov="normal")
    covered = image[..., 3] == 1.0
    assert 0.05 < covered.mean() < 1.0
    np.testing.assert_allclose(np.linalg.norm(image[covered, :3], axis=1), 1.0, atol=1e-5)


def test_default_scene_renders():
    image = surfgrad.render(None, width=32, height=24)
    assert image.shape == (24, 32, 4) and np.isfinite(image).all()


def test_scene_errors_name_the_field(tmp_path):
    # tests/render/scene_test.cpp, badCases().
    bad = {"meshes": [{"procedural": {"type": "sphere"}}], "mehses": []}
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.render(bad, width=16, height=16)
    assert e.value.element == "mehses" and "unknown field" in e.value.reason
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.render({"meshes": [{"procedural": {"type": "teapot"}}]}, width=16, height=16)
    assert e.value.element == "meshes[0].procedural.type" and "expected one of" in e.value.reason
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.render('{"meshes": [', width=16, height=16)
    assert "invalid JSON" in e.value.reason
    missing = tmp_path / "missing.json"
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.render(missing, width=16, height=16)
    assert e.value.file == str(missing)


@pytest.mark.parametrize(
    "kwargs, named",
    [
        ({"aov": "depth"}, "aov"),
        ({"renderer": "vulkan"}, "renderer"),
        ({"width": -1}, "width"),
        ({"height": 9000}, "height"),  # 1..8192
        ({"seconds": float("nan")}, "seconds"),
    ],
)
def test_render_refuses_bad_arguments(kwargs, named):
    args = {"width": 16, "height": 16, **kwargs}
    with pytest.raises(ValueError) as e:
        surfgrad.render(plane_scene(), **args)
    assert_names(e, named)


def test_render_refuses_a_scene_of_the_wrong_type():
    with pytest.raises(TypeError):
        surfgrad.render(42, width=16, height=16)


# ---------------------------------------------------------------------------
# Shared shader functions


def test_eval_functions_and_signatures():
    names = surfgrad.eval_functions()
    assert {"resolve", "tspace-to-deriv", "tbn"} <= set(names)
    sig = surfgrad.eval_signature("resolve")
    assert sig["name"] == "resolve"
    assert "normalize(n - sg)" in sig["summary"]
    # shaders/sg/eval/kernels.glsl, SG_EVAL_RESOLVE_IN/OUT: n, sg required; resolve_sign
    # optional with default 1.
    inputs = [(f["key"], f["width"], f["kind"], f["optional"]) for f in sig["inputs"]]
    assert inputs == [
        ("n", 3, "float", False),
        ("sg", 3, "float", False),
        ("resolve_sign", 1, "float", True),
    ]
    assert sig["inputs"][2]["default"] == 1.0
    assert [(f["key"], f["width"]) for f in sig["outputs"]] == [("n", 3)]
    flip = surfgrad.eval_signature("tspace-to-deriv")["inputs"][1]
    assert (flip["key"], flip["kind"], flip["default"]) == ("flip_v", "bool", 0.0)
    with pytest.raises(ValueError) as e:
        surfgrad.eval_signature("no-such-function")
    assert_names(e, "no-such-function")


def test_eval_resolve_known_answers():
    # CliEval.GoodLinesGiveKnownAnswers: normalize((0,0,1) - (0.5,0,0)) = (-1, 0, 2) / sqrt(5);
    # with resolve_sign -1: -normalize((0,0,2) - (0,0.75,0)) = (0, 0.6, -0.8). Float output: 1e-6.
    out = surfgrad.eval(
        "resolve",
        n=np.array([[0, 0, 1], [0, 0, 2]], np.float32),
        sg=np.array([[0.5, 0, 0], [0, 0.75, 0]], np.float32),
        resolve_sign=np.array([[1], [-1]], np.float32),
    )
    assert set(out) == {"n"} and out["n"].shape == (2, 3) and out["n"].dtype == np.float32
    np.testing.assert_allclose(out["n"][0], [-1 / math.sqrt(5), 0, 2 / math.sqrt(5)], atol=1e-6)
    np.testing.assert_allclose(out["n"][1], [0, 0.6, -0.8], atol=1e-6)
    # An omitted optional input takes its default (resolve_sign 1); a scalar broadcasts.
    default = surfgrad.eval("resolve", n=[0, 0, 1], sg=[0.5, 0, 0])
    np.testing.assert_allclose(default["n"], [-1 / math.sqrt(5), 0, 2 / math.sqrt(5)], atol=1e-6)
    flipped = surfgrad.eval("resolve", n=[[0, 0, 2]] * 3, sg=[[0, 0.75, 0]] * 3, resolve_sign=-1.0)
    np.testing.assert_allclose(flipped["n"], [[0, 0.6, -0.8]] * 3, atol=1e-6)


def test_eval_tspace_to_deriv_known_answers():
    # d = -m.xy / m.z with m.z = sqrt(1 - |m.xy|^2) = 0.8; flip_v negates the green channel.
    out = surfgrad.eval("tspace-to-deriv", m=np.array([[0.6, 0.0]], np.float32))
    np.testing.assert_allclose(out["d"], [[-0.75, 0.0]], atol=1e-6)
    flipped = surfgrad.eval("tspace-to-deriv", m=[0.0, 0.6], flip_v=True)
    np.testing.assert_allclose(flipped["d"], [0.0, 0.75], atol=1e-6)


def test_eval_tbn_over_a_grid_of_records():
    # d.x t + d.y b (L5) on (4, 5) records: two products and a sum in binary32, values up to 4:
    # 1e-6 relative.
    rng = np.random.default_rng(11)
    d = rng.uniform(-2, 2, (4, 5, 2)).astype(np.float32)
    t = rng.uniform(-1, 1, (4, 5, 3)).astype(np.float32)
    b = rng.uniform(-1, 1, (4, 5, 3)).astype(np.float32)
    out = surfgrad.eval("tbn", d=d, t=t, b=b)
    assert out["sg"].shape == (4, 5, 3)
    expected = d[..., :1].astype(np.float64) * t + d[..., 1:].astype(np.float64) * b
    np.testing.assert_allclose(out["sg"], expected, rtol=0, atol=1e-6 * 4)


def test_eval_refuses_bad_inputs():
    n = np.zeros((2, 3), np.float32)
    n[:, 2] = 1
    with pytest.raises(ValueError) as e:
        surfgrad.eval("no-such-function", n=n)
    assert_names(e, "no-such-function")
    with pytest.raises(ValueError) as e:
        surfgrad.eval("resolve", n=n)  # sg is required
    assert_names(e, "sg")
    with pytest.raises(ValueError) as e:
        surfgrad.eval("resolve", n=n, sg=np.zeros((2, 2), np.float32))  # width 3
    assert_names(e, "sg")
    with pytest.raises(ValueError) as e:
        surfgrad.eval("resolve", n=n, sg=np.zeros((3, 3), np.float32))  # 2 records vs 3
    assert_names(e, "sg")
    with pytest.raises(ValueError) as e:
        surfgrad.eval("resolve", n=n, sg=np.zeros((2, 3), np.float32), sgg=1.0)
    assert_names(e, "sgg")
    with pytest.raises(ValueError) as e:
        surfgrad.eval("resolve", n=n, sg=np.full((2, 3), np.nan, np.float32))
    assert_names(e, "sg")
