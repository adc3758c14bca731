"""Fluorescent media as data: a luminescent centre's excitation, emission and quantum yield.

A :class:`Fluorescence` describes one centre in a material (data in
:mod:`warpoptics.materials.datasets.fluorescence`):

- ``excitation``: alpha_x(l), the absorption coefficient (1/mm, base e) of the centre.  It is part
  of the material's absorption: :func:`with_fluorescence` adds it to the host's alpha(l), so that
  alpha_x <= alpha everywhere inside the material's range and a path segment's absorbed power
  splits into the centre's share alpha_x / alpha and the rest (heat);
- ``emission``: the spectrum of the re-emitted photons, a probability density over wavelength
  (1/nm, unit area over the light grid 240-830 nm of ``spectra.LIGHT_RANGE_NM``);
- ``quantum_yield``: photons emitted per photon the centre absorbs (0..1).

Emission is isotropic and unpolarized (a new source inside the stone, the transport is the
tracer's).  Energy: a photon absorbed at l_x and re-emitted at l_e carries l_x / l_e of its
energy, so the energy yield quantum_yield x l_x / <l_e> is below 1 wherever the emission lies
to the red of the excitation (Stokes shift).

The device material table (``materials.dispersion.MaterialTable``, ``fl_*`` fields, built by
``build_material_table`` from ``mat.fluorescence``) carries the channels the tracer reads, on the
1 nm light grid: the yield, alpha_x at the grid nodes, the emission density at the nodes and the
CDFs of both over the 1 nm bins (to sample the re-emitted wavelength, or in a camera tracer the
excitation wavelength).  The ``@wp.func`` s below read them; NumPy wrappers launch them.

Energy balance of a slab (:func:`slab_reemission`, the closed form the tracer test will use):
a collimated beam of monochromatic photons at l_x enters a slab of thickness d at normal
incidence through index-matched faces (no reflection); a fraction 1 - exp(-alpha d) is absorbed
(Bouguer–Lambert), alpha_x / alpha of it by the centre, and quantum_yield times that is
re-emitted (counted where it is created, before any re-absorption).
"""

from __future__ import annotations

import math

import numpy as np
import warp as wp

from .. import device as _device
from .. import validate as val
from ..errors import InputError
from ..spectra import LIGHT_MIN_NM, LIGHT_RANGE_NM, light_grid
from .absorption import AbsorptionSpectrum, with_absorption
from .datasets.fluorescence import CENTRES
from .dispersion import Material, MaterialTable, Uniaxial

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "Fluorescence",
    "with_fluorescence",
    "with_own_excitation",
    "centre",
    "slab_reemission",
    "fluorescence_yield",
    "excitation_alpha",
    "emission_pdf",
    "sample_emission",
    "sample_excitation",
    "excitation_pdf",
    "sample_cdf_row",
    "cdf_row_pdf",
    "bin_cdf",
    "fluorescence_values",
    "sample_emission_wavelengths",
    "CENTRES",
]

_GRID_MIN = wp.constant(LIGHT_MIN_NM)
_GRID_COUNT = wp.constant(len(light_grid()))


def _bands_density(bands, wl: np.ndarray) -> np.ndarray:
    """Sum of Gaussian bands (centre nm, FWHM nm, height) at ``wl`` (closed form, NumPy)."""
    out = np.zeros_like(wl)
    for c, fwhm, h in bands:
        sigma = fwhm / (2.0 * math.sqrt(2.0 * math.log(2.0)))
        out += h * np.exp(-0.5 * ((wl - c) / sigma) ** 2)
    return out


