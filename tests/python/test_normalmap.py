# surfgrad.normalmap from Python (python/surfgrad/normalmap.pyi): the height-field-correct
# normal-map operations of Loviscach, "Care and Feeding of Normal Vectors" (GDC 2008), on numpy
# grids: slopes of heights and back (Poisson), scale/add/blend/modulate/curves, encodings, image
# files, LEAN (Olano and Baker 2010) and Toksvig (2005) MIP chains, the rasterized frames of a mesh.
#
# Known values:
#  - central differences of a sine are exactly A sin(w) cos(w u + phi) (a trigonometric
#    identity), of a linear ramp its two coefficients;
#  - tests/normalmap/poisson_test.cpp: to_height inverts from_height to 1e-4 texels (tiling and
#    finite grids), a flat map integrates to a flat height;
#  - tests/normalmap/ops_analytic_test.cpp: scale -1 twice and add(d, d) = scale 2 bit for bit;
#  - tests/normalmap/mips_test.cpp: the LEAN chain of d = (c + a cos, e + b sin) with full periods
#    per footprint has mean (c, e) and covariance (a^2/2, b^2/2, 0); Toksvig's s2 approximates the
#    slope variance; every level keeps the mean; the EXR layout round-trips bit for bit;
#  - tests/normalmap/encoding_test.cpp: encodings carry the same slopes, DirectX green mirrors the
#    green channel, object space through a mesh's frames inverts.
# Grids are (H, W[, C]) float32 with row 0 the bottom row; texel (i, j) sits at (i + 0.5, j + 0.5).
import struct
import zlib

import numpy as np
import pytest

import surfgrad
from surfgrad import normalmap
from conftest import angle_deg, assert_names

TWO_PI = 2.0 * np.pi


def texel_centres(width, height):
    """u, v of every texel centre as (H, W) arrays in double (row 0 at the bottom)."""
    v, u = np.mgrid[0:height, 0:width].astype(np.float64) + 0.5
    return u, v


def sines(width, height, amplitude):
    """Heights and exact slopes of the tiling sum of sines of tests/normalmap/analytic_fields.h
    (one period of each wave over the tile), in double."""
    waves = [(1.0, 2, 1, 0.3), (0.6, -1, 3, 1.1), (0.35, 4, -3, 2.0)]
    u, v = texel_centres(width, height)
    h = np.zeros_like(u)
    d = np.zeros(u.shape + (2,))
    for a, p, q, phase in waves:
        arg = TWO_PI * (p * u / width + q * v / height) + phase
        h += amplitude * a * np.sin(arg)
        c = amplitude * a * TWO_PI * np.cos(arg)
        d[..., 0] += c * p / width
        d[..., 1] += c * q / height
    return h, d


def non_tiling(width, height):
    """The smooth field of tests/normalmap/poisson_test.cpp that does not tile."""
    u, v = texel_centres(width, height)
    return 0.002 * (u - 0.3 * width) ** 2 - 0.03 * v + 4 * np.sin(u / 13.0 + v / 29.0)


def f32(a):
    return np.ascontiguousarray(a, dtype=np.float32)


def png_bytes(rows_top_first):
    """A minimal 8-bit RGB PNG (filter 0 on every row, no interlace) whose FIRST stored row is
    rows_top_first[0]: the file order of every image format, top row first."""
    rows = np.asarray(rows_top_first, np.uint8)
    height, width = rows.shape[:2]

    def chunk(kind, data):
        return (
            struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
        )

    raw = b"".join(b"\x00" + rows[r].tobytes() for r in range(height))
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(raw))
        + chunk(b"IEND", b"")
    )


# ---------------------------------------------------------------------------
# Heights and slopes


