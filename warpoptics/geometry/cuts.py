"""Parametric gem cuts and simple optical solids, as watertight convex triangle meshes.

Every solid here is built the same way: as the intersection of half-spaces ``n . x <= d``
(``n`` the outward unit normal of a facet plane, ``d`` its distance from the origin, in mm),
which makes it convex and closed by construction (:func:`convex_from_planes`).  The mesh keeps
the facet structure in ``mesh.metadata``:

``"planes"``       (K, 4) float64, one row ``[nx, ny, nz, d]`` per facet, outward unit normal
``"facet_names"``  K names ("table", "star 3", "pavilion main 0", ...)
``"face_facet"``   (F,) int64, the facet each triangle belongs to
``"proportions"``  a :class:`Proportions` (gem cuts) or ``None``

Conventions: millimetres, right-handed, z up, normals out of the solid.  Gem cuts have their
girdle centred on the z = 0 plane (crown above, pavilion below); other solids are centred on the
origin, except :func:`ground_plane` whose top face is at ``z``.  Angles are in degrees; facet
angles are measured between the facet and the girdle plane (i.e. between the facet normal and
the z axis), the convention of gem cutters and of GemCAD.

Proportions follow the usual gemological definitions (GIA): crown height, pavilion depth, girdle
thickness and total depth as fractions of the girdle diameter (of the width for fancy shapes);
crown height from the top of the girdle to the table, pavilion depth from the bottom of the
girdle to the culet.  The table of a brilliant is measured corner to corner of its octagon
(through the bezel/main azimuth, the profile of Tolkowsky's derivation).

References
----------
- M. Tolkowsky, *Diamond Design: A Study of the Reflection and Refraction of Light in a Diamond*,
  E. & F. N. Spon, London, 1919 (table 53 %, crown 34.5 deg, pavilion 40.75 deg).
- GIA, *Diamond Grading ABC* / GIA cut-grading system: star length, lower-girdle length,
  girdle thickness and depth definitions.
- S. Guy and C. Soler, "Graphics Gems Revisited", ACM TOG 23(3), 2004 (convex faceted stones).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np
import trimesh

from ..errors import InputError

__all__ = [
    "Proportions",
    "convex_from_planes",
    "open_direction",
    "direction_words",
    "rhomb",
    "rhomb_axis_angle",
    "measure_proportions",
    "round_brilliant",
    "oval",
    "pear",
    "marquise",
    "emerald",
    "princess",
    "step_cut",
    "prism",
    "plate",
    "cube",
    "sphere",
    "ground_plane",
    "wavy_sheet",
    "SHAPES",
]


@dataclasses.dataclass(frozen=True)
class Proportions:
    """Proportions of a cut, lengths in mm, ratios as fractions of ``width``.

    ``width`` is the girdle diameter of a round stone (the smaller girdle extent of a fancy
    shape); ``length`` the larger extent.  ``crown_height`` is from the top of the girdle to the
    table, ``pavilion_depth`` from the bottom of the girdle to the culet (keel), ``girdle`` the
    girdle thickness at its thin points, ``total_depth`` table to culet.  Angles in degrees
    (``None`` where a cut has no single such angle).
    """

    shape: str
    length: float
    width: float
    table: float
    crown_height: float
    pavilion_depth: float
    girdle: float
    total_depth: float
    crown_angle: float | None = None
    pavilion_angle: float | None = None

    def summary(self) -> str:
        """One human-readable block, percentages of the width."""
        lines = [
            f"shape            {self.shape}",
            f"length x width   {self.length:.4g} x {self.width:.4g} mm "
            f"(ratio {self.length / self.width:.3f})",
            f"table            {100 * self.table:.1f} %",
            f"crown height     {100 * self.crown_height:.1f} %",
            f"girdle           {100 * self.girdle:.1f} %",
            f"pavilion depth   {100 * self.pavilion_depth:.1f} %",
            f"total depth      {100 * self.total_depth:.1f} %",
        ]
        if self.crown_angle is not None:
            lines.append(f"crown angle      {self.crown_angle:.2f} deg")
        if self.pavilion_angle is not None:
            lines.append(f"pavilion angle   {self.pavilion_angle:.2f} deg")
        return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# Half-space intersection
# ---------------------------------------------------------------------------------------------


# The largest problem convex_from_planes takes.  Qhull's half-space intersection and the facet
# rings are O(K log K); measured 0.34 s for 1801 planes (600 facets per tier, the test in
# test_gemcad.py) on a shared 2-core machine, i.e. ~0.2 ms per plane: 20000 planes is a few seconds.
# Beyond that the caller gets that estimate instead of a long wait.
MAX_PLANES = 20000


def _plane_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(n, a)
    u /= np.linalg.norm(u)
    v = np.cross(n, u)  # (u, v, n) right-handed: polygons built in (u, v) are CCW about n
    return u, v


def open_direction(normals) -> np.ndarray | None:
    """A unit direction in which ``{x : n_i . x <= d_i}`` runs off to infinity (its recession
    cone ``{v : n_i . v <= 0}`` holds more than 0), or None when the planes close around a
    bounded solid, whatever the offsets.  Six small linear programmes: the largest +-v_k over
    the cone cut to the unit cube."""
    from scipy.optimize import linprog

    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    n = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    for axis in ((0.0, 0.0, -1.0), (0.0, 0.0, 1.0)):  # the usual case, named plainly: down or up
        if np.all(n @ np.array(axis) <= 0.0):
            return np.array(axis)
    for k, sign in ((2, -1.0), (2, 1.0), (0, 1.0), (0, -1.0), (1, 1.0), (1, -1.0)):  # down first
        c = np.zeros(3)
        c[k] = -sign
        res = linprog(c, A_ub=n, b_ub=np.zeros(len(n)), bounds=[(-1.0, 1.0)] * 3, method="highs")
        if res.status == 0 and res.x is not None and -res.fun > 1e-9:
            v = np.asarray(res.x, dtype=np.float64)
            return v / np.linalg.norm(v)
    return None


def direction_words(v) -> str:
    """A direction as words for a message: ``"-z (down)"`` for an axis, else the rounded vector."""
    v = np.asarray(v, dtype=np.float64)
    names = {
        (0, 1): "+x",
        (0, -1): "-x",
        (1, 1): "+y",
        (1, -1): "-y",
        (2, 1): "+z (up)",
        (2, -1): "-z (down)",
    }
    k = int(np.argmax(np.abs(v)))
    if abs(v[k]) > 0.999:
        return names[(k, 1 if v[k] > 0 else -1)]
    return "(" + ", ".join(f"{c:.3f}" for c in v) + ")"


def _interior_point(n: np.ndarray, d: np.ndarray, source) -> tuple[np.ndarray, float]:
    """Chebyshev centre of ``{x : n x <= d}`` (the centre of the largest inscribed ball) and its
    radius, by linear programming; raises if the set is empty, flat or unbounded."""
    from scipy.optimize import linprog

    k = len(n)
    a_ub = np.hstack([n, np.ones((k, 1))])
    # the ball radius is capped so that an unbounded set still gives a finite LP
    cap = 1e6 * float(np.max(np.abs(d)))
    res = linprog(
        c=[0.0, 0.0, 0.0, -1.0],
        A_ub=a_ub,
        b_ub=d,
        bounds=[(None, None)] * 3 + [(0.0, cap)],
        method="highs",
    )
    if res.status != 0 or res.x is None:
        raise InputError("the facet planes enclose no solid", file=source)
    x, r = res.x[:3], float(res.x[3])
    if r >= 0.5 * cap:
        raise InputError(
            "the facet planes do not enclose a bounded solid (is a crown, pavilion or girdle missing?)",
            file=source,
        )
    return x, r


def convex_from_planes(
    normals,
    offsets,
    names: Sequence[str] | None = None,
    *,
    proportions: Proportions | None = None,
    source: str | None = None,
    merge_tol: float = 1e-6,
) -> trimesh.Trimesh:
    """The convex polyhedron ``{x : n_i . x <= d_i for all i}`` as a watertight triangle mesh.

    ``normals`` (K, 3) need not be unit length (they are normalised, ``offsets`` with them).
    Each plane that bounds a face of positive area becomes one facet; redundant planes are
    dropped (their names with them), and so is a facet thinner than ``merge_tol`` times the size
    of the solid (a sliver left by rounded input, which would only give triangles whose normals
    are noise).  Raises :class:`InputError` if the intersection is empty, flat or unbounded, or
    if there are more than :data:`MAX_PLANES` planes.  ``source`` names the input in error
    messages (a file name).  Vertices closer than ``merge_tol`` times the largest plane distance
    are merged: 1e-6 (6.5 nm on a 6.5 mm stone) joins the clusters that rounded input (a .asc
    file's six decimals) makes of a vertex where four or more planes meet; at 1e-7 two such
    points of a real design ("For Fun", PC 46.019) stay apart and the triangle between them tilts
    40 deg off its facet, at 1e-5 merging starts to move vertices visibly (Compear 1:1.25).  An
    edge whose direction the input does not fix (facet planes that nearly share a line, "Astryx
    Star") is collapsed as well, by its ends' planes rather than their distance
    (:func:`_collapse_ill_conditioned_edges`).

    The intersection is Qhull's (``scipy.spatial.HalfspaceIntersection``, Barber, Dobkin &
    Huhdanpaa 1996) from the Chebyshev centre (a linear programme): O(K log K) in the number of
    planes.
    """
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    d = np.asarray(offsets, dtype=np.float64).reshape(-1)
    if len(n) != len(d):
        raise ValueError("normals and offsets differ in length")
    if names is None:
        names = [f"facet {i}" for i in range(len(n))]
    names = list(names)
    if len(n) < 4:
        raise InputError("at least 4 planes are needed to bound a solid", file=source, value=len(n))
    if len(n) > MAX_PLANES:
        raise InputError(
            f"too many facet planes: {len(n)} (about {2e-4 * len(n):.0f} s to build at ~0.2 ms per plane)",
            file=source,
            allowed=f"at most {MAX_PLANES}",
        )
    length = np.linalg.norm(n, axis=1)
    if np.any(length == 0) or not np.all(np.isfinite(n)) or not np.all(np.isfinite(d)):
        raise InputError("a facet plane has a zero or non-finite normal", file=source)
    n = n / length[:, None]
    d = d / length
    scale = float(np.max(np.abs(d)))
    if scale <= 0:
        raise InputError("all facet planes pass through the origin: the solid is empty", file=source)
    way = open_direction(n)
    if way is not None:
        raise InputError(
            f"the facet planes do not close: the solid is open toward {direction_words(way)}, where no "
            "facet faces (is a crown, pavilion or girdle missing?)",
            file=source,
        )
    tol = merge_tol * scale
    active = np.ones(len(n), dtype=bool)
    for _ in range(8):  # dropping a sliver can expose another only rarely; 8 rounds is ample
        result = _intersect(n, d, active, tol, source)
        slivers = result[-1]
        if not slivers:
            break
        active[slivers] = False
    vertices, rings, keep, _ = result

    faces: list[list[int]] = []
    face_facet: list[int] = []
    planes: list[np.ndarray] = []
    facet_names: list[str] = []
    vertices = list(vertices)
    for ring, i in zip(rings, keep, strict=True):
        k = len(planes)
        planes.append(np.array([*n[i], d[i]]))
        facet_names.append(names[i])
        # a fan from the centroid: no triangle is thinner than the polygon's inradius allows, also
        # where the ring has collinear vertices (points of neighbouring facets on this one's edge)
        m = len(ring)
        if m == 3:
            faces.append(list(ring))
            face_facet.append(k)
            continue
        pts = np.array([vertices[x] for x in ring])
        vertices.append(pts.mean(axis=0))
        c = len(vertices) - 1
        for a in range(m):
            faces.append([c, ring[a], ring[(a + 1) % m]])
            face_facet.append(k)

    mesh = trimesh.Trimesh(vertices=np.array(vertices), faces=np.array(faces, dtype=np.int64), process=False)
    if not mesh.is_watertight or mesh.volume <= 0:
        raise InputError("the facet planes did not give a closed solid (degenerate design?)", file=source)
    mesh.metadata["planes"] = np.array(planes)
    mesh.metadata["facet_names"] = facet_names
    mesh.metadata["face_facet"] = np.array(face_facet, dtype=np.int64)
    mesh.metadata["proportions"] = proportions
    return mesh


def _merge_labels(pts: np.ndarray, tol: float) -> tuple[int, np.ndarray]:
    """Clusters of points closer than ``tol`` (transitively): their number and each point's label."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(pts).query_pairs(tol, output_type="ndarray").reshape(-1, 2)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(pts), len(pts)))
    return connected_components(graph, directed=False)


def _root(parent: list[int], x: int) -> int:
    """The representative of ``x`` in a union-find forest (with path halving)."""
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x


def _collapse_ill_conditioned_edges(verts, planes_of, na, da, tol, reach=100.0, max_tilt=1e-4):
    """Merge the two ends of an edge whose direction the input does not determine.

    Where facet planes nearly share a line (a design's meetpoint at which the next tier meets the
    girdle: "Astryx Star", its P1-P3-G1-G2 meet), the distance merge can leave an edge whose ends
    are ``|ab|`` apart (2.2e-5 mm on a 6.5 mm stone, six merge distances) while one end, a merged
    cluster, lies off its planes by its residual ``r`` (here 5e-8 mm, the input's rounding).  A
    triangle on that edge tilts by about ``r / |ab|`` (3e-3 rad): a normal that is noise, and
    ``trimesh``'s ``is_convex`` turns false.  Such an edge (``r / |ab| > max_tilt``; 1e-4 rad,
    where the edges of exact triple points are at 1e-9) is collapsed when the least-squares point
    of the union of its ends' planes lies within ``tol`` of every one of them (the distance merge's
    own criterion) and its ends are closer than ``reach * tol``, so that no vertex moves further
    than a few merge distances.  Returns the new vertices and their plane sets.
    """
    from scipy.spatial import cKDTree

    verts = np.asarray(verts, dtype=np.float64)
    planes_of = [set(p) for p in planes_of]

    def residual(x: np.ndarray, ps: list[int]) -> float:
        return float(np.max(np.abs(na[ps] @ x - da[ps]))) if ps else 0.0

    for _ in range(8):  # a merge can bring a third end within reach only rarely
        pairs = cKDTree(verts).query_pairs(reach * tol, output_type="ndarray").reshape(-1, 2)
        if not len(pairs):
            break
        own = {int(x): residual(verts[x], sorted(planes_of[x])) for x in np.unique(pairs)}
        length = np.linalg.norm(verts[pairs[:, 0]] - verts[pairs[:, 1]], axis=1)
        worst = np.array([max(own[int(a)], own[int(b)]) for a, b in pairs])
        risky = worst > max_tilt * length
        pairs, length = pairs[risky], length[risky]
        parent = list(range(len(verts)))
        merged = False
        for a, b in pairs[np.argsort(length)]:
            ra, rb = _root(parent, int(a)), _root(parent, int(b))
            if ra == rb or len(planes_of[ra] & planes_of[rb]) < 2:
                continue  # the same vertex already, or not the two ends of an edge
            ps = sorted(planes_of[ra] | planes_of[rb])
            sol, _, rank, _ = np.linalg.lstsq(na[ps], da[ps], rcond=None)
            if rank < 3 or residual(sol, ps) > tol:
                continue
            parent[rb] = ra
            planes_of[ra] = set(ps)
            verts[ra] = sol
            merged = True
        if not merged:
            break
        roots = sorted({_root(parent, x) for x in range(len(verts))})
        verts = verts[roots]
        planes_of = [planes_of[r] for r in roots]
    return verts, planes_of


def _intersect(n, d, active, tol, source):
    """Vertices, CCW facet rings (vertex ids), plane index of each ring and the sliver planes of
    the intersection of the ``active`` half-spaces (see :func:`convex_from_planes`).

    Which planes meet at a vertex is Qhull's combinatorics (the dual facets), not a distance test,
    so that neighbouring facets always agree on their shared vertices and the surface is closed.
    """
    from scipy.spatial import HalfspaceIntersection, QhullError

    idx = np.flatnonzero(active)
    na, da = n[idx], d[idx]
    center, radius = _interior_point(na, da, source)
    if radius <= 10 * tol:
        raise InputError("the facet planes enclose no solid (empty or flat)", file=source)
    try:
        hs = HalfspaceIntersection(np.hstack([na, -da[:, None]]), center)
    except QhullError as exc:
        first = str(exc).splitlines()[0]
        raise InputError(f"the facet planes enclose no solid ({first})", file=source) from None

    # Qhull reports a vertex where more than three planes meet once per triangle of its dual (a
    # brilliant's star tips), and rounded input (six decimals) splits such a vertex into a cluster
    # of near-coincident ones: merge them, each cluster lying on the union of its members' planes,
    # at the least-squares point of those planes
    pts = hs.intersections
    nv, label = _merge_labels(pts, tol)
    planes_of: list[set[int]] = [set() for _ in range(nv)]
    for p, dual in enumerate(hs.dual_facets):
        planes_of[label[p]].update(int(j) for j in dual)
    verts = np.zeros((nv, 3))
    np.add.at(verts, label, pts)
    verts /= np.bincount(label, minlength=nv)[:, None]
    for x, ps in enumerate(planes_of):
        ps_list = sorted(ps)
        if len(ps_list) >= 3:
            sol, _, rank, _ = np.linalg.lstsq(na[ps_list], da[ps_list], rcond=None)
            if rank == 3 and np.linalg.norm(sol - verts[x]) < 10 * tol:
                verts[x] = sol
    verts, planes_of = _collapse_ill_conditioned_edges(verts, planes_of, na, da, tol)
    members: list[list[int]] = [[] for _ in range(len(idx))]
    for x, ps in enumerate(planes_of):
        for j in ps:
            members[j].append(x)

    rings, keep, slivers = [], [], []
    for j in range(len(idx)):
        ids = np.array(members[j], dtype=np.int64)
        if len(ids) < 3:
            continue  # a redundant plane, or one that touches the solid in an edge or a vertex
        u, v = _plane_basis(na[j])
        rel = verts[ids] - verts[ids].mean(axis=0)
        p2 = np.column_stack([rel @ u, rel @ v])
        order = np.argsort(np.arctan2(p2[:, 1], p2[:, 0]))
        q = p2[order]
        # thickness of the polygon: its area over its longest chord, a lower bound of its width
        area = 0.5 * abs(np.sum(q[:, 0] * np.roll(q[:, 1], -1) - q[:, 1] * np.roll(q[:, 0], -1)))
        chord = float(np.max(np.linalg.norm(q[:, None, :] - q[None, :, :], axis=-1)))
        if area <= tol * chord:
            slivers.append(int(idx[j]))
            continue
        rings.append([int(x) for x in ids[order]])
        keep.append(int(idx[j]))
    if len(keep) < 4:
        raise InputError("the facet planes enclose no solid", file=source)
    return verts, rings, keep, slivers


def measure_proportions(mesh: trimesh.Trimesh, shape: str = "mesh") -> Proportions:
    """Proportions measured on a faceted mesh with girdle at z ~ 0 (GemCAD designs, loaded files).

    Width is the smaller of the x and y extents; the table is the extent of the top horizontal
    facet along that axis; the girdle spans from the lowest crown vertex (thin point) down to the
    highest pavilion vertex, crown and pavilion facets being the non-vertical facets facing up
    and down.  Angles are not reported (a design has many).
    """
    from .mesh import facet_planes

    planes, face_facet = facet_planes(mesh)
    v = np.asarray(mesh.vertices)
    ext = v.max(axis=0) - v.min(axis=0)
    axis = 0 if ext[0] <= ext[1] else 1
    width, length = float(ext[axis]), float(ext[1 - axis])
    nz = planes[:, 2]
    fz = nz[face_facet]
    tri = mesh.faces
    crown_v = np.unique(tri[fz > 1e-6].ravel())
    pav_v = np.unique(tri[fz < -1e-6].ravel())
    top_faces = np.flatnonzero(fz > 1 - 1e-9)
    table_v = np.unique(tri[top_faces].ravel()) if len(top_faces) else np.array([], dtype=np.int64)
    ztop, zbot = float(v[:, 2].max()), float(v[:, 2].min())
    g_top = float(v[crown_v, 2].min()) if len(crown_v) else ztop
    g_bot = float(v[pav_v, 2].max()) if len(pav_v) else zbot
    table = float(np.ptp(v[table_v, axis])) / width if len(table_v) else 0.0
    return Proportions(
        shape=shape,
        length=length,
        width=width,
        table=table,
        crown_height=(ztop - g_top) / width,
        pavilion_depth=(g_bot - zbot) / width,
        girdle=max(g_top - g_bot, 0.0) / width,
        total_depth=(ztop - zbot) / width,
    )


def _plane_through(p0, p1, p2) -> tuple[np.ndarray, float]:
    """Outward (away from the origin) plane through three points."""
    nrm = np.cross(np.asarray(p1) - p0, np.asarray(p2) - p0)
    nrm /= np.linalg.norm(nrm)
    dd = float(nrm @ p0)
    return (nrm, dd) if dd >= 0 else (-nrm, -dd)


def _plane_from_point_dirs(p, a, b) -> tuple[np.ndarray, float]:
    """Outward plane through point ``p`` spanned by directions ``a`` and ``b``."""
    nrm = np.cross(a, b)
    nrm /= np.linalg.norm(nrm)
    dd = float(nrm @ p)
    return (nrm, dd) if dd >= 0 else (-nrm, -dd)


def _check(name: str, value: float, lo: float, hi: float, *, lo_open=False, hi_open=False, unit="") -> float:
    v = float(value)
    ok = math.isfinite(v) and (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
    if not ok:
        allowed = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}{unit}"
        raise InputError("out of range", field=name, value=value, allowed=allowed)
    return v


# ---------------------------------------------------------------------------------------------
# Brilliant family
# ---------------------------------------------------------------------------------------------


def _outline_round(theta: np.ndarray) -> np.ndarray:
    return np.ones_like(theta)


def _outline_ellipse(ratio: float) -> Callable[[np.ndarray], np.ndarray]:
    # half-length = ratio, half-width = 1 (units of the half-width)
    def r(theta):
        return 1.0 / np.sqrt((np.cos(theta) / ratio) ** 2 + np.sin(theta) ** 2)

    return r


def _pointed_half(h: float, w: float, theta: np.ndarray) -> np.ndarray:
    """Distance to a vesica arc reaching (h, 0) and (0, +-w), along direction theta (|theta| <= 90)."""
    c = (h * h - w * w) / (2.0 * w)
    rc = c + w
    s = np.abs(np.sin(theta))
    return -c * s + np.sqrt(c * c * s * s + rc * rc - c * c)


def _outline_marquise(ratio: float) -> Callable[[np.ndarray], np.ndarray]:
    def r(theta):
        return _pointed_half(ratio, 1.0, theta)

    return r


def _outline_pear(ratio: float) -> Callable[[np.ndarray], np.ndarray]:
    # round end: unit half-circle for x <= 0; pointed end reaching x = 2 ratio - 1
    h = 2.0 * ratio - 1.0

    def r(theta):
        theta = np.asarray(theta, dtype=np.float64)
        out = np.ones_like(theta)
        front = np.cos(theta) > 0
        out[front] = _pointed_half(h, 1.0, theta[front])
        return out

    return r


def _brilliant(
    shape: str,
    outline: Callable[[np.ndarray], np.ndarray],
    half_width: float,
    table: float,
    crown_angle: float,
    pavilion_angle: float,
    star_length: float,
    lower_girdle_length: float,
    girdle: float,
    culet: float,
    girdle_facets: int,
) -> trimesh.Trimesh:
    """The 57/58-facet brilliant over an outline ``r(theta)`` (in units of the half-width).

    The round stone is constructed exactly from its defining points (unit radius, girdle at z=0):
    girdle points G_j at azimuth 22.5 j deg (even j: bezel/main azimuths), table corners T_k,
    star tips S_k on the ridge between bezels k and k+1, lower-girdle tips L_k on the ridge
    between mains k and k+1 and the culet point C.  Fancy shapes move every point radially onto
    the outline (z kept) and rebuild each facet plane through its moved defining points.
    """
    table = _check("table", table, 0.05, 0.95)
    crown_angle = _check("crown_angle", crown_angle, 5.0, 60.0, unit=" deg")
    pavilion_angle = _check("pavilion_angle", pavilion_angle, 20.0, 60.0, unit=" deg")
    star_length = _check("star_length", star_length, 0.05, 0.95)
    lower_girdle_length = _check("lower_girdle_length", lower_girdle_length, 0.05, 0.95)
    girdle = _check("girdle", girdle, 0.0, 0.2)
    culet = _check("culet", culet, 0.0, 0.3)
    if girdle_facets not in (16, 32, 64, 128):
        raise InputError(
            "unsupported girdle facet count",
            field="girdle_facets",
            value=girdle_facets,
            allowed="16, 32, 64, 128",
        )
    a = math.radians(crown_angle)
    p = math.radians(pavilion_angle)
    c225 = math.cos(math.radians(22.5))
    g2 = girdle  # half-thickness in units of the half-width (girdle is a fraction of the width)
    rt = table
    zt = g2 + (1.0 - rt) * math.tan(a)
    rs = rt * c225 + star_length * (1.0 - rt * c225)
    zs = g2 + (1.0 - rs * c225) * math.tan(a)
    rl = 1.0 - lower_girdle_length
    zl = -g2 - (1.0 - rl * c225) * math.tan(p)
    zc = -g2 - math.tan(p)

    def warp_pt(rho, theta, z):
        th = np.asarray(theta, dtype=np.float64)
        rr = rho * outline(np.atleast_1d(th))[0]
        return np.array([rr * math.cos(th), rr * math.sin(th), z])

    phi = [math.radians(45.0 * k) for k in range(8)]
    psi = [math.radians(22.5 + 45.0 * k) for k in range(8)]
    Gu = [warp_pt(1.0, math.radians(22.5 * j), g2) for j in range(16)]
    Gl = [warp_pt(1.0, math.radians(22.5 * j), -g2) for j in range(16)]
    T = [warp_pt(rt, phi[k], zt) for k in range(8)]
    S = [warp_pt(rs, psi[k], zs) for k in range(8)]
    L = [warp_pt(rl, psi[k], zl) for k in range(8)]
    C = np.array([0.0, 0.0, zc])

    normals, offsets, names = [], [], []

    def add(plane, name):
        normals.append(plane[0])
        offsets.append(plane[1])
        names.append(name)

    add((np.array([0.0, 0.0, 1.0]), zt), "table")
    for k in range(8):
        add(_plane_through(T[k], T[(k + 1) % 8], S[k]), f"star {k}")
    for k in range(8):
        add(_plane_from_point_dirs(T[k], Gu[2 * k] - T[k], S[k] - S[k - 1]), f"bezel {k}")
    for k in range(8):
        add(_plane_through(Gu[2 * k], Gu[2 * k + 1], S[k]), f"upper girdle {2 * k}")
        add(_plane_through(Gu[2 * k + 1], Gu[(2 * k + 2) % 16], S[k]), f"upper girdle {2 * k + 1}")
    for k in range(8):
        add(_plane_from_point_dirs(C, Gl[2 * k] - C, L[k] - L[k - 1]), f"pavilion main {k}")
    for k in range(8):
        add(_plane_through(Gl[2 * k], Gl[2 * k + 1], L[k]), f"lower girdle {2 * k}")
        add(_plane_through(Gl[2 * k + 1], Gl[(2 * k + 2) % 16], L[k]), f"lower girdle {2 * k + 1}")
    if culet > 0:
        add((np.array([0.0, 0.0, -1.0]), -(zc + culet * math.tan(p))), "culet")
    if girdle > 0:
        th = np.radians(np.arange(girdle_facets) * 360.0 / girdle_facets)
        pts = [warp_pt(1.0, t, 0.0) for t in th]
        for j in range(girdle_facets):
            add(
                _plane_from_point_dirs(
                    pts[j], pts[(j + 1) % girdle_facets] - pts[j], np.array([0.0, 0.0, 1.0])
                ),
                f"girdle {j}",
            )

    s = half_width
    mesh = convex_from_planes(np.array(normals), np.array(offsets) * s, names)
    ext = mesh.bounds[1] - mesh.bounds[0]
    width, length = float(min(ext[0], ext[1])), float(max(ext[0], ext[1]))
    zmin = float(mesh.bounds[0][2])
    round_ = shape == "round_brilliant"
    # ratios: relative to the width (2 s for every outline here, the outline's half-width is 1)
    w_ref = 2.0 * s
    mesh.metadata["proportions"] = Proportions(
        shape=shape,
        length=length,
        width=width,
        table=rt,
        crown_height=(zt - g2) * s / w_ref,
        pavilion_depth=(-g2 * s - zmin) / w_ref,
        girdle=2.0 * g2 * s / w_ref,
        total_depth=(zt * s - zmin) / w_ref,
        crown_angle=crown_angle if round_ else None,
        pavilion_angle=pavilion_angle if round_ else None,
    )
    mesh.metadata["symmetry"] = (8, True) if round_ else (2, True) if shape != "pear" else (1, True)
    mesh.metadata["shape"] = shape
    return mesh


def round_brilliant(
    diameter: float = 1.0,
    table: float = 0.53,
    crown_angle: float = 34.5,
    pavilion_angle: float = 40.75,
    *,
    star_length: float = 0.5,
    lower_girdle_length: float = 0.75,
    girdle: float = 0.02,
    culet: float = 0.0,
    girdle_facets: int = 16,
) -> trimesh.Trimesh:
    """Round brilliant: table, 8 stars, 8 bezels, 16 upper girdle, 8 pavilion mains, 16 lower
    girdle (57 facets), plus a culet (58) when ``culet > 0``, plus ``girdle_facets`` vertical
    girdle facets when ``girdle > 0``.

    Defaults are Tolkowsky's (1919) ideal: table 53 %, crown 34.5 deg, pavilion 40.75 deg,
    which give crown height 16.2 % and pavilion depth 43.1 %.

    Parameters
    ----------
    diameter : girdle diameter in mm (through the 16 points where bezels, mains and the
        upper/lower girdle facets touch the girdle).
    table : table width / diameter, corner to corner of the octagon.
    crown_angle, pavilion_angle : bezel and pavilion-main angles to the girdle plane, degrees.
    star_length : radial extent of the stars from the table edge, as a fraction of the distance
        from the table edge to the girdle (GIA definition, typically 0.45-0.55).
    lower_girdle_length : radial extent of the lower girdle facets from the girdle, as a fraction
        of the girdle radius (typically 0.75-0.80).
    girdle : girdle thickness / diameter at the 16 points where the bezels, mains and girdle
        facets meet the girdle (0 = knife edge).  With more than 16 girdle facets the girdle is
        scalloped: thinner between those points, as on polished stones.
    culet : culet size / diameter (0 = pointed).
    girdle_facets : number of vertical girdle facets (16, 32, 64 or 128).
    """
    diameter = _check("diameter", diameter, 0.0, 1e4, lo_open=True, unit=" mm")
    return _brilliant(
        "round_brilliant",
        _outline_round,
        diameter / 2,
        table,
        crown_angle,
        pavilion_angle,
        star_length,
        lower_girdle_length,
        girdle,
        culet,
        girdle_facets,
    )


def _fancy(shape, outline_factory, length, width, kw) -> trimesh.Trimesh:
    width = _check("width", width, 0.0, 1e4, lo_open=True, unit=" mm")
    length = _check("length", length, width, 1e4, unit=" mm (>= width)")
    ratio = length / width
    if shape != "oval" and ratio < 1.05:
        raise InputError(f"a {shape} needs length/width >= 1.05", field="length", value=length)
    defaults = dict(
        table=0.53,
        crown_angle=34.5,
        pavilion_angle=40.75,
        star_length=0.5,
        lower_girdle_length=0.75,
        girdle=0.02,
        culet=0.0,
        girdle_facets=16,
    )
    unknown = set(kw) - set(defaults)
    if unknown:
        raise TypeError(f"unexpected argument(s) {sorted(unknown)}")
    defaults.update(kw)
    return _brilliant(shape, outline_factory(ratio), width / 2, **defaults)


def oval(length: float = 1.5, width: float = 1.0, **kw) -> trimesh.Trimesh:
    """Oval brilliant: the round brilliant's facets over an elliptic girdle (length along x).

    Keyword arguments as :func:`round_brilliant`; the angles are those of the facets across the
    width, facets along the length are flatter, as on real ovals.
    """
    return _fancy("oval", _outline_ellipse, length, width, kw)


def pear(length: float = 1.5, width: float = 1.0, **kw) -> trimesh.Trimesh:
    """Pear brilliant: round end (radius width/2, centred on the origin) towards -x, point at
    x = length - width/2.  Keyword arguments as :func:`round_brilliant`."""
    return _fancy("pear", _outline_pear, length, width, kw)


def marquise(length: float = 2.0, width: float = 1.0, **kw) -> trimesh.Trimesh:
    """Marquise (navette) brilliant: girdle of two circular arcs meeting in points at
    x = +-length/2.  Keyword arguments as :func:`round_brilliant`."""
    return _fancy("marquise", _outline_marquise, length, width, kw)


# ---------------------------------------------------------------------------------------------
# Step cuts
# ---------------------------------------------------------------------------------------------


def step_cut(
    length: float = 1.4,
    width: float = 1.0,
    *,
    corner: float = 0.15,
    table: float = 0.6,
    crown_angles: Sequence[float] = (45.0, 30.0),
    pavilion_angles: Sequence[float] = (50.0, 43.0, 38.0),
    girdle: float = 0.02,
    shape: str = "step_cut",
) -> trimesh.Trimesh:
    """Step cut over a rectangle with 45-degree cut corners (an octagon).

    Each tier is a ring of facets parallel to the girdle outline (4 sides + 4 corners), at the
    tier's angle to the girdle plane.  The crown insets the outline by ``(1 - table) * width / 2``
    from girdle to table in equal steps, the pavilion by ``width / 2`` from girdle to keel (a
    keel line of length ``length - width``, a point for a square).  For the facets to exist the
    angles must decrease from the girdle inwards (the solid is convex).

    ``corner`` : the length cut off each side at a corner, as a fraction of the width.
    """
    width = _check("width", width, 0.0, 1e4, lo_open=True, unit=" mm")
    length = _check("length", length, width, 1e4, unit=" mm (>= width)")
    corner = _check("corner", corner, 0.0, 0.45)
    table = _check("table", table, 0.05, 0.95)
    girdle = _check("girdle", girdle, 0.0, 0.2)
    crown_angles = [float(x) for x in crown_angles]
    pavilion_angles = [float(x) for x in pavilion_angles]
    if not crown_angles or not pavilion_angles:
        raise InputError("a step cut needs at least one crown and one pavilion tier", field="crown_angles")
    for nm, seq in (("crown_angles", crown_angles), ("pavilion_angles", pavilion_angles)):
        for x in seq:
            _check(nm, x, 5.0, 85.0, unit=" deg")
        if any(b >= a for a, b in zip(seq, seq[1:], strict=False)):
            raise InputError("tier angles must decrease from the girdle inwards", field=nm, value=tuple(seq))
    W, Lh = width / 2, length / 2
    c = corner * width
    edges = [
        ((1.0, 0.0), Lh, "side +x"),
        ((0.0, 1.0), W, "side +y"),
        ((-1.0, 0.0), Lh, "side -x"),
        ((0.0, -1.0), W, "side -y"),
    ]
    if c > 0:
        r2 = 1 / math.sqrt(2)
        hc = (Lh + W - c) * r2
        edges += [
            ((r2, r2), hc, "corner +x+y"),
            ((-r2, r2), hc, "corner -x+y"),
            ((-r2, -r2), hc, "corner -x-y"),
            ((r2, -r2), hc, "corner +x-y"),
        ]
    g2 = girdle * width / 2
    normals, offsets, names = [], [], []
    for (ex, ey), h, nm in edges:
        normals.append((ex, ey, 0.0))
        offsets.append(h)
        names.append(f"girdle {nm}")

    def tiers(angles, total_inset, sign, label):
        z = sign * g2
        delta = 0.0
        step = total_inset / len(angles)
        for t, ang in enumerate(angles):
            al = math.radians(ang)
            for (ex, ey), h, nm in edges:
                nrm = (math.sin(al) * ex, math.sin(al) * ey, sign * math.cos(al))
                normals.append(nrm)
                offsets.append(math.sin(al) * (h - delta) + sign * math.cos(al) * z)
                names.append(f"{label} {t + 1} {nm}")
            delta += step
            z += sign * step * math.tan(al)
        return z

    zt = tiers(crown_angles, (1 - table) * W, 1.0, "crown step")
    zk = tiers(pavilion_angles, W, -1.0, "pavilion step")
    normals.append((0.0, 0.0, 1.0))
    offsets.append(zt)
    names.append("table")
    mesh = convex_from_planes(np.array(normals), np.array(offsets), names)
    mesh.metadata["proportions"] = Proportions(
        shape=shape,
        length=length,
        width=width,
        table=table,
        crown_height=(zt - g2) / width,
        pavilion_depth=(-g2 - zk) / width,
        girdle=2 * g2 / width,
        total_depth=(zt - zk) / width,
        crown_angle=crown_angles[0] if len(crown_angles) == 1 else None,
        pavilion_angle=pavilion_angles[-1] if len(pavilion_angles) == 1 else None,
    )
    mesh.metadata["symmetry"] = (4, True) if length == width else (2, True)
    mesh.metadata["shape"] = shape
    return mesh


def emerald(
    length: float = 1.4,
    width: float = 1.0,
    *,
    corner: float = 0.15,
    table: float = 0.6,
    crown_angles: Sequence[float] = (45.0, 30.0),
    pavilion_angles: Sequence[float] = (50.0, 43.0, 38.0),
    girdle: float = 0.02,
) -> trimesh.Trimesh:
    """Emerald cut: rectangular step cut with cut corners (see :func:`step_cut`)."""
    return step_cut(
        length,
        width,
        corner=corner,
        table=table,
        crown_angles=crown_angles,
        pavilion_angles=pavilion_angles,
        girdle=girdle,
        shape="emerald",
    )


def princess(
    width: float = 1.0,
    *,
    table: float = 0.7,
    crown_angle: float = 35.0,
    pavilion_angles: Sequence[float] = (50.0, 44.0, 40.0),
    girdle: float = 0.02,
) -> trimesh.Trimesh:
    """Princess (square, sharp corners): one crown tier, a stepped pyramidal pavilion to a point.

    A simplification of the commercial princess, whose pavilion chevrons are split further.
    """
    return step_cut(
        width,
        width,
        corner=0.0,
        table=table,
        crown_angles=(crown_angle,),
        pavilion_angles=pavilion_angles,
        girdle=girdle,
        shape="princess",
    )


# ---------------------------------------------------------------------------------------------
# Optical solids
# ---------------------------------------------------------------------------------------------


def _box(sx: float, sy: float, sz: float, zc: float = 0.0, names=None) -> trimesh.Trimesh:
    normals = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    offsets = [sx / 2, sx / 2, sy / 2, sy / 2, sz / 2 + zc, sz / 2 - zc]
    names = names or ["+x", "-x", "+y", "-y", "+z", "-z"]
    return convex_from_planes(np.array(normals, dtype=float), np.array(offsets), names)


def prism(apex_angle: float = 60.0, size: float = 10.0, length: float = 10.0) -> trimesh.Trimesh:
    """Triangular prism: an isosceles cross-section in the x-z plane extruded along y.

    The refracting edge (apex) is parallel to y at the top; ``size`` is the width of each of the
    two refracting faces (mm), ``apex_angle`` the angle between them (degrees), ``length`` the
    extent along y.  The bounding box is centred on the origin.  Facets: "face +x", "face -x"
    (refracting faces, normals in the x-z plane), "base" (normal -z), "end +y", "end -y".
    """
    A = math.radians(_check("apex_angle", apex_angle, 1.0, 179.0, unit=" deg"))
    size = _check("size", size, 0.0, 1e4, lo_open=True, unit=" mm")
    length = _check("length", length, 0.0, 1e4, lo_open=True, unit=" mm")
    h = size * math.cos(A / 2)  # apex height above the base
    half_base = size * math.sin(A / 2)
    z_apex, z_base = h / 2, -h / 2
    n_r = np.array([math.cos(A / 2), 0.0, math.sin(A / 2)])
    n_l = np.array([-math.cos(A / 2), 0.0, math.sin(A / 2)])
    apex = np.array([0.0, 0.0, z_apex])
    normals = [n_r, n_l, (0, 0, -1), (0, 1, 0), (0, -1, 0)]
    offsets = [n_r @ apex, n_l @ apex, -z_base, length / 2, length / 2]
    m = convex_from_planes(
        np.array(normals, dtype=float), np.array(offsets), ["face +x", "face -x", "base", "end +y", "end -y"]
    )
    m.metadata["shape"] = "prism"
    m.metadata["apex_angle"] = math.degrees(A)
    m.metadata["base_width"] = 2 * half_base
    return m


def plate(width: float = 10.0, length: float = 10.0, thickness: float = 1.0) -> trimesh.Trimesh:
    """Plane-parallel plate (mm), faces normal to z, centred on the origin."""
    width = _check("width", width, 0.0, 1e5, lo_open=True, unit=" mm")
    length = _check("length", length, 0.0, 1e5, lo_open=True, unit=" mm")
    thickness = _check("thickness", thickness, 0.0, 1e5, lo_open=True, unit=" mm")
    m = _box(length, width, thickness)
    m.metadata["shape"] = "plate"
    return m


def cube(size: float = 1.0) -> trimesh.Trimesh:
    """Cube of edge ``size`` (mm), axis-aligned, centred on the origin."""
    size = _check("size", size, 0.0, 1e5, lo_open=True, unit=" mm")
    m = _box(size, size, size)
    m.metadata["shape"] = "cube"
    return m


def sphere(diameter: float = 1.0, subdivisions: int = 3) -> trimesh.Trimesh:
    """Icosphere of the given circumscribed diameter (mm), centred on the origin.

    ``subdivisions`` 3 gives 1280 triangles (each its own facet plane); the flat facets deviate
    from the true sphere by at most ~0.2 % of the radius at 3 subdivisions.
    """
    diameter = _check("diameter", diameter, 0.0, 1e5, lo_open=True, unit=" mm")
    if int(subdivisions) != subdivisions or not 0 <= subdivisions <= 6:
        raise InputError("out of range", field="subdivisions", value=subdivisions, allowed="0..6")
    m = trimesh.creation.icosphere(subdivisions=int(subdivisions), radius=diameter / 2)
    nrm = np.asarray(m.face_normals, dtype=np.float64)
    d = np.einsum("ij,ij->i", nrm, m.triangles_center)
    m.metadata["planes"] = np.column_stack([nrm, d])
    m.metadata["facet_names"] = [f"face {i}" for i in range(len(m.faces))]
    m.metadata["face_facet"] = np.arange(len(m.faces), dtype=np.int64)
    m.metadata["proportions"] = None
    m.metadata["shape"] = "sphere"
    return m


#: calcite's cleavage rhombohedron: the interfacial angle between adjacent cleavage faces is
#: 74.95 deg (its supplement 105.05 deg), e.g. Hurlbut & Klein, *Manual of Mineralogy*, 19th ed.
CALCITE_RHOMB_ANGLE = 74.95


def rhomb_axis_angle(face_angle: float = CALCITE_RHOMB_ANGLE) -> float:
    """Angle (degrees) between the 3-fold axis of a rhombohedron and each face normal, from the
    angle ``face_angle`` between adjacent face normals: cos(face_angle) = (3 cos^2 beta - 1) / 2
    (three normals at beta from the axis, 120 deg apart).  Calcite: 44.63 deg."""
    c = math.cos(math.radians(face_angle))
    return math.degrees(math.acos(math.sqrt((2.0 * c + 1.0) / 3.0)))


def rhomb(thickness: float = 5.0, face_angle: float = CALCITE_RHOMB_ANGLE) -> trimesh.Trimesh:
    """A rhombohedron (a cleavage rhomb of calcite by default) with all three pairs of opposite
    faces ``thickness`` mm apart, centred on the origin.

    One face pair is normal to z ("top" +z, "bottom" -z).  The 3-fold axis (calcite's optic axis,
    ``metadata["optic_axis"]``) lies in the x-z plane at :func:`rhomb_axis_angle` from z (44.63 deg
    for calcite), and the other two face normals are the top normal turned by +-120 deg about it,
    so adjacent faces meet at ``face_angle`` between normals (dihedral 180 - face_angle).
    """
    thickness = _check("thickness", thickness, 0.0, 1e5, lo_open=True, unit=" mm")
    face_angle = _check("face_angle", face_angle, 1.0, 89.0, unit=" deg")
    beta = math.radians(rhomb_axis_angle(face_angle))
    axis = np.array([math.sin(beta), 0.0, math.cos(beta)])
    n1 = np.array([0.0, 0.0, 1.0])

    def turn(v, ang):  # Rodrigues rotation about the axis
        a = math.radians(ang)
        return v * math.cos(a) + np.cross(axis, v) * math.sin(a) + axis * (axis @ v) * (1 - math.cos(a))

    n2, n3 = turn(n1, 120.0), turn(n1, -120.0)
    normals = np.array([n1, -n1, n2, -n2, n3, -n3])
    names = ["top", "bottom", "face 2", "face -2", "face 3", "face -3"]
    m = convex_from_planes(normals, np.full(6, thickness / 2), names)
    m.metadata["shape"] = "rhomb"
    m.metadata["optic_axis"] = axis
    return m


def ground_plane(size: float = 100.0, thickness: float = 1.0, z: float = 0.0) -> trimesh.Trimesh:
    """A ground slab ``size`` x ``size`` x ``thickness`` mm whose top face is the plane z = ``z``.

    A closed slab rather than an open quad so that every solid in a scene is watertight.
    """
    size = _check("size", size, 0.0, 1e6, lo_open=True, unit=" mm")
    thickness = _check("thickness", thickness, 0.0, 1e6, lo_open=True, unit=" mm")
    m = _box(size, size, thickness, zc=float(z) - thickness / 2)
    m.metadata["shape"] = "ground_plane"
    return m


def wavy_sheet(
    width: float = 10.0,
    length: float = 10.0,
    amplitude: float = 0.0,
    wavelength_x: float = 5.0,
    wavelength_y: float = 5.0,
    resolution: int = 64,
) -> trimesh.Trimesh:
    """An open sheet z = amplitude sin(2 pi x / wavelength_x) sin(2 pi y / wavelength_y) over
    ``length`` (x) by ``width`` (y) mm, centred on the origin, normals toward +z (mm).

    For thin-film surfaces (``surface = "film"`` / ``"shell"``, ``stages.coated``): amplitude 0 is
    a flat quad.  ``resolution`` grid cells per side; each triangle is its own facet.
    """
    width = _check("width", width, 0.0, 1e6, lo_open=True, unit=" mm")
    length = _check("length", length, 0.0, 1e6, lo_open=True, unit=" mm")
    amplitude = _check("amplitude", amplitude, 0.0, 1e6, unit=" mm")
    wavelength_x = _check("wavelength_x", wavelength_x, 0.0, 1e6, lo_open=True, unit=" mm")
    wavelength_y = _check("wavelength_y", wavelength_y, 0.0, 1e6, lo_open=True, unit=" mm")
    if int(resolution) != resolution or not 1 <= resolution <= 1024:
        raise InputError("out of range", field="resolution", value=resolution, allowed="1..1024")
    r = 1 if amplitude == 0.0 else int(resolution)
    xs = np.linspace(-length / 2, length / 2, r + 1)
    ys = np.linspace(-width / 2, width / 2, r + 1)
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    gz = amplitude * np.sin(2 * np.pi * gx / wavelength_x) * np.sin(2 * np.pi * gy / wavelength_y)
    verts = np.column_stack([gx.ravel(), gy.ravel(), gz.ravel()])
    idx = np.arange((r + 1) * (r + 1)).reshape(r + 1, r + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    m = trimesh.Trimesh(verts, faces, process=False)
    nrm = np.asarray(m.face_normals, dtype=np.float64)
    m.metadata["planes"] = np.column_stack([nrm, np.einsum("ij,ij->i", nrm, m.triangles_center)])
    m.metadata["face_facet"] = np.arange(len(m.faces), dtype=np.int64)
    m.metadata["facet_names"] = [f"face {i}" for i in range(len(m.faces))]
    m.metadata["proportions"] = None
    m.metadata["shape"] = "wavy_sheet"
    return m


#: Shapes by name, for the command line and scene files.
SHAPES: dict[str, Callable[..., trimesh.Trimesh]] = {
    "round_brilliant": round_brilliant,
    "oval": oval,
    "pear": pear,
    "marquise": marquise,
    "emerald": emerald,
    "princess": princess,
    "step_cut": step_cut,
    "prism": prism,
    "plate": plate,
    "cube": cube,
    "sphere": sphere,
    "ground_plane": ground_plane,
    "rhomb": rhomb,
}
# (``wavy_sheet`` is an open surface for films, not a solid: scene files name it, SHAPES does not)
