"""Dispersion models n(λ) + i k(λ) and the device-side material table used by the renderer.

A material channel (isotropic, or the ordinary / extraordinary index of a uniaxial crystal) is

    N(λ) = [ formula(λ) + curve_n(λ) ] + i curve_k(λ)

where ``formula`` is one of the refractiveindex.info dispersion formulas 1–9 (Sellmeier, Cauchy,
... with coefficients in µm; kind 0 = none), ``curve_n`` an additive, piecewise-linear tabulated
curve (a measured n(λ), or the Kramers–Kronig correction Δn of an absorbing material) and
``curve_k`` a piecewise-linear tabulated extinction coefficient k(λ) >= 0.  Every number is a
kernel *argument* (packed arrays in a :class:`MaterialTable` struct), so a scene with any number
of materials compiles the kernels once.

The renderer builds the table once per scene (:func:`build_material_table`) and calls
:func:`material_eval` (complex N_o, N_e) and :func:`material_alpha` (alpha, 1/mm) in its
kernels; ``rgb3_alpha_*`` hold the rgb3 mode's absorbances (Guy & Soler's §6.1 triplets for the
six gems of that table, otherwise eq. 9 of the material's alpha(λ)).  The calls in full:
docs/design/material_table.md.  ``material_eval`` clamps wavelengths outside a material's range
to its ends (no NaN in a kernel); the NumPy API (``mat.n``, ``mat.k``, ``mat.alpha``) refuses
them with an ``InputError`` and launches :func:`material_eval` itself, so the renderer and the
tests run the same code.  A uniaxial e-ray's absorption is
:func:`warpoptics.optics.absorption.pleochroic_kappa` of ``a_o``, ``a_e`` (Guy & Soler eq. 7).

Conventions: exp(-i omega t), N = n + i k with k >= 0 absorbing; alpha = 4 pi k / lambda
(Weidlich & Wilkie 2009, eq. 3), base e, 1/mm.  Float32 throughout (relative precision ~1e-7).

References: M. N. Polyanskiy, "Refractiveindex.info database of optical constants", Sci. Data
11, 94 (2024) (formula types 1–9); A. Weidlich, A. Wilkie, "Anomalous dispersion in predictive
rendering", CGF 28(4), 2009, eq. 2–3.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import warp as wp

from .. import device as _device
from ..errors import InputError
from ..spectra import light_grid
from .rgb_weights import rgb_weights
from .units import alpha_from_k_wp

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "MaterialTable",
    "material_eval",
    "material_eval_channel",
    "material_eval_beta",
    "material_alpha",
    "material_optics",
    "rii_formula",
    "curve_eval",
    "build_material_table",
    "Channel",
    "Isotropic",
    "Uniaxial",
    "Biaxial",
    "Material",
    "Sellmeier",
    "Cauchy",
    "Tabulated",
    "Formula",
    "dispersion_bg",
    "abbe_number",
    "CIE_RGB_PRIMARIES_NM",
    "VISIBLE_RANGE_NM",
]

# plausibility limits for user-given optical constants (the densest natural solids have n < 5;
# metals reach k ~ 10 in the visible)
_N_MAX = 20.0
_K_MAX = 100.0

#: the CIE 1931 RGB primaries (nm) behind the Guy & Soler §6.1 absorbances (Guy & Soler 2004 §4.1;
#: Wyszecki & Stiles 1982).  The renderer's rgb3 mode samples warpoptics.spectra.RGB3_WAVELENGTHS.
CIE_RGB_PRIMARIES_NM = (700.0, 546.1, 435.8)
#: the colour integration range of warpoptics (docs/conventions.md, "Units").
VISIBLE_RANGE_NM = (360.0, 830.0)

_MAX_COEFFS = 32


# ----------------------------------------------------------------------------------------------
# Device code
# ----------------------------------------------------------------------------------------------


@wp.struct
class MaterialTable:
    """All materials of a scene, packed; channel c = 2 * mat_id + (0 ordinary | 1 extraordinary).

    Per channel (length 2M): ``formula_kind`` (0 none, 1–9 refractiveindex.info formula type),
    ``coeff_offset``/``coeff_count`` into ``coeffs`` (µm-based coefficients),
    ``ncurve_offset``/``ncurve_count`` and ``kcurve_offset``/``kcurve_count`` into the packed
    piecewise-linear curves ``curve_lam`` (nm, increasing within a curve) / ``curve_val``.
    Per material (length M): ``lam_min``/``lam_max`` (nm, evaluation is clamped to it),
    ``optic_axis`` (unit vector), ``uniaxial`` (0/1), ``rgb3_alpha_o``/``rgb3_alpha_e``
    (alpha at R, G, B in 1/mm, base e).

    Biaxial crystals (:class:`Biaxial`): channels 2 m and 2 m + 1 are n_alpha and n_gamma, and
    ``beta_channel[m]`` (-1 for every other material, which therefore evaluates exactly as
    before) is the channel of n_beta, appended after the 2M o/e channels; ``crystal_frame[m]``
    holds the principal axes X, Y, Z as rows (already turned into the world by the pipelines:
    each biaxial object has its own entry) and ``rgb3_alpha_o``/``_b``/``_e`` the eq. 9
    absorbances for D along X / Y / Z.
    """

    formula_kind: wp.array(dtype=wp.int32)
    coeff_offset: wp.array(dtype=wp.int32)
    coeff_count: wp.array(dtype=wp.int32)
    coeffs: wp.array(dtype=wp.float32)
    ncurve_offset: wp.array(dtype=wp.int32)
    ncurve_count: wp.array(dtype=wp.int32)
    kcurve_offset: wp.array(dtype=wp.int32)
    kcurve_count: wp.array(dtype=wp.int32)
    curve_lam: wp.array(dtype=wp.float32)
    curve_val: wp.array(dtype=wp.float32)
    lam_min: wp.array(dtype=wp.float32)
    lam_max: wp.array(dtype=wp.float32)
    optic_axis: wp.array(dtype=wp.vec3f)
    uniaxial: wp.array(dtype=wp.int32)
    rgb3_alpha_o: wp.array(dtype=wp.vec3f)
    rgb3_alpha_e: wp.array(dtype=wp.vec3f)
    # fluorescence (materials/fluorescence.py): per material the quantum yield (0: none) and a
    # row (-1: none) of the tables on the 1 nm light grid (spectra.LIGHT_RANGE_NM): the centre's
    # alpha_x (1/mm) and emission density (1/nm) at the nodes, the CDFs over the bins
    fl_yield: wp.array(dtype=wp.float32)
    fl_row: wp.array(dtype=wp.int32)
    fl_excitation: wp.array2d(dtype=wp.float32)
    fl_emission: wp.array2d(dtype=wp.float32)
    fl_emission_cdf: wp.array2d(dtype=wp.float32)
    fl_excitation_cdf: wp.array2d(dtype=wp.float32)
    beta_channel: wp.array(dtype=wp.int32)
    crystal_frame: wp.array(dtype=wp.mat33f)
    rgb3_alpha_b: wp.array(dtype=wp.vec3f)
    # colour zoning (materials/zoning.py, optics/zoning.py): per material the zone family
    # (optics.zoning.ZONE_*; 0: none), its number of zones (0: none), the world -> object frame
    # of its stone, the zones' unit normal or axis and their origin (object frame), and the first
    # index zone_start[m] of its zones in zone_bound (the count - 1 offsets or radii, mm, object
    # frame) and zone_material (the table entry whose absorption each zone has)
    zone_kind: wp.array(dtype=wp.int32)
    zone_count: wp.array(dtype=wp.int32)
    zone_start: wp.array(dtype=wp.int32)
    zone_frame: wp.array(dtype=wp.mat44f)
    zone_axis: wp.array(dtype=wp.vec3f)
    zone_origin: wp.array(dtype=wp.vec3f)
    zone_bound: wp.array(dtype=wp.float32)
    zone_material: wp.array(dtype=wp.int32)


@wp.func
def _coef(coeffs: wp.array(dtype=wp.float32), off: int, cnt: int, i: int):
    # zero-padded coefficient access (refractiveindex.info formulas omit trailing zeros)
    if i < cnt:
        return coeffs[off + i]
    return 0.0


@wp.func
def rii_formula(kind: int, coeffs: wp.array(dtype=wp.float32), off: int, cnt: int, lam_um: float):
    """Refractive index from refractiveindex.info formula ``kind`` (1–9), λ in µm; kind 0 -> 0.

    1 Sellmeier  n²−1 = C1 + Σ C_i λ²/(λ² − C_{i+1}²)      2 Sellmeier-2  ... /(λ² − C_{i+1})
    3 polynomial n² = C1 + Σ C_i λ^C_{i+1}                  4 RefractiveIndex.INFO (two poles + powers)
    5 Cauchy     n = C1 + Σ C_i λ^C_{i+1}                   6 gases  n−1 = C1 + Σ C_i/(C_{i+1} − λ⁻²)
    7 Herzberger 8 Retro 9 Exotic   (see "Dispersion formulas.pdf" of the database)
    """
    l2 = lam_um * lam_um
    if kind == 1 or kind == 2:
        nsq = 1.0 + _coef(coeffs, off, cnt, 0)
        for i in range(1, cnt, 2):
            c = _coef(coeffs, off, cnt, i + 1)
            if kind == 1:
                c = c * c
            nsq += coeffs[off + i] * l2 / (l2 - c)
        return wp.sqrt(wp.max(nsq, 0.0))
    if kind == 3:
        nsq = _coef(coeffs, off, cnt, 0)
        for i in range(1, cnt, 2):
            nsq += coeffs[off + i] * wp.pow(lam_um, _coef(coeffs, off, cnt, i + 1))
        return wp.sqrt(wp.max(nsq, 0.0))
    if kind == 4:
        nsq = _coef(coeffs, off, cnt, 0)
        for j in range(2):
            i = 1 + 4 * j
            if i < cnt:
                num = coeffs[off + i] * wp.pow(lam_um, _coef(coeffs, off, cnt, i + 1))
                den = l2 - wp.pow(_coef(coeffs, off, cnt, i + 2), _coef(coeffs, off, cnt, i + 3))
                nsq += num / den
        for i in range(9, cnt, 2):
            nsq += coeffs[off + i] * wp.pow(lam_um, _coef(coeffs, off, cnt, i + 1))
        return wp.sqrt(wp.max(nsq, 0.0))
    if kind == 5:
        n = _coef(coeffs, off, cnt, 0)
        for i in range(1, cnt, 2):
            n += coeffs[off + i] * wp.pow(lam_um, _coef(coeffs, off, cnt, i + 1))
        return n
    if kind == 6:
        n = 1.0 + _coef(coeffs, off, cnt, 0)
        for i in range(1, cnt, 2):
            n += coeffs[off + i] / (_coef(coeffs, off, cnt, i + 1) - 1.0 / l2)
        return n
    if kind == 7:
        d = l2 - 0.028
        n = _coef(coeffs, off, cnt, 0) + _coef(coeffs, off, cnt, 1) / d
        n += _coef(coeffs, off, cnt, 2) / (d * d)
        p = l2
        for i in range(3, cnt):
            n += coeffs[off + i] * p
            p = p * l2
        return n
    if kind == 8:
        t = _coef(coeffs, off, cnt, 0)
        t += _coef(coeffs, off, cnt, 1) * l2 / (l2 - _coef(coeffs, off, cnt, 2))
        t += _coef(coeffs, off, cnt, 3) * l2
        return wp.sqrt(wp.max((2.0 * t + 1.0) / (1.0 - t), 0.0))
    if kind == 9:
        x = lam_um - _coef(coeffs, off, cnt, 4)
        nsq = _coef(coeffs, off, cnt, 0) + _coef(coeffs, off, cnt, 1) / (l2 - _coef(coeffs, off, cnt, 2))
        nsq += _coef(coeffs, off, cnt, 3) * x / (x * x + _coef(coeffs, off, cnt, 5))
        return wp.sqrt(wp.max(nsq, 0.0))
    return 0.0


@wp.func
def curve_eval(
    lam: wp.array(dtype=wp.float32), val: wp.array(dtype=wp.float32), off: int, cnt: int, x: float
):
    """Piecewise-linear curve through (lam[off+j], val[off+j]), constant beyond its ends; 0 if empty."""
    if cnt <= 0:
        return 0.0
    last = off + cnt - 1
    if cnt == 1 or x <= lam[off]:
        return val[off]
    if x >= lam[last]:
        return val[last]
    lo = off
    hi = last
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if lam[mid] <= x:
            lo = mid
        else:
            hi = mid
    t = (x - lam[lo]) / (lam[hi] - lam[lo])
    return val[lo] + t * (val[hi] - val[lo])


@wp.func
def material_eval_channel(table: MaterialTable, mat_id: int, channel: int, wavelength_nm: float):
    """Complex index (n, k) of one channel (0 ordinary/isotropic, 1 extraordinary) at λ (nm)."""
    lam = wp.clamp(wavelength_nm, table.lam_min[mat_id], table.lam_max[mat_id])
    c = 2 * mat_id + channel
    n = rii_formula(
        table.formula_kind[c], table.coeffs, table.coeff_offset[c], table.coeff_count[c], lam * 1.0e-3
    )
    n += curve_eval(table.curve_lam, table.curve_val, table.ncurve_offset[c], table.ncurve_count[c], lam)
    k = curve_eval(table.curve_lam, table.curve_val, table.kcurve_offset[c], table.kcurve_count[c], lam)
    return wp.vec2f(n, wp.max(k, 0.0))


@wp.func
def material_eval_beta(table: MaterialTable, mat_id: int, wavelength_nm: float):
    """Complex n_beta (n, k) of a biaxial material at λ (nm); call only when
    ``table.beta_channel[mat_id] >= 0``."""
    lam = wp.clamp(wavelength_nm, table.lam_min[mat_id], table.lam_max[mat_id])
    c = table.beta_channel[mat_id]
    n = rii_formula(
        table.formula_kind[c], table.coeffs, table.coeff_offset[c], table.coeff_count[c], lam * 1.0e-3
    )
    n += curve_eval(table.curve_lam, table.curve_val, table.ncurve_offset[c], table.ncurve_count[c], lam)
    k = curve_eval(table.curve_lam, table.curve_val, table.kcurve_offset[c], table.kcurve_count[c], lam)
    return wp.vec2f(n, wp.max(k, 0.0))


@wp.func
def material_eval(table: MaterialTable, mat_id: int, wavelength_nm: float):
    """(N_o, N_e): complex indices n + i k (``wp.vec2f``) of material ``mat_id`` at λ (nm).

    Isotropic materials return N_o == N_e.  λ is clamped to the material's range.
    """
    return (
        material_eval_channel(table, mat_id, 0, wavelength_nm),
        material_eval_channel(table, mat_id, 1, wavelength_nm),
    )


@wp.func
def _alpha_of(nk: wp.vec2f, wavelength_nm: float):
    return alpha_from_k_wp(nk[1], wavelength_nm)


@wp.func
def material_optics(table: MaterialTable, mat_id: int, wavelength_nm: float):
    """(N_o, N_e, (alpha_o, alpha_e)): :func:`material_eval` and :func:`material_alpha` from one
    evaluation of the channels (a tracer needs both at every interface of a stone)."""
    lam = wp.max(wavelength_nm, 1.0e-3)
    no, ne = material_eval(table, mat_id, lam)
    return no, ne, wp.vec2f(_alpha_of(no, lam), _alpha_of(ne, lam))


@wp.func
def material_alpha(table: MaterialTable, mat_id: int, wavelength_nm: float):
    """(alpha_o, alpha_e) in 1/mm (base e) = 4 pi k / λ of material ``mat_id`` at λ (nm)."""
    no, ne, a = material_optics(table, mat_id, wavelength_nm)
    return a[0], a[1]


# ----------------------------------------------------------------------------------------------
# Kernels
# ----------------------------------------------------------------------------------------------


@wp.kernel
def _material_eval_kernel(
    offset: int,
    wavelength_nm: wp.array(dtype=wp.float32),
    mat_id: wp.array(dtype=wp.int32),
    table: MaterialTable,
    out_o: wp.array(dtype=wp.vec2f),
    out_e: wp.array(dtype=wp.vec2f),
    out_alpha: wp.array(dtype=wp.vec2f),
):
    i = wp.tid() + offset
    lam = wavelength_nm[i]
    m = mat_id[i]
    no, ne, a = material_optics(table, m, lam)
    out_o[i] = no
    out_e[i] = ne
    out_alpha[i] = a


@wp.kernel
def _material_eval_beta_kernel(
    offset: int,
    wavelength_nm: wp.array(dtype=wp.float32),
    mat_id: wp.array(dtype=wp.int32),
    table: MaterialTable,
    out_b: wp.array(dtype=wp.vec2f),
    out_alpha: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    lam = wp.max(wavelength_nm[i], 1.0e-3)
    nb = material_eval_beta(table, mat_id[i], lam)
    out_b[i] = nb
    out_alpha[i] = _alpha_of(nb, lam)


# ----------------------------------------------------------------------------------------------
# Host side: channels, materials, the table builder
# ----------------------------------------------------------------------------------------------


def _as_curve(wavelength_nm, values, what: str) -> tuple[np.ndarray, np.ndarray]:
    lam = np.asarray(wavelength_nm, dtype=np.float64).reshape(-1)
    val = np.asarray(values, dtype=np.float64).reshape(-1)
    if lam.shape != val.shape:
        raise InputError(
            f"{what}: wavelength and value arrays differ in length ({lam.size} vs {val.size})",
            field=what,
        )
    if lam.size == 0:
        raise InputError(f"{what}: empty table", field=what)
    if not (np.all(np.isfinite(lam)) and np.all(np.isfinite(val))):
        raise InputError(f"{what}: non-finite entries in the table", field=what, allowed="finite numbers")
    if np.any(lam <= 0):
        raise InputError(f"{what}: wavelengths must be positive (nm)", field=what, value=float(lam.min()))
    order = np.argsort(lam, kind="stable")
    lam, val = lam[order], val[order]
    if np.any(np.diff(lam) == 0):
        raise InputError(f"{what}: repeated wavelength in the table", field=what)
    return lam, val


@dataclass(frozen=True)
class Channel:
    """One refractive-index channel: N = formula(λ) + curve_n(λ) + i curve_k(λ); λ in nm.

    ``formula_kind`` 0–9 (refractiveindex.info type, coefficients in µm), ``n_curve`` and
    ``k_curve`` ``(wavelength_nm, values)`` tuples or ``None``.
    """

    formula_kind: int = 0
    coeffs: tuple[float, ...] = ()
    n_curve: tuple[np.ndarray, np.ndarray] | None = None
    k_curve: tuple[np.ndarray, np.ndarray] | None = None

    def __post_init__(self):
        if self.formula_kind not in range(10):
            raise InputError(
                "unknown dispersion formula type",
                field="formula",
                value=self.formula_kind,
                allowed="0-9 (refractiveindex.info types)",
            )
        if len(self.coeffs) > _MAX_COEFFS:
            raise InputError(
                "too many formula coefficients",
                field="coefficients",
                value=len(self.coeffs),
                allowed=f"<= {_MAX_COEFFS}",
            )
        if not all(math.isfinite(c) for c in self.coeffs):
            raise InputError("non-finite formula coefficient", field="coefficients", value=self.coeffs)
        if self.formula_kind == 0 and self.n_curve is None:
            raise InputError("a channel needs a formula or a tabulated n(λ)", field="n")
        if self.k_curve is not None and np.any(self.k_curve[1] < 0):
            raise InputError(
                "extinction coefficient k must be >= 0 (k > 0 absorbs)",
                field="k",
                value=float(np.min(self.k_curve[1])),
            )

    def with_curves(self, n_curve=None, k_curve=None) -> Channel:
        return Channel(self.formula_kind, self.coeffs, n_curve, k_curve)


def _check_wavelength(wavelength_nm, lo: float, hi: float, name: str) -> np.ndarray:
    lam = np.asarray(wavelength_nm, dtype=np.float64)
    if not np.all(np.isfinite(lam)):
        bad = lam[~np.isfinite(lam)].flat[0].item()  # the element, not the array: one line
        raise InputError("wavelength must be finite", field="wavelength_nm", value=bad)
    if lam.size and (lam.min() < lo - 1e-6 or lam.max() > hi + 1e-6):
        bad = float(lam.min() if lam.min() < lo - 1e-6 else lam.max())
        raise InputError(
            f"wavelength outside the data range of {name}",
            field="wavelength_nm",
            value=bad,
            allowed=f"{lo:g}-{hi:g} nm",
        )
    return lam


class Material:
    """Common base of :class:`Isotropic` and :class:`Uniaxial` (the renderer accepts either)."""

    name: str
    source: str
    wavelength_range_nm: tuple[float, float]
    rgb3_alpha: tuple[tuple[float, float, float], tuple[float, float, float]] | None
    #: a luminescent centre (materials.fluorescence.Fluorescence) or None
    fluorescence = None
    #: colour zones of a stone (materials.zoning.Zoning, set by zoned_material) or None
    zoning = None

    def _channels(self) -> tuple[Channel, Channel]:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def is_uniaxial(self) -> bool:
        return False

    @property
    def optic_axis(self) -> tuple[float, float, float]:
        return (0.0, 0.0, 1.0)

    def _eval(self, wavelength_nm, device=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(N_o, N_e, alpha) arrays (..., 2) through :func:`material_eval` (one launch)."""
        lo, hi = self.wavelength_range_nm
        lam = _check_wavelength(wavelength_nm, lo, hi, self.name)
        dev = _device.get_device(device)
        table = self._table(dev)
        no, ne, alpha = _device.elementwise(
            _material_eval_kernel,
            [(lam, wp.float32), (0, wp.int32)],
            [wp.vec2f, wp.vec2f, wp.vec2f],
            extra=(table,),
            device=dev,
        )
        return no, ne, alpha

    def _table(self, dev) -> MaterialTable:
        cache = self.__dict__.setdefault("_table_cache", {})
        key = str(dev)
        if key not in cache:
            # the NumPy path needs no rgb3 absorbances (and computing them evaluates alpha here)
            cache[key] = build_material_table([self], device=dev, rgb3=False)[0]
        return cache[key]


