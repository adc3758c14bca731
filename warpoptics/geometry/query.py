"""Device-side ray queries: closest hit against a scene of solids (BVH or convex facet planes).

Every object is a closed triangle mesh in its own (object) space plus an instance transform.
Two closest-hit paths share one result:

- **BVH**: one ``wp.Mesh`` per object; ``wp.mesh_query_ray`` in object space.  Any mesh.
- **Convex**: the facet planes ``n . x <= d`` of a convex object.  Entering: Haines' slab test
  over the planes (the largest entering distance among front-facing planes, against the
  smallest leaving distance among back-facing ones); from inside, leaving: the nearest plane
  ahead.  No triangles, no tree: a loop over K planes (Haines 1991, Guy & Soler 2004 §3).

``object_exit_hit(geom, k, origin, direction, t_max)`` is the query for a ray known to travel
inside object ``k`` (after a refraction into it, the tracer's common case): only that object,
and on the convex path only the planes the ray is leaving through.  ``medium_closest_hit`` adds
the solids nested in ``k`` (``geom.parent``, geometry/nesting.py) when the scene has any.

``scene_closest_hit(geom, origin, direction, t_max)`` (and ``scene_closest_hit_leaving``, which
skips the convex solid a ray leaves) picks the convex path for objects flagged
convex (automatically: watertight, convex and at most ``convex_max_planes`` facets), the BVH for
the others; ``geom.mode`` can force one path (for tests and benchmarks).  Kernels take the whole
scene as ONE :class:`SceneGeometry` struct argument.

Conventions: world space in mm, right-handed.  ``direction`` need not be unit length: ``t`` is
in multiples of its length (a distance in mm when it is unit length), and instance transforms
preserve it (``x_obj = M x_world`` maps the ray's parameter unchanged).  Normals are unit,
world space, pointing out of the object (for a ray inside a solid the hit normal points along
the ray).  A ray that starts exactly on a surface may report that surface at ``t ~ 0``: the
caller offsets origins.  Geometry is float32.

An example kernel: docs/design/ray_queries.md.

References
- E. Haines, "Fast Ray-Convex Polyhedron Intersection", in *Graphics Gems II*, J. Arvo (ed.),
  Academic Press, 1991, pp. 247-250.
- S. Guy and C. Soler, "Graphics Gems Revisited", ACM TOG 23(3), 2004 (convexity of gems).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
import trimesh
import warp as wp

from .. import device as _device
from .mesh import facet_neighbours, facet_planes

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "MODE_AUTO",
    "MODE_BVH",
    "MODE_CONVEX",
    "SceneGeometry",
    "RayHit",
    "convex_closest_hit",
    "convex_exit_hit",
    "ray_meets_sphere",
    "object_exit_hit",
    "medium_closest_hit",
    "offset_epsilon",
    "convex_exit_near",
    "world_normal",
    "plane_t",
    "scene_closest_hit",
    "Hits",
    "GeometryScene",
]

MODE_AUTO = 0
MODE_BVH = 1
MODE_CONVEX = 2
_MODES = {"auto": MODE_AUTO, "bvh": MODE_BVH, "convex": MODE_CONVEX}
_BIG = 1.0e30


@wp.struct
class SceneGeometry:
    """All solids of a scene, for kernels (one argument).

    Per object k (``num_objects`` of them): ``mesh_ids[k]`` (``wp.Mesh`` id), ``world_to_object[k]``
    (4x4 affine), ``convex[k]`` (1: use the plane path in auto mode), its facet planes
    ``planes[plane_start[k] : plane_start[k] + plane_count[k]]`` (object space, ``(nx, ny, nz, d)``,
    outward unit normal, mm), the facet of each of its triangles ``face_facet[face_start[k] + f]``
    and an object-space bounding sphere ``bounding_sphere[k] = (cx, cy, cz, r)`` (culls rays
    for the convex path).  ``mode``: 0 auto, 1 BVH for all, 2 convex planes for all.
    ``parent[k]``: the innermost object containing object k (-1: the ambient medium), ``nested``
    1 if any object has a parent; ``epsilon[k]``: the origin offset (mm) of rays leaving k's
    surface (:func:`offset_epsilon`).
    """

    num_objects: wp.int32
    mode: wp.int32
    mesh_ids: wp.array(dtype=wp.uint64)
    world_to_object: wp.array(dtype=wp.mat44f)
    convex: wp.array(dtype=wp.int32)
    plane_start: wp.array(dtype=wp.int32)
    plane_count: wp.array(dtype=wp.int32)
    planes: wp.array(dtype=wp.vec4f)
    # the same planes in blocks of PLANE_BLOCK, structure of arrays (nx[16], ny[16], nz[16],
    # d[16]; padding planes n = 0, d = 1), floats block_start[k] .. for block_count[k] blocks
    plane_blocks: wp.array(dtype=wp.float32)
    block_start: wp.array(dtype=wp.int32)
    block_count: wp.array(dtype=wp.int32)
    face_start: wp.array(dtype=wp.int32)
    face_facet: wp.array(dtype=wp.int32)
    # edge neighbours of the facets (mesh.facet_neighbours, local facet indices): those of facet f
    # of object k are adj[adj_start[plane_start[k] + f] : adj_start[plane_start[k] + f + 1]]
    adj_start: wp.array(dtype=wp.int32)
    adj: wp.array(dtype=wp.int32)
    bounding_sphere: wp.array(dtype=wp.vec4f)
    # nesting (geometry/nesting.py): the innermost solid around object k (-1: none), and whether
    # any object has one; a ray inside k meets k's surface or that of a solid whose parent is k
    parent: wp.array(dtype=wp.int32)
    nested: wp.int32
    # origin offset of a new ray leaving object k's surface, mm (offset_epsilon: relative to the
    # object's size and to the float32 spacing at its position)
    epsilon: wp.array(dtype=wp.float32)


@wp.struct
class RayHit:
    """Closest hit: ``t`` (ray parameter; = t_max and ``object`` = -1 on a miss), ``object``,
    ``facet`` (facet/plane index within the object), ``face`` (triangle index within the object,
    -1 when found by the convex path), ``normal`` (world, unit, outward)."""

    t: wp.float32
    object: wp.int32
    facet: wp.int32
    face: wp.int32
    normal: wp.vec3f


@wp.func
def ray_miss(t_max: wp.float32):
    """The :class:`RayHit` of a ray that meets nothing within ``t_max``."""
    hit = RayHit()
    hit.t = t_max
    hit.object = -1
    hit.facet = -1
    hit.face = -1
    hit.normal = wp.vec3f(0.0, 0.0, 0.0)
    return hit


@wp.func
def world_normal(world_to_object: wp.mat44f, n_obj: wp.vec3f):
    """Unit world-space normal of an object-space normal (the inverse transpose of the object's
    transform, which ``world_to_object`` is the inverse of)."""
    return wp.normalize(wp.transform_vector(wp.transpose(world_to_object), n_obj))


@wp.func
def plane_t(plane: wp.vec4f, origin: wp.vec3f, direction: wp.vec3f):
    """Ray parameter where the ray meets the plane ``n . x = d`` (``plane`` = (n, d))."""
    n = wp.vec3f(plane[0], plane[1], plane[2])
    return (plane[3] - wp.dot(n, origin)) / wp.dot(n, direction)


@wp.func
def convex_closest_hit(
    planes: wp.array(dtype=wp.vec4f),
    start: wp.int32,
    count: wp.int32,
    origin: wp.vec3f,
    direction: wp.vec3f,
    t_max: wp.float32,
):
    """Closest hit of a ray with the convex polyhedron ``n_k . x <= d_k`` (Haines 1991).

    Returns ``(t, k)``: the ray parameter in ``(0, t_max)`` and the local index of the facet
    plane hit, or ``(t_max, -1)``.  From outside the hit is the entering plane with the largest
    ``t``; from inside (all entering ``t <= 0``) it is the leaving plane with the smallest ``t``.
    """
    t_near = float(-_BIG)
    t_far = float(_BIG)
    k_near = int(-1)  # noqa: UP018 (a mutable Warp variable needs its type)
    k_far = int(-1)  # noqa: UP018 (a mutable Warp variable needs its type)
    miss = int(0)  # noqa: UP018 (a mutable Warp variable needs its type)
    for k in range(count):
        p = planes[start + k]
        n = wp.vec3f(p[0], p[1], p[2])
        vn = wp.dot(n, direction)
        vd = wp.dot(n, origin) - p[3]  # > 0: origin outside this plane
        # "the point at t_near (t_far) is outside plane k" <=> plane k moves t_near up (t_far down);
        # tested without the division, which is done only on an update.
        if vn < 0.0 and vd + t_near * vn > 0.0:  # front-facing (entering) plane
            t_near = -vd / vn
            k_near = k
            if t_near > t_far:
                miss = 1
                break
        elif vn > 0.0 and vd + t_far * vn > 0.0:  # back-facing (leaving) plane
            t_far = -vd / vn
            k_far = k
            if t_near > t_far or t_far < 0.0:
                miss = 1
                break
        elif vn == 0.0 and vd > 0.0:  # parallel to the plane, outside it
            miss = 1
            break
    t_hit = t_max
    facet = int(-1)  # noqa: UP018 (a mutable Warp variable needs its type)
    if miss == 0 and t_far >= 0.0:
        if t_near > 0.0:
            if t_near < t_max:
                t_hit = t_near
                facet = k_near
        elif t_far < t_max:
            t_hit = t_far
            facet = k_far
    return t_hit, facet


PLANE_BLOCK = 16

# The exit query is the tracer's hottest loop (about 40 % of a render's time with one scalar
# plane after the other).  For a ray starting inside, the nearest leaving plane is the one with
# the largest rate of approach r_k = (n_k . d) / (d_k - n_k . o): t_k = 1 / r_k for leaving
# planes (r > 0), while entering planes have r <= 0 (the origin is inside, d_k - n_k . o > 0).
# An argmax needs no comparison against a running t, so 16 planes go through SIMD registers at
# once (clang vector extensions on the CPU; CUDA gets the plain loop, one thread per ray anyway).
# An origin on or just outside a leaving plane (d_k - n_k . o <= 0) makes that plane the exit
# at t <= 0, as the scalar loop did.  Measured on 200,000 inside rays of a brilliant, one thread:
# 3.75 vs 2.18 M rays/s through object_exit_hit (scripts/bench/bench_ray_queries.py), the same
# facets and t; the whole diamond.toml render 1.6x faster.  The snippets' 16 and 64 (= 4 x 16
# floats per block) are PLANE_BLOCK.
_EXIT_HEAD = r"""
    const float* p = blocks.data + start;
    float best = 0.0f;
    int k_best = -1;
