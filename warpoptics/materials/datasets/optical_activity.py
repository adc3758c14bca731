"""Optical activity (rotatory power) of crystals, as plain data.

Each entry of :data:`ROTATORY_DISPERSION` is a Drude sum for the rotatory power along the optic
axis, rho(lambda) = sum_i A_i / (lambda^2 - lambda_i^2) in degrees per millimetre with lambda in
micrometres, given as ``terms`` ((A_i, lambda_i^2), ...), its validity range in nm and its
source; ``perpendicular_ratio`` is G11 / G33, the gyration perpendicular to the axis relative to
that along it, used by ``optics.plate.gyration_rotatory_power``.

Provenance
----------
- quartz: P. Drude, *Lehrbuch der Optik* (1900; *The Theory of Optics*, 1902, natural
  rotation): rho = 12.200 / (lambda^2 - 0.010627) - 5.046 / lambda^2, fitted to the
  measurements of Soret & Sarasin (1882) over the visible and near UV; the constant
  lambda_1^2 = 0.010627 um^2 and the second ("unknown", at lambda^2 = 0) term are the ones
  T. M. Lowry and W. R. Coode-Adams, Phil. Trans. R. Soc. A 226, 391 (1927) start from.  It
  gives 21.71 deg/mm at the sodium D line, 17.33 at C (656.3 nm) and 32.71 at F (486.1 nm),
  against 21.72, 17.31 and 32.72 measured (Soret & Sarasin and others, as tabulated in
  Winkelmann, Handbuch der Physik); tests hold it to those within 0.2 %.
  Right-handed (dextrorotatory) and left-handed quartz rotate by the same amount in opposite
  senses.  Perpendicular to the axis the gyration of quartz is reported of opposite sign and
  roughly half as large, but the values scatter between sources and none is used here; the
  default ratio is 0, the usual approximation rho(theta) = rho_axis cos^2 theta.  The G11
  term grows as sin^2 theta, away from the axis, where the linear birefringence dominates
  the coupling (tau / (delta / 2) < 0.1 beyond the third ring of a 2 mm plate).
"""

from __future__ import annotations

ROTATORY_DISPERSION = {
    "quartz": dict(
        terms=((12.200, 0.010627), (-5.046, 0.0)),
        range_nm=(230.0, 2000.0),
        perpendicular_ratio=0.0,
        source="Drude 1900 (Lehrbuch der Optik), fit to Soret & Sarasin 1882: "
        "rho = 12.200/(lambda^2 - 0.010627) - 5.046/lambda^2 deg/mm, lambda in um",
    ),
}