def test_from_height_of_a_sine_is_its_central_difference():
    # (h(u + 1) - h(u - 1)) / 2 of h = A sin(w u + phi) is A sin(w) cos(w u + phi) exactly; the
    # sampled slope differs from the analytic A w cos by the factor sin(w) / w (0.96 at w =
    # 2 pi 4 / 64), so this tells central differences from any other stencil.
    width, height, amplitude, phase = 64, 48, 5.0, 0.4
    omega = TWO_PI * 4 / width
    u, v = texel_centres(width, height)
    h = amplitude * np.sin(omega * u + phase)
    slopes = normalmap.from_height(f32(h))
    assert slopes.shape == (height, width, 2) and slopes.dtype == np.float32
    expected = amplitude * np.sin(omega) * np.cos(omega * u + phase)
    # Heights in binary32 (|h| <= 5: 3e-7 rounding), differenced and halved: 1e-6 with margin.
    np.testing.assert_allclose(slopes[..., 0], expected, rtol=0, atol=1e-6)
    np.testing.assert_allclose(slopes[..., 1], 0.0, rtol=0, atol=1e-6)
    # scale multiplies the height: the slopes double exactly (binary32 doubling).
    np.testing.assert_array_equal(normalmap.from_height(f32(h), scale=2.0), 2 * slopes)


@pytest.mark.parametrize("wrap", ["clamp", "repeat"])
def test_from_height_of_a_ramp_gives_its_coefficients_row_zero_at_the_bottom(wrap):
    # h = 3 u + 5 v in texels, v growing with the row index (row 0 at the bottom): d = (3, 5)
    # inside; clamp takes one-sided differences at the border, which are exact for a ramp too.
    u, v = texel_centres(16, 12)
    slopes = normalmap.from_height(f32(3 * u + 5 * v), wrap=wrap)
    inner = slopes if wrap == "clamp" else slopes[1:-1, 1:-1]
    # Heights up to 108 in binary32 (7.6e-6 ulp), differenced: 1e-5.
    np.testing.assert_allclose(inner[..., 0], 3.0, atol=1e-5)
    np.testing.assert_allclose(inner[..., 1], 5.0, atol=1e-5)


@pytest.mark.parametrize(
    "width, height, wrap",
    [(64, 64, "repeat"), (48, 40, "repeat"), (64, 64, "clamp"), (50, 37, "clamp")],
)
def test_to_height_inverts_from_height(width, height, wrap):
    # Poisson.ToHeightInvertsFromHeight: exact in exact arithmetic; binary32 heights through
    # double transforms: 1e-4 texels. Heights come back measured from their lowest texel.
    h = sines(width, height, 2.25)[0] if wrap == "repeat" else non_tiling(width, height)
    h = f32(h - h.min())
    slopes = normalmap.from_height(h, wrap=wrap)
    back = normalmap.to_height(slopes, wrap=wrap)
    assert back.shape == (height, width) and back.dtype == np.float32
    assert back.min() == 0.0
    assert np.abs(back - h).max() < 1e-4
    assert np.abs(normalmap.from_height(back, wrap=wrap) - slopes).max() < 1e-5


def test_to_height_of_a_flat_map_is_flat():
    # Poisson.DegenerateSizesAndFlatFields.
    flat = normalmap.to_height(np.zeros((48, 64, 2), np.float32), wrap="clamp")
    np.testing.assert_array_equal(flat, np.zeros((48, 64), np.float32))
    for shape in [(1, 1, 2), (7, 1, 2), (1, 5, 2), (2, 2, 2)]:
        tiny = normalmap.to_height(np.full(shape, 0.3, np.float32))
        assert tiny.shape == shape[:2] and np.isfinite(tiny).all() and (tiny >= 0).all()


def test_to_height_reports_progress_and_lets_exceptions_through():
    slopes = normalmap.from_height(f32(sines(32, 32, 2.0)[0]))
    seen = []
    normalmap.to_height(slopes, progress=seen.append)
    assert seen, "normalmap/src/poisson.cpp reports every stage"
    assert all(0.0 <= f <= 1.0 for f in seen)
    assert seen == sorted(seen) and seen[-1] == 1.0

    def fail(fraction):
        raise RuntimeError("stop at %g" % fraction)

    with pytest.raises(RuntimeError, match="stop at"):
        normalmap.to_height(slopes, progress=fail)


