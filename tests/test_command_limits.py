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
    assert len(last) < 400, last
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
