"""The inverse of the chromophore model: concentrations from a measured absorption spectrum or from
a target colour.

Two problems, one entry point, :func:`fit_chromophores`:

- **Spectrum.**  alpha(λ) of a host is linear in its chromophores' concentrations
  (:func:`~warpoptics.materials.chromophores.chromophore_alpha`), so a measured alpha(λ) (or a
  decadic absorbance over a stated path, alpha = ln 10 · A / d) over a wavelength window is fitted
  by non-negative least squares (Lawson & Hanson 1974, ``scipy.optimize.nnls``) on the band
  sets' unit-concentration spectra, optionally with a non-negative constant (a flat baseline:
  reflection or scattering losses left in the data).  The residual is reported as the RMS of
  alpha(fit) − alpha(measured) in 1/mm and relative to the RMS of the data.
- **Colour.**  The stone is a polished plate of the stated thickness (``materials.plate``:
  (1 − R)² exp(−alpha d) per wave, the mean over the host's waves, as the ``colorchange``
  command); its CIELAB under the stated light (``color.spectrum_lab``) is brought to the target
  by bounded least squares on the Lab difference (``scipy.optimize.least_squares``, concentrations
  >= 0, several starts), then polished on CIEDE2000.  A faceted stone is not rendered: its cut and
  size enter only as this effective path length (for a face-up round brilliant roughly 1–2 times
  its depth).  The residual is CIEDE2000 (CIE 142-2001, colour-science) between the target and
  the colour of the fitted concentrations recomputed by the full path (``plate_transmittance`` of
  the coloured material).  Three or more chromophores usually reach a colour in many ways: the
  solution is one of them, the nearest to the starting concentrations the optimiser finds.

CSV files (:func:`read_absorption_csv`): two columns, wavelength (nm) and the value, comma
separated; lines starting with ``#`` and blank lines are skipped, a first line that is not numeric
is a header.  Errors name the file and the row.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from .chromophores import band_set, chromophore_alpha, chromophores, host_info, resolve_chromophore

__all__ = ["QUANTITIES", "FitResult", "read_absorption_csv", "fit_chromophores"]

#: what a spectrum's values are: decadic absorbance over ``path_mm``, or alpha (base e)
QUANTITIES = ("absorbance", "alpha_per_mm", "alpha_per_cm")

_LN10 = math.log(10.0)


@dataclass(frozen=True)
class FitResult:
    """The fitted concentrations and how well they fit.

    ``concentrations``: {chromophore: value in ``units[chromophore]``}.  ``kind``: "spectrum" or
    "colour".  ``residual``: spectrum, the RMS of alpha(fit) − alpha(data) in 1/mm over the fitted
    window; colour, CIEDE2000 between target and fit.  ``relative_residual``: spectrum, residual /
    RMS of the data (None for a colour).  Spectrum fits also carry ``wavelength_nm``,
    ``alpha_measured``, ``alpha_fitted`` (1/mm) and ``baseline_per_mm``; colour fits ``target_lab``,
    ``lab`` (the fitted colour), ``illuminant`` and ``thickness_mm``.
    """

    host: str
    kind: str
    concentrations: dict[str, float]
    units: dict[str, str]
    residual: float
    relative_residual: float | None = None
    wavelength_nm: np.ndarray | None = None
    alpha_measured: np.ndarray | None = None
    alpha_fitted: np.ndarray | None = None
    baseline_per_mm: float = 0.0
    target_lab: tuple[float, float, float] | None = None
    lab: tuple[float, float, float] | None = None
    illuminant: str | None = None
    thickness_mm: float | None = None
    polarization: str | None = None
    notes: list[str] = field(default_factory=list)

    def summary(self) -> str:
        """A few lines for the command line."""
        lines = [f"host           {self.host}"]
        for name, c in self.concentrations.items():
            lines.append(f"  {name:22s} {c:.6g} {self.units[name]}")
        if self.kind == "spectrum":
            lo, hi = float(self.wavelength_nm[0]), float(self.wavelength_nm[-1])  # type: ignore[index]
            lines.append(
                f"fit            alpha over {lo:g}-{hi:g} nm ({self.polarization}), "
                f"{len(self.wavelength_nm)} points"  # type: ignore[arg-type]
            )
            if self.baseline_per_mm:
                lines.append(f"baseline       {self.baseline_per_mm:.4g} 1/mm")
            lines.append(
                f"residual       RMS {self.residual:.4g} 1/mm ({100 * (self.relative_residual or 0):.2f} % "
                "of the data's RMS)"
            )
        else:
            t, f = self.target_lab, self.lab
            lines.append(f"target         L* {t[0]:.2f} a* {t[1]:.2f} b* {t[2]:.2f} under {self.illuminant}")  # type: ignore[index]
            lines.append(f"fitted         L* {f[0]:.2f} a* {f[1]:.2f} b* {f[2]:.2f}")  # type: ignore[index]
            lines.append(f"residual       CIEDE2000 {self.residual:.3f} ({self.thickness_mm:g} mm plate)")
        lines.extend(self.notes)
        return "\n".join(lines)


# ----------------------------------------------------------------------------------------------
# Input
# ----------------------------------------------------------------------------------------------


def _to_alpha(values: np.ndarray, quantity: str, path_mm, *, file=None) -> np.ndarray:
    if quantity not in QUANTITIES:
        raise InputError(
            "unknown quantity", file=file, field="quantity", value=quantity, allowed=", ".join(QUANTITIES)
        )
    if quantity == "alpha_per_mm":
        return values
    if quantity == "alpha_per_cm":
        return values / 10.0
    if path_mm is None:
        raise InputError("a decadic absorbance needs the path length in mm", file=file, field="path_mm")
    if (
        isinstance(path_mm, bool)
        or not isinstance(path_mm, (int, float))
        or not (math.isfinite(path_mm) and path_mm > 0)
    ):
        raise InputError("must be a number > 0 (mm)", file=file, field="path_mm", value=path_mm)
    return _LN10 * values / float(path_mm)


def read_absorption_csv(path, *, quantity: str = "absorbance", path_mm: float | None = None):
    """(wavelength_nm, alpha_per_mm) from a CSV of wavelength (nm) and ``quantity`` ("absorbance":
    decadic absorbance over ``path_mm`` mm; "alpha_per_mm" or "alpha_per_cm": base-e absorption
    coefficient), sorted by wavelength.  Bad rows raise :class:`InputError` naming the file and
    the row (1-based line number)."""
    p = Path(path)
    if not p.is_file():
        raise InputError("spectrum file not found", file=str(path), field="spectrum")
    try:
        text = p.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise InputError("not a text (UTF-8) file", file=str(path), field="spectrum") from None
    rows: list[tuple[float, float, int]] = []
    seen_data = False
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        cells = [c.strip() for c in line.split(",")]
        if len(cells) < 2:
            raise InputError(
                "needs two comma-separated columns: wavelength (nm), value",
                file=str(path),
                field=f"row {number}",
                value=raw,
            )
        try:
            lam, val = float(cells[0]), float(cells[1])
        except ValueError:
            if not seen_data and not rows:
                seen_data = True  # the one header line
                continue
            raise InputError("not a number", file=str(path), field=f"row {number}", value=raw) from None
        seen_data = True
        if not (math.isfinite(lam) and math.isfinite(val)):
            raise InputError("must be finite", file=str(path), field=f"row {number}", value=raw)
        if lam <= 0:
            raise InputError("wavelength must be > 0 nm", file=str(path), field=f"row {number}", value=raw)
        rows.append((lam, val, number))
    if len(rows) < 2:
        raise InputError("needs at least two data rows", file=str(path), field="spectrum", value=len(rows))
    rows.sort(key=lambda r: r[0])
    for a, b in zip(rows, rows[1:], strict=False):
        if a[0] == b[0]:
            raise InputError(
                f"wavelength {a[0]:g} nm given twice (rows {a[2]} and {b[2]})",
                file=str(path),
                field=f"row {b[2]}",
            )
    lam = np.array([r[0] for r in rows])
    values = np.array([r[1] for r in rows])
    return lam, _to_alpha(values, quantity, path_mm, file=str(path))


# ----------------------------------------------------------------------------------------------
# Fits
# ----------------------------------------------------------------------------------------------


def _host_and_index(host, index):
    """A host crystal, or a chromophore variety's host (and its index unless ``index`` is given):
    ``"tanzanite"`` fits the zoisite band sets with tanzanite's indices."""
    from .chromophores import hosts
    from .library import variety_chromophores

    if isinstance(host, str) and host.strip().lower() in hosts():
        return host.strip().lower(), index
    variety = variety_chromophores(host) if isinstance(host, str) else None
    if variety is None:
        host_info(host)  # the unknown-host error, with the closest names
    name, _concentrations, variety_index = variety  # type: ignore[misc]
    return name, index if index is not None else variety_index


