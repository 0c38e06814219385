#!/usr/bin/env python3
"""50-digit Airy sums beyond and near a film's critical angle, for tests/suite/beyond_critical.rs.

Frustrated total reflection (PHYSICS.md sec. 5, "Beyond the critical angle of a layer"): a film of
index n2 < n1 sin t1 between n1 (the light's side) and n3 carries an evanescent wave,
cos t2 = +i sqrt(n1^2 sin^2 t1 - n2^2)/n2 (e^{-i w t}), and the Airy sum of
tools/airy_mpmath.py (imported, not copied) holds with that complex cosine:
e^{i b} = e^{-2 kappa d}, kappa = 2 pi/lam sqrt(n1^2 sin^2 t1 - n2^2). The ray model totally
reflects at the top face (r12, |r12| = 1) and lets nothing through; the columns give the exact
R, T, 1 - R and |r - r12| that it misses.

Rows of kind "ftir": cos t1 an exact binary64 input (beyond the critical angle, from 1e-9 to
far beyond it), films 1 nm - 10 um, substrates denser or rarer than n1 sin t1.

Rows of kind "near": a plane wave along the f64 direction (dx, 0, dz), normalized as the case
loader does (glam: v * (1/sqrt(x*x + y*y + z*z)) in binary64, reproduced here), on a film whose
normal is (0, 0, 1): cos^2 t1 = dz'^2/(dx'^2 + dz'^2) of the normalized components at 50 digits,
within 1e-12 .. 1e-6 of the critical angle on either side.

Two-beam plate under a point source, top beam beyond the critical angle (PHYSICS.md sec. 5,
"Plate, two beams"): the top beam's r12 = e^{i phi} (complex cos t2), the beam through the plate
entering below the critical angle (its entry point by findroot); unpolarized light in the
paper's two channels; with --two-beam, one row per probe point of the scenes listed in
TWO_BEAM (heights along the normal (0, 0, 1), lateral distance x), written to
tests/data/beyond_critical_two_beam_mpmath.csv.

Run: python3 tools/beyond_critical_mpmath.py > tests/data/beyond_critical_mpmath.csv
     python3 tools/beyond_critical_mpmath.py --two-beam > tests/data/beyond_critical_two_beam_mpmath.csv
"""
import math
import os
import random
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from airy_mpmath import airy, coeffs  # noqa: E402
from mp_two_beam import intensity_at, landing  # noqa: E402

mp.mp.dps = 50


def amplitudes(n1, n2, n3, d, c1, lam, pol):
    """|r - r12| (50 digits) of the Airy sum with complex cos t2."""
    N1, N2, N3, D, C1, LAM = map(mp.mpf, (n1, n2, n3, d, c1, lam))
    r12, t12, c2 = coeffs(N1, N2, C1, pol)
    r21, t21, _ = coeffs(N2, N1, c2, pol)
    r23, _, _ = coeffs(N2, N3, c2, pol)
    e = mp.expjpi(4 * N2 * D * c2 / LAM)
    r = r12 + t12 * t21 * r23 * e / (1 - r21 * r23 * e)
    return abs(r - r12)


def loader_normalize(x, y, z):
    inv = 1.0 / math.sqrt(x * x + y * y + z * z)
    return x * inv, y * inv, z * inv


def two_beam(n1, n2, d, hs, ho, x, lam):
    """I = 1/2 |r12s e^{i phi1} + a2s e^{i phi2}|^2 + 1/2 (|r12p|^2 + |a2p|^2
    + 2 Re(r12p conj(a2p) e^{i(phi1 - phi2)}) cos(t1 - t2)), complex r12."""
    n1, n2, d, hs, ho, x, lam = map(mp.mpf, (n1, n2, d, hs, ho, x, lam))
    ac = n2 * hs / mp.sqrt(n1 * n1 - n2 * n2) if n1 > n2 else x

    land = landing(n1, n2, d, hs, ho, x)
    a = mp.findroot(land, (mp.mpf(0), min(x, ac * (1 - mp.mpf(10) ** -40))), solver="anderson")
    return intensity_at(n1, n2, d, hs, ho, x, lam, a)[0]


