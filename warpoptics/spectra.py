"""Wavelength grids, colour-matching functions, illuminants and wavelength sampling.

All colour integrals run over 360-830 nm with the CIE 1931 2 degree observer (from
colour-science).  Tristimulus values use the *luminance* normalisation

    XYZ[S] = integral S(l) cmf(l) dl / integral ybar(l) dl,

so that a constant spectrum S = 1 has Y = 1.  Illuminants are scaled to Y = 1 as well.

Wavelength sampling strategies (``@wp.func sample_wavelength``) return the wavelength of sample
``index`` of ``count`` and an ``xyz_weight`` such that sum(xyz_weight * S(wavelength)) estimates
XYZ[S]:

- ``rgb3`` — the CIE 1931 RGB primaries 700, 546.1 and 435.8 nm (Guy & Soler 2004 §4.1), weighted
  so that a constant spectrum is exact; biased for anything but smooth spectra: the three-IOR
  baseline of the three-wavelength diamond paper, whose banding it reproduces.
- ``uniform`` — a random wavelength, pdf 1/470 nm.
- ``importance`` — pdf proportional to xbar + ybar + zbar, by inverse CDF of a table.
- ``stratified`` — ``count`` jittered strata of equal width (Weidlich & Wilkie 2009, "stratified
  spectral sub-rays"; 45 by default in the renderer).

Two ranges: the **colour range** :data:`COLOR_RANGE_NM` (360-830 nm: the CMFs, every XYZ integral
and every camera wavelength sample) and the **light range** :data:`LIGHT_RANGE_NM` (240-830 nm:
the light-spectrum table, so that a light's ultraviolet is there for fluorescence excitation).
Light spectra are data: rows of ``SpectralTables.illuminants`` chosen by an index that kernels
take as an argument, so any illuminant compiles nothing new.  Rows: the CIE illuminants
(:data:`ILLUMINANTS`, E, D65, A first), the UV lamp models (:data:`UV_LAMPS`) and spectra
registered with :func:`register_spectrum`; the rows and the UV lamp models are described in
docs/design/light_spectra.md.

References: CIE 015:2018 (colorimetry); Weidlich & Wilkie 2009 §4 (stratified sub-rays); "Spectral
dispersion with Sellmeier and wavelength importance sampling" (uniform and importance sampling by
the CIE curves).
"""

from __future__ import annotations

import functools

import numpy as np
import warp as wp

from .device import device_function, elementwise, get_device
from .errors import InputError
from .validate import finite_array

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "LAMBDA_MIN",
    "LAMBDA_MAX",
    "COLOR_RANGE_NM",
    "LIGHT_MIN_NM",
    "LIGHT_RANGE_NM",
    "ILLUMINANTS",
    "UV_LAMPS",
    "light_spectrum_names",
    "light_spectrum_row",
    "register_spectrum",
    "light_spectrum",
    "light_spectrum_value",
    "srgb_basis_value",
    "light_values",
    "STRATEGIES",
    "RGB3_WAVELENGTHS",
    "grid",
    "cmf",
    "illuminant",
    "spectrum_to_xyz",
    "SpectralTables",
    "spectral_tables",
    "cmf_xyz",
    "illuminant_value",
    "rgb_spectrum_value",
    "rgb_to_spectrum",
    "sample_wavelength",
    "sample_wavelengths",
    "strategy_id",
]

LAMBDA_MIN = 360.0
LAMBDA_MAX = 830.0
_STEP = 1.0
_COUNT = int(round((LAMBDA_MAX - LAMBDA_MIN) / _STEP)) + 1
#: the colour range: CMFs, XYZ integrals, camera wavelength samples (CIE 1931 2 degree)
COLOR_RANGE_NM = (LAMBDA_MIN, LAMBDA_MAX)
#: start of the light-spectrum table: below the 253.65 nm mercury line of short-wave UV lamps
LIGHT_MIN_NM = 240.0
#: the light range: where light spectra are tabulated (the ultraviolet an excitation may need)
LIGHT_RANGE_NM = (LIGHT_MIN_NM, LAMBDA_MAX)
_LIGHT_COUNT = int(round((LAMBDA_MAX - LIGHT_MIN_NM) / _STEP)) + 1
_UV_COUNT = int(round((LAMBDA_MIN - LIGHT_MIN_NM) / _STEP))  # light-grid samples below 360 nm

