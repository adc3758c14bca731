"""The newer commands (grade, chart, microscope) at and past their limits: every flag checked
before the first render, one clear line naming the flag (or the file and field) and the value,
exit status 2, no traceback; and the journals and tables they read back are checked too."""

from __future__ import annotations

import shutil

import pytest

from warpoptics import cli


def _run(argv, capsys) -> tuple[int, str]:
    """(exit status, stderr) of ``warpoptics ARGV`` run in-process (argparse exits itself)."""
    try:
        rc = cli.main([str(a) for a in argv])
    except SystemExit as exc:  # argparse refuses a flag before the command runs
        rc = int(exc.code or 0)
    return rc, capsys.readouterr().err


def _refused(argv, capsys, *needles) -> str:
    rc, err = _run(argv, capsys)
    assert rc == 2, err
    assert "Traceback" not in err
    last = err.strip().splitlines()[-1]
    for n in needles:
        assert n in last, err
    assert len(last) < 1200, last  # one readable line (a list of allowed names at most)
    return last


# ---- flags refused by argparse before anything is read or rendered ------------------------------

FLAG_CASES = [
    (["grade", "aset", "round_brilliant", "--wavelengths", "0"], ["--wavelengths", "0"]),
    (["grade", "aset", "round_brilliant", "--lighting", "moon"], ["--lighting"]),
    (["grade", "idealscope", "round_brilliant", "--lighting", "iso"], ["--lighting"]),
    (["grade", "hearts", "round_brilliant", "--lighting", "iso"], ["--lighting"]),
    (["grade", "idealscope", "round_brilliant", "--head", "nan"], ["--head"]),
    (["grade", "aset", "round_brilliant", "--head", "nan"], ["--head", "finite"]),
    (["grade", "aset", "round_brilliant", "--head", "0"], ["--head", "0"]),
    (["grade", "aset", "round_brilliant", "--head", "45"], ["--head", "< 45"]),
    (["grade", "aset", "round_brilliant", "--diameter", "0"], ["--diameter", "0"]),
    (["grade", "map", "round_brilliant", "--lighting", "moon"], ["--lighting", "'moon'", "iso"]),
    (["grade", "map", "round_brilliant", "--size", "100000"], ["--size", "100000"]),
    (["grade", "map", "round_brilliant", "--tilt", "inf"], ["--tilt", "finite"]),
    (["grade", "tilt", "round_brilliant", "--fps", "0"], ["--fps", "0"]),
    (["grade", "tilt", "round_brilliant", "--fps", "nan"], ["--fps", "finite"]),
    (["grade", "tilt", "round_brilliant", "--workers", "0"], ["--workers"]),
    (["grade", "optimize", "round_brilliant", "--budget", "-1"], ["--budget"]),
    (["grade", "optimize", "round_brilliant", "--min-weight", "1"], ["--min-weight", "< 1"]),
    (["grade", "retarget", "x.asc", "--index", "nan"], ["--index"]),
]


@pytest.mark.parametrize(
    ("argv", "needles"), FLAG_CASES, ids=[" ".join(c[0][1:2] + c[0][3:]) for c in FLAG_CASES]
)
def test_grade_flags_refused_before_any_work(tmp_path, capsys, argv, needles):
    _refused([*argv, "-o", tmp_path / "out.png"], capsys, *needles)
    assert list(tmp_path.iterdir()) == []


def test_flag_type_echoes_no_long_value():
    import argparse

    from warpoptics import validate as val

    parse = val.flag(float, lo=0.0, lo_open=True, hi=10.0)
    assert parse("2.5") == 2.5
    for bad in ("0", "11", "nan", "-inf", "abc", "9" * 10_000):
        with pytest.raises(argparse.ArgumentTypeError) as exc:
            parse(bad)
        assert len(str(exc.value)) < 120


def test_input_error_caps_the_value_it_echoes():
    from warpoptics.errors import InputError

    text = str(InputError("too many", field="tilts", value=list(range(900_001))))
    assert len(text) < 300 and "characters" in text and text.startswith("tilts = [0, 1, 2")


def test_tilt_list_too_long_says_the_count(tmp_path, capsys):
    last = _refused(
        ["grade", "tilt", "round_brilliant", "--tilts", "0:90:0.0001", "-o", tmp_path / "t"],
        capsys,
        "--tilts",
        "900,001 values",
    )
    assert len(last) < 200


