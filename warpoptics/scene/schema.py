"""The tables of a TOML scene -> validated frozen configs, with errors that name file, field and value.

A scene file has the tables ``[camera]``, ``[render]``, ``[[light]]``, ``[[object]]`` and ``[[surface]]`` (see
docs/conventions.md and the files in ``scenes/``).  ``Scene.load(path)`` reads and validates it;
``scene.with_overrides({"render.spp": 4, "object.0.diameter": 5.0})`` returns a modified copy
(dotted paths, as the CLI's ``--set`` and the sweep axes use them).
"""

from __future__ import annotations

import dataclasses
import inspect
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import validate as val
from ..errors import InputError
from ..film.views import parse_view
from ..geometry import cuts
from ..materials.zoning import MAX_ZONES, ZONING_KINDS, Zoning
from ..stages.caustics import MAX_PATHS as _CAUSTIC_PATHS_MAX
from ..stages.coherence import DEFAULT_COHERENCE_WIDTH_MM
from ..stages.environment import LATLONG_CONVENTIONS, EnvironmentConfig
from ..stages.surfaces import BSDF_KINDS, LAMP_KINDS, MIS_MODES, LampConfig, SurfaceConfig
from .coating import film_config

__all__ = [
    "RenderConfig",
    "ObjectConfig",
    "render_config",
    "object_configs",
    "light_config",
    "light_spectrum",
    "surface_config",
    "view_config",
    "object_config",
    "SPECTRAL_MODES",
    "ESTIMATORS",
    "TONE_CURVES",
]

SPECTRAL_MODES = ("rgb3", "uniform", "importance", "stratified")
BIREFRINGENCE_MODES = ("exact", "approx", "coherent")
ESTIMATORS = ("auto", "beam", "point")
TONE_CURVES = ("filmic", "reinhard", "clip")
MIS_CHOICES = tuple(MIS_MODES)
# the largest light tint (a factor on radiance, itself <= 1e12): products stay inside float32
MAX_TINT = 1.0e6


