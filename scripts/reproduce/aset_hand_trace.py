"""ASET zones of a round brilliant traced by hand, independently of the renderer.

Two checks of `warpoptics.grading.scopes.aset`, which builds the zones from renders:

1. The **meridional closed form** (Harding, "Faceting limitations", cutstudy.com; the classic
   table-ray analysis): a ray entering the table along the axis meets a pavilion main at incidence
   p (the pavilion angle), the opposite main at 180 - 3p, and travels up at |180 - 4p| from the
   axis; it leaves the table at asin(n sin|180 - 4p|) from the zenith unless that exceeds the
   critical angle asin(1/n) (24.4 deg in diamond).  The second main transmits when
   180 - 3p < 24.4 deg (p > 51.9 deg), but a steep main sends that light out *upward* until
   p + asin(n sin(180 - 3p)) < 90 deg: only above p = 55.48 deg (:func:`centre_leak_onset`) does
   the pavilion centre see light from below the girdle plane, ASET's leakage.  (The "nailhead" of
   deep stones, 44.0-46.0 deg, is this exit angle falling inside the observer's 10 deg head.)
   :func:`meridional` returns these angles.
2. A **3-D path tree in NumPy** (:func:`trace_zones`): camera rays from the observer (250 mm, as in
   `face_up_scene`) into the stone's convex polyhedron (its facet planes, `mesh.metadata`), split
   at every facet into the reflected and refracted branch with unpolarized Fresnel power
   coefficients (`warpoptics.optics.fresnel_power`: the mean of Rs and Rp; the renderer carries
   Jones matrices, so multi-bounce weights differ at the per-cent level), to a depth of 40 facets
   and a branch energy of 1e-6.  Each branch that leaves the stone is binned by the zenith angle
   of its direction (the direction the light comes from): blue [0, head), red [head, 45), green
   [45, 90), leak beyond 90 (below the girdle plane).  It returns both the energy per zone (all
   orders: the physical mix an ASET shows) and the zone of each pixel's strongest single path.

Run: ``python scripts/reproduce/aset_hand_trace.py`` (prints the numbers quoted in the README's
grading section and `tests/test_grading_aset.py`; ~1 min on one core).
"""

from __future__ import annotations

import math

import numpy as np

N_DIAMOND = 2.4175  # n_D of diamond (589 nm), as `scopes._stone_scene` uses
ZONES = ("blue", "red", "green", "leak")


def meridional(p_deg: float, n: float = N_DIAMOND) -> dict:
    """The axial table ray of a brilliant with pavilion angle ``p_deg`` in its main's meridional
    plane (module docstring): incidences ``i1``, ``i2`` on the two mains, the internal angle of
    the returning ray from the axis, its exit angle from the zenith through the table (None when
    the table reflects it totally), and, when the second main transmits (i2 < critical), the
    elevation of the transmitted ray above the girdle plane, 90 - (p + asin(n sin i2)) with a
    minus sign: negative is light from below the girdle plane (ASET leakage), positive light from
    just above it (the green zone)."""
    crit = math.degrees(math.asin(1.0 / n))
    i1, i2 = p_deg, 180.0 - 3.0 * p_deg
    up = abs(180.0 - 4.0 * p_deg)
    out = math.degrees(math.asin(n * math.sin(math.radians(up)))) if up < crit else None
    elev = None
    if 0.0 <= i2 < crit:
        # the second main's outward normal is p from the downward vertical; the ray leaves on the
        # far side of the normal from the first main, turned up along the facet by t2
        elev = -(90.0 - (p_deg + math.degrees(math.asin(n * math.sin(math.radians(i2))))))
    return {
        "i1": i1,
        "i2": i2,
        "internal": up,
        "exit_zenith": out,
        "pavilion_exit_elevation": elev,
        "crit": crit,
    }


