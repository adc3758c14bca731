"""The spectral bundle: one path tree traced for many wavelengths at once, in dispersive stones.

Why.  With dispersion every wavelength refracts its own way, and one tree per wavelength sample
at its own pixel position makes a pixel's colour the estimate of a few wavelengths that each
meet a soft box or miss it.  At one pixel position, though, the light that arrives is a smooth
function of the wavelength along any fixed sequence of facets, so a few wavelengths there
integrate the spectrum almost exactly.

What.  :func:`trace_bundle` follows ONE primary ray for a *bundle* of up to :data:`LANES`
wavelengths (lanes).  Each lane carries its own ray (origin, direction, polarization frame,
Jones matrix, weight) and gets its own Fresnel amplitudes, Snell direction and Bouguer–Lambert
absorption from the one interface event (``optics.interface.backward_isotropic``), so every lane
is traced exactly.  The lanes share the camera ray, the first hit, the branch stack and choices
and the film update.  At every node lanes that meet the same facet form one group; a lane that
crosses a facet edge, or is totally reflected where the others are not, continues in another
group, so each lane's estimate is that of a separate per-wavelength tree.  Branch choices
(deterministic split, energy-weighted pick, Russian roulette) are made per group from its lanes'
mean energy and applied to all of them with the weight 1/probability: unbiased for every lane.

Scope. Isotropic, uncoated, non-fluorescent solids in an environment light (no surfaces, lamps,
films or caustics, no solid inside another; not rgb3): :func:`bundle_obstacle` is the Renderer's
test and names what stands in the way; everything else is traced per wavelength by
``stages.trace.trace_radiance``. A split puts a node's reflected children at its own stack
position and the refracted ones at the next, so
positions grow only with splits; when the :data:`BUNDLE_ROWS` positions or the :data:`NODE_ROWS`
pending groups are used up, a group continues stochastically instead of splitting (as
``max_splits`` does).

Costs, the noise left, and the variants measured and dropped: docs/design/bundles.md.

References: Wilkie et al. 2014, "Hero wavelength spectral sampling", CGF 33(4); Guy & Soler
2004, §5 (the pruned facet tree); Veach 1997, ch. 4 (splitting, selection weighted by
1/probability, Russian roulette).
"""

from __future__ import annotations

import warp as wp

from ..film.leaf import add_leaf
from ..geometry.query import (
    RayHit,
    SceneGeometry,
    convex_exit_near,
    object_exit_hit,
    scene_closest_hit_leaving,
)
from ..materials.dispersion import Isotropic, MaterialTable
from ..optics.absorption import bouguer_lambert
from ..optics.branches import ROW_B, ROW_D, ROW_IN, ROW_MI, ROW_MR, ROW_O, ROW_W, Cand, roulette
from ..optics.interface import backward_isotropic
from ..optics.jones import (
    Jones,
    coherency_unpolarized,
    jones_zero,
)
from ..spectra import SpectralTables
from .environment import Environment, environment_basis, environment_coefficients
from .fluorescence import has_fluorescence
from .media import isotropic_optics, zoned_isotropic_kappa
from .trace import TraceParams

wp.set_module_options({"enable_backward": False})  # no adjoint code (see device.py)

__all__ = [
    "LANES",
    "BUNDLE_ROWS",
    "NODE_ROWS",
    "LaneWavelengths",
    "LaneWeights",
    "trace_bundle",
    "bundle_applies",
    "bundle_obstacle",
]

#: wavelengths per bundle (16 lanes with a low-discrepancy jitter: at one pixel position the
#: spectral noise is below the pixel-position noise, scripts/bench/fire_convergence.py)
LANES = 16
#: lane-row positions of the depth-first stack (a position is added only by a split)
BUNDLE_ROWS = 17
#: pending groups (nodes) of the stack
NODE_ROWS = 64
_L = wp.constant(LANES)
_ROWS = wp.constant(BUNDLE_ROWS)
_NODES = wp.constant(NODE_ROWS)
# lane row layout: origin, direction, polarization basis x, Jones (re 4, im 4), weight
_O = wp.constant(0)
_D = wp.constant(3)
_B = wp.constant(6)
_MR = wp.constant(9)
_MI = wp.constant(13)
_W = wp.constant(17)
_LANE_COLS = 18
# node columns: lane-row position, object inside (-1 ambient), depth, lane mask, solid left (-1)
_POS = wp.constant(0)
_IN = wp.constant(1)
_DEPTH = wp.constant(2)
_MASK = wp.constant(3)
_LEFT = wp.constant(4)

