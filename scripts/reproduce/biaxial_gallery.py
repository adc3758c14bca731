"""Biaxial gallery: trichroic step cuts along X, Y, Z; andalusite biaxial vs uniaxial;
a peridot brilliant's doubled back facets.

Writes into ``--out-dir`` (default ``docs/gallery``):

- ``biaxial_trichroism.png``: tanzanite and iolite long step cuts (14 x 7 mm) on the white dome,
  seen from above with the principal axis X, Y or Z toward the eye (the other two axes across
  the image, cyclic: X toward the eye puts Y left-right).  Along each axis the light is carried
  by the two eigenwaves whose D lie along the other two axes, so the three views show the three
  principal spectra mixed two at a time; under each view its dichroscope (``dichroscope`` at
  ``eigenwave_angle``: fast wave left) separates the two, and across the three views each
  principal colour shows twice.
- ``biaxial_andalusite.png``: the andalusite of Guy & Soler 2004 fig. 11 e-g (the same long step cut, dome,
  camera and panels as ``guy_soler_fig11_andalusite.py``, absorbance x 5 where the paper's weak
  triplets show colour): top row the library's biaxial andalusite (Handbook of Mineralogy indices,
  the §6.1 spectra per axis: X o-like, Y = Z e-like), bottom row the paper's uniaxial
  approximation ``andalusite_uniaxial``.  The biaxial Z (its n_gamma ~ the paper's n_e) lies where
  the uniaxial optic axis lies: toward the eye (X left-right), up-down or left-right (X toward
  the eye in both).
- ``biaxial_peridot.png``: a peridot round brilliant (6.5 mm, Y — the optic normal — along the
  table normal), a close-up (1.3 mm field) through the crown onto the pavilion, studio light:
  the biaxial stone (each back facet edge seen twice: doubling) beside the same stone with the
  one index n_beta (its Y channel: single edges).  Prints the angle between the two refracted
  rays at a crown facet (optics.biaxial_waves) and the edge offset it makes after 4 mm.
- ``biaxial_gallery.json``: the numbers printed: per stone and axis the mean colour (xy, Y),
  CIEDE2000 (brightness removed) between the three views of each stone, biaxial vs uniaxial
  andalusite per orientation, and the peridot's ray split and edge doubling.

Usage:
    python scripts/reproduce/biaxial_gallery.py [--out-dir docs/gallery] [--size 112] [--quick]
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import _guy_soler_panels as sp
import numpy as np
from _gallery import write_json

import warpoptics as wo

AXIS_NAMES = "XYZ"


def _frame_toward(axis: int, toward: np.ndarray, across: np.ndarray) -> list[list[float]]:
    """crystal_axes rows X, Y, Z with principal axis ``axis`` along ``toward`` and the next one
    (cyclic) along ``across``; the third completes a right-handed frame."""
    rows = np.zeros((3, 3))
    rows[axis] = toward
    rows[(axis + 1) % 3] = across
    rows[(axis + 2) % 3] = np.cross(toward, across)
    return rows.tolist()


def _panel(label: str, obj: dict, *, size: int, wavelengths: int, device, **kw) -> sp.Panel:
    sc = sp.gem_scene(obj, size=size, wavelengths=wavelengths, **kw)
    return sp.render_panel(label, sc, device)


def _colour(p: sp.Panel) -> dict:
    xyz = p.mean_xyz()
    return {"Y": round(float(xyz[1]), 4), "xy": [round(float(v), 4) for v in xyz[:2] / xyz.sum()]}


DOME = dict(camera=sp.TOP_CAMERA, render={"exposure": 0.0}, light={"type": "environment", "map": "dome"})


def trichroism(size: int, wavelengths: int, device, out: dict) -> list:
    """Tanzanite and iolite along X, Y, Z: one montage row per stone."""
    probe = sp.gem_scene({"shape": "emerald", "material": "bk7"}, size=size, wavelengths=1, **DOME)
    axes = sp.camera_axes(probe)
    rows = []
    for stone in ("tanzanite", "iolite"):
        panels = []
        for i, a in enumerate(AXIS_NAMES):
            obj = {
                "shape": "emerald",
                **sp.LONG_STEP_CUT,
                "material": stone,
                "crystal_axes": _frame_toward(i, axes["toward the eye"], axes["left-right"]),
            }
            panels.append(
                _panel(f"{stone} along {a}", obj, size=size, wavelengths=wavelengths, device=device, **DOME)
            )
        entry: dict = {a: _colour(p) for a, p in zip(AXIS_NAMES, panels, strict=True)}
        for u, v in ((0, 1), (0, 2), (1, 2)):
            entry[f"dE00 {AXIS_NAMES[u]}-{AXIS_NAMES[v]}"] = round(sp.delta_e(panels[u], panels[v]), 2)
        for p in panels:
            print(f"  {p.label:20s} {p.describe()}  ({p.seconds:.1f} s)")
        print(f"  {stone}: dE00 X-Y {entry['dE00 X-Y']}, X-Z {entry['dE00 X-Z']}, Y-Z {entry['dE00 Y-Z']}")
        rows.append([(p.label, p.image.display()) for p in panels])
        rows.append(_dichroscope_row(stone, panels, probe, axes, entry))
        out[stone] = entry
    return rows


def _dichroscope_row(stone: str, panels, probe, axes, entry: dict) -> list:
    """The dichroscope of each view at the angle of its fast eigenwave (views.eigenwave_angle):
    the two windows are the two principal spectra whose D lie across the view."""
    from warpoptics.film.views import dichroscope, eigenwave_angle
    from warpoptics.stages.camera import camera_basis

    fwd, right, up = camera_basis(probe.camera)
    mat = wo.materials.get(stone)
    row = []
    for i, (a, p) in enumerate(zip(AXIS_NAMES, panels, strict=True)):
        frame = np.array(_frame_toward(i, axes["toward the eye"], axes["left-right"]))
        angle = eigenwave_angle(mat.with_crystal_axes(frame), fwd, right, up)
        d = dichroscope(p.image, angle, gap=2)
        w = p.image.xyz.shape[1]
        # the two D axes across the view, fast (lower principal index) first
        fast, slow = (AXIS_NAMES[j] for j in range(3) if j != i)
        win = {fast: d.xyz[:, :w][p.stone].mean(axis=0), slow: d.xyz[:, w + 2 :][p.stone].mean(axis=0)}
        de = float(wo.color.delta_e2000(win[fast] / win[fast][1], win[slow] / win[slow][1]))
        entry[f"dichroscope along {a}"] = {
            "angle_deg": round(angle, 2),
            **{f"D along {k}": [round(float(c), 4) for c in v[:2] / v.sum()] for k, v in win.items()},
            "dE00 between windows": round(de, 2),
        }
        print(f"  {stone} along {a}: dichroscope at {angle:.0f} deg, D along {fast} | {slow}: dE00 {de:.2f}")
        row.append((f"dichroscope: D {fast} | D {slow}", d.display()))
    return row


def andalusite(size: int, wavelengths: int, device, out: dict, scale: float = 5.0) -> list:
    """Biaxial andalusite (top) beside the Guy & Soler uniaxial approximation (bottom)."""
    probe = sp.gem_scene({"shape": "emerald", "material": "bk7"}, size=size, wavelengths=1, **DOME)
    axes = sp.camera_axes(probe)
    eye, lr, ud = axes["toward the eye"], axes["left-right"], axes["up-down"]
    base = {"shape": "emerald", **sp.LONG_STEP_CUT, "absorption_scale": scale}
    # the uniaxial optic axis, and the biaxial frame with Z there (rows X, Y, Z)
    orientations = {
        "toward the eye": (eye, [lr, np.cross(eye, lr), eye]),
        "up-down": (ud, [eye, np.cross(ud, eye), ud]),
        "left-right": (lr, [eye, np.cross(lr, eye), lr]),
    }
    bi, uni = [], []
    for name, (axis, frame) in orientations.items():
        obj_b = {**base, "material": "andalusite", "crystal_axes": [list(map(float, r)) for r in frame]}
        obj_u = {**base, "material": "andalusite_uniaxial", "optic_axis": [float(v) for v in axis]}
        bi.append(
            _panel(f"biaxial, Z {name}", obj_b, size=size, wavelengths=wavelengths, device=device, **DOME)
        )
        uni.append(
            _panel(f"uniaxial, axis {name}", obj_u, size=size, wavelengths=wavelengths, device=device, **DOME)
        )
    entry: dict = {"absorption_scale": scale}
    for name, pb, pu in zip(orientations, bi, uni, strict=True):
        de = round(sp.delta_e(pb, pu), 2)
        entry[name] = {"biaxial": _colour(pb), "uniaxial": _colour(pu), "dE00 biaxial-uniaxial": de}
        print(f"  {pb.label:26s} {pb.describe()}  ({pb.seconds:.1f} s)")
        print(f"  {pu.label:26s} {pu.describe()}  dE00 biaxial vs uniaxial {de:.2f}")
    entry["dE00 between orientations"] = {
        "biaxial": [round(sp.delta_e(bi[0], bi[j]), 2) for j in (1, 2)],
        "uniaxial": [round(sp.delta_e(uni[0], uni[j]), 2) for j in (1, 2)],
    }
    out["andalusite"] = entry
    return [[(f"x{scale:g} {p.label}", p.image.display()) for p in row] for row in (bi, uni)]


def peridot(size: int, wavelengths: int, device, out: dict) -> list:
    """Peridot brilliant, a close-up through the crown (1.3 mm field): biaxial (doubled back
    facet edges) vs one index, n_beta."""
    camera = {"position": [0.0, -12.0, 38.0], "look_at": [0.9, 0.6, 0.0], "up": [0.0, 1.0, 0.0], "fov": 2.0}
    # Y (n_beta, the optic normal) along the table normal z: X along x, Z along -y
    obj = {
        "shape": "round_brilliant",
        "diameter": 6.5,
        "material": "peridot",
        "crystal_axes": [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
    }
    # studio light (its edges draw the facets); 3 spp: a crystal path picks one wave per branch
    # below the split threshold, so the biaxial panel is noisier than the isotropic one
    kw = dict(
        size=size, wavelengths=wavelengths, camera=camera, render={"max_depth": 6, "spp": 3, "exposure": -1.0}
    )
    panels = [sp.render_panel("peridot (biaxial)", sp.gem_scene(obj, **kw), device)]
    # the same stone with one index: its n_beta channel (index and absorption for D along Y)
    iso = {k: v for k, v in obj.items() if k != "crystal_axes"}
    sc = sp.gem_scene({**iso, "material": "bk7"}, **kw)
    sc = dataclasses.replace(
        sc, objects=(dataclasses.replace(sc.objects[0], material=wo.materials.get("peridot").beta),)
    )
    panels.append(sp.render_panel("isotropic n_beta", sc, device))
    # the doubling: the two refracted rays of a camera ray entering a crown facet (34.5°) at the
    # camera's incidence, their angle, and the edge offset after the ~4 mm to the back facets
    n = wo.materials.get("peridot").n(589.3)
    f = np.subtract(camera["look_at"], camera["position"])
    f /= np.linalg.norm(f)
    c = np.radians(34.5)
    normal = np.array([0.0, -np.sin(c), np.cos(c)])  # a crown facet facing the camera
    _, rays, _ = wo.optics.biaxial_waves(f, normal, np.array(obj["crystal_axes"]), 1.0, *n)
    split = float(np.degrees(np.arccos(np.clip(rays[0] @ rays[1], -1.0, 1.0))))
    offset = 4.0 * np.radians(split)
    dist = float(np.linalg.norm(np.subtract(camera["look_at"], camera["position"])))
    field = 2.0 * dist * np.tan(np.radians(camera["fov"] / 2))  # mm across the image
    out["peridot"] = {
        "n_alpha, n_beta, n_gamma (589.3 nm)": [round(float(v), 4) for v in n],
        "birefringence n_gamma - n_alpha": round(float(n[2] - n[0]), 4),
        "ray split through a crown facet (deg)": round(split, 3),
        "edge doubling after 4 mm (mm)": round(offset, 4),
        "edge doubling (px)": round(offset / field * size, 1),
    }
    for p in panels:
        print(f"  {p.label:30s} {p.describe()}  ({p.seconds:.1f} s)")
    print(
        f"  peridot: the two rays through a crown facet {split:.3f} deg apart: back-facet edges doubled by "
        f"{offset:.3f} mm after 4 mm ({offset / field * size:.1f} px in this {field:.2f} mm field)"
    )
    return [[(p.label, p.image.display()) for p in panels]]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out-dir", default="docs/gallery", help="folder for the PNGs and the JSON")
    ap.add_argument("--size", type=int, default=None, help="panel size in pixels (default 112; peridot 160)")
    ap.add_argument(
        "--wavelengths", type=int, default=None, help="stratified wavelengths per pixel (default 12)"
    )
    ap.add_argument("--quick", action="store_true", help="tiny panels (a smoke test)")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)
    size, wl = sp.sizes(args, 112, 12)
    big = size if (args.size or args.quick) else 160
    out_dir = Path(args.out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    numbers: dict = {"size": size, "wavelengths": wl}
    print(f"tanzanite and iolite step cuts along X, Y, Z ({size} px, {wl} wavelengths, dome light)")
    sp.montage(
        str(out_dir / "biaxial_trichroism.png"),
        trichroism(size, wl, args.device, numbers),
        title="trichroism: principal axis X | Y | Z toward the eye",
    )
    print("andalusite (Guy & Soler 2004 fig. 11 e-g): biaxial vs the uniaxial approximation")
    sp.montage(
        str(out_dir / "biaxial_andalusite.png"),
        andalusite(size, wl, args.device, numbers),
        title="andalusite x5: biaxial (top) vs uniaxial approximation (bottom)",
    )
    print(f"peridot brilliant, close-up through the crown ({big} px)")
    sp.montage(
        str(out_dir / "biaxial_peridot.png"),
        peridot(big, wl, args.device, numbers),
        title="peridot close-up: doubled back facets (biaxial) vs one index",
    )
    numbers["seconds"] = round(time.perf_counter() - t0, 1)
    write_json(out_dir / "biaxial_gallery.json", numbers)
    names = "biaxial_trichroism.png, biaxial_andalusite.png, biaxial_peridot.png, biaxial_gallery.json"
    print(f"wrote {out_dir}/{{{names}}}")
    print(f"total {numbers['seconds']:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
