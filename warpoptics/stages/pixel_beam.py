"""Pixel beams: a pixel's whole footprint traced through a convex stone as beams.

Why.  With spectral bundles (``stages/bundle.py``) a dispersive stone's noise is mostly where a
pixel's sample positions fall relative to facet edges.  A beam follows the whole pixel instead:
the part of the pixel whose rays meet each facet is a convex polygon (``geometry/polygon.py``:
pixel coordinates, a ray per vertex), and one Fresnel solution, one Jones matrix and a few
environment lookups serve each part.

What.  :func:`trace_beam` follows the pixel's polygon (:func:`pixel_beam`: the corners' camera
rays) for each of ``count`` wavelengths.  Entering the stone it is cut by the front facets its
rays meet; a part's outside reflection leaves the convex stone, its refraction continues inside,
where it is cut by the facets its rays leave through: each piece's refraction out is a leaf, its
internal reflection continues.  Every vertex's ray is reflected and refracted exactly
(``optics.fresnel``); a piece's amplitudes, Jones matrix and weight are its centre ray's
(``optics.interface.backward_isotropic``).  A leaf adds the piece's area fraction of the pixel
times the light averaged over up to 8 directions uniform in the piece, one per 0.0015 rad of
their spread (:func:`_lookup_count`), on the R2 sequence over the pixel's wavelengths, which
form one rotated lattice (``pipelines/render.py``).  Random choices left: Russian roulette
below ``split_threshold`` and, when the stack is full, a pick weighted by 1/probability.

Accuracy.  Orthographic camera: every cut and interpolated ray is exact, so the estimate is
unbiased.  Pinhole: rays interpolated after the first refraction are exact to first order in
the pixel's angle, and a part's Fresnel factors and absorption are its centre ray's (second
order).  Blocks (``render.beam_block``): a block of pixels traced as one beam, each leaf shared
by the pixels it covers; the centre ray's Fresnel factors make the bias first order in the
block's angle, so the default takes blocks up to 0.12 degrees.

Crystals and coatings: a part is one wave (o/e, fast/slow) through ``backward_crystal`` at its
centre, each vertex moved by its own wave (``backward_child_rays``); a coated solid takes the
stack's amplitudes at the centre.

Scope: convex solids (isotropic, uniaxial, biaxial or coated) seen through a pinhole or
orthographic camera.  A block's beam enters the stone :func:`beam_target` finds nothing in front
of; parts and misses that may meet anything but the environment (another solid, a surface, a
lamp) go on as point samples (``trace_radiance``), so the estimate stays unbiased.
Measurements and the variants dropped: docs/design/pixel_beams.md.

References: Heckbert & Hanrahan 1984, "Beam tracing polygonal objects", SIGGRAPH 84; Igehy
1999, "Tracing ray differentials", SIGGRAPH 99; Guy & Soler 2004, §5 (the pruned facet tree);
Veach 1997, ch. 4 (Russian roulette, selection weighted by 1/probability).
"""

from __future__ import annotations

import numpy as np
import warp as wp

from ..device import get_device
from ..film.leaf import add_coherency, add_leaf
from ..geometry.polygon import (
    COLS,
    MAX_VERTICES,
    BeamPolygon,
    VertexValues,
    clip_by_values,
    polygon_area,
    random_point,
)
from ..geometry.query import SceneGeometry, convex_closest_hit, world_normal
from ..materials.dispersion import MaterialTable
from ..optics.absorption import bouguer_lambert
from ..optics.biaxial import is_biaxial, medium_wave_normal
from ..optics.birefringence import uniaxial_medium
from ..optics.branches import ROW_B, ROW_D, ROW_IN, ROW_MI, ROW_MODE, ROW_MR, ROW_W, Cand, roulette
from ..optics.fresnel import reflect_direction, refract_direction
from ..optics.interface import (
    backward_child_rays,
    backward_coated,
    backward_crystal,
    backward_isotropic,
    event_tangential,
    is_uniaxial,
)
from ..optics.jones import Jones, coherency_unpolarized, jones_identity, jones_zero
from ..spectra import SpectralTables
from .bundle import LaneWavelengths, LaneWeights
from .camera import CameraParams, camera_ray
from .coated import KIND_COATED, coating_at
from .environment import Environment, environment_basis, environment_coefficients, spectral_response
from .media import isotropic_optics, object_medium, segment_kappa, zoned_isotropic_kappa, zoned_kappa
from .surfaces import Surfaces
from .trace import TraceParams, trace_radiance

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "MAX_PLANES",
    "MAX_PIECES",
    "STACK_ROWS",
    "SINK_COLS",
    "pixel_beam",
    "trace_beam",
    "sink_sums",
    "beam_obstacle",
    "beam_objects",
    "BeamScene",
    "beam_scene",
    "beam_targets",
]

#: facet planes of the stone a beam can handle
MAX_PLANES = 128
#: pieces one cut may give (beyond it: one of the rest, picked by fraction)
MAX_PIECES = 8
#: pending parts of the beam (beyond it: one of the rest, picked by fraction)
STACK_ROWS = 32
_PLANES = wp.constant(MAX_PLANES)
_PIECES = wp.constant(MAX_PIECES)
_STACK = wp.constant(STACK_ROWS)
_C = wp.constant(COLS)
_BIG = wp.constant(1.0e20)
#: environment lookups per leaf
_LOOKUPS = wp.constant(8)
_LOOKUP_ANGLE = wp.constant(0.0015)
# piece columns: the polygon (vertex i at COLS i), vertex count, fraction of the pixel, facet, the
# mean ray parameter from where the cut beam started (the centre ray's path, mm)
_P_NV = wp.constant(COLS * MAX_VERTICES)
_P_FRAC = wp.constant(COLS * MAX_VERTICES + 1)
_P_FACET = wp.constant(COLS * MAX_VERTICES + 2)
_P_T = wp.constant(COLS * MAX_VERTICES + 3)
_PIECE_COLS = COLS * MAX_VERTICES + 4
# stack columns: the piece's, then basis x, Jones (re 4, im 4), weight, depth
_S_B = wp.constant(_PIECE_COLS)
_S_MR = wp.constant(_PIECE_COLS + 3)
_S_MI = wp.constant(_PIECE_COLS + 7)
_S_W = wp.constant(_PIECE_COLS + 11)
_S_DEPTH = wp.constant(_PIECE_COLS + 12)
_S_MODE = wp.constant(_PIECE_COLS + 13)  # the wave's mode in a crystal (-1 isotropic, 0 o, 1 e)
_STACK_COLS = _PIECE_COLS + 14
# the sink's columns (a row per pixel): J_X, J_Y, J_Z (re 4, im 4 each), the scalar renderer's
# X, Y, Z, the fraction of the pixel that met the stone
_K_X = wp.constant(0)
_K_Y = wp.constant(8)
_K_Z = wp.constant(16)
_K_S = wp.constant(24)
_K_COVER = wp.constant(27)
SINK_COLS = 28
_SINK = wp.constant(SINK_COLS)

PieceBuf = wp.types.matrix(shape=(MAX_PIECES, _PIECE_COLS), dtype=wp.float32)
BeamStack = wp.types.matrix(shape=(STACK_ROWS, _STACK_COLS), dtype=wp.float32)
PlaneList = wp.types.vector(length=MAX_PLANES, dtype=wp.int32)
#: a crystal event's children's directions at each vertex of a part (3 columns per child)
VertexChildren = wp.types.matrix(shape=(MAX_VERTICES, 12), dtype=wp.float32)


@wp.struct
class BeamScene:
    """What beams need of the rest of a scene (:func:`beam_scene`): per object whether beams
    may enter it (``eligible``) and its world bounding sphere; the world planes ``(n, d)`` of the
    surfaces and area lights (``rect``; n.x = d on the plane), the spheres around those
    rectangles (``rect_sphere``) and, per object and plane, the least and greatest n.x - d over
    the object's vertices (``side``); ``others``: 1 when the scene holds
    anything besides one stone in the environment, so that parts and misses may meet it;
    ``traced``: 1 when lights the environment lookups do not see (suns, spots) make every leaf
    and miss a point sample; ``target``: when ``others``, each block's :func:`beam_target` for
    the camera of the pass (:func:`beam_targets`)."""

    num_objects: int
    eligible: wp.array(dtype=wp.int32)
    sphere: wp.array(dtype=wp.vec4f)
    num_rects: int
    rect: wp.array(dtype=wp.vec4f)
    rect_sphere: wp.array(dtype=wp.vec4f)
    side: wp.array2d(dtype=wp.vec2f)
    others: int
    traced: int
    target: wp.array(dtype=wp.int32)


@wp.func
def _p(poly: BeamPolygon, i: int):
    return wp.vec3f(poly[i, 2], poly[i, 3], poly[i, 4])


