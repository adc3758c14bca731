"""The interface event: what light does at a boundary between two media, for every tracer.

This module is the one place where a ray meets an interface.  The camera trace
(``stages/trace.py``, backward from the eye), the optical bench (``stages/forward.py``) and the
caustic light tracer (``stages/caustics.py``), forward from a light, and the coated solids of
``stages/coated.py`` all call these ``@wp.func`` functions; each event writes its children (reflected and
refracted waves; o and e in a crystal) as rows of a candidate matrix (``optics/branches.py``) and
returns their energies, and the tracer keeps them all or picks one.

The laws it composes, each in its own place:

- Fresnel amplitudes, the refracted direction and the transmitted flux ratio, the last two
  derived from the Fresnel solution (``fresnel.fresnel_amplitudes``, ``refract_from_fresnel``,
  ``transmitted_flux_ratio``, as Mitsuba 3's ``refract`` reuses ``fresnel()``'s cos_theta_t);
- a thin-film stack instead of the bare interface: :func:`interface_amplitudes`
  (``thinfilm.coating_amplitudes_scaled``);
- crystals: ``biaxial.crystal_fresnel`` (Guy & Soler 2004 eq. 5, exact mode: the uniaxial
  solve, or the biaxial solver when a side is biaxial), or
  ``birefringence.interface_jones_approx`` (eq. 10, approx mode, uniaxial only);
- power normalisation of amplitudes: ``fresnel.flux_ratio`` with the waves' normal fluxes;
- the Jones algebra of a child: ``branches.child_jones_sp`` (backward, eq. 12 accumulated from the
  eye) or ``jones_mul`` on the left (forward).

Conventions.  ``nrm`` is the unit normal on the side the ray arrives from (medium A); B is the
other side.  Children go to A (reflection) or B (refraction) and carry the object index they run
in (``in_a``/``in_b``, -1 the ambient medium), depth + 1 and their mode (-1 isotropic, 0 o,
1 e).  Backward events take the parent's Jones matrix ``m`` (field on the parent's segment ->
camera) and extend it on the right; forward events take the source-to-ray matrix and extend it on
the left.  Both normalise amplitudes by the square root of the normal flux ratio so that ``|M|^2``
is power, and both handle total internal reflection (no refracted child; |r| = 1 with its phase).

Adding a medium (how biaxial crystals were added, and what the tracers call):
docs/design/interface_event.md.

References: Born & Wolf, Principles of Optics, 7th ed., §1.5-1.6; Guy & Soler 2004, "Graphics
Gems Revisited", eq. 2-5, 10, 12; Beyerle & McDermid 1998, Appl. Opt. 37(34); Mitsuba 3,
``include/mitsuba/render/fresnel.h`` (``refract``).
"""

from __future__ import annotations

import warp as wp

from .biaxial import (
    EventWaves,
    crystal_fresnel,
    crystal_fresnel_both,
    event_fresnel,
    event_waves,
    is_biaxial,
    medium_waves,
    wave_index,
)
from .birefringence import (
    InterfaceSolution,
    PlaneWave,
    UniaxialMedium,
    extraordinary_wave,
    interface_jones_approx,
    oe_frame_x,
    ordinary_wave,
)
from .branches import ROW_MODE, ROW_W, Cand, add_child, child_jones_sp, parent_in_sp, write_jones, write_row
from .complex import c_mul
from .fresnel import (
    FresnelAmplitudes,
    flux_ratio,
    fresnel_amplitudes,
    fresnel_reverse,
    refract_from_fresnel,
    refracted_cos,
    transmitted_flux_ratio,
    unpolarized_power,
)
from .jones import (
    Jones,
    coherency_transform,
    frame_change,
    jones,
    jones_diag,
    jones_entry,
    jones_identity,
    jones_mul,
    jones_real,
    jones_scale,
    jones_zero,
    s_vector,
)
from .thinfilm import CoatingStack, coating_amplitudes_scaled

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "is_uniaxial",
    "interface_amplitudes",
    "child_of",
    "backward_isotropic",
    "backward_coated",
    "backward_crystal_exact",
    "backward_uniaxial_approx",
    "event_tangential",
    "backward_child_rays",
    "backward_crystal",
    "ray_power",
    "forward_event",
]


