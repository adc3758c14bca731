"""Where a gem render's noise comes from: the map's edges or the facets' edges.

A pixel's samples fall on different facet sequences of the stone (facet edges in the pixel's
footprint, at every depth of the path tree) and, within one sequence, leave toward nearby
directions of the environment (map edges: the soft boxes' rims).  Pre-filtered environment
lookups (ray cones through the flat facets) would remove the second kind; only integrating the
pixel over the facet tree (beam tracing) removes the first.  This script measures their shares:
the fire benchmark's two scenes (``scenes/bench_fire.toml``, dispersive, and its clear twin
``bench_fire_clear.toml``) rendered twice with independent seeds, with the studio map as it is
and blurred by a Gaussian of ``--sigma`` texels (scipy.ndimage, wrapped in azimuth).  The noise
of one render is rms(a - b) / sqrt 2 / mean (``equal_error.rel_noise``; linear sRGB, all pixels:
the renders are unbiased).
If the blurred map's noise is close to the sharp one's, the facets' edges dominate.

Second, which facet edges: a pixel whose footprint holds an edge of the facets the camera rays
hit first (8x8 sub-pixel rays through ``stages.camera.camera_ray`` meet more than one facet, or
the stone and the background: ``geometry.query.scene_closest_hit``) could be integrated exactly
by clipping the pixel against the projected front facets, a far smaller step than beam tracing
the whole tree.  The script reports those pixels' share of the variance (uniform sampling, two
seeds) and their variance per pixel against the other pixels on the stone: if the first-hit
edges held most of it, that step would pay; if the edge pixels are only a little noisier than
the rest, the noise comes from the edges seen deeper in the tree.

    python scripts/bench/fire_noise_sources.py [--res 64] [--spp 16] [--sigma 4 16] [--sub 8]
        [--json scripts/bench/results/fire_noise_sources.json]
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import OpenImageIO as oiio
import warp as wp
from scipy.ndimage import gaussian_filter

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import warpoptics as wo  # noqa: E402
from warpoptics.geometry.query import SceneGeometry, scene_closest_hit  # noqa: E402
from warpoptics.pipelines.render import Renderer  # noqa: E402
from warpoptics.stages.camera import CameraParams, camera_ray  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from equal_error import rel_noise  # noqa: E402

MAP = ROOT / "scenes" / "bench_studio.exr"


def blurred_map(sigma: float, path: Path) -> None:
    """The benchmark map blurred by a Gaussian of ``sigma`` texels (azimuth wraps), as EXR."""
    a = oiio.ImageBuf(str(MAP)).get_pixels(oiio.FLOAT)
    b = np.stack(
        [gaussian_filter(a[..., c], sigma=sigma, mode=("nearest", "wrap")) for c in range(a.shape[2])], -1
    )
    out = oiio.ImageBuf(oiio.ImageSpec(a.shape[1], a.shape[0], a.shape[2], oiio.FLOAT))
    out.set_pixels(oiio.ROI(), b.astype(np.float32))
    if not out.write(str(path)):
        raise RuntimeError(f"{path}: {out.geterror()}")


def noise(scene: str, map_path: Path, res: int, spp: int) -> tuple[float, float]:
    """(relative noise of one render, CPU seconds per render)."""
    base = wo.Scene.load(ROOT / "scenes" / f"{scene}.toml")
    imgs, cpu = [], 0.0
    for seed in (11, 12):
        over = {"camera.width": res, "camera.height": res, "render.spp": spp, "render.seed": seed}
        sc = base.with_overrides({**over, "light.0.map": str(map_path)})
        t0 = time.process_time()
        imgs.append(wo.render(sc).rgb.astype(np.float64))
        cpu += time.process_time() - t0
    return rel_noise(np.stack(imgs)), cpu / 2.0


@wp.kernel
def _first_facets(cam: CameraParams, geom: SceneGeometry, sub: int, out: wp.array2d(dtype=wp.int32)):
    # the facet that sub-pixel ray s of pixel `pix` meets first (-1: the background)
    pix, s = wp.tid()
    px = float(pix % cam.width) + (float(s % sub) + 0.5) / float(sub)
    py = float(pix / cam.width) + (float(s / sub) + 0.5) / float(sub)
    o, d, _b = camera_ray(cam, px, py, 0.5, 0.5)
    h = scene_closest_hit(geom, o, d, 1.0e30)
    out[pix, s] = -1
    if h.object >= 0:
        out[pix, s] = h.facet


def first_hit_edges(scene: str, res: int, spp: int, sub: int) -> dict:
    """The variance share of the pixels with a first-hit facet edge (module docstring)."""
    sc = wo.Scene.load(ROOT / "scenes" / f"{scene}.toml").with_overrides(
        {"camera.width": res, "camera.height": res, "render.spp": spp, "render.adaptive": False}
    )
    r = Renderer(sc)
    ids = wp.zeros((res * res, sub * sub), dtype=wp.int32, device="cpu")
    wp.launch(
        _first_facets,
        dim=(res * res, sub * sub),
        inputs=[r.camera.params, r.geometry.geometry, sub, ids],
        device="cpu",
    )
    f = ids.numpy()
    edge = (f.min(1) != f.max(1)).reshape(res, res)
    stone = (f.max(1) >= 0).reshape(res, res)
    imgs = [wo.render(sc.with_overrides({"render.seed": seed})).rgb.astype(np.float64) for seed in (21, 22)]
    var = ((imgs[0] - imgs[1]) ** 2 / 2.0).sum(-1)
    return {
        "scene": scene,
        "stone_pixels": float(stone.mean()),
        "edge_pixels": float(edge.mean()),
        "variance_share_of_edge_pixels": float(var[edge].sum() / var.sum()),
        "edge_over_other_stone_pixels": float(var[edge].mean() / var[~edge & stone].mean()),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--sigma", type=float, nargs="+", default=[4.0, 16.0], help="blur, map texels")
    ap.add_argument("--sub", type=int, default=8, help="sub-pixel rays per side for the first-hit facets")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args(argv)
    width = oiio.ImageInput.open(str(MAP)).spec().width
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        maps = [(0.0, MAP)]
        for s in args.sigma:
            p = Path(tmp) / f"blur_{s:g}.exr"
            blurred_map(s, p)
            maps.append((s, p))
        for scene in ("bench_fire_clear", "bench_fire"):
            sharp = None
            for s, p in maps:
                n, cpu = noise(scene, p, args.res, args.spp)
                sharp = n if sharp is None else sharp
                deg = s * 360.0 / width
                rows.append({"scene": scene, "sigma_texels": s, "sigma_deg": deg, "noise": n, "cpu_s": cpu})
                print(
                    f"{scene:17s} map blur {deg:4.1f} deg: one render {100 * n:.2f} % noise"
                    f" ({(n / sharp) ** 2:.2f} of the sharp map's variance), {cpu:.1f} CPU-s",
                    flush=True,
                )
    edges = []
    for scene in ("bench_fire_clear", "bench_fire"):
        e = first_hit_edges(scene, args.res, args.spp, args.sub)
        edges.append(e)
        print(
            f"{scene:17s} first-hit facet edges in {100 * e['edge_pixels']:.1f} % of the pixels"
            f" ({100 * e['stone_pixels']:.1f} % on the stone):"
            f" {100 * e['variance_share_of_edge_pixels']:.0f} %"
            f" of the variance, {e['edge_over_other_stone_pixels']:.2f}x the other stone pixels' per pixel",
            flush=True,
        )
    if args.json:
        from warpoptics.atomic import atomic_path

        with atomic_path(args.json) as tmp_json, open(tmp_json, "w") as f:
            json.dump({"res": args.res, "spp": args.spp, "rows": rows, "first_hit_edges": edges}, f, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
