#!/usr/bin/env python3
"""50-digit two-beam reflectances of a plate at normal incidence for
tests/suite/fuzz_generators.rs (the `coherence_gaussian` closed form's own error per spectral
sample, src/harness/analytic/coherence.rs `two_beam_normal_reflectance`).

With a1 = r12 = (n1 - n2)/(n1 + n2) and a2 = t12 r23 t21 = 4 n1 n2 (n2 - n3)/((n1 + n2)^2 (n2 + n3))
(real at normal incidence) and delta = 4 pi n2 d/lambda (PHYSICS.md sec. 3),

    R = a1^2 + a2^2 + 2 a1 a2 cos(delta) = (a1 + a2)^2 - 4 a1 a2 sin^2(delta/2).

Rows: indices 0.001-10 (ambient, plate, substrate), thicknesses 1 nm - 1 mm, wavelengths
200-2500 nm; half of them near a dark fringe (a substrate index chosen so that a2 is within
1e-3 of a1, and d so that sin^2(delta/2) is within 1e-4 of 1): R down to ~1e-9 of (a1 + a2)^2,
where the f64 form lost ~1e-11 of R (`fringe fuzz --family coherence_gaussian`, seed 1 #1795).
Inputs written with repr() and read back exactly; n2*d is formed exactly from the binary64 inputs.
Run: python3 tools/coherence_two_beam_mpmath.py > tests/data/coherence_two_beam_mpmath.csv
"""
import random

import mpmath as mp

mp.mp.dps = 50
rng = random.Random(3)


def reflectance(n1, n2, n3, d, lam):
    n1, n2, n3, d, lam = (mp.mpf(x) for x in (n1, n2, n3, d, lam))
    a1 = (n1 - n2) / (n1 + n2)
    a2 = 4 * n1 * n2 * (n2 - n3) / ((n1 + n2) ** 2 * (n2 + n3))
    return a1 * a1 + a2 * a2 + 2 * a1 * a2 * mp.cos(4 * mp.pi * n2 * d / lam)


def main():
    print("n1,n2,n3,thickness_m,lambda_m,reflectance")
    for i in range(80):
        n1 = 10 ** rng.uniform(-3, 1)
        n2 = 10 ** rng.uniform(-3, 1)
        lam = rng.uniform(200e-9, 2500e-9)
        d = 10 ** rng.uniform(-9, -3)
        n3 = 10 ** rng.uniform(-3, 1)
        if i % 2 == 1:
            # a2 = a1 (1 + e): solve for n3 at 50 digits, then round.
            N1, N2 = mp.mpf(n1), mp.mpf(n2)
            a1 = (N1 - N2) / (N1 + N2)
            q = a1 * (1 + mp.mpf(10) ** rng.uniform(-6, -3)) * (N1 + N2) ** 2 / (4 * N1 * N2)
            # (n2 - n3)/(n2 + n3) = q  =>  n3 = n2 (1 - q)/(1 + q)
            if abs(q) >= 1:
                continue
            n3 = float(N2 * (1 - q) / (1 + q))
            if not (1e-3 <= n3 <= 10):
                continue
            # d so that 2 n2 d / lam = k + 1/2 (+ a little): sin^2(delta/2) near 1.
            k = int(2 * n2 * d / lam)
            d = float((k + 0.5 + mp.mpf(10) ** rng.uniform(-6, -3)) * mp.mpf(lam) / (2 * mp.mpf(n2)))
        r = reflectance(n1, n2, n3, d, lam)
        print(",".join([repr(float(x)) for x in (n1, n2, n3, d, lam)] + [mp.nstr(r, 25)]))


if __name__ == "__main__":
    main()