#: sampling strategy names -> ids used inside kernels
STRATEGIES = {"rgb3": 0, "uniform": 1, "importance": 2, "stratified": 3}
STRATEGY_RGB3 = wp.constant(0)
STRATEGY_UNIFORM = wp.constant(1)
STRATEGY_IMPORTANCE = wp.constant(2)
STRATEGY_STRATIFIED = wp.constant(3)

#: the R, G, B wavelengths (nm) of the three-wavelength mode: the CIE 1931 RGB primaries
#: (Guy & Soler 2004 §4.1; Wyszecki & Stiles 1982)
RGB3_WAVELENGTHS = (700.0, 546.1, 435.8)

#: CIE illuminant names (colour-science's spelling) -> row in SpectralTables.illuminants; E,
#: D65 and A keep rows 0, 1, 2 (kernels and thin-film tables rely on them); all have Y = 1
_CIE_NAMES = (
    ("E", "D65", "A", "B", "C", "D50", "D55", "D60", "D75")
    + tuple(f"FL{i}" for i in range(1, 13))
    + tuple(f"FL3.{i}" for i in range(1, 16))
    + tuple(f"HP{i}" for i in range(1, 6))
    + ("LED-B1", "LED-B2", "LED-B3", "LED-B4", "LED-B5", "LED-BH1", "LED-RGB1", "LED-V1", "LED-V2")
)
ILLUMINANTS = {name: row for row, name in enumerate(_CIE_NAMES)}
#: UV lamps (module docstring): name -> (centre nm, FWHM nm) of the Gaussian line shape
UV_LAMPS = {"UV365": (365.0, 9.0), "UV254": (253.652, 2.0)}
#: other accepted spellings: CIE 015 writes F1..F12 for colour-science's FL1..FL12
_ALIASES = {f"F{i}": f"FL{i}" for i in range(1, 13)}
#: measured spectra (register_spectrum): name -> values on the light grid (not yet normalised)
_MEASURED: dict[str, np.ndarray] = {}
#: bumped whenever a spectrum is registered, so that spectral_tables() rebuilds its rows
_REGISTRY_VERSION = [0]


#: spacing (nm) of the coarse spectral grid on which materials are tabulated for the device and
#: checked for dispersion (95 samples over 360-830 nm): ``grid(COARSE_STEP_NM)``
COARSE_STEP_NM = 5.0


def grid(step: float = 1.0, start: float = LAMBDA_MIN, stop: float = LAMBDA_MAX) -> np.ndarray:
    """Wavelengths (nm) from ``start`` to ``stop`` inclusive, spaced by ``step``."""
    if step <= 0:
        raise ValueError(f"step must be > 0, got {step}")
    n = int(np.floor((stop - start) / step + 1e-9)) + 1
    return start + step * np.arange(n, dtype=np.float64)


@functools.lru_cache(maxsize=1)
def _cmf_1nm() -> np.ndarray:
    import colour

    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    shape = colour.SpectralShape(LAMBDA_MIN, LAMBDA_MAX, _STEP)
    return np.asarray(cmfs.copy().align(shape).values, dtype=np.float64)


@functools.cache
def _illuminant_1nm(name: str) -> np.ndarray:
    import colour

    shape = colour.SpectralShape(LAMBDA_MIN, LAMBDA_MAX, _STEP)
    name = _canonical(name)
    if name == "E":
        values = np.ones(_COUNT)
    elif name == "D65":
        # tabulated 300-780 nm in colour; CIE extends it to 830 nm with nearly constant values,
        # colour's default constant extrapolation is used beyond 780 nm
        values = colour.SDS_ILLUMINANTS["D65"].copy().align(shape).values
    elif name == "A":
        values = colour.colorimetry.sd_CIE_standard_illuminant_A(shape).values
    elif name in ILLUMINANTS:
        values = _cie_table(name, shape)
    else:
        raise ValueError(f"unknown illuminant {name!r} (allowed: {', '.join(ILLUMINANTS)})")
    values = np.asarray(values, dtype=np.float64)
    ybar = _cmf_1nm()[:, 1]
    return values * (ybar.sum() / (values * ybar).sum())  # Y = 1


