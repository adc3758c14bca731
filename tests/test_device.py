import os
import signal
import time

import numpy as np
import pytest
import warp as wp

import warpoptics as wo
from warpoptics.device import elementwise, launch_tiled


@wp.kernel
def _work(offset: int, x: wp.array(dtype=wp.float32), out: wp.array(dtype=wp.float32)):
    i = wp.tid() + offset
    s = float(0.0)
    for j in range(50):
        s += wp.sin(x[i] * float(j + 1))
    out[i] = s


def test_tiled_equals_single_launch(device):
    rng = np.random.default_rng(0)
    n = 10007  # prime: tiles of unequal length
    x = wp.array(rng.random(n).astype(np.float32), device=device)
    single = wp.zeros(n, dtype=wp.float32, device=device)
    wp.launch(_work, dim=n, inputs=[0, x, single], device=device)
    for threads, tile in [(1, None), (2, None), (2, 1), (3, 997), (8, 64)]:
        tiled = wp.zeros(n, dtype=wp.float32, device=device)
        launch_tiled(_work, n, [x, tiled], device=device, threads=threads, tile_size=tile)
        assert np.array_equal(single.numpy(), tiled.numpy()), (threads, tile)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork")
def test_tiled_launch_works_in_a_forked_child():
    """A child forked after the thread pool started has none of its threads: its tiled launches
    must start a pool of their own, not wait forever on the parent's (a fork-context
    multiprocessing pool, a fuzz case)."""
    n = 4001
    x = wp.array(np.linspace(0.0, 1.0, n, dtype=np.float32), device="cpu")
    want = wp.zeros(n, dtype=wp.float32, device="cpu")
    launch_tiled(_work, n, [x, want], device="cpu", threads=2, tile_size=500)  # the pool starts
    pid = os.fork()
    if pid == 0:  # pragma: no cover (the child)
        code = 1
        try:
            got = wp.zeros(n, dtype=wp.float32, device="cpu")
            launch_tiled(_work, n, [x, got], device="cpu", threads=2, tile_size=500)
            code = 0 if np.array_equal(got.numpy(), want.numpy()) else 3
        finally:
            os._exit(code)
    deadline = time.monotonic() + 60.0
    while time.monotonic() < deadline:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0, status
            return
        time.sleep(0.05)
    os.kill(pid, signal.SIGKILL)
    os.waitpid(pid, 0)
    pytest.fail("the forked child's tiled launch did not finish within 60 s")


def test_elementwise_broadcasts(device):
    @wp.kernel
    def add_scale(
        offset: int, a: wp.array(dtype=wp.vec3f), b: wp.array(dtype=wp.float32), out: wp.array(dtype=wp.vec3f)
    ):
        i = wp.tid() + offset
        out[i] = a[i] * b[i]

    a = np.arange(6, dtype=np.float32).reshape(2, 1, 3)
    b = np.array([1.0, 2.0, 3.0], dtype=np.float32)
    (out,) = elementwise(add_scale, [(a, wp.vec3f), (b, wp.float32)], [wp.vec3f], device=device)
    assert out.shape == (2, 3, 3)
    np.testing.assert_allclose(out, a * b[None, :, None])


def test_elementwise_rejects_wrong_vector_length(device):
    @wp.kernel
    def ident(offset: int, a: wp.array(dtype=wp.vec3f), out: wp.array(dtype=wp.vec3f)):
        i = wp.tid() + offset
        out[i] = a[i]

    with pytest.raises(ValueError, match="last axis of length 3"):
        elementwise(ident, [(np.zeros((4, 2)), wp.vec3f)], [wp.vec3f], device=device)


def test_device_choice(monkeypatch):
    monkeypatch.delenv("WARPOPTICS_DEVICE", raising=False)
    assert wo.device.get_device().is_cpu
    monkeypatch.setenv("WARPOPTICS_DEVICE", "cpu")
    assert wo.device.get_device().alias == "cpu"
    with pytest.raises(ValueError, match="not available"):
        wo.device.get_device("cuda:57")


def test_thread_count_env(monkeypatch):
    monkeypatch.setenv("WARPOPTICS_THREADS", "3")
    assert wo.device.cpu_threads() == 3
    monkeypatch.setenv("WARPOPTICS_THREADS", "zero")
    with pytest.raises(ValueError, match="WARPOPTICS_THREADS"):
        wo.device.cpu_threads()