class Isotropic(Material):
    """An isotropic material N(λ) = n(λ) + i k(λ) (λ in nm, vacuum).

    Build one with :func:`Sellmeier`, :func:`Cauchy`, :func:`Tabulated`, :func:`Formula`,
    :func:`warpoptics.materials.from_refractiveindex` or the library
    (:func:`warpoptics.materials.get`).
    """

    def __init__(
        self,
        channel: Channel,
        *,
        wavelength_range_nm: tuple[float, float],
        name: str = "material",
        source: str = "",
        rgb3_alpha: tuple[float, float, float] | None = None,
        validate: bool = True,
    ) -> None:
        lo, hi = (float(wavelength_range_nm[0]), float(wavelength_range_nm[1]))
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
            raise InputError(
                "wavelength range must be 0 < min < max (nm)",
                field="wavelength_range_nm",
                value=wavelength_range_nm,
            )
        self.channel = channel
        self.name = name
        self.source = source
        self.wavelength_range_nm = (lo, hi)
        self.rgb3_alpha = None if rgb3_alpha is None else (tuple(rgb3_alpha), tuple(rgb3_alpha))
        if validate:
            self._validate()

    def _channels(self) -> tuple[Channel, Channel]:
        return self.channel, self.channel

    def _validate(self) -> None:
        lo, hi = self.wavelength_range_nm
        lam = np.linspace(lo, hi, 257)
        no, _, _ = self._eval(lam)
        n, k = no[..., 0], no[..., 1]
        if not np.all(np.isfinite(no)):
            raise InputError(f"{self.name}: n(λ) is not finite inside {lo:g}-{hi:g} nm", field="n")
        if np.any(n > _N_MAX) or np.any(k > _K_MAX):
            i = int(np.argmax(n))
            raise InputError(
                f"{self.name}: refractive index or extinction absurdly large inside {lo:g}-{hi:g} nm",
                field="n",
                value=float(max(n.max(), k.max())),
                allowed=f"n <= {_N_MAX:g}, k <= {_K_MAX:g}",
            )
        absorbing = k > 1e-3
        bad = (n < 1.0) & ~absorbing
        if np.any(n <= 0) or np.any(bad):
            i = int(np.argmin(n))
            raise InputError(
                f"{self.name}: refractive index below 1 at {lam[i]:.1f} nm for a non-absorbing material",
                field="n",
                value=float(n[i]),
                allowed="n >= 1 (n < 1 only with k > 1e-3)",
            )

    def n(self, wavelength_nm, *, device=None) -> np.ndarray:
        """Real refractive index at ``wavelength_nm`` (nm); same shape as the input."""
        return self._eval(wavelength_nm, device)[0][..., 0]

    def k(self, wavelength_nm, *, device=None) -> np.ndarray:
        """Extinction coefficient k >= 0 at ``wavelength_nm`` (nm)."""
        return self._eval(wavelength_nm, device)[0][..., 1]

    def alpha(self, wavelength_nm, *, device=None) -> np.ndarray:
        """Absorption coefficient alpha = 4 pi k / λ in 1/mm (base e)."""
        return self._eval(wavelength_nm, device)[2][..., 0]

    def complex_n(self, wavelength_nm, *, device=None) -> np.ndarray:
        """n + i k as a complex NumPy array."""
        nk = self._eval(wavelength_nm, device)[0]
        return nk[..., 0] + 1j * nk[..., 1]

    def __repr__(self) -> str:
        lo, hi = self.wavelength_range_nm
        return f"Isotropic({self.name!r}, {lo:g}-{hi:g} nm)"


