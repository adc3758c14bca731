"""Camera scenes: ``Scene.load(path)`` reads a TOML file and validates it into frozen configs
(:mod:`.schema`); ``scene.with_overrides({"render.spp": 4, "object.0.diameter": 5.0})`` returns a
modified copy (dotted paths, as the CLI's ``--set`` and the sweep axes use them).
"""

from __future__ import annotations

import copy
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .. import validate as val
from ..errors import InputError
from ..stages.camera import CameraConfig
from ..stages.environment import EnvironmentConfig
from ..stages.surfaces import LampConfig, SurfaceConfig
from .schema import (
    ObjectConfig,
    RenderConfig,
    light_config,
    object_configs,
    render_config,
    surface_config,
    view_config,
)

__all__ = ["Scene", "set_dotted", "parse_value", "parse_set_options"]

_CAMERA_KEYS = set(CameraConfig.__dataclass_fields__) - {"source"}
_TOP_KEYS = {"camera", "render", "light", "object", "surface", "view"}


@dataclass(frozen=True)
class Scene:
    """A validated scene.  ``data`` keeps the raw TOML tables for overrides and sweeps."""

    camera: CameraConfig
    render: RenderConfig
    lights: tuple[EnvironmentConfig, ...]
    objects: tuple[ObjectConfig, ...]
    data: dict = field(repr=False, compare=False, default_factory=dict)
    path: str | None = None
    view: str | None = None  # [view]: polarization view spec for the CLI ("polariscope", "analyzer:30")
    surfaces: tuple[SurfaceConfig, ...] = ()  # [[surface]] (stages/surfaces.py)
    lamps: tuple[LampConfig, ...] = ()  # [[light]] of type directional / area

    @classmethod
    def load(cls, path: str | Path) -> Scene:
        return cls.from_dict(val.toml_file(path), path=str(Path(path)))

    @classmethod
    def from_dict(cls, data: dict, *, path: str | None = None) -> Scene:
        file = path or "<scene>"
        base_dir = Path(path).parent if path else Path.cwd()
        val.check_keys(data, _TOP_KEYS, file=file, prefix="")
        cam_t = data.get("camera", {})
        if not isinstance(cam_t, dict):
            raise InputError("must be a table [camera]", file=file, field="camera")
        val.check_keys(cam_t, _CAMERA_KEYS, file=file, prefix="camera.")
        cam_kw = dict(cam_t)
        for k in ("position", "look_at", "up"):
            if k in cam_kw:
                cam_kw[k] = val.vec3(cam_kw[k], file=file, field=f"camera.{k}")
        for k in ("fov", "view_height", "aperture", "focus_distance"):
            if k in cam_kw:
                val.number(cam_kw[k], file=file, field=f"camera.{k}")
        camera = CameraConfig(**cam_kw, source=file)
        render = render_config(data.get("render", {}), file)
        lights_t = data.get("light", [{"type": "environment", "map": "studio"}])
        if not isinstance(lights_t, list):
            raise InputError("must be an array of tables [[light]]", file=file, field="light")
        all_lights = [light_config(t, i, file, base_dir) for i, t in enumerate(lights_t)]
        lamps = tuple(lt for lt in all_lights if isinstance(lt, LampConfig))
        lights = tuple(lt for lt in all_lights if not isinstance(lt, LampConfig))
        if not lights and lamps:
            lights = (EnvironmentConfig(map="constant", intensity=0.0, source=file),)  # lamps only: black sky
        if len(lights) != 1:
            raise InputError(
                "exactly one environment light is supported", file=file, field="light", value=len(lights)
            )
        surf_t = data.get("surface", [])
        if not isinstance(surf_t, list):
            raise InputError("must be an array of tables [[surface]]", file=file, field="surface")
        surfaces = tuple(surface_config(t, i, file, base_dir) for i, t in enumerate(surf_t))
        objs_t = data.get("object", [])
        if not isinstance(objs_t, list) or (not objs_t and not surfaces):
            raise InputError(
                "a scene needs at least one [[object]] or [[surface]]", file=file, field="object"
            )
        objects = tuple(ob for i, t in enumerate(objs_t) for ob in object_configs(t, i, file, base_dir))
        view = view_config(data["view"], file) if "view" in data else None
        return cls(
            camera=camera,
            render=render,
            lights=lights,
            objects=objects,
            data=copy.deepcopy(data),
            path=path,
            view=view,
            surfaces=surfaces,
            lamps=lamps,
        )

    def with_overrides(self, overrides: dict[str, Any] | None = None, **kw) -> Scene:
        """A copy with dotted-path overrides applied, e.g. ``{"render.spp": 4,
        "object.0.pavilion_angle": 41.0}``; keyword ``width=...`` etc. go to ``[camera]`` for
        width/height and to ``[render]`` otherwise."""
        data = copy.deepcopy(self.data)
        items = dict(overrides or {})
        for k, v in kw.items():
            if v is None:
                continue
            items[f"camera.{k}" if k in _CAMERA_KEYS else f"render.{k}"] = v
        file = self.path or "<scene>"
        for dotted, value in items.items():
            set_dotted(data, dotted, value, file=file)
        return Scene.from_dict(data, path=self.path)


def set_dotted(data: dict, dotted: str, value, *, file: str = "<scene>") -> None:
    """Set ``data[a][b]...`` from ``"a.b.c"``; integers index arrays of tables (``object.0``)."""
    parts = dotted.split(".")
    if len(parts) < 2:
        raise InputError(
            "expected a dotted path like render.spp or object.0.diameter", file=file, field=dotted
        )
    node: Any = data
    for i, part in enumerate(parts[:-1]):
        if isinstance(node, list):
            try:
                node = node[int(part)]
            except (ValueError, IndexError):
                raise InputError(
                    f"no element {part!r} (there are {len(node)})", file=file, field=".".join(parts[: i + 1])
                ) from None
        else:
            if not isinstance(node, dict):
                raise InputError(
                    "is a value, not a table: nothing can be set inside it",
                    file=file,
                    field=".".join(parts[:i]),
                    value=node,
                )
            if part not in node:
                if part in ("object", "light", "surface"):
                    raise InputError("no such array of tables", file=file, field=".".join(parts[: i + 1]))
                node[part] = {}
            if part == "material" and isinstance(node[part], str):
                # a library material named by a string becomes the table it stands for, so
                # that --set object.0.material.kramers_kronig=true reaches below it
                node[part] = {"base": node[part]}
            node = node[part]
    last = parts[-1]
    if isinstance(node, list):
        raise InputError("cannot replace a whole table", file=file, field=dotted)
    if not isinstance(node, dict):
        raise InputError(
            "is a value, not a table: nothing can be set inside it",
            file=file,
            field=".".join(parts[:-1]),
            value=node,
        )
    node[last] = value


def parse_set_options(items) -> dict:
    """The ``--set KEY=VALUE`` options of a command as {dotted path: value} (:func:`parse_value`);
    one-line error for an item without ``=``."""
    out = {}
    for item in items or []:
        if "=" not in item:
            raise InputError("expected KEY=VALUE", field="--set", value=item)
        key, value = item.split("=", 1)
        out[key.strip()] = parse_value(value.strip())
    return out


def parse_value(text: str):
    """A ``--set key=value`` value: TOML syntax (numbers, true/false, "strings", [lists]) or a bare string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text
