"""The trace stage: a camera (backward) path tree through dielectric solids to the lights.

One call of :func:`trace_radiance` follows everything that light arriving along one primary ray
can have come through.  At every interface the path splits into the reflected and the refracted
branch.  While a branch carries at least ``split_threshold`` of the primary ray's energy both
children are followed deterministically on an explicit stack (the per-pixel form of the pruned
facet tree of Guy & Soler 2004 §5; ``max_splits`` bounds the extra branches); below it one child
is chosen by energy and weighted by 1/probability, and Russian roulette ends weak paths, so the
estimate is unbiased while the bright low-order paths carry no noise.

Conventions.  A polarized branch carries a Jones matrix M from the field on its segment (basis
``x`` perpendicular to the segment, ``y = k x x``, ``k`` the direction light travels) to the
field at the camera (image right, image up); backward across an interface
``M_child = M_parent B diag(r_s, r_p)`` (or t), B the s/p frame of the outgoing wave in the
parent's frame (Guy & Soler 2004 eq. 12, accumulated from the eye).  Unpolarized radiance L
arrives as the coherency matrix ``L/2 M M^dagger``; ``polarized=False`` carries power
coefficients instead.  Transmitted amplitudes are scaled by sqrt(Re(N_out cos t) / Re(N_in cos i))
so that |M|^2 is power; absorption is Bouguer–Lambert exp(-alpha l), alpha = 4 pi k / lambda.

A branch carries the solid it runs in (nested solids: ``geometry/nesting.py``), so every
interface sees the media on its two sides.  Fluorescence and the coherent mode are compiled only
into variants of the tracer (:func:`trace_variant`); :data:`trace_radiance` is every other
scene's.  The derivations: docs/design/point_tracer.md; units and frames: docs/conventions.md.

References: Guy & Soler 2004, "Graphics Gems Revisited", §5 and eq. 12; Veach 1997, ch. 4
(splitting, Russian roulette).
"""

from __future__ import annotations

import contextlib
import functools
from dataclasses import dataclass

import numpy as np
import warp as wp

from .. import validate as val
from ..film.leaf import add_leaf, add_light
from ..geometry.query import RayHit, SceneGeometry, medium_closest_hit, scene_closest_hit_leaving
from ..materials.dispersion import MaterialTable
from ..optics.absorption import bouguer_lambert
from ..optics.birefringence import uniaxial_medium
from ..optics.branches import (
    COLS,
    ROW_B,
    ROW_D,
    ROW_DEPTH,
    ROW_IN,
    ROW_MI,
    ROW_MODE,
    ROW_MR,
    ROW_O,
    ROW_W,
    ROW_WN,
    STACK_SIZE,
    Cand,
    Stack,
    pick_child,
    roulette,
    write_row,
)
from ..optics.interface import backward_coated, backward_crystal, backward_isotropic, is_uniaxial
from ..optics.jones import (
    Jones,
    coherency_transform,
    coherency_unpolarized,
    jones_identity,
    jones_zero,
)
from ..spectra import SpectralTables
from .coated import KIND_COATED, FilmSurfaces, coating_at, empty_film_surfaces, film_surface_children
from .coherence import DEFAULT_COHERENCE_WIDTH_MM, LeafBuffer, coherent_flush, coherent_leaf, segment_phase
from .environment import Environment, environment_coefficients, spectral_response
from .fluorescence import (
    COL_ENERGY,
    COL_KAPPA,
    COL_LENGTH,
    Candidate,
    Reemission,
    build_reemission,
    emission_weight,
    reemission_start,
)
from .media import object_medium, segment_kappa, zoned_kappa
from .surfaces import Surfaces, surface_radiance, surfaces_closest_hit

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "TraceParams",
    "TraceConfig",
    "TraceStage",
    "trace_radiance",
    "trace_variant",
    "default_params",
    "BIREFRINGENCE",
]

