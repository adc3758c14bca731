"""Interference-colour tables (Smits & Meyer 1990 §2.1) and their per-ray lookup.

A Warp kernel fills a table: XYZ under an illuminant and Smits–Meyer-clipped linear sRGB (§3.2,
``color.gamut_clip_smits_meyer``), indexed by the optical thickness t' = t n cos(theta) (eq. 11)
for single films and by angle for multilayers, from either the paper's model
(:mod:`.smits_meyer`) or the exact stack (:mod:`.stack`); :func:`color_table_lookup`
interpolates them per ray.  :func:`morpho_stack` builds the Morpho vane's layers.

References
----------
* B. E. Smits and G. W. Meyer, "Newton's colors: simulating interference phenomena in
  realistic image synthesis", 1990, §2.1, §3.2, §4.3.
* T. F. Anderson and A. G. Richards, J. Appl. Phys. 13, 748 (1942) (the Morpho model).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import warp as wp

from ...color import gamut_clip_smits_meyer
from ...device import elementwise, get_device
from ...errors import InputError
from ...spectra import ILLUMINANTS, SpectralTables, cmf_xyz, illuminant_value, spectral_tables
from ...validate import finite_array
from .smits_meyer import (
    smits_meyer_film_reflectance,
    smits_meyer_morpho_thickness_wp,
    smits_meyer_multilayer_intensity,
)
from .stack import CoatingStack, make_coating_stack, stack_amplitudes, stack_power

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "TableModel",
    "table_spectral_reflectance",
    "color_table_lookup",
    "ColorTable",
    "film_color_table",
    "multilayer_color_table",
    "morpho_stack",
]


# Colour-table models (the ``model`` argument of the table kernel)
TABLE_SMITS_MEYER_FILM = wp.constant(0)
TABLE_EXACT_FILM = wp.constant(1)
TABLE_SMITS_MEYER_MULTILAYER = wp.constant(2)
TABLE_EXACT_MULTILAYER = wp.constant(3)


@wp.struct
class TableModel:
    """Parameters of a colour table (see :func:`film_color_table`, :func:`multilayer_color_table`).

    ``model``       TABLE_* constant
    ``phase``       1 = with the phase change (eq. 7), 0 = without (eq. 8)
    ``K``           amplitude constant of eq. 7/8
    ``d1_nm``, ``d2_nm``, ``n_layer``, ``layers``, ``A0``   eq. 9 and 14
    ``stack``       exact models: film table = one single-layer coating per entry, multilayer
                    table = coating 0
    ``n_front``, ``n_back``   exact models: ambient and substrate indices
    """

    model: int
    phase: float
    K: float
    d1_nm: float
    d2_nm: float
    n_layer: float
    layers: int
    A0: float
    stack: CoatingStack
    n_front: wp.vec2d
    n_back: wp.vec2d


@wp.func
def table_spectral_reflectance(m: TableModel, entry: int, axis_value: float, wavelength_nm: float):
    """Reflectance at ``wavelength_nm`` of table entry ``entry`` whose axis value is ``axis_value``
    (optical thickness t' in nm for film tables, angle in degrees for multilayer tables)."""
    if m.model == TABLE_SMITS_MEYER_FILM:
        return smits_meyer_film_reflectance(wavelength_nm, axis_value, m.phase, m.K)
    cos_t = wp.cos(wp.radians(axis_value))
    if m.model == TABLE_SMITS_MEYER_MULTILAYER:
        t = smits_meyer_morpho_thickness_wp(m.d1_nm, m.d2_nm, m.n_layer, cos_t)
        return smits_meyer_multilayer_intensity(wavelength_nm, t, m.layers, m.A0)
    coating = entry
    c = wp.float64(1.0)
    if m.model == TABLE_EXACT_MULTILAYER:
        coating = 0
        c = wp.float64(cos_t)
    wl = wp.float64(wavelength_nm)
    rs, rp, ts, tp = stack_amplitudes(m.stack, coating, wl, c, m.n_front, m.n_back, 0)
    p = stack_power(rs, rp, ts, tp, c, m.n_front, m.n_back)
    return float(wp.float64(0.5) * (p[0] + p[1]))


@wp.func
def color_table_lookup(table: wp.array(dtype=wp.vec3f), axis_start: float, axis_step: float, x: float):
    """Linear interpolation in a colour table sampled at ``axis_start + j * axis_step``, clamped.

    The renderer's per-ray lookup of Smits & Meyer 1990 §2.1: index a precomputed XYZ or RGB
    table by the optical thickness t' = t n cos(theta) (eq. 11), or by angle for multilayers.
    """
    count = table.shape[0]
    u = wp.clamp((x - axis_start) / axis_step, 0.0, float(count - 1))
    j = wp.min(int(u), wp.max(count - 2, 0))
    f = u - float(j)
    if count == 1:
        return table[0]
    return table[j] * (1.0 - f) + table[j + 1] * f


# ---------------------------------------------------------------------------------------------
# Kernels (element-wise, launched through device.elementwise)
# ---------------------------------------------------------------------------------------------


@wp.kernel
def _table_kernel(
    offset: int,
    entry: wp.array(dtype=wp.int32),
    axis_value: wp.array(dtype=float),
    m: TableModel,
    spectral: SpectralTables,
    illuminant: int,
    step_nm: float,
    exposure: float,
    xyz_out: wp.array(dtype=wp.vec3f),
    rgb_out: wp.array(dtype=wp.vec3f),
):
    """XYZ = sum over lambda of rho E xbar dlambda (trapezoid on a ``step_nm`` grid over
    360-830 nm, luminance normalisation: a perfect reflector has Y = 1); RGB = Smits–Meyer clip
    of ``exposure * XYZ`` into the linear-sRGB cube [0, 1]^3."""
    i = wp.tid() + offset
    e = entry[i]
    x = axis_value[i]
    n = int(wp.floor((spectral.lambda_max - spectral.lambda_min) / step_nm + 1.0e-4))
    xyz = wp.vec3f(0.0, 0.0, 0.0)
    for j in range(n + 1):
        wl = spectral.lambda_min + float(j) * step_nm
        w = step_nm
        if j == 0 or j == n:
            w = 0.5 * step_nm
        rho = table_spectral_reflectance(m, e, x, wl)
        xyz += cmf_xyz(spectral, wl) * (w * rho * illuminant_value(spectral, illuminant, wl))
    xyz_out[i] = xyz
    rgb_out[i] = gamut_clip_smits_meyer(xyz * exposure, 1.0)


@wp.kernel
def _lookup_kernel(
    offset: int,
    x: wp.array(dtype=float),
    table: wp.array(dtype=wp.vec3f),
    axis_start: float,
    axis_step: float,
    out: wp.array(dtype=wp.vec3f),
):
    i = wp.tid() + offset
    out[i] = color_table_lookup(table, axis_start, axis_step, x[i])


# ---------------------------------------------------------------------------------------------
# Python wrappers
# ---------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ColorTable:
    """A precomputed interference-colour table (Smits & Meyer 1990 §2.1).

    ``axis``      (N,) sample positions: optical thickness t' = t n cos(theta) in nm (film
                  tables) or angle of incidence in degrees (multilayer tables), uniform spacing
    ``quantity``  "optical_thickness_nm" or "angle_deg"
    ``xyz``       (N, 3) CIE XYZ of the reflected light under ``illuminant`` (a perfect white
                  reflector has Y = 1)
    ``rgb``       (N, 3) linear sRGB, Smits–Meyer clip of ``exposure * xyz`` into [0, 1]^3
    ``xyz_device``, ``rgb_device``   the same as ``wp.array(dtype=wp.vec3f)`` for
                  :func:`color_table_lookup` in kernels
    """

    axis: np.ndarray
    quantity: str
    model: str
    phase_change: bool
    illuminant: str
    exposure: float
    xyz: np.ndarray
    rgb: np.ndarray
    xyz_device: wp.array
    rgb_device: wp.array
    description: str = ""

    @property
    def axis_start(self) -> float:
        return float(self.axis[0])

    @property
    def axis_step(self) -> float:
        return float(self.axis[1] - self.axis[0]) if self.axis.size > 1 else 1.0

    def lookup(self, x, which: str = "rgb", *, device=None) -> np.ndarray:
        """Interpolated table values at ``x`` (same unit as ``axis``), shape ``x.shape + (3,)``,
        through the kernel-side :func:`color_table_lookup`."""
        if which not in ("rgb", "xyz"):
            raise InputError("unknown table", field="which", value=which, allowed='"rgb", "xyz"')
        table = self.rgb_device if which == "rgb" else self.xyz_device
        (out,) = elementwise(
            _lookup_kernel,
            [(finite_array(x, field="x").astype(np.float32), wp.float32)],
            [wp.vec3f],
            extra=(table, self.axis_start, self.axis_step),
            device=device or table.device,
        )
        return out


def _table_model(model: int, device, **kw) -> TableModel:
    m = TableModel()
    m.model = model
    m.phase = float(kw.get("phase", 1.0))
    m.K = float(kw.get("K", 1.0))
    m.d1_nm = float(kw.get("d1_nm", 0.0))
    m.d2_nm = float(kw.get("d2_nm", 0.0))
    m.n_layer = float(kw.get("n_layer", 1.0))
    m.layers = int(kw.get("layers", 1))
    m.A0 = float(kw.get("A0", 1.0))
    m.stack = kw.get("stack") or make_coating_stack([[]], device=device)
    nf = complex(kw.get("n_front", 1.0))
    nb = complex(kw.get("n_back", 1.0))
    m.n_front = wp.vec2d(nf.real, nf.imag)
    m.n_back = wp.vec2d(nb.real, nb.imag)
    return m


def _fill_table(
    m,
    axis,
    quantity,
    model_name,
    phase_change,
    illuminant,
    step_nm,
    exposure,
    peak_luminance,
    description,
    device,
):
    dev = get_device(device)
    if illuminant not in ILLUMINANTS:
        raise InputError(
            "unknown illuminant", field="illuminant", value=illuminant, allowed=", ".join(ILLUMINANTS)
        )
    if not step_nm > 0:
        raise InputError("wavelength step must be > 0", field="step_nm", value=step_nm, allowed="> 0")
    axis = np.asarray(axis, dtype=np.float64)
    entries = np.arange(axis.size, dtype=np.int32)
    xyz, _ = elementwise(
        _table_kernel,
        [(entries, wp.int32), (axis, wp.float32)],
        [wp.vec3f, wp.vec3f],
        extra=(m, spectral_tables(dev), ILLUMINANTS[illuminant], float(step_nm), 1.0),
        device=dev,
    )
    if exposure is None:
        ymax = float(np.max(xyz[:, 1])) if xyz.size else 0.0
        exposure = peak_luminance / ymax if ymax > 0 else 1.0
    _, rgb = elementwise(
        _table_kernel,
        [(entries, wp.int32), (axis, wp.float32)],
        [wp.vec3f, wp.vec3f],
        extra=(m, spectral_tables(dev), ILLUMINANTS[illuminant], float(step_nm), float(exposure)),
        device=dev,
    )
    return ColorTable(
        axis=axis,
        quantity=quantity,
        model=model_name,
        phase_change=phase_change,
        illuminant=illuminant,
        exposure=float(exposure),
        xyz=xyz,
        rgb=rgb,
        xyz_device=wp.array(xyz, dtype=wp.vec3f, device=dev),
        rgb_device=wp.array(rgb, dtype=wp.vec3f, device=dev),
        description=description,
    )


def _uniform_axis(start: float, stop: float, count: int, name: str) -> np.ndarray:
    if count < 2 or not stop > start:
        raise InputError(
            f"{name} axis needs count >= 2 and stop > start", field=name, value=(start, stop, count)
        )
    return np.linspace(start, stop, int(count))


def film_color_table(
    *,
    phase_change: bool = True,
    model: str = "smits-meyer",
    max_optical_thickness_nm: float = 1500.0,
    count: int = 751,
    n_film: float | complex = 1.33,
    n_front: float | complex = 1.0,
    n_substrate: float | complex | None = None,
    K: float = 1.0,
    illuminant: str = "D65",
    step_nm: float = 5.0,
    exposure: float | None = None,
    peak_luminance: float = 1.0,
    device=None,
) -> ColorTable:
    """Single-film colour table indexed by optical thickness t' = t n cos(theta) (eq. 11), nm.

    ``model="smits-meyer"``: eq. 7 (``phase_change``) or eq. 8, independent of n (Nassau; the
    table is computed for n = 1).  ``model="exact"``: the exact reflectance at normal incidence
    of a film of index ``n_film`` and thickness t'/n_film between ``n_front`` and
    ``n_substrate`` (default 1.0 with the phase change — a soap film — and 1.77 without, a
    water film on sapphire: both reflections then have the same sign).  ``exposure`` scales XYZ
    before the gamut clip (default ``peak_luminance / max Y``: the brightest entry gets Y =
    ``peak_luminance``).  ``step_nm``: wavelength step of the colour integral.
    """
    axis = _uniform_axis(0.0, max_optical_thickness_nm, count, "optical thickness")
    phase = 1.0 if phase_change else 0.0
    dev = get_device(device)
    if model == "smits-meyer":
        m = _table_model(0, dev, phase=phase, K=K)
        desc = f"Smits-Meyer eq. {'7' if phase_change else '8'}, K={K}"
    elif model == "exact":
        if n_substrate is None:
            n_substrate = 1.0 if phase_change else 1.77
        nfilm = complex(n_film)
        stack = make_coating_stack([[(nfilm, t / nfilm.real)] for t in axis], device=dev)
        m = _table_model(1, dev, stack=stack, n_front=n_front, n_back=n_substrate)
        desc = f"exact: n={n_front} | film n={n_film} | n={n_substrate}, normal incidence"
    else:
        raise InputError("unknown model", field="model", value=model, allowed='"exact", "smits-meyer"')
    return _fill_table(
        m,
        axis,
        "optical_thickness_nm",
        model,
        phase_change,
        illuminant,
        step_nm,
        exposure,
        peak_luminance,
        desc,
        dev,
    )


def morpho_stack(d1_nm: float = 150.0, d2_nm: float = 50.0, n: float | complex = 1.53, layers: int = 12):
    """Layers of the Morpho vane model: ``layers`` mullions (index ``n``, thickness ``d2_nm``)
    separated by air gaps ``d1_nm`` (Anderson & Richards 1942; Smits & Meyer 1990 §4.3).
    Returns (indices, thicknesses) front to back, for :func:`reflectance` with air around."""
    idx = []
    thick = []
    for j in range(layers):
        if j:
            idx.append(1.0 + 0.0j)
            thick.append(float(d1_nm))
        idx.append(complex(n))
        thick.append(float(d2_nm))
    return np.asarray(idx), np.asarray(thick)


def multilayer_color_table(
    *,
    model: str = "smits-meyer",
    d1_nm: float = 150.0,
    d2_nm: float = 50.0,
    n: float = 1.53,
    layers: int = 12,
    A0: float = 1.0,
    max_angle: float = 89.0,
    count: int = 90,
    illuminant: str = "D65",
    step_nm: float = 2.0,
    exposure: float | None = None,
    peak_luminance: float = 0.5,
    device=None,
) -> ColorTable:
    """Multilayer (Morpho) colour table indexed by angle of incidence in degrees (§4.3).

    ``model="smits-meyer"``: eq. 9 with the effective thickness of eq. 14.  ``model="exact"``:
    unpolarized exact reflectance of :func:`morpho_stack` in air.  Exposure as in
    :func:`film_color_table` (default peak Y 0.5: the saturated blues keep some colour).
    """
    axis = _uniform_axis(0.0, max_angle, count, "angle")
    if not 0.0 < max_angle <= 90.0:
        raise InputError("max_angle must be in (0, 90] degrees", field="max_angle", value=max_angle)
    dev = get_device(device)
    if model == "smits-meyer":
        m = _table_model(2, dev, d1_nm=d1_nm, d2_nm=d2_nm, n_layer=n, layers=layers, A0=A0)
        desc = f"Smits-Meyer eq. 9 + 14: d1={d1_nm} nm, d2={d2_nm} nm, n={n}, {layers} layers"
    elif model == "exact":
        idx, thick = morpho_stack(d1_nm, d2_nm, n, layers)
        stack = make_coating_stack([list(zip(idx, thick, strict=True))], device=dev)
        m = _table_model(3, dev, stack=stack)
        desc = f"exact: {layers} layers n={n} d2={d2_nm} nm, air gaps d1={d1_nm} nm"
    else:
        raise InputError("unknown model", field="model", value=model, allowed='"exact", "smits-meyer"')
    return _fill_table(
        m, axis, "angle_deg", model, False, illuminant, step_nm, exposure, peak_luminance, desc, dev
    )