"""
_EXIT_SIMD = r"""
    typedef float v16 __attribute__((ext_vector_type(16)));
    const v16 tiny = (v16)(1.0e-30f);
    for (int b = 0; b < nblocks; ++b) {
        const float* q = p + 64 * b;
        v16 nx, ny, nz, h;
        __builtin_memcpy(&nx, q, 64);
        __builtin_memcpy(&ny, q + 16, 64);
        __builtin_memcpy(&nz, q + 32, 64);
        __builtin_memcpy(&h, q + 48, 64);
        v16 vn = nx * dx + ny * dy + nz * dz;
        v16 vd = h - (nx * ox + ny * oy + nz * oz);
        v16 r = vn / __builtin_elementwise_max(vd, tiny);
        float m = __builtin_reduce_max(r);
        if (m > best) {
            best = m;
            for (int j = 0; j < 16; ++j) {
                if (r[j] == m) { k_best = 16 * b + j; break; }
            }
        }
    }
"""
# the same, one plane at a time (CUDA; tests/test_query.py runs it on the CPU against the SIMD one)
_EXIT_SCALAR = r"""
    for (int b = 0; b < nblocks; ++b) {
        const float* q = p + 64 * b;
        for (int j = 0; j < 16; ++j) {
            float vn = q[j] * dx + q[16 + j] * dy + q[32 + j] * dz;
            float vd = q[48 + j] - (q[j] * ox + q[16 + j] * oy + q[32 + j] * oz);
            float r = vn / (vd > 1.0e-30f ? vd : 1.0e-30f);
            if (r > best) { best = r; k_best = 16 * b + j; }
        }
    }
