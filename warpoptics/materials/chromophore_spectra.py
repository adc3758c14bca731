"""Measured chromophore spectra (digitized or numeric data of a published figure or database file)
and how a band set of :mod:`.chromophores` compares with one.

A spectrum file is a CSV whose comment lines (``#``) say where the data come from (paper or
database file, figure, sample, concentration, polarization, thickness, how the values were
obtained), followed by ``key: value`` lines the reader uses, then the table:

- ``host``, ``chromophore``: the band set the spectrum is compared with;
- ``quantity``: ``sigma_cm2`` (absorption cross section, base e) or ``absorbance10`` (decadic
  absorbance of a slab);
- ``concentration``: the sample's concentration in the band set's unit;
- ``number_density_cm3`` (``sigma_cm2``): the chromophore's number density at ``concentration``;
- ``path_mm``, ``baseline`` (``absorbance10``): the slab thickness and the absorbance removed per
  column (``column=value, ...``);
- ``columns``: ``column=polarization, ...`` (the host's polarization names);
- ``peaks_nm``: the measured maxima checked, ``pol=λ1,λ2; pol=λ3``;
- ``also`` (optional): other band sets of the host present in the sample,
  ``name=concentration, ...``: the comparison is of their sum;
- ``role`` (optional): ``fit`` (default: the band set was fitted to this spectrum and cites it)
  or ``check`` (an independent spectrum the band set is compared with, not fitted to).

alpha (1/mm, base e) is ``sigma * number_density / 10`` or ``ln(10) (A - baseline) / path_mm``.

:func:`compare` evaluates the band set at the sample's concentration (:func:`.chromophore_alpha`)
and returns, per polarization, the band maxima, the peak alpha ratio and the RMS relative error
over 400-700 nm at the points where the measured alpha exceeds 5 % of that polarization's maximum
there (below that the relative error of a near-zero value says nothing about colour; the
thresholds are those of the chromophore data's acceptance criteria: centres within 5 nm, peaks
within 15 %, RMS below 20 %).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["MeasuredSpectrum", "read_measured_spectrum", "concentrations", "compare", "rms_mask", "CRITERIA"]

#: acceptance criteria: band centre (nm), peak alpha (relative), RMS relative error, the
#: wavelength range of the RMS and the fraction of the maximum below which points are left out
CRITERIA = dict(centre_nm=5.0, peak_rel=0.15, rms_rel=0.20, rms_range_nm=(400.0, 700.0), rms_floor=0.05)

_KEYS = {
    "host",
    "chromophore",
    "quantity",
    "concentration",
    "number_density_cm3",
    "path_mm",
    "baseline",
    "columns",
    "peaks_nm",
    "also",
    "role",
}


@dataclass
class MeasuredSpectrum:
    """One measured spectrum: alpha (1/mm, base e) per polarization at ``concentration``."""

    path: Path
    host: str
    chromophore: str
    concentration: float
    wavelength_nm: np.ndarray
    alpha: dict[str, np.ndarray]
    peaks_nm: dict[str, list[float]]
    also: dict[str, float] = field(default_factory=dict)
    meta: dict[str, str] = field(default_factory=dict)
    comments: list[str] = field(default_factory=list)


def _pairs(text: str, sep: str = ",") -> dict[str, str]:
    out = {}
    for item in text.split(sep):
        if item.strip():
            k, _, v = item.partition("=")
            out[k.strip()] = v.strip()
    return out


def read_measured_spectrum(path) -> MeasuredSpectrum:
    """Read a spectrum file (see the module docstring) and convert it to alpha (1/mm, base e)."""
    path = Path(path)
    meta: dict[str, str] = {}
    comments: list[str] = []
    table: list[str] = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            s = line.rstrip("\n")
            if s.startswith("#"):
                comments.append(s[1:].strip())
            elif table or s.startswith("lambda_nm"):
                if s.strip():
                    table.append(s)
            elif ":" in s:
                k, _, v = s.partition(":")
                if k.strip() not in _KEYS:
                    raise InputError("unknown key in a spectrum file", field=str(path), value=k.strip())
                meta[k.strip()] = v.strip()
    missing = {"host", "chromophore", "quantity", "concentration", "columns", "peaks_nm"} - set(meta)
    if missing or not table:
        raise InputError("incomplete spectrum file", field=str(path), value=sorted(missing) or "no table")
    rows = list(csv.DictReader(table))
    lam = np.array([float(r["lambda_nm"]) for r in rows])
    columns = _pairs(meta["columns"])
    alpha: dict[str, np.ndarray] = {}
    for col, pol in columns.items():
        v = np.array([float(r[col]) for r in rows])
        if meta["quantity"] == "sigma_cm2":
            alpha[pol] = v * float(meta["number_density_cm3"]) / 10.0
        elif meta["quantity"] == "absorbance10":
            base = float(_pairs(meta.get("baseline", "")).get(col, 0.0))
            alpha[pol] = math.log(10.0) * (v - base) / float(meta["path_mm"])
        else:
            raise InputError(
                "quantity must be sigma_cm2 or absorbance10", field=str(path), value=meta["quantity"]
            )
    peaks = {}
    for item in meta["peaks_nm"].split(";"):
        if item.strip():
            pol, _, lams = item.partition("=")
            peaks[pol.strip()] = [float(x) for x in lams.split(",")]
    return MeasuredSpectrum(
        path=path,
        host=meta["host"],
        chromophore=meta["chromophore"],
        concentration=float(meta["concentration"]),
        wavelength_nm=lam,
        alpha=alpha,
        peaks_nm=peaks,
        also={k: float(v) for k, v in _pairs(meta.get("also", "")).items()},
        meta=meta,
        comments=comments,
    )


def rms_mask(wavelength_nm, alpha) -> np.ndarray:
    """The points of the RMS comparison: 400-700 nm and alpha above 5 % of its maximum there."""
    lo, hi = CRITERIA["rms_range_nm"]
    lam = np.asarray(wavelength_nm, float)
    a = np.asarray(alpha, float)
    inside = (lam >= lo) & (lam <= hi)
    top = np.max(a[inside]) if np.any(inside) else 0.0
    return inside & (a > CRITERIA["rms_floor"] * top)


def _local_maxima(lam: np.ndarray, a: np.ndarray) -> np.ndarray:
    inner = (a[1:-1] >= a[:-2]) & (a[1:-1] >= a[2:]) & (a[1:-1] > 0)
    return lam[1:-1][inner]


def concentrations(spectrum: MeasuredSpectrum) -> dict[str, float]:
    """The sample's band sets and concentrations: its chromophore and the ``also`` ones."""
    return {spectrum.chromophore: spectrum.concentration, **spectrum.also}


