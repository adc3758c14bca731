"""Nesting of solids: which solid contains which, and the refusal of solids that partly overlap.

A stone in water, in a glass, or an inclusion in a stone is a solid wholly inside another.  The
tracers follow such scenes with one table: ``parent[k]``, the innermost solid containing solid k
(-1: the ambient medium).  A ray in solid k that meets k's surface leaves into ``parent[k]``; one
that meets the surface of a solid nested in k enters it (``geometry.query.medium_closest_hit``).
Since solids only nest or stay apart, the medium stack of a ray — k, parent[k], parent[parent[k]],
... — is fixed by the solid it is in, so a path row carries only that solid (no per-row stack),
and the index ratio at every interface is that of the two media on its sides.

:func:`object_parents` finds the table, in world space:

1. candidate pairs: objects whose world bounding boxes overlap (a uniform grid of the typical
   box size, large containers tested against all; disjoint instances cost O(n log n));
2. crossing surfaces: two closed triangle surfaces intersect iff an edge of one pierces a
   triangle of the other (for triangles in general position), so every edge of either mesh is
   cast as a segment against the other (``query.GeometryScene.closest_hit``, BVH); a crossing
   strictly inside a segment means the solids partly overlap: refused with both objects named;
3. containment of the pairs that do not cross: the generalized winding number of the outer
   closed mesh at face centres of the inner one, a hair inward (van Oosterom & Strackee 1983,
   the solid angle of a triangle; Jacobson et al. 2013): 1 inside, 0 outside.  Coincident
   solids (each inside the other: a stone given twice) contain neither; the light meets one.

Surfaces that only touch (a vertex or an edge on the other surface) do not count as crossing.
A mesh that intersects itself is refused when it is loaded (``geometry.self_intersection``).

References:
    van Oosterom, A., Strackee, J. 1983. The solid angle of a plane triangle. IEEE Trans. Biomed.
        Eng. 30(2), 125-126.
    Jacobson, A., Kavan, L., Sorkine-Hornung, O. 2013. Robust inside-outside segmentation using
        generalized winding numbers. ACM TOG 32(4).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import trimesh

from .query import GeometryScene

__all__ = ["OverlapError", "object_parents", "point_medium", "winding_number", "world_boxes"]

# a crossing closer than this (relative segment parameter) to an end of an edge is a touch
_TOUCH = 1.0e-6
# face centres of the inner mesh at which the winding number of the outer one is evaluated
_SAMPLES = 16
# how far (relative to the mesh's size) those samples are moved inward, off the surface
_INWARD = 1.0e-6


class OverlapError(ValueError):
    """Two solids that partly overlap: ``first`` and ``second`` are their indices."""

    def __init__(self, message: str, first: int, second: int) -> None:
        super().__init__(message)
        self.first = first
        self.second = second


def winding_number(mesh: trimesh.Trimesh, points: np.ndarray) -> np.ndarray:
    """Generalized winding number of the closed ``mesh`` at ``points`` (m, 3), same frame: the sum
    of the signed solid angles of its triangles over 4 pi (1 inside, 0 outside, 1/2 on the
    surface; van Oosterom & Strackee 1983)."""
    tri = np.asarray(mesh.vertices, dtype=np.float64)[np.asarray(mesh.faces)]
    out = np.empty(len(points))
    for i, p in enumerate(np.asarray(points, dtype=np.float64)):
        a, b, c = (tri[:, k] - p for k in range(3))
        la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
        num = np.einsum("ij,ij->i", a, np.cross(b, c))
        den = (
            la * lb * lc
            + np.einsum("ij,ij->i", a, b) * lc
            + np.einsum("ij,ij->i", a, c) * lb
            + np.einsum("ij,ij->i", b, c) * la
        )
        out[i] = np.sum(2.0 * np.arctan2(num, den)) / (4.0 * np.pi)
    return out


def world_boxes(objects: Sequence[tuple[trimesh.Trimesh, np.ndarray]]):
    """World bounding boxes (lo, hi), (n, 3) each, of meshes with object-to-world transforms (the
    box of each mesh's transformed box corners)."""
    local: dict[int, np.ndarray] = {}
    corners = np.empty((len(objects), 8, 3))
    xfs = np.empty((len(objects), 4, 4))
    for i, (mesh, xf) in enumerate(objects):
        key = id(mesh)
        if key not in local:
            lo, hi = np.asarray(mesh.bounds, dtype=np.float64)
            local[key] = np.array([[(lo, hi)[(k >> a) & 1][a] for a in range(3)] for k in range(8)])
        corners[i] = local[key]
        xfs[i] = xf
    w = np.einsum("nij,nkj->nki", xfs[:, :3, :3], corners) + xfs[:, None, :3, 3]
    return w.min(axis=1), w.max(axis=1)


def _box_pairs(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Pairs (i, j), i < j, of boxes that overlap or touch (k, 2), vectorized: boxes much larger
    than the typical one (a tank around stones) are tested against all; the others go into the
    cells of a uniform grid of the typical size, and only boxes sharing a cell are compared.
    Disjoint instances (100,000 stones on a table) cost O(n log n)."""
    n = len(lo)
    ext = (hi - lo).max(axis=1)
    cell = max(float(np.median(ext)), 1e-30)
    big = ext > 2.0 * cell
    pairs = []
    for b in np.flatnonzero(big):
        hit = np.flatnonzero(np.all((lo[b] <= hi) & (lo <= hi[b]), axis=1))
        hit = hit[hit != b]
        pairs.append(np.stack([np.full(len(hit), b), hit], axis=1))
    small = np.flatnonzero(~big)
    if len(small) > 1:
        c_lo = np.floor(lo[small] / cell).astype(np.int64)
        c_hi = np.floor(hi[small] / cell).astype(np.int64)
        keys, owners = [], []
        for off in np.ndindex(3, 3, 3):  # a small box spans at most 3 cells per axis
            c = c_lo + np.array(off)
            ok = np.all(c <= c_hi, axis=1)
            keys.append(c[ok])
            owners.append(small[ok])
        key = np.concatenate(keys)
        owner = np.concatenate(owners)
        order = np.lexsort(key.T[::-1])
        key, owner = key[order], owner[order]
        new_cell = np.ones(len(key), dtype=bool)
        new_cell[1:] = np.any(key[1:] != key[:-1], axis=1)
        starts = np.flatnonzero(new_cell)
        sizes = np.diff(np.append(starts, len(key)))
        # every entry with each later entry of its cell
        cnt = np.repeat(starts + sizes, sizes) - np.arange(len(key)) - 1
        first = np.repeat(np.arange(len(key)), cnt)
        second = first + 1 + np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        pairs.append(np.stack([owner[first], owner[second]], axis=1))
    if not pairs:
        return np.zeros((0, 2), dtype=np.int64)
    ij = np.concatenate(pairs).astype(np.int64)
    ij = np.sort(ij, axis=1)
    ij = np.unique(ij[:, 0] * n + ij[:, 1])
    i, j = ij // n, ij % n
    keep = np.all((lo[i] <= hi[j]) & (lo[j] <= hi[i]), axis=1)
    return np.stack([i[keep], j[keep]], axis=1)


def _edges_cross(edges_world: np.ndarray, target, xf_target: np.ndarray) -> bool:
    """Whether any segment (m, 2, 3), world, crosses the surface of ``target`` (a one-object
    GeometryScene of the mesh in its own frame, placed by ``xf_target``) strictly inside it."""
    inv = np.linalg.inv(xf_target)
    a = edges_world[:, 0] @ inv[:3, :3].T + inv[:3, 3]
    b = edges_world[:, 1] @ inv[:3, :3].T + inv[:3, 3]
    hits = target.closest_hit(a, b - a, 1.0)
    t = hits.t
    return bool(np.any((t > _TOUCH) & (t < 1.0 - _TOUCH)))


def object_parents(
    objects: Sequence[tuple[trimesh.Trimesh, np.ndarray]],
    *,
    solid: Sequence[bool] | None = None,
    device=None,
) -> np.ndarray:
    """The innermost object containing each object (int32 (n,), -1: none) of closed meshes with
    their object-to-world transforms (mm).  Raises :class:`OverlapError` for two objects whose
    surfaces cross (they partly overlap), and where ``solid[k]`` is False (a thin
    shell or a film surface: no volume of its own) for object k inside or around another."""
    n = len(objects)
    parents = np.full(n, -1, dtype=np.int32)
    if n < 2:
        return parents
    lo, hi = world_boxes(objects)
    pairs = _box_pairs(lo, hi)
    if not len(pairs):
        return parents
    scenes: dict[int, GeometryScene] = {}
    edges: dict[int, np.ndarray] = {}

    def scene_of(k: int) -> GeometryScene:
        mesh = objects[k][0]
        if id(mesh) not in scenes:
            scenes[id(mesh)] = GeometryScene([mesh], convex=False, device=device)
        return scenes[id(mesh)]

    def world_edges(k: int) -> np.ndarray:
        if k not in edges:
            mesh, xf = objects[k]
            v = np.asarray(mesh.vertices, dtype=np.float64) @ np.asarray(xf)[:3, :3].T + xf[:3, 3]
            edges[k] = v[np.asarray(mesh.edges_unique)]
        return edges[k]

    def inside(a: int, b: int) -> bool:
        # is a inside closed b?  Only possible when a's box lies in b's.  The samples are face
        # centres of a moved a hair (1e-6 of its size) inward, so that surfaces that touch or
        # coincide are not sampled on b's surface (where the winding number jumps)
        if not objects[b][0].is_watertight:
            return False
        if np.any(lo[a] < lo[b]) or np.any(hi[a] > hi[b]):
            return False
        mesh_a, xf_a = objects[a]
        mesh_b, xf_b = objects[b]
        pick = np.linspace(0, len(mesh_a.faces) - 1, min(len(mesh_a.faces), _SAMPLES)).astype(int)
        v = np.asarray(mesh_a.triangles_center, dtype=np.float64)[pick]
        v = v - np.asarray(mesh_a.face_normals)[pick] * (_INWARD * float(mesh_a.scale))
        v = v @ np.asarray(xf_a)[:3, :3].T + xf_a[:3, 3]
        inv = np.linalg.inv(xf_b)
        w = winding_number(mesh_b, v @ inv[:3, :3].T + inv[:3, 3])
        return bool(np.median(w) > 0.5)

    containers: list[list[int]] = [[] for _ in range(n)]
    for i, j in pairs:
        i, j = int(i), int(j)
        if _edges_cross(world_edges(i), scene_of(j), objects[j][1]) or _edges_cross(
            world_edges(j), scene_of(i), objects[i][1]
        ):
            raise OverlapError(f"the surfaces of object.{i} and object.{j} intersect", i, j)
        i_in_j, j_in_i = inside(i, j), inside(j, i)
        if i_in_j and j_in_i:
            # coincident solids (a stone given twice): neither contains the other; the ray
            # queries resolve their tied faces the same way every time, so the light meets one
            # of them (tests/test_physical_edge_cases.py: the one-stone image, byte for byte)
            continue
        if solid is not None and (i_in_j or j_in_i) and not (solid[i] and solid[j]):
            a, b = (i, j) if i_in_j else (j, i)
            raise OverlapError(
                f"object.{a} lies inside object.{b}: only solids nest (not a thin shell or a film surface)",
                a,
                b,
            )
        if i_in_j:
            containers[i].append(j)
        elif j_in_i:
            containers[j].append(i)
    for k in range(n):
        if containers[k]:
            # the containers of k nest in one another: the innermost has the most containers
            parents[k] = max(containers[k], key=lambda c: len(containers[c]))
    return parents


def point_medium(objects: Sequence[tuple[trimesh.Trimesh, np.ndarray]], parents: np.ndarray, point) -> int:
    """The innermost solid containing the world ``point`` (mm), -1 for the ambient medium: where a
    camera inside a solid (in water, in a glass) starts its rays.  ``parents`` from
    :func:`object_parents`."""
    x = np.asarray(point, dtype=np.float64).reshape(3)
    if not len(objects):
        return -1
    lo, hi = world_boxes(objects)
    best, best_depth = -1, -1
    for k in np.flatnonzero(np.all((lo <= x) & (x <= hi), axis=1)):
        mesh, xf = objects[int(k)]
        if not mesh.is_watertight:
            continue
        inv = np.linalg.inv(xf)
        if winding_number(mesh, (inv[:3, :3] @ x + inv[:3, 3])[None])[0] > 0.5:
            depth, j = 0, int(k)
            while parents[j] >= 0:
                depth, j = depth + 1, int(parents[j])
            if depth > best_depth:
                best, best_depth = int(k), depth
    return best
