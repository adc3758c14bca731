"""Shared helpers of the Guy & Soler 2004 gem-picture reproductions.

``gem_scene`` builds a small studio scene around one stone, ``render_panel`` renders it and
measures the stone (mean colour over the pixels whose primary ray hit it), ``montage`` writes the
labelled panels side by side as one small PNG (Pillow, a dependency of matplotlib).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass

import numpy as np

import warpoptics as wo


def parser(doc: str, default_out: str) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(description=doc.splitlines()[0])
    p.add_argument("-o", "--output", default=default_out, help=f"PNG to write (default {default_out})")
    p.add_argument("--size", type=int, default=None, help="panel size in pixels")
    p.add_argument("--wavelengths", type=int, default=None, help="stratified wavelength samples per pixel")
    p.add_argument("--quick", action="store_true", help="tiny panels (a smoke test, seconds)")
    p.add_argument("--device", default=None)
    return p


def sizes(args, size: int, wavelengths: int) -> tuple[int, int]:
    """Panel size and wavelength count from the options (``--quick``: 24 px, 4 wavelengths)."""
    s = args.size or (24 if args.quick else size)
    w = args.wavelengths or (4 if args.quick else wavelengths)
    if s < 8 or s > 1024:
        raise SystemExit("error: --size must be in 8..1024")
    if w < 1 or w > 256:
        raise SystemExit("error: --wavelengths must be in 1..256")
    return s, w


def gem_scene(
    obj: dict,
    *,
    size: int,
    wavelengths: int,
    camera: dict | None = None,
    render: dict | None = None,
    light: dict | None = None,
) -> wo.Scene:
    """A stone in the studio environment, seen from the front and above (scenes/tourmaline.toml)."""
    cam = {
        "type": "perspective",
        "position": [0.0, -24.0, 26.0],
        "look_at": [0.0, 0.0, -0.5],
        "up": [0.0, 0.0, 1.0],
        "fov": 20.0,
        "width": size,
        "height": size,
        **(camera or {}),
    }
    ren = {
        "spectral": "stratified",
        "wavelengths": wavelengths,
        "polarization": True,
        "birefringence": "exact",
        "max_depth": 12,
        "exposure": 1.0,
        **(render or {}),
    }
    return wo.Scene.from_dict(
        {
            "camera": cam,
            "render": ren,
            "light": [light or {"type": "environment", "map": "studio"}],
            "object": [obj],
        }
    )


@dataclass
class Panel:
    label: str
    image: wo.Image
    seconds: float

    @property
    def stone(self) -> np.ndarray:
        return self.image.alpha > 0.99

    def mean_xyz(self, mask=None) -> np.ndarray:
        m = self.stone if mask is None else (self.stone & mask)
        return self.image.xyz[m].mean(axis=0)

    def describe(self, mask=None) -> str:
        xyz = self.mean_xyz(mask)
        xy = xyz[:2] / max(xyz.sum(), 1e-30)
        rgb = wo.color.gamut_clip(xyz[None], 1.0e30)[0]
        rgb = rgb / max(rgb.max(), 1e-30)
        return (
            f"Y {xyz[1]:.4f}  xy ({xy[0]:.4f}, {xy[1]:.4f})  relative linear sRGB "
            f"({rgb[0]:.2f}, {rgb[1]:.2f}, {rgb[2]:.2f})"
        )


def render_panel(label: str, scene: wo.Scene, device=None) -> Panel:
    t0 = time.perf_counter()
    img = wo.render(scene, device=device)
    return Panel(label, img, time.perf_counter() - t0)


def delta_e(a: Panel, b: Panel, mask_a=None, mask_b=None) -> float:
    """CIEDE2000 between the mean stone colours, each normalized to Y = 1 (chromatic difference
    without the brightness), and with brightness (the second number)."""
    xa, xb = a.mean_xyz(mask_a), b.mean_xyz(mask_b)
    return float(wo.color.delta_e2000(xa / xa[1], xb / xb[1]))


def montage(path: str, panels, *, gap: int = 4, title: str | None = None) -> None:
    """Display-encoded RGB panels (H, W, 3 in [0, 1]) side by side with a label under each;
    ``panels`` is a list of (label, rgb) or a list of such rows."""
    from PIL import Image as PILImage
    from PIL import ImageDraw

    rows = panels if panels and isinstance(panels[0], list) else [panels]
    label_h = 14
    top = 14 if title else 0
    row_h = [max(p.shape[0] for _, p in r) + label_h for r in rows]
    w = max(sum(p.shape[1] for _, p in r) + gap * (len(r) - 1) for r in rows)
    canvas = PILImage.new("RGB", (w, top + sum(row_h)), (0, 0, 0))
    draw = ImageDraw.Draw(canvas)
    if title:
        draw.text((3, 1), title, fill=(220, 220, 220))
    y = top
    for r, rh in zip(rows, row_h, strict=True):
        x = 0
        for label, rgb in r:
            im = PILImage.fromarray(np.round(np.clip(rgb, 0, 1) * 255).astype(np.uint8))
            canvas.paste(im, (x, y))
            draw.text((x + 3, y + rh - label_h + 1), label, fill=(220, 220, 220))
            x += rgb.shape[1] + gap
        y += rh
    arr = np.asarray(canvas).astype(np.float64) / 255.0
    wo.film.image.write_png(path, arr)


def camera_axes(scene: wo.Scene) -> dict[str, np.ndarray]:
    """World directions of a scene's camera: toward the eye, image left-right and image up-down."""
    c = scene.camera
    f = np.subtract(c.look_at, c.position).astype(np.float64)
    f /= np.linalg.norm(f)
    right = np.cross(f, c.up)
    right /= np.linalg.norm(right)
    up = np.cross(right, f)
    return {"toward the eye": -f, "left-right": right, "up-down": up, "diagonal": (right + up) / np.sqrt(2.0)}