def compare(spectrum: MeasuredSpectrum, alpha_fn=None) -> dict[str, dict]:
    """The band set ``spectrum.host``/``spectrum.chromophore`` at ``spectrum.concentration`` (plus
    the ``also`` band sets at theirs) against the measured alpha, per polarization: ``peaks`` (one
    entry per stated maximum: measured wavelength and alpha, the nearest model maximum, the model
    alpha there, the distance between the two maxima and the peak ratio model/measured), ``rms``
    (relative, over :func:`rms_mask`) and ``n_rms`` (its points).

    ``alpha_fn(wavelength_nm, polarization)`` replaces the library's band set (the fit script
    passes its trial parameters)."""
    if alpha_fn is None:
        from .chromophores import chromophore_alpha

        conc = concentrations(spectrum)

        def alpha_fn(lam, pol):
            return chromophore_alpha(spectrum.host, conc, lam, pol)

    out = {}
    lam = spectrum.wavelength_nm
    for pol, meas in spectrum.alpha.items():
        model = np.asarray(alpha_fn(lam, pol), float)
        mask = rms_mask(lam, meas)
        rel = (model[mask] - meas[mask]) / meas[mask]
        peaks = []
        for p in spectrum.peaks_nm.get(pol, []):
            win = (lam >= p - 15.0) & (lam <= p + 15.0)
            i = np.flatnonzero(win)[np.argmax(meas[win])]
            lam_m, a_m = float(lam[i]), float(meas[i])
            fine = np.arange(lam_m - 40.0, lam_m + 40.0 + 1e-9, 0.25)
            mf = np.asarray(alpha_fn(fine, pol), float)
            maxima = _local_maxima(fine, mf)
            nearest = float(maxima[np.argmin(np.abs(maxima - lam_m))]) if maxima.size else math.nan
            a_model = float(np.asarray(alpha_fn(np.array([lam_m]), pol), float)[0])
            peaks.append(
                dict(
                    stated_nm=p,
                    measured_nm=lam_m,
                    measured_alpha=a_m,
                    model_nm=nearest,
                    model_alpha=a_model,
                    centre_error_nm=abs(nearest - lam_m),
                    peak_ratio=a_model / a_m,
                )
            )
        out[pol] = dict(peaks=peaks, rms=float(np.sqrt(np.mean(rel**2))), n_rms=int(mask.sum()))
    return out