def test_normals_from_slopes_and_back():
    # n = normalize(-d.x, -d.y, 1) ("Normal in Short Form"); d = -n.xy / n.z.
    d = sines(32, 24, 3.0)[1]
    normals = normalmap.normals_from_slopes(f32(d))
    expected = np.concatenate([-d, np.ones(d.shape[:2] + (1,))], axis=-1)
    expected /= np.linalg.norm(expected, axis=-1, keepdims=True)
    # One binary32 normalization: a few ulps.
    np.testing.assert_allclose(normals, expected, rtol=0, atol=1e-6)
    back = normalmap.slopes_from_normals(normals)
    # The slope divides by n.z >= 0.4 here: the normals' 1e-7 error grows to ~1e-6 of |d| ~ 2.
    np.testing.assert_allclose(back, d, rtol=0, atol=1e-5)


# ---------------------------------------------------------------------------
# Operations


def test_scale_and_add_are_exact():
    # OpsAnalytic.ScaleMinusOneTwiceIsIdentityAndAddSelfIsScaleTwo: negation and doubling are
    # exact in binary32.
    d = f32(sines(64, 64, 2.25)[1])
    np.testing.assert_array_equal(normalmap.scale(normalmap.scale(d, -1.0), -1.0), d)
    np.testing.assert_array_equal(normalmap.add(d, 1.0, d, 1.0), normalmap.scale(d, 2.0))
    np.testing.assert_array_equal(normalmap.scale(d, 2.0), 2 * d)
    other = f32(np.flip(d, axis=1))
    # wa dA + wb dB: two binary32 products and a sum (1.5 ulps of values up to ~2).
    np.testing.assert_allclose(
        normalmap.add(d, 0.7, other, 1.3), 0.7 * d.astype(np.float64) + 1.3 * other, atol=1e-6
    )


def test_blend_with_a_constant_mask_picks_one_map():
    # (1 - m) dA + m dB + (hB - hA) dm with dm = 0: A at m = 0, B at m = 1.
    a = f32(sines(32, 32, 2.0)[1])
    b = f32(np.flip(a, axis=0))
    np.testing.assert_allclose(normalmap.blend(a, b, np.zeros((32, 32), np.float32)), a, atol=1e-7)
    np.testing.assert_allclose(normalmap.blend(a, b, np.ones((32, 32), np.float32)), b, atol=1e-7)


def test_modulate_by_a_constant_gain_scales_the_slopes():
    # d g + h dg with dg = 0 (a constant gain has zero central differences).
    d = f32(sines(32, 32, 2.0)[1])
    out = normalmap.modulate(d, np.full((32, 32), 0.5, np.float32))
    np.testing.assert_allclose(out, 0.5 * d, atol=1e-7)


def test_identity_curve_keeps_the_slopes():
    # f(x) = x through the points (0, 0), (1, 1): f' = 1 and the chain rule gives d back; the
    # normalization to the height range and back costs a few ulps.
    d = f32(sines(32, 32, 2.0)[1])
    out = normalmap.curves(d, points=[(0.0, 0.0), (1.0, 1.0)])
    np.testing.assert_allclose(out, d, atol=1e-5)


def test_malformed_curve_and_warp_text_are_input_errors():
    d = np.zeros((8, 8, 2), np.float32)
    with pytest.raises(surfgrad.InputError):
        normalmap.curves(d, points="0,0 0.5")
    with pytest.raises(surfgrad.InputError):
        normalmap.deform(d, "twist:3")


def test_operations_refuse_bad_grids():
    d = np.zeros((8, 8, 2), np.float32)
    with pytest.raises(TypeError) as e:
        normalmap.scale(d.astype(np.float64), 2.0)
    assert_names(e, "slopes")
    with pytest.raises(ValueError) as e:
        normalmap.scale(np.zeros((8, 8, 3), np.float32), 2.0)
    assert_names(e, "slopes")
    with pytest.raises(ValueError) as e:
        normalmap.add(d, 1.0, np.zeros((8, 16, 2), np.float32), 1.0)  # one size for all grids
    assert_names(e, "b")
    nan = d.copy()
    nan[3, 4, 1] = np.nan
    with pytest.raises(ValueError) as e:
        normalmap.to_height(nan)
    assert_names(e, "slopes")
    with pytest.raises(ValueError) as e:
        normalmap.from_height(np.zeros((8, 8, 1), np.float32))
    assert_names(e, "height")
    with pytest.raises(ValueError) as e:
        normalmap.from_height(np.zeros((8, 8), np.float32), wrap="mirror")
    assert_names(e, "wrap")
    with pytest.raises(ValueError) as e:
        normalmap.from_height(np.zeros((8, 16), np.float32)[:, ::2])
    assert_names(e, "height")
    with pytest.raises(ValueError) as e:
        normalmap.blend(d, d, np.zeros((8, 7), np.float32))
    assert_names(e, "mask")