def _names(host: str, which) -> list[str]:
    if which is None:
        return chromophores(host)
    if isinstance(which, str):
        which = [s for s in which.split(",") if s.strip()]
    out = []
    for key in which:
        name = resolve_chromophore(host, key)
        if name not in out:
            out.append(name)
    if not out:
        raise InputError("no chromophores to fit", field="chromophores", value=which)
    return out


def _polarizations(host: str, polarization: str) -> list[str]:
    pols = list(host_info(host)["polarizations"])
    if polarization == "mean":
        return pols
    if polarization not in pols:
        raise InputError(
            f"no such polarization in {host}",
            field="polarization",
            value=polarization,
            allowed=", ".join(["mean", *pols]),
        )
    return [polarization]


def _basis(host: str, names: Sequence[str], wavelength_nm: np.ndarray, pols: Sequence[str]) -> np.ndarray:
    """alpha per unit concentration: shape (len(pols), len(wavelength_nm), len(names))."""
    return np.stack(
        [
            np.stack(
                [chromophore_alpha(host, {n: 1.0}, wavelength_nm, p).astype(np.float64) for n in names],
                axis=-1,
            )
            for p in pols
        ]
    )


def _fit_spectrum(host, names, lam, alpha, polarization, baseline, window) -> FitResult:
    from scipy.optimize import nnls

    pols = _polarizations(host, polarization)
    lo, hi = window
    if not (0 < lo < hi):
        raise InputError("bad wavelength window", field="wavelength_range_nm", value=window)
    sel = (lam >= lo) & (lam <= hi)
    need = len(names) + int(baseline)
    if int(sel.sum()) < max(need, 2):
        raise InputError(
            f"too few data points in {lo:g}-{hi:g} nm to fit {need} unknowns",
            field="spectrum",
            value=int(sel.sum()),
        )
    lam, alpha = lam[sel], alpha[sel]
    a = _basis(host, names, lam, pols).mean(axis=0)
    if baseline:
        a = np.concatenate([a, np.ones((len(lam), 1))], axis=1)
    norms = np.linalg.norm(a, axis=0)
    live = norms > 0
    if not live[: len(names)].any():
        raise InputError(
            f"no chromophore absorbs in {lo:g}-{hi:g} nm for this polarization",
            field="chromophores",
            value=names,
        )
    x = np.zeros(a.shape[1])
    x[live], _ = nnls(a[:, live] / norms[live], alpha)
    x[live] /= norms[live]
    notes = [
        f"not determined: {n} has no absorption in {lo:g}-{hi:g} nm ({polarization})"
        for n, ok in zip(names, live, strict=False)
        if not ok
    ]
    fitted = a @ x
    rms = float(np.sqrt(np.mean((fitted - alpha) ** 2)))
    scale = float(np.sqrt(np.mean(alpha**2)))
    return FitResult(
        host=host_info(host)["name"],
        kind="spectrum",
        concentrations={n: float(c) for n, c in zip(names, x, strict=False)},
        units={n: band_set(host, n).unit for n in names},
        residual=rms,
        relative_residual=rms / scale if scale > 0 else float("inf"),
        wavelength_nm=lam,
        alpha_measured=alpha,
        alpha_fitted=fitted,
        baseline_per_mm=float(x[-1]) if baseline else 0.0,
        polarization=polarization,
        notes=notes,
    )


