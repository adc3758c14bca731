"""Polarizing-microscope scenes: a TOML file with ``[microscope]`` and ``[sample]`` -> a validated
:class:`MicroscopeScene` (``warpoptics microscope SCENE.toml -o out.png``; the views are computed
by ``pipelines/microscope.py``: :func:`~warpoptics.pipelines.microscope.microscope_view`).

.. code-block:: toml

    [microscope]
    mode = "orthoscopic"        # "orthoscopic" (parallel light) | "conoscopic" (Bertrand lens)
    polarizer = 0.0             # degrees from image right toward image up (E-W)
    analyzer = 90.0             # crossed (N-S); "none" for plane-polarized light only
    stage_rotation = 0.0        # degrees, the stage (and the sample) turned counter-clockwise
    accessory = "none"          # "first_order_red" (550 nm) | "quarter_wave" (147 nm) | "quartz_wedge"
    accessory_angle = 45.0      # its slow direction (NE-SW)
    wedge_max_nm = 2000.0       # quartz wedge: retardation 0 at the left edge to this at the right
    illuminant = "D65"
    numerical_aperture = 0.5    # conoscopic
    wavelength = "white"        # conoscopic: "white" or a wavelength in nm (monochromatic)
    size = 256                  # image pixels (square)
    field_mm = 2.0              # orthoscopic: the field of view across the image
    mounting_index = 1.54       # the medium around the sample (Canada balsam; 1.0: air)

    [sample]
    kind = "plate"              # "plate" | "thin_section"
    material = "calcite"        # a library name or an inline material table
    thickness_mm = 0.03
    optic_axis = [0.0, 0.0, 1.0]   # uniaxial plate (world: z = the microscope axis)
    # crystal_axes = [[X], [Y], [Z]] for a biaxial plate (default: the material's own, see
    #                ``pipelines.microscope.plate_optics``)
    # optical_activity = "right"   (quartz: the rotation along the axis, materials/activity.py)
    # thin section: grains = 40, seed = 0 (Voronoi cells, random orientations)

Every value is checked by :mod:`warpoptics.validate` (unknown keys get a suggestion; an error
names the file, the field and the value).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .. import validate as val
from ..errors import InputError
from ..materials.activity import optical_activity
from ..materials.dispersion import Biaxial, Material, Uniaxial
from ..materials.spec import material_from_spec
from ..spectra import ILLUMINANTS, LAMBDA_MAX, LAMBDA_MIN

__all__ = [
    "MICROSCOPE_MODES",
    "ACCESSORIES",
    "SAMPLE_KINDS",
    "MicroscopeConfig",
    "SampleConfig",
    "MicroscopeScene",
]

MICROSCOPE_MODES = ("orthoscopic", "conoscopic")
#: accessory plates: name -> retardation (nm) of the ideal retarder (stages/polariscope.py);
#: the quartz wedge is a ramp 0..wedge_max_nm across the field instead of one value
ACCESSORIES = {"none": 0.0, "first_order_red": 550.0, "quarter_wave": 147.0, "quartz_wedge": None}
SAMPLE_KINDS = ("plate", "thin_section")
#: a petrographic thin section's standard thickness, mm
THIN_SECTION_MM = 0.03

_MICROSCOPE_KEYS = {
    "mode",
    "polarizer",
    "analyzer",
    "stage_rotation",
    "accessory",
    "accessory_angle",
    "wedge_max_nm",
    "illuminant",
    "numerical_aperture",
    "wavelength",
    "size",
    "field_mm",
    "mounting_index",
}
_SAMPLE_KEYS = {
    "kind",
    "material",
    "thickness_mm",
    "optic_axis",
    "crystal_axes",
    "grains",
    "seed",
    "optical_activity",
}
#: handedness of an optically active plate (materials/activity.py holds the data, quartz)
ACTIVITY_HANDS = ("right", "left")


@dataclass(frozen=True)
class MicroscopeConfig:
    """``[microscope]`` (module docstring); angles in degrees, ``analyzer`` None: no analyzer."""

    mode: str = "orthoscopic"
    polarizer: float = 0.0
    analyzer: float | None = 90.0
    stage_rotation: float = 0.0
    accessory: str = "none"
    accessory_angle: float = 45.0
    wedge_max_nm: float = 2000.0
    illuminant: str = "D65"
    numerical_aperture: float = 0.5
    wavelength: float | None = None  # None: white light
    size: int = 256
    field_mm: float = 2.0
    mounting_index: float = 1.0

    @property
    def accessory_nm(self) -> float:
        """The accessory's retardation (nm; the quartz wedge: its largest)."""
        r = ACCESSORIES[self.accessory]
        return self.wedge_max_nm if r is None else r


