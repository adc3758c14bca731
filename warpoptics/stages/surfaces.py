"""Opaque surfaces (a table under the stones) and lamps (sun, light boxes) for the camera tracer.

The solids of ``geometry.query`` are gems that the split-tree tracer (``stages.trace``) follows
specularly.  This module adds what a gem photograph has around them:

- **Surfaces**: opaque two-sided rectangles (``[[surface]]``; a ground ``plane`` is a large
  square at ``z = height``), diffuse (Lambertian) or glossy: a dielectric-coated diffuse, a GGX
  lobe (Walter et al. 2007 eq. 33 D, eq. 34 G1, eq. 20 BRDF) with the coat's unpolarized Fresnel
  reflectance from ``optics.fresnel.fresnel_amplitudes``, plus the base weighted by the coat's
  transmittance in and out, (1 - R_i)(1 - R_o) albedo / pi (no inter-reflections in the coat).
  Albedos (colour, checker, image texture; linear sRGB) become reflectance spectra with the
  Mallett–Yuksel basis (``spectra.rgb_spectrum_value`` divided by D65).
- **Lamps**: ``directional`` (a sun: irradiance E on a surface facing it, optional angular
  radius), rectangular ``area`` lights (uniform radiance, one- or two-sided, opaque emitters seen
  by every ray) and ``spot`` lights (intensity I on the axis, E = I cos / d^2, smooth cone
  edge).  A lamp's ``spectrum`` tints its emission through ``spectra.light_spectrum_value``
  (default D65).  The environment (``stages.environment``) stays the background.

At a surface hit (``surface_radiance``): next-event estimation with one sample of every area
light, every sun and the environment, combined with one BSDF-sampled bounce by the power
heuristic (Veach 1997 §9.2.4, beta = 2) for what both can hit; the bounce continues up to
``max_diffuse`` hits with Russian roulette.  A diffuse surface depolarizes: its radiance enters
the branch as an unpolarized source, like the environment.

Shadows through stones (``stone_shadows``).  With 1 (``render.stone_shadows = true``, caustics
off) a shadow or bounce ray that meets a gem is attenuated, not refracted: per stone the
unpolarized Fresnel transmittance 1 - R at entry and exit (at the straight line's angle) times
exp(-alpha l) along the straight chord (uniaxial: the mean of the o- and e-wave filters), giving
coloured shadows but no caustics.  With 0, set by the Renderer whenever ``render.caustics`` is
on, a gem blocks those rays and the light tracer (``stages/caustics.py``) owns every path
lamp -> gem -> surface, so no light through a stone is counted twice
(docs/design/caustics.md, "Path ownership").

References: Walter, Marschner, Li & Torrance, "Microfacet Models for Refraction through Rough
Surfaces", EGSR 2007; Veach 1997, §9.2 (MIS, power heuristic); Pharr, Jakob & Humphreys,
Physically Based Rendering, 3rd ed., §13.6, §14.2; Mallett & Yuksel, "Spectral Primary
Decomposition for Rendering with sRGB Reflectance", EGSR 2019.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import warp as wp

from ..device import device_function, elementwise, get_device
from ..errors import InputError
from ..geometry.directions import polar_azimuth
from ..geometry.query import (
    RayHit,
    SceneGeometry,
    medium_closest_hit,
    object_exit_hit,
    scene_closest_hit,
)
from ..materials.dispersion import MaterialTable
from ..optics.fresnel import fresnel_amplitudes, unpolarized_power
from ..optics.microfacet import ggx_d, ggx_g1, ggx_sample_normal, orthonormal_basis
from ..spectra import (
    SpectralTables,
    illuminant_value,
    light_spectrum_row,
    light_spectrum_value,
    rgb_spectrum_value,
    spectral_tables,
)
from ..validate import choice, finite_array
from .environment import Environment, environment_radiance
from .media import medium_alpha, object_medium, zoned_alpha_pair

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "Surfaces",
    "SurfaceHit",
    "SurfaceConfig",
    "LampConfig",
    "SurfaceStage",
    "BSDF_KINDS",
    "ALBEDO_KINDS",
    "LAMP_KINDS",
    "MIS_MODES",
    "surfaces_closest_hit",
    "surface_radiance",
    "gem_transmittance",
    "albedo_rgb",
    "dielectric_reflectance",
    "bsdf_eval",
    "bsdf_pdf",
    "power_heuristic",
    "env_sample",
    "env_pdf",
    "reflectance_value",
    "rect_irradiance_factor",
    "bsdf_values",
    "reflectance_spectrum",
    "area_emission",
    "sun_irradiance",
    "spot_intensity",
    "lamp_spectrum_row",
]

BSDF_KINDS = {"diffuse": 0, "glossy": 1}
ALBEDO_KINDS = {"color": 0, "checker": 1, "texture": 2}
LAMP_KINDS = ("directional", "area", "spot")
#: how surface hits estimate direct light: both strategies with MIS (the renderer), or only
#: one of them (for tests: each alone is unbiased for area lights and the environment)
MIS_MODES = {"mis": 0, "light": 1, "bsdf": 2}

_GLOSSY = wp.constant(1)
_CHECKER = wp.constant(1)
_TEXTURE = wp.constant(2)
_HIT_NONE = wp.constant(0)
_HIT_SURFACE = wp.constant(1)
_HIT_LIGHT = wp.constant(2)
_MIS = wp.constant(0)
_LIGHT_ONLY = wp.constant(1)
_BSDF_ONLY = wp.constant(2)
_MAX_BOUNCES = 8  # loop bound of the diffuse path (the value used is Surfaces.max_diffuse)
_MAX_STONES = 8  # stones a shadow ray may cross
_EPS = 1.0e-3  # mm, origin offset off a surface
_BIG = 1.0e30
_P_SPEC = 0.5  # glossy: probability of sampling the GGX lobe (the rest: cosine)

# the largest texture atlas (float32 RGB): textures are stacked by rows, the widest sets its width
_MAX_ATLAS_BYTES = 2 << 30


@wp.struct
class Surfaces:
    """Surfaces and lamps of a scene for kernels (one argument).  Arrays have at least one
    (dummy) row; the counts say how many are real.  Geometry in mm, world frame.

    Surface k: rectangle ``centre + a u + b v``, ``|a| <= half[0], |b| <= half[1]`` with unit
    ``normal = u x v``; BSDF ``bsdf`` (0 diffuse, 1 glossy) with ``roughness`` (GGX alpha =
    roughness^2) and coat index ``ior``; albedo ``albedo_kind`` (0 colour ``color_a``, 1 checker
    ``color_a``/``color_b`` of squares ``square`` mm, 2 texture rows ``tex_row .. + tex_size[1]``
    of ``texture`` tiled every ``tile`` (mm x mm) starting at the corner (-half)).
    Area light j: rectangle like a surface, radiance ``a_rgb`` (linear sRGB x D65 basis, Y = 1
    per unit), emitting along ``a_normal`` (both sides if ``a_two_sided``).
    Sun j: unit ``d_dir`` from the scene toward the sun, irradiance ``d_rgb`` on a surface facing
    it, ``d_cos_max`` cosine of the angular radius (1: a delta direction)."""

    num_surfaces: int
    centre: wp.array(dtype=wp.vec3f)
    normal: wp.array(dtype=wp.vec3f)
    u: wp.array(dtype=wp.vec3f)
    v: wp.array(dtype=wp.vec3f)
    half: wp.array(dtype=wp.vec2f)
    bsdf: wp.array(dtype=wp.int32)
    roughness: wp.array(dtype=wp.float32)
    ior: wp.array(dtype=wp.float32)
    albedo_kind: wp.array(dtype=wp.int32)
    color_a: wp.array(dtype=wp.vec3f)
    color_b: wp.array(dtype=wp.vec3f)
    square: wp.array(dtype=wp.float32)
    tile: wp.array(dtype=wp.vec2f)
    tex_row: wp.array(dtype=wp.int32)
    tex_size: wp.array(dtype=wp.vec2i)
    texture: wp.array2d(dtype=wp.vec3f)
    num_area: int
    a_centre: wp.array(dtype=wp.vec3f)
    a_normal: wp.array(dtype=wp.vec3f)
    a_u: wp.array(dtype=wp.vec3f)
    a_v: wp.array(dtype=wp.vec3f)
    a_half: wp.array(dtype=wp.vec2f)
    a_rgb: wp.array(dtype=wp.vec3f)
    a_two_sided: wp.array(dtype=wp.int32)
    num_sun: int
    d_dir: wp.array(dtype=wp.vec3f)
    d_rgb: wp.array(dtype=wp.vec3f)
    d_cos_max: wp.array(dtype=wp.float32)
    num_spot: int
    p_pos: wp.array(dtype=wp.vec3f)  # spot position, mm
    p_dir: wp.array(dtype=wp.vec3f)  # unit axis (the direction the spot shines)
    p_rgb: wp.array(dtype=wp.vec3f)  # radiant intensity on the axis (E = I cos / d^2, d in mm)
    p_cos_outer: wp.array(dtype=wp.float32)  # cos of the cone half-angle (intensity 0 beyond)
    p_cos_inner: wp.array(dtype=wp.float32)  # cos of (half-angle - blend): full intensity within
    a_spectrum: wp.array(dtype=wp.int32)  # light-spectrum row of each area light (-1: D65)
    d_spectrum: wp.array(dtype=wp.int32)  # ... of each sun
    p_spectrum: wp.array(dtype=wp.int32)  # ... of each spot
    env_rows: int  # environment sampling table (0 rows: cosine-weighted sampling instead)
    env_cols: int
    env_marginal: wp.array(dtype=wp.float32)  # (rows + 1) CDF over rows (polar angle bands)
    env_conditional: wp.array(dtype=wp.float32)  # rows x (cols + 1) CDF over columns per row
    env_cell_pdf: wp.array(dtype=wp.float32)  # rows x cols, probability of each cell
    max_diffuse: int  # surface hits per camera-path leaf (1: direct light only)
    mis_mode: int  # 0 MIS, 1 light sampling only, 2 BSDF sampling only
    stone_shadows: int  # 1: straight-through filter; 0: stones block lamps (for caustic tracing)


@wp.struct
class SurfaceHit:
    """Closest surface or lamp hit: ``kind`` 0 none, 1 surface, 2 area light; ``index``; ray
    parameter ``t``; local rectangle coordinates ``a, b`` (mm)."""

    kind: int
    index: int
    t: float
    a: float
    b: float


# ----------------------------------------------------------------------------------------------
# Geometry


@wp.func
def _rect_hit(
    c: wp.vec3f, n: wp.vec3f, u: wp.vec3f, v: wp.vec3f, half: wp.vec2f, o: wp.vec3f, d: wp.vec3f, t_max: float
):
    """Ray parameter and local coordinates of a rectangle hit in (0, t_max), else t = t_max."""
    dn = wp.dot(d, n)
    t_hit = t_max
    a = float(0.0)
    b = float(0.0)
    if wp.abs(dn) > 1.0e-12:
        t = wp.dot(c - o, n) / dn
        if t > 0.0 and t < t_max:
            x = o + d * t - c
            a = wp.dot(x, u)
            b = wp.dot(x, v)
            if wp.abs(a) <= half[0] and wp.abs(b) <= half[1]:
                t_hit = t
    return t_hit, a, b


@wp.func
def surfaces_closest_hit(s: Surfaces, o: wp.vec3f, d: wp.vec3f, t_max: float):
    """Closest surface or area light along the ray within (0, t_max)."""
    h = SurfaceHit()
    h.kind = _HIT_NONE
    h.index = -1
    h.t = t_max
    for k in range(s.num_surfaces):
        t, a, b = _rect_hit(s.centre[k], s.normal[k], s.u[k], s.v[k], s.half[k], o, d, h.t)
        if t < h.t:
            h.kind = _HIT_SURFACE
            h.index = k
            h.t = t
            h.a = a
            h.b = b
    for k in range(s.num_area):
        t, a, b = _rect_hit(s.a_centre[k], s.a_normal[k], s.a_u[k], s.a_v[k], s.a_half[k], o, d, h.t)
        if t < h.t:
            h.kind = _HIT_LIGHT
            h.index = k
            h.t = t
            h.a = a
            h.b = b
    return h


@wp.func
def sample_cone(axis: wp.vec3f, cos_max: float, u1: float, u2: float):
    """A direction uniform in solid angle in the cone of half-angle acos(cos_max) about the unit
    ``axis`` (pdf 1 / (2 pi (1 - cos_max))), from uniform ``u1``, ``u2``."""
    ct = 1.0 - u1 * (1.0 - cos_max)
    st = wp.sqrt(wp.max(1.0 - ct * ct, 0.0))
    ph = 2.0 * wp.pi * u2
    ta, tb = orthonormal_basis(axis)
    return wp.normalize(ta * (st * wp.cos(ph)) + tb * (st * wp.sin(ph)) + axis * ct)


# ----------------------------------------------------------------------------------------------
# BSDF


@wp.func
def reflectance_value(t: SpectralTables, rgb: wp.vec3f, wavelength: float):
    """Spectral reflectance of a linear-sRGB albedo: the emitter spectrum of the colour
    (D65 x Mallett–Yuksel basis, ``rgb_spectrum_value``) divided by D65, in [0, 1] for
    colours in [0, 1]^3 (the basis spectra sum to 1)."""
    d65 = illuminant_value(t, 1, wavelength)
    r = float(0.0)
    if d65 > 0.0:
        r = rgb_spectrum_value(t, rgb, wavelength) / d65
    return wp.max(r, 0.0)


@wp.func
def dielectric_reflectance(cos_i: float, ior: float):
    """Unpolarized Fresnel reflectance (|rs|^2 + |rp|^2) / 2 from air onto a coat of index ``ior``
    (``optics.fresnel.fresnel_amplitudes``)."""
    f = fresnel_amplitudes(cos_i, wp.vec2f(1.0, 0.0), wp.vec2f(ior, 0.0))
    return unpolarized_power(f.rs, f.rp)


@wp.func
def bsdf_eval(
    kind: int, albedo: float, roughness: float, ior: float, n: wp.vec3f, wo: wp.vec3f, wi: wp.vec3f
):
    """BSDF value f(wo, wi) (1/sr) of a surface with unit normal ``n`` on the side of ``wo``;
    ``wo`` toward the viewer, ``wi`` toward the light (both unit, pointing away from the
    surface).  Diffuse: albedo / pi.  Glossy: GGX coat + transmitted diffuse (module doc)."""
    ci = wp.dot(n, wi)
    co = wp.dot(n, wo)
    if ci <= 0.0 or co <= 0.0:
        return 0.0
    if kind != _GLOSSY:
        return albedo / wp.pi
    alpha = wp.max(roughness * roughness, 1.0e-4)
    h = wp.normalize(wi + wo)
    f_spec = dielectric_reflectance(wp.dot(wi, h), ior)
    spec = f_spec * ggx_d(wp.dot(n, h), alpha) * ggx_g1(ci, alpha) * ggx_g1(co, alpha) / (4.0 * ci * co)
    diff = (1.0 - dielectric_reflectance(ci, ior)) * (1.0 - dielectric_reflectance(co, ior)) * albedo / wp.pi
    return spec + diff


@wp.func
def bsdf_pdf(kind: int, roughness: float, n: wp.vec3f, wo: wp.vec3f, wi: wp.vec3f):
    """Solid-angle pdf (1/sr) of :func:`bsdf_sample` choosing ``wi``."""
    ci = wp.dot(n, wi)
    if ci <= 0.0 or wp.dot(n, wo) <= 0.0:
        return 0.0
    p_cos = ci / wp.pi
    if kind != _GLOSSY:
        return p_cos
    alpha = wp.max(roughness * roughness, 1.0e-4)
    h = wp.normalize(wi + wo)
    ch = wp.dot(n, h)
    p_spec = ggx_d(ch, alpha) * ch / (4.0 * wp.max(wp.abs(wp.dot(wo, h)), 1.0e-8))
    return _P_SPEC * p_spec + (1.0 - _P_SPEC) * p_cos


@wp.func
def _cosine_dir(n: wp.vec3f, u1: float, u2: float):
    t, b = orthonormal_basis(n)
    r = wp.sqrt(u1)
    phi = 2.0 * wp.pi * u2
    return wp.normalize(t * (r * wp.cos(phi)) + b * (r * wp.sin(phi)) + n * wp.sqrt(wp.max(1.0 - u1, 0.0)))


@wp.func
def bsdf_sample(kind: int, roughness: float, n: wp.vec3f, wo: wp.vec3f, u0: float, u1: float, u2: float):
    """A direction ``wi`` drawn from the BSDF's sampling density (cosine; glossy: with
    probability 1/2 a GGX half vector, Walter et al. 2007 eq. 35-36, reflected about it)."""
    if kind != _GLOSSY or u0 >= _P_SPEC:
        return _cosine_dir(n, u1, u2)
    h = ggx_sample_normal(n, wp.max(roughness * roughness, 1.0e-4), u1, u2)
    return wp.normalize(h * (2.0 * wp.dot(wo, h)) - wo)


@wp.func
def cdf_find(cdf: wp.array(dtype=wp.float32), start: int, count: int, u: float):
    # index j in [0, count) with cdf[start + j] <= u < cdf[start + j + 1] (binary search)
    lo = int(0)
    hi = count
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if cdf[start + mid] <= u:
            lo = mid
        else:
            hi = mid
    return lo


@wp.func
def env_sample(s: Surfaces, u1: float, u2: float, u3: float, u4: float):
    """A direction drawn from the environment table: a cell by its probability (marginal row,
    then column), then uniform in (polar angle, azimuth) within the cell.  The table is over
    world directions, z up: theta = acos(z) in rows, phi = atan2(y, x) in columns."""
    row = cdf_find(s.env_marginal, 0, s.env_rows, u1)
    col = cdf_find(s.env_conditional, row * (s.env_cols + 1), s.env_cols, u2)
    theta = (float(row) + u3) * wp.pi / float(s.env_rows)
    phi = (float(col) + u4) * 2.0 * wp.pi / float(s.env_cols) - wp.pi
    st = wp.sin(theta)
    return wp.vec3f(st * wp.cos(phi), st * wp.sin(phi), wp.cos(theta))


@wp.func
def env_pdf(s: Surfaces, d: wp.vec3f):
    """Solid-angle pdf (1/sr) of :func:`env_sample` drawing unit ``d``: cell probability over
    the cell's (theta, phi) area times the Jacobian 1 / sin(theta)."""
    theta, phi = polar_azimuth(d)
    row = wp.clamp(int(theta / wp.pi * float(s.env_rows)), 0, s.env_rows - 1)
    col = wp.clamp(int((phi + wp.pi) / (2.0 * wp.pi) * float(s.env_cols)), 0, s.env_cols - 1)
    st = wp.sin(theta)
    if st <= 1.0e-7:
        return 0.0
    p = s.env_cell_pdf[row * s.env_cols + col]
    area = (wp.pi / float(s.env_rows)) * (2.0 * wp.pi / float(s.env_cols))
    return p / (area * st)


