"""Shared by the input-error tests (moved from test_reliability.py): a tiny valid scene, a way to
break one field of it, and the check that a broken scene is refused with one clear line."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest

from warpoptics.errors import InputError
from warpoptics.pipelines.render import Renderer
from warpoptics.scene import Scene

ROOT = Path(__file__).resolve().parents[1]
FILE = "/scenes/x.toml"  # the file name every API error must name

BASE = {
    "camera": {
        "position": [0.0, -22.0, 30.0],
        "look_at": [0.0, 0.0, -0.3],
        "fov": 15.0,
        "width": 4,
        "height": 4,
    },
    "render": {"spectral": "stratified", "wavelengths": 3, "max_depth": 6},
    "light": [{"type": "environment", "map": "studio"}],
    "object": [{"shape": "round_brilliant", "diameter": 6.5, "material": "diamond"}],
}
DEL = object()


def mod(**mods) -> dict:
    """BASE with ``a__b__0__c=value`` replacements (``DEL`` deletes the key)."""
    d = copy.deepcopy(BASE)
    for k, v in mods.items():
        parts = k.split("__")
        node = d
        for p in parts[:-1]:
            node = node[int(p)] if isinstance(node, list) else node.setdefault(p, {})
        last = int(parts[-1]) if isinstance(node, list) else parts[-1]
        if v is DEL:
            del node[last]
        else:
            node[last] = v
    return d


def assert_clear_scene_error(data, match, field, value):
    """Loading ``data`` as a scene raises an InputError matching ``match`` on one line."""
    with pytest.raises(InputError, match=match) as info:
        Renderer(Scene.from_dict(data, path=FILE))
    msg = str(info.value)
    # the message names the file (the scene, or the mesh file at fault), the field and the value
    assert FILE in msg or (field.endswith((".ply", ".obj", ".asc")) and field in msg), msg
    assert field in msg, msg
    if value is not None:
        assert value in msg, msg
    assert "\n" not in msg
