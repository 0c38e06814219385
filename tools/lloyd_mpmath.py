#!/usr/bin/env python3
"""50-digit Lloyd's-mirror intensities for tests/suite/closed_form_precision.rs.

A line source through s along the axis a, a dielectric mirror plane through q with normal n
(neither normalized: mpmath normalizes them at 50 digits), the source's medium of index n1, the
mirror's of index n2, screen point p, vacuum wavelength lam (PHYSICS.md sec. 5 "Lloyd"). The image
method at 50 digits: h_s, h_p the heights above the mirror, s' = s - 2 h_s n^ the image source,
r_d and r_i the distances from p to the axes through s and s' (perpendicular to a), cos t =
(h_s + h_p)/r_i at the mirror, and

    I = |1 + r_s(cos t) exp(2 pi i n1 (r_i - r_d)/lam)|^2

with r_s = (n1 cos t - n2 cos t2)/(n1 cos t + n2 cos t2), cos t2 = +i sqrt(...) beyond the
critical angle of a rarer mirror (P1, P5). Inputs are written with repr() and read back as the
exact binary64 values. Points sit on and next to dark fringes, at grazing (on and just above the
mirror plane), in air, water and glass above the mirror, with rarer mirrors (near and beyond the
critical angle), in scenes rotated at random and moved up to 10 m from the origin.
Run: python3 tools/lloyd_mpmath.py > tests/data/lloyd_mpmath.csv
"""
import random

import mpmath as mp
from mp_geometry import apply, dot, rotation

mp.mp.dps = 50
rng = random.Random(20261128)



def intensity(s, a, q, n, p, n1, n2, lam):
    S, A, Q, N, P = ([mp.mpf(x) for x in v] for v in (s, a, q, n, p))
    N1, N2, LAM = mp.mpf(n1), mp.mpf(n2), mp.mpf(lam)
    nn = mp.sqrt(dot(N, N))
    N = [x / nn for x in N]
    an = mp.sqrt(dot(A, A))
    A = [x / an for x in A]
    hs = dot([x - y for x, y in zip(S, Q)], N)
    if hs < 0:
        N = [-x for x in N]
        hs = -hs
    hp = dot([x - y for x, y in zip(P, Q)], N)
    image = [x - 2 * hs * y for x, y in zip(S, N)]

    def perp(u):
        return mp.sqrt(dot(u, u) - dot(u, A) ** 2)

    rd = perp([x - y for x, y in zip(P, S)])
    ri = perp([x - y for x, y in zip(P, image)])
    ci = (hs + hp) / ri
    st2 = (N1 / N2) ** 2 * (1 - ci * ci)
    ct = mp.sqrt(1 - st2)  # +i sqrt(st2 - 1) beyond the critical angle
    rs = (N1 * ci - N2 * ct) / (N1 * ci + N2 * ct)
    return abs(1 + rs * mp.expjpi(2 * N1 * (ri - rd) / LAM)) ** 2


def main():
    print("sx,sy,sz,ax,ay,az,qx,qy,qz,nx,ny,nz,px,py,pz,n1,n2,lambda_m,intensity")
    for k in range(60):
        lam = rng.choice([200e-9, 400e-9, 550e-9, 633e-9, 1064e-9])
        n1 = rng.choice([1.0, 1.0, 1.333, 1.5, 2.4])
        rarer = k % 3 == 2
        n2 = n1 * rng.choice([0.6, 0.9, 0.999]) if rarer else n1 * rng.choice([1.2, 1.5, 2.0])
        h = 10 ** rng.uniform(-6, -1)
        L = 10 ** rng.uniform(-3, 1)
        # Screen heights: the m-th dark fringe of r_s ~ -1 (2 h y/L ~ m lam/n1), a small shift off
        # it, on the mirror plane and just above it (grazing).
        kind = k % 5
        if kind == 3:
            y = 0.0
        elif kind == 4:
            y = L * 10 ** rng.uniform(-9, -4)
        else:
            m = rng.randint(1, 200)
            y = m * lam * L / (2 * h * n1) * (1 + rng.choice([0.0, 1e-9, -1e-7, 1e-5]))
            y = min(y, 10 * L)
        R = rotation(rng) if k % 4 else [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
        off = [rng.uniform(-10, 10) for _ in range(3)] if k % 2 else [0.0, 0.0, 0.0]
        # Local frame: mirror z = 0, normal +z, source axis along y, screen at x = L.
        loc = lambda v: [o + c for o, c in zip(off, apply(R, v))]
        s = loc([0.0, 0.0, h])
        q = loc([rng.uniform(-1, 1), rng.uniform(-1, 1), 0.0]) if k % 6 == 1 else loc([0.0, 0.0, 0.0])
        p = loc([L, rng.uniform(-0.01, 0.01), y])
        a = apply(R, [0.0, 1.0, 0.0])
        n = apply(R, [0.0, 0.0, 1.0 if k % 7 else -1.0])
        I = intensity(s, a, q, n, p, n1, n2, lam)
        vals = [*s, *a, *q, *n, *p, n1, n2, lam]
        print(",".join(repr(float(v)) for v in vals) + "," + mp.nstr(I, 30))


if __name__ == "__main__":
    main()
