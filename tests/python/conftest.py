# Shared fixtures and helpers of the Python module's tests (tests/python/test_*.py).
#
# The module under test is `surfgrad` (python/src/*.cpp, API in python/surfgrad/*.pyi), found
# through PYTHONPATH (the build puts the package at <build>/python/surfgrad):
#
#   PYTHONPATH=build-test/python LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe \
#       EGL_PLATFORM=surfaceless /usr/bin/python3 -m pytest tests/python -q
#
# The data folder is $SURFGRAD_DATA_DIR, else the repository's data/ (data/README.md). Tests write
# only below pytest's tmp_path. Tests marked `gl` render through OpenGL 4.5 on EGL (Mesa's
# llvmpipe without a GPU); `-m "not gl"` leaves them out.
#
# The helpers below are the independent side of the comparisons: a glTF accessor reader in plain
# numpy (the oracle for the module's glTF loader, as tinygltf is for tests/mesh/gltf_test.cpp),
# the unit cube cage of tests/mesh/mesh_test_util.h as OBJ text, and angle measures in double.
import json
import os
import sys
from pathlib import Path

import numpy as np
import pytest

# No bytecode caches beside the tests (the repository stays as it was).
sys.dont_write_bytecode = True

# Mesa's software rasterizer through a surfaceless EGL context, as scripts/test runs the C++
# tests; set before the module (and libEGL) is loaded. The environment's values win.
for _key, _value in (
    ("LIBGL_ALWAYS_SOFTWARE", "1"),
    ("GALLIUM_DRIVER", "llvmpipe"),
    ("EGL_PLATFORM", "surfaceless"),
):
    os.environ.setdefault(_key, _value)

REPO_DIR = Path(__file__).resolve().parents[2]


def pytest_configure(config):
    config.addinivalue_line(
        "markers",
        "gl: renders through OpenGL (EGL surfaceless; LIBGL_ALWAYS_SOFTWARE=1 "
        "GALLIUM_DRIVER=llvmpipe EGL_PLATFORM=surfaceless on a machine without a GPU)",
    )


@pytest.fixture(scope="session")
def sg():
    """The module under test (imported once; a failed import fails every test that uses it)."""
    import surfgrad

    return surfgrad


@pytest.fixture(scope="session")
def data_dir():
    env = os.environ.get("SURFGRAD_DATA_DIR")
    path = Path(env) if env else REPO_DIR / "data"
    if not (path / "README.md").is_file():
        pytest.fail(f"data folder not found at {path} (set SURFGRAD_DATA_DIR)")
    return path


# ---------------------------------------------------------------------------
# Small meshes as text

# Unit cube [-1, 1]^3, 6 quads, outward counter-clockwise faces, one UV per corner (a cross
# layout): kCubeObj of tests/mesh/mesh_test_util.h, character for character.
CUBE_OBJ = """v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
f 1/1 4/2 3/3 2/4
f 5/1 6/2 7/3 8/4
f 1/1 2/2 6/3 5/4
f 2/1 3/2 7/3 6/4
f 3/1 4/2 8/3 7/4
f 4/1 1/2 5/3 8/4
"""


def plane_cage_obj(n_x, n_y, chart, offset):
    """An n_x x n_y grid of unit quads in the plane z = 0 over [0, n_x] x [0, n_y] with UVs an
    affine image of (x, y): (s, t) = chart @ (x, y) + offset, one UV per vertex (planeCage of
    tests/mesh/tangents_limit_test.cpp) as OBJ text."""
    lines = []
    for y in range(n_y + 1):
        for x in range(n_x + 1):
            lines.append(f"v {x} {y} 0")
    for y in range(n_y + 1):
        for x in range(n_x + 1):
            s, t = np.asarray(chart, np.float64) @ (x, y) + np.asarray(offset, np.float64)
            lines.append(f"vt {s!r} {t!r}")
    for y in range(n_y):
        for x in range(n_x):
            ids = [y * (n_x + 1) + x, y * (n_x + 1) + x + 1]
            ids += [(y + 1) * (n_x + 1) + x + 1, (y + 1) * (n_x + 1) + x]
            lines.append("f " + " ".join(f"{i + 1}/{i + 1}" for i in ids))
    return "\n".join(lines) + "\n"


def write_text(path, text):
    path = Path(path)
    path.write_text(text)
    return path


# ---------------------------------------------------------------------------
# glTF accessors in plain numpy (the oracle for the loader)

_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
_DTYPES = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}


def gltf_accessor(gltf_path, index):
    """Accessor `index` of a .gltf file with external buffers, as a (count, components) or
    (count,) numpy array of the file's component type (no sparse accessors)."""
    gltf_path = Path(gltf_path)
    doc = json.loads(gltf_path.read_text())
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    buf = doc["buffers"][view["buffer"]]
    raw = (gltf_path.parent / buf["uri"]).read_bytes()
    dtype = np.dtype(_DTYPES[acc["componentType"]])
    comps = _COMPONENTS[acc["type"]]
    stride = view.get("byteStride", dtype.itemsize * comps)
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    out = np.empty((acc["count"], comps), dtype)
    for i in range(acc["count"]):
        row = raw[start + i * stride : start + i * stride + dtype.itemsize * comps]
        out[i] = np.frombuffer(row, dtype)
    return out[:, 0] if comps == 1 else out


def gltf_primitive(gltf_path, mesh=0, primitive=0):
    """POSITION, NORMAL, TEXCOORD_n (flipped to t up: t = 1 - v, surfgrad's convention),
    TANGENT and indices (uint32) of one primitive, read straight from the file."""
    doc = json.loads(Path(gltf_path).read_text())
    prim = doc["meshes"][mesh]["primitives"][primitive]
    out = {}
    for name, index in prim["attributes"].items():
        values = gltf_accessor(gltf_path, index)
        if name.startswith("TEXCOORD_"):
            values = values.astype(np.float32)
            values[:, 1] = np.float32(1.0) - values[:, 1]
        out[name] = values
    out["indices"] = gltf_accessor(gltf_path, prim["indices"]).astype(np.uint32)
    return out


# ---------------------------------------------------------------------------
# Angles


def angle_deg(a, b):
    """Angle in degrees between rows of a and b, in double, accurate near 0 (atan2 of |a x b|
    and a.b; an acos of a float dot would floor at ~0.03 degrees)."""
    a = np.asarray(a, np.float64)[..., :3]
    b = np.asarray(b, np.float64)[..., :3]
    cross = np.linalg.norm(np.cross(a, b), axis=-1)
    return np.degrees(np.arctan2(cross, np.sum(a * b, axis=-1)))


def normalized(v):
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def assert_names(excinfo, *words):
    """The exception's message names every word (the argument, a file, an element); a tuple
    of words is one name spelled in any of those ways ("uv_set" or "UV set 1")."""
    message = str(excinfo.value)
    for word in words:
        spellings = word if isinstance(word, tuple) else (word,)
        assert any(w in message for w in spellings), f"{word!r} not in the message {message!r}"
