#!/usr/bin/env python3
"""50-digit Fresnel-rhomb retardances near the critical angle for
tests/suite/fuzz_generators.rs (the `rhomb_retardance` closed form's own error).

One TIR at a face of unit normal N inside glass of index n_g against a medium of index n_o: with
the wave's direction u (an exact binary64 vector, normalized here at 50 digits), sin^2 t = |u x N|^2,
cos t = |u.N|, n21 = n_o/n_g, and (PHYSICS.md sec. 5, P5 and P6)

    retardance = arg r_p - arg r_s = 2 atan(R/cos t) - 2 atan(R/(n21^2 cos t)),
    R = sqrt(sin^2 t - n21^2).

Rows: dense prisms (n_g/n_o from 1 + 1e-6 to 1e4) at t - t_c from 1e-12 rad to 0.1 rad above the
critical angle, the pair (u, N) rotated at random (as `fringe fuzz` moves its scenes), every input
written with repr() and read back exactly. `fringe fuzz --family rhomb_retardance` found the old
closed form (t = acos(u.N) in binary64) off by up to 5e-4 rad there while the tracer was right.
Run: python3 tools/rhomb_mpmath.py > tests/data/rhomb_mpmath.csv
"""
import math
import random

import mpmath as mp
from mp_geometry import apply, rotation

mp.mp.dps = 50
rng = random.Random(2026)


def retardance(ng, no, u, n):
    u = [mp.mpf(x) for x in u]
    n = [mp.mpf(x) for x in n]
    lu = mp.sqrt(sum(x * x for x in u))
    ln = mp.sqrt(sum(x * x for x in n))
    u = [x / lu for x in u]
    n = [x / ln for x in n]
    c = abs(sum(a * b for a, b in zip(u, n)))
    cr = [u[1] * n[2] - u[2] * n[1], u[2] * n[0] - u[0] * n[2], u[0] * n[1] - u[1] * n[0]]
    s2 = sum(x * x for x in cr)
    n21 = mp.mpf(no) / mp.mpf(ng)
    g = s2 - n21 * n21
    assert g > 0
    r = mp.sqrt(g)
    return 2 * mp.atan(r / c) - 2 * mp.atan(r / (n21 * n21 * c))


def main():
    print("n_glass,n_out,ux,uy,uz,nx,ny,nz,retardance_rad")
    for _ in range(60):
        no = 10 ** rng.uniform(-3, 1)
        ng = no * (1 + 10 ** rng.uniform(-6, 4))
        if ng > 10:
            ng = 10.0
        crit = math.asin(no / ng)
        off = 10 ** rng.uniform(-12, -1)
        t = min(crit + off, math.pi / 2 - 1e-9)
        u = [math.sin(t), 0.0, -math.cos(t)]
        n = [0.0, 0.0, -1.0]
        if rng.random() < 0.75:
            R = rotation(rng)
            u, n = apply(R, u), apply(R, n)
        try:
            d = retardance(ng, no, u, n)
        except AssertionError:
            continue  # rounding put this draw at or below the critical angle
        cols = [repr(float(x)) for x in [ng, no, *u, *n]]
        print(",".join(cols + [mp.nstr(d, 25)]))


if __name__ == "__main__":
    main()