@wp.func
def _d(poly: BeamPolygon, i: int):
    return wp.vec3f(poly[i, 5], poly[i, 6], poly[i, 7])


@wp.func
def _set_ray(poly: BeamPolygon, i: int, x: wp.vec3f, d: wp.vec3f):
    for c in range(3):
        poly[i, 2 + c] = x[c]
        poly[i, 5 + c] = d[c]
    return poly


@wp.func
def _centre(poly: BeamPolygon, nv: int):
    """The part's centre ray: the mean of its vertices' points and (unit) directions."""
    x = wp.vec3f(0.0, 0.0, 0.0)
    d = wp.vec3f(0.0, 0.0, 0.0)
    for i in range(nv):
        x = x + _p(poly, i)
        d = d + _d(poly, i)
    return x / float(wp.max(nv, 1)), wp.normalize(d)


@wp.func
def pixel_beam(cam: CameraParams, px: int, py: int, bw: int, bh: int):
    """The beam of the block of ``bw`` x ``bh`` pixels from pixel (px, py) on: its corners
    (u, v) = (0, 0), (bw, 0), (bw, bh), (0, bh) in the block's pixel coordinates, with the
    camera's rays through them, the directions scaled to unit length along the camera's axis
    (then a pinhole's are linear in (u, v), and so exact when interpolated), and the basis x of
    the block centre's ray."""
    o_c, d_c, bx = camera_ray(cam, float(px) + 0.5 * float(bw), float(py) + 0.5 * float(bh), 0.5, 0.5)
    poly = BeamPolygon()
    for i in range(4):
        u = float(0.0)
        v = float(0.0)
        if i == 1 or i == 2:
            u = float(bw)
        if i >= 2:
            v = float(bh)
        o, d, b = camera_ray(cam, float(px) + u, float(py) + v, 0.5, 0.5)
        poly[i, 0] = u
        poly[i, 1] = v
        poly = _set_ray(poly, i, o, d / wp.dot(d, cam.forward))
    return poly, bx


@wp.func
def _obj(geom: SceneGeometry, k: int, poly: BeamPolygon, i: int):
    """Vertex i's ray in object k's space (ray parameters are the same in both spaces)."""
    m = geom.world_to_object[k]
    return wp.transform_point(m, _p(poly, i)), wp.transform_vector(m, _d(poly, i))


@wp.func
def _t_exit(geom: SceneGeometry, s: int, g: int, x: wp.vec3f, d: wp.vec3f):
    """Ray parameter at which the object-space ray x + t d leaves through plane g of the object
    whose planes start at ``s`` (_BIG: the plane does not face the ray)."""
    pl = geom.planes[s + g]
    n = wp.vec3f(pl[0], pl[1], pl[2])
    sd = wp.dot(n, d)
    if sd <= 0.0:
        return _BIG
    return (pl[3] - wp.dot(n, x)) / sd


@wp.func
def _t_entry(geom: SceneGeometry, s: int, g: int, x: wp.vec3f, d: wp.vec3f):
    """Ray parameter at which the object-space ray x + t d enters through plane g (-_BIG: the
    plane does not face the ray and x is inside it, so it sets no bound; _BIG: it does not face
    the ray and x is outside it, so the ray never enters: a ray parallel to a side facet and
    beside the stone misses it)."""
    pl = geom.planes[s + g]
    n = wp.vec3f(pl[0], pl[1], pl[2])
    sd = wp.dot(n, d)
    if sd >= 0.0:
        if wp.dot(n, x) > pl[3]:
            return _BIG
        return -_BIG
    return (pl[3] - wp.dot(n, x)) / sd


@wp.func
def _exit_argmin(geom: SceneGeometry, s: int, count: int, x: wp.vec3f, d: wp.vec3f):
    best = int(0)
    t_best = float(_BIG)
    for g in range(count):
        t = _t_exit(geom, s, g, x, d)
        if t < t_best:
            t_best = t
            best = g
    return best


@wp.func
def _exits_via(geom: SceneGeometry, s: int, f: int, x: wp.vec3f, d: wp.vec3f, tol: float):
    """Whether the ray x + t d from inside the convex solid leaves through facet ``f``: where it
    meets f's plane lies inside the planes of f's edge neighbours (``mesh.facet_neighbours``;
    ``geometry.query.convex_exit_near`` tests a ray the same way)."""
    a = geom.adj_start[s + f]
    b = geom.adj_start[s + f + 1]
    t = _t_exit(geom, s, f, x, d)
    if b == a or t >= _BIG:
        return 0
    q = x + d * t
    for i in range(a, b):
        pl = geom.planes[s + geom.adj[i]]
        if wp.dot(wp.vec3f(pl[0], pl[1], pl[2]), q) - pl[3] > tol:
            return 0
    return 1


@wp.func
def _add_candidate(lst: PlaneList, n: int, g: int):
    for i in range(n):
        if lst[i] == g:
            return lst, n
    if n < _PLANES:
        lst[n] = g
        n += 1
    return lst, n


@wp.func
def _project(geom: SceneGeometry, k: int, poly: BeamPolygon, nv: int, f: int):
    """Every vertex's ray moved to where it meets facet plane f of object k, and the mean of the
    moves (ray parameters)."""
    out = poly
    t_sum = float(0.0)
    pl = geom.planes[geom.plane_start[k] + f]
    n = wp.vec3f(pl[0], pl[1], pl[2])
    for i in range(nv):
        xo, do = _obj(geom, k, poly, i)
        x = _p(poly, i)
        d = _d(poly, i)
        sd = wp.dot(n, do)
        t = float(0.0)
        if sd != 0.0:
            t = (pl[3] - wp.dot(n, xo)) / sd
        t_sum += t
        out = _set_ray(out, i, x + d * t, d)
    return out, t_sum / float(wp.max(nv, 1))


@wp.func
def _reservoir(over: float, held: float, frac: float, u: float):
    """One step of weighted reservoir sampling (Chao 1982) over the parts that find no free row:
    ``over`` is the sum of the fractions met so far (0: none yet, then the part held in the row,
    of fraction ``held``, is the first).  Returns (keep the new part of fraction ``frac``, the new
    sum); the part kept at the end carries the whole sum, which is unbiased."""
    if over == 0.0:
        over = held
    over = over + frac
    return u * over < frac, over


@wp.func
def _put_piece(
    buf: PieceBuf,
    nb: int,
    q: BeamPolygon,
    nq: int,
    frac: float,
    facet: int,
    t: float,
    over: float,
    rng: wp.uint32,
):
    """Append a piece; one beyond the buffer's rows joins the last row's reservoir (kept with
    probability frac / all the fractions that met it, which it then carries: unbiased)."""
    row = nb
    if nb < _PIECES:
        nb += 1
    else:
        row = _PIECES - 1
        keep, over = _reservoir(over, buf[row, _P_FRAC], frac, wp.randf(rng))
        buf[row, _P_FRAC] = over
        if not keep:
            return buf, nb, over, rng
        frac = over
    for i in range(nq):
        for c in range(_C):
            buf[row, _C * i + c] = q[i, c]
    buf[row, _P_NV] = float(nq)
    buf[row, _P_FRAC] = frac
    buf[row, _P_FACET] = float(facet)
    buf[row, _P_T] = t
    return buf, nb, over, rng


@wp.func
def _add_region(
    geom: SceneGeometry,
    k: int,
    buf: PieceBuf,
    nb: int,
    q: BeamPolygon,
    m: int,
    f: int,
    area: float,
    covered: float,
    over: float,
    rng: wp.uint32,
):
    """A cut's region ``q`` of the beam (``area`` in all) that meets facet f: moved onto f and
    added as a piece with its fraction of the beam, unless empty; ``covered`` sums the
    fractions."""
    if m >= 3:
        a_f = polygon_area(q, m)
        if a_f > 0.0:
            frac = a_f / area
            covered += frac
            qp, t_mean = _project(geom, k, q, m, f)
            buf, nb, over, rng = _put_piece(buf, nb, qp, m, frac, f, t_mean, over, rng)
    return buf, nb, covered, over, rng


@wp.func
def _entry_region(geom: SceneGeometry, k: int, f: int, poly: BeamPolygon, nv: int):
    """The part of ``poly`` whose rays enter object k through facet f: f is the last plane they
    cross inward (largest entry parameter) and that comes before every outward crossing."""
    s0 = geom.plane_start[k]
    q = poly
    m = nv
    for g in range(geom.plane_count[k]):
        if g == f or m == 0:
            continue
        s = VertexValues()
        for i in range(m):
            x, d = _obj(geom, k, q, i)
            tf = _t_entry(geom, s0, f, x, d)
            tg_in = _t_entry(geom, s0, g, x, d)
            if tg_in > -_BIG:
                s[i] = tf - tg_in
            else:
                s[i] = _t_exit(geom, s0, g, x, d) - tf
        q, m = clip_by_values(q, m, s)
    return q, m


