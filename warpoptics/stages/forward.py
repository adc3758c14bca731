"""Forward (light) tracing for the optical bench: beams through solids onto screens.

One thread follows one beam ray (one position of the :class:`~warpoptics.stages.beam.Beam` at one
wavelength sample) and the whole tree of rays it splits into, with the camera tracer's physics:
closest hits (``geometry.query.scene_closest_hit``), indices and absorption
(``materials.dispersion``), and the one forward interface event (``optics.interface``: Fresnel
amplitudes or a coating's for isotropic media, the generalized Fresnel solution of Guy & Soler
2004 eq. 5 for crystals).

Conventions.  A ray carries a Jones matrix ``M`` from the source field (beam frame) to its own
and a weight ``w``; its power is ``w tr(M C M^dagger)`` times its emitted power, ``C`` the
source coherency (trace 1).  Amplitudes are normalised by the square root of the normal
Poynting-flux ratio so that ``|M|^2`` is power.  Isotropic media (``mode = -1``): two field
components in the frame ``(x, d x x)``.  Uniaxial crystals: a ray is one eigenmode, o (0) or e
(1), whose amplitude is row 0 of ``M``; an e ray travels along its Poynting direction and keeps
its wave normal for the next interface (Beyerle & McDermid 1998); pleochroic absorption
kappa^e(theta) of eq. 7 along the ray path.

Splitting: above ``split_threshold`` of the ray's power every child (reflected, refracted; o and
e) is followed; below it one child is chosen by power and weighted by 1/probability, which
carries the parent's power exactly, so the energy ledger closes per ray.  An interface never
returns more power than arrives.  Ledger per ray (columns of ``LEDGER``, relative to emitted
power): emitted = screen + absorbed + escaped + truncated + lost (no exit found) + overflow
(deposits beyond ``max_deposits``) + interface (not accounted for by the amplitudes).

Determinism: each thread writes its own ledger row and deposit slots and draws its own random
stream; the host reduces in a fixed order, so results do not depend on the thread count.

References: Guy & Soler 2004, "Graphics Gems Revisited", eq. 2-7, 12; Beyerle & McDermid 1998,
"Ray-tracing formulas for refraction and internal reflection in uniaxial crystals", Appl. Opt.
37(34); Veach 1997, ch. 4 (splitting, selection weighted by 1/probability).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import warp as wp

from .. import validate as val
from ..device import launch_tiled, load_module
from ..film.screen import ScreenSet, screen_hit
from ..geometry.query import RayHit, SceneGeometry, scene_closest_hit
from ..materials.dispersion import MaterialTable
from ..optics.absorption import bouguer_lambert
from ..optics.birefringence import uniaxial_medium
from ..optics.branches import (
    ROW_W,
    STACK_SIZE,
    Cand,
    Ray,
    Stack,
    copy_row,
    pick_child,
    read_row,
    write_row,
)
from ..optics.interface import forward_event, is_uniaxial, ray_power
from ..optics.jones import (
    Jones,
    coherency_transform,
    frame_change,
    jones_identity,
    jones_mul,
    jones_real,
    perpendicular,
    stokes_from_coherency,
)
from ..optics.thinfilm import CoatingStack
from .beam import BeamParams, beam_ray
from .media import object_medium, segment_kappa, zoned_kappa

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "ForwardParams",
    "ForwardConfig",
    "forward_params",
    "ForwardStage",
    "Deposits",
    "forward_trace_kernel",
    "forward_step",
    "LEDGER",
]

#: names of the ledger columns (see the module docstring)
LEDGER = ("screen", "absorbed", "escaped", "truncated", "lost", "overflow", "interface")
_L_SCREEN, _L_ABS, _L_ESC, _L_TRUNC, _L_LOST, _L_OVER, _L_IFACE = 0, 1, 2, 3, 4, 5, 6


@wp.struct
class ForwardParams:
    """Per-run settings of the forward trace (values, not compile-time constants)."""

    max_depth: int
    split_threshold: float  # relative power above which a node splits deterministically
    t_max: float  # mm
    ambient: wp.vec2f  # complex index around the objects
    max_deposits: int  # screen deposit slots per beam ray
    seed: int
    object_material: wp.array(dtype=wp.int32)
    object_absorption_scale: wp.array(dtype=wp.float32)
    object_axis: wp.array(dtype=wp.vec3f)  # world-space unit optic axis (uniaxial objects)
    object_coating: wp.array(dtype=wp.int32)  # coating index in the CoatingStack, -1: bare


@dataclass(frozen=True)
class ForwardConfig:
    """Settings of the forward tracer (a bench scene's ``[render]``): path depth, the relative
    power above which rays split deterministically, screen deposits kept per ray, the seed."""

    max_depth: int = 16
    split_threshold: float = 1.0e-4
    max_deposits: int = 24
    seed: int = 0

    def __post_init__(self) -> None:
        val.integer(self.max_depth, field="render.max_depth", lo=0, hi=256)
        val.number(self.split_threshold, field="render.split_threshold", lo=0.0, hi=1.0)
        val.integer(self.max_deposits, field="render.max_deposits", lo=1, hi=1024)
        val.integer(self.seed, field="render.seed", lo=0, hi=2**31 - 1)


@wp.func
def _medium(fp: ForwardParams, mats: MaterialTable, obj: int, wavelength: float):
    """(UniaxialMedium, complex index N_o, (alpha_o, alpha_e)) of object ``obj`` or, for -1, of the
    ambient medium (``stages.media.object_medium``)."""
    if obj < 0:
        return uniaxial_medium(fp.ambient[0], fp.ambient[0], wp.vec3f(0.0)), fp.ambient, wp.vec2f(0.0, 0.0)
    med, no, ne, alpha = object_medium(mats, fp.object_material[obj], fp.object_axis[obj], wavelength)
    return med, no, alpha


@wp.func
def _keep_children(
    st: Any, n: int, cand: Cand, ea: wp.vec4f, e_sum: float, c: int, split_threshold: float, rng: wp.uint32
):
    """Continue the tree with the children of an interface: all of them while they carry at
    least ``split_threshold`` (and the stack has room), else one chosen by power
    (``branches.pick_child``), weighted by 1/probability (carries ``e_sum`` exactly).  Returns
    (st, n, rng)."""
    if e_sum >= split_threshold and n + c <= STACK_SIZE:
        for j in range(c):
            st = copy_row(st, n + j, cand, j)
        return st, n + c, rng
    j = pick_child(ea, c, wp.randf(rng) * e_sum)
    st = copy_row(st, n, cand, j)
    st[n, ROW_W] = st[n, ROW_W] * (e_sum / ea[j])
    return st, n + 1, rng


@wp.func
def forward_step(
    st: Any,
    n: int,
    rng: wp.uint32,
    fp: ForwardParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    coatings: CoatingStack,
    hit: RayHit,
    r: Ray,
    e: float,
    wl: float,
    csrc: Jones,
):
    """The forward ray ``r`` of power ``e`` that reached ``hit``: Bouguer–Lambert along its segment
    inside a solid, the cut at ``max_depth``, then the interface event
    (``optics.interface.forward_event``) and the split (:func:`_keep_children`).  Returns (st, n,
    rng, (absorbed, truncated, interface loss)) for the ledger."""
    e_abs = float(0.0)
    w = r.w
    med_a, n_a, alpha_a = _medium(fp, mats, r.inside, wl)
    if r.inside >= 0:
        kappa = segment_kappa(
            mats,
            fp.object_material[r.inside],
            alpha_a,
            -1,
            r.mode,
            r.wn,
            med_a,
            fp.object_absorption_scale[r.inside],
        )
        kappa = zoned_kappa(
            mats,
            fp.object_material[r.inside],
            kappa,
            -1,
            r.mode,
            r.wn,
            med_a,
            fp.object_absorption_scale[r.inside],
            wl,
            r.o,
            r.d,
            hit.t,
        )
        att = bouguer_lambert(kappa, hit.t)
        e_abs = e * (1.0 - att)
        w = w * att
        e = e * att
    if e <= 0.0 and r.depth < fp.max_depth:
        return st, n, rng, wp.vec3f(e_abs, 0.0, 0.0)
    obj_b = hit.object
    if wp.dot(r.d, hit.normal) >= 0.0:
        obj_b = geom.parent[hit.object]  # leaving the solid: into the one around it (nesting)
    med_b, n_b, alpha_b = _medium(fp, mats, obj_b, wl)
    # the same index on both sides and no coating (an index-matched, invisible container):
    # nothing reflects and nothing bends, so the crossing does not count toward max_depth
    depth = r.depth
    if fp.object_coating[hit.object] < 0 and not is_uniaxial(med_a) and not is_uniaxial(med_b):
        if n_a[0] == n_b[0] and n_a[1] == n_b[1]:
            depth = r.depth - 1  # forward_event gives its children depth + 1
    if depth >= fp.max_depth:
        return st, n, rng, wp.vec3f(e_abs, e, 0.0)
    if e <= 0.0:
        return st, n, rng, wp.vec3f(e_abs, 0.0, 0.0)
    x = r.o + r.d * hit.t
    cand, ea, e_sum, c = forward_event(
        r.d,
        r.wn,
        r.b,
        r.m,
        r.mode,
        depth,
        hit.normal,
        x,
        r.inside,
        obj_b,
        med_a,
        med_b,
        n_a,
        n_b,
        coatings,
        fp.object_coating[hit.object],
        wl,
        geom.epsilon[hit.object],
        w,
        e,
        csrc,
    )
    if c > 0:
        st, n, rng = _keep_children(st, n, cand, ea, e_sum, c, fp.split_threshold, rng)
    return st, n, rng, wp.vec3f(e_abs, 0.0, e - e_sum)


@wp.kernel
def forward_trace_kernel(
    offset: int,
    base_ray: int,
    fp: ForwardParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    coatings: CoatingStack,
    beam: BeamParams,
    screens: ScreenSet,
    wavelengths: wp.array(dtype=wp.float32),
    dep_screen: wp.array(dtype=wp.int32),
    dep_uv: wp.array(dtype=wp.vec2f),
    dep_stokes: wp.array(dtype=wp.vec4f),
    dep_depth: wp.array(dtype=wp.int32),
    ledger: wp.array2d(dtype=wp.float64),
):
    """One beam ray (position i / n_wl, wavelength sample i % n_wl, i = base_ray + thread) and its
    whole split tree; deposit slots and ledger rows are indexed by the thread (chunk-relative)."""
    li = wp.tid() + offset
    i = base_ray + li
    n_wl = wavelengths.shape[0]
    wl = wavelengths[i % n_wl]
    o0, d0, bx0 = beam_ray(beam, i / n_wl)
    csrc = beam.source_coherency
    rng = wp.rand_init(fp.seed, i)
    st = Stack()
    st = write_row(st, 0, o0, d0, bx0, jones_identity(), 1.0, -1, 0, -1, d0)
    n = int(1)
    ndep = int(0)
    e_screen = float(0.0)
    e_abs = float(0.0)
    e_esc = float(0.0)
    e_trunc = float(0.0)
    e_over = float(0.0)
    e_lost = float(0.0)
    e_iface = float(0.0)
    base = li * fp.max_deposits
    for k in range(fp.max_deposits):
        dep_screen[base + k] = -1
    while n > 0:
        n -= 1
        r = read_row(st, n)
        e = ray_power(r.m, r.w, csrc)
        hit = scene_closest_hit(geom, r.o, r.d, fp.t_max)
        if r.inside < 0:
            t_s, k_s, su, sv = screen_hit(screens, r.o, r.d, hit.t)
            if k_s >= 0:
                # deposit: coherency in the screen frame (x = screen right projected perpendicular to d)
                xs = screens.right[k_s] - r.d * wp.dot(r.d, screens.right[k_s])
                if wp.dot(xs, xs) < 1.0e-12:
                    xs = perpendicular(r.d)
                xs = wp.normalize(xs)
                rot = jones_real(frame_change(r.d, r.b, xs))
                coh = coherency_transform(jones_mul(rot, r.m), csrc)
                sv4 = stokes_from_coherency(coh) * r.w
                if ndep < fp.max_deposits:
                    slot = base + ndep
                    dep_screen[slot] = k_s
                    dep_uv[slot] = wp.vec2f(su, sv)
                    dep_stokes[slot] = sv4
                    dep_depth[slot] = r.depth
                    ndep += 1
                    e_screen += sv4[0]
                else:
                    e_over += sv4[0]
                continue
            if hit.object < 0:
                e_esc += e
                continue
        elif hit.object < 0:
            e_lost += e  # a ray inside a solid found no exit
            continue
        # the segment's absorption, then the interface: the one step both forward tracers share
        st, n, rng, ledger_step = forward_step(st, n, rng, fp, geom, mats, coatings, hit, r, e, wl, csrc)
        e_abs += ledger_step[0]
        e_trunc += ledger_step[1]
        e_iface += ledger_step[2]
    ledger[li, _L_SCREEN] = wp.float64(e_screen)
    ledger[li, _L_ABS] = wp.float64(e_abs)
    ledger[li, _L_ESC] = wp.float64(e_esc)
    ledger[li, _L_TRUNC] = wp.float64(e_trunc)
    ledger[li, _L_LOST] = wp.float64(e_lost)
    ledger[li, _L_OVER] = wp.float64(e_over)
    ledger[li, _L_IFACE] = wp.float64(e_iface)


def forward_params(
    object_material,
    absorption_scale,
    object_axis,
    object_coating,
    *,
    config: ForwardConfig,
    ambient=(1.0, 0.0),
    t_max: float = 1.0e6,
    device=None,
) -> ForwardParams:
    """The kernel struct of a forward trace; per-object arrays have one entry per object."""
    p = ForwardParams()
    p.max_depth = int(config.max_depth)
    p.split_threshold = float(config.split_threshold)
    p.t_max = float(t_max)
    p.ambient = wp.vec2f(*ambient)
    p.max_deposits = int(config.max_deposits)
    p.seed = int(config.seed)
    p.object_material = wp.array(np.asarray(object_material, dtype=np.int32), dtype=wp.int32, device=device)
    p.object_absorption_scale = wp.array(
        np.asarray(absorption_scale, dtype=np.float32), dtype=wp.float32, device=device
    )
    p.object_axis = wp.array(
        np.asarray(object_axis, dtype=np.float32).reshape(-1, 3), dtype=wp.vec3f, device=device
    )
    p.object_coating = wp.array(np.asarray(object_coating, dtype=np.int32), dtype=wp.int32, device=device)
    return p


@dataclass
class Deposits:
    """The forward stage's output for one launch of ``count`` beam rays (device arrays the stage
    owns, reused from launch to launch): ``max_deposits`` slots per ray of screen index (-1:
    empty), position on the screen, Stokes vector and interfaces crossed, and the per-ray ledger."""

    screen: Any
    uv: Any
    stokes: Any
    depth: Any
    ledger: Any


class ForwardStage:
    """The optical bench's forward trace (docs/conventions.md, "Stages"): owns its frozen
    :class:`ForwardConfig`, its device data (:class:`ForwardParams`), its kernel
    (:data:`forward_trace_kernel`) and the deposit buffers it fills — allocated once per launch
    size and reused, so :meth:`run` allocates nothing after the first call of a size."""

    def __init__(
        self,
        config: ForwardConfig,
        object_material,
        absorption_scale,
        object_axis,
        object_coating,
        *,
        ambient=(1.0, 0.0),
        device=None,
    ) -> None:
        if not isinstance(config, ForwardConfig):
            raise TypeError(f"config must be a ForwardConfig, not {type(config).__name__}")
        self.config = config
        self.device = device
        self.params = forward_params(
            object_material,
            absorption_scale,
            object_axis,
            object_coating,
            config=config,
            ambient=ambient,
            device=device,
        )
        self._buffers: dict[int, Deposits] = {}

    def load(self) -> None:
        """Load the kernel now (from the kernel cache, or compile it), outside a timed region."""
        load_module(forward_trace_kernel, self.device)

    def buffers(self, count: int) -> Deposits:
        """The deposit buffers for launches of ``count`` beam rays (allocated on first use)."""
        if count not in self._buffers:
            k, dev = self.config.max_deposits, self.device
            self._buffers[count] = Deposits(
                screen=wp.empty(count * k, dtype=wp.int32, device=dev),
                uv=wp.empty(count * k, dtype=wp.vec2f, device=dev),
                stokes=wp.empty(count * k, dtype=wp.vec4f, device=dev),
                depth=wp.empty(count * k, dtype=wp.int32, device=dev),
                ledger=wp.zeros((count, len(LEDGER)), dtype=wp.float64, device=dev),
            )
        return self._buffers[count]

    def run(
        self,
        start: int,
        count: int,
        out: Deposits,
        *,
        geometry: SceneGeometry,
        materials: MaterialTable,
        coatings: CoatingStack,
        beam: BeamParams,
        screens: ScreenSet,
        wavelengths,
        threads: int | None = None,
        tile_size: int | None = None,
    ) -> Deposits:
        """Trace beam rays ``[start, start + count)`` (ray ``i`` is beam ray ``i // n_wl`` at
        wavelength sample ``i % n_wl``) into ``out`` (:meth:`buffers` of at least ``count``)."""
        inputs = [
            self.params,
            geometry,
            materials,
            coatings,
            beam,
            screens,
            wavelengths,
            out.screen,
            out.uv,
            out.stokes,
            out.depth,
            out.ledger,
        ]
        launch_tiled(
            forward_trace_kernel,
            count,
            [start, *inputs],
            device=self.device,
            threads=threads,
            tile_size=tile_size,
        )
        return out