# ---------------------------------------------------------------------------
# Encodings


@pytest.mark.parametrize(
    "encoding, is_float",
    [
        ("rgb", False),
        ("rg", False),
        ("ag", False),
        ("deriv", False),
        ("deriv", True),
        ("signed", True),
    ],
)
def test_every_encoding_carries_the_same_slopes(encoding, is_float):
    # Encoding.EveryEncodingCarriesTheSameSlopes (float round trips: 1e-5, binary32 rounding of
    # the normalization and the division by n.z at slopes up to 1.2).
    d = f32(sines(64, 48, 3.0)[1])
    image = normalmap.encode_slopes(d, encoding, deriv_range=4.0, is_float=is_float)
    assert image.shape[:2] == d.shape[:2]
    assert image.shape[2] == {"rgb": 3, "rg": 2, "ag": 4, "deriv": 2, "signed": 3}[encoding]
    back = normalmap.decode_slopes(image, encoding, deriv_range=4.0, is_float=is_float)
    assert np.linalg.norm(back - d, axis=-1).max() < 1e-5


def test_directx_green_mirrors_the_green_channel():
    # Encoding.DirectXGreenMirrorsTheGreenChannel (here before quantization: 1 - c in binary32).
    d = f32(sines(32, 32, 2.0)[1])
    gl = normalmap.encode_slopes(d, "rgb", green="gl")
    dx = normalmap.encode_slopes(d, "rgb", green="dx")
    np.testing.assert_allclose(dx[..., 1], 1.0 - gl[..., 1], atol=1e-7)
    np.testing.assert_array_equal(dx[..., 0], gl[..., 0])
    back = normalmap.decode_slopes(dx, "rgb", green="dx")
    np.testing.assert_allclose(back, normalmap.decode_slopes(gl, "rgb"), atol=1e-5)


def test_encode_normals_is_half_n_plus_half():
    n = normalmap.normals_from_slopes(f32(sines(16, 16, 2.0)[1]))
    np.testing.assert_allclose(normalmap.encode_normals(n), 0.5 * n + 0.5, atol=1e-7)
    np.testing.assert_allclose(normalmap.decode_normals(normalmap.encode_normals(n)), n, atol=1e-5)


def test_unknown_encoding_and_green_are_value_errors():
    d = np.zeros((4, 4, 2), np.float32)
    with pytest.raises(ValueError) as e:
        normalmap.encode_slopes(d, "bc5")
    assert_names(e, "encoding")
    with pytest.raises(ValueError) as e:
        normalmap.decode_slopes(np.zeros((4, 4, 3), np.float32), green="up")
    assert_names(e, "green")
    with pytest.raises(ValueError) as e:
        normalmap.decode_slopes(np.zeros((4, 4, 2), np.float32), "rgb")  # 3 channels needed
    assert_names(e, "image")


# ---------------------------------------------------------------------------
# Image files


def test_read_image_puts_the_files_top_row_last(tmp_path):
    # A PNG written here byte by byte: stored rows red (top), then green.
    path = tmp_path / "two_rows.png"
    path.write_bytes(png_bytes([[[255, 0, 0]] * 3, [[0, 255, 0]] * 3]))
    image, bits = normalmap.read_image(path)
    assert bits == "8"
    assert image.shape == (2, 3, 3) and image.dtype == np.float32
    np.testing.assert_array_equal(image[0], [[0, 1, 0]] * 3)  # row 0: the bottom, green
    np.testing.assert_array_equal(image[1], [[1, 0, 0]] * 3)