"""
_EXIT_PLANE = (
    _EXIT_HEAD
    + "#if defined(__clang__) && !defined(__CUDA_ARCH__)\n"
    + _EXIT_SIMD
    + "#else\n"
    + _EXIT_SCALAR
    + "#endif\n    return k_best;\n"
)


@wp.func_native(_EXIT_PLANE)
def convex_exit_plane(
    blocks: wp.array(dtype=wp.float32),
    start: wp.int32,
    nblocks: wp.int32,
    ox: wp.float32,
    oy: wp.float32,
    oz: wp.float32,
    dx: wp.float32,
    dy: wp.float32,
    dz: wp.float32,
) -> wp.int32:
    """Index of the plane through which a ray starting INSIDE a convex polyhedron leaves it
    (planes in SoA blocks, see ``SceneGeometry.plane_blocks``); -1 if none (a degenerate
    direction)."""
    ...


@wp.func
def convex_exit_hit(
    geom: SceneGeometry, k: wp.int32, origin: wp.vec3f, direction: wp.vec3f, t_max: wp.float32
):
    """Exit of a ray that starts INSIDE convex object ``k`` (object space): ``(t, plane)`` or
    ``(t_max, -1)``; for an inside origin the same as :func:`convex_closest_hit`."""
    f = convex_exit_plane(
        geom.plane_blocks,
        geom.block_start[k],
        geom.block_count[k],
        origin[0],
        origin[1],
        origin[2],
        direction[0],
        direction[1],
        direction[2],
    )
    if f < 0:
        return t_max, -1
    t = plane_t(geom.planes[geom.plane_start[k] + f], origin, direction)
    if t >= t_max:
        return t_max, -1
    return t, f


@wp.func
def ray_meets_sphere(sphere: wp.vec4f, origin: wp.vec3f, direction: wp.vec3f, t_max: wp.float32):
    """False only if the ray segment ``(0, t_max)`` certainly misses the sphere ``(cx, cy, cz, r)``
    (conservative: a 1e-4 relative margin on the radius)."""
    oc = origin - wp.vec3f(sphere[0], sphere[1], sphere[2])
    r = sphere[3] * 1.0001
    c = wp.dot(oc, oc) - r * r
    meets = True
    if c > 0.0:  # origin outside the sphere
        b = wp.dot(oc, direction)
        dd = wp.dot(direction, direction)
        if b >= 0.0 or b * b - dd * c < 0.0:
            meets = False
        elif (-b - wp.sqrt(b * b - dd * c)) > t_max * dd:  # sphere entered beyond t_max
            meets = False
    return meets


@wp.func
def scene_closest_hit(geom: SceneGeometry, origin: wp.vec3f, direction: wp.vec3f, t_max: wp.float32):
    """Closest hit of a world-space ray with all objects of ``geom`` within ``(0, t_max)``."""
    return scene_closest_hit_leaving(geom, origin, direction, t_max, -1)


@wp.func
def scene_closest_hit_leaving(
    geom: SceneGeometry, origin: wp.vec3f, direction: wp.vec3f, t_max: wp.float32, left: wp.int32
):
    """:func:`scene_closest_hit` for a ray that starts on the surface of object ``left`` and
    travels away from it (reflected off it from outside, or transmitted out of it; -1: none).
    A convex solid cannot be met again by such a ray, so it is skipped instead of testing all
    its facet planes (diamond.toml 160x160, one thread, alternating runs: 8 % less CPU time)."""
    hit = ray_miss(t_max)
    n_obj = wp.vec3f(0.0, 0.0, 0.0)
    m_hit = wp.identity(n=4, dtype=wp.float32)
    for k in range(geom.num_objects):
        m = geom.world_to_object[k]
        o = wp.transform_point(m, origin)
        d = wp.transform_vector(m, direction)
        use_convex = geom.mode == 2 or (geom.mode == 0 and geom.convex[k] != 0)
        if use_convex:
            s = geom.plane_start[k]
            t = hit.t
            f = int(-1)  # noqa: UP018 (a mutable Warp variable needs its type)
            if k != left and ray_meets_sphere(geom.bounding_sphere[k], o, d, hit.t):
                t, f = convex_closest_hit(geom.planes, s, geom.plane_count[k], o, d, hit.t)
            if f >= 0:
                hit.t = t
                hit.object = k
                hit.facet = f
                hit.face = -1
                p = geom.planes[s + f]
                n_obj = wp.vec3f(p[0], p[1], p[2])
                m_hit = m
        else:
            q = wp.mesh_query_ray(geom.mesh_ids[k], o, d, hit.t)
            if q.result and q.t < hit.t:
                hit.t = q.t
                hit.object = k
                hit.face = q.face
                hit.facet = geom.face_facet[geom.face_start[k] + q.face]
                n_obj = q.normal
                m_hit = m
    if hit.object >= 0:
        # normals transform with the inverse transpose of object_to_world = transpose(world_to_object)
        hit.normal = world_normal(m_hit, n_obj)
    return hit


@wp.func
def object_exit_hit(
    geom: SceneGeometry, k: wp.int32, origin: wp.vec3f, direction: wp.vec3f, t_max: wp.float32
):
    """Where a ray that travels INSIDE object ``k`` leaves it (solids nested in ``k`` are not
    searched: :func:`medium_closest_hit`).

    The tracer's query after a refraction into a solid: only object ``k`` is searched, and its
    convex path needs only the leaving planes (:func:`convex_exit_hit`).  Same result struct as
    :func:`scene_closest_hit` (``object`` = k, or -1 if nothing within ``t_max``)."""
    hit = ray_miss(t_max)
    m = geom.world_to_object[k]
    o = wp.transform_point(m, origin)
    d = wp.transform_vector(m, direction)
    n_obj = wp.vec3f(0.0, 0.0, 0.0)
    if geom.mode == 2 or (geom.mode == 0 and geom.convex[k] != 0):
        s = geom.plane_start[k]
        t, f = convex_exit_hit(geom, k, o, d, t_max)
        if f >= 0:
            hit.t = t
            hit.object = k
            hit.facet = f
            p = geom.planes[s + f]
            n_obj = wp.vec3f(p[0], p[1], p[2])
    else:
        q = wp.mesh_query_ray(geom.mesh_ids[k], o, d, t_max)
        if q.result:
            hit.t = q.t
            hit.object = k
            hit.face = q.face
            hit.facet = geom.face_facet[geom.face_start[k] + q.face]
            n_obj = q.normal
    if hit.object >= 0:
        hit.normal = world_normal(m, n_obj)
    return hit


@wp.func
def medium_closest_hit(
    geom: SceneGeometry, k: wp.int32, origin: wp.vec3f, direction: wp.vec3f, t_max: wp.float32
):
    """Closest hit of a ray travelling in the medium of object ``k``: inside ``k`` and outside the
    solids nested in it (``geom.parent[j] == k``, geometry/nesting.py).  It meets ``k``'s own
    surface (:func:`object_exit_hit`) or enters one of those children (tested from outside as in
    :func:`scene_closest_hit_leaving`).  A scene without nesting is :func:`object_exit_hit`."""
    hit = object_exit_hit(geom, k, origin, direction, t_max)
    if geom.nested != 0:
        for j in range(geom.num_objects):
            if geom.parent[j] == k:
                m = geom.world_to_object[j]
                o = wp.transform_point(m, origin)
                d = wp.transform_vector(m, direction)
                found = int(0)
                n_obj = wp.vec3f(0.0, 0.0, 0.0)
                if geom.mode == 2 or (geom.mode == 0 and geom.convex[j] != 0):
                    if ray_meets_sphere(geom.bounding_sphere[j], o, d, hit.t):
                        s = geom.plane_start[j]
                        t, f = convex_closest_hit(geom.planes, s, geom.plane_count[j], o, d, hit.t)
                        if f >= 0:
                            found = 1
                            hit.t = t
                            hit.facet = f
                            hit.face = -1
                            p = geom.planes[s + f]
                            n_obj = wp.vec3f(p[0], p[1], p[2])
                else:
                    q = wp.mesh_query_ray(geom.mesh_ids[j], o, d, hit.t)
                    if q.result and q.t < hit.t:
                        found = 1
                        hit.t = q.t
                        hit.face = q.face
                        hit.facet = geom.face_facet[geom.face_start[j] + q.face]
                        n_obj = q.normal
                if found != 0:
                    hit.object = j
                    hit.normal = world_normal(m, n_obj)
    return hit


@wp.func
def _exits_through(
    geom: SceneGeometry, s: wp.int32, facet: wp.int32, o: wp.vec3f, d: wp.vec3f, t_max: float, tol: float
):
    """(t, 1) if the object-space ray, inside the convex object whose planes start at ``s``,
    leaves it through ``facet``; else (t_max, 0).  The point where it meets the facet's plane is
    its exit iff it lies on the facet (a convex solid is left once, and a boundary point reached
    from inside is that exit), i.e. inside the planes of the facet's edge neighbours
    (``mesh.facet_neighbours``), within ``tol`` mm.  A facet without neighbours (a plane that
    bounds no face) is never accepted."""
    a = geom.adj_start[s + facet]
    b = geom.adj_start[s + facet + 1]
    pl = geom.planes[s + facet]
    n = wp.vec3f(pl[0], pl[1], pl[2])
    if wp.dot(n, d) <= 0.0 or b == a:
        return t_max, 0
    t = plane_t(pl, o, d)
    if t <= 0.0 or t >= t_max:
        return t_max, 0
    x = o + d * t
    for i in range(a, b):
        q = geom.planes[s + geom.adj[i]]
        if wp.dot(wp.vec3f(q[0], q[1], q[2]), x) - q[3] > tol:
            return t_max, 0
    return t, 1


@wp.func
def convex_exit_near(
    geom: SceneGeometry,
    k: wp.int32,
    facet: wp.int32,
    origin: wp.vec3f,
    direction: wp.vec3f,
    t_max: wp.float32,
):
    """For a world-space ray INSIDE convex object ``k``: ``(hit, 1)`` if it leaves through
    ``facet`` or one of its edge neighbours — ``hit`` as :func:`object_exit_hit` gives it —, else
    ``(miss, 0)``: then ask :func:`object_exit_hit`.  A few plane tests instead of all planes when
    the facet is a good guess (the exit of a ray of a neighbouring wavelength: the spectral
    bundles' lanes).  Points within 1e-6 of the object's radius outside a neighbouring plane
    count as on the facet (float32 round-off of the hit point is ~1e-7 of it)."""
    hit = ray_miss(t_max)
    m = geom.world_to_object[k]
    o = wp.transform_point(m, origin)
    d = wp.transform_vector(m, direction)
    s = geom.plane_start[k]
    tol = 1.0e-6 * geom.bounding_sphere[k][3]
    f = facet
    t, ok = _exits_through(geom, s, f, o, d, t_max, tol)
    if ok == 0:
        for i in range(geom.adj_start[s + facet], geom.adj_start[s + facet + 1]):
            f = geom.adj[i]
            t, ok = _exits_through(geom, s, f, o, d, t_max, tol)
            if ok != 0:
                break
    if ok != 0:
        p = geom.planes[s + f]
        hit.t = t
        hit.object = k
        hit.facet = f
        hit.normal = world_normal(m, wp.vec3f(p[0], p[1], p[2]))
    return hit, ok


@wp.kernel
def _closest_hit_kernel(
    offset: int,
    origins: wp.array(dtype=wp.vec3f),
    directions: wp.array(dtype=wp.vec3f),
    t_max: wp.array(dtype=wp.float32),
    geom: SceneGeometry,
    out_t: wp.array(dtype=wp.float32),
    out_object: wp.array(dtype=wp.int32),
    out_facet: wp.array(dtype=wp.int32),
    out_face: wp.array(dtype=wp.int32),
    out_normal: wp.array(dtype=wp.vec3f),
):
    i = wp.tid() + offset
    h = scene_closest_hit(geom, origins[i], directions[i], t_max[i])
    out_t[i] = h.t
    out_object[i] = h.object
    out_facet[i] = h.facet
    out_face[i] = h.face
    out_normal[i] = h.normal


@wp.kernel
def _exit_hit_kernel(
    offset: int,
    origins: wp.array(dtype=wp.vec3f),
    directions: wp.array(dtype=wp.vec3f),
    objects: wp.array(dtype=wp.int32),
    t_max: wp.array(dtype=wp.float32),
    geom: SceneGeometry,
    out_t: wp.array(dtype=wp.float32),
    out_object: wp.array(dtype=wp.int32),
    out_facet: wp.array(dtype=wp.int32),
    out_face: wp.array(dtype=wp.int32),
    out_normal: wp.array(dtype=wp.vec3f),
):
    i = wp.tid() + offset
    h = object_exit_hit(geom, objects[i], origins[i], directions[i], t_max[i])
    out_t[i] = h.t
    out_object[i] = h.object
    out_facet[i] = h.facet
    out_face[i] = h.face
    out_normal[i] = h.normal


class Hits(NamedTuple):
    """Closest hits as NumPy arrays: ``t`` (inf on a miss), ``object``, ``facet`` and ``face``
    (-1 on a miss; ``face`` -1 also where the convex path answered), ``normal`` (..., 3)."""

    t: np.ndarray
    object: np.ndarray
    facet: np.ndarray
    face: np.ndarray
    normal: np.ndarray


def _plane_blocks(planes_all, plane_start, plane_count):
    """SoA blocks of PLANE_BLOCK planes per object (``SceneGeometry.plane_blocks``): floats,
    float offset and block count of every object (instances share their mesh's blocks)."""
    allp = np.concatenate(planes_all).astype(np.float32)
    chunks, start_of = [], {}
    block_start, block_count = [], []
    total = 0
    for p0, pc in zip(plane_start, plane_count, strict=True):
        nb = -(-pc // PLANE_BLOCK)
        if (p0, pc) not in start_of:
            pad = np.zeros((nb * PLANE_BLOCK, 4), np.float32)
            pad[:, 3] = 1.0  # n = 0, d = 1: rate of approach 0, never the exit
            pad[:pc] = allp[p0 : p0 + pc]
            chunks.append(np.ascontiguousarray(pad.reshape(nb, PLANE_BLOCK, 4).transpose(0, 2, 1)).ravel())
            start_of[(p0, pc)] = total
            total += chunks[-1].size
        block_start.append(start_of[(p0, pc)])
        block_count.append(nb)
    blocks = np.concatenate(chunks) if chunks and total else np.zeros(4 * PLANE_BLOCK, np.float32)
    return blocks, np.array(block_start, np.int32), np.array(block_count, np.int32)


#: origin offset (mm) of a ray leaving a surface, for objects of bounding radius >= EPS_RADIUS
EPS_OFFSET = 1.0e-4
#: mm: below this bounding radius the offset shrinks with the object (EPS_OFFSET r / EPS_RADIUS)
EPS_RADIUS = 0.25
#: the offset is at least this many float32 spacings of the largest coordinate on the object
EPS_ULPS = 2.0


def offset_epsilon(radius, center) -> np.ndarray:
    """Origin offset (mm) of new rays leaving the surface of objects with world bounding spheres
    of ``radius`` (n,) and ``center`` (n, 3), mm.

    A new ray starts ``epsilon`` along its direction from the hit point so that its query does not
    find the surface it leaves.  Two bounds: relative to the object's size (1e-4 mm for a stone of
    radius >= 0.25 mm, 4e-4 of the radius below: the offset never skips a noticeable part of a
    small stone), and at least ``EPS_ULPS`` float32 spacings of the largest coordinate a point of
    the object has (``(|c|_max + r) 2^-23``: round-off of a hit point far from the origin)."""
    r = np.asarray(radius, dtype=np.float64).reshape(-1)
    c = np.asarray(center, dtype=np.float64).reshape(-1, 3)
    rel = EPS_OFFSET * np.minimum(1.0, r / EPS_RADIUS)
    floor = EPS_ULPS * (np.abs(c).max(axis=1) + r) * float(np.finfo(np.float32).eps)
    return np.maximum(rel, floor)


class GeometryScene:
    """Solids on a device, with their BVHs and facet planes, ready for kernels.

    ``objects``: meshes, or ``(mesh, object_to_world)`` pairs with a 4x4 affine transform (mm).
    ``convex``: ``"auto"`` (convex path for watertight convex meshes with at most
    ``convex_max_planes`` facets), ``True``/``False`` for all, or a per-object sequence of those.
    The ``wp.Mesh`` objects live as long as this scene; :attr:`geometry` is the struct to pass to
    kernels (``mode`` auto).  ``parents``: the innermost object containing each object (-1:
    none), as ``geometry.nesting.object_parents`` finds it; None: no object is nested.
    """

    def __init__(
        self,
        objects: Sequence[trimesh.Trimesh | tuple[trimesh.Trimesh, np.ndarray]],
        *,
        convex: bool | str | Sequence[bool | str] = "auto",
        convex_max_planes: int = 256,
        allow_empty: bool = False,
        parents: Sequence[int] | None = None,
        device=None,
    ) -> None:
        self.device = _device.get_device(device)
        objs = []
        for ob in objects:
            if isinstance(ob, trimesh.Trimesh):
                objs.append((ob, np.eye(4)))
            else:
                mesh, xf = ob
                xf = np.asarray(xf, dtype=np.float64)
                if xf.shape != (4, 4) or not np.all(np.isfinite(xf)):
                    raise ValueError("an object transform must be a finite 4x4 matrix")
                objs.append((mesh, xf))
        if not objs and not allow_empty:
            raise ValueError("a scene needs at least one object")
        if isinstance(convex, (bool, str)):
            convex = [convex] * len(objs)
        if len(convex) != len(objs):
            raise ValueError("convex: one flag per object")
        self.meshes: list[wp.Mesh] = []
        self.convex_flags: list[bool] = []
        planes_all, face_facet_all, w2o, spheres = [], [], [], []
        adj_counts, adj_all = [], []  # per unique mesh: facet neighbour counts and indices
        plane_start, plane_count, face_start = [], [], []
        np_, nf = 0, 0
        # instancing: objects given the SAME trimesh object share one wp.Mesh (one BVH, one set of
        # vertices) and one range of facet planes; only their transforms differ
        shared: dict[tuple[int, str], tuple] = {}
        for (mesh, xf), flag in zip(objs, convex, strict=True):
            key = (id(mesh), str(flag))
            if key in shared:
                wmesh, p0, pc, f0, sphere, use = shared[key]
                self.convex_flags.append(use)
                self.meshes.append(wmesh)
                plane_start.append(p0)
                plane_count.append(pc)
                face_start.append(f0)
                w2o.append(np.linalg.inv(xf))
                spheres.append(sphere)
                continue
            planes, face_facet = facet_planes(mesh)
            can = bool(mesh.is_watertight and mesh.is_convex)
            if flag == "auto":
                use = can and len(planes) <= convex_max_planes
            else:
                use = bool(flag)
                if use and not can:
                    raise ValueError("convex=True for a mesh that is not a closed convex solid")
            self.convex_flags.append(use)
            pts = wp.array(np.asarray(mesh.vertices, dtype=np.float32), dtype=wp.vec3f, device=self.device)
            idx = wp.array(np.asarray(mesh.faces, dtype=np.int32).ravel(), dtype=wp.int32, device=self.device)
            self.meshes.append(wp.Mesh(points=pts, indices=idx))
            planes_all.append(planes)
            face_facet_all.append(face_facet)
            nb_start, nb = facet_neighbours(mesh, face_facet, len(planes))
            adj_counts.append(np.diff(nb_start))
            adj_all.append(nb)
            plane_start.append(np_)
            plane_count.append(len(planes))
            face_start.append(nf)
            np_ += len(planes)
            nf += len(mesh.faces)
            w2o.append(np.linalg.inv(xf))
            v = np.asarray(mesh.vertices, dtype=np.float64)
            center = 0.5 * (v.min(axis=0) + v.max(axis=0))
            spheres.append([*center, float(np.max(np.linalg.norm(v - center, axis=1)))])
            shared[key] = (
                self.meshes[-1],
                plane_start[-1],
                plane_count[-1],
                face_start[-1],
                spheres[-1],
                use,
            )
        #: number of distinct meshes (BVHs) on the device; instances share one
        self.unique_meshes = len(shared)
        if not objs:
            # an empty scene (surfaces only): dummy rows, num_objects = 0
            planes_all, face_facet_all = [np.zeros((1, 4))], [np.zeros(1, dtype=np.int64)]
            w2o, spheres = [np.eye(4)], [[0.0, 0.0, 0.0, 0.0]]
            plane_start, plane_count, face_start = [0], [0], [0]
            adj_counts, adj_all = [np.zeros(1, np.int64)], [np.zeros(0, np.int64)]
            self.convex_flags = [False]
        dev = self.device
        self._convex_possible = [bool(m.is_watertight and m.is_convex) for m, _ in objs]
        g = SceneGeometry()
        g.num_objects = len(objs)
        g.mode = MODE_AUTO
        ids = np.array([m.id for m in self.meshes] or [0], dtype=np.uint64)
        g.mesh_ids = wp.array(ids, dtype=wp.uint64, device=dev)
        g.world_to_object = wp.array(np.array(w2o, dtype=np.float32), dtype=wp.mat44f, device=dev)
        g.convex = wp.array(np.array(self.convex_flags, dtype=np.int32), dtype=wp.int32, device=dev)
        g.plane_start = wp.array(np.array(plane_start, dtype=np.int32), dtype=wp.int32, device=dev)
        g.plane_count = wp.array(np.array(plane_count, dtype=np.int32), dtype=wp.int32, device=dev)
        g.planes = wp.array(np.concatenate(planes_all).astype(np.float32), dtype=wp.vec4f, device=dev)
        blocks, block_start, block_count = _plane_blocks(planes_all, plane_start, plane_count)
        g.plane_blocks = wp.array(blocks, dtype=wp.float32, device=dev)
        g.block_start = wp.array(block_start, dtype=wp.int32, device=dev)
        g.block_count = wp.array(block_count, dtype=wp.int32, device=dev)
        g.face_start = wp.array(np.array(face_start, dtype=np.int32), dtype=wp.int32, device=dev)
        g.face_facet = wp.array(np.concatenate(face_facet_all).astype(np.int32), dtype=wp.int32, device=dev)
        adj_start = np.concatenate([[0], np.cumsum(np.concatenate(adj_counts))]).astype(np.int32)
        adj = np.concatenate([*adj_all, np.zeros(1, np.int64)]).astype(np.int32)  # never empty
        g.adj_start = wp.array(adj_start, dtype=wp.int32, device=dev)
        g.adj = wp.array(adj, dtype=wp.int32, device=dev)
        g.bounding_sphere = wp.array(np.array(spheres, dtype=np.float32), dtype=wp.vec4f, device=dev)
        par = np.full(max(len(objs), 1), -1, dtype=np.int32)
        if parents is not None:
            if len(parents) != len(objs):
                raise ValueError("parents: one entry per object")
            par[: len(objs)] = np.asarray(parents, dtype=np.int32)
        g.parent = wp.array(par, dtype=wp.int32, device=dev)
        g.nested = int(np.any(par >= 0))
        # world bounding spheres: the object-space sphere through each transform
        eps = np.full(1, EPS_OFFSET)
        #: world bounding spheres (n, 4: centre, radius, mm) and world vertices of the objects
        #: (pixel beams: stages/pixel_beam.py beam_scene)
        self.world_spheres = np.zeros((0, 4))
        self.world_vertices = [
            np.asarray(m.vertices, np.float64) @ xf[:3, :3].T + xf[:3, 3] for m, xf in objs
        ]
        if objs:
            xfs = np.array([xf for _, xf in objs], dtype=np.float64)
            sph = np.array(spheres, dtype=np.float64)
            centers = np.einsum("nij,nj->ni", xfs[:, :3, :3], sph[:, :3]) + xfs[:, :3, 3]
            radii = sph[:, 3] * np.linalg.norm(xfs[:, :3, :3], ord=2, axis=(1, 2))
            eps = offset_epsilon(radii, centers)
            self.world_spheres = np.column_stack([centers, radii])
        g.epsilon = wp.array(eps.astype(np.float32), dtype=wp.float32, device=dev)
        self.geometry = g
        self._by_mode = {MODE_AUTO: g}

    def with_mode(self, mode: str = "auto") -> SceneGeometry:
        """The scene struct with a forced path: ``"auto"``, ``"bvh"`` or ``"convex"`` (all objects
        must then be closed convex solids)."""
        if mode not in _MODES:
            raise ValueError(f"mode {mode!r}: expected one of {sorted(_MODES)}")
        code = _MODES[mode]
        if code == MODE_CONVEX and not all(self._convex_possible):
            raise ValueError("mode 'convex' needs every object to be a closed convex solid")
        if code not in self._by_mode:
            src = self.geometry
            g = SceneGeometry()
            for name in (
                "num_objects",
                "mesh_ids",
                "world_to_object",
                "convex",
                "plane_start",
                "plane_count",
                "planes",
                "plane_blocks",
                "block_start",
                "block_count",
                "face_start",
                "face_facet",
                "adj_start",
                "adj",
                "bounding_sphere",
                "parent",
                "nested",
                "epsilon",
            ):
                setattr(g, name, getattr(src, name))
            g.mode = code
            self._by_mode[code] = g
        return self._by_mode[code]

    def launch_closest_hit(
        self,
        origins: wp.array,
        directions: wp.array,
        t_max: wp.array,
        out: Sequence[wp.array],
        *,
        mode: str = "auto",
        threads: int | None = None,
    ) -> None:
        """Closest hits of device arrays of rays into ``out = (t, object, facet, face, normal)``
        (tiled over ``threads`` CPU threads; one launch on CUDA)."""
        _device.launch_tiled(
            _closest_hit_kernel,
            len(origins),
            [origins, directions, t_max, self.with_mode(mode), *out],
            device=self.device,
            threads=threads,
        )

    def closest_hit(self, origins, directions, t_max=np.inf, *, mode: str = "auto") -> Hits:
        """Closest hits of NumPy rays (..., 3), broadcast; ``t_max`` in ray-parameter units."""
        t_max = np.minimum(np.asarray(t_max, dtype=np.float64), _BIG)
        t, obj, facet, face, normal = _device.elementwise(
            _closest_hit_kernel,
            [(origins, wp.vec3f), (directions, wp.vec3f), (t_max, wp.float32)],
            [wp.float32, wp.int32, wp.int32, wp.int32, wp.vec3f],
            extra=(self.with_mode(mode),),
            device=self.device,
        )
        t = np.where(obj >= 0, t, np.inf)
        return Hits(t, obj, facet, face, normal)

    def launch_exit_hit(
        self,
        origins: wp.array,
        directions: wp.array,
        objects: wp.array,
        t_max: wp.array,
        out: Sequence[wp.array],
        *,
        mode: str = "auto",
        threads: int | None = None,
    ) -> None:
        """Exits of device arrays of rays inside the given objects into
        ``out = (t, object, facet, face, normal)``."""
        _device.launch_tiled(
            _exit_hit_kernel,
            len(origins),
            [origins, directions, objects, t_max, self.with_mode(mode), *out],
            device=self.device,
            threads=threads,
        )

    def exit_hit(self, origins, directions, objects, t_max=np.inf, *, mode: str = "auto") -> Hits:
        """Where rays travelling inside ``objects`` (indices, broadcast) leave them (NumPy)."""
        obj = np.asarray(objects)
        if obj.size and (obj.min() < 0 or obj.max() >= self.geometry.num_objects):
            raise ValueError(f"object index out of range [0, {self.geometry.num_objects})")
        t_max = np.minimum(np.asarray(t_max, dtype=np.float64), _BIG)
        t, o, facet, face, normal = _device.elementwise(
            _exit_hit_kernel,
            [(origins, wp.vec3f), (directions, wp.vec3f), (obj, wp.int32), (t_max, wp.float32)],
            [wp.float32, wp.int32, wp.int32, wp.int32, wp.vec3f],
            extra=(self.with_mode(mode),),
            device=self.device,
        )
        t = np.where(o >= 0, t, np.inf)
        return Hits(t, o, facet, face, normal)