@wp.func
def _exit_region(geom: SceneGeometry, k: int, f: int, poly: BeamPolygon, nv: int, cands: PlaneList, nc: int):
    """The part of ``poly`` whose rays leave object k through facet f first among the
    candidates."""
    s0 = geom.plane_start[k]
    q = poly
    m = nv
    for ci in range(nc):
        e = cands[ci]
        if e == f or m == 0:
            continue
        s = VertexValues()
        for i in range(m):
            x, d = _obj(geom, k, q, i)
            s[i] = _t_exit(geom, s0, e, x, d) - _t_exit(geom, s0, f, x, d)
        q, m = clip_by_values(q, m, s)
    return q, m


@wp.func
def _entry_split(geom: SceneGeometry, k: int, poly: BeamPolygon, nv: int, rng: wp.uint32):
    """Cut a beam arriving from outside convex object k by the facets its rays enter through:
    (pieces on their facets with their fractions of the beam, count, the fraction of the pieces
    beyond the buffer's rows that one of them carries: 0 when every piece has its row); no
    pieces for k < 0 (no object: :func:`beam_target`)."""
    buf = PieceBuf()
    if k < 0:
        return buf, int(0), float(0.0), rng
    s0 = geom.plane_start[k]
    count = geom.plane_count[k]
    nb = int(0)
    first = int(-2)
    same = int(1)
    hits = int(0)
    for i in range(nv):
        x, d = _obj(geom, k, poly, i)
        t_in = float(-_BIG)
        t_out = float(_BIG)
        g_in = int(-1)
        for g in range(count):
            ti = _t_entry(geom, s0, g, x, d)
            if ti > t_in:
                t_in = ti
                g_in = g
            t_out = wp.min(t_out, _t_exit(geom, s0, g, x, d))
        g_hit = int(-1)
        if g_in >= 0 and t_in <= t_out:
            g_hit = g_in
            hits += 1
        if first == -2:
            first = g_hit
        elif g_hit != first:
            same = 0
    if same != 0 and first >= 0:
        q, t_mean = _project(geom, k, poly, nv, first)
        buf, nb, over, rng = _put_piece(buf, nb, q, nv, 1.0, first, t_mean, 0.0, rng)
        return buf, nb, over, rng
    if hits == 0:
        # no corner's ray hits: the whole beam misses unless the solid's bounding sphere comes
        # closer to the centre ray than the corners' rays spread there (object space)
        sph = geom.bounding_sphere[k]
        c = wp.vec3f(sph[0], sph[1], sph[2])
        reach = float(0.0)
        x0 = wp.vec3f(0.0, 0.0, 0.0)
        d0 = wp.vec3f(0.0, 0.0, 0.0)
        for i in range(nv):
            x, d = _obj(geom, k, poly, i)
            x0 = x0 + x / float(nv)
            d0 = d0 + d / float(nv)
        near = x0 + d0 * (wp.dot(c - x0, d0) / wp.dot(d0, d0))
        for i in range(nv):
            x, d = _obj(geom, k, poly, i)
            reach = wp.max(reach, wp.length(x + d * (wp.dot(c - x, d) / wp.dot(d, d)) - near))
        if wp.length(c - near) > sph[3] + reach:
            return buf, 0, 0.0, rng
    area = polygon_area(poly, nv)
    covered = float(0.0)
    over = float(0.0)
    for f in range(count):
        q, m = _entry_region(geom, k, f, poly, nv)
        buf, nb, covered, over, rng = _add_region(geom, k, buf, nb, q, m, f, area, covered, over, rng)
    return buf, nb, over, rng


@wp.func
def _exit_candidates(geom: SceneGeometry, k: int, poly: BeamPolygon, nv: int, tol: float):
    """The facet the first vertex's ray leaves object k through, and 0 candidates if every
    vertex's ray leaves through it (then the whole part does: the facet's projection along
    the rays is convex); else the candidate facets of a cut (those the vertices' rays leave
    through and their edge neighbours)."""
    s = geom.plane_start[k]
    count = geom.plane_count[k]
    x0, d0 = _obj(geom, k, poly, 0)
    f0 = _exit_argmin(geom, s, count, x0, d0)
    cands = PlaneList()
    nc = int(0)
    for i in range(1, nv):
        xi, di = _obj(geom, k, poly, i)
        if _exits_via(geom, s, f0, xi, di, tol) == 0:
            if nc == 0:
                cands, nc = _add_candidate(cands, nc, f0)
                for a in range(geom.adj_start[s + f0], geom.adj_start[s + f0 + 1]):
                    cands, nc = _add_candidate(cands, nc, geom.adj[a])
            fi = _exit_argmin(geom, s, count, xi, di)
            cands, nc = _add_candidate(cands, nc, fi)
            for a in range(geom.adj_start[s + fi], geom.adj_start[s + fi + 1]):
                cands, nc = _add_candidate(cands, nc, geom.adj[a])
    return f0, nc, cands


@wp.func
def _exit_split(
    geom: SceneGeometry,
    k: int,
    poly: BeamPolygon,
    nv: int,
    f0: int,
    nc: int,
    cands: PlaneList,
    rng: wp.uint32,
):
    """Cut a beam inside convex object k by the facets its rays leave through, given the
    candidates :func:`_exit_candidates` found: (pieces on their facets with fractions of the
    beam and mean path lengths, count)."""
    count = geom.plane_count[k]
    buf = PieceBuf()
    nb = int(0)
    area = polygon_area(poly, nv)
    if area <= 0.0:
        return buf, 0, rng  # a degenerate part carries no light
    over = float(0.0)
    if nc == 0:
        q, t_mean = _project(geom, k, poly, nv, f0)
        buf, nb, over, rng = _put_piece(buf, nb, q, nv, 1.0, f0, t_mean, 0.0, rng)
        return buf, nb, rng
    for attempt in range(2):
        if attempt == 1:
            # the candidates missed a facet the beam meets: all planes
            nc = count
            for g in range(count):
                cands[g] = g
        nb = int(0)
        over = float(0.0)
        covered = float(0.0)
        for ci in range(nc):
            f = cands[ci]
            q, m = _exit_region(geom, k, f, poly, nv, cands, nc)
            buf, nb, covered, over, rng = _add_region(geom, k, buf, nb, q, m, f, area, covered, over, rng)
        if wp.abs(covered - 1.0) < 1.0e-3:
            break
    return buf, nb, rng


@wp.func
def _may_meet_sphere(poly: BeamPolygon, nv: int, c: wp.vec3f, r: float):
    """Whether any ray of the beam ``poly`` (its vertices' rays and every ray between them) may
    meet the sphere (c, r): a ray from within ``ro`` of the centre ray's origin meets the sphere
    only if the centre's origin sees the sphere grown by ``ro`` within the rays' angular spread
    of the centre direction.  Conservative (True may be a miss), never wrong when False."""
    x_c, d_c = _centre(poly, nv)
    ro = float(0.0)
    cos_min = float(1.0)
    for i in range(nv):
        ro = wp.max(ro, wp.length(_p(poly, i) - x_c))
        cos_min = wp.min(cos_min, wp.dot(wp.normalize(_d(poly, i)), d_c))
    v = c - x_c
    dist = wp.length(v)
    rr = r + ro
    if dist <= rr:
        return True
    spread = wp.acos(wp.clamp(cos_min, -1.0, 1.0)) + wp.asin(wp.min(rr / dist, 1.0))
    return wp.acos(wp.clamp(wp.dot(v, d_c) / dist, -1.0, 1.0)) <= spread + 1.0e-4


@wp.func
def _sides(poly: BeamPolygon, nv: int, pl: wp.vec4f):
    """Of the beam's vertex rays against the plane n.x = d: how many origins lie on its positive
    side, on its negative side, and of those how many rays point away from the plane or along
    it (positive side, negative side)."""
    n = wp.vec3f(pl[0], pl[1], pl[2])
    pos = int(0)
    neg = int(0)
    pos_away = int(0)
    neg_away = int(0)
    for i in range(nv):
        sd = wp.dot(n, _p(poly, i)) - pl[3]
        sdir = wp.dot(n, _d(poly, i))
        if sd > 0.0:
            pos += 1
            if sdir >= 0.0:
                pos_away += 1
        elif sd < 0.0:
            neg += 1
            if sdir <= 0.0:
                neg_away += 1
    return pos, neg, pos_away, neg_away


