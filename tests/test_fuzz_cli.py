"""Property-based fuzz of the ``warpoptics`` command line: hypothesis over every subcommand's
options, discovered from the argparse parser (so a new subcommand or flag is fuzzed without an
edit here).  Each case starts from a small valid command line and changes one to three things:
an option's value (types, NaN/Inf, negative, zero, huge, empty strings), an option left out, or
the input file (missing, a folder, garbage bytes, an empty file, a file of another kind).  A case
must end in one of these ways:

- exit 2 with a clear message (argparse's usage error or the command's one-line error),
- exit 0 with every output file non-empty and finite (EXR/NumPy pixels, numbers in CSV/JSON/text),
  and no NaN or Inf printed,

never a traceback, a crash, a hang (each case has a timeout) or a stray worker process.  Work that
would be large must be refused up front (exit 2), which is a pass.

Each case runs in a forked child of the test process (warp, the kernels and the command modules
are imported once, in the parent), with its own working folder, an address-space and a
process-count limit, and a hard timeout that kills the child's process group.

CI runs a small, derandomized budget: ``WARPOPTICS_FUZZ_EXAMPLES`` cases per subcommand (default
3).  A longer local run that counts the outcomes instead of stopping at the first failure::

    WARPOPTICS_FUZZ_EXAMPLES=150 WARPOPTICS_FUZZ_COLLECT=1 WARPOPTICS_FUZZ_REPORT=fuzz.json \\
        python -m pytest -p no:xdist tests/test_fuzz_cli.py -q
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import re
import resource
import signal
import sys
import time
import traceback
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from _helpers import ROOT

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, Phase, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="the fuzz forks a child per case")

EXAMPLES = int(os.environ.get("WARPOPTICS_FUZZ_EXAMPLES", "3"))
REPORT = os.environ.get("WARPOPTICS_FUZZ_REPORT")
COLLECT = os.environ.get("WARPOPTICS_FUZZ_COLLECT", "") not in ("", "0")
CASE_TIMEOUT_S = float(os.environ.get("WARPOPTICS_FUZZ_TIMEOUT", "90"))  # a loaded 2-core machine
MEMORY_LIMIT = 6 * 2**30  # address space of a case (bytes): a larger need must be refused first
MAX_PROCESSES = 48  # processes a case may start (pools, Dask workers) beyond the user's own

# ---- the small valid command line each case starts from -------------------------------------

CAMERA_SCENE = """\
[camera]
position = [0.0, -22.0, 30.0]
look_at = [0.0, 0.0, -0.3]
fov = 15.0
width = 4
height = 4

[render]
spectral = "stratified"
wavelengths = 3
max_depth = 6

[[light]]
type = "environment"
map = "studio"

[[object]]
shape = "round_brilliant"
diameter = 6.5
material = "diamond"
"""

BENCH_SCENE = """\
[source]
type = "beam"
kind = "collimated"
position = [-5.0, 0.0, 0.9326926]
direction = [1.0, 0.0, 0.0]
width = 0.004
spectrum = "E"
rays = 4

[render]
wavelengths = 4
max_depth = 6