class Uniaxial(Material):
    """A uniaxial crystal: ``ordinary`` and ``extraordinary`` :class:`Isotropic` channels and a
    unit ``optic_axis`` (object frame, default +z).  Each channel carries its own k(λ), i.e. the
    K^o(λ), K^e(λ) of the pleochroic absorbance of Guy & Soler 2004 eq. 7."""

    def __init__(
        self,
        ordinary: Isotropic,
        extraordinary: Isotropic,
        *,
        optic_axis: Sequence[float] = (0.0, 0.0, 1.0),
        name: str = "crystal",
        source: str = "",
        rgb3_alpha: tuple[Sequence[float], Sequence[float]] | None = None,
    ) -> None:
        axis = np.asarray(optic_axis, dtype=np.float64).reshape(-1)
        if axis.shape != (3,) or not np.all(np.isfinite(axis)):
            raise InputError("optic axis must be 3 finite numbers", field="optic_axis", value=optic_axis)
        norm = float(np.linalg.norm(axis))
        if norm < 1e-12:
            raise InputError(
                "optic axis must not be the zero vector",
                field="optic_axis",
                value=tuple(axis.tolist()),
                allowed="a non-zero 3-vector",
            )
        self.ordinary = ordinary
        self.extraordinary = extraordinary
        self._axis = tuple((axis / norm).tolist())
        self.name = name
        self.source = source
        lo = max(ordinary.wavelength_range_nm[0], extraordinary.wavelength_range_nm[0])
        hi = min(ordinary.wavelength_range_nm[1], extraordinary.wavelength_range_nm[1])
        if not lo < hi:
            raise InputError(
                f"{name}: ordinary and extraordinary ranges do not overlap", field="wavelength_range_nm"
            )
        self.wavelength_range_nm = (lo, hi)
        self.rgb3_alpha = None if rgb3_alpha is None else (tuple(rgb3_alpha[0]), tuple(rgb3_alpha[1]))

    @property
    def is_uniaxial(self) -> bool:
        return True

    @property
    def optic_axis(self) -> tuple[float, float, float]:
        return self._axis

    def _channels(self) -> tuple[Channel, Channel]:
        return self.ordinary.channel, self.extraordinary.channel

    def with_optic_axis(self, axis: Sequence[float]) -> Uniaxial:
        out = Uniaxial(
            self.ordinary,
            self.extraordinary,
            optic_axis=axis,
            name=self.name,
            source=self.source,
            rgb3_alpha=self.rgb3_alpha,
        )
        out.fluorescence = self.fluorescence
        return out

    def n(self, wavelength_nm, *, device=None) -> np.ndarray:
        """(n_o, n_e) stacked on a trailing axis of length 2."""
        no, ne, _ = self._eval(wavelength_nm, device)
        return np.stack([no[..., 0], ne[..., 0]], axis=-1)

    def k(self, wavelength_nm, *, device=None) -> np.ndarray:
        """(k_o, k_e) stacked on a trailing axis of length 2."""
        no, ne, _ = self._eval(wavelength_nm, device)
        return np.stack([no[..., 1], ne[..., 1]], axis=-1)

    def alpha(self, wavelength_nm, *, device=None) -> np.ndarray:
        """(alpha_o, alpha_e) in 1/mm (base e), trailing axis of length 2."""
        return self._eval(wavelength_nm, device)[2]

    def birefringence(self, wavelength_nm=589.3, *, device=None) -> np.ndarray:
        """n_e − n_o (positive for optically positive crystals)."""
        n = self.n(wavelength_nm, device=device)
        return n[..., 1] - n[..., 0]

    def __repr__(self) -> str:
        lo, hi = self.wavelength_range_nm
        return f"Uniaxial({self.name!r}, {lo:g}-{hi:g} nm, axis={self._axis})"


