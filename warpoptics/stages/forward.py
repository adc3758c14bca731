"""Forward (light) tracing for the optical bench: beams through solids onto screens.

One thread follows one beam ray (one position of the :class:`~warpoptics.stages.beam.Beam` at one
wavelength sample) and the whole tree of rays it splits into, with the physics of the camera
tracer (``stages.trace``): closest hits by ``geometry.query.scene_closest_hit``, indices and
absorption by ``materials.dispersion.material_eval`` / ``material_alpha``, isotropic interfaces
by ``optics.fresnel.fresnel_amplitudes`` (or ``optics.thinfilm.coating_amplitudes`` for a coated
object), uniaxial interfaces by the generalized Fresnel solution ``optics.birefringence
.generalized_fresnel`` (Guy & Soler 2004 eq. 5 after McClain et al. 1993), frames and Jones
algebra by ``optics.jones``.

Forward transport
-----------------
A ray carries a 2x2 complex Jones matrix ``M`` mapping the source field (in the beam's frame)
to the ray's field, and a scalar weight ``w``; its power is ``w tr(M C M^dagger)`` with ``C``
the beam's source coherency matrix (trace 1), times the ray's emitted power.  Amplitudes are
normalised by the square root of the normal Poynting-flux ratio at every interface so that
``|M|^2`` is power (for isotropic media ``Re(N2 cos t) / Re(N1 cos i)``, as in ``stages.trace``;
for uniaxial media the ``flux`` of each wave of eq. 5).

Media and modes: in an isotropic medium (``mode = -1``) the field has two components in the
frame ``(x, d x x)``.  In a uniaxial crystal a ray is one eigenmode, o (``mode = 0``) or e
(``mode = 1``), and row 0 of ``M`` holds its scalar amplitude (row 1 is zero): entering a crystal
an unpolarized ray splits into an o ray and an e ray.  An e ray travels along its Poynting (ray)
direction, while its wave normal (kept on the ray) enters the next interface's eq. 5 - Beyerle &
McDermid 1998.  Leaving the crystal, the o and e amplitudes of each transmitted wave become the
s/p components of an isotropic ray.  Pleochroic absorption: kappa_o for o rays, kappa^e(theta)
of eq. 7 (``kappa_extraordinary``) for e rays, Bouguer-Lambert along the ray path.

Splitting: while a ray's tree node carries at least ``split_threshold`` of the ray's emitted
power (and the stack has room), every child (reflected, refracted; o and e) is followed -
deterministically.  Below it one child is chosen with probability proportional to its power and
weighted by 1/probability, which carries the parent's power exactly, so the energy ledger
closes per ray, not only on average.  An interface never returns more power than arrives (with an
absorbing incident medium the Fresnel flux split can, near total reflection: the children are
then scaled to the incident power).  Paths end on a screen, escape, are absorbed, or are cut
at ``max_depth`` interfaces ("truncated").

Energy ledger per ray (relative to its emitted power), columns of ``LEDGER``: screen, absorbed
(Bouguer-Lambert in the media), escaped (left the scene), truncated (cut at ``max_depth``), lost
(a ray inside a solid that found no exit: a crack in a mesh, or float32 round-off), overflow
(screen deposits beyond the ``max_deposits`` slots of the ray: counted, not recorded),
interface (power not accounted for by the Fresnel amplitudes at an interface: zero for
transparent media up to float32 rounding, the interface absorption of absorbing ones).
emitted = screen + absorbed + escaped + truncated + lost + overflow + interface.

Determinism: each thread writes only its own ledger row and deposit slots and draws its own
random stream ``rand_init(seed, ray index)``; the reductions run on the host in a fixed order,
so results are identical for any thread count or tiling.

References:
    Guy, S., Soler, C. 2004. Graphics Gems Revisited. ACM TOG 23(3). eq. 2-7, 12.
    Beyerle, G., McDermid, I. S. 1998. Ray-tracing formulas for refraction and internal
        reflection in uniaxial crystals. Applied Optics 37(34).
    Veach, E. 1997. Robust Monte Carlo Methods for Light Transport Simulation, ch. 4
        (splitting and random selection weighted by 1/probability).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import warp as wp

from .. import validate as val
from ..geometry.query import RayHit, SceneGeometry, scene_closest_hit
from ..materials.dispersion import MaterialTable, material_alpha, material_eval
from ..optics.birefringence import PlaneWave, generalized_fresnel, kappa_extraordinary, uniaxial_medium
from ..optics.fresnel import fresnel_amplitudes
from ..optics.jones import (
    Jones,
    coherency_transform,
    frame_change,
    jones,
    jones_diag,
    jones_identity,
    jones_mul,
    jones_real,
    jones_scale,
    perpendicular,
    s_vector,
    stokes_from_coherency,
)
from ..optics.thinfilm import CoatingStack, coating_amplitudes
from .beam import BeamParams, beam_ray
from .branches import (
    _W,
    STACK_SIZE,
    Cand,
    Ray,
    copy_row,
    write_row,
)
from .branches import (
    Stack as _Stack,
)
from .branches import (
    read_row as _read_row,
)
from ..film.screen import ScreenSet, screen_hit

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["ForwardParams", "ForwardConfig", "forward_params", "forward_trace_kernel", "forward_interface", "forward_step", "LEDGER",
           "STACK_SIZE"]

#: names of the ledger columns (see the module docstring)
LEDGER = ("screen", "absorbed", "escaped", "truncated", "lost", "overflow", "interface")
_L_SCREEN, _L_ABS, _L_ESC, _L_TRUNC, _L_LOST, _L_OVER, _L_IFACE = 0, 1, 2, 3, 4, 5, 6


@wp.struct
class ForwardParams:
    """Per-run settings of the forward trace (values, not compile-time constants)."""

    max_depth: int
    split_threshold: float  # relative power above which a node splits deterministically
    t_max: float  # mm
    epsilon: float  # origin offset along a new direction, mm
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
def _push(
    st: Any,
    n: int,
    o: wp.vec3f,
    d: wp.vec3f,
    s: wp.vec3f,
    b: wp.vec3f,
    m: Jones,
    w: float,
    inside: int,
    depth: int,
    mode: int,
):
    # the shared row layout keeps the wave normal s in the _WN columns
    return write_row(st, n, o, d, b, m, w, inside, depth, mode, s)


@wp.func
def ray_power(m: Jones, w: float, source: Jones):
    """Relative power w tr(M C M^dagger) of a ray (C: source coherency, trace 1)."""
    j = coherency_transform(m, source)
    return w * (j.re[0, 0] + j.re[1, 1])


@wp.func
def _medium_index(p: ForwardParams, mats: MaterialTable, obj: int, wavelength: float):
    if obj < 0:
        return p.ambient, p.ambient
    return material_eval(mats, p.object_material[obj], wavelength)


@wp.func
def _is_uniaxial(p: ForwardParams, mats: MaterialTable, obj: int):
    if obj < 0:
        return 0
    return mats.uniaxial[p.object_material[obj]]


@wp.func
def _crystal(p: ForwardParams, mats: MaterialTable, obj: int, wavelength: float):
    # real indices and world optic axis (zero axis: isotropic) for generalized_fresnel
    no, ne = _medium_index(p, mats, obj, wavelength)
    if _is_uniaxial(p, mats, obj) == 0:
        return uniaxial_medium(no[0], no[0], wp.vec3f(0.0))
    return uniaxial_medium(no[0], ne[0], p.object_axis[obj])


@wp.func
def _segment_alpha(
    p: ForwardParams, mats: MaterialTable, obj: int, mode: int, s: wp.vec3f, wavelength: float
):
    # Bouguer-Lambert coefficient (1/mm) of a ray segment inside object obj (Guy & Soler eq. 6, 7)
    mid = p.object_material[obj]
    ao, ae = material_alpha(mats, mid, wavelength)
    a = ao
    if mode == 1:
        no, ne = material_eval(mats, mid, wavelength)
        a = kappa_extraordinary(wp.dot(s, p.object_axis[obj]), ao, ae, no[0], ne[0])
    return a * p.object_absorption_scale[obj]


@wp.func
def _flux_scale(out_flux: float, in_flux: float):
    if in_flux <= 0.0 or out_flux <= 0.0:
        return 0.0
    return wp.sqrt(out_flux / in_flux)


@wp.struct
class _WaveCtx:
    """What every outgoing wave of one interface event shares."""

    x: wp.vec3f  # hit point
    eps: float  # origin offset
    w: float  # weight of the incident ray
    source: Jones  # source coherency
    depth: int  # depth of the children
    flux_in: float  # normal Poynting flux of the incident wave per unit |amplitude|^2


@wp.func
def _wave_ctx(x: wp.vec3f, eps: float, w: float, source: Jones, depth: int, flux_in: float):
    ctx = _WaveCtx()
    ctx.x = x
    ctx.eps = eps
    ctx.w = w
    ctx.source = source
    ctx.depth = depth
    ctx.flux_in = flux_in
    return ctx


@wp.func
def _push_wave(
    st: Any,
    n: int,
    c: int,
    ea: wp.vec4f,
    e_sum: float,
    ctx: _WaveCtx,
    wave: PlaneWave,
    coef: Jones,
    m: Jones,
    inside: int,
    mode: int,
):
    """Candidate row n + c for an outgoing wave of the generalized Fresnel solution: Jones
    ``coef m`` power-normalised by the fluxes, travelling along the wave's ray; skipped when the
    wave is evanescent or carries no power.  Returns (st, ea, e_sum, c)."""
    if wave.propagating == 1:
        mk = jones_scale(jones_mul(coef, m), _flux_scale(wave.flux, ctx.flux_in))
        ek = ray_power(mk, ctx.w, ctx.source)
        if ek > 0.0:
            st = _push(
                st,
                n + c,
                ctx.x + wave.ray * ctx.eps,
                wave.ray,
                wave.wave_normal,
                wave.e_re,
                mk,
                ctx.w,
                inside,
                ctx.depth,
                mode,
            )
            ea[c] = ek
            e_sum += ek
            c += 1
    return st, ea, e_sum, c


@wp.func
def forward_interface(
    fp: ForwardParams,
    mats: MaterialTable,
    coatings: CoatingStack,
    hit: RayHit,
    r: Ray,
    w: float,
    e: float,
    wl: float,
    csrc: Jones,
):
    """One interface event of the forward ray ``r`` (weight ``w`` after its segment's
    absorption, power ``e``) hitting ``hit``: the reflected and
    refracted children (o and e waves at a crystal) in rows 0..c-1 of a candidate matrix, with
    Fresnel / coating / generalized-Fresnel amplitudes.  Returns (cand, powers, e_sum, c); the
    tracers (``forward_trace_kernel``, ``caustics``) keep them all or choose one.  The stack is
    not an argument: a @wp.func argument is a by-value copy."""
    o = r.o
    d = r.d
    s_in = r.wn
    bx = r.b
    m = r.m
    mode = r.mode
    inside = r.inside
    depth = r.depth
    cand = Cand()
    x = o + d * hit.t
    n_out = hit.normal
    entering = wp.dot(d, n_out) < 0.0
    nrm = n_out  # unit normal on the incident side
    obj_b = hit.object
    if not entering:
        nrm = -n_out
        obj_b = -1
    obj_a = inside
    # candidates are written to rows n .. n + c - 1, then kept (split) or one is chosen
    c = int(0)
    e_sum = float(0.0)
    ea = wp.vec4f(0.0)
    if _is_uniaxial(fp, mats, obj_a) == 0 and _is_uniaxial(fp, mats, obj_b) == 0:
        # isotropic interface: Fresnel (or the coating's stack) in the s/p frame
        n_a, n_a_e = _medium_index(fp, mats, obj_a, wl)
        n_b, n_b_e = _medium_index(fp, mats, obj_b, wl)
        # Light arriving from an absorbing medium: Fresnel with the real part of its index
        # (the weak-absorption approximation; its absorption is Bouguer-Lambert along the
        # path).  ``c_normal_component`` takes the Im >= 0 root of N2 cos t, which for an
        # absorbing *incident* medium is the backward-travelling one (|r| >> 1).
        n_a = wp.vec2f(n_a[0], 0.0)
        cos_a = wp.clamp(-wp.dot(d, nrm), 0.0, 1.0)
        s = s_vector(d, n_out)
        f = fresnel_amplitudes(cos_a, n_a, n_b)
        rs = f.rs
        rp = f.rp
        ts = f.ts
        tp = f.tp
        coat = fp.object_coating[hit.object]
        if coat >= 0:
            if entering:
                rs, rp, ts, tp = coating_amplitudes(coatings, coat, wl, cos_a, n_a, n_b, 0)
            else:
                rs, rp, ts, tp = coating_amplitudes(coatings, coat, wl, cos_a, n_b, n_a, 1)
        m_sp = jones_mul(jones_real(frame_change(d, bx, s)), m)
        d_r = wp.normalize(d + nrm * (2.0 * cos_a))
        m_r = jones_mul(jones_diag(rs, rp), m_sp)
        e_r = ray_power(m_r, w, csrc)
        if e_r > 0.0:
            cand = _push(cand, c, x + d_r * fp.epsilon, d_r, d_r, s, m_r, w, obj_a, depth + 1, -1)
            ea[c] = e_r
            e_sum += e_r
            c += 1
        eta = n_a[0] / n_b[0]
        sin2_b = eta * eta * (1.0 - cos_a * cos_a)
        if sin2_b < 1.0:
            cos_b = wp.sqrt(1.0 - sin2_b)
            d_t = wp.normalize(d * eta + nrm * (eta * cos_a - cos_b))
            ratio = float(0.0)
            if f.n1_cos_i[0] > 0.0:
                ratio = wp.max(f.n2_cos_t[0], 0.0) / f.n1_cos_i[0]
            m_t = jones_scale(jones_mul(jones_diag(ts, tp), m_sp), wp.sqrt(ratio))
            e_t = ray_power(m_t, w, csrc)
            if e_t > 0.0:
                cand = _push(cand, c, x + d_t * fp.epsilon, d_t, d_t, s, m_t, w, obj_b, depth + 1, -1)
                ea[c] = e_t
                e_sum += e_t
                c += 1
    else:
        # a uniaxial side: generalized Fresnel amplitudes (eq. 5) per incident mode
        ma = _crystal(fp, mats, obj_a, wl)
        mb = _crystal(fp, mats, obj_b, wl)
        zero = wp.vec2f(0.0, 0.0)
        if mode < 0:
            # isotropic incident ray: its s/p (= o/e) components both excite every wave
            so = generalized_fresnel(s_in, 0, nrm, ma, mb)
            se = generalized_fresnel(s_in, 1, nrm, ma, mb)
            m_in = jones_mul(jones_real(frame_change(s_in, bx, so.incident.e_re)), m)
            f_in = so.incident.flux
            ctx = _wave_ctx(x, fp.epsilon, w, csrc, depth + 1, f_in)
            cand, ea, e_sum, c = _push_wave(
                cand, 0, c, ea, e_sum, ctx, so.ro, jones(so.r_o, se.r_o, so.r_e, se.r_e), m_in, obj_a, -1
            )
            cand, ea, e_sum, c = _push_wave(
                cand, 0, c, ea, e_sum, ctx, so.to, jones(so.t_o, se.t_o, zero, zero), m_in, obj_b, 0
            )
            cand, ea, e_sum, c = _push_wave(
                cand, 0, c, ea, e_sum, ctx, so.te, jones(so.t_e, se.t_e, zero, zero), m_in, obj_b, 1
            )
        else:
            # one eigenmode inside a crystal: row 0 of M is its amplitude
            sol = generalized_fresnel(s_in, mode, nrm, ma, mb)
            ctx = _wave_ctx(x, fp.epsilon, w, csrc, depth + 1, sol.incident.flux)
            cand, ea, e_sum, c = _push_wave(
                cand, 0, c, ea, e_sum, ctx, sol.ro, jones_diag(sol.r_o, zero), m, obj_a, 0
            )
            cand, ea, e_sum, c = _push_wave(
                cand, 0, c, ea, e_sum, ctx, sol.re, jones_diag(sol.r_e, zero), m, obj_a, 1
            )
            if _is_uniaxial(fp, mats, obj_b) == 0:
                # into an isotropic medium: the o/e amplitudes are its s/p components
                cand, ea, e_sum, c = _push_wave(
                    cand, 0, c, ea, e_sum, ctx, sol.to, jones(sol.t_o, zero, sol.t_e, zero), m, obj_b, -1
                )
            else:
                cand, ea, e_sum, c = _push_wave(
                    cand, 0, c, ea, e_sum, ctx, sol.to, jones_diag(sol.t_o, zero), m, obj_b, 0
                )
                cand, ea, e_sum, c = _push_wave(
                    cand, 0, c, ea, e_sum, ctx, sol.te, jones_diag(sol.t_e, zero), m, obj_b, 1
                )
    if e_sum > e:
        # a passive interface creates no power: with an absorbing incident medium the
        # plane-wave flux split is not unique and |r|^2 can exceed 1 near total reflection
        g = e / e_sum
        for j in range(c):
            cand[j, _W] = cand[j, _W] * g
            ea[j] = ea[j] * g
        e_sum = e
    return cand, ea, e_sum, c


@wp.func
def _keep_children(st: Any, n: int, cand: Cand, ea: wp.vec4f, e_sum: float, c: int, split_threshold: float,
                   rng: wp.uint32):
    """Continue the tree with the children of an interface: all of them while they carry at
    least ``split_threshold`` (and the stack has room), else one chosen by power with uniform
    from ``rng``, weighted by 1/probability (carries ``e_sum`` exactly).  Returns (st, n, rng)."""
    if e_sum >= split_threshold and n + c <= STACK_SIZE:
        for j in range(c):
            st = copy_row(st, n + j, cand, j)
        return st, n + c, rng
    x = wp.randf(rng) * e_sum
    j = int(0)
    acc = ea[0]
    while j < c - 1 and x >= acc:
        j += 1
        acc += ea[j]
    st = copy_row(st, n, cand, j)
    st[n, _W] = st[n, _W] * (e_sum / ea[j])
    return st, n + 1, rng


@wp.func
def forward_step(
    st: Any,
    n: int,
    rng: wp.uint32,
    fp: ForwardParams,
    mats: MaterialTable,
    coatings: CoatingStack,
    hit: RayHit,
    r: Ray,
    e: float,
    wl: float,
    csrc: Jones,
):
    """The forward ray ``r`` of power ``e`` that reached ``hit``: Bouguer–Lambert along its segment
    inside a solid, the cut at ``max_depth``, then the interface event (:func:`forward_interface`)
    and the split (:func:`_keep_children`).  Returns (st, n, rng, (absorbed, truncated,
    interface loss)) for the ledger."""
    e_abs = float(0.0)
    w = r.w
    if r.inside >= 0:
        att = wp.exp(-_segment_alpha(fp, mats, r.inside, r.mode, r.wn, wl) * hit.t)
        e_abs = e * (1.0 - att)
        w = w * att
        e = e * att
    if r.depth >= fp.max_depth:
        return st, n, rng, wp.vec3f(e_abs, e, 0.0)
    if e <= 0.0:
        return st, n, rng, wp.vec3f(e_abs, 0.0, 0.0)
    cand, ea, e_sum, c = forward_interface(fp, mats, coatings, hit, r, w, e, wl, csrc)
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
    st = _Stack()
    st = _push(st, 0, o0, d0, d0, bx0, jones_identity(), 1.0, -1, 0, -1)
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
        r = _read_row(st, n)
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
        st, n, rng, ledger_step = forward_step(st, n, rng, fp, mats, coatings, hit, r, e, wl, csrc)
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
    epsilon: float = 1.0e-4,
    device=None,
) -> ForwardParams:
    """The kernel struct of a forward trace; per-object arrays have one entry per object."""
    p = ForwardParams()
    p.max_depth = int(config.max_depth)
    p.split_threshold = float(config.split_threshold)
    p.t_max = float(t_max)
    p.epsilon = float(epsilon)
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