def centre_leak_onset(n: float = N_DIAMOND) -> float:
    """The pavilion angle (deg) above which the axial table ray leaves through the second main
    from below the girdle plane (``pavilion_exit_elevation`` < 0): 55.48 deg in diamond."""
    from scipy.optimize import brentq

    crit = math.degrees(math.asin(1.0 / n))
    lo = (180.0 - crit) / 3.0 + 1e-9  # i2 = critical: the second main starts to transmit
    return float(brentq(lambda p: meridional(p, n)["pavilion_exit_elevation"], lo, 59.9))


def _fresnel_R(cos_i, n1, n2):
    from warpoptics.optics import fresnel_power

    rs, rp, _, _ = fresnel_power(np.clip(cos_i, 0.0, 1.0), n1, n2)
    return 0.5 * (np.asarray(rs) + np.asarray(rp))


def _exit_planes(planes, o, d, entering: bool):
    """Ray-polyhedron intersection with the convex solid {x: N x <= D}: for rays outside
    (``entering``) the entry parameter and facet (max over front-facing planes, -1 on a miss), for
    rays inside the exit parameter and facet (min over back-facing planes)."""
    nrm, dist = planes[:, :3], planes[:, 3]
    nd = d @ nrm.T  # (N, F)
    no = o @ nrm.T
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (dist[None, :] - no) / nd
    if entering:
        t_in = np.where(nd < 0, t, -np.inf)
        t_out = np.where(nd > 0, t, np.inf)
        k = np.argmax(t_in, axis=1)
        ti = t_in[np.arange(len(o)), k]
        hit = (ti < t_out.min(axis=1)) & (ti > 0)
        return np.where(hit, ti, np.nan), np.where(hit, k, -1)
    t_out = np.where(nd > 1e-12, t, np.inf)
    t_out = np.where(t_out > 1e-9, t_out, np.inf)
    k = np.argmin(t_out, axis=1)
    return t_out[np.arange(len(o)), k], k


def _zone(zen_deg, head_deg):
    return np.where(zen_deg < head_deg, 0, np.where(zen_deg < 45.0, 1, np.where(zen_deg < 90.0, 2, 3)))


