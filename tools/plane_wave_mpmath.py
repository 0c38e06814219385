#!/usr/bin/env python3
"""50-digit plane-wave phases through a TIR prism for tests/suite/closed_form_precision.rs.

The optical path that `plane_wave_beams` (and the Fresnel rhomb, TIR interference) needs: a plane
wave along u0 (an exact binary64 vector, normalized here at 50 digits) with phase 0 on the plane
through the reference point r0, in a medium of index n0, meets an entry face (refraction into the
glass), a face where it reflects (total internal reflection for the denser glasses), and an exit
face (refraction out); the phase at a point x a few centimetres beyond is, by wavefront continuity
(PHYSICS.md sec. 5 "TIR"),

    Op = sum_k n_k u_k.(Q_{k+1} - Q_k) + n_last u_last.(x - Q_last),   Q_0 = r0,

with u_k refracted by Snell's law in vector form and reflected as u - 2(u.N)N, every face normal
normalized at 50 digits from its binary64 components. Rows give cos and sin of 2 pi Op/lam.
Prisms of n = 1.5-1.9 in air or water, beams tilted off the entry normal, scenes rotated at random
and moved up to 10 m. Inputs written with repr(), read back exactly.
Run: python3 tools/plane_wave_mpmath.py > tests/data/plane_wave_mpmath.csv
"""
import math
import random

import mpmath as mp
from mp_geometry import apply, dot, rotation

mp.mp.dps = 50
rng = random.Random(1131)



def unit(v):
    v = [mp.mpf(x) for x in v]
    m = mp.sqrt(dot(v, v))
    return [x / m for x in v]


def refract(u, n, n1, n2):
    if dot(u, n) > 0:
        n = [-x for x in n]
    ci = -dot(u, n)
    eta = mp.mpf(n1) / mp.mpf(n2)
    ct = mp.sqrt(1 - eta * eta * (1 - ci * ci))
    return [eta * a + (eta * ci - ct) * b for a, b in zip(u, n)]


def reflect(u, n):
    k = 2 * dot(u, n)
    return [a - k * b for a, b in zip(u, n)]


cols = ["ux", "uy", "uz", "r0x", "r0y", "r0z", "n0"]
for f in range(3):
    cols += [f"q{f}x", f"q{f}y", f"q{f}z", f"m{f}x", f"m{f}y", f"m{f}z", f"nb{f}", f"na{f}", f"refl{f}"]
cols += ["x", "y", "z", "lambda_m", "cos_phase", "sin_phase"]
print(",".join(cols))
for k in range(40):
    n0 = rng.choice([1.0, 1.0, 1.333])
    ng = rng.choice([1.5, 1.7, 1.9])
    lam = rng.choice([400e-9, 550e-9, 633e-9, 1064e-9])
    tilt = rng.choice([0.0, 1e-3, -0.05, 0.1])
    R = rotation(rng) if k % 4 else [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    off = [rng.uniform(-10, 10) for _ in range(3)] if k % 2 else [0.0, 0.0, 0.0]
    loc = lambda v: [o + c for o, c in zip(off, apply(R, v))]
    c30, s30 = math.cos(math.radians(30)), math.sin(math.radians(30))
    d = [c30 * math.cos(tilt) + s30 * math.sin(tilt), 0.0, -s30 * math.cos(tilt) + c30 * math.sin(tilt)]
    u0 = apply(R, d)
    r0 = loc([-0.008660254037844387, 0.0, 0.010000000000000002])
    faces = [
        (loc([0.0, 0.0, 0.005]), apply(R, [-c30, 0.0, s30]), n0, ng, 0),
        (loc([0.008660254037844385, 0.0, 0.0]), apply(R, [0.0, 0.0, -1.0]), ng, ng, 1),
        (loc([0.01732050807568877, 0.0, 0.005]), apply(R, [c30, 0.0, s30]), ng, n0, 0),
    ]
    x = loc([0.06 + rng.uniform(-0.01, 0.01), rng.uniform(-0.002, 0.002), 0.03 + rng.uniform(-0.01, 0.01)])
    u = unit(u0)
    q = [mp.mpf(v) for v in r0]
    n = mp.mpf(n0)
    op = mp.mpf(0)
    for qf, mf, nb, na, refl in faces:
        Q = [mp.mpf(v) for v in qf]
        op += n * dot(u, [a - b for a, b in zip(Q, q)])
        q = Q
        N = unit(mf)
        if refl:
            u = reflect(u, N)
        else:
            u = refract(u, N, nb, na)
            n = mp.mpf(na)
    X = [mp.mpf(v) for v in x]
    op += n * dot(u, [a - b for a, b in zip(X, q)])
    ph = 2 * op / mp.mpf(lam)
    vals = [*u0, *r0, n0]
    for qf, mf, nb, na, refl in faces:
        vals += [*qf, *mf, nb, na, refl]
    vals += [*x, lam]
    print(",".join(repr(float(v)) for v in vals) + "," + mp.nstr(mp.cospi(ph), 30) + "," + mp.nstr(mp.sinpi(ph), 30))