@pytest.mark.parametrize(
    "name, bits",
    [("a.png", "8"), ("a.png", "16"), ("a.tif", "16"), ("a.exr", "float"), ("a.exr", "half")],
)
def test_write_image_round_trip(tmp_path, name, bits):
    rng = np.random.default_rng(5)
    if bits in ("8", "16"):
        q = 2 ** int(bits) - 1
        codes = rng.integers(0, q + 1, (7, 5, 3))
        image = f32(codes / q)
    else:
        image = f32(rng.uniform(-3, 3, (7, 5, 3)))
        if bits == "half":
            image = image.astype(np.float16).astype(np.float32)  # representable in half
    normalmap.write_image(tmp_path / name, image, bits, attributes={"surfgrad:encoding": "rgb"})
    back, back_bits = normalmap.read_image(tmp_path / name)
    assert back_bits == bits and back.shape == image.shape
    if bits in ("8", "16"):
        # The integer codes survive; code / q as binary32 may differ in the last bit from ours
        # (a multiply by 1 / q instead of a division): 2e-7 relative.
        np.testing.assert_array_equal(np.rint(back.astype(np.float64) * q), codes)
        np.testing.assert_allclose(back, image, rtol=2e-7, atol=0)
    else:
        np.testing.assert_array_equal(back, image)  # float and half samples: bit exact


def test_write_image_takes_two_dimensional_grids(tmp_path):
    height = f32(np.arange(12).reshape(3, 4) / 11.0)
    normalmap.write_image(tmp_path / "h.exr", height)
    back, bits = normalmap.read_image(tmp_path / "h.exr")
    assert bits == "float"  # the format's default
    np.testing.assert_array_equal(back.reshape(3, 4), height)


def test_image_files_errors(tmp_path):
    good = tmp_path / "good.png"
    good.write_bytes(png_bytes([[[1, 2, 3]] * 4] * 4))
    truncated = tmp_path / "truncated.png"
    truncated.write_bytes(good.read_bytes()[:40])
    with pytest.raises(surfgrad.InputError) as e:
        normalmap.read_image(truncated)
    assert e.value.file == str(truncated)
    with pytest.raises(surfgrad.InputError) as e:
        normalmap.read_image(tmp_path / "missing.png")
    assert e.value.file == str(tmp_path / "missing.png")
    image = np.zeros((4, 4, 3), np.float32)
    with pytest.raises(surfgrad.InputError):
        normalmap.write_image(tmp_path / "a.bmp", image)
    with pytest.raises(ValueError) as e:
        normalmap.write_image(tmp_path / "a.png", image, bits="12")
    assert_names(e, "bits")
    nan = image.copy()
    nan[1, 2, 0] = np.nan
    with pytest.raises(ValueError) as e:
        normalmap.write_image(tmp_path / "a.exr", nan)
    assert_names(e, "image")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["good.png", "truncated.png"]


def test_real_map_decodes_to_finite_slopes(data_dir):
    image, bits = normalmap.read_image(data_dir / "textures/technicalFabricSmall_normal_256.png")
    assert bits == "8" and image.shape[:2] == (256, 256)
    slopes = normalmap.decode_slopes(image)
    # Listing 4 bounds every slope by 128: flat, horizon and beyond-the-circle texels included.
    assert np.isfinite(slopes).all() and np.abs(slopes).max() <= 128.0


# ---------------------------------------------------------------------------
# MIP chains

A, B, C, E, PERIOD = 0.6, 0.3, 0.2, -0.1, 16  # tests/normalmap/mips_test.cpp kA kB kC kE kP


def known_field(width, height, scale=1.0, mean=True):
    """d = (c + a cos(2 pi u / P), e + b sin(2 pi v / P)) at texel centres: every aligned P x P
    block holds full periods, so its mean is (c, e), var x = a^2 / 2, var y = b^2 / 2, cov 0."""
    u, v = texel_centres(width, height)
    dx = (C if mean else 0.0) + scale * A * np.cos(TWO_PI * u / PERIOD)
    dy = (E if mean else 0.0) + scale * B * np.sin(TWO_PI * v / PERIOD)
    return f32(np.stack([dx, dy], axis=-1))