@wp.func
def is_uniaxial(med: UniaxialMedium):
    """A medium with an optic axis (the zero axis marks an isotropic medium)."""
    return wp.dot(med.axis, med.axis) > 0.0


@wp.func
def interface_amplitudes(
    f: FresnelAmplitudes,
    stack: CoatingStack,
    coat: int,
    wavelength: float,
    cos_i: float,
    n_front: wp.vec2f,
    n_back: wp.vec2f,
    from_back: int,
    scale: float,
):
    """(rs, rp, ts, tp) of the interface: the bare Fresnel amplitudes ``f`` (``coat`` < 0) or
    those of coating ``coat`` of ``stack`` (layers scaled by ``scale``) seen from its front or
    back.  A film conserves the tangential wave vector, so directions and flux ratios are those
    of the bare interface."""
    if coat < 0:
        return f.rs, f.rp, f.ts, f.tp
    return coating_amplitudes_scaled(stack, coat, wavelength, cos_i, n_front, n_back, from_back, scale)


@wp.func
def event_parent(m: Jones, k_out: wp.vec3f, parent_x: wp.vec3f, s: wp.vec3f, polarized: int):
    """What the children of a backward event share: M_parent B (``branches.parent_in_sp``) when
    polarized; the scalar renderer carries ``m`` unchanged."""
    if polarized != 0:
        return parent_in_sp(m, k_out, parent_x, s)
    return m


@wp.func
def child_of(mb: Jones, w: float, a_s: wp.vec2f, a_p: wp.vec2f, power_scale: float, polarized: int):
    """(M_child, w_child) of a backward child with s/p amplitudes (a_s, a_p), ``mb`` =
    :func:`event_parent`: polarized, M_parent B diag(a_s, a_p) sqrt(power_scale)
    (``child_jones_sp``); scalar, ``mb`` (the parent's matrix, unchanged) and the weight times the
    unpolarized power coefficient ``unpolarized_power(a_s, a_p) power_scale``."""
    if polarized != 0:
        return child_jones_sp(mb, a_s, a_p, wp.sqrt(wp.max(power_scale, 0.0))), w
    return mb, w * unpolarized_power(a_s, a_p) * power_scale


# ---------------------------------------------------------------------------------------------
# Backward (camera) events: the parent is the wave leaving the interface toward the camera
# ---------------------------------------------------------------------------------------------


@wp.func
def _isotropic_fresnel(d: wp.vec3f, nrm: wp.vec3f, n_a: wp.vec2f, n_b: wp.vec2f):
    """The geometry and bare amplitudes of a backward isotropic event: (cos_a, Fresnel A -> B,
    refracted direction into B — zero under total internal reflection —, cos_b, Fresnel B -> A).
    The direction comes from the A -> B solution (``refract_from_fresnel``); the amplitudes of
    light from B are those of B -> A (``fresnel_reverse``: ``fresnel_amplitudes(cos_b, n_b, n_a)``,
    between lossless media the A -> B solution swapped)."""
    cos_a = wp.clamp(-wp.dot(d, nrm), 0.0, 1.0)
    f_r = fresnel_amplitudes(cos_a, n_a, n_b)
    d_t = refract_from_fresnel(d, nrm, f_r, n_a, n_b)
    cos_b = float(0.0)
    f_t = FresnelAmplitudes()
    if wp.dot(d_t, d_t) > 0.0:
        cos_b = refracted_cos(f_r, n_b)
        f_t = fresnel_reverse(f_r, cos_b, n_a, n_b)
    return cos_a, f_r, d_t, cos_b, f_t