def test_grade_hearts_of_a_cube_needs_no_diameter(tmp_path):
    """A cut without a girdle diameter (a cube) is framed by its own extent, not given a
    ``diameter`` key the user never set."""
    import argparse

    from warpoptics.commands.grade import stone_from_args

    args = argparse.Namespace(stone="cube", diameter=None, material=None, set=["size=3"])
    stone, frame = stone_from_args(args)
    assert "diameter" not in stone and frame == pytest.approx(3.0)
    args = argparse.Namespace(stone="round_brilliant", diameter=None, material=None, set=None)
    assert stone_from_args(args) == ({"shape": "round_brilliant", "diameter": 6.5}, None)


# ---- the optimizer: budget, impossible constraints, journals --------------------------------------

_OPT = [
    "grade",
    "optimize",
    "round_brilliant",
    "--param",
    "pavilion_angle=38:44",
    "--size",
    "8",
    "--wavelengths",
    "1",
    "--protocol-tilts",
    "0",
    "--protocol-azimuths",
    "0",
    "--quiet",
]


def test_optimize_budget_below_one_generation(tmp_path, capsys):
    _refused([*_OPT, "--budget", "2", "-o", tmp_path / "o"], capsys, "budget = 2", "one generation of 4")


@pytest.mark.parametrize("depth", ["0:0.1", "5:6"])
def test_optimize_impossible_depth_says_what_was_measured(tmp_path, capsys, depth):
    last = _refused([*_OPT, "--budget", "4", "--depth", depth, "-o", tmp_path / "o"], capsys, "constraints")
    assert "measured: depth 0.5" in last and "widen" in last


@pytest.fixture(scope="module")
def journal_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("opt") / "o"
    assert cli.main([*_OPT, "--budget", "4", "-o", str(out)]) == 0
    return out


def _copy(journal_run, tmp_path):
    dst = tmp_path / "o"
    shutil.copytree(journal_run, dst)
    return dst


def test_optimize_resume_refuses_an_edited_objective(journal_run, tmp_path, capsys):
    out = _copy(journal_run, tmp_path)
    lines = (out / "journal.csv").read_text().splitlines(keepends=True)
    head = lines[0].rstrip("\n").split(",")
    row = lines[1].rstrip("\n").split(",")
    row[head.index("objective")] = "1e308"
    lines[1] = ",".join(row) + "\n"
    (out / "journal.csv").write_text("".join(lines))
    last = _refused(
        [*_OPT, "--budget", "4", "--resume", "-o", out], capsys, "journal.csv", "objective = '1e308'"
    )
    assert "edited or damaged" in last


def test_optimize_resume_refuses_a_non_finite_metric(journal_run, tmp_path, capsys):
    out = _copy(journal_run, tmp_path)
    lines = (out / "journal.csv").read_text().splitlines(keepends=True)
    head = lines[0].rstrip("\n").split(",")
    row = lines[1].rstrip("\n").split(",")
    row[head.index("light_return")] = "inf"
    lines[1] = ",".join(row) + "\n"
    (out / "journal.csv").write_text("".join(lines))
    _refused([*_OPT, "--budget", "4", "--resume", "-o", out], capsys, "journal.csv", "light_return")


@pytest.mark.parametrize("garbage", [b'\x00\xff"' + b"z" * 200_000 + b"\n", b'"\r\x00junk\n'])
def test_optimize_resume_on_garbage_bytes_names_the_file(journal_run, tmp_path, capsys, garbage):
    out = _copy(journal_run, tmp_path)
    with open(out / "journal.csv", "ab") as f:
        f.write(garbage)
    rc, err = _run([*_OPT, "--budget", "4", "--resume", "-o", out], capsys)
    assert "Traceback" not in err
    if rc != 0:  # a torn line of the wrong width is dropped; one the csv module cannot read is refused
        assert rc == 2 and "journal.csv" in err and "not a results table" in err, err


def test_optimize_resume_of_an_intact_journal_renders_nothing(journal_run, tmp_path, capsys):
    out = _copy(journal_run, tmp_path)
    before = (out / "journal.csv").read_text()
    rc = cli.main([*_OPT, "--budget", "4", "--resume", "-o", str(out)])
    assert rc == 0, capsys.readouterr().err
    assert (out / "journal.csv").read_text() == before  # every candidate came from the journal


# ---- chart: the interference colour of a thick plate, the chart's limits ---------------------------

