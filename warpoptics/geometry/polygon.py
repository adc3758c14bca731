"""Beam polygons: a convex polygon of a pixel whose every vertex carries its own ray.

Why.  A pixel's colour is the integral of the light over the pixel.  Sampling points in it
leaves noise wherever a facet edge, seen directly or many reflections deep, falls inside the
pixel (scripts/bench/fire_noise_sources.py: that is most of a diamond's noise).  Beam tracing
(Heckbert & Hanrahan 1984) follows the pixel's footprint instead: a polygon in the pixel's own
coordinates (u, v in [0, 1]^2, so its area IS its fraction of the pixel), each vertex carrying
the ray of the camera through that point of the pixel (a point and a direction), moved along
with it through every reflection and refraction.  Where the vertices' rays meet different
facets the polygon is cut (Sutherland & Hodgman 1974) where the signed difference of two
facets' ray parameters changes sign along an edge, and the new vertex's ray is the linear
interpolation of the edge's two rays.  For an orthographic camera the rays of a pixel are an
affine family (one direction), so the interpolation and the cuts are exact; for a pinhole the
camera's rays are linear in (u, v) until they refract, and afterwards the interpolation is
exact to first order in the pixel's size (ray differentials, Igehy 1999).

What is here: the polygon (:data:`BeamPolygon`, up to :data:`MAX_VERTICES` vertices, columns
u, v, point xyz, direction xyz), its clip by per-vertex signed values
(:func:`clip_by_values`), its area in pixel units (:func:`polygon_area`), a uniform random point
in it (:func:`random_point`), and NumPy wrappers for tests.  The tracer that uses them is
``stages/pixel_beam.py``.

References:
    Heckbert, P., Hanrahan, P. 1984. Beam tracing polygonal objects. SIGGRAPH 84, 119-127.
    Sutherland, I., Hodgman, G. 1974. Reentrant polygon clipping. CACM 17(1), 32-42.
    Igehy, H. 1999. Tracing ray differentials. SIGGRAPH 99, 179-186.
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ..device import get_device

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "MAX_VERTICES",
    "COLS",
    "BeamPolygon",
    "VertexValues",
    "clip_by_values",
    "polygon_area",
    "random_point",
    "clip_polygon",
    "random_points",
]

#: vertices a beam polygon may have (a quad gains at most one per cut; a pixel's parts keep a few)
MAX_VERTICES = 12
#: columns of a vertex: u, v (pixel coordinates), point xyz, direction xyz
COLS = 8
_MAXV = wp.constant(MAX_VERTICES)
_COLS = wp.constant(COLS)
BeamPolygon = wp.types.matrix(shape=(MAX_VERTICES, COLS), dtype=wp.float32)
VertexValues = wp.types.vector(length=MAX_VERTICES, dtype=wp.float32)


@wp.func
def clip_by_values(poly: BeamPolygon, nv: int, s: VertexValues):
    """The part of convex polygon ``poly`` (``nv`` vertices) where the signed value ``s`` (given
    at the vertices, linear along the edges) is >= 0 (Sutherland-Hodgman): ``(polygon, vertex
    count)``.  A crossing vertex interpolates every column of the edge's two vertices.  Vertices
    beyond :data:`MAX_VERTICES` are dropped (the caller checks the areas)."""
    out = BeamPolygon()
    m = int(0)
    if nv == 0:
        return out, 0
    prev = nv - 1
    s_prev = s[prev]
    for i in range(nv):
        s_cur = s[i]
        if (s_cur >= 0.0) != (s_prev >= 0.0):
            a = s_prev / (s_prev - s_cur)
            if m < _MAXV:
                for c in range(_COLS):
                    out[m, c] = poly[prev, c] + (poly[i, c] - poly[prev, c]) * a
                m += 1
        if s_cur >= 0.0:
            if m < _MAXV:
                for c in range(_COLS):
                    out[m, c] = poly[i, c]
                m += 1
        prev = i
        s_prev = s_cur
    return out, m


@wp.func
def polygon_area(poly: BeamPolygon, nv: int):
    """Area in the pixel's (u, v): the polygon's fraction of the pixel (shoelace formula)."""
    a = float(0.0)
    for i in range(nv):
        j = (i + 1) % nv
        a += poly[i, 0] * poly[j, 1] - poly[j, 0] * poly[i, 1]
    return 0.5 * wp.abs(a)


@wp.func
def random_point(poly: BeamPolygon, nv: int, u1: float, u2: float):
    """Barycentric weights (as a VertexValues over the vertices) of the point that ``(u1, u2)``
    in the unit square maps to, uniform in the polygon's (u, v) area: ``u1`` picks a fan
    triangle by area and, rescaled within that triangle's share, with ``u2`` a point in it
    (Turk's square-to-triangle map).  The map keeps area ratios, so stratified or
    low-discrepancy points of the square stay so in the polygon.  Interpolating any column with
    the weights gives its value at that point."""
    w = VertexValues()
    total = polygon_area(poly, nv)
    target = u1 * total
    acc = float(0.0)
    k = int(1)
    at = float(0.0)
    for t in range(1, nv - 1):
        at = 0.5 * wp.abs(
            (poly[t, 0] - poly[0, 0]) * (poly[t + 1, 1] - poly[0, 1])
            - (poly[t + 1, 0] - poly[0, 0]) * (poly[t, 1] - poly[0, 1])
        )
        k = t
        if acc + at >= target:
            break
        acc += at
    # u1's place within the picked triangle's share: uniform again
    s = float(0.0)
    if at > 0.0:
        s = wp.clamp((target - acc) / at, 0.0, 1.0)
    r = wp.sqrt(s)
    w[0] = 1.0 - r
    w[k] = r * (1.0 - u2)
    w[k + 1] = r * u2
    if nv < 3:
        w = VertexValues()
        w[0] = 1.0
    return w


# --- NumPy wrappers (tests) ---------------------------------------------------------------


@wp.kernel
def _clip_kernel(
    polys: wp.array(dtype=BeamPolygon),
    counts: wp.array(dtype=wp.int32),
    a: wp.array(dtype=wp.vec2f),
    b: wp.array(dtype=wp.float32),
    out: wp.array(dtype=BeamPolygon),
    out_counts: wp.array(dtype=wp.int32),
    out_area: wp.array(dtype=wp.float32),
):
    i = wp.tid()
    p = polys[i]
    s = VertexValues()
    for k in range(counts[i]):
        s[k] = a[i][0] * p[k, 0] + a[i][1] * p[k, 1] + b[i]
    q, m = clip_by_values(p, counts[i], s)
    out[i] = q
    out_counts[i] = m
    out_area[i] = polygon_area(q, m)


def clip_polygon(vertices, a, b, device=None) -> tuple[list[np.ndarray], np.ndarray]:
    """Clip beam polygons ``vertices`` (``(n, nv, COLS)`` or one ``(nv, COLS)``: u, v and any
    other columns) to the half-plane ``a . (u, v) + b >= 0`` (one ``a``, ``b`` per polygon or one
    for all) with :func:`clip_by_values`: the clipped vertex lists and their (u, v) areas."""
    dev = get_device(device)
    pts = np.asarray(vertices, dtype=np.float32)
    if pts.ndim == 2:
        pts = pts[None]
    n, nv, cols = pts.shape
    if nv > MAX_VERTICES or cols > COLS:
        raise ValueError(f"a beam polygon has at most {MAX_VERTICES} vertices of {COLS} columns")
    buf = np.zeros((n, MAX_VERTICES, COLS), dtype=np.float32)
    buf[:, :nv, :cols] = pts
    a_np = np.broadcast_to(np.asarray(a, dtype=np.float32), (n, 2)).copy()
    b_np = np.broadcast_to(np.asarray(b, dtype=np.float32), (n,)).copy()
    out = wp.zeros(n, dtype=BeamPolygon, device=dev)
    out_c = wp.zeros(n, dtype=wp.int32, device=dev)
    out_a = wp.zeros(n, dtype=wp.float32, device=dev)
    wp.launch(
        _clip_kernel,
        dim=n,
        inputs=[
            wp.array(buf, dtype=BeamPolygon, device=dev),
            wp.array(np.full(n, nv, dtype=np.int32), dtype=wp.int32, device=dev),
            wp.array(a_np, dtype=wp.vec2f, device=dev),
            wp.array(b_np, dtype=wp.float32, device=dev),
            out,
            out_c,
            out_a,
        ],
        device=dev,
    )
    polys, cs = out.numpy(), out_c.numpy()
    return [polys[i, : cs[i], :cols].copy() for i in range(n)], out_a.numpy()


@wp.kernel
def _point_kernel(poly: BeamPolygon, nv: int, u: wp.array(dtype=wp.vec2f), out: wp.array(dtype=wp.vec2f)):
    i = wp.tid()
    b = random_point(poly, nv, u[i][0], u[i][1])
    x = wp.vec2f(0.0, 0.0)
    for k in range(nv):
        x = x + wp.vec2f(poly[k, 0], poly[k, 1]) * b[k]
    out[i] = x


def random_points(vertices, u, device=None) -> np.ndarray:
    """The (u, v) points :func:`random_point` gives for the points ``u`` of the unit square (``(n, 2)``) in
    the convex polygon ``vertices`` (``(nv, 2)``)."""
    dev = get_device(device)
    pts = np.asarray(vertices, dtype=np.float32)
    buf = np.zeros((MAX_VERTICES, COLS), dtype=np.float32)
    buf[: len(pts), :2] = pts
    u_np = np.asarray(u, dtype=np.float32)
    out = wp.zeros(len(u_np), dtype=wp.vec2f, device=dev)
    wp.launch(
        _point_kernel,
        dim=len(u_np),
        inputs=[BeamPolygon(buf), len(pts), wp.array(u_np, dtype=wp.vec2f, device=dev), out],
        device=dev,
    )
    return out.numpy()
