"""An independent reference for the dispersive benchmark stone: Mitsuba 3, band by band.

Mitsuba's ``dielectric`` has one index: it cannot render a dispersive stone in one go.  But a
clear stone's image is a sum over wavelength bands, and inside a narrow band the index is
nearly constant.  So the spectrum 360-830 nm is cut into bands, and for each band b Mitsuba
renders the stone with ``int_ior`` = the library diamond's index in that band, through a
``specfilm`` whose single sensor response is a box over the band (Mitsuba traces only
wavelengths inside it).  The environment is a *grey* lat-long map g(direction) -- the
luminance of the benchmark's studio map -- whose spectrum is, by the scene's definition, the
same in every direction: g(direction) x S(lambda) with S = CIE D65 (warpoptics: "an RGB-white
environment is D65", stages/environment.py).  With a fixed index nothing in the transport
depends on the wavelength, so Mitsuba's band image is G_b(pixel) x (its own white spectrum
integrated over the band); dividing by that white integral (a render of a white map with no
stone, same film) leaves G_b, the stone's transport of the grey map at n_b, in which
Mitsuba's own RGB-to-spectrum model of the map cancels exactly.  The colour image is then

    XYZ(pixel) = sum_b G_b(pixel) * integral over b of cmf(lambda) S(lambda) dlambda / integral of ybar S

with the CIE 1931 2-degree functions and D65 from colour-science, and compared in linear sRGB
with warpoptics' converged dispersive render of the same scene: relative RMSE over the whole
image (all pixels, all three channels) / mean, free of both renderers' noise (split halves,
``equal_error.converged_difference``).

The band cut: bands of equal weight w(lambda) = (xbar + ybar + zbar) S (narrow where the eye
is sensitive), each band's index the w-weighted mean of n(lambda) over the band (n is nearly
linear inside a band: the error of a constant index is second order in the band width).  The
band error is measured by halving the bands (``--bands``).

Polarization: the benchmark renders polarized; Mitsuba's ``scalar_spectral_polarized`` variant
with the plain ``path`` integrator carries Mueller matrices along the path and films the
intensity S0 for an unpolarized source and sensor -- the quantity of our polarized render
(S0 after polarized transport differs from an unpolarized render: ``--unpolarized`` compares
unpolarized with unpolarized).

    python scripts/bench/fire_reference.py                     # the full-size comparison (hours)
    python scripts/bench/fire_reference.py --width 64 --height 64 --bands 24 --mitsuba-spp 256 \\
        --ours-spp 64 --ours-passes 8 --json scripts/bench/results/fire_reference_64.json
    python scripts/bench/fire_reference.py --quick             # seconds: a smoke run

References:
    Jakob, W. et al. 2022, Mitsuba 3 (plugins ``specfilm``, ``dielectric``, ``envmap``, ``path``;
    variant ``scalar_spectral_polarized``).  CIE 015:2018 (CIE 1931 observer, D65), via
    colour-science.  Peter, F. 1923, Z. Phys. 15, 358 (diamond's Sellmeier fit, the library's).
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from equal_error import converged_difference, log, rel_noise  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "bench_fire.toml"
STUDIO_MAP = ROOT / "scenes" / "bench_studio.exr"
LAMBDA_MIN, LAMBDA_MAX = 360, 830  # nm, warpoptics' colour integrals (docs/conventions.md)
CLEAR_INDEX = 2.4173  # any constant: the Mitsuba export needs a clear, isotropic stone


def observer_and_illuminant() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(wavelengths 360..830 nm at 1 nm, CIE 1931 2-degree cmfs (N, 3), D65 (N,)) from
    colour-science, independent of warpoptics' spectral tables."""
    import colour

    shape = colour.SpectralShape(LAMBDA_MIN, LAMBDA_MAX, 1)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape)
    d65 = colour.SDS_ILLUMINANTS["D65"].copy().align(shape)
    return np.asarray(shape.wavelengths, dtype=np.float64), np.asarray(cmfs.values), np.asarray(d65.values)