# "coherent": the exact events, with optical phases and the coherent leaf addition (stages/coherence.py)
BIREFRINGENCE = {"exact": 0, "approx": 1, "coherent": 0}
# stack rows in the ambient medium that leave the surface of solid k store inside = _LEFT - k
_LEFT = wp.constant(-2)


@wp.struct
class TraceParams:
    """Per-render settings of the trace stage (values, not compile-time constants)."""

    max_depth: int  # interfaces per path (Mitsuba's max_depth - 1); an index-matched one is free
    split_threshold: float  # split deterministically while a branch carries >= this energy
    max_splits: int  # at most this many extra branches from deterministic splits per primary ray
    rr_threshold: float  # below this energy a branch survives Russian roulette with p = e / rr
    t_max: float  # mm
    camera_medium: int  # the solid the camera is in (geometry.nesting.point_medium; -1: ambient)
    ambient: wp.vec2f  # complex index of the medium around the objects (air: 1)
    rgb3: int  # 1: use the materials' eq. 9 RGB absorbances (channel = sample index)
    birefringence: int  # 0 exact (separate o/e directions), 1 approx (shared direction, eq. 10)
    object_material: wp.array(dtype=wp.int32)  # material id of each object
    object_absorption_scale: wp.array(dtype=wp.float32)  # multiplier of alpha per object
    object_axis: wp.array(dtype=wp.vec3f)  # optic axis in world space; zero: isotropic
    films: FilmSurfaces  # per-object coatings, thin shells, film surfaces (stages/coated.py)
    reemission: Reemission  # fluorescent re-emission (stages/fluorescence.py; enabled 0: none)
    coherence_width: float  # mm: leaves closer than this across their direction add as amplitudes
    coherence_cos: float  # ... if the cosine between their directions is at least this


@dataclass(frozen=True)
class TraceConfig:
    """Settings of the backward tracer (from a camera scene's ``[render]``)."""

    max_depth: int = 12
    split_threshold: float = 0.002
    max_splits: int = 64
    rr_threshold: float = 1.0e-4
    polarized: bool = True
    birefringence: str = "exact"
    coherence_width_mm: float = DEFAULT_COHERENCE_WIDTH_MM
    coherence_cos: float = 1.0

    def __post_init__(self) -> None:
        val.integer(self.max_depth, field="render.max_depth", lo=0, hi=256)
        val.number(self.split_threshold, field="render.split_threshold", lo=0.0, hi=1.0)
        val.integer(self.max_splits, field="render.max_splits", lo=0, hi=4096)
        val.number(self.rr_threshold, field="render.rr_threshold", lo=0.0, hi=1.0)
        val.boolean(self.polarized, field="render.polarization")
        val.choice(self.birefringence, tuple(BIREFRINGENCE), field="render.birefringence")
        val.number(self.coherence_width_mm, field="render.coherence_width_mm", lo=0.0, hi=1.0e3)
        val.number(self.coherence_cos, field="coherence_cos", lo=-1.0, hi=1.0)


@wp.func
def _object_medium(p: TraceParams, mats: MaterialTable, obj: int, wavelength: float):
    """(UniaxialMedium with real indices, real index n_o as a complex number, (alpha_o, alpha_e))
    of object ``obj`` (``stages.media.object_medium``; interfaces use the real part of the index,
    see there).  The tracer keeps the last one it evaluated: a path tree at one wavelength meets
    the same stone at every interface, so the material formulas run once per stone and tree."""
    med, no, ne, alpha = object_medium(mats, p.object_material[obj], p.object_axis[obj], wavelength)
    return med, wp.vec2f(no[0], 0.0), alpha


@wp.func
def _start_offset(geom: SceneGeometry, inside: int, left: int):
    """How far past its interface a child row starts (``geom.epsilon`` of the solid whose surface
    it left: the one it runs inside, or the one it left into the ambient medium; 0 for camera rays
    and film children, which do not record it).  The coherent mode adds it to the segment's
    phase.  In nested scenes a segment that left an inner solid is offset by that solid's epsilon:
    there this is an approximation."""
    if inside >= 0:
        return geom.epsilon[inside]
    if left >= 0:
        return geom.epsilon[left]
    return 0.0


