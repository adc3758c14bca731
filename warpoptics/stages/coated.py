"""Thin films in the camera tracer: coated interfaces, thin shells and opaque film surfaces.

An ``[[object]]`` may carry thin-film layers (``coating``) and a surface kind (``surface``):

* ``surface = "solid"`` (default) with a ``coating``: a **coated interface**.  Every face of
  the solid carries the stack (front = the ambient medium, back = the solid); the backward
  interface event uses the exact stack amplitudes (s and p, complex, with phase;
  ``optics.thinfilm.coating_amplitudes_scaled``) instead of bare Fresnel, in both directions
  (entering: light reflected on the ambient side, or transmitted from inside; leaving: the
  stack seen from its back).  Directions are those of the bare interface (a film conserves the
  tangential wave vector).
* ``surface = "shell"``: a **thin shell** with no volume (air | film | air, a soap bubble):
  the ray reflects with the film's r and passes straight on with its t (no refraction, the
  same medium on both sides).
* ``surface = "film"``: an **opaque film surface** (oil on water over dark asphalt, the Morpho
  multilayer over its absorbing scales): reflection with the stack's r over a substrate whose
  complex index is the object's ``material``; the transmitted light is absorbed.  Optional
  ``roughness`` (GGX alpha) draws a stochastic microfacet normal per hit.

The film thickness may vary over the surface (``film_thickness = { profile = ... }``): every layer
is scaled per hit so that the stack's total thickness follows the profile — Smits & Meyer 1990
§4.2 (a soap film thinning under gravity: proportional to the normalised height below the top
plus Perlin turbulence) or eq. 12–13 (an oil drop: t_max exp(-k1 (x^2 + y^2 + k2 turb))).

The backward event (:func:`film_children`) follows ``trace._isotropic_children``: the child's
Jones matrix is ``M_parent . B . diag(a_s, a_p)`` with ``B`` the frame change from the s/p frame
of the outgoing wave to the parent's frame, and transmitted amplitudes are scaled by
sqrt(Re(N_a cos a) / Re(N_b cos b)) so that |M|^2 is the transmitted power.

References
----------
* B. E. Smits and G. W. Meyer, "Newton's colors: simulating interference phenomena in
  realistic image synthesis", 1990 (seed 004): eq. 12–13 (oil slick), §4.2 (soap film),
  §4.3 (Morpho multilayer, Anderson & Richards 1942).
* M. Born and E. Wolf, *Principles of Optics*, §1.6 (the stack, see ``optics.thinfilm``).
* B. Walter et al., "Microfacet models for refraction through rough surfaces", EGSR 2007
  (GGX distribution, eq. 33, its sampling eq. 35–36, Smith G1 eq. 34; the estimator weight
  G |i.m| / (|i.n| |m.n|) of eq. 41).
* K. Perlin, "An image synthesizer", SIGGRAPH 1985 (turbulence).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import warp as wp

from ..device import elementwise, get_device
from ..errors import InputError
from ..fields import oil_slick_thickness_f, soap_film_thickness_f, turbulence, turbulence_3d
from ..materials.dispersion import MaterialTable, material_eval
from ..optics.complex import c_abs2
from ..optics.jones import (
    Jones,
    jones_identity,
    s_vector,
)
from ..optics.thinfilm import CoatingStack, coating_amplitudes_scaled, make_coating_stack
from .branches import Cand, branch_energy, child_jones, write_row

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "FilmSurfaces",
    "FilmConfig",
    "SURFACE_KINDS",
    "THICKNESS_PROFILES",
    "film_children",
    "film_thickness_nm",
    "turbulence_3d",
    "film_config",
    "build_film_surfaces",
    "empty_film_surfaces",
    "film_event",
    "film_thickness",
]

#: ``kind`` codes of :class:`FilmSurfaces` (0: a bare solid, the tracer's own event)
KIND_BARE = wp.constant(0)
KIND_COATED = wp.constant(1)
KIND_SHELL = wp.constant(2)
KIND_FILM = wp.constant(3)
SURFACE_KINDS = {"solid": 1, "shell": 2, "film": 3}
#: ``profile`` codes
THICKNESS_PROFILES = {"uniform": 0, "gravity": 1, "oil_drop": 2}
PROFILE_GRAVITY = wp.constant(1)
PROFILE_OIL = wp.constant(2)
#: ``normal_model`` codes: the mesh's face normal, an analytic sphere, an analytic wavy sheet
NORMAL_FACE = wp.constant(0)
NORMAL_SPHERE = wp.constant(1)
NORMAL_WAVY = wp.constant(2)

# index samples of coating layers (the spectral range of the renderer, as the bench uses)
_GRID_START_NM = 360.0
_GRID_STEP_NM = 5.0
_GRID = _GRID_START_NM + _GRID_STEP_NM * np.arange(95)


@wp.struct
class FilmSurfaces:
    """Per-object film data for the trace kernel (arrays indexed by object).

    ``kind``          0 bare solid, 1 coated solid, 2 thin shell, 3 opaque film surface
    ``coating``       coating index in ``stack`` (-1: none)
    ``stack``         the layers of all coatings (``optics.thinfilm.CoatingStack``)
    ``nominal_nm``    total thickness of the coating's layers as given, nm (profiles scale it)
    ``profile``       0 uniform, 1 gravity (soap film, §4.2), 2 oil drop (eq. 13)
    ``profile_a``     gravity: (top_nm, bottom_nm, k2, noise frequency);
                      oil drop: (max_nm, k1, k2, noise frequency)
    ``profile_seed``  (seed, octaves) of the turbulence
    ``frame``         object-space (z_min, z_max, half size, 0), mm: the profile's coordinates
    ``roughness``     GGX alpha of film surfaces (0: mirror)
    ``normal_model``  0 face normal, 1 sphere about the object origin, 2 wavy sheet
    ``shape_a``       wavy sheet: (amplitude mm, wavelength_x mm, wavelength_y mm, 0)
    """

    kind: wp.array(dtype=wp.int32)
    coating: wp.array(dtype=wp.int32)
    stack: CoatingStack
    nominal_nm: wp.array(dtype=wp.float32)
    profile: wp.array(dtype=wp.int32)
    profile_a: wp.array(dtype=wp.vec4f)
    profile_seed: wp.array(dtype=wp.vec2i)
    frame: wp.array(dtype=wp.vec4f)
    roughness: wp.array(dtype=wp.float32)
    normal_model: wp.array(dtype=wp.int32)
    shape_a: wp.array(dtype=wp.vec4f)


# ---------------------------------------------------------------------------------------------
# @wp.func
# ---------------------------------------------------------------------------------------------


@wp.func
def film_thickness_nm(fs: FilmSurfaces, obj: int, xl: wp.vec3f):
    """Total film thickness (nm) of object ``obj`` at the object-space point ``xl`` (mm).

    Uniform: the coating's own total.  Gravity (Smits & Meyer 1990 §4.2): h = normalised depth
    below the top of the object (0 top, 1 bottom), t = top + (bottom - top) max(h + k2 turb, 0)
    (``soap_film_thickness_f``), turbulence in 3-D at frequency f per half size.  Oil drop
    (eq. 13): (u, v) = (x, y) / half size, t = t_max exp(-k1 (u^2 + v^2 + k2 turb(f u, f v)))
    (``oil_slick_thickness_f``)."""
    prof = fs.profile[obj]
    t = fs.nominal_nm[obj]
    if prof == PROFILE_GRAVITY:
        a = fs.profile_a[obj]
        fr = fs.frame[obj]
        sd = fs.profile_seed[obj]
        h = wp.clamp((fr[1] - xl[2]) / wp.max(fr[1] - fr[0], 1.0e-12), 0.0, 1.0)
        turb = turbulence_3d(sd[0], xl * (a[3] / wp.max(fr[2], 1.0e-12)), sd[1])
        t = a[0] + soap_film_thickness_f(h, a[2], turb, a[1] - a[0])
    elif prof == PROFILE_OIL:
        a = fs.profile_a[obj]
        fr = fs.frame[obj]
        sd = fs.profile_seed[obj]
        u = xl[0] / wp.max(fr[2], 1.0e-12)
        v = xl[1] / wp.max(fr[2], 1.0e-12)
        turb = turbulence(sd[0], u * a[3], v * a[3], sd[1])
        t = oil_slick_thickness_f(u, v, a[1], a[2], turb, a[0])
    return wp.max(t, 0.0)


@wp.func
def _shading_normal(fs: FilmSurfaces, obj: int, xl: wp.vec3f, w2o: wp.mat44f, face_normal: wp.vec3f):
    """World unit normal of the smooth surface the mesh tessellates, on the side of
    ``face_normal`` (analytic sphere or wavy sheet; else the face normal)."""
    model = fs.normal_model[obj]
    nl = wp.vec3f(0.0, 0.0, 0.0)
    if model == NORMAL_SPHERE:
        nl = xl
    elif model == NORMAL_WAVY:
        a = fs.shape_a[obj]
        kx = 2.0 * wp.pi / wp.max(a[1], 1.0e-12)
        ky = 2.0 * wp.pi / wp.max(a[2], 1.0e-12)
        dzdx = a[0] * kx * wp.cos(kx * xl[0]) * wp.sin(ky * xl[1])
        dzdy = a[0] * ky * wp.sin(kx * xl[0]) * wp.cos(ky * xl[1])
        nl = wp.vec3f(-dzdx, -dzdy, 1.0)
    if wp.dot(nl, nl) <= 0.0:
        return face_normal
    nw = wp.normalize(wp.transform_vector(wp.transpose(w2o), nl))
    if wp.dot(nw, face_normal) < 0.0:
        nw = -nw
    return nw


@wp.func
def _ggx_g1(cos_v: float, alpha: float):
    """Smith G1 of the GGX distribution (Walter et al. 2007, eq. 34)."""
    c2 = wp.max(cos_v * cos_v, 1.0e-12)
    tan2 = wp.max(1.0 - c2, 0.0) / c2
    return 2.0 / (1.0 + wp.sqrt(1.0 + alpha * alpha * tan2))


@wp.func
def _ggx_normal(n: wp.vec3f, alpha: float, u1: float, u2: float):
    """A microfacet normal drawn from D(m) |m.n| of GGX about ``n`` (Walter et al. 2007,
    eq. 35–36)."""
    tan_t = alpha * wp.sqrt(u1 / wp.max(1.0 - u1, 1.0e-7))
    cos_t = 1.0 / wp.sqrt(1.0 + tan_t * tan_t)
    sin_t = tan_t * cos_t
    phi = 2.0 * wp.pi * u2
    t = wp.vec3f(1.0, 0.0, 0.0)
    if wp.abs(n[0]) > 0.9:
        t = wp.vec3f(0.0, 1.0, 0.0)
    t = wp.normalize(wp.cross(n, t))
    b = wp.cross(n, t)
    return wp.normalize(n * cos_t + t * (sin_t * wp.cos(phi)) + b * (sin_t * wp.sin(phi)))


@wp.func
def _child(
    m: Jones,
    w: float,
    k_out: wp.vec3f,
    parent_x: wp.vec3f,
    s: wp.vec3f,
    a_s: wp.vec2f,
    a_p: wp.vec2f,
    power_scale: float,
    polarized: int,
):
    """(M_child, w_child): M_parent . B . diag(a_s, a_p) sqrt(power_scale) (B: the s/p frame of
    the outgoing wave -> the parent's frame, as branches.child_jones), or in scalar mode the
    weight times the unpolarized power 0.5 (|a_s|^2 + |a_p|^2) power_scale."""
    if polarized != 0:
        return child_jones(m, k_out, parent_x, s, a_s, a_p, wp.sqrt(wp.max(power_scale, 0.0))), w
    return m, w * 0.5 * power_scale * (c_abs2(a_s) + c_abs2(a_p))


@wp.func(inline=False)  # out of line: compile time (see trace_radiance)
def film_children(
    cand: Cand,
    fs: FilmSurfaces,
    mats: MaterialTable,
    mat_id: int,
    obj: int,
    m: Jones,
    w: float,
    bx: wp.vec3f,
    d: wp.vec3f,
    n_out: wp.vec3f,
    n_a: wp.vec2f,
    n_b: wp.vec2f,
    x: wp.vec3f,
    w2o: wp.mat44f,
    eps: float,
    in_a: int,
    in_b: int,
    depth: int,
    polarized: int,
    wavelength: float,
    rng: wp.uint32,
):
    """Backward interface event at a coated solid, a thin shell or an opaque film surface.

    The backward ray ``d`` (from the camera) meets object ``obj`` at ``x`` with outward face
    normal ``n_out``; medium A (index ``n_a``, real part, object ``in_a``) is the side it
    arrives from, B (``n_b``, ``in_b``) the other.  Children (at most two) are written to
    ``cand`` rows 0..count-1 like ``trace._isotropic_children``; returns
    (cand, energies, count, rng).

    The stack's front faces the ambient medium: light reflected on the ambient side sees it
    from the front (``from_back = 0``), light from inside a coated solid from the back.
    Transmitted light arrives from B with the Snell cosine cos_b of the bare interface (films
    keep the tangential wave vector), amplitudes scaled by sqrt(Re(N_a cos_a) / Re(N_b cos_b)).
    Shells: B = A, straight through, no scaling.  Film surfaces: reflection only, over the
    complex substrate index of ``mat_id``; with roughness alpha > 0 the mirror normal is a GGX
    microfacet normal m and the child's weight G2 |i.m| / (|i.n| |m.n|) (Walter et al. 2007,
    eq. 41), none if the reflection leaves below the surface.
    """
    kind = fs.kind[obj]
    coat = fs.coating[obj]
    energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
    count = int(0)
    entering = wp.dot(d, n_out) < 0.0
    nrm = n_out  # geometric normal on the arrival side
    front = int(1)  # the arrival side is the stack's front (the ambient side)
    if not entering:
        nrm = -n_out
        front = 0
    xl = wp.transform_point(w2o, x)
    nominal = fs.nominal_nm[obj]
    scale = float(1.0)
    if nominal > 0.0:
        scale = film_thickness_nm(fs, obj, xl) / nominal
    k_out = -d
    if kind == KIND_COATED:
        # the stack's front medium is the ambient: A when the ray arrives from outside
        n_front = n_a
        n_back = n_b
        if front == 0:
            n_front = n_b
            n_back = n_a
        cos_a = wp.clamp(-wp.dot(d, nrm), 0.0, 1.0)
        s = s_vector(d, n_out)
        eta = n_a[0] / n_b[0]
        sin2_b = eta * eta * (1.0 - cos_a * cos_a)
        if sin2_b < 1.0:
            cos_b = wp.sqrt(1.0 - sin2_b)
            d_t = wp.normalize(d * eta + nrm * (eta * cos_a - cos_b))
            # light from B: it meets the stack from its back when A is the ambient (front) side
            rs, rp, ts, tp = coating_amplitudes_scaled(
                fs.stack, coat, wavelength, cos_b, n_front, n_back, front, scale
            )
            ratio = float(0.0)
            if n_b[0] * cos_b > 0.0:
                ratio = n_a[0] * cos_a / (n_b[0] * cos_b)
            m_t, w_t = _child(m, w, k_out, bx, s, ts, tp, ratio, polarized)
            e_t = branch_energy(m_t, w_t)
            if e_t > 0.0:
                cand = write_row(cand, count, x + d_t * eps, d_t, s, m_t, w_t, in_b, depth + 1, -1, -d_t)
                energies[count] = e_t
                count += 1
        d_r = wp.normalize(d + nrm * (2.0 * cos_a))
        rs, rp, ts, tp = coating_amplitudes_scaled(
            fs.stack, coat, wavelength, cos_a, n_front, n_back, 1 - front, scale
        )
        m_r, w_r = _child(m, w, k_out, bx, s, rs, rp, 1.0, polarized)
        e_r = branch_energy(m_r, w_r)
        if e_r > 0.0:
            cand = write_row(cand, count, x + d_r * eps, d_r, s, m_r, w_r, in_a, depth + 1, -1, -d_r)
            energies[count] = e_r
            count += 1
        return cand, energies, count, rng
    # shells and film surfaces: a smooth (analytic) normal, optionally a microfacet normal
    ns = _shading_normal(fs, obj, xl, w2o, nrm)
    if -wp.dot(d, ns) <= 1.0e-6:
        ns = nrm  # the smooth normal turned away from the ray (grazing, silhouette)
    weight = float(1.0)
    alpha = fs.roughness[obj]
    if kind == KIND_FILM and alpha > 0.0:
        u1 = wp.randf(rng)
        u2 = wp.randf(rng)
        mf = _ggx_normal(ns, alpha, u1, u2)
        cos_o = -wp.dot(d, ns)
        cos_om = -wp.dot(d, mf)
        if cos_om <= 0.0:
            return cand, energies, count, rng
        d_m = d + mf * (2.0 * cos_om)
        cos_i = wp.dot(d_m, ns)
        if cos_i <= 0.0:
            return cand, energies, count, rng
        weight = _ggx_g1(cos_o, alpha) * _ggx_g1(cos_i, alpha) * cos_om / (cos_o * wp.dot(mf, ns))
        ns = mf
    cos_a = wp.clamp(-wp.dot(d, ns), 0.0, 1.0)
    s = s_vector(d, ns)
    d_r = wp.normalize(d + ns * (2.0 * cos_a))
    n_sub = n_a
    if kind == KIND_FILM:
        nsub_o, nsub_e = material_eval(mats, mat_id, wavelength)
        n_sub = nsub_o
        front = 1  # a film surface is seen from its front on either side of the sheet
    if kind == KIND_SHELL:
        # light from the other side passes straight on (no refraction: the same medium)
        rs, rp, ts, tp = coating_amplitudes_scaled(fs.stack, coat, wavelength, cos_a, n_a, n_a, front, scale)
        m_t, w_t = _child(m, w, k_out, bx, s, ts, tp, 1.0, polarized)
        e_t = branch_energy(m_t, w_t)
        if e_t > 0.0:
            cand = write_row(cand, count, x + d * eps, d, s, m_t, w_t, in_a, depth + 1, -1, -d)
            energies[count] = e_t
            count += 1
    if wp.dot(d_r, nrm) > 0.0:
        # light from A: the stack's front faces A, except on the back of a shell (A on both sides)
        rs, rp, ts, tp = coating_amplitudes_scaled(
            fs.stack, coat, wavelength, cos_a, n_a, n_sub, 1 - front, scale
        )
        m_r, w_r = _child(m, w, k_out, bx, s, rs, rp, weight, polarized)
        e_r = branch_energy(m_r, w_r)
        if e_r > 0.0:
            cand = write_row(cand, count, x + d_r * eps, d_r, s, m_r, w_r, in_a, depth + 1, -1, -d_r)
            energies[count] = e_r
            count += 1
    return cand, energies, count, rng


# ---------------------------------------------------------------------------------------------
# Kernels
# ---------------------------------------------------------------------------------------------


@wp.kernel
def _film_event_kernel(
    offset: int,
    direction: wp.array(dtype=wp.vec3f),
    normal: wp.array(dtype=wp.vec3f),
    position: wp.array(dtype=wp.vec3f),
    wavelength: wp.array(dtype=float),
    fs: FilmSurfaces,
    mats: MaterialTable,
    mat_id: int,
    obj: int,
    n_ambient: wp.vec2f,
    n_object: wp.vec2f,
    polarized: int,
    seed: int,
    dir0: wp.array(dtype=wp.vec3f),
    dir1: wp.array(dtype=wp.vec3f),
    jones0: wp.array(dtype=wp.vec4f),
    jones0_im: wp.array(dtype=wp.vec4f),
    jones1: wp.array(dtype=wp.vec4f),
    jones1_im: wp.array(dtype=wp.vec4f),
    energy: wp.array(dtype=wp.vec2f),
    count_out: wp.array(dtype=wp.int32),
):
    i = wp.tid() + offset
    d = wp.normalize(direction[i])
    n_out = wp.normalize(normal[i])
    n_a = n_ambient
    n_b = n_object
    in_a = int(-1)
    in_b = obj
    if wp.dot(d, n_out) > 0.0:
        n_a = n_object
        n_b = n_ambient
        in_a = obj
        in_b = -1
    if fs.kind[obj] != KIND_COATED:
        n_a = n_ambient
        n_b = n_ambient
        in_a = -1
        in_b = -1
    bx = s_vector(d, n_out)
    cand = Cand()
    rng = wp.rand_init(seed, i)
    cand, e, count, rng = film_children(
        cand,
        fs,
        mats,
        mat_id,
        obj,
        jones_identity(),
        1.0,
        bx,
        d,
        n_out,
        n_a,
        n_b,
        position[i],
        wp.identity(n=4, dtype=wp.float32),
        1.0e-4,
        in_a,
        in_b,
        0,
        polarized,
        wavelength[i],
        rng,
    )
    dir0[i] = wp.vec3f(cand[0, 3], cand[0, 4], cand[0, 5])
    dir1[i] = wp.vec3f(cand[1, 3], cand[1, 4], cand[1, 5])
    jones0[i] = wp.vec4f(cand[0, 9], cand[0, 10], cand[0, 11], cand[0, 12])
    jones0_im[i] = wp.vec4f(cand[0, 13], cand[0, 14], cand[0, 15], cand[0, 16])
    jones1[i] = wp.vec4f(cand[1, 9], cand[1, 10], cand[1, 11], cand[1, 12])
    jones1_im[i] = wp.vec4f(cand[1, 13], cand[1, 14], cand[1, 15], cand[1, 16])
    energy[i] = wp.vec2f(e[0], e[1])
    count_out[i] = count


@wp.kernel
def _thickness_kernel(
    offset: int,
    position: wp.array(dtype=wp.vec3f),
    fs: FilmSurfaces,
    obj: int,
    out: wp.array(dtype=float),
):
    i = wp.tid() + offset
    out[i] = film_thickness_nm(fs, obj, position[i])


# ---------------------------------------------------------------------------------------------
# Configuration (scene files) and device data
# ---------------------------------------------------------------------------------------------

_FILM_KEYS = ("surface", "coating", "film_thickness", "roughness")
_LAYER_KEYS = {"n", "k", "material", "thickness_nm"}
_PROFILE_KEYS = {
    "uniform": {"profile"},
    "gravity": {"profile", "top_nm", "bottom_nm", "noise", "noise_scale", "seed", "octaves"},
    "oil_drop": {"profile", "max_nm", "k1", "k2", "noise_scale", "seed", "octaves"},
}
_PROFILE_DEFAULTS = {
    "gravity": {
        "top_nm": 0.0,
        "bottom_nm": 1000.0,
        "noise": 0.15,
        "noise_scale": 3.0,
        "seed": 0,
        "octaves": 5,
    },
    "oil_drop": {"max_nm": 1000.0, "k1": 3.0, "k2": 0.3, "noise_scale": 4.0, "seed": 0, "octaves": 6},
}


@dataclass(frozen=True)
class FilmConfig:
    """The film keys of an ``[[object]]`` (validated): ``surface`` ("solid", "shell", "film"),
    ``layers`` ((index spec, thickness_nm), ... front to back; a spec is a complex number, a
    library name, a refractiveindex.info page "main/TiO2/Devore-o" or an inline material table),
    ``profile`` and its parameters, ``roughness`` (GGX alpha, film surfaces)."""

    surface: str = "solid"
    layers: tuple = ()
    profile: str = "uniform"
    profile_params: dict = field(default_factory=dict)
    roughness: float = 0.0


def _err(msg, file, fld, value=None, allowed=None):
    return InputError(msg, file=file, field=fld, value=value, allowed=allowed)


def _num(v, file, fld, lo=-math.inf, hi=math.inf, integer=False):
    if isinstance(v, bool) or not isinstance(v, int if integer else (int, float)):
        raise _err("must be an integer" if integer else "must be a number", file, fld, v)
    if not math.isfinite(v) or v < lo or v > hi:
        rng = f">= {lo:g}" + ("" if hi == math.inf else f" and <= {hi:g}")
        raise _err("out of range", file, fld, v, rng)
    return v


def _layer_material(spec, file, fld):
    """The Material of a layer's ``material`` value (InputError naming file/field/value)."""
    from ..materials import from_refractiveindex, material_from_spec

    try:
        if isinstance(spec, str) and "/" in spec:
            return from_refractiveindex(spec)
        if isinstance(spec, (str, dict)):
            return material_from_spec(spec)
    except InputError as exc:
        raise _err(exc.message, file, fld, spec, exc.allowed) from None
    except (OSError, KeyError, ValueError) as exc:
        raise _err(f"unknown material ({exc})", file, fld, spec) from None
    raise _err("must be a material name, a refractiveindex.info page or an inline table", file, fld, spec)


