"""The coherent birefringence mode of the camera trace (``render.birefringence = "coherent"``).

In the ``exact`` mode every leaf of a primary ray's path tree adds L/2 M M^dagger to the pixel's
coherency: the o and e waves (and all other branches) add incoherently.  In the coherent mode
each branch also carries its optical phase in its Jones matrix, and leaves that leave the stone
together are added as amplitudes first.

- Phase (:func:`segment_phase`): a wave of normal s and its own index n (n_o, n_e(theta), a
  biaxial sheet's ``biaxial.wave_index``) gains k0 n (s . t) L over a ray path of length L along
  the ray direction t (Born & Wolf §15.2; Guy & Soler 2004 §4.1), multiplied into M as
  exp(i 2 pi n (s.t) L / lambda), formed in float64.  Fresnel and TIR phases are in the
  amplitudes.  At a leaf the phase of the incident plane wave at the exit point is multiplied in,
  so leaves of one direction refer to the same wave.
- Addition (:func:`coherent_flush`): leaves of one primary ray are summed as amplitudes (after
  ``jones.frame_change`` into one frame) when their directions agree within ``coherence_cos``
  and their exit points lie within the coherence width ``render.coherence_width_mm`` across the
  direction (van Cittert–Zernike, 0.16 lambda / alpha for a source of angular radius alpha; the
  default 0.001 mm is a light box of 0.088 rad at 550 nm); other leaves add incoherently.
- Leaf buffer: ``LEAVES`` rows per thread, flushed at the end of ``trace_radiance``; a leaf
  that finds it full is added incoherently.  Cross terms are weighted sqrt(w_i w_j), exact for
  split branches and an approximation for stochastic ones (< 0.2 % of a pixel's energy).

Leaves on opaque surfaces or lamps stay incoherent; scalar renders ignore the mode; bundles and
shared-spectrum paths are off in it (the phases depend on the wavelength).  The derivation, the
coherence widths of common sources and the buffer's rules: docs/design/coherent_mode.md.

References: Born & Wolf, Principles of Optics, 7th ed., §10.4.2 (van Cittert–Zernike), §15.2
(phase and ray velocity in crystals); Guy & Soler 2004, §4.1.
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