def light_grid() -> np.ndarray:
    """The 1 nm grid of the light-spectrum table, :data:`LIGHT_RANGE_NM` inclusive."""
    return grid(_STEP, LIGHT_MIN_NM, LAMBDA_MAX)


def _cie_table(name: str, shape) -> np.ndarray:
    """colour-science's CIE illuminant ``name`` on ``shape``: its own interpolation inside its
    tabulated range, zero below it (no invented ultraviolet), constant above it."""
    import colour

    if name == "E":
        return np.ones(len(shape.wavelengths))
    if name == "A":
        return np.asarray(colour.colorimetry.sd_CIE_standard_illuminant_A(shape).values)
    sd = colour.SDS_ILLUMINANTS[name]
    values = np.asarray(sd.copy().align(shape).values, dtype=np.float64)
    values[shape.wavelengths < sd.shape.start - 1e-9] = 0.0
    return values


def _y_of(values_visible: np.ndarray) -> float:
    """Y (luminance normalisation) of a spectrum on the 1 nm colour grid, as _illuminant_1nm."""
    ybar = _cmf_1nm()[:, 1]
    return float((values_visible * ybar).sum() / ybar.sum())


@functools.cache
def _light_1nm(name: str) -> np.ndarray:
    """Row ``name`` of the light-spectrum table on :func:`light_grid` (float64)."""
    import colour

    if name in UV_LAMPS:
        centre, fwhm = UV_LAMPS[name]
        wl = light_grid()
        g = np.exp(-0.5 * ((wl - centre) / (fwhm / (2.0 * np.sqrt(2.0 * np.log(2.0))))) ** 2)
        if name == "UV254":
            g[wl >= LAMBDA_MIN] = 0.0  # filtered: no visible mercury lines (module docstring)
        # radiant power of D65 at Y = 1 over the colour range (trapezoid, 1 nm)
        target = np.trapezoid(_illuminant_1nm("D65"), grid())
        return g * (target / np.trapezoid(g, wl))
    if name in _MEASURED:
        return _MEASURED[name]
    # CIE illuminant: 360-830 nm exactly as the colour tables have always been; the
    # ultraviolet part below 360 nm from the same data, scaled by the same factor
    visible = _illuminant_1nm(name)
    if name == "E":
        uv = np.ones(_UV_COUNT)
    else:
        raw_visible = _cie_table(name, colour.SpectralShape(LAMBDA_MIN, LAMBDA_MAX, _STEP))
        scale = visible[_COUNT // 2] / raw_visible[_COUNT // 2] if raw_visible[_COUNT // 2] > 0 else 0.0
        full = _cie_table(name, colour.SpectralShape(LIGHT_MIN_NM, LAMBDA_MAX, _STEP))
        uv = full[:_UV_COUNT] * scale
    return np.concatenate([uv, visible])


def light_spectrum_names() -> list[str]:
    """Every name a light's ``spectrum`` accepts: CIE illuminants, UV lamps, registered spectra."""
    return [*ILLUMINANTS, *_ALIASES, *UV_LAMPS, *_MEASURED]


def _canonical(name: str) -> str:
    return _ALIASES.get(name, name)


def light_spectrum_row(name: str, *, file: str | None = None, field: str = "light.spectrum") -> int:
    """Row of light spectrum ``name`` in ``SpectralTables.illuminants`` (InputError if unknown)."""
    from .validate import choice

    key = _canonical(name) if isinstance(name, str) else name
    choice(key, [*ILLUMINANTS, *UV_LAMPS, *_MEASURED], file=file, field=field)
    return _row_names().index(key)


def _row_names() -> list[str]:
    return [*ILLUMINANTS, *UV_LAMPS, *_MEASURED]


def register_spectrum(
    wavelength_nm,
    values,
    *,
    normalize: str = "luminance",
    file: str | None = None,
    field: str = "light.spectrum",
) -> str:
    """Add a measured light spectrum (relative spectral power at ``wavelength_nm``, nm,
    increasing) to the light table and return its name (``"measured:<hash>"``, the same for the
    same data).  Linear interpolation on the 1 nm light grid, zero outside the data.
    ``normalize``: ``"luminance"`` (Y = 1, like the CIE illuminants; needs visible power) or
    ``"power"`` (the radiant power of the UV lamps, for spectra without visible light)."""
    import hashlib

    from . import validate as val
    from .errors import InputError

    val.choice(normalize, ("luminance", "power"), file=file, field=field + ".normalize")
    try:
        wl = np.asarray(wavelength_nm, dtype=np.float64)
        v = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("must be lists of numbers", file=file, field=field, value=wavelength_nm) from None
    if wl.ndim != 1 or v.shape != wl.shape or len(wl) < 2:
        raise InputError(
            "wavelength_nm and values must be lists of the same length >= 2",
            file=file,
            field=field,
            value=f"{wl.shape} and {v.shape}",
        )
    if not (np.isfinite(wl).all() and np.isfinite(v).all()):
        raise InputError("must be finite numbers", file=file, field=field)
    if np.any(np.diff(wl) <= 0):
        raise InputError("must increase strictly", file=file, field=field + ".wavelength_nm")
    if wl[0] < 100.0 or wl[-1] > 5000.0:
        raise InputError(
            "out of range",
            file=file,
            field=field + ".wavelength_nm",
            value=[wl[0], wl[-1]],
            allowed="100-5000 nm",
        )
    if v.min() < 0:
        raise InputError("must be >= 0", file=file, field=field + ".values", value=float(v.min()))
    lg = light_grid()
    row = np.interp(lg, wl, v, left=0.0, right=0.0)
    if normalize == "luminance":
        y = _y_of(row[_UV_COUNT:])
        if not y > 0:
            raise InputError(
                'has no visible light (Y = 0); use normalize = "power"', file=file, field=field + ".values"
            )
        row = row / y
    else:
        p = np.trapezoid(row, lg)
        if not p > 0:
            raise InputError("has no power inside 240-830 nm", file=file, field=field + ".values")
        row = row * (np.trapezoid(_illuminant_1nm("D65"), grid()) / p)
    digest = hashlib.sha1(row.astype(np.float32).tobytes()).hexdigest()[:12]
    name = f"measured:{digest}"
    if name not in _MEASURED:
        _MEASURED[name] = row
        _REGISTRY_VERSION[0] += 1
    return name


def light_spectrum(name: str, wavelength_nm) -> np.ndarray:
    """Relative spectral power of light spectrum ``name`` (any :func:`light_spectrum_names`)
    at ``wavelength_nm`` (linear interpolation of its 1 nm row; zero outside 240-830 nm)."""
    light_spectrum_row(name, field="spectrum")
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    return np.interp(wl, light_grid(), _light_1nm(_canonical(name)), left=0.0, right=0.0)


def cmf(wavelength_nm) -> np.ndarray:
    """CIE 1931 2 degree colour-matching functions at ``wavelength_nm`` (linear interpolation of
    the 1 nm table; zero outside 360-830 nm).  Shape ``(..., 3)``."""
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    table = _cmf_1nm()
    g = grid()
    return np.stack([np.interp(wl, g, table[:, c], left=0.0, right=0.0) for c in range(3)], axis=-1)


def illuminant(name: str, wavelength_nm) -> np.ndarray:
    """Relative spectral power of CIE illuminant ``name`` (:data:`ILLUMINANTS`, e.g. "E", "D65",
    "A"), scaled to Y = 1, over the colour range 360-830 nm (zero outside it; the ultraviolet
    part of a light is :func:`light_spectrum`)."""
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    return np.interp(wl, grid(), _illuminant_1nm(name), left=0.0, right=0.0)


def spectrum_to_xyz(wavelength_nm, values) -> np.ndarray:
    """XYZ of a sampled spectrum (trapezoidal rule on its own grid, luminance normalisation).

    ``values`` may have extra leading axes; the last axis runs over ``wavelength_nm``.
    """
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    s = np.asarray(values, dtype=np.float64)
    c = cmf(wl)
    norm = _cmf_1nm()[:, 1].sum() * _STEP
    integrand = s[..., :, None] * c
    return np.trapezoid(integrand, wl, axis=-2) / norm


# ----------------------------------------------------------------------------------------------
# Device tables


@wp.struct
class SpectralTables:
    """Tables for spectral kernels, 1 nm spacing from ``lambda_min``.

    cmf:          (count,) vec3f, CIE 1931 xbar, ybar, zbar divided by integral(ybar)
    illuminants:  (rows, light_count) float, the light spectra on the light grid (1 nm from
                  ``light_min``, module docstring): CIE illuminants (Y = 1; E, D65, A in rows
                  0, 1, 2), UV lamps, registered spectra (rows: ``light_spectrum_row``)
    srgb_basis:   (light_count,) vec3f, the Mallett–Yuksel sRGB basis spectra alone (they sum
                  to 1) on the light grid, constant outside their 380-780 nm table
    cdf:          (count,) float, CDF of the importance pdf over the bins [l_j, l_j + 1 nm)
    bin_pdf:      (count,) float, importance pdf (1/nm) on each bin
    rgb3_weight:  (3,) vec3f, XYZ weight of each rgb3 wavelength
    rgb3_wavelength: vec3f, the three rgb3 wavelengths (nm)
    rgb_basis:    (count,) vec3f, D65 times the Mallett–Yuksel sRGB basis spectra (emission
                  spectrum of a linear-sRGB colour; (1, 1, 1) gives D65 with Y = 1)
    """

    cmf: wp.array(dtype=wp.vec3f)
    illuminants: wp.array2d(dtype=wp.float32)
    cdf: wp.array(dtype=wp.float32)
    bin_pdf: wp.array(dtype=wp.float32)
    rgb3_weight: wp.array(dtype=wp.vec3f)
    rgb3_wavelength: wp.vec3f
    rgb_basis: wp.array(dtype=wp.vec3f)
    srgb_basis: wp.array(dtype=wp.vec3f)
    lambda_min: float
    lambda_max: float
    count: int
    light_min: float
    light_count: int


def _importance_pdf_bins() -> np.ndarray:
    """Piecewise-constant pdf over the 1 nm bins, proportional to xbar+ybar+zbar (bin average)."""
    s = _cmf_1nm().sum(axis=1)
    # bins [l_j, l_j+1) for j < count-1; the last grid point closes the range
    b = 0.5 * (s[:-1] + s[1:])
    b = np.maximum(b, 1e-4 * b.max())  # keep every wavelength reachable (pdf > 0 everywhere)
    return b / (b.sum() * _STEP)


def _rgb3_weights() -> np.ndarray:
    """XYZ weight per rgb3 wavelength: w_c = k_c cmf(l_c) with the k_c that make a constant
    spectrum exact, sum_c w_c = XYZ[S = 1] (the CIE RGB primaries' tristimulus columns scaled to
    the equal-energy white)."""
    m = cmf(np.asarray(RGB3_WAVELENGTHS))  # row c = xbar, ybar, zbar at l_c
    xyz_e = _cmf_1nm().sum(axis=0) / _cmf_1nm()[:, 1].sum()
    k = np.linalg.solve(m.T, xyz_e)
    return m * k[:, None]  # row c = weight of wavelength c


@functools.lru_cache(maxsize=1)
def _srgb_basis_light() -> np.ndarray:
    """The Mallett–Yuksel sRGB basis (colour-science) on the light grid, extended as constants."""
    import colour

    basis = colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019
    wl = light_grid()
    return np.stack([np.interp(wl, basis.wavelengths, basis.values[:, c]) for c in range(3)], axis=-1)


@functools.lru_cache(maxsize=1)
def _rgb_basis_1nm() -> np.ndarray:
    """D65 x the sRGB basis spectra of Mallett & Yuksel 2019 (colour-science), 360-830 nm.

    The three basis functions sum to 1 at every wavelength, so (1, 1, 1) is D65 (Y = 1); they are
    tabulated 380-780 nm and extended as constants."""
    import colour

    basis = colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019
    wl = grid()
    b = np.stack([np.interp(wl, basis.wavelengths, basis.values[:, c]) for c in range(3)], axis=-1)
    return b * _illuminant_1nm("D65")[:, None]


def rgb_to_spectrum(rgb, wavelength_nm) -> np.ndarray:
    """Emission spectrum of linear-sRGB colours ``(..., 3)`` at ``wavelength_nm`` (broadcast):
    D65 times the Mallett–Yuksel basis; its XYZ is close to the colour's (exact for greys)."""
    wl = np.asarray(wavelength_nm, dtype=np.float64)
    b = _rgb_basis_1nm()
    basis = np.stack([np.interp(wl, grid(), b[:, c], left=0.0, right=0.0) for c in range(3)], axis=-1)
    return (np.asarray(rgb, dtype=np.float64) * basis).sum(axis=-1)


@functools.lru_cache(maxsize=8)
def _tables_for(device_alias: str, version: int) -> SpectralTables:
    dev = get_device(device_alias)
    t = SpectralTables()
    cm = _cmf_1nm() / _cmf_1nm()[:, 1].sum() / _STEP
    t.cmf = wp.array(cm.astype(np.float32), dtype=wp.vec3f, device=dev)
    ill = np.stack([_light_1nm(n) for n in _row_names()])
    t.illuminants = wp.array(ill.astype(np.float32), dtype=wp.float32, device=dev)
    pdf = _importance_pdf_bins()
    cdf = np.concatenate([[0.0], np.cumsum(pdf * _STEP)])
    cdf /= cdf[-1]
    t.cdf = wp.array(cdf.astype(np.float32), dtype=wp.float32, device=dev)
    t.bin_pdf = wp.array(np.concatenate([pdf, [pdf[-1]]]).astype(np.float32), dtype=wp.float32, device=dev)
    t.rgb3_weight = wp.array(_rgb3_weights().astype(np.float32), dtype=wp.vec3f, device=dev)
    t.rgb3_wavelength = wp.vec3f(*RGB3_WAVELENGTHS)
    t.rgb_basis = wp.array(_rgb_basis_1nm().astype(np.float32), dtype=wp.vec3f, device=dev)
    t.srgb_basis = wp.array(_srgb_basis_light().astype(np.float32), dtype=wp.vec3f, device=dev)
    t.lambda_min = LAMBDA_MIN
    t.lambda_max = LAMBDA_MAX
    t.count = _COUNT
    t.light_min = LIGHT_MIN_NM
    t.light_count = _LIGHT_COUNT
    return t


def spectral_tables(device=None) -> SpectralTables:
    """The shared :class:`SpectralTables` on ``device`` (built once per device, and again after
    :func:`register_spectrum` added a row: get the tables after the scene's lights are made)."""
    return _tables_for(get_device(device).alias, _REGISTRY_VERSION[0])


def strategy_id(name: str) -> int:
    """Kernel id of a sampling strategy name."""
    try:
        return STRATEGIES[name]
    except KeyError:
        raise InputError(
            "unknown spectral sampling", field="strategy", value=name, allowed=", ".join(STRATEGIES)
        ) from None


# ----------------------------------------------------------------------------------------------
# Kernel-side functions


@wp.func
def _table_coord(t: SpectralTables, wavelength: float):
    x = (wavelength - t.lambda_min) / 1.0
    x = wp.clamp(x, 0.0, float(t.count - 1))
    j = wp.min(int(x), t.count - 2)
    return j, x - float(j)


@wp.func
def cmf_xyz(t: SpectralTables, wavelength: float):
    """CIE 1931 xbar, ybar, zbar at ``wavelength`` (nm), divided by integral(ybar); zero outside
    the table."""
    if wavelength < t.lambda_min or wavelength > t.lambda_max:
        return wp.vec3f(0.0, 0.0, 0.0)
    j, f = _table_coord(t, wavelength)
    return t.cmf[j] * (1.0 - f) + t.cmf[j + 1] * f


@wp.func
def _light_coord(t: SpectralTables, wavelength: float):
    # the light grid starts at an integer wavelength, so x and f are exact in float32 and the
    # interpolation weights inside 360-830 nm are bit for bit those of the colour grid
    x = (wavelength - t.light_min) / 1.0
    x = wp.clamp(x, 0.0, float(t.light_count - 1))
    j = wp.min(int(x), t.light_count - 2)
    return j, x - float(j)


@wp.func
def illuminant_value(t: SpectralTables, which: int, wavelength: float):
    """Relative power of light-spectrum row ``which`` (E=0, D65=1, A=2, others by
    ``light_spectrum_row``) at ``wavelength`` (nm): zero outside the light range 240-830 nm."""
    if wavelength < t.light_min or wavelength > t.lambda_max:
        return 0.0
    j, f = _light_coord(t, wavelength)
    return t.illuminants[which, j] * (1.0 - f) + t.illuminants[which, j + 1] * f


@wp.func
def srgb_basis_value(t: SpectralTables, wavelength: float):
    """The three Mallett–Yuksel sRGB basis spectra at ``wavelength`` (they sum to 1; zero
    outside the light range)."""
    if wavelength < t.light_min or wavelength > t.lambda_max:
        return wp.vec3f(0.0, 0.0, 0.0)
    j, f = _light_coord(t, wavelength)
    return t.srgb_basis[j] * (1.0 - f) + t.srgb_basis[j + 1] * f


@wp.func
def light_spectrum_value(t: SpectralTables, spectrum: int, rgb: wp.vec3f, wavelength: float):
    """Spectral radiance at ``wavelength`` (nm) of a light of linear-sRGB colour ``rgb`` whose
    white is light-spectrum row ``spectrum``: dot(rgb, basis(l)) S(l) -- the one law of every
    lamp and RGB environment.  ``spectrum`` < 0: D65, read from the D65 x basis table inside
    the colour range (:func:`rgb_spectrum_value`, the lights' values before light spectra
    existed, bit for bit) and as basis x D65 below it (D65's ultraviolet)."""
    if spectrum < 0:
        if wavelength >= t.lambda_min:
            return rgb_spectrum_value(t, rgb, wavelength)
        return wp.dot(rgb, srgb_basis_value(t, wavelength)) * illuminant_value(t, 1, wavelength)
    return wp.dot(rgb, srgb_basis_value(t, wavelength)) * illuminant_value(t, spectrum, wavelength)


@wp.func
def rgb_spectrum_value(t: SpectralTables, rgb: wp.vec3f, wavelength: float):
    """Spectral radiance at ``wavelength`` of an emitter of linear-sRGB colour ``rgb``
    (D65 x Mallett–Yuksel basis; see :func:`rgb_to_spectrum`)."""
    if wavelength < t.lambda_min or wavelength > t.lambda_max:
        return 0.0
    j, f = _table_coord(t, wavelength)
    return wp.dot(rgb, t.rgb_basis[j] * (1.0 - f) + t.rgb_basis[j + 1] * f)


@wp.func
def _sample_importance(t: SpectralTables, u: float):
    # binary search for the bin j with cdf[j] <= u < cdf[j+1]
    lo = int(0)
    hi = t.count - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if t.cdf[mid] <= u:
            lo = mid
        else:
            hi = mid
    c0 = t.cdf[lo]
    c1 = t.cdf[lo + 1]
    f = float(0.5)
    if c1 > c0:
        f = wp.clamp((u - c0) / (c1 - c0), 0.0, 1.0)
    wl = t.lambda_min + float(lo) + f
    return wl, t.bin_pdf[lo]


@wp.func
def sample_wavelength(t: SpectralTables, strategy: int, u: float, index: int, count: int):
    """Wavelength (nm) of sample ``index`` of ``count`` with uniform random ``u`` in [0, 1), and
    its ``xyz_weight`` (see module docstring).  For ``rgb3`` ``count`` must be 3 and ``u`` is
    unused; for ``stratified`` ``index`` selects the stratum."""
    width = t.lambda_max - t.lambda_min
    inv_n = 1.0 / float(count)
    if strategy == STRATEGY_RGB3:
        c = wp.clamp(index, 0, 2)
        return t.rgb3_wavelength[c], t.rgb3_weight[c]
    if strategy == STRATEGY_IMPORTANCE:
        wl, pdf = _sample_importance(t, u)
        return wl, cmf_xyz(t, wl) * (inv_n / pdf)
    if strategy == STRATEGY_STRATIFIED:
        wl = t.lambda_min + (float(index) + u) * width * inv_n
        return wl, cmf_xyz(t, wl) * (width * inv_n)
    # uniform
    wl = t.lambda_min + u * width
    return wl, cmf_xyz(t, wl) * (width * inv_n)


@wp.kernel
def _sample_kernel(
    offset: int,
    u: wp.array(dtype=wp.float32),
    index: wp.array(dtype=wp.int32),
    t: SpectralTables,
    strategy: int,
    count: int,
    wavelength: wp.array(dtype=wp.float32),
    weight: wp.array(dtype=wp.vec3f),
):
    i = wp.tid() + offset
    wl, w = sample_wavelength(t, strategy, u[i], index[i], count)
    wavelength[i] = wl
    weight[i] = w


@wp.kernel
def _cmf_kernel(
    offset: int,
    wavelength: wp.array(dtype=wp.float32),
    t: SpectralTables,
    out: wp.array(dtype=wp.vec3f),
):
    i = wp.tid() + offset
    out[i] = cmf_xyz(t, wavelength[i])


@wp.kernel
def _light_kernel(
    offset: int,
    spectrum: wp.array(dtype=wp.int32),
    rgb: wp.array(dtype=wp.vec3f),
    wavelength: wp.array(dtype=wp.float32),
    t: SpectralTables,
    out: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    out[i] = light_spectrum_value(t, spectrum[i], rgb[i], wavelength[i])


def light_values(spectrum, rgb, wavelength_nm, *, device=None) -> np.ndarray:
    """NumPy wrapper of :func:`light_spectrum_value`: ``spectrum`` a name (or a row, -1 for the
    default D65 lights), ``rgb`` linear sRGB ``(..., 3)``, broadcast with ``wavelength_nm``."""
    row = light_spectrum_row(spectrum, field="spectrum") if isinstance(spectrum, str) else spectrum
    (out,) = elementwise(
        _light_kernel,
        [(row, wp.int32), (rgb, wp.vec3f), (wavelength_nm, wp.float32)],
        [wp.float32],
        extra=[spectral_tables(device)],
        device=device,
    )
    return out


@device_function(sample_wavelength)
def sample_wavelengths(strategy: str, u, index, count: int, *, device=None) -> tuple[np.ndarray, np.ndarray]:
    """NumPy wrapper of :func:`sample_wavelength`: returns ``(wavelength_nm, xyz_weight)``.

    ``u`` (uniform in [0, 1)) and ``index`` (sample number, 0..count-1) broadcast together.
    """
    sid = strategy_id(strategy)
    if isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 1:
        raise InputError("must be an integer >= 1", field="count", value=count)
    if strategy == "rgb3" and count != 3:
        raise InputError("rgb3 sampling uses exactly 3 wavelengths", field="count", value=count, allowed="3")
    ua = finite_array(u, field="u").astype(np.float64)
    if np.any((ua < 0.0) | (ua > 1.0)):
        raise InputError("must lie in [0, 1)", field="u", value=float(ua[(ua < 0) | (ua > 1)].flat[0]))
    ia = finite_array(index, field="index")
    if np.any(ia != np.round(ia)) or np.any((ia < 0) | (ia >= count)):
        bad = ia[(ia != np.round(ia)) | (ia < 0) | (ia >= count)].flat[0]
        raise InputError(
            "must be an integer sample number", field="index", value=bad.item(), allowed=f"0..{count - 1}"
        )
    wl, w = elementwise(
        _sample_kernel,
        [(ua, wp.float32), (ia.astype(np.int64), wp.int32)],
        [wp.float32, wp.vec3f],
        extra=[spectral_tables(device), sid, int(count)],
        device=device,
    )
    return wl, w


@device_function(cmf_xyz)
def cmf_device(wavelength_nm, *, device=None) -> np.ndarray:
    """NumPy wrapper of the kernel-side :func:`cmf_xyz` (normalised by integral ybar, per nm)."""
    (out,) = elementwise(
        _cmf_kernel,
        [(finite_array(wavelength_nm, field="wavelength_nm"), wp.float32)],
        [wp.vec3f],
        extra=[spectral_tables(device)],
        device=device,
    )
    return out