def trace_zones(
    stone: dict,
    *,
    size: int = 48,
    head_deg: float = 10.0,
    distance_mm: float = 250.0,
    n: float = N_DIAMOND,
    max_depth: int = 40,
    min_energy: float = 1e-6,
    tilt_deg: float = 0.0,
) -> dict:
    """Per-pixel zone energies (size, size, 4) [blue, red, green, leak] of ``stone`` (a
    ``round_brilliant`` object table) face-up, the index (size, size) of each pixel's strongest
    path's zone (-1 off the stone), the energy lost to the depth/energy cut-offs, and the pixel
    radius in girdle radii.  Framing as `face_up_scene`: the half-width is 0.54 diameters at z = 0."""
    from warpoptics.geometry.cuts import round_brilliant

    kw = {k: v for k, v in stone.items() if k not in ("shape", "material")}
    mesh = round_brilliant(**kw)
    planes = np.asarray(mesh.metadata["planes"], dtype=np.float64)
    if tilt_deg:  # the stone turned about the world x axis (`presets.tilt_rotation`, azimuth 0)
        t_ = math.radians(tilt_deg)
        rx = np.array(
            [[1.0, 0.0, 0.0], [0.0, math.cos(t_), -math.sin(t_)], [0.0, math.sin(t_), math.cos(t_)]]
        )
        planes = np.concatenate([planes[:, :3] @ rx.T, planes[:, 3:]], axis=1)
    d_mm = float(stone.get("diameter", 1.0))
    half = 0.54 * d_mm
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    xx, yy = np.meshgrid(c * half, -c * half)
    target = np.stack([xx.ravel(), yy.ravel(), np.zeros(xx.size)], axis=-1)
    cam = np.array([0.0, 0.0, distance_mm])
    d = target - cam
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    o = np.repeat(cam[None, :], len(d), axis=0)
    npix = size * size
    energy = np.zeros((npix, 4))
    best = np.full(npix, -1.0)
    best_zone = np.full(npix, -1)
    lost = np.zeros(npix)
    # leakage by the number of partial (not total) internal reflections on its path: 0 = light
    # that reaches the pavilion by total reflections alone, 1+ = light sent back by a Fresnel
    # reflection at a facet it could have left through
    leak_by_partial = np.zeros((npix, 3))

    t, k = _exit_planes(planes, o, d, entering=True)
    hit = k >= 0
    pix = np.nonzero(hit)[0]
    o, d, k, t = o[hit], d[hit], k[hit], t[hit]
    x = o + d * t[:, None]
    nrm = planes[k, :3]
    cos_i = -(d * nrm).sum(axis=1)
    R = _fresnel_R(cos_i, 1.0, n)

    def deposit(pix_, w_, dirs_, partial_=None):
        z = _zone(np.degrees(np.arccos(np.clip(dirs_[:, 2], -1.0, 1.0))), head_deg)
        np.add.at(energy, (pix_, z), w_)
        if partial_ is not None:
            lk = z == 3
            np.add.at(leak_by_partial, (pix_[lk], np.minimum(partial_[lk], 2)), w_[lk])
        better = w_ > best[pix_]
        # several paths of one pixel in one batch: keep the largest (sort so it is written last)
        order = np.argsort(w_)
        pb, wb, zb, bb = pix_[order], w_[order], z[order], better[order]
        best[pb[bb]] = np.maximum(best[pb[bb]], wb[bb])
        best_zone[pb[bb]] = zb[bb]

    refl = d - 2.0 * (d * nrm).sum(axis=1)[:, None] * nrm  # the external reflection goes to the sky
    deposit(pix, R, refl)
    # refraction into the stone (Snell, vector form)
    eta = 1.0 / n
    cos_t = np.sqrt(1.0 - eta**2 * (1.0 - cos_i**2))
    dt = eta * d + (eta * cos_i - cos_t)[:, None] * nrm
    rays = [(pix, x, dt / np.linalg.norm(dt, axis=1, keepdims=True), 1.0 - R, np.zeros(len(pix), dtype=int))]
    for _depth in range(max_depth):
        nxt = []
        for pix_, o_, d_, w_, np_ in rays:
            if len(pix_) == 0:
                continue
            t, k = _exit_planes(planes, o_ + 1e-9 * d_, d_, entering=False)
            x = o_ + d_ * t[:, None]
            nrm = planes[k, :3]
            cos_i = (d_ * nrm).sum(axis=1)
            sin_t2 = n**2 * (1.0 - cos_i**2)
            tir = sin_t2 >= 1.0
            R = np.where(tir, 1.0, _fresnel_R(cos_i, n, 1.0))
            # transmitted: leaves the stone
            tr = ~tir
            cos_t = np.sqrt(np.clip(1.0 - sin_t2, 0.0, 1.0))
            dout = n * d_ + (cos_t - n * cos_i)[:, None] * nrm
            if tr.any():
                dn = dout[tr] / np.linalg.norm(dout[tr], axis=1, keepdims=True)
                deposit(pix_[tr], (w_ * (1.0 - R))[tr], dn, np_[tr])
            dr = d_ - 2.0 * cos_i[:, None] * nrm
            wr = w_ * R
            keep = wr >= min_energy
            np.add.at(lost, pix_[~keep], wr[~keep])
            npr = np_ + (~tir).astype(int)
            nxt.append((pix_[keep], x[keep], dr[keep], wr[keep], npr[keep]))
        rays = nxt
    for pix_, _o, _d, w_, _n in rays:
        np.add.at(lost, pix_, w_)
    r = np.hypot(xx, yy).ravel() / (0.5 * d_mm)
    return {
        "energy": energy.reshape(size, size, 4),
        "dominant": best_zone.reshape(size, size),
        "lost": lost.reshape(size, size),
        "leak_by_partial": leak_by_partial.reshape(size, size, 3),
        "r": r.reshape(size, size),
    }


