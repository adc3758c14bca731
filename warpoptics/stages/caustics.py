"""Caustics on the table: a light tracer for the paths lamp -> gem(s) -> diffuse surface -> eye.

The camera tracer (``stages.trace`` + ``stages.surfaces``) cannot find light that a gem
*refracts or reflects* onto a diffuse table: a diffuse hit's next-event estimation aims at the
lamps in straight lines, and a lamp seen through a gem is a specular connection.  This stage
traces those paths from the lamps (Veach 1997 §10, "particle tracing") and splats them into the
camera's film.

Path ownership (L lamp, S gem interface, D diffuse surface, E eye): the camera estimator owns
E S* D (D)* L and E S* L, and with caustics on a gem *blocks* its shadow and bounce rays
(``Surfaces.stone_shadows = 0``) so that no light through a stone is counted twice; this tracer
owns L S+ D E (a lamp ray that hits a surface before any gem is dropped); nobody owns a caustic
seen through a gem, bounced again, or lit by the environment.

Light paths: a lamp chosen by ``lamp_prob``, emission aimed at the objects' bounding spheres
(chosen by radius squared), one wavelength per path (the scene's strategy), then the optical
bench's transport (``stages.forward.forward_step``: the same interface event, absorption,
splitting and branch stack).  Lamps are unpolarized; coated objects and films are refused.  A
surface hit is connected to the camera by a shadow ray and splatted with the camera's importance
(pinhole or orthographic; a thin lens as a pinhole at its centre), unpolarized.  Deposits are
added on the host in a fixed order, so an image does not depend on the thread count.  Each path
keeps a power ledger (:data:`CAUSTIC_LEDGER`).

The ownership rules, the emission pdfs, the camera importance and the ledger's columns are
derived in docs/design/caustics.md.

References: Veach 1997, Robust Monte Carlo Methods for Light Transport Simulation, §10.1-10.3;
Pharr, Jakob & Humphreys 2016, Physically Based Rendering, 3rd ed., §16.1.1, §16.2; Guy & Soler
2004 (the forward transport of ``stages.forward``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import warp as wp

from .. import interrupt
from .. import validate as val
from ..color import SRGB_TO_XYZ
from ..device import get_device, launch_tiled, load_module
from ..geometry.query import SceneGeometry, scene_closest_hit
from ..materials.dispersion import MaterialTable
from ..optics.branches import Stack, read_row, write_row
from ..optics.interface import ray_power
from ..optics.jones import (
    jones_identity,
    jones_scale,
    perpendicular,
)
from ..optics.microfacet import orthonormal_basis
from ..optics.thinfilm import CoatingStack, make_coating_stack
from ..spectra import SpectralTables, sample_wavelength, strategy_id
from .camera import CameraParams
from .forward import ForwardConfig, ForwardParams, forward_params, forward_step
from .surfaces import (
    Surfaces,
    albedo_rgb,
    area_emission,
    bsdf_eval,
    cdf_find,
    reflectance_value,
    sample_cone,
    spot_intensity,
    sun_irradiance,
    surfaces_closest_hit,
)

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["CausticParams", "CausticConfig", "CausticStage", "CAUSTIC_LEDGER", "caustic_importance"]

#: names of the ledger columns (docs/design/caustics.md, "The ledger")
CAUSTIC_LEDGER = ("surface", "absorbed", "escaped", "truncated", "lost", "interface", "overflow", "reflected")
_C_SURF, _C_ABS, _C_ESC, _C_TRUNC, _C_LOST, _C_IFACE, _C_OVER, _C_REFL = 0, 1, 2, 3, 4, 5, 6, 7

_ORTHO = wp.constant(1)
_HIT_SURFACE = wp.constant(1)
_EPS_SURF = 1.0e-3  # mm, shadow-ray origin offset off a surface (as stages.surfaces)
_CHUNK = 1 << 16  # light paths per launch (deposit buffers: CHUNK x max_deposits slots)
#: the most light paths of one run: the kernels index paths (and seed their random streams) in
#: int32, and the count is rounded up to a multiple of the wavelength strata (<= 4096), so it
#: stays below 2^31 (past it the index wraps negative: wrong wavelengths and streams, silently)
MAX_PATHS = 2**31 - 4096


@wp.struct
class CausticParams:
    """Per-run settings of the light tracer (values, not compile-time constants)."""

    num_lamps: int  # suns, then area lights, then spots (Surfaces order)
    lamp_cdf: wp.array(dtype=wp.float32)  # num_lamps + 1
    lamp_prob: wp.array(dtype=wp.float32)
    num_targets: int
    t_centre: wp.array(dtype=wp.vec3f)  # world bounding sphere of each object, mm
    t_radius: wp.array(dtype=wp.float32)
    t_cdf: wp.array(dtype=wp.float32)  # num_targets + 1
    t_prob: wp.array(dtype=wp.float32)
    all_centre: wp.vec3f  # a sphere around all targets (upstream start of sun rays)
    all_radius: float
    strategy: int  # spectra strategy id
    count: int  # wavelength strata per group of paths
    splat_scale: float  # count / number of paths
    seed: int
    max_deposits: int


@wp.func
def _target_cone(cp: CausticParams, k: int, y: wp.vec3f):
    # axis and cos(half-angle) of the cone from y around target sphere k (whole sphere if inside)
    to = cp.t_centre[k] - y
    d2 = wp.dot(to, to)
    r = cp.t_radius[k]
    if d2 <= r * r * 1.0001:
        return wp.vec3f(0.0, 0.0, 1.0), -1.0
    dist = wp.sqrt(d2)
    return to / dist, wp.sqrt(wp.max(1.0 - r * r / d2, 0.0))


@wp.func
def _cone_pdf(cp: CausticParams, y: wp.vec3f, w: wp.vec3f):
    """Mixture solid-angle pdf of a direction w from y: sum_k p_k [w in cone_k] / (2 pi (1 - cos a_k))."""
    pdf = float(0.0)
    for k in range(cp.num_targets):
        ax, cmax = _target_cone(cp, k, y)
        if wp.dot(w, ax) >= cmax:
            pdf += cp.t_prob[k] / (2.0 * wp.pi * (1.0 - cmax))
    return pdf


@wp.func
def _disc_pdf(cp: CausticParams, axis: wp.vec3f, cos_max: float, o: wp.vec3f, d: wp.vec3f):
    """Mixture area pdf (per unit area perpendicular to the sun axis) of the sun ray o + t d:
    sum_k p_k [crosses disc_k] / (pi R_k'^2), disc_k through target k's centre, perpendicular to
    ``axis``, radius R_k' = R_k / cos_max."""
    pdf = float(0.0)
    for k in range(cp.num_targets):
        c = cp.t_centre[k]
        rr = cp.t_radius[k] / cos_max
        t = wp.dot(c - o, axis) / wp.dot(d, axis)
        q = o + d * t - c
        if wp.dot(q, q) <= rr * rr:
            pdf += cp.t_prob[k] / (wp.pi * rr * rr)
    return pdf


@wp.func
def _emit(cp: CausticParams, s: Surfaces, tables: SpectralTables, wl: float, rng: wp.uint32):
    """A lamp ray aimed at the targets: (origin, unit direction, spectral flux weight (already
    divided by the lamp's and the direction's / position's probabilities), rng)."""
    lamp = cdf_find(cp.lamp_cdf, 0, cp.num_lamps, wp.randf(rng))
    k = cdf_find(cp.t_cdf, 0, cp.num_targets, wp.randf(rng))
    p_lamp = cp.lamp_prob[lamp]
    o = wp.vec3f(0.0)
    d = wp.vec3f(0.0, 0.0, -1.0)
    flux = float(0.0)
    if lamp < s.num_sun:
        j = lamp
        axis = -s.d_dir[j]  # direction of travel of the sunlight
        cmax = s.d_cos_max[j]
        d = axis
        scale = float(1.0)
        if cmax < 1.0:
            d = sample_cone(axis, cmax, wp.randf(rng), wp.randf(rng))
            scale = 2.0 * (1.0 - cmax) / (1.0 - cmax * cmax)
        # a point uniform on target k's disc (perpendicular to the axis), moved upstream along d
        # to a plane beyond every target
        ta, tb = orthonormal_basis(axis)
        rr = cp.t_radius[k] / cmax
        rad = rr * wp.sqrt(wp.randf(rng))
        ph = 2.0 * wp.pi * wp.randf(rng)
        p = cp.t_centre[k] + ta * (rad * wp.cos(ph)) + tb * (rad * wp.sin(ph))
        back = (wp.dot(p - cp.all_centre, axis) + cp.all_radius + 1.0) / wp.dot(d, axis)
        o = p - d * back
        pdf = _disc_pdf(cp, axis, cmax, o, d)
        if pdf > 0.0:
            flux = sun_irradiance(s, tables, j, wl) * scale * wp.dot(d, axis) / (pdf * p_lamp)
    elif lamp < s.num_sun + s.num_area:
        j = lamp - s.num_sun
        h2 = s.a_half[j]
        o = (
            s.a_centre[j]
            + s.a_u[j] * ((2.0 * wp.randf(rng) - 1.0) * h2[0])
            + s.a_v[j] * ((2.0 * wp.randf(rng) - 1.0) * h2[1])
        )
        ax, cmax = _target_cone(cp, k, o)
        d = sample_cone(ax, cmax, wp.randf(rng), wp.randf(rng))
        cos_l = wp.dot(d, s.a_normal[j])
        if s.a_two_sided[j] != 0:
            cos_l = wp.abs(cos_l)
        pdf = _cone_pdf(cp, o, d)
        if cos_l > 0.0 and pdf > 0.0:
            area = 4.0 * h2[0] * h2[1]
            flux = area_emission(s, tables, j, wl) * cos_l * area / (pdf * p_lamp)
        o = o + d * 1.0e-4
    else:
        j = lamp - s.num_sun - s.num_area
        o = s.p_pos[j]
        ax, cmax = _target_cone(cp, k, o)
        d = sample_cone(ax, cmax, wp.randf(rng), wp.randf(rng))
        c_ax = wp.dot(d, s.p_dir[j])
        co = s.p_cos_outer[j]
        cin = s.p_cos_inner[j]
        fall = float(0.0)  # the falloff of stages.surfaces' spot NEE
        if cin - co > 1.0e-7:
            fall = wp.smoothstep(co, cin, c_ax)
        elif c_ax >= co:
            fall = 1.0
        pdf = _cone_pdf(cp, o, d)
        if fall > 0.0 and pdf > 0.0:
            flux = spot_intensity(s, tables, j, wl) * fall / (pdf * p_lamp)
    return o, d, flux, rng


@wp.func
def caustic_importance(cam: CameraParams, x: wp.vec3f, n: wp.vec3f):
    """Camera connection of a surface point x (unit normal n on the lit side): returns (pixel
    index or -1, unit direction from x to the camera, distance to it, importance factor
    cos(theta_x) s_x s_y / (r^2 cos^3 theta_c) (perspective, pinhole at the lens centre) or
    cos(theta_x) s_x s_y (orthographic); module docstring, Veach 1997 §10 / pbrt ``We``)."""
    pix = int(-1)
    w = wp.vec3f(0.0)
    dist = float(0.0)
    imp = float(0.0)
    p = x - cam.position
    z = wp.dot(p, cam.forward)
    if z > 0.0:
        sx = float(0.0)
        sy = float(0.0)
        if cam.kind == _ORTHO:
            w = -cam.forward
            dist = z
            sx = wp.dot(p, cam.right) / cam.half_width
            sy = wp.dot(p, cam.up) / cam.half_height
            imp = float(cam.width) * float(cam.height) / (4.0 * cam.half_width * cam.half_height)
        else:
            dist = wp.length(p)
            w = -p / dist
            sx = wp.dot(p, cam.right) / (z * cam.tan_half_x)
            sy = wp.dot(p, cam.up) / (z * cam.tan_half_y)
            cos_c = z / dist
            imp = float(cam.width) * float(cam.height) / (4.0 * cam.tan_half_x * cam.tan_half_y)
            imp = imp / (dist * dist * cos_c * cos_c * cos_c)
        cos_x = wp.dot(n, w)
        px = (sx + 1.0) * 0.5 * float(cam.width)
        py = (1.0 - sy) * 0.5 * float(cam.height)
        if cos_x > 0.0 and px >= 0.0 and py >= 0.0 and px < float(cam.width) and py < float(cam.height):
            ix = wp.min(int(px), cam.width - 1)
            iy = wp.min(int(py), cam.height - 1)
            pix = iy * cam.width + ix
            imp = imp * cos_x
    return pix, w, dist, imp


@wp.kernel
def _caustic_kernel(
    offset: int,
    base_path: int,
    cp: CausticParams,
    fp: ForwardParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    coatings: CoatingStack,
    surf: Surfaces,
    cam: CameraParams,
    tables: SpectralTables,
    dep_pix: wp.array(dtype=wp.int32),
    dep_xyz: wp.array(dtype=wp.vec3f),
    ledger: wp.array2d(dtype=wp.float64),
):
    """One light path (i = base_path + thread) and its split tree; deposit slots and ledger rows
    are indexed by the thread (chunk-relative)."""
    li = wp.tid() + offset
    i = base_path + li
    rng = wp.rand_init(cp.seed, i)
    wl, w_xyz = sample_wavelength(tables, cp.strategy, wp.randf(rng), i % cp.count, cp.count)
    o0, d0, flux, rng = _emit(cp, surf, tables, wl, rng)
    csrc = jones_scale(jones_identity(), 0.5)  # unpolarized lamps: coherency I/2 (trace 1)
    base = li * cp.max_deposits
    for k in range(cp.max_deposits):
        dep_pix[base + k] = -1
    st = Stack()
    n = int(0)
    if flux > 0.0:
        st = write_row(st, 0, o0, d0, perpendicular(d0), jones_identity(), 1.0, -1, 0, -1, d0)
        n = 1
    ndep = int(0)
    e_surf = float(0.0)
    e_abs = float(0.0)
    e_esc = float(0.0)
    e_trunc = float(0.0)
    e_lost = float(0.0)
    e_iface = float(0.0)
    e_over = float(0.0)
    e_refl = float(0.0)
    while n > 0:
        n -= 1
        r = read_row(st, n)
        e = ray_power(r.m, r.w, csrc)
        o = r.o
        d = r.d
        hit = scene_closest_hit(geom, o, d, fp.t_max)
        if r.inside < 0:
            sh = surfaces_closest_hit(surf, o, d, hit.t)
            if sh.kind == _HIT_SURFACE and r.depth >= 1:
                # L S+ D: this tracer's path; connect the diffuse point to the eye (D E)
                e_surf += e
                if r.depth == 1:
                    e_refl += e  # an external reflection off a facet (reflective caustic)
                k = sh.index
                x = o + d * sh.t
                nrm_s = surf.normal[k]
                if wp.dot(d, nrm_s) > 0.0:
                    nrm_s = -nrm_s  # the lit side
                pix, w_cam, dist, imp = caustic_importance(cam, x, nrm_s)
                if pix >= 0 and imp > 0.0:
                    xs = x + nrm_s * _EPS_SURF
                    blocked = surfaces_closest_hit(surf, xs, w_cam, dist * 0.999).kind != 0
                    if not blocked:
                        blocked = scene_closest_hit(geom, xs, w_cam, dist * 0.999).object >= 0
                    if not blocked:
                        albedo = reflectance_value(tables, albedo_rgb(surf, k, sh.a, sh.b), wl)
                        f_r = bsdf_eval(
                            surf.bsdf[k], albedo, surf.roughness[k], surf.ior[k], nrm_s, w_cam, -d
                        )
                        val = e * flux * f_r * imp * cp.splat_scale
                        if val > 0.0:
                            if ndep < cp.max_deposits:
                                dep_pix[base + ndep] = pix
                                dep_xyz[base + ndep] = w_xyz * val
                                ndep += 1
                            else:
                                e_over += e  # no free deposit slot: counted, not splatted
                continue
            if sh.kind != 0:
                # a lamp, or a surface before any gem (camera-owned E D L): not this tracer's
                e_esc += e
                continue
            if hit.object < 0:
                e_esc += e
                continue
        elif hit.object < 0:
            e_lost += e  # a ray inside a solid found no exit
            continue
        # the segment's absorption, then the interface: the optical bench's own step (stages.forward)
        st, n, rng, ledger_step = forward_step(st, n, rng, fp, geom, mats, coatings, hit, r, e, wl, csrc)
        e_abs += ledger_step[0]
        e_trunc += ledger_step[1]
        e_iface += ledger_step[2]
    if flux <= 0.0:
        e_esc = 1.0  # an emission sample that carries nothing (outside a spot's cone, behind a box)
    ledger[li, _C_SURF] = wp.float64(e_surf)
    ledger[li, _C_ABS] = wp.float64(e_abs)
    ledger[li, _C_ESC] = wp.float64(e_esc)
    ledger[li, _C_TRUNC] = wp.float64(e_trunc)
    ledger[li, _C_LOST] = wp.float64(e_lost)
    ledger[li, _C_IFACE] = wp.float64(e_iface)
    ledger[li, _C_OVER] = wp.float64(e_over)
    ledger[li, _C_REFL] = wp.float64(e_refl)


def _luminance(rgb) -> float:
    # Y of a linear-sRGB colour (colour-science's sRGB matrix, ``color.SRGB_TO_XYZ``), >= 0
    return max(float(SRGB_TO_XYZ[1] @ np.asarray(rgb, dtype=np.float64)), 0.0)


def _solid_angles(centres, radii, point) -> float:
    """Approximate total solid angle (pi r^2 / d^2, at most pi) of the target spheres from a point."""
    return sum(
        math.pi * rk**2 / max(float(np.sum((ck - point) ** 2)), rk**2)
        for ck, rk in zip(centres, radii, strict=True)
    )


def _bounding_spheres(meshes) -> tuple[np.ndarray, np.ndarray]:
    """World bounding sphere (centre of the bounding box, max vertex distance) of each (mesh, xf)."""
    centres, radii = [], []
    for mesh, xf in meshes:
        v = np.asarray(mesh.vertices, dtype=np.float64)
        xf = np.asarray(xf, dtype=np.float64)
        vw = v @ xf[:3, :3].T + xf[:3, 3]
        c = 0.5 * (vw.min(axis=0) + vw.max(axis=0))
        centres.append(c)
        radii.append(float(np.linalg.norm(vw - c, axis=1).max()) * 1.001 + 1.0e-4)
    return np.asarray(centres).reshape(-1, 3), np.asarray(radii)


@dataclass(frozen=True)
class CausticConfig:
    """Settings of the light tracer: ``paths`` light paths, the spectral sampling (``spectral``,
    ``wavelengths``: as ``[render]``), path depth and splitting, deposits kept per path, the
    ambient index and the seed."""

    paths: int
    spectral: str = "stratified"
    wavelengths: int = 45
    max_depth: int = 12
    split_threshold: float = 0.01
    max_deposits: int = 16
    ambient_index: float = 1.0
    seed: int = 0

    def __post_init__(self) -> None:
        f = "caustics."
        val.integer(self.paths, field=f + "paths", lo=1, hi=MAX_PATHS)
        val.choice(self.spectral, ("rgb3", "uniform", "importance", "stratified"), field=f + "spectral")
        val.integer(self.wavelengths, field=f + "wavelengths", lo=1, hi=4096)
        val.integer(self.max_depth, field=f + "max_depth", lo=0, hi=256)
        val.number(self.split_threshold, field=f + "split_threshold", lo=0.0, hi=1.0)
        val.integer(self.max_deposits, field=f + "max_deposits", lo=1, hi=1024)
        val.number(self.ambient_index, field=f + "ambient_index", lo=1.0, hi=10.0)
        val.integer(self.seed, field=f + "seed", lo=0, hi=2**31 - 1)


class CausticStage:
    """The light tracer of a :class:`~warpoptics.pipelines.render.Renderer` (``[render] caustics = true``).

    ``paths``: number of light paths (rounded up to a multiple of the wavelength ``count``).
    :meth:`run` returns the caustic film (H*W, 3) XYZ in float64 that the Renderer adds to its
    camera film; :attr:`ledger` the summed ledger (``CAUSTIC_LEDGER``) of the last run, relative
    to one path's emitted power (divide by ``paths`` for fractions)."""

    def __init__(
        self,
        config: CausticConfig,
        *,
        meshes,
        lamps,
        object_material,
        absorption_scale,
        object_axis,
        camera,
        surfaces,
        geometry,
        materials,
        tables,
        device=None,
    ):
        cfg = config
        self.config = config
        self.device = get_device(device)
        dev = self.device
        self.camera = camera
        self.surfaces = surfaces
        self.geometry = geometry
        self.materials = materials
        self.tables = tables
        centres, radii = _bounding_spheres(meshes)
        s = surfaces
        # lamp powers toward the gems (selection probabilities; any positive choice is unbiased)
        r2 = float((radii**2).sum()) if len(radii) else 0.0
        power = []
        suns = [lp for lp in lamps if lp.type == "directional"]
        areas = [lp for lp in lamps if lp.type == "area"]
        spots = [lp for lp in lamps if lp.type == "spot"]
        for lp in suns:
            cmax = math.cos(math.radians(lp.angular_radius))
            power.append(_luminance(np.asarray(lp.tint) * lp.irradiance) * math.pi * r2 / cmax**2)
        for lp in areas:
            a = float(np.prod(lp.size))
            c = np.asarray(lp.center, dtype=np.float64)
            om = _solid_angles(centres, radii, c)
            power.append(_luminance(np.asarray(lp.tint) * lp.radiance) * a * om)
        for lp in spots:
            c = np.asarray(lp.center, dtype=np.float64)
            om = _solid_angles(centres, radii, c)
            power.append(_luminance(np.asarray(lp.tint) * lp.intensity) * om)
        power = np.asarray(power, dtype=np.float64)
        self.enabled = len(radii) > 0 and len(power) > 0 and power.sum() > 0.0
        if not self.enabled:
            power = np.ones(1)
        lamp_prob = power / power.sum()
        t_prob = radii**2 / r2 if r2 > 0 else np.ones(1)
        if self.enabled:
            assert len(lamp_prob) == s.num_sun + s.num_area + s.num_spot
        cp = CausticParams()
        cp.num_lamps = len(lamp_prob)
        cp.lamp_prob = wp.array(lamp_prob.astype(np.float32), dtype=wp.float32, device=dev)
        cp.lamp_cdf = wp.array(
            np.concatenate([[0.0], np.cumsum(lamp_prob)[:-1], [1.0]]).astype(np.float32),
            dtype=wp.float32,
            device=dev,
        )
        nt = max(len(radii), 1)
        cp.num_targets = len(radii)
        cent = centres if len(radii) else np.zeros((1, 3))
        rad = radii if len(radii) else np.ones(1)
        cp.t_centre = wp.array(cent.astype(np.float32), dtype=wp.vec3f, device=dev)
        cp.t_radius = wp.array(rad.astype(np.float32), dtype=wp.float32, device=dev)
        cp.t_prob = wp.array(np.resize(t_prob, nt).astype(np.float32), dtype=wp.float32, device=dev)
        t_cdf = np.concatenate([[0.0], np.cumsum(np.resize(t_prob, nt))[:-1], [1.0]])
        cp.t_cdf = wp.array(t_cdf.astype(np.float32), dtype=wp.float32, device=dev)
        lo = (cent - rad[:, None]).min(axis=0)
        hi = (cent + rad[:, None]).max(axis=0)
        cp.all_centre = wp.vec3f(*(0.5 * (lo + hi)))
        cp.all_radius = float(0.5 * np.linalg.norm(hi - lo)) + 1.0e-3
        strat = cfg.spectral if cfg.spectral in ("uniform", "importance", "stratified") else "importance"
        count = int(cfg.wavelengths) if strat == "stratified" else 1
        cp.strategy = strategy_id(strat)
        cp.count = count
        self.paths = int(math.ceil(max(int(cfg.paths), 1) / count) * count)
        cp.splat_scale = float(count) / float(self.paths)
        cp.seed = int(cfg.seed) * 7919 + 104729  # a stream apart from the camera pass's
        cp.max_deposits = int(cfg.max_deposits)
        self.params = cp
        self.forward = forward_params(
            np.asarray(object_material, dtype=np.int32) if len(object_material) else np.zeros(1, np.int32),
            np.asarray(absorption_scale, np.float32) if len(absorption_scale) else np.ones(1, np.float32),
            np.asarray(object_axis, np.float32).reshape(-1, 3) if len(object_axis) else np.zeros((1, 3)),
            -np.ones(max(len(object_material), 1), dtype=np.int32),  # no coatings (pipelines/caustics.py)
            config=ForwardConfig(
                max_depth=cfg.max_depth,
                split_threshold=cfg.split_threshold,
                max_deposits=cfg.max_deposits,
                seed=cfg.seed,
            ),
            ambient=(cfg.ambient_index, 0.0),
            device=dev,
        )
        self.coatings = make_coating_stack([[]], device=dev)
        self.ledger = np.zeros(len(CAUSTIC_LEDGER))
        self.seconds = 0.0
        # per-launch deposit buffers, allocated once (run() fills them chunk by chunk)
        self._chunk = min(_CHUNK, self.paths)
        md = cp.max_deposits
        self._dep_pix = wp.zeros(self._chunk * md, dtype=wp.int32, device=dev)
        self._dep_xyz = wp.zeros(self._chunk * md, dtype=wp.vec3f, device=dev)
        self._ledger = wp.zeros((self._chunk, len(CAUSTIC_LEDGER)), dtype=wp.float64, device=dev)

    def run(
        self,
        film: np.ndarray,
        *,
        threads: int | None = None,
        tile_size: int | None = None,
        progress: bool = False,
    ) -> np.ndarray:
        """Trace the light paths and write the caustic film into the caller's ``film`` ((H*W, 3)
        float64, overwritten); returns it.  The paths run in launches of ``_CHUNK`` (65,536): a
        progress bar (``progress``) counts them, and Ctrl-C stops the run between two launches
        (``interrupt.check``)."""
        cam = self.camera.params
        npix = cam.width * cam.height
        if film.shape != (npix, 3) or film.dtype != np.float64:
            raise ValueError(f"film must be float64 of shape ({npix}, 3), got {film.dtype} {film.shape}")
        film[:] = 0.0
        self.ledger = np.zeros(len(CAUSTIC_LEDGER))
        if not self.enabled:
            return film
        dev = self.device
        load_module(_caustic_kernel, dev)
        t0 = time.perf_counter()
        chunk = self._chunk
        md = self.params.max_deposits
        dep_pix, dep_xyz, ledger = self._dep_pix, self._dep_xyz, self._ledger
        bar = None
        if progress:
            from tqdm.auto import tqdm  # as the camera pass's bar (pipelines.render)

            bar = tqdm(total=self.paths, unit="path", unit_scale=True, desc="caustics", leave=False)
        try:
            for base in range(0, self.paths, chunk):
                interrupt.check()  # Ctrl-C that a library swallowed: stop between launches
                nb = min(chunk, self.paths - base)
                launch_tiled(
                    _caustic_kernel,
                    nb,
                    [
                        base,
                        self.params,
                        self.forward,
                        self.geometry,
                        self.materials,
                        self.coatings,
                        self.surfaces,
                        cam,
                        self.tables,
                        dep_pix,
                        dep_xyz,
                        ledger,
                    ],
                    device=dev,
                    threads=threads,
                    tile_size=tile_size,
                )
                pix = dep_pix.numpy()[: nb * md]
                xyz = dep_xyz.numpy()[: nb * md]
                keep = pix >= 0
                # fixed-order reduction on the host: deterministic for any thread count
                np.add.at(film, pix[keep], xyz[keep].astype(np.float64))
                self.ledger += ledger.numpy()[:nb].sum(axis=0)
                if bar is not None:
                    bar.update(nb)
        finally:
            if bar is not None:
                bar.close()
        self.seconds = time.perf_counter() - t0
        if not np.isfinite(film).all():
            raise FloatingPointError("caustic film is not finite: this is a bug, please report the scene")
        return film
