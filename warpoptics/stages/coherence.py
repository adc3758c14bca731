"""The coherent birefringence mode of the camera trace (``render.birefringence = "coherent"``).

In the ``exact`` mode every leaf of a primary ray's path tree (a branch that reaches the
environment) adds L/2 M M^dagger to the pixel's coherency: the o and e waves (and all other
branches) add incoherently.  In the coherent mode each branch also carries its optical phase in its
Jones matrix, and leaves that leave the stone together are added as amplitudes first.

Phase along a segment (:func:`segment_phase`).  A plane wave of wave normal s and index n (the
wave's own index: n_o, n_e(theta) of a uniaxial wave, the fast/slow sheet of a biaxial one,
``biaxial.wave_index``) gains the phase k . dx = k0 n (s . t) L over a ray (energy) path of length
L along the unit ray direction t (Born & Wolf, Principles of Optics, 7th ed., §15.2: the phase
travels along s with the phase velocity c/n, the energy along t with the ray velocity
c/(n s.t); Guy & Soler 2004 §4.1 carry the same k . x in their eq. 5 waves).  In an isotropic
medium s = t.  It is multiplied into M as exp(i 2 pi n (s.t) L / lambda) (``plate.slab_phase``,
formed in float64).  The Fresnel and TIR phases are already in the amplitudes.  Children of an
interface start ``epsilon`` along their direction from the interface point, so a segment's
length from that point is hit.t + epsilon (depth > 0).

Leaf reference.  The environment is an incoherent superposition of plane waves; the wave arriving
along -d has phase k0 n_amb (-d . x) at the point x where the leaf leaves the stone, which is
multiplied in when the leaf is stored: the phases of leaves of the same direction then refer to
the same incident plane wave.

Addition rule (:func:`coherent_flush`).  Leaves of one primary ray are summed as amplitudes
(M_g = sum_j sqrt(w_j) M_j F_j, F_j the change from the group's first frame to the leaf's
frame, ``jones.frame_change``) when their directions agree within the angular tolerance
(cos >= ``coherence_cos``: the environment's angular resolution, see ``direction_tolerance``) and
the separation of their exit points across the direction is below the illumination's coherence
width ``render.coherence_width_mm``; other leaves are added incoherently.  Two points of a field
from a uniformly bright source of angular radius alpha are coherent (|mu12| >= 0.88) within
0.16 lambda / alpha (van Cittert-Zernike; Born & Wolf §10.4.2).  The default 0.001 mm is that width
at lambda = 0.55 um for a diffuse light box of angular radius alpha = 0.088 rad (a 50 mm
diffuser seen from 280 mm, the polariscope/light-table geometry); sunlight (alpha = 4.65 mrad)
gives 0.019 mm, a stopped-down microscope condenser (alpha ~ 0.01-0.05) 0.002-0.009 mm.

Leaf buffer.  The leaves of a primary ray wait in a per-thread buffer of ``LEAVES`` rows, flushed
at the end of ``trace_radiance``; a leaf that finds the buffer full is added incoherently at once
(documented overflow: it loses only its interference with the others); a leaf toward a black
direction (below a dome's horizon) adds nothing and is not stored.  The cross terms are
weighted sqrt(w_i w_j): exact for deterministically split branches.  A branch continued
stochastically (below ``split_threshold``, weight 1/probability) keeps its own term unbiased, but
its cross terms carry sqrt(1/probability): an approximation, on branches of < 0.2 % of the
pixel's energy.  Leaves that end on
an opaque surface or a lamp (``stages/surfaces.py``, extended incoherent sources) stay incoherent.
Scalar renders (``polarization = false``) have no amplitudes and ignore the mode; the spectral
bundle and shared-spectrum paths are turned off in this mode (the phases depend on the
wavelength: one tree per wavelength sample, ``pipelines/render.py``).
"""

from __future__ import annotations

import math

