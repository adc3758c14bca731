"""The one validation toolkit (warpoptics.validate) and the frozen configs that validate with it in
``__post_init__``: a bad value gives the same one-line InputError (message, field, value, allowed)
whether the config is built in Python (file None) or read from a scene file (file named)."""

from __future__ import annotations

import dataclasses

import pytest

from warpoptics import validate as val
from warpoptics.errors import InputError
from warpoptics.scene import Scene
from warpoptics.scene.bench import BenchConfig, BenchScene
from warpoptics.scene.schema import RenderConfig
from warpoptics.stages.caustics import CausticConfig
from warpoptics.stages.forward import ForwardConfig
from warpoptics.stages.trace import TraceConfig

FILE = "scene.toml"
CAMERA_SCENE = {"object": [{"shape": "cube"}]}
BENCH_SCENE = {"source": {"type": "beam"}, "sensor": [{"type": "screen"}]}


def _same(a: InputError, b: InputError) -> None:
    assert (a.message, a.field, a.value, a.allowed) == (b.message, b.field, b.value, b.allowed)
    assert a.file is None and b.file == FILE
    assert FILE in str(b) and "\n" not in str(b)


@pytest.mark.parametrize(
    ("key", "value", "message", "allowed"),
    [
        ("spp", 0, "out of range", ">= 1 and <= 1048576"),
        ("spp", 2.0, "must be an integer", None),
        ("spectral", "rgb", "unknown value; did you mean 'rgb3'?", "rgb3, uniform, importance, stratified"),
        ("polarization", "no", "must be true or false", None),  # "no" is not False (nor True)
        ("caustics", 1, "must be true or false", None),
        ("exposure", 41.0, "out of range", ">= -40.0 and <= 40.0"),
        ("ambient_index", float("nan"), "must be a finite number", None),
        ("tone", "aces", "unknown value", "filmic, reinhard, clip"),
    ],
)
def test_render_config_python_and_toml_give_the_same_error(key, value, message, allowed):
    with pytest.raises(InputError) as py:
        RenderConfig(**{key: value})
    with pytest.raises(InputError) as toml:
        Scene.from_dict({**CAMERA_SCENE, "render": {key: value}}, path=FILE)
    _same(py.value, toml.value)
    assert py.value.field == f"render.{key}" and py.value.message == message and py.value.allowed == allowed


def test_render_config_replace_validates():
    cfg = RenderConfig()
    with pytest.raises(InputError, match=r"render.max_depth = 300: out of range"):
        dataclasses.replace(cfg, max_depth=300)


def test_adaptive_pilot_rule():
    # pilot_spp 0: a quarter of spp, at least 2; it must be below spp
    assert RenderConfig(spp=32, adaptive=True).pilot == 8
    assert RenderConfig(spp=4, adaptive=True).pilot == 2
    with pytest.raises(InputError, match="render.spp = 2"):
        RenderConfig(spp=2, adaptive=True)


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("max_deposits", 0, "out of range"),
        ("tone", "x", "unknown value"),
        ("seed", True, "must be an integer"),
    ],
)
def test_bench_config_python_and_toml_give_the_same_error(key, value, message):
    with pytest.raises(InputError) as py:
        BenchConfig(**{key: value})
    with pytest.raises(InputError) as toml:
        BenchScene.from_dict({**BENCH_SCENE, "render": {key: value}}, path=FILE)
    _same(py.value, toml.value)
    assert py.value.message == message


@pytest.mark.parametrize(
    ("make", "field"),
    [
        (lambda: TraceConfig(max_depth=-1), "render.max_depth"),
        (lambda: TraceConfig(birefringence="coherent-ish"), "render.birefringence"),
        (lambda: TraceConfig(polarized="yes"), "render.polarization"),
        (lambda: ForwardConfig(split_threshold=2.0), "render.split_threshold"),
        (lambda: CausticConfig(paths=0), "caustics.paths"),
        (lambda: CausticConfig(paths=10, spectral="rgb4"), "caustics.spectral"),
    ],
)
def test_stage_configs_validate_in_post_init(make, field):
    with pytest.raises(InputError) as info:
        make()
    assert info.value.field == field and "\n" not in str(info.value)


def test_toolkit_pieces():
    assert val.number(3, field="x", lo=0, hi=3) == 3
    with pytest.raises(InputError, match=r"x = 0: out of range \(allowed: > 0\)"):
        val.number(0, field="x", lo=0, lo_open=True)
    assert val.boolean(False, field="b") is False
    for bad in ("no", "false", 0, None):
        with pytest.raises(InputError, match="must be true or false"):
            val.boolean(bad, field="b")
    assert val.vec3([1, 2, 3], field="v") == (1.0, 2.0, 3.0)
    with pytest.raises(InputError, match="three numbers"):
        val.vec3([1, 2], field="v")
    with pytest.raises(InputError, match="zero vector"):
        val.unit_vec3([0, 0, 0], field="v")
    assert val.pair([2, 3], field="r", integer=True) == (2, 3)
    with pytest.raises(InputError, match=r"render.sp: unknown key; did you mean 'spp'\?"):
        val.check_keys({"sp": 1}, {"spp", "seed"}, prefix="render.")
    with pytest.raises(InputError, match=r"linear sRGB components >= 0 and <= 1.0"):
        val.rgb([0.5, 1.5, 0.0], field="c", hi=1.0)