CHART_CASES = [
    (["chart", "michel-levy", "--max-thickness", "-5"], ["--max-thickness", "-5"]),
    (["chart", "michel-levy", "--max-retardation", "1e9"], ["--max-retardation", "1e9", "100000"]),
    (["chart", "michel-levy", "--max-retardation", "nan"], ["--max-retardation", "finite"]),
    (["chart", "conoscope", "--thickness", "0.1", "--wavelength", "100"], ["--wavelength", ">= 360"]),
    (["chart", "conoscope", "--thickness", "-1"], ["--thickness", "-1", ">= 0"]),
    (["chart", "conoscope", "--thickness", "0.1", "--na", "1.5"], ["--na", "1.5"]),
    (["chart", "conoscope", "--thickness", "0.1", "--size", "0"], ["--size"]),
    (["chart", "colour", "--thickness", "inf"], ["--thickness", "finite"]),
    (["chart", "colour", "--thickness", "0.1", "--axis", "0", "nan", "1"], ["--axis"]),
]


@pytest.mark.parametrize(("argv", "needles"), CHART_CASES, ids=[" ".join(c[0][1:]) for c in CHART_CASES])
def test_chart_flags_refused_before_any_work(tmp_path, capsys, argv, needles):
    _refused([*argv, "-o", tmp_path / "chart.png"], capsys, *needles)
    assert list(tmp_path.iterdir()) == []


def test_conoscope_and_microscope_scenes_share_the_wavelength_bound():
    from warpoptics import spectra
    from warpoptics.commands import chart

    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices["chart"]
    wl = next(a for a in sub._actions if a.dest == "wavelength")
    assert wl.type(str(spectra.LAMBDA_MIN)) == spectra.LAMBDA_MIN
    assert chart.LAMBDA_MIN is spectra.LAMBDA_MIN


def _dense_quartz_lab(thickness_mm: float):
    """CIELAB (D65) of a quartz plate (optic axis in the plate at 45 degrees, in air) between
    crossed polarizers, from colour-science's sd_to_XYZ on a 0.01 nm grid: each wave crosses two
    faces (Fresnel amplitude t = 4n / (1 + n)^2 at normal incidence), so I = 1/4 (t_o^2 + t_e^2 -
    2 t_o t_e cos delta), delta = 2 pi d (n_e - n_o) / lambda.  ``thickness_mm=None``: the
    fringe-free limit (cos delta averaged to 0)."""
    colour = pytest.importorskip("colour")
    import numpy as np

    import warpoptics as wo

    quartz = wo.materials.get("quartz")
    shape = colour.SpectralShape(360.0, 830.0, 0.01)
    lam = np.asarray(shape.wavelengths, dtype=np.float64)
    lo, hi = quartz.wavelength_range_nm
    n = np.asarray(quartz.n(np.clip(lam, lo, hi)), dtype=np.float64)
    n_o, n_e = n[:, 0], n[:, 1]
    t_o, t_e = 4 * n_o / (1 + n_o) ** 2, 4 * n_e / (1 + n_e) ** 2
    cos_d = 0.0 if thickness_mm is None else np.cos(2 * np.pi * thickness_mm * 1e6 * (n_e - n_o) / lam)
    t = 0.25 * (t_o**2 + t_e**2 - 2 * t_o * t_e * cos_d)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape)
    d65 = colour.SDS_ILLUMINANTS["D65"].copy().align(shape)
    xyz = colour.sd_to_XYZ(colour.SpectralDistribution(t, shape), cmfs, d65, method="Integration") / 100.0
    white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    return colour.XYZ_to_Lab(xyz, white), colour


@pytest.mark.parametrize("thickness_mm", [3.0, 10.0])
def test_thick_plate_colour_matches_a_dense_integration(thickness_mm):
    """3 mm and 10 mm of quartz: fringes 4.7 and 1.4 nm apart at 360 nm, finer than the 5 nm
    grid, used to alias into a = -1.7, b = 3.2 and a = 4.8, b = 2.1; now within 0.2 CIEDE2000
    of the dense integral (both nearly neutral)."""
    from warpoptics import materials
    from warpoptics.pipelines import microscope as ms

    ref, colour = _dense_quartz_lab(thickness_mm)
    ic = ms.interference_colour(materials.get("quartz"), thickness_mm)
    assert colour.delta_E(ref, ic.lab, method="CIE 2000") < 0.2, (ref, ic.lab)
    assert abs(ic.lab[1]) < 0.5 and abs(ic.lab[2]) < 0.5


