"""Colour conversions and the Smits–Meyer clip, checked against colour-science and geometry."""

import colour
import numpy as np
import pytest

from warpoptics import color, spectra
from warpoptics.commands.spectrum import clip_comparison


def test_matrices_match_colour_science():
    rng = np.random.default_rng(0)
    xyz = rng.random((50, 3))
    cs = colour.RGB_COLOURSPACES["sRGB"]
    npm = colour.normalised_primary_matrix(cs.primaries, cs.whitepoint)
    np.testing.assert_allclose(color.SRGB_TO_XYZ, npm, atol=1e-15)
    # against the IEC 61966-2-1 matrices as colour-science stores them (rounded to 4 decimals)
    np.testing.assert_allclose(color.xyz_to_srgb_linear(xyz), xyz @ cs.matrix_XYZ_to_RGB.T, atol=1e-3)
    np.testing.assert_allclose(color.srgb_linear_to_xyz(xyz), xyz @ cs.matrix_RGB_to_XYZ.T, atol=1e-4)
    np.testing.assert_allclose(color.srgb_linear_to_xyz(color.xyz_to_srgb_linear(xyz)), xyz, atol=1e-12)


def test_in_gamut_colours_are_unchanged(device):
    rng = np.random.default_rng(1)
    rgb = rng.uniform(0.001, 0.999, (2000, 3))
    out = color.gamut_clip(color.srgb_linear_to_xyz(rgb), 1.0, device=device)
    np.testing.assert_allclose(out, rgb, atol=2e-6)  # float32 matrix round trip


def test_clipped_colours_keep_y_and_land_on_the_boundary(device):
    rng = np.random.default_rng(2)
    # random chromaticities from the spectral locus outward, luminance inside (0, 1)
    rgb = rng.uniform(-0.8, 1.6, (5000, 3))
    xyz = color.srgb_linear_to_xyz(rgb)
    y = xyz[:, 1]
    keep = (y > 0.02) & (y < 0.98) & ((rgb < 0) | (rgb > 1)).any(axis=1)
    xyz = xyz[keep]
    out = color.gamut_clip(xyz, 1.0, device=device)
    out_xyz = color.srgb_linear_to_xyz(out)
    np.testing.assert_allclose(out_xyz[:, 1], xyz[:, 1], atol=3e-6)  # Y held (Smits & Meyer 1990 §3)
    # on the boundary: one channel at 0 or 1 within float32 round-off
    dist = np.minimum(np.abs(out), np.abs(out - 1)).min(axis=1)
    assert dist.max() < 3e-6
    assert out.min() >= 0 and out.max() <= 1
    # moved along the line toward the grey (Y, Y, Y): out - rgb parallel to grey - rgb
    src = color.xyz_to_srgb_linear(xyz)
    grey = out_xyz[:, 1:2] * np.ones(3)
    cross = np.cross(out - src, grey - src)
    scale = np.linalg.norm(grey - src, axis=1) ** 2
    assert (np.linalg.norm(cross, axis=1) / scale).max() < 1e-4
    # and no further than needed: the point a little back toward the source is outside the cube
    back = out + 1e-3 * (src - out)
    assert (((back < -1e-7) | (back > 1 + 1e-7)).any(axis=1)).all()


def test_extreme_luminance(device):
    out = color.gamut_clip([[0.5, -0.1, 0.3], [2.0, 3.0, 2.5], [-1.0, -1.0, -1.0]], 1.0, device=device)
    np.testing.assert_allclose(out[0], 0.0)  # Y < 0 -> black
    np.testing.assert_allclose(out[1], 1.0)  # Y > 1 -> white
    np.testing.assert_allclose(out[2], 0.0)
    # HDR: a huge max_value only removes negative components, holding Y
    xyz = color.srgb_linear_to_xyz([4.0, -0.2, 0.5])
    hdr = color.gamut_clip(xyz, 1e30, device=device)
    assert hdr.min() >= 0
    assert color.srgb_linear_to_xyz(hdr)[1] == pytest.approx(xyz[1], rel=1e-5)


def test_spectral_locus_hue_change_is_measured_and_smaller_than_naive(device):
    wl = np.linspace(400.0, 700.0, 301)
    res = clip_comparison(wl, device=device)
    sm, naive = res["hue_shift_smits_meyer"], res["hue_shift_naive"]
    print(
        f"\nCIELAB hue change over 400-700 nm: Smits-Meyer mean {sm.mean():.2f} max {sm.max():.2f} deg;"
        f" per-channel mean {naive.mean():.2f} max {naive.max():.2f} deg"
    )
    # Smits–Meyer: Y exact; per-channel clipping changes Y by up to ~0.12
    assert np.abs(res["dY_smits_meyer"]).max() < 1e-5
    assert np.abs(res["dY_naive"]).max() > 0.05
    # measured: mean 9.0 vs 10.4 deg, max 20.7 vs 41.6 deg — the paper's "hue changes only a little"
    assert sm.max() < 25.0
    assert sm.max() < 0.7 * naive.max()
    assert sm.mean() < naive.mean()


def test_tone_map_and_encoding():
    x = np.array([0.0, 0.18, 1.0, 10.0])
    for curve in ("clip", "reinhard", "filmic"):
        y = color.tone_map(x, curve=curve)
        assert np.all(np.diff(y) >= 0) and y.min() >= 0 and y.max() <= 1
    np.testing.assert_allclose(color.tone_map(x, curve="reinhard"), x / (1 + x))
    assert color.tone_map([1.0], exposure=1.0, curve="clip")[0] == 1.0
    # sRGB transfer function reference values (IEC 61966-2-1)
    np.testing.assert_allclose(
        color.encode_srgb([0.0, 0.0031308, 0.18, 1.0]), [0.0, 0.04045, 0.4613561, 1.0], atol=1e-5
    )
    with pytest.raises(ValueError, match="allowed"):
        color.tone_map(x, curve="aces2")


def test_delta_e2000_reference_pair():
    # Sharma, Wu & Dalal 2005, test pair 1: Lab (50, 2.6772, -79.7751) vs (50, 0, -82.7485): dE00 = 2.0425
    wp_xy = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    a = colour.Lab_to_XYZ([50.0, 2.6772, -79.7751], wp_xy)
    b = colour.Lab_to_XYZ([50.0, 0.0, -82.7485], wp_xy)
    assert color.delta_e2000(a, b) == pytest.approx(2.0425, abs=1e-4)
    assert spectra.LAMBDA_MIN == 360.0