# Out of line, like the rarely taken branches (the birefringent events, film_surface_children,
# surface_radiance): with every function inlined into the pixel kernel, NVRTC needed 515 s to
# build the render module for sm_90 (and > 9 min with the adjoint code Warp generated until the
# modules set enable_backward=False); out of line, 244 s.  CPU speed: no measurable change.


def _make_trace_radiance(fluorescence: bool, coherent: bool):
    """The camera trace, compiled without (the default, :data:`trace_radiance`) or with the
    fluorescent re-emission pass and the coherent mode (:func:`trace_variant`): their code is left
    out of the kernel of scenes that do not use them (``wp.static``), so those cost nothing."""

    @wp.func(inline=False)
    def trace_radiance(
        p: TraceParams,
        geom: SceneGeometry,
        mats: MaterialTable,
        env: Environment,
        surf: Surfaces,
        tables: SpectralTables,
        polarized: int,
        origin: wp.vec3f,
        direction: wp.vec3f,
        basis_x: wp.vec3f,
        wavelength: float,
        weight: wp.vec3f,
        response: wp.mat33f,
        channel: int,
        rng: wp.uint32,
    ):
        """The light arriving along a primary ray: (coherency matrices J_X, J_Y, J_Z in the camera
        frame — the X-, Y- and Z-weighted light, so tr(J_Y) = Y and the Stokes vector of J_Y is the
        Y-weighted one — hit_any, rays_traced, rng).

        ``response`` turns the coefficients of the environment light that reaches a leaf into XYZ
        (environment.spectral_response): the one-wavelength estimate at ``wavelength`` with XYZ sample
        ``weight``, or for a path tree that does not depend on the wavelength (non-dispersive,
        non-absorbing scenes) the exact integral over the spectrum (EnvironmentLight.exact_response).
        ``wavelength`` and ``weight`` are still the sample's for the materials and the surfaces stage."""
        st = Stack()
        st = write_row(
            st, 0, origin, direction, basis_x, jones_identity(), 1.0, p.camera_medium, 0, -1, -direction
        )
        n = int(1)
        cand = Cand()
        acc_x = jones_zero()
        acc_y = jones_zero()
        acc_z = jones_zero()
        scalar_xyz = wp.vec3f(0.0, 0.0, 0.0)
        hit_any = int(0)
        rays = int(0)
        splits = int(0)
        # the medium around the objects, and the last object medium evaluated (see _object_medium)
        ambient_med = uniaxial_medium(p.ambient[0], p.ambient[0], wp.vec3f(0.0, 0.0, 0.0))
        ambient_n = wp.vec2f(p.ambient[0], 0.0)
        c_obj = int(-1)
        c_med = ambient_med
        c_n = ambient_n
        c_alpha = wp.vec2f(0.0, 0.0)
        ch3 = int(-1)  # rgb3 mode: the channel's eq. 9 absorbances (segments and shadow rays)
        if p.rgb3 != 0:
            ch3 = wp.clamp(channel, 0, 2)
        if wp.static(coherent):
            leaves = LeafBuffer()  # coherent mode: the leaves of this primary ray (stages/coherence.py)
            n_leaves = int(0)
        # fluorescence (stages/fluorescence.py): the camera tree keeps one segment inside a
        # fluorescent medium (the reservoir row fl_row, weight sum fl_total); in a second pass of the
        # same loop (phase 1, emission = 1) that segment's excitation tree is traced at the excitation
        # wavelength, and its radiance enters the camera tree's sums as unpolarized emission.  The
        # wavelength, the XYZ weight and the response of the tree being traced are wl, wgt and resp;
        # the pass switch sits outside the branch loop, so that loop selects no more state than
        # without fluorescence.
        wl = wavelength
        wgt = weight
        resp = response
        if wp.static(fluorescence):
            fl_row = Candidate()
            fl_total = float(0.0)
            emission = int(0)
            fl_factor = float(0.0)
            main_x = jones_zero()
            main_y = jones_zero()
            main_z = jones_zero()
            main_s = wp.vec3f(0.0, 0.0, 0.0)
            # the re-emission draws its random numbers from a stream of its own, seeded by the trace's
            # state and its camera sample (wavelength, ray: they differ from trace to trace even where the
            # camera tree draws nothing), so the camera tree's choices -- and every later trace of the
            # pixel -- are those of the same scene without fluorescence: the emission only adds light
            fl_rng = rng
            main_rng = rng
            if p.reemission.enabled != 0:
                h1 = int(wavelength * 16384.0) ^ int(direction[0] * 1.0e8) ^ (int(direction[1] * 1.0e8) * 3)
                h2 = int(wp.mod(origin[0] * 1.0e5, 1.0e9)) ^ (int(wp.mod(origin[1] * 1.0e5, 1.0e9)) * 7)
                fl_rng = wp.rand_init(
                    h1 ^ int(rng >> wp.uint32(1)), h2 ^ int(wp.mod(origin[2] * 1.0e5, 1.0e9))
                )
        for phase in range(wp.static(2 if fluorescence else 1)):
            if wp.static(fluorescence):
                if phase == 1 and fl_total > 0.0:
                    # the camera tree is done: its re-emission, once
                    fl_obj = int(fl_row[0, ROW_IN])
                    main_rng = rng
                    o_f, d_f, b_f, wl_x, fl_factor, rng = reemission_start(
                        fl_row,
                        fl_total,
                        p.reemission,
                        mats,
                        p.object_material[fl_obj],
                        p.object_absorption_scale[fl_obj],
                        wl,
                        fl_rng,
                    )
                    if fl_factor <= 0.0:
                        rng = main_rng
                    else:
                        main_x = acc_x
                        main_y = acc_y
                        main_z = acc_z
                        main_s = scalar_xyz
                        acc_x = jones_zero()
                        acc_y = jones_zero()
                        acc_z = jones_zero()
                        scalar_xyz = wp.vec3f(0.0, 0.0, 0.0)
                        wl = wl_x
                        wgt = wp.vec3f(1.0, 1.0, 1.0)
                        resp = spectral_response(env, tables, wl, wgt)
                        c_obj = int(-1)
                        splits = int(0)
                        emission = 1
                        # the root row, element by element (reassigning the stack in a branch would make
                        # Warp select the whole 40 x 24 matrix at every branch of the loop)
                        for c in range(3):
                            st[0, ROW_O + c] = o_f[c]
                            st[0, ROW_D + c] = d_f[c]
                            st[0, ROW_B + c] = b_f[c]
                            st[0, ROW_WN + c] = -d_f[c]
                        for c in range(4):
                            st[0, ROW_MR + c] = 0.0
                            st[0, ROW_MI + c] = 0.0
                        st[0, ROW_MR + 0] = 1.0  # the unit Jones matrix: unpolarized emission
                        st[0, ROW_MR + 3] = 1.0
                        st[0, ROW_W] = 1.0
                        st[0, ROW_IN] = float(fl_obj)
                        st[0, ROW_DEPTH] = 1.0
                        st[0, ROW_MODE] = -1.0
                        n = 1
            while n > 0:
                n -= 1
                # read the row inline (a wp.func argument is a by-value copy of the whole stack)
                o = wp.vec3f(st[n, ROW_O], st[n, ROW_O + 1], st[n, ROW_O + 2])
                d = wp.vec3f(st[n, ROW_D], st[n, ROW_D + 1], st[n, ROW_D + 2])
                bx = wp.vec3f(st[n, ROW_B], st[n, ROW_B + 1], st[n, ROW_B + 2])
                wn = wp.vec3f(st[n, ROW_WN], st[n, ROW_WN + 1], st[n, ROW_WN + 2])
                m = Jones()
                m.re = wp.mat22(st[n, ROW_MR], st[n, ROW_MR + 1], st[n, ROW_MR + 2], st[n, ROW_MR + 3])
                m.im = wp.mat22(st[n, ROW_MI], st[n, ROW_MI + 1], st[n, ROW_MI + 2], st[n, ROW_MI + 3])
                w = st[n, ROW_W]
                inside = int(st[n, ROW_IN])
                left = int(-1)
                if inside <= _LEFT:
                    # a ray in the ambient medium leaving the surface of solid `left` (see the children below)
                    left = _LEFT - inside
                    inside = -1
                depth = int(st[n, ROW_DEPTH])
                mode = int(st[n, ROW_MODE])
                rays += 1
                hit = RayHit()
                if inside >= 0:
                    # its own surface or that of a solid nested in it (solids nest or stay apart)
                    hit = medium_closest_hit(geom, inside, o, d, p.t_max)
                else:
                    hit = scene_closest_hit_leaving(geom, o, d, p.t_max, left)
                    # the surfaces stage (stages/surfaces.py): an opaque surface or a lamp in front of every
                    # solid ends the branch with its (unpolarized) radiance, like the environment below
                    if surf.num_surfaces + surf.num_area > 0:
                        sh = surfaces_closest_hit(surf, o, d, hit.t)
                        if sh.kind != 0:
                            radiance, rng = surface_radiance(
                                surf,
                                geom,
                                mats,
                                env,
                                tables,
                                p.object_material,
                                p.object_absorption_scale,
                                p.ambient[0],
                                o,
                                d,
                                sh,
                                wl,
                                ch3,
                                rng,
                            )
                            # one wavelength per path here: surfaces turn the shared-spectrum path off;
                            # a lit surface's light is unpolarized (no polarizer axis)
                            acc_x, acc_y, acc_z, scalar_xyz = add_leaf(
                                acc_x, acc_y, acc_z, scalar_xyz, polarized, m, w, wp.vec3f(0.0, 0.0, 0.0),
                                -d, bx, wgt * radiance,
                            )  # fmt: skip
                            continue
                if hit.object < 0:
                    if inside < 0:
                        # the environment behind env.polarizer (a polariscope's sheet; zero axis:
                        # unpolarized), arriving along k = -d in the frame (bx, k x bx)
                        xyz = resp * environment_coefficients(env, d)
                        if wp.static(coherent):
                            if polarized != 0:  # amplitudes, added per coherence cell (coherence.py)
                                leaves, n_leaves, acc_x, acc_y, acc_z = coherent_leaf(
                                    leaves, n_leaves, acc_x, acc_y, acc_z, m, w, o, d, bx, xyz,
                                    env.polarizer, p.ambient[0], depth, _start_offset(geom, inside, left), wl,
                                )  # fmt: skip
                            else:
                                scalar_xyz += xyz * w
                        else:
                            acc_x, acc_y, acc_z, scalar_xyz = add_leaf(
                                acc_x, acc_y, acc_z, scalar_xyz, polarized, m, w, env.polarizer, -d, bx, xyz
                            )
                    # a segment inside a solid that finds no exit leaked through a crack: dropped
                    continue
                if depth == 0:
                    hit_any = 1
                if inside >= 0 and inside != c_obj:
                    c_med, c_n, c_alpha = _object_medium(p, mats, inside, wl)
                    c_obj = inside
                med_a = ambient_med
                n_a = ambient_n
                if inside >= 0:
                    med_a = c_med
                    n_a = c_n
                    kappa = segment_kappa(
                        mats,
                        p.object_material[inside],
                        c_alpha,
                        ch3,
                        mode,
                        wn,
                        med_a,
                        p.object_absorption_scale[inside],
                    )
                    # a colour-zoned stone: the mean kappa of this wave through its zones
                    kappa = zoned_kappa(
                        mats,
                        p.object_material[inside],
                        kappa,
                        ch3,
                        mode,
                        wn,
                        med_a,
                        p.object_absorption_scale[inside],
                        wl,
                        o,
                        d,
                        hit.t,
                    )
                    if wp.static(fluorescence):
                        if p.reemission.enabled != 0 and emission == 0 and ch3 < 0:
                            if mats.fl_yield[p.object_material[inside]] > 0.0:
                                # a segment inside a fluorescent medium: a re-emission candidate, kept
                                # with probability W / sum W (its row st[n] is still the popped one)
                                e_fl, w_fl = emission_weight(m, w, kappa, hit.t)
                                if w_fl > 0.0:
                                    fl_total += w_fl
                                    if wp.randf(fl_rng) * fl_total < w_fl:
                                        for c in range(COLS):
                                            fl_row[0, c] = st[n, c]
                                        fl_row[0, COL_LENGTH] = hit.t
                                        fl_row[0, COL_KAPPA] = kappa
                                        fl_row[0, COL_ENERGY] = e_fl
                    w = w * bouguer_lambert(kappa, hit.t)
                if wp.static(coherent):
                    m = segment_phase(
                        m, med_a, mode, wn, d, hit.t, depth, _start_offset(geom, inside, left), wl
                    )
                if w <= 0.0:
                    continue
                x = o + d * hit.t
                eps = geom.epsilon[hit.object]  # origin offset of the children (query.offset_epsilon)
                n_out = hit.normal
                entering = wp.dot(d, n_out) < 0.0
                nrm = n_out  # unit normal on the side the backward ray arrives from (medium A)
                obj_b = hit.object
                if not entering:
                    nrm = -n_out
                    obj_b = geom.parent[hit.object]  # leaving a solid: into the one around it (nesting)
                med_b = ambient_med
                n_b = ambient_n
                if obj_b >= 0:
                    if obj_b != c_obj:
                        c_med, c_n, c_alpha = _object_medium(p, mats, obj_b, wl)
                        c_obj = obj_b
                    med_b = c_med
                    n_b = c_n
                count = int(0)
                energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
                film_kind = p.films.kind[hit.object]
                crystal = is_uniaxial(med_a) or is_uniaxial(med_b)
                # the same index on both sides and no film (an index-matched, invisible container):
                # nothing reflects and nothing bends, so the crossing is not a scattering event and
                # does not count toward max_depth
                matched = film_kind == 0 and not crystal and n_a[0] == n_b[0]
                if depth >= p.max_depth and not matched:
                    continue
                if film_kind != 0 and film_kind != KIND_COATED and not crystal:
                    # a thin shell or an opaque film surface (stages/coated.py)
                    obj_f = hit.object
                    cand, energies, count, rng = film_surface_children(
                        cand,
                        p.films,
                        mats,
                        p.object_material[obj_f],
                        obj_f,
                        m,
                        w,
                        bx,
                        d,
                        n_out,
                        n_a,
                        x,
                        geom.world_to_object[obj_f],
                        eps,
                        inside,
                        depth,
                        polarized,
                        wl,
                        rng,
                    )
                else:
                    # the interface event (optics/interface.py), bare or with the object's coating
                    if film_kind == KIND_COATED and not crystal:
                        coat, scale = coating_at(p.films, hit.object, x, geom.world_to_object[hit.object])
                        a_is_front = int(0)
                        if entering:
                            a_is_front = 1
                        cand, energies, count = backward_coated(
                            cand,
                            m,
                            w,
                            bx,
                            d,
                            n_out,
                            nrm,
                            n_a,
                            n_b,
                            x,
                            eps,
                            inside,
                            obj_b,
                            depth,
                            polarized,
                            p.films.stack,
                            coat,
                            wl,
                            scale,
                            a_is_front,
                        )
                    elif not crystal:
                        # a bare interface between isotropic media: the hot path
                        cand, energies, count = backward_isotropic(
                            cand, m, w, bx, d, n_out, nrm, n_a, n_b, x, eps, inside, obj_b, depth, polarized
                        )
                    else:
                        cand, energies, count = backward_crystal(
                            cand,
                            m,
                            w,
                            bx,
                            d,
                            wn,
                            mode,
                            n_out,
                            nrm,
                            med_a,
                            med_b,
                            n_a,
                            n_b,
                            x,
                            eps,
                            inside,
                            obj_b,
                            depth,
                            polarized,
                            p.birefringence,
                        )
                if matched:
                    for k in range(count):
                        cand[k, ROW_DEPTH] = float(depth)
                if p.films.kind[hit.object] == 0:
                    # the children in the ambient medium leave the solid's surface (reflected off it from
                    # outside, or transmitted out): remember which, so their query can skip it if convex
                    # (geometry/query.py scene_closest_hit_leaving).  Not for films: a shell has air inside.
                    for k in range(count):
                        if cand[k, ROW_IN] == -1.0:
                            cand[k, ROW_IN] = float(_LEFT - hit.object)
                e_parent = float(0.0)
                for k in range(count):
                    e_parent += energies[k]
                if e_parent <= 0.0:
                    continue
                if e_parent >= p.split_threshold and n + count <= STACK_SIZE and splits < p.max_splits:
                    # deterministic split: every child (pushed in reverse so the first is traced first)
                    splits += count - 1
                    for k in range(count):
                        kk = count - 1 - k
                        for c in range(COLS):  # inline: a wp.func would copy the whole stack by value
                            st[n, c] = cand[kk, c]
                        n += 1
                else:
                    # stochastic continuation: one child chosen by energy, weighted by 1/probability
                    pick = pick_child(energies, count, wp.randf(rng) * e_parent)
                    scale = e_parent / energies[pick]
                    # Russian roulette on weak paths (the energy after the choice is e_parent)
                    if e_parent < p.rr_threshold:
                        alive, boost = roulette(e_parent, p.rr_threshold, wp.randf(rng))
                        if alive == 0:
                            continue
                        scale = scale * boost
                    for c in range(COLS):
                        st[n, c] = cand[pick, c]
                    st[n, ROW_W] = st[n, ROW_W] * scale
                    n += 1
        if wp.static(coherent):
            if n_leaves > 0:
                acc_x, acc_y, acc_z = coherent_flush(
                    leaves, n_leaves, acc_x, acc_y, acc_z, env.polarizer, p.coherence_width, p.coherence_cos
                )
        if wp.static(fluorescence):
            if emission != 0:
                # the excitation tree's radiance (weight (1, 1, 1): its three sums alike) re-emitted
                # unpolarized into the kept segment, seen with the camera sample's XYZ weight
                l_x = scalar_xyz[1]
                if polarized != 0:
                    l_x = acc_y.re[0, 0] + acc_y.re[1, 1]
                a = fl_factor * l_x
                m_fl = Jones()
                m_fl.re = wp.mat22(
                    fl_row[0, ROW_MR], fl_row[0, ROW_MR + 1], fl_row[0, ROW_MR + 2], fl_row[0, ROW_MR + 3]
                )
                m_fl.im = wp.mat22(
                    fl_row[0, ROW_MI], fl_row[0, ROW_MI + 1], fl_row[0, ROW_MI + 2], fl_row[0, ROW_MI + 3]
                )
                w_fl = fl_row[0, ROW_W]
                k_fl = coherency_transform(m_fl, coherency_unpolarized(w_fl))
                acc_x, acc_y, acc_z = add_light(main_x, main_y, main_z, k_fl, weight * a)
                scalar_xyz = main_s + weight * (w_fl * a)
                rng = main_rng
        if polarized == 0:
            acc_x = coherency_unpolarized(scalar_xyz[0])
            acc_y = coherency_unpolarized(scalar_xyz[1])
            acc_z = coherency_unpolarized(scalar_xyz[2])
        return acc_x, acc_y, acc_z, hit_any, rays, rng

    return trace_radiance


