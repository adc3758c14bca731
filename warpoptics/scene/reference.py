"""The scene-file reference, read from the validators: every table's keys, ranges and defaults.

The keys of a table are what its validator accepts (it lists them when it refuses an unknown
key), the range of a number or a choice is what the validator says when it refuses a value far
out of range, and a default is the value of the validated config when the key is left out.  Only
what the code cannot say lives here: each key's type, unit and one-line description
(:data:`FIELDS`).  :func:`tables` joins the two; ``docs/_ext/scene_reference.py`` renders it
and ``tests/test_scene_reference.py`` fails when a key has no description or no unit.
"""

from __future__ import annotations

import contextlib
import copy
import inspect
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any
from unittest import mock

import numpy as np
import warp as wp

from ..errors import InputError
from ..geometry import cuts
from ..materials import spec as material_spec
from . import microscope as microscope_scene
from .bench import BenchScene
from .load import Scene
from .microscope import MicroscopeScene

__all__ = ["FieldDoc", "FieldRow", "Table", "FIELDS", "CUT_PARAMETERS", "tables", "undocumented", "stale"]

#: the type names a :class:`FieldDoc` may give (the probes a type gets: numbers are tried far out
#: of range on both sides, choices with a value no table accepts)
TYPES = ("number", "integer", "boolean", "choice", "string", "vector", "list", "table", "path")
#: the unit of a dimensionless value
NO_UNIT = "-"
_UNKNOWN_KEY = "zz_not_a_key"
_NO_DEFAULT = object()


@dataclass(frozen=True)
class FieldDoc:
    """What the code cannot say about a key: its ``type`` (one of :data:`TYPES`), ``unit``
    (:data:`NO_UNIT` when dimensionless) and ``description``; ``default`` reads the key's default
    from the validated config when the config names it otherwise (None: the attribute of the key's
    name; a string: another attribute; a callable: applied to the config)."""

    type: str
    unit: str
    description: str
    default: str | Callable[[Any], Any] | None = None
    #: other keys the table needs for the validator to reach this key's range (probing only)
    needs: tuple[tuple[str, Any], ...] = ()


@dataclass(frozen=True)
class FieldRow:
    """One key of the reference: ``range`` and ``default`` as text (``""`` where there is none)."""

    key: str
    type: str
    unit: str
    range: str
    default: str
    description: str


@dataclass(frozen=True)
class Table:
    """One table of a scene file, as the reference shows it."""

    name: str
    scene_kind: str
    intro: str
    rows: tuple[FieldRow, ...]


@dataclass(frozen=True)
class _Spec:
    name: str  # as written in a scene file: "[render]", "[[light]] type = \"area\""
    scene_kind: str  # "camera", "bench", "microscope"
    intro: str
    doc: str  # the key of FIELDS
    load: Callable[[dict], Any]  # validates a whole scene (or the table itself)
    base: dict  # the smallest valid input
    path: tuple  # where the table sits in ``base``
    config: Callable[[Any], Any] | None  # the validated config holding the defaults
    exclude: frozenset = frozenset()  # keys documented in another table


_SPHERE = {"shape": "sphere"}


def _camera_scene(**tables) -> dict:
    return {"object": [dict(_SPHERE)], **tables}


def _bench_scene(**tables) -> dict:
    data = {"source": {"type": "beam"}, "sensor": [{"type": "screen"}], "object": [dict(_SPHERE)]}
    data.update(tables)
    return data


def _microscope_scene(**tables) -> dict:
    data = {"microscope": {}, "sample": {"material": "quartz", "thickness_mm": 0.03}}
    data.update(tables)
    return data


def _load_camera(data: dict):
    return Scene.from_dict(data, path=str(Path.cwd() / "scene.toml"))


def _load_bench(data: dict):
    return BenchScene.from_dict(data, path=str(Path.cwd() / "bench.toml"))


def _load_microscope(data: dict):
    return MicroscopeScene.from_dict(data, path=str(Path.cwd() / "microscope.toml"))


class _ProbeBase:
    """What a library name resolves to while an inline material is only validated: building a
    real material evaluates its dispersion in a kernel, and the checks of the keys after
    ``base`` do not need it."""

    fluorescence = None
    name = "probe"


def _inline_material(data: dict):
    """Validate an inline ``material`` table (``materials.spec``) without building it: the
    library lookup of ``base`` returns a stand-in (see :func:`_no_kernels`), and whatever comes
    after the checks (building the spectra, which the stand-in cannot do) counts as accepted."""
    try:
        return material_spec.material_from_spec(data)
    except (InputError, _Accepted):
        raise
    except Exception as exc:  # noqa: BLE001 - past the checks, into the building
        raise _Accepted from exc


def _film(data: dict):
    return _load_camera(data).objects[0].film