def test_a_kilometre_plate_is_neutral():
    """1 km: the fringes (1e-5 nm apart) average away; the colour is that of the o and e powers
    added (within 0.1 CIEDE2000), neutral to |a*|, |b*| < 0.25, and the grid stays bounded."""
    from warpoptics import materials
    from warpoptics.pipelines import microscope as ms

    ref, colour = _dense_quartz_lab(None)
    ic = ms.interference_colour(materials.get("quartz"), 1.0e6)
    assert ic.wavelength_nm.size <= ms.MAX_COLOUR_SAMPLES
    assert colour.delta_E(ref, ic.lab, method="CIE 2000") < 0.1, (ref, ic.lab)
    assert abs(ic.lab[1]) < 0.25 and abs(ic.lab[2]) < 0.25


def test_thin_plate_colour_unchanged_by_the_band_average():
    """A 30 um section: fringes far wider than the grid; the band average changes its colour by
    less than 0.05 CIEDE2000 from the point samples."""
    colour = pytest.importorskip("colour")
    import numpy as np

    from warpoptics import materials, spectra
    from warpoptics.color import xyz_to_lab
    from warpoptics.pipelines import microscope as ms

    ic = ms.interference_colour(materials.get("quartz"), 0.03)
    lam = ic.wavelength_nm
    point = xyz_to_lab(spectra.spectrum_to_xyz(lam, ic.transmission * spectra.illuminant("D65", lam)))
    assert colour.delta_E(point, ic.lab, method="CIE 2000") < 0.05
    assert np.all(np.abs(ic.band_transmission - ic.transmission) < 0.01)


def test_michel_levy_high_orders_are_grey(tmp_path):
    import numpy as np

    from warpoptics.pipelines import microscope as ms

    chart = ms.michel_levy_chart(max_retardation_nm=1.0e5, columns=41)
    far = chart.srgb[chart.retardation_nm > 2.0e4]
    assert np.ptp(far, axis=-1).max() < 0.02  # R = G = B: no aliased colours
    with pytest.raises(ms.InputError, match="max_retardation_nm"):
        ms.michel_levy_chart(max_retardation_nm=1.0e9)


# ---- microscope: thin sections at their limits ---------------------------------------------------


def test_voronoi_grain_map_is_the_nearest_centre():
    """The KD-tree grain map (O(P log G), where 4096 x 4096 px of 4096 grains once took > 120 s
    and 2.5 GB by brute force) is the brute-force nearest centre."""
    import numpy as np

    from warpoptics.pipelines import microscope as ms

    grain, centres = ms.voronoi_grains(300, 3, 64, 2.0, 30.0)
    c = ((np.arange(64) + 0.5) / 64 - 0.5) * 2.0
    xx, yy = np.meshgrid(c, -c)
    p = np.stack([xx.ravel(), yy.ravel()], axis=-1) @ ms.stage_turn(-30.0)[:2, :2].T
    brute = np.argmin(((p[:, None, :] - centres[None]) ** 2).sum(-1), axis=1).reshape(64, 64)
    assert np.array_equal(grain, brute)


@pytest.mark.parametrize("material", ["quartz", "tanzanite"])
def test_thin_section_grains_in_one_launch_are_each_plates_colour(material):
    """All grains at once (a crystal frame per direction in the polariscope stage) give each
    grain the colour of :func:`interference_colour` of that grain alone."""
    import numpy as np

    from warpoptics import materials
    from warpoptics.pipelines import microscope as ms
    from warpoptics.scene.microscope import MicroscopeScene

    data = {
        "microscope": {
            "mode": "orthoscopic",
            "polarizer": 0.0,
            "analyzer": 90.0,
            "size": 16,
            "mounting_index": 1.54,
        },
        "sample": {
            "kind": "thin_section",
            "material": material,
            "thickness_mm": 0.03,
            "grains": 6,
            "seed": 2,
        },
    }
    view = ms.microscope_view(MicroscopeScene.from_dict(data))
    mat = materials.get(material)
    for k, axes in enumerate(view.crystal_axes):
        kw = {"crystal_axes": axes} if material == "tanzanite" else {"optic_axis": tuple(axes[2])}
        one = ms.interference_colour(mat, 0.03, n_ambient=1.54, **kw)
        np.testing.assert_allclose(view.grain_xyz[k], one.xyz, rtol=1e-5, atol=1e-7)