@dataclass(frozen=True)
class SampleConfig:
    """``[sample]``: ``material`` (a dispersion model), ``optic_axis`` / ``crystal_axes`` (world,
    before the stage rotation; None: the defaults of ``pipelines.microscope.plate_optics``)."""

    kind: str
    material: Material
    material_name: str
    thickness_mm: float
    optic_axis: tuple[float, float, float] | None = None
    crystal_axes: tuple[tuple[float, float, float], ...] | None = None
    grains: int = 40
    seed: int = 0
    optical_activity: str | None = None  # "right" | "left" (pipelines.microscope.resolve_activity)


@dataclass(frozen=True)
class MicroscopeScene:
    """A validated microscope scene (:meth:`load`, :meth:`from_dict`)."""

    microscope: MicroscopeConfig
    sample: SampleConfig
    path: str | None = None
    data: dict = field(default_factory=dict, repr=False, compare=False)

    @classmethod
    def load(cls, path: str | Path) -> MicroscopeScene:
        return cls.from_dict(val.toml_file(path), path=str(Path(path)))

    @classmethod
    def from_dict(cls, data: dict, *, path: str | None = None) -> MicroscopeScene:
        file = path or "<scene>"
        val.check_keys(data, {"microscope", "sample"}, file=file)
        for k in ("microscope", "sample"):
            if k not in data:
                raise InputError(f"a microscope scene needs a [{k}] table", file=file, field=k)
            if not isinstance(data[k], dict):
                raise InputError(f"must be a table [{k}]", file=file, field=k, value=data[k])
        mic = _microscope(data["microscope"], file)
        sample = _sample(data["sample"], file)
        if mic.mode == "conoscopic" and sample.kind == "thin_section":
            raise InputError(
                "a conoscopic figure is of one crystal: use a plate sample",
                file=file,
                field="sample.kind",
                value=sample.kind,
                allowed="plate (with microscope.mode = 'conoscopic')",
            )
        if mic.mode == "conoscopic" and mic.accessory == "quartz_wedge":
            raise InputError(
                "the quartz wedge is an orthoscopic accessory (a retardation ramp across the field)",
                file=file,
                field="microscope.accessory",
                value=mic.accessory,
                allowed="none, first_order_red, quarter_wave",
            )
        if mic.mode == "conoscopic" and not mic.numerical_aperture < mic.mounting_index:
            raise InputError(
                "the numerical aperture must be below the mounting index",
                file=file,
                field="microscope.numerical_aperture",
                value=mic.numerical_aperture,
                allowed=f"< {mic.mounting_index:g}",
            )
        return cls(microscope=mic, sample=sample, path=path, data=data)


def _microscope(t: dict, file: str) -> MicroscopeConfig:
    f = "microscope."
    val.check_keys(t, _MICROSCOPE_KEYS, file=file, prefix=f)
    kw: dict[str, Any] = {}
    if "mode" in t:
        kw["mode"] = val.choice(t["mode"], MICROSCOPE_MODES, file=file, field=f + "mode")
    for k, lo, hi in (
        ("polarizer", -360.0, 360.0),
        ("stage_rotation", -360.0, 360.0),
        ("accessory_angle", -360.0, 360.0),
        ("wedge_max_nm", 0.0, 1.0e5),
        ("field_mm", 1.0e-3, 100.0),
        ("mounting_index", 1.0, 3.0),
    ):
        if k in t:
            kw[k] = float(val.number(t[k], file=file, field=f + k, lo=lo, hi=hi))
    if "analyzer" in t:
        a = t["analyzer"]
        kw["analyzer"] = (
            None
            if a == "none"
            else float(val.number(a, file=file, field=f + "analyzer", lo=-360.0, hi=360.0))
        )
    if "accessory" in t:
        kw["accessory"] = val.choice(t["accessory"], tuple(ACCESSORIES), file=file, field=f + "accessory")
    if "illuminant" in t:
        kw["illuminant"] = val.choice(t["illuminant"], tuple(ILLUMINANTS), file=file, field=f + "illuminant")
    if "numerical_aperture" in t:
        kw["numerical_aperture"] = float(
            val.number(
                t["numerical_aperture"],
                file=file,
                field=f + "numerical_aperture",
                lo=0.0,
                hi=2.5,
                lo_open=True,
            )
        )
    if "wavelength" in t:
        w = t["wavelength"]
        kw["wavelength"] = (
            None
            if w == "white"
            else float(val.number(w, file=file, field=f + "wavelength", lo=LAMBDA_MIN, hi=LAMBDA_MAX))
        )
    if "size" in t:
        kw["size"] = val.integer(t["size"], file=file, field=f + "size", lo=8, hi=4096)
    return MicroscopeConfig(**kw)


