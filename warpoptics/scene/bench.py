"""Optical-bench scenes: ``BenchScene.load(path)`` validates a TOML file into frozen configs.

A bench scene is a TOML file like a camera scene, with a ``[source]`` beam instead of the camera
and ``[[sensor]]`` screens (every field, with units and defaults: the scene-file reference)::

    [source]
    type = "beam"                 # the only source type of a bench
    kind = "collimated"           # "collimated" | "spot"
    position = [-20.0, 0.0, 0.0]  # mm
    direction = [1.0, 0.0, 0.0]
    width = 0.5                   # beam diameter, mm (collimated)
    divergence = 10.0             # full cone angle, degrees (spot)
    spectrum = "E"                # "E" | "D65" | "A" | [r, g, b] (linear sRGB)
    lines = [589.3]               # optional: only these wavelengths (nm), equal power
    polarization = "unpolarized"  # "linear" (with polarization_angle, deg) | "right" | "left"
    power = 1.0                   # W
    rays = 256                    # beam positions (each traced at every wavelength sample)

    [render]                      # optional: wavelengths, max_depth, split_threshold, ...

    [[sensor]]
    type = "screen"
    name = "wall"
    center = [200.0, 0.0, 0.0]
    normal = [-1.0, 0.0, 0.0]     # toward the light
    up = [0.0, 0.0, 1.0]
    size = [40.0, 20.0]           # mm
    resolution = [400, 200]       # pixels

    [[object]]                    # as in camera scenes, plus an optional coating (front to substrate)
    shape = "plate"
    material = "bk7"
    coating = [{ n = 2.0, k = 0.0, thickness_nm = 300.0 }]   # or { material = "water", thickness_nm = ... }

Objects are validated by the camera scenes' object rules and the one coating schema
(:mod:`.coating`: the same keys and errors); ``coating`` coats every face of its object (the stack
faces the ambient medium).  The pipeline is :mod:`warpoptics.pipelines.bench`.
"""

from __future__ import annotations

import copy
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .. import validate as val
from ..errors import InputError
from ..film.screen import Screen
from ..stages.beam import Beam
from .load import set_dotted
from .schema import TONE_CURVES, ObjectConfig, object_config

__all__ = ["BenchConfig", "BenchScene", "is_bench_scene"]

_SOURCE_KEYS = {
    "type",
    "kind",
    "position",
    "direction",
    "width",
    "divergence",
    "spectrum",
    "lines",
    "polarization",
    "polarization_angle",
    "polarization_x",
    "power",
    "rays",
}
_SENSOR_KEYS = {"type", "name", "center", "normal", "up", "size", "resolution"}
_TOP_KEYS = {"source", "sensor", "render", "object"}


@dataclass(frozen=True)
class BenchConfig:
    """``[render]`` of a bench scene."""

    wavelengths: int = 32
    max_depth: int = 16
    split_threshold: float = 1.0e-4
    max_deposits: int = 24
    seed: int = 0
    ambient_index: float = 1.0
    exposure: float = 0.0
    tone: str = "filmic"
    source: str | None = field(default=None, compare=False)  # scene file, for messages

    def __post_init__(self) -> None:
        file = self.source
        for k, lo, hi in (
            ("wavelengths", 1, 4096),
            ("max_depth", 0, 256),
            ("max_deposits", 1, 1024),
            ("seed", 0, 2**31 - 1),
        ):
            val.integer(getattr(self, k), file=file, field=f"render.{k}", lo=lo, hi=hi)
        for k, flo, fhi in (
            ("split_threshold", 0.0, 1.0),
            ("ambient_index", 1.0, 10.0),
            ("exposure", -40.0, 40.0),
        ):
            val.number(getattr(self, k), file=file, field=f"render.{k}", lo=flo, hi=fhi)
        val.choice(self.tone, TONE_CURVES, file=file, field="render.tone")


def is_bench_scene(path: str | Path) -> bool:
    """True if the TOML file has a ``[source]`` table (an optical-bench scene)."""
    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError):
        return False
    return isinstance(data.get("source"), dict)


def _render_config(t: dict, file) -> BenchConfig:
    if not isinstance(t, dict):
        raise InputError("must be a table [render]", file=file, field="render")
    val.check_keys(t, set(BenchConfig.__dataclass_fields__) - {"source"}, file=file, prefix="render.")
    return BenchConfig(**t, source=file)


def _source(t: dict, file) -> Beam:
    if not isinstance(t, dict):
        raise InputError("must be a table [source]", file=file, field="source")
    val.check_keys(t, _SOURCE_KEYS, file=file, prefix="source.")
    val.choice(t.get("type", "beam"), ("beam",), file=file, field="source.type")
    kw: dict[str, Any] = {}
    if "kind" in t:
        kw["type"] = val.choice(t["kind"], ("collimated", "spot"), file=file, field="source.kind")
    for k in ("position", "direction", "polarization_x"):
        if k in t:
            kw[k] = val.vec3(t[k], file=file, field=f"source.{k}")
    for k, lo in (("width", 0.0), ("divergence", 0.0), ("polarization_angle", -math.inf), ("power", 0.0)):
        if k in t:
            kw[k] = float(val.number(t[k], file=file, field=f"source.{k}", lo=lo))
    if "rays" in t:
        kw["rays"] = int(
            val.number(t["rays"], file=file, field="source.rays", lo=1, hi=1 << 24, integer=True)
        )
    if "spectrum" in t:
        s = t["spectrum"]
        kw["spectrum"] = s if isinstance(s, str) else val.vec3(s, file=file, field="source.spectrum")
    if "lines" in t:
        lines = t["lines"]
        if not isinstance(lines, list) or not lines:
            raise InputError(
                "must be a list of wavelengths in nm", file=file, field="source.lines", value=lines
            )
        kw["lines"] = tuple(
            float(val.number(v, file=file, field="source.lines", lo=360.0, hi=830.0)) for v in lines
        )
    if "polarization" in t:
        kw["polarization"] = val.choice(
            t["polarization"],
            ("unpolarized", "linear", "right", "left"),
            file=file,
            field="source.polarization",
        )
    try:
        return Beam(**kw)
    except InputError as exc:
        raise InputError(
            exc.message, file=file, field=exc.field, value=exc.value, allowed=exc.allowed
        ) from None


