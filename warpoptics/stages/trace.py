"""The trace stage: a camera (backward) path tree through dielectric solids to the lights.

One call of :func:`trace_radiance` follows everything that light arriving along one primary ray
can have come through.  At every interface the path splits into the reflected and the refracted
branch (total internal reflection leaves one).  While a branch still carries at least
``split_threshold`` of the primary ray's energy both children are followed *deterministically*
(an explicit stack): the per-pixel form of the pruned facet tree of Guy & Soler 2004 §5.  Below
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

from ..geometry.query import SceneGeometry, scene_closest_hit
from ..materials.dispersion import MaterialTable, material_alpha, material_eval
from ..optics.complex import c_abs2
from ..optics.fresnel import fresnel_amplitudes
from ..optics.jones import (
    Jones,
    coherency_transform,
    coherency_unpolarized,
    frame_change,
    jones_add,
    jones_diag,
    jones_identity,
    jones_mul,
    jones_real,
    jones_scale,
    jones_zero,
    s_vector,
)
from ..spectra import SpectralTables
from .environment import Environment, environment_radiance

__all__ = ["TraceParams", "TraceConfig", "trace_radiance", "STACK_SIZE"]

#: rows of the per-thread branch stack (a depth-first tree needs about one row per level)
STACK_SIZE = 40
_COLS = 24
_Stack = wp.types.matrix(shape=(STACK_SIZE, _COLS), dtype=wp.float32)
# stack row layout
_O = 0  # origin xyz
_D = 3  # direction xyz (backward: from the camera toward the light)
_B = 6  # polarization basis x
_MR = 9  # Jones real part (4)
_MI = 13  # Jones imaginary part (4)
_W = 17  # scalar weight (absorption, roulette); the energy is w |M|^2 / 2
_IN = 18  # object the segment runs inside (-1: the ambient medium)
_DEPTH = 19  # number of interfaces crossed so far


@wp.struct
class TraceParams:
    """Per-render settings of the trace stage (values, not compile-time constants)."""

    max_depth: int  # interfaces per path (Mitsuba's max_depth - 1)
    split_threshold: float  # split deterministically while a branch carries >= this energy
    rr_threshold: float  # below this energy a branch survives Russian roulette with p = e / rr
    t_max: float  # mm
    epsilon: float  # origin offset along the new direction, mm
    ambient: wp.vec2f  # complex index of the medium around the objects (air: 1)
    rgb3: int  # 1: use the materials' eq. 9 RGB absorbances (channel = sample index)
    object_material: wp.array(dtype=wp.int32)  # material id of each object
    object_absorption_scale: wp.array(dtype=wp.float32)  # multiplier of alpha per object


@dataclass(frozen=True)
class TraceConfig:
    max_depth: int = 12
    split_threshold: float = 0.002
    rr_threshold: float = 1.0e-4
    polarized: bool = True


@wp.func
def _push(
    st: _Stack, n: int, o: wp.vec3f, d: wp.vec3f, b: wp.vec3f, m: Jones, w: float, inside: int, depth: int
):
    for c in range(3):
        st[n, _O + c] = o[c]
        st[n, _D + c] = d[c]
        st[n, _B + c] = b[c]
    st[n, _MR + 0] = m.re[0, 0]
    st[n, _MR + 1] = m.re[0, 1]
    st[n, _MR + 2] = m.re[1, 0]
    st[n, _MR + 3] = m.re[1, 1]
    st[n, _MI + 0] = m.im[0, 0]
    st[n, _MI + 1] = m.im[0, 1]
    st[n, _MI + 2] = m.im[1, 0]
    st[n, _MI + 3] = m.im[1, 1]
    st[n, _W] = w
    st[n, _IN] = float(inside)
    st[n, _DEPTH] = float(depth)
    return st


@wp.func
def _row_vec(st: _Stack, n: int, c0: int):
    return wp.vec3f(st[n, c0], st[n, c0 + 1], st[n, c0 + 2])


@wp.func
def _row_jones(st: _Stack, n: int):
    m = Jones()
    m.re = wp.mat22(st[n, _MR], st[n, _MR + 1], st[n, _MR + 2], st[n, _MR + 3])
    m.im = wp.mat22(st[n, _MI], st[n, _MI + 1], st[n, _MI + 2], st[n, _MI + 3])
    return m


@wp.func
def _energy(m: Jones, w: float):
    # transmitted power for unpolarized light: w tr(M M^dagger) / 2
    s = float(0.0)
    for i in range(2):
        for k in range(2):
            s += m.re[i, k] * m.re[i, k] + m.im[i, k] * m.im[i, k]
    return 0.5 * w * s


@wp.func
def _child_jones(m: Jones, k_out: wp.vec3f, parent_x: wp.vec3f, s: wp.vec3f, a_s: wp.vec2f, a_p: wp.vec2f, scale: float):
    # M_child = M_parent . B . diag(a_s, a_p) * scale, B: s/p frame of the outgoing wave -> parent frame
    b = jones_real(frame_change(k_out, s, parent_x))
    return jones_scale(jones_mul(m, jones_mul(b, jones_diag(a_s, a_p))), scale)


@wp.func
def _medium_index(p: TraceParams, mats: MaterialTable, obj: int, wavelength: float):
    if obj < 0:
        return p.ambient
    no, ne = material_eval(mats, p.object_material[obj], wavelength)
    return no


@wp.func
def _medium_alpha(p: TraceParams, mats: MaterialTable, obj: int, wavelength: float, channel: int):
    mid = p.object_material[obj]
    a = float(0.0)
    if p.rgb3 != 0:
        a = mats.rgb3_alpha_o[mid][wp.clamp(channel, 0, 2)]
    else:
        ao, ae = material_alpha(mats, mid, wavelength)
        a = ao
    return a * p.object_absorption_scale[obj]


@wp.func
def trace_radiance(
    p: TraceParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    env: Environment,
    tables: SpectralTables,
    polarized: int,
    origin: wp.vec3f,
    direction: wp.vec3f,
    basis_x: wp.vec3f,
    wavelength: float,
    channel: int,
    rng: wp.uint32,
):
    """Coherency matrix (camera frame) of the light arriving along a primary ray, at one
    wavelength (nm).  Returns (J, hit_any, rays_traced, rng)."""
    st = _Stack()
    st = _push(st, 0, origin, direction, basis_x, jones_identity(), 1.0, -1, 0)
    n = int(1)
    acc = jones_zero()
    acc_scalar = float(0.0)
    hit_any = int(0)
    rays = int(0)
    while n > 0:
        n -= 1
        o = _row_vec(st, n, _O)
        d = _row_vec(st, n, _D)
        bx = _row_vec(st, n, _B)
        m = _row_jones(st, n)
        w = st[n, _W]
        inside = int(st[n, _IN])
        depth = int(st[n, _DEPTH])
        rays += 1
        hit = scene_closest_hit(geom, o, d, p.t_max)
        if hit.object < 0:
            if inside < 0:
                radiance = environment_radiance(env, tables, d, wavelength)
                if polarized != 0:
                    acc = jones_add(acc, coherency_transform(m, coherency_unpolarized(w * radiance)))
                else:
                    acc_scalar += w * radiance
            # a segment inside a solid that finds no exit leaked through a crack: dropped
            continue
        if depth == 0:
            hit_any = 1
        if inside >= 0:
            alpha = _medium_alpha(p, mats, inside, wavelength, channel)
            w = w * wp.exp(-alpha * hit.t)
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
        obj_a = inside
        n_a = _medium_index(p, mats, obj_a, wavelength)
        n_b = _medium_index(p, mats, obj_b, wavelength)
        cos_a = wp.clamp(-wp.dot(d, nrm), 0.0, 1.0)
        s = s_vector(d, n_out)
        k_out = -d  # light leaves the interface toward the camera along -d
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
        # refraction: light arriving from medium B, transmitted into A (unless TIR)
        eta = n_a[0] / n_b[0]
        sin2_b = eta * eta * (1.0 - cos_a * cos_a)
        e_t = float(0.0)
        m_t = m
        w_t = float(0.0)
        d_t = d
        if sin2_b < 1.0:
            cos_b = wp.sqrt(1.0 - sin2_b)
            d_t = wp.normalize(d * eta + nrm * (eta * cos_a - cos_b))
            f_t = fresnel_amplitudes(cos_b, n_b, n_a)
            ratio = float(0.0)
            if f_t.n1_cos_i[0] > 0.0:
                ratio = wp.max(f_t.n2_cos_t[0], 0.0) / f_t.n1_cos_i[0]
            w_t = w
            if polarized != 0:
                m_t = _child_jones(m, k_out, bx, s, f_t.ts, f_t.tp, wp.sqrt(ratio))
            else:
                w_t = w * 0.5 * ratio * (c_abs2(f_t.ts) + c_abs2(f_t.tp))
            e_t = _energy(m_t, w_t)
        e_parent = e_r + e_t
        if e_parent <= 0.0:
            continue
        in_t = hit.object
        if not entering:
            in_t = -1
        take_r = e_r > 0.0
        take_t = e_t > 0.0
        if e_parent < p.split_threshold or n + 2 > STACK_SIZE:
            # stochastic continuation: one child, chosen by energy, weighted by 1/probability
            u = wp.randf(rng)
            p_r = e_r / e_parent
            if u < p_r:
                take_t = False
                w_r = w_r / p_r
            else:
                take_r = False
                w_t = w_t / (1.0 - p_r)
            # Russian roulette on weak paths (energy after the choice = e_parent)
            if e_parent < p.rr_threshold:
                q = e_parent / p.rr_threshold
                if wp.randf(rng) >= q:
                    continue
                w_r = w_r / q
                w_t = w_t / q
        if take_t:
            st = _push(st, n, x + d_t * p.epsilon, d_t, s, m_t, w_t, in_t, depth + 1)
            n += 1
        if take_r:
            st = _push(st, n, x + d_r * p.epsilon, d_r, s, m_r, w_r, obj_a, depth + 1)
            n += 1
    if polarized == 0:
        acc = coherency_unpolarized(acc_scalar)
    return acc, hit_any, rays, rng


def default_params(objects_material: np.ndarray, absorption_scale: np.ndarray, *, config: TraceConfig,
                   ambient=(1.0, 0.0), t_max: float = 1.0e6, epsilon: float = 1.0e-4, rgb3: bool = False,
                   device=None) -> TraceParams:
    p = TraceParams()
    p.max_depth = int(config.max_depth)
    p.split_threshold = float(config.split_threshold)
    p.rr_threshold = float(config.rr_threshold)
    p.t_max = float(t_max)
    p.epsilon = float(epsilon)
    p.ambient = wp.vec2f(*ambient)
    p.rgb3 = int(rgb3)
    p.object_material = wp.array(np.asarray(objects_material, dtype=np.int32), dtype=wp.int32, device=device)
    p.object_absorption_scale = wp.array(np.asarray(absorption_scale, dtype=np.float32), dtype=wp.float32,
                                         device=device)
    return p