def _lab_triple(target) -> tuple[float, float, float]:
    try:
        t = tuple(float(v) for v in target)
    except (TypeError, ValueError):
        raise InputError(
            "a CIELAB target is three numbers L*, a*, b*", field="target_lab", value=target
        ) from None
    if len(t) != 3 or not all(math.isfinite(v) for v in t) or not (0.0 <= t[0] <= 100.0):
        raise InputError(
            "a CIELAB target is three finite numbers with 0 <= L* <= 100", field="target_lab", value=target
        )
    return t  # type: ignore[return-value]


def _fit_colour(host, names, target, illuminant, thickness_mm, index) -> FitResult:
    import colour
    from scipy.optimize import least_squares, minimize

    from .. import validate as val
    from ..color import spectrum_lab
    from ..spectra import grid, light_spectrum_row
    from .library import chromophore_material
    from .plate import plate_transmittance

    light_spectrum_row(illuminant, field="illuminant")
    d = float(val.number(thickness_mm, field="thickness_mm", lo=0.0, hi=1.0e4))
    if d <= 0:
        raise InputError("a colour fit needs a path length > 0 mm", field="thickness_mm", value=thickness_mm)
    tgt = np.array(_lab_triple(target))
    g = grid()
    pols = list(host_info(host)["polarizations"])
    basis = _basis(host, names, g, pols)  # (pol, λ, chromophore)
    # (1 - R)^2 of the colourless host, the mean over its waves (the waves' R differ by < 1e-3)
    fresnel = plate_transmittance(chromophore_material(host, {}, index=index), d, g)

    def lab_of(c):
        t = fresnel * np.exp(-d * basis @ c).mean(axis=0)
        return spectrum_lab(g, t, illuminant, field="illuminant")[0]

    def de00(c):
        return float(colour.delta_E(lab_of(c), tgt, method="CIE 2000"))

    ref = np.array([band_set(host, n).reference_concentration for n in names], dtype=np.float64)
    best = None
    for start in (0.3, 1.0, 3.0, 0.05):
        ls = least_squares(lambda c: lab_of(c) - tgt, ref * start, bounds=(0.0, np.inf), x_scale=ref)
        if best is None or ls.cost < best.cost:
            best = ls
    assert best is not None
    x = best.x
    pol = minimize(lambda u: de00(np.abs(u)), x, method="Nelder-Mead", options={"xatol": 1e-9, "fatol": 1e-6})
    if de00(np.abs(pol.x)) < de00(x):
        x = np.abs(pol.x)
    conc = {n: float(c) for n, c in zip(names, x, strict=False)}
    # the residual by the full path: the coloured material's own plate transmittance
    mat = chromophore_material(host, conc, index=index)
    lab = spectrum_lab(g, plate_transmittance(mat, d, g), illuminant, field="illuminant")[0]
    return FitResult(
        host=host_info(host)["name"],
        kind="colour",
        concentrations=conc,
        units={n: band_set(host, n).unit for n in names},
        residual=float(colour.delta_E(lab, tgt, method="CIE 2000")),
        target_lab=tuple(float(v) for v in tgt),  # type: ignore[arg-type]
        lab=tuple(float(v) for v in lab),  # type: ignore[arg-type]
        illuminant=illuminant,
        thickness_mm=d,
    )