[[sensor]]
type = "screen"
name = "wall"
center = [100.0, 0.0, -30.0]
normal = [-1.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
size = [60.0, 1.0]
resolution = [30, 2]

[[object]]
shape = "prism"
apex_angle = 40.0
size = 2.0
length = 2.0
material = "bk7"
"""

MICROSCOPE_SCENE = """\
[microscope]
mode = "orthoscopic"
polarizer = 0.0
analyzer = 90.0
accessory = "quartz_wedge"
accessory_angle = 45.0
wedge_max_nm = 2000.0
illuminant = "D65"
size = 16
mounting_index = 1.54

[sample]
kind = "plate"
material = "quartz"
thickness_mm = 0.03
optic_axis = [1.0, 1.0, 0.0]
"""

SWEEP = """\
name = "fuzz"
scene = "camera.toml"

[[axis]]
name = "diameter"
path = "object.0.diameter"
values = [6.0, 6.5]
"""

SPECTRUM_CSV = "400,0.1\n500,0.8\n600,0.3\n700,0.9\n"

GEMCAD = ROOT / "tests" / "data" / "gemcad" / "SRB.asc"

# one valid, small invocation per subcommand (words as the user types them); the fuzz changes it.
# A subcommand missing here is fuzzed from its positional pool and options alone.
_GRADE_SMALL = ["--size", "8", "--wavelengths", "2"]
BASE_ARGV: dict[str, list[str]] = {
    "render": ["{camera}", "-o", "{out}/img.exr"],
    "view": ["{camera}", "--width", "8", "--height", "6", "--port", "0", "--max-passes", "2"],
    "bench": ["{bench}", "-o", "{out}/bench.exr"],
    "info": [],
    "spectrum": ["-o", "{out}/spectrum.png"],
    "material": ["diamond"],
    "cut": ["round_brilliant", "-o", "{out}/cut.obj"],
    "thinfilm": ["table", "-o", "{out}/table.csv", "--count", "8"],
    "chart": ["michel-levy", "-o", "{out}/chart.png"],
    "microscope": ["{microscope}", "-o", "{out}/micro.png"],
    "sweep": ["{sweep}", "-o", "{out}/sweep", "--quiet"],
    "colorchange": ["alexandrite"],
    "grade report": [
        "round_brilliant", "-o", "{out}/report", *_GRADE_SMALL, "--quiet", "--no-fire",
        "--protocol-tilts", "0", "--protocol-azimuths", "0",
    ],
    "grade aset": ["round_brilliant", "-o", "{out}/aset.png", *_GRADE_SMALL],
    "grade idealscope": ["round_brilliant", "-o", "{out}/is.png", *_GRADE_SMALL],
    "grade hearts": ["round_brilliant", "-o", "{out}/hearts.png", *_GRADE_SMALL],
    "grade map": ["round_brilliant", "-o", "{out}/map.png", *_GRADE_SMALL],
    "grade tilt": [
        "round_brilliant", "-o", "{out}/tilt", *_GRADE_SMALL, "--quiet", "--tilts", "0",
        "--azimuths", "0",
    ],
    "grade optimize": [
        "round_brilliant", "-o", "{out}/opt", *_GRADE_SMALL, "--quiet", "--budget", "2",
        "--popsize", "2", "--param", "pavilion_angle=40:42:41", "--protocol-tilts", "0",
        "--protocol-azimuths", "0",
    ],
    "grade retarget": ["{gemcad}", "-o", "{out}/retarget.asc", "--index", "1.544"],
}  # fmt: skip

# options a case never passes: they only print help or switch tracebacks on by design
SKIP_OPTIONS = {"-h", "--help", "--version", "--debug"}


# ---- the parser, walked ----------------------------------------------------------------------


def _walk(parser: argparse.ArgumentParser, prefix: tuple[str, ...], out: dict) -> None:
    sub = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if sub:
        for name, sp in sub[0].choices.items():
            _walk(sp, (*prefix, name), out)
    elif prefix:
        out[" ".join(prefix)] = [a for a in parser._actions if not isinstance(a, argparse._HelpAction)]


def _commands() -> dict[str, list[argparse.Action]]:
    from warpoptics.cli import build_parser

    out: dict[str, list[argparse.Action]] = {}
    _walk(build_parser(), (), out)
    return out


COMMANDS = _commands()
GLOBAL_OPTIONS = [
    a
    for a in __import__("warpoptics.cli", fromlist=["build_parser"]).build_parser()._actions
    if a.option_strings and not set(a.option_strings) & SKIP_OPTIONS and a.nargs != argparse.PARSER
]


# ---- values ------------------------------------------------------------------------------------

EXTREME_NUMBERS = [
    "0", "-0", "1", "-1", "2", "3", "0.5", "-0.5", "1e-9", "1e-308", "45", "90", "360", "1000",
    "2147483647", "2147483648", "9223372036854775808", "1e9", "1e18", "1e38", "1e308", "-1e308",
    "nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e999",
]  # fmt: skip
SMALL_INTS = ["0", "1", "2", "3", "4", "-1", "-2"]
HUGE_INTS = ["2147483647", "2147483648", "1000000000", "9223372036854775808", "10" * 12]
JUNK = ["", " ", "abc", "1,2", "1:2:3", "=", "--", "-", "é", "0x10", "1_0", "[1]", "{}", "none", "true"]
# words the commands know, so that a string option sometimes passes its first check
WORDS = [
    "diamond", "quartz", "calcite", "sapphire", "alexandrite", "tanzanite", "bk7", "water",
    "round_brilliant", "oval", "prism", "D65", "A", "E", "F2", "iso", "cos", "daylight", "moon",
    "light_return", "fire", "brightness", "analyzer:45", "polariscope", "dichroscope:auto",
    "dichroscope:30", "none", "studio", "D65,A", "A,D65", "D65,D65", "cpu", "cuda:0", "cpu:1",
    "tcp://127.0.0.1:1", "0:30:10", "0,22.5", "30:0:1", "0:90:0", "1:2", "40:44", "38:44:43",
]  # fmt: skip
# dotted paths a KEY=VALUE option (--set, --param) may set
SET_KEYS = [
    "camera.width", "camera.height", "render.spp", "render.wavelengths", "render.max_depth",
    "render.spectral", "object.0.diameter", "object.0.material", "light.0.intensity",
    "pavilion_angle", "crown_angle", "table", "diameter", "material", "source.rays",
    "microscope.size", "sample.thickness_mm", "tier:1", "girdle", "nosuch", "", "object.9.x",
]  # fmt: skip


def _number_text(kind: str):
    if kind == "int":
        return st.one_of(
            st.sampled_from(SMALL_INTS),
            st.sampled_from(SMALL_INTS),
            st.sampled_from(HUGE_INTS),
            st.integers(min_value=-(2**70), max_value=2**70).map(str),
            st.sampled_from(EXTREME_NUMBERS + JUNK),
        )
    return st.one_of(
        st.sampled_from(EXTREME_NUMBERS),
        st.sampled_from(EXTREME_NUMBERS),
        st.floats(min_value=-100.0, max_value=100.0).map(repr),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.sampled_from(JUNK),
    )


def _list_text():
    """Comma lists and start:stop:step ranges of hostile numbers."""
    num = st.sampled_from(EXTREME_NUMBERS + SMALL_INTS + ["", "x"])
    return st.one_of(
        st.lists(num, min_size=1, max_size=4).map(",".join),
        st.lists(num, min_size=2, max_size=4).map(":".join),
    )


def _key_value():
    value = st.one_of(
        st.sampled_from(EXTREME_NUMBERS + WORDS + JUNK),
        _list_text(),
        st.sampled_from(['"diamond"', "[1,2]", "[nan, 0, 1]", "{a=1}", '"x.png"']),
    )
    return st.builds(
        lambda k, v, sep: f"{k}{sep}{v}", st.sampled_from(SET_KEYS), value, st.sampled_from("==:")
    )


def _text():
    return st.one_of(
        st.sampled_from(WORDS),
        st.sampled_from(JUNK + EXTREME_NUMBERS),
        _list_text(),
        st.text(max_size=8),
    )


def _output(draw, example: str | None) -> str:
    """An output path: a valid one of another type, a folder, a file's child, a missing folder,
    an empty string, a read-only place."""
    ext = Path(example).suffix if example else ".png"
    return draw(
        st.sampled_from(
            [
                "{out}/o" + ext,
                "{out}/new/deeper/o" + ext,
                "{out}/o.png",
                "{out}/o.exr",
                "{out}/o.csv",
                "{out}/o.json",
                "{out}/o.pdf",
                "{out}/o.obj",
                "{out}/o",
                "{out}/o.xyz",
                "{out}",
                "{out}/afolder",
                "{out}/garbage.bin/o" + ext,
                "/proc/warpoptics_fuzz/o" + ext,
                "",
                "-",
            ]
        )
    )


INPUTS = {
    "{missing}": "missing.toml",
    "{folder}": "afolder",
    "{garbage}": "garbage.bin",
    "{empty}": "empty.toml",
    "{badtoml}": "bad.toml",
    "{camera}": "camera.toml",
    "{bench}": "bench.toml",
    "{microscope}": "microscope.toml",
    "{sweep}": "sweep.toml",
    "{csv}": "spectrum.csv",
    "{gemcad}": str(GEMCAD),
}


def _input(draw, base: str | None) -> str:
    """A positional input: the base one, a file of another kind, or a broken file."""
    hostile = sorted(INPUTS) + ["{garbage_asc}", "{garbage_obj}", "{empty_csv}"]
    pool = st.sampled_from(hostile + WORDS[:12] + [""])
    if base is not None:
        return draw(st.one_of(st.just(base), pool))
    return draw(pool)


def _kind(action: argparse.Action) -> str:
    """ "int", "float" or "text": what the option's ``type=`` accepts (``int``, ``float`` or a
    range-checking parser of either), found by asking it."""

    def accepts(text: str) -> bool:
        try:
            action.type(text)  # type: ignore[misc]
        except Exception:  # noqa: BLE001 (argparse.ArgumentTypeError, ValueError, ...)
            return False
        return True

    if action.type is None or accepts("abc"):
        return "text"
    if any(accepts(x) for x in ("0.5", "2.5", "45.5", "589.5", "1500.5")):
        return "float"
    if any(accepts(x) for x in ("0", "1", "2", "8", "16", "64", "256", "1000")):
        return "int"
    return "text"


# in-range probes: the values of these an option accepts are its edges and plausible values, so
# that a case gets past argparse and reaches the work.  Large accepted floats (a retardation, a
# thickness) must be refused with an estimate or finish within the timeout; counts stay small
# (an optimizer budget of 10^5 renders is long by request, and prints its progress)
FLOAT_PROBES = [
    "0", "1e-9", "0.001", "0.5", "1", "2", "3", "8", "16", "45", "89.9", "90", "179.9", "180",
    "360", "1000", "4096", "10000", "1e5", "1e6", "1e9",
]  # fmt: skip
INT_PROBES = ["0", "1", "2", "3", "4", "8", "16", "32", "64"]
_ACCEPTED: dict[int, list[str]] = {}


def _accepted(action: argparse.Action) -> list[str]:
    if id(action) not in _ACCEPTED:
        ok = []
        for x in INT_PROBES if _kind(action) == "int" else FLOAT_PROBES:
            try:
                action.type(x)  # type: ignore[misc]
                ok.append(x)
            except Exception:  # noqa: BLE001, PERF203
                pass
        _ACCEPTED[id(action)] = ok or ["0"]
    return _ACCEPTED[id(action)]


def _value(draw, action: argparse.Action, example: str | None) -> list[str]:
    """The words one option adds to a command line."""
    flag = draw(
        st.sampled_from([s for s in action.option_strings if s.startswith("--")] or action.option_strings)
    )
    if action.nargs == 0:  # store_true and friends
        return [flag]
    dest = action.dest
    if dest in ("output", "plot"):
        return [flag, _output(draw, example)]
    kind = _kind(action)
    if action.choices:
        v = draw(st.one_of(st.sampled_from(list(action.choices)), st.sampled_from(JUNK)))
    elif kind in ("int", "float"):
        v = draw(st.one_of(st.sampled_from(_accepted(action)), _number_text(kind)))
    elif isinstance(action, argparse._AppendAction):
        v = draw(_key_value())
    else:
        v = draw(st.one_of(_text(), _list_text()))
    n = action.nargs if isinstance(action.nargs, int) else 1
    words = [v] + [draw(_number_text("float")) for _ in range(n - 1)]
    if any(w.startswith("-") for w in words):
        return [f"{flag}={words[0]}", *words[1:]] if n == 1 else [flag, *words]
    return [flag, *words]


def _option_map(argv: list[str], actions: list[argparse.Action]) -> dict[str, tuple[int, int]]:
    """Where each option of ``argv`` sits: dest -> (start, length)."""
    by_flag = {s: a for a in actions for s in a.option_strings}
    out: dict[str, tuple[int, int]] = {}
    i = 0
    while i < len(argv):
        a = by_flag.get(argv[i])
        if a is None:
            i += 1
            continue
        n = 1 if a.nargs == 0 else 1 + (a.nargs if isinstance(a.nargs, int) else 1)
        if a.dest not in out or not isinstance(a, argparse._AppendAction):
            out[a.dest] = (i, n)
        i += n
    return out


@st.composite
def command_lines(draw, command: str) -> list[str]:
    """The command's base line with one to three changes."""
    actions = COMMANDS[command]
    base = list(BASE_ARGV.get(command, []))
    options = [a for a in actions if a.option_strings and not set(a.option_strings) & SKIP_OPTIONS]
    positionals = [a for a in actions if not a.option_strings]
    placed = _option_map(base, actions)
    # positionals of the base line come first, in order
    n_pos = 0
    while n_pos < len(base) and not base[n_pos].startswith("-") and n_pos < len(positionals):
        n_pos += 1
    pos_words = base[:n_pos]
    rest = base[n_pos:]
    rest_placed = {k: (i - n_pos, n) for k, (i, n) in placed.items()}
    edits = draw(st.integers(min_value=1, max_value=3))
    drop: set[str] = set()
    extra: list[str] = []
    for _ in range(edits):
        kind = draw(st.sampled_from(["option", "option", "option", "positional", "drop", "global"]))
        if kind == "positional" and positionals:
            j = draw(st.integers(min_value=0, max_value=len(positionals) - 1))
            a = positionals[j]
            base_word = pos_words[j] if j < len(pos_words) else None
            if a.choices:
                word = draw(st.one_of(st.sampled_from(list(a.choices)), st.sampled_from(JUNK + WORDS)))
            else:
                word = _input(draw, base_word)
            while len(pos_words) <= j:
                pos_words.append("")
            pos_words[j] = word
        elif kind == "drop" and rest_placed:
            drop.add(draw(st.sampled_from(sorted(rest_placed))))
        elif kind == "global" and GLOBAL_OPTIONS:
            a = draw(st.sampled_from(GLOBAL_OPTIONS))
            extra = _value(draw, a, None) + extra
            extra = ["GLOBAL", *extra]
        elif options:
            a = draw(st.sampled_from(options))
            example = None
            if a.dest in rest_placed:
                i, n = rest_placed[a.dest]
                example = rest[i + 1] if n > 1 else None
                if not isinstance(a, argparse._AppendAction):
                    drop.add(a.dest)
            extra += _value(draw, a, example)
    kept: list[str] = []
    for dest, (i, n) in sorted(rest_placed.items(), key=lambda kv: kv[1][0]):
        if dest not in drop:
            kept += rest[i : i + n]
    glob: list[str] = []
    local: list[str] = []
    it = iter(extra)
    for w in it:
        if w == "GLOBAL":
            flag = next(it)
            glob.append(flag)
            if "=" not in flag:
                act = next(a for a in GLOBAL_OPTIONS if flag in a.option_strings)
                if act.nargs != 0:
                    glob.append(next(it))
        else:
            local.append(w)
    return [*glob, *command.split(), *pos_words, *kept, *local]


