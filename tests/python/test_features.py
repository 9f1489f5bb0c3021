# surfgrad.features from Python (python/surfgrad/features.pyi): feature curves from JSON and SVG
# baked into feature maps (Parilov, Rosenberg, Zorin 2005; Parilov, Zorin 2008), sampled as the
# shader does, saved and loaded.
#
# Known values:
#  - tests/features/maps_bake_test.cpp, FeatureMapsBake.FitTransform: the polyline (-3, 10) to
#    (5, 14) in a 64^2 map with a 4-texel margin is scaled by 7 and centred: texel = 7 input +
#    (25, -52), the segment (4, 18) to (60, 46), its midpoint (32, 32) on the zero set;
#  - the exact distance to that segment, in double (a different method from the bake's):
#    tests/features/maps_accuracy_test.cpp, FeatureMapsAccuracy.LinearPolylines bounds the
#    reconstructed distance near straight segments (|d - exact| < 0.01 at offsets up to 0.5
#    texel, < 1e-4 on the curve) and the gradient's angle; the corner distances are the exact
#    distances clamped to the band (features/include/surfgrad/features/feature_maps.h, BakeOptions);
#  - tests/features/maps_storage_test.cpp: save/load is exact; bad files are InputErrors;
#  - docs/features-input.md: the JSON errors and their elements.
import numpy as np
import pytest

import surfgrad
from surfgrad import features
from conftest import assert_names

LINE_JSON = '{"version": 1, "curves": [{"points": [[-3, 10], [5, 14]]}]}'
A_TEXEL = np.array([4.0, 18.0])  # the segment's ends in texel space (7 x input + (25, -52))
B_TEXEL = np.array([60.0, 46.0])
DIRECTION = (B_TEXEL - A_TEXEL) / np.linalg.norm(B_TEXEL - A_TEXEL)
LEFT = np.array([-DIRECTION[1], DIRECTION[0]])  # left of the curve's direction


def segment_distance(points):
    """Exact distance (double) from points (M, 2) to the segment, and the parameter of the
    closest point along it (0 at A, 1 at B)."""
    points = np.asarray(points, np.float64)
    ab = B_TEXEL - A_TEXEL
    t = np.clip((points - A_TEXEL) @ ab / (ab @ ab), 0.0, 1.0)
    closest = A_TEXEL + t[:, None] * ab
    return np.linalg.norm(points - closest, axis=1), t


@pytest.fixture(scope="module")
def line_maps():
    return features.bake(json=LINE_JSON, size=64, margin=4.0, mode="linear")


def test_fit_puts_the_curve_where_the_cpp_test_says(line_maps):
    assert line_maps.size == 64
    assert line_maps.mode == "linear"
    assert line_maps.has_near_field is False
    assert isinstance(line_maps.stats, dict)
    # The input midpoint (1, 12) maps to (32, 32), on the zero set (1e-4: quantized edge points
    # times the gradient scale plus binary32 rounding of the position).
    r = line_maps.sample(np.array([[32.0, 32.0]], np.float32))
    assert r["dist"][0] < 1e-4


def test_sample_near_a_straight_segment(line_maps):
    # Points along the middle of the segment (more than 1.5 texels from its ends) at the
    # offsets of FeatureMapsAccuracy.LinearPolylines on both sides.
    along = np.linspace(0.1, 0.9, 41)
    on_curve = A_TEXEL + along[:, None] * (B_TEXEL - A_TEXEL)
    r = line_maps.sample(on_curve.astype(np.float32))
    assert r["dist"].shape == (41,) and r["grad"].shape == (41, 2)
    assert r["side"].shape == (41,) and r["profile"].dtype == np.int32 and r["width"].shape == (41,)
    # On the curve: the GPU layout rounds corner distances and gradients to half floats
    # (features/include/surfgrad/features/feature_maps.h: 5e-4 texels at d < 1), and both enter the
    # reconstruction: 2e-3. Measured 8e-4 here, the same as `surfgrad features sample` gives.
    assert r["dist"].max() < 2e-3
    for offset, max_deg in ((0.01, 2.0), (0.05, 8.0), (0.2, 25.0), (0.5, 25.0)):
        for side in (1.0, -1.0):
            points = on_curve + side * offset * LEFT
            r = line_maps.sample(points.astype(np.float32))
            exact, _ = segment_distance(points)
            # Linear in the partition triangles next to a straight curve and exact at the
            # corners: measured <= 0.003, bound 0.01.
            assert np.abs(r["dist"] - exact).max() < 0.01
            # +1 left of the nearest curve, else -1 (shaders/sg/features/kernels.glsl).
            np.testing.assert_array_equal(r["side"], np.full(41, side, r["side"].dtype))
            # The gradient points away from the curve on the sample's own side: measured 0.9 /
            # 4.7 / 11.8 / 17.1 degrees at 0.01 / 0.05 / 0.2 / 0.5 texels; the C++ bounds.
            g = r["grad"].astype(np.float64)
            cos = np.clip(g @ (side * LEFT) / np.linalg.norm(g, axis=1), -1, 1)
            assert np.degrees(np.arccos(cos)).max() < max_deg


