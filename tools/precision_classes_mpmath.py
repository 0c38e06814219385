#!/usr/bin/env python3
"""50-digit values of the fuzz-found precision classes (tests/suite/precision_classes.rs).

Each case file in tests/fuzz_found/ named below is evaluated from its own numbers, at every
probe point, in 50-digit arithmetic:

* `airy` cases (a plane wave on a film, far field, one incidence angle per probe point): the
  direction the tracer is given, d = normalize(sin t a - cos t N) built in binary64 exactly as
  `case::build::incidence_direction` builds it (glam's normalize is v * (1/|v|)), and the plate
  normal normalized in binary64 as `geometry::Plane` holds it; cos t1 = |d.N|/(|d||N|) of those
  binary64 vectors in 50 digits; then the Airy sum of tools/airy_mpmath.py (R, or T on the
  transmitted side), mixed over s and p by the linear polarization angle (the reference axis
  is the s direction in these scenes). Thickness um*1e-6 and wavelength nm*1e-9 are the
  binary64 products the loader forms.
* `coherence_gaussian` cases (normal incidence, two beams, Gaussian light): the spectrum of
  `case::build::spectrum` (trapezoid weights over +-sigmas in wavenumber) in 50 digits, and per
  sample the two-beam reflectance |r12 + t12 r23 t21 e^{i 4 pi n2 d/lam}|^2, summed with the
  normalized weights; d at each probe point is thickness_nm * 1e-9 (binary64 product).

Run: python3 tools/precision_classes_mpmath.py > tests/data/precision_classes_mpmath.csv
"""
import json
import math
import os

import mpmath as mp

from airy_mpmath import airy, airy_cut  # the Airy sum of tests/data/airy_mpmath.csv

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))
FOUND = os.path.join(HERE, "..", "tests", "fuzz_found")
CASES = [
    "fuzz_airy_s7_25",
    "fuzz_airy_s7_31",
    "fuzz_airy_s7_37",
    "fuzz_airy_s7_40",
    "fuzz_airy_s7_46",
    "fuzz_coherence_gaussian_s7_87",
]


def normalize(v):
    r = 1.0 / math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return [v[0] * r, v[1] * r, v[2] * r]


def index(case, name):
    return case["scene"]["media"][name]["constant"]["n"]


def sweep_points(sw):
    n = sw["count"]
    if n == 1:
        return [sw["from"]]
    return [sw["from"] + (sw["to"] - sw["from"]) * i / (n - 1) for i in range(n)]


def airy_case(case, extra_normalizations=0, orders=None):
    """R or T of the case's film at every sweep point, 50 digits, for the direction as the case
    file writes it, renormalized `extra_normalizations` more times in f64 (as a tracer that
    normalizes an already-unit direction holds it); linear or unpolarized light. With `orders`,
    the orders a tracer cut at 2 `orders` + 1 internal reflections gives alone (`airy_cut`: the
    sum a tail bound asks for)."""
    sw = case["probe"]["sweep"]
    par = sw["parameter"]["incidence_angle_deg"]
    side = sw["observe"]["far_field"]["side"]
    plate = case["scene"]["surfaces"][0]["plate"]
    n1, n2, n3 = (index(case, plate[k]) for k in ("above", "medium", "below"))
    d = plate["thickness_um"] * 1e-6
    lam = case["light"]["monochrome"]["wavelength_nm"] * 1e-9
    pol = case["scene"]["sources"][0]["polarization"]
    if "linear" in pol:
        fs = mp.cos(mp.mpf(math.radians(pol["linear"]["angle_deg"]))) ** 2
    else:
        fs = mp.mpf(1) / 2
    normal = normalize(plate["normal"])
    out = []
    for deg in sweep_points(sw):
        t = math.radians(deg)
        n = normalize(par["surface_normal"])
        ax = par["in_plane_axis"]
        k = ax[0] * n[0] + ax[1] * n[1] + ax[2] * n[2]
        a = normalize([ax[i] - k * n[i] for i in range(3)])
        dv = normalize([math.sin(t) * a[i] - math.cos(t) * n[i] for i in range(3)])
        for _ in range(extra_normalizations):
            dv = normalize(dv)
        D = [mp.mpf(x) for x in dv]
        N = [mp.mpf(x) for x in normal]
        dot = sum(x * y for x, y in zip(D, N))
        c1 = abs(dot) / mp.sqrt(sum(x * x for x in D) * sum(x * x for x in N))
        Rs, Ts = airy(n1, n2, n3, d, c1, lam, 0)
        Rp, Tp = airy(n1, n2, n3, d, c1, lam, 1)
        if orders is not None:
            Rs, Ts = airy_cut(n1, n2, n3, d, c1, lam, 0, orders)
            Rp, Tp = airy_cut(n1, n2, n3, d, c1, lam, 1, orders)
        v = fs * Rs + (1 - fs) * Rp if side == "reflected" else fs * Ts + (1 - fs) * Tp
        out.append(v)
    return out


def coherence_case(case):
    sw = case["probe"]["sweep"]
    g = case["light"]["gaussian"]
    plate = case["scene"]["surfaces"][0]["plate"]
    n1, n2, n3 = (mp.mpf(index(case, plate[k])) for k in ("above", "medium", "below"))
    lam0 = mp.mpf(g["center_nm"]) * mp.mpf("1e-9")
    k0 = 2 * mp.pi / lam0
    dk = 2 * mp.pi * mp.mpf(g["fwhm_nm"]) * mp.mpf("1e-9") / lam0**2
    sigma = dk / (2 * mp.sqrt(2 * mp.log(2)))
    m, s = g["samples"], mp.mpf(g["sigmas"])
    samples = []
    for i in range(m):
        x = -s + 2 * s * i / (m - 1)
        w = (mp.mpf(1) / 2 if i in (0, m - 1) else 1) * mp.exp(-x * x / 2)
        samples.append((2 * mp.pi / (k0 + x * sigma), w))
    total = sum(w for _, w in samples)
    r12 = (n1 - n2) / (n1 + n2)
    t12 = 2 * n1 / (n1 + n2)
    r23 = (n2 - n3) / (n2 + n3)
    t21 = 2 * n2 / (n1 + n2)
    a1, a2 = r12, t12 * r23 * t21
    out = []
    for nm in sweep_points(sw):
        d = mp.mpf(nm * 1e-9)
        v = sum(w * abs(a1 + a2 * mp.expjpi(4 * n2 * d / lam)) ** 2 for lam, w in samples)
        out.append(v / total)
    return out


def main():
    print("case,point,value")
    for name in CASES:
        case = json.load(open(os.path.join(FOUND, name + ".json")))
        model = next(iter(case["references"][0]["model"]))
        values = airy_case(case) if model == "airy" else coherence_case(case)
        for i, v in enumerate(values):
            print(f"{name},{i},{mp.nstr(v, 30)}")


if __name__ == "__main__":
    main()