class Biaxial(Material):
    """A biaxial crystal: principal index channels ``alpha``, ``beta``, ``gamma``
    (:class:`Isotropic`, n_alpha <= n_beta <= n_gamma over the range; each carries its own k(λ),
    the absorption for D along that principal axis) along the principal axes X, Y, Z — the rows
    of ``crystal_axes`` (object frame; default the identity).

    ``two_v(λ)`` is the optic-axial angle in degrees from the indices, ``optic_sign`` "+" when Z
    is the acute bisectrix (at 589.3 nm).  ``uniaxial_approximation()`` is the stone as today's
    uniaxial model (n_o, n_e = the two principal indices farthest from n_beta's partner, the optic
    axis along the acute bisectrix), kept for comparison.  ``rgb3_alpha`` (optional): the eq. 9
    absorbance triplets for D along X, Y, Z."""

    def __init__(
        self,
        alpha: Isotropic,
        beta: Isotropic,
        gamma: Isotropic,
        *,
        crystal_axes=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
        name: str = "biaxial",
        source: str = "",
        rgb3_alpha=None,
    ) -> None:
        from ..validate import crystal_frame

        self.alpha_channel = alpha
        self.beta = beta
        self.gamma = gamma
        self.name = name
        self.source = source
        self._axes = crystal_frame(crystal_axes, field="crystal_axes")
        lo = max(c.wavelength_range_nm[0] for c in (alpha, beta, gamma))
        hi = min(c.wavelength_range_nm[1] for c in (alpha, beta, gamma))
        if not lo < hi:
            raise InputError(
                f"{name}: the ranges of the three indices do not overlap", field="wavelength_range_nm"
            )
        self.wavelength_range_nm = (lo, hi)
        # the order is checked over the colour range (formula pages may have IR poles beyond it)
        lam = np.linspace(max(lo, VISIBLE_RANGE_NM[0]), min(hi, VISIBLE_RANGE_NM[1]), 48)
        na, nb, ng = alpha.n(lam), beta.n(lam), gamma.n(lam)
        if np.any(na > nb + 1e-9) or np.any(nb > ng + 1e-9) or np.any(ng - na <= 0):
            i = int(np.argmax((na > nb + 1e-9) | (nb > ng + 1e-9) | (ng - na <= 0)))
            raise InputError(
                f"{name}: principal indices must satisfy n_alpha <= n_beta <= n_gamma, n_alpha < n_gamma",
                field="n_alpha, n_beta, n_gamma",
                value=(round(float(na[i]), 5), round(float(nb[i]), 5), round(float(ng[i]), 5)),
                allowed=f"ordered at every wavelength ({lam[i]:.0f} nm fails)",
            )
        self.rgb3_alpha = (
            None if rgb3_alpha is None else tuple(tuple(float(v) for v in t) for t in rgb3_alpha)
        )

    @property
    def crystal_axes(self) -> np.ndarray:
        """(3, 3) rows X, Y, Z (object frame, or world for a pipeline's per-object entry)."""
        return self._axes.copy()

    @property
    def optic_axis(self) -> tuple[float, float, float]:
        # the Z row: what a tracer's per-object axis array carries (unused for biaxial media)
        return tuple(float(v) for v in self._axes[2])

    def _channels(self) -> tuple[Channel, Channel]:
        return self.alpha_channel.channel, self.gamma.channel

    def with_crystal_axes(self, axes) -> Biaxial:
        return Biaxial(
            self.alpha_channel,
            self.beta,
            self.gamma,
            crystal_axes=axes,
            name=self.name,
            source=self.source,
            rgb3_alpha=self.rgb3_alpha,
        )

    def _eval3(self, wavelength_nm, device=None):
        no, ne, alpha = self._eval(wavelength_nm, device)
        lo, hi = self.wavelength_range_nm
        lam = _check_wavelength(wavelength_nm, lo, hi, self.name)
        dev = _device.get_device(device)
        nb, ab = _device.elementwise(
            _material_eval_beta_kernel,
            [(lam, wp.float32), (0, wp.int32)],
            [wp.vec2f, wp.float32],
            extra=(self._table(dev),),
            device=dev,
        )
        n = np.stack([no[..., 0], nb[..., 0], ne[..., 0]], axis=-1)
        k = np.stack([no[..., 1], nb[..., 1], ne[..., 1]], axis=-1)
        a = np.stack([alpha[..., 0], ab, alpha[..., 1]], axis=-1)
        return n, k, a

    def n(self, wavelength_nm, *, device=None) -> np.ndarray:
        """(n_alpha, n_beta, n_gamma) on a trailing axis of length 3."""
        return self._eval3(wavelength_nm, device)[0]

    def k(self, wavelength_nm, *, device=None) -> np.ndarray:
        """(k_X, k_Y, k_Z) on a trailing axis of length 3."""
        return self._eval3(wavelength_nm, device)[1]

    def alpha(self, wavelength_nm, *, device=None) -> np.ndarray:
        """(alpha_X, alpha_Y, alpha_Z) in 1/mm (base e): absorption for D along each axis."""
        return self._eval3(wavelength_nm, device)[2]

    def two_v(self, wavelength_nm=589.3, *, device=None) -> np.ndarray:
        """The optic-axial angle 2V in degrees at ``wavelength_nm`` (from the three indices)."""
        from ..optics.biaxial import optic_axial_angle

        n = self.n(wavelength_nm, device=device)
        return optic_axial_angle(n[..., 0], n[..., 1], n[..., 2])[0]

    @property
    def optic_sign(self) -> str:
        """ "+" when Z (n_gamma) bisects the acute angle of the optic axes at 589.3 nm, else "-"."""
        from ..optics.biaxial import optic_axial_angle

        n = self.n(589.3)
        return "+" if bool(optic_axial_angle(n[0], n[1], n[2])[1]) else "-"

    def optic_axes(self, wavelength_nm=589.3) -> np.ndarray:
        """(2, 3) unit optic axes (of wave normals) in the crystal's frame of ``crystal_axes``."""
        n = self.n(wavelength_nm)
        s2 = (n[0] ** -2 - n[1] ** -2) / (n[0] ** -2 - n[2] ** -2)
        vz = np.arcsin(np.sqrt(np.clip(s2, 0.0, 1.0)))
        local = np.array([[np.sin(vz), 0.0, np.cos(vz)], [-np.sin(vz), 0.0, np.cos(vz)]])
        return local @ self._axes

    def uniaxial_approximation(self) -> Uniaxial:
        """Today's uniaxial model of this stone, for comparison: positive (Z acute bisectrix):
        n_o = n_alpha (D along X), n_e = n_gamma, optic axis Z; negative: n_o = n_gamma,
        n_e = n_alpha, optic axis X.  Each keeps its channel's k(λ)."""
        if self.optic_sign == "+":
            o, e, axis = self.alpha_channel, self.gamma, self._axes[2]
        else:
            o, e, axis = self.gamma, self.alpha_channel, self._axes[0]
        rgb3 = None
        if self.rgb3_alpha is not None:
            rx, _, rz = self.rgb3_alpha
            rgb3 = (rx, rz) if self.optic_sign == "+" else (rz, rx)
        return Uniaxial(
            o,
            e,
            optic_axis=tuple(axis),
            name=f"{self.name} (uniaxial approximation)",
            source=self.source + "; uniaxial approximation (n_beta dropped)",
            rgb3_alpha=rgb3,
        )

    def __repr__(self) -> str:
        lo, hi = self.wavelength_range_nm
        return f"Biaxial({self.name!r}, {lo:g}-{hi:g} nm)"