class Fluorescence:
    """One luminescent centre (module docstring).  ``emission_nm``/``emission``: the emitted
    photon spectrum at increasing wavelengths (any scale; normalised here to unit area on the
    1 nm light grid, linear in between, zero outside the data)."""

    def __init__(
        self,
        excitation: AbsorptionSpectrum,
        emission_nm,
        emission,
        quantum_yield: float,
        *,
        name: str = "fluorescence",
        source: str = "",
        fit: str = "",
        field: str = "fluorescence",
    ) -> None:
        if not isinstance(excitation, AbsorptionSpectrum):
            raise InputError("must be an AbsorptionSpectrum", field=field + ".excitation")
        self.quantum_yield = float(val.number(quantum_yield, field=field + ".quantum_yield", lo=0.0, hi=1.0))
        wl = np.asarray(emission_nm, dtype=np.float64)
        e = np.asarray(emission, dtype=np.float64)
        if wl.ndim != 1 or e.shape != wl.shape or wl.size < 2 or np.any(np.diff(wl) <= 0):
            raise InputError(
                "emission needs >= 2 increasing wavelengths and as many values", field=field + ".emission"
            )
        if not (np.isfinite(e).all() and e.min() >= 0):
            raise InputError("emission values must be finite and >= 0", field=field + ".emission")
        g = light_grid()
        node = np.interp(g, wl, e, left=0.0, right=0.0)
        area = np.trapezoid(node, g)
        if not area > 0:
            raise InputError(
                "no emission inside the light range",
                field=field + ".emission",
                allowed=f"{LIGHT_RANGE_NM[0]:g}-{LIGHT_RANGE_NM[1]:g} nm",
            )
        self.excitation = excitation
        self._emission_nodes = node / area
        self.name = name
        self.source = source
        self.fit = fit

    # -- NumPy side --------------------------------------------------------------------------
    def emission_pdf(self, wavelength_nm) -> np.ndarray:
        """Emitted photon density (1/nm, unit area) at ``wavelength_nm``."""
        return np.interp(
            np.asarray(wavelength_nm, dtype=np.float64), light_grid(), self._emission_nodes, 0.0, 0.0
        )

    def excitation_alpha(self, wavelength_nm) -> np.ndarray:
        """alpha_x (1/mm, base e) of the centre at ``wavelength_nm``."""
        return self.excitation.alpha(wavelength_nm)

    def mean_emission_nm(self) -> float:
        """Mean wavelength of the emitted photons (nm)."""
        g = light_grid()
        return float(np.trapezoid(g * self._emission_nodes, g))

    def with_yield(self, quantum_yield: float) -> Fluorescence:
        return self._copy(quantum_yield=quantum_yield)

    def with_excitation(self, excitation: AbsorptionSpectrum) -> Fluorescence:
        return self._copy(excitation=excitation)

    def scaled(self, strength: float) -> Fluorescence:
        """The same centre at ``strength`` times its concentration (alpha_x scaled)."""
        val.number(strength, field="fluorescence.strength", lo=0.0, hi=1.0e6)
        return self._copy(excitation=self.excitation.scaled(float(strength)))

    def _copy(self, **kw) -> Fluorescence:
        args = dict(excitation=self.excitation, quantum_yield=self.quantum_yield)
        args.update(kw)
        return Fluorescence(
            args["excitation"],
            light_grid(),
            self._emission_nodes,
            args["quantum_yield"],
            name=self.name,
            source=self.source,
            fit=self.fit,
        )

    def device_rows(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(alpha_x at the light-grid nodes, emission density at the nodes, emission CDF and
        excitation CDF over the 1 nm bins), float64, each of the light grid's length."""
        g = light_grid()
        ax = self.excitation.alpha(g)
        return ax, self._emission_nodes, bin_cdf(self._emission_nodes), bin_cdf(ax)

    def __repr__(self) -> str:
        return (
            f"Fluorescence({self.name!r}, yield {self.quantum_yield:g}, "
            f"emission mean {self.mean_emission_nm():.1f} nm)"
        )


def bin_cdf(nodes: np.ndarray) -> np.ndarray:
    """CDF over the 1 nm bins [l_j, l_j + 1) of a piecewise-linear density given at the nodes:
    cdf[0] = 0, cdf[j + 1] - cdf[j] = the bin's trapezoid; all zero for a zero density."""
    b = 0.5 * (nodes[:-1] + nodes[1:])
    c = np.concatenate([[0.0], np.cumsum(b)])
    return c / c[-1] if c[-1] > 0 else np.zeros_like(c)


def centre(
    name: str, *, quantum_yield: float | None = None, strength: float = 1.0, field: str = "fluorescence"
) -> Fluorescence:
    """The luminescent centre ``name`` of :data:`CENTRES` ("N3", "Cr3+ corundum", "Cr3+ spinel",
    "uranyl glass"), optionally with another yield and ``strength`` x its concentration."""
    val.choice(name, tuple(CENTRES), field=field + ".centre")
    c = CENTRES[name]
    g = light_grid()
    shape = _bands_density(c["excitation"], g)
    ex = AbsorptionSpectrum(
        g, shape * (c["peak_alpha_per_mm"] / shape.max()), name=f"{name} excitation", source=c["source"]
    )
    fl = Fluorescence(
        ex,
        g,
        _bands_density(c["emission"], g),
        c["quantum_yield"] if quantum_yield is None else quantum_yield,
        name=name,
        source=c["source"],
        fit=c["fit"],
        field=field,
    )
    return fl if strength == 1.0 else fl.scaled(strength)


def with_fluorescence(mat: Material, fl: Fluorescence, *, name: str | None = None) -> Material:
    """``mat`` carrying the centre ``fl``: its absorption alpha(l) + alpha_x(l) inside its range
    (both waves of a uniaxial crystal: the centre is taken as isotropic) and ``.fluorescence``."""
    # with_absorption adds alpha_x to the host's own absorption (k curves add)
    ex = fl.excitation
    out = with_absorption(mat, (ex, ex) if isinstance(mat, Uniaxial) else ex, name=name or mat.name)
    out.source = f"{mat.source}; fluorescence: {fl.source}"
    out.fluorescence = fl
    out.fluorescence_host = mat  # the material without the centre (spec.py re-applies on it)
    out.__dict__.pop("_table_cache", None)  # built while validating, before the centre was set
    return out


def with_own_excitation(mat: Material, fl: Fluorescence) -> Material:
    """``mat`` carrying ``fl`` whose absorption is already ``mat``'s own (its bands are the
    centre's, e.g. a chromophore variety's Cr3+): alpha_x = ``mat``'s alpha (the weaker wave of a
    birefringent crystal, so that alpha_x <= alpha for every wave) on the light grid, nothing
    added; ``fl`` gives the emission and the yield."""
    import copy

    g = light_grid()
    lo, hi = mat.wavelength_range_nm
    inside = (g >= lo) & (g <= hi)
    a = np.zeros_like(g)
    alpha = np.asarray(mat.alpha(g[inside]))
    a[inside] = alpha.min(axis=-1) if alpha.ndim > 1 else alpha
    fl = fl.with_excitation(AbsorptionSpectrum(g, a, name=f"{mat.name} absorption", source=mat.source))
    out = copy.copy(mat)
    out.__dict__.pop("_table_cache", None)
    out.fluorescence = fl
    out.fluorescence_host = mat
    return out


def slab_reemission(
    fl: Fluorescence, alpha_total_per_mm: float, thickness_mm: float, wavelength_nm: float
) -> dict[str, float]:
    """Closed-form photon balance per incident photon for the slab of the module docstring:
    ``absorbed`` 1 - exp(-alpha d), ``absorbed_by_centre`` alpha_x / alpha of it, ``emitted``
    quantum_yield x that (alpha: the material's total absorption at ``wavelength_nm``)."""
    a = float(alpha_total_per_mm)
    ax = float(fl.excitation_alpha(wavelength_nm))
    if ax > a * (1 + 1e-6):
        raise InputError(
            "the centre absorbs more than the material",
            field="alpha_total_per_mm",
            value=a,
            allowed=f">= {ax:g}",
        )
    absorbed = -math.expm1(-a * thickness_mm)
    # min: alpha from the float32 material table may be 1e-7 below a float64 alpha_x it contains
    by_centre = absorbed * min(ax / a, 1.0) if a > 0 else 0.0
    return {"absorbed": absorbed, "absorbed_by_centre": by_centre, "emitted": fl.quantum_yield * by_centre}


# ----------------------------------------------------------------------------------------------
# Device side: the material table's fluorescence channels


@wp.func
def _grid_coord(wavelength: float):
    x = wp.clamp(wavelength - _GRID_MIN, 0.0, float(_GRID_COUNT - 1))
    j = wp.min(int(x), _GRID_COUNT - 2)
    return j, x - float(j)


@wp.func
def fluorescence_yield(t: MaterialTable, mat_id: int):
    """Quantum yield of material ``mat_id`` (0 for a non-fluorescent one)."""
    return t.fl_yield[mat_id]


@wp.func
def _row_value(table: wp.array2d(dtype=wp.float32), row: int, wavelength: float):
    if row < 0 or wavelength < _GRID_MIN or wavelength > _GRID_MIN + float(_GRID_COUNT - 1):
        return 0.0
    j, f = _grid_coord(wavelength)
    return table[row, j] * (1.0 - f) + table[row, j + 1] * f


@wp.func
def excitation_alpha(t: MaterialTable, mat_id: int, wavelength: float):
    """alpha_x (1/mm) of the material's centre at ``wavelength`` (nm); 0 without one."""
    return _row_value(t.fl_excitation, t.fl_row[mat_id], wavelength)


@wp.func
def emission_pdf(t: MaterialTable, mat_id: int, wavelength: float):
    """Emitted photon density (1/nm) of the material's centre at ``wavelength``; 0 without one."""
    return _row_value(t.fl_emission, t.fl_row[mat_id], wavelength)


@wp.func
def sample_cdf_row(cdf: wp.array2d(dtype=wp.float32), row: int, u: float):
    """A wavelength (nm) drawn from row ``row`` of a CDF table over the 1 nm bins of the light
    grid (``bin_cdf``) and its pdf (1/nm): the bin j with cdf[j] <= u < cdf[j + 1] (binary
    search), uniform inside it; pdf = the bin's mass / 1 nm."""
    lo = int(0)
    hi = _GRID_COUNT - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if cdf[row, mid] <= u:
            lo = mid
        else:
            hi = mid
    c0 = cdf[row, lo]
    c1 = cdf[row, lo + 1]
    f = float(0.5)
    if c1 > c0:
        f = wp.clamp((u - c0) / (c1 - c0), 0.0, 1.0)
    return _GRID_MIN + float(lo) + f, c1 - c0


@wp.func
def cdf_row_pdf(cdf: wp.array2d(dtype=wp.float32), row: int, wavelength: float):
    """The pdf (1/nm) with which :func:`sample_cdf_row` draws ``wavelength`` from row ``row``:
    the mass of its 1 nm bin; 0 outside the light grid."""
    if wavelength < _GRID_MIN or wavelength > _GRID_MIN + float(_GRID_COUNT - 1):
        return 0.0
    j, _f = _grid_coord(wavelength)
    return cdf[row, j + 1] - cdf[row, j]


@wp.func
def sample_emission(t: MaterialTable, mat_id: int, u: float):
    """A re-emitted wavelength (nm) from uniform ``u`` and its pdf (1/nm, piecewise constant on
    the 1 nm bins); (0, 0) for a material without a centre."""
    row = t.fl_row[mat_id]
    if row < 0:
        return 0.0, 0.0
    return sample_cdf_row(t.fl_emission_cdf, row, u)


@wp.func
def sample_excitation(t: MaterialTable, mat_id: int, u: float):
    """An excitation wavelength (nm) drawn proportional to alpha_x (for a camera tracer that
    meets an emission event and looks for the light that caused it) and its pdf (1/nm)."""
    row = t.fl_row[mat_id]
    if row < 0:
        return 0.0, 0.0
    return sample_cdf_row(t.fl_excitation_cdf, row, u)


@wp.func
def excitation_pdf(t: MaterialTable, mat_id: int, wavelength: float):
    """The pdf (1/nm) with which :func:`sample_excitation` draws ``wavelength``; 0 without a
    centre."""
    row = t.fl_row[mat_id]
    if row < 0:
        return 0.0
    return cdf_row_pdf(t.fl_excitation_cdf, row, wavelength)


@wp.kernel
def _values_kernel(
    offset: int,
    wavelength: wp.array(dtype=wp.float32),
    t: MaterialTable,
    mat_id: int,
    ax: wp.array(dtype=wp.float32),
    em: wp.array(dtype=wp.float32),
    q: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    ax[i] = excitation_alpha(t, mat_id, wavelength[i])
    em[i] = emission_pdf(t, mat_id, wavelength[i])
    q[i] = fluorescence_yield(t, mat_id)


@wp.kernel
def _sample_kernel(
    offset: int,
    u: wp.array(dtype=wp.float32),
    t: MaterialTable,
    mat_id: int,
    which: int,
    wl: wp.array(dtype=wp.float32),
    pdf: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    if which == 0:
        a, b = sample_emission(t, mat_id, u[i])
        wl[i] = a
        pdf[i] = b
    else:
        a, b = sample_excitation(t, mat_id, u[i])
        wl[i] = a
        pdf[i] = b


def _material_table(mat: Material, device) -> tuple[MaterialTable, object]:
    dev = _device.get_device(device)
    return mat._table(dev), dev


def fluorescence_values(
    mat: Material, wavelength_nm, *, device=None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """NumPy wrapper of the device channels: (alpha_x, emission density, yield) at
    ``wavelength_nm`` read from ``mat``'s material table."""
    table, dev = _material_table(mat, device)
    ax, em, q = _device.elementwise(
        _values_kernel,
        [(wavelength_nm, wp.float32)],
        [wp.float32, wp.float32, wp.float32],
        extra=(table, 0),
        device=dev,
    )
    return ax, em, q


def sample_emission_wavelengths(
    mat: Material, u, *, excitation: bool = False, device=None
) -> tuple[np.ndarray, np.ndarray]:
    """NumPy wrapper of :func:`sample_emission` (or :func:`sample_excitation`): (wavelength, pdf)."""
    table, dev = _material_table(mat, device)
    wl, pdf = _device.elementwise(
        _sample_kernel,
        [(u, wp.float32)],
        [wp.float32, wp.float32],
        extra=(table, 0, 1 if excitation else 0),
        device=dev,
    )
    return wl, pdf