def test_microscope_view_refuses_what_memory_cannot_hold():
    from warpoptics.errors import InputError
    from warpoptics.pipelines import microscope as ms

    need = ms.check_microscope_memory(4096, available=2**40)
    assert need == 4096 * 4096 * ms.MICROSCOPE_BYTES_PER_PIXEL
    with pytest.raises(InputError, match=r"microscope.size = 4096: the view would need about 2.8 GiB"):
        ms.check_microscope_memory(4096, available=2**30)


@pytest.mark.parametrize(
    ("flags", "needles"),
    [(["--size", "5000"], ["--size", "5000", "<= 4096"]), (["--stage", "nan"], ["--stage", "finite"])],
)
def test_microscope_flags_refused_before_any_work(tmp_path, capsys, flags, needles):
    from _helpers import ROOT

    scene = ROOT / "scenes" / "microscope" / "quartz_thin_section.toml"
    _refused(["microscope", scene, "-o", tmp_path / "m.png", *flags], capsys, *needles)
    assert list(tmp_path.iterdir()) == []


# ---- GemCAD designs: facets that do not close, repeated facets -------------------------------------

_OCTAHEDRON_CROWN = "GemCad 4.41\ng 96 48.0\ny 4 n\nI 1.54\nH open design\na 54.74 0.68041 0 72 48 24\n"


def test_gemcad_facets_that_do_not_close_say_so_and_name_the_tiers(tmp_path, capsys):
    """A crown and a girdle without a pavilion: a prism open downward, once reported as an
    "object size 5.2e16 mm ... below 0.1 um" (the unbounded solid Qhull closed far away)."""
    design = tmp_path / "open.asc"
    design.write_text(_OCTAHEDRON_CROWN + "a 90 1 0 72 48 24\n")
    last = _refused(["cut", design, "-o", tmp_path / "o.ply"], capsys, "open.asc", "do not close")
    assert "open toward -z (down)" in last
    assert "tier 1 at 54.74 deg (crown" in last and "tier 2 at 90 deg (girdle" in last
    assert "object size" not in last


def test_open_direction_of_planes():
    import numpy as np

    from warpoptics.geometry.cuts import open_direction

    cube = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=float)
    assert open_direction(cube) is None
    v = open_direction(cube[[0, 1, 2, 3, 4]])  # no bottom
    np.testing.assert_allclose(v, [0.0, 0.0, -1.0])
    v = open_direction(cube[[1, 2, 3, 4, 5]])  # no +x face
    assert v is not None and v[0] > 0.99


def test_gemcad_repeated_facets_warn_once_each_on_one_line(tmp_path, capsys):
    design = tmp_path / "dup.asc"
    design.write_text(_OCTAHEDRON_CROWN + "a -54.74 0.68041 0 24 48 72\na -54.74 0.68041 0 24\n")
    rc = cli.main(["grade", "aset", str(design), "-o", str(tmp_path / "a.png"), "--size", "8"])
    err = capsys.readouterr().err
    assert rc == 0, err
    lines = err.strip().splitlines()
    # two repeated facets (@0 and @24); the design is read twice, each warning is shown once
    assert len(lines) == 2 and len(set(lines)) == 2, err
    for ln in lines:
        assert ln.startswith("warpoptics grade: warning: ") and "repeats the plane of line 7" in ln
    assert "UserWarning" not in err


# ---- outputs that cannot be written: said before the work, and said right ---------------------------


def _read_only(monkeypatch):
    """Make every temporary file fail as on a read-only file system that reports no free space
    (as a full read-only mount does)."""
    import errno
    import os
    import shutil
    import tempfile

    def refuse(*a, **k):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    monkeypatch.setattr(shutil, "disk_usage", lambda p: shutil._ntuple_diskusage(1 << 20, 1 << 20, 0))


@pytest.mark.parametrize(
    "argv",
    [
        ["grade", "aset", "round_brilliant", "--size", "8", "-o", "{tmp}/a.png"],
        ["grade", "tilt", "round_brilliant", "--size", "8", "-o", "{tmp}/tilt"],
        ["chart", "michel-levy", "-o", "{tmp}/chart.png"],
        ["microscope", "{scene}", "--size", "16", "-o", "{tmp}/m.png"],
    ],
    ids=["grade aset", "grade tilt", "chart", "microscope"],
)
def test_read_only_output_is_said_before_any_work(tmp_path, capsys, monkeypatch, argv):
    from _helpers import ROOT

    import warpoptics.pipelines.render as render_pipeline

    scene = ROOT / "scenes" / "microscope" / "quartz_thin_section.toml"
    _read_only(monkeypatch)
    monkeypatch.setattr(render_pipeline, "render", lambda *a, **k: pytest.fail("rendered before the check"))
    args = [a.format(tmp=tmp_path, scene=scene) for a in argv]
    last = _refused(args, capsys, "Read-only file system", "(-o)")
    assert "disk is full" not in last


