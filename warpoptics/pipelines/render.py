"""The standard camera pipeline: Camera -> Trace -> Film -> colour and output.

``render(scene, **overrides) -> Image``.  The pipeline kernel composes the stages' ``@wp.func``s
per pixel: for each of the pixel's ``spp x wavelengths`` samples it draws a wavelength
(``spectra.sample_wavelength``), a primary ray (``stages.camera.camera_ray``), traces its path
tree (``stages.trace.trace_radiance``) and accumulates the Film: XYZ and the Y-weighted Stokes
vector (S0 = Y) in float64.  Pixels are launched in row chunks (a progress bar) and each chunk in
tiles from a thread pool; each pixel owns its random sequence (seeded by scene seed, pixel and
pass), so an image does not depend on the thread count or the tiling.
"""

from __future__ import annotations

import functools
import math
import time
from pathlib import Path

import numpy as np
import warp as wp

from ..device import get_device, launch_tiled, load_module
from ..errors import InputError
from ..film.image import Image
from ..film.views import polarizer_world_axis
from ..geometry.nesting import point_medium
from ..geometry.query import GeometryScene, SceneGeometry
from ..materials import material_from_spec
from ..materials.dispersion import MaterialTable, build_material_table
from ..optics.jones import stokes_from_coherency
from ..scene import Scene
from ..spectra import (
    COARSE_STEP_NM,
    STRATEGY_STRATIFIED,
    SpectralTables,
    sample_wavelength,
    spectral_tables,
    strategy_id,
)
from ..spectra import grid as spectral_grid
from ..stages.bundle import LaneWavelengths, LaneWeights, bundle_obstacle, trace_bundle
from ..stages.camera import Camera, CameraParams, camera_ray
from ..stages.coated import build_film_surfaces
from ..stages.coherence import direction_tolerance
from ..stages.environment import ENV_KINDS, Environment, EnvironmentLight, spectral_response
from ..stages.fluorescence import (
    build_reemission,
    emission_media_supported,
    has_fluorescence,
    scene_light_spectra,
)
from ..stages.pixel_beam import (
    SINK_COLS,
    BeamScene,
    beam_objects,
    beam_obstacle,
    beam_scene,
    beam_targets,
    sink_sums,
    trace_beam,
)
from ..stages.surfaces import Surfaces, SurfaceStage
from ..stages.trace import (
    TraceConfig,
    TraceParams,
    TraceStage,
    trace_radiance,
)
from .adaptive import allocate
from .caustics import caustic_stage
from .objects import build_objects, world_axes

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "render",
    "Renderer",
    "FilmParams",
    "estimate_render_bytes",
    "available_memory_bytes",
    "check_render_memory",
]


@wp.struct
class FilmParams:
    width: int
    height: int
    spp: int  # end of the pixel sample range (all pixels alike unless ``adaptive``)
    spp_begin: int  # start of the range: a round continues a pixel's sequence where the last one ended
    adaptive: int  # 1: each pixel's range ends at its own ``spp_end`` (adaptive sampling round)
    count: int  # wavelength samples (traces) per spp: strata, random draws, or 3 for rgb3
    strategy: int
    seed: int
    pass_index: int
    round: int  # sampling round within the pass (its own stream of trace decisions)
    shared: int  # 1: non-dispersive scene, every trace carries the whole spectrum (``response``)
    response: wp.mat33f  # the exact spectral integral (EnvironmentLight.exact_response) when shared
    bundle: int  # 1: dispersive scene traced in spectral bundles (stages/bundle.py)
    groups: int  # bundles per spp (each takes every groups-th stratum of the count)
    beam: int  # 1: each bundle traces the pixel's whole footprint as beams (stages/pixel_beam.py)
    beam_block: int  # beams: a thread traces blocks of beam_block x beam_block pixels as one beam


# Values drawn from the camera stream per trace (wavelength, lens u, lens v): a round that starts
# at sample k skips 3 k of them, so a pixel's sequence is the same however it is split in rounds.
_DRAWS_PER_TRACE = wp.constant(3)


@wp.func
def _stokes_d(s: wp.vec4f):
    """A Stokes vector in the film's float64."""
    return wp.vec4d(wp.float64(s[0]), wp.float64(s[1]), wp.float64(s[2]), wp.float64(s[3]))


@wp.func
def _add_to_film(
    pix: int,
    xyz: wp.vec3d,
    sq: wp.vec3d,
    stokes: wp.vec4d,
    stokes_x: wp.vec4d,
    stokes_z: wp.vec4d,
    hit_fraction: float,
    rays: int,
    xyz_out: wp.array(dtype=wp.vec3d),
    sq_out: wp.array(dtype=wp.vec3d),
    stokes_out: wp.array(dtype=wp.vec4d),
    alpha_out: wp.array(dtype=wp.float64),
    rays_out: wp.array(dtype=wp.int64),
    stokes_xyz_out: wp.array2d(dtype=wp.vec4d),
):
    """Add one pixel's sums to the film (both estimators of the pixel kernel write through here)."""
    xyz_out[pix] = xyz_out[pix] + xyz
    sq_out[pix] = sq_out[pix] + sq
    stokes_out[pix] = stokes_out[pix] + stokes
    alpha_out[pix] = alpha_out[pix] + wp.float64(hit_fraction)
    rays_out[pix] = rays_out[pix] + wp.int64(rays)
    stokes_xyz_out[pix, 0] = stokes_xyz_out[pix, 0] + stokes_x
    stokes_xyz_out[pix, 1] = stokes_xyz_out[pix, 1] + stokes
    stokes_xyz_out[pix, 2] = stokes_xyz_out[pix, 2] + stokes_z