@wp.func
def power_heuristic(pdf_a: float, pdf_b: float):
    """Veach's power heuristic (beta = 2): weight of strategy a against b (one sample each)."""
    a2 = pdf_a * pdf_a
    s = a2 + pdf_b * pdf_b
    if s <= 0.0:
        return 0.0
    return a2 / s


@wp.func
def albedo_rgb(s: Surfaces, k: int, a: float, b: float):
    kind = s.albedo_kind[k]
    if kind == _CHECKER:
        sq = s.square[k]
        ia = int(wp.floor(a / sq))
        ib = int(wp.floor(b / sq))
        if ((ia + ib) % 2 + 2) % 2 == 1:
            return s.color_b[k]
        return s.color_a[k]
    if kind == _TEXTURE:
        tile = s.tile[k]
        size = s.tex_size[k]
        fu = (a + s.half[k][0]) / tile[0]
        fv = (b + s.half[k][1]) / tile[1]
        fu = fu - wp.floor(fu)
        fv = fv - wp.floor(fv)
        # image row 0 at the top (far v edge), nearest texel
        ix = wp.clamp(int(fu * float(size[0])), 0, size[0] - 1)
        iy = wp.clamp(int((1.0 - fv) * float(size[1])), 0, size[1] - 1)
        return s.texture[s.tex_row[k] + iy, ix]
    return s.color_a[k]


