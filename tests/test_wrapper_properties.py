"""Property-based checks of the Fresnel and thin-film wrappers: energy is conserved and every
output is physical over random inputs (hypothesis)."""

from __future__ import annotations

import importlib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

# the modules (``warpoptics.optics`` re-exports functions with the same names)
fr = importlib.import_module("warpoptics.optics.fresnel")
jo = importlib.import_module("warpoptics.optics.jones")
tf = importlib.import_module("warpoptics.optics.thinfilm")

_PROP = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@_PROP
@given(
    cos_i=st.floats(0.0, 1.0),
    n1=st.floats(1.0, 4.0),
    n2=st.floats(1.0, 4.0),
    k2=st.one_of(st.just(0.0), st.floats(1e-6, 50.0)),
)
def test_fresnel_power_is_physical(device, cos_i, n1, n2, k2):
    rs, rp, ts, tp = fr.fresnel(np.array([cos_i]), n1, n2 + 1j * k2, device=device)
    Rs, Rp, Ts, Tp = fr.fresnel_power(np.array([cos_i]), n1, n2 + 1j * k2, device=device)
    for x in (rs, rp, ts, tp, Rs, Rp, Ts, Tp):
        assert np.all(np.isfinite(x))
    # energy: R + T = 1 (float32: 2e-4), reflectances in [0, 1]; at exactly grazing incidence the
    # normal flux is zero and T (a flux ratio) is reported as 0
    for R, T in ((Rs, Ts), (Rp, Tp)):
        assert -1e-6 <= R[0] <= 1 + 1e-5 and T[0] >= -1e-5 and R[0] + T[0] <= 1 + 2e-4
        if cos_i > 1e-3:
            assert R[0] + T[0] == pytest.approx(1.0, abs=2e-4)
    # an interface turns a coherency matrix into a Hermitian PSD one with DOP <= 1
    m = np.zeros((1, 2, 2), complex)
    m[0, 0, 0], m[0, 1, 1] = rs[0], rp[0]
    j = jo.coherency_apply(m, np.eye(2)[None] * 0.5, device=device)
    assert np.allclose(j, np.conj(np.swapaxes(j, -1, -2)), atol=1e-6)
    assert np.linalg.eigvalsh(j).min() >= -1e-6
    p = jo.dop(j, device=device)
    assert np.all(np.isfinite(p)) and np.all((p >= 0) & (p <= 1 + 1e-6))


@_PROP
@given(
    layers=st.lists(
        st.tuples(st.floats(1.0, 3.0), st.floats(0.0, 2.0), st.floats(0.0, 5000.0)), min_size=0, max_size=5
    ),
    angle=st.floats(0.0, 90.0),
    n_sub=st.floats(1.0, 3.0),
    k_sub=st.floats(0.0, 5.0),
    wl=st.floats(300.0, 1000.0),
)
def test_thin_film_energy_never_exceeds_one(device, layers, angle, n_sub, k_sub, wl):
    n = [a + 1j * b for a, b, _ in layers]
    d = [c for _, _, c in layers]
    for pol in ("s", "p"):
        r = tf.reflectance(wl, n, d, 1.0, n_sub + 1j * k_sub, angle=angle, polarization=pol, device=device)
        t = tf.transmittance(wl, n, d, 1.0, n_sub + 1j * k_sub, angle=angle, polarization=pol, device=device)
        assert np.isfinite(r) and np.isfinite(t)
        assert -1e-6 <= r <= 1 + 1e-5 and t >= -1e-6
        assert r + t <= 1 + 1e-4
        if all(b == 0 for b, *_ in [(x[1],) for x in layers]) and k_sub == 0:
            assert r + t == pytest.approx(1.0, abs=1e-4)
