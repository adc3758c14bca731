"""TOML scenes -> validated configuration objects, with errors that name file, field and value.

A scene file has the tables ``[camera]``, ``[render]``, ``[[light]]``, ``[[object]]`` and ``[[surface]]`` (see
DESIGN.md and the files in ``scenes/``).  ``Scene.load(path)`` reads and validates it;
``scene.with_overrides({"render.spp": 4, "object.0.diameter": 5.0})`` returns a modified copy
(dotted paths, as the CLI's ``--set`` and the sweep axes use them).
"""

from __future__ import annotations

import copy
import dataclasses
import difflib
import inspect
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InputError
from .stages.camera import CameraConfig
from .stages.environment import EnvironmentConfig
from .stages.surfaces import BSDF_KINDS, LAMP_KINDS, MIS_MODES, LampConfig, SurfaceConfig

__all__ = ["Scene", "RenderConfig", "ObjectConfig", "SHAPES", "SPECTRAL_MODES"]

SPECTRAL_MODES = ("rgb3", "uniform", "importance", "stratified")
BIREFRINGENCE_MODES = ("exact", "approx")
TONE_CURVES = ("filmic", "reinhard", "clip")
MIS_CHOICES = tuple(MIS_MODES)


def _suggest(key: str, allowed) -> str:
    close = difflib.get_close_matches(key, list(allowed), n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


def _check_keys(table: dict, allowed, *, file, prefix: str) -> None:
    for key in table:
        if key not in allowed:
            raise InputError(
                f"unknown key{_suggest(key, allowed)}", file=file, field=f"{prefix}{key}",
                allowed=", ".join(sorted(allowed)),
            )


def _number(v, *, file, field_name, lo=-math.inf, hi=math.inf, integer=False, lo_open=False):
    ok_type = isinstance(v, int) if integer else isinstance(v, (int, float))
    if isinstance(v, bool) or not ok_type:
        kind = "an integer" if integer else "a number"
        raise InputError(f"must be {kind}", file=file, field=field_name, value=v)
    if not math.isfinite(v):
        raise InputError("must be a finite number", file=file, field=field_name, value=v)
    if v < lo or v > hi or (lo_open and v == lo):
        lo_s = f"> {lo}" if lo_open else f">= {lo}"
        rng = lo_s if hi == math.inf else f"{lo_s} and <= {hi}"
        raise InputError("out of range", file=file, field=field_name, value=v, allowed=rng)
    return v


def _vec3(v, *, file, field_name):
    if not isinstance(v, (list, tuple)) or len(v) != 3:
        raise InputError("must be a list of three numbers [x, y, z]", file=file, field=field_name, value=v)
    return tuple(float(_number(c, file=file, field_name=field_name)) for c in v)


def _choice(v, allowed, *, file, field_name):
    if not isinstance(v, str) or v not in allowed:
        hint = _suggest(v, allowed) if isinstance(v, str) else ""
        raise InputError(f"unknown value{hint}", file=file, field=field_name, value=v, allowed=", ".join(allowed))
    return v


@dataclass(frozen=True)
class RenderConfig:
    """``[render]``: how to render (see DESIGN.md)."""

    spectral: str = "stratified"
    wavelengths: int = 45
    polarization: bool = True
    birefringence: str = "exact"
    max_depth: int = 12
    spp: int = 1
    seed: int = 0
    split_threshold: float = 0.002
    max_splits: int = 64
    rr_threshold: float = 1.0e-4
    exposure: float = 0.0
    tone: str = "filmic"
    ambient_index: float = 1.0
    # surfaces (stages/surfaces.py): surface hits per path leaf, direct-light estimator, and
    # whether stones filter shadow rays (straight-through) or block them
    diffuse_depth: int = 3
    mis: str = "mis"
    stone_shadows: bool = True
    # caustics (stages/caustics.py): a light tracer for lamp -> gem -> surface -> eye; with it on,
    # stones block the camera's shadow rays (stone_shadows is ignored); caustic_paths 0: one light
    # path per pixel sample (width x height x spp)
    caustics: bool = False
    caustic_paths: int = 0
    # adaptive sampling (adaptive.py): a pilot of pilot_spp samples (0: spp / 4, at least 2) in
    # every pixel decides where the rest go; the pass costs about what spp everywhere would
    adaptive: bool = False
    pilot_spp: int = 0


_RENDER_FIELDS = {f for f in RenderConfig.__dataclass_fields__}


def _render_config(table: dict, file) -> RenderConfig:
    _check_keys(table, _RENDER_FIELDS, file=file, prefix="render.")
    t = dict(table)
    f = lambda k: f"render.{k}"  # noqa: E731
    if "spectral" in t:
        _choice(t["spectral"], SPECTRAL_MODES, file=file, field_name=f("spectral"))
    if "birefringence" in t:
        _choice(t["birefringence"], BIREFRINGENCE_MODES, file=file, field_name=f("birefringence"))
    if "tone" in t:
        _choice(t["tone"], TONE_CURVES, file=file, field_name=f("tone"))
    if "mis" in t:
        _choice(t["mis"], MIS_CHOICES, file=file, field_name=f("mis"))
    if "stone_shadows" in t and not isinstance(t["stone_shadows"], bool):
        raise InputError("must be true or false", file=file, field=f("stone_shadows"),
                         value=t["stone_shadows"])
    if "caustics" in t and not isinstance(t["caustics"], bool):  # caustics (stages/caustics.py)
        raise InputError("must be true or false", file=file, field=f("caustics"), value=t["caustics"])
    if "caustic_paths" in t:
        _number(t["caustic_paths"], file=file, field_name=f("caustic_paths"), lo=0, hi=1 << 34, integer=True)
    if "adaptive" in t and not isinstance(t["adaptive"], bool):
        raise InputError("must be true or false", file=file, field=f("adaptive"), value=t["adaptive"])
    if "pilot_spp" in t:
        _number(t["pilot_spp"], file=file, field_name=f("pilot_spp"), lo=0, hi=1 << 20, integer=True)
    if "polarization" in t and not isinstance(t["polarization"], bool):
        raise InputError("must be true or false", file=file, field=f("polarization"), value=t["polarization"])
    for k, lo, hi in (("wavelengths", 1, 4096), ("max_depth", 0, 256), ("max_splits", 0, 4096), ("spp", 1, 1 << 20), ("seed", 0, 2**31 - 1),
                      ("diffuse_depth", 1, 8)):
        if k in t:
            _number(t[k], file=file, field_name=f(k), lo=lo, hi=hi, integer=True)
    for k, lo, hi in (("split_threshold", 0.0, 1.0), ("rr_threshold", 0.0, 1.0), ("exposure", -40.0, 40.0),
                      ("ambient_index", 1.0, 10.0)):
        if k in t:
            _number(t[k], file=file, field_name=f(k), lo=lo, hi=hi)
    cfg = RenderConfig(**t)
    if cfg.adaptive:
        from .adaptive import pilot_spp

        pilot = pilot_spp(cfg.spp, cfg.pilot_spp)
        if not 2 <= pilot < cfg.spp:
            raise InputError(f"adaptive sampling needs a pilot of 2 or more samples and fewer than spp = {cfg.spp}"
                             " (spp >= 3; pilot_spp 0 takes spp / 4)",
                             file=file, field=f("pilot_spp") if cfg.pilot_spp else f("spp"),
                             value=cfg.pilot_spp if cfg.pilot_spp else cfg.spp)
    if cfg.spectral == "rgb3" and "wavelengths" in t and t["wavelengths"] != 3:
        raise InputError("rgb3 uses exactly 3 wavelengths", file=file, field=f("wavelengths"), value=t["wavelengths"])
    return cfg


def _shape_functions() -> dict:
    from .geometry import cuts

    names = ["round_brilliant", "oval", "pear", "marquise", "emerald", "princess", "prism", "plate", "cube",
             "sphere", "step_cut", "wavy_sheet", "rhomb"]
    return {n: getattr(cuts, n) for n in names if hasattr(cuts, n)}


SHAPES = ("round_brilliant", "oval", "pear", "marquise", "emerald", "princess", "prism", "plate", "cube", "sphere",
          "step_cut", "rhomb", "mesh", "gemcad", "wavy_sheet")
_OBJECT_COMMON = {"shape", "material", "position", "rotation", "scale", "optic_axis", "absorption_scale", "path",
                  "name", "instances"}
_OBJECT_COMMON |= {"surface", "coating", "film_thickness", "roughness"}  # films: stages/coated.py


@dataclass(frozen=True)
class ObjectConfig:
    """``[[object]]``: a solid, its material and its placement."""

    shape: str
    material: Any = "diamond"
    params: dict = field(default_factory=dict)  # keyword arguments of the cut function
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation: tuple[float, float, float] = (0.0, 0.0, 0.0)  # degrees about x, then y, then z
    scale: float = 1.0
    optic_axis: tuple[float, float, float] | None = None  # object frame; default the material's
    absorption_scale: float = 1.0
    path: str | None = None
    name: str | None = None
    film: Any = None  # stages.coated.FilmConfig: coating, shell or film surface (None: bare solid)

    def transform(self) -> np.ndarray:
        """4x4 object -> world transform (scale, then rotations x, y, z, then translation)."""
        rx, ry, rz = (math.radians(a) for a in self.rotation)
        cx, sx, cy, sy, cz, sz = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
        mx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
        my = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
        mz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
        m = np.eye(4)
        m[:3, :3] = mz @ my @ mx * self.scale
        m[:3, 3] = self.position
        return m

    def rotation_matrix(self) -> np.ndarray:
        return self.transform()[:3, :3] / self.scale


def _object_config(table: dict, index: int, file, base_dir: Path) -> ObjectConfig:
    prefix = f"object.{index}."
    if not isinstance(table, dict):
        raise InputError("must be a table [[object]]", file=file, field=f"object.{index}", value=table)
    if "shape" not in table:
        raise InputError("missing key", file=file, field=prefix + "shape", allowed=", ".join(SHAPES))
    shape = _choice(table["shape"], SHAPES, file=file, field_name=prefix + "shape")
    params = {k: v for k, v in table.items() if k not in _OBJECT_COMMON}
    if shape in ("mesh", "gemcad"):
        allowed_params = {"diameter"} if shape == "gemcad" else {"repair"}
    else:
        fn = _shape_functions()[shape]
        sig = inspect.signature(fn).parameters
        allowed_params = {p for p, v in sig.items() if v.kind not in (v.VAR_KEYWORD, v.VAR_POSITIONAL)}
        if any(v.kind == v.VAR_KEYWORD for v in sig.values()):
            # the brilliant family forwards its keywords to round_brilliant
            allowed_params |= set(inspect.signature(_shape_functions()["round_brilliant"]).parameters)
    _check_keys(params, allowed_params | _OBJECT_COMMON, file=file, prefix=prefix)
    for k, v in params.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            if not (k == "repair" and isinstance(v, bool)):
                raise InputError("must be a number", file=file, field=prefix + k, value=v)
        elif not math.isfinite(v):
            raise InputError("must be finite", file=file, field=prefix + k, value=v)
    kw: dict[str, Any] = {"shape": shape, "params": params}
    if "material" in table:
        m = table["material"]
        if not isinstance(m, (str, dict)):
            raise InputError("must be a material name or an inline table", file=file, field=prefix + "material",
                             value=m)
        kw["material"] = m
    for k in ("position", "rotation"):
        if k in table:
            kw[k] = _vec3(table[k], file=file, field_name=prefix + k)
    if "optic_axis" in table:
        ax = _vec3(table["optic_axis"], file=file, field_name=prefix + "optic_axis")
        if np.linalg.norm(ax) == 0:
            raise InputError("the optic axis must not be zero", file=file, field=prefix + "optic_axis", value=list(ax))
        kw["optic_axis"] = ax
    if "scale" in table:
        kw["scale"] = float(_number(table["scale"], file=file, field_name=prefix + "scale", lo=1.0e-4, hi=1.0e4))
    if "absorption_scale" in table:
        kw["absorption_scale"] = float(
            _number(table["absorption_scale"], file=file, field_name=prefix + "absorption_scale", lo=0.0)
        )
    if shape in ("mesh", "gemcad"):
        if "path" not in table or not isinstance(table["path"], str):
            raise InputError("a mesh object needs path = \"file\"", file=file, field=prefix + "path")
        p = Path(table["path"])
        if not p.is_absolute():
            p = base_dir / p
        if not p.is_file():
            raise InputError("file not found", file=file, field=prefix + "path", value=table["path"])
        kw["path"] = str(p)
    if "name" in table:
        kw["name"] = str(table["name"])
    from .stages.coated import film_config  # films: coating / shell / film surface keys

    kw["film"] = film_config(table, index, file)
    return ObjectConfig(**kw)


def _object_configs(table: dict, index: int, file, base_dir: Path) -> list[ObjectConfig]:
    """One ``[[object]]`` table: one object, or one per entry of ``instances = [[x, y, z], ...]``
    (positions in mm that replace ``position``; the instances share one mesh)."""
    ob = _object_config(table, index, file, base_dir)
    if "instances" not in table:
        return [ob]
    inst = table["instances"]
    field_name = f"object.{index}.instances"
    if not isinstance(inst, list) or not inst:
        raise InputError("must be a non-empty list of positions [[x, y, z], ...]", file=file,
                         field=field_name, value=inst)
    return [dataclasses.replace(ob, position=_vec3(p, file=file, field_name=f"{field_name}.{j}"))
            for j, p in enumerate(inst)]


_LIGHT_KEYS = {"type", "map", "intensity", "tint", "rotation", "polarizer"}


def _light_config(
    table: dict, index: int, file, base_dir: Path | None = None
) -> EnvironmentConfig | LampConfig:
    prefix = f"light.{index}."
    if not isinstance(table, dict):
        raise InputError("must be a table [[light]]", file=file, field=f"light.{index}", value=table)
    ltype = table.get("type", "environment")
    _choice(ltype, ("environment", "constant", *LAMP_KINDS), file=file, field_name=prefix + "type")
    if ltype in LAMP_KINDS:
        return _lamp_config(table, ltype, prefix, file)
    _check_keys(table, _LIGHT_KEYS, file=file, prefix=prefix)
    kw: dict[str, Any] = {"source": file}
    if ltype == "constant":
        kw["map"] = "constant"
    elif "map" in table:
        m = table["map"]
        if not isinstance(m, str):
            raise InputError("must be a map name or a file path", file=file, field=prefix + "map", value=m)
        if Path(m).suffix and not Path(m).is_absolute() and base_dir is not None:
            m = str(base_dir / m)  # a map file is found next to the scene file, like mesh paths
        kw["map"] = m
    if "intensity" in table:
        kw["intensity"] = float(_number(table["intensity"], file=file, field_name=prefix + "intensity", lo=0.0,
                                          hi=1.0e12))
    if "tint" in table:
        kw["tint"] = _vec3(table["tint"], file=file, field_name=prefix + "tint")
        if min(kw["tint"]) < 0:
            raise InputError("must be >= 0", file=file, field=prefix + "tint", value=list(kw["tint"]))
    if "rotation" in table:
        kw["rotation_deg"] = float(_number(table["rotation"], file=file, field_name=prefix + "rotation"))
    if "polarizer" in table and table["polarizer"] != "none":
        # an ideal linear polarizer in front of the light (polariscope), degrees on the image
        kw["polarizer"] = float(_number(table["polarizer"], file=file, field_name=prefix + "polarizer"))
    return EnvironmentConfig(**kw)


_VIEW_KEYS = {"kind", "angle"}


def _view_config(table, file) -> str | None:
    """``[view]``: the polarization view the CLI applies (``warpoptics.views``), as a spec string."""
    from .views import parse_view

    if not isinstance(table, dict):
        raise InputError("must be a table [view]", file=file, field="view", value=table)
    _check_keys(table, _VIEW_KEYS, file=file, prefix="view.")
    kind = table.get("kind", "none")
    angle = table.get("angle")
    if angle is not None:
        angle = float(_number(angle, file=file, field_name="view.angle"))
    try:
        k, arg = parse_view(kind, angle, field="view.kind")
    except InputError as exc:
        raise InputError(exc.message, file=file, field=exc.field, value=exc.value,
                         allowed=exc.allowed) from None
    return None if k == "none" else (k if arg is None else f"{k}:{arg}")


_LAMP_KEYS = {
    "directional": {"type", "direction", "irradiance", "tint", "angular_radius"},
    "area": {"type", "center", "normal", "up", "size", "radiance", "tint", "double_sided"},
    "spot": {"type", "center", "direction", "intensity", "tint", "cone_angle", "blend"},
}


def _unit(v, *, file, field_name):
    x = _vec3(v, file=file, field_name=field_name)
    if np.linalg.norm(x) == 0:
        raise InputError("must not be the zero vector", file=file, field=field_name, value=list(x))
    return x


def _size2(v, *, file, field_name, hi=1.0e6):
    if not isinstance(v, (list, tuple)) or len(v) != 2:
        raise InputError("must be a list of two numbers [width, height] in mm", file=file, field=field_name,
                         value=v)
    return tuple(float(_number(c, file=file, field_name=field_name, lo=0.0, hi=hi, lo_open=True)) for c in v)


def _rgb(v, *, file, field_name, hi=math.inf):
    x = _vec3(v, file=file, field_name=field_name)
    if min(x) < 0 or max(x) > hi:
        raise InputError("out of range", file=file, field=field_name, value=list(x),
                         allowed=f"linear sRGB components >= 0 and <= {hi}" if hi != math.inf else ">= 0")
    return x


def _lamp_config(table: dict, ltype: str, prefix: str, file) -> LampConfig:
    """``[[light]] type = "directional"`` or ``"area"`` (stages/surfaces.py)."""
    _check_keys(table, _LAMP_KEYS[ltype], file=file, prefix=prefix)
    kw: dict[str, Any] = {"type": ltype, "source": file}
    for k in ("direction", "normal", "up"):
        if k in table:
            kw[k] = _unit(table[k], file=file, field_name=prefix + k)
    if "center" in table:
        kw["center"] = _vec3(table["center"], file=file, field_name=prefix + "center")
    if "size" in table:
        kw["size"] = _size2(table["size"], file=file, field_name=prefix + "size")
    for k in ("irradiance", "radiance", "intensity"):
        if k in table:
            kw[k] = float(_number(table[k], file=file, field_name=prefix + k, lo=0.0, hi=1.0e12))
    if "tint" in table:
        kw["tint"] = _rgb(table["tint"], file=file, field_name=prefix + "tint")
    if "angular_radius" in table:
        kw["angular_radius"] = float(_number(table["angular_radius"], file=file,
                                             field_name=prefix + "angular_radius", lo=0.0, hi=45.0))
    for k in ("cone_angle", "blend"):
        if k in table:
            kw[k] = float(_number(table[k], file=file, field_name=prefix + k, lo=0.0, hi=90.0))
    if "double_sided" in table:
        if not isinstance(table["double_sided"], bool):
            raise InputError("must be true or false", file=file, field=prefix + "double_sided",
                             value=table["double_sided"])
        kw["double_sided"] = table["double_sided"]
    if "up" in kw and "normal" in kw and np.linalg.norm(np.cross(kw["up"], kw["normal"])) < 1e-9:
        raise InputError("is parallel to the normal", file=file, field=prefix + "up", value=list(kw["up"]))
    return LampConfig(**kw)


SURFACE_TYPES = ("plane", "rectangle")
_SURFACE_KEYS = {
    "plane": {"type", "height", "size", "bsdf", "roughness", "ior", "color", "checker", "square", "texture",
              "tile"},
    "rectangle": {"type", "center", "normal", "up", "size", "bsdf", "roughness", "ior", "color", "checker",
                  "square", "texture", "tile"},
}


def _surface_config(table: dict, index: int, file, base_dir: Path) -> SurfaceConfig:
    """``[[surface]]``: ``type = "plane"`` (``height`` mm, ``size`` mm) or ``"rectangle"``
    (``center``, ``normal``, ``up``, ``size = [w, h]``); ``bsdf = "diffuse" | "glossy"``
    (``roughness``, coat ``ior``); albedo ``color = [r, g, b]``, or ``checker = [[r, g, b], [r, g, b]]``
    with ``square`` mm, or ``texture = "file.png"`` with ``tile = [w, h]`` mm."""
    prefix = f"surface.{index}."
    if not isinstance(table, dict):
        raise InputError("must be a table [[surface]]", file=file, field=f"surface.{index}", value=table)
    stype = _choice(table.get("type", "plane"), SURFACE_TYPES, file=file, field_name=prefix + "type")
    _check_keys(table, _SURFACE_KEYS[stype], file=file, prefix=prefix)
    kw: dict[str, Any] = {}
    if stype == "plane":
        h = float(_number(table.get("height", 0.0), file=file, field_name=prefix + "height"))
        s = float(_number(table.get("size", 1000.0), file=file, field_name=prefix + "size", lo=0.0, hi=1.0e6,
                          lo_open=True))
        kw.update(center=(0.0, 0.0, h), normal=(0.0, 0.0, 1.0), size=(s, s), up=(0.0, 1.0, 0.0))
    else:
        for k in ("normal", "up"):
            if k in table:
                kw[k] = _unit(table[k], file=file, field_name=prefix + k)
        if "center" in table:
            kw["center"] = _vec3(table["center"], file=file, field_name=prefix + "center")
        if "size" in table:
            kw["size"] = _size2(table["size"], file=file, field_name=prefix + "size")
        if "up" in kw and np.linalg.norm(np.cross(kw["up"], kw.get("normal", (0.0, 0.0, 1.0)))) < 1e-9:
            raise InputError("is parallel to the normal", file=file, field=prefix + "up",
                             value=list(kw["up"]))
    if "bsdf" in table:
        kw["bsdf"] = _choice(table["bsdf"], tuple(BSDF_KINDS), file=file, field_name=prefix + "bsdf")
    if "roughness" in table:
        kw["roughness"] = float(_number(table["roughness"], file=file, field_name=prefix + "roughness",
                                        lo=0.01, hi=1.0))
    if "ior" in table:
        kw["ior"] = float(_number(table["ior"], file=file, field_name=prefix + "ior", lo=1.0, hi=4.0))
    albedos = [k for k in ("color", "checker", "texture") if k in table]
    if len(albedos) > 1:
        raise InputError("give one albedo: color, checker or texture", file=file, field=prefix + albedos[1],
                         allowed="one of color, checker, texture")
    if "color" in table:
        kw["color"] = _rgb(table["color"], file=file, field_name=prefix + "color", hi=1.0)
    if "checker" in table:
        c = table["checker"]
        if not isinstance(c, list) or len(c) != 2:
            raise InputError("must be two colours [[r, g, b], [r, g, b]]", file=file,
                             field=prefix + "checker", value=c)
        kw["albedo"] = "checker"
        kw["color"] = _rgb(c[0], file=file, field_name=prefix + "checker.0", hi=1.0)
        kw["color2"] = _rgb(c[1], file=file, field_name=prefix + "checker.1", hi=1.0)
    elif "square" in table:
        raise InputError("square needs checker = [[r, g, b], [r, g, b]]", file=file, field=prefix + "square")
    if "square" in table:
        kw["square"] = float(_number(table["square"], file=file, field_name=prefix + "square", lo=0.0,
                                     hi=1.0e6, lo_open=True))
    if "texture" in table:
        t = table["texture"]
        if not isinstance(t, str):
            raise InputError("must be an image file path", file=file, field=prefix + "texture", value=t)
        p = Path(t)
        if not p.is_absolute():
            p = base_dir / p
        if not p.is_file():
            raise InputError("texture file not found", file=file, field=prefix + "texture", value=t)
        kw["albedo"] = "texture"
        kw["texture"] = str(p)
    if "tile" in table:
        if "texture" not in table:
            raise InputError("tile needs texture = \"file\"", file=file, field=prefix + "tile")
        kw["tile"] = _size2(table["tile"], file=file, field_name=prefix + "tile")
    return SurfaceConfig(**kw)


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
        p = Path(path)
        if not p.is_file():
            raise InputError("scene file not found", file=str(p))
        try:
            data = tomllib.loads(p.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"not valid TOML ({exc})", file=str(p)) from None
        except UnicodeDecodeError:
            raise InputError("not a UTF-8 text file", file=str(p)) from None
        return cls.from_dict(data, path=str(p))

    @classmethod
    def from_dict(cls, data: dict, *, path: str | None = None) -> Scene:
        file = path or "<scene>"
        base_dir = Path(path).parent if path else Path.cwd()
        _check_keys(data, _TOP_KEYS, file=file, prefix="")
        cam_t = data.get("camera", {})
        if not isinstance(cam_t, dict):
            raise InputError("must be a table [camera]", file=file, field="camera")
        _check_keys(cam_t, _CAMERA_KEYS, file=file, prefix="camera.")
        cam_kw = dict(cam_t)
        for k in ("position", "look_at", "up"):
            if k in cam_kw:
                cam_kw[k] = _vec3(cam_kw[k], file=file, field_name=f"camera.{k}")
        for k in ("fov", "view_height", "aperture", "focus_distance"):
            if k in cam_kw:
                _number(cam_kw[k], file=file, field_name=f"camera.{k}")
        camera = CameraConfig(**cam_kw, source=file)
        render = _render_config(data.get("render", {}), file)
        lights_t = data.get("light", [{"type": "environment", "map": "studio"}])
        if not isinstance(lights_t, list):
            raise InputError("must be an array of tables [[light]]", file=file, field="light")
        all_lights = [_light_config(t, i, file, base_dir) for i, t in enumerate(lights_t)]
        lamps = tuple(lt for lt in all_lights if isinstance(lt, LampConfig))
        lights = tuple(lt for lt in all_lights if not isinstance(lt, LampConfig))
        if not lights and lamps:
            lights = (EnvironmentConfig(map="constant", intensity=0.0, source=file),)  # lamps only: black sky
        if len(lights) != 1:
            raise InputError("exactly one environment light is supported", file=file, field="light",
                             value=len(lights))
        surf_t = data.get("surface", [])
        if not isinstance(surf_t, list):
            raise InputError("must be an array of tables [[surface]]", file=file, field="surface")
        surfaces = tuple(_surface_config(t, i, file, base_dir) for i, t in enumerate(surf_t))
        objs_t = data.get("object", [])
        if not isinstance(objs_t, list) or (not objs_t and not surfaces):
            raise InputError("a scene needs at least one [[object]] or [[surface]]", file=file,
                             field="object")
        objects = tuple(ob for i, t in enumerate(objs_t) for ob in _object_configs(t, i, file, base_dir))
        view = _view_config(data["view"], file) if "view" in data else None
        return cls(camera=camera, render=render, lights=lights, objects=objects, data=copy.deepcopy(data),
                   path=path, view=view, surfaces=surfaces, lamps=lamps)

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
        raise InputError("expected a dotted path like render.spp or object.0.diameter", file=file, field=dotted)
    node: Any = data
    for i, part in enumerate(parts[:-1]):
        if isinstance(node, list):
            try:
                node = node[int(part)]
            except (ValueError, IndexError):
                raise InputError(f"no element {part!r} (there are {len(node)})", file=file,
                                 field=".".join(parts[: i + 1])) from None
        else:
            if part not in node:
                if part in ("object", "light", "surface"):
                    raise InputError("no such array of tables", file=file, field=".".join(parts[: i + 1]))
                node[part] = {}
            node = node[part]
    last = parts[-1]
    if isinstance(node, list):
        raise InputError("cannot replace a whole table", file=file, field=dotted)
    node[last] = value


def parse_value(text: str):
    """A ``--set key=value`` value: TOML syntax (numbers, true/false, "strings", [lists]) or a bare string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text