@wp.func
def _may_meet_plane(poly: BeamPolygon, nv: int, pl: wp.vec4f):
    """Whether any ray of the beam ``poly`` may cross the plane n.x = d (False when every origin
    lies on one side and every direction points away from the plane or along it)."""
    _pos, _neg, pos_away, neg_away = _sides(poly, nv, pl)
    return pos_away != nv and neg_away != nv


@wp.func
def _may_meet_rect(bs: BeamScene, r: int, poly: BeamPolygon, nv: int):
    """Whether any ray of the beam may meet surface or lamp rectangle ``r``: it must cross the
    rectangle's plane and meet the sphere around it."""
    sp = bs.rect_sphere[r]
    c = wp.vec3f(sp[0], sp[1], sp[2])
    return _may_meet_plane(poly, nv, bs.rect[r]) and _may_meet_sphere(poly, nv, c, sp[3])


@wp.func(inline=False)  # out of line: kept out of the beams' hot loops (code size)
def _clear(bs: BeamScene, poly: BeamPolygon, nv: int, k: int):
    """Whether the beam ``poly`` (rays leaving object k, or missing it) surely meets nothing but
    the environment: then the environment lookups are its light, else point samples."""
    if bs.traced != 0:
        return False
    if bs.others == 0:
        return True
    for j in range(bs.num_objects):
        if j != k:
            sp = bs.sphere[j]
            if _may_meet_sphere(poly, nv, wp.vec3f(sp[0], sp[1], sp[2]), sp[3]):
                return False
    for r in range(bs.num_rects):
        if _may_meet_rect(bs, r, poly, nv):
            return False
    return True


@wp.func(inline=False)  # out of line: kept out of the beams' hot loops (code size)
def beam_target(bs: BeamScene, poly: BeamPolygon, nv: int):
    """The object a block's beam enters: the one nearest the camera among those its rays may meet
    (-1: none), when beams may enter it and nothing may stand in front of it for any of the rays:
    every other object it may meet lies wholly behind it, and every surface or lamp plane has
    the camera and the whole object on one side.  -2: the block is point-sampled."""
    x_c, _d_c = _centre(poly, nv)
    ro = float(0.0)
    for i in range(nv):
        ro = wp.max(ro, wp.length(_p(poly, i) - x_c))
    k = int(-1)
    near_k = float(_BIG)
    far_k = float(_BIG)
    for j in range(bs.num_objects):
        sp = bs.sphere[j]
        c = wp.vec3f(sp[0], sp[1], sp[2])
        if _may_meet_sphere(poly, nv, c, sp[3]):
            dist = wp.length(c - x_c)
            if dist - sp[3] - ro < near_k:
                near_k = dist - sp[3] - ro
                far_k = dist + sp[3] + ro
                k = j
    if k < 0:
        return k
    if bs.eligible[k] == 0:
        return -2
    for j in range(bs.num_objects):
        sp = bs.sphere[j]
        c = wp.vec3f(sp[0], sp[1], sp[2])
        if j != k and _may_meet_sphere(poly, nv, c, sp[3]):
            if wp.length(c - x_c) - sp[3] - ro < far_k:
                return -2
    tol = 1.0e-3 * bs.sphere[k][3]
    for r in range(bs.num_rects):
        if _may_meet_rect(bs, r, poly, nv):
            pos, neg, _pa, _na = _sides(poly, nv, bs.rect[r])
            ext = bs.side[k, r]
            if not ((pos == nv and ext[0] >= -tol) or (neg == nv and ext[1] <= tol)):
                return -2
    return k


@wp.func
def _meets_convex(geom: SceneGeometry, k: int, o: wp.vec3f, d: wp.vec3f):
    """Whether the world ray o + t d (t > 0) from outside convex object k meets it (its facet
    planes: ``geometry.query.convex_closest_hit``)."""
    m = geom.world_to_object[k]
    x = wp.transform_point(m, o)
    v = wp.transform_vector(m, d)
    _t, facet = convex_closest_hit(geom.planes, geom.plane_start[k], geom.plane_count[k], x, v, _BIG)
    return facet >= 0


@wp.func
def _lookup_count(poly: BeamPolygon, nv: int):
    """How many environment lookups a part's light takes: one per _LOOKUP_ANGLE of the angular
    diameter of its rays' directions, 1 to _LOOKUPS."""
    _x, d_c = _centre(poly, nv)
    spread = float(0.0)
    for r in range(nv):
        spread = wp.max(spread, wp.length(wp.normalize(_d(poly, r)) - d_c))
    return wp.clamp(int(wp.ceil(2.0 * spread / _LOOKUP_ANGLE)), 1, _LOOKUPS)


@wp.func
def _part_light(env: Environment, b3: wp.vec3f, poly: BeamPolygon, nv: int, rot: wp.vec2f, g: float):
    """The environment's light at one wavelength (basis ``b3``) averaged over the directions of
    the part's rays, by n <= _LOOKUPS points uniform in the part (:func:`_lookup_count`): those
    of the R2 sequence (Roberts 2018) from index ``g`` n on, rotated by ``rot``; lane g's points
    follow lane g-1's (neighbouring wavelengths' parts are alike, and so is their n), so the
    lanes of neighbouring wavelengths spread their lookups evenly over similar parts.  (Indexed
    from g _LOOKUPS instead, single lookups leave gaps of 7 between lanes: 2.7 % instead of
    1.4 % at 64x64 and 32 wavelengths.)"""
    acc = float(0.0)
    n = _lookup_count(poly, nv)
    for i in range(n):
        u = _r2(rot, g * float(n) + float(i))
        b = random_point(poly, nv, u[0], u[1])
        d = wp.vec3f(0.0, 0.0, 0.0)
        for r in range(nv):
            d = d + _d(poly, r) * b[r]
        acc += wp.dot(b3, environment_coefficients(env, wp.normalize(d)))
    return acc / float(n)


@wp.func
def _sink_jones(sink: wp.array2d(dtype=wp.float32), pix: int, c: int):
    m = Jones()
    m.re = wp.mat22(sink[pix, c], sink[pix, c + 1], sink[pix, c + 2], sink[pix, c + 3])
    m.im = wp.mat22(sink[pix, c + 4], sink[pix, c + 5], sink[pix, c + 6], sink[pix, c + 7])
    return m


@wp.func
def _sink_set_jones(sink: wp.array2d(dtype=wp.float32), pix: int, c: int, m: Jones):
    for i in range(2):
        for j in range(2):
            sink[pix, c + 2 * i + j] = m.re[i, j]
            sink[pix, c + 4 + 2 * i + j] = m.im[i, j]


@wp.func
def sink_sums(sink: wp.array2d(dtype=wp.float32), pix: int, polarized: int):
    """Pixel ``pix``'s sums in the beams' sink (:func:`trace_beam`): (coherency matrices J_X,
    J_Y, J_Z, the fraction of the pixel that met the stone), and the row cleared for the next
    bundle."""
    acc_x = jones_zero()
    acc_y = jones_zero()
    acc_z = jones_zero()
    if polarized != 0:
        acc_x = _sink_jones(sink, pix, _K_X)
        acc_y = _sink_jones(sink, pix, _K_Y)
        acc_z = _sink_jones(sink, pix, _K_Z)
    else:
        acc_x = coherency_unpolarized(sink[pix, _K_S])
        acc_y = coherency_unpolarized(sink[pix, _K_S + 1])
        acc_z = coherency_unpolarized(sink[pix, _K_S + 2])
    cover = sink[pix, _K_COVER]
    for c in range(_SINK):
        sink[pix, c] = 0.0
    return acc_x, acc_y, acc_z, cover


@wp.func
def _sink_read(sink: wp.array2d(dtype=wp.float32), pix: int):
    """Pixel ``pix``'s running sums: J_X, J_Y, J_Z and the scalar renderer's XYZ."""
    sc = wp.vec3f(sink[pix, _K_S], sink[pix, _K_S + 1], sink[pix, _K_S + 2])
    return _sink_jones(sink, pix, _K_X), _sink_jones(sink, pix, _K_Y), _sink_jones(sink, pix, _K_Z), sc


@wp.func
def _sink_write(
    sink: wp.array2d(dtype=wp.float32),
    pix: int,
    polarized: int,
    acc_x: Jones,
    acc_y: Jones,
    acc_z: Jones,
    sc: wp.vec3f,
):
    if polarized != 0:
        _sink_set_jones(sink, pix, _K_X, acc_x)
        _sink_set_jones(sink, pix, _K_Y, acc_y)
        _sink_set_jones(sink, pix, _K_Z, acc_z)
    else:
        for c in range(3):
            sink[pix, _K_S + c] = sc[c]


