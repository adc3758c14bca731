"""Fluorescent re-emission in the camera (backward) tracer: from an emission to an excitation wavelength.

A fluorescent medium (``materials.fluorescence``: excitation alpha_x, emission density f_em,
quantum yield Q) is a source inside the stone.  In energy units its emission coefficient at the
emission wavelength l_e is

    j(x, l_e) = Q f_em(l_e) int dl_x alpha_x(l_x) (l_x / l_e) (1 / 4 pi) int L(x, w', l_x) dw'

(photons absorbed at l_x are re-emitted isotropically and unpolarized at l_e).  The estimator,
called from ``stages.trace.trace_radiance``: every segment of a camera tree at l_e inside the
medium is a candidate with weight W_i = E_i B_i (branch energy times the Bouguer–Lambert integral
over the segment, :func:`emission_weight`); one is kept by weighted reservoir sampling; on it a
point (distance ~ exp(-kappa s)), an excitation wavelength (:func:`sample_excitation_wavelength`,
a one-sample mixture of alpha_x and alpha_x x the lights' spectra) and a uniform direction are
drawn, and the tracer continues there at l_x, unpolarized.  The radiance it gathers enters the
camera through the kept segment's Jones matrix with the factor of :func:`reemission_start`.

The excitation tree and the emitted light are transported like any other light (refraction,
total reflection, absorption including the centre's self-absorption).  One generation only:
re-emission of re-emitted light is not followed.  Isotropic hosts only
(``emission_media_supported``).  The derivation: docs/design/fluorescence.md.

References: Pharr, Jakob & Humphreys, Physically Based Rendering, 3rd ed., §11.1 (emission in the
equation of transfer), §13.3.1 (weighted reservoir sampling), §13.10 (one-sample MIS); Glassner
1995, "A model for fluorescence and phosphorescence".
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ..errors import InputError
from ..materials.dispersion import Isotropic, MaterialTable
from ..materials.fluorescence import (
    bin_cdf,
    cdf_row_pdf,
    emission_pdf,
    excitation_alpha,
    excitation_pdf,
    fluorescence_yield,
    sample_cdf_row,
    sample_excitation,
)
from ..optics.absorption import bouguer_lambert_integral, sample_bouguer_lambert_distance
from ..optics.branches import COLS, ROW_D, ROW_O, ROW_WN, branch_energy
from ..optics.jones import Jones
from ..optics.microfacet import orthonormal_basis
from ..spectra import light_grid, light_spectrum

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "Reemission",
    "Candidate",
    "COL_LENGTH",
    "COL_KAPPA",
    "COL_ENERGY",
    "emission_weight",
    "sample_excitation_wavelength",
    "excitation_wavelength_pdf",
    "reemission_start",
    "build_reemission",
    "scene_light_spectra",
    "emission_media_supported",
    "has_fluorescence",
]


#: probability of drawing l_x from alpha_x x the lights (module docstring): every light of a
#: scene (an RGB environment: D65 x basis <= D65 x its largest coefficient; a surface: albedo x
#: its lamps) is bounded by its light spectrum, so that strategy is near-optimal; alpha_x alone
#: keeps every wavelength the centre absorbs reachable (defensive mixture)
LIGHT_MIX = 0.9


@wp.struct
class Reemission:
    """Per-render re-emission settings (values, not compile-time constants)."""

    enabled: int  # 1: some object of the scene is fluorescent (0: the tracer never looks)
    # per centre row of the material table (``MaterialTable.fl_row``): the CDF over the 1 nm bins
    # of the light grid of alpha_x x the scene's light spectra (build_reemission)
    light_cdf: wp.array2d(dtype=wp.float32)
    # per centre row: the probability of drawing l_x from light_cdf (the rest from alpha_x alone);
    # 0 where the lights have no power under the excitation
    light_mix: wp.array(dtype=wp.float32)


#: the segment of a camera tree kept for its re-emission (weighted reservoir sampling): the branch
#: row of ``optics.branches`` it was popped as (origin, direction, Jones matrix, weight at its
#: start, object, depth), with three columns reused: its length, the total absorption
#: coefficient at the emission wavelength on it and its branch energy.  A matrix the tracer
#: fills element by element (a struct reassigned in the loop would be selected at every branch)
Candidate = wp.types.matrix(shape=(1, COLS), dtype=wp.float32)
COL_LENGTH = ROW_WN
COL_KAPPA = ROW_WN + 1
COL_ENERGY = ROW_WN + 2


@wp.func
def emission_weight(m: Jones, w: float, kappa: float, length: float):
    """(E, W) of a segment inside a fluorescent medium: its branch energy E
    (``optics.branches.branch_energy``) and its reservoir weight W = E x
    ``bouguer_lambert_integral(kappa, length)``."""
    e = branch_energy(m, w)
    return e, e * bouguer_lambert_integral(kappa, length)


@wp.func
def excitation_wavelength_pdf(re: Reemission, mats: MaterialTable, mat_id: int, wavelength: float):
    """The pdf (1/nm) of :func:`sample_excitation_wavelength` at ``wavelength``: (1 - m) p_alpha
    + m p_light, with m = ``re.light_mix`` of the material's centre."""
    row = mats.fl_row[mat_id]
    if row < 0:
        return 0.0
    mix = re.light_mix[row]
    pdf = (1.0 - mix) * excitation_pdf(mats, mat_id, wavelength)
    if mix > 0.0:
        pdf += mix * cdf_row_pdf(re.light_cdf, row, wavelength)
    return pdf


