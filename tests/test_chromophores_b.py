"""Band sets of quartz, olivine, zoisite, cordierite, tourmaline, topaz and zircon against what their
sources state.  (The face-up hues of their varieties are checked in tests/test_varieties.py.)

Band sets fitted to a measured spectrum are compared with it in tests/test_chromophore_spectra.py;
for the others no absorption coefficients with a stated concentration were available (see each
host module), so the checks against the sources are of band positions (within 5 nm of the maxima
stated in the sources' text, ``tests/data/chromophores/b_band_centres.csv``) and of the stated
polarization orderings (``b_polarization_order.csv``).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from warpoptics.materials import chromophores as C

DATA = Path(__file__).parent / "data" / "chromophores"


def _rows(name: str) -> list[dict]:
    with open(DATA / name, encoding="utf-8") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


CENTRES = _rows("b_band_centres.csv")
ORDERS = _rows("b_polarization_order.csv")


def _unit(host: str, chromophore: str) -> dict[str, float]:
    return {chromophore: C.band_set(host, chromophore).reference_concentration}


@pytest.mark.parametrize("row", CENTRES, ids=lambda r: f"{r['host']}-{r['chromophore']}-{r['centre_nm']}")
def test_band_maximum_where_the_source_states_it(row, device):
    """alpha(λ) of the band set peaks within 5 nm of the maximum the source states (a local
    maximum of the summed bands, so overlapping bands of the same set count)."""
    c = float(row["centre_nm"])
    lam = np.arange(c - 40.0, c + 40.0 + 1e-9, 0.25)
    a = C.chromophore_alpha(
        row["host"], _unit(row["host"], row["chromophore"]), lam, row["polarization"], device=device
    )
    inner = (a[1:-1] >= a[:-2]) & (a[1:-1] >= a[2:]) & (a[1:-1] > 0)
    peaks = lam[1:-1][inner]
    assert peaks.size, f"no maximum within 40 nm of {c} nm"
    nearest = peaks[np.argmin(np.abs(peaks - c))]
    assert abs(nearest - c) <= 5.0, f"maximum at {nearest} nm, stated {row['as_stated']}"


@pytest.mark.parametrize(
    "row", ORDERS, ids=lambda r: f"{r['host']}-{r['chromophore']}-{r['stronger']}>{r['weaker']}"
)
def test_polarization_order_stated_by_the_source(row, device):
    host, name = row["host"], row["chromophore"]
    lam = np.array([float(row["wavelength_nm"])])
    strong = C.chromophore_alpha(host, _unit(host, name), lam, row["stronger"], device=device)[0]
    weak = C.chromophore_alpha(host, _unit(host, name), lam, row["weaker"], device=device)[0]
    assert strong > 0
    assert strong > float(row["ratio_min"]) * weak, row["as_stated"]


def test_every_band_set_says_what_it_is():
    """Each of these band sets cites its source; one fitted to a measured spectrum names the file
    (tests/test_chromophore_spectra.py compares them) and says what is still chosen; the others,
    having no measured absorption coefficient, say in their note what was chosen."""
    spectra = {p.name for p in (DATA / "spectra").glob("*.csv")}
    for host in ("quartz", "olivine", "zoisite", "cordierite", "tourmaline", "topaz", "zircon"):
        for name in C.chromophores(host):
            bs = C.band_set(host, name)
            assert bs.source and "chosen" in bs.note, (host, name)
            if "measured:" in bs.note:
                assert any(f in bs.source for f in spectra), (host, name)
    # every stated centre belongs to a band set that exists
    assert {(r["host"], r["chromophore"]) for r in CENTRES} <= {
        (h, n) for h in C.hosts() for n in C.chromophores(h)
    }


def test_linear_in_concentration_and_tail_sets_the_violet(device):
    """Beer's law in the data as used: doubling a concentration doubles alpha; citrine's Fe3+ is
    an edge, rising towards the violet."""
    lam = np.array([400.0, 450.0, 500.0, 600.0])
    one = C.chromophore_alpha("tourmaline", {"Cu2+": 1.0, "Mn3+": 0.3}, lam, "o", device=device)
    two = C.chromophore_alpha("tourmaline", {"Cu2+": 2.0, "Mn3+": 0.6}, lam, "o", device=device)
    np.testing.assert_allclose(two, 2.0 * one, rtol=1e-6)
    fe = C.chromophore_alpha("quartz", {"Fe3+": 1.0}, lam, "o", device=device)
    assert fe[0] == pytest.approx(1.0, rel=1e-5)  # the edge's stated value at 400 nm
    assert np.all(np.diff(fe) < 0)