def film_config(table: dict, index: int, file: str | None) -> FilmConfig | None:
    """Validate the film keys (``surface``, ``coating``, ``film_thickness``, ``roughness``) of
    ``[[object]]`` number ``index``; None when it has none.  Errors name file, field and value."""
    if not any(k in table for k in _FILM_KEYS):
        return None
    prefix = f"object.{index}."
    surface = table.get("surface", "solid")
    if surface not in SURFACE_KINDS:
        raise _err("unknown surface kind", file, prefix + "surface", surface, ", ".join(SURFACE_KINDS))
    coat = table.get("coating", [])
    if isinstance(coat, dict):
        coat = [coat]
    if not isinstance(coat, list):
        raise _err("must be an array of layer tables", file, prefix + "coating", coat)
    layers = []
    for j, layer in enumerate(coat):
        f = f"{prefix}coating.{j}."
        if not isinstance(layer, dict):
            raise _err("must be a table { material = ..., thickness_nm = ... }", file, f[:-1], layer)
        for k in layer:
            if k not in _LAYER_KEYS:
                raise _err("unknown key", file, f + k, None, ", ".join(sorted(_LAYER_KEYS)))
        if "thickness_nm" not in layer:
            raise _err("missing key", file, f + "thickness_nm")
        d = float(_num(layer["thickness_nm"], file, f + "thickness_nm", lo=0.0, hi=1.0e6))
        if ("n" in layer) == ("material" in layer):
            raise _err('a layer needs exactly one of n = ... or material = "name"', file, f + "material")
        if "n" in layer:
            n = float(_num(layer["n"], file, f + "n", lo=1.0e-3, hi=100.0))
            k = float(_num(layer.get("k", 0.0), file, f + "k", lo=0.0, hi=100.0))
            layers.append((complex(n, k), d))
        else:
            if "k" in layer:
                raise _err("k goes with n, not with material", file, f + "k", layer["k"])
            _layer_material(layer["material"], file, f + "material")  # validate now
            layers.append((layer["material"], d))
    if surface in ("shell", "film") and not layers:
        raise _err(
            f'a surface = "{surface}" object needs a coating (its film layers)', file, prefix + "coating"
        )
    th = table.get("film_thickness", {"profile": "uniform"})
    if not isinstance(th, dict):
        raise _err("must be a table { profile = ... }", file, prefix + "film_thickness", th)
    profile = th.get("profile", "uniform")
    if profile not in THICKNESS_PROFILES:
        raise _err(
            "unknown thickness profile",
            file,
            prefix + "film_thickness.profile",
            profile,
            ", ".join(THICKNESS_PROFILES),
        )
    for k in th:
        if k not in _PROFILE_KEYS[profile]:
            raise _err(
                f"unknown key for profile {profile!r}",
                file,
                prefix + "film_thickness." + k,
                None,
                ", ".join(sorted(_PROFILE_KEYS[profile])),
            )
    params = dict(_PROFILE_DEFAULTS.get(profile, {}))
    for k, v in th.items():
        if k == "profile":
            continue
        fld = prefix + "film_thickness." + k
        if k in ("seed", "octaves"):
            params[k] = int(
                _num(
                    v,
                    file,
                    fld,
                    lo=0 if k == "seed" else 1,
                    hi=2**31 - 1 if k == "seed" else 12,
                    integer=True,
                )
            )
        else:
            params[k] = float(_num(v, file, fld, lo=0.0, hi=1.0e6))
    if profile != "uniform" and not layers:
        raise _err("a thickness profile needs a coating", file, prefix + "film_thickness")
    roughness = float(_num(table.get("roughness", 0.0), file, prefix + "roughness", lo=0.0, hi=1.0))
    if roughness > 0.0 and surface != "film":
        raise _err('roughness applies to surface = "film" only', file, prefix + "roughness", roughness)
    return FilmConfig(
        surface=surface, layers=tuple(layers), profile=profile, profile_params=params, roughness=roughness
    )