@wp.func
def _sink_leaf(
    sink: wp.array2d(dtype=wp.float32),
    pix: int,
    polarized: int,
    m: Jones,
    w: float,
    polarizer: wp.vec3f,
    k: wp.vec3f,
    basis_x: wp.vec3f,
    xyz: wp.vec3f,
):
    """A leaf's light into pixel ``pix``'s sums (``film.leaf.add_leaf``, the one rule)."""
    acc_x, acc_y, acc_z, sc = _sink_read(sink, pix)
    acc_x, acc_y, acc_z, sc = add_leaf(acc_x, acc_y, acc_z, sc, polarized, m, w, polarizer, k, basis_x, xyz)
    _sink_write(sink, pix, polarized, acc_x, acc_y, acc_z, sc)


@wp.func
def _sink_coherency(
    sink: wp.array2d(dtype=wp.float32),
    pix: int,
    polarized: int,
    m: Jones,
    w: float,
    c_x: Jones,
    c_y: Jones,
    c_z: Jones,
):
    """A point sample's light (coherencies from the camera trace) into pixel ``pix``'s sums
    through the part's Jones matrix ``m`` and weight ``w`` (``film.leaf.add_coherency``)."""
    acc_x, acc_y, acc_z, sc = _sink_read(sink, pix)
    acc_x, acc_y, acc_z, sc = add_coherency(acc_x, acc_y, acc_z, sc, polarized, m, w, c_x, c_y, c_z)
    _sink_write(sink, pix, polarized, acc_x, acc_y, acc_z, sc)


@wp.func(inline=False)  # out of line: the point tracer's state stays out of the beams' loops
def _point_sample(
    p: TraceParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    env: Environment,
    surf: Surfaces,
    tables: SpectralTables,
    polarized: int,
    o: wp.vec3f,
    d: wp.vec3f,
    b: wp.vec3f,
    wl: float,
    xyz_w: wp.vec3f,
    resp: wp.mat33f,
    sink: wp.array2d(dtype=wp.float32),
    pix: int,
    m: Jones,
    w: float,
    rng: wp.uint32,
):
    """A point sample along (o, d) (frame ``b``) at one wavelength, traced by the point tracer
    (``trace_radiance``), into pixel ``pix``'s sums through Jones matrix ``m`` and weight ``w``.
    Returns (whether it met anything, rays traced, rng)."""
    c_x, c_y, c_z, hit, nr, rng = trace_radiance(
        p, geom, mats, env, surf, tables, polarized, o, d, b, wl, xyz_w, resp, 0, rng
    )
    _sink_coherency(sink, pix, polarized, m, w, c_x, c_y, c_z)
    return hit, nr, rng


@wp.func(inline=False)
def _part_sample(
    p: TraceParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    env: Environment,
    surf: Surfaces,
    tables: SpectralTables,
    polarized: int,
    q: BeamPolygon,
    nq: int,
    ix0: int,
    ix1: int,
    iy0: int,
    iy1: int,
    x_off: wp.vec3f,
    basis: wp.vec3f,
    wl: float,
    xyz_w: wp.vec3f,
    resp: wp.mat33f,
    sink: wp.array2d(dtype=wp.float32),
    pix0: int,
    width: int,
    m: Jones,
    w: float,
    u: wp.vec2f,
    rng: wp.uint32,
):
    """A leaving part continued as a point sample: the ray at ``u`` uniform in the part (by its
    area in the block's pixel coordinates; origin moved off the facet by ``x_off``), traced on,
    its light entering the pixel it falls in (of the cells [ix0, ix1] x [iy0, iy1]; ``pix0``
    the block's first pixel) through the part's Jones matrix and weight.  Returns (rays, rng)."""
    bw = random_point(q, nq, u[0], u[1])
    x = wp.vec3f(0.0, 0.0, 0.0)
    d = wp.vec3f(0.0, 0.0, 0.0)
    pu = float(0.0)
    pv = float(0.0)
    for r in range(nq):
        x = x + _p(q, r) * bw[r]
        d = d + _d(q, r) * bw[r]
        pu += q[r, 0] * bw[r]
        pv += q[r, 1] * bw[r]
    d = wp.normalize(d)
    ix = wp.clamp(int(wp.floor(pu)), ix0, ix1)
    iy = wp.clamp(int(wp.floor(pv)), iy0, iy1)
    b = wp.normalize(basis - d * wp.dot(basis, d))
    _hit, nr, rng = _point_sample(
        p, geom, mats, env, surf, tables, polarized, x + x_off, d, b, wl, xyz_w, resp, sink,
        pix0 + ix + iy * width, m, w, rng,
    )  # fmt: skip
    return nr, rng


@wp.func(inline=False)
def _miss_sample(
    p: TraceParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    env: Environment,
    surf: Surfaces,
    tables: SpectralTables,
    polarized: int,
    k: int,
    cam: CameraParams,
    px: int,
    py: int,
    wl: float,
    xyz_w: wp.vec3f,
    sink: wp.array2d(dtype=wp.float32),
    pix: int,
    u: wp.vec2f,
    rng: wp.uint32,
):
    """A point sample at ``u`` uniform in pixel (px, py) for its part that misses object ``k``
    (a ray that meets k is the beams' and adds nothing; k < 0: none is), traced and added to
    the pixel's sums.  Returns (whether it met anything, rays, rng)."""
    o, d, b = camera_ray(cam, float(px) + u[0], float(py) + u[1], 0.5, 0.5)
    if k >= 0:
        if _meets_convex(geom, k, o, d):
            return int(0), int(0), rng
    resp = spectral_response(env, tables, wl, xyz_w)
    return _point_sample(
        p,
        geom,
        mats,
        env,
        surf,
        tables,
        polarized,
        o,
        d,
        b,
        wl,
        xyz_w,
        resp,
        sink,
        pix,
        jones_identity(),
        1.0,
        rng,
    )


@wp.func
def _r2(rot: wp.vec2f, g: float):
    """Point g of the R2 sequence (Roberts 2018) rotated by ``rot`` (Cranley-Patterson)."""
    u = rot + wp.vec2f(g * 0.7548776662466927, g * 0.5698402909980532)
    return u - wp.vec2f(wp.floor(u[0]), wp.floor(u[1]))


@wp.func
def _cells(q: BeamPolygon, nq: int, bw: int, bh: int):
    """The block's pixels that part ``q`` may overlap: (first column, last, first row, last)."""
    u0 = float(_BIG)
    u1 = float(-_BIG)
    v0 = float(_BIG)
    v1 = float(-_BIG)
    for r in range(nq):
        u0 = wp.min(u0, q[r, 0])
        u1 = wp.max(u1, q[r, 0])
        v0 = wp.min(v0, q[r, 1])
        v1 = wp.max(v1, q[r, 1])
    ix0 = wp.clamp(int(wp.floor(u0)), 0, bw - 1)
    iy0 = wp.clamp(int(wp.floor(v0)), 0, bh - 1)
    return ix0, wp.clamp(int(wp.ceil(u1)) - 1, ix0, bw - 1), iy0, wp.clamp(int(wp.ceil(v1)) - 1, iy0, bh - 1)


@wp.func
def _in_cell(q: BeamPolygon, nq: int, ix: int, iy: int, ix0: int, ix1: int, iy0: int, iy1: int):
    """The part of ``q`` in the block's pixel (ix, iy), of the cells [ix0, ix1] x [iy0, iy1] it
    may overlap (only the cells' inner edges cut it)."""
    c = q
    m = nq
    for side in range(4):
        s = VertexValues()
        cut = int(0)
        for r in range(m):
            if side == 0 and ix > ix0:
                s[r] = c[r, 0] - float(ix)
                cut = 1
            elif side == 1 and ix < ix1:
                s[r] = float(ix + 1) - c[r, 0]
                cut = 1
            elif side == 2 and iy > iy0:
                s[r] = c[r, 1] - float(iy)
                cut = 1
            elif side == 3 and iy < iy1:
                s[r] = float(iy + 1) - c[r, 1]
                cut = 1
        if cut != 0:
            c, m = clip_by_values(c, m, s)
    return c, m