def spectral_bands(n_bands: int, index) -> list[dict]:
    """``n_bands`` bands of equal weight (xbar + ybar + zbar) D65 over 360-830 nm on the 1 nm
    grid: ``{"lo", "hi", "n", "xyz"}`` with ``n`` the weighted mean of ``index(lambda)`` over
    the band and ``xyz`` the band's CIE weights (integral of cmf D65 over the band / integral
    of ybar D65 over 360-830 nm, so that a white map, G_b = 1 in every band, has Y = 1)."""
    wl, cmfs, s = observer_and_illuminant()
    w = cmfs.sum(1) * s
    # band edges at grid points where the cumulative weight crosses k / n_bands
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]))])
    cuts = np.searchsorted(cum / cum[-1], np.arange(1, n_bands) / n_bands)
    edges = np.unique(np.concatenate([[0], cuts, [len(wl) - 1]]))
    n_l = np.asarray(index(wl), dtype=np.float64)
    norm = np.trapezoid(cmfs[:, 1] * s, wl)
    out = []
    for i0, i1 in zip(edges[:-1], edges[1:], strict=True):
        sl = slice(i0, i1 + 1)
        out.append(
            {
                "lo": float(wl[i0]),
                "hi": float(wl[i1]),
                "n": float(np.trapezoid(n_l[sl] * w[sl], wl[sl]) / np.trapezoid(w[sl], wl[sl])),
                "xyz": np.trapezoid(cmfs[sl] * s[sl, None], wl[sl], axis=0) / norm,
            }
        )
    return out


def band_weights(bands: list[dict], spectrum: np.ndarray) -> np.ndarray:
    """(band, 3) CIE weights of ``bands`` for a white of relative spectrum ``spectrum`` (1 nm,
    360-830 nm), normalised to Y = 1: what :func:`spectral_bands` gives for D65."""
    wl, cmfs, _ = observer_and_illuminant()
    norm = np.trapezoid(cmfs[:, 1] * spectrum, wl)
    out = []
    for b in bands:
        sl = (wl >= b["lo"]) & (wl <= b["hi"])
        out.append(np.trapezoid(cmfs[sl] * spectrum[sl, None], wl[sl], axis=0) / norm)
    return np.array(out)


def upsampling_effect(scene, *, n_bands: int, spp: int, peer_spectrum: np.ndarray, device=None) -> dict:
    """What the white spectrum of a grey map alone does to the dispersive image: our band images
    G_b (the non-dispersive stone at each band's index, polarized, Y of a white-Y map = 1) summed
    once with D65 (ours) and once with ``peer_spectrum`` (indicatrix's spectrum of an RGB
    (1, 1, 1) texel, ``indicatrix_peer --spectrum 1 1 1``): the relative RMSE of linear sRGB
    between the two images.  Both come from the same G_b, so their noise is shared."""
    import warpoptics as wo

    bands = spectral_bands(n_bands, wo.materials.get("diamond").n)
    g = np.stack(
        [
            wo.render(
                scene.with_overrides({"object.0.material": {"cauchy": [b["n"]]}, "render.spp": spp}),
                seed=7,
                device=device,
            ).xyz[..., 1]
            for b in bands
        ]
    )
    _, _, d65 = observer_and_illuminant()
    out = {}
    for name, spec in (("d65", d65), ("indicatrix_white", peer_spectrum)):
        w = band_weights(bands, spec)
        from warpoptics.color import xyz_to_srgb_linear

        out[name] = xyz_to_srgb_linear(np.tensordot(g, w, axes=([0], [0])))
    a, b = out["indicatrix_white"], out["d65"]
    return {
        "bands": n_bands,
        "spp_per_band": spp,
        "rel_rmse_linear_srgb": float(np.sqrt(((a - b) ** 2).mean()) / b.mean()),
        "mean_rel_diff": float(a.mean() / b.mean() - 1.0),
    }


def grey_map(src: str | Path, dst: str | Path, *, blur_deg: float = 0.0) -> Path:
    """The luminance of the RGB lat-long map ``src`` (Rec. 709 / sRGB weights) as a grey map,
    optionally blurred by a Gaussian of ``blur_deg`` degrees (in texel space: periodic in
    azimuth, clamped at the poles) -- softer edges, less noise per sample in both renderers."""
    from scipy.ndimage import gaussian_filter

    from warpoptics.color import SRGB_TO_XYZ
    from warpoptics.film.image import read_image, write_exr

    img, _ = read_image(src)
    y = img[..., :3].astype(np.float64) @ SRGB_TO_XYZ[1]
    if blur_deg > 0:
        sigma = blur_deg / 180.0 * y.shape[0]  # texels (rows span 180 degrees)
        y = gaussian_filter(y, sigma=sigma, mode=("nearest", "wrap"))
    write_exr(dst, np.repeat(y[..., None], 3, -1).astype(np.float32), ["R", "G", "B"])
    return Path(dst)