LaneStack = wp.types.matrix(shape=(BUNDLE_ROWS * LANES, _LANE_COLS), dtype=wp.float32)
NodeStack = wp.types.matrix(shape=(NODE_ROWS, 5), dtype=wp.int32)
LaneWavelengths = wp.types.vector(length=LANES, dtype=wp.float32)
LaneInts = wp.types.vector(length=LANES, dtype=wp.int32)
LaneWeights = wp.types.matrix(shape=(LANES, 3), dtype=wp.float32)  # XYZ sample weight per lane


@wp.func
def _bit(mask: int, j: int):
    return (mask >> j) & 1


@wp.func(inline=False)  # out of line, like trace_radiance (compile time)
def trace_bundle(
    p: TraceParams,
    geom: SceneGeometry,
    mats: MaterialTable,
    env: Environment,
    tables: SpectralTables,
    polarized: int,
    origin: wp.vec3f,
    direction: wp.vec3f,
    basis_x: wp.vec3f,
    wavelengths: LaneWavelengths,
    weights: LaneWeights,
    count: int,
    rng: wp.uint32,
):
    """The light arriving along a primary ray for ``count`` (<= LANES) wavelengths at once:
    (coherency matrices J_X, J_Y, J_Z in the camera frame summed over the lanes, lane j's light
    weighted by its XYZ sample weight ``weights[j]``; hit_any; rays traced (ray queries of all
    lanes); rng).  Each lane's part is distributed exactly as ``trace_radiance`` at that
    wavelength would give it (module docstring)."""
    ls = LaneStack()
    ns = NodeStack()
    cand = Cand()
    basis = LaneWeights()  # the environment's basis spectra at each lane's wavelength
    lane_n = LaneWavelengths()  # each lane's (real) index in the solid last met
    lane_kappa = LaneWavelengths()  # and its absorption coefficient (times the object's scale), 1/mm
    lane_t = LaneWavelengths()  # the lanes' hits at the node being traced
    lane_obj = LaneInts()
    lane_facet = LaneInts()
    lane_nrm = LaneWeights()
    for j in range(count):
        b3 = environment_basis(env, tables, wavelengths[j])
        for c in range(3):
            basis[j, c] = b3[c]
            ls[j, _O + c] = origin[c]
            ls[j, _D + c] = direction[c]
            ls[j, _B + c] = basis_x[c]
        ls[j, _MR + 0] = 1.0
        ls[j, _MR + 3] = 1.0
        ls[j, _W] = 1.0
    ns[0, _POS] = 0
    ns[0, _IN] = -1
    ns[0, _DEPTH] = 0
    ns[0, _MASK] = (1 << count) - 1
    ns[0, _LEFT] = -1
    n = int(1)
    acc_x = jones_zero()
    acc_y = jones_zero()
    acc_z = jones_zero()
    scalar_xyz = wp.vec3f(0.0, 0.0, 0.0)
    hit_any = int(0)
    rays = int(0)
    c_obj = int(-1)
    while n > 0:
        n -= 1
        pos = ns[n, _POS]
        inside = ns[n, _IN]
        depth = ns[n, _DEPTH]
        remaining = ns[n, _MASK]
        left = ns[n, _LEFT]
        base = pos * _L
        # every lane's own hit.  The primary ray is the same for all lanes: one query.  Inside a
        # convex solid a lane first tries the facet its neighbour (the previous lane, the next
        # shorter wavelength) left through and that facet's edge neighbours
        # (geometry.query.convex_exit_near: exact, a few plane tests); only where that fails does
        # it query all planes.
        guess = int(-1)
        convex_in = int(0)
        if inside >= 0:
            if geom.mode == 2 or (geom.mode == 0 and geom.convex[inside] != 0):
                convex_in = 1
        for j in range(count):
            if _bit(remaining, j) == 1:
                r = base + j
                if depth == 0 and guess >= 0:
                    lane_t[j] = lane_t[0]
                    lane_obj[j] = lane_obj[0]
                    lane_facet[j] = lane_facet[0]
                    for c in range(3):
                        lane_nrm[j, c] = lane_nrm[0, c]
                    continue
                o_j = wp.vec3f(ls[r, _O], ls[r, _O + 1], ls[r, _O + 2])
                d_j = wp.vec3f(ls[r, _D], ls[r, _D + 1], ls[r, _D + 2])
                through = int(0)
                if convex_in != 0 and guess >= 0:
                    hg, through = convex_exit_near(geom, inside, guess, o_j, d_j, p.t_max)
                    if through != 0:
                        lane_t[j] = hg.t
                        lane_obj[j] = inside
                        lane_facet[j] = hg.facet
                        for c in range(3):
                            lane_nrm[j, c] = hg.normal[c]
                        guess = hg.facet
                if through == 0:
                    hj = RayHit()
                    if inside >= 0:
                        hj = object_exit_hit(geom, inside, o_j, d_j, p.t_max)
                    else:
                        hj = scene_closest_hit_leaving(geom, o_j, d_j, p.t_max, left)
                    rays += 1
                    lane_t[j] = hj.t
                    lane_obj[j] = hj.object
                    lane_facet[j] = hj.facet
                    for c in range(3):
                        lane_nrm[j, c] = hj.normal[c]
                    guess = hj.facet
                    if depth == 0:
                        guess = 0  # marks the primary ray as queried
        # the groups of lanes that meet the same facet (or nothing), one after the other
        while remaining != 0:
            first = int(0)
            while _bit(remaining, first) == 0:
                first += 1
            obj = lane_obj[first]
            group = int(0)
            for j in range(first, count):
                if _bit(remaining, j) == 1 and lane_obj[j] == obj and lane_facet[j] == lane_facet[first]:
                    group = group | (1 << j)
            remaining = remaining - group
            if obj < 0:
                if inside < 0:
                    # the environment light, seen by every lane of the group
                    for j in range(first, count):
                        if _bit(group, j) == 1:
                            r = base + j
                            d_j = wp.vec3f(ls[r, _D], ls[r, _D + 1], ls[r, _D + 2])
                            rad = wp.dot(
                                wp.vec3f(basis[j, 0], basis[j, 1], basis[j, 2]),
                                environment_coefficients(env, d_j),
                            )
                            xyz = wp.vec3f(weights[j, 0], weights[j, 1], weights[j, 2]) * rad
                            b_j = wp.vec3f(ls[r, _B], ls[r, _B + 1], ls[r, _B + 2])
                            m_j = Jones()  # read inline: a wp.func would copy the whole stack
                            m_j.re = wp.mat22(ls[r, _MR], ls[r, _MR + 1], ls[r, _MR + 2], ls[r, _MR + 3])
                            m_j.im = wp.mat22(ls[r, _MI], ls[r, _MI + 1], ls[r, _MI + 2], ls[r, _MI + 3])
                            acc_x, acc_y, acc_z, scalar_xyz = add_leaf(
                                acc_x, acc_y, acc_z, scalar_xyz, polarized, m_j, ls[r, _W], env.polarizer,
                                -d_j, b_j, xyz,
                            )  # fmt: skip
                # a segment inside a solid that finds no exit leaked through a crack: dropped
                continue
            if depth == 0:
                hit_any = 1
            if obj != c_obj:
                # every lane's index and absorption in the solid met (entered or left: solids do
                # not overlap), evaluated again only when the bundle meets another solid; in an
                # isotropic solid a segment's absorption does not depend on its direction, so
                # stages.media.isotropic_optics is evaluated here once per lane, not per segment
                for j in range(count):
                    n_j, kappa_j = isotropic_optics(
                        mats,
                        p.object_material[obj],
                        p.object_axis[obj],
                        wavelengths[j],
                        p.object_absorption_scale[obj],
                    )
                    lane_n[j] = n_j
                    lane_kappa[j] = kappa_j
                c_obj = obj
            if depth >= p.max_depth:
                continue
            n_out = wp.vec3f(lane_nrm[first, 0], lane_nrm[first, 1], lane_nrm[first, 2])
            d_first = wp.vec3f(ls[base + first, _D], ls[base + first, _D + 1], ls[base + first, _D + 2])
            entering = wp.dot(d_first, n_out) < 0.0
            nrm = n_out  # unit normal on the side the backward ray arrives from (medium A)
            in_b = obj
            if not entering:
                nrm = -n_out
                in_b = -1
            # each lane's children: reflected (back into A) in rows base + j, refracted (into B) in
            # rows base + L + j, the next position; a lane's parent row is read before they are
            # written, and its pending nodes all sit below this position
            mask_t = int(0)
            mask_r = int(0)
            e_t = float(0.0)
            e_r = float(0.0)
            for j in range(first, count):
                if _bit(group, j) == 1:
                    r = base + j
                    o_j = wp.vec3f(ls[r, _O], ls[r, _O + 1], ls[r, _O + 2])
                    d_j = wp.vec3f(ls[r, _D], ls[r, _D + 1], ls[r, _D + 2])
                    b_j = wp.vec3f(ls[r, _B], ls[r, _B + 1], ls[r, _B + 2])
                    m_j = Jones()  # read inline: a wp.func would copy the whole stack
                    m_j.re = wp.mat22(ls[r, _MR], ls[r, _MR + 1], ls[r, _MR + 2], ls[r, _MR + 3])
                    m_j.im = wp.mat22(ls[r, _MI], ls[r, _MI + 1], ls[r, _MI + 2], ls[r, _MI + 3])
                    w_j = ls[r, _W]
                    n_a = wp.vec2f(p.ambient[0], 0.0)
                    n_b = wp.vec2f(lane_n[j], 0.0)
                    if inside >= 0:
                        # Bouguer-Lambert along the lane's own segment (inside == obj: a lane
                        # inside a solid meets that solid's surface), through the zones of a
                        # colour-zoned stone; a clear stone skips exp
                        kappa_j = zoned_isotropic_kappa(
                            mats,
                            p.object_material[obj],
                            lane_kappa[j],
                            lane_n[j],
                            p.object_absorption_scale[obj],
                            wavelengths[j],
                            o_j,
                            d_j,
                            lane_t[j],
                        )
                        if kappa_j != 0.0:
                            w_j = w_j * bouguer_lambert(kappa_j, lane_t[j])
                        n_a = wp.vec2f(lane_n[j], 0.0)
                        n_b = wp.vec2f(p.ambient[0], 0.0)
                    cand, energies, k = backward_isotropic(
                        cand,
                        m_j,
                        w_j,
                        b_j,
                        d_j,
                        n_out,
                        nrm,
                        n_a,
                        n_b,
                        o_j + d_j * lane_t[j],
                        geom.epsilon[obj],
                        inside,
                        in_b,
                        depth,
                        polarized,
                    )
                    for i in range(k):
                        row = base + j  # reflected child
                        if int(cand[i, ROW_IN]) == inside:
                            mask_r = mask_r | (1 << j)
                            e_r += energies[i]
                        else:
                            row = base + _L + j  # refracted child
                            mask_t = mask_t | (1 << j)
                            e_t += energies[i]
                        for c in range(3):
                            ls[row, _O + c] = cand[i, ROW_O + c]
                            ls[row, _D + c] = cand[i, ROW_D + c]
                            ls[row, _B + c] = cand[i, ROW_B + c]
                        for c in range(4):
                            ls[row, _MR + c] = cand[i, ROW_MR + c]
                            ls[row, _MI + c] = cand[i, ROW_MI + c]
                        ls[row, _W] = cand[i, ROW_W]
            # the group's branch choice from its lanes' mean energy
            inv = 1.0 / float(count)
            e_t = e_t * inv
            e_r = e_r * inv
            e_parent = e_t + e_r
            if e_parent <= 0.0:
                continue
            keep_t = mask_t != 0
            keep_r = mask_r != 0
            scale = float(1.0)
            # (pos + 2: a node at position pos writes its refracted children at pos + 1 before
            # this choice, so a split may only create position pos + 1 <= _ROWS - 2)
            if e_parent < p.split_threshold or n + 2 > _NODES or pos + 2 >= _ROWS:
                # stochastic continuation: one child by energy, weighted by 1/probability
                if keep_t and keep_r:
                    if wp.randf(rng) * e_parent < e_t:
                        keep_r = False
                        scale = e_parent / e_t
                    else:
                        keep_t = False
                        scale = e_parent / e_r
                # Russian roulette on weak paths (the energy after the choice is e_parent)
                if e_parent < p.rr_threshold:
                    alive, boost = roulette(e_parent, p.rr_threshold, wp.randf(rng))
                    if alive == 0:
                        continue
                    scale = scale * boost
            in_t = obj
            left_t = -1
            left_r = -1
            if not entering:
                in_t = -1
                left_t = obj  # refracted out of the solid: leaves it
            if inside < 0:
                left_r = obj  # reflected off the outside: leaves it
            if keep_t and not keep_r:
                # the refracted child alone: down to this position (positions grow only at splits)
                for j in range(first, count):
                    if _bit(mask_t, j) == 1:
                        for c in range(_LANE_COLS):
                            ls[base + j, c] = ls[base + _L + j, c]
            # push the reflected child below the refracted one (the refracted is traced first)
            if keep_r:
                for j in range(first, count):
                    if _bit(mask_r, j) == 1:
                        ls[base + j, _W] = ls[base + j, _W] * scale
                ns[n, _POS] = pos
                ns[n, _IN] = inside
                ns[n, _DEPTH] = depth + 1
                ns[n, _MASK] = mask_r
                ns[n, _LEFT] = left_r
                n += 1
            if keep_t:
                pos_t = pos
                if keep_r:
                    pos_t = pos + 1
                for j in range(first, count):
                    if _bit(mask_t, j) == 1:
                        ls[pos_t * _L + j, _W] = ls[pos_t * _L + j, _W] * scale
                ns[n, _POS] = pos_t
                ns[n, _IN] = in_t
                ns[n, _DEPTH] = depth + 1
                ns[n, _MASK] = mask_t
                ns[n, _LEFT] = left_t
                n += 1
    if polarized == 0:
        acc_x = coherency_unpolarized(scalar_xyz[0])
        acc_y = coherency_unpolarized(scalar_xyz[1])
        acc_z = coherency_unpolarized(scalar_xyz[2])
    return acc_x, acc_y, acc_z, hit_any, rays, rng


