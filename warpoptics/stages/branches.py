"""The branch stack of the tracers: one row per pending ray of a path tree.

Both tracers (``trace.py``, backward from the camera, and ``forward.py``, forward from a beam)
follow a tree of rays depth-first with an explicit stack held in a per-thread local matrix; this
module is the one place of its row layout and of the helpers that read and write rows.
"""

from __future__ import annotations

from typing import Any

import warp as wp

from ..optics.jones import Jones, frame_change, jones_diag, jones_mul, jones_real, jones_scale

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["STACK_SIZE", "COLS", "Stack", "Cand", "write_row", "write_jones", "copy_row", "Ray", "read_row",
           "branch_energy", "child_jones"]

#: rows of the per-thread branch stack (a depth-first tree needs about one row per level)
STACK_SIZE = 40
COLS = 24
Stack = wp.types.matrix(shape=(STACK_SIZE, COLS), dtype=wp.float32)
Cand = wp.types.matrix(shape=(4, COLS), dtype=wp.float32)  # the children of one interface event
# row layout (stack and candidates)
_O = 0  # origin xyz
_D = 3  # direction xyz (backward: from the camera toward the light; the ray / energy direction)
_B = 6  # polarization basis x (isotropic segments)
_MR = 9  # Jones real part (4)
_MI = 13  # Jones imaginary part (4)
_W = 17  # scalar weight (absorption, roulette); the energy is w |M|^2 / 2
_IN = 18  # object the segment runs inside (-1: the ambient medium)
_DEPTH = 19  # number of interfaces crossed so far
_MODE = 20  # -1 isotropic segment, 0 ordinary, 1 extraordinary wave of a uniaxial crystal
_WN = 21  # wave normal of the light on the segment (light's direction of travel), xyz


@wp.func
def write_jones(st: Any, n: int, m: Jones):
    st[n, _MR + 0] = m.re[0, 0]
    st[n, _MR + 1] = m.re[0, 1]
    st[n, _MR + 2] = m.re[1, 0]
    st[n, _MR + 3] = m.re[1, 1]
    st[n, _MI + 0] = m.im[0, 0]
    st[n, _MI + 1] = m.im[0, 1]
    st[n, _MI + 2] = m.im[1, 0]
    st[n, _MI + 3] = m.im[1, 1]
    return st


@wp.func
def write_row(
    st: Any, n: int, o: wp.vec3f, d: wp.vec3f, b: wp.vec3f, m: Jones, w: float, inside: int, depth: int,
    mode: int, wn: wp.vec3f,
):
    for c in range(3):
        st[n, _O + c] = o[c]
        st[n, _D + c] = d[c]
        st[n, _B + c] = b[c]
        st[n, _WN + c] = wn[c]
    st = write_jones(st, n, m)
    st[n, _W] = w
    st[n, _IN] = float(inside)
    st[n, _DEPTH] = float(depth)
    st[n, _MODE] = float(mode)
    return st


@wp.func
def copy_row(dst: Any, i: int, src: Any, k: int):
    for c in range(COLS):
        dst[i, c] = src[k, c]
    return dst


@wp.struct
class Ray:
    """One stack row, unpacked: a pending ray of a path tree (see the row layout above)."""

    o: wp.vec3f
    d: wp.vec3f
    b: wp.vec3f
    wn: wp.vec3f
    m: Jones
    w: float
    inside: int
    depth: int
    mode: int


@wp.func
def read_row(st: Any, n: int):
    """Row ``n`` of ``st`` as a :class:`Ray` (one call per pop: an argument is a by-value copy of
    the whole stack, which the camera tracer, the hottest loop, avoids by reading inline)."""
    r = Ray()
    r.o = wp.vec3f(st[n, _O], st[n, _O + 1], st[n, _O + 2])
    r.d = wp.vec3f(st[n, _D], st[n, _D + 1], st[n, _D + 2])
    r.b = wp.vec3f(st[n, _B], st[n, _B + 1], st[n, _B + 2])
    r.wn = wp.vec3f(st[n, _WN], st[n, _WN + 1], st[n, _WN + 2])
    m = Jones()
    m.re = wp.mat22(st[n, _MR], st[n, _MR + 1], st[n, _MR + 2], st[n, _MR + 3])
    m.im = wp.mat22(st[n, _MI], st[n, _MI + 1], st[n, _MI + 2], st[n, _MI + 3])
    r.m = m
    r.w = st[n, _W]
    r.inside = int(st[n, _IN])
    r.depth = int(st[n, _DEPTH])
    r.mode = int(st[n, _MODE])
    return r


@wp.func
def branch_energy(m: Jones, w: float):
    """Power a branch carries for unpolarized light: w tr(M M^dagger) / 2."""
    s = float(0.0)
    for i in range(2):
        for k in range(2):
            s += m.re[i, k] * m.re[i, k] + m.im[i, k] * m.im[i, k]
    return 0.5 * w * s


@wp.func
def child_jones(m: Jones, k_out: wp.vec3f, parent_x: wp.vec3f, s: wp.vec3f, a_s: wp.vec2f, a_p: wp.vec2f,
                scale: float):
    """Jones matrix of a child across an interface, backward (Guy & Soler 2004 eq. 12 from the
    eye): M_parent . B . diag(a_s, a_p) * scale, with B turning the s/p frame of the outgoing wave
    (``k_out``, ``s``) into the parent's frame (x = ``parent_x``)."""
    b = jones_real(frame_change(k_out, s, parent_x))
    return jones_scale(jones_mul(m, jones_mul(b, jones_diag(a_s, a_p))), scale)
