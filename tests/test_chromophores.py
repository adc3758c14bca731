"""Chromophore band sets (materials.chromophores): the laws against closed forms, linearity in
concentration, name resolution, the host/variety scene hook and its errors.  Band sets of real
hosts are checked against the digitized points of their sources (tests/data/chromophores/)."""

from __future__ import annotations

import csv
import types
from pathlib import Path

import numpy as np
import pytest

import warpoptics as wo
from warpoptics.errors import InputError
from warpoptics.materials import chromophores as C
from warpoptics.materials.absorption import AbsorptionSpectrum, Band
from warpoptics.materials.datasets.chromophores import HOSTS

HC = 1239.841984

# a test host: two polarizations, two band sets (not package data)
_TEST_HOST = types.SimpleNamespace(
    HOST=dict(
        polarizations=("o", "e"),
        index=("constants", 1.768, 1.760, 0.018),
        source="test constants",
        description="a uniaxial test crystal",
    ),
    BAND_SETS={
        "Cr3+": dict(
            unit="ppma",
            reference_concentration=100.0,
            bands={
                "o": ((550.0, 30.0, 0.8, "gaussian_wavenumber"), (410.0, 25.0, 1.2, "gaussian")),
                "e": ((565.0, 30.0, 0.5, "gaussian"),),
            },
            tails={"o": (350.0, 2.0, 0.25)},
            source="test data",
        ),
        "Fe2+-Ti4+": dict(
            unit="ppma",
            reference_concentration=50.0,
            bands={"o": ((580.0, 60.0, 0.4, "lorentzian"),), "e": ((700.0, 80.0, 0.3, "gaussian"),)},
            source="test data",
        ),
        "Fe3+": dict(
            unit="ppma",
            reference_concentration=1000.0,
            bands={"o": ((450.0, 5.0, 0.1, "gaussian"),), "e": ()},
            source="test data",
        ),
    },
)


@pytest.fixture
def test_host(monkeypatch):
    monkeypatch.setitem(HOSTS, "testcrystal", _TEST_HOST)
    monkeypatch.setattr(C, "_band_sets", {})
    yield "testcrystal"


def _closed_form(lam, conc):
    lam = np.asarray(lam, float)
    out_o = np.zeros_like(lam)
    out_e = np.zeros_like(lam)
    f_cr = conc.get("Cr3+", 0.0) / 100.0
    out_o += f_cr * 0.8 * np.exp(-0.5 * (550.0 * (550.0 / lam - 1.0) / 30.0) ** 2)
    out_o += f_cr * 1.2 * np.exp(-0.5 * ((lam - 410.0) / 25.0) ** 2)
    out_o += f_cr * 2.0 * np.exp(np.minimum((HC / lam - HC / 350.0) / 0.25, 60.0))
    out_e += f_cr * 0.5 * np.exp(-0.5 * ((lam - 565.0) / 30.0) ** 2)
    f_ft = conc.get("Fe2+-Ti4+", 0.0) / 50.0
    out_o += f_ft * 0.4 * 60.0**2 / ((lam - 580.0) ** 2 + 60.0**2)
    out_e += f_ft * 0.3 * np.exp(-0.5 * ((lam - 700.0) / 80.0) ** 2)
    return out_o, out_e


def test_alpha_matches_closed_form_and_is_linear(test_host, device):
    lam = np.linspace(380.0, 780.0, 81)
    conc = {"Cr3+": 250.0, "Fe2+-Ti4+": 20.0}
    ao = C.chromophore_alpha(test_host, conc, lam, "o", device=device)
    ae = C.chromophore_alpha(test_host, conc, lam, "e", device=device)
    ref_o, ref_e = _closed_form(lam, conc)
    np.testing.assert_allclose(ao, ref_o, rtol=2e-5, atol=1e-7)
    np.testing.assert_allclose(ae, ref_e, rtol=2e-5, atol=1e-7)
    # Beer's law: doubling every concentration doubles alpha; the sum of parts is the whole
    a2 = C.chromophore_alpha(test_host, {k: 2 * v for k, v in conc.items()}, lam, "o", device=device)
    np.testing.assert_allclose(a2, 2 * ao, rtol=1e-5)
    parts = sum(C.chromophore_alpha(test_host, {k: v}, lam, "o", device=device) for k, v in conc.items())
    np.testing.assert_allclose(parts, ao, rtol=1e-5, atol=1e-8)
    assert np.all(C.chromophore_alpha(test_host, {"Cr3+": 0.0}, lam, "o", device=device) == 0)


