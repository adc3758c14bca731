"""The trace stage: a camera (backward) path tree through dielectric solids to the lights.

One call of :func:`trace_radiance` follows everything that light arriving along one primary ray
can have come through.  At every interface the path splits into the reflected and the refracted
branch (total internal reflection leaves one).  While a branch still carries at least
``split_threshold`` of the primary ray's energy both children are followed *deterministically*
(an explicit stack): the per-pixel form of the pruned facet tree of Guy & Soler 2004 §5 (``max_splits`` bounds the
extra branches per primary ray: birefringent stones double their branches at every internal
reflection).  Below
the threshold one child is chosen at random with probability proportional to its energy and
weighted by 1/probability, and Russian roulette ends weak paths — so the estimate stays unbiased
while the bright, low-order paths that make a gem's picture carry no noise.

Polarization (``polarized=True``): a branch carries a 2x2 complex Jones matrix M that maps the
field of light on its segment (in the branch's own frame: basis vector ``x`` perpendicular to
the segment, ``y = k x x`` with ``k`` the direction the light travels) to the field arriving at
the camera (camera frame: image right, image up).  Going backward across an interface the
parent's matrix is extended on the right: ``M_child = M_parent B diag(r_s, r_p)`` (or with t),
where ``B`` turns the s/p frame of the outgoing wave into the parent's frame, and the child's
frame is the s/p frame of its incident wave (Guy & Soler 2004 eq. 12, accumulated from the eye).
Unpolarized light of radiance L entering the path arrives as the coherency matrix
``L/2 M M^dagger``.  With ``polarized=False`` the branch carries the unpolarized power
coefficients instead (a scalar renderer, for comparison with unpolarized peers).

Transmitted amplitudes are scaled by sqrt(Re(N_out cos t) / Re(N_in cos i)) so that |M|^2 is the
transmitted power; radiance's n^2 factors cancel on paths that start and end in the same
ambient medium.  Absorption follows Bouguer–Lambert, exp(-alpha l) on the intensity, with alpha
= 4 pi k / lambda from the material table (or the eq. 9 RGB absorbances in ``rgb3`` mode).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import warp as wp

from .. import validate as val
from ..geometry.query import RayHit, SceneGeometry, object_exit_hit, scene_closest_hit_leaving
from ..materials.dispersion import MaterialTable, material_optics
from ..optics.birefringence import (
    UniaxialMedium,
    extraordinary_wave,
    generalized_fresnel,
    interface_jones_approx,
    kappa_extraordinary,
    n_e_theta,
    oe_frame_x,
    ordinary_wave,
    uniaxial_medium,
)
from ..optics.complex import c_abs2, c_mul
from ..optics.fresnel import fresnel_amplitudes, refract_direction
from ..optics.jones import (
    Jones,
    coherency_transform,
    coherency_unpolarized,
    frame_change,
    jones,
    jones_add,
    jones_entry,
    jones_identity,
    jones_mul,
    jones_real,
    jones_scale,
    jones_zero,
    s_vector,
)
from ..optics.polarizer import sheet_polarizer_coherency
from ..spectra import SpectralTables
from .branches import (
    _B,
    _D,
    _DEPTH,
    _IN,
    _MI,
    _MODE,
    _MR,
    _O,
    _W,
    _WN,
    COLS,
    STACK_SIZE,
)
from .branches import (
    Cand as _Cand,
)
from .branches import (
    Stack as _Stack,
)
from .branches import branch_energy as _energy
from .branches import child_jones as _child_jones
from .branches import (
    write_jones as _write_jones,
)
from .branches import (
    write_row as _write_row,
)
from .coated import FilmSurfaces, empty_film_surfaces, film_children  # films: coated interfaces, shells
from .environment import Environment, environment_coefficients
from .surfaces import Surfaces, surface_radiance, surfaces_closest_hit

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["TraceParams", "TraceConfig", "trace_radiance", "default_params", "STACK_SIZE", "BIREFRINGENCE"]

BIREFRINGENCE = {"exact": 0, "approx": 1}
_APPROX = wp.constant(1)
# stack rows in the ambient medium that leave the surface of solid k store inside = _LEFT - k
_LEFT = wp.constant(-2)


@wp.struct
class TraceParams:
    """Per-render settings of the trace stage (values, not compile-time constants)."""

    max_depth: int  # interfaces per path (Mitsuba's max_depth - 1)
    split_threshold: float  # split deterministically while a branch carries >= this energy
    max_splits: int  # at most this many extra branches from deterministic splits per primary ray
    rr_threshold: float  # below this energy a branch survives Russian roulette with p = e / rr
    t_max: float  # mm
    epsilon: float  # origin offset along the new direction, mm
    ambient: wp.vec2f  # complex index of the medium around the objects (air: 1)
    rgb3: int  # 1: use the materials' eq. 9 RGB absorbances (channel = sample index)
    birefringence: int  # 0 exact (separate o/e directions), 1 approx (shared direction, eq. 10)
    object_material: wp.array(dtype=wp.int32)  # material id of each object
    object_absorption_scale: wp.array(dtype=wp.float32)  # multiplier of alpha per object
    object_axis: wp.array(dtype=wp.vec3f)  # optic axis in world space; zero: isotropic
    films: FilmSurfaces  # per-object coatings, thin shells, film surfaces (stages/coated.py)


@dataclass(frozen=True)
class TraceConfig:
    """Settings of the backward tracer (from a camera scene's ``[render]``)."""

    max_depth: int = 12
    split_threshold: float = 0.002
    max_splits: int = 64
    rr_threshold: float = 1.0e-4
    polarized: bool = True
    birefringence: str = "exact"

    def __post_init__(self) -> None:
        val.integer(self.max_depth, field="render.max_depth", lo=0, hi=256)
        val.number(self.split_threshold, field="render.split_threshold", lo=0.0, hi=1.0)
        val.integer(self.max_splits, field="render.max_splits", lo=0, hi=4096)
        val.number(self.rr_threshold, field="render.rr_threshold", lo=0.0, hi=1.0)
        val.boolean(self.polarized, field="render.polarization")
        val.choice(self.birefringence, tuple(BIREFRINGENCE), field="render.birefringence")


@wp.func
def _apply(m: Jones, vx: wp.vec2f, vy: wp.vec2f):
    # M (vx, vy)^T for complex vx, vy: the camera field of a field with these frame components
    a = c_mul(jones_entry(m, 0, 0), vx) + c_mul(jones_entry(m, 0, 1), vy)
    b = c_mul(jones_entry(m, 1, 0), vx) + c_mul(jones_entry(m, 1, 1), vy)
    return a, b


@wp.func
def _object_medium(p: TraceParams, mats: MaterialTable, obj: int, wavelength: float):
    """(UniaxialMedium with real indices and world optic axis (zero: isotropic), index n_o, and
    (alpha_o, alpha_e)) of object ``obj`` at ``wavelength``.  The tracer keeps the last one it
    evaluated: a path tree at one wavelength meets the same stone at every interface, so the
    material formulas (Sellmeier terms, tabulated n and k) run once per stone and tree.

    Interfaces use the real part of the index: a dielectric's k (< 1e-3 for any stone or dye
    solution one can see through) changes Fresnel coefficients by O(k^2), while with an
    absorbing *incident* medium the plane-wave reflectance is no longer bounded by 1 (the wave is
    inhomogeneous) and would break energy conservation near the critical angle.  k acts where it
    matters, as Bouguer–Lambert attenuation exp(-4 pi k l / lambda) along each segment."""
    no, ne, alpha = material_optics(mats, p.object_material[obj], wavelength)
    return uniaxial_medium(no[0], ne[0], p.object_axis[obj]), wp.vec2f(no[0], 0.0), alpha


@wp.func
def _is_uniaxial(med: UniaxialMedium):
    return wp.dot(med.axis, med.axis) > 0.0


@wp.func
def _segment_kappa(
    p: TraceParams, mats: MaterialTable, obj: int, med: UniaxialMedium, alpha: wp.vec2f, channel: int,
    mode: int, wn: wp.vec3f,
):
    """Intensity absorption coefficient (1/mm, base e) along a segment inside ``obj``: alpha of
    the material (``alpha`` = (alpha_o, alpha_e) at the wavelength), the o-wave's K^o, or the
    e-wave's kappa^e(theta) (Guy & Soler 2004 eq. 7)."""
    mid = p.object_material[obj]
    a_o = alpha[0]
    a_e = alpha[1]
    if p.rgb3 != 0:
        c = wp.clamp(channel, 0, 2)
        a_o = mats.rgb3_alpha_o[mid][c]
        a_e = mats.rgb3_alpha_e[mid][c]
    kappa = a_o
    if mode == 1:
        kappa = kappa_extraordinary(wp.dot(wn, med.axis), a_o, a_e, med.no, med.ne)
    return kappa * p.object_absorption_scale[obj]


@wp.func
def _scaled(c: wp.vec2f, s: float):
    return wp.vec2f(c[0] * s, c[1] * s)


@wp.func(inline=False)  # out of line: compile time (see trace_radiance)
def _exact_children(
    cand: _Cand,
    m: Jones,
    w: float,
    bx: wp.vec3f,
    w_a: wp.vec3f,
    mode_a: int,
    nrm: wp.vec3f,
    med_a: UniaxialMedium,
    med_b: UniaxialMedium,
    x: wp.vec3f,
    eps: float,
    in_a: int,
    in_b: int,
    depth: int,
):
    """Backward interface event with a uniaxial medium on either side (Guy & Soler 2004 eq. 5).

    The parent is the wave leaving the interface into medium A toward the camera: unit wave
    normal ``w_a`` (pointing into A), mode ``mode_a`` (-1: isotropic A, frame (bx, w_a x bx)).
    Every wave that can feed it arrives with the same tangential wave vector (phase matching):
    from A (reflection) and from B (transmission), in the o and e modes of a crystal or the two
    polarizations of an isotropic medium.  Each is solved forward with ``generalized_fresnel``;
    the coefficient to our outgoing wave, power-normalised by the normal Poynting fluxes, becomes
    the child's Jones column.  Crystal children are single-mode (o and e travel apart);
    an isotropic child carries both polarizations."""
    n_eff = med_a.no
    if mode_a == 1:
        n_eff = n_e_theta(wp.dot(w_a, med_a.axis), med_a.no, med_a.ne)
    k_out = w_a * n_eff
    kt = k_out - nrm * wp.dot(k_out, nrm)
    y_par = wp.cross(w_a, bx)
    energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
    count = int(0)
    for side in range(2):
        n_into = nrm
        med_x = med_a
        med_y = med_b
        inside = in_a
        if side == 1:
            n_into = -nrm
            med_x = med_b
            med_y = med_a
            inside = in_b
        iso_x = not _is_uniaxial(med_x)
        c0x = wp.vec2f(0.0, 0.0)
        c0y = wp.vec2f(0.0, 0.0)
        c1x = wp.vec2f(0.0, 0.0)
        c1y = wp.vec2f(0.0, 0.0)
        iso_basis = wp.vec3f(0.0, 0.0, 0.0)
        iso_dir = wp.vec3f(0.0, 0.0, 0.0)
        iso_any = int(0)
        for mode_in in range(2):
            # the incident wave is the time reverse of the outgoing wave into X with tangential -kt
            wv = ordinary_wave(-kt, n_into, med_x, n_into)
            if mode_in == 1 and not iso_x:
                wv = extraordinary_wave(-kt, n_into, med_x, n_into)
            if wv.propagating == 0:
                continue
            d_in = -wv.wave_normal
            sol = generalized_fresnel(d_in, mode_in, n_into, med_x, med_y)
            if sol.solved == 0 or sol.incident.flux <= 0.0:
                continue
            wo = sol.ro
            co = sol.r_o
            we = sol.re
            ce = sol.r_e
            if side == 1:
                wo = sol.to
                co = sol.t_o
                we = sol.te
                ce = sol.t_e
            inv = 1.0 / wp.sqrt(sol.incident.flux)
            fo = wp.vec2f(0.0, 0.0)
            fe = wp.vec2f(0.0, 0.0)
            if wo.propagating == 1:
                fo = _scaled(co, wp.sqrt(wp.max(wo.flux, 0.0)) * inv)
            if we.propagating == 1:
                fe = _scaled(ce, wp.sqrt(wp.max(we.flux, 0.0)) * inv)
            vx = wp.vec2f(0.0, 0.0)
            vy = wp.vec2f(0.0, 0.0)
            if mode_a < 0:
                # isotropic A: both outgoing polarizations travel along w_a; project E on the frame
                vx = _scaled(fo, wp.dot(wo.e_re, bx)) + _scaled(fe, wp.dot(we.e_re, bx))
                vy = _scaled(fo, wp.dot(wo.e_re, y_par)) + _scaled(fe, wp.dot(we.e_re, y_par))
            elif mode_a == 0:
                vx = fo
            else:
                vx = fe
            ax, ay = _apply(m, vx, vy)
            if iso_x:
                iso_any = 1
                if mode_in == 0:
                    c0x = ax
                    c0y = ay
                    iso_basis = sol.incident.e_re
                    iso_dir = -d_in
                else:
                    c1x = ax
                    c1y = ay
            else:
                mc = jones(ax, wp.vec2f(0.0, 0.0), ay, wp.vec2f(0.0, 0.0))
                e = _energy(mc, w)
                if e > 0.0:
                    dr = -sol.incident.ray
                    cand = _write_row(cand, count, x + dr * eps, dr, bx, mc, w, inside, depth + 1, mode_in, d_in)
                    energies[count] = e
                    count += 1
        if iso_any != 0:
            mc = jones(c0x, c1x, c0y, c1y)
            e = _energy(mc, w)
            if e > 0.0:
                cand = _write_row(cand, count, x + iso_dir * eps, iso_dir, iso_basis, mc, w, inside, depth + 1, -1,
                                  -iso_dir)
                energies[count] = e
                count += 1
    return cand, energies, count


@wp.func(inline=False)  # out of line: compile time (see trace_radiance)
def _approx_children(
    cand: _Cand,
    m: Jones,
    w: float,
    bx: wp.vec3f,
    w_a: wp.vec3f,
    mode_a: int,
    nrm: wp.vec3f,
    med_a: UniaxialMedium,
    med_b: UniaxialMedium,
    x: wp.vec3f,
    eps: float,
    in_a: int,
    in_b: int,
    depth: int,
):
    """Backward interface event in the approximate model of Guy & Soler 2004 §4.2: one direction
    per side (mirror and Snell with the mean index (no + ne)/2), Jones matrices of eq. 10 between
    o/e frames, and o and e kept incoherent (a diagonal coherency in the crystal: one child per
    mode, sharing the direction)."""
    n_a = 0.5 * (med_a.no + med_a.ne)
    n_b = 0.5 * (med_b.no + med_b.ne)
    energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
    count = int(0)
    cos_a = wp.abs(wp.dot(w_a, nrm))
    for side in range(2):
        n_into = nrm
        med_x = med_a
        med_y = med_b
        n_x = n_a
        n_y = n_b
        inside = in_a
        d_in = w_a - nrm * (2.0 * wp.dot(w_a, nrm))
        scale = float(1.0)
        if side == 1:
            n_into = -nrm
            med_x = med_b
            med_y = med_a
            n_x = n_b
            n_y = n_a
            inside = in_b
            back = refract_direction(-w_a, nrm, n_a, n_b)
            if wp.dot(back, back) == 0.0:
                continue  # total internal reflection: nothing comes from B
            d_in = -back
            cos_x = wp.abs(wp.dot(d_in, nrm))
            if cos_x <= 0.0:
                continue
            scale = wp.sqrt(n_a * cos_a / (n_b * cos_x))
        ij = interface_jones_approx(d_in, n_into, med_x, med_y, wp.vec2f(n_x, 0.0), wp.vec2f(n_y, 0.0))
        j = ij.mr
        if side == 1:
            j = ij.mt
        # rows: outgoing o/e of A along w_a; columns: incident o/e of X along d_in
        p = jones_scale(j, scale)
        if mode_a < 0:
            axis_a = med_a.axis
            if not _is_uniaxial(med_a):
                axis_a = n_into
            x_out = oe_frame_x(w_a, axis_a, n_into)
            p = jones_mul(jones_real(frame_change(w_a, x_out, bx)), p)
        else:
            # keep only the row of the parent's mode (the other mode is a different branch)
            r0 = jones_entry(p, mode_a, 0)
            r1 = jones_entry(p, mode_a, 1)
            p = jones(r0, r1, wp.vec2f(0.0, 0.0), wp.vec2f(0.0, 0.0))
        mc = jones_mul(m, p)
        dr = -d_in
        if not _is_uniaxial(med_x):
            axis_x = n_into
            bxc = oe_frame_x(d_in, axis_x, n_into)
            e = _energy(mc, w)
            if e > 0.0:
                cand = _write_row(cand, count, x + dr * eps, dr, bxc, mc, w, inside, depth + 1, -1, d_in)
                energies[count] = e
                count += 1
        else:
            for mode_in in range(2):
                a0 = jones_entry(mc, 0, mode_in)
                a1 = jones_entry(mc, 1, mode_in)
                mk = jones(a0, wp.vec2f(0.0, 0.0), a1, wp.vec2f(0.0, 0.0))
                e = _energy(mk, w)
                if e > 0.0:
                    cand = _write_row(cand, count, x + dr * eps, dr, bx, mk, w, inside, depth + 1, mode_in, d_in)
                    energies[count] = e
                    count += 1
    return cand, energies, count


@wp.func
def _isotropic_children(
    cand: _Cand,
    m: Jones,
    w: float,
    bx: wp.vec3f,
    d: wp.vec3f,
    n_out: wp.vec3f,
    nrm: wp.vec3f,
    n_a: wp.vec2f,
    n_b: wp.vec2f,
    x: wp.vec3f,
    eps: float,
    in_a: int,
    in_b: int,
    depth: int,
    polarized: int,
):
    """Backward interface event between isotropic media: Fresnel's laws (fresnel_amplitudes)."""
    cos_a = wp.clamp(-wp.dot(d, nrm), 0.0, 1.0)
    s = s_vector(d, n_out)
    k_out = -d  # light leaves the interface toward the camera along -d
    energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
    count = int(0)
    # refraction: light arriving from medium B, transmitted into A (unless TIR)
    eta = n_a[0] / n_b[0]
    sin2_b = eta * eta * (1.0 - cos_a * cos_a)
    if sin2_b < 1.0:
        cos_b = wp.sqrt(1.0 - sin2_b)
        d_t = wp.normalize(d * eta + nrm * (eta * cos_a - cos_b))
        f_t = fresnel_amplitudes(cos_b, n_b, n_a)
        ratio = float(0.0)
        if f_t.n1_cos_i[0] > 0.0:
            ratio = wp.max(f_t.n2_cos_t[0], 0.0) / f_t.n1_cos_i[0]
        m_t = m
        w_t = w
        if polarized != 0:
            m_t = _child_jones(m, k_out, bx, s, f_t.ts, f_t.tp, wp.sqrt(ratio))
        else:
            w_t = w * 0.5 * ratio * (c_abs2(f_t.ts) + c_abs2(f_t.tp))
        e_t = _energy(m_t, w_t)
        if e_t > 0.0:
            cand = _write_row(cand, count, x + d_t * eps, d_t, s, m_t, w_t, in_b, depth + 1, -1, -d_t)
            energies[count] = e_t
            count += 1
    # reflection: light arriving from medium A, reflected back into A
    d_r = wp.normalize(d + nrm * (2.0 * cos_a))
    f_r = fresnel_amplitudes(cos_a, n_a, n_b)
    m_r = m
    w_r = w
    if polarized != 0:
        m_r = _child_jones(m, k_out, bx, s, f_r.rs, f_r.rp, 1.0)
    else:
        w_r = w * 0.5 * (c_abs2(f_r.rs) + c_abs2(f_r.rp))
    e_r = _energy(m_r, w_r)
    if e_r > 0.0:
        cand = _write_row(cand, count, x + d_r * eps, d_r, s, m_r, w_r, in_a, depth + 1, -1, -d_r)
        energies[count] = e_r
        count += 1
    return cand, energies, count


@wp.func
def _add_light(acc_x: Jones, acc_y: Jones, acc_z: Jones, k_unit: Jones, xyz: wp.vec3f):
    """Add light of colour ``xyz`` arriving with coherency ``k_unit`` per unit radiance."""
    return (jones_add(acc_x, jones_scale(k_unit, xyz[0])), jones_add(acc_y, jones_scale(k_unit, xyz[1])),
            jones_add(acc_z, jones_scale(k_unit, xyz[2])))


# Out of line, like the rarely taken branches (_exact_children, _approx_children, film_children,
# surface_radiance): with every function inlined into the pixel kernel, NVRTC needed 515 s to
# build the render module for sm_90 (and > 9 min with the adjoint code Warp generated until the
# modules set enable_backward=False); out of line, 244 s.  CPU speed: no measurable change.
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
    ``wavelength`` and ``weight`` are still the sample's for the materials and the surfaces hook."""
    st = _Stack()
    st = _write_row(st, 0, origin, direction, basis_x, jones_identity(), 1.0, -1, 0, -1, -direction)
    n = int(1)
    cand = _Cand()
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
    while n > 0:
        n -= 1
        # read the row inline (a wp.func argument is a by-value copy of the whole stack)
        o = wp.vec3f(st[n, _O], st[n, _O + 1], st[n, _O + 2])
        d = wp.vec3f(st[n, _D], st[n, _D + 1], st[n, _D + 2])
        bx = wp.vec3f(st[n, _B], st[n, _B + 1], st[n, _B + 2])
        wn = wp.vec3f(st[n, _WN], st[n, _WN + 1], st[n, _WN + 2])
        m = Jones()
        m.re = wp.mat22(st[n, _MR], st[n, _MR + 1], st[n, _MR + 2], st[n, _MR + 3])
        m.im = wp.mat22(st[n, _MI], st[n, _MI + 1], st[n, _MI + 2], st[n, _MI + 3])
        w = st[n, _W]
        inside = int(st[n, _IN])
        left = int(-1)
        if inside <= _LEFT:
            # a ray in the ambient medium leaving the surface of solid `left` (see the children below)
            left = _LEFT - inside
            inside = -1
        depth = int(st[n, _DEPTH])
        mode = int(st[n, _MODE])
        rays += 1
        hit = RayHit()
        if inside >= 0:
            hit = object_exit_hit(geom, inside, o, d, p.t_max)  # solids do not overlap
        else:
            hit = scene_closest_hit_leaving(geom, o, d, p.t_max, left)
            # surfaces hook (stages/surfaces.py): an opaque surface or a lamp in front of every
            # solid ends the branch with its (unpolarized) radiance, like the environment below
            if surf.num_surfaces + surf.num_area > 0:
                sh = surfaces_closest_hit(surf, o, d, hit.t)
                if sh.kind != 0:
                    ch3 = int(-1)  # rgb3 mode: the channel's eq. 9 absorbances in shadow rays too
                    if p.rgb3 != 0:
                        ch3 = wp.clamp(channel, 0, 2)
                    radiance, rng = surface_radiance(surf, geom, mats, env, tables, p.object_material,
                                                     p.object_absorption_scale, p.ambient[0], o, d, sh,
                                                     wavelength, ch3, rng)
                    # one wavelength per path here: surfaces turn the shared-spectrum path off
                    xyz_s = weight * radiance
                    if polarized != 0:
                        k_unit = coherency_transform(m, coherency_unpolarized(w))
                        acc_x, acc_y, acc_z = _add_light(acc_x, acc_y, acc_z, k_unit, xyz_s)
                    else:
                        scalar_xyz += xyz_s * w
                    continue
        if hit.object < 0:
            if inside < 0:
                xyz = response * environment_coefficients(env, d)
                if polarized != 0:
                    # polarized illumination hook (polariscope): the light behind env.polarizer
                    # (zero axis: unpolarized, coherency_unpolarized); frame (bx, k x bx), k = -d
                    k_unit = coherency_transform(m, sheet_polarizer_coherency(env.polarizer, -d, bx, w))
                    acc_x, acc_y, acc_z = _add_light(acc_x, acc_y, acc_z, k_unit, xyz)
                else:
                    scalar_xyz += xyz * w
            # a segment inside a solid that finds no exit leaked through a crack: dropped
            continue
        if depth == 0:
            hit_any = 1
        if inside >= 0 and inside != c_obj:
            c_med, c_n, c_alpha = _object_medium(p, mats, inside, wavelength)
            c_obj = inside
        med_a = ambient_med
        n_a = ambient_n
        if inside >= 0:
            med_a = c_med
            n_a = c_n
            kappa = _segment_kappa(p, mats, inside, med_a, c_alpha, channel, mode, wn)
            w = w * wp.exp(-kappa * hit.t)
        if depth >= p.max_depth or w <= 0.0:
            continue
        x = o + d * hit.t
        n_out = hit.normal
        entering = wp.dot(d, n_out) < 0.0
        nrm = n_out  # unit normal on the side the backward ray arrives from (medium A)
        obj_b = hit.object
        if not entering:
            nrm = -n_out
            obj_b = -1
        med_b = ambient_med
        n_b = ambient_n
        if obj_b >= 0:
            if obj_b != c_obj:
                c_med, c_n, c_alpha = _object_medium(p, mats, obj_b, wavelength)
                c_obj = obj_b
            med_b = c_med
            n_b = c_n
        count = int(0)
        energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
        if _is_uniaxial(med_a) or _is_uniaxial(med_b):
            if p.birefringence == _APPROX:
                cand, energies, count = _approx_children(
                    cand, m, w, bx, wn, mode, nrm, med_a, med_b, x, p.epsilon, inside, obj_b, depth
                )
            else:
                cand, energies, count = _exact_children(
                    cand, m, w, bx, wn, mode, nrm, med_a, med_b, x, p.epsilon, inside, obj_b, depth
                )
            if polarized == 0:
                # scalar mode: keep only the power of each child (no polarization memory)
                for k in range(count):
                    cand[k, _W] = energies[k]
                    unit = Jones()
                    if int(cand[k, _MODE]) < 0:
                        unit = jones_identity()
                    else:
                        unit = jones_real(wp.mat22(wp.sqrt(2.0), 0.0, 0.0, 0.0))
                    cand = _write_jones(cand, k, unit)
        elif p.films.kind[hit.object] != 0:
            # films hook: coated interface, thin shell or film surface (stages/coated.py)
            obj_f = hit.object
            cand, energies, count, rng = film_children(
                cand, p.films, mats, p.object_material[obj_f], obj_f, m, w, bx, d, n_out, n_a, n_b, x,
                geom.world_to_object[obj_f], p.epsilon, inside, obj_b, depth, polarized, wavelength, rng
            )
        else:
            cand, energies, count = _isotropic_children(
                cand, m, w, bx, d, n_out, nrm, n_a, n_b, x, p.epsilon, inside, obj_b, depth, polarized
            )
        if p.films.kind[hit.object] == 0:
            # the children in the ambient medium leave the solid's surface (reflected off it from
            # outside, or transmitted out): remember which, so their query can skip it if convex
            # (geometry/query.py scene_closest_hit_leaving).  Not for films: a shell has air inside.
            for k in range(count):
                if cand[k, _IN] == -1.0:
                    cand[k, _IN] = float(_LEFT - hit.object)
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
            u = wp.randf(rng) * e_parent
            pick = int(count - 1)
            acc_e = float(0.0)
            for k in range(count):
                acc_e += energies[k]
                if u < acc_e and pick == count - 1 and k < count - 1:
                    pick = k
            scale = e_parent / energies[pick]
            # Russian roulette on weak paths (the energy after the choice is e_parent)
            if e_parent < p.rr_threshold:
                q = e_parent / p.rr_threshold
                if wp.randf(rng) >= q:
                    continue
                scale = scale / q
            for c in range(COLS):
                st[n, c] = cand[pick, c]
            st[n, _W] = st[n, _W] * scale
            n += 1
    if polarized == 0:
        acc_x = coherency_unpolarized(scalar_xyz[0])
        acc_y = coherency_unpolarized(scalar_xyz[1])
        acc_z = coherency_unpolarized(scalar_xyz[2])
    return acc_x, acc_y, acc_z, hit_any, rays, rng


def default_params(objects_material: np.ndarray, absorption_scale: np.ndarray, object_axis: np.ndarray, *,
                   config: TraceConfig, ambient=(1.0, 0.0), t_max: float = 1.0e6, epsilon: float = 1.0e-4,
                   rgb3: bool = False, device=None, films: FilmSurfaces | None = None) -> TraceParams:
    """TraceParams for objects with material ids, alpha multipliers and world optic axes (zero
    rows for isotropic objects)."""
    p = TraceParams()
    p.max_depth = int(config.max_depth)
    p.split_threshold = float(config.split_threshold)
    p.max_splits = int(config.max_splits)
    p.rr_threshold = float(config.rr_threshold)
    p.t_max = float(t_max)
    p.epsilon = float(epsilon)
    p.ambient = wp.vec2f(*ambient)
    p.rgb3 = int(rgb3)
    p.birefringence = BIREFRINGENCE[config.birefringence]
    p.object_axis = wp.array(np.asarray(object_axis, dtype=np.float32).reshape(-1, 3), dtype=wp.vec3f, device=device)
    p.object_material = wp.array(np.asarray(objects_material, dtype=np.int32), dtype=wp.int32, device=device)
    p.object_absorption_scale = wp.array(np.asarray(absorption_scale, dtype=np.float32), dtype=wp.float32,
                                         device=device)
    p.films = films if films is not None else empty_film_surfaces(len(p.object_material), device=device)
    return p
