"""Renders too large for memory are refused before anything is allocated."""

from __future__ import annotations

import importlib

import pytest
from _helpers import BASE, FILE

from warpoptics.errors import InputError
from warpoptics.pipelines.render import Renderer, check_render_memory, estimate_render_bytes
from warpoptics.scene import Scene


def test_render_too_large_for_memory_is_refused(monkeypatch):
    need = estimate_render_bytes(100_000, 100_000)
    assert need > 100_000 * 100_000 * 72  # at least the float64 film
    # film and image with per-channel Stokes (polarization views): 564 bytes per pixel
    with pytest.raises(InputError, match=r"about 5252\.7 GiB") as info:
        check_render_memory(100_000, 100_000, available=8 * 2**30, file=FILE)
    assert "100000x100000" in str(info.value) and FILE in str(info.value)
    assert check_render_memory(64, 64, available=8 * 2**30) == estimate_render_bytes(64, 64)
    # the renderer checks before it allocates anything
    wr = importlib.import_module("warpoptics.pipelines.render")
    monkeypatch.setattr(wr, "available_memory_bytes", lambda: 1000)
    with pytest.raises(InputError, match="GiB"):
        Renderer(Scene.from_dict(BASE, path=FILE))