@wp.func(inline=False)  # out of line, like trace_bundle (compile time)
def _trace_entry(
    p: TraceParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    env: Environment,
    surf: Surfaces,
    tables: SpectralTables,
    polarized: int,
    bs: BeamScene,
    k: int,
    cam: CameraParams,
    px0: int,
    py0: int,
    bw: int,
    bh: int,
    width: int,
    sink: wp.array2d(dtype=wp.float32),
    basis_x: wp.vec3f,
    entry: PieceBuf,
    n_entry: int,
    wavelengths: LaneWavelengths,
    weights: LaneWeights,
    count: int,
    first: int,
    step: int,
    rot: wp.vec2f,
    rng: wp.uint32,
):
    """:func:`trace_beam` for the block's beam cut by its entry into object ``k`` (``entry``,
    ``n_entry`` pieces, every one with its own row) and the block centre's basis x; ``k`` = -1:
    the block meets no object, -2: it is point-sampled (:func:`beam_target`)."""
    a_beam = float(bw * bh)  # the block's pixels (fractions are of the block)
    ko = wp.max(k, 0)
    m_w = geom.world_to_object[ko]
    s = geom.plane_start[ko]
    tol = 1.0e-6 * geom.bounding_sphere[ko][3]
    eps = geom.epsilon[ko]
    mat = p.object_material[ko]
    coated = p.films.kind[ko] == KIND_COATED
    one = jones_identity()
    parts = int(0)
    # each pixel's share of the entry is its cover
    for i in range(n_entry):
        nq = int(entry[i, _P_NV])
        q = BeamPolygon()
        for r in range(nq):
            for c in range(_C):
                q[r, c] = entry[i, _C * r + c]
        share = entry[i, _P_FRAC] * a_beam
        ix0, ix1, iy0, iy1 = _cells(q, nq, bw, bh)
        if ix0 == ix1 and iy0 == iy1:
            sink[px0 + ix0 + (py0 + iy0) * width, _K_COVER] += share
        else:
            a_q = polygon_area(q, nq)
            for iy in range(iy0, iy1 + 1):
                for ix in range(ix0, ix1 + 1):
                    cq, cm = _in_cell(q, nq, ix, iy, ix0, ix1, iy0, iy1)
                    if cm >= 3 and a_q > 0.0:
                        sink[px0 + ix + (py0 + iy) * width, _K_COVER] += share * polygon_area(cq, cm) / a_q
    # each pixel's part that misses the stone: the directions of the pixel's spread, or where they
    # may meet something else, a point sample per wavelength uniform in the pixel (one that meets
    # the stone is the beams' and adds nothing: unbiased)
    for iy in range(bh):
        for ix in range(bw):
            pix = px0 + ix + (py0 + iy) * width
            miss_c = wp.clamp(1.0 - sink[pix, _K_COVER], 0.0, 1.0)
            sink[pix, _K_COVER] = 1.0 - miss_c
            if miss_c > 1.0e-6:
                cell, bx_c = pixel_beam(cam, px0 + ix, py0 + iy, 1, 1)
                _x_c, d_cell = _centre(cell, 4)
                clear = k != -2
                if clear and bs.others != 0:
                    clear = _clear(bs, cell, 4, k)
                for j in range(count):
                    xyz_w = wp.vec3f(weights[j, 0], weights[j, 1], weights[j, 2])
                    g_j = float(first + j * step)
                    if clear:
                        b3 = environment_basis(env, tables, wavelengths[j])
                        rad = _part_light(env, b3, cell, 4, rot, g_j)
                        _sink_leaf(
                            sink, pix, polarized, one, miss_c, env.polarizer, -d_cell, bx_c, xyz_w * rad
                        )
                    else:
                        hit, nr, rng = _miss_sample(
                            p, geom, mats, env, surf, tables, polarized, k, cam, px0 + ix, py0 + iy,
                            wavelengths[j], xyz_w, sink, pix, _r2(rot, g_j), rng,
                        )  # fmt: skip
                        sink[pix, _K_COVER] += float(hit) / float(count)
                        parts += nr
    if n_entry == 0:
        return parts, rng
    cand = Cand()
    st = BeamStack()
    for j in range(count):
        wl = wavelengths[j]
        # lane j's index among the pixel's wavelengths, in the order of their strata
        g = float(first + j * step)
        b3 = environment_basis(env, tables, wl)
        xyz_w = wp.vec3f(weights[j, 0], weights[j, 1], weights[j, 2])
        resp = wp.mat33f()
        if bs.others != 0:
            resp = spectral_response(env, tables, wl, xyz_w)  # for parts traced on as point samples
        # a crystal (uniaxial or biaxial): each part is one wave (o or e, fast or slow) with its own
        # index and absorption; an isotropic stone's index and kappa serve every part of the lane
        amb = uniaxial_medium(p.ambient[0], p.ambient[0], wp.vec3f(0.0, 0.0, 0.0))
        med_s, no_s, _ne_s, alpha_s = object_medium(mats, mat, p.object_axis[k], wl)
        crystal = is_uniaxial(med_s)
        n_in = no_s[0]
        kappa = float(0.0)
        if not crystal:
            n_in, kappa = isotropic_optics(mats, mat, p.object_axis[k], wl, p.object_absorption_scale[k])
        n = int(0)
        over = float(0.0)  # the reservoir in the stack's last row: the fractions that met it
        # the pieces of the cut being traced: first the entry's, then those of popped parts
        buf = entry
        nb = n_entry
        inside = int(-1)
        depth = int(0)
        b_w = basis_x
        m_j = one
        w_j = float(1.0)
        mode_j = int(-1)
        while True:
            for i in range(nb):
                if depth >= p.max_depth:
                    break
                nq = int(buf[i, _P_NV])
                frac = buf[i, _P_FRAC]
                f = int(buf[i, _P_FACET])
                q = BeamPolygon()
                for r in range(nq):
                    for c in range(_C):
                        q[r, c] = buf[i, _C * r + c]
                parts += 1
                x_c, d_c = _centre(q, nq)
                pl = geom.planes[s + f]
                n_out = world_normal(m_w, wp.vec3f(pl[0], pl[1], pl[2]))
                n_a = wp.vec2f(p.ambient[0], 0.0)
                n_b = wp.vec2f(n_in, 0.0)
                med_a = amb
                med_b = med_s
                nrm = n_out
                in_b = k
                w_i = w_j
                # the parent's wave normal is the light's (optics/interface.py): against the ray
                wn_c = -d_c
                if inside >= 0:
                    n_a = wp.vec2f(n_in, 0.0)
                    n_b = wp.vec2f(p.ambient[0], 0.0)
                    med_a = med_s
                    med_b = amb
                    nrm = -n_out
                    in_b = -1
                    # Bouguer-Lambert along the centre ray's segment (module docstring), through
                    # the zones of a colour-zoned stone (the segment ends at the centre x_c); in a
                    # crystal the kappa of the centre ray's wave (Guy & Soler 2004 eq. 7)
                    l_c = buf[i, _P_T] * wp.length(_d(q, 0))
                    x_s = x_c - d_c * l_c
                    kappa_c = float(0.0)
                    if crystal:
                        wn_c = -medium_wave_normal(d_c, mode_j, med_s)
                        sc = p.object_absorption_scale[k]
                        kappa_c = segment_kappa(mats, mat, alpha_s, -1, mode_j, wn_c, med_s, sc)
                        kappa_c = zoned_kappa(
                            mats, mat, kappa_c, -1, mode_j, wn_c, med_s, sc, wl, x_s, d_c, l_c
                        )
                    else:
                        kappa_c = zoned_isotropic_kappa(
                            mats, mat, kappa, n_in, p.object_absorption_scale[k], wl, x_s, d_c, l_c
                        )
                    if kappa_c != 0.0:
                        w_i = w_i * bouguer_lambert(kappa_c, l_c)
                b_i = wp.normalize(b_w - d_c * wp.dot(b_w, d_c))
                kc = int(0)
                energies = wp.vec4f(0.0, 0.0, 0.0, 0.0)
                vch = VertexChildren()
                # the vertices' rays move as isotropic ones (Snell) unless the crystal is exact
                snell = not crystal
                n_av = n_a[0]
                n_bv = n_b[0]
                if crystal:
                    # the crystal event (optics.interface.backward_crystal) for the centre ray
                    cand, energies, kc = backward_crystal(
                        cand, m_j, w_i, b_i, d_c, wn_c, mode_j, n_out, nrm, med_a, med_b, n_a, n_b, x_c, eps,
                        inside, in_b, depth, polarized, p.birefringence,
                    )  # fmt: skip
                    if p.birefringence != 0 and not is_biaxial(med_s):
                        # approx (Guy & Soler 2004 §4.2): one direction per side, by the mean indices
                        snell = True
                        n_av = 0.5 * (med_a.no + med_a.ne)
                        n_bv = 0.5 * (med_b.no + med_b.ne)
                    else:
                        # exact: every vertex ray by its own wave (its wave normal from its ray,
                        # the event's tangential wave vector, each child's wave on its side); a
                        # vertex whose child's wave does not propagate (total reflection there
                        # alone) keeps the centre child's direction
                        for r in range(nq):
                            d_r = wp.normalize(_d(q, r))
                            wn_r = -d_r
                            if inside >= 0:
                                wn_r = -medium_wave_normal(d_r, mode_j, med_s)
                            rays = backward_child_rays(
                                event_tangential(wn_r, mode_j, nrm, med_a), nrm, med_a, med_b
                            )
                            for ci in range(kc):
                                row_v = int(0)
                                if int(cand[ci, ROW_IN]) == in_b:
                                    row_v = 2
                                if int(cand[ci, ROW_MODE]) == 1:
                                    row_v += 1
                                for c in range(3):
                                    vch[r, 3 * ci + c] = rays[row_v, c]
                                if rays[row_v, 0] == 0.0 and rays[row_v, 1] == 0.0 and rays[row_v, 2] == 0.0:
                                    for c in range(3):
                                        vch[r, 3 * ci + c] = cand[ci, ROW_D + c]
                elif coated:
                    # a coated solid: the stack's amplitudes at the centre (stages/coated.py);
                    # a film keeps the tangential wave vector, so the vertices move by Snell
                    coat, f_scale = coating_at(p.films, k, x_c, m_w)
                    a_front = int(0)
                    if inside < 0:
                        a_front = 1
                    cand, energies, kc = backward_coated(
                        cand, m_j, w_i, b_i, d_c, n_out, nrm, n_a, n_b, x_c, eps, inside, in_b, depth,
                        polarized, p.films.stack, coat, wl, f_scale, a_front,
                    )  # fmt: skip
                else:
                    cand, energies, kc = backward_isotropic(
                        cand, m_j, w_i, b_i, d_c, n_out, nrm, n_a, n_b, x_c, eps, inside, in_b, depth,
                        polarized,
                    )  # fmt: skip
                for ci in range(kc):
                    d_ch = wp.vec3f(cand[ci, ROW_D], cand[ci, ROW_D + 1], cand[ci, ROW_D + 2])
                    b_ch = wp.vec3f(cand[ci, ROW_B], cand[ci, ROW_B + 1], cand[ci, ROW_B + 2])
                    reflected = int(cand[ci, ROW_IN]) == inside
                    # every vertex's ray reflected or refracted by the same laws as the centre's
                    qc = q
                    for r in range(nq):
                        d_n = wp.vec3f(vch[r, 3 * ci], vch[r, 3 * ci + 1], vch[r, 3 * ci + 2])
                        if snell:
                            d_r = wp.normalize(_d(q, r))
                            d_n = reflect_direction(d_r, n_out)
                            if not reflected:
                                d_n = refract_direction(d_r, nrm, n_av, n_bv)
                                if wp.dot(d_n, d_n) == 0.0:
                                    d_n = d_ch  # total internal reflection at this vertex alone
                        qc = _set_ray(qc, r, _p(q, r), d_n)
                    w_c = cand[ci, ROW_W]
                    m_c = Jones()
                    m_c.re = wp.mat22(
                        cand[ci, ROW_MR], cand[ci, ROW_MR + 1], cand[ci, ROW_MR + 2], cand[ci, ROW_MR + 3]
                    )
                    m_c.im = wp.mat22(
                        cand[ci, ROW_MI], cand[ci, ROW_MI + 1], cand[ci, ROW_MI + 2], cand[ci, ROW_MI + 3]
                    )
                    if int(cand[ci, ROW_IN]) < 0:
                        # leaves the convex stone (reflected off it or refracted out): a leaf,
                        # shared among the pixels it overlaps by their areas of it
                        share = frac * a_beam
                        ix0, ix1, iy0, iy1 = _cells(qc, nq, bw, bh)
                        traced = False
                        if bs.others != 0:  # (a test of one int on the common path: no struct copies)
                            traced = not _clear(bs, qc, nq, k)
                        if traced:
                            # its rays may meet another object, a surface or a lamp: a point sample
                            nr, rng = _part_sample(
                                p, geom, mats, env, surf, tables, polarized, qc, nq, ix0, ix1, iy0, iy1,
                                n_out * eps, b_ch, wl, xyz_w, resp, sink, px0 + py0 * width, width, m_c,
                                w_c * share, _r2(rot, g), rng,
                            )  # fmt: skip
                            parts += nr
                            continue
                        if ix0 == ix1 and iy0 == iy1:
                            rad = _part_light(env, b3, qc, nq, rot, g)
                            _sink_leaf(
                                sink, px0 + ix0 + (py0 + iy0) * width, polarized, m_c, w_c * share,
                                env.polarizer, -d_ch, b_ch, xyz_w * rad,
                            )  # fmt: skip
                        else:
                            a_q = polygon_area(qc, nq)
                            for iy in range(iy0, iy1 + 1):
                                for ix in range(ix0, ix1 + 1):
                                    cq, cm = _in_cell(qc, nq, ix, iy, ix0, ix1, iy0, iy1)
                                    a_c = float(0.0)
                                    if cm >= 3 and a_q > 0.0:
                                        a_c = polygon_area(cq, cm)
                                    if a_c > 0.0:
                                        rad = _part_light(env, b3, cq, cm, rot, g)
                                        _sink_leaf(
                                            sink, px0 + ix + (py0 + iy) * width, polarized, m_c,
                                            w_c * share * a_c / a_q, env.polarizer, -d_ch, b_ch, xyz_w * rad,
                                        )  # fmt: skip
                        continue
                    if depth + 1 >= p.max_depth:
                        continue  # its next interface would be one too many
                    # roulette: a part carrying less than split_threshold of a pixel's light
                    # continues with probability e / split_threshold (weighted by its inverse)
                    e = energies[ci] * frac * a_beam
                    if e < p.split_threshold:
                        alive, boost = roulette(e, p.split_threshold, wp.randf(rng))
                        if alive == 0:
                            continue
                        w_c = w_c * boost
                    row = n
                    frac_row = frac
                    if n < _STACK:
                        n += 1
                    else:
                        # the stack is full: its last row is a reservoir of the parts beyond it,
                        # keeping one with probability frac / (all that met it), which then
                        # carries their whole fraction (unbiased)
                        row = _STACK - 1
                        keep, over = _reservoir(over, st[row, _P_FRAC], frac, wp.randf(rng))
                        frac_row = over
                        if not keep:
                            st[row, _P_FRAC] = over
                            continue
                    for r in range(nq):
                        for c in range(_C):
                            st[row, _C * r + c] = qc[r, c]
                    st[row, _P_NV] = float(nq)
                    st[row, _P_FRAC] = frac_row
                    st[row, _P_FACET] = float(f)
                    for c in range(3):
                        st[row, _S_B + c] = b_ch[c]
                    for c in range(4):
                        st[row, _S_MR + c] = cand[ci, ROW_MR + c]
                        st[row, _S_MI + c] = cand[ci, ROW_MI + c]
                    st[row, _S_W] = w_c
                    st[row, _S_DEPTH] = float(depth + 1)
                    st[row, _S_MODE] = cand[ci, ROW_MODE]
            if n == 0:
                break
            # pop a part inside the stone and cut it by the facets its rays leave through
            n -= 1
            if n == _STACK - 1:
                over = float(0.0)  # the reservoir row is popped
            nq = int(st[n, _P_NV])
            frac = st[n, _P_FRAC]
            q = BeamPolygon()
            for r in range(nq):
                for c in range(_C):
                    q[r, c] = st[n, _C * r + c]
            b_w = wp.vec3f(st[n, _S_B], st[n, _S_B + 1], st[n, _S_B + 2])
            m_j = Jones()
            m_j.re = wp.mat22(st[n, _S_MR], st[n, _S_MR + 1], st[n, _S_MR + 2], st[n, _S_MR + 3])
            m_j.im = wp.mat22(st[n, _S_MI], st[n, _S_MI + 1], st[n, _S_MI + 2], st[n, _S_MI + 3])
            w_j = st[n, _S_W]
            depth = int(st[n, _S_DEPTH])
            mode_j = int(st[n, _S_MODE])
            inside = k
            f0, nc, cands = _exit_candidates(geom, k, q, nq, tol)
            if nq < 3 or polygon_area(q, nq) <= 0.0:
                nb = 0  # a degenerate part carries no light
            elif nc == 0:
                # the whole part leaves through one facet (the common case: written here, not
                # through _exit_split, whose piece buffer is copied by value)
                pl0 = geom.planes[s + f0]
                n0 = wp.vec3f(pl0[0], pl0[1], pl0[2])
                t_sum = float(0.0)
                for r in range(nq):
                    xo, do = _obj(geom, k, q, r)
                    t = (pl0[3] - wp.dot(n0, xo)) / wp.dot(n0, do)
                    t_sum += t
                    buf[0, _C * r] = q[r, 0]
                    buf[0, _C * r + 1] = q[r, 1]
                    for c in range(3):
                        buf[0, _C * r + 2 + c] = q[r, 2 + c] + q[r, 5 + c] * t
                        buf[0, _C * r + 5 + c] = q[r, 5 + c]
                buf[0, _P_NV] = float(nq)
                buf[0, _P_FRAC] = frac
                buf[0, _P_FACET] = float(f0)
                buf[0, _P_T] = t_sum / float(nq)
                nb = 1
            else:
                buf, nb, rng = _exit_split(geom, k, q, nq, f0, nc, cands, rng)
                for i in range(nb):
                    buf[i, _P_FRAC] = buf[i, _P_FRAC] * frac
    return parts, rng


