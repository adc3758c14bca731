import os

import numpy as np
import pytest

from warpoptics.atomic import atomic_path
from warpoptics.errors import InputError
from warpoptics.film.image import read_image, write_exr, write_png


def test_exr_roundtrip_with_named_channels(tmp_path):
    rng = np.random.default_rng(0)
    a = rng.normal(size=(7, 5, 7)).astype(np.float32)  # negative values survive (Stokes S1..S3)
    names = ["R", "G", "B", "S0", "S1", "S2", "S3"]
    p = write_exr(tmp_path / "img.exr", a, names)
    b, got = read_image(p)
    assert got == names
    np.testing.assert_array_equal(a, b)
    assert [f for f in os.listdir(tmp_path) if f.startswith(".")] == []  # no temporary left behind


def test_png_roundtrip(tmp_path):
    a = np.linspace(0, 1, 4 * 6 * 3).reshape(4, 6, 3)
    p = write_png(tmp_path / "img.png", a)
    b, names = read_image(p)
    assert b.shape == (4, 6, 3)
    np.testing.assert_allclose(b, np.round(a * 255) / 255, atol=1e-6)


def test_failed_write_keeps_old_file(tmp_path):
    target = tmp_path / "keep.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            with open(tmp, "w") as f:
                f.write("half")
            raise RuntimeError("crash in the middle")
    assert target.read_text() == "old"
    assert sorted(os.listdir(tmp_path)) == ["keep.txt"]


def test_read_errors_name_the_file(tmp_path):
    with pytest.raises(InputError, match="missing.exr: file not found"):
        read_image(tmp_path / "missing.exr")
    bad = tmp_path / "bad.exr"
    bad.write_bytes(b"not an image")
    with pytest.raises(InputError, match="bad.exr"):
        read_image(bad)


def test_atomic_writes_get_normal_permissions(tmp_path):
    p = write_png(tmp_path / "perm.png", np.zeros((2, 2, 3)))
    umask = os.umask(0)
    os.umask(umask)
    assert (p.stat().st_mode & 0o777) == (0o666 & ~umask)