trace_radiance = _make_trace_radiance(False, False)


@functools.cache
def trace_variant(fluorescence: bool, coherent: bool):
    """The camera trace with the re-emission pass and/or the coherent mode's phases and leaf
    buffer (built, and compiled, on first use); :data:`trace_radiance` has neither."""
    if not fluorescence and not coherent:
        return trace_radiance
    return _make_trace_radiance(fluorescence, coherent)


def default_params(
    objects_material: np.ndarray,
    absorption_scale: np.ndarray,
    object_axis: np.ndarray,
    *,
    config: TraceConfig,
    ambient=(1.0, 0.0),
    t_max: float = 1.0e6,
    camera_medium: int = -1,
    rgb3: bool = False,
    device=None,
    films: FilmSurfaces | None = None,
    reemission: Reemission | None = None,
) -> TraceParams:
    """TraceParams for objects with material ids, alpha multipliers and world optic axes (zero
    rows for isotropic objects); ``camera_medium``: the object the camera is inside (-1: none)."""
    p = TraceParams()
    p.max_depth = int(config.max_depth)
    p.split_threshold = float(config.split_threshold)
    p.max_splits = int(config.max_splits)
    p.rr_threshold = float(config.rr_threshold)
    p.t_max = float(t_max)
    p.camera_medium = int(camera_medium)
    p.ambient = wp.vec2f(*ambient)
    p.rgb3 = int(rgb3)
    p.birefringence = BIREFRINGENCE[config.birefringence]
    p.coherence_width = float(config.coherence_width_mm)
    p.coherence_cos = float(config.coherence_cos)
    p.object_axis = wp.array(
        np.asarray(object_axis, dtype=np.float32).reshape(-1, 3), dtype=wp.vec3f, device=device
    )
    p.object_material = wp.array(np.asarray(objects_material, dtype=np.int32), dtype=wp.int32, device=device)
    p.object_absorption_scale = wp.array(
        np.asarray(absorption_scale, dtype=np.float32), dtype=wp.float32, device=device
    )
    p.films = films if films is not None else empty_film_surfaces(len(p.object_material), device=device)
    p.reemission = reemission if reemission is not None else build_reemission([], None, device=device)
    return p