def _layer_index_samples(spec) -> np.ndarray | complex:
    if isinstance(spec, complex):
        return spec
    mat = _layer_material(spec, None, "coating.material")
    lo, hi = mat.wavelength_range_nm
    g = np.clip(_GRID, lo, hi)
    n = np.asarray(mat.n(g), dtype=np.float64)
    k = np.asarray(mat.k(g), dtype=np.float64) if hasattr(mat, "k") else np.zeros_like(n)
    return n + 1j * k


def _normal_model(shape: str, params: dict) -> tuple[int, tuple]:
    if shape == "sphere":
        return 1, (0.0, 0.0, 0.0, 0.0)
    if shape == "wavy_sheet":
        import inspect

        from ..geometry import cuts

        defaults = {k: v.default for k, v in inspect.signature(cuts.wavy_sheet).parameters.items()}
        p = {**defaults, **params}
        return 2, (float(p["amplitude"]), float(p["wavelength_x"]), float(p["wavelength_y"]), 0.0)
    return 0, (0.0, 0.0, 0.0, 0.0)


def make_film_surfaces(configs, *, frames=None, shapes=None, device=None) -> FilmSurfaces:
    """A :class:`FilmSurfaces` for objects with these :class:`FilmConfig` (None: bare solid).

    ``frames``: per object (z_min, z_max, half size) in object space (mm), for the profiles;
    ``shapes``: per object (shape name, cut parameters), for the analytic normals."""
    dev = get_device(device)
    n = max(len(configs), 1)
    kind = np.zeros(n, np.int32)
    coating = np.full(n, -1, np.int32)
    nominal = np.zeros(n, np.float32)
    profile = np.zeros(n, np.int32)
    pa = np.zeros((n, 4), np.float32)
    ps = np.zeros((n, 2), np.int32)
    frame = np.zeros((n, 4), np.float32)
    rough = np.zeros(n, np.float32)
    nmodel = np.zeros(n, np.int32)
    sa = np.zeros((n, 4), np.float32)
    layers = []
    for i, cfg in enumerate(configs):
        if frames is not None:
            frame[i, :3] = frames[i]
        if cfg is None:
            continue
        kind[i] = SURFACE_KINDS[cfg.surface]
        coating[i] = len(layers)
        layers.append([(_layer_index_samples(s), d) for s, d in cfg.layers])
        nominal[i] = sum(d for _, d in cfg.layers)
        profile[i] = THICKNESS_PROFILES[cfg.profile]
        q = cfg.profile_params
        if cfg.profile == "gravity":
            pa[i] = (q["top_nm"], q["bottom_nm"], q["noise"], q["noise_scale"])
        elif cfg.profile == "oil_drop":
            pa[i] = (q["max_nm"], q["k1"], q["k2"], q["noise_scale"])
        ps[i] = (q.get("seed", 0), q.get("octaves", 1))
        rough[i] = cfg.roughness
        if shapes is not None and cfg.surface in ("shell", "film"):
            nmodel[i], sa[i] = _normal_model(*shapes[i])
    # one wavelength grid for all layers: dispersionless layers are repeated on it
    rows = []
    for coat in layers:
        rows.append([(np.full(_GRID.size, v) if np.ndim(v) == 0 else v, d) for v, d in coat])
    fs = FilmSurfaces()
    fs.kind = wp.array(kind, dtype=wp.int32, device=dev)
    fs.coating = wp.array(coating, dtype=wp.int32, device=dev)
    fs.stack = make_coating_stack(
        rows or [[]], wavelength_start_nm=_GRID_START_NM, wavelength_step_nm=_GRID_STEP_NM, device=dev
    )
    fs.nominal_nm = wp.array(nominal, dtype=wp.float32, device=dev)
    fs.profile = wp.array(profile, dtype=wp.int32, device=dev)
    fs.profile_a = wp.array(pa, dtype=wp.vec4f, device=dev)
    fs.profile_seed = wp.array(ps, dtype=wp.vec2i, device=dev)
    fs.frame = wp.array(frame, dtype=wp.vec4f, device=dev)
    fs.roughness = wp.array(rough, dtype=wp.float32, device=dev)
    fs.normal_model = wp.array(nmodel, dtype=wp.int32, device=dev)
    fs.shape_a = wp.array(sa, dtype=wp.vec4f, device=dev)
    return fs


