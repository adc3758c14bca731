"""geometry.directions: the polar angle and azimuth of the lat-long lookup against NumPy's float64
arccos/arctan2 (an independent implementation), over the sphere and where polynomial atan
approximations go wrong: the poles, the axes, the octant split at tan(pi/8), the branch cut."""

from __future__ import annotations

import numpy as np
import pytest

from warpoptics.geometry.directions import polar_azimuths

# float32 carries ~6e-8 relative: a few ulp of pi is 3e-7 rad (2e-4 of a texel of a 4k map)
TOL = 4.0e-7


def _reference(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    dd = d.astype(np.float64)
    n = np.linalg.norm(dd, axis=-1)
    return np.arccos(np.clip(dd[..., 2] / n, -1.0, 1.0)), np.arctan2(dd[..., 1], dd[..., 0])


def _angle_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * (a - b))))  # modulo 2 pi: -pi and pi are one azimuth


def test_random_directions_match_numpy() -> None:
    rng = np.random.default_rng(5)
    d = rng.normal(size=(200_000, 3)).astype(np.float32)
    d[:2000, :2] *= 1e-4  # within 1e-4 rad of the poles, where acos(z) loses its digits
    t = np.float32(np.tan(np.pi / 8))
    d[2000:4000, 1] = d[2000:4000, 0] * t * (1 + rng.uniform(-1e-6, 1e-6, 2000)).astype(np.float32)
    d[4000:6000, 1] = -d[4000:6000, 0] * (1 + rng.uniform(-1e-6, 1e-6, 2000)).astype(np.float32)
    d *= rng.uniform(0.5, 3.0, (len(d), 1)).astype(np.float32)  # any length
    theta, phi = polar_azimuths(d)
    t_ref, p_ref = _reference(d)
    assert np.max(np.abs(theta - t_ref)) < TOL
    assert np.max(_angle_error(phi, p_ref)) < TOL


@pytest.mark.parametrize(
    "d, theta, phi",
    [
        ((1, 0, 0), np.pi / 2, 0.0),
        ((0, 1, 0), np.pi / 2, np.pi / 2),
        ((-1, 0, 0), np.pi / 2, np.pi),
        ((0, -1, 0), np.pi / 2, -np.pi / 2),
        ((0, 0, 1), 0.0, 0.0),
        ((0, 0, -1), np.pi, 0.0),
        ((1, 1, np.sqrt(2)), np.pi / 4, np.pi / 4),
        ((-1, -1, 0), np.pi / 2, -3 * np.pi / 4),
        ((0, 0, 0), 0.0, 0.0),  # not a direction: finite angles, never NaN
    ],
)
def test_exact_points(d, theta, phi) -> None:
    t, p = polar_azimuths(np.array(d, dtype=np.float32))
    assert float(t) == pytest.approx(theta, abs=TOL)
    assert float(p) == pytest.approx(phi, abs=TOL)


def test_lookup_follows_the_layout() -> None:
    """The angles put the lat-long lookup where latlong_uv (the NumPy twin) says, to 1e-6 in u, v."""
    from warpoptics.stages.environment import latlong_uv

    rng = np.random.default_rng(9)
    d = rng.normal(size=(10_000, 3)).astype(np.float32)
    theta, phi = polar_azimuths(d)
    uv = latlong_uv(d)
    u = np.mod(0.5 - phi / (2 * np.pi), 1.0)
    du = np.abs(u - uv[:, 0])
    assert np.max(np.minimum(du, 1.0 - du)) < 1e-6
    assert np.max(np.abs(theta / np.pi - uv[:, 1])) < 1e-6