class TraceStage:
    """The camera trace stage (docs/conventions.md, "Stages"): owns its frozen :class:`TraceConfig`, its
    device data (:class:`TraceParams`: each object's material, absorption scale, optic axis,
    coatings, fluorescent re-emission) and the device function a pipeline's pixel kernel calls,
    :attr:`function` — :data:`trace_radiance`, or the variant with the re-emission pass
    (``reemission`` given) and/or the coherent mode (``config.birefringence == "coherent"``),
    :func:`trace_variant`.  The stage is fused into the pixel kernel (a camera sample's whole path
    tree stays in registers and on the stack, no ray queue), so its "run" is that kernel's launch:
    the pipeline owns the film it fills (``pipelines/render.py``).  ``medium(k)`` sets, for the
    launches inside the ``with`` block, the solid the camera rays start in (a moved camera)."""

    def __init__(
        self,
        config: TraceConfig,
        objects_material: np.ndarray,
        absorption_scale: np.ndarray,
        object_axis: np.ndarray,
        *,
        ambient=(1.0, 0.0),
        camera_medium: int = -1,
        rgb3: bool = False,
        films: FilmSurfaces | None = None,
        reemission: Reemission | None = None,
        device=None,
    ) -> None:
        if not isinstance(config, TraceConfig):
            raise TypeError(f"config must be a TraceConfig, not {type(config).__name__}")
        self.config = config
        self.fluorescence = reemission is not None
        self.coherent = config.birefringence == "coherent"
        self.camera_medium = int(camera_medium)
        self.params = default_params(
            objects_material,
            absorption_scale,
            object_axis,
            config=config,
            ambient=ambient,
            camera_medium=camera_medium,
            rgb3=rgb3,
            device=device,
            films=films,
            reemission=reemission,
        )
        self.function = trace_variant(self.fluorescence, self.coherent)

    @contextlib.contextmanager
    def medium(self, camera_medium: int):
        """Camera rays start in solid ``camera_medium`` (-1: the ambient medium) inside the block."""
        self.params.camera_medium = int(camera_medium)
        try:
            yield self
        finally:
            self.params.camera_medium = self.camera_medium
