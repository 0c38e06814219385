#!/usr/bin/env python3
"""50-digit Young intensities at and next to dark fringes for tests/suite/truth_found_edges.rs.

Two coherent line sources through s1, s2 along `axis`, screen point p, vacuum wavelength lam,
ambient index n (every input an exact binary64 number, written with repr()):

    two-channel model (fraction f polarized along the axis):
        I = f (2 + 2 cos d) + (1 - f)(2 + 2 cos a cos d)
    basis-free unpolarized light (PHYSICS.md sec. 3):
        I = 2 + (1 + cos^2 a) cos d

with d = 2 pi n (r1 - r2)/lam, r_k the distance from p to line k perpendicular to the axis and
cos a = v1.v2/(r1 r2) (PHYSICS.md sec. 5 "Young"). The axis is held as the closed form holds it
(glam's normalize in binary64, v * (1/|v|)), then everything is evaluated with 50 digits.

Scenes: slits d = 100..2000 wavelengths apart, screens 100..10000 d away, points up to 60 degrees
off axis, in ambients n = 0.0019..3.9, turned about a random axis and moved up to 500 m; each
point is put at a dark fringe (n (r1 - r2)/lam = m + 1/2 + eps) with eps from 1e-8 to 1e-3
cycles, so I runs from ~1e-15 to ~1e-5 of the bright fringe's 4. The columns cos_d and cos_a are
cos d and cos a rounded once to binary64: the best f64 inputs a formula 2 + (...) cos d can have.

Run: python3 tools/young_dark_mpmath.py > tests/data/young_dark_mpmath.csv
"""
import math
import random

import mpmath as mp

mp.mp.dps = 50
rng = random.Random(20261129)


def norm64(v):
    """glam's DVec3::normalize in binary64."""
    length = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    r = 1.0 / length
    return [v[0] * r, v[1] * r, v[2] * r]


def rotation(rng):
    """A random rotation matrix (rows), from a random unit quaternion, in mpmath."""
    q = [mp.mpf(rng.gauss(0, 1)) for _ in range(4)]
    s = mp.sqrt(sum(x * x for x in q))
    w, x, y, z = (c / s for c in q)
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]


def apply(m, v, t):
    return [sum(m[i][k] * v[k] for k in range(3)) + t[i] for i in range(3)]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


print("s1x,s1y,s1z,s2x,s2y,s2z,ax,ay,az,px,py,pz,lambda_m,n,axis_fraction,basis_free,cos_d,cos_a,intensity")
for k in range(64):
    lam = rng.choice([400e-9, 550e-9, 633e-9, 906e-9, 1064e-9])
    n, d = 1.0, 0.0
    while n * d / lam < 2:  # at least two dark fringes between the axis and 58 degrees
        n = rng.choice([0.001914255925021086, 1.0, 1.333, 3.9])
        d = rng.choice([100, 500, 2000]) * lam
    l = rng.choice([100, 1000, 10000]) * d
    basis_free = k % 4 == 3
    f = 0.5 if basis_free else rng.choice([1.0, 0.5, 0.0])
    eps = rng.choice([1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3]) * rng.choice([1, -1])
    turned = k % 2 == 1
    rot = rotation(rng) if turned else [[mp.mpf(int(i == j)) for j in range(3)] for i in range(3)]
    shift = [mp.mpf(rng.uniform(-500, 500)) if k % 4 >= 2 else mp.mpf(0) for _ in range(3)]
    # Local frame: slits along z through (0, +-d/2, 0), screen at x = l. The m-th dark fringe
    # off axis (up to ~60 degrees): n (r2 - r1)/lam = m + 1/2 + eps, solved for y exactly.
    D, L, N, LAM = mp.mpf(d), mp.mpf(l), mp.mpf(n), mp.mpf(lam)
    m_max = int(n * d / lam * 0.85)
    m = rng.randint(-m_max, m_max - 1)
    target = (m + mp.mpf(1) / 2 + eps) * LAM / N
    # r2 - r1 = t on the hyperbola: r2^2 - r1^2 = 2 y D gives r1 + r2 = 2 y D / t, so
    # y^2 (D^2/t^2 - 1) = L^2 + (D^2 - t^2)/4, y of the sign of t.
    y = mp.sign(target) * mp.sqrt((L**2 + (D**2 - target**2) / 4) / (D**2 / target**2 - 1))
    z = mp.mpf(rng.uniform(-1, 1))
    s1 = [float(c) for c in apply(rot, [0, D / 2, 0], shift)]
    s2 = [float(c) for c in apply(rot, [0, -D / 2, 0], shift)]
    p = [float(c) for c in apply(rot, [L, y, z], shift)]
    axis = [float(c) for c in apply(rot, [0, 0, 1], [0, 0, 0])]
    # Everything below from the binary64 numbers as the closed form holds them.
    A = [mp.mpf(c) for c in norm64(axis)]
    vs = []
    for s in (s1, s2):
        v = [mp.mpf(p[i]) - mp.mpf(s[i]) for i in range(3)]
        along = dot(v, A)
        vs.append([v[i] - along * A[i] for i in range(3)])
    r1, r2 = mp.sqrt(dot(vs[0], vs[0])), mp.sqrt(dot(vs[1], vs[1]))
    delta = 2 * mp.pi * N * (r1 - r2) / LAM
    cos_a = dot(vs[0], vs[1]) / (r1 * r2)
    if basis_free:
        I = 2 + (1 + cos_a**2) * mp.cos(delta)
    else:
        F = mp.mpf(f)
        I = F * (2 + 2 * mp.cos(delta)) + (1 - F) * (2 + 2 * cos_a * mp.cos(delta))
    vals = [*s1, *s2, *axis, *p, lam, n, f, float(basis_free), float(mp.cos(delta)), float(cos_a)]
    print(",".join(repr(float(v)) for v in vals) + "," + mp.nstr(I, 30))