def bundle_obstacle(scene, built, *, beams: bool = False) -> str | None:
    """Why a camera scene cannot be traced in spectral bundles, or None where it can: bundles
    need ``render.bundle`` and isotropic, uncoated, non-fluorescent solids in an environment
    light, none inside another (no surfaces, lamps, films, caustics or nesting; not rgb3).  The
    reason reaches ``Image.stats["estimator_reason"]``.  ``beams``: the tracer asking is pixel
    beams (``stages/pixel_beam.py``), which follow uniaxial and biaxial stones and coated
    solids too (point-sampled bundles do not)."""
    r = scene.render
    if not bool(getattr(r, "bundle", True)):
        return "render.bundle = false"
    if r.spectral == "rgb3":
        return "rgb3 traces its three wavelengths one by one"
    # beams meet surfaces, lamps, shells and nested solids by point samples (stages/pixel_beam.py)
    if scene.surfaces and not beams:
        return "the scene has diffuse or glossy surfaces"
    if scene.lamps and not beams:
        return "the scene has lamps"
    if r.caustics:
        return "render.caustics = true"
    films = [ob.film for ob in scene.objects if getattr(ob, "film", None) is not None]
    if any(f.surface != "solid" for f in films) and not beams:
        return "the scene has a thin shell or a film surface"
    if films and not beams:
        return "a stone is coated (thin-film stack)"
    if len(built.materials) == 0:
        return "the scene has no solid"
    if not beams and not all(isinstance(m, Isotropic) and not m.is_uniaxial for m in built.materials):
        return "a stone is birefringent (uniaxial or biaxial)"
    if built.nested and not beams:
        return "a solid lies inside another"
    # fluorescent re-emission switches a path's wavelength (stages/fluorescence.py)
    if has_fluorescence(built.materials):
        return "a stone fluoresces"
    return None


def bundle_applies(scene, built) -> bool:
    """Whether a camera scene can be traced in spectral bundles (:func:`bundle_obstacle` is None)."""
    return bundle_obstacle(scene, built) is None