# (name, n1, n2, thickness_m, h_src_m, h_obs_m, lambda_m, [x_m ...]): the scene of
# tests/suite/beyond_critical.rs (two-beam, dense ambient 1.5 over an air gap 0.2 mm).
TWO_BEAM = [
    # thickness and wavelength as the loader forms them (thickness_um * 1e-6, nm * 1e-9).
    ("air_gap", 1.5, 1.0, 200.0 * 1e-6, 0.01, 0.02, 500.0 * 1e-9, [0.05]),
]


def main_two_beam():
    print("name,point,intensity")
    for name, n1, n2, d, hs, ho, lam, xs in TWO_BEAM:
        for k, x in enumerate(xs):
            print(f"{name},{k}," + mp.nstr(two_beam(n1, n2, d, hs, ho, x, lam), 30))


def main():
    rng = random.Random(1212)
    print("kind,n1,n2,n3,thickness_m,cos_theta_1,dir_x,dir_z,lambda_m,pol,"
          "reflectance,transmittance,one_minus_reflectance,delta_r")
    rows = 0
    while rows < 48:
        n1 = rng.choice([1.5, 1.7, 2.4, 3.5])
        n2 = rng.choice([1.0, 1.33, 1.2])
        n3 = rng.choice([1.0, n1, 1.6, 4.0])
        d = 10 ** rng.uniform(-9, -5)
        lam = rng.choice([200e-9, 550e-9, 1064e-9])
        pol = rng.randint(0, 1)
        s = n2 / n1 * (1 + 10 ** rng.uniform(-9, -0.01))
        if s >= 1:
            continue
        c1 = math.sqrt(1 - s * s)
        N1, N2, C1 = mp.mpf(n1), mp.mpf(n2), mp.mpf(c1)
        if N1 * mp.sqrt(1 - C1 * C1) <= N2:
            continue
        R, T = airy(n1, n2, n3, d, c1, lam, pol)
        dr = amplitudes(n1, n2, n3, d, c1, lam, pol)
        vals = [n1, n2, n3, d, c1, 0.0, 0.0, lam, pol]
        print("ftir," + ",".join(repr(v) for v in vals) + "," + ",".join(
            mp.nstr(v, 30) for v in (R, T, 1 - R, dr)))
        rows += 1
    rows = 0
    while rows < 24:
        n1 = rng.choice([1.5, 2.4])
        n2 = rng.choice([1.0, 1.33])
        n3 = rng.choice([1.0, n1, 1.6])
        d = 10 ** rng.uniform(-8, -5)
        lam = rng.choice([400e-9, 633e-9])
        pol = rng.randint(0, 1)
        sc = n2 / n1
        s = sc * (1 + rng.choice([-1, 1]) * 10 ** rng.uniform(-12, -6))
        # A direction (dx, 0, -dz) with a tilt that is not a rounded sin/cos pair.
        dx, dz = s * 3.0, -math.sqrt(1 - s * s) * 3.0
        ux, _, uz = loader_normalize(dx, 0.0, dz)
        UX, UZ = mp.mpf(ux), mp.mpf(uz)
        cos_sq = UZ * UZ / (UX * UX + UZ * UZ)
        c1 = mp.sqrt(cos_sq)
        N1, N2 = mp.mpf(n1), mp.mpf(n2)
        below = N1 * N1 * (1 - cos_sq) < N2 * N2
        R, T = airy(n1, n2, n3, d, c1, lam, pol) if below else (mp.mpf(1), mp.mpf(0))
        if not below:
            continue  # only the propagating side here (beyond: kind ftir)
        vals = [n1, n2, n3, d, 0.0, dx, dz, lam, pol]
        print("near," + ",".join(repr(v) for v in vals) + "," + ",".join(
            mp.nstr(v, 30) for v in (R, T, 1 - R, mp.mpf(0))))
        rows += 1


if __name__ == "__main__":
    main_two_beam() if "--two-beam" in sys.argv else main()