def test_lean_gives_the_known_mean_and_covariance():
    # Mips.LeanGivesTheKnownMeanAndCovariance: channels (dx, dy, dxx, dyy, dxy); covariance
    # (dxx - dx^2, dyy - dy^2, dxy - dx dy). Averages of 256+ binary32 values of O(0.5): 1e-6.
    levels = normalmap.mips(known_field(64, 32), "lean")
    assert [lv.shape for lv in levels] == [
        (32 >> k if 32 >> k else 1, 64 >> k, 5) for k in range(7)
    ]
    for level in levels[4:]:  # level 4 (4 x 2 texels) has 16 x 16 footprints
        m = level.astype(np.float64)
        np.testing.assert_allclose(m[..., 0], C, atol=1e-6)
        np.testing.assert_allclose(m[..., 1], E, atol=1e-6)
        np.testing.assert_allclose(m[..., 2] - m[..., 0] ** 2, A * A / 2, atol=1e-6)
        np.testing.assert_allclose(m[..., 3] - m[..., 1] ** 2, B * B / 2, atol=1e-6)
        np.testing.assert_allclose(m[..., 4] - m[..., 0] * m[..., 1], 0.0, atol=1e-6)
    # Level 0 has no spread within a texel.
    m0 = levels[0].astype(np.float64)
    spread = np.abs(m0[..., 2] - m0[..., 0] ** 2) + np.abs(m0[..., 3] - m0[..., 1] ** 2)
    assert spread.max() < 1e-6


@pytest.mark.parametrize("scale, tolerance", [(0.1, 0.005), (0.3, 0.03)])
def test_toksvig_approximates_the_slope_variance(scale, tolerance):
    # Mips.ToksvigApproximatesTheSlopeVariance: zero-mean slopes; s2 ~ (var x + var y) / 2 with
    # the fourth-moment term making it low by about the variance itself (measured 0.1% at
    # scale 0.1, 1.0% at 0.3; bounds 0.5% and 3%).
    levels = normalmap.mips(known_field(64, 64, scale, mean=False), "toksvig")
    assert levels[0].shape == (64, 64, 4)
    want = scale * scale * (A * A + B * B) / 4
    assert abs(levels[4][2, 1, 3] / want - 1.0) < tolerance  # a 16 x 16 footprint
    assert levels[0][5, 5, 3] < 1e-6  # unit normals: s2 = 0 to rounding


def test_every_level_keeps_the_mean_and_the_file_round_trips(tmp_path):
    # Mips.EveryLevelKeepsTheMeanAndTheFileRoundTrips: odd sizes (overlap-weighted box
    # footprints); equal-area footprints keep the mean up to binary32 storage (2e-6).
    d = f32(sines(77, 50, 5.0)[1])
    levels = normalmap.mips(d, "lean")
    assert levels[-1].shape[:2] == (1, 1)
    mean0 = levels[0].astype(np.float64).mean(axis=(0, 1))
    for level in levels:
        np.testing.assert_allclose(level.astype(np.float64).mean(axis=(0, 1)), mean0, atol=2e-6)
    path = tmp_path / "lean.exr"
    normalmap.write_mips(path, levels, "lean", "repeat")
    back, names, layout = normalmap.read_mips(path)
    assert names == ["dx", "dy", "dxx", "dyy", "dxy"]
    assert layout == "lean"
    assert len(back) == len(levels)
    for a, b in zip(back, levels):
        np.testing.assert_array_equal(a, b)  # 32-bit float channels: bit exact