@wp.func
def _bundle_lanes(tables: SpectralTables, film: FilmParams, grp: int, ju: float):
    """The wavelengths and weights of bundle ``grp`` of a sample (every groups-th stratum of the
    spectrum, all with the jitter ``ju``): (lanes, weights, lane count)."""
    lanes = LaneWavelengths()
    lane_w = LaneWeights()
    nl = int(0)
    for stratum in range(grp, film.count, film.groups):
        # uniform and importance draws: a rotated lattice in u (stratified as well)
        uu = ju
        if film.strategy != STRATEGY_STRATIFIED:
            uu = ju + float(stratum) / float(film.count)
            uu = uu - wp.floor(uu)
        wl, w = sample_wavelength(tables, film.strategy, uu, stratum, film.count)
        lanes[nl] = wl
        lane_w[nl, 0] = w[0]
        lane_w[nl, 1] = w[1]
        lane_w[nl, 2] = w[2]
        nl += 1
    return lanes, lane_w, nl


# the beams' sink columns after the stage's: the XYZ of the pixel's current sample
_SINK_GROUP = wp.constant(SINK_COLS)
BEAM_SINK_COLS = SINK_COLS + 3


@wp.func
def _render_beam_block(
    block: int,
    cam: CameraParams,
    film: FilmParams,
    tp: TraceParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    env: Environment,
    surf: Surfaces,
    tables: SpectralTables,
    polarized: int,
    beams: BeamScene,
    spp_end: wp.array(dtype=wp.int32),
    sink: wp.array2d(dtype=wp.float32),
    xyz_out: wp.array(dtype=wp.vec3d),
    sq_out: wp.array(dtype=wp.vec3d),
    stokes_out: wp.array(dtype=wp.vec4d),
    alpha_out: wp.array(dtype=wp.float64),
    rays_out: wp.array(dtype=wp.int64),
    stokes_xyz_out: wp.array2d(dtype=wp.vec4d),
):
    """Pixel beams (stages/pixel_beam.py): the samples of one block of ``film.beam_block``
    squared pixels (fewer at the film's right and bottom edges), each bundle of a sample traced
    as one beam through the whole block.  The block's pixels share its random streams (those of
    its first pixel): each pixel's estimate is distributed as a one-pixel beam's would be, and
    neighbouring pixels' noise is correlated within a block."""
    bsz = film.beam_block
    nbx = (film.width + bsz - 1) / bsz
    px0 = (block % nbx) * bsz
    py0 = (block / nbx) * bsz
    bw = wp.min(bsz, film.width - px0)
    bh = wp.min(bsz, film.height - py0)
    pix = px0 + py0 * film.width
    end = film.spp
    if film.adaptive != 0:
        end = int(0)
        for iy in range(bh):
            for ix in range(bw):
                end = wp.max(end, spp_end[pix + ix + iy * film.width])
    if end <= film.spp_begin:
        return
    n_pix = film.width * film.height
    rng = wp.rand_init(film.seed * 1000003 + film.pass_index, pix)
    rng_trace = wp.rand_init(film.seed * 1000003 + film.pass_index, pix + n_pix * (1 + film.round))
    rot_x = wp.randf(rng)
    rot_y = wp.randf(rng)
    rot_u = wp.randf(rng)
    # the object the block's beam enters (stages/pixel_beam.py beam_targets; a stone alone: 0)
    k = int(0)
    if beams.others != 0:
        k = beams.target[block]
    for _skip in range(film.spp_begin * film.groups * _DRAWS_PER_TRACE):
        wp.randf(rng)
    for kb in range(film.spp_begin * film.groups, end * film.groups):
        grp = kb % film.groups
        smp = kb / film.groups
        # (the camera stream's draws of a bundle: lens u, v and one reserved, unused by beams)
        wp.randf(rng)
        wp.randf(rng)
        wp.randf(rng)
        # all bundles of the sample share the jitter, so the pixel's wavelengths are one rotated
        # lattice; a beam's light is continuous in the wavelength, and a lattice integrates that
        # far better (stages/pixel_beam.py)
        ju = rot_u + float(smp) * 0.6180339887498949
        lanes, lane_w, nl = _bundle_lanes(tables, film, grp, ju - wp.floor(ju))
        # the lanes' lookups rotated by the sample's R2 point (independent of the wavelengths)
        rot_b = wp.vec2f(rot_x + float(smp) * 0.7548776662466927, rot_y + float(smp) * 0.5698402909980532)
        nr, rng_trace = trace_beam(
            tp, geom, mats, env, surf, tables, polarized, beams, cam, px0, py0, bw, bh, film.width,
            sink, lanes, lane_w, nl, grp, film.groups, rot_b, k, rng_trace,
        )  # fmt: skip
        # the block's parts counted evenly over its pixels (the rest at its first)
        cells = bw * bh
        rays_out[pix] = rays_out[pix] + wp.int64(nr % cells)
        for iy in range(bh):
            for ix in range(bw):
                pc = pix + ix + iy * film.width
                coh_x, coh, coh_z, cover = sink_sums(sink, pc, polarized)
                if film.adaptive != 0 and smp >= spp_end[pc]:
                    rays_out[pc] = rays_out[pc] + wp.int64(nr / cells)
                    continue  # this pixel has its samples
                s = stokes_from_coherency(coh)
                sx = stokes_from_coherency(coh_x)
                sz = stokes_from_coherency(coh_z)
                # the sample's XYZ (its bundles' sum) and its square enter the film at its end
                sink[pc, _SINK_GROUP] += sx[0]
                sink[pc, _SINK_GROUP + 1] += s[0]
                sink[pc, _SINK_GROUP + 2] += sz[0]
                xyz = wp.vec3d(0.0, 0.0, 0.0)
                if grp == film.groups - 1:
                    for c in range(3):
                        xyz[c] = wp.float64(sink[pc, _SINK_GROUP + c])
                        sink[pc, _SINK_GROUP + c] = 0.0
                _add_to_film(
                    pc, xyz, wp.cw_mul(xyz, xyz), _stokes_d(s), _stokes_d(sx), _stokes_d(sz),
                    cover / float(film.groups), nr / cells, xyz_out, sq_out, stokes_out, alpha_out, rays_out,
                    stokes_xyz_out,
                )  # fmt: skip