def _specs() -> list[_Spec]:
    layer = {"n": 1.5, "thickness_nm": 100.0}
    specs = [
        _Spec(
            "[camera]",
            "camera",
            "The camera: where it is, what it looks at, the image size.",
            "camera",
            _load_camera,
            _camera_scene(camera={}),
            ("camera",),
            lambda s: s.camera,
        ),
        _Spec(
            "[render]",
            "camera",
            "How to render: spectral and polarization modes, sampling, tone.",
            "render",
            _load_camera,
            _camera_scene(render={}),
            ("render",),
            lambda s: s.render,
        ),
        _Spec(
            '[[light]] type = "environment" | "constant"',
            "camera",
            "The one environment light: a built-in map, an image file or a constant sky.",
            "light",
            _load_camera,
            _camera_scene(light=[{"type": "environment"}]),
            ("light", 0),
            lambda s: s.lights[0],
        ),
    ]
    for kind, intro in (
        ("directional", "A distant lamp (the sun): parallel light of a given irradiance."),
        ("area", "A rectangular light box of a given radiance."),
        ("spot", "A point lamp with a cone."),
    ):
        specs.append(
            _Spec(
                f'[[light]] type = "{kind}"',
                "camera",
                intro,
                f"lamp.{kind}",
                _load_camera,
                _camera_scene(light=[{"type": kind}]),
                ("light", 0),
                lambda s: s.lamps[0],
            )
        )
    specs += [
        _Spec(
            "[[light]] spectrum = { ... }",
            "camera",
            "A measured light spectrum given inline (any light's ``spectrum`` key).",
            "light.spectrum",
            _load_camera,
            _camera_scene(
                light=[
                    {
                        "type": "environment",
                        "spectrum": {"wavelength_nm": [400.0, 700.0], "values": [1.0, 1.0]},
                    }
                ]
            ),
            ("light", 0, "spectrum"),
            None,
        ),
        _Spec(
            "[[object]]",
            "camera",
            "A solid: its shape, material and placement. The shape's own parameters follow below.",
            "object",
            _load_camera,
            _camera_scene(object=[{"shape": "mesh", "path": __file__}]),
            ("object", 0),
            lambda s: s.objects[0],
            frozenset({"repair"}),
        ),
        _Spec(
            "[[object]] coating = [{ ... }, ...]",
            "camera",
            "One thin-film layer of an object's coating, listed from the front to the substrate.",
            "object.coating",
            _film,
            _camera_scene(object=[dict(_SPHERE, coating=[dict(layer)])]),
            ("object", 0, "coating", 0),
            None,
        ),
    ]
    for profile in ("uniform", "gravity", "oil_drop"):
        specs.append(
            _Spec(
                f'[[object]] film_thickness = {{ profile = "{profile}" }}',
                "camera",
                "How a coating's thickness varies over the surface.",
                f"object.film_thickness.{profile}",
                _film,
                _camera_scene(
                    object=[dict(_SPHERE, coating=[dict(layer)], film_thickness={"profile": profile})]
                ),
                ("object", 0, "film_thickness"),
                lambda f: dict(f.profile_params, profile=f.profile),
            )
        )
    specs += [
        _Spec(
            "[[object]] material = { ... }",
            "camera",
            "An inline material: a library stone or a Cauchy index, with absorption added.",
            "object.material",
            _inline_material,
            {"base": "diamond"},
            (),
            None,
        ),
        _Spec(
            "[[object]] material.bands = [{ ... }, ...]",
            "camera",
            "One absorption band of an inline material.",
            "object.material.bands",
            _inline_material,
            {"base": "diamond", "bands": [{"center_nm": 550.0, "width_nm": 40.0, "peak_alpha_per_mm": 0.1}]},
            ("bands", 0),
            None,
        ),
        _Spec(
            "[[object]] material.fluorescence = { ... }",
            "camera",
            "A luminescent centre added to an inline material.",
            "object.material.fluorescence",
            _inline_material,
            {"base": "diamond", "fluorescence": {"centre": "n3"}},
            ("fluorescence",),
            None,
        ),
    ]
    zones = {
        "planar": {"normal": [0.0, 0.0, 1.0], "offsets": [0.0], "absorption": ["none", "none"]},
        "halves": {"normal": [0.0, 0.0, 1.0], "absorption": ["none", "none"]},
        "core_rim": {"axis": [0.0, 0.0, 1.0], "radii": [1.0], "absorption": ["none", "none"]},
    }
    for kind, zone in zones.items():
        specs.append(
            _Spec(
                f'[[object]] zoning = {{ type = "{kind}" }}',
                "camera",
                "Colour zones inside the stone (docs/guide/zoning.md): the host's indices"
                " everywhere, one absorption per zone.",
                f"object.zoning.{kind}",
                _load_camera,
                _camera_scene(object=[dict(_SPHERE, zoning=dict(zone, type=kind))]),
                ("object", 0, "zoning"),
                lambda s: {"origin": s.objects[0].zoning.origin, "offset": s.objects[0].zoning.bounds[0]},
            )
        )
    for kind in ("plane", "rectangle"):
        specs.append(
            _Spec(
                f'[[surface]] type = "{kind}"',
                "camera",
                "An opaque surface (a table, a backdrop): diffuse or glossy, plain, checked or textured.",
                f"surface.{kind}",
                _load_camera,
                _camera_scene(surface=[{"type": kind}]),
                ("surface", 0),
                lambda s: s.surfaces[0],
            )
        )
    specs += [
        _Spec(
            "[view]",
            "camera",
            "The polarization view the command line applies to the image.",
            "view",
            _load_camera,
            _camera_scene(view={}),
            ("view",),
            None,
        ),
        _Spec(
            "[source]",
            "bench",
            "The optical bench's light: a beam traced forward.",
            "bench.source",
            _load_bench,
            _bench_scene(),
            ("source",),
            lambda s: s.source,
        ),
        _Spec(
            "[[sensor]]",
            "bench",
            "A screen that absorbs and records every ray that meets it.",
            "bench.sensor",
            _load_bench,
            _bench_scene(),
            ("sensor", 0),
            lambda s: s.sensors[0],
        ),
        _Spec(
            "[render] (bench)",
            "bench",
            "How to trace a bench scene.",
            "bench.render",
            _load_bench,
            _bench_scene(render={}),
            ("render",),
            lambda s: s.render,
        ),
        _Spec(
            "[microscope]",
            "microscope",
            "The polarizing microscope: mode, polarizers, stage, light.",
            "microscope",
            _load_microscope,
            _microscope_scene(),
            ("microscope",),
            lambda s: s.microscope,
        ),
        _Spec(
            "[sample]",
            "microscope",
            "What lies on the stage: a crystal plate or a thin section.",
            "sample",
            _load_microscope,
            _microscope_scene(),
            ("sample",),
            lambda s: s.sample,
        ),
    ]
    return specs