@wp.func
def _isotropic_children(
    cand: Cand,
    m: Jones,
    w: float,
    bx: wp.vec3f,
    d: wp.vec3f,
    n_out: wp.vec3f,
    nrm: wp.vec3f,
    x: wp.vec3f,
    eps: float,
    in_a: int,
    in_b: int,
    depth: int,
    polarized: int,
    cos_a: float,
    d_t: wp.vec3f,
    t_flux: float,
    ts: wp.vec2f,
    tp: wp.vec2f,
    rs: wp.vec2f,
    rp: wp.vec2f,
):
    """The refracted (from B, unless ``d_t`` is zero) and reflected (in A) children of a backward
    isotropic event with the given amplitudes and transmitted flux ratio: (cand, energies, count)."""
    s = s_vector(d, n_out)
    k_out = -d  # light leaves the interface toward the camera along -d
    energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
    count = int(0)
    # the refracted child is added in every case (without energy under total internal
    # reflection): a conditional add_child would select between two copies of ``cand``
    m_t = jones_zero()
    w_t = float(0.0)
    mb = event_parent(m, k_out, bx, s, polarized)
    if wp.dot(d_t, d_t) > 0.0:
        m_t, w_t = child_of(mb, w, ts, tp, t_flux, polarized)
    cand, energies, count = add_child(
        cand, energies, count, x + d_t * eps, d_t, s, m_t, w_t, in_b, depth + 1, -1, -d_t
    )
    d_r = wp.normalize(d + nrm * (2.0 * cos_a))
    m_r, w_r = child_of(mb, w, rs, rp, 1.0, polarized)
    cand, energies, count = add_child(
        cand, energies, count, x + d_r * eps, d_r, s, m_r, w_r, in_a, depth + 1, -1, -d_r
    )
    return cand, energies, count


