"""Atomic writers: a write that fails midway leaves the old file and no temporary behind."""

from __future__ import annotations

import pytest
from _helpers import ROOT


def test_writers_are_atomic(tmp_path, monkeypatch):
    """A writer that fails midway leaves the old file untouched and no temporary file behind."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from warpoptics.film.image import save_figure
    from warpoptics.geometry import cuts, gemcad

    dest = tmp_path / "plot.png"
    dest.write_bytes(b"old")
    fig = plt.figure()

    def boom(*a, **k):
        raise RuntimeError("disk full")

    monkeypatch.setattr(fig, "savefig", boom)
    with pytest.raises(RuntimeError):
        save_figure(fig, dest)
    plt.close(fig)
    assert dest.read_bytes() == b"old" and sorted(p.name for p in tmp_path.iterdir()) == ["plot.png"]

    asc = tmp_path / "stone.asc"
    gemcad.write(cuts.round_brilliant(), asc)
    assert asc.read_bytes().startswith(b"GemCad") or asc.stat().st_size > 100
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plot.png", "stone.asc"]


def test_no_writer_bypasses_atomic_path():
    """Source scan: every savefig / mesh export / open(..., 'w') in the package and scripts goes
    through ``atomic_path`` or ``save_figure`` (a new writer must too)."""
    import re

    offenders = []
    files = list((ROOT / "warpoptics").rglob("*.py")) + list((ROOT / "scripts").rglob("*.py"))
    for f in files:
        text = f.read_text(encoding="utf-8")
        for i, line in enumerate(text.splitlines(), 1):
            s = line.strip()
            if s.startswith("#"):
                continue
            writes = (
                re.search(r"\.savefig\(", s)
                or re.search(r"\.export\(", s)
                or re.search(r"np\.save(txt)?\(", s)
                or re.search(r"open\([^)]*['\"][wa]b?['\"]", s)
                or re.search(r"\.write_(text|bytes)\(", s)
            )
            # "not-a-replace:" marks the two intended non-atomic writes (an append-only journal
            # with fsync per row, a lock file); anything else must go through a temporary file
            if writes and "tmp" not in s and "not-a-replace:" not in s:
                offenders.append(f"{f.relative_to(ROOT)}:{i}: {s}")
    assert not offenders, "\n".join(offenders)


# -- a full disk must never replace a good file --------------------------------------------------

# every writer of the package, on a file that already holds good bytes; run on a full disk
_WRITERS = r"""
import os, sys, numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from warpoptics.errors import OutputError
from warpoptics.film.image import write_image, save_figure
from warpoptics.geometry import cuts, gemcad
from warpoptics.geometry.gltf import export_gltf
from warpoptics.materials import get
from warpoptics.atomic import atomic_path
from warpoptics.sweep.results import write_text_atomic, append_line
d = sys.argv[1]
# noise does not compress: each file is larger than the space left
big = np.random.default_rng(1).random((300, 300, 3))
mesh = cuts.sphere(diameter=1.0, subdivisions=5)
fig = plt.figure()
plt.imshow(big)
def mesh_export(p):
    with atomic_path(p) as tmp:
        mesh.export(tmp, file_type="ply")
writers = {
    "a.png": lambda p: write_image(p, big),
    "a.exr": lambda p: write_image(p, big),
    "a.pdf": lambda p: save_figure(fig, p),
    "a.ply": mesh_export,
    "a.asc": lambda p: gemcad.write(cuts.round_brilliant(), p),
    "a.glb": lambda p: export_gltf(p, mesh, get("diamond")),
    "a.csv": lambda p: write_text_atomic(p, "x" * 400_000),
}
for name in writers:
    with open(os.path.join(d, name), "wb") as f:
        f.write(b"good")
# fill the disk
fd = os.open(os.path.join(d, "filler"), os.O_WRONLY | os.O_CREAT)
try:
    while True:
        os.write(fd, b"\0" * 4096)
except OSError:
    os.close(fd)
ok = 0
for name, w in writers.items():
    p = os.path.join(d, name)
    try:
        w(p)
        print("NOERROR", name)
    except OutputError as e:
        assert p in str(e) and ".tmp" not in str(e) and "\n" not in str(e), str(e)
        ok += 1
    assert open(p, "rb").read() == b"good", name
try:
    append_line(os.path.join(d, "a.csv"), "y" * 100_000)
except OutputError as e:
    assert "a.csv" in str(e)
    ok += 1
