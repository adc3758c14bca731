"""Fit chromophore band sets to the measured spectra in tests/data/chromophores/spectra/.

For each spectrum file (read with :func:`warpoptics.materials.chromophore_spectra.read_measured_spectrum`)
the bands of the template below (shape fixed; centre, width and peak free; an optional Urbach tail
with its reference wavelength fixed) are fitted with scipy's least squares to the measured alpha
(1/mm, base e, at the sample's concentration): relative residuals at the points of the RMS test
(400-700 nm, alpha above 5 % of the maximum), and absolute residuals, in units of that 5 % floor,
at the other points of 380-720 nm so that the tails stay small where the sample absorbs little.
The script prints the fitted parameters in the form of the host modules' ``bands`` tuples (peak
alpha at the sample's concentration, which is each refitted band set's reference concentration)
and the comparison (:func:`~warpoptics.materials.chromophore_spectra.compare`): band maxima, peak
ratios and RMS relative errors, first of the fit, then of the library's band set as it stands.

    python scripts/fit_chromophore_bands.py [file-name-substring ...]
    python scripts/fit_chromophore_bands.py --joint FITTED.csv CHECK.csv POL

``--joint`` refits the library's POL bands of FITTED's band set to both spectra at once (CHECK's
concentration free, the relative residuals of both at their RMS points) and prints the comparison
with each: what a refit to an independent check spectrum would cost the fitted one.

The templates say which bands a spectrum shows (a choice of the model: how many bands, which
shape); everything fitted comes from the measured points.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

from warpoptics.materials.chromophore_spectra import CRITERIA, compare, read_measured_spectrum, rms_mask

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data" / "chromophores" / "spectra"
HC_EV_NM = 1239.841984

G, GW = "gaussian", "gaussian_wavenumber"
V455 = "V 455 nm"

#: file -> polarization -> (bands [(centre, width, peak, shape[, band set])], tail (reference_nm,
#: alpha, width_ev) or None): initial guesses, the peaks relative to the maximum of the data in
#: 400-700 nm.  A band naming a band set belongs to that set (one of the file's "also" sets), not
#: to the file's chromophore; a tail naming one (a 4th element) is that set's edge as the library
#: has it (reference and slope kept, only its strength fitted: the set's concentration).
TEMPLATES = {
    "corundum_cr3_gia2020_sample1110.csv": {
        "o": (
            [(558, 29, 1, G), (410, 24, 1, G), (505, 20, 0.1, G), (475, 4, 0.03, G), (693.5, 1.2, 0.05, G)],
            None,
        ),
        "e": ([(546, 30, 0.2, G), (398, 25, 1, G), (500, 20, 0.03, G)], None),
    },
    "corundum_v3_gia2020.csv": {
        "o": ([(577.5, 40, 0.35, G), (400, 22, 1, G)], None),
        "e": ([(575, 40, 0.06, G), (405, 20, 1, G)], None),
    },
    "corundum_feti_gia2020.csv": {
        "o": ([(580, 60, 1, GW), (720, 80, 0.4, GW), (400, 60, 0.15, GW)], None),
        "e": ([(707.5, 90, 1, GW), (480, 50, 0.4, GW)], (380.0, 0.1, 0.3)),
    },
    "beryl_cr3_caltech_grr3570.csv": {
        "o": ([(605, 35, 1, G), (433, 25, 1, G), (683, 3, 0.1, G)], (380.0, 0.2, 0.3)),
        "e": ([(638, 40, 1, G), (422, 25, 1, G), (684, 2.5, 0.3, G), (650, 8, 0.2, G)], None),
    },
    "quartz_amethyst_caltech_ameth_bo.csv": {
        "o": ([(542.5, 50, 1, GW)], (400.0, 0.5, 0.25, "Fe3+")),
    },
    "zoisite_v3_caltech_grr1265.csv": {
        "x": ([(545, 45, 1, GW), (420, 40, 0.2, GW)], None),
        "y": ([(605, 30, 1, GW), (530, 30, 0.5, GW), (745, 40, 0.8, GW), (410, 15, 1, GW)], None),
        "z": (
            [
                (605, 30, 0.4, GW),
                (530, 30, 0.2, GW),
                (725, 20, 0.3, GW),
                (442, 20, 1, GW, V455),
                (400, 12, 3, GW, V455),
            ],
            None,
        ),
    },
    "chrysoberyl_cr3_caltech_grr874.csv": {
        "y": ([(565, 35, 0.2, G), (432, 22, 1, G), (405, 20, 0.4, G)], None),
        "z": ([(596, 35, 1, G), (415, 30, 0.6, G), (680, 2.0, 0.2, G)], None),
    },
    "olivine_fe2_caltech_grr418_alpha.csv": {
        "x": (
            [
                (402, 5, 0.3, GW),
                (451, 9, 0.25, GW),
                (493, 9, 0.1, GW),
                (640, 35, 0.2, GW),
                (1052, 120, 4, GW),
                (870, 60, 1.5, GW),
            ],
            (380.0, 0.8, 0.2),
        ),
    },
    "olivine_fe2_caltech_grr418_beta.csv": {
        "y": (
            [
                (402, 5, 0.2, GW),
                (428, 8, 0.1, GW),
                (452, 8, 0.2, GW),
                (470, 8, 0.2, GW),
                (491, 8, 0.2, GW),
                (650, 40, 0.2, GW),
                (1095, 120, 3, GW),
                (880, 60, 1.5, GW),
            ],
            (380.0, 0.8, 0.2),
        ),
    },
    "olivine_fe2_caltech_grr418_gamma.csv": {
        "z": (
            [
                (380, 8, 0.5, GW),
                (430, 8, 0.3, GW),
                (446, 6, 0.2, GW),
                (490, 15, 0.1, GW),
                (638, 30, 0.15, GW),
                (1048, 80, 18, GW),
                (870, 60, 2, GW),
            ],
            None,
        ),
    },
}

#: band sets whose unit is the alpha (1/mm) of one polarization at one wavelength (the measured
#: maximum of the main band), because the source gives no concentration (a shape-only sample) or
#: because the library's varieties are expressed in that unit: file -> (polarization, nm).  Their
#: fitted bands are printed divided by the fit's alpha there (reference concentration 1), and the
#: sample's concentration in that unit is the measured alpha there (the file's "concentration").
#: The other files' units are those of the source (wt% oxide, ppma) at the sample's concentration,
#: or the sample itself (concentration 1.0) where the source gives none.
NORMALIZE = {
    "corundum_feti_gia2020.csv": ("o", 580.0),
    "beryl_cr3_caltech_grr3570.csv": ("o", 605.0),
    "zoisite_v3_caltech_grr1265.csv": ("y", 605.0),
}


def profile(shape: str, lam, c, w):
    lam = np.asarray(lam, float)
    if shape == G:
        return np.exp(-0.5 * ((lam - c) / w) ** 2)
    if shape == GW:
        return np.exp(-0.5 * (c * (c / lam - 1.0) / w) ** 2)
    return w * w / ((lam - c) ** 2 + w * w)


def tail(lam, ref, a, w_ev):
    x = (HC_EV_NM / np.asarray(lam, float) - HC_EV_NM / ref) / w_ev
    return a * np.exp(np.minimum(x, 60.0))


def _bands(params, bands):
    """[(centre, width, peak, shape)] from the free parameters."""
    out, k = [], 0
    for b in bands:
        out.append((params[k], np.exp(params[k + 1]), np.exp(params[k + 2]), b[3]))
        k += 3
    return out, k


def model(params, bands, tl, lam):
    out = np.zeros_like(np.asarray(lam, float))
    fitted, k = _bands(params, bands)
    for c, w, p, shape in fitted:
        out = out + p * profile(shape, lam, c, w)
    if tl is not None and len(tl) > 3:  # an "also" set's edge: only its strength is free
        out = out + tail(lam, tl[0], np.exp(params[k]), tl[2])
    elif tl is not None:
        la, lw = params[k : k + 2]
        out = out + tail(lam, tl[0], np.exp(la), np.exp(lw))
    return out


def fit_one(lam, meas, bands, tl, peaks=()):
    top = np.max(meas[(lam >= 400) & (lam <= 700)])
    p0, lo, hi = [], [], []
    for b in bands:
        c, w, p = b[:3]
        p0 += [c, np.log(w), np.log(max(p * top, 1e-9))]
        lo += [c - 25.0, np.log(0.3), -40.0]
        hi += [c + 25.0, np.log(400.0), 10.0]
    if tl is not None and len(tl) > 3:
        p0 += [np.log(tl[1] * top)]
        lo += [-40.0]
        hi += [10.0]
    elif tl is not None:
        p0 += [np.log(tl[1] * top), np.log(tl[2])]
        lo += [-40.0, np.log(0.02)]
        hi += [10.0, np.log(3.0)]
    mask = rms_mask(lam, meas)
    rest = (~mask) & (lam >= 380.0) & (lam <= 720.0)
    floor = CRITERIA["rms_floor"] * top

    # at each measured maximum: the model's value (relative) and its logarithmic slope, which is
    # zero where the model peaks; both weighted by sqrt(number of RMS points) so that they hold
    # against the many points of the RMS sum (for the slope: a 1 nm offset from the top of a 30 nm
    # wide band weighs about as much as a 20 % residual at every point)
    pk = np.array([lam[np.argmin(np.abs(lam - x))] for x in peaks], float)
    pk_meas = np.array([meas[np.argmin(np.abs(lam - x))] for x in peaks], float)
    pk_at = np.array(list(peaks), float)

    def resid(p):
        m = model(p, bands, tl, lam)
        parts = [(m[mask] - meas[mask]) / meas[mask], 0.5 * (m[rest] - meas[rest]) / floor]
        if len(pk):
            mp = model(p, bands, tl, pk)
            up, dn = model(p, bands, tl, pk_at + 0.5), model(p, bands, tl, pk_at - 0.5)
            wt = np.sqrt(mask.sum())
            parts += [wt * (mp - pk_meas) / pk_meas, wt * 180.0 * (up - dn) / (up + dn)]
        return np.concatenate(parts)

    r = least_squares(resid, p0, bounds=(lo, hi), x_scale="jac", max_nfev=20000)
    return r.x


def describe(params, bands, tl, scale: float = 1.0, band_set=None) -> str:
    """The bands of ``band_set`` (None: the file's own chromophore) as a data-module tuple."""
    fitted, k = _bands(params, bands)
    own = [(f, b) for f, b in zip(fitted, bands, strict=True) if (b[4] if len(b) > 4 else None) == band_set]
    if band_set is not None:  # an "also" set: its unit is its own (first) band's peak alpha
        scale = own[0][0][2] if own else 1.0
        tl = None
    elif tl is not None and len(tl) > 3:  # the edge is another set's
        tl = None
    parts = [f'({c:.1f}, {w:.2f}, {p / scale:.4g}, "{shape}")' for (c, w, p, shape), _ in own]
    s = "(" + ", ".join(parts) + ("," if len(parts) == 1 else "") + ")"
    if tl is not None:
        la, lw = params[k : k + 2]
        s += f"  tail=({tl[0]:.1f}, {np.exp(la) / scale:.4g}, {np.exp(lw):.3f})"
    elif band_set is None and len(bands) * 3 < len(params):  # another set's edge
        s += f"  (edge of another band set: strength {np.exp(params[k]):.4g})"
    return s


def report(result: dict) -> str:
    lines = []
    for pol, r in result.items():
        pk = "; ".join(
            f"{p['measured_nm']:.0f} nm: model max {p['model_nm']:.2f} "
            f"(d {p['centre_error_nm']:.2f} nm), "
            f"alpha {p['model_alpha']:.4g} vs {p['measured_alpha']:.4g} "
            f"({100 * (p['peak_ratio'] - 1):+.1f} %)"
            for p in r["peaks"]
        )
        lines.append(f"    {pol}: RMS {100 * r['rms']:.1f} % over {r['n_rms']} points; {pk}")
    return "\n".join(lines)


def joint(fitted_name: str, check_name: str, pol: str) -> int:
    """The ``--joint`` refit (module docstring)."""
    from warpoptics.materials import chromophores as C

    a, b = read_measured_spectrum(DATA / fitted_name), read_measured_spectrum(DATA / check_name)
    bs = C.band_set(a.host, a.chromophore)
    bands = [(x.center_nm, x.width_nm, x.peak_alpha_per_mm, x.shape) for x in bs.bands[pol]]
    p0 = [v for c, w, pk, _ in bands for v in (c, np.log(w), np.log(pk))] + [0.0]
    ref = bs.reference_concentration
    la, ma = a.wavelength_nm, a.alpha[pol]
    lb, mb = b.wavelength_nm, b.alpha[pol]
    ka, kb = rms_mask(la, ma), rms_mask(lb, mb)
    rest = (~ka) & (la >= 380.0) & (la <= 720.0)
    floor = CRITERIA["rms_floor"] * np.max(ma[(la >= 400) & (la <= 700)])
    sa, sb = a.concentration / ref, b.concentration / ref

    def resid(p):
        m_a = sa * model(p[:-1], bands, None, la)
        m_b = sb * np.exp(p[-1]) * model(p[:-1], bands, None, lb)
        return np.concatenate(
            [(m_a[ka] - ma[ka]) / ma[ka], 0.5 * (m_a[rest] - ma[rest]) / floor, (m_b[kb] - mb[kb]) / mb[kb]]
        )

    p = least_squares(resid, p0, x_scale="jac", max_nfev=20000).x
    print(f"joint refit of {a.host} {a.chromophore} {pol}: {pol}={describe(p[:-1], bands, None, 1.0 / sa)}")
    print(f"  {b.path.name}: concentration {b.concentration * np.exp(p[-1]):.4g} (file: {b.concentration:g})")
    for sp, s in ((a, sa), (b, sb * np.exp(p[-1]))):
        print(f"  {sp.path.name}:")
        print(report({pol: compare(sp, lambda lam, _pol, s=s: s * model(p[:-1], bands, None, lam))[pol]}))
    return 0


def main(argv) -> int:
    if argv[:1] == ["--joint"]:
        return joint(*argv[1:4])
    files = sorted(DATA.glob("*.csv"))
    if argv:
        files = [f for f in files if any(a in f.name for a in argv)]
    for f in files:
        sp = read_measured_spectrum(f)
        tpl = TEMPLATES.get(f.name)
        print(f"{f.name}: {sp.host} {sp.chromophore} at {sp.concentration:g}")
        if tpl is None:  # a check spectrum (role: check): the library's band set against it
            print("    (no template)")
            print("  library:")
            print(report(compare(sp)))
            continue
        fitted = {}
        for pol, (bands, tl) in tpl.items():
            p = fit_one(sp.wavelength_nm, sp.alpha[pol], bands, tl, sp.peaks_nm.get(pol, ()))
            fitted[pol] = (p, bands, tl)
            print(f"  {pol}={describe(p, bands, tl)}")
        if f.name in NORMALIZE:
            npol, nlam = NORMALIZE[f.name]
            scale = float(model(*fitted[npol], np.array([nlam]))[0])
            i = int(np.argmin(np.abs(sp.wavelength_nm - nlam)))
            print(
                f"  normalized to alpha_{npol}({nlam:g} nm) = 1; the sample's concentration in that unit "
                f"(measured alpha there): {sp.alpha[npol][i]:.4g}"
            )
            for pol, (p, bands, tl) in fitted.items():
                print(f"  {pol}={describe(p, bands, tl, scale)}")
        for name in sp.also:
            amp = [
                float(np.exp(p[3 * i + 2]))
                for pol, (p, bands, tl) in fitted.items()
                for i, b in enumerate(bands)
                if len(b) > 4 and b[4] == name
            ]
            edge = [
                float(np.exp(p[3 * len(bands)]))
                for pol, (p, bands, tl) in fitted.items()
                if tl is not None and len(tl) > 3 and tl[3] == name
            ]
            if edge and not amp:
                print(f"  band set {name!r}: its edge as the library has it, strength {edge[0]:.4g}")
                continue
            print(
                f"  band set {name!r} (unit: the peak alpha of its first band; the sample has "
                f"{amp[0] if amp else float('nan'):.4g}):"
            )
            for pol, (p, bands, tl) in fitted.items():
                print(f"  {pol}={describe(p, bands, tl, band_set=name)}")
        res = compare(sp, lambda lam, pol, fitted=fitted: model(*fitted[pol], lam))
        print("  fit:")
        print(report(res))
        try:
            print("  library:")
            print(report(compare(sp)))
        except Exception as e:  # a band set not (yet) in the library
            print(f"    ({e})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