# ---- running a case ----------------------------------------------------------------------------


def _setup_inputs(folder: Path) -> None:
    """The files a case may name, written once per test module."""
    (folder / "camera.toml").write_text(CAMERA_SCENE, encoding="utf-8")
    (folder / "bench.toml").write_text(BENCH_SCENE, encoding="utf-8")
    (folder / "microscope.toml").write_text(MICROSCOPE_SCENE, encoding="utf-8")
    (folder / "sweep.toml").write_text(SWEEP, encoding="utf-8")
    (folder / "spectrum.csv").write_text(SPECTRUM_CSV, encoding="utf-8")
    (folder / "empty.toml").write_bytes(b"")
    (folder / "empty.csv").write_bytes(b"")
    (folder / "bad.toml").write_text("[camera\nwidth = = 3\n", encoding="utf-8")
    rng = np.random.default_rng(0)
    junk = bytes(rng.integers(0, 256, 4096, dtype=np.uint8))
    for name in ("garbage.bin", "garbage.asc", "garbage.obj"):
        (folder / name).write_bytes(junk)
    (folder / "afolder").mkdir(exist_ok=True)


def _expand(argv: list[str], inputs: Path, out: Path) -> list[str]:
    names = {
        **{k: str(inputs / v) if not os.path.isabs(v) else v for k, v in INPUTS.items()},
        "{garbage_asc}": str(inputs / "garbage.asc"),
        "{garbage_obj}": str(inputs / "garbage.obj"),
        "{empty_csv}": str(inputs / "empty.csv"),
        "{out}": str(out),
    }
    res = []
    for w in argv:
        for k, v in names.items():
            w = w.replace(k, v)
        res.append(w)
    return res