def test_library_stderr_is_captured_not_printed(capfd):
    import os

    from warpoptics.film.image import _captured_stderr

    with _captured_stderr() as said:
        os.write(2, b"libpng error: Write Error\n")
    assert "libpng error: Write Error" in said()
    assert "libpng" not in capfd.readouterr().err


# ---- glTF optics and colour-change spectra: the file, the field, the value -------------------------


@pytest.mark.parametrize(
    ("ior", "needle"), [('"NaN"', "must be a number"), ("NaN", "finite"), ("0.5", "out of range")]
)
def test_gltf_bad_ior_is_refused_naming_it(tmp_path, ior, needle):
    import json

    import warpoptics as wo
    from warpoptics.errors import InputError
    from warpoptics.geometry import gltf
    from warpoptics.materials import Cauchy

    path = gltf.export_gltf(tmp_path / "g.gltf", wo.cuts.round_brilliant(diameter=3.0), Cauchy(1.8))
    tree = json.loads(path.read_text())
    tree["materials"][0]["extensions"]["KHR_materials_ior"]["ior"] = "__IOR__"
    path.write_text(json.dumps(tree).replace('"__IOR__"', ior))
    with pytest.raises(InputError) as exc:
        gltf.import_gltf(path)
    text = str(exc.value)
    assert "g.gltf" in text and "KHR_materials_ior.ior" in text and needle in text, text


@pytest.mark.parametrize(
    ("csv", "needles"),
    [
        ("400,0.5\n", ["rows = 1", "two rows"]),
        ("400,0.5\n500,nan\n", ["value (column 2) = nan", "row 2"]),
        ("400,0.5\n500,-0.1\n", ["value (column 2) = -0.1", "row 2"]),
        ("500,0.5\n400,0.3\n", ["wavelength (column 1) = 400.0", "must increase"]),
        ("400\n500\n", ["columns = 1"]),
        ("a,b\n", ["not a CSV of numbers"]),
        ("", ["holds no rows"]),
    ],
    ids=["one row", "nan", "negative", "decreasing", "one column", "text", "empty"],
)
def test_colorchange_csv_errors_name_the_file_and_row(tmp_path, capsys, csv, needles):
    f = tmp_path / "spec.csv"
    f.write_text(csv)
    last = _refused(["colorchange", f], capsys, "spec.csv", *needles)
    assert "shape" not in last and "(2,)" not in last


# ---- sweeps: a scene that is the sweep itself, a tilt object past the scene's objects ----------------


def test_sweep_whose_scene_is_itself_names_the_file(tmp_path, capsys):
    sweep = tmp_path / "self.toml"
    sweep.write_text('scene = "self.toml"\n[[axis]]\nname = "spp"\npath = "render.spp"\nvalues = [1]\n')
    last = _refused(["sweep", sweep, "-o", tmp_path / "out"], capsys, "self.toml", "scene = 'self.toml'")
    assert "this sweep file itself" in last


def test_sweep_tilt_object_past_the_objects_is_refused_before_rendering(tmp_path, capsys):
    from _helpers import ROOT

    sweep = tmp_path / "tilt.toml"
    scene = (ROOT / "scenes" / "diamond.toml").as_posix()
    sweep.write_text(
        f'scene = "{scene}"\n[[axis]]\nname = "spp"\npath = "render.spp"\nvalues = [1]\n'
        '[[view]]\nname = "v"\nmetrics = ["scintillation"]\ntilt_object = 5\n'
    )
    last = _refused(["sweep", sweep, "-o", tmp_path / "out"], capsys, "tilt.toml", "view.v.tilt_object = 5")
    assert "has 1 object" in last
    assert not (tmp_path / "out" / "results.csv").exists()