def rgb3_alpha_of(mat: Material, *, illuminant: str = "E", cmfs: str = "srgb", device=None):
    """(K^o_rgb, K^e_rgb) in 1/mm for the renderer's rgb3 mode: eq. 9 of the material's alpha(λ).

    The default ``cmfs="srgb"`` matches the rgb3 channels of the renderer (sRGB primaries,
    warpoptics.spectra.RGB3_WAVELENGTHS).  Both CMF sets have negative lobes (r̄ below ~545 nm),
    so eq. 9 of a narrow band there (e.g. rose bengal at 549 nm) can come out negative in a
    channel; a negative absorbance would amplify light, so each channel is clamped at 0 here
    (``rgb_absorbance`` itself stays the plain eq. 9).  Materials carrying the Guy & Soler table
    (``mat.rgb3_alpha``) use those triplets verbatim instead (see build_material_table).
    """
    lam, w = rgb_weights(illuminant, cmfs)
    lo, hi = mat.wavelength_range_nm
    a = mat.alpha(np.clip(lam, lo, hi), device=device)
    if isinstance(mat, Biaxial):
        return tuple(tuple(np.maximum(w @ a[:, j], 0.0).tolist()) for j in range(3))
    if isinstance(mat, Uniaxial):
        ko, ke = np.maximum(w @ a[:, 0], 0.0), np.maximum(w @ a[:, 1], 0.0)
        return tuple(ko.tolist()), tuple(ke.tolist())
    t = tuple(np.maximum(w @ a, 0.0).tolist())
    return t, t