@wp.func
def backward_isotropic(
    cand: Cand,
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
    """Backward event at a bare interface between isotropic media: (cand, energies, count).

    The backward ray ``d`` arrives from A.  Light reaching the camera along -d came reflected in A
    (Fresnel ``fresnel_amplitudes(cos_a, n_a, n_b)``) or refracted from B (unless total internal
    reflection: ``refract_from_fresnel`` of the same solution gives its direction, and its
    amplitudes are those of B -> A, power-normalised by ``transmitted_flux_ratio``)."""
    cos_a, f_r, d_t, cos_b, f_t = _isotropic_fresnel(d, nrm, n_a, n_b)
    return _isotropic_children(
        cand,
        m,
        w,
        bx,
        d,
        n_out,
        nrm,
        x,
        eps,
        in_a,
        in_b,
        depth,
        polarized,
        cos_a,
        d_t,
        transmitted_flux_ratio(f_t),
        f_t.ts,
        f_t.tp,
        f_r.rs,
        f_r.rp,
    )


@wp.func
def backward_coated(
    cand: Cand,
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
    stack: CoatingStack,
    coat: int,
    wavelength: float,
    scale: float,
    a_is_front: int,
):
    """:func:`backward_isotropic` at a coated interface: the stack ``coat`` of ``stack`` (layers
    scaled by ``scale``) replaces the bare amplitudes (``interface_amplitudes``); ``a_is_front``
    says whether A faces the stack's front (the ambient side).  A film conserves the tangential
    wave vector, so directions and flux ratios are the bare interface's.  A separate function so
    that the bare event, the hot path, does not carry the stack."""
    n_front = n_a
    n_back = n_b
    if a_is_front == 0:
        n_front = n_b
        n_back = n_a
    cos_a, f_r, d_t, cos_b, f_t = _isotropic_fresnel(d, nrm, n_a, n_b)
    rs, rp, u_s, u_p = interface_amplitudes(
        f_r, stack, coat, wavelength, cos_a, n_front, n_back, 1 - a_is_front, scale
    )
    t_r, t_p2, ts, tp = interface_amplitudes(
        f_t, stack, coat, wavelength, cos_b, n_front, n_back, a_is_front, scale
    )
    return _isotropic_children(
        cand,
        m,
        w,
        bx,
        d,
        n_out,
        nrm,
        x,
        eps,
        in_a,
        in_b,
        depth,
        polarized,
        cos_a,
        d_t,
        transmitted_flux_ratio(f_t),
        ts,
        tp,
        rs,
        rp,
    )


@wp.func
def _apply(m: Jones, vx: wp.vec2f, vy: wp.vec2f):
    # M (vx, vy)^T for complex vx, vy: the camera field of a field with these frame components
    a = c_mul(jones_entry(m, 0, 0), vx) + c_mul(jones_entry(m, 0, 1), vy)
    b = c_mul(jones_entry(m, 1, 0), vx) + c_mul(jones_entry(m, 1, 1), vy)
    return a, b


@wp.func
def _scaled(c: wp.vec2f, s: float):
    return wp.vec2f(c[0] * s, c[1] * s)


@wp.func
def event_tangential(w_a: wp.vec3f, mode_a: int, nrm: wp.vec3f, med_a: UniaxialMedium):
    """The tangential wave vector (/ k0) that every wave of a backward event shares (phase
    matching): that of the parent leaving into A with unit wave normal ``w_a`` and mode
    ``mode_a`` (``nrm`` the unit normal on A's side)."""
    k_out = w_a * wave_index(med_a, mode_a, w_a)
    return k_out - nrm * wp.dot(k_out, nrm)


@wp.func
def backward_child_rays(kt: wp.vec3f, nrm: wp.vec3f, med_a: UniaxialMedium, med_b: UniaxialMedium):
    """The directions of the children of an exact backward crystal event
    (:func:`backward_crystal_exact`) of tangential wave vector ``kt`` (:func:`event_tangential`),
    without their amplitudes: each child runs backward along the ray of the wave leaving the
    interface into its side with tangential -kt (the time reverse of the wave it feeds the
    parent with).  (A mode 0, A mode 1, B mode 0, B mode 1); an isotropic side's one child is
    its mode 0; a wave that does not propagate gives the zero vector.  Pixel beams move each
    vertex ray of a part by these (``stages/pixel_beam.py``)."""
    out = wp.mat44f()
    for side in range(2):
        n_into = nrm
        med_x = med_a
        if side == 1:
            n_into = -nrm
            med_x = med_b
        w0, w1 = medium_waves(-kt, n_into, med_x, n_into)
        if w0.propagating != 0:
            for c in range(3):
                out[2 * side, c] = w0.ray[c]
        if w1.propagating != 0:
            for c in range(3):
                out[2 * side + 1, c] = w1.ray[c]
    return out


@wp.func(inline=False)  # out of line: compile time (see stages/trace.py trace_radiance)
def backward_crystal_exact(
    cand: Cand,
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
    """Backward interface event with a crystal (uniaxial or biaxial) on either side (Guy & Soler
    2004 eq. 5).

    The parent is the wave leaving the interface into medium A toward the camera: unit wave
    normal ``w_a`` (pointing into A), mode ``mode_a`` (-1: isotropic A, frame (bx, w_a x bx)).
    Every wave that can feed it arrives with the same tangential wave vector (phase matching):
    from A (reflection) and from B (transmission), in the o and e modes of a crystal or the two
    polarizations of an isotropic medium (fast and slow in a biaxial one).  Each is solved forward
    with ``crystal_fresnel``;
    the coefficient to our outgoing wave, power-normalised by the normal Poynting fluxes, becomes
    the child's Jones column.  Crystal children are single-mode (o and e travel apart);
    an isotropic child carries both polarizations."""
    kt = event_tangential(w_a, mode_a, nrm, med_a)
    y_par = wp.cross(w_a, bx)
    energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
    count = int(0)
    # a biaxial side: its four waves of this tangential wave vector from one quartic, shared by
    # the four solves below (incident and reflected on one side are transmitted of the other)
    bi_any = is_biaxial(med_a) or is_biaxial(med_b)
    ev = EventWaves()
    if bi_any:
        ev = event_waves(w_a, mode_a, nrm, med_a, med_b)
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
        iso_x = not is_uniaxial(med_x)
        c0x = wp.vec2f(0.0, 0.0)
        c0y = wp.vec2f(0.0, 0.0)
        c1x = wp.vec2f(0.0, 0.0)
        c1y = wp.vec2f(0.0, 0.0)
        iso_basis = wp.vec3f(0.0, 0.0, 0.0)
        iso_dir = wp.vec3f(0.0, 0.0, 0.0)
        iso_any = int(0)
        for mode_in in range(2):
            # the incident wave is the time reverse of the outgoing wave into X with tangential -kt
            sol = InterfaceSolution()
            if bi_any:
                sol = event_fresnel(ev, side, mode_in, nrm, med_a, med_b)
            else:
                wv = ordinary_wave(-kt, n_into, med_x, n_into)
                if mode_in == 1 and not iso_x:
                    wv = extraordinary_wave(-kt, n_into, med_x, n_into)
                if wv.propagating == 0:
                    continue
                sol = crystal_fresnel(-wv.wave_normal, mode_in, n_into, med_x, med_y)
            if sol.solved == 0 or sol.incident.flux <= 0.0:
                continue
            d_in = sol.incident.wave_normal
            wo = sol.ro
            co = sol.r_o
            we = sol.re
            ce = sol.r_e
            if side == 1:
                wo = sol.to
                co = sol.t_o
                we = sol.te
                ce = sol.t_e
            fo = wp.vec2f(0.0, 0.0)
            fe = wp.vec2f(0.0, 0.0)
            if wo.propagating == 1:
                fo = _scaled(co, wp.sqrt(flux_ratio(sol.incident.flux, wo.flux)))
            if we.propagating == 1:
                fe = _scaled(ce, wp.sqrt(flux_ratio(sol.incident.flux, we.flux)))
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
                dr = -sol.incident.ray
                cand, energies, count = add_child(
                    cand, energies, count, x + dr * eps, dr, bx, mc, w, inside, depth + 1, mode_in, d_in
                )
        if iso_any != 0:
            mc = jones(c0x, c1x, c0y, c1y)
            cand, energies, count = add_child(
                cand,
                energies,
                count,
                x + iso_dir * eps,
                iso_dir,
                iso_basis,
                mc,
                w,
                inside,
                depth + 1,
                -1,
                -iso_dir,
            )
    return cand, energies, count


@wp.func(inline=False)  # out of line: compile time (see stages/trace.py trace_radiance)
def backward_uniaxial_approx(
    cand: Cand,
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
    n_a = wp.vec2f(0.5 * (med_a.no + med_a.ne), 0.0)
    n_b = wp.vec2f(0.5 * (med_b.no + med_b.ne), 0.0)
    energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
    count = int(0)
    cos_a = wp.abs(wp.dot(w_a, nrm))
    f_ab = fresnel_amplitudes(cos_a, n_a, n_b)
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
            back = refract_from_fresnel(-w_a, nrm, f_ab, n_a, n_b)
            if wp.dot(back, back) == 0.0:
                continue  # total internal reflection: nothing comes from B
            d_in = -back
            # power normalisation of light from B into A: the flux ratio of that wave pair, the
            # inverse of the A -> B one
            scale = wp.sqrt(flux_ratio(f_ab.n2_cos_t[0], f_ab.n1_cos_i[0]))
        ij = interface_jones_approx(d_in, n_into, med_x, med_y, n_x, n_y)
        j = ij.mr
        if side == 1:
            j = ij.mt
        # rows: outgoing o/e of A along w_a; columns: incident o/e of X along d_in
        p = jones_scale(j, scale)
        if mode_a < 0:
            axis_a = med_a.axis
            if not is_uniaxial(med_a):
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
        if not is_uniaxial(med_x):
            axis_x = n_into
            bxc = oe_frame_x(d_in, axis_x, n_into)
            cand, energies, count = add_child(
                cand, energies, count, x + dr * eps, dr, bxc, mc, w, inside, depth + 1, -1, d_in
            )
        else:
            for mode_in in range(2):
                a0 = jones_entry(mc, 0, mode_in)
                a1 = jones_entry(mc, 1, mode_in)
                mk = jones(a0, wp.vec2f(0.0, 0.0), a1, wp.vec2f(0.0, 0.0))
                cand, energies, count = add_child(
                    cand, energies, count, x + dr * eps, dr, bx, mk, w, inside, depth + 1, mode_in, d_in
                )
    return cand, energies, count


@wp.func
def backward_crystal(
    cand: Cand,
    m: Jones,
    w: float,
    bx: wp.vec3f,
    d: wp.vec3f,
    wn: wp.vec3f,
    mode: int,
    n_out: wp.vec3f,
    nrm: wp.vec3f,
    med_a: UniaxialMedium,
    med_b: UniaxialMedium,
    n_a: wp.vec2f,
    n_b: wp.vec2f,
    x: wp.vec3f,
    eps: float,
    in_a: int,
    in_b: int,
    depth: int,
    polarized: int,
    approx: int,
):
    """The backward interface event with a crystal on either side: exact (eq. 5 with the media's
    own wave solvers, uniaxial or biaxial) or, with ``approx`` and no biaxial side, eq. 10.
    (cand, energies, count).  Isotropic interfaces are :func:`backward_isotropic` (bare) and
    :func:`backward_coated`; the camera trace chooses among the three by the media.

    In scalar mode (``polarized`` = 0) a crystal's children keep only their power (a unit Jones
    matrix per child: no polarization memory), as the isotropic event does."""
    count = int(0)
    energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
    if approx != 0 and not is_biaxial(med_a) and not is_biaxial(med_b):
        cand, energies, count = backward_uniaxial_approx(
            cand, m, w, bx, wn, mode, nrm, med_a, med_b, x, eps, in_a, in_b, depth
        )
    else:
        cand, energies, count = backward_crystal_exact(
            cand, m, w, bx, wn, mode, nrm, med_a, med_b, x, eps, in_a, in_b, depth
        )
    if polarized == 0:
        for k in range(count):
            cand[k, ROW_W] = energies[k]
            unit = Jones()
            if int(cand[k, ROW_MODE]) < 0:
                unit = jones_identity()
            else:
                unit = jones_real(wp.mat22(wp.sqrt(2.0), 0.0, 0.0, 0.0))
            cand = write_jones(cand, k, unit)
    return cand, energies, count


# ---------------------------------------------------------------------------------------------
# Forward (light) events: the parent is the wave arriving at the interface from the source
# ---------------------------------------------------------------------------------------------


@wp.func
def ray_power(m: Jones, w: float, source: Jones):
    """Relative power w tr(M C M^dagger) of a forward ray (C: source coherency, trace 1)."""
    j = coherency_transform(m, source)
    return w * (j.re[0, 0] + j.re[1, 1])


@wp.struct
class _WaveCtx:
    """What every outgoing wave of one forward event shares."""

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
    cand: Cand,
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
    """Candidate row c for an outgoing wave of the generalized Fresnel solution: Jones
    ``coef m`` power-normalised by the fluxes, travelling along the wave's ray; skipped when the
    wave is evanescent or carries no power.  Returns (cand, ea, e_sum, c)."""
    if wave.propagating == 1:
        mk = jones_scale(jones_mul(coef, m), wp.sqrt(flux_ratio(ctx.flux_in, wave.flux)))
        ek = ray_power(mk, ctx.w, ctx.source)
        if ek > 0.0:
            cand = write_row(
                cand,
                c,
                ctx.x + wave.ray * ctx.eps,
                wave.ray,
                wave.e_re,
                mk,
                ctx.w,
                inside,
                ctx.depth,
                mode,
                wave.wave_normal,
            )
            ea[c] = ek
            e_sum += ek
            c += 1
    return cand, ea, e_sum, c


@wp.func
def forward_event(
    d: wp.vec3f,
    s_in: wp.vec3f,
    bx: wp.vec3f,
    m: Jones,
    mode: int,
    depth: int,
    n_out: wp.vec3f,
    x: wp.vec3f,
    obj_a: int,
    obj_b: int,
    med_a: UniaxialMedium,
    med_b: UniaxialMedium,
    n_a: wp.vec2f,
    n_b: wp.vec2f,
    stack: CoatingStack,
    coat: int,
    wavelength: float,
    eps: float,
    w: float,
    e: float,
    csrc: Jones,
):
    """The forward interface event of a ray (direction ``d``, wave normal ``s_in``, frame ``bx``,
    source-to-ray Jones ``m``, mode, weight ``w`` after its segment's absorption, power ``e``)
    arriving at ``x`` from object ``obj_a`` (medium A) onto ``obj_b`` (B); ``n_out`` the outward
    normal of the surface hit.  Returns (cand, powers, e_sum, count).

    Isotropic media: Fresnel (or the coating's stack) in the s/p frame, the refracted direction
    and flux ratio from the same Fresnel solution.  A uniaxial side: the generalized Fresnel
    amplitudes (eq. 5) per incident mode, each outgoing wave power-normalised by its flux.  An
    interface never returns more power than arrives (with an absorbing incident medium the
    plane-wave flux split is not unique and |r|^2 can exceed 1 near total reflection: the children
    are then scaled to the incident power)."""
    cand = Cand()
    entering = wp.dot(d, n_out) < 0.0
    nrm = n_out  # unit normal on the incident side
    if not entering:
        nrm = -n_out
    c = int(0)
    e_sum = float(0.0)
    ea = wp.vec4f(0.0)
    if not is_uniaxial(med_a) and not is_uniaxial(med_b):
        # Light arriving from an absorbing medium: Fresnel with the real part of its index (the
        # weak-absorption approximation; its absorption is Bouguer-Lambert along the path).
        # ``c_normal_component`` takes the Im >= 0 root of N2 cos t, which for an absorbing
        # *incident* medium is the backward-travelling one (|r| >> 1).
        na = wp.vec2f(n_a[0], 0.0)
        cos_a = wp.clamp(-wp.dot(d, nrm), 0.0, 1.0)
        s = s_vector(d, n_out)
        f = fresnel_amplitudes(cos_a, na, n_b)
        # a coating's front faces the ambient medium: seen from the back when leaving the solid
        n_front = na
        n_back = n_b
        from_back = int(0)
        if not entering:
            n_front = n_b
            n_back = na
            from_back = 1
        rs, rp, ts, tp = interface_amplitudes(
            f, stack, coat, wavelength, cos_a, n_front, n_back, from_back, 1.0
        )
        m_sp = jones_mul(jones_real(frame_change(d, bx, s)), m)
        d_r = wp.normalize(d + nrm * (2.0 * cos_a))
        m_r = jones_mul(jones_diag(rs, rp), m_sp)
        e_r = ray_power(m_r, w, csrc)
        if e_r > 0.0:
            cand = write_row(cand, c, x + d_r * eps, d_r, s, m_r, w, obj_a, depth + 1, -1, d_r)
            ea[c] = e_r
            e_sum += e_r
            c += 1
        d_t = refract_from_fresnel(d, nrm, f, na, n_b)
        if wp.dot(d_t, d_t) > 0.0:
            m_t = jones_scale(jones_mul(jones_diag(ts, tp), m_sp), wp.sqrt(transmitted_flux_ratio(f)))
            e_t = ray_power(m_t, w, csrc)
            if e_t > 0.0:
                cand = write_row(cand, c, x + d_t * eps, d_t, s, m_t, w, obj_b, depth + 1, -1, d_t)
                ea[c] = e_t
                e_sum += e_t
                c += 1
    else:
        zero = wp.vec2f(0.0, 0.0)
        if mode < 0:
            # isotropic incident ray: its s/p (= o/e) components both excite every wave
            so, se = crystal_fresnel_both(s_in, nrm, med_a, med_b)
            m_in = jones_mul(jones_real(frame_change(s_in, bx, so.incident.e_re)), m)
            ctx = _wave_ctx(x, eps, w, csrc, depth + 1, so.incident.flux)
            cand, ea, e_sum, c = _push_wave(
                cand, c, ea, e_sum, ctx, so.ro, jones(so.r_o, se.r_o, so.r_e, se.r_e), m_in, obj_a, -1
            )
            cand, ea, e_sum, c = _push_wave(
                cand, c, ea, e_sum, ctx, so.to, jones(so.t_o, se.t_o, zero, zero), m_in, obj_b, 0
            )
            cand, ea, e_sum, c = _push_wave(
                cand, c, ea, e_sum, ctx, so.te, jones(so.t_e, se.t_e, zero, zero), m_in, obj_b, 1
            )
        else:
            # one eigenmode inside a crystal: row 0 of M is its amplitude
            sol = crystal_fresnel(s_in, mode, nrm, med_a, med_b)
            ctx = _wave_ctx(x, eps, w, csrc, depth + 1, sol.incident.flux)
            cand, ea, e_sum, c = _push_wave(
                cand, c, ea, e_sum, ctx, sol.ro, jones_diag(sol.r_o, zero), m, obj_a, 0
            )
            cand, ea, e_sum, c = _push_wave(
                cand, c, ea, e_sum, ctx, sol.re, jones_diag(sol.r_e, zero), m, obj_a, 1
            )
            if not is_uniaxial(med_b):
                # into an isotropic medium: the o/e amplitudes are its s/p components
                cand, ea, e_sum, c = _push_wave(
                    cand, c, ea, e_sum, ctx, sol.to, jones(sol.t_o, zero, sol.t_e, zero), m, obj_b, -1
                )
            else:
                cand, ea, e_sum, c = _push_wave(
                    cand, c, ea, e_sum, ctx, sol.to, jones_diag(sol.t_o, zero), m, obj_b, 0
                )
                cand, ea, e_sum, c = _push_wave(
                    cand, c, ea, e_sum, ctx, sol.te, jones_diag(sol.t_e, zero), m, obj_b, 1
                )
    if e_sum > e:
        g = e / e_sum
        for j in range(c):
            cand[j, ROW_W] = cand[j, ROW_W] * g
            ea[j] = ea[j] * g
        e_sum = e
    return cand, ea, e_sum, c
