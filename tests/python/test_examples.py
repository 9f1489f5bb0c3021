# The example scripts of examples/python run as a user runs them (a new interpreter, the same
# PYTHONPATH), on small inputs, writing only below tmp_path; their outputs are read back through
# the module: the .glb has a tangent per vertex (MikkTSpace's w = +-1), the LEAN file one level
# per power of two with the layout's channels (tests/normalmap/mips_test.cpp), the feature-curve
# image the requested size. A malformed input ends with status 1 and the InputError's line.
import os
import subprocess
import sys

import numpy as np
import pytest

import surfgrad
from surfgrad import normalmap
from conftest import REPO_DIR

EXAMPLES = REPO_DIR / "examples/python"


def run(script, *args):
    return subprocess.run(
        [sys.executable, str(EXAMPLES / script), *map(str, args)],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1"},
    )


def test_gltf_tangents(tmp_path, data_dir):
    out = tmp_path / "tangents.glb"
    done = run(
        "gltf_tangents.py", data_dir / "gltf/NormalTangentTest/glTF/NormalTangentTest.gltf", out
    )
    assert done.returncode == 0, done.stderr
    assert "wrote" in done.stdout
    mesh = surfgrad.load_mesh(out)
    assert mesh.tangents.shape == (mesh.vertex_count, 4)
    assert mesh.tangent_uv_set == 0
    assert set(np.unique(mesh.tangents[:, 3])) <= {-1.0, 1.0}
    # One float normalization per tangent: a few ulps.
    np.testing.assert_allclose(np.linalg.norm(mesh.tangents[:, :3], axis=1), 1.0, atol=1e-6)


def test_gltf_tangents_limit_method(tmp_path, data_dir):
    out = tmp_path / "spot.glb"
    done = run(
        "gltf_tangents.py",
        data_dir / "meshes/spot/spot_control_mesh.obj",
        out,
        "--method",
        "limit",
        "--level",
        "1",
    )
    assert done.returncode == 0, done.stderr
    assert surfgrad.load_mesh(out).tangents.shape[1] == 4


def test_gltf_tangents_reports_bad_input(tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0\n")
    done = run("gltf_tangents.py", bad, tmp_path / "out.glb")
    assert done.returncode == 1
    assert done.stderr.startswith("gltf_tangents: error: ") and "line 2" in done.stderr
    assert not (tmp_path / "out.glb").exists()


def test_lean_mips(tmp_path, data_dir):
    out = tmp_path / "lean.exr"
    done = run("lean_mips.py", data_dir / "textures/technicalFabricSmall_normal_256.png", out)
    assert done.returncode == 0, done.stderr
    levels, names, _layout = normalmap.read_mips(out)
    assert len(levels) == 9  # 256^2 ... 1^2
    assert names == ["dx", "dy", "dxx", "dyy", "dxy"]
    # Box filtering keeps the mean slope at every level (mips_test.cpp: 2e-6 of binary32 storage).
    means = np.array([lv.astype(np.float64)[..., :2].mean(axis=(0, 1)) for lv in levels])
    np.testing.assert_allclose(means, np.broadcast_to(means[0], means.shape), atol=2e-6)


@pytest.mark.parametrize("extra", [[], ["--window", "8", "8", "24", "24", "--mode", "linear"]])
def test_svg_feature_bake(tmp_path, data_dir, extra):
    out = tmp_path / "flame.png"
    maps = tmp_path / "flame.exr"
    done = run(
        "svg_feature_bake.py",
        data_dir / "svg/flame.svg",
        out,
        "--size",
        "32",
        "--pixels",
        "96",
        "--maps",
        maps,
        *extra
    )
    assert done.returncode == 0, done.stderr
    image, bits = normalmap.read_image(out)
    assert image.shape[:2] == (96, 96) and bits == "8"
    assert np.ptp(image) > 0  # grooves lit differently from the flat surface
    assert surfgrad.features.load(maps).size == 32


def test_examples_default_to_the_repository_data(tmp_path):
    done = run("lean_mips.py", tmp_path / "default.exr")
    assert done.returncode == 0, done.stderr
    assert "technicalFabricSmall_normal_256.png" in done.stdout
