"""Image metrics against hand-computed values on synthetic images, and CIEDE2000 against Sharma et al.

References independent of the code: CIELAB and CIE 1976 u'v' written out here from CIE 15:2004;
CIEDE2000 test pairs from G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 color-difference
formula: implementation notes, supplementary test data, and mathematical observations", Color
Res. Appl. 30(1), 21-30 (2005), table 1.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from warpoptics import metrics as wm
from warpoptics.errors import InputError

D65 = np.array([0.95047, 1.0, 1.08883])  # CIE 15:2004 D65, Y = 1 (4-digit xy rounding: 1e-4 level)


def lab_by_hand(xyz, white=D65):
    """CIE 15:2004 eq. 8.1-8.3."""
    t = np.asarray(xyz, dtype=float) / white
    d = 6.0 / 29.0
    f = np.where(t > d**3, np.cbrt(t), t / (3 * d * d) + 4.0 / 29.0)
    return np.stack(
        [116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], axis=-1
    )


def xyz_from_lab(lab, white=D65):
    """Inverse of CIE 15:2004 eq. 8.1-8.3."""
    lab = np.asarray(lab, dtype=float)
    fy = (lab[..., 0] + 16) / 116
    fx = fy + lab[..., 1] / 500
    fz = fy - lab[..., 2] / 200
    d = 6.0 / 29.0

    def finv(f):
        return np.where(f > d, f**3, 3 * d * d * (f - 4.0 / 29.0))

    return np.stack([finv(fx), finv(fy), finv(fz)], axis=-1) * white


def test_mean_color_alpha_weighted():
    xyz = np.array([[[0.2, 0.3, 0.4], [0.6, 0.5, 0.1]], [[9.0, 9.0, 9.0], [0.0, 0.0, 0.0]]])
    alpha = np.array([[1.0, 0.5], [0.0, 0.0]])
    m = wm.mean_color(xyz, alpha)
    want = (np.array([0.2, 0.3, 0.4]) * 1.0 + np.array([0.6, 0.5, 0.1]) * 0.5) / 1.5
    assert np.allclose([m["X"], m["Y"], m["Z"]], want, rtol=0, atol=1e-15)
    lab = lab_by_hand(want)
    # white point: our D65 is from xy (0.3127, 0.3290); CIE's 4-digit XYZ differs by < 1e-4
    assert abs(m["L"] - lab[0]) < 1e-3 and abs(m["a"] - lab[1]) < 0.02 and abs(m["b"] - lab[2]) < 0.02
    assert m["C"] == pytest.approx(math.hypot(m["a"], m["b"]), rel=1e-12)
    assert m["h"] == pytest.approx(math.degrees(math.atan2(m["b"], m["a"])) % 360, rel=1e-12)
    assert m["coverage"] == pytest.approx(1.5 / 4)


def test_mean_color_white_and_empty():
    m = wm.mean_color(np.broadcast_to(wm.D65_WHITE_XYZ, (3, 3, 3)))
    assert m["L"] == pytest.approx(100.0, abs=1e-9) and m["C"] < 1e-9
    e = wm.mean_color(np.ones((2, 2, 3)), np.zeros((2, 2)))
    assert e["Y"] == 0.0 and e["L"] == 0.0 and e["coverage"] == 0.0


@pytest.mark.parametrize(
    "lab1, lab2, want",
    [
        ((50.0, 2.6772, -79.7751), (50.0, 0.0, -82.7485), 2.0425),
        ((50.0, 3.1571, -77.2803), (50.0, 0.0, -82.7485), 2.8615),
        ((50.0, 2.8361, -74.0200), (50.0, 0.0, -82.7485), 3.4412),
        ((50.0, 2.5, 0.0), (73.0, 25.0, -18.0), 27.1492),
        ((60.2574, -34.0099, 36.2677), (60.4626, -34.1751, 39.4387), 1.2644),
    ],
)
def test_delta_e_image_sharma_pairs(lab1, lab2, want):
    white = wm.D65_WHITE_XYZ
    a = xyz_from_lab(np.array([[lab1]]), white)
    b = xyz_from_lab(np.array([[lab2]]), white)
    de = wm.delta_e_image(a, b)
    assert de.shape == (1, 1)
    assert de[0, 0] == pytest.approx(want, abs=1e-4)  # the table's 4 decimals
    assert wm.delta_e_mean_color(a, None, b, None) == pytest.approx(want, abs=1e-4)


def test_delta_e_stats_weights():
    de = np.array([[1.0, 2.0], [3.0, 100.0]])
    aa = np.array([[1.0, 0.0], [0.5, 0.0]])
    ab = np.array([[0.0, 1.0], [0.25, 0.0]])
    s = wm.delta_e_stats(de, aa, ab)
    # weights max(aa, ab) = [[1, 1], [0.5, 0]]
    assert s["dE_mean"] == pytest.approx((1 + 2 + 1.5) / 2.5)
    assert s["dE_max"] == 3.0  # the uncovered pixel (100) is ignored
    assert s["dE_p95"] == pytest.approx(np.percentile([1.0, 2.0, 3.0], 95))
    assert wm.delta_e_stats(de)["dE_max"] == 100.0


def test_difference_image_range():
    img = wm.difference_image(np.array([[0.0, 5.0, 10.0, 50.0]]), scale=10.0)
    assert img.shape == (1, 4, 3) and img.min() >= 0 and img.max() <= 1
    assert img[0, 0].max() < 0.02  # inferno starts black
    assert np.array_equal(img[0, 2], img[0, 3])  # saturates at full scale
    assert img[0, 1].sum() > img[0, 0].sum()
    with pytest.raises(InputError):
        wm.difference_image(np.zeros((1, 1)), scale=0.0)


def test_uv_and_saturation_by_hand():
    xyz = np.array([0.2, 0.1, 0.0])
    d = 0.2 + 15 * 0.1
    u, v = 4 * 0.2 / d, 9 * 0.1 / d
    assert np.allclose(wm.uv_prime(xyz), [u, v], rtol=1e-14)
    # D65 u'v' = (0.1978, 0.4683) (CIE 15:2004 table T.3, 4 decimals)
    s = 13 * math.hypot(u - 0.1978, v - 0.4683)
    assert wm.saturation_uv(xyz) == pytest.approx(s, abs=13 * 1e-4)
    assert wm.saturation_uv(wm.D65_WHITE_XYZ * 7.0) == pytest.approx(0.0, abs=1e-12)  # luminance-free
    assert wm.saturation_uv(np.zeros(3)) == 0.0  # black is not coloured


def test_light_return_by_hand():
    xyz = np.zeros((2, 2, 3))
    xyz[..., 1] = [[0.5, 0.8], [1.0, 1.0]]
    alpha = np.array([[1.0, 0.5], [0.0, 0.0]])  # background pixels (Y = 1, the dome) do not count
    assert wm.light_return(xyz, alpha) == pytest.approx((0.5 + 0.4) / 1.5)
    assert wm.light_return(xyz, alpha, white_y=2.0) == pytest.approx((0.5 + 0.4) / 3.0)
    assert wm.light_return(xyz, np.zeros((2, 2))) == 0.0
    with pytest.raises(InputError):
        wm.light_return(xyz, np.ones((3, 3)))


def test_fire_by_hand():
    white = wm.D65_WHITE_XYZ * 0.9
    red = np.array([0.2, 0.1, 0.0])
    xyz = np.array([[white, red]])
    alpha = np.array([[1.0, 1.0]])
    s_red = wm.saturation_uv(red)
    assert wm.fire(xyz, alpha) == pytest.approx(0.1 * s_red / 2.0, rel=1e-12)
    assert wm.fire(xyz, alpha, min_saturation=s_red + 1e-6) == 0.0
    # a stone of one colour has no fire about its own mean chromaticity
    same = np.array([[red, red * 3.0]])
    assert wm.fire(same, alpha, reference="mean") == pytest.approx(0.0, abs=1e-12)
    assert wm.fire(same, alpha) == pytest.approx((0.1 + 0.3) * s_red / 2.0, rel=1e-12)
    with pytest.raises(InputError):
        wm.fire(xyz, alpha, reference="grey")


def test_scintillation_by_hand():
    def img(ys):
        x = np.zeros((1, len(ys), 3))
        x[..., 1] = ys
        return x

    a = np.ones((1, 2))
    assert wm.scintillation(img([1.0, 0.0]), a, [(img([0.0, 1.0]), a)]) == pytest.approx(1.0)
    assert wm.scintillation(img([1.0, 0.5]), a, [(img([1.0, 0.5]), a)]) == 0.0
    # |1-1| + |1-0| over (2) + (1): 1/3; averaged with an unchanged tilt: 1/6
    assert wm.scintillation(img([1.0, 1.0]), a, [(img([1.0, 0.0]), a)]) == pytest.approx(1 / 3)
    assert wm.scintillation(
        img([1.0, 1.0]), a, [(img([1.0, 0.0]), a), (img([1.0, 1.0]), a)]
    ) == pytest.approx(1 / 6)
    # a pixel the stone leaves under the tilt does not count (weights min(alpha0, alphak))
    assert wm.scintillation(img([1.0, 1.0]), a, [(img([1.0, 0.0]), np.array([[1.0, 0.0]]))]) == 0.0
    with pytest.raises(InputError):
        wm.scintillation(img([1.0]), np.ones((1, 1)), [])