def zone_fractions(res: dict, mask=None) -> dict:
    """Energy shares of the four zones and the area shares of the pixels each zone dominates
    (strongest path), within ``mask`` (default the stone)."""
    on = res["dominant"] >= 0
    m = on if mask is None else on & mask
    e = res["energy"][m].sum(axis=0)
    e = e / e.sum()
    a = np.array([(res["dominant"][m] == z).mean() for z in range(4)])
    return {
        **{z: float(e[i]) for i, z in enumerate(ZONES)},
        **{f"area_{z}": float(a[i]) for i, z in enumerate(ZONES)},
    }


def main() -> None:
    print("meridional axial ray (n = 2.4175, critical 24.44 deg):")
    for p in (38.0, 39.0, 40.75, 41.5, 42.0, 43.0, 44.5, 48.0, 51.0, 52.0, 53.0, 55.0, 56.0):
        m = meridional(p)
        ex = "TIR" if m["exit_zenith"] is None else f"{m['exit_zenith']:.1f}"
        el = m["pavilion_exit_elevation"]
        pv = "TIR" if el is None else f"elevation {el:+.1f}"
        print(
            f"  p={p:5.2f}: i1={m['i1']:.2f} i2={m['i2']:.2f} up {m['internal']:.2f}; "
            f"table exit {ex}; main 2 {pv}"
        )
    print(f"axial ray leaks from below the girdle plane for p > {centre_leak_onset():.2f} deg")
    base = {"shape": "round_brilliant", "diameter": 6.5, "material": "diamond", "crown_angle": 34.5}
    stones = (("tolkowsky", 0.53, 40.75), ("deep43", 0.55, 43.0))
    for label, table, pav in stones:
        for tilt in (0.0, 10.0, 20.0):
            res = trace_zones({**base, "table": table, "pavilion_angle": pav}, size=64, tilt_deg=tilt)
            r, on = res["r"], res["dominant"] >= 0
            regions = {
                "stone": None,
                "centre r<0.3": r < 0.3,
                "table ring": (r >= 0.3) & (r < table * math.cos(math.pi / 8)),
                "crown r>=table": r >= table,
            }
            for name, mask in regions.items():
                f = zone_fractions(res, mask)
                e = res["energy"] / np.maximum(res["energy"].sum(axis=-1, keepdims=True), 1e-300)
                m = on if mask is None else on & mask
                a_lk = float((np.argmax(e, axis=-1)[m] == 3).mean())
                print(
                    f"{label} tilt {tilt:g} {name}: "
                    + " ".join(f"{z}={f[z]:.3f}" for z in ZONES)
                    + f" | leak-dominated area {a_lk:.3f}"
                )
            if tilt == 0.0:
                c = on & (r < 0.3)
                lb = res["leak_by_partial"][c].sum(axis=0) / res["energy"][c].sum()
                print(f"{label} centre leakage by partial reflections 0 / 1 / 2+: {np.round(lb, 4)}")
                print(f"{label} lost to the cut-offs: {res['lost'][on].mean():.1e}")
    print("centre (r < 0.3) vs pavilion angle (table 55 %):")
    for p in (43.0, 50.0, 54.0, 55.0, 55.5, 56.0, 57.0):
        res = trace_zones({**base, "table": 0.55, "pavilion_angle": p}, size=48)
        c = (res["dominant"] >= 0) & (res["r"] < 0.3)
        e = res["energy"][c]
        print(
            f"  {p:4.1f}: leak energy {e[:, 3].sum() / e.sum():.3f}, "
            f"leak-dominated area {(np.argmax(e, 1) == 3).mean():.3f}"
        )


if __name__ == "__main__":
    main()
