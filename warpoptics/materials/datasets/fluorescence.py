"""Luminescent centres as data: excitation (absorption) bands, emission bands, quantum yield.

Each entry of :data:`CENTRES` has

``excitation``  Gaussian bands (centre nm, FWHM nm, relative height) of the centre's absorption;
                scaled so that its maximum is ``peak_alpha_per_mm`` (1/mm, base e)
``peak_alpha_per_mm``  the absorption coefficient at the excitation maximum of the library's
                "medium" stone (an illustrative strength: real stones span orders of magnitude;
                scenes scale it with ``strength``)
``emission``    Gaussian bands (centre nm, FWHM nm, relative height) of the emitted photon
                spectrum (normalised to unit area by ``materials.fluorescence``)
``quantum_yield`` photons emitted per photon the centre absorbs
``source``      where the band positions and the yield come from
``fit``         what of it is a fit: every spectrum here is a sum of Gaussians placed on the
                published band positions, not a digitised measurement

Provenance
----------
- **N3 (diamond, blue)**: the N3 centre (three nitrogen atoms around a vacancy), zero-phonon line
  415.2 nm (2.985 eV) in absorption and emission, absorption vibronic band on the short side
  (maxima near 403, 394, 384 nm, tail to about 340 nm), emission sideband on the long side with
  maxima near 428, 439 and 452 nm reaching about 500 nm; A. M. Zaitsev, *Optical Properties of
  Diamond: A Data Handbook*, Springer 2001, the 2.985 eV centre; G. Davies, J. Phys. C 7, 3797
  (1974).  Quantum efficiency 0.29: M. F. Thomaz, G. Davies, Proc. R. Soc. Lond. A 362, 405
  (1978), from the measured decay time.  The 365 nm long-wave lamp excites the vibronic band,
  which is why N3 diamonds glow blue under it.
- **Cr3+ in corundum (ruby, red)**: excitation = the Cr3+ bands of the library's ruby (McClure
  1962: 4A2 -> 4T2 at 556 nm, 4A2 -> 4T1 at 407 nm, E perpendicular to c); emission R1 694.3 nm,
  R2 692.9 nm and the vibronic sideband to about 720 nm (T. H. Maiman et al., Phys. Rev. 123,
  1151 (1961)); quantum efficiency 0.7 of the same paper's measurement (room temperature).
- **Cr3+ in spinel (red spinel, red)**: 4A2 -> 4T2 near 540 nm and 4A2 -> 4T1 near 400 nm;
  emission R line 685.5 nm with the N lines at 686-700 nm and a sideband to about 720 nm
  (W. Mikenda, A. Preisinger, J. Lumin. 26, 53 and 67 (1981)).  Yield 0.5: illustrative (no
  single measured value for natural spinel; of the order of ruby's).
- **Uranyl (uranium glass, green)**: UO2(2+) in a silicate glass absorbs below about 480 nm
  (weak vibronic bands near 420-470 nm, strong absorption below 420 nm, the 365 nm lamp's
  range) and emits the vibronic progression with maxima near 505, 525, 550 and 575 nm
  (E. Rabinowitch, R. L. Belford, *Spectroscopy and Photochemistry of Uranyl Compounds*,
  Pergamon 1964, ch. 2 and 7).  Yield 0.5: illustrative.
"""

from __future__ import annotations

__all__ = ["CENTRES"]

CENTRES: dict[str, dict] = {
    "N3": dict(
        excitation=(
            (415.2, 3.0, 0.55),
            (403.0, 10.0, 0.85),
            (394.0, 12.0, 1.0),
            (384.0, 14.0, 0.8),
            (365.0, 30.0, 0.45),
        ),
        peak_alpha_per_mm=0.05,
        emission=(
            (415.2, 2.5, 0.12),
            (428.0, 10.0, 0.7),
            (439.0, 14.0, 1.0),
            (452.0, 18.0, 0.8),
            (475.0, 30.0, 0.3),
        ),
        quantum_yield=0.29,
        source="N3 centre: Zaitsev 2001, Davies 1974 (bands); Thomaz & Davies 1978 (yield 0.29)",
        fit="Gaussian bands on the published maxima; peak alpha illustrative",
    ),
    "Cr3+ corundum": dict(
        excitation=((556.0, 80.0, 1.0), (407.0, 60.0, 1.15)),
        peak_alpha_per_mm=0.30,
        emission=((694.3, 1.5, 1.0), (692.9, 1.5, 0.6), (705.0, 12.0, 0.12), (715.0, 15.0, 0.08)),
        quantum_yield=0.7,
        source="Cr3+ in corundum: McClure 1962 (absorption), Maiman et al. 1961 (emission, yield 0.7)",
        fit="Gaussian bands on the published maxima; peak alpha illustrative",
    ),
    "Cr3+ spinel": dict(
        excitation=((540.0, 80.0, 1.0), (400.0, 60.0, 1.1)),
        peak_alpha_per_mm=0.25,
        emission=((685.5, 1.5, 1.0), (687.5, 2.5, 0.5), (697.0, 6.0, 0.45), (710.0, 14.0, 0.25)),
        quantum_yield=0.5,
        source="Cr3+ in spinel: Mikenda & Preisinger 1981 (bands); yield 0.5 illustrative",
        fit="Gaussian bands on the published maxima; peak alpha and yield illustrative",
    ),
    "uranyl glass": dict(
        excitation=((330.0, 70.0, 1.0), (415.0, 20.0, 0.35), (440.0, 18.0, 0.15), (470.0, 16.0, 0.05)),
        peak_alpha_per_mm=0.4,
        emission=((505.0, 16.0, 0.55), (525.0, 20.0, 1.0), (550.0, 24.0, 0.8), (575.0, 28.0, 0.35)),
        quantum_yield=0.5,
        source="uranyl in glass: Rabinowitch & Belford 1964 (bands); yield 0.5 illustrative",
        fit="Gaussian bands on the published maxima; peak alpha and yield illustrative",
    ),
}