def fit_chromophores(
    host: str,
    *,
    spectrum=None,
    quantity: str = "alpha_per_mm",
    path_mm: float | None = None,
    polarization: str = "mean",
    baseline: bool = False,
    wavelength_range_nm: tuple[float, float] = (400.0, 700.0),
    target_lab=None,
    illuminant: str = "D65",
    thickness_mm: float | None = None,
    chromophores: Sequence[str] | str | None = None,
    index: tuple | None = None,
) -> FitResult:
    """Non-negative concentrations of ``host``'s chromophores (all, or those named in
    ``chromophores``) that reproduce a measured spectrum or a target colour.  ``host`` is a host
    crystal (``chromophores.hosts()``) or a chromophore variety (``"tanzanite"``: its host's band
    sets, its index).

    Spectrum: ``spectrum`` is a CSV path (:func:`read_absorption_csv`) or a pair (wavelength_nm,
    values), the values in ``quantity`` ("absorbance" needs ``path_mm``); the fit covers
    ``wavelength_range_nm``, for one of the host's polarizations or their ``"mean"`` (unpolarized
    light through a weakly absorbing plate), with an optional flat ``baseline``.

    Colour: ``target_lab`` (L*, a*, b*) under ``illuminant`` (a light of ``spectra``, CIELAB
    against that light's white) for a plate ``thickness_mm`` thick (the stone's effective path
    length); ``index`` optionally replaces the host's colourless index (GEMS format).

    Returns a :class:`FitResult` (its ``residual`` says how well the fit did)."""
    host, index = _host_and_index(host, index)
    if (spectrum is None) == (target_lab is None):
        raise InputError(
            "give either a spectrum or a target colour (target_lab)", field="spectrum/target_lab"
        )
    names = _names(host, chromophores)
    if spectrum is not None:
        if isinstance(spectrum, (str, Path)):
            lam, alpha = read_absorption_csv(spectrum, quantity=quantity, path_mm=path_mm)
        else:
            try:
                lam_in, val_in = spectrum
            except (TypeError, ValueError):
                raise InputError(
                    "a spectrum is a CSV path or a pair (wavelength_nm, values)", field="spectrum"
                ) from None
            lam = np.asarray(lam_in, dtype=np.float64).reshape(-1)
            vals = np.asarray(val_in, dtype=np.float64).reshape(-1)
            if (
                lam.shape != vals.shape
                or lam.size < 2
                or not (np.isfinite(lam).all() and np.isfinite(vals).all())
            ):
                raise InputError(
                    "wavelengths and values must be finite arrays of one length >= 2",
                    field="spectrum",
                    value=(lam.size, vals.size),
                )
            order = np.argsort(lam)
            lam, vals = lam[order], vals[order]
            alpha = _to_alpha(vals, quantity, path_mm)
        return _fit_spectrum(host, names, lam, alpha, polarization, baseline, wavelength_range_nm)
    if thickness_mm is None:
        raise InputError("a colour fit needs the plate thickness (path length) in mm", field="thickness_mm")
    return _fit_colour(host, names, target_lab, illuminant, thickness_mm, index)