import warp as wp

from ..film.leaf import add_light
from ..optics.biaxial import wave_index
from ..optics.birefringence import UniaxialMedium
from ..optics.jones import (
    Jones,
    coherency_transform,
    frame_change,
    jones_add,
    jones_mul,
    jones_real,
    jones_scale,
)
from ..optics.plate import slab_phase
from ..optics.polarizer import sheet_polarizer_coherency

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "LEAVES",
    "LeafBuffer",
    "DEFAULT_COHERENCE_WIDTH_MM",
    "direction_tolerance",
    "jones_phase",
    "segment_phase",
    "coherent_leaf",
    "coherent_flush",
]

#: rows of the per-primary leaf buffer
LEAVES = 8
_LEAVES = wp.constant(LEAVES)
# columns: sqrt(w) M (re 4, im 4), exit point x (3), direction d (3), basis x (3), colour xyz (3)
_C_RE = wp.constant(0)
_C_IM = wp.constant(4)
_C_X = wp.constant(8)
_C_D = wp.constant(11)
_C_B = wp.constant(14)
_C_XYZ = wp.constant(17)
LeafBuffer = wp.types.matrix(shape=(LEAVES, 20), dtype=wp.float32)

#: 0.16 lambda / alpha at 550 nm, alpha = 0.088 rad (module docstring), mm
DEFAULT_COHERENCE_WIDTH_MM = 0.001
#: angular tolerance of a procedural (smooth) environment map, rad
_PROCEDURAL_TOLERANCE = 1.0e-3


def direction_tolerance(map_height: int) -> float:
    """Cosine of the angular tolerance for leaves to count as one direction: one texel of a
    lat-long map (pi / height), 1 mrad for procedural (smooth) maps (``map_height`` 0)."""
    ang = math.pi / map_height if map_height > 0 else _PROCEDURAL_TOLERANCE
    return math.cos(ang)


@wp.func
def jones_phase(m: Jones, ph: wp.vec2f):
    """M times the complex scalar ``ph``."""
    r = Jones()
    r.re = m.re * ph[0] - m.im * ph[1]
    r.im = m.re * ph[1] + m.im * ph[0]
    return r


@wp.func
def segment_phase(
    m: Jones,
    med: UniaxialMedium,
    mode: int,
    wn: wp.vec3f,
    d: wp.vec3f,
    t: float,
    depth: int,
    eps: float,
    wavelength: float,
):
    """M exp(i 2 pi n (s.t) L / lambda) for a segment of ray direction -``d`` (the backward ray's
    ``d``), wave normal ``wn`` (the light's), the wave's index in ``med`` for ``mode`` and length
    L = ``t`` (+ ``eps`` for children, which start eps past the interface)."""
    length = t
    if depth > 0:
        length = t + eps
    q = wave_index(med, mode, wn) * wp.dot(wn, -d)
    return jones_phase(m, slab_phase(q, 0.0, length, wavelength))


@wp.func
def _store(buf: LeafBuffer, i: int, m: Jones, x: wp.vec3f, d: wp.vec3f, bx: wp.vec3f, xyz: wp.vec3f):
    for r in range(2):
        for c in range(2):
            buf[i, _C_RE + 2 * r + c] = m.re[r, c]
            buf[i, _C_IM + 2 * r + c] = m.im[r, c]
    for c in range(3):
        buf[i, _C_X + c] = x[c]
        buf[i, _C_D + c] = d[c]
        buf[i, _C_B + c] = bx[c]
        buf[i, _C_XYZ + c] = xyz[c]
    return buf


@wp.func
def _vec(buf: LeafBuffer, i: int, c0: int):
    return wp.vec3f(buf[i, c0], buf[i, c0 + 1], buf[i, c0 + 2])