# ----------------------------------------------------------------------------------------------
# Lamps and shadows


@wp.func
def _area_emission(s: Surfaces, t: SpectralTables, k: int, d: wp.vec3f, wavelength: float):
    """Radiance of area light k seen along ray direction ``d`` (from the viewer to the lamp)."""
    c = -wp.dot(d, s.a_normal[k])
    if c <= 0.0 and s.a_two_sided[k] == 0:
        return 0.0
    return area_emission(s, t, k, wavelength)


@wp.func
def area_emission(s: Surfaces, t: SpectralTables, k: int, wavelength: float):
    """Spectral radiance of area light k on its emitting side(s) at ``wavelength`` (nm)."""
    return light_spectrum_value(t, s.a_spectrum[k], s.a_rgb[k], wavelength)


@wp.func
def sun_irradiance(s: Surfaces, t: SpectralTables, k: int, wavelength: float):
    """Spectral irradiance of sun k on a surface facing it at ``wavelength`` (nm)."""
    return light_spectrum_value(t, s.d_spectrum[k], s.d_rgb[k], wavelength)


@wp.func
def spot_intensity(s: Surfaces, t: SpectralTables, k: int, wavelength: float):
    """Spectral radiant intensity of spot k on its axis at ``wavelength`` (nm)."""
    return light_spectrum_value(t, s.p_spectrum[k], s.p_rgb[k], wavelength)


