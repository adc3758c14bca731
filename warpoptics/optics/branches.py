"""Path-tree nodes: the children of an interface event, the per-thread branch stack, branch choice.

Every tracer (the camera trace ``stages/trace.py``, backward from the eye; the optical bench
``stages/forward.py`` and the caustic light tracer ``stages/caustics.py``, forward from a light)
follows a tree of rays depth-first with an explicit stack held in a per-thread local matrix.  An
interface event (``optics/interface.py``) writes its children as rows of a candidate matrix
``Cand``; the tracer then keeps them all (a deterministic split) or one of them
(:func:`pick_child`, weighted by 1/probability, then :func:`roulette`).  This module is the one
place of the row layout, of the helpers that read and write rows and of the branch choice.

References:
    Guy, S., Soler, C. 2004. Graphics Gems Revisited, §5 (the facet tree with energy pruning).
    Veach, E. 1997. Robust Monte Carlo Methods for Light Transport Simulation, ch. 4 (splitting,
        random selection weighted by 1/probability, Russian roulette).
"""

from __future__ import annotations

from typing import Any

import warp as wp

from ..optics.jones import Jones, frame_change, jones_diag, jones_mul, jones_real, jones_scale

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "STACK_SIZE",
    "COLS",
    "Stack",
    "Cand",
    "write_row",
    "write_jones",
    "copy_row",
    "Ray",
    "read_row",
    "branch_energy",
    "parent_in_sp",
    "child_jones_sp",
    "add_child",
    "pick_child",
    "roulette",
    "ROW_O",
    "ROW_D",
    "ROW_B",
    "ROW_MR",
    "ROW_MI",
    "ROW_W",
    "ROW_IN",
    "ROW_DEPTH",
    "ROW_MODE",
    "ROW_WN",
]

#: rows of the per-thread branch stack (a depth-first tree needs about one row per level)
STACK_SIZE = 40
COLS = 24
Stack = wp.types.matrix(shape=(STACK_SIZE, COLS), dtype=wp.float32)
Cand = wp.types.matrix(shape=(4, COLS), dtype=wp.float32)  # the children of one interface event
# row layout (stack and candidates)
ROW_O = 0  # origin xyz
ROW_D = 3  # direction xyz (backward: from the camera toward the light; the ray / energy direction)
ROW_B = 6  # polarization basis x (isotropic segments)
ROW_MR = 9  # Jones real part (4)
ROW_MI = 13  # Jones imaginary part (4)
ROW_W = 17  # scalar weight (absorption, roulette); the energy is w |M|^2 / 2
ROW_IN = 18  # object the segment runs inside (-1: the ambient medium)
ROW_DEPTH = 19  # number of interfaces crossed so far
ROW_MODE = 20  # -1 isotropic segment, 0 ordinary, 1 extraordinary wave of a uniaxial crystal
ROW_WN = 21  # wave normal of the light on the segment (light's direction of travel), xyz


@wp.func
def write_jones(st: Any, n: int, m: Jones):
    st[n, ROW_MR + 0] = m.re[0, 0]
    st[n, ROW_MR + 1] = m.re[0, 1]
    st[n, ROW_MR + 2] = m.re[1, 0]
    st[n, ROW_MR + 3] = m.re[1, 1]
    st[n, ROW_MI + 0] = m.im[0, 0]
    st[n, ROW_MI + 1] = m.im[0, 1]
    st[n, ROW_MI + 2] = m.im[1, 0]
    st[n, ROW_MI + 3] = m.im[1, 1]
    return st