@wp.func
def _jones(buf: LeafBuffer, i: int):
    m = Jones()
    m.re = wp.mat22(buf[i, _C_RE], buf[i, _C_RE + 1], buf[i, _C_RE + 2], buf[i, _C_RE + 3])
    m.im = wp.mat22(buf[i, _C_IM], buf[i, _C_IM + 1], buf[i, _C_IM + 2], buf[i, _C_IM + 3])
    return m


@wp.func
def coherent_leaf(
    buf: LeafBuffer,
    count: int,
    acc_x: Jones,
    acc_y: Jones,
    acc_z: Jones,
    m: Jones,
    w: float,
    o: wp.vec3f,
    d: wp.vec3f,
    bx: wp.vec3f,
    xyz: wp.vec3f,
    polarizer: wp.vec3f,
    n_ambient: float,
    depth: int,
    eps: float,
    wavelength: float,
):
    """A leaf (a branch of Jones ``m``, weight ``w``, origin ``o``, direction ``d`` toward the
    environment, frame ``bx``, environment colour ``xyz``) into the buffer with its incident-wave
    reference phase; a full buffer adds it incoherently at once.  (buf, count, acc_x, acc_y,
    acc_z).  A leaf of a black direction (``xyz`` zero: below a dome's horizon, a black sky)
    adds nothing coherent or not (a group takes its first leaf's colour, and leaves of one
    direction see one colour) and is not stored, so that it does not take a row from the lit
    leaves after it (a conoscope sphere's reflections toward the floor fill the buffer)."""
    if xyz[0] == 0.0 and xyz[1] == 0.0 and xyz[2] == 0.0:
        return buf, count, acc_x, acc_y, acc_z
    if count >= _LEAVES:
        k_unit = coherency_transform(m, sheet_polarizer_coherency(polarizer, -d, bx, w))
        acc_x, acc_y, acc_z = add_light(acc_x, acc_y, acc_z, k_unit, xyz)
        return buf, count, acc_x, acc_y, acc_z
    x = o
    if depth > 0:
        x = o - d * eps  # the exit point on the stone's surface
    ma = jones_scale(jones_phase(m, slab_phase(n_ambient, 0.0, -wp.dot(d, x), wavelength)), wp.sqrt(w))
    buf = _store(buf, count, ma, x, d, bx, xyz)
    return buf, count + 1, acc_x, acc_y, acc_z


@wp.func
def coherent_flush(
    buf: LeafBuffer,
    count: int,
    acc_x: Jones,
    acc_y: Jones,
    acc_z: Jones,
    polarizer: wp.vec3f,
    width: float,
    cos_tol: float,
):
    """Add the buffered leaves: groups of one direction (cos >= ``cos_tol``) whose exit points lie
    within ``width`` across it as amplitudes (in the first leaf's frame), then their coherency
    with the first leaf's source and colour.  Returns (acc_x, acc_y, acc_z)."""
    used = int(0)
    for i in range(count):
        if (used >> i) & 1 == 0:
            xi = _vec(buf, i, _C_X)
            di = _vec(buf, i, _C_D)
            bi = _vec(buf, i, _C_B)
            ki = -di
            mg = _jones(buf, i)
            for j in range(i + 1, count):
                if (used >> j) & 1 == 0:
                    dj = _vec(buf, j, _C_D)
                    sep = _vec(buf, j, _C_X) - xi
                    lat = sep - di * wp.dot(sep, di)
                    if wp.dot(di, dj) >= cos_tol and wp.length(lat) < width:
                        f = jones_real(frame_change(ki, bi, _vec(buf, j, _C_B)))
                        mg = jones_add(mg, jones_mul(_jones(buf, j), f))
                        used = used | (1 << j)
            k_unit = coherency_transform(mg, sheet_polarizer_coherency(polarizer, ki, bi, 1.0))
            acc_x, acc_y, acc_z = add_light(acc_x, acc_y, acc_z, k_unit, _vec(buf, i, _C_XYZ))
    return acc_x, acc_y, acc_z
