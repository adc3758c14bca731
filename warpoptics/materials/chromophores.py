"""Gem colour from chromophores: alpha(λ) of a host crystal as the sum over its chromophores of
concentration × that chromophore's measured band set in that host.

A :class:`ChromophoreBands` is one chromophore (Cr3+, Fe2+-Ti4+ charge transfer, a colour
centre, ...) in one host crystal: for each polarization of the host (``"o"`` E⊥c and ``"e"`` E∥c
for a uniaxial host, ``"x"``, ``"y"``, ``"z"`` for D along the principal axes X, Y, Z of a biaxial
host, ``"iso"`` for a cubic one) a tuple of :class:`~warpoptics.materials.absorption.Band` s whose
peaks are the base-e alpha (1/mm) at the set's ``reference_concentration`` (in its ``unit``), plus
an optional :class:`UrbachTail` (the UV absorption edge or charge-transfer band whose tail sets
the violet end).  Absorption is linear in concentration (Beer's law):

    alpha_p(λ) = Σ_c (C_c / C_ref,c) [Σ_b peak_b band_profile_b(λ) + tail_c,p(λ)]

The band sets are data, one module per host under :mod:`warpoptics.materials.datasets.chromophores`,
each citing the measured spectrum (paper, figure or table, concentration, path length) it comes
from; ``tests/data/chromophores/spectra/`` keeps the numeric points of those spectra, read by
:mod:`.chromophore_spectra` and compared in tests/test_chromophore_spectra.py (the sets without a
readable measured spectrum say in their notes what is chosen; docs/design/chromophore_spectra.md).

The device-side law is :func:`urbach_tail` (and ``absorption.bands_alpha``); the kernel here sums
them over a flat table of bands and tails; :func:`chromophore_alpha` is its NumPy wrapper and
:func:`host_alpha` tabulates a host's spectra for ``with_absorption``.

References
----------
- R. G. Burns, *Mineralogical Applications of Crystal Field Theory*, 2nd ed., Cambridge 1993,
  ch. 3 (band shapes on an energy scale) and ch. 4 (intervalence charge transfer).
- F. Urbach, Phys. Rev. 92, 1324 (1953): the exponential absorption edge
  alpha = alpha_0 exp((E − E_0)/E_u).
- E. V. Dubinsky, J. Stone-Sundberg, J. L. Emmett, "A quantitative description of the causes of
  color in corundum", Gems & Gemology 56(1), 2–28 (2020): alpha = concentration × cross section.
"""

from __future__ import annotations

import difflib
import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import warp as wp

from .. import device as _device
from ..device import device_function
from ..errors import InputError
from .absorption import BAND_SHAPES, AbsorptionSpectrum, Band, bands_alpha
from .datasets.chromophores import HOSTS
from .units import finite_array, nonnegative_array, wavelength_array

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "urbach_tail",
    "urbach_tail_alpha",
    "UrbachTail",
    "ChromophoreBands",
    "hosts",
    "host_info",
    "chromophores",
    "band_set",
    "resolve_chromophore",
    "normalize_concentrations",
    "chromophore_alpha",
    "host_alpha",
    "chromophore_source",
]

#: hc in eV·nm (CODATA 2018: 1239.841984 eV nm)
_HC_EV_NM = 1239.841984
#: the exponent's cap (e^60 ~ 1e26): the tail of a UV edge far below its reference wavelength
_MAX_EXPONENT = 60.0

# ----------------------------------------------------------------------------------------------
# Device code
# ----------------------------------------------------------------------------------------------


@wp.func
def urbach_tail(wavelength_nm: float, reference_nm: float, alpha_ref: float, width_ev: float):
    """alpha_ref · exp((E − E_ref)/width_ev) with E = hc/λ (Urbach 1953): an absorption edge (or
    a UV charge-transfer band's long-wavelength tail) that is alpha_ref at ``reference_nm`` and
    falls by e every ``width_ev`` towards the red.  The exponent is capped at 60."""
    x = (_HC_EV_NM / wavelength_nm - _HC_EV_NM / reference_nm) / width_ev
    return alpha_ref * wp.exp(wp.min(x, _MAX_EXPONENT))