#: the widest block (degrees) beam_block = 0 gives a pinhole camera's beams: a part's Fresnel
#: factors are its centre ray's, so a pixel's share of a wider block's part is off to first
#: order in the block's angle (scripts/bench/diamond512.py: 0.47 % relative RMSE at 0.117 deg,
#: 4x4 pixels of scenes/diamond_fire.toml; 0.20 % at 2x2)
AUTO_BLOCK_DEGREES = 0.12


def beam_block(scene) -> int:
    """The pixels per side of a pixel beam's block: ``render.beam_block``, or for 0 the most
    (up to 8) that keep a pinhole camera's block within AUTO_BLOCK_DEGREES (1 for other
    cameras: an orthographic camera's beams are exact at any size, set it explicitly)."""
    b = int(scene.render.beam_block)
    if b > 0:
        return b
    c = scene.camera
    if c.type == "orthographic":
        return 1
    pixel = c.fov / c.height  # degrees (the field of view is vertical)
    return max(1, min(8, int(AUTO_BLOCK_DEGREES / pixel)))


def _make_render_pixels(trace, module=None):
    """The pixel kernel over a camera trace (``stages.trace.trace_radiance``, or a variant with
    the fluorescent re-emission pass or the coherent mode, ``stages.trace.trace_variant``).  A
    variant gets a Warp module of its own (``module="unique"``): built on first use, it does not
    change this module's hash, so the default kernel is not compiled again.  Pixel beams, which
    continue their parts with ``trace_radiance``, are compiled into the default kernel only
    (the variants' scenes are point-sampled)."""
    with_beams = trace is trace_radiance

    @wp.kernel(module=module, enable_backward=False)
    def _render_pixels(
        offset: int,
        base: int,
        cam: CameraParams,
        film: FilmParams,
        tp: TraceParams,
        geom: SceneGeometry,
        mats: MaterialTable,
        env: Environment,
        surf: Surfaces,
        tables: SpectralTables,
        polarized: int,
        spp_end: wp.array(dtype=wp.int32),  # per pixel, when film.adaptive
        xyz_out: wp.array(dtype=wp.vec3d),
        sq_out: wp.array(dtype=wp.vec3d),  # sums of squares of the per-spp XYZ (noise estimate)
        stokes_out: wp.array(dtype=wp.vec4d),
        alpha_out: wp.array(dtype=wp.float64),
        rays_out: wp.array(dtype=wp.int64),
        stokes_xyz_out: wp.array2d(
            dtype=wp.vec4d
        ),  # per-channel Stokes (pixel, X|Y|Z) for polarization views
        beam_sink: wp.array2d(dtype=wp.float32),  # pixel beams' per-pixel sums (a row per pixel)
        beams: BeamScene,  # what pixel beams need of the rest of the scene
    ):
        """Adds to each pixel's sums over its samples ``[spp_begin, spp_end)`` (each spp is ``count``
        traces): the per-spp XYZ, its squares, the Stokes vectors, hits and rays; the Renderer
        divides by the pixel's spp."""
        if wp.static(with_beams):
            if film.beam != 0:
                # pixel beams: the launch index is a block of pixels
                _render_beam_block(
                    base + wp.tid() + offset, cam, film, tp, geom, mats, env, surf, tables, polarized, beams,
                    spp_end, beam_sink, xyz_out, sq_out, stokes_out, alpha_out, rays_out, stokes_xyz_out,
                )  # fmt: skip
                return
        pix = base + wp.tid() + offset
        px = pix % film.width
        py = pix / film.width
        end = film.spp
        if film.adaptive != 0:
            end = spp_end[pix]
        if end <= film.spp_begin:
            return
        # two streams per pixel: camera samples (wavelength, jitter, lens) and trace decisions, so the
        # samples a pixel draws do not depend on what its paths met (an empty scene sees the same ones)
        n_pix = film.width * film.height
        rng = wp.rand_init(film.seed * 1000003 + film.pass_index, pix)
        rng_trace = wp.rand_init(film.seed * 1000003 + film.pass_index, pix + n_pix * (1 + film.round))
        xyz = wp.vec3d(0.0, 0.0, 0.0)
        sq = wp.vec3d(0.0, 0.0, 0.0)
        group = wp.vec3d(0.0, 0.0, 0.0)
        stokes = wp.vec4d(0.0, 0.0, 0.0, 0.0)
        stokes_x = wp.vec4d(0.0, 0.0, 0.0, 0.0)  # X- and Z-weighted Stokes (the Y one is `stokes`)
        stokes_z = wp.vec4d(0.0, 0.0, 0.0, 0.0)
        hits = float(0.0)
        rays = int(0)
        # a trace at one wavelength estimates XYZ / count (its weight has 1/count); a shared one the whole
        scale = wp.float64(1.0)
        if film.shared != 0:
            scale = wp.float64(1.0) / wp.float64(film.count)
        # pixel positions: the R2 low-discrepancy sequence (Roberts 2018) with a random per-pixel
        # rotation (Cranley–Patterson): every sample is uniform over the pixel (unbiased), and the
        # samples of a pixel cover it evenly, which is where a gem's noise comes from (facet edges)
        rot_x = wp.randf(rng)
        rot_y = wp.randf(rng)
        if film.bundle != 0:
            # spectral bundles (stages/bundle.py): each of the `groups` bundles of an spp takes every
            # groups-th stratum of the spectrum (all of it, at one pixel position).  The strata of a
            # bundle share one jitter that follows the golden-ratio sequence over the bundles (a
            # rotated lattice in the sampling variable, low-discrepancy from bundle to bundle):
            # every wavelength is still uniform within its stratum, so the estimate is unbiased.
            rot_u = wp.randf(rng)
            for _skip in range(film.spp_begin * film.groups * _DRAWS_PER_TRACE):
                wp.randf(rng)
            for kb in range(film.spp_begin * film.groups, end * film.groups):
                grp = kb % film.groups
                jx = rot_x + float(kb) * 0.7548776662466927
                jy = rot_y + float(kb) * 0.5698402909980532
                jx = jx - wp.floor(jx)
                jy = jy - wp.floor(jy)
                lu = wp.randf(rng)
                lv = wp.randf(rng)
                o, d, bx = camera_ray(cam, float(px) + jx, float(py) + jy, lu, lv)
                ju = rot_u + float(kb) * 0.6180339887498949
                lanes, lane_w, nl = _bundle_lanes(tables, film, grp, ju - wp.floor(ju))
                wp.randf(rng)  # (reserved: keeps _DRAWS_PER_TRACE draws per bundle)
                coh_x, coh, coh_z, hit_i, nr, rng_trace = trace_bundle(
                    tp, geom, mats, env, tables, polarized, o, d, bx, lanes, lane_w, nl, rng_trace
                )
                cover = float(hit_i)
                s = stokes_from_coherency(coh)
                sx = stokes_from_coherency(coh_x)
                sz = stokes_from_coherency(coh_z)
                gv = wp.vec3d(wp.float64(sx[0]), wp.float64(s[0]), wp.float64(sz[0]))
                group += gv
                if grp == film.groups - 1:
                    xyz += group
                    sq += wp.cw_mul(group, group)
                    group = wp.vec3d(0.0, 0.0, 0.0)
                stokes += _stokes_d(s)
                stokes_x += _stokes_d(sx)
                stokes_z += _stokes_d(sz)
                hits += cover
                rays += nr
            _add_to_film(
                pix,
                xyz,
                sq,
                stokes,
                stokes_x,
                stokes_z,
                hits / float(film.groups),
                rays,
                xyz_out,
                sq_out,
                stokes_out,
                alpha_out,
                rays_out,
                stokes_xyz_out,
            )
            return
        for _skip in range(film.spp_begin * film.count * _DRAWS_PER_TRACE):
            wp.randf(rng)
        for k in range(film.spp_begin * film.count, end * film.count):
            stratum = k % film.count
            u = wp.randf(rng)
            wl, w = sample_wavelength(tables, film.strategy, u, stratum, film.count)
            jx = rot_x + float(k) * 0.7548776662466927
            jy = rot_y + float(k) * 0.5698402909980532
            jx = jx - wp.floor(jx)
            jy = jy - wp.floor(jy)
            lu = wp.randf(rng)
            lv = wp.randf(rng)
            o, d, b = camera_ray(cam, float(px) + jx, float(py) + jy, lu, lv)
            response = film.response
            if film.shared == 0:
                response = spectral_response(env, tables, wl, w)
            coh_x, coh, coh_z, hit, nr, rng_trace = trace(
                tp, geom, mats, env, surf, tables, polarized, o, d, b, wl, w, response, stratum, rng_trace
            )
            s = stokes_from_coherency(coh)
            sx = stokes_from_coherency(coh_x)
            sz = stokes_from_coherency(coh_z)
            g = wp.vec3d(wp.float64(sx[0]), wp.float64(s[0]), wp.float64(sz[0])) * scale
            group += g
            if stratum == film.count - 1:
                xyz += group
                sq += wp.cw_mul(group, group)
                group = wp.vec3d(0.0, 0.0, 0.0)
            stokes += _stokes_d(s) * scale
            stokes_x += _stokes_d(sx) * scale
            stokes_z += _stokes_d(sz) * scale
            hits += float(hit)
            rays += nr
        _add_to_film(
            pix,
            xyz,
            sq,
            stokes,
            stokes_x,
            stokes_z,
            hits / float(film.count),
            rays,
            xyz_out,
            sq_out,
            stokes_out,
            alpha_out,
            rays_out,
            stokes_xyz_out,
        )

    return _render_pixels