@wp.func
def _area_pdf(s: Surfaces, k: int, d: wp.vec3f, dist: float):
    """Solid-angle pdf of sampling area light k uniformly by area, seen along ``d`` at ``dist``."""
    h = s.a_half[k]
    area = 4.0 * h[0] * h[1]
    c = wp.abs(wp.dot(d, s.a_normal[k]))
    if c <= 1.0e-8 or area <= 0.0:
        return 0.0
    return dist * dist / (area * c)


@wp.func
def _interface_t(cos_i: float, n1: wp.vec2f, n2: wp.vec2f):
    # unpolarized power transmittance 1 - R of a lossless interface
    f = fresnel_amplitudes(cos_i, n1, n2)
    return 1.0 - unpolarized_power(f.rs, f.rp)


@wp.func
def _medium_index_alpha(
    mats: MaterialTable,
    obj_material: wp.array(dtype=wp.int32),
    obj_absorption: wp.array(dtype=wp.float32),
    ambient: float,
    k: int,
    wavelength: float,
    rgb3_channel: int,
):
    """(real index, alpha 1/mm) of the medium of object ``k`` (-1: the ambient medium) for a
    straight-through shadow ray: a crystal's mean index and mean of its o/e absorption."""
    if k < 0:
        return ambient, 0.0
    mid = obj_material[k]
    med, no, ne, alpha = object_medium(mats, mid, wp.vec3f(0.0), wavelength)
    a_o, a_e = medium_alpha(mats, mid, alpha, rgb3_channel)
    return 0.5 * (no[0] + ne[0]), 0.5 * (a_o + a_e) * obj_absorption[k]


@wp.func
def _nested_transmittance(
    geom: SceneGeometry,
    mats: MaterialTable,
    obj_material: wp.array(dtype=wp.int32),
    obj_absorption: wp.array(dtype=wp.float32),
    ambient: float,
    x: wp.vec3f,
    d: wp.vec3f,
    t_max: float,
    wavelength: float,
    rgb3_channel: int,
):
    """:func:`gem_transmittance` in a scene of nested solids (a stone in a glass of water): the
    straight segment from medium to medium (``geometry.query.medium_closest_hit``; leaving a solid
    enters the one around it), Fresnel 1 - R between the indices on the two sides of every
    interface (from its outer side, as there) and Bouguer-Lambert along every segment inside a
    solid."""
    tr = float(1.0)
    o = x
    remaining = t_max
    cur = int(-1)  # surfaces and lamps lie in the ambient medium
    n_cur = ambient
    a_cur = float(0.0)
    for _i in range(2 * _MAX_STONES):
        if tr <= 0.0:
            break
        h = RayHit()
        if cur < 0:
            h = scene_closest_hit(geom, o, d, remaining)
        else:
            h = medium_closest_hit(geom, cur, o, d, remaining)
        if h.object < 0:
            break
        k = h.object
        nxt = k
        if wp.dot(d, h.normal) >= 0.0:
            nxt = geom.parent[k]  # leaving k into the solid around it
        n_nxt, a_nxt = _medium_index_alpha(
            mats, obj_material, obj_absorption, ambient, nxt, wavelength, rgb3_channel
        )
        # Fresnel seen from the outer side of k's surface at the straight ray's angle, entering or
        # leaving (no refraction, no total reflection: gem_transmittance's model)
        n_outer = n_cur
        n_inner = n_nxt
        if nxt != k:
            n_outer = n_nxt
            n_inner = n_cur
        cos_i = wp.abs(wp.dot(d, h.normal))
        a_seg = a_cur
        if cur >= 0:
            if mats.zone_count[obj_material[cur]] > 0:
                # a colour-zoned stone: the mean o/e absorption of this segment through its zones
                pair = zoned_alpha_pair(
                    mats, obj_material[cur], 0.0, 0.0, rgb3_channel, wavelength, o, d, h.t
                )
                a_seg = 0.5 * (pair[0] + pair[1]) * obj_absorption[cur]
        tr *= wp.exp(-a_seg * h.t) * _interface_t(cos_i, wp.vec2f(n_outer, 0.0), wp.vec2f(n_inner, 0.0))
        eps = geom.epsilon[k]
        remaining = remaining - h.t - eps
        if remaining <= 0.0:
            break
        o = o + d * (h.t + eps)
        cur = nxt
        n_cur = n_nxt
        a_cur = a_nxt
    return tr


@wp.func
def gem_transmittance(
    geom: SceneGeometry,
    mats: MaterialTable,
    obj_material: wp.array(dtype=wp.int32),
    obj_absorption: wp.array(dtype=wp.float32),
    ambient: float,
    x: wp.vec3f,
    d: wp.vec3f,
    t_max: float,
    wavelength: float,
    rgb3_channel: int,
):
    """Straight-through transmittance of the stones along the segment x + t d, 0 < t < t_max
    (module doc: Fresnel 1 - R at entry and exit x exp(-alpha l); refraction is NOT followed).
    ``rgb3_channel`` >= 0: the rgb3 mode's eq. 9 absorbances of that channel, as the tracer uses.
    Nested solids: :func:`_nested_transmittance`."""
    if geom.nested != 0:
        return _nested_transmittance(
            geom, mats, obj_material, obj_absorption, ambient, x, d, t_max, wavelength, rgb3_channel
        )
    tr = float(1.0)
    o = x
    remaining = t_max
    for _i in range(_MAX_STONES):
        if geom.num_objects == 0 or tr <= 0.0:
            break
        h = scene_closest_hit(geom, o, d, remaining)
        if h.object < 0:
            break
        k = h.object
        eps = geom.epsilon[k]  # the tracer's origin offset (geometry.query.offset_epsilon)
        p_in = o + d * h.t
        ex = object_exit_hit(geom, k, p_in + d * eps, d, _BIG)
        chord = float(0.0)
        cos_out = float(1.0)
        if ex.object >= 0:
            chord = ex.t + eps
            cos_out = wp.abs(wp.dot(d, ex.normal))
        cos_in = wp.abs(wp.dot(d, h.normal))
        mid = obj_material[k]
        med, no, ne, alpha = object_medium(mats, mid, wp.vec3f(0.0), wavelength)
        a_o, a_e = medium_alpha(mats, mid, alpha, rgb3_channel)
        # a colour-zoned stone: the mean o/e absorption of the chord through its zones
        a_oe = zoned_alpha_pair(mats, mid, a_o, a_e, rgb3_channel, wavelength, p_in, d, chord)
        a_o = a_oe[0]
        a_e = a_oe[1]
        sc = obj_absorption[k]
        amb = wp.vec2f(ambient, 0.0)
        n_o = wp.vec2f(no[0], 0.0)
        n_e = wp.vec2f(ne[0], 0.0)
        t_o = _interface_t(cos_in, amb, n_o) * _interface_t(cos_out, amb, n_o)
        t_e = _interface_t(cos_in, amb, n_e) * _interface_t(cos_out, amb, n_e)
        tr *= 0.5 * (t_o * wp.exp(-a_o * sc * chord) + t_e * wp.exp(-a_e * sc * chord))
        step = h.t + chord + eps
        remaining = remaining - step
        if remaining <= 0.0:
            break
        o = o + d * step
    return tr