def _sensor(t: dict, index: int, file) -> Screen:
    prefix = f"sensor.{index}."
    if not isinstance(t, dict):
        raise InputError("must be a table", file=file, field=f"sensor.{index}")
    val.check_keys(t, _SENSOR_KEYS, file=file, prefix=prefix)
    val.choice(t.get("type", "screen"), ("screen",), file=file, field=prefix + "type")
    kw: dict[str, Any] = {"name": str(t.get("name", f"screen{index}"))}
    for k in ("center", "normal", "up"):
        if k in t:
            kw[k] = val.vec3(t[k], file=file, field=prefix + k)
    for k, integer in (("size", False), ("resolution", True)):
        if k in t:
            v = t[k]
            if not isinstance(v, list) or len(v) != 2:
                raise InputError(
                    "must be a list of two numbers [width, height]", file=file, field=prefix + k, value=v
                )
            kw[k] = tuple(
                val.number(c, file=file, field=prefix + k, lo=0, lo_open=True, integer=integer) for c in v
            )
    try:
        return Screen(**kw)
    except InputError as exc:
        raise InputError(
            exc.message,
            file=file,
            field=prefix + (exc.field or "").split(".")[-1],
            value=exc.value,
            allowed=exc.allowed,
        ) from None


@dataclass(frozen=True)
class BenchScene:
    """A validated bench scene (``data`` keeps the raw TOML for overrides)."""

    source: Beam
    sensors: tuple[Screen, ...]
    objects: tuple[ObjectConfig, ...]
    render: BenchConfig
    data: dict = field(repr=False, compare=False, default_factory=dict)
    path: str | None = None

    @classmethod
    def load(cls, path: str | Path) -> BenchScene:
        return cls.from_dict(val.toml_file(path), path=str(Path(path)))

    @classmethod
    def from_dict(cls, data: dict, *, path: str | None = None) -> BenchScene:
        file = path or "<scene>"
        base_dir = Path(path).parent if path else Path.cwd()
        val.check_keys(data, _TOP_KEYS, file=file, prefix="")
        if "source" not in data:
            raise InputError(
                'a bench scene needs a [source] table (type = "beam")', file=file, field="source"
            )
        source = _source(data["source"], file)
        sensors_t = data.get("sensor", [])
        if isinstance(sensors_t, dict):
            sensors_t = [sensors_t]
        if not isinstance(sensors_t, list) or not sensors_t:
            raise InputError("a bench scene needs at least one [[sensor]] screen", file=file, field="sensor")
        sensors = tuple(_sensor(t, i, file) for i, t in enumerate(sensors_t))
        objs_t = data.get("object", [])
        if not isinstance(objs_t, list):
            raise InputError("must be an array of tables [[object]]", file=file, field="object")
        objects = []
        for i, t in enumerate(objs_t):
            if not isinstance(t, dict):
                raise InputError("must be a table", file=file, field=f"object.{i}")
            ob = object_config(t, i, file, base_dir)
            if ob.film is not None and (ob.film.surface != "solid" or ob.film.profile != "uniform"):
                # the forward tracer coats whole solids with a uniform stack (stages/forward.py)
                bad = "surface" if ob.film.surface != "solid" else "film_thickness"
                raise InputError(
                    "a bench object takes a uniform coating only",
                    file=file,
                    field=f"object.{i}.{bad}",
                    allowed="coating = [...] on a solid",
                )
            objects.append(ob)
        render = _render_config(data.get("render", {}), file)
        return cls(
            source=source,
            sensors=sensors,
            objects=tuple(objects),
            render=render,
            data=copy.deepcopy(data),
            path=path,
        )

    @property
    def coatings(self) -> tuple[tuple | None, ...]:
        """Per object its coating layers ((index spec, thickness_nm), ... front to substrate) or None."""
        return tuple(None if ob.film is None else ob.film.layers for ob in self.objects)

    def with_overrides(self, overrides: dict[str, Any] | None = None) -> BenchScene:
        """A copy with dotted-path overrides, e.g. ``{"source.rays": 64, "object.0.position": [...]}``."""
        data = copy.deepcopy(self.data)
        for dotted, value in (overrides or {}).items():
            parts = dotted.split(".")
            if parts[0] == "sensor" and isinstance(data.get("sensor"), dict):
                data["sensor"] = [data["sensor"]]
            set_dotted(data, dotted, value, file=self.path or "<scene>")
        return BenchScene.from_dict(data, path=self.path)