def empty_film_surfaces(num_objects: int, *, device=None) -> FilmSurfaces:
    """No films: every object a bare solid."""
    return make_film_surfaces([None] * max(int(num_objects), 1), device=device)


def build_film_surfaces(scene: Any, meshes, mats, *, device=None) -> FilmSurfaces:
    """The :class:`FilmSurfaces` of a scene's objects (``meshes``: (trimesh, transform) pairs,
    ``mats``: their materials, as ``render._build_objects`` returns them).  Coated and film
    objects must be isotropic (InputError naming the object)."""
    configs, frames, shapes = [], [], []
    for i, (ob, (mesh, _), mat) in enumerate(zip(scene.objects, meshes, mats, strict=True)):
        cfg = getattr(ob, "film", None)
        if cfg is not None and getattr(mat, "is_uniaxial", False):
            raise InputError(
                "coatings, shells and film surfaces need an isotropic material (birefringent "
                "stones are not coated here)",
                file=scene.path,
                field=f"object.{i}.material",
                value=getattr(mat, "name", str(ob.material)),
            )
        configs.append(cfg)
        lo, hi = np.asarray(mesh.bounds, dtype=np.float64)
        frames.append((lo[2], hi[2], 0.5 * float(np.max(hi - lo))))
        shapes.append((ob.shape, dict(ob.params)))
    return make_film_surfaces(configs, frames=frames, shapes=shapes, device=device)