@wp.func
def trace_beam(
    p: TraceParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    env: Environment,
    surf: Surfaces,
    tables: SpectralTables,
    polarized: int,
    bs: BeamScene,
    cam: CameraParams,
    px0: int,
    py0: int,
    bw: int,
    bh: int,
    width: int,
    sink: wp.array2d(dtype=wp.float32),
    wavelengths: LaneWavelengths,
    weights: LaneWeights,
    count: int,
    first: int,
    step: int,
    rot: wp.vec2f,
    k: int,
    rng: wp.uint32,
):
    """The light reaching the camera through the block of ``bw`` x ``bh`` pixels from pixel
    (px0, py0) (:func:`pixel_beam`; a film ``width`` pixels wide) at ``count`` wavelengths,
    added to each pixel's row of ``sink`` (:func:`sink_sums` reads it): coherency matrices J_X,
    J_Y, J_Z summed over the lanes, lane j's light weighted by ``weights[j]``, averaged over the
    pixel, and the fraction of the pixel that meets the stone.  Returns (the beam parts and point
    rays traced, rng).  The block's beam enters object ``k`` (:func:`beam_target`); a leaf's
    part is cut by the pixels it overlaps (in the block's pixel coordinates, which every part
    carries), each pixel taking its share of the part's fraction of the block.  Lane j is the
    pixel's wavelength ``first + j step`` in the order of its strata: its environment lookups
    follow the R2 sequence over that index, rotated by ``rot`` (uniform, independent of the
    wavelengths), so that neighbouring wavelengths' lookups spread evenly over their parts
    (module docstring).  Module docstring for the method."""
    poly, basis_x = pixel_beam(cam, px0, py0, bw, bh)
    # the entry cut is the same for every wavelength (none for k < 0)
    entry, n_entry, over, rng = _entry_split(geom, k, poly, 4, rng)
    if over == 0.0 or bw * bh == 1:
        return _trace_entry(
            p, geom, mats, env, surf, tables, polarized, bs, k, cam, px0, py0, bw, bh, width, sink, basis_x,
            entry, n_entry, wavelengths, weights, count, first, step, rot, rng,
        )  # fmt: skip
    # more entry pieces than rows: a piece standing in for others would move their light to its
    # own pixels, so each pixel of the block is a beam of its own
    parts = int(0)
    for iy in range(bh):
        for ix in range(bw):
            cell, bx_c = pixel_beam(cam, px0 + ix, py0 + iy, 1, 1)
            e_c, n_c, _over, rng = _entry_split(geom, k, cell, 4, rng)
            n_p, rng = _trace_entry(
                p, geom, mats, env, surf, tables, polarized, bs, k, cam, px0 + ix, py0 + iy, 1, 1, width,
                sink, bx_c, e_c, n_c, wavelengths, weights, count, first, step, rot, rng,
            )  # fmt: skip
            parts += n_p
    return parts, rng