def _user_processes() -> int:
    uid = os.getuid()
    n = 0
    for p in Path("/proc").iterdir():
        if p.name.isdigit():
            try:
                if p.stat().st_uid == uid:
                    n += 1
            except OSError:
                pass
    return n


def _child(argv: list[str], work: Path) -> None:
    """Run in the forked child: the command, its outcome as JSON in ``work/outcome.json``."""
    record: dict = {}
    try:
        os.setpgid(0, 0)
        os.chdir(work)
        out_fd = os.open(work / "stdout.txt", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        err_fd = os.open(work / "stderr.txt", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
        null = os.open(os.devnull, os.O_RDONLY)
        os.dup2(null, 0)
        os.dup2(out_fd, 1)
        os.dup2(err_fd, 2)
        sys.stdin = open(0, encoding="utf-8", closefd=False)  # noqa: SIM115
        sys.stdout = open(1, "w", encoding="utf-8", closefd=False, buffering=1)  # noqa: SIM115
        sys.stderr = open(2, "w", encoding="utf-8", closefd=False, buffering=1)  # noqa: SIM115
        for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGALRM):
            signal.signal(sig, signal.SIG_DFL)
        signal.alarm(int(CASE_TIMEOUT_S) + 60)  # ends the case even if the test process died
        with contextlib.suppress(ValueError, OSError):  # not every system limits address space
            resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
        if Path("/proc").is_dir():  # Linux: count the user's processes, allow a few more
            nproc = _user_processes() + MAX_PROCESSES
            hard = resource.getrlimit(resource.RLIMIT_NPROC)[1]
            if hard == resource.RLIM_INFINITY or nproc < hard:
                resource.setrlimit(resource.RLIMIT_NPROC, (nproc, hard))
        import webbrowser

        webbrowser.open = lambda *a, **k: True  # --open: no browser from a test
        _one_pass_view(work)
        from warpoptics.cli import main

        try:
            record = {"exit": main(argv)}
        except SystemExit as exc:
            code = exc.code
            record = {"exit": code if isinstance(code, int) else (0 if code is None else 2)}
        except BaseException as exc:  # noqa: BLE001 (what the test is looking for)
            record = {"exception": type(exc).__name__, "traceback": traceback.format_exc()[-4000:]}
        sys.stdout.flush()
        sys.stderr.flush()
        import multiprocessing.util

        multiprocessing.util._exit_function()  # what interpreter exit does: join the children
    except BaseException as exc:  # noqa: BLE001 (the harness itself failed)
        record = {"harness": f"{type(exc).__name__}: {exc}"}
    finally:
        try:
            (work / "outcome.json").write_text(json.dumps(record), encoding="utf-8")
        finally:
            os._exit(0)


def _one_pass_view(work: Path) -> None:
    """``view`` serves until Ctrl-C: in a case it renders two passes and saves the mean instead."""
    from warpoptics.commands import view

    class OnePass(view.ViewServer):
        def __init__(self, *a, **k):
            super().__init__(*a, **k)

            def serve_two_passes(*_a, **_k):
                self.frame()
                self.frame()
                np.save(work / "out" / "view_xyz.npy", np.asarray(self.preview.image().xyz))

            self.httpd.serve_forever = serve_two_passes

    view.ViewServer = OnePass


def _run_case(argv: list[str], work: Path) -> dict:
    """Fork, run ``argv`` in the child, wait at most CASE_TIMEOUT_S, clean up its process group."""
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:  # pragma: no cover (the child)
        _child(argv, work)
    t0 = time.monotonic()
    status = None
    while time.monotonic() - t0 < CASE_TIMEOUT_S:
        got, st_ = os.waitpid(pid, os.WNOHANG)
        if got:
            status = st_
            break
        time.sleep(0.02)
    seconds = time.monotonic() - t0
    stray = False
    try:
        # anyone left in the child's process group after it ended (a few seconds' grace for
        # workers that are shutting down)
        end = time.monotonic() + 10.0
        while status is not None and time.monotonic() < end:
            os.killpg(pid, 0)
            time.sleep(0.1)
        stray = status is not None
        os.killpg(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    if status is None:
        os.waitpid(pid, 0)
        return {"hang": True, "seconds": seconds}
    outcome: dict = {"seconds": seconds}
    if os.WIFSIGNALED(status):
        outcome["signal"] = os.WTERMSIG(status)
    f = work / "outcome.json"
    if f.exists():
        outcome.update(json.loads(f.read_text(encoding="utf-8")))
    outcome["stray"] = stray
    return outcome


# ---- judging an outcome ------------------------------------------------------------------------

_NONFINITE = re.compile(r"(?<![\w.])[-+]?(nan|inf|infinity)(?![\w])", re.IGNORECASE)


def _nonfinite_in_file(path: Path) -> str | None:
    """Why the file is not a finite, non-empty output (None: it is)."""
    if path.stat().st_size == 0:
        return "empty"
    ext = path.suffix.lower()
    try:
        if ext in (".exr", ".hdr", ".tif", ".tiff"):
            import OpenImageIO as oiio

            buf = oiio.ImageBuf(str(path))
            px = buf.get_pixels(oiio.FLOAT)
            if px is None:
                return f"unreadable image ({buf.geterror()})"
            if not np.isfinite(px).all():
                return "non-finite pixels"
        elif ext in (".npy",):
            if not np.isfinite(np.load(path)).all():
                return "non-finite array"
        elif ext in (".npz",):
            with np.load(path) as z:
                for k in z.files:
                    if z[k].dtype.kind in "fc" and not np.isfinite(z[k]).all():
                        return f"non-finite array {k}"
        elif ext in (".png", ".jpg", ".jpeg"):
            from PIL import Image as PILImage

            with PILImage.open(path) as im:
                im.load()
        elif ext in (".csv", ".json", ".txt", ".md", ".obj", ".asc", ".toml", ".svg", ".off", ".ply"):
            text = path.read_text(encoding="utf-8", errors="replace")
            m = _NONFINITE.search(text)
            if m:
                return f"non-finite number {m.group(0)!r} in text"
    except Exception as exc:  # noqa: BLE001
        return f"unreadable ({type(exc).__name__}: {exc})"
    return None


def judge(outcome: dict, work: Path) -> tuple[str, str]:
    """(kind, detail): kind is "ok", "refused", "usage" or a failure family."""
    if outcome.get("hang"):
        return "HANG", f"no answer within {CASE_TIMEOUT_S:.0f} s"
    if "harness" in outcome:
        return "HARNESS", outcome["harness"]
    if "signal" in outcome:
        return "CRASH", f"killed by signal {outcome['signal']}"
    if "exception" in outcome:
        return f"TRACEBACK {outcome['exception']}", outcome["traceback"]
    stderr = (work / "stderr.txt").read_text(encoding="utf-8", errors="replace")
    stdout = (work / "stdout.txt").read_text(encoding="utf-8", errors="replace")
    if "Traceback (most recent call last)" in stderr:
        return "TRACEBACK (printed)", stderr[-3000:]
    if outcome.get("stray"):
        return "STRAY PROCESS", "a process of the case outlived it"
    code = outcome.get("exit")
    if code == 0:
        for p in sorted((work / "out").rglob("*")):
            if p.is_file() and not p.name.startswith("."):  # not a lock file
                why = _nonfinite_in_file(p)
                if why:
                    return "BAD OUTPUT", f"{p.relative_to(work)}: {why}"
        m = _NONFINITE.search(stdout)
        if m:
            line = next(ln for ln in stdout.splitlines() if m.group(0) in ln)
            return "NON-FINITE PRINTED", line[:500]
        return "ok", ""
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    last = lines[-1] if lines else ""
    if code == 2 and ": error:" in last:
        if len(last) > 2000:
            return "LONG ERROR", f"{len(last)} characters: {last[:300]}"
        return ("usage" if "usage:" in stderr else "refused"), last
    return "UNCLEAR EXIT", f"exit {code}; stderr: {stderr[-1000:]!r}"


# ---- the tests ---------------------------------------------------------------------------------

_COUNTS: Counter = Counter()
_FAILURES: list[dict] = []


@pytest.fixture(scope="module")
def fuzz_dir(tmp_path_factory):
    """Inputs written once; the kernels the base lines use compiled and loaded in this process
    (outside the per-case timeout, and inherited by every forked case)."""
    folder = tmp_path_factory.mktemp("fuzz_cli")
    _setup_inputs(folder)
    from warpoptics.pipelines.render import Renderer
    from warpoptics.scene import Scene

    Renderer(Scene.load(folder / "camera.toml")).run()
    yield folder
    if REPORT:
        data = {"counts": {k: n for k, n in sorted(_COUNTS.items()) if n}, "failures": _FAILURES}
        Path(REPORT).write_text(json.dumps(data, indent=1), encoding="utf-8")


_CASE = Counter()


def check_command_line(argv: list[str], folder: Path, *, command: str) -> tuple[str, str]:
    """Run one case in a fresh working folder and judge it; record the outcome."""
    _CASE["n"] += 1
    work = folder / "cases" / f"{_CASE['n']:06d}"
    (work / "out").mkdir(parents=True)
    full = _expand(argv, folder, work / "out")
    outcome = _run_case(full, work)
    kind, detail = judge(outcome, work)
    _COUNTS[f"{command}: {kind}"] += 1
    _COUNTS[f"all: {kind}"] += 1
    if kind not in ("ok", "refused", "usage"):
        _FAILURES.append({"command": command, "argv": argv, "kind": kind, "detail": detail[-1500:]})
    else:
        import shutil

        shutil.rmtree(work, ignore_errors=True)
    return kind, detail


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_base_command_line_works(fuzz_dir, command):
    """The line each fuzz case starts from runs and writes a finite output (else the fuzz would
    only ever test refusals)."""
    if command not in BASE_ARGV:
        pytest.skip(f"no base line for {command}: fuzzed from its options alone")
    kind, detail = check_command_line([*command.split(), *BASE_ARGV[command]], fuzz_dir, command=command)
    assert kind == "ok", f"{command}: {kind}: {detail}"


@pytest.mark.parametrize("command", sorted(COMMANDS))
@settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=not COLLECT,
    database=None,
    phases=[Phase.explicit, Phase.generate],
    suppress_health_check=list(HealthCheck),
)
@given(data=st.data())
def test_fuzzed_command_line_is_a_clear_answer(fuzz_dir, command, data):
    argv = data.draw(command_lines(command), label="argv")
    kind, detail = check_command_line(argv, fuzz_dir, command=command)
    if not COLLECT:
        assert kind in ("ok", "refused", "usage"), f"warpoptics {' '.join(argv)}: {kind}: {detail}"


# cases the fuzz once failed on, kept as they were found (after the fix: a clear answer)
REGRESSIONS = [
    # a local Dask cluster of 2^31 workers: a MemoryError traceback while Dask listed them
    ["sweep", "{sweep}", "-o", "{out}/sweep", "--quiet", "--dask-local", "2147483647"],
    # `--size=--`: Python 3.11's argparse stored an empty list, unchecked (a TypeError later)
    ["microscope", "{microscope}", "--size=--", "--stage=-2.5126865409501846", "--output", "{out}/o.pdf"],
    ["render", "{camera}", "-o", "{out}/img.exr", "--width=--"],
    # a GIF frame of 10^9 s: an OverflowError traceback after every render
    [
        "grade", "tilt", "round_brilliant", "-o", "{out}/tilt", "--size", "8", "--wavelengths", "2",
        "--quiet", "--tilts", "0", "--azimuths", "0", "--fps", "1e-9",
    ],
    # an unknown device found after a local Dask cluster started: its shutdown printed a traceback
    [
        "--device", "2:inf", "grade", "report", "round_brilliant", "-o", "{out}/report", "--size", "8",
        "--quiet", "--no-fire", "--protocol-tilts", "0", "--protocol-azimuths", "0", "--dask-local", "2",
    ],
    # a NUL in --device: a ValueError traceback from os.environ
    ["--device", "\x01\x00-", "info"],
    # a chart 1e-9 nm wide: matplotlib's glyph rasterizer overflowed (a RuntimeError traceback)
    ["chart", "michel-levy", "-o", "{out}/chart.png", "--max-retardation", "1e-9"],
]  # fmt: skip


@pytest.mark.parametrize("argv", REGRESSIONS, ids=lambda a: " ".join(a))
def test_found_by_the_fuzz_is_a_clear_answer(fuzz_dir, argv):
    kind, detail = check_command_line(argv, fuzz_dir, command="regressions")
    assert kind in ("ok", "refused", "usage"), f"warpoptics {' '.join(argv)}: {kind}: {detail}"


def test_walk_finds_every_subcommand():
    """The walk reaches nested subcommands (grade's) and every option of them."""
    assert {"render", "sweep", "grade aset", "grade optimize"} <= set(COMMANDS)
    flags = {s for a in COMMANDS["grade tilt"] for s in a.option_strings}
    assert {"--fps", "--tilts", "--workers"} <= flags
    assert {"--device"} <= {s for a in GLOBAL_OPTIONS for s in a.option_strings}


def test_the_harness_sees_a_traceback_and_a_non_finite_file(fuzz_dir, tmp_path):
    """The judge is not blind: ``--debug`` turns the clear error into the traceback a case must
    never show, and a NaN in a written table or image is caught."""
    kind, detail = check_command_line(
        ["--debug", "render", "{missing}", "-o", "{out}/x.png"], fuzz_dir, command="harness"
    )
    assert kind.startswith("TRACEBACK"), (kind, detail)
    _FAILURES.pop()  # not a finding of the fuzz
    _COUNTS.subtract({f"harness: {kind}": 1, f"all: {kind}": 1})
    (tmp_path / "t.csv").write_text("a,b\n1.0,nan\n", encoding="utf-8")
    (tmp_path / "e.csv").write_text("", encoding="utf-8")
    (tmp_path / "ok.csv").write_text("a,b\n1.0,2.5e-3\nbanana,infinite_loop\n", encoding="utf-8")
    np.save(tmp_path / "x.npy", np.array([1.0, np.inf]))
    assert "non-finite" in _nonfinite_in_file(tmp_path / "t.csv")
    assert _nonfinite_in_file(tmp_path / "e.csv") == "empty"
    assert _nonfinite_in_file(tmp_path / "ok.csv") is None
    assert "non-finite" in _nonfinite_in_file(tmp_path / "x.npy")
