"""Meshes from files (OBJ, STL, PLY, GLB/GLTF, OFF) via trimesh, validated for ray tracing.

A mesh enters the renderer as a closed surface with outward normals, in millimetres.  Validation
rejects, with an :class:`~warpoptics.errors.InputError` naming the file and what is wrong:

- no faces, non-finite coordinates;
- degenerate (zero-area) faces;
- inconsistent winding (adjacent faces oriented oppositely);
- not watertight (open boundary edges or non-manifold edges);
- inverted (consistent winding, but the normals point inwards: negative volume);
- a surface that passes through itself (two triangles that cross, with a witness;
  :mod:`warpoptics.geometry.self_intersection`);
- a size outside the one size rule of every object (:func:`size_problem`: largest extent in
  ``[SIZE_MIN, SIZE_MAX]`` mm; e.g. a model in metres).

``repair=True`` opts in to fixes (merge duplicate vertices, drop degenerate faces, make the
winding consistent, fan-fill boundary loops, invert an inside-out mesh); anything still wrong is
an error.  Scale is never
guessed: pass ``scale`` (e.g. 1000 for a model in metres).

:func:`facet_planes` groups coplanar faces into facets (planes ``[n, d]``, outward ``n``), which
the convex ray-query path uses; the cuts of :mod:`warpoptics.geometry.cuts` carry theirs.
"""

from __future__ import annotations

import os

import numpy as np
import trimesh

from ..errors import InputError
from .self_intersection import self_intersection

__all__ = [
    "SUPPORTED_EXTENSIONS",
    "SIZE_MIN",
    "SIZE_MAX",
    "SIZE_ALLOWED",
    "load_mesh",
    "validate_mesh",
    "facet_planes",
    "facet_neighbours",
    "scale_problem",
    "size_problem",
]

#: the range of object sizes (largest world extent, mm) the tracers serve: below 0.1 um, a
#: fraction of a wavelength, geometric optics does not apply; 100 m is the largest scene
SIZE_MIN = 1.0e-4
SIZE_MAX = 1.0e5
#: float32 spacing at an object's farthest coordinate must stay below this fraction of its size
#: (about 16,000 sizes from the origin: a 6.5 mm stone up to x ~ 1.1e5 mm)
SPACING_MAX = 2.0e-3


#: the ``allowed`` part of every size error (InputError), for meshes, cuts and GemCAD designs alike
SIZE_ALLOWED = f"largest extent in [{SIZE_MIN:g}, {SIZE_MAX:g}] mm"


def size_problem(size: float) -> str | None:
    """Why an object of largest extent ``size`` (mm) is out of the tracers' range, or None: the one
    size rule; callers raise it as an InputError with the field that sets the size, its value and
    ``allowed=SIZE_ALLOWED``."""
    if SIZE_MIN <= size <= SIZE_MAX:
        return None
    return (
        f"object size {size:.4g} mm (largest extent) out of range: below 0.1 um geometric optics does "
        "not apply; lengths are in mm (a model in metres needs scale = 1000, in cm scale = 10)"
    )


def scale_problem(size: float, far: float) -> str | None:
    """Why an object of largest world extent ``size`` (mm) whose farthest coordinate is ``far``
    (max |x|, mm) cannot be traced accurately in float32, or None: :func:`size_problem`, then the
    placement.  The one rule for every shape (cuts, meshes, GemCAD designs) and placement; within
    it the tracers offset ray origins relative to the object (``geometry.query.offset_epsilon``)
    and a stone renders as the same stone at reference size."""
    why = size_problem(size)
    if why is not None:
        return why
    spacing = far * float(np.finfo(np.float32).eps)
    if spacing > SPACING_MAX * size:
        return (
            f"the object lies {far:.4g} mm from the origin, {far / size:.3g} times its size: float32 "
            f"coordinates there are {spacing / size:.2%} of the object (at most {SPACING_MAX:.1%}, "
            f"{SPACING_MAX / float(np.finfo(np.float32).eps):.3g} sizes); move the scene toward the origin"
        )
    return None


SUPPORTED_EXTENSIONS = (".obj", ".stl", ".ply", ".glb", ".gltf", ".off")