@wp.kernel(enable_backward=False)
def _beam_targets_kernel(
    bs: BeamScene, cam: CameraParams, width: int, height: int, bsz: int, target: wp.array(dtype=wp.int32)
):
    b = wp.tid()
    nbx = (width + bsz - 1) / bsz
    px0 = (b % nbx) * bsz
    py0 = (b / nbx) * bsz
    poly, _bx = pixel_beam(cam, px0, py0, wp.min(bsz, width - px0), wp.min(bsz, height - py0))
    target[b] = beam_target(bs, poly, 4)


def beam_targets(bs: BeamScene, cam, width: int, height: int, block: int, device=None) -> None:
    """Each block's :func:`beam_target` for camera ``cam`` on a ``width`` x ``height`` film in
    blocks of ``block`` pixels, into ``bs.target`` (a kernel of its own, run before a pass when
    the scene holds more than one stone in the environment: a target chosen inside the pixel
    kernel cost a stone alone 10-20 % of its render time, measured on diamond_fire.toml)."""
    if not bs.others:
        return
    n = (-(-int(width) // block)) * (-(-int(height) // block))
    if bs.target.shape[0] < n:
        bs.target = wp.zeros(n, dtype=wp.int32, device=bs.target.device)
    inputs = [bs, cam, int(width), int(height), int(block), bs.target]
    wp.launch(_beam_targets_kernel, dim=n, inputs=inputs, device=device or bs.target.device)


def beam_objects(scene, geometry, built) -> list[bool]:
    """Per object of ``scene``, whether beams may enter it: a closed convex solid of at most
    :data:`MAX_PLANES` facet planes, not a thin shell or film surface, neither inside another
    solid nor around one (``geometry``: the scene's GeometryScene; ``built``: its built
    objects)."""
    counts = geometry.geometry.plane_count.numpy()
    parents = geometry.geometry.parent.numpy()
    flags = []
    for i, ob in enumerate(scene.objects):
        film = getattr(ob, "film", None)
        flags.append(
            bool(geometry._convex_possible[i])
            and int(counts[i]) <= MAX_PLANES
            and (film is None or film.surface == "solid")
            and int(parents[i]) < 0
            and not bool(np.any(parents[: len(scene.objects)] == i))
        )
    return flags


def beam_obstacle(scene, geometry, built=None) -> str | None:
    """Why pixel beams cannot trace ``scene`` (already traced in spectral bundles:
    ``stages.bundle.bundle_obstacle``), or None where they can: at least one closed convex solid
    beams may enter (:func:`beam_objects`; the rest of the scene, other solids, surfaces and
    lamps, is met by point samples that parts and misses continue as), seen through a pinhole
    or orthographic camera."""
    if scene.camera.type == "thin_lens" and scene.camera.aperture > 0.0:
        return "a thin lens with an aperture is point-sampled"
    if not any(beam_objects(scene, geometry, built)):
        if not all(geometry._convex_possible):
            return "beams enter closed convex solids (this scene has none they can enter)"
        return f"beams enter convex solids of at most {MAX_PLANES} facet planes, not shells or nested ones"
    return None


def beam_scene(geometry, surfaces, eligible, device=None) -> BeamScene:
    """The :class:`BeamScene` of a scene: its objects' world bounding spheres and vertices
    (``geometry``: a GeometryScene), the planes of its surfaces and area lights (``surfaces``: the
    ``Surfaces`` struct of stages/surfaces.py) and the objects beams may enter (``eligible``)."""
    dev = get_device(device)
    n = len(eligible)
    planes, spheres = [], []
    for count, centre, normal, half in (
        (surfaces.num_surfaces, surfaces.centre, surfaces.normal, surfaces.half),
        (surfaces.num_area, surfaces.a_centre, surfaces.a_normal, surfaces.a_half),
    ):
        c = centre.numpy()[:count].astype(np.float64)
        nrm = normal.numpy()[:count].astype(np.float64)
        hs = half.numpy()[:count].astype(np.float64)
        for ci, ni, hi in zip(c, nrm, hs, strict=True):
            planes.append([*ni, float(ni @ ci)])
            spheres.append([*ci, float(np.linalg.norm(hi))])
    side = np.zeros((max(n, 1), max(len(planes), 1), 2), dtype=np.float32)
    for i, v in enumerate(geometry.world_vertices[:n]):
        for r, pl in enumerate(planes):
            sd = v @ np.asarray(pl[:3]) - pl[3]
            side[i, r] = (sd.min(), sd.max())
    bs = BeamScene()
    bs.num_objects = n
    bs.eligible = wp.array(np.array([*map(int, eligible)] or [0], dtype=np.int32), dtype=wp.int32, device=dev)
    obj_spheres = np.asarray(geometry.world_spheres, dtype=np.float32).reshape(-1, 4)
    bs.sphere = wp.array(obj_spheres if n else np.zeros((1, 4), np.float32), dtype=wp.vec4f, device=dev)
    bs.num_rects = len(planes)
    rect = np.array(planes or [[0.0, 0.0, 1.0, 0.0]], dtype=np.float32)
    bs.rect = wp.array(rect, dtype=wp.vec4f, device=dev)
    bs.rect_sphere = wp.array(
        np.array(spheres or [[0.0, 0.0, 0.0, 0.0]], dtype=np.float32), dtype=wp.vec4f, device=dev
    )
    bs.side = wp.array(side, dtype=wp.vec2f, device=dev)
    bs.traced = int(surfaces.num_sun > 0 or surfaces.num_spot > 0)
    bs.target = wp.zeros(1, dtype=wp.int32, device=dev)
    bs.others = int(n > 1 or len(planes) > 0 or bs.traced != 0)
    return bs