def build_material_table(
    materials: Sequence[Material], device=None, *, rgb3: bool = True
) -> tuple[MaterialTable, list[int]]:
    """Pack ``materials`` into one :class:`MaterialTable` on ``device``; returns (table, ids).

    ``ids[i]`` is the ``mat_id`` of ``materials[i]`` in kernels (its index).  Build once per
    scene; nothing is compiled per material.  ``rgb3=False`` leaves ``rgb3_alpha_*`` at zero
    (skips the eq. 9 integrals for materials without tabulated RGB absorbances).
    """
    dev = _device.get_device(device)
    if len(materials) == 0:
        raise InputError("a material table needs at least one material", field="materials")
    # zoned stones (materials/zoning.py): each zone's material is an entry of its own, after the
    # given ones (their ids stay 0..len-1)
    n_given = len(materials)
    materials = list(materials)
    zoned = []  # (host index, Zoning, entry ids of its zones)
    for i in range(n_given):
        zoning = getattr(materials[i], "zoning", None)
        if zoning is not None:
            zoned.append((i, zoning, list(range(len(materials), len(materials) + len(zoning.absorption)))))
            materials.extend(zoning.absorption)
    kinds, c_off, c_cnt, coeffs = [], [], [], []
    n_off, n_cnt, k_off, k_cnt, lam_all, val_all = [], [], [], [], [], []
    lam_min, lam_max, axes, uni, rgb_o, rgb_e = [], [], [], [], [], []
    fl_yield, fl_row, fl_rows = [], [], []
    beta_ch, frames, rgb_b, extra = [], [], [], []
    # linear in the number of materials (100,000 instances share one material object): a running
    # curve offset, and each distinct material's eq. 9 integrals computed once
    total = [0]
    rgb3_of: dict[int, tuple] = {}

    def add_curve(curve, offs, cnts):
        if curve is None:
            offs.append(0)
            cnts.append(0)
            return
        offs.append(total[0])
        cnts.append(len(curve[0]))
        total[0] += len(curve[0])
        lam_all.append(np.asarray(curve[0], dtype=np.float32))
        val_all.append(np.asarray(curve[1], dtype=np.float32))

    for mat in materials:
        if not isinstance(mat, Material):
            raise InputError(
                "not a material",
                field="material",
                value=type(mat).__name__,
                allowed="Isotropic | Uniaxial | Biaxial",
            )
        for ch in mat._channels():
            kinds.append(ch.formula_kind)
            c_off.append(len(coeffs))
            c_cnt.append(len(ch.coeffs))
            coeffs.extend(ch.coeffs)
            add_curve(ch.n_curve, n_off, n_cnt)
            add_curve(ch.k_curve, k_off, k_cnt)
        lam_min.append(mat.wavelength_range_nm[0])
        lam_max.append(mat.wavelength_range_nm[1])
        axes.append(mat.optic_axis)
        uni.append(1 if mat.is_uniaxial else 0)
        rb = (0.0, 0.0, 0.0)
        if isinstance(mat, Biaxial):
            beta_ch.append(2 * len(materials) + len(extra))
            extra.append(mat.beta.channel)
            frames.append(mat.crystal_axes)
            if mat.rgb3_alpha is not None:
                ro, rb, re_ = mat.rgb3_alpha
            elif rgb3:
                if id(mat) not in rgb3_of:
                    rgb3_of[id(mat)] = rgb3_alpha_of(mat, device=dev)
                ro, rb, re_ = rgb3_of[id(mat)]
            else:
                ro, re_ = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        else:
            beta_ch.append(-1)
            frames.append(np.zeros((3, 3)))
            if mat.rgb3_alpha is not None:
                ro, re_ = mat.rgb3_alpha
            elif rgb3:
                if id(mat) not in rgb3_of:
                    rgb3_of[id(mat)] = rgb3_alpha_of(mat, device=dev)
                ro, re_ = rgb3_of[id(mat)]
            else:
                ro, re_ = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        rgb_o.append(ro)
        rgb_e.append(re_)
        rgb_b.append(rb)
        fl = getattr(mat, "fluorescence", None)
        if fl is None:
            fl_yield.append(0.0)
            fl_row.append(-1)
        else:
            fl_yield.append(fl.quantum_yield)
            fl_row.append(len(fl_rows))
            fl_rows.append(fl.device_rows())
    for ch in extra:  # the n_beta channels of biaxial materials, after the 2M o/e channels
        kinds.append(ch.formula_kind)
        c_off.append(len(coeffs))
        c_cnt.append(len(ch.coeffs))
        coeffs.extend(ch.coeffs)
        add_curve(ch.n_curve, n_off, n_cnt)
        add_curve(ch.k_curve, k_off, k_cnt)

    def arr(values, dtype, np_dtype):
        a = np.asarray(values, dtype=np_dtype)
        if a.size == 0:
            a = np.zeros(1, dtype=np_dtype)
        return wp.array(a, dtype=dtype, device=dev)

    t = MaterialTable()
    t.formula_kind = arr(kinds, wp.int32, np.int32)
    t.coeff_offset = arr(c_off, wp.int32, np.int32)
    t.coeff_count = arr(c_cnt, wp.int32, np.int32)
    t.coeffs = arr(coeffs, wp.float32, np.float32)
    t.ncurve_offset = arr(n_off, wp.int32, np.int32)
    t.ncurve_count = arr(n_cnt, wp.int32, np.int32)
    t.kcurve_offset = arr(k_off, wp.int32, np.int32)
    t.kcurve_count = arr(k_cnt, wp.int32, np.int32)
    t.curve_lam = arr(np.concatenate(lam_all) if lam_all else [], wp.float32, np.float32)
    t.curve_val = arr(np.concatenate(val_all) if val_all else [], wp.float32, np.float32)
    t.lam_min = arr(lam_min, wp.float32, np.float32)
    t.lam_max = arr(lam_max, wp.float32, np.float32)
    t.optic_axis = wp.array(np.asarray(axes, dtype=np.float32).reshape(-1, 3), dtype=wp.vec3f, device=dev)
    t.uniaxial = arr(uni, wp.int32, np.int32)
    t.rgb3_alpha_o = wp.array(np.asarray(rgb_o, dtype=np.float32).reshape(-1, 3), dtype=wp.vec3f, device=dev)
    t.rgb3_alpha_e = wp.array(np.asarray(rgb_e, dtype=np.float32).reshape(-1, 3), dtype=wp.vec3f, device=dev)
    t.fl_yield = arr(fl_yield, wp.float32, np.float32)
    t.fl_row = arr(fl_row, wp.int32, np.int32)
    n_grid = len(light_grid())
    for k, attr in enumerate(("fl_excitation", "fl_emission", "fl_emission_cdf", "fl_excitation_cdf")):
        rows = np.asarray([r[k] for r in fl_rows], dtype=np.float32).reshape(-1, n_grid)
        if rows.shape[0] == 0:
            rows = np.zeros((1, n_grid), dtype=np.float32)
        setattr(t, attr, wp.array(rows, dtype=wp.float32, device=dev))
    t.beta_channel = arr(beta_ch, wp.int32, np.int32)
    t.crystal_frame = wp.array(
        np.asarray(frames, dtype=np.float32).reshape(-1, 3, 3), dtype=wp.mat33f, device=dev
    )
    t.rgb3_alpha_b = wp.array(np.asarray(rgb_b, dtype=np.float32).reshape(-1, 3), dtype=wp.vec3f, device=dev)
    _zone_arrays(t, len(materials), zoned, dev)
    return t, list(range(n_given))


