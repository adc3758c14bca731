"""GemCAD tier angles as scene keys, sweep axes and optimizer parameters (geometry.gemcad.recut_tiers).

The corpus design is SRB.asc (GemCad for Windows' standard round brilliant: tier "2" the eight
pavilion mains at 41.5 deg, meeting at the culet).  The checks read the angles back from the
built mesh's facet planes (an independent path: the half-space intersection, scaled to mm) and
compare the re-solved height with the closed form of the centre-point rule: mains through the
culet point (0, 0, -z_c) at angle t have the height z_c cos t.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from _helpers import ROOT

from warpoptics.errors import InputError
from warpoptics.geometry import gemcad
from warpoptics.geometry.cuts import convex_from_planes
from warpoptics.grading.performance import PROTOCOL
from warpoptics.pipelines.objects import build_objects
from warpoptics.scene import Scene
from warpoptics.sweep.grading import protocol_scene, protocol_sweep
from warpoptics.sweep.optimize import CutOptimizer, Parameter
from warpoptics.sweep.results import read_results
from warpoptics.sweep.runner import SweepRunner
from warpoptics.sweep.spec import Axis

SRB = ROOT / "tests" / "data" / "gemcad" / "SRB.asc"
STONE = {"shape": "gemcad", "path": str(SRB), "diameter": 6.5}
TINY = dataclasses.replace(PROTOCOL, tilts=(0.0,), azimuths=(0.0,), size=8, wavelengths=1)


def _tier_angles(mesh, name: str) -> list[float]:
    """Angles (deg from the girdle plane) of the mesh facets of tier ``name`` (facet names are
    '<tier name> @<index>')."""
    return [
        math.degrees(math.acos(min(1.0, abs(float(p[2])))))
        for p, n in zip(mesh.metadata["planes"], mesh.metadata["facet_names"], strict=True)
        if n.startswith(f"{name} @")
    ]


def _mesh(scene: Scene):
    return build_objects(scene.objects, file=scene.path).meshes[0][0]


def test_recut_rule_closed_form_and_read_back():
    d = gemcad.read_design(SRB)
    mains = d.tiers[2]
    z_c = mains.distance / math.cos(math.radians(abs(mains.angle)))  # the culet depth, design units
    culet = convex_from_planes(*d.planes()[:2]).vertices[:, 2].min()
    assert culet == pytest.approx(-z_c, abs=1e-7)
    for t in (40.0, 41.5, 43.0, 44.5):
        r = gemcad.recut_tiers(d, {"2": t})
        assert r.tiers[2].angle == -t and r.tiers[2].indices == mains.indices
        assert r.tiers[2].distance == pytest.approx(z_c * math.cos(math.radians(t)), rel=1e-9)
        # the other tiers are not re-cut, and the culet (the mains' meet point) stays put
        assert [x for i, x in enumerate(r.tiers) if i != 2] == [x for i, x in enumerate(d.tiers) if i != 2]
        assert convex_from_planes(*r.planes()[:2]).vertices[:, 2].min() == pytest.approx(-z_c, abs=1e-7)
        m = gemcad.design_to_mesh(r, 6.5)
        got = _tier_angles(m, "2")
        assert len(got) == 8 and np.allclose(got, t, atol=1e-6)
    # by position (#3 is the third 'a' record: the same tier) and unchanged at its own angle
    assert gemcad.recut_tiers(d, {"#3": 43.0}).tiers[2] == gemcad.recut_tiers(d, {"2": 43.0}).tiers[2]
    assert gemcad.recut_tiers(d, {"2": 41.5}).tiers[2].distance == pytest.approx(mains.distance, abs=1e-8)


def test_sweep_axis_over_a_tier_angle(tmp_path):
    angles = (40.0, 42.0, 44.0)
    sweep = protocol_sweep(
        STONE, TINY, axes=[Axis("mains", angles, path="object.0.tier_angles.2")], fire=False, frame_mm=6.5
    )
    base = protocol_scene(STONE, TINY, frame_mm=6.5)
    depths = []
    for job, t in zip(sweep.jobs(), angles, strict=True):
        m = _mesh(base.with_overrides(job.overrides))
        got = _tier_angles(m, "2")
        assert len(got) == 8 and np.allclose(got, t, atol=1e-6), (t, got)
        assert np.allclose(_tier_angles(m, "1"), 42.5, atol=1e-6)  # the lower halves keep theirs
        depths.append(m.metadata["proportions"].total_depth)
    assert depths[2] > depths[1]  # steeper mains through the same culet: a deeper stone
    res = SweepRunner(sweep, tmp_path / "sweep", progress=False).run()
    assert [float(r["mains"]) for r in res.rows] == list(angles)
    lr = [float(r["light_return"]) for r in res.rows]
    assert all(0 < x < 1 for x in lr) and len(set(lr)) == 3  # three different stones rendered


def test_optimizer_over_a_tier_angle(tmp_path):
    opt = CutOptimizer(
        STONE,
        [Parameter("mains", "object.0.tier_angles.2", 40.0, 44.0, 43.0)],
        tmp_path / "opt",
        protocol=TINY,
        budget=4,
        popsize=4,
        frame_mm=6.5,
    )
    r = opt.run()
    _h, rows = read_results(tmp_path / "opt" / "journal.csv")
    assert r["evaluations"] == 4 and len({x["mains"] for x in rows}) == 4
    best = float(r["best"]["values"]["mains"])
    # best.asc is the re-cut design: its tier '2' at the best angle, the other tiers as in SRB
    out = gemcad.read_design(tmp_path / "opt" / "best.asc")
    src = gemcad.read_design(SRB)
    assert out.tiers[2].angle == pytest.approx(-best, abs=1e-6)
    assert [t.angle for i, t in enumerate(out.tiers) if i != 2] == [
        t.angle for i, t in enumerate(src.tiers) if i != 2
    ]


@pytest.mark.parametrize(
    "angles, field, words",
    [
        ({"Z": 41.0}, "object.0.tier_angles.Z", "no such tier"),
        ({"#9": 41.0}, "object.0.tier_angles.#9", "no such tier"),
        ({"2": 95.0}, "object.0.tier_angles.2", "(0, 90)"),
        ({"A": -30.0}, "object.0.tier_angles.A", "crown angle"),
        ({"T": 3.0}, "object.0.tier_angles.T", "table"),
        ({"G": 80.0}, "object.0.tier_angles.G", "girdle"),
        ({"2": "steep"}, "object.0.tier_angles.2", "number"),
        ({"2": 41.0, "#3": 42.0}, "object.0.tier_angles.#3", "same tier"),
        ({"B": 5.0}, "object.0.tier_angles.B", "cut away"),
        (41.0, "object.0.tier_angles", "table of tier"),
    ],
)
def test_bad_tier_angles_one_line_error(angles, field, words):
    data = {
        "camera": {"position": [0, 0, 50], "look_at": [0, 0, 0], "up": [0, 1, 0], "width": 8, "height": 8},
        "object": [{**STONE, "tier_angles": angles}],
    }
    with pytest.raises(InputError) as ei:
        _mesh(Scene.from_dict(data, path="scene.toml"))  # a bad key at load, a cut-away tier at build
    msg = str(ei.value)
    assert "\n" not in msg and field in msg and words in msg and "scene.toml" in msg, msg


def test_grade_optimize_cli_tier_parameter_errors(tmp_path, capsys):
    from warpoptics.cli import main

    for param, words in (("tier:Q=40:44:43", "no such tier"), ("tier:2=40:95:43", "(0, 90)")):
        code = main(["grade", "optimize", str(SRB), "--param", param, "-o", str(tmp_path / "o"), "--quiet"])
        err = [ln for ln in capsys.readouterr().err.splitlines() if "CUDA" not in ln]
        assert code == 2 and len(err) == 1, err
        assert "object.0.tier_angles." in err[0] and words in err[0], err
    assert not (tmp_path / "o" / "journal.csv").exists()  # refused before the search began