def test_mip_files_errors(tmp_path):
    levels = normalmap.mips(np.zeros((8, 8, 2), np.float32), "lean")
    # normalmap/src/image_file.cpp, writeMipChain: OpenEXR only.
    with pytest.raises(surfgrad.InputError) as e:
        normalmap.write_mips(tmp_path / "lean.png", levels, "lean")
    assert "OpenEXR" in e.value.reason
    with pytest.raises(ValueError) as e:
        normalmap.write_mips(tmp_path / "lean.exr", [lv[..., :4].copy() for lv in levels], "lean")
    assert_names(e, "levels")  # lean levels have 5 channels
    with pytest.raises(ValueError) as e:
        normalmap.write_mips(tmp_path / "lean.exr", levels, "lean", wrap="mirror")
    assert_names(e, "wrap")
    assert list(tmp_path.iterdir()) == []  # nothing half-written
    normalmap.write_mips(tmp_path / "good.exr", levels, "lean")
    data = (tmp_path / "good.exr").read_bytes()
    (tmp_path / "truncated.exr").write_bytes(data[: len(data) // 2])
    with pytest.raises(surfgrad.InputError) as e:
        normalmap.read_mips(tmp_path / "truncated.exr")
    assert e.value.file == str(tmp_path / "truncated.exr")


def test_mips_report_progress_and_refuse_unknown_layouts():
    seen = []
    normalmap.mips(np.zeros((16, 16, 2), np.float32), "lean", progress=seen.append)
    assert seen and seen == sorted(seen) and all(0 <= f <= 1 for f in seen)
    with pytest.raises(ValueError) as e:
        normalmap.mips(np.zeros((16, 16, 2), np.float32), "trilinear")
    assert_names(e, "layout")


def test_shade_is_uniform_on_a_flat_map_and_brighter_toward_the_light():
    flat = np.tile(np.array([0, 0, 1], np.float32), (8, 8, 1))
    lit = normalmap.shade(flat)
    assert lit.shape[:2] == (8, 8) and np.isfinite(lit).all()
    assert np.ptp(lit) == 0.0
    light = np.array([0.4, 0.5, 0.77])
    toward = np.tile(f32(light / np.linalg.norm(light)), (8, 8, 1))
    away = np.tile(f32([-0.6, -0.6, 0.52915026]), (8, 8, 1))
    assert normalmap.shade(toward).mean() > lit.mean() > normalmap.shade(away).mean()


# ---------------------------------------------------------------------------
# Object space through a mesh's frames


def unit_square_mesh():
    """Two triangles covering the UV square exactly: P = (s, t, 0), normal +z, UV = (s, t); its
    MikkTSpace tangents are (1, 0, 0, +1) everywhere."""
    positions = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    normals = np.tile(np.array([0, 0, 1], np.float32), (4, 1))
    mesh = surfgrad.RenderMesh(
        positions,
        np.array([[0, 1, 2], [0, 2, 3]], np.uint32),
        normals=normals,
        uv_sets=[positions[:, :2].copy()],
    )
    surfgrad.generate_tangents(mesh)
    return mesh


def test_rasterized_frames_of_the_unit_square():
    frames = normalmap.rasterize_frames(unit_square_mesh(), 0, 16, 8)
    assert frames["covered"].shape == (8, 16) and frames["covered"].dtype == np.uint8
    assert frames["covered"].all()
    np.testing.assert_allclose(frames["normal"], np.broadcast_to([0, 0, 1], (8, 16, 3)), atol=1e-6)
    np.testing.assert_allclose(
        frames["tangent"], np.broadcast_to([1, 0, 0, 1], (8, 16, 4)), atol=1e-6
    )


def test_object_space_through_an_identity_frame_and_back():
    # With T = +x, B = +y, N = +z the object-space normal is the tangent-space one, and the
    # inverse returns the slopes (Encoding.ObjectSpaceThroughSpotsFramesMatchesTbnAndInverts:
    # binary32 frames of O(1) vectors, 1e-3 degrees).
    frames = normalmap.rasterize_frames(unit_square_mesh(), 0, 32, 32)
    d = f32(sines(32, 32, 2.0)[1])
    obj = normalmap.object_from_tangent(d, frames)
    assert angle_deg(obj, normalmap.normals_from_slopes(d)).max() < 1e-3
    back = normalmap.tangent_from_object(obj, frames)
    assert (
        angle_deg(normalmap.normals_from_slopes(back), normalmap.normals_from_slopes(d)).max()
        < 1e-3
    )


def test_frames_of_a_different_size_are_refused():
    frames = normalmap.rasterize_frames(unit_square_mesh(), 0, 16, 16)
    with pytest.raises(ValueError) as e:
        normalmap.object_from_tangent(np.zeros((8, 8, 2), np.float32), frames)
    assert_names(e, "frames")
    with pytest.raises(ValueError) as e:
        normalmap.rasterize_frames(unit_square_mesh(), 1, 16, 16)  # one UV set
    assert_names(e, "uv_set")
    with pytest.raises(ValueError) as e:
        normalmap.rasterize_frames(unit_square_mesh(), 0, 0, 16)
    assert_names(e, "width")