left = sorted(n for n in os.listdir(d) if n not in writers and n != "filler")
assert not left, left
print("OK", ok)
"""


def _unshare_ok() -> bool:
    import shutil
    import subprocess

    if shutil.which("unshare") is None:
        return False
    r = subprocess.run(["unshare", "-rm", "true"], capture_output=True, timeout=30)
    return r.returncode == 0


def _on_tiny_tmpfs(script: str, *args: str, size: str = "64k", timeout: int = 240):
    """Run ``script`` with a fresh tmpfs of ``size`` as its first argument, in a private mount
    namespace (``unshare -rm``: no root needed where user namespaces are allowed)."""
    import os
    import subprocess
    import sys

    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    sh = (
        'd=$(mktemp -d) && mount -t tmpfs -o size="$1" tmpfs "$d" && shift && '
        '{ "$@" "$d"; rc=$?; umount "$d"; rmdir "$d"; exit $rc; }'
    )
    return subprocess.run(
        ["unshare", "-rm", "sh", "-c", sh, "sh", size, sys.executable, "-c", script, *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        env=env,
        cwd=ROOT,
    )


@pytest.mark.skipif(not _unshare_ok(), reason="needs unshare -rm to mount a small tmpfs")
def test_full_disk_every_writer_keeps_old_file():
    """On a real full disk (a tmpfs): every writer raises one OutputError naming the
    user's path, the old file keeps its bytes, no temporary file is left.  (Before: a PNG was
    replaced by a truncated 4 KiB file with exit 0.)"""
    r = _on_tiny_tmpfs(_WRITERS, size="256k")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "NOERROR" not in r.stdout
    assert "OK 8" in r.stdout, r.stdout + r.stderr


_RENDER = r"""
import os, subprocess, sys
d = sys.argv[-1]
out = os.path.join(d, "out.exr")
with open(out, "wb") as f:
    f.write(b"good")
fd = os.open(os.path.join(d, "filler"), os.O_WRONLY | os.O_CREAT)
try:
    while True:
        os.write(fd, b"\0" * 4096)
except OSError:
    os.close(fd)
r = subprocess.run([sys.executable, "-m", "warpoptics.cli", "render", "scenes/diamond.toml", "-o", out,
                    "--width", "48", "--height", "48", "--spp", "1"], capture_output=True, text=True)
print("RC", r.returncode)
print("ERR", r.stderr.strip())
print("OUT", r.stdout.strip())
print("KEPT", open(out, "rb").read() == b"good")
print("LEFT", sorted(n for n in os.listdir(d) if n not in ("out.exr", "filler")))
"""


@pytest.mark.skipif(not _unshare_ok(), reason="needs unshare -rm to mount a small tmpfs")
def test_full_disk_render_command_exits_2_and_keeps_output():
    """``render -o out.exr`` on a full disk: exit 2, one line naming out.exr, no success line,
    the old file kept, no temporary file left."""
    r = _on_tiny_tmpfs(_RENDER, size="64k")
    lines = dict(ln.split(" ", 1) for ln in r.stdout.splitlines() if " " in ln)
    assert lines.get("RC") == "2", r.stdout + r.stderr
    assert "cannot write" in lines["ERR"] and "out.exr" in lines["ERR"] and ".tmp" not in lines["ERR"]
    assert len(lines["ERR"].splitlines()) == 1 and "Traceback" not in lines["ERR"]
    assert lines.get("OUT", "") == "" or "out.exr:" not in lines["OUT"]
    assert lines["KEPT"] == "True" and lines["LEFT"] == "[]"


@pytest.mark.parametrize("step", ["fsync", "verify", "empty"])
def test_injected_write_failure_keeps_old_file(tmp_path, monkeypatch, step):
    """A write error at each check of atomic_path (fsync reporting ENOSPC, a file that does not
    read back, a writer that wrote nothing) keeps the old file, leaves no temporary, and names
    the user's path, not the temporary one."""
    import errno

    from warpoptics import atomic
    from warpoptics.errors import OutputError

    dest = tmp_path / "out.bin"
    dest.write_bytes(b"good")
    verify = None
    if step == "fsync":

        def fail(fd):
            raise OSError(errno.ENOSPC, "No space left on device")

        monkeypatch.setattr(atomic.os, "fsync", fail)
    elif step == "verify":

        def verify(tmp):
            raise OSError(0, f"{tmp} is truncated")

    with pytest.raises(OutputError) as info:
        with atomic.atomic_path(dest, field="-o", verify=verify) as tmp:
            if step != "empty":
                with open(tmp, "wb") as f:
                    f.write(b"new bytes")
    msg = str(info.value)
    assert str(dest) in msg and "-o" in msg and ".tmp" not in msg and "\n" not in msg, msg
    assert dest.read_bytes() == b"good"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.bin"]


def test_folder_in_the_way_names_the_output(tmp_path, capsys):
    """``cut -o x.ply`` where x.ply is a folder: one line naming x.ply (before: a hidden
    ``.x.4u88awi6.tmp.ply: Is a directory``), exit 2, nothing left behind."""
    from warpoptics.cli import main

    target = tmp_path / "x.ply"
    target.mkdir()
    assert main(["cut", "round_brilliant", "-o", str(target)]) == 2
    err = capsys.readouterr().err.strip()
    assert str(target) in err and ".tmp" not in err and "folder" in err and "\n" not in err, err
    assert [p.name for p in tmp_path.iterdir()] == ["x.ply"] and not any(target.iterdir())
