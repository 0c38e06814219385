#!/usr/bin/env python3
"""50-digit Young intensities for tests/suite/closed_form_precision.rs.

Two coherent line sources along z through s1, s2 (exact binary64 inputs), screen point p, vacuum
wavelength lam, medium index n, a fraction f of the intensity polarized along the slit axis:

    I = f (2 + 2 cos d) + (1 - f)(2 + 2 cos a cos d),  d = 2 pi n (r1 - r2)/lam,

r_k the distance from p to slit k perpendicular to z and cos a = v1.v2/(r1 r2) (PHYSICS.md sec. 5
"Young"; the paper's eq. 4 for parallel fields). Every input is written with repr() and read
back by mpmath as the exact binary64 value, so the Rust test feeds the closed form the very same
numbers. Points sit on and next to dark fringes, in air and in water, in scenes turned about z
and moved up to 10 m from the origin. Run: python3 tools/young_mpmath.py > tests/data/young_mpmath.csv
"""
import math
import random

import mpmath as mp

mp.mp.dps = 50
rng = random.Random(20261128)

print("s1x,s1y,s2x,s2y,px,py,lambda_m,n,axis_fraction,intensity")
for k in range(48):
    lam = rng.choice([400e-9, 550e-9, 633e-9, 1064e-9])
    n = rng.choice([1.0, 1.333, 1.5])
    d = rng.choice([100, 500, 2000]) * lam
    l = rng.choice([100, 1000, 10000]) * d
    f = rng.choice([1.0, 0.5, 0.0])
    phi = rng.uniform(0, 2 * math.pi)
    offset = (rng.uniform(-10, 10), rng.uniform(-10, 10))
    # Near the m-th dark fringe: n d y / l ~ (m + 1/2) lam, plus a small random shift.
    m = rng.randint(-40, 40)
    y = (m + 0.5) * lam * l / (n * d) * (1 + rng.choice([0.0, 1e-9, -1e-7, 1e-5]))
    c, s = math.cos(phi), math.sin(phi)
    rot = lambda x, yy: (offset[0] + c * x - s * yy, offset[1] + s * x + c * yy)
    s1 = rot(0.0, d / 2)
    s2 = rot(0.0, -d / 2)
    p = rot(l, y)
    M = [mp.mpf(v) for v in (*s1, *s2, *p)]
    v1 = (M[4] - M[0], M[5] - M[1])
    v2 = (M[4] - M[2], M[5] - M[3])
    r1 = mp.sqrt(v1[0] ** 2 + v1[1] ** 2)
    r2 = mp.sqrt(v2[0] ** 2 + v2[1] ** 2)
    delta = 2 * mp.pi * mp.mpf(n) * (r1 - r2) / mp.mpf(lam)
    cos_a = (v1[0] * v2[0] + v1[1] * v2[1]) / (r1 * r2)
    F = mp.mpf(f)
    I = F * (2 + 2 * mp.cos(delta)) + (1 - F) * (2 + 2 * cos_a * mp.cos(delta))
    vals = [*s1, *s2, *p, lam, n, f]
    print(",".join(repr(float(v)) for v in vals) + "," + mp.nstr(I, 30))