_render_pixels = _make_render_pixels(trace_radiance)


@functools.cache
def _render_pixels_over(trace):
    """The pixel kernel over a trace stage's device function (``TraceStage.function``; the
    default ``trace_radiance``: ``_render_pixels``)."""
    if trace is trace_radiance:
        return _render_pixels
    return _make_render_pixels(trace, module="unique")


# bytes per pixel: the float64 film (xyz 24 + stokes 32 + alpha 8 + ray count 8 + per-channel stokes
# 3 x 32) and, when the image is read back and saved, its NumPy copies and the EXR buffer
# (19 channels float64 + float32)
FILM_BYTES_PER_PIXEL = 24 + 32 + 8 + 8 + 96
OUTPUT_BYTES_PER_PIXEL = FILM_BYTES_PER_PIXEL + 19 * 8 + 19 * 4


def estimate_render_bytes(width: int, height: int, *, beams: bool = False) -> int:
    """Peak memory (bytes) a ``width x height`` render needs for its film and output image, and
    with ``beams`` the pixel beams' per-pixel sums; the per-thread trace stack is small (a few
    kB) and not counted."""
    per_pixel = FILM_BYTES_PER_PIXEL + OUTPUT_BYTES_PER_PIXEL + (4 * BEAM_SINK_COLS if beams else 0)
    return int(width) * int(height) * per_pixel