def _sample(t: dict, file: str) -> SampleConfig:
    f = "sample."
    val.check_keys(t, _SAMPLE_KEYS, file=file, prefix=f)
    kind = val.choice(t.get("kind", "plate"), SAMPLE_KINDS, file=file, field=f + "kind")
    if "material" not in t:
        raise InputError(
            "missing key (a library name or an inline material table)", file=file, field=f + "material"
        )
    spec = t["material"]
    if not isinstance(spec, (str, dict)):
        raise InputError(
            "must be a material name or an inline table", file=file, field=f + "material", value=spec
        )
    try:
        mat = material_from_spec(spec)
    except InputError as exc:
        sub = f".{exc.field}" if exc.field and exc.field != "material" else ""
        raise InputError(
            exc.message, file=file, field=f"{f}material{sub}", value=exc.value, allowed=exc.allowed
        ) from None
    default_d = THIN_SECTION_MM if kind == "thin_section" else None
    if "thickness_mm" not in t and default_d is None:
        raise InputError("missing key (the plate thickness, mm)", file=file, field=f + "thickness_mm")
    d = float(
        val.number(t.get("thickness_mm", default_d), file=file, field=f + "thickness_mm", lo=0.0, hi=100.0)
    )
    kw: dict[str, Any] = {}
    if "optic_axis" in t:
        if not isinstance(mat, Uniaxial):
            raise InputError(
                "optic_axis orients a uniaxial material; a biaxial one takes crystal_axes",
                file=file,
                field=f + "optic_axis",
                value=t["optic_axis"],
            )
        kw["optic_axis"] = val.unit_vec3(t["optic_axis"], file=file, field=f + "optic_axis")
    if "crystal_axes" in t:
        if not isinstance(mat, Biaxial):
            raise InputError(
                "crystal_axes orient a biaxial material", file=file, field=f + "crystal_axes", value=spec
            )
        a = val.crystal_frame(t["crystal_axes"], file=file, field=f + "crystal_axes")
        kw["crystal_axes"] = tuple(tuple(float(c) for c in r) for r in a)
    if kind == "thin_section":
        for k in ("optic_axis", "crystal_axes"):
            if k in kw:
                raise InputError(
                    "a thin section's grains take random orientations (set grains and seed)",
                    file=file,
                    field=f + k,
                )
        if "grains" in t:
            kw["grains"] = val.integer(t["grains"], file=file, field=f + "grains", lo=1, hi=4096)
        if "seed" in t:
            kw["seed"] = val.integer(t["seed"], file=file, field=f + "seed", lo=0, hi=2**31 - 1)
    else:
        for k in ("grains", "seed"):
            if k in t:
                raise InputError(
                    "only a thin section has grains", file=file, field=f + k, allowed="kind = 'thin_section'"
                )
    name = spec if isinstance(spec, str) else str(spec.get("base", "inline"))
    if "optical_activity" in t:
        hand = val.choice(t["optical_activity"], ACTIVITY_HANDS, file=file, field=f + "optical_activity")
        try:
            optical_activity(getattr(mat, "name", name), hand)
        except InputError as exc:
            raise InputError(
                exc.message, file=file, field=f + "optical_activity", value=name, allowed=exc.allowed
            ) from None
        if not isinstance(mat, Uniaxial):
            raise InputError(
                "optical activity is modelled for uniaxial plates only",
                file=file,
                field=f + "optical_activity",
                value=name,
            )
        kw["optical_activity"] = hand
    return SampleConfig(kind=kind, material=mat, material_name=name, thickness_mm=d, **kw)