def _table_of(data: Any, path: tuple) -> Any:
    node = data
    for p in path:
        node = node[p]
    return node


class _Accepted(Exception):
    """Raised in place of a kernel launch: validation is over and the value was accepted."""


@contextlib.contextmanager
def _no_kernels():
    """Validate without computing: a kernel launch (an inline material's absorption spectrum, say)
    comes after every check, so it stops the load instead of compiling and running kernels."""

    def refuse(*args, **kwargs):
        raise _Accepted

    launch, load = wp.launch, wp.Module.load
    wp.launch, wp.Module.load = refuse, refuse  # type: ignore[method-assign]
    try:
        with (
            warnings.catch_warnings(),
            np.errstate(all="ignore"),
            # library materials evaluate their dispersion in a kernel when they are built: the
            # checks around them need only a stand-in
            mock.patch.object(material_spec, "get", lambda name: _ProbeBase()),
            mock.patch.object(microscope_scene, "material_from_spec", lambda spec: _ProbeBase()),
        ):
            warnings.simplefilter("ignore")  # a value far out of range that a validator lets through
            yield
    finally:
        wp.launch, wp.Module.load = launch, load  # type: ignore[method-assign]


def _refusal(spec: _Spec, key: str, value: Any, needs=()) -> InputError | None:
    """The validator's error for ``key = value`` in the table (None: accepted or refused elsewhere)."""
    data = copy.deepcopy(spec.base)
    _table_of(data, spec.path).update(dict(needs))
    _table_of(data, spec.path)[key] = value
    try:
        with _no_kernels():
            spec.load(data)
    except _Accepted:
        return None
    except InputError as exc:
        field = str(exc.field or "")
        name = field.rsplit(".", 1)[-1] if "." in field else field
        return exc if key in name.split("/") or field.endswith("." + key) else None
    return None


def _keys(spec: _Spec) -> list[str]:
    exc = _refusal(spec, _UNKNOWN_KEY, 0)
    if exc is None or not exc.allowed:
        raise RuntimeError(f"the validator of {spec.name} did not list its keys")
    return sorted(k.strip() for k in exc.allowed.split(",") if k.strip() not in spec.exclude)


def _range(spec: _Spec, key: str, doc: FieldDoc) -> str:
    if doc.type == "boolean":
        return "true or false"
    if doc.type == "choice":
        exc = _refusal(spec, key, "\x00")
        return "one of " + exc.allowed if exc is not None and exc.allowed else ""
    if doc.type in ("number", "integer"):
        far = 2**62 if doc.type == "integer" else 1.0e300
        texts = []
        for v in (-far, far):
            exc = _refusal(spec, key, v, doc.needs)
            if exc is not None:
                text = exc.allowed or exc.message
                if text not in texts:
                    texts.append(text)
        return "; ".join(texts) if texts else "any finite number"
    return ""


def _default(spec: _Spec, key: str, doc: FieldDoc) -> str:
    if spec.config is None:
        return ""
    with _no_kernels():
        config = spec.config(spec.load(copy.deepcopy(spec.base)))
    if callable(doc.default):
        value = doc.default(config)
    elif isinstance(config, dict):
        value = config.get(doc.default or key, _NO_DEFAULT)
    else:
        value = getattr(config, doc.default or key, _NO_DEFAULT)
    if value is _NO_DEFAULT or key in _table_of(spec.base, spec.path):
        return ""
    return _format(value)


def _format(value: Any) -> str:
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, tuple):
        return "[" + ", ".join(_format(v) for v in value) + "]"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _cut_tables() -> list[Table]:
    """The parameters of every cut shape: the keyword arguments of its function in
    :mod:`warpoptics.geometry.cuts` (defaults from its signature)."""
    spec = _specs()[0]
    out = []
    shapes = _refusal(
        _Spec("", "", "", "", _load_camera, _camera_scene(), ("object", 0), None), "shape", "\x00"
    )
    assert shapes is not None and shapes.allowed
    common = set(
        _keys(
            _Spec(
                "",
                "",
                "",
                "",
                _load_camera,
                _camera_scene(object=[{"shape": "mesh", "path": __file__}]),
                ("object", 0),
                None,
            )
        )
    )
    for shape in (s.strip() for s in shapes.allowed.split(",")):
        base = {"shape": shape, "path": __file__} if shape in ("mesh", "gemcad") else {"shape": shape}
        probe = _Spec("", "", "", "", _load_camera, _camera_scene(object=[base]), ("object", 0), None)
        keys = sorted(set(_keys(probe)) - common - {"path"} | ({"repair"} if shape == "mesh" else set()))
        fn = getattr(cuts, shape, None)
        sig = dict(inspect.signature(fn).parameters) if fn is not None else {}
        if any(p.kind == p.VAR_KEYWORD for p in sig.values()):
            # the brilliant family forwards its keywords to round_brilliant
            sig = {**inspect.signature(cuts.round_brilliant).parameters, **sig}
        rows = []
        for key in keys:
            doc = CUT_PARAMETERS.get(key)
            if doc is None:
                rows.append(FieldRow(key, "", "", "", "", ""))
                continue
            d = sig.get(key)
            default = "" if d is None or d.default is inspect.Parameter.empty else _format(d.default)
            rows.append(FieldRow(key, doc.type, doc.unit, "", default, doc.description))
        where = f"``warpoptics.geometry.cuts.{shape}``" if fn is not None else "the file it reads"
        out.append(
            Table(f'[[object]] shape = "{shape}"', spec.scene_kind, f"Parameters of {where}.", tuple(rows))
        )
    return out