def available_memory_bytes() -> int | None:
    """Memory the process could still allocate: ``MemAvailable`` from /proc/meminfo, else
    ``os.sysconf`` free pages; ``None`` where neither is known."""
    import os

    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def check_render_memory(
    width: int, height: int, *, available: int | None = None, file: str | None = None, beams: bool = False
) -> int:
    """Refuse (InputError with the estimate in GiB) a render whose film and image would not fit in
    ``available`` bytes (default: :func:`available_memory_bytes`).  Returns the estimate."""
    need = estimate_render_bytes(width, height, beams=beams)
    avail = available_memory_bytes() if available is None else int(available)
    if avail is not None and need > avail:
        raise InputError(
            f"the image would need about {need / 2**30:.1f} GiB of memory but only {avail / 2**30:.1f} GiB "
            "is available; render a smaller image or crop it",
            file=file,
            field="camera.width x camera.height",
            value=f"{width}x{height}",
        )
    return need


def _non_dispersive(mats, step_nm: float = COARSE_STEP_NM) -> bool:
    """Whether every material has the same index (o and e) and zero absorption at all the
    wavelengths of the spectral tables (evaluated through the materials' own kernels)."""
    grid = spectral_grid(step_nm)
    for m in mats:
        n = np.asarray(m.n(grid), dtype=np.float64)
        a = np.asarray(m.alpha(grid), dtype=np.float64)
        if np.ptp(n.reshape(len(grid), -1), axis=0).max() > 1e-6:
            return False
        if np.abs(a).max() > 0.0:
            return False
        # a colour-zoned stone absorbs with its zones' materials (materials/zoning.py)
        zoning = getattr(m, "zoning", None)
        for z in zoning.absorption if zoning is not None else ():
            if np.abs(np.asarray(z.alpha(grid), dtype=np.float64)).max() > 0.0:
                return False
    return True