@dataclass(frozen=True)
class RenderConfig:
    """``[render]``: how to render (docs/conventions.md has the estimators and modes)."""

    spectral: str = "stratified"
    wavelengths: int = 45
    polarization: bool = True
    birefringence: str = "exact"
    # coherent mode: leaves closer than this across their direction add as amplitudes (mm; the
    # default and its source: stages/coherence.py)
    coherence_width_mm: float = DEFAULT_COHERENCE_WIDTH_MM
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
    # dispersive stones: one path tree per bundle of up to bundle_lanes (<= 16) of a pixel sample's
    # wavelengths at one pixel position (stages/bundle.py) where the scene allows it; false: one
    # tree per wavelength sample at its own position
    bundle: bool = True
    bundle_lanes: int = 8
    # the camera estimator: "beam" traces a pixel's (or a block's) whole footprint through the
    # stone as beams (stages/pixel_beam.py), "point" traces point samples (stages/trace.py,
    # stages/bundle.py), "auto" takes beams wherever they apply; Image.stats["estimator"] and
    # ["estimator_reason"] say which ran and why.  Beams leave only spectral noise: pair them
    # with >= 24 stratified wavelengths, bundle_lanes = 16, spp = 1 (scenes/diamond_fire.toml)
    estimator: str = "auto"
    # deprecated: true is estimator = "beam", false is "point" (warns; see CHANGELOG.md)
    pixel_beam: bool | None = None
    # pixel beams: each beam follows a block of beam_block x beam_block pixels, shared among the
    # pixels at its leaves (a facet edge is cut once, not in every pixel: 2x faster at 4x4);
    # through a pinhole a pixel's share is biased to first order in the block's angle (0.47 %
    # relative RMSE at 0.12 deg).  0: blocks up to 0.12 deg wide (pipelines/render.py
    # beam_block), 1: one beam per pixel
    beam_block: int = 0
    source: str | None = field(default=None, compare=False)  # scene file, for messages

    def __post_init__(self) -> None:
        file, f = self.source, (lambda k: f"render.{k}")  # noqa: E731
        val.choice(self.spectral, SPECTRAL_MODES, file=file, field=f("spectral"))
        val.choice(self.birefringence, BIREFRINGENCE_MODES, file=file, field=f("birefringence"))
        val.choice(self.tone, TONE_CURVES, file=file, field=f("tone"))
        val.choice(self.mis, MIS_CHOICES, file=file, field=f("mis"))
        for k in ("polarization", "stone_shadows", "caustics", "adaptive", "bundle"):
            val.boolean(getattr(self, k), file=file, field=f(k))
        val.choice(self.estimator, ESTIMATORS, file=file, field=f("estimator"))
        if self.pixel_beam is not None:
            val.boolean(self.pixel_beam, file=file, field=f("pixel_beam"))
            wanted = "beam" if self.pixel_beam else "point"
            if self.estimator not in ("auto", wanted):
                raise InputError(
                    f"render.pixel_beam = {str(self.pixel_beam).lower()} contradicts render.estimator",
                    file=file,
                    field=f("estimator"),
                    value=self.estimator,
                    allowed=f'"{wanted}", or drop render.pixel_beam (deprecated)',
                )
            warnings.warn(
                f"{file + ': ' if file else ''}render.pixel_beam is deprecated: use render.estimator = "
                f'"{wanted}"',
                DeprecationWarning,
                stacklevel=3,
            )
            object.__setattr__(self, "estimator", wanted)
        cp = self.caustic_paths
        if isinstance(cp, int) and not isinstance(cp, bool) and cp > _CAUSTIC_PATHS_MAX:
            raise InputError(
                "more light paths than one run can index (the kernels number paths in int32); "
                "for more light, add runs with other seeds",
                file=file,
                field=f("caustic_paths"),
                value=cp,
                allowed=f"0 to {_CAUSTIC_PATHS_MAX:,} (2^31 - 4096)",
            )
        for k, lo, hi in (
            ("wavelengths", 1, 4096),
            ("max_depth", 0, 256),
            ("max_splits", 0, 4096),
            ("spp", 1, 1 << 20),
            ("seed", 0, 2**31 - 1),
            ("diffuse_depth", 1, 8),
            ("caustic_paths", 0, _CAUSTIC_PATHS_MAX),  # int32 path indices (stages/caustics.py)
            ("pilot_spp", 0, 1 << 20),
            ("bundle_lanes", 1, 16),
            ("beam_block", 0, 16),
        ):
            val.integer(getattr(self, k), file=file, field=f(k), lo=lo, hi=hi)
        for k, flo, fhi in (
            ("split_threshold", 0.0, 1.0),
            ("rr_threshold", 0.0, 1.0),
            ("exposure", -40.0, 40.0),
            ("ambient_index", 1.0, 10.0),
            ("coherence_width_mm", 0.0, 1.0e3),
        ):
            val.number(getattr(self, k), file=file, field=f(k), lo=flo, hi=fhi)
        if self.adaptive and not RenderConfig.pilot_fits(self.spp, self.pilot_spp):
            raise InputError(
                f"adaptive sampling needs a pilot of 2 or more samples and fewer than spp = {self.spp}"
                " (spp >= 3; pilot_spp 0 takes spp / 4)",
                file=file,
                field=f("pilot_spp") if self.pilot_spp else f("spp"),
                value=self.pilot_spp if self.pilot_spp else self.spp,
            )
        if self.spp * self.wavelengths >= 2**31:
            # samples are counted in int32 in the kernels: past 2^31 they wrap and render black
            raise InputError(
                f"spp x wavelengths = {self.spp * self.wavelengths:,} samples per pixel is too many",
                file=file,
                field=f("spp"),
                value=self.spp,
                allowed=f"spp x wavelengths < 2^31 (here spp <= {(2**31 - 1) // self.wavelengths:,})",
            )
        if self.spectral == "rgb3" and self.wavelengths not in (3, _DEFAULT_WAVELENGTHS):
            raise InputError(
                "rgb3 uses exactly 3 wavelengths", file=file, field=f("wavelengths"), value=self.wavelengths
            )

    @property
    def pilot(self) -> int:
        """Pilot samples per pixel of adaptive sampling (:meth:`pilot_for` of this config)."""
        return RenderConfig.pilot_for(self.spp, self.pilot_spp)

    @staticmethod
    def pilot_for(spp: int, pilot_spp: int = 0) -> int:
        """Pilot samples per pixel of adaptive sampling: ``pilot_spp`` if given, else a quarter of
        ``spp`` (at least 2).  The pilot's variances steer everything after it.  Measured on
        bench_diamond at 256x256 (3 seeds, noise of one pass): spp 32 with a pilot of 4 -> 0.99 %,
        of 8 -> 0.90 % (same time); spp 24 with a pilot of 3 -> 1.39 %."""
        return int(pilot_spp) if pilot_spp > 0 else max(2, spp // 4)

    @staticmethod
    def pilot_fits(spp: int, pilot_spp: int = 0) -> bool:
        """Whether adaptive sampling has a pilot of 2 or more samples and samples left after it."""
        return 2 <= RenderConfig.pilot_for(spp, pilot_spp) < spp


_DEFAULT_WAVELENGTHS = RenderConfig.__dataclass_fields__["wavelengths"].default
_RENDER_FIELDS = set(RenderConfig.__dataclass_fields__) - {"source"}


def render_config(table: dict, file: str | None) -> RenderConfig:
    """``[render]`` of a camera scene (unknown keys refused, values checked by :class:`RenderConfig`)."""
    if not isinstance(table, dict):
        raise InputError("must be a table [render]", file=file, field="render", value=table)
    val.check_keys(table, _RENDER_FIELDS, file=file, prefix="render.")
    if table.get("spectral") == "rgb3" and "wavelengths" in table and table["wavelengths"] != 3:
        raise InputError(
            "rgb3 uses exactly 3 wavelengths",
            file=file,
            field="render.wavelengths",
            value=table["wavelengths"],
        )
    return RenderConfig(**table, source=file)


def _shape_functions() -> dict:
    names = [
        "round_brilliant",
        "oval",
        "pear",
        "marquise",
        "emerald",
        "princess",
        "prism",
        "plate",
        "cube",
        "sphere",
        "step_cut",
        "wavy_sheet",
        "rhomb",
    ]
    return {n: getattr(cuts, n) for n in names if hasattr(cuts, n)}


SHAPES = (
    "round_brilliant",
    "oval",
    "pear",
    "marquise",
    "emerald",
    "princess",
    "prism",
    "plate",
    "cube",
    "sphere",
    "step_cut",
    "rhomb",
    "mesh",
    "gemcad",
    "wavy_sheet",
)
_OBJECT_COMMON = {
    "shape",
    "material",
    "position",
    "rotation",
    "scale",
    "optic_axis",
    "crystal_axes",
    "optic_axial_plane",
    "acute_bisectrix",
    "absorption_scale",
    "path",
    "name",
    "instances",
    "zoning",
}
_OBJECT_COMMON |= {"surface", "coating", "film_thickness", "roughness"}  # films: stages/coated.py
_TIER_ANGLES = ("crown_angles", "pavilion_angles")  # list-valued cut parameters (step_cut)


@dataclass(frozen=True)
class ObjectConfig:
    """``[[object]]``: a solid, its material and its placement."""

    shape: str
    material: Any = "diamond"
    # where the material came from: "scene", "default" (diamond) or "gemcad" (the design's I line)
    material_source: str = "default"
    params: dict = field(default_factory=dict)  # keyword arguments of the cut function
    position: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rotation: tuple[float, float, float] = (0.0, 0.0, 0.0)  # degrees about x, then y, then z
    scale: float = 1.0
    optic_axis: tuple[float, float, float] | None = None  # object frame; default the material's
    # biaxial stones: principal axes X, Y, Z (rows, object frame); default the material's
    crystal_axes: tuple[tuple[float, float, float], ...] | None = None
    # "axes": crystal_axes are X, Y, Z; "bisectrix": they are (acute bisectrix, Y, bisectrix x Y),
    # mapped to X, Y, Z by the material's optic sign (pipelines/objects.py)
    crystal_axes_kind: str = "axes"
    absorption_scale: float = 1.0
    path: str | None = None
    name: str | None = None
    film: Any = None  # stages.coated.FilmConfig: coating, shell or film surface (None: bare solid)
    zoning: Zoning | None = None  # colour zones (materials/zoning.py; :func:`zoning_config`)

    def transform(self) -> np.ndarray:
        """4x4 object -> world transform (scale, then rotations x, y, z, then translation)."""
        rx, ry, rz = (math.radians(a) for a in self.rotation)
        cx, sx, cy, sy, cz, sz = (
            math.cos(rx),
            math.sin(rx),
            math.cos(ry),
            math.sin(ry),
            math.cos(rz),
            math.sin(rz),
        )
        mx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
        my = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
        mz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
        m = np.eye(4)
        m[:3, :3] = mz @ my @ mx * self.scale
        m[:3, 3] = self.position
        return m

    def rotation_matrix(self) -> np.ndarray:
        return self.transform()[:3, :3] / self.scale


def _crystal_axes(table: dict, prefix: str, file) -> dict:
    """A biaxial stone's orientation: ``crystal_axes = [[X], [Y], [Z]]`` (principal axes of
    n_alpha, n_beta, n_gamma, object frame) or ``optic_axial_plane`` (its normal is Y) with
    ``acute_bisectrix`` (Z for an optically positive stone, X for a negative one: the material
    decides which, so the pair is stored as (bisectrix, Y, bisectrix x Y) with
    ``crystal_axes_kind = "bisectrix"`` and resolved by the pipeline)."""
    has_axes = "crystal_axes" in table
    has_pair = "optic_axial_plane" in table or "acute_bisectrix" in table
    if has_axes and has_pair:
        raise InputError(
            "give crystal_axes or optic_axial_plane + acute_bisectrix, not both",
            file=file,
            field=prefix + "crystal_axes",
        )
    if "optic_axis" in table and (has_axes or has_pair):
        raise InputError(
            "optic_axis is for uniaxial stones; a biaxial one takes crystal_axes",
            file=file,
            field=prefix + "optic_axis",
        )
    if has_axes:
        a = val.crystal_frame(table["crystal_axes"], file=file, field=prefix + "crystal_axes")
        return {"crystal_axes": tuple(tuple(float(c) for c in r) for r in a)}
    if has_pair:
        for k in ("optic_axial_plane", "acute_bisectrix"):
            if k not in table:
                raise InputError(
                    "optic_axial_plane and acute_bisectrix go together",
                    file=file,
                    field=prefix + k,
                    allowed="both keys (vectors: the plane's normal, the bisectrix)",
                )
        y = np.asarray(
            val.unit_vec3(table["optic_axial_plane"], file=file, field=prefix + "optic_axial_plane")
        )
        b = np.asarray(val.unit_vec3(table["acute_bisectrix"], file=file, field=prefix + "acute_bisectrix"))
        y = y / np.linalg.norm(y)
        b = b / np.linalg.norm(b)
        if abs(float(y @ b)) > 1e-4:
            raise InputError(
                "the acute bisectrix must lie in the optic-axial plane (perpendicular to its normal)",
                file=file,
                field=prefix + "acute_bisectrix",
                value=list(b),
                allowed="acute_bisectrix . optic_axial_plane = 0",
            )
        rows = (tuple(b), tuple(y), tuple(np.cross(b, y)))
        return {"crystal_axes": rows, "crystal_axes_kind": "bisectrix"}
    return {}


def object_config(table: dict, index: int, file, base_dir: Path) -> ObjectConfig:
    prefix = f"object.{index}."
    if not isinstance(table, dict):
        raise InputError("must be a table [[object]]", file=file, field=f"object.{index}", value=table)
    if "shape" not in table:
        raise InputError("missing key", file=file, field=prefix + "shape", allowed=", ".join(SHAPES))
    shape = val.choice(table["shape"], SHAPES, file=file, field=prefix + "shape")
    params = {k: v for k, v in table.items() if k not in _OBJECT_COMMON}
    if shape in ("mesh", "gemcad"):
        allowed_params = {"diameter", "tier_angles"} if shape == "gemcad" else {"repair"}
    else:
        fn = _shape_functions()[shape]
        sig = inspect.signature(fn).parameters
        allowed_params = {p for p, v in sig.items() if v.kind not in (v.VAR_KEYWORD, v.VAR_POSITIONAL)}
        if any(v.kind == v.VAR_KEYWORD for v in sig.values()):
            # the brilliant family forwards its keywords to round_brilliant
            allowed_params |= set(inspect.signature(_shape_functions()["round_brilliant"]).parameters)
    val.check_keys(params, allowed_params | _OBJECT_COMMON, file=file, prefix=prefix)
    for k, v in params.items():
        if k == "tier_angles" and shape == "gemcad":
            continue  # checked against the design below, once its path is known
        if k in _TIER_ANGLES and isinstance(v, list):
            # a step cut's tiers: one angle (degrees) per tier, as `cut --crown-angles 40,30` takes
            if not 1 <= len(v) <= 16:
                raise InputError(
                    "must list 1 to 16 tier angles",
                    file=file,
                    field=prefix + k,
                    value=v,
                    allowed="[a, b, ...]",
                )
            for a in v:
                val.number(a, file=file, field=prefix + k, lo=0.0, hi=90.0, lo_open=True)
            params[k] = tuple(float(a) for a in v)
        elif isinstance(v, bool) or not isinstance(v, (int, float)):
            if not (k == "repair" and isinstance(v, bool)):
                raise InputError("must be a number", file=file, field=prefix + k, value=v)
        elif not math.isfinite(v):
            raise InputError("must be finite", file=file, field=prefix + k, value=v)
    kw: dict[str, Any] = {"shape": shape, "params": params}
    if "material" in table:
        m = table["material"]
        if not isinstance(m, (str, dict)):
            raise InputError(
                "must be a material name or an inline table", file=file, field=prefix + "material", value=m
            )
        kw["material"] = m
        kw["material_source"] = "scene"
    for k in ("position", "rotation"):
        if k in table:
            kw[k] = val.vec3(table[k], file=file, field=prefix + k)
    if "optic_axis" in table:
        ax = val.vec3(table["optic_axis"], file=file, field=prefix + "optic_axis")
        if np.linalg.norm(ax) == 0:
            raise InputError(
                "the optic axis must not be zero", file=file, field=prefix + "optic_axis", value=list(ax)
            )
        kw["optic_axis"] = ax
    kw.update(_crystal_axes(table, prefix, file))
    if "scale" in table:
        kw["scale"] = float(
            val.number(table["scale"], file=file, field=prefix + "scale", lo=1.0e-4, hi=1.0e4)
        )
    if "absorption_scale" in table:
        kw["absorption_scale"] = float(
            val.number(table["absorption_scale"], file=file, field=prefix + "absorption_scale", lo=0.0)
        )
    if shape in ("mesh", "gemcad"):
        if "path" not in table or not isinstance(table["path"], str):
            raise InputError('a mesh object needs path = "file"', file=file, field=prefix + "path")
        p = Path(table["path"])
        if not p.is_absolute():
            p = base_dir / p
        if not p.is_file():
            raise InputError("file not found", file=file, field=prefix + "path", value=table["path"])
        kw["path"] = str(p)
        if shape == "gemcad" and ("material" not in table or "tier_angles" in params):
            from ..geometry.gemcad import check_tier_angles, read_design

            design = read_design(p)
            if "tier_angles" in params:
                # tiers re-cut at new angles (geometry.gemcad.recut_tiers): tier -> signed angle
                try:
                    todo = check_tier_angles(design, params["tier_angles"])
                except InputError as exc:
                    raise InputError(
                        exc.message,
                        file=file,
                        field=prefix + str(exc.field),
                        value=exc.value,
                        allowed=exc.allowed,
                    ) from None
                params["tier_angles"] = tuple((key, angle) for _i, (key, angle) in sorted(todo.items()))
            if "material" not in table:
                # a GemCAD design states the index it was designed for (its I line): use it unless
                # the scene names a material (other readers do the same; the render summary says which)
                kw["material"] = {"cauchy": [float(design.refractive_index)]}
                kw["material_source"] = "gemcad"
    if "name" in table:
        kw["name"] = str(table["name"])
    kw["film"] = film_config(table, index, file)
    if "zoning" in table:
        kw["zoning"] = zoning_config(table["zoning"], prefix + "zoning", file)
    return ObjectConfig(**kw)


# the keys of each zoning type: the surfaces' direction, their positions, the rest in common
_ZONING_KEYS = {
    "planar": ("normal", "offsets"),
    "halves": ("normal", "offset"),
    "core_rim": ("axis", "radii"),
}


def zoning_config(value: Any, field_name: str, file) -> Zoning:
    """An object's ``zoning`` table (materials/zoning.py): colour zones with the host's indices
    and one absorption each (a library material name or an inline material table, whose
    absorption is used; an inline table without ``base`` takes the object's; ``"none"``: a
    clear zone), object frame, mm::

        zoning = { type = "planar", normal = [0, 0, 1], offsets = [-0.5, 0.5],
                   absorption = ["sapphire", { base = "sapphire" }, "sapphire"] }   # 3 bands
        zoning = { type = "halves", normal = [1, 0, 0], offset = 0.0,
                   absorption = [<below the plane>, <above it>] }
        zoning = { type = "core_rim", axis = [0, 0, 1], radii = [1.2], absorption = [<core>, <rim>] }

    ``origin`` (default [0, 0, 0]) is the point the offsets are measured from (the planes) or a
    point of the cylinders' axis.  Zones are listed from the side opposite ``normal`` (planar,
    halves) or from the core outward; offsets and radii increase; at most
    ``materials.zoning.MAX_ZONES`` zones."""
    if not isinstance(value, dict):
        raise InputError("must be a table { type = ..., ... }", file=file, field=field_name, value=value)
    if "type" not in value:
        raise InputError(
            "missing key", file=file, field=field_name + ".type", allowed=", ".join(ZONING_KINDS)
        )
    kind = val.choice(value["type"], ZONING_KINDS, file=file, field=field_name + ".type")
    direction, where = _ZONING_KEYS[kind]
    val.check_keys(
        value, {"type", "origin", "absorption", direction, where}, file=file, prefix=field_name + "."
    )
    for k in (direction, "absorption") + (() if kind == "halves" else (where,)):
        if k not in value:
            raise InputError("missing key", file=file, field=f"{field_name}.{k}")
    ax = np.asarray(val.unit_vec3(value[direction], file=file, field=f"{field_name}.{direction}"))
    f_where = f"{field_name}.{where}"
    if kind == "halves":
        bounds = [float(val.number(value.get(where, 0.0), file=file, field=f_where))]
    else:
        raw = value[where]
        if not isinstance(raw, list) or not 1 <= len(raw) <= MAX_ZONES - 1:
            raise InputError(
                f"must be a list of 1 to {MAX_ZONES - 1} numbers (mm)", file=file, field=f_where, value=raw
            )
        lo = 0.0 if kind == "core_rim" else -math.inf
        bounds = [float(val.number(b, file=file, field=f_where, lo=lo, lo_open=True)) for b in raw]
        if any(b1 <= b0 for b0, b1 in zip(bounds[:-1], bounds[1:], strict=True)):
            raise InputError("must increase", file=file, field=f_where, value=raw)
    absorption = value["absorption"]
    n_zones = len(bounds) + 1
    if not isinstance(absorption, list) or len(absorption) != n_zones:
        raise InputError(
            f"must list one absorption per zone ({n_zones}: one more than the {where})",
            file=file,
            field=field_name + ".absorption",
            value=absorption,
        )
    for j, a in enumerate(absorption):
        if not isinstance(a, (str, dict)):
            raise InputError(
                "must be a material name or an inline material table",
                file=file,
                field=f"{field_name}.absorption.{j}",
                value=a,
            )
    origin = val.vec3(value.get("origin", [0.0, 0.0, 0.0]), file=file, field=field_name + ".origin")
    return Zoning(
        kind=kind,
        axis=tuple(float(c) for c in ax / np.linalg.norm(ax)),  # type: ignore[arg-type]
        bounds=tuple(bounds),
        absorption=tuple(absorption),
        origin=origin,
    )


def object_configs(table: dict, index: int, file, base_dir: Path) -> list[ObjectConfig]:
    """One ``[[object]]`` table: one object, or one per entry of ``instances = [[x, y, z], ...]``
    (positions in mm that replace ``position``; the instances share one mesh)."""
    ob = object_config(table, index, file, base_dir)
    if "instances" not in table:
        return [ob]
    inst = table["instances"]
    field_name = f"object.{index}.instances"
    if not isinstance(inst, list) or not inst:
        raise InputError(
            "must be a non-empty list of positions [[x, y, z], ...]", file=file, field=field_name, value=inst
        )
    return [
        dataclasses.replace(ob, position=val.vec3(p, file=file, field=f"{field_name}.{j}"))
        for j, p in enumerate(inst)
    ]


_LIGHT_KEYS = {
    "type",
    "map",
    "intensity",
    "tint",
    "rotation",
    "polarizer",
    "convention",
    "head_radius",
    "head_direction",
    "spectrum",
}
_SPECTRUM_KEYS = {"wavelength_nm", "values", "normalize"}


def light_spectrum(value, field_name: str, file, base_dir: Path | None = None) -> str:
    """A light's ``spectrum``: a name (CIE illuminant "D65", "A", "FL2", "LED-B3", ...; UV lamp
    "UV365", "UV254"), a two-column CSV file (wavelength nm, relative power; found next to the
    scene file) or an inline table ``{wavelength_nm = [...], values = [...], normalize =
    "luminance" | "power"}``.  Measured spectra are registered in the light table
    (``spectra.register_spectrum``); returns the name the light config takes."""
    from .. import spectra

    if isinstance(value, dict):
        val.check_keys(value, _SPECTRUM_KEYS, file=file, prefix=field_name + ".")
        for k in ("wavelength_nm", "values"):
            if k not in value:
                raise InputError("missing key", file=file, field=f"{field_name}.{k}")
            v = value[k]
            if not isinstance(v, list) or not all(
                isinstance(x, (int, float)) and not isinstance(x, bool) for x in v
            ):
                raise InputError("must be a list of numbers", file=file, field=f"{field_name}.{k}", value=v)
        return spectra.register_spectrum(
            value["wavelength_nm"],
            value["values"],
            normalize=value.get("normalize", "luminance"),
            file=file,
            field=field_name,
        )
    if not isinstance(value, str):
        raise InputError(
            "must be a spectrum name, a .csv file or a table {wavelength_nm, values}",
            file=file,
            field=field_name,
            value=value,
        )
    if Path(value).suffix.lower() == ".csv":
        path = Path(value)
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
        if not path.is_file():
            raise InputError("spectrum file not found", file=file, field=field_name, value=value)
        try:
            data = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
        except ValueError as exc:
            raise InputError(
                f"unreadable spectrum file ({exc})", file=file, field=field_name, value=value
            ) from None
        if data.shape[1] < 2:
            raise InputError(
                "needs two columns: wavelength (nm), relative power", file=file, field=field_name, value=value
            )
        return spectra.register_spectrum(data[:, 0], data[:, 1], file=file, field=field_name)
    spectra.light_spectrum_row(value, file=file, field=field_name)
    return value


def light_config(
    table: dict, index: int, file, base_dir: Path | None = None
) -> EnvironmentConfig | LampConfig:
    prefix = f"light.{index}."
    if not isinstance(table, dict):
        raise InputError("must be a table [[light]]", file=file, field=f"light.{index}", value=table)
    ltype = table.get("type", "environment")
    val.choice(ltype, ("environment", "constant", *LAMP_KINDS), file=file, field=prefix + "type")
    if ltype in LAMP_KINDS:
        return _lamp_config(table, ltype, prefix, file, base_dir)
    val.check_keys(table, _LIGHT_KEYS, file=file, prefix=prefix)
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
        kw["intensity"] = float(
            val.number(table["intensity"], file=file, field=prefix + "intensity", lo=0.0, hi=1.0e12)
        )
    if "tint" in table:
        # bounded like intensity: radiance x tint must stay far inside float32
        kw["tint"] = val.rgb(table["tint"], file=file, field=prefix + "tint", hi=MAX_TINT)
    if "rotation" in table:
        kw["rotation_deg"] = float(val.number(table["rotation"], file=file, field=prefix + "rotation"))
    if "convention" in table:
        # how the lat-long map is laid out (stages/environment.py: blender, mitsuba, mirrored)
        kw["convention"] = val.choice(
            table["convention"], tuple(LATLONG_CONVENTIONS), file=file, field=prefix + "convention"
        )
    if "spectrum" in table:
        kw["spectrum"] = light_spectrum(table["spectrum"], prefix + "spectrum", file, base_dir)
    if "polarizer" in table and table["polarizer"] != "none":
        # an ideal linear polarizer in front of the light (polariscope), degrees on the image
        kw["polarizer"] = float(val.number(table["polarizer"], file=file, field=prefix + "polarizer"))
    if "head_radius" in table:
        # the observer's head blocking the light (degrees of angular radius about head_direction)
        kw["head_radius_deg"] = float(
            val.number(table["head_radius"], file=file, field=prefix + "head_radius", lo=0.0, hi=90.0)
        )
    if "head_direction" in table:
        kw["head_direction"] = val.unit_vec3(
            table["head_direction"], file=file, field=prefix + "head_direction"
        )
    return EnvironmentConfig(**kw)


_VIEW_KEYS = {"kind", "angle"}


def view_config(table, file) -> str | None:
    """``[view]``: the polarization view the CLI applies (``warpoptics.views``), as a spec string."""
    if not isinstance(table, dict):
        raise InputError("must be a table [view]", file=file, field="view", value=table)
    val.check_keys(table, _VIEW_KEYS, file=file, prefix="view.")
    kind = table.get("kind", "none")
    angle = table.get("angle")
    if angle is not None:
        angle = float(val.number(angle, file=file, field="view.angle"))
    try:
        k, arg = parse_view(kind, angle, field="view.kind")
    except InputError as exc:
        raise InputError(
            exc.message, file=file, field=exc.field, value=exc.value, allowed=exc.allowed
        ) from None
    return None if k == "none" else (k if arg is None else f"{k}:{arg}")


_LAMP_KEYS = {
    "directional": {"type", "direction", "irradiance", "tint", "angular_radius", "spectrum"},
    "area": {"type", "center", "normal", "up", "size", "radiance", "tint", "double_sided", "spectrum"},
    "spot": {"type", "center", "direction", "intensity", "tint", "cone_angle", "blend", "spectrum"},
}


def _lamp_config(table: dict, ltype: str, prefix: str, file, base_dir: Path | None = None) -> LampConfig:
    """``[[light]] type = "directional"``, ``"area"`` or ``"spot"`` (stages/surfaces.py)."""
    val.check_keys(table, _LAMP_KEYS[ltype], file=file, prefix=prefix)
    kw: dict[str, Any] = {"type": ltype, "source": file}
    if "spectrum" in table:
        kw["spectrum"] = light_spectrum(table["spectrum"], prefix + "spectrum", file, base_dir)
    for k in ("direction", "normal", "up"):
        if k in table:
            kw[k] = val.unit_vec3(table[k], file=file, field=prefix + k)
    if "center" in table:
        kw["center"] = val.vec3(table["center"], file=file, field=prefix + "center")
    if "size" in table:
        # a lamp below a micrometre: its 1/area sampling density overflows float32 with the radiance
        kw["size"] = val.pair(
            table["size"], file=file, field=prefix + "size", lo=1.0e-3, lo_open=False, hi=1.0e6
        )
    for k in ("irradiance", "radiance", "intensity"):
        if k in table:
            kw[k] = float(val.number(table[k], file=file, field=prefix + k, lo=0.0, hi=1.0e12))
    if "tint" in table:
        kw["tint"] = val.rgb(table["tint"], file=file, field=prefix + "tint", hi=MAX_TINT)
    if "angular_radius" in table:
        kw["angular_radius"] = float(
            val.number(table["angular_radius"], file=file, field=prefix + "angular_radius", lo=0.0, hi=45.0)
        )
    for k in ("cone_angle", "blend"):
        if k in table:
            kw[k] = float(val.number(table[k], file=file, field=prefix + k, lo=0.0, hi=90.0))
    if "double_sided" in table:
        if not isinstance(table["double_sided"], bool):
            raise InputError(
                "must be true or false", file=file, field=prefix + "double_sided", value=table["double_sided"]
            )
        kw["double_sided"] = table["double_sided"]
    if "up" in kw and "normal" in kw and np.linalg.norm(np.cross(kw["up"], kw["normal"])) < 1e-9:
        raise InputError("is parallel to the normal", file=file, field=prefix + "up", value=list(kw["up"]))
    return LampConfig(**kw)


SURFACE_TYPES = ("plane", "rectangle")
_SURFACE_KEYS = {
    "plane": {
        "type",
        "height",
        "size",
        "bsdf",
        "roughness",
        "ior",
        "color",
        "checker",
        "square",
        "texture",
        "tile",
    },
    "rectangle": {
        "type",
        "center",
        "normal",
        "up",
        "size",
        "bsdf",
        "roughness",
        "ior",
        "color",
        "checker",
        "square",
        "texture",
        "tile",
    },
}


def surface_config(table: dict, index: int, file, base_dir: Path) -> SurfaceConfig:
    """``[[surface]]``: ``type = "plane"`` (``height`` mm, ``size`` mm) or ``"rectangle"``
    (``center``, ``normal``, ``up``, ``size = [w, h]``); ``bsdf = "diffuse" | "glossy"``
    (``roughness``, coat ``ior``); albedo ``color = [r, g, b]``, or ``checker = [[r, g, b], [r, g, b]]``
    with ``square`` mm, or ``texture = "file.png"`` with ``tile = [w, h]`` mm."""
    prefix = f"surface.{index}."
    if not isinstance(table, dict):
        raise InputError("must be a table [[surface]]", file=file, field=f"surface.{index}", value=table)
    stype = val.choice(table.get("type", "plane"), SURFACE_TYPES, file=file, field=prefix + "type")
    val.check_keys(table, _SURFACE_KEYS[stype], file=file, prefix=prefix)
    kw: dict[str, Any] = {}
    if stype == "plane":
        h = float(val.number(table.get("height", 0.0), file=file, field=prefix + "height"))
        s = float(
            val.number(
                table.get("size", 1000.0), file=file, field=prefix + "size", lo=0.0, hi=1.0e6, lo_open=True
            )
        )
        kw.update(center=(0.0, 0.0, h), normal=(0.0, 0.0, 1.0), size=(s, s), up=(0.0, 1.0, 0.0))
    else:
        for k in ("normal", "up"):
            if k in table:
                kw[k] = val.unit_vec3(table[k], file=file, field=prefix + k)
        if "center" in table:
            kw["center"] = val.vec3(table["center"], file=file, field=prefix + "center")
        if "size" in table:
            kw["size"] = val.pair(table["size"], file=file, field=prefix + "size", hi=1.0e6)
        if "up" in kw and np.linalg.norm(np.cross(kw["up"], kw.get("normal", (0.0, 0.0, 1.0)))) < 1e-9:
            raise InputError(
                "is parallel to the normal", file=file, field=prefix + "up", value=list(kw["up"])
            )
    if "bsdf" in table:
        kw["bsdf"] = val.choice(table["bsdf"], tuple(BSDF_KINDS), file=file, field=prefix + "bsdf")
    if "roughness" in table:
        kw["roughness"] = float(
            val.number(table["roughness"], file=file, field=prefix + "roughness", lo=0.01, hi=1.0)
        )
    if "ior" in table:
        kw["ior"] = float(val.number(table["ior"], file=file, field=prefix + "ior", lo=1.0, hi=4.0))
    albedos = [k for k in ("color", "checker", "texture") if k in table]
    if len(albedos) > 1:
        raise InputError(
            "give one albedo: color, checker or texture",
            file=file,
            field=prefix + albedos[1],
            allowed="one of color, checker, texture",
        )
    if "color" in table:
        kw["color"] = val.rgb(table["color"], file=file, field=prefix + "color", hi=1.0)
    if "checker" in table:
        c = table["checker"]
        if not isinstance(c, list) or len(c) != 2:
            raise InputError(
                "must be two colours [[r, g, b], [r, g, b]]", file=file, field=prefix + "checker", value=c
            )
        kw["albedo"] = "checker"
        kw["color"] = val.rgb(c[0], file=file, field=prefix + "checker.0", hi=1.0)
        kw["color2"] = val.rgb(c[1], file=file, field=prefix + "checker.1", hi=1.0)
    elif "square" in table:
        raise InputError("square needs checker = [[r, g, b], [r, g, b]]", file=file, field=prefix + "square")
    if "square" in table:
        kw["square"] = float(
            val.number(table["square"], file=file, field=prefix + "square", lo=0.0, hi=1.0e6, lo_open=True)
        )
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
            raise InputError('tile needs texture = "file"', file=file, field=prefix + "tile")
        kw["tile"] = val.pair(table["tile"], file=file, field=prefix + "tile", hi=1.0e6)
    return SurfaceConfig(**kw)