def tables() -> list[Table]:
    """Every table of every scene kind, with its rows read from the validators."""
    out = []
    for spec in _specs():
        docs = FIELDS.get(spec.doc, {})
        rows = []
        for key in _keys(spec):
            doc = docs.get(key)
            if doc is None:
                rows.append(FieldRow(key, "", "", "", "", ""))
                continue
            rows.append(
                FieldRow(
                    key, doc.type, doc.unit, _range(spec, key, doc), _default(spec, key, doc), doc.description
                )
            )
        out.append(Table(spec.name, spec.scene_kind, spec.intro, tuple(rows)))
    return out + _cut_tables()


def stale() -> list[str]:
    """``"table: key"`` for every described key that no validator accepts (a key removed or renamed)."""
    out = []
    for spec in _specs():
        accepted = set(_keys(spec))
        out += [f"{spec.name}: {k}" for k in FIELDS.get(spec.doc, {}) if k not in accepted]
    cut_keys = {r.key for t in _cut_tables() for r in t.rows}
    out += [f"cut parameter: {k}" for k in CUT_PARAMETERS if k not in cut_keys]
    out += [f"{name}: (no such table)" for name in set(FIELDS) - {spec.doc for spec in _specs()}]
    return out


def undocumented() -> list[str]:
    """``"table: key"`` for every key a validator accepts that has no type, unit or description."""
    return [
        f"{t.name}: {r.key}"
        for t in tables()
        for r in t.rows
        if not (r.type in TYPES and r.unit and r.description)
    ]


_F = FieldDoc
_MM, _DEG, _NM = "mm", "degrees", "nm"
_SPECTRUM = _F(
    "string",
    NO_UNIT,
    'the light\'s white: a CIE illuminant ("D65", "A", "FL2", "LED-B3", ...), a UV lamp ("UV365",'
    ' "UV254"), a two-column CSV file (nm, relative power) or an inline table; default D65',
)
_TINT = _F("vector", NO_UNIT, "linear-sRGB colour [r, g, b] the light's spectrum is multiplied by")
_ALBEDO = {
    "bsdf": _F("choice", NO_UNIT, "diffuse (Lambert) or glossy (a GGX coat over a diffuse base)"),
    "roughness": _F("number", NO_UNIT, "GGX roughness of a glossy surface"),
    "ior": _F("number", NO_UNIT, "refractive index of a glossy surface's coat"),
    "color": _F("vector", NO_UNIT, "albedo, linear sRGB [r, g, b]"),
    "checker": _F("list", NO_UNIT, "a checkerboard albedo: two colours [[r, g, b], [r, g, b]]"),
    "square": _F("number", _MM, "side of a checker square", needs=(("checker", [[1, 1, 1], [0, 0, 0]]),)),
    "texture": _F("path", NO_UNIT, "an image file as the albedo (found next to the scene file)"),
    "tile": _F("vector", _MM, "size [w, h] of one repetition of the texture"),
}
_THIN_SECTION = (("kind", "thin_section"),)
_THICKNESS_NOISE = {
    "noise_scale": _F("number", _MM, "feature size of the turbulence noise"),
    "seed": _F("integer", NO_UNIT, "seed of the turbulence noise"),
    "octaves": _F("integer", NO_UNIT, "octaves of the turbulence noise"),
    "profile": _F("choice", NO_UNIT, "the thickness profile", "profile"),
}

