"""Optical bench: double refraction in calcite (Guy & Soler 2004, §3.1).

One unpolarized 589.3 nm beam at normal incidence on a 10 mm calcite plate whose optic axis lies
at 45 degrees to the faces leaves as two spots: the ordinary one straight through, the
extraordinary one displaced by the walk-off, thickness x tan(rho), with (Born & Wolf §15.3)

    tan(rho) = (ne^2 - no^2) sin t cos t / (ne^2 cos^2 t + no^2 sin^2 t),   t = 45 deg,

and each spot fully linearly polarized, at right angles to the other (o: perpendicular to the
principal plane x-z, e: in it).  Readout: measured and predicted separation, each spot's power,
degree of polarization and angle.

    python scripts/reproduce/bench_calcite.py -o out/bench_calcite.png
"""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "bench" / "calcite.toml"


def predicted_walkoff(no: float, ne: float, theta_deg: float) -> float:
    """Walk-off angle rho (rad) between wave normal and ray for a wave normal at theta to the axis."""
    t = math.radians(theta_deg)
    return math.atan(
        (ne**2 - no**2) * math.sin(t) * math.cos(t) / (ne**2 * math.cos(t) ** 2 + no**2 * math.sin(t) ** 2)
    )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", required=True, help="PNG image of the screen to write")
    ap.add_argument("--rays", type=int, default=None, help="beam positions (default: the scene's)")
    ap.add_argument("--device", default=None)
    args = ap.parse_args(argv)

    import warpoptics as wo
    from warpoptics.pipelines.bench import bench
    from warpoptics.scene.bench import BenchScene

    scene = BenchScene.load(SCENE)
    over = {"source.rays": args.rays} if args.rays else None
    r = bench(scene, device=args.device, overrides=over)
    ob = scene.objects[0]
    thickness = ob.params["thickness"]
    axis = np.asarray(ob.optic_axis, dtype=float)
    theta = math.degrees(math.acos(abs(axis[2]) / np.linalg.norm(axis)))
    lam = scene.source.lines[0]
    cal = wo.materials.get("calcite")
    no, ne = float(cal.ordinary.n(lam)), float(cal.extraordinary.n(lam))
    rho = predicted_walkoff(no, ne, theta)
    pred = thickness * abs(math.tan(rho))
    s1, s2 = r.spots(0, count=2, radius=0.25)
    sep = math.hypot(s1["u"] - s2["u"], s1["v"] - s2["v"])
    print(f"calcite at {lam} nm: no = {no:.5f}, ne = {ne:.5f}; axis at {theta:.2f} deg to the normal")
    print(f"walk-off rho = {math.degrees(rho):.4f} deg; predicted separation = {pred:.5f} mm")
    print(f"measured separation = {sep:.5f} mm (error {100 * (sep / pred - 1):+.3f} %)")
    for name, s in (("spot 1", s1), ("spot 2", s2)):
        print(
            f"{name}: u = {s['u']:+.5f} mm, v = {s['v']:+.5f} mm, power = {s['power']:.4f} W, "
            f"DoP = {s['dop']:.6f}, angle = {s['angle']:+.3f} deg"
        )
    d_angle = abs((s1["angle"] - s2["angle"] + 90.0) % 180.0 - 90.0)
    print(f"angle between the two polarizations = {d_angle:.3f} deg")
    lg = r.ledger
    print("ledger (W): " + ", ".join(f"{k} {v:.6f}" for k, v in lg.items()))
    print(f"closure (screen + absorbed + escaped) / emitted - 1 = {r.balance():+.2e}")
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    r.save(args.output)
    exr = os.path.splitext(args.output)[0] + ".exr"
    r.save(exr)
    print(f"wrote {args.output} and {exr}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