def load_mesh(
    path: str | os.PathLike,
    *,
    scale: float = 1.0,
    repair: bool = False,
    check_size: bool = True,
    closed: bool = True,
) -> trimesh.Trimesh:
    """Load a triangle mesh (mm after multiplying by ``scale``) and validate it (see module doc).
    ``check_size=False`` leaves the size rule to the caller (a scene checks it on the object's world
    size, after its ``scale``: ``pipelines.objects``).

    Scenes with several meshes (GLB) are concatenated into one solid in world coordinates.
    ``closed=False`` accepts open surfaces (thin shells and film surfaces, ``stages.coated``):
    no watertightness or volume check.
    """
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext not in SUPPORTED_EXTENSIONS:
        raise InputError(
            "unsupported mesh format",
            file=path,
            value=ext or "(none)",
            allowed=", ".join(SUPPORTED_EXTENSIONS),
        )
    if not os.path.isfile(path):
        raise InputError("no such file", file=path)
    try:
        # process=False first: processing drops NaN vertices, which would then be reported as
        # "not watertight" instead of what they are
        loaded = trimesh.load(path, force="mesh", process=False, validate=False)
    except Exception as exc:  # trimesh raises many types for bad files
        raise InputError(f"cannot read mesh: not a valid {ext} file ({exc})", file=path) from exc
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise InputError("the file holds no triangle mesh", file=path)
    bad = ~np.isfinite(loaded.vertices).all(axis=1)
    if bad.any():
        raise InputError(
            f"{int(bad.sum())} vertex(es) with non-finite coordinates, "
            f"e.g. vertex {int(np.flatnonzero(bad)[0])}",
            file=path,
        )
    loaded.process(validate=False)
    if scale != 1.0:
        if not np.isfinite(scale) or scale <= 0:
            raise InputError("scale must be a positive number", field="scale", value=scale)
        loaded.apply_scale(float(scale))
    if check_size:
        size = float(np.max(loaded.extents))
        why = size_problem(size)
        if why is not None:
            raise InputError(why, file=path, field="scale", value=scale, allowed=SIZE_ALLOWED)
    return validate_mesh(loaded, name=path, repair=repair, check_size=False, closed=closed)


def validate_mesh(
    mesh: trimesh.Trimesh,
    *,
    name: str | None = None,
    repair: bool = False,
    check_size: bool = True,
    closed: bool = True,
) -> trimesh.Trimesh:
    """Check (and with ``repair`` fix, on a copy) a mesh for ray tracing; return the mesh to use.
    ``closed=False``: an open surface (no watertightness or volume check); ``check_size=False``:
    the caller applies the size rule (:func:`size_problem`)."""
    if not isinstance(mesh, trimesh.Trimesh):
        raise InputError("not a triangle mesh", file=name, value=type(mesh).__name__)
    if len(mesh.faces) == 0:
        raise InputError("the mesh has no faces", file=name)
    if not np.all(np.isfinite(mesh.vertices)):
        raise InputError("the mesh has non-finite vertex coordinates", file=name)
    size = float(np.max(mesh.extents))
    why = size_problem(size) if check_size else None
    if why is not None:
        raise InputError(why, file=name, field="size", value=size, allowed=SIZE_ALLOWED)
    if not size > 0.0:
        raise InputError("the mesh has no extent (all vertices coincide)", file=name)
    if repair:
        mesh = mesh.copy()
        mesh.merge_vertices()
    area_tol = (1e-9 * size) ** 2  # far below any real face, far above float64 round-off
    degenerate = mesh.area_faces <= area_tol
    if np.any(degenerate):
        if not repair:
            raise InputError(
                f"{int(degenerate.sum())} degenerate (zero-area) face(s), e.g. face "
                f"{int(np.flatnonzero(degenerate)[0])} (use repair to drop them)",
                file=name,
            )
        mesh.update_faces(~degenerate)
        mesh.remove_unreferenced_vertices()
    if not mesh.is_winding_consistent:
        if not repair:
            raise InputError(
                "inconsistent winding: adjacent faces are oriented oppositely (use repair)", file=name
            )
        mesh = _fix_winding(mesh)
    if not closed:
        _refuse_self_intersection(mesh, name)
        return mesh
    if not mesh.is_watertight:
        if not repair:
            raise InputError(
                "not watertight: the surface has open or non-manifold edges; a refracting "
                "solid must be closed (use repair to fill small holes)",
                file=name,
            )
        mesh = _fill_holes(mesh)
        if not mesh.is_watertight:
            raise InputError("not watertight, and repair could not close it", file=name)
        if not mesh.is_winding_consistent:
            mesh = _fix_winding(mesh)
    if mesh.volume < 0:
        if not repair:
            raise InputError(
                "inverted: the normals point into the solid (negative volume; use repair)", file=name
            )
        mesh.invert()
    if not repair and not mesh.is_winding_consistent:  # pragma: no cover - defensive
        raise InputError("inconsistent winding", file=name)
    _refuse_self_intersection(mesh, name)
    return mesh


