# surfgrad.bake from Python (python/surfgrad/__init__.pyi, "Baking"; docs/bake.md): a plane
# cage under an analytic height field, read back in the module's grid convention (row 0 at the
# bottom), and the errors of bad input.
import numpy as np
import pytest

import surfgrad

AMP = 0.02


def height(x, y):
    return AMP * np.sin(2 * np.pi * x) * np.cos(2 * np.pi * y)


def write_plane_cage(path, n=4, uvs=True):
    # n x n quads over [0,1]^2 at z = 0, UV = (x, y), boundary edge-and-corner: the limit
    # surface is the square itself (linear precision of the B-spline rules).
    lines = ["t interpolateboundary 1/0/0 1"]
    for j in range(n + 1):
        for i in range(n + 1):
            lines.append(f"v {i / n} {j / n} 0")
            if uvs:
                lines.append(f"vt {i / n} {j / n}")
    for j in range(n):
        for i in range(n):
            v0 = j * (n + 1) + i + 1
            quad = [v0, v0 + 1, v0 + n + 2, v0 + n + 1]
            lines.append("f " + " ".join(f"{v}/{v}" if uvs else f"{v}" for v in quad))
    path.write_text("\n".join(lines) + "\n")


def write_height_mesh(path, n=200, lo=-0.1, hi=1.1):
    xs = np.linspace(lo, hi, n + 1)
    lines = []
    for y in xs:
        for x in xs:
            lines.append(f"v {x:.9g} {y:.9g} {height(x, y):.9g}")
    for j in range(n):
        for i in range(n):
            v0 = j * (n + 1) + i + 1
            lines.append(f"f {v0} {v0 + 1} {v0 + n + 2}")
            lines.append(f"f {v0} {v0 + n + 2} {v0 + n + 1}")
    path.write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def plane(tmp_path_factory):
    d = tmp_path_factory.mktemp("bake")
    write_plane_cage(d / "cage.obj")
    write_height_mesh(d / "high.obj")
    return surfgrad.load_cage(d / "cage.obj"), surfgrad.load_mesh(d / "high.obj"), d


def test_plane_gives_the_analytic_heights_row_0_at_the_bottom(plane):
    cage, high, _ = plane
    r = surfgrad.bake(high, cage, size=(64, 48), max_distance=0.1)
    assert r["displacement"].shape == (48, 64)
    assert r["object_normal"].shape == (48, 64, 3)
    assert r["tangent_slopes"].shape == (48, 64, 2)
    assert "residual_slopes" not in r  # only with residual=True
    assert r["state"].dtype == np.uint8
    assert (r["state"] == 1).all() and r["stats"]["hits"] == 64 * 48
    j, i = np.mgrid[0:48, 0:64]
    x, y = (i + 0.5) / 64, (j + 0.5) / 48
    # The texel's point is its centre (row 0 at t = 0.5 / 48, the bottom), to binary32 rounding
    # of coordinates of order 1 after Newton's steps (a few ulps: 2e-6).
    np.testing.assert_allclose(r["position"][..., 0], x, atol=2e-6)
    np.testing.assert_allclose(r["position"][..., 1], y, atol=2e-6)
    # Linear interpolation of h over the high mesh's triangles (diameter d = sqrt(2) 1.2 / 200)
    # errs by at most M d^2 / 2, M = 2 A (2 pi)^2 the largest second derivative: 4e-5.
    d = np.sqrt(2) * 1.2 / 200
    bound = 0.5 * d * d * 2 * AMP * (2 * np.pi) ** 2 + 1e-6
    assert np.abs(r["displacement"] - height(x, y)).max() <= bound


def test_refined_surface_and_threads_give_the_same_heights_on_a_plane(plane):
    cage, high, _ = plane
    a = surfgrad.bake(high, cage, size=32, max_distance=0.1, threads=1)
    b = surfgrad.bake(high, cage, size=32, max_distance=0.1, surface="refined", level=1, threads=2)
    # On the plane both surfaces are the square: the same rays and hits, up to the rounding of the
    # two ways of reaching the texel's point (patch bases vs barycentrics: a few ulps of heights
    # of order 0.02, far below 1e-6).
    np.testing.assert_allclose(a["displacement"], b["displacement"], atol=1e-6)
    # The residual on request: the high mesh is the displaced plane, so the
    # displacement explains its normal and inside the map the residual is
    # the error of the central differences (texel D = 1/32): D^2/6 max|h_xxx|
    # = 8.1e-4, plus the high mesh's interpolation errors (vertex spacing
    # d = 1.2 sqrt(2) / 200): heights M d^2 / 2 = 5.7e-5 over D (1.8e-3) and
    # slopes 3.6e-4 (tests/bake/bake_test.cpp derives the same terms);
    # 3e-3 in all. The whole slopes reach 0.12.
    c = surfgrad.bake(high, cage, size=32, max_distance=0.1, residual=True)
    assert c["residual_slopes"].shape == (32, 32, 2)
    assert np.all(np.isfinite(c["residual_slopes"]))
    assert np.abs(c["residual_slopes"][1:-1, 1:-1]).max() < 3e-3


def test_bad_input_and_arguments_raise(plane, tmp_path):
    cage, high, _ = plane
    write_plane_cage(tmp_path / "nouv.obj", uvs=False)
    with pytest.raises(surfgrad.InputError) as e:
        surfgrad.bake(high, surfgrad.load_cage(tmp_path / "nouv.obj"), size=16)
    assert e.value.element == "uv set 0"
    with pytest.raises(ValueError, match="surface"):
        surfgrad.bake(high, cage, size=16, surface="triangles")
    with pytest.raises(ValueError, match="threads"):
        surfgrad.bake(high, cage, size=16, threads=2000)
    with pytest.raises(surfgrad.InputError, match="size"):
        surfgrad.bake(high, cage, size=0)
    with pytest.raises(surfgrad.InputError, match="same space and scale"):
        surfgrad.bake(high, cage, size=16, max_distance=1e-6)
