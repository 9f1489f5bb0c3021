# The module as a whole (python/surfgrad/__init__.pyi, the conventions at its top): version, the
# InputError type, the submodules, thread counts (0 = all cores, 1..1024) and the GIL: long calls
# release it, so other Python threads run meanwhile.
import re
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import surfgrad
from surfgrad import features, normalmap


def test_version_and_submodules():
    assert re.fullmatch(r"\d+\.\d+\.\d+.*", surfgrad.__version__)
    assert surfgrad.normalmap is normalmap and surfgrad.features is features


def test_input_error_is_a_value_error_with_its_parts(tmp_path):
    assert issubclass(surfgrad.InputError, ValueError)
    path = tmp_path / "bad.obj"
    path.write_text("v 0 0 0\nv 1 0\n")
    with pytest.raises(ValueError) as e:  # catchable as the ValueError it is
        surfgrad.load_cage(path)
    error = e.value
    assert isinstance(error, surfgrad.InputError)
    assert (error.file, error.element) == (str(path), "line 2")
    assert str(error) == f"{error.file}: {error.element}: {error.reason}"


def test_every_threads_argument_takes_the_documented_range():
    # 0 = all cores, 1 = the calling thread, 2..1024 that many.
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    normals = np.tile(np.array([0, 0, 1], np.float32), (3, 1))
    uvs = positions[:, :2].copy()
    corners = np.arange(3, dtype=np.uint32)
    for threads in (0, 1, 2, 1024):
        t = surfgrad.mikktspace(positions, normals, uvs, corners, threads=threads)
        np.testing.assert_array_equal(t[:, 3], [1, 1, 1])
    for threads in (-1, 1025):
        with pytest.raises(ValueError, match="threads"):
            surfgrad.mikktspace(positions, normals, uvs, corners, threads=threads)
    with pytest.raises(TypeError):
        surfgrad.mikktspace(positions, normals, uvs, corners, threads=1.5)


def sine_slopes(size):
    v, u = np.mgrid[0:size, 0:size].astype(np.float64) + 0.5
    h = 5 * np.sin(2 * np.pi * 3 * u / size) * np.cos(2 * np.pi * 2 * v / size)
    return normalmap.from_height(h.astype(np.float32))


def test_long_calls_release_the_gil():
    # While a worker thread is inside one long call, this thread keeps running Python code. If
    # the call held the GIL, this thread would see the call only in the instant before the
    # worker entered it (one 5 ms switch interval at most).
    slopes = sine_slopes(1024)
    state = {"inside": False}
    durations = []

    def worker():
        state["inside"] = True
        start = time.perf_counter()
        normalmap.to_height(slopes, wrap="clamp")
        durations.append(time.perf_counter() - start)
        state["inside"] = False

    thread = threading.Thread(target=worker)
    seen = []
    thread.start()
    while thread.is_alive():
        if state["inside"]:
            seen.append(time.perf_counter())
    thread.join()
    assert durations and durations[0] > 0.02, "the call must last long enough to tell"
    observed = (seen[-1] - seen[0]) if len(seen) > 1 else 0.0
    assert observed > 0.5 * durations[0], (observed, durations[0])


def stub_names(stub):
    """Public top-level functions and classes of a .pyi file, and each class's public members."""
    import ast

    tree = ast.parse(stub.read_text())
    names, members = set(), {}
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)) and not node.name.startswith("_"):
            names.add(node.name)
        if isinstance(node, ast.ClassDef):
            own = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef) and not item.name.startswith("_"):
                    own.add(item.name)
                elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    own.add(item.target.id)
            members[node.name] = own
    return names, members


@pytest.mark.parametrize(
    "stub, module_name",
    [
        ("__init__.pyi", "surfgrad"),
        ("normalmap.pyi", "surfgrad.normalmap"),
        ("features.pyi", "surfgrad.features"),
    ],
)
def test_type_stubs_describe_exactly_the_module(stub, module_name):
    # The stubs are the documented API: every function and class they declare exists (with
    # every member), and the module has nothing public they do not declare.
    import importlib

    module = importlib.import_module(module_name)
    path = Path(surfgrad.__file__).with_name(stub)
    names, members = stub_names(path)
    public = {
        n
        for n in dir(module)
        if not n.startswith("_")
        and (callable(getattr(module, n)) or isinstance(getattr(module, n), type))
        and not isinstance(getattr(module, n), type(surfgrad))
    }
    assert names - public == set(), f"declared in {stub} but missing from {module_name}"
    assert public - names == set(), f"in {module_name} but not declared in {stub}"
    for cls, own in members.items():
        obj = getattr(module, cls)
        missing = {m for m in own if not hasattr(obj, m)}
        assert not missing, f"{module_name}.{cls} lacks {sorted(missing)} declared in {stub}"