@pytest.mark.parametrize(
    ("argv", "needles"),
    [
        (["chart", "colour", "--material", "nonsense", "--thickness", "1"], ["--material = 'nonsense'"]),
        (["chart", "michel-levy", "--illuminant", "X9", "-o", "{tmp}/c.png"], ["--illuminant = 'X9'"]),
    ],
    ids=["material", "illuminant"],
)
def test_chart_names_its_flags(tmp_path, capsys, argv, needles):
    _refused([a.format(tmp=tmp_path) for a in argv], capsys, *needles)
    assert list(tmp_path.iterdir()) == []


def test_white_light_conoscope_of_a_thick_plate_does_not_alias():
    """A 1 mm calcite plate cut across its axis, NA 0.5, white light: on the default 10 nm grid
    the figure's colours match a 0.1 nm grid (fringes resolved) within 1.5 CIEDE2000 for 95 % of
    the pupil and 3 at most (point samples: 17.8 and 23.5, the outer isochromes aliased)."""
    colour = pytest.importorskip("colour")
    import numpy as np

    from warpoptics import materials
    from warpoptics.color import xyz_to_lab
    from warpoptics.pipelines import microscope as ms

    calcite = materials.get("calcite")
    coarse = ms.conoscopic_figure(calcite, 1.0, size=48, wavelength_nm=None, exposure=1.0)
    fine = ms.conoscopic_figure(calcite, 1.0, size=48, wavelength_nm=None, exposure=1.0, step_nm=0.1)
    p = coarse.pupil
    de = colour.delta_E(xyz_to_lab(coarse.xyz[p]), xyz_to_lab(fine.xyz[p]), method="CIE 2000")
    assert np.percentile(de, 95) < 1.5 and de.max() < 3.0, (np.percentile(de, 95), de.max())


@pytest.mark.parametrize(("name", "axis"), [("calcite", (1.0, 0.0, 1.0)), ("calcite", (0.0, 0.0, 1.0))])
def test_retardation_of_tilted_waves_is_the_stages_fringe_rate(name, axis):
    """The band average's phase slope for a tilted wave (index surfaces, Snell's transverse
    vector) counts the fringes the polariscope stage itself shows between 500 and 540 nm."""
    import numpy as np
    from scipy.signal import hilbert

    from warpoptics import materials
    from warpoptics.pipelines import microscope as ms

    mat = materials.get(name)
    k = np.array([[0.3, 0.1, np.sqrt(0.9)]])
    lam = np.linspace(500.0, 540.0, 200_001)
    coh, inc = ms.plate_between_polarizers(
        k, 3.0, lam, ms.plate_optics(mat, lam, optic_axis=axis)[0],
        crystal_frame=ms.plate_optics(mat, 550.0, optic_axis=axis)[2],
    )  # fmt: skip
    fringe = coh[0] - inc[0]
    phase = np.unwrap(np.angle(hilbert(fringe - fringe.mean())))
    inner = slice(2000, -2000)  # away from the transform's edge effects
    measured = abs(phase[inner][-1] - phase[inner][0]) / (2 * np.pi)
    frame = ms.plate_optics(mat, 550.0, optic_axis=axis)[2]
    ret = ms._retardation_directions(mat, 3.0, k, lam[inner][[0, -1]], frame, 1.0)[0]
    predicted = ret[0] / lam[inner][0] - ret[1] / lam[inner][-1]
    assert measured == pytest.approx(predicted, rel=0.05), (measured, predicted)


def test_protocol_views_are_bounded_distinct_and_uniquely_named(tmp_path, capsys):
    """A report's protocol of 801 tilts x 719 azimuths was refused only by its 575,201 view names
    colliding (a00 for 0 and 0.5), in a 19-million-character message."""
    from warpoptics.errors import InputError
    from warpoptics.grading.performance import Protocol

    last = _refused(
        ["grade", "report", "round_brilliant", "--protocol-tilts", "0:80:0.1", "--protocol-azimuths",
         "0:359:0.5", "-o", tmp_path / "r"],
        capsys,
        "575,201 views",
    )  # fmt: skip
    assert len(last) < 200
    with pytest.raises(InputError, match="lists a value twice"):
        Protocol(tilts=(0.0, 5.0, 5.0))
    names = [n for n, *_ in Protocol(tilts=(0.0, 5.0), azimuths=(0.0, 0.5)).view_rotations()]
    assert names == ["t0_a0", "t5_a0", "t5_a0p5"]
    assert [n for n, *_ in Protocol().view_rotations()][:3] == ["t00_a00", "t05_a00", "t05_a22"]