@wp.func
def write_row(
    st: Any,
    n: int,
    o: wp.vec3f,
    d: wp.vec3f,
    b: wp.vec3f,
    m: Jones,
    w: float,
    inside: int,
    depth: int,
    mode: int,
    wn: wp.vec3f,
):
    for c in range(3):
        st[n, ROW_O + c] = o[c]
        st[n, ROW_D + c] = d[c]
        st[n, ROW_B + c] = b[c]
        st[n, ROW_WN + c] = wn[c]
    st = write_jones(st, n, m)
    st[n, ROW_W] = w
    st[n, ROW_IN] = float(inside)
    st[n, ROW_DEPTH] = float(depth)
    st[n, ROW_MODE] = float(mode)
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
    r.o = wp.vec3f(st[n, ROW_O], st[n, ROW_O + 1], st[n, ROW_O + 2])
    r.d = wp.vec3f(st[n, ROW_D], st[n, ROW_D + 1], st[n, ROW_D + 2])
    r.b = wp.vec3f(st[n, ROW_B], st[n, ROW_B + 1], st[n, ROW_B + 2])
    r.wn = wp.vec3f(st[n, ROW_WN], st[n, ROW_WN + 1], st[n, ROW_WN + 2])
    m = Jones()
    m.re = wp.mat22(st[n, ROW_MR], st[n, ROW_MR + 1], st[n, ROW_MR + 2], st[n, ROW_MR + 3])
    m.im = wp.mat22(st[n, ROW_MI], st[n, ROW_MI + 1], st[n, ROW_MI + 2], st[n, ROW_MI + 3])
    r.m = m
    r.w = st[n, ROW_W]
    r.inside = int(st[n, ROW_IN])
    r.depth = int(st[n, ROW_DEPTH])
    r.mode = int(st[n, ROW_MODE])
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
def parent_in_sp(m: Jones, k_out: wp.vec3f, parent_x: wp.vec3f, s: wp.vec3f):
    """M_parent . B, with B turning the s/p frame of the outgoing wave (``k_out``, ``s``) into the
    parent's frame (x = ``parent_x``): what every child of one event starts from, so an event
    computes it once, not once per child."""
    return jones_mul(m, jones_real(frame_change(k_out, s, parent_x)))


@wp.func
def child_jones_sp(mb: Jones, a_s: wp.vec2f, a_p: wp.vec2f, scale: float):
    """Jones matrix of a child across an interface, backward (Guy & Soler 2004 eq. 12 from the
    eye): (M_parent . B) . diag(a_s, a_p) * scale, ``mb`` = :func:`parent_in_sp`."""
    return jones_scale(jones_mul(mb, jones_diag(a_s, a_p)), scale)


@wp.func
def pick_child(energies: wp.vec4f, count: int, u: float):
    """Index of the child chosen with probability energies[k] / sum, for ``u`` uniform in
    [0, sum): the first k whose running sum exceeds u (the last child takes round-off)."""
    k = int(0)
    acc = energies[0]
    while k < count - 1 and u >= acc:
        k += 1
        acc += energies[k]
    return k


@wp.func
def roulette(e: float, threshold: float, u: float):
    """Russian roulette on a branch of energy ``e``: (survives, weight factor).  Below
    ``threshold`` the branch survives with probability e / threshold and is then weighted by its
    inverse, which keeps the estimate unbiased; above it nothing changes."""
    if e >= threshold:
        return 1, 1.0
    q = e / threshold
    if u >= q:
        return 0, 0.0
    return 1, 1.0 / q


@wp.func
def add_child(
    cand: Any,
    energies: wp.vec4f,
    count: int,
    o: wp.vec3f,
    d: wp.vec3f,
    b: wp.vec3f,
    m: Jones,
    w: float,
    inside: int,
    depth: int,
    mode: int,
    wn: wp.vec3f,
):
    """Append a backward child as row ``count`` of ``cand`` with its energy (:func:`branch_energy`)
    if it carries any; returns (cand, energies, count).  The row is written either way (a child
    without energy is overwritten by the next one or lies beyond ``count``): a conditional write
    would make the compiled code select between two copies of the whole candidate matrix."""
    e = branch_energy(m, w)
    row = wp.min(count, 3)  # an event has at most 4 children (2 reflected, 2 refracted waves)
    cand = write_row(cand, row, o, d, b, m, w, inside, depth, mode, wn)
    energies[row] = e
    if e > 0.0:
        count = row + 1
    return cand, energies, count
