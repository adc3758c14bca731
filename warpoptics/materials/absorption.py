"""Absorption spectra: bands, tables, RGB absorbances (Guy & Soler 2004, eq. 9) and unit conversions.

An :class:`AbsorptionSpectrum` is alpha(λ): the base-e absorption coefficient in 1/mm (docs/conventions.md),
tabulated and linearly interpolated.  Build one from Gaussian / Lorentzian bands
(:meth:`AbsorptionSpectrum.from_bands`), from a table in any of the supported units
(:meth:`AbsorptionSpectrum.from_table`), or from an RGB absorbance triplet by inverting eq. 9 of
Guy & Soler 2004 onto a smooth non-negative basis (:func:`spectrum_from_rgb`), so that
``rgb_absorbance(spectrum_from_rgb(K)) == K``.  :func:`with_absorption` gives a material the
extinction coefficient k = alpha λ / 4π of a spectrum (K^o, K^e for a uniaxial crystal).

Units (all helpers are ``@wp.func`` with NumPy wrappers):
- alpha (1/mm, base e) = 4 pi k / λ_mm (Weidlich & Wilkie 2009, eq. 3);
- decadic absorbance per cm A_10 (the chemist's absorbance of a 1 cm cell):
  alpha [1/mm] = ln(10) · A_10 / 10.

The Guy & Soler 2004 §6.1 table (:data:`GUY_SOLER_2004_GEMS`): the paper states no unit for its absorbances
(K_r, K_g, K_b), and its worked example ("L = 1 cm and κ = 0.4" giving a 0.00125 % error) is not
self-consistent (κL = 0.4 gives ~8 %; 0.00125 % needs κL ~ 0.005).  warpoptics reads them as base-e
absorbance per mm, alpha (1/mm) = K (:data:`GUY_SOLER_2004_ALPHA_PER_MM`, the one place to change this
reading): blue sapphire then has alpha ~ 0.3/mm in the red, the order of measured values for
natural blue sapphire (decadic absorbance 1–5 per cm, i.e. alpha 0.2–1.2 /mm), and the table's
"light blue", "yellow green" colours appear in stones of a few mm; read per cm, a 6 mm sapphire
renders almost grey.  Note that the table lists sapphire's *e* triplet first.

References
----------
- S. Guy, C. Soler, "Graphics gems revisited", ACM TOG 23(3), 2004: eq. 6 (Bouguer–Lambert),
  eq. 7 (pleochroic absorbance, after Born & Wolf), eq. 9 (RGB absorbance), §6.1 (gem table).
- A. Weidlich, A. Wilkie, "Anomalous dispersion in predictive rendering", CGF 28(4), 2009, eq. 3–4.
- W. D. Wright (1928), J. Guild (1931): CIE 1931 2° RGB colour matching functions (primaries
  700, 546.1, 435.8 nm), as tabulated in colour-science ("Wright & Guild 1931 2 Degree RGB CMFs").
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import warp as wp

from .. import device as _device
from ..device import device_function
from ..errors import InputError
from ..optics.absorption import pleochroic_kappa
from .datasets.guy_soler_2004 import GUY_SOLER_2004_ALPHA_PER_MM, GUY_SOLER_2004_GEMS
from .dispersion import Biaxial, Material, Uniaxial, rgb3_alpha_of, with_absorption_k
from .rgb_weights import rgb_weights
from .units import (
    alpha_from_absorbance_per_cm,
    alpha_from_k,
    finite_array,
    k_from_alpha,
    nonnegative_array,
    wavelength_array,
)

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "band_profile",
    "bands_alpha",
    "BAND_SHAPES",
    "pleochroic_alpha",
    "Band",
    "AbsorptionSpectrum",
    "rgb_absorbance",
    "spectrum_from_rgb",
    "rgb3_alpha_of",
    "with_absorption",
    "guy_soler_2004_spectra",
]

# ----------------------------------------------------------------------------------------------
# Device code
# ----------------------------------------------------------------------------------------------


@wp.func
def band_profile(shape: int, wavelength_nm: float, center_nm: float, width_nm: float):
    """Unit-peak band shape: 0 Gaussian exp(−(λ−c)²/2w²) (w = σ), 1 Lorentzian w²/((λ−c)² + w²)
    (w = half width at half maximum), 2 Gaussian in wavenumber exp(−(c²/λ − c)²/2w²), whose σ in
    wavenumber is w/c² (w: σ in nm at the centre), the shape of crystal-field bands measured on an
    energy scale (Burns 1993, ch. 3)."""
    x = wavelength_nm - center_nm
    if shape == 0:
        return wp.exp(-0.5 * x * x / (width_nm * width_nm))
    if shape == 2:
        y = center_nm * (center_nm / wavelength_nm - 1.0) / width_nm
        return wp.exp(-0.5 * y * y)
    return width_nm * width_nm / (x * x + width_nm * width_nm)


@wp.func
def bands_alpha(
    wavelength_nm: float,
    shape: wp.array(dtype=wp.int32),
    center: wp.array(dtype=wp.float32),
    width: wp.array(dtype=wp.float32),
    peak: wp.array(dtype=wp.float32),
):
    """The sum of bands ``peak · band_profile`` at one wavelength (1/mm)."""
    s = float(0.0)  # noqa: UP018 (a dynamic Warp variable, mutated in the loop)
    for b in range(center.shape[0]):
        s += peak[b] * band_profile(shape[b], wavelength_nm, center[b], width[b])
    return s


@wp.kernel
def _bands_kernel(
    offset: int,
    wavelength_nm: wp.array(dtype=wp.float32),
    shape: wp.array(dtype=wp.int32),
    center: wp.array(dtype=wp.float32),
    width: wp.array(dtype=wp.float32),
    peak: wp.array(dtype=wp.float32),
    out: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    out[i] = bands_alpha(wavelength_nm[i], shape, center, width, peak)


@wp.kernel
def _pleochroic_kernel(
    offset: int,
    alpha_o: wp.array(dtype=wp.float32),
    alpha_e: wp.array(dtype=wp.float32),
    n_o: wp.array(dtype=wp.float32),
    n_e: wp.array(dtype=wp.float32),
    cos_theta: wp.array(dtype=wp.float32),
    out: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    out[i] = pleochroic_kappa(cos_theta[i], alpha_o[i], alpha_e[i], n_o[i], n_e[i])


# ----------------------------------------------------------------------------------------------
# NumPy wrappers
# ----------------------------------------------------------------------------------------------


@device_function(pleochroic_kappa)
def pleochroic_alpha(alpha_o, alpha_e, n_o, n_e, cos_theta, *, device=None) -> np.ndarray:
    """e-ray absorption (Guy & Soler 2004 eq. 7); the law is ``optics.absorption.pleochroic_kappa``."""
    (out,) = _device.elementwise(
        _pleochroic_kernel,
        [
            (nonnegative_array("alpha_o", alpha_o), wp.float32),
            (nonnegative_array("alpha_e", alpha_e), wp.float32),
            (finite_array("n_o", n_o), wp.float32),
            (finite_array("n_e", n_e), wp.float32),
            (finite_array("cos_theta", cos_theta), wp.float32),
        ],
        [wp.float32],
        device=device,
    )
    return out


# ----------------------------------------------------------------------------------------------
# Spectra
# ----------------------------------------------------------------------------------------------

#: band shape name -> the ``shape`` code of ``band_profile``
BAND_SHAPES = {"gaussian": 0, "lorentzian": 1, "gaussian_wavenumber": 2}
_SHAPES = BAND_SHAPES


# the largest band peak (1/mm): a metal's is ~1e5; above ~3e38 float32 tables overflow to inf
_MAX_ALPHA = 1e9


@dataclass(frozen=True)
class Band:
    """One absorption band: peak alpha (1/mm) at ``center_nm``; ``width_nm`` is σ for a Gaussian,
    the half width at half maximum for a Lorentzian, σ at the centre (in nm) for a Gaussian in
    wavenumber (``band_profile``)."""

    center_nm: float
    width_nm: float
    peak_alpha_per_mm: float
    shape: str = "gaussian"

    def __post_init__(self):
        if not isinstance(self.shape, str) or self.shape not in _SHAPES:
            raise InputError(
                "unknown band shape", field="shape", value=self.shape, allowed=", ".join(_SHAPES)
            )
        for name in ("center_nm", "width_nm", "peak_alpha_per_mm"):
            v = getattr(self, name)
            if not math.isfinite(v):
                raise InputError("must be finite", field=name, value=v)
        if self.center_nm <= 0 or self.width_nm <= 0:
            raise InputError(
                "band centre and width must be > 0 nm",
                field="center_nm/width_nm",
                value=(self.center_nm, self.width_nm),
            )
        if self.peak_alpha_per_mm > _MAX_ALPHA:
            raise InputError(
                "band peak too large (an absorption depth below a picometre)",
                field="peak_alpha_per_mm",
                value=self.peak_alpha_per_mm,
                allowed=f"<= {_MAX_ALPHA:g} 1/mm",
            )
        if self.peak_alpha_per_mm < 0:
            raise InputError(
                "band peak must be >= 0 (negative absorption)",
                field="peak_alpha_per_mm",
                value=self.peak_alpha_per_mm,
            )


class AbsorptionSpectrum:
    """alpha(λ) in 1/mm (base e), tabulated at increasing wavelengths (nm), linear in between,
    zero outside the table."""

    def __init__(self, wavelength_nm, alpha_per_mm, *, name: str = "absorption", source: str = "") -> None:
        lam = wavelength_array(wavelength_nm).reshape(-1)
        a = nonnegative_array("alpha", alpha_per_mm).reshape(-1)
        if lam.shape != a.shape or lam.size < 2:
            raise InputError(
                "absorption table needs >= 2 wavelengths and as many values",
                field="alpha",
                value=(lam.size, a.size),
            )
        order = np.argsort(lam)
        lam, a = lam[order], a[order]
        if np.any(np.diff(lam) <= 0):
            raise InputError("repeated wavelength in absorption table", field="wavelength_nm")
        self.wavelength_nm = lam
        self.alpha_per_mm = a
        self.name = name
        self.source = source

    @classmethod
    def from_bands(
        cls,
        bands: Sequence[Band],
        *,
        wavelength_range_nm: tuple[float, float] = (300.0, 900.0),
        step_nm: float = 1.0,
        name: str = "bands",
        source: str = "",
        device=None,
    ) -> AbsorptionSpectrum:
        """Sum of bands, tabulated every ``step_nm`` over ``wavelength_range_nm``."""
        bands = list(bands)
        lo, hi = wavelength_range_nm
        if not (0 < lo < hi) or step_nm <= 0:
            raise InputError("bad wavelength grid", field="wavelength_range_nm", value=(lo, hi, step_nm))
        lam = np.arange(lo, hi + 0.5 * step_nm, step_nm)
        if not bands:
            return cls(lam, np.zeros_like(lam), name=name, source=source)
        dev = _device.get_device(device)
        arrs = (
            wp.array(np.array([_SHAPES[b.shape] for b in bands], np.int32), dtype=wp.int32, device=dev),
            wp.array(np.array([b.center_nm for b in bands], np.float32), dtype=wp.float32, device=dev),
            wp.array(np.array([b.width_nm for b in bands], np.float32), dtype=wp.float32, device=dev),
            wp.array(
                np.array([b.peak_alpha_per_mm for b in bands], np.float32), dtype=wp.float32, device=dev
            ),
        )
        (alpha,) = _device.elementwise(
            _bands_kernel, [(lam, wp.float32)], [wp.float32], extra=arrs, device=dev
        )
        return cls(lam, np.maximum(alpha, 0.0), name=name, source=source)

    @classmethod
    def from_table(
        cls, wavelength_nm, values, *, unit: str = "alpha_per_mm", name: str = "table", source: str = ""
    ) -> AbsorptionSpectrum:
        """From a table in ``unit``: "alpha_per_mm" (base e), "k" (extinction coefficient),
        "absorbance_per_cm" (decadic) or "alpha_per_cm" (base e)."""
        lam = wavelength_array(wavelength_nm)
        v = nonnegative_array(unit, values)
        if unit == "alpha_per_mm":
            a = v
        elif unit == "alpha_per_cm":
            a = v / 10.0
        elif unit == "k":
            a = alpha_from_k(v, lam)
        elif unit == "absorbance_per_cm":
            a = alpha_from_absorbance_per_cm(v)
        else:
            raise InputError(
                "unknown absorption unit",
                field="unit",
                value=unit,
                allowed="alpha_per_mm, alpha_per_cm, k, absorbance_per_cm",
            )
        return cls(lam, a, name=name, source=source)

    def alpha(self, wavelength_nm) -> np.ndarray:
        """alpha (1/mm) at ``wavelength_nm`` (linear interpolation, 0 outside the table)."""
        return np.interp(
            np.asarray(wavelength_nm, dtype=np.float64),
            self.wavelength_nm,
            self.alpha_per_mm,
            left=0.0,
            right=0.0,
        )

    def k(self, wavelength_nm=None, *, device=None) -> np.ndarray:
        """Extinction coefficient k = alpha λ / 4 pi (at the table's wavelengths if None)."""
        lam = self.wavelength_nm if wavelength_nm is None else np.asarray(wavelength_nm, dtype=np.float64)
        return k_from_alpha(self.alpha(lam), lam, device=device)

    def scaled(self, factor: float) -> AbsorptionSpectrum:
        if not (math.isfinite(factor) and factor >= 0):
            raise InputError("scale factor must be finite and >= 0", field="factor", value=factor)
        return AbsorptionSpectrum(
            self.wavelength_nm, self.alpha_per_mm * factor, name=self.name, source=self.source
        )

    def __repr__(self) -> str:
        return (
            f"AbsorptionSpectrum({self.name!r}, {self.wavelength_nm[0]:g}-{self.wavelength_nm[-1]:g} nm, "
            f"max alpha {self.alpha_per_mm.max():.4g}/mm)"
        )


# ----------------------------------------------------------------------------------------------
# Guy & Soler 2004 eq. 9 and its inversion
# ----------------------------------------------------------------------------------------------


def rgb_absorbance(spectrum, *, illuminant: str = "E", cmfs: str = "cie1931_rgb") -> np.ndarray:
    """(κ_r, κ_g, κ_b) of Guy & Soler 2004 eq. 9: κ_c = ∫ κ(λ) c̄(λ) S0(λ) dλ / ∫ c̄(λ) S0(λ) dλ.

    ``spectrum``: an :class:`AbsorptionSpectrum`, a callable κ(λ_nm), or a pair (λ_nm, κ).
    c̄: ``cmfs="cie1931_rgb"`` the CIE 1931 RGB colour matching functions (Wright & Guild;
    380–780 nm, 5 nm), as in the source; ``"srgb"`` the linear-sRGB ones (the renderer's rgb3
    channels).  S0: the white light, ``illuminant`` "E" (default), "D65" or "A"
    (warpoptics.spectra).  Units are those of κ.  Both CMF sets have negative lobes, so a narrow
    band can give a negative channel (see :func:`rgb3_alpha_of`).
    """
    lam, w = rgb_weights(illuminant, cmfs)
    if isinstance(spectrum, AbsorptionSpectrum):
        kappa = spectrum.alpha(lam)
    elif callable(spectrum):
        kappa = np.asarray(spectrum(lam), dtype=np.float64)
    else:
        x, y = spectrum
        kappa = np.interp(lam, np.asarray(x, np.float64), np.asarray(y, np.float64))
    return w @ kappa


def _bspline_basis(x: np.ndarray, knots_inner: np.ndarray) -> np.ndarray:
    """Clamped cubic B-spline basis (non-negative, partition of unity) at ``x``: (len(x), nb)."""
    from scipy.interpolate import BSpline

    t = np.concatenate([[knots_inner[0]] * 3, knots_inner, [knots_inner[-1]] * 3])
    nb = len(t) - 4
    out = np.empty((len(x), nb))
    for j in range(nb):
        c = np.zeros(nb)
        c[j] = 1.0
        out[:, j] = BSpline(t, c, 3, extrapolate=False)(x)
    return np.nan_to_num(out)


def spectrum_from_rgb(
    rgb,
    *,
    illuminant: str = "E",
    cmfs: str = "cie1931_rgb",
    wavelength_range_nm: tuple[float, float] = (360.0, 830.0),
    n_basis: int | None = None,
    name: str = "rgb",
    source: str = "",
) -> AbsorptionSpectrum:
    """A smooth, non-negative alpha(λ) whose eq. 9 RGB absorbance is ``rgb`` (1/mm).

    The spectrum is a cubic B-spline with ``n_basis`` coefficients c >= 0 on
    ``wavelength_range_nm`` minimising the roughness Σ (Δ²c)² (plus 1e-6 Σ c²) subject to
    W c = rgb, where W is eq. 9 applied to the basis (a quadratic programme, SLSQP).  It is
    tabulated at the CMF nodes (5 nm) so that :func:`rgb_absorbance` returns ``rgb`` to the
    solver tolerance (~1e-9 relative).  ``n_basis=None`` tries 12, 24 then 48 functions and
    keeps the smoothest that reaches the triplet (strongly peaked triplets need narrower ones).
    """
    target = nonnegative_array("rgb", rgb).reshape(-1)
    if target.shape != (3,):
        raise InputError("an RGB absorbance needs 3 values", field="rgb", value=rgb)
    tries = (12, 24, 48) if n_basis is None else (int(n_basis),)
    err = float("inf")
    for nb in tries:
        lam_tab, alpha, err = _invert_rgb(target, illuminant, cmfs, wavelength_range_nm, nb)
        if err <= 1e-6:
            return AbsorptionSpectrum(
                lam_tab, alpha, name=name, source=source or f"eq. 9 inversion of {tuple(target.tolist())}"
            )
    raise InputError(
        f"no smooth non-negative spectrum has this RGB absorbance under eq. 9 (residual {err:.2g})",
        field="rgb",
        value=tuple(target.tolist()),
    )


def _invert_rgb(target: np.ndarray, illuminant: str, cmfs: str, wavelength_range_nm, n_basis: int):
    """(λ table, alpha table, relative residual) of the eq. 9 inversion with ``n_basis`` B-splines."""
    from scipy.optimize import minimize

    lo, hi = wavelength_range_nm
    lam_cmf, w = rgb_weights(illuminant, cmfs)
    knots = np.linspace(lo, hi, n_basis - 2)
    lam_tab = np.union1d(np.arange(lo, hi + 1e-9, 5.0), lam_cmf)
    lam_tab = lam_tab[(lam_tab >= lo) & (lam_tab <= hi)]
    if np.all(target == 0):
        return lam_tab, np.zeros_like(lam_tab), 0.0
    basis_tab = _bspline_basis(lam_tab, knots)
    A = w @ _bspline_basis(lam_cmf, knots)  # (3, nb): eq. 9 of each basis function
    d2 = np.diff(np.eye(n_basis), 2, axis=0)
    H = d2.T @ d2 + 1e-6 * np.eye(n_basis)
    scale = float(np.max(target))
    tgt = target / scale
    x0 = np.full(n_basis, float(np.mean(tgt)))
    res = minimize(
        lambda c: float(c @ H @ c),
        x0,
        jac=lambda c: 2.0 * H @ c,
        method="SLSQP",
        bounds=[(0.0, None)] * n_basis,
        constraints=[{"type": "eq", "fun": lambda c: A @ c - tgt, "jac": lambda c: A}],
        options={"ftol": 1e-14, "maxiter": 500},
    )
    c = np.maximum(res.x, 0.0)
    err = float(np.max(np.abs(A @ c - tgt)))
    if not res.success:
        err = max(err, 1.0)
    return lam_tab, np.maximum(basis_tab @ c, 0.0) * scale, err


def with_absorption(
    mat: Material, absorption, *, name: str | None = None, source: str | None = None, device=None
) -> Material:
    """``mat`` with the extinction coefficient k = alpha λ/4π of ``absorption`` (an
    :class:`AbsorptionSpectrum`; for a :class:`Uniaxial`, a pair (K^o, K^e) or one spectrum for
    both; for a :class:`Biaxial`, a triple for D along X, Y, Z).  The real index is unchanged
    (see ``kramers_kronig.anomalous`` for Δn)."""
    if isinstance(mat, Biaxial):
        if isinstance(absorption, AbsorptionSpectrum):
            absorption = (absorption, absorption, absorption)
        sx, sy, sz = absorption
        return Biaxial(
            with_absorption(mat.alpha_channel, sx, device=device),
            with_absorption(mat.beta, sy, device=device),
            with_absorption(mat.gamma, sz, device=device),
            crystal_axes=mat.crystal_axes,
            name=name or mat.name,
            source=source or mat.source,
        )
    if isinstance(mat, Uniaxial):
        if isinstance(absorption, AbsorptionSpectrum):
            absorption = (absorption, absorption)
        so, se = absorption
        o = with_absorption(mat.ordinary, so, device=device)
        e = with_absorption(mat.extraordinary, se, device=device)
        return Uniaxial(o, e, optic_axis=mat.optic_axis, name=name or mat.name, source=source or mat.source)
    if not isinstance(absorption, AbsorptionSpectrum):
        raise InputError(
            "absorption must be an AbsorptionSpectrum", field="absorption", value=type(absorption).__name__
        )
    lo, hi = mat.wavelength_range_nm
    lam = absorption.wavelength_nm
    lam = np.unique(np.concatenate([[lo, hi], lam[(lam > lo) & (lam < hi)]]))
    k = k_from_alpha(absorption.alpha(lam), lam, device=device)
    return with_absorption_k(mat, lam, k, name=name, source=source)


# ----------------------------------------------------------------------------------------------
# The Guy & Soler 2004 §6.1 gem table
# ----------------------------------------------------------------------------------------------


def guy_soler_2004_spectra(name: str) -> tuple[AbsorptionSpectrum, AbsorptionSpectrum]:
    """(K^o(λ), K^e(λ)) in 1/mm for a gem of Guy & Soler's table, by the eq. 9 inversion of its triplets."""
    try:
        row = GUY_SOLER_2004_GEMS[name]
    except KeyError as exc:
        raise InputError(
            "not in Guy & Soler's table", field="name", value=name, allowed=", ".join(GUY_SOLER_2004_GEMS)
        ) from exc
    cache = _seed_cache.get(name)
    if cache is None:
        ko = np.asarray(row["K_o"]) * GUY_SOLER_2004_ALPHA_PER_MM
        so = spectrum_from_rgb(ko, name=f"{name} K^o", source="Guy & Soler 2004 §6.1, eq. 9 inversion")
        if row["K_e"] is None:
            se = so
        else:
            ke = np.asarray(row["K_e"]) * GUY_SOLER_2004_ALPHA_PER_MM
            se = spectrum_from_rgb(ke, name=f"{name} K^e", source="Guy & Soler 2004 §6.1, eq. 9 inversion")
        cache = (so, se)
        _seed_cache[name] = cache
    return cache


_seed_cache: dict[str, tuple[AbsorptionSpectrum, AbsorptionSpectrum]] = {}