@wp.kernel
def _chromophore_kernel(
    offset: int,
    wavelength_nm: wp.array(dtype=wp.float32),
    shape: wp.array(dtype=wp.int32),
    center: wp.array(dtype=wp.float32),
    width: wp.array(dtype=wp.float32),
    peak: wp.array(dtype=wp.float32),
    tail_ref: wp.array(dtype=wp.float32),
    tail_alpha: wp.array(dtype=wp.float32),
    tail_width: wp.array(dtype=wp.float32),
    out: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    lam = wavelength_nm[i]
    s = bands_alpha(lam, shape, center, width, peak)
    for t in range(tail_ref.shape[0]):
        s += urbach_tail(lam, tail_ref[t], tail_alpha[t], tail_width[t])
    out[i] = s


@wp.kernel
def _urbach_kernel(
    offset: int,
    wavelength_nm: wp.array(dtype=wp.float32),
    reference_nm: wp.array(dtype=wp.float32),
    alpha_ref: wp.array(dtype=wp.float32),
    width_ev: wp.array(dtype=wp.float32),
    out: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    out[i] = urbach_tail(wavelength_nm[i], reference_nm[i], alpha_ref[i], width_ev[i])


# ----------------------------------------------------------------------------------------------
# Data types
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class UrbachTail:
    """An exponential absorption edge: alpha ``alpha_per_mm`` (1/mm, base e, at the band set's
    reference concentration) at ``reference_nm``, falling by e per ``width_ev`` of photon
    energy towards longer wavelengths (:func:`urbach_tail`)."""

    reference_nm: float
    alpha_per_mm: float
    width_ev: float

    def __post_init__(self):
        for name in ("reference_nm", "alpha_per_mm", "width_ev"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise InputError("must be a finite number", field=name, value=v)
        if self.reference_nm <= 0 or self.width_ev <= 0 or self.alpha_per_mm < 0:
            raise InputError(
                "a tail needs reference_nm > 0, width_ev > 0 and alpha_per_mm >= 0",
                field="tail",
                value=(self.reference_nm, self.alpha_per_mm, self.width_ev),
            )


@dataclass(frozen=True)
class ChromophoreBands:
    """One chromophore in one host: per-polarization bands (and UV tails) at a reference
    concentration, with the measured spectrum they come from.

    ``bands``: polarization -> tuple of :class:`Band` (peak alpha in 1/mm, base e, at
    ``reference_concentration`` in ``unit``); every polarization of the host must be present
    (an empty tuple for none).  ``tails``: polarization -> :class:`UrbachTail` (optional).
    ``source``: paper, figure/table, sample, concentration and path length of the measured
    spectrum; ``note``: what the numbers are where the source gives less than absolute
    absorption (e.g. band positions and relative heights only).
    """

    host: str
    chromophore: str
    unit: str
    reference_concentration: float
    bands: Mapping[str, tuple[Band, ...]]
    source: str
    tails: Mapping[str, UrbachTail] = field(default_factory=dict)
    note: str = ""

    def __post_init__(self):
        c = self.reference_concentration
        if isinstance(c, bool) or not isinstance(c, (int, float)) or not (math.isfinite(c) and c > 0):
            raise InputError(
                "reference concentration must be a finite number > 0",
                field=f"{self.host}.{self.chromophore}.reference_concentration",
                value=c,
            )
        if not self.source:
            raise InputError("a band set needs its source", field=f"{self.host}.{self.chromophore}.source")
        for pol, bands in self.bands.items():
            for b in bands:
                if not isinstance(b, Band):
                    raise InputError(
                        "must be a Band", field=f"{self.host}.{self.chromophore}.bands.{pol}", value=b
                    )
        unknown = set(self.tails) - set(self.bands)
        if unknown:
            raise InputError(
                "tail for a polarization without bands",
                field=f"{self.host}.{self.chromophore}.tails",
                value=sorted(unknown),
            )

    def scaled_bands(self, polarization: str, concentration: float) -> tuple[list[Band], list[UrbachTail]]:
        """The bands and tails of ``polarization`` at ``concentration`` (linear scaling)."""
        f = float(concentration) / float(self.reference_concentration)
        bands = [
            Band(b.center_nm, b.width_nm, b.peak_alpha_per_mm * f, b.shape)
            for b in self.bands.get(polarization, ())
        ]
        t = self.tails.get(polarization)
        tails = [] if t is None else [UrbachTail(t.reference_nm, t.alpha_per_mm * f, t.width_ev)]
        return bands, tails


# ----------------------------------------------------------------------------------------------
# Registry look-ups
# ----------------------------------------------------------------------------------------------


def hosts() -> list[str]:
    """The host crystals with band sets (``datasets.chromophores``)."""
    return list(HOSTS)


def _host_key(host) -> str:
    key = host.strip().lower() if isinstance(host, str) else None
    if key not in HOSTS:
        close = difflib.get_close_matches(str(host).lower(), list(HOSTS), n=2, cutoff=0.5)
        hint = f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""
        raise InputError(
            f"unknown chromophore host{hint}", field="host", value=host, allowed=", ".join(HOSTS)
        )
    return key


def host_info(host: str) -> dict:
    """The host's ``HOST`` record: ``polarizations``, ``index`` (the library's index entry of the
    colourless crystal), ``source``, ``description``, and ``name`` (the host's key)."""
    key = _host_key(host)
    return {**HOSTS[key].HOST, "name": key}


_band_sets: dict[str, dict[str, ChromophoreBands]] = {}


def _band_sets_of(host: str) -> dict[str, ChromophoreBands]:
    """The host's band sets as :class:`ChromophoreBands` (built once from the plain data)."""
    key = _host_key(host)
    if key not in _band_sets:
        pols = HOSTS[key].HOST["polarizations"]
        built = {}
        for name, d in HOSTS[key].BAND_SETS.items():
            missing = [p for p in pols if p not in d["bands"]]
            extra = [p for p in d["bands"] if p not in pols]
            if missing or extra:
                raise InputError(
                    f"band set polarizations must be the host's {pols}",
                    field=f"{key}.{name}.bands",
                    value=sorted(d["bands"]),
                )
            built[name] = ChromophoreBands(
                host=key,
                chromophore=name,
                unit=d["unit"],
                reference_concentration=d["reference_concentration"],
                bands={p: tuple(Band(*b) for b in d["bands"][p]) for p in pols},
                tails={p: UrbachTail(*t) for p, t in d.get("tails", {}).items()},
                source=d["source"],
                note=d.get("note", ""),
            )
        _band_sets[key] = built
    return _band_sets[key]


def chromophores(host: str) -> list[str]:
    """The chromophores with band sets in ``host``."""
    return list(_band_sets_of(host))


def band_set(host: str, chromophore: str) -> ChromophoreBands:
    """The band set of ``chromophore`` (any accepted spelling, :func:`resolve_chromophore`) in
    ``host``."""
    return _band_sets_of(host)[resolve_chromophore(host, chromophore)]


def _element(name: str) -> str:
    """``"Cr3+"`` -> ``"cr"``; ``"Fe2+-Ti4+"`` -> ``"fe-ti"``; a colour centre keeps its name."""
    return re.sub(r"[0-9]+\+?", "", name).replace(" ", "").lower()


def resolve_chromophore(host: str, key: str, *, field: str = "chromophores") -> str:
    """The band-set name in ``host`` that ``key`` stands for: the exact name (case-insensitive),
    or the name without charges when only one band set has that element ("Cr" -> "Cr3+" in
    corundum; "Fe" is ambiguous there: Fe3+, Fe2+-Ti4+)."""
    names = chromophores(host)
    if not isinstance(key, str):
        raise InputError("a chromophore name must be a string", field=field, value=key)
    k = key.strip()
    for n in names:
        if n.lower() == k.lower():
            return n
    matches = [n for n in names if _element(n) == _element(k)]
    if len(matches) == 1:
        return matches[0]
    hint = f" (ambiguous: {', '.join(matches)})" if matches else ""
    raise InputError(f"no such chromophore in {host}{hint}", field=f"{field}.{key}", allowed=", ".join(names))


def normalize_concentrations(host: str, concentrations: Mapping, *, field: str = "chromophores") -> dict:
    """``{band-set name: concentration}`` from user keys and values (finite numbers >= 0)."""
    if not isinstance(concentrations, Mapping):
        raise InputError("must be a table of chromophore = concentration", field=field, value=concentrations)
    out: dict[str, float] = {}
    for key, value in concentrations.items():
        name = resolve_chromophore(host, key, field=field)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise InputError("must be a number", field=f"{field}.{key}", value=value)
        if value < 0:
            raise InputError("a concentration must be >= 0", field=f"{field}.{key}", value=value)
        if name in out:
            raise InputError("given twice (two spellings)", field=f"{field}.{key}", value=value)
        out[name] = float(value)
    return out


def _polarization(host: str, polarization: str) -> str:
    pols = host_info(host)["polarizations"]
    if polarization not in pols:
        raise InputError(
            f"no such polarization in {host}",
            field="polarization",
            value=polarization,
            allowed=", ".join(pols),
        )
    return polarization


# ----------------------------------------------------------------------------------------------
# NumPy wrappers
# ----------------------------------------------------------------------------------------------


@device_function(urbach_tail)
def urbach_tail_alpha(wavelength_nm, reference_nm, alpha_ref, width_ev, *, device=None) -> np.ndarray:
    """alpha (1/mm) of :func:`urbach_tail`, broadcast over its arguments."""
    (out,) = _device.elementwise(
        _urbach_kernel,
        [
            (wavelength_array(wavelength_nm), wp.float32),
            (wavelength_array(reference_nm), wp.float32),
            (nonnegative_array("alpha_ref", alpha_ref), wp.float32),
            (finite_array("width_ev", width_ev), wp.float32),
        ],
        [wp.float32],
        device=device,
    )
    return out


def _sum(wavelength_nm, bands: list[Band], tails: list[UrbachTail], device=None) -> np.ndarray:
    dev = _device.get_device(device)

    def arr(values, dtype, np_dtype):
        return wp.array(np.asarray(values, np_dtype), dtype=dtype, device=dev)

    extra = (
        arr([BAND_SHAPES[b.shape] for b in bands], wp.int32, np.int32),
        arr([b.center_nm for b in bands], wp.float32, np.float32),
        arr([b.width_nm for b in bands], wp.float32, np.float32),
        arr([b.peak_alpha_per_mm for b in bands], wp.float32, np.float32),
        arr([t.reference_nm for t in tails], wp.float32, np.float32),
        arr([t.alpha_per_mm for t in tails], wp.float32, np.float32),
        arr([t.width_ev for t in tails], wp.float32, np.float32),
    )
    (out,) = _device.elementwise(
        _chromophore_kernel, [(wavelength_nm, wp.float32)], [wp.float32], extra=extra, device=dev
    )
    return np.maximum(out, 0.0)


def _collect(host: str, concentrations: Mapping, polarization: str):
    conc = normalize_concentrations(host, concentrations)
    sets = _band_sets_of(host)
    bands: list[Band] = []
    tails: list[UrbachTail] = []
    for name, c in conc.items():
        if c == 0:
            continue
        b, t = sets[name].scaled_bands(polarization, c)
        bands += b
        tails += t
    return bands, tails


def chromophore_alpha(host: str, concentrations: Mapping, wavelength_nm, polarization: str, *, device=None):
    """alpha (1/mm, base e) of ``host`` with ``concentrations`` ({chromophore: concentration in
    its band set's unit}) for light polarized ``polarization`` (one of the host's:
    :func:`host_info`), at ``wavelength_nm``; linear in each concentration."""
    _polarization(host, polarization)
    lam = wavelength_array(wavelength_nm)
    bands, tails = _collect(host, concentrations, polarization)
    return _sum(lam, bands, tails, device=device).reshape(np.shape(lam))


def chromophore_source(host: str, concentrations: Mapping) -> str:
    """The provenance of a host's absorption: each chromophore's concentration and band set
    source (and its note)."""
    conc = normalize_concentrations(host, concentrations)
    sets = _band_sets_of(host)
    parts = []
    for name, c in conc.items():
        bs = sets[name]
        note = f" [{bs.note}]" if bs.note else ""
        parts.append(f"{name} {c:g} {bs.unit}: {bs.source}{note}")
    key = _host_key(host)
    return f"{key} chromophores: " + "; ".join(parts) if parts else f"{key}, no chromophores (colourless)"


def host_alpha(
    host: str,
    concentrations: Mapping,
    *,
    wavelength_range_nm: tuple[float, float] = (300.0, 900.0),
    step_nm: float = 1.0,
    device=None,
) -> tuple[AbsorptionSpectrum, ...]:
    """One :class:`AbsorptionSpectrum` per polarization of ``host`` (its ``polarizations`` order:
    (o, e) uniaxial, (x, y, z) biaxial, (iso,) cubic), tabulated every ``step_nm`` over
    ``wavelength_range_nm``, for ``with_absorption``."""
    lo, hi = wavelength_range_nm
    if not (0 < lo < hi) or not (step_nm > 0):
        raise InputError("bad wavelength grid", field="wavelength_range_nm", value=(lo, hi, step_nm))
    lam = np.arange(lo, hi + 0.5 * step_nm, step_nm)
    src = chromophore_source(host, concentrations)
    out = []
    for pol in host_info(host)["polarizations"]:
        a = chromophore_alpha(host, concentrations, lam, pol, device=device)
        out.append(AbsorptionSpectrum(lam, a, name=f"{_host_key(host)} alpha_{pol}", source=src))
    return tuple(out)