def reference_scene(map_path, *, width: int, height: int, polarization: bool = True, scene=SCENE):
    """The benchmark scene (dispersive diamond) under the grey map, at ``width x height``."""
    import warpoptics as wo

    return wo.Scene.load(scene).with_overrides(
        {
            "light.0.map": str(map_path),
            "camera.width": int(width),
            "camera.height": int(height),
            "render.polarization": bool(polarization),
        }
    )


def mitsuba_band_images(
    scene,
    bands: list[dict],
    *,
    spp: int,
    seed: int,
    polarized: bool = True,
    env_step: float = 10.0,
    sampler: str = "ldsampler",
) -> np.ndarray:
    """G_b: Mitsuba's image of the stone at each band's index, relative to a white map (band,
    H, W), from ``specfilm`` box-response renders (module docstring).  ``sampler``: Mitsuba's
    (``ldsampler``, low-discrepancy, has the least noise per sample here; passes with different
    ``seed`` are independent)."""
    import mitsuba as mi

    from warpoptics.pipelines import mitsuba_export as mx

    mi.set_variant("scalar_spectral_polarized" if polarized else "scalar_spectral")
    spp = effective_spp(spp, sampler)
    # the exporter wants a clear, isotropic stone: give it the constant-index twin (same mesh);
    # a grey map bakes exactly at any env_step (its spectrum has the XYZ of D65 x g)
    twin = scene.with_overrides(
        {"object.0.material": {"cauchy": [CLEAR_INDEX]}, "object.0.absorption_scale": 0.0}
    )
    cam = twin.camera
    out = np.empty((len(bands), cam.height, cam.width))
    with tempfile.TemporaryDirectory(prefix="fire_reference_") as tmp:
        d = mx.mitsuba_scene_dict(twin, tmp, spp=spp, seed=seed, env_step=env_step, sampler=sampler)
        white_light = dict(d["light"])
        white_light["bitmap"] = mi.Bitmap(np.ones(np.asarray(d["light"]["bitmap"]).shape, dtype=np.float32))
        for i, b in enumerate(bands):
            film = {
                "type": "specfilm",
                "width": cam.width,
                "height": cam.height,
                "rfilter": {"type": "box"},
                "component_format": "float32",
                "band": {
                    "type": "regular",
                    "wavelength_min": b["lo"],
                    "wavelength_max": b["hi"],
                    "values": "1, 1, 1",
                },
            }
            d["object_0"]["bsdf"]["int_ior"] = b["n"]
            d["sensor"]["film"] = film
            d["sensor"]["sampler"]["seed"] = int(seed) * 1000 + i
            img = np.asarray(
                mi.render(mi.load_dict(d), spp=int(spp), seed=int(seed) * 1000 + i), dtype=np.float64
            )
            # the white reference of this film: a white map, no stone, a small film (it is uniform)
            wd = {
                "type": "scene",
                "light": white_light,
                "integrator": {"type": "path", "max_depth": 2},
                "sensor": {**d["sensor"], "film": {**film, "width": 4, "height": 4}},
            }
            white = float(np.asarray(mi.render(mi.load_dict(wd), spp=64), dtype=np.float64).mean())
            out[i] = img[..., 0] / white
    return out


def effective_spp(spp: int, sampler: str) -> int:
    """The sample count Mitsuba renders: its ``ldsampler`` rounds up to a power of 4."""
    if sampler != "ldsampler":
        return int(spp)
    return int(4 ** int(np.ceil(np.log(max(spp, 1)) / np.log(4) - 1e-9)))


def synthesize_rgb(g: np.ndarray, bands: list[dict]) -> np.ndarray:
    """Linear sRGB (H, W, 3) of the band images ``g`` (band, H, W) weighted by the bands' CIE
    weights (no gamut clipping: a linear comparison)."""
    from warpoptics.color import xyz_to_srgb_linear

    xyz = np.tensordot(g, np.stack([b["xyz"] for b in bands]), axes=([0], [0]))
    return xyz_to_srgb_linear(xyz)