@wp.func
def sample_excitation_wavelength(re: Reemission, mats: MaterialTable, mat_id: int, u_pick: float, u: float):
    """An excitation wavelength (nm) for material ``mat_id``'s centre: with probability
    ``light_mix`` from alpha_x x the scene's light spectra, else from alpha_x alone
    (``materials.fluorescence.sample_excitation``); returns it and the mixture pdf (1/nm)."""
    row = mats.fl_row[mat_id]
    wl = float(0.0)
    if row < 0:
        return wl, 0.0
    if u_pick < re.light_mix[row]:
        wl, _p = sample_cdf_row(re.light_cdf, row, u)
    else:
        wl, _p = sample_excitation(mats, mat_id, u)
    return wl, excitation_wavelength_pdf(re, mats, mat_id, wl)


@wp.func
def reemission_start(
    c: Candidate,
    total: float,
    re: Reemission,
    mats: MaterialTable,
    mat_id: int,
    absorption_scale: float,
    emission_wavelength: float,
    rng: wp.uint32,
):
    """The excitation tree of the kept segment ``c`` (reservoir weight sum ``total``; module
    docstring, steps 2-3): (origin, direction, basis x of its unpolarized root ray, excitation
    wavelength, factor, rng).  The light L_x that tree gathers (per unit weight) reaches the
    camera as unpolarized radiance factor x L_x through the row's Jones matrix with its weight;
    factor 0: nothing to trace."""
    s = wp.randf(rng)
    u_pick = wp.randf(rng)
    u_wl = wp.randf(rng)
    u1 = wp.randf(rng)
    u2 = wp.randf(rng)
    dist = sample_bouguer_lambert_distance(c[0, COL_KAPPA], c[0, COL_LENGTH], s)
    o = wp.vec3f(c[0, ROW_O], c[0, ROW_O + 1], c[0, ROW_O + 2])
    d = wp.vec3f(c[0, ROW_D], c[0, ROW_D + 1], c[0, ROW_D + 2])
    origin = o + d * dist
    # a uniform direction on the sphere (pdf 1 / 4 pi, which cancels the 1 / 4 pi of j)
    z = 1.0 - 2.0 * u1
    r = wp.sqrt(wp.max(0.0, 1.0 - z * z))
    phi = 2.0 * wp.pi * u2
    direction = wp.vec3f(r * wp.cos(phi), r * wp.sin(phi), z)
    bx, _by = orthonormal_basis(direction)
    wl_x, pdf = sample_excitation_wavelength(re, mats, mat_id, u_pick, u_wl)
    factor = float(0.0)
    energy = c[0, COL_ENERGY]
    if pdf > 0.0 and energy > 0.0:
        ax = excitation_alpha(mats, mat_id, wl_x) * absorption_scale
        em = emission_pdf(mats, mat_id, emission_wavelength)
        q = fluorescence_yield(mats, mat_id)
        factor = (total / energy) * q * em * (wl_x / emission_wavelength) * ax / pdf
    return origin, direction, bx, wl_x, factor, rng


# ----------------------------------------------------------------------------------------------
# Host side


def has_fluorescence(materials) -> bool:
    """Whether any of ``materials`` carries a luminescent centre with a positive yield."""
    return any(
        getattr(m, "fluorescence", None) is not None and m.fluorescence.quantum_yield > 0 for m in materials
    )


def emission_media_supported(materials, *, file: str | None = None) -> None:
    """Refuse a fluorescent birefringent material (module docstring: isotropic hosts only)."""
    for m in materials:
        fl = getattr(m, "fluorescence", None)
        if fl is not None and fl.quantum_yield > 0 and not (isinstance(m, Isotropic) and not m.is_uniaxial):
            raise InputError(
                "fluorescence is traced in isotropic stones only (a birefringent host splits the "
                "emission into o and e waves); use an isotropic host or quantum_yield = 0",
                file=file,
                field=f"material {m.name}",
                value=type(m).__name__,
            )


def scene_light_spectra(scene) -> np.ndarray:
    """Sum over the scene's lights (environment and lamps) of their spectra on the light grid,
    each normalised to unit power over 240-830 nm (the light-weighted excitation strategy)."""
    g = light_grid()
    names = []
    env = scene.lights[0]
    names.append(env.spectrum or ("E" if env.map == "constant" else "D65"))
    for lamp in scene.lamps:
        names.append(lamp.spectrum or "D65")
    total = np.zeros_like(g)
    for name in names:
        s = light_spectrum(name, g)
        p = np.trapezoid(s, g)
        if p > 0:
            total += s / p
    return total


def build_reemission(materials, light_spectra: np.ndarray | None, *, device=None) -> Reemission:
    """The :class:`Reemission` of a material list in material-table order (the centre rows of
    ``build_material_table`` follow it) and the scene's light spectra on the light grid
    (:func:`scene_light_spectra`; None: alpha_x alone)."""
    re = Reemission()
    rows, mix = [], []
    done: dict[int, tuple[np.ndarray, float]] = {}  # instances share one material object
    for m in materials:
        fl = getattr(m, "fluorescence", None)
        if fl is None:
            continue
        if id(m) not in done:
            ax = fl.device_rows()[0]
            if light_spectra is None:
                done[id(m)] = (np.zeros_like(ax), 0.0)
            else:
                cdf = bin_cdf(np.maximum(ax, 0.0) * np.asarray(light_spectra, dtype=np.float64))
                done[id(m)] = (cdf, LIGHT_MIX if cdf[-1] > 0 else 0.0)
        rows.append(done[id(m)][0])
        mix.append(done[id(m)][1])
    re.enabled = 1 if has_fluorescence(materials) else 0
    if not rows:
        rows, mix = [np.zeros(len(light_grid()))], [0.0]
    re.light_cdf = wp.array(np.asarray(rows, dtype=np.float32), dtype=wp.float32, device=device)
    re.light_mix = wp.array(np.asarray(mix, dtype=np.float32), dtype=wp.float32, device=device)
    return re
