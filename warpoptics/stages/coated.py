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

A coated solid is the ordinary interface event with the coating's amplitudes
(``optics.interface.backward_isotropic``); shells and film surfaces are
:func:`film_surface_children`; the Jones matrices follow the tracer's rule
(docs/design/point_tracer.md).

References
* B. E. Smits and G. W. Meyer, "Newton's colors: simulating interference phenomena in
  realistic image synthesis", 1990: eq. 12–13 (oil slick), §4.2 (soap film),
  §4.3 (Morpho multilayer, Anderson & Richards 1942).
* M. Born and E. Wolf, *Principles of Optics*, §1.6 (the stack, see ``optics.thinfilm``).
* B. Walter et al., "Microfacet models for refraction through rough surfaces", EGSR 2007
  (GGX distribution, eq. 33, its sampling eq. 35–36, Smith G1 eq. 34; the estimator weight
  G |i.m| / (|i.n| |m.n|) of eq. 41).
* K. Perlin, "An image synthesizer", SIGGRAPH 1985 (turbulence).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import warp as wp

from ..device import device_function, elementwise, get_device
from ..errors import InputError
from ..fields import oil_slick_thickness_wp, soap_film_thickness_wp, turbulence, turbulence_3d
from ..geometry.query import world_normal
from ..materials.dispersion import Biaxial, MaterialTable, material_eval
from ..optics.branches import Cand, add_child
from ..optics.interface import backward_coated, child_of, event_parent
from ..optics.jones import (
    Jones,
    jones_identity,
    s_vector,
)
from ..optics.microfacet import ggx_g1, ggx_sample_normal
from ..optics.thinfilm import CoatingStack, coating_amplitudes_scaled, make_coating_stack
from ..spectra import COARSE_STEP_NM
from ..spectra import grid as spectral_grid
from ..validate import finite_array

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "FilmSurfaces",
    "FilmConfig",
    "SURFACE_KINDS",
    "THICKNESS_PROFILES",
    "film_surface_children",
    "coating_at",
    "film_thickness_nm",
    "layer_material",
    "layer_index_samples",
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
_GRID = spectral_grid(COARSE_STEP_NM)
_GRID_START_NM = float(_GRID[0])
_GRID_STEP_NM = COARSE_STEP_NM


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
    (``soap_film_thickness_wp``), turbulence in 3-D at frequency f per half size.  Oil drop
    (eq. 13): (u, v) = (x, y) / half size, t = t_max exp(-k1 (u^2 + v^2 + k2 turb(f u, f v)))
    (``oil_slick_thickness_wp``)."""
    prof = fs.profile[obj]
    t = fs.nominal_nm[obj]
    if prof == PROFILE_GRAVITY:
        a = fs.profile_a[obj]
        fr = fs.frame[obj]
        sd = fs.profile_seed[obj]
        h = wp.clamp((fr[1] - xl[2]) / wp.max(fr[1] - fr[0], 1.0e-12), 0.0, 1.0)
        turb = turbulence_3d(sd[0], xl * (a[3] / wp.max(fr[2], 1.0e-12)), sd[1])
        t = a[0] + soap_film_thickness_wp(h, a[2], turb, a[1] - a[0])
    elif prof == PROFILE_OIL:
        a = fs.profile_a[obj]
        fr = fs.frame[obj]
        sd = fs.profile_seed[obj]
        u = xl[0] / wp.max(fr[2], 1.0e-12)
        v = xl[1] / wp.max(fr[2], 1.0e-12)
        turb = turbulence(sd[0], u * a[3], v * a[3], sd[1])
        t = oil_slick_thickness_wp(u, v, a[1], a[2], turb, a[0])
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
    nw = world_normal(w2o, nl)
    if wp.dot(nw, face_normal) < 0.0:
        nw = -nw
    return nw


@wp.func
def coating_at(fs: FilmSurfaces, obj: int, x: wp.vec3f, w2o: wp.mat44f):
    """(coating index in ``fs.stack``, thickness scale) of a coated solid at the world point
    ``x``: the layers are scaled so that the stack's total follows the object's thickness
    profile (:func:`film_thickness_nm`).  The interface event with the coating is
    ``optics.interface.backward_isotropic``."""
    scale = float(1.0)
    nominal = fs.nominal_nm[obj]
    if nominal > 0.0:
        scale = film_thickness_nm(fs, obj, wp.transform_point(w2o, x)) / nominal
    return fs.coating[obj], scale


@wp.func(inline=False)  # out of line: compile time (see stages/trace.py trace_radiance)
def film_surface_children(
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
    x: wp.vec3f,
    w2o: wp.mat44f,
    eps: float,
    in_a: int,
    depth: int,
    polarized: int,
    wavelength: float,
    rng: wp.uint32,
):
    """Backward event at a thin shell or an opaque film surface (coated solids are an ordinary
    interface event with the coating's amplitudes, ``optics.interface.backward_isotropic``).

    The backward ray ``d`` (from the camera) meets object ``obj`` at ``x`` with outward face
    normal ``n_out``, arriving from medium A (index ``n_a``, object ``in_a``).  Children (at most
    two) are written to ``cand`` rows 0..count-1; returns (cand, energies, count, rng).  Shells: the
    film's r, and its t straight on (the same medium on both sides, no refraction).  Film
    surfaces: reflection only, over the complex substrate index of ``mat_id``; with roughness
    alpha > 0 the mirror normal is a GGX microfacet normal m and the child's weight
    G2 |i.m| / (|i.n| |m.n|) (Walter et al. 2007, eq. 41), none if the reflection leaves below the
    surface.
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
    # shells and film surfaces: a smooth (analytic) normal, optionally a microfacet normal
    ns = _shading_normal(fs, obj, xl, w2o, nrm)
    if -wp.dot(d, ns) <= 1.0e-6:
        ns = nrm  # the smooth normal turned away from the ray (grazing, silhouette)
    weight = float(1.0)
    alpha = fs.roughness[obj]
    if kind == KIND_FILM and alpha > 0.0:
        u1 = wp.randf(rng)
        u2 = wp.randf(rng)
        mf = ggx_sample_normal(ns, alpha, u1, u2)
        cos_o = -wp.dot(d, ns)
        cos_om = -wp.dot(d, mf)
        if cos_om <= 0.0:
            return cand, energies, count, rng
        d_m = d + mf * (2.0 * cos_om)
        cos_i = wp.dot(d_m, ns)
        if cos_i <= 0.0:
            return cand, energies, count, rng
        weight = ggx_g1(cos_o, alpha) * ggx_g1(cos_i, alpha) * cos_om / (cos_o * wp.dot(mf, ns))
        ns = mf
    cos_a = wp.clamp(-wp.dot(d, ns), 0.0, 1.0)
    s = s_vector(d, ns)
    mb = event_parent(m, k_out, bx, s, polarized)
    d_r = wp.normalize(d + ns * (2.0 * cos_a))
    n_sub = n_a
    if kind == KIND_FILM:
        nsub_o, nsub_e = material_eval(mats, mat_id, wavelength)
        n_sub = nsub_o
        front = 1  # a film surface is seen from its front on either side of the sheet
    if kind == KIND_SHELL:
        # light from the other side passes straight on (no refraction: the same medium)
        rs, rp, ts, tp = coating_amplitudes_scaled(fs.stack, coat, wavelength, cos_a, n_a, n_a, front, scale)
        m_t, w_t = child_of(mb, w, ts, tp, 1.0, polarized)
        cand, energies, count = add_child(
            cand, energies, count, x + d * eps, d, s, m_t, w_t, in_a, depth + 1, -1, -d
        )
    if wp.dot(d_r, nrm) > 0.0:
        # light from A: the stack's front faces A, except on the back of a shell (A on both sides)
        rs, rp, ts, tp = coating_amplitudes_scaled(
            fs.stack, coat, wavelength, cos_a, n_a, n_sub, 1 - front, scale
        )
        m_r, w_r = child_of(mb, w, rs, rp, weight, polarized)
        cand, energies, count = add_child(
            cand, energies, count, x + d_r * eps, d_r, s, m_r, w_r, in_a, depth + 1, -1, -d_r
        )
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
    e = wp.vec4f(0.0, 0.0, 0.0, 0.0)
    count = int(0)
    if fs.kind[obj] == KIND_COATED:
        # a coated solid: the ordinary interface event with the coating's amplitudes
        coat, scale = coating_at(fs, obj, position[i], wp.identity(n=4, dtype=wp.float32))
        entering = wp.dot(d, n_out) < 0.0
        nrm = n_out
        a_is_front = int(1)
        if not entering:
            nrm = -n_out
            a_is_front = 0
        cand, e, count = backward_coated(
            cand,
            jones_identity(),
            1.0,
            bx,
            d,
            n_out,
            nrm,
            n_a,
            n_b,
            position[i],
            1.0e-4,
            in_a,
            in_b,
            0,
            polarized,
            fs.stack,
            coat,
            wavelength[i],
            scale,
            a_is_front,
        )
    else:
        cand, e, count, rng = film_surface_children(
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
            position[i],
            wp.identity(n=4, dtype=wp.float32),
            1.0e-4,
            in_a,
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


def layer_material(spec, file: str | None = None, fld: str = "coating.material"):
    """The Material of a layer's ``material`` value (InputError naming file/field/value)."""
    from ..materials import from_refractiveindex, material_from_spec

    try:
        if isinstance(spec, str) and "/" in spec:
            return from_refractiveindex(spec)
        if isinstance(spec, (str, dict)):
            return material_from_spec(spec)
    except InputError as exc:
        raise InputError(exc.message, file=file, field=fld, value=spec, allowed=exc.allowed) from None
    except (OSError, KeyError, ValueError) as exc:
        raise InputError(f"unknown material ({exc})", file=file, field=fld, value=spec) from None
    raise InputError(
        "must be a material name, a refractiveindex.info page or an inline table",
        file=file,
        field=fld,
        value=spec,
    )


def layer_index_samples(spec) -> np.ndarray | complex:
    """A layer's index n + ik on the coating grid (360-830 nm, 5 nm; clipped to the material's data
    range); a complex ``spec`` is returned as it is (dispersionless)."""
    if isinstance(spec, complex):
        return spec
    mat = layer_material(spec)
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
        layers.append([(layer_index_samples(s), d) for s, d in cfg.layers])
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


def build_film_surfaces(films, shapes, meshes, mats, *, file: str | None = None, device=None) -> FilmSurfaces:
    """The :class:`FilmSurfaces` of a scene's objects: per object its :class:`FilmConfig` (None: bare
    solid) in ``films``, its (shape name, cut parameters) in ``shapes``, its (trimesh, transform) in
    ``meshes`` and its material in ``mats``.  Coated and film objects must be isotropic (InputError
    naming ``file`` and the object)."""
    configs, frames = [], []
    for i, (cfg, (mesh, _), mat) in enumerate(zip(films, meshes, mats, strict=True)):
        # a Biaxial has is_uniaxial False (its own table flag): refused by its class
        if cfg is not None and (getattr(mat, "is_uniaxial", False) or isinstance(mat, Biaxial)):
            raise InputError(
                "coatings, shells and film surfaces need an isotropic material (birefringent "
                "stones are not coated here)",
                file=file,
                field=f"object.{i}.material",
                value=getattr(mat, "name", str(mat)),
            )
        configs.append(cfg)
        lo, hi = np.asarray(mesh.bounds, dtype=np.float64)
        frames.append((lo[2], hi[2], 0.5 * float(np.max(hi - lo))))
    return make_film_surfaces(configs, frames=frames, shapes=list(shapes), device=device)


# ---------------------------------------------------------------------------------------------
# NumPy wrappers
# ---------------------------------------------------------------------------------------------


@device_function(film_surface_children)
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
    """The renderer's backward film event on NumPy rays (``optics.interface.backward_isotropic`` with
    the coating for coated solids, :func:`film_surface_children` for shells and film surfaces).

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
        [
            (finite_array(direction, field="direction"), wp.vec3f),
            (finite_array(normal, field="normal"), wp.vec3f),
            (finite_array(position, field="position"), wp.vec3f),
            (finite_array(wavelength_nm, field="wavelength_nm"), wp.float32),
        ],
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


@device_function(film_thickness_nm)
def film_thickness(config: FilmConfig, position, *, frame=(0.0, 1.0, 1.0), device=None) -> np.ndarray:
    """Film thickness (nm) of :func:`film_thickness_nm` at object-space points (..., 3), mm."""
    dev = get_device(device)
    fs = make_film_surfaces([config], frames=[frame], device=dev)
    (out,) = elementwise(
        _thickness_kernel,
        [(finite_array(position, field="position"), wp.vec3f)],
        [wp.float32],
        extra=(fs, 0),
        device=dev,
    )
    return out