@wp.func
def _visibility(
    s: Surfaces,
    geom: SceneGeometry,
    mats: MaterialTable,
    obj_material: wp.array(dtype=wp.int32),
    obj_absorption: wp.array(dtype=wp.float32),
    ambient: float,
    x: wp.vec3f,
    d: wp.vec3f,
    dist: float,
    wavelength: float,
    rgb3_channel: int,
):
    """Transmittance of a shadow ray: 0 if a surface or lamp blocks it, else the stones' filter."""
    h = surfaces_closest_hit(s, x, d, dist)
    if h.kind != _HIT_NONE:
        return 0.0
    if geom.num_objects == 0:
        return 1.0
    if s.stone_shadows == 0:
        g = scene_closest_hit(geom, x, d, dist)
        if g.object >= 0:
            return 0.0
        return 1.0
    return gem_transmittance(
        geom, mats, obj_material, obj_absorption, ambient, x, d, dist, wavelength, rgb3_channel
    )


@wp.func(inline=False)  # out of line: compile time (see trace_radiance)
def surface_radiance(
    s: Surfaces,
    geom: SceneGeometry,
    mats: MaterialTable,
    env: Environment,
    tables: SpectralTables,
    obj_material: wp.array(dtype=wp.int32),
    obj_absorption: wp.array(dtype=wp.float32),
    ambient: float,
    origin: wp.vec3f,
    direction: wp.vec3f,
    first: SurfaceHit,
    wavelength: float,
    rgb3_channel: int,
    rng: wp.uint32,
):
    """Unpolarized spectral radiance leaving the surface or lamp ``first`` (found along the ray
    origin + t direction) toward the ray's origin, at ``wavelength`` (nm).  Returns (L, rng).

    Lamps: their emission.  Surfaces: NEE of every lamp and the environment, MIS with BSDF
    sampling, and a BSDF-sampled diffuse path of up to ``s.max_diffuse`` surface hits."""
    if first.kind == _HIT_LIGHT:
        return _area_emission(s, tables, first.index, direction, wavelength), rng
    radiance = float(0.0)
    beta = float(1.0)
    hit = first
    ro = origin
    rd = direction
    for bounce in range(_MAX_BOUNCES):
        k = hit.index
        x = ro + rd * hit.t
        n = s.normal[k]
        if wp.dot(rd, n) > 0.0:
            n = -n
        wo = -rd
        kind = s.bsdf[k]
        rough = s.roughness[k]
        ior = s.ior[k]
        albedo = reflectance_value(tables, albedo_rgb(s, k, hit.a, hit.b), wavelength)
        xs = x + n * _EPS
        # --- next-event estimation: one sample of every lamp and of the environment
        if s.mis_mode != _BSDF_ONLY:
            for j in range(s.num_area):
                h2 = s.a_half[j]
                p = (
                    s.a_centre[j]
                    + s.a_u[j] * ((2.0 * wp.randf(rng) - 1.0) * h2[0])
                    + s.a_v[j] * ((2.0 * wp.randf(rng) - 1.0) * h2[1])
                )
                to = p - xs
                dist = wp.length(to)
                if dist <= 0.0:
                    continue
                wi = to / dist
                le = _area_emission(s, tables, j, wi, wavelength)
                pdf_l = _area_pdf(s, j, wi, dist)
                if le <= 0.0 or pdf_l <= 0.0:
                    continue
                f = bsdf_eval(kind, albedo, rough, ior, n, wo, wi)
                if f <= 0.0:
                    continue
                vis = _visibility(
                    s,
                    geom,
                    mats,
                    obj_material,
                    obj_absorption,
                    ambient,
                    xs,
                    wi,
                    dist * 0.999,
                    wavelength,
                    rgb3_channel,
                )
                w = float(1.0)
                if s.mis_mode == _MIS:
                    w = power_heuristic(pdf_l, bsdf_pdf(kind, rough, n, wo, wi))
                radiance += beta * w * f * wp.dot(n, wi) * le * vis / pdf_l
            # the environment: its importance table, or cosine-weighted directions about the normal
            wi_e = wp.vec3f(0.0, 0.0, 1.0)
            pdf_e = float(0.0)
            if s.env_rows > 0:
                wi_e = env_sample(s, wp.randf(rng), wp.randf(rng), wp.randf(rng), wp.randf(rng))
                if wp.dot(n, wi_e) > 0.0:
                    pdf_e = env_pdf(s, wi_e)
            else:
                wi_e = _cosine_dir(n, wp.randf(rng), wp.randf(rng))
                pdf_e = wp.dot(n, wi_e) / wp.pi
            if pdf_e > 0.0:
                f = bsdf_eval(kind, albedo, rough, ior, n, wo, wi_e)
                if f > 0.0:
                    le = environment_radiance(env, tables, wi_e, wavelength)
                    if le > 0.0:
                        vis = _visibility(
                            s,
                            geom,
                            mats,
                            obj_material,
                            obj_absorption,
                            ambient,
                            xs,
                            wi_e,
                            _BIG,
                            wavelength,
                            rgb3_channel,
                        )
                        w = float(1.0)
                        if s.mis_mode == _MIS:
                            w = power_heuristic(pdf_e, bsdf_pdf(kind, rough, n, wo, wi_e))
                        radiance += beta * w * f * wp.dot(n, wi_e) * le * vis / pdf_e
        # suns (delta or small cones): light sampling only (no BSDF ray can find them)
        for j in range(s.num_sun):
            wi = s.d_dir[j]
            cmax = s.d_cos_max[j]
            scale = float(1.0)  # E cos / (radiance integral): 1 for a delta sun
            if cmax < 1.0:
                # uniform direction in the cone; radiance E / (pi sin^2 r), pdf 1 / (2 pi (1 - cos r))
                u1 = wp.randf(rng)
                wi = sample_cone(wi, cmax, u1, wp.randf(rng))
                scale = 2.0 * (1.0 - cmax) / (1.0 - cmax * cmax)
            cos_i = wp.dot(n, wi)
            if cos_i <= 0.0:
                continue
            f = bsdf_eval(kind, albedo, rough, ior, n, wo, wi)
            if f <= 0.0:
                continue
            e = sun_irradiance(s, tables, j, wavelength)
            vis = _visibility(
                s, geom, mats, obj_material, obj_absorption, ambient, xs, wi, _BIG, wavelength, rgb3_channel
            )
            radiance += beta * f * cos_i * e * scale * vis
        # spots (point lights with a smooth cone edge): light sampling only, like the suns
        for j in range(s.num_spot):
            to = s.p_pos[j] - xs
            dist2 = wp.dot(to, to)
            if dist2 <= 0.0:
                continue
            dist = wp.sqrt(dist2)
            wi = to / dist
            cos_i = wp.dot(n, wi)
            if cos_i <= 0.0:
                continue
            c_ax = -wp.dot(wi, s.p_dir[j])
            co = s.p_cos_outer[j]
            cin = s.p_cos_inner[j]
            fall = float(0.0)
            if cin - co > 1.0e-7:
                fall = wp.smoothstep(co, cin, c_ax)
            elif c_ax >= co:
                fall = 1.0
            if fall <= 0.0:
                continue
            f = bsdf_eval(kind, albedo, rough, ior, n, wo, wi)
            if f <= 0.0:
                continue
            e = spot_intensity(s, tables, j, wavelength) * fall / dist2
            vis = _visibility(
                s,
                geom,
                mats,
                obj_material,
                obj_absorption,
                ambient,
                xs,
                wi,
                dist * 0.999,
                wavelength,
                rgb3_channel,
            )
            radiance += beta * f * cos_i * e * vis
        # --- BSDF-sampled bounce: finds area lights and the environment (MIS), and other surfaces
        wi = bsdf_sample(kind, rough, n, wo, wp.randf(rng), wp.randf(rng), wp.randf(rng))
        pdf_b = bsdf_pdf(kind, rough, n, wo, wi)
        if pdf_b <= 0.0:
            break
        f = bsdf_eval(kind, albedo, rough, ior, n, wo, wi)
        beta = beta * f * wp.dot(n, wi) / pdf_b
        if beta <= 0.0:
            break
        nxt = surfaces_closest_hit(s, xs, wi, _BIG)
        if geom.num_objects > 0:
            if s.stone_shadows == 0:
                g = scene_closest_hit(geom, xs, wi, nxt.t)
                if g.object >= 0:
                    break
            else:
                beta = beta * gem_transmittance(
                    geom, mats, obj_material, obj_absorption, ambient, xs, wi, nxt.t, wavelength, rgb3_channel
                )
        if nxt.kind == _HIT_NONE:
            if s.mis_mode != _LIGHT_ONLY:
                w = float(1.0)
                if s.mis_mode == _MIS:
                    pdf_env = wp.dot(n, wi) / wp.pi
                    if s.env_rows > 0:
                        pdf_env = env_pdf(s, wi)
                    w = power_heuristic(pdf_b, pdf_env)
                radiance += beta * w * environment_radiance(env, tables, wi, wavelength)
            break
        if nxt.kind == _HIT_LIGHT:
            if s.mis_mode != _LIGHT_ONLY:
                w = float(1.0)
                if s.mis_mode == _MIS:
                    w = power_heuristic(pdf_b, _area_pdf(s, nxt.index, wi, nxt.t))
                radiance += beta * w * _area_emission(s, tables, nxt.index, wi, wavelength)
            break
        # another surface: continue the diffuse path (Russian roulette after the first bounce)
        if bounce + 1 >= s.max_diffuse:
            break
        if bounce >= 1:
            q = wp.min(beta, 0.95)
            if wp.randf(rng) >= q:
                break
            beta = beta / q
        hit = nxt
        ro = xs
        rd = wi
    return radiance, rng


