"""Warp initialisation, device choice and CPU tile-parallel launching.

Warp runs one CPU launch on one thread.  Launches issued from several Python threads run at
once (the GIL is released inside ``wp.launch``), so long CPU launches are split into tiles and
issued from a thread pool sized to the cores.  Every kernel launched through this module takes
an ``offset: int`` as its *first* argument and indexes ``i = wp.tid() + offset``; a tile is then
just a launch of a sub-range, and the result is identical to one launch of the whole range.

Environment variables:
``WARPOPTICS_DEVICE``   default device ("cpu" unless set; "cuda:0" for a GPU)
``WARPOPTICS_THREADS``  number of CPU worker threads (default: all cores)

No adjoint code: warpoptics never differentiates through its kernels, so every module that
defines Warp kernels, functions or structs sets ``wp.set_module_options({"enable_backward":
False})`` right after its imports.  It must be the module option: Warp copies
``wp.config.enable_backward`` into a module's options when the module is created (at import),
so setting the config later has no effect on our modules and would change the user's own.
With the backward code a cold CPU start (64x64 ``diamond.toml``) took 64 s (24 s without), and
NVRTC had not finished the render module after 9.5 minutes on an H100 host.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
import threading
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import warp as wp

__all__ = [
    "init",
    "get_device",
    "cpu_threads",
    "launch_tiled",
    "elementwise",
    "device_function",
    "to_warp",
    "load_module",
]

_init_lock = threading.Lock()
_initialized = False


def init() -> None:
    """Initialise Warp once, quietly (no greeting, no per-module load messages)."""
    global _initialized
    if _initialized:
        return
    with _init_lock:
        if _initialized:
            return
        wp.config.log_level = wp.LOG_WARNING
        wp.config.quiet = True
        if (os.environ.get("WARPOPTICS_DEVICE") or "cpu").startswith("cuda"):
            wp.init()
        else:
            with _without_cuda_driver_warning():
                wp.init()
        _initialized = True


@contextlib.contextmanager
def _without_cuda_driver_warning():
    """Drop the line Warp's native code prints to stderr when a machine has no CUDA driver
    ("Could not find or load the NVIDIA CUDA driver"): a CPU user did not ask for CUDA.  Everything
    else written to stderr meanwhile is passed on."""
    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError, AttributeError):  # no real stderr (an embedded interpreter)
        yield
        return
    with tempfile.TemporaryFile() as capture:
        os.dup2(capture.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            capture.seek(0)
            text = capture.read().decode("utf-8", errors="replace")
            rest = [
                ln
                for ln in text.splitlines(True)
                if "Could not find or load the NVIDIA CUDA driver" not in ln
            ]
            if rest:
                sys.stderr.write("".join(rest))


def get_device(device: str | wp.Device | None = None) -> wp.Device:
    """The device to run on: the argument, else ``$WARPOPTICS_DEVICE``, else ``"cpu"``."""
    init()
    if isinstance(device, wp.Device):
        return device
    name = device or os.environ.get("WARPOPTICS_DEVICE") or "cpu"
    try:
        return wp.get_device(name)
    except Exception as exc:  # Warp raises RuntimeError/ValueError depending on the name
        available = ", ".join(d.alias for d in wp.get_devices())
        raise ValueError(f"device {name!r} is not available (available: {available})") from exc


def cpu_threads() -> int:
    """Number of worker threads for tiled CPU launches (``$WARPOPTICS_THREADS`` or all cores)."""
    env = os.environ.get("WARPOPTICS_THREADS")
    if env:
        try:
            n = int(env)
        except ValueError as exc:
            raise ValueError(f"WARPOPTICS_THREADS={env!r} is not an integer") from exc
        if n < 1:
            raise ValueError(f"WARPOPTICS_THREADS={env!r} must be >= 1")
        return n
    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1)


_pools: dict[int, ThreadPoolExecutor] = {}
_pool_lock = threading.Lock()


def _forget_pools_in_child() -> None:
    """A forked child has none of its parent's pool threads: start afresh there (else the first
    tiled launch waits forever on work no thread will take)."""
    global _pool_lock
    _pools.clear()
    _pool_lock = threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pools_in_child)


def _pool(threads: int) -> ThreadPoolExecutor:
    with _pool_lock:
        pool = _pools.get(threads)
        if pool is None:
            pool = ThreadPoolExecutor(max_workers=threads, thread_name_prefix="warpoptics")
            _pools[threads] = pool
        return pool


def launch_tiled(
    kernel,
    dim: int,
    inputs: Sequence,
    *,
    device=None,
    threads: int | None = None,
    tile_size: int | None = None,
) -> None:
    """Launch ``kernel(offset, *inputs)`` over ``range(dim)``, split into tiles on the CPU.

    On a CUDA device this is a single launch.  On the CPU the range is split into tiles of
    ``tile_size`` elements (default: about 16 tiles per thread, so that a costly stone in a few
    tiles does not leave a core idle: 7-10 % less wall time for diamond_fire.toml and
    sapphire.toml in beams on 2 cores) launched from a thread pool of
    ``threads`` workers.  The kernel must index ``i = wp.tid() + offset``; tiles write disjoint
    elements, so the result does not depend on the tiling.
    """
    dev = get_device(device)
    dim = int(dim)
    if dim <= 0:
        return
    if threads is None:
        threads = cpu_threads()
    if not dev.is_cpu or threads <= 1 and tile_size is None:
        wp.launch(kernel, dim=dim, inputs=[0, *inputs], device=dev)
        return
    if tile_size is None:
        tile_size = max(1, -(-dim // (16 * threads)))
    tile_size = max(1, int(tile_size))
    starts = range(0, dim, tile_size)
    if len(starts) == 1 or threads <= 1:
        for s in starts:
            wp.launch(kernel, dim=min(tile_size, dim - s), inputs=[s, *inputs], device=dev)
        return
    # Compile/load the module on the calling thread before fanning out.
    load_module(kernel, dev)
    futures = [
        _pool(threads).submit(wp.launch, kernel, dim=min(tile_size, dim - s), inputs=[s, *inputs], device=dev)
        for s in starts
    ]
    for f in futures:
        f.result()


def load_module(kernel, device=None) -> None:
    """Compile (or load from the cache) the module of ``kernel`` for ``device`` now.

    On the CPU ``wp.launch`` uses block_dim=1, while ``Module.load`` defaults to the module's
    block_dim (256): a different module hash, i.e. a second full compile of every module.  Load
    the variant that launches use.
    """
    dev = get_device(device)
    if dev.is_cpu:
        kernel.module.load(dev, 1)
    else:
        kernel.module.load(dev)


def _np_scalar(dtype):
    return wp.dtype_to_numpy(getattr(dtype, "_wp_scalar_type_", dtype))


def _dtype_length(dtype) -> int:
    return int(getattr(dtype, "_length_", 1))


def to_warp(value, dtype, device=None) -> wp.array:
    """Upload ``value`` as a contiguous 1-D Warp array of ``dtype`` (vector dtypes take the last axis)."""
    dev = get_device(device)
    np_scalar = _np_scalar(dtype)
    arr = np.ascontiguousarray(np.asarray(value, dtype=np_scalar))
    length = _dtype_length(dtype)
    if length > 1:
        arr = arr.reshape(-1, length)
    else:
        arr = arr.reshape(-1)
    return wp.array(arr, dtype=dtype, device=dev)


def device_function(func):
    """Pair a NumPy wrapper with the ``@wp.func`` it launches, as ``wrapper.wp`` (the naming rule
    of README "How it is built": a law is one ``@wp.func`` and one wrapper, ``f`` and ``f.wp``; a
    device function that would share its wrapper's name carries the suffix ``_wp``).  Users'
    own kernels call ``wo.optics.fresnel.wp(cos_i, n1, n2)``; tests check the pairing."""

    def mark(wrapper):
        wrapper.wp = func
        return wrapper

    return mark


def elementwise(
    kernel,
    inputs: Sequence[tuple[object, object]],
    outputs: Sequence[object],
    *,
    extra: Sequence = (),
    device=None,
) -> list[np.ndarray]:
    """Broadcast NumPy inputs, launch an element-wise kernel, return NumPy outputs.

    The shared launcher behind every NumPy wrapper of a ``@wp.func``.  The kernel signature is
    ``kernel(offset: int, in_0, ..., in_k, *extra, out_0, ..., out_m)`` where each ``in_j`` and
    ``out_j`` is a 1-D ``wp.array`` of the given dtype and ``extra`` are passed through unchanged
    (tables, material parameters).

    ``inputs`` is a list of ``(value, dtype)``.  Vector dtypes (``wp.vec3f``...) consume the last
    axis of their value; all leading shapes broadcast together (NumPy rules).  Each output comes
    back with the broadcast shape, plus a trailing axis for vector dtypes.
    """
    dev = get_device(device)
    arrays = []
    shapes = []
    for value, dtype in inputs:
        np_scalar = _np_scalar(dtype)
        a = np.asarray(value, dtype=np_scalar)
        length = _dtype_length(dtype)
        if length > 1:
            if a.ndim == 0 or a.shape[-1] != length:
                raise ValueError(
                    f"expected an array with a last axis of length {length}, got shape {a.shape}"
                )
            shapes.append(a.shape[:-1])
        else:
            shapes.append(a.shape)
        arrays.append((a, dtype, length))
    shape = np.broadcast_shapes(*shapes) if shapes else ()
    n = int(np.prod(shape, dtype=np.int64))
    wp_inputs = []
    for a, dtype, length in arrays:
        target = (*shape, length) if length > 1 else shape
        b = np.broadcast_to(a, target)
        wp_inputs.append(to_warp(b, dtype, dev))
    wp_outputs = [wp.zeros(n, dtype=dtype, device=dev) for dtype in outputs]
    launch_tiled(kernel, n, [*wp_inputs, *extra, *wp_outputs], device=dev)
    result = []
    for arr, dtype in zip(wp_outputs, outputs, strict=True):
        out = arr.numpy()
        length = _dtype_length(dtype)
        result.append(out.reshape((*shape, length) if length > 1 else shape))
    return result