def _zone_arrays(t: MaterialTable, count: int, zoned: list, dev) -> None:
    """Fill the table's zoning arrays (see :class:`MaterialTable`) for ``count`` entries, of which
    the hosts in ``zoned`` (host id, Zoning, zone entry ids) are zoned."""
    kind = np.zeros(count, dtype=np.int32)
    num = np.zeros(count, dtype=np.int32)
    start = np.zeros(count, dtype=np.int32)
    frame = np.tile(np.eye(4, dtype=np.float32), (count, 1, 1))
    axis = np.zeros((count, 3), dtype=np.float32)
    origin = np.zeros((count, 3), dtype=np.float32)
    bounds: list[float] = []
    zone_mat: list[int] = []
    for host, zoning, ids in zoned:
        kind[host] = 2 if zoning.family == "cylinders" else 1
        num[host] = len(ids)
        start[host] = len(zone_mat)
        frame[host] = zoning.frame()
        axis[host] = zoning.axis
        origin[host] = zoning.origin
        bounds.extend([*zoning.bounds, 0.0])  # padded to one per zone: the same start for both
        zone_mat.extend(ids)
    t.zone_kind = wp.array(kind, dtype=wp.int32, device=dev)
    t.zone_count = wp.array(num, dtype=wp.int32, device=dev)
    t.zone_start = wp.array(start, dtype=wp.int32, device=dev)
    t.zone_frame = wp.array(frame, dtype=wp.mat44f, device=dev)
    t.zone_axis = wp.array(axis, dtype=wp.vec3f, device=dev)
    t.zone_origin = wp.array(origin, dtype=wp.vec3f, device=dev)
    t.zone_bound = wp.array(np.asarray(bounds or [0.0], dtype=np.float32), dtype=wp.float32, device=dev)
    t.zone_material = wp.array(np.asarray(zone_mat or [0], dtype=np.int32), dtype=wp.int32, device=dev)