def ours_rgb(scene, *, seed: int, device=None) -> np.ndarray:
    """warpoptics' linear sRGB (H, W, 3) of ``scene`` (no gamut clipping)."""
    import warpoptics as wo
    from warpoptics.color import xyz_to_srgb_linear

    return xyz_to_srgb_linear(wo.render(scene, seed=seed, device=device).xyz)


def compare(
    scene,
    *,
    n_bands: int,
    mitsuba_spp: int,
    mitsuba_passes: int = 2,
    ours_passes: int,
    polarized: bool = True,
    device=None,
    twins: tuple[str, ...] = ("clear", "unpolarized"),
) -> dict:
    """Mitsuba's band-by-band reference against our dispersive render of ``scene``: the converged
    relative RMSE of linear sRGB and the checks around it (see the module docstring).
    ``twins`` also compares what must *not* agree: ``"clear"``, our non-dispersive twin (constant
    index, the dispersion removed), and ``"unpolarized"`` (if ``polarized``), our unpolarized
    render."""
    import warpoptics as wo

    mat = wo.materials.get("diamond")
    bands = spectral_bands(n_bands, mat.n)
    res: dict = {
        "width": scene.camera.width,
        "height": scene.camera.height,
        "bands": n_bands,
        "band_edges_nm": [b["lo"] for b in bands] + [bands[-1]["hi"]],
        "band_index": [b["n"] for b in bands],
        "polarized": polarized,
        "mitsuba_spp_per_band_per_pass": effective_spp(mitsuba_spp, "ldsampler"),
    }
    t0 = time.process_time()
    mit = np.stack(
        [
            synthesize_rgb(
                mitsuba_band_images(scene, bands, spp=mitsuba_spp, seed=k, polarized=polarized), bands
            )
            for k in range(mitsuba_passes)
        ]
    )
    res["mitsuba_cpu_seconds"] = time.process_time() - t0
    t0 = time.process_time()
    ours = np.stack([ours_rgb(scene, seed=100 + k, device=device) for k in range(ours_passes)])
    res["ours_cpu_seconds"] = time.process_time() - t0
    res["ours_passes"], res["ours_spp_per_pass"] = ours_passes, scene.render.spp
    res["agreement"] = converged_difference(ours, mit, labels=("ours", "mitsuba"), quantity="rgb")
    res["rel_noise_one_pass"] = {"ours": rel_noise(ours), "mitsuba": rel_noise(mit)}
    # the stone's own pixels: the background (the map seen directly) agrees by construction
    alpha = (
        wo.render(
            scene.with_overrides({"render.spp": 1, "render.adaptive": False}), seed=0, device=device
        ).alpha
        > 0.5
    )
    res["stone_pixels"] = int(alpha.sum())
    res["agreement_stone"] = converged_difference(
        ours[:, alpha], mit[:, alpha], labels=("ours", "mitsuba"), quantity="rgb"
    )
    if "clear" in twins:
        twin = scene.with_overrides({"object.0.material": {"cauchy": [CLEAR_INDEX]}})
        clear = np.stack([ours_rgb(twin, seed=200 + k, device=device) for k in range(ours_passes)])
        res["nondispersive_vs_reference"] = converged_difference(clear, mit, labels=("ours_clear", "mitsuba"))
    if "unpolarized" in twins and polarized:
        unpol = scene.with_overrides({"render.polarization": False})
        up = np.stack([ours_rgb(unpol, seed=300 + k, device=device) for k in range(ours_passes)])
        res["unpolarized_vs_reference"] = converged_difference(up, mit, labels=("ours_unpol", "mitsuba"))
    res["_images"] = {"ours": ours.mean(0), "mitsuba": mit.mean(0)}
    return res


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(SCENE))
    ap.add_argument(
        "--map", default=str(STUDIO_MAP), help="RGB lat-long map whose luminance lights the stone"
    )
    ap.add_argument("--blur", type=float, default=0.0, help="blur the grey map by this many degrees")
    ap.add_argument("--width", type=int, default=256)
    ap.add_argument("--height", type=int, default=256)
    ap.add_argument("--bands", type=int, default=32)
    ap.add_argument("--mitsuba-spp", type=int, default=1024, help="Mitsuba spp per band per pass")
    ap.add_argument("--mitsuba-passes", type=int, default=2)
    ap.add_argument("--ours-spp", type=int, default=64, help="our spp per pass (x the scene's wavelengths)")
    ap.add_argument("--ours-passes", type=int, default=16)
    ap.add_argument("--unpolarized", action="store_true", help="compare unpolarized renders")
    ap.add_argument("--quick", action="store_true", help="a smoke run: 16x16, 6 bands, few samples")
    ap.add_argument(
        "--upsampling-effect",
        metavar="PEER_BIN",
        help="instead: measure what indicatrix's white spectrum (from this indicatrix_peer binary) "
        "changes against D65 (our band images, --bands, --ours-spp per band)",
    )
    ap.add_argument("--json", help="write the results here")
    ap.add_argument("--save", help="write the two mean images to this .npz")
    args = ap.parse_args(argv)
    if args.quick:
        args.width = args.height = 16
        args.bands, args.mitsuba_spp, args.ours_spp, args.ours_passes = 6, 16, 4, 4
    with tempfile.TemporaryDirectory(prefix="fire_reference_map_") as tmp:
        gmap = grey_map(args.map, Path(tmp) / "grey.exr", blur_deg=args.blur)
        scene = reference_scene(
            gmap, width=args.width, height=args.height, polarization=not args.unpolarized, scene=args.scene
        ).with_overrides({"render.spp": args.ours_spp})
        if args.upsampling_effect:
            import subprocess

            out = subprocess.run(
                [args.upsampling_effect, "--spectrum", "1", "1", "1"],
                capture_output=True,
                text=True,
                check=True,
            ).stdout
            spec = np.array([float(line.split()[1]) for line in out.splitlines()])
            res = upsampling_effect(scene, n_bands=args.bands, spp=args.ours_spp, peer_spectrum=spec)
            print(json.dumps(res, indent=2))
            if args.json:
                from warpoptics.atomic import atomic_path

                with atomic_path(args.json) as tmp:
                    Path(tmp).write_text(json.dumps(res, indent=2))
            return 0
        log(
            f"{args.scene} under the grey luminance of {args.map}: {args.width}x{args.height}, "
            f"{args.bands} bands x {args.mitsuba_spp} spp x {args.mitsuba_passes} Mitsuba passes; ours "
            f"{args.ours_passes} passes of {args.ours_spp} spp x {scene.render.wavelengths} wavelengths"
        )
        res = compare(
            scene,
            n_bands=args.bands,
            mitsuba_spp=args.mitsuba_spp,
            mitsuba_passes=args.mitsuba_passes,
            ours_passes=args.ours_passes,
            polarized=not args.unpolarized,
        )
    images = res.pop("_images")
    res["command"] = " ".join(["python", "scripts/bench/fire_reference.py", *(argv or sys.argv[1:])])
    a, s = res["agreement"], res["agreement_stone"]
    print(
        f"ours (dispersive) vs Mitsuba band by band: converged relative RMSE of linear sRGB "
        f"{100 * a['converged_rel_rmse']:.2f} % "
        f"(2-sigma upper {100 * a['converged_rel_rmse_upper_2sigma']:.2f} %; "
        f"raw {100 * a['raw_rel_rmse_of_means']:.2f} %), mean {100 * a['mean_rel_diff']:+.2f} %; "
        f"stone pixels only ({res['stone_pixels']}): {100 * s['converged_rel_rmse']:.2f} % "
        f"(of the stone's mean)"
    )
    for key, label in (
        ("nondispersive_vs_reference", "our clear twin"),
        ("unpolarized_vs_reference", "ours unpol."),
    ):
        if key in res:
            print(f"{label} vs the reference: {100 * res[key]['converged_rel_rmse']:.2f} % (must not agree)")
    if args.json:
        from warpoptics.film.image import atomic_path

        with atomic_path(args.json) as tmp:
            Path(tmp).write_text(json.dumps(res, indent=2, default=lambda x: np.asarray(x).tolist()))
    if args.save:
        np.savez_compressed(args.save, **images)
    return 0


if __name__ == "__main__":
    sys.exit(main())
