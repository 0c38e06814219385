#!/usr/bin/env python3
"""50-digit reflectance of the 0.1 nm film of `fringe fuzz --family airy --count 1000 --seed 1`,
scene 499 (shrunk: tests/fuzz_found/fuzz_airy_s1_499.json), for tests/suite/truth_thick_plates.rs.

A film of n = 1.5 and thickness 1e-10 m (thickness_um 0.0001 * 1e-6 in binary64) in air,
200 nm, s polarized, at 0 and 1 degree incidence: the plane-wave Airy sum
r = (r12 + r23 e^{2 i beta}) / (1 + r12 r23 e^{2 i beta}), beta = 2 pi n2 d cos(theta2)/lambda
(PHYSICS.md sec. 5 "Airy"), R = |r|^2. The scene's f64 direction at 1 degree is within ~1e-16 rad
of the exact angle, which moves R of this film by ~1e-18 of itself (dR/dtheta ~ 2e-9 / rad at
1 degree): the exact angle stands for it. R does not depend on where the film is: the test moves
it 0, 1, 10, 100 and 1000 m from the origin.
Run: python3 tools/airy_translated_mpmath.py > tests/data/airy_translated_mpmath.csv
"""
import mpmath as mp

mp.mp.dps = 50
M = mp.mpf


def reflectance_s(n1, n2, n3, d, lam, theta):
    c1 = mp.cos(theta)
    s2 = 1 - c1 * c1
    c2 = mp.sqrt(1 - (n1 / n2) ** 2 * s2)
    c3 = mp.sqrt(1 - (n1 / n3) ** 2 * s2)
    a1, a2, a3 = n1 * c1, n2 * c2, n3 * c3
    r12, r23 = (a1 - a2) / (a1 + a2), (a2 - a3) / (a2 + a3)
    e = mp.expjpi(4 * n2 * d * c2 / lam)
    r = (r12 + r23 * e) / (1 + r12 * r23 * e)
    return abs(r) ** 2


if __name__ == "__main__":
    print("case,point,value")
    d = M(0.0001 * 1e-6)
    lam = M(200.0 * 1e-9)
    for i, deg in enumerate([0, 1]):
        v = reflectance_s(M(1), M(1.5), M(1), d, lam, M(deg) * mp.pi / 180)
        print(f"fuzz_airy_s1_499,{i},{mp.nstr(v, 30)}")