#: type, unit and description of every key of every scene table (the key of the outer dict names
#: the table, as :func:`tables` looks it up)
FIELDS: dict[str, dict[str, FieldDoc]] = {
    "camera": {
        "type": _F("choice", NO_UNIT, "projection: perspective (pinhole), orthographic or thin lens"),
        "position": _F("vector", _MM, "where the camera is [x, y, z]"),
        "look_at": _F("vector", _MM, "the point the camera looks at [x, y, z]"),
        "up": _F("vector", NO_UNIT, "the direction that is up in the image (made perpendicular to the view)"),
        "fov": _F("number", _DEG, "vertical field of view (perspective, thin lens)"),
        "view_height": _F("number", _MM, "height of the view (orthographic)"),
        "width": _F("integer", "pixels", "image width"),
        "height": _F("integer", "pixels", "image height"),
        "aperture": _F("number", _MM, "aperture diameter of the thin lens (0: pinhole)"),
        "focus_distance": _F("number", _MM, "distance in focus (thin lens); none: the distance to look_at"),
    },
    "render": {
        "spectral": _F(
            "choice",
            NO_UNIT,
            "wavelength strategy: three IORs, uniform or XYZ-importance random"
            " wavelengths, or stratified jittered sub-rays",
        ),
        "wavelengths": _F("integer", NO_UNIT, "wavelength samples per pixel sample (rgb3: 3)"),
        "polarization": _F("boolean", NO_UNIT, "carry Jones/coherency matrices (Stokes layers in the EXR)"),
        "birefringence": _F(
            "choice",
            NO_UNIT,
            "crystals: separate o/e directions (exact), a shared direction"
            " (approx) or exact with optical phases added as amplitudes (coherent)",
        ),
        "coherence_width_mm": _F(
            "number", _MM, "coherent mode: leaves closer than this across their direction add as amplitudes"
        ),
        "max_depth": _F("integer", NO_UNIT, "interfaces a path may cross"),
        "spp": _F("integer", NO_UNIT, "samples per pixel of one pass"),
        "seed": _F("integer", NO_UNIT, "random seed; the same seed gives the same image on any thread count"),
        "split_threshold": _F(
            "number",
            NO_UNIT,
            "follow both reflection and refraction while a branch"
            " carries more than this fraction of the pixel's energy",
        ),
        "max_splits": _F("integer", NO_UNIT, "deterministic splits per path tree"),
        "rr_threshold": _F("number", NO_UNIT, "Russian roulette below this fraction of the energy"),
        "exposure": _F("number", "stops", "exposure of the tone-mapped output"),
        "tone": _F("choice", NO_UNIT, "tone curve of PNG output"),
        "ambient_index": _F("number", NO_UNIT, "refractive index of the medium around the objects"),
        "diffuse_depth": _F("integer", NO_UNIT, "surface hits per path leaf"),
        "mis": _F(
            "choice",
            NO_UNIT,
            "direct light on surfaces: multiple importance sampling, lights only or BSDF only",
        ),
        "stone_shadows": _F(
            "boolean",
            NO_UNIT,
            "stones filter shadow rays (coloured straight-through shadows) instead of blocking them",
        ),
        "caustics": _F("boolean", NO_UNIT, "a light tracer adds lamp -> stone -> surface -> eye paths"),
        "caustic_paths": _F(
            "integer", NO_UNIT, "light paths of the caustic tracer (0: one per pixel sample)"
        ),
        "adaptive": _F(
            "boolean",
            NO_UNIT,
            "adaptive sampling: a pilot in every pixel decides where the rest of the samples go (unbiased)",
        ),
        "pilot_spp": _F(
            "integer", NO_UNIT, "pilot samples per pixel of adaptive sampling (0: spp / 4, at least 2)"
        ),
        "bundle": _F(
            "boolean",
            NO_UNIT,
            "dispersive stones: trace a sample's wavelengths in bundles at one pixel position",
        ),
        "bundle_lanes": _F("integer", NO_UNIT, "wavelengths per bundle"),
        "estimator": _F(
            "choice",
            NO_UNIT,
            "camera estimator: point samples, pixel beams, or auto (beams wherever they apply)",
        ),
        "pixel_beam": _F(
            "boolean",
            NO_UNIT,
            "trace the pixel's whole footprint through one convex stone as beams (see render.estimator)",
        ),
        "beam_block": _F(
            "integer",
            "pixels",
            "pixel beams: a beam follows a block of beam_block x"
            " beam_block pixels (0: blocks up to 0.12 degrees wide, 1: one beam per pixel)",
        ),
    },
    "light": {
        "type": _F("choice", NO_UNIT, "the kind of light; the lamps have tables of their own below"),
        "map": _F(
            "string",
            NO_UNIT,
            'a built-in map ("studio", "dome", "cos", ...) or a lat-long'
            " .exr/.hdr/.png file (found next to the scene file)",
        ),
        "intensity": _F("number", NO_UNIT, "radiance scale of the map"),
        "tint": _TINT,
        "rotation": _F(
            "number", _DEG, "turns the map counter-clockwise about +z, seen from above", "rotation_deg"
        ),
        "convention": _F(
            "choice",
            NO_UNIT,
            "layout of a lat-long file: Blender's, Mitsuba's envmap, or Blender's mirrored left-right",
        ),
        "polarizer": _F(
            "number",
            _DEG,
            "an ideal linear polarizer in front of the light: transmission"
            ' axis from image right toward image up ("none": unpolarized)',
        ),
        "head_radius": _F(
            "number", _DEG, "the observer's head: a black cone of this angular radius", "head_radius_deg"
        ),
        "head_direction": _F("vector", NO_UNIT, "axis of the observer's head cone (world)"),
        "spectrum": _SPECTRUM,
    },
    "lamp.directional": {
        "type": _F("choice", NO_UNIT, "a lamp: directional"),
        "direction": _F("vector", NO_UNIT, "the direction the light travels"),
        "irradiance": _F(
            "number",
            NO_UNIT,
            "irradiance on a surface facing the light (1: a white"
            " Lambertian surface has Y = 1/pi x irradiance)",
        ),
        "angular_radius": _F("number", _DEG, "angular radius of the source (0: a point at infinity)"),
        "tint": _TINT,
        "spectrum": _SPECTRUM,
    },
    "lamp.area": {
        "type": _F("choice", NO_UNIT, "a lamp: area"),
        "center": _F("vector", _MM, "centre of the light box"),
        "normal": _F("vector", NO_UNIT, "the direction the emitting side faces"),
        "up": _F("vector", NO_UNIT, "direction of the box's h edge (none: chosen from the normal)"),
        "size": _F("vector", _MM, "[w, h] of the box"),
        "radiance": _F("number", NO_UNIT, "radiance of the emitting side"),
        "double_sided": _F("boolean", NO_UNIT, "emit from both sides"),
        "tint": _TINT,
        "spectrum": _SPECTRUM,
    },
    "lamp.spot": {
        "type": _F("choice", NO_UNIT, "a lamp: spot"),
        "center": _F("vector", _MM, "position of the lamp"),
        "direction": _F("vector", NO_UNIT, "axis of the cone"),
        "intensity": _F("number", NO_UNIT, "radiant intensity on the axis"),
        "cone_angle": _F("number", _DEG, "half-angle of the cone"),
        "blend": _F("number", _DEG, "width of the cone's soft edge"),
        "tint": _TINT,
        "spectrum": _SPECTRUM,
    },
    "light.spectrum": {
        "wavelength_nm": _F("list", _NM, "wavelengths of the measured spectrum"),
        "values": _F("list", NO_UNIT, "relative power at each wavelength"),
        "normalize": _F(
            "choice",
            NO_UNIT,
            'scale to the luminance ("luminance") or the power ("power") of D65; default luminance',
        ),
    },
    "object": {
        "shape": _F(
            "choice", NO_UNIT, "a cut (its parameters are listed below), a mesh file or a GemCAD design"
        ),
        "material": _F(
            "table",
            NO_UNIT,
            "a library name or an inline table (below); default diamond, or a GemCAD design's own index",
        ),
        "position": _F("vector", _MM, "translation [x, y, z]"),
        "rotation": _F("vector", _DEG, "rotations about x, then y, then z"),
        "scale": _F("number", NO_UNIT, "uniform scale, applied first"),
        "optic_axis": _F(
            "vector", NO_UNIT, "a uniaxial stone's optic axis in the object's frame (none: the material's)"
        ),
        "crystal_axes": _F(
            "list",
            NO_UNIT,
            "a biaxial stone's principal axes X, Y, Z (rows, object frame; right-handed and orthogonal)",
        ),
        "optic_axial_plane": _F(
            "vector",
            NO_UNIT,
            "a biaxial stone: the normal of the optic-axial plane (Y), with acute_bisectrix",
        ),
        "acute_bisectrix": _F(
            "vector",
            NO_UNIT,
            "a biaxial stone: the acute bisectrix of the optic axes, in the optic-axial plane",
        ),
        "absorption_scale": _F("number", NO_UNIT, "factor on the material's absorption coefficient"),
        "path": _F(
            "path",
            NO_UNIT,
            "mesh file (OBJ, PLY, STL, OFF, glTF) or GemCAD .asc design, found next to the scene file",
        ),
        "name": _F("string", NO_UNIT, "a name for messages and exports"),
        "instances": _F(
            "list", _MM, "positions [[x, y, z], ...] of copies sharing one mesh (replace position)"
        ),
        "surface": _F(
            "choice",
            NO_UNIT,
            "with a coating: a coated solid, a closed thin shell (a bubble) or an open film surface",
        ),
        "coating": _F("list", NO_UNIT, "thin-film layers from the front to the substrate (table below)"),
        "film_thickness": _F("table", NO_UNIT, "how the coating's thickness varies (tables below)"),
        "roughness": _F("number", NO_UNIT, "GGX roughness of a film surface (0: smooth)"),
        "zoning": _F(
            "table",
            NO_UNIT,
            "colour zones inside the stone (planar bands, two halves, or core"
            " and rim), each with its own absorption; the host keeps its indices",
        ),
    },
    "object.coating": {
        "n": _F("number", NO_UNIT, "real part of the layer's refractive index"),
        "k": _F("number", NO_UNIT, "extinction coefficient of the layer (with n)"),
        "material": _F("string", NO_UNIT, "a library material as the layer's index (instead of n, k)"),
        "thickness_nm": _F("number", _NM, "physical thickness of the layer"),
    },
    "object.film_thickness.uniform": {"profile": _THICKNESS_NOISE["profile"]},
    "object.film_thickness.gravity": {
        **_THICKNESS_NOISE,
        "top_nm": _F("number", _NM, "thickness at the top of the object"),
        "bottom_nm": _F("number", _NM, "thickness at the bottom (a film draining under gravity)"),
        "noise": _F("number", NO_UNIT, "relative amplitude of the turbulence"),
    },
    "object.film_thickness.oil_drop": {
        **_THICKNESS_NOISE,
        "max_nm": _F("number", _NM, "thickness at the centre of the drop"),
        "k1": _F("number", NO_UNIT, "radial fall-off of the drop (Smits & Meyer eq. 12)"),
        "k2": _F("number", NO_UNIT, "turbulence weight (Smits & Meyer eq. 13)"),
    },
    "object.material": {
        "base": _F("string", NO_UNIT, "a library material to start from"),
        "cauchy": _F(
            "list",
            NO_UNIT,
            "Cauchy coefficients A, B, ... of n = A + B / lambda^2 + ... (lambda in"
            " micrometres); [A] is non-dispersive",
        ),
        "host": _F("string", NO_UNIT, "a host crystal whose chromophores are given by chromophores"),
        "chromophores": _F("table", NO_UNIT, "chromophore = concentration, in each band set's own unit"),
        "bands": _F("list", NO_UNIT, "absorption bands added to the material (table below)"),
        "absorption_rgb": _F(
            "vector", "1/mm", "an RGB absorbance triplet (Guy & Soler eq. 9), turned into a smooth spectrum"
        ),
        "kramers_kronig": _F(
            "boolean", NO_UNIT, "add the anomalous dispersion of the absorption (Weidlich & Wilkie)"
        ),
        "optic_axis": _F("vector", NO_UNIT, "optic axis of a uniaxial material"),
        "fluorescence": _F("table", NO_UNIT, "a luminescent centre: a name or a table (below)"),
    },
    **{
        f"object.zoning.{kind}": {
            "type": _F("choice", NO_UNIT, "the zones' family"),
            **keys,
            "origin": _F("vector", _MM, "the point the offsets are measured from, or a point of the axis"),
            "absorption": _F(
                "list",
                NO_UNIT,
                "one material per zone whose absorption it has: a library name, an inline"
                ' material table (without a start: the object\'s), or "none" (clear)',
            ),
        }
        for kind, keys in (
            (
                "planar",
                {
                    "normal": _F("vector", NO_UNIT, "the bands' normal (object frame)"),
                    "offsets": _F("list", _MM, "increasing offsets of the planes between the bands"),
                },
            ),
            (
                "halves",
                {
                    "normal": _F("vector", NO_UNIT, "the normal of the plane between the halves"),
                    "offset": _F("number", _MM, "the plane's offset along its normal"),
                },
            ),
            (
                "core_rim",
                {
                    "axis": _F("vector", NO_UNIT, "the cylinders' axis (object frame)"),
                    "radii": _F("list", _MM, "increasing radii between the core, the shells and the rim"),
                },
            ),
        )
    },
    "object.material.bands": {
        "center_nm": _F("number", _NM, "centre wavelength of the band"),
        "width_nm": _F("number", _NM, "width of the band"),
        "peak_alpha_per_mm": _F("number", "1/mm", "absorption coefficient at the band's centre (base e)"),
        "shape": _F(
            "choice",
            NO_UNIT,
            'band shape: "gaussian", "lorentzian" or "gaussian_wavenumber" (a Gaussian in wavenumber,'
            " width = sigma in nm at the centre); default gaussian",
        ),
    },
    "object.material.fluorescence": {
        "centre": _F(
            "string",
            NO_UNIT,
            "the luminescent centre (N3, Cr3+ spinel, uranium glass; default the base's own)",
        ),
        "quantum_yield": _F("number", NO_UNIT, "photons emitted per photon absorbed by the centre"),
        "strength": _F("number", NO_UNIT, "factor on the centre's concentration (its absorption)"),
        "add_absorption": _F(
            "boolean",
            NO_UNIT,
            "add the centre's absorption to the material's (false when the base holds its bands already)",
        ),
    },
    "surface.plane": {
        "type": _F("choice", NO_UNIT, "a horizontal square (plane) or any rectangle"),
        "height": _F("number", _MM, "z of the plane", lambda c: c.center[2]),
        "size": _F("number", _MM, "side of the square", lambda c: c.size[0]),
        **_ALBEDO,
    },
    "surface.rectangle": {
        "type": _F("choice", NO_UNIT, "a horizontal square (plane) or any rectangle"),
        "center": _F("vector", _MM, "centre of the rectangle"),
        "normal": _F("vector", NO_UNIT, "the side that is seen"),
        "up": _F("vector", NO_UNIT, "direction of the h edge (none: chosen from the normal)"),
        "size": _F("vector", _MM, "[w, h]"),
        **_ALBEDO,
    },
    "view": {
        "kind": _F(
            "choice",
            NO_UNIT,
            "the image seen through an analyzer, a polariscope (crossed"
            " polarizers) or a dichroscope; none: the plain image",
        ),
        "angle": _F("number", _DEG, "analyzer or dichroscope angle from image right toward image up"),
    },
    "bench.source": {
        "type": _F("choice", NO_UNIT, "the source kind"),
        "kind": _F(
            "choice", NO_UNIT, "collimated (parallel rays over a disc) or spot (a point into a cone)", "type"
        ),
        "position": _F("vector", _MM, "centre of the disc, or the spot's position"),
        "direction": _F("vector", NO_UNIT, "direction of the beam"),
        "width": _F("number", _MM, "diameter of a collimated beam"),
        "divergence": _F("number", _DEG, "full cone angle of a spot"),
        "spectrum": _F("string", NO_UNIT, 'an illuminant ("E", "D65", "A") or a linear-sRGB triple'),
        "lines": _F("list", _NM, "emit only these wavelengths, equal power each"),
        "polarization": _F("choice", NO_UNIT, "unpolarized, linear, or right/left circular"),
        "polarization_angle": _F("number", _DEG, "linear polarization from polarization_x toward y"),
        "polarization_x": _F(
            "vector", NO_UNIT, "x axis of the polarization frame (none: chosen from the direction)"
        ),
        "power": _F("number", "W", "power of the beam"),
        "rays": _F("integer", NO_UNIT, "rays (positions or directions) per wavelength"),
    },
    "bench.sensor": {
        "type": _F("choice", NO_UNIT, "the sensor kind"),
        "name": _F("string", NO_UNIT, "the screen's name in outputs (default screen<N>)"),
        "center": _F("vector", _MM, "centre of the screen"),
        "normal": _F("vector", NO_UNIT, "toward the lit side"),
        "up": _F("vector", NO_UNIT, "image up on the screen"),
        "size": _F("vector", _MM, "[width, height]"),
        "resolution": _F("vector", "pixels", "[width, height]"),
    },
    "bench.render": {
        "wavelengths": _F("integer", NO_UNIT, "wavelength samples"),
        "max_depth": _F("integer", NO_UNIT, "interfaces a ray may cross"),
        "split_threshold": _F("number", NO_UNIT, "follow both branches above this fraction of the power"),
        "max_deposits": _F("integer", NO_UNIT, "screen deposits one source ray may leave"),
        "seed": _F("integer", NO_UNIT, "random seed"),
        "ambient_index": _F("number", NO_UNIT, "refractive index around the objects"),
        "exposure": _F("number", "stops", "exposure of the screen images"),
        "tone": _F("choice", NO_UNIT, "tone curve of PNG output"),
    },
    "microscope": {
        "mode": _F(
            "choice", NO_UNIT, "orthoscopic (the image of the plate) or conoscopic (the interference figure)"
        ),
        "polarizer": _F("number", _DEG, "transmission axis of the polarizer"),
        "analyzer": _F("number", _DEG, 'transmission axis of the analyzer ("none": no analyzer)'),
        "stage_rotation": _F("number", _DEG, "rotation of the stage"),
        "accessory": _F("choice", NO_UNIT, "an accessory plate in the slot"),
        "accessory_angle": _F("number", _DEG, "slow axis of the accessory"),
        "wedge_max_nm": _F("number", _NM, "largest retardation of the quartz wedge"),
        "illuminant": _F("choice", NO_UNIT, "the lamp's spectrum"),
        "numerical_aperture": _F("number", NO_UNIT, "numerical aperture of the condenser and objective"),
        "wavelength": _F("number", _NM, 'monochromatic light ("none": white light)'),
        "size": _F("integer", "pixels", "image size"),
        "field_mm": _F("number", _MM, "field of view (orthoscopic)"),
        "mounting_index": _F("number", NO_UNIT, "refractive index of the mounting medium"),
    },
    "sample": {
        "kind": _F("choice", NO_UNIT, "a crystal plate or a thin section of grains"),
        "material": _F("string", NO_UNIT, "a library material"),
        "thickness_mm": _F("number", _MM, "thickness of the plate (a thin section: 0.03)"),
        "optic_axis": _F("vector", NO_UNIT, "optic axis of a uniaxial plate (world, before the stage)"),
        "crystal_axes": _F("list", NO_UNIT, "principal axes X, Y, Z of a biaxial plate (rows)"),
        "grains": _F("integer", NO_UNIT, "Voronoi grains of a thin section", needs=_THIN_SECTION),
        "seed": _F("integer", NO_UNIT, "seed of the grains and their orientations", needs=_THIN_SECTION),
        "optical_activity": _F("choice", NO_UNIT, "handedness of an optically active plate (quartz)"),
    },
}