def _refuse_self_intersection(mesh: trimesh.Trimesh, name: str | None) -> None:
    """InputError with a witness (two triangles and a point they share) when the surface of
    ``mesh`` passes through itself (``self_intersection``; repair does not fix it)."""
    cross = self_intersection(mesh)
    if cross is None:
        return
    x = ", ".join(f"{v:.6g}" for v in cross.point)
    raise InputError(
        f"the surface intersects itself: triangles {cross.edge_face} and {cross.face} cross at "
        f"({x}) mm; a refracting solid must not pass through itself (split it into separate objects, "
        "nested or apart)",
        file=name,
    )


def _edge_direction(face: np.ndarray, a: int, b: int) -> int:
    """+1 if the face runs a -> b, -1 if b -> a."""
    i = int(np.flatnonzero(face == a)[0])
    return 1 if face[(i + 1) % 3] == b else -1


def _fix_winding(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Flip faces so that every pair of edge-adjacent faces runs their shared edge in opposite
    directions (breadth-first over each connected component, its first face kept)."""
    from collections import deque

    faces = np.asarray(mesh.faces).copy()
    nf = len(faces)
    neighbours: list[list[tuple[int, int, int]]] = [[] for _ in range(nf)]
    for (f, g), (a, b) in zip(mesh.face_adjacency, mesh.face_adjacency_edges, strict=True):
        neighbours[f].append((int(g), int(a), int(b)))
        neighbours[g].append((int(f), int(a), int(b)))
    flip = np.zeros(nf, dtype=bool)
    seen = np.zeros(nf, dtype=bool)
    for seed in range(nf):
        if seen[seed]:
            continue
        seen[seed] = True
        queue = deque([seed])
        while queue:
            f = queue.popleft()
            for g, a, b in neighbours[f]:
                if seen[g]:
                    continue
                df = _edge_direction(faces[f], a, b) * (-1 if flip[f] else 1)
                flip[g] = df * _edge_direction(faces[g], a, b) == 1
                seen[g] = True
                queue.append(g)
    faces[flip] = faces[flip][:, ::-1]
    return trimesh.Trimesh(mesh.vertices, faces, process=False)


def _fill_holes(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """Close each boundary loop with a fan of triangles wound like its neighbours (small holes)."""
    edges = mesh.edges  # directed, three per face
    key = np.sort(edges, axis=1)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    boundary = edges[counts[inv.ravel()] == 1]
    nxt: dict[int, int] = {}
    for a, b in boundary:
        if int(a) in nxt:  # a vertex starting two boundary edges: non-manifold, leave it
            return mesh
        nxt[int(a)] = int(b)
    new_faces = []
    seen: set[int] = set()
    for start in list(nxt):
        if start in seen:
            continue
        loop = [start]
        seen.add(start)
        v = nxt[start]
        while v != start:
            if v in seen or v not in nxt:
                return mesh
            loop.append(v)
            seen.add(v)
            v = nxt[v]
        # existing faces traverse the loop forwards; the patch traverses it backwards
        for i in range(1, len(loop) - 1):
            new_faces.append([loop[0], loop[i + 1], loop[i]])
    if not new_faces:
        return mesh
    return trimesh.Trimesh(mesh.vertices, np.vstack([mesh.faces, new_faces]), process=False)


def facet_planes(mesh: trimesh.Trimesh, *, angle_tol: float = 1e-5) -> tuple[np.ndarray, np.ndarray]:
    """Facet planes of a mesh and the facet of each face.

    Returns ``planes`` (K, 4) float64 rows ``[nx, ny, nz, d]`` (unit outward normal, ``n . x = d``
    on the facet) and ``face_facet`` (F,) int64.  Uses ``mesh.metadata`` when it carries them
    (cuts and GemCAD designs), else groups edge-adjacent faces into facets when their normals
    differ by less than ``angle_tol`` radians or the smaller one's third vertex lies within
    ``angle_tol`` times the mesh size of the larger one's plane (1e-5: above float32 round-off of
    files, far below the degrees between the facets of a gem); the facet normal is the
    area-weighted mean, so slivers do not tilt it.
    """
    md = mesh.metadata
    if "planes" in md and "face_facet" in md and len(md["face_facet"]) == len(mesh.faces):
        return np.asarray(md["planes"], dtype=np.float64), np.asarray(md["face_facet"], dtype=np.int64)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    nf = len(mesh.faces)
    adj = mesh.face_adjacency
    # coplanar by plane, not by triangle normals: a sliver triangle (three nearly collinear
    # vertices of a real design, its normal noise) lies in its neighbour's plane although its own
    # normal is far off; test the unshared vertex of the smaller face against the larger's plane
    area = mesh.area_faces
    big = np.where(area[adj[:, 0]] >= area[adj[:, 1]], 0, 1)
    rows = np.arange(len(adj))
    f_big, f_small = adj[rows, big], adj[rows, 1 - big]
    unshared = mesh.face_adjacency_unshared[rows, 1 - big]
    off = np.einsum(
        "ij,ij->i", mesh.vertices[unshared] - mesh.vertices[mesh.faces[f_big, 0]], mesh.face_normals[f_big]
    )
    size = float(np.max(mesh.extents)) if len(mesh.vertices) else 1.0
    in_plane = (np.abs(off) < angle_tol * size) & (
        np.einsum("ij,ij->i", mesh.face_normals[f_big], mesh.face_normals[f_small]) > 0  # not a fold
    )
    same = adj[(mesh.face_adjacency_angles < angle_tol) | in_plane]
    graph = coo_matrix((np.ones(len(same)), (same[:, 0], same[:, 1])), shape=(nf, nf))
    k, face_facet = connected_components(graph, directed=False)
    face_facet = face_facet.astype(np.int64)
    normals = np.zeros((k, 3))
    np.add.at(normals, face_facet, mesh.face_normals * mesh.area_faces[:, None])
    length = np.linalg.norm(normals, axis=1)
    length[length == 0] = 1.0
    normals /= length[:, None]
    # d: area-weighted mean of n . centroid over the facet's faces
    dsum = np.zeros(k)
    asum = np.zeros(k)
    np.add.at(
        dsum, face_facet, np.einsum("ij,ij->i", normals[face_facet], mesh.triangles_center) * mesh.area_faces
    )
    np.add.at(asum, face_facet, mesh.area_faces)
    asum[asum == 0] = 1.0
    planes = np.column_stack([normals, dsum / asum])
    return planes, face_facet


def facet_neighbours(
    mesh: trimesh.Trimesh, face_facet: np.ndarray, count: int
) -> tuple[np.ndarray, np.ndarray]:
    """The edge neighbours of every facet: ``(start, index)``, the facets sharing a mesh edge with
    facet f being ``index[start[f] : start[f + 1]]`` (``count`` facets, ``face_facet`` from
    :func:`facet_planes`).  In a closed convex solid a facet is the part of its plane inside its
    edge neighbours' planes (a convex polygon is the intersection of its edges' half-planes), which
    is what ``geometry.query.convex_exit_near`` tests."""
    ff = np.asarray(face_facet, dtype=np.int64)
    adj = np.asarray(mesh.face_adjacency, dtype=np.int64).reshape(-1, 2)
    fa, fb = ff[adj[:, 0]], ff[adj[:, 1]]
    keep = fa != fb
    pairs = np.concatenate([np.stack([fa[keep], fb[keep]], 1), np.stack([fb[keep], fa[keep]], 1)])
    pairs = np.unique(pairs, axis=0) if len(pairs) else np.zeros((0, 2), np.int64)
    start = np.zeros(count + 1, dtype=np.int64)
    np.add.at(start, pairs[:, 0] + 1, 1)
    return np.cumsum(start), pairs[:, 1].copy()