@wp.func
def rect_irradiance_factor(a: float, b: float, c: float):
    """Configuration factor from a point to a parallel a x b rectangle at distance c with one
    corner straight above the point (Siegel & Howell, *Thermal Radiation Heat Transfer*, app. C,
    factor C-11 / Howell's catalogue B-3): E = pi L F for uniform radiance L."""
    aa = a / c
    bb = b / c
    sa = wp.sqrt(1.0 + aa * aa)
    sb = wp.sqrt(1.0 + bb * bb)
    return (aa / sa * wp.atan(bb / sa) + bb / sb * wp.atan(aa / sb)) / (2.0 * wp.pi)


# ----------------------------------------------------------------------------------------------
# Kernels (NumPy wrappers)


@wp.kernel
def _bsdf_kernel(
    offset: int,
    kind: wp.array(dtype=wp.int32),
    albedo: wp.array(dtype=wp.float32),
    roughness: wp.array(dtype=wp.float32),
    ior: wp.array(dtype=wp.float32),
    n: wp.array(dtype=wp.vec3f),
    wo: wp.array(dtype=wp.vec3f),
    wi: wp.array(dtype=wp.vec3f),
    f_out: wp.array(dtype=wp.float32),
    pdf_out: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    f_out[i] = bsdf_eval(kind[i], albedo[i], roughness[i], ior[i], n[i], wo[i], wi[i])
    pdf_out[i] = bsdf_pdf(kind[i], roughness[i], n[i], wo[i], wi[i])


@wp.kernel
def _env_table_kernel(
    offset: int,
    env: Environment,
    tables: SpectralTables,
    rows: int,
    cols: int,
    sub: int,
    out: wp.array(dtype=wp.float32),
):
    # mean radiance (sum of 3 wavelengths) over sub x sub directions of each (theta, phi) cell
    i = wp.tid() + offset
    row = i / cols
    col = i - row * cols
    acc = float(0.0)
    for a in range(sub):
        for b in range(sub):
            theta = (float(row) + (float(a) + 0.5) / float(sub)) * wp.pi / float(rows)
            phi = (float(col) + (float(b) + 0.5) / float(sub)) * 2.0 * wp.pi / float(cols) - wp.pi
            st = wp.sin(theta)
            d = wp.vec3f(st * wp.cos(phi), st * wp.sin(phi), wp.cos(theta))
            for k in range(3):
                acc += environment_radiance(env, tables, d, 450.0 + 100.0 * float(k))
    out[i] = acc / float(sub * sub)


@wp.kernel
def _reflectance_kernel(
    offset: int,
    rgb: wp.array(dtype=wp.vec3f),
    wavelength: wp.array(dtype=wp.float32),
    tables: SpectralTables,
    out: wp.array(dtype=wp.float32),
):
    i = wp.tid() + offset
    out[i] = reflectance_value(tables, rgb[i], wavelength[i])


# ----------------------------------------------------------------------------------------------
# Python side


@device_function(bsdf_eval)
def bsdf_values(kind: str, albedo, roughness, ior, normal, wo, wi, *, device=None):
    """NumPy wrapper of :func:`bsdf_eval` and :func:`bsdf_pdf`: returns (f, pdf), broadcast."""
    k = BSDF_KINDS[choice(kind, BSDF_KINDS, field="kind")]
    f, pdf = elementwise(
        _bsdf_kernel,
        [
            (k, wp.int32),
            (finite_array(albedo, field="albedo"), wp.float32),
            (finite_array(roughness, field="roughness"), wp.float32),
            (finite_array(ior, field="ior"), wp.float32),
            (finite_array(normal, field="normal"), wp.vec3f),
            (finite_array(wo, field="wo"), wp.vec3f),
            (finite_array(wi, field="wi"), wp.vec3f),
        ],
        [wp.float32, wp.float32],
        device=device,
    )
    return f, pdf


@device_function(reflectance_value)
def reflectance_spectrum(rgb, wavelength_nm, *, device=None) -> np.ndarray:
    """NumPy wrapper of :func:`reflectance_value`: reflectance of linear-sRGB albedos at λ (nm)."""
    (out,) = elementwise(
        _reflectance_kernel,
        [
            (finite_array(rgb, field="rgb"), wp.vec3f),
            (finite_array(wavelength_nm, field="wavelength_nm"), wp.float32),
        ],
        [wp.float32],
        extra=(spectral_tables(device),),
        device=device,
    )
    return out


@dataclass(frozen=True)
class SurfaceConfig:
    """``[[surface]]``: an opaque rectangle (``type = "plane"``: a ``size`` x ``size`` square at
    ``z = height``, normal +z; ``type = "rectangle"``: ``center``, ``normal``, ``size = [w, h]``,
    optional ``up`` for the direction of the h edge), a BSDF and an albedo."""

    center: tuple[float, float, float] = (0.0, 0.0, 0.0)
    normal: tuple[float, float, float] = (0.0, 0.0, 1.0)
    up: tuple[float, float, float] | None = None
    size: tuple[float, float] = (1000.0, 1000.0)
    bsdf: str = "diffuse"
    roughness: float = 0.3
    ior: float = 1.5
    albedo: str = "color"
    color: tuple[float, float, float] = (0.5, 0.5, 0.5)
    color2: tuple[float, float, float] = (0.1, 0.1, 0.1)
    square: float = 1.0
    texture: str | None = None
    tile: tuple[float, float] = (10.0, 10.0)


@dataclass(frozen=True)
class LampConfig:
    """``[[light]] type = "directional"`` (``direction`` the light travels, ``irradiance``,
    ``tint``, ``angular_radius`` degrees), ``type = "area"`` (``center``, ``normal`` the
    emitting side faces, ``size = [w, h]``, ``up``, ``radiance``, ``tint``, ``double_sided``) or
    ``type = "spot"`` (``center`` its position, ``direction`` its axis, ``intensity`` on the axis,
    ``cone_angle`` half-angle and ``blend`` of the soft edge, degrees)."""

    type: str
    direction: tuple[float, float, float] = (0.0, 0.0, -1.0)
    irradiance: float = 1.0
    angular_radius: float = 0.0
    center: tuple[float, float, float] = (0.0, 0.0, 10.0)
    normal: tuple[float, float, float] = (0.0, 0.0, -1.0)
    up: tuple[float, float, float] | None = None
    size: tuple[float, float] = (10.0, 10.0)
    radiance: float = 1.0
    tint: tuple[float, float, float] = (1.0, 1.0, 1.0)
    double_sided: bool = False
    intensity: float = 1.0
    cone_angle: float = 30.0
    blend: float = 5.0
    # the lamp's white (module docstring): a name of spectra.light_spectrum_names(); None: D65
    spectrum: str | None = None
    source: str | None = field(default=None, compare=False)

    def __post_init__(self):
        if self.spectrum is not None:
            light_spectrum_row(self.spectrum, file=self.source, field="light.spectrum")


def lamp_spectrum_row(spectrum: str | None) -> int:
    """The ``Surfaces.*_spectrum`` row of a lamp with light spectrum ``spectrum``: -1 (the D65 x
    basis table, the values before light spectra existed, bit for bit) for None or D65."""
    if spectrum is None:
        return -1
    row = light_spectrum_row(spectrum)
    return -1 if row == 1 else row


def _frame(normal, up) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(n, u, v) with v along ``up`` made perpendicular to n (default: +y, or +x for n ~ y)."""
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    if up is None:
        up = (0.0, 1.0, 0.0) if abs(n[1]) < 0.9 else (1.0, 0.0, 0.0)
    v = np.asarray(up, dtype=np.float64)
    v = v - n * (v @ n)
    v = v / np.linalg.norm(v)
    u = np.cross(v, n)  # u x v = n
    return n, u, v


def _arr(values, dtype, width, device):
    a = np.asarray(values, dtype=np.float32 if dtype not in (wp.int32, wp.vec2i) else np.int32)
    if len(a) == 0:
        a = np.zeros((1, width) if width > 1 else (1,), dtype=a.dtype)
    return wp.array(a, dtype=dtype, device=device)


class SurfaceStage:
    """Owns the :class:`Surfaces` struct of a scene's surfaces and lamps on a device."""

    def __init__(
        self,
        surfaces=(),
        lamps=(),
        *,
        max_diffuse: int = 3,
        mis: str = "mis",
        stone_shadows: bool = True,
        environment=None,
        env_table: tuple[int, int] = (64, 128),
        source: str | None = None,
        device=None,
    ):
        dev = get_device(device)
        self.device = dev
        s = Surfaces()
        rows = {
            k: []
            for k in (
                "centre",
                "normal",
                "u",
                "v",
                "half",
                "bsdf",
                "rough",
                "ior",
                "akind",
                "ca",
                "cb",
                "square",
                "tile",
                "tex_row",
                "tex_size",
            )
        }
        textures = []
        tex_rows = 0
        for i, sc in enumerate(surfaces):
            n, u, v = _frame(sc.normal, sc.up)
            rows["centre"].append(sc.center)
            rows["normal"].append(n)
            rows["u"].append(u)
            rows["v"].append(v)
            rows["half"].append((sc.size[0] / 2, sc.size[1] / 2))
            rows["bsdf"].append(BSDF_KINDS[sc.bsdf])
            rows["rough"].append(sc.roughness)
            rows["ior"].append(sc.ior)
            rows["akind"].append(ALBEDO_KINDS[sc.albedo])
            rows["ca"].append(sc.color)
            rows["cb"].append(sc.color2)
            rows["square"].append(sc.square)
            rows["tile"].append(sc.tile)
            if sc.albedo == "texture":
                tex = _load_texture(sc.texture, source, f"surface.{i}.texture")
                rows["tex_row"].append(tex_rows)
                rows["tex_size"].append((tex.shape[1], tex.shape[0]))
                textures.append(tex)
                tex_rows += tex.shape[0]
            else:
                rows["tex_row"].append(0)
                rows["tex_size"].append((1, 1))
        s.num_surfaces = len(surfaces)
        s.centre = _arr(rows["centre"], wp.vec3f, 3, dev)
        s.normal = _arr(rows["normal"], wp.vec3f, 3, dev)
        s.u = _arr(rows["u"], wp.vec3f, 3, dev)
        s.v = _arr(rows["v"], wp.vec3f, 3, dev)
        s.half = _arr(rows["half"], wp.vec2f, 2, dev)
        s.bsdf = _arr(rows["bsdf"], wp.int32, 1, dev)
        s.roughness = _arr(rows["rough"], wp.float32, 1, dev)
        s.ior = _arr(rows["ior"], wp.float32, 1, dev)
        s.albedo_kind = _arr(rows["akind"], wp.int32, 1, dev)
        s.color_a = _arr(rows["ca"], wp.vec3f, 3, dev)
        s.color_b = _arr(rows["cb"], wp.vec3f, 3, dev)
        s.square = _arr(rows["square"], wp.float32, 1, dev)
        s.tile = _arr(rows["tile"], wp.vec2f, 2, dev)
        s.tex_row = _arr(rows["tex_row"], wp.int32, 1, dev)
        s.tex_size = _arr(rows["tex_size"], wp.vec2i, 2, dev)
        if textures:
            wmax = max(t.shape[1] for t in textures)
            need = tex_rows * wmax * 3 * 4
            if need > _MAX_ATLAS_BYTES:
                sizes = ", ".join(f"{t.shape[1]}x{t.shape[0]}" for t in textures)
                raise InputError(
                    f"the textures ({sizes}) are packed into one {wmax}x{tex_rows} atlas of "
                    f"{need / 2**30:.1f} GiB; use smaller textures",
                    file=source,
                    field="surface.texture",
                    allowed=f"an atlas (widest texture x all heights) <= {_MAX_ATLAS_BYTES / 2**30:g} GiB",
                )
            atlas = np.zeros((tex_rows, wmax, 3), dtype=np.float32)
            r0 = 0
            for t in textures:
                atlas[r0 : r0 + t.shape[0], : t.shape[1]] = t
                r0 += t.shape[0]
        else:
            atlas = np.zeros((1, 1, 3), dtype=np.float32)
        s.texture = wp.array(atlas, dtype=wp.vec3f, device=dev)
        area = [lp for lp in lamps if lp.type == "area"]
        suns = [lp for lp in lamps if lp.type == "directional"]
        a = {k: [] for k in ("centre", "normal", "u", "v", "half", "rgb", "two")}
        for lp in area:
            n, u, v = _frame(lp.normal, lp.up)
            a["centre"].append(lp.center)
            a["normal"].append(n)
            a["u"].append(u)
            a["v"].append(v)
            a["half"].append((lp.size[0] / 2, lp.size[1] / 2))
            a["rgb"].append(np.asarray(lp.tint) * lp.radiance)
            a["two"].append(int(lp.double_sided))
        s.num_area = len(area)
        s.a_centre = _arr(a["centre"], wp.vec3f, 3, dev)
        s.a_normal = _arr(a["normal"], wp.vec3f, 3, dev)
        s.a_u = _arr(a["u"], wp.vec3f, 3, dev)
        s.a_v = _arr(a["v"], wp.vec3f, 3, dev)
        s.a_half = _arr(a["half"], wp.vec2f, 2, dev)
        s.a_rgb = _arr(a["rgb"], wp.vec3f, 3, dev)
        s.a_two_sided = _arr(a["two"], wp.int32, 1, dev)
        s.num_sun = len(suns)
        dirs = [-np.asarray(lp.direction) / np.linalg.norm(lp.direction) for lp in suns]
        s.d_dir = _arr(dirs, wp.vec3f, 3, dev)
        s.d_rgb = _arr([np.asarray(lp.tint) * lp.irradiance for lp in suns], wp.vec3f, 3, dev)
        s.d_cos_max = _arr([math.cos(math.radians(lp.angular_radius)) for lp in suns], wp.float32, 1, dev)
        spots = [lp for lp in lamps if lp.type == "spot"]
        s.num_spot = len(spots)
        s.p_pos = _arr([lp.center for lp in spots], wp.vec3f, 3, dev)
        s.p_dir = _arr(
            [np.asarray(lp.direction) / np.linalg.norm(lp.direction) for lp in spots], wp.vec3f, 3, dev
        )
        s.p_rgb = _arr([np.asarray(lp.tint) * lp.intensity for lp in spots], wp.vec3f, 3, dev)
        s.p_cos_outer = _arr([math.cos(math.radians(lp.cone_angle)) for lp in spots], wp.float32, 1, dev)
        s.p_cos_inner = _arr(
            [math.cos(math.radians(max(lp.cone_angle - lp.blend, 0.0))) for lp in spots], wp.float32, 1, dev
        )
        s.a_spectrum = _arr([lamp_spectrum_row(lp.spectrum) for lp in area], wp.int32, 1, dev)
        s.d_spectrum = _arr([lamp_spectrum_row(lp.spectrum) for lp in suns], wp.int32, 1, dev)
        s.p_spectrum = _arr([lamp_spectrum_row(lp.spectrum) for lp in spots], wp.int32, 1, dev)
        self._env_table(s, environment, env_table, dev)
        s.max_diffuse = int(max_diffuse)
        s.mis_mode = MIS_MODES[mis]
        s.stone_shadows = int(bool(stone_shadows))
        self.struct = s

    def _env_table(self, s: Surfaces, environment, shape, dev) -> None:
        """Importance table of the environment (``EnvironmentLight``) for NEE at surfaces:
        cell probability proportional to (mean radiance + 1 % of the mean) x solid angle.  Only for
        maps with structure (studio, sky, lat-long); a constant or dome sky keeps cosine sampling,
        which is exact for a Lambertian surface there."""
        from ..device import launch_tiled
        from .environment import ENV_KINDS

        rows, cols = shape
        use = (
            environment is not None
            and s.num_surfaces > 0
            and environment.struct.kind not in (ENV_KINDS["constant"], ENV_KINDS["dome"])
        )
        if use:
            lum = wp.zeros(rows * cols, dtype=wp.float32, device=dev)
            launch_tiled(
                _env_table_kernel,
                rows * cols,
                [environment.struct, spectral_tables(dev), rows, cols, 4, lum],
                device=dev,
            )
            y = np.maximum(lum.numpy().astype(np.float64).reshape(rows, cols), 0.0)
            theta = (np.arange(rows) + 0.5) * np.pi / rows
            w = (y + 0.01 * max(y.mean(), 1e-30)) * np.sin(theta)[:, None]
            p = w / w.sum()
            row_p = p.sum(axis=1)
            marg = np.concatenate([[0.0], np.cumsum(row_p)])
            marg /= marg[-1]
            cond = np.concatenate([np.zeros((rows, 1)), np.cumsum(p, axis=1)], axis=1)
            cond /= np.maximum(cond[:, -1:], 1e-300)
            s.env_rows, s.env_cols = rows, cols
            s.env_marginal = wp.array(marg.astype(np.float32), dtype=wp.float32, device=dev)
            s.env_conditional = wp.array(cond.ravel().astype(np.float32), dtype=wp.float32, device=dev)
            s.env_cell_pdf = wp.array(p.ravel().astype(np.float32), dtype=wp.float32, device=dev)
        else:
            s.env_rows, s.env_cols = 0, 0
            for name in ("env_marginal", "env_conditional", "env_cell_pdf"):
                setattr(s, name, wp.zeros(1, dtype=wp.float32, device=dev))

    @property
    def empty(self) -> bool:
        return self.struct.num_surfaces == 0 and self.struct.num_area == 0


def _load_texture(path: str | None, source: str | None, field_name: str) -> np.ndarray:
    from ..film.image import read_image

    if path is None or not Path(path).is_file():
        raise InputError("texture file not found", file=source, field=field_name, value=path)
    try:
        pixels, _names = read_image(path)
    except InputError as exc:
        raise InputError(
            f"unreadable texture ({exc.message})", file=source, field=field_name, value=path
        ) from None
    if pixels.shape[2] < 3:
        pixels = np.repeat(pixels[..., :1], 3, axis=2)
    pixels = np.asarray(pixels[..., :3], dtype=np.float64)
    if Path(path).suffix.lower() not in (".exr", ".hdr"):
        from colour import cctf_decoding

        pixels = np.asarray(cctf_decoding(np.clip(pixels, 0.0, 1.0), function="sRGB"))
    if not np.isfinite(pixels).all():
        raise InputError("the texture has non-finite pixels", file=source, field=field_name, value=path)
    return np.ascontiguousarray(np.clip(pixels, 0.0, 1.0), dtype=np.float32)