#: type, unit and description of the keyword arguments of the cuts (warpoptics.geometry.cuts)
CUT_PARAMETERS: dict[str, FieldDoc] = {
    "diameter": _F("number", _MM, "girdle diameter (a sphere: its circumscribed diameter)"),
    "table": _F("number", NO_UNIT, "table width as a fraction of the diameter (step cuts: of the width)"),
    "crown_angle": _F("number", _DEG, "bezel angle to the girdle plane"),
    "pavilion_angle": _F("number", _DEG, "pavilion-main angle to the girdle plane"),
    "star_length": _F("number", NO_UNIT, "radial extent of the stars, a fraction of table edge to girdle"),
    "lower_girdle_length": _F(
        "number", NO_UNIT, "radial extent of the lower girdle facets, a fraction of the girdle radius"
    ),
    "girdle": _F("number", NO_UNIT, "girdle thickness as a fraction of the diameter (width)"),
    "culet": _F("number", NO_UNIT, "culet size as a fraction of the diameter (0: pointed)"),
    "girdle_facets": _F("integer", NO_UNIT, "vertical girdle facets (16, 32, 64 or 128)"),
    "length": _F("number", _MM, "extent along x (a prism: along its edge)"),
    "width": _F("number", _MM, "extent along y (a brilliant outline: across)"),
    "corner": _F("number", NO_UNIT, "length cut off each side at a corner, a fraction of the width"),
    "crown_angles": _F("list", _DEG, "one angle per crown tier, from the girdle inwards"),
    "pavilion_angles": _F("list", _DEG, "one angle per pavilion tier, from the girdle inwards"),
    "apex_angle": _F("number", _DEG, "angle between the two refracting faces"),
    "size": _F("number", _MM, "edge of a cube; width of each refracting face of a prism"),
    "thickness": _F("number", _MM, "distance between opposite faces"),
    "subdivisions": _F("integer", NO_UNIT, "icosphere subdivisions (3: 1280 triangles)"),
    "face_angle": _F("number", _DEG, "angle between the normals of adjacent faces"),
    "amplitude": _F("number", _MM, "height of the sheet's waves"),
    "wavelength_x": _F("number", _MM, "period of the waves along x"),
    "wavelength_y": _F("number", _MM, "period of the waves along y"),
    "resolution": _F("integer", NO_UNIT, "grid cells per side"),
    "repair": _F("boolean", NO_UNIT, "merge duplicate vertices and fix the winding of a mesh file"),
    "tier_angles": _F("table", _DEG, "GemCAD tiers re-cut at new angles: { <tier name or #k> = angle }"),
}