def test_gaussian_wavenumber_profile_is_a_gaussian_in_energy(device):
    """Band shape 2: half maximum where the wavenumber is sigma*sqrt(2 ln 2) from the centre."""
    c, w = 550.0, 30.0
    sigma_nu = w / c**2  # 1/nm
    dnu = sigma_nu * np.sqrt(2 * np.log(2))
    lam = np.array([1 / (1 / c + dnu), c, 1 / (1 / c - dnu)])
    s = AbsorptionSpectrum.from_bands([Band(c, w, 1.0, "gaussian_wavenumber")], step_nm=0.01, device=device)
    np.testing.assert_allclose(s.alpha(lam), [0.5, 1.0, 0.5], atol=2e-4)
    # asymmetric in wavelength: wider on the red side
    assert lam[2] - c > c - lam[0]


def test_urbach_tail_closed_form(device):
    lam = np.array([300.0, 350.0, 400.0, 500.0])
    a = C.urbach_tail_alpha(lam, 350.0, 3.0, 0.2, device=device)
    np.testing.assert_allclose(a, 3.0 * np.exp((HC / lam - HC / 350.0) / 0.2), rtol=1e-5)
    assert C.urbach_tail_alpha.wp is C.urbach_tail


def test_names_resolve_and_errors(test_host):
    assert C.resolve_chromophore(test_host, "cr") == "Cr3+"
    assert C.resolve_chromophore(test_host, "CR3+") == "Cr3+"
    assert C.resolve_chromophore(test_host, "Fe-Ti") == "Fe2+-Ti4+"
    assert C.resolve_chromophore(test_host, "Fe3+") == "Fe3+"
    with pytest.raises(InputError, match="chromophores.Ni: no such chromophore"):
        C.resolve_chromophore(test_host, "Ni")
    with pytest.raises(InputError, match="unknown chromophore host.*did you mean 'testcrystal'"):
        C.host_info("testcrystl")
    with pytest.raises(InputError, match="chromophores.Cr.*>= 0"):
        C.normalize_concentrations(test_host, {"Cr": -1.0})
    with pytest.raises(InputError, match="chromophores.Cr.*must be a number"):
        C.normalize_concentrations(test_host, {"Cr": "lots"})
    with pytest.raises(InputError, match="given twice"):
        C.normalize_concentrations(test_host, {"Cr": 1.0, "Cr3+": 2.0})
    with pytest.raises(InputError, match="no such polarization"):
        C.chromophore_alpha(test_host, {"Cr": 1.0}, [500.0], "x")


def test_host_alpha_and_material(test_host, device):
    so, se = C.host_alpha(test_host, {"Cr": 100.0})
    lam = np.array([410.0, 550.0, 565.0])
    ref_o, ref_e = _closed_form(lam, {"Cr3+": 100.0})
    np.testing.assert_allclose(so.alpha(lam), ref_o, rtol=1e-5)
    np.testing.assert_allclose(se.alpha(lam), ref_e, rtol=1e-5)
    assert "Cr3+ 100 ppma: test data" in so.source
    mat = wo.materials.material_from_spec({"host": test_host, "chromophores": {"Cr": 100.0}})
    assert isinstance(mat, wo.materials.Uniaxial)
    np.testing.assert_allclose(mat.alpha(lam), np.stack([ref_o, ref_e], axis=-1), rtol=1e-4)
    assert mat.chromophore_concentrations == {"Cr3+": 100.0}


