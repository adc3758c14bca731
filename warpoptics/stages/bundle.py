"""The spectral bundle: one path tree traced for many wavelengths at once, in dispersive stones.

Why.  In a clear stone without dispersion one path tree serves the whole spectrum
(``EnvironmentLight.exact_response``), so a pixel's only noise is where its samples fall (facet
edges), and the R2 pixel sequence removes it quickly.  With dispersion every wavelength refracts
its own way; tracing one tree per wavelength sample at its own pixel position makes a pixel's
colour the estimate of a few wavelengths that each meet a soft box or miss it (measured on the
issue-19 diamond, 32x32: relative RMSE ~ N^-0.55, against N^-0.75 for the clear stone, and 11x
the clear stone's noise at 512 traces per pixel).  At one pixel position, though, the light that
arrives is a smooth function of the wavelength along any fixed sequence of facets, so a few
wavelengths there integrate the spectrum almost exactly.

What.  :func:`trace_bundle` follows ONE primary ray for a *bundle* of up to :data:`LANES`
wavelengths (lanes).  Each lane carries its own ray (origin, direction, polarization frame,
Jones matrix, weight): at every interface each lane gets its own Fresnel amplitudes, Snell
direction and Bouguer–Lambert absorption from the one interface event
(``optics.interface.backward_isotropic``) with its own index, so every lane is traced exactly.
What the lanes share is the work around them: the camera ray, the first hit, the branch stack and
choices, the film update.  At every node each lane's own ray query gives its facet; lanes that
meet the same facet form one group (the common case: all of them), and a lane whose ray crosses a
facet edge, or that is totally reflected where the others are not, simply continues in another
group — nothing is dropped or re-weighted, so each lane's estimate is the one of a separate
per-wavelength tree.  Branch choices (deterministic split, the energy-weighted pick, Russian
roulette) are made per group from its lanes' mean energy and applied to all of them with the
weight 1/probability: unbiased for every lane (a choice may depend on anything already traced).

An earlier version kept one facet sequence per bundle, chosen by a random hero lane, and dropped
the lanes that left it, weighting the rest by the balance heuristic of hero-wavelength sampling
(Wilkie et al. 2014): unbiased too, but 1.4x the noise of grouping (32x32, 16 lanes: 0.42 vs
0.30 relative RMSE), because near dispersed facet edges few lanes stay.

What a lane costs, and two ways around it that were measured and dropped (issue 19).  A lane
pays, per node, its own interface event (``backward_isotropic``: ~100 ns on one core) and, per
leaf, its own environment lookup (40-80 ns on the lat-long map) and film update (~5 ns); that is
0.39 of a whole single-wavelength trace per added lane (1.7 us per pixel position for one lane,
11.6 us for 16, the clear stone 1.5 us on session 9's machine; 0.33 of a trace on session 10's
slower one; ``scripts/bench/bench_lane_cost.py``).  (1) Interpolated
lanes: trace every s-th lane and carry the lanes between as interpolations of their two traced
neighbours while both meet the same facets (interpolated and then traced exactly where they
part or near the critical angle).  In a diamond the traced neighbours part often enough that
the lanes between were traced much of the way anyway: at stride 4 ray queries per position fell
only from 22.9 to 15.4 and the time not at all (16 lanes, 32x32: 13.8, 12.8 and 14.0 us per
position at stride 1, 4 and 15), with a second-order bias (0.25 % RMSE at stride 4).
(2) Leaf points: at a leaf, look up each lane's cell of the spectrum at several wavelengths with
the exit direction, Jones matrix and weight interpolated toward the neighbouring lanes of the
group.  It removes much of the spectral noise of few lanes (4 lanes, 64x64: 10.7 -> 5.7 % at 128
positions per pixel), but a point costs an environment lookup and a film update, what a traced
lane pays at the leaf: at equal error the best setting (2 lanes, 4 points each) was 1.18x faster than
8 traced lanes (27.7 vs 32.7 CPU-s to 1 %) but the interpolation over 200 nm left a per-pixel
bias of ~2.4 % RMSE (2 lanes, 8 points, against a 16-lane, 64-point reference); 4 lanes with 2
points each was 1.05x faster.  Neither was kept.

Three more, measured and dropped in session 10 (64x64 issue-19 stone, 8 lanes, 64 positions per
pixel, one thread; CPU-s to 1 % extrapolated with the R2 slope 0.75 from the noise between seeds;
the experiments' code is not in the repository).  Where a lane's work goes: 3.4 interface events
per lane and position (3.42 for one lane, 26.7 for 8), and full exit queries inside the stone
5.3 per position for 8 lanes against 3.2 for one (the neighbour-facet guess answers the rest).
(3) A clear control variate: each bundle also carries the same stone without dispersion (every
material at its 560 nm index and absorption) as one more lane with minus the exact clear-stone
response, and k clear-stone trees per bundle (one tree for the whole spectrum, a fifth of a
bundle's cost) at positions of their own add it back: unbiased.  At one position per pixel the
difference has 0.17 of the bundle's variance (48x48, 12 seeds), but at 64 positions only ~0.5:
the facet-edge noise the two share is what the R2 sequence already removes, and the dispersed
edges that remain converge slower.  k = 0, 2, 4, 8: 34.8, 51.9, 53.5, 71.7 CPU-s to 1 %
(adaptive: k = 0 27.2, k = 2 42.8).  (4) Thinning weak groups: halve a group's lanes (one random
parity, the kept lanes at twice the weight) while their mean energy is below T; T = 0, 0.05, 0.1,
0.15, 0.3: 32.8, 30.6, 32.3, 31.1, 49.4 CPU-s to 1 % (4 seeds, +-10 %): no gain beyond the
noise, since the lanes' events sit in the few strong nodes of the split tree.  (5) One
environment lookup for lanes that leave in one direction (reflected off the outside): images
identical, no change measurable in five alternating whole-process pairs (3.5-4.4 s each).

Made cheaper in session 11 (kept, every tracer gains): a lane's interface event solved Fresnel
twice, A -> B for the reflected child and direction and B -> A for the refracted child's
amplitudes; between lossless media the second is the first swapped (``fresnel_reverse``, the
Stokes relations: two real divisions instead of a complex square root and four complex ones, and
more accurate near grazing), and the lat-long lookup's ``acosf``/``atan2f`` became one polynomial
atan (``geometry/directions.py``).  ``backward_isotropic`` 117 -> 85 ns; an 8-lane position
0.91x the time (median of 11 alternating process pairs, 32x32 issue-19 stone, one thread: the
machine's noise is +-10 % a run); the clear stone's position unchanged within that noise
(``scripts/bench/results/bench_lane_cost_ab.log``).
Measured the same way and not kept: an 8-lane stack (``LANES`` = 8, half the per-position
zeroing and cache footprint; it would cap ``bundle_lanes`` at 8): median 0.96, within the noise;
Warp's ``optimization_level`` 3 instead of the CPU default 2: median 1.05 (slower).  A lane's
absorption coefficient is now evaluated once per solid met, not per segment (images bitwise
equal; no change measurable).

Where the noise that is left comes from (session 11, ``scripts/bench/fire_noise_sources.py``):
not the map's edges.  Blurring the studio map by 1.4 deg (wider than a pixel's exit cone through
flat facets at 64x64) leaves 0.89 of the clear stone's variance and 0.90 of the dispersive one's;
even 5.6 deg leaves 0.54 / 0.56.  So pre-filtered environment lookups (ray cones) could remove
at most ~10 %; the rest is which facet sequences a pixel's samples meet, which only integrating
the pixel over the facet tree (beam tracing) would remove.  Nor is it mostly the edges of the
facets the camera meets first, which clipping each pixel against the projected front facets
would integrate exactly: the 38 % of the stone's pixels that hold such an edge (64x64) carry
49-50 % of the variance but only 1.5x the other stone pixels' per pixel, so that step would
remove ~1/6 of it; the rest comes from the edges seen deeper in the tree.  Session 12 removes
it: ``render.pixel_beam`` traces a bundle's lanes through the pixel's whole footprint
(``stages/pixel_beam.py``), which on this stone at 64x64 reaches 1 % in half the time of the
point-sampled bundles (``scripts/bench/results/bench_fire_64_beams.*``); with session 13's
wavelength lattice, at 256x256 in one 32-wavelength pass, 1.39x the clear stone's time
(``bench_fire_256_beams.*``).

Scope.  Isotropic, uncoated solids in an environment light (no surfaces, lamps or films, no
solid inside another: a bundle keeps one solid's indices; not rgb3): :func:`bundle_applies` is
the Renderer's test; everything else is traced per wavelength by
``stages.trace.trace_radiance``.  Lane rows: a split puts a node's reflected children at its own
stack position and the refracted ones at the next, a single child stays at the node's position,
so positions grow only with splits; each lane's pending nodes sit below the one being traced,
so groups can share positions.  When the :data:`BUNDLE_ROWS` positions or the :data:`NODE_ROWS`
pending groups are used up, a group continues stochastically instead of splitting (as
``max_splits`` does in ``trace_radiance``).

References:
    Wilkie, A., Nawaz, S., Droske, M., Weidlich, A., Hanika, J. 2014. Hero wavelength spectral
        sampling.  Computer Graphics Forum 33(4) (EGSR).
    Guy, S., Soler, C. 2004. Graphics Gems Revisited, §5 (the pruned facet tree).
    Veach, E. 1997. Robust Monte Carlo Methods for Light Transport Simulation, ch. 4 (splitting,
        random selection weighted by 1/probability, Russian roulette).
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
from .media import isotropic_optics
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
                        # inside a solid meets that solid's surface); a clear stone skips exp
                        if lane_kappa[j] != 0.0:
                            w_j = w_j * bouguer_lambert(lane_kappa[j], lane_t[j])
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


def bundle_applies(scene, built) -> bool:
    """Whether a camera scene can be traced in spectral bundles (``render.bundle`` and isotropic,
    uncoated, non-fluorescent solids in an environment light, none inside another: no surfaces,
    lamps, films, caustics or nesting; not rgb3)."""
    r = scene.render
    return (
        bool(getattr(r, "bundle", True))
        and r.spectral != "rgb3"
        and not scene.surfaces
        and not scene.lamps
        and not r.caustics
        and not any(getattr(ob, "film", None) for ob in scene.objects)
        and all(isinstance(m, Isotropic) and not m.is_uniaxial for m in built.materials)
        and len(built.materials) > 0
        and not built.nested
        # fluorescent re-emission switches a path's wavelength (stages/fluorescence.py)
        and not has_fluorescence(built.materials)
    )
