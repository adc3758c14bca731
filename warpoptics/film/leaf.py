"""The camera film's sink at a path end: light found by a backward path enters the pixel's sums.

A camera path ends at a light — the environment, a lamp, or an opaque surface lit by them — with
``xyz``: the X-, Y- and Z-weighted radiance of that light along the path's last segment.  The
polarized renderer carries the path's Jones matrix ``M`` (light's field on the segment -> field at
the camera, ``stages/trace.py``), so unpolarized light of unit radiance arrives as
``M (I/2) M^dagger`` (Guy & Soler 2004 eq. 12) and light behind a sheet polarizer as ``M K M^dagger``
with ``K`` the polarizer's coherency (``optics/polarizer.py``); the scalar renderer carries the
path's power coefficient ``w`` instead.  :func:`add_leaf` is that one rule, called by every
camera tracer (the per-wavelength tree in ``stages/trace.py`` and the spectral bundles in
``stages/bundle.py``); the coherent mode's amplitude sums are ``stages/coherence.py``'s.
"""

from __future__ import annotations

import warp as wp

from ..optics.jones import Jones, coherency_transform, jones_add, jones_scale
from ..optics.polarizer import sheet_polarizer_coherency

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["add_light", "add_leaf", "add_coherency"]


@wp.func
def add_light(acc_x: Jones, acc_y: Jones, acc_z: Jones, k_unit: Jones, xyz: wp.vec3f):
    """Add light of colour ``xyz`` arriving with coherency ``k_unit`` per unit radiance to the
    X-, Y- and Z-weighted coherency sums."""
    return (
        jones_add(acc_x, jones_scale(k_unit, xyz[0])),
        jones_add(acc_y, jones_scale(k_unit, xyz[1])),
        jones_add(acc_z, jones_scale(k_unit, xyz[2])),
    )


@wp.func
def add_leaf(
    acc_x: Jones,
    acc_y: Jones,
    acc_z: Jones,
    scalar_xyz: wp.vec3f,
    polarized: int,
    m: Jones,
    w: float,
    polarizer: wp.vec3f,
    k: wp.vec3f,
    basis_x: wp.vec3f,
    xyz: wp.vec3f,
):
    """A path end: light of colour ``xyz`` travelling along ``k`` (frame ``basis_x``) — behind a
    sheet polarizer with absorbing axis ``polarizer`` (zero: unpolarized light) — enters the sums
    through the path's Jones matrix ``m`` (polarized renderer) or its power coefficient ``w``
    (scalar renderer).  Returns the updated ``(acc_x, acc_y, acc_z, scalar_xyz)``."""
    if polarized != 0:
        k_unit = coherency_transform(m, sheet_polarizer_coherency(polarizer, k, basis_x, w))
        acc_x, acc_y, acc_z = add_light(acc_x, acc_y, acc_z, k_unit, xyz)
    else:
        scalar_xyz = scalar_xyz + xyz * w
    return acc_x, acc_y, acc_z, scalar_xyz


@wp.func
def add_coherency(
    acc_x: Jones,
    acc_y: Jones,
    acc_z: Jones,
    scalar_xyz: wp.vec3f,
    polarized: int,
    m: Jones,
    w: float,
    c_x: Jones,
    c_y: Jones,
    c_z: Jones,
):
    """A path end whose light is already a coherency (``c_x, c_y, c_z``: the X-, Y- and
    Z-weighted light a camera trace returns, in the frame of the path's last segment): it
    enters the sums as ``w M C M^dagger`` (polarized renderer) or as ``w tr C`` (scalar renderer,
    whose traces return unpolarized coherencies).  Pixel beams continue a part this way by a
    point sample (``stages/pixel_beam.py``)."""
    if polarized != 0:
        acc_x = jones_add(acc_x, coherency_transform(m, jones_scale(c_x, w)))
        acc_y = jones_add(acc_y, coherency_transform(m, jones_scale(c_y, w)))
        acc_z = jones_add(acc_z, coherency_transform(m, jones_scale(c_z, w)))
    else:
        tr = wp.vec3f(c_x.re[0, 0] + c_x.re[1, 1], c_y.re[0, 0] + c_y.re[1, 1], c_z.re[0, 0] + c_z.re[1, 1])
        scalar_xyz = scalar_xyz + tr * w
    return acc_x, acc_y, acc_z, scalar_xyz
