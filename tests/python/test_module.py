# The module as a whole (python/surfgrad/__init__.pyi, the conventions at its top): version, the
# InputError type, the submodules, thread counts (0 = all cores, 1..1024) and the GIL: long calls
# release it, so other Python threads run meanwhile.
import re
import threading
import time

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
