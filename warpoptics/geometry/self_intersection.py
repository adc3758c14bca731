"""Self-intersection of a triangle mesh: does its surface pass through itself?

A refracting solid whose surface crosses itself (two interpenetrating parts merged into one file,
a vertex pushed through the opposite face) has no consistent inside: the tracers would follow
rays through it silently wrong.  :func:`self_intersection` finds a witness: two triangles that
intersect and a point they share.

Two triangles in general position intersect iff an edge of one crosses the other (the segment
and the triangle meet at a point strictly inside both).  So every edge of the mesh is tested
against the triangles whose bounding boxes its own box overlaps (``wp.mesh_query_aabb`` on the
mesh's BVH), skipping the triangles that share a vertex with the edge (its own faces and the fan
around its ends, which meet it at that vertex by construction).  The test is in float64 with a
margin: the edge's ends must lie on opposite sides of the triangle's plane, and the crossing
point inside the triangle, by more than ``TOUCH`` times the mesh size, so surfaces that only
touch (a vertex or an edge on a face, coplanar faces) do not count.  The cost is about
one BVH box query per edge: O(E log F).

Not detected (degenerate, not general position): two triangles that share a vertex and overlap
in one plane (a face folded flat onto its neighbour).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import trimesh
import warp as wp

from ..device import get_device, launch_tiled

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = ["TOUCH", "Crossing", "self_intersection"]

#: a crossing nearer than this (times the mesh's largest extent) to the triangle's plane or edges
#: is a touch, not a crossing: well above float32 round-off of mesh files (6e-8), far below any
#: real feature of a stone
TOUCH = 1.0e-6


class Crossing(NamedTuple):
    """A witness of a self-intersection: triangle ``edge_face`` (one whose edge crosses) and
    triangle ``face`` meet at ``point`` (mesh frame, mm)."""

    edge_face: int
    face: int
    point: np.ndarray


@wp.func
def _side(a: wp.vec3d, b: wp.vec3d, x: wp.vec3d, n: wp.vec3d):
    # signed distance of x from the line a-b, within the plane of unit normal n (> 0: inward for a
    # triangle wound counter-clockwise about n)
    e = b - a
    return wp.dot(wp.cross(e, x - a), n) / wp.length(e)


@wp.func
def _shares_vertex(tri: wp.vec3i, ia: wp.int32, ib: wp.int32):
    return tri[0] == ia or tri[1] == ia or tri[2] == ia or tri[0] == ib or tri[1] == ib or tri[2] == ib


@wp.kernel
def _edge_crossings(
    offset: int,
    mesh: wp.uint64,
    points: wp.array(dtype=wp.vec3d),
    faces: wp.array(dtype=wp.vec3i),
    edges: wp.array(dtype=wp.vec2i),
    pad: float,
    tol: wp.float64,
    out_face: wp.array(dtype=wp.int32),
    out_point: wp.array(dtype=wp.vec3d),
):
    e = wp.tid() + offset
    ia = edges[e][0]
    ib = edges[e][1]
    p = points[ia]
    q = points[ib]
    lo = wp.vec3f(float(wp.min(p[0], q[0])), float(wp.min(p[1], q[1])), float(wp.min(p[2], q[2])))
    hi = wp.vec3f(float(wp.max(p[0], q[0])), float(wp.max(p[1], q[1])), float(wp.max(p[2], q[2])))
    query = wp.mesh_query_aabb(mesh, lo - wp.vec3f(pad), hi + wp.vec3f(pad))
    f = int(0)
    found = int(-1)
    point = wp.vec3d(0.0)
    while wp.mesh_query_aabb_next(query, f):
        tri = faces[f]
        if not _shares_vertex(tri, ia, ib):
            a = points[tri[0]]
            b = points[tri[1]]
            c = points[tri[2]]
            n = wp.normalize(wp.cross(b - a, c - a))
            dp = wp.dot(n, p - a)
            dq = wp.dot(n, q - a)
            if (dp > tol and dq < -tol) or (dp < -tol and dq > tol):
                x = p + (q - p) * (dp / (dp - dq))
                # on an edge of the triangle counts: two mirror-image parts cross only there
                inside = _side(a, b, x, n) > -tol and _side(b, c, x, n) > -tol and _side(c, a, x, n) > -tol
                # the lowest index: the same witness for any BVH order
                if inside and (found < 0 or f < found):
                    found = f
                    point = x
    out_face[e] = found
    out_point[e] = point


def self_intersection(mesh: trimesh.Trimesh, *, device=None) -> Crossing | None:
    """A witness that ``mesh``'s surface crosses itself (see the module doc), or None.  The mesh
    must have finite vertices and no zero-area faces (``geometry.mesh.validate_mesh``)."""
    dev = get_device(device)
    verts = np.ascontiguousarray(mesh.vertices, dtype=np.float64)
    faces = np.ascontiguousarray(mesh.faces, dtype=np.int32)
    if len(faces) < 2:
        return None
    edges = np.ascontiguousarray(mesh.edges_unique, dtype=np.int32)
    size = float(np.max(np.ptp(verts, axis=0)))
    far = float(np.max(np.abs(verts)))
    bvh = wp.Mesh(
        points=wp.array(verts.astype(np.float32), dtype=wp.vec3f, device=dev),
        indices=wp.array(faces.ravel(), dtype=wp.int32, device=dev),
    )
    out_face = wp.empty(len(edges), dtype=wp.int32, device=dev)
    out_point = wp.empty(len(edges), dtype=wp.vec3d, device=dev)
    # the float32 boxes of the BVH are padded by more than their round-off
    pad = 1.0e-5 * (size + far)
    launch_tiled(
        _edge_crossings,
        len(edges),
        [
            bvh.id,
            wp.array(verts, dtype=wp.vec3d, device=dev),
            wp.array(faces, dtype=wp.vec3i, device=dev),
            wp.array(edges, dtype=wp.vec2i, device=dev),
            pad,
            TOUCH * size,
            out_face,
            out_point,
        ],
        device=dev,
    )
    hit = out_face.numpy()
    crossing = np.flatnonzero(hit >= 0)
    if not len(crossing):
        return None
    e = int(crossing[0])
    # a face of the crossing edge: the first of the directed face edges that is this edge
    edge_face = int(np.flatnonzero(np.asarray(mesh.edges_unique_inverse) == e)[0] // 3)
    return Crossing(edge_face, int(hit[e]), out_point.numpy()[e].copy())
