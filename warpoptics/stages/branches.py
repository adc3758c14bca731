"""The branch stack of the tracers: one row per pending ray of a path tree.

Both tracers (``trace.py``, backward from the camera, and ``forward.py``, forward from a beam)
follow a tree of rays depth-first with an explicit stack held in a per-thread local matrix; this
module is the one place of its row layout and of the helpers that read and write rows.
"""

from __future__ import annotations

from typing import Any

import warp as wp

from ..optics.jones import Jones

__all__ = ["STACK_SIZE", "COLS", "Stack", "Cand", "write_row", "write_jones", "copy_row", "row_vec", "row_jones"]

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


@wp.func
def row_vec(st: Any, n: int, c0: int):
    return wp.vec3f(st[n, c0], st[n, c0 + 1], st[n, c0 + 2])


@wp.func
def row_jones(st: Any, n: int):
    m = Jones()
    m.re = wp.mat22(st[n, _MR], st[n, _MR + 1], st[n, _MR + 2], st[n, _MR + 3])
    m.im = wp.mat22(st[n, _MI], st[n, _MI + 1], st[n, _MI + 2], st[n, _MI + 3])
    return m