# ---------------------------------------------------------------------------------------------
# NumPy wrappers
# ---------------------------------------------------------------------------------------------


def film_event(
    config: FilmConfig,
    direction,
    normal,
    wavelength_nm,
    *,
    position=(0.0, 0.0, 0.0),
    n_ambient: float = 1.0,
    material: Any = None,
    polarized: bool = True,
    frame=(0.0, 1.0, 1.0),
    shape: tuple = ("plate", {}),
    seed: int = 0,
    device=None,
) -> dict:
    """The renderer's backward film event (:func:`film_children`) on NumPy rays.

    ``direction`` (..., 3): backward ray direction (from the camera); ``normal`` (..., 3): the
    surface's outward normal; ``material``: the object's material (the solid of a coated
    interface, the substrate of a film surface; default n = 1.5).  The parent is the identity
    Jones matrix with weight 1, its basis the s vector, so the children's energies are the
    unpolarized reflectance / transmittance of the event.  Returns ``count``, ``energy``
    (..., 2), ``direction`` (..., 2, 3) and ``jones`` (..., 2, 2, 2) complex per child
    (rows: the camera-side frame, columns: the child's s/p frame).
    """
    from ..materials import material_from_spec
    from ..materials.dispersion import build_material_table

    dev = get_device(device)
    mat = material_from_spec(material if material is not None else {"cauchy": [1.5]})
    table, ids = build_material_table([mat], dev)
    fs = make_film_surfaces([config], frames=[frame], shapes=[shape], device=dev)
    n_obj = float(np.asarray(mat.n(550.0)))
    outs = elementwise(
        _film_event_kernel,
        [(direction, wp.vec3f), (normal, wp.vec3f), (position, wp.vec3f), (wavelength_nm, wp.float32)],
        [wp.vec3f, wp.vec3f, wp.vec4f, wp.vec4f, wp.vec4f, wp.vec4f, wp.vec2f, wp.int32],
        extra=(
            fs,
            table,
            int(ids[0]),
            0,
            wp.vec2f(float(n_ambient), 0.0),
            wp.vec2f(n_obj, 0.0),
            int(bool(polarized)),
            int(seed),
        ),
        device=dev,
    )
    d0, d1, j0r, j0i, j1r, j1i, energy, count = outs
    jones = np.stack([(j0r + 1j * j0i), (j1r + 1j * j1i)], axis=-2).reshape(*j0r.shape[:-1], 2, 2, 2)
    return {"count": count, "energy": energy, "direction": np.stack([d0, d1], axis=-2), "jones": jones}


def film_thickness(config: FilmConfig, position, *, frame=(0.0, 1.0, 1.0), device=None) -> np.ndarray:
    """Film thickness (nm) of :func:`film_thickness_nm` at object-space points (..., 3), mm."""
    dev = get_device(device)
    fs = make_film_surfaces([config], frames=[frame], device=dev)
    (out,) = elementwise(_thickness_kernel, [(position, wp.vec3f)], [wp.float32], extra=(fs, 0), device=dev)
    return out