# ----------------------------------------------------------------------------------------------
# Constructors
# ----------------------------------------------------------------------------------------------


def Formula(
    kind: int,
    coefficients: Sequence[float],
    *,
    wavelength_range_nm: tuple[float, float],
    name: str = "formula",
    source: str = "",
) -> Isotropic:
    """A refractiveindex.info dispersion formula of type ``kind`` (1–9), coefficients in µm."""
    if int(kind) not in range(1, 10):
        raise InputError(
            "unknown refractiveindex.info formula type", field="formula", value=kind, allowed="1-9"
        )
    ch = Channel(int(kind), tuple(float(c) for c in coefficients))
    return Isotropic(ch, wavelength_range_nm=wavelength_range_nm, name=name, source=source)


def Sellmeier(
    B: Sequence[float],
    C: Sequence[float],
    *,
    A: float = 1.0,
    wavelength_range_nm: tuple[float, float] = VISIBLE_RANGE_NM,
    name: str = "sellmeier",
    source: str = "",
) -> Isotropic:
    """Sellmeier dispersion n² = A + Σ B_i λ² / (λ² − C_i), λ in µm, C_i in µm² (Schott form).

    Stored as refractiveindex.info formula 2 with C1 = A − 1.
    """
    B = [float(b) for b in np.atleast_1d(B)]
    C = [float(c) for c in np.atleast_1d(C)]
    if len(B) != len(C) or not B:
        raise InputError(
            "Sellmeier needs as many B as C terms (at least one)", field="B, C", value=(len(B), len(C))
        )
    lo_um, hi_um = wavelength_range_nm[0] * 1e-3, wavelength_range_nm[1] * 1e-3
    for c in C:
        if c >= 0 and lo_um <= math.sqrt(c) <= hi_um:
            raise InputError(
                "a Sellmeier pole lies inside the wavelength range",
                field="C",
                value=c,
                allowed=f"sqrt(C) outside {lo_um:g}-{hi_um:g} µm",
            )
    coeffs = [float(A) - 1.0]
    for b, c in zip(B, C, strict=True):
        coeffs += [b, c]
    return Formula(
        2,
        coeffs,
        wavelength_range_nm=wavelength_range_nm,
        name=name,
        source=source or f"Sellmeier B={B}, C={C} µm²",
    )


def Cauchy(
    *coefficients: float,
    wavelength_range_nm: tuple[float, float] = VISIBLE_RANGE_NM,
    name: str = "cauchy",
    source: str = "",
) -> Isotropic:
    """Cauchy dispersion n = A + B/λ² + C/λ⁴ + ... with λ in µm: ``Cauchy(A, B, C, ...)``.

    Stored as refractiveindex.info formula 5 (exponents −2, −4, ...).
    """
    if not coefficients:
        raise InputError("Cauchy needs at least the constant term A", field="coefficients")
    coeffs = [float(coefficients[0])]
    for i, c in enumerate(coefficients[1:], start=1):
        coeffs += [float(c), -2.0 * i]
    return Formula(
        5,
        coeffs,
        wavelength_range_nm=wavelength_range_nm,
        name=name,
        source=source or f"Cauchy {tuple(float(c) for c in coefficients)} (λ in µm)",
    )


def Tabulated(
    wavelength_nm,
    n,
    k=None,
    *,
    name: str = "tabulated",
    source: str = "table",
) -> Isotropic:
    """Tabulated n(λ) (and optionally k(λ)), linearly interpolated; the range is the table's."""
    lam, nv = _as_curve(wavelength_nm, n, "n")
    k_curve = None
    if k is not None:
        lam_k, kv = _as_curve(wavelength_nm, k, "k")
        if np.any(kv < 0):
            raise InputError("extinction coefficient k must be >= 0", field="k", value=float(kv.min()))
        k_curve = (lam_k, kv)
    if lam.size < 2:
        raise InputError("a table needs at least two wavelengths", field="wavelength_nm", value=lam.size)
    return Isotropic(
        Channel(0, (), (lam, nv), k_curve), wavelength_range_nm=(lam[0], lam[-1]), name=name, source=source
    )


def with_absorption_k(
    mat: Isotropic, wavelength_nm, k, *, dn=None, name: str | None = None, source: str | None = None
) -> Isotropic:
    """``mat`` with an extinction coefficient table k(λ) (replacing/adding to its own on the
    given grid) and optionally an additive Δn(λ) on the same grid."""
    lam, kv = _as_curve(wavelength_nm, k, "k")
    if np.any(kv < 0):
        raise InputError("extinction coefficient k must be >= 0", field="k", value=float(kv.min()))
    ch = mat.channel
    if ch.k_curve is not None:
        kv = kv + np.interp(lam, *ch.k_curve)
    n_curve = ch.n_curve
    if dn is not None:
        _, dv = _as_curve(wavelength_nm, dn, "dn")
        base = np.interp(lam, *ch.n_curve) if ch.n_curve is not None else 0.0
        n_curve = (lam, base + dv)
    lo = max(mat.wavelength_range_nm[0], float(lam[0]))
    hi = min(mat.wavelength_range_nm[1], float(lam[-1]))
    return Isotropic(
        ch.with_curves(n_curve, (lam, kv)),
        wavelength_range_nm=(lo, hi),
        name=name or mat.name,
        source=source or mat.source,
    )


# ----------------------------------------------------------------------------------------------
# Gemological figures
# ----------------------------------------------------------------------------------------------


def _n_real(mat: Material, wavelength_nm, channel: str = "o") -> np.ndarray:
    if isinstance(mat, Biaxial):
        j = {"o": 0, "alpha": 0, "beta": 1, "gamma": 2}.get(channel)
        if j is None:
            raise InputError(
                "unknown channel of a biaxial material",
                field="channel",
                value=channel,
                allowed="alpha, beta, gamma",
            )
        return mat.n(wavelength_nm)[..., j]
    if isinstance(mat, Uniaxial):
        n = mat.n(wavelength_nm)
        return n[..., 0] if channel == "o" else n[..., 1]
    return mat.n(wavelength_nm)


def dispersion_bg(mat: Material, *, channel: str = "o") -> float:
    """Gemological dispersion n(430.8 nm) − n(686.7 nm) (Fraunhofer B and G lines).

    For a uniaxial crystal, ``channel`` selects "o" (default) or "e"; for a biaxial one "alpha"
    (the default "o" reads as alpha), "beta" or "gamma".
    """
    n = _n_real(mat, np.array([430.8, 686.7]), channel)
    return float(n[0] - n[1])


def abbe_number(mat: Material, *, channel: str = "o") -> float:
    """Abbe number V_d = (n_d − 1) / (n_F − n_C) at 587.56, 486.13, 656.27 nm."""
    n = _n_real(mat, np.array([587.56, 486.13, 656.27]), channel)
    return float((n[0] - 1.0) / (n[1] - n[2]))