@pytest.mark.parametrize(
    ("spec", "match"),
    [
        ({"host": "testcrystal", "chromophores": {"Ni": 1}}, r"chromophores\.Ni: no such chromophore"),
        ({"host": "testcrystal", "chromophores": [1]}, "chromophore = concentration"),
        ({"host": "nowhere"}, "host = 'nowhere': unknown chromophore host"),
        ({"host": "testcrystal", "base": "ruby"}, "exactly one of"),
        ({"base": "spinel", "chromophores": {"Cr": 1}}, "base = 'spinel': has no chromophores"),
        ({"host": "testcrystal", "chromophores": {"Cr": 1}, "bands": []}, "bands: give either"),
    ],
)
def test_scene_material_errors(test_host, spec, match):
    with pytest.raises(InputError, match=match):
        wo.materials.material_from_spec(spec)


# ----------------------------------------------------------------------------------------------
# Band sets of the corundum, beryl, chrysoberyl, spinel, garnet and diamond hosts against the band
# maxima and polarization orders their sources state (tests/data/chromophores/a_*.csv)
# ----------------------------------------------------------------------------------------------

DATA = Path(__file__).parent / "data" / "chromophores"


def _rows(name: str) -> list[dict]:
    with open(DATA / name, encoding="utf-8") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


STATED_CENTRES = _rows("a_band_centres.csv")
STATED_ORDERS = _rows("a_polarization_order.csv")


def _reference(host: str, chromophore: str) -> dict[str, float]:
    return {chromophore: C.band_set(host, chromophore).reference_concentration}


@pytest.mark.parametrize(
    "row",
    STATED_CENTRES,
    ids=lambda r: f"{r['host']}-{r['chromophore']}-{r['polarization']}-{r['centre_nm']}",
)
def test_band_maximum_where_the_source_states_it(row, device):
    """A local maximum of the band set's alpha(λ) lies within 5 nm of each stated band maximum."""
    c = float(row["centre_nm"])
    lam = np.arange(c - 40.0, c + 40.0 + 1e-9, 0.25)
    host, name = row["host"], row["chromophore"]
    a = C.chromophore_alpha(host, _reference(host, name), lam, row["polarization"], device=device)
    inner = (a[1:-1] >= a[:-2]) & (a[1:-1] >= a[2:]) & (a[1:-1] > 0)
    peaks = lam[1:-1][inner]
    assert peaks.size, f"no maximum within 40 nm of {c} nm"
    nearest = peaks[np.argmin(np.abs(peaks - c))]
    assert abs(nearest - c) <= 5.0, f"maximum at {nearest} nm, stated {row['as_stated']}"


@pytest.mark.parametrize("row", STATED_ORDERS, ids=lambda r: f"{r['chromophore']}-{r['wavelength_nm']}")
def test_polarization_order_stated_by_the_source(row, device):
    host, name = row["host"], row["chromophore"]
    lam = np.array([float(row["wavelength_nm"])])
    strong = C.chromophore_alpha(host, _reference(host, name), lam, row["stronger"], device=device)[0]
    weak = C.chromophore_alpha(host, _reference(host, name), lam, row["weaker"], device=device)[0]
    assert strong > float(row["ratio_min"]) * weak > 0 or (strong > 0 and weak == 0), row["as_stated"]


def test_every_band_set_of_these_hosts_says_what_it_is():
    """Each band set names its source; a set fitted to a measured spectrum says "measured" and names
    the spectrum file it is tested against (tests/test_chromophore_spectra.py); any other set
    says in its note that its strengths were chosen."""
    spectra = {p.name for p in (DATA / "spectra").glob("*.csv")}
    for host in ("corundum", "beryl", "chrysoberyl", "spinel", "almandine", "spessartine", "grossular"):
        for name in C.chromophores(host):
            bs = C.band_set(host, name)
            assert bs.source, (host, name)
            if "measured:" in bs.note:
                assert any(f in bs.source for f in spectra), (host, name)
            else:
                assert "chosen" in bs.note, (host, name)
    for host in ("andradite", "diamond"):
        for name in C.chromophores(host):
            assert "chosen" in C.band_set(host, name).note