def test_corner_distances_are_exact_and_clamped_to_the_band(line_maps):
    d = line_maps.distance()
    assert d.shape == (65, 65) and d.dtype == np.float32
    j, i = np.mgrid[0:65, 0:65]  # row j is y = j: row 0 at the bottom
    corners = np.stack([i.ravel(), j.ravel()], axis=1)
    exact, t = segment_distance(corners)
    exact = np.minimum(exact, 16.0).reshape(65, 65)  # the default band, 16 texels
    # Away from the ends, where the maps end curves on texel boundaries. Exact in double,
    # stored in binary32: 2e-6 at the 16-texel band edge; 1e-5 with margin.
    interior = ((t > 0.05) & (t < 0.95)).reshape(65, 65)
    assert interior.sum() > 1000
    np.testing.assert_allclose(np.abs(d[interior]), exact[interior], rtol=0, atol=1e-5)
    assert np.abs(d).max() <= 16.0


def test_save_and_load_are_exact(line_maps, tmp_path):
    # FeatureMapsStorage.RoundTripIsExact.
    path = tmp_path / "line.exr"
    line_maps.save(path)
    back = features.load(path)
    assert (back.size, back.mode, back.has_near_field) == (64, "linear", False)
    np.testing.assert_array_equal(back.distance(), line_maps.distance())
    points = np.random.default_rng(3).uniform(0, 64, (500, 2)).astype(np.float32)
    a, b = line_maps.sample(points), back.sample(points)
    for key in ("dist", "grad", "side", "profile", "width"):
        np.testing.assert_array_equal(a[key], b[key])