def axis_panels(
    material: str,
    orientations: list[str],
    *,
    size: int,
    wavelengths: int,
    device=None,
    obj: dict | None = None,
    **scene_kw,
) -> list[Panel]:
    """One panel per optic-axis orientation (names of :func:`camera_axes`), same stone and light;
    ``scene_kw`` go to :func:`gem_scene` (camera, render, light)."""
    base = {"shape": "emerald", "length": 8.0, "width": 6.0, "material": material, **(obj or {})}
    probe = gem_scene(base, size=size, wavelengths=wavelengths, **scene_kw)
    axes = camera_axes(probe)
    out = []
    for name in orientations:
        a = axes[name]
        sc = gem_scene(
            {**base, "optic_axis": [float(v) for v in a]}, size=size, wavelengths=wavelengths, **scene_kw
        )
        out.append(render_panel(name, sc, device))
    return out


#: the pleochroism panels (fig. 3, fig. 11 e-g): a long step cut seen from above on the white dome
TOP_CAMERA = {"position": [0.0, -8.0, 40.0], "look_at": [0.0, 0.0, -0.5], "fov": 24.0}
LONG_STEP_CUT = {"length": 14.0, "width": 7.0}


def pleochroism_rows(
    material: str, orientations: list[str], scales, *, size: int, wavelengths: int, device=None
) -> list[list[tuple[str, np.ndarray]]]:
    """Rows of panels (one row per absorbance scale, one panel per optic-axis orientation) of a
    long step cut on the dome, printing each panel's colour and its dE00 against the row's first."""
    rows = []
    for scale in scales:
        panels = axis_panels(
            material,
            orientations,
            size=size,
            wavelengths=wavelengths,
            device=device,
            obj={**LONG_STEP_CUT, "absorption_scale": scale},
            camera=TOP_CAMERA,
            render={"exposure": 0.0},
            light={"type": "environment", "map": "dome"},
        )
        ref = panels[0]
        for p in panels:
            print(
                f"  absorbance x{scale:g}  axis {p.label:15s} {p.describe()}  dE00 vs {ref.label} "
                f"{delta_e(p, ref):5.2f}  ({p.seconds:.1f} s)"
            )
        rows.append([(f"x{scale:g}: axis {p.label}", p.image.display()) for p in panels])
    return rows
