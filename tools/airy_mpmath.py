#!/usr/bin/env python3
"""50-digit Airy reflectances and transmittances for tests/suite/closed_form_precision.rs.

A film of index n2 and thickness d between n1 (the light's side) and n3, lit at cos t1 (an exact
binary64 input), vacuum wavelength lam, polarization s or p (PHYSICS.md sec. 5 "Plate / film,
multi-beam (Airy)"; Born & Wolf sec. 1.6.4):

    r = r12 + t12 t21 r23 e^{i b}/(1 - r21 r23 e^{i b}),  t = t12 t23 e^{i b/2}/(1 - r21 r23 e^{i b}),
    b = 4 pi n2 d cos t2/lam,  R = |r|^2,  T = n3 cos t3/(n1 cos t1) |t|^2 (0 beyond the critical
    angle of the substrate, where cos t3 is imaginary),

Fresnel coefficients in the cosine forms (P1-P4), complex beyond a critical angle. Grazing (cos t1
down to 1e-6), near Brewster, near the substrate's critical angle, films from 1 pm to 1 mm
(b up to ~6e4 rad), high index contrast, ambient media. Inputs written with repr(), read back
exactly. Run: python3 tools/airy_mpmath.py > tests/data/airy_mpmath.csv
"""
import math
import random

import mpmath as mp

mp.mp.dps = 50


def coeffs(na, nb, ca, pol):
    cb = mp.sqrt(1 - (na / nb) ** 2 * (1 - ca * ca))
    if pol == 0:
        r = (na * ca - nb * cb) / (na * ca + nb * cb)
        t = 2 * na * ca / (na * ca + nb * cb)
    else:
        r = (nb * ca - na * cb) / (nb * ca + na * cb)
        t = 2 * na * ca / (nb * ca + na * cb)
    return r, t, cb


def film(n1, n2, n3, d, c1, lam, pol):
    """The film's coefficients in 50 digits: (r12, t12, t21, r21, r23, t23, c3, e, h), e the round
    trip's phase factor and h the single pass's."""
    N1, N2, N3, D, C1, LAM = map(mp.mpf, (n1, n2, n3, d, c1, lam))
    r12, t12, c2 = coeffs(N1, N2, C1, pol)
    r21, t21, _ = coeffs(N2, N1, c2, pol)
    r23, t23, c3 = coeffs(N2, N3, c2, pol)
    e = mp.expjpi(4 * N2 * D * c2 / LAM)
    h = mp.expjpi(2 * N2 * D * c2 / LAM)
    return r12, t12, t21, r21, r23, t23, c3, e, h


def airy(n1, n2, n3, d, c1, lam, pol):
    r12, t12, t21, r21, r23, t23, c3, e, h = film(n1, n2, n3, d, c1, lam, pol)
    N1, N3, C1 = map(mp.mpf, (n1, n3, c1))
    den = 1 - r21 * r23 * e
    R = abs(r12 + t12 * t21 * r23 * e / den) ** 2
    if mp.im(c3) != 0 or c3 == 0:
        T = mp.mpf(0)
    else:
        T = N3 * mp.re(c3) / (N1 * C1) * abs(t12 * t23 * h / den) ** 2
    return R, T


def airy_cut(n1, n2, n3, d, c1, lam, pol, orders):
    """(R, T) of the orders a tracer cut at 2 `orders` + 1 internal reflections gives (the
    budget of an Airy tail bound): T of the transmitted orders 0 … `orders` (order k: 2k
    internal reflections), R of the top reflection and the reflected orders 1 … `orders` + 1
    (order k: 2k − 1), each the geometric sum of `airy` above, cut."""
    r12, t12, t21, r21, r23, t23, c3, e, h = film(n1, n2, n3, d, c1, lam, pol)
    N1, N3, C1 = map(mp.mpf, (n1, n3, c1))
    s = sum((r21 * r23 * e) ** k for k in range(orders + 1))
    R = abs(r12 + t12 * t21 * r23 * e * s) ** 2
    T = N3 * mp.re(c3) / (N1 * C1) * abs(t12 * t23 * h * s) ** 2
    return R, T


def main():
    rng = random.Random(1130)
    print("n1,n2,n3,thickness_m,cos_theta_1,lambda_m,pol,reflectance,transmittance")
    rows = 0
    while rows < 64:
        n1 = rng.choice([1.0, 1.0, 1.333, 1.5])
        n2 = rng.choice([1.38, 1.5, 2.4, 4.0, 1.2])
        n3 = rng.choice([n1, 1.0, 1.5, 1.7, 3.5])
        d = 10 ** rng.uniform(-12, -3)
        lam = rng.choice([200e-9, 400e-9, 550e-9, 700e-9, 1064e-9])
        pol = rng.randint(0, 1)
        kind = rows % 4
        if kind == 0:
            c1 = 10 ** rng.uniform(-6, -2)  # grazing
        elif kind == 1:
            c1 = math.cos(math.atan(n2 / n1)) * (1 + rng.choice([0.0, 1e-9, -1e-6]))  # Brewster
        elif kind == 2 and n3 < n1:
            # near the substrate's critical angle, on either side
            s = n3 / n1 * (1 + rng.choice([1e-9, -1e-9, 1e-6, -1e-6]))
            c1 = math.sqrt(1 - s * s)
        else:
            c1 = rng.uniform(0, 1)
        if n1 * math.sqrt(max(0.0, 1 - c1 * c1)) >= n2 * 0.999999:
            continue  # no propagating wave in the film (the reference refuses it)
        R, T = airy(n1, n2, n3, d, c1, lam, pol)
        vals = [n1, n2, n3, d, c1, lam, pol]
        print(",".join(repr(v) for v in vals) + "," + mp.nstr(R, 30) + "," + mp.nstr(T, 30))
        rows += 1


if __name__ == "__main__":
    main()