def test_bad_map_files_are_input_errors(line_maps, tmp_path):
    # FeatureMapsStorage.RejectsBadFiles: missing, not an image, truncated.
    with pytest.raises(surfgrad.InputError) as e:
        features.load(tmp_path / "none.exr")
    assert "no such file" in e.value.reason
    (tmp_path / "text.exr").write_text("hello")
    with pytest.raises(surfgrad.InputError) as e:
        features.load(tmp_path / "text.exr")
    assert e.value.file == str(tmp_path / "text.exr")
    line_maps.save(tmp_path / "good.exr")
    data = (tmp_path / "good.exr").read_bytes()
    (tmp_path / "trunc.exr").write_bytes(data[: len(data) // 2])
    with pytest.raises(surfgrad.InputError):
        features.load(tmp_path / "trunc.exr")


# ---------------------------------------------------------------------------
# Sources


def test_json_file_and_json_text_bake_the_same_maps(tmp_path):
    path = tmp_path / "line.json"
    path.write_text(LINE_JSON)
    a = features.bake(path, size=32, threads=1)
    b = features.bake(json=LINE_JSON, size=32, threads=1)
    np.testing.assert_array_equal(a.distance(), b.distance())


def test_svg_file_and_svg_text_bake_the_same_maps(data_dir):
    path = data_dir / "svg/flame.svg"
    a = features.bake(path, size=64, mode="quadratic")
    b = features.bake(svg=path.read_text(), size=64, mode="quadratic")
    assert a.mode == "quadratic"
    np.testing.assert_array_equal(a.distance(), b.distance())
    d = a.distance()
    assert np.isfinite(d).all() and d.min() < 0.5 and np.abs(d).max() <= 16.0


def test_bake_is_the_same_bits_for_every_thread_count(data_dir):
    path = data_dir / "svg/flame.svg"
    one = features.bake(path, size=128, threads=1)
    two = features.bake(path, size=128, threads=2)
    np.testing.assert_array_equal(one.distance(), two.distance())


def test_bake_reports_progress():
    seen = []
    features.bake(json=LINE_JSON, size=32, progress=lambda stage, f: seen.append((stage, f)))
    # features/src/bake.cpp reports ("scan", 1.0) at the end of every scan.
    assert ("scan", 1.0) in seen
    assert all(isinstance(stage, str) and 0.0 <= f <= 1.0 for stage, f in seen)


def test_near_field_profiles():
    curve = (
        '{"version": 1, "curves": [{"points": [[-3, 10], [5, 14]], '
        '"profile": "vgroove", "width": 0.5}]}'
    )
    maps = features.bake(json=curve, size=64, margin=4.0, near_field=True)
    assert maps.has_near_field
    mid = (A_TEXEL + B_TEXEL) / 2
    points = np.array([mid + 1.0 * LEFT, mid - 2.0 * LEFT, mid + 15.0 * LEFT], np.float32)
    r = maps.sample(points)
    # Within the near band: the exact distance to the input curve (tests/features/near_test.cpp
    # bounds it at 0.01 texel; binary32 positions give ~1e-5), the curve's profile and width.
    np.testing.assert_allclose(r["dist"][:2], [1.0, 2.0], atol=0.01)
    assert (r["profile"][:2] >= 0).all() and (r["width"][:2] > 0).all()
    # Far outside it: no profile (-1, shaders/sg/features/evaluate.glsl).
    assert r["profile"][2] == -1
    paper = maps.sample(points, near="paper")
    # The papers' interpolation: exact corner distances of a straight line, interpolated
    # (FeatureMapsAccuracy.LinearPolylines' bound, 0.01).
    assert np.abs(paper["dist"][:2] - [1.0, 2.0]).max() < 0.01
    names = features.profile_names()
    assert {"vgroove", "crease", "ridge", "step", "seam"} <= set(names)


# ---------------------------------------------------------------------------
# Errors


@pytest.mark.parametrize(
    "text, element, reason",
    [
        # docs/features-input.md, "JSON schema": the error examples.
        ('{"version": 2, "curves": []}', "version", "unsupported version 2"),
        ('{"version": 1, "curves": []}', "curves", "no curves"),
        (
            '{"version": 1, "curves": [{"points": [[0, 0], [1, 0]], "widht": 1}]}',
            "curves[0].widht",
            "unknown key",
        ),
        (
            '{"version": 1, "curves": [{"points": [[0, 0], [1, 0], [1, 0]]}]}',
            "curves[0].points[2]",
            "coincides with the previous point",
        ),
        ('{"version": 1, "curves": [', "line 1", "JSON syntax error"),
    ],
)
def test_malformed_json_is_an_input_error(text, element, reason):
    with pytest.raises(surfgrad.InputError) as e:
        features.bake(json=text, size=32)
    assert element in e.value.element
    assert reason in e.value.reason


def test_malformed_svg_is_an_input_error():
    # tests/features/input_svg_test.cpp, InputSvg.PathErrors.
    svg = (
        '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><path d="M10 10 X 5"/></svg>'
    )
    with pytest.raises(surfgrad.InputError) as e:
        features.bake(svg=svg, size=32)
    assert e.value.element == "path #1 command 2 'X'"
    assert "unknown path command" in e.value.reason


@pytest.mark.parametrize(
    "kwargs, named",
    [
        ({"size": 0}, "size"),
        ({"mode": "cubic"}, "mode"),
        ({"threads": -1}, "threads"),
        ({"threads": 2000}, "threads"),
        ({"band": float("nan")}, "band"),
        ({"margin": -1.0}, "margin"),
        ({"smooth_iterations": -1}, ("smooth_iterations", "iterations")),
    ],
)
def test_bake_refuses_bad_options(kwargs, named):
    with pytest.raises(ValueError) as e:
        features.bake(json=LINE_JSON, **kwargs)
    assert_names(e, named)


def test_bake_needs_exactly_one_source(tmp_path):
    with pytest.raises(ValueError):
        features.bake(size=32)
    with pytest.raises(ValueError):
        features.bake(tmp_path / "a.json", json=LINE_JSON, size=32)
    with pytest.raises(ValueError) as e:
        features.bake(text="Ag", size=32)  # text needs a font
    assert_names(e, "font")


def test_sample_refuses_bad_points(line_maps):
    with pytest.raises(TypeError) as e:
        line_maps.sample(np.zeros((4, 2), np.float64))
    assert_names(e, "points")
    with pytest.raises(ValueError) as e:
        line_maps.sample(np.zeros((4, 3), np.float32))
    assert_names(e, "points")
    with pytest.raises(ValueError) as e:
        line_maps.sample(np.array([[1.0, np.nan]], np.float32))
    assert_names(e, "points")
    with pytest.raises(ValueError) as e:
        line_maps.sample(np.zeros((4, 2), np.float32), near="fuzzy")
    assert_names(e, "near")
    empty = line_maps.sample(np.zeros((0, 2), np.float32))
    assert empty["dist"].shape == (0,)