class Renderer:
    """The standard pipeline for a scene; owns every stage's device data.  ``run()`` renders."""

    def __init__(
        self,
        scene: Scene,
        *,
        device=None,
        shared_spectrum: bool | None = None,
        spectral_bundle: bool | None = None,
    ):
        self.scene = scene
        self.device = get_device(device)
        r = scene.render
        check_render_memory(
            scene.camera.width, scene.camera.height, file=scene.path, beams=r.estimator != "point"
        )
        built = build_objects(scene.objects, file=scene.path)
        meshes, mats = built.meshes, built.materials
        emission_media_supported(mats, file=scene.path)
        self.fluorescence = has_fluorescence(mats) and r.spectral != "rgb3"
        if self.fluorescence and r.birefringence == "coherent":
            raise InputError(
                "the coherent mode does not trace fluorescent re-emission",
                file=scene.path,
                field="render.birefringence",
                value=r.birefringence,
                allowed='"exact" or "approx" with a fluorescent material',
            )
        self.geometry = GeometryScene(meshes, allow_empty=True, parents=built.parents, device=self.device)
        if mats:
            self.materials, ids = build_material_table(mats, self.device)
        else:  # surfaces only: a placeholder material table (no object refers to it)
            self.materials, ids = build_material_table([material_from_spec("diamond")], self.device)
            ids = []
        films = build_film_surfaces(
            [ob.film for ob in scene.objects],
            [(ob.shape, dict(ob.params)) for ob in scene.objects],
            meshes,
            mats,
            file=scene.path,
            device=self.device,
        )
        self.camera = Camera(scene.camera)
        self.environment = EnvironmentLight(scene.lights[0], self.device)
        self.source_polarizer = scene.lights[0].polarizer
        if self.source_polarizer is not None:
            # polarized illumination (a polariscope): the sheet faces the camera (film/views.py);
            # polarized light needs the polarized (Jones) renderer
            if not r.polarization:
                raise InputError(
                    "polarized light needs render.polarization = true",
                    file=scene.path,
                    field="light.0.polarizer",
                    value=self.source_polarizer,
                )
            p = self.camera.params
            axis = polarizer_world_axis(
                np.array(p.right, dtype=np.float64), np.array(p.up, dtype=np.float64), self.source_polarizer
            )
            self.environment.struct.polarizer = wp.vec3f(*axis.astype(np.float32))
        self.surfaces = SurfaceStage(
            scene.surfaces,
            scene.lamps,
            max_diffuse=r.diffuse_depth,
            mis=r.mis,
            # caustics own the light through stones: stones then block NEE
            stone_shadows=r.stone_shadows and not r.caustics,
            environment=self.environment,
            source=scene.path,
            device=self.device,
        )
        self.tables = spectral_tables(self.device)
        trace_config = TraceConfig(
            max_depth=r.max_depth,
            split_threshold=r.split_threshold,
            max_splits=r.max_splits,
            rr_threshold=r.rr_threshold,
            polarized=r.polarization,
            birefringence=r.birefringence,
            coherence_width_mm=r.coherence_width_mm,
            coherence_cos=direction_tolerance(
                self.environment.struct.height if self.environment.struct.kind == ENV_KINDS["latlong"] else 0
            ),
        )
        # a camera inside a solid (in water, in a glass) starts its rays in that medium
        self._nesting = (meshes, built.parents)
        self._media: dict[tuple, int] = {}
        self.camera_medium = self._camera_medium(scene.camera.position)
        self.trace = TraceStage(
            trace_config,
            np.asarray(ids, dtype=np.int32),
            np.array([ob.absorption_scale for ob in scene.objects], dtype=np.float32),
            world_axes(scene.objects, built, file=scene.path),
            ambient=(r.ambient_index, 0.0),
            camera_medium=self.camera_medium,
            rgb3=r.spectral == "rgb3",
            device=self.device,
            films=films,
            # fluorescent media re-emit (stages/fluorescence.py); off otherwise (and in rgb3)
            reemission=build_reemission(mats, scene_light_spectra(scene), device=self.device)
            if self.fluorescence
            else None,
        )
        # the pixel kernel: camera samples -> the trace stage's function -> the film's sums
        self._pixels = _render_pixels_over(self.trace.function)
        film = FilmParams()
        film.width, film.height = self.camera.width, self.camera.height
        film.spp = r.spp
        # `wavelengths` samples per spp: strata of the spectrum (stratified) or independent draws
        # (uniform, importance), each weighted 1/count (spectra.sample_wavelength)
        film.count = 3 if r.spectral == "rgb3" else r.wavelengths
        film.strategy = strategy_id(r.spectral)
        film.seed = r.seed
        film.pass_index = 0
        # a scene whose every material has one index and no absorption at all wavelengths traces
        # one path tree per sample for the whole spectrum (exact: the tree does not depend on
        # the wavelength); rgb3 keeps its three indices by definition
        self.shared_spectrum = (
            r.spectral != "rgb3"
            and shared_spectrum is not False
            # beams asked for by name trace a clear stone's spectrum in bundles too
            and r.estimator != "beam"
            and _non_dispersive(mats)
            # films: a film's r and t depend on the wavelength (stages/coated.py)
            and not any(getattr(ob, "film", None) for ob in scene.objects)
            # surfaces and lamps: spectral albedos, one random path per wavelength
            and not scene.surfaces
            and not scene.lamps
            # coherent mode: the optical phases depend on the wavelength
            and r.birefringence != "coherent"
            # re-emission changes the wavelength along a path
            and not self.fluorescence
        )
        film.shared = 1 if self.shared_spectrum else 0
        # a dispersive (or absorbing) scene of isotropic, uncoated stones in an environment light
        # traces one path tree per bundle of up to render.bundle_lanes wavelengths at one pixel position
        # (stages/bundle.py); `spectral_bundle=False` or `render.bundle = false` traces a tree
        # per wavelength
        why = None
        if self.shared_spectrum:
            why = "a clear, non-dispersive scene: each point sample carries the whole spectrum"
        elif spectral_bundle is False:
            why = "spectral bundles turned off by the caller"
        elif r.birefringence == "coherent":
            why = "the coherent mode adds o/e amplitudes along point samples"
        elif self.camera_medium >= 0:
            why = "the camera sits inside a solid"
        self.spectral_bundle = why is None and bundle_obstacle(scene, built) is None
        # the camera estimator (render.estimator): pixel beams (stages/pixel_beam.py: a bundle's
        # lanes trace the pixel's whole footprint, through crystals and coatings too) wherever they apply,
        # else point samples; Image.stats and the command line say which ran and why
        if why is None:
            why = bundle_obstacle(scene, built, beams=True)
        if why is None:
            why = beam_obstacle(scene, self.geometry, built)
        if r.estimator == "beam" and why is not None:
            raise InputError(
                "pixel beams cannot trace this scene: " + why,
                file=scene.path,
                field="render.estimator",
                value="beam",
                allowed='"auto" or "point" for this scene',
            )
        if why is None and r.estimator == "auto" and (scene.surfaces or scene.lamps):
            # beams continue the parts that meet surfaces and lamps as point samples, one per part
            # and wavelength: unbiased, but slower to a given noise than point samples where the
            # surfaces' light dominates (docs/design/pixel_beams.md, "Other solids, surfaces, lamps")
            why = "auto keeps point samples in scenes with surfaces or lamps (beams by name)"
        self.pixel_beam = r.estimator != "point" and why is None
        self.estimator = "beam" if self.pixel_beam else "point"
        self.estimator_reason = (
            'render.estimator = "point"'
            if r.estimator == "point"
            else f"render.estimator = {r.estimator!r}" + ("" if why is None else ": " + why)
        )
        # a scene beams trace but point bundles do not (a crystal, a coating): the lanes are the beams'
        self.spectral_bundle = self.spectral_bundle or self.pixel_beam
        film.bundle = 1 if self.spectral_bundle else 0
        film.beam = 1 if self.pixel_beam else 0
        # per object whether beams may enter it, the spheres and planes they test (stages/pixel_beam.py)
        self.beam_scene = beam_scene(
            self.geometry,
            self.surfaces.struct,
            beam_objects(scene, self.geometry, built) if self.pixel_beam else [False] * len(scene.objects),
            device=self.device,
        )
        film.beam_block = beam_block(scene) if self.pixel_beam else 1
        film.groups = -(-film.count // r.bundle_lanes) if self.spectral_bundle else 1
        # the whole spectrum at every leaf, integrated exactly (no spectral noise); a shared
        # scene's `wavelengths` then only multiplies the pixel samples per spp
        film.response = wp.mat33f(
            self.environment.exact_response(self.tables, r.spectral).astype(np.float32).ravel().tolist()
            if self.shared_spectrum
            else np.zeros(9).tolist()
        )
        self.film = film
        film.spp_begin = 0
        film.adaptive = 0
        film.round = 0
        self.pilot = r.pilot if r.adaptive else 0
        n = film.width * film.height
        self.spp_end = wp.zeros(n if r.adaptive else 1, dtype=wp.int32, device=self.device)
        self.sq = wp.zeros(n, dtype=wp.vec3d, device=self.device)
        self.xyz = wp.zeros(n, dtype=wp.vec3d, device=self.device)
        self.stokes = wp.zeros(n, dtype=wp.vec4d, device=self.device)
        self.alpha = wp.zeros(n, dtype=wp.float64, device=self.device)
        self.rays = wp.zeros(n, dtype=wp.int64, device=self.device)
        self.stokes_xyz = wp.zeros((n, 3), dtype=wp.vec4d, device=self.device)
        self._sinks: dict[int, wp.array] = {}  # pixel beams' per-pixel sums, by film pixels
        self.caustics = None  # the caustic light tracer (stages/caustics.py)
        if r.caustics:
            self.caustics = caustic_stage(
                scene,
                built,
                ids,
                camera=self.camera,
                surfaces=self.surfaces,
                geometry=self.geometry,
                materials=self.materials,
                tables=self.tables,
                device=self.device,
            )
            self.caustic_film = np.zeros((n, 3), dtype=np.float64)  # the light tracer's output, reused

    def run(
        self,
        *,
        progress: bool = False,
        threads: int | None = None,
        tile_size: int | None = None,
        rows_per_chunk: int | None = None,
    ) -> Image:
        f = self.film
        r = self.scene.render
        load_module(self._pixels, self.device)  # compile (first run) outside the timed region
        for arr in (self.xyz, self.sq, self.stokes, self.alpha, self.rays, self.stokes_xyz):
            arr.zero_()
        h, w = f.height, f.width
        if rows_per_chunk is None:
            rows_per_chunk = max(1, min(f.height, 16384 // max(f.width, 1)))
        bsz = f.beam_block if f.beam else 1
        rows_per_chunk = -(-rows_per_chunk // bsz) * bsz  # whole blocks of pixel beams
        chunks = list(range(0, f.height, rows_per_chunk))
        rounds = 2 if r.adaptive else 1
        bar = None
        if progress:
            from tqdm.auto import tqdm  # a widget in Jupyter, text in a terminal

            bar = tqdm(total=f.height * rounds, unit="row", desc="render", leave=False, dynamic_ncols=True)
        t0 = time.perf_counter()
        spp = np.full((h, w), r.spp, dtype=np.int32)
        try:
            for rnd in range(rounds):
                f.round, f.adaptive, f.spp_begin, f.spp = rnd, 0, 0, r.spp
                if r.adaptive and rnd == 0:
                    f.spp = self.pilot  # the pilot: the same samples everywhere
                elif r.adaptive:
                    # every pixel's count from its neighbours' pilot (adaptive.py)
                    spp = allocate(
                        self.xyz.numpy().reshape(h, w, 3),
                        self.sq.numpy().reshape(h, w, 3),
                        self.rays.numpy().reshape(h, w),
                        pilot=self.pilot,
                        spp=r.spp,
                        traces=f.count,
                        seed=r.seed,
                    )
                    self.spp_end.assign(spp.ravel())
                    f.round, f.adaptive, f.spp_begin = 1, 1, self.pilot
                inputs = self._kernel_inputs(self.camera.params, self)
                for row0 in chunks:
                    rows = min(rows_per_chunk, f.height - row0)
                    first, count = self._launch_range(row0, rows, f.width)
                    launch_tiled(
                        self._pixels,
                        count,
                        [first, *inputs],
                        device=self.device,
                        threads=threads,
                        tile_size=tile_size,
                    )
                    if bar is not None:
                        bar.update(rows)
        finally:
            if bar is not None:
                bar.close()
        elapsed = time.perf_counter() - t0
        inv = 1.0 / spp.astype(np.float64)
        xyz = self.xyz.numpy().reshape(h, w, 3) * inv[..., None]
        stokes = self.stokes.numpy().reshape(h, w, 4) * inv[..., None]
        alpha = self.alpha.numpy().reshape(h, w) * inv
        rays = int(self.rays.numpy().sum())
        stokes_xyz = self.stokes_xyz.numpy().reshape(h, w, 3, 4) * inv[..., None, None]
        caustic_stats = {}
        if self.caustics is not None:
            # add the light tracer's film (unpolarized: S0 only) to the camera's
            cxyz = self.caustics.run(
                self.caustic_film, threads=threads, tile_size=tile_size, progress=progress
            ).reshape(h, w, 3)
            xyz = xyz + cxyz
            stokes[..., 0] += cxyz[..., 1]
            stokes_xyz[..., 0] += cxyz  # the S0 of each of X, Y, Z
            caustic_stats = {"caustic_seconds": self.caustics.seconds, "caustic_paths": self.caustics.paths}
        if not (np.isfinite(xyz).all() and np.isfinite(stokes).all()):
            bad = int((~np.isfinite(xyz)).any(axis=-1).sum())
            raise FloatingPointError(f"{bad} pixels are not finite: this is a bug, please report the scene")
        stats = {
            "seconds": elapsed,
            "rays": rays,
            "rays_per_second": rays / elapsed if elapsed > 0 else math.inf,
            "width": w,
            "height": h,
            "spp_mean": float(spp.mean()),
            "spp_max": int(spp.max()),
            "estimator": self.estimator,
            "estimator_reason": self.estimator_reason,
            **caustic_stats,
        }
        self.spp_per_pixel = spp
        return Image(
            xyz=xyz,
            stokes=stokes,
            alpha=alpha,
            exposure=r.exposure,
            tone=r.tone,
            stats=stats,
            stokes_xyz=stokes_xyz,
            source_polarizer=self.source_polarizer,
        )

    def _kernel_inputs(self, camera: CameraParams, out) -> list:
        """The pixel kernel's arguments after the launch offset: the scene's stages and the film
        ``out`` (any object with the arrays ``xyz, sq, stokes, alpha, rays, stokes_xyz``: the
        Renderer's own, or a preview's); for pixel beams among several objects, each block's
        target for this camera first."""
        if self.film.beam:
            w, h = int(camera.width), int(camera.height)
            beam_targets(self.beam_scene, camera, w, h, self.film.beam_block, self.device)
        return [
            camera,
            self.film,
            self.trace.params,
            self.geometry.geometry,
            self.materials,
            self.environment.struct,
            self.surfaces.struct,
            self.tables,
            1 if self.trace.config.polarized else 0,
            self.spp_end,
            out.xyz,
            out.sq,
            out.stokes,
            out.alpha,
            out.rays,
            out.stokes_xyz,
            self._sink(int(camera.width) * int(camera.height)),
            self.beam_scene,
        ]

    def _sink(self, n: int):
        """The pixel beams' sums for a film of ``n`` pixels (a row per pixel, zero between
        bundles; stages/pixel_beam.py), or a placeholder when the scene is not traced in beams."""
        n = n if self.film.beam else 1
        if n not in self._sinks:
            self._sinks[n] = wp.zeros((n, BEAM_SINK_COLS), dtype=wp.float32, device=self.device)
        return self._sinks[n]

    def _launch_range(self, row0: int, rows: int, width: int) -> tuple[int, int]:
        """(first launch index, count) of the film rows [row0, row0 + rows): pixels, or for
        pixel beams the blocks of ``film.beam_block`` rows that start there."""
        if not self.film.beam:
            return row0 * width, rows * width
        b = self.film.beam_block
        nbx = -(-width // b)
        return (row0 // b) * nbx, -(-rows // b) * nbx

    def launch_indices(self, width: int, height: int) -> np.ndarray:
        """The launch index (pixel, or pixel beams' block) of each pixel of a film of that size,
        ``(height, width)``: :meth:`render_pass`'s ``launch`` ranges in pixels."""
        y, x = np.mgrid[0:height, 0:width]
        if not self.film.beam:
            return y * width + x
        b = self.film.beam_block
        return (y // b) * (-(-width // b)) + x // b

    def load_kernels(self) -> None:
        """Load the pipeline kernel now (from the kernel cache, or compile it), so that the first
        :meth:`render_pass` or :meth:`run` does not pay for it."""
        load_module(self._pixels, self.device)

    def render_pass(
        self,
        film,
        *,
        pass_index: int = 0,
        spp_begin: int = 0,
        spp: int = 1,
        camera: CameraParams | None = None,
        threads: int | None = None,
        tile_size: int | None = None,
        launch: tuple[int, int] | None = None,
    ) -> None:
        """Add one progressive pass to ``film``: the samples ``[spp_begin, spp_begin + spp)`` of
        pass ``pass_index`` in every pixel (uniform: no adaptive rounds, no caustics), seen through
        ``camera`` (default the scene's); ``launch = (first, count)``: only those launch indices
        (pixels, or for pixel beams blocks: :meth:`launch_indices` maps the film's pixels).

        ``film`` is any object with ``width``, ``height`` and the arrays ``xyz, sq, stokes, alpha,
        rays, stokes_xyz`` laid out like the Renderer's own for that size (``pipelines/preview.py``
        owns one; a smaller film with a camera of its size is a low-resolution draft of the same
        scene); the kernel adds its sums, so the caller divides by the samples it accumulated.
        The camera stream continues the pixel's R2 sequence where ``spp_begin`` says, and each
        block of samples draws its trace decisions from its own stream (``round = spp_begin``),
        so passes ``spp_begin = 0, 1, 2, ...`` of one ``pass_index`` sample each pixel as
        independently as one render of that many spp.  Every setting is a value: nothing is
        compiled per pass, camera or film size.
        """
        cam = self.camera.params if camera is None else camera
        w, h = int(film.width), int(film.height)
        if (cam.width, cam.height) != (w, h):
            raise ValueError(f"the camera is {cam.width}x{cam.height} but the film {w}x{h}")
        f = self.film
        saved = (f.width, f.height, f.pass_index, f.round, f.adaptive, f.spp_begin, f.spp, f.bundle, f.groups)
        # a moved camera (the preview's orbit) may be in another medium; bundles start outside
        medium = self._camera_medium(tuple(float(v) for v in cam.position))
        if medium >= 0:
            f.bundle, f.groups = 0, 1
        f.width, f.height = w, h
        f.pass_index, f.round, f.adaptive = int(pass_index), int(spp_begin), 0
        f.spp_begin, f.spp = int(spp_begin), int(spp_begin) + int(spp)
        try:
            with self.trace.medium(medium):
                inputs = self._kernel_inputs(cam, film)
                first, n = self._launch_range(0, h, w)
                if launch is not None:
                    first, n = first + int(launch[0]), max(0, min(int(launch[1]), n - int(launch[0])))
                launch_tiled(
                    self._pixels,
                    n,
                    [first, *inputs],
                    device=self.device,
                    threads=threads,
                    tile_size=tile_size,
                )
        finally:
            f.width, f.height, f.pass_index, f.round, f.adaptive, f.spp_begin, f.spp, f.bundle, f.groups = (
                saved
            )

    def _camera_medium(self, position) -> int:
        """The solid a camera at ``position`` (mm) is in, -1 outside all (cached per position)."""
        key = tuple(float(v) for v in position)
        if key not in self._media:
            self._media[key] = point_medium(*self._nesting, key)
        return self._media[key]


def render(
    scene: Scene | str | Path,
    *,
    device=None,
    progress: bool = False,
    threads: int | None = None,
    tile_size: int | None = None,
    overrides: dict | None = None,
    **kw,
) -> Image:
    """Render a scene (a :class:`Scene` or a path to a TOML file) with the standard pipeline.

    Keyword overrides: ``width``, ``height`` (camera) and any ``[render]`` field (``spp``,
    ``spectral``, ``wavelengths``, ``polarization``, ``max_depth``, ``seed`` ...); ``overrides``
    takes dotted paths (``{"object.0.diameter": 5.0}``).
    """
    if not isinstance(scene, Scene):
        scene = Scene.load(scene)
    if kw or overrides:
        scene = scene.with_overrides(overrides, **kw)
    return Renderer(scene, device=device).run(progress=progress, threads=threads, tile_size=tile_size)
