#!/usr/bin/env python3
"""50-digit Fizeau-wedge intensities for tests/suite/closed_form_precision.rs.

The wedge as a scene gives it: top face through qt with normal nt (the light comes from above,
along -nt), bottom face through qb with normal nb, indices n1 above, n inside, n3 below, screen
point p, vacuum wavelength lam (PHYSICS.md sec. 5 "Wedge"). An independent ray trace at 50 digits,
not the Rust closed form's algebra: the entry point E on the top face is found with
mpmath.findroot such that the ray (down along -nt, reflected at the bottom face, refracted out at
the top face) passes through p. With t1, t2 the two inside lengths and X the exit point,

    Op_bottom - Op_top = n (t1 + t2) + n1 |p - X| - n1 h_obs,   h_obs = (p - qt).nt^,
    I = |r12 + t12 r23 t21 exp(2 pi i (Op_bottom - Op_top)/lam)|^2     (s polarization, P1, P3)

r23 complex when the bottom face totally reflects. Inputs are written with repr() and read
back as exact binary64 values. Angles 1e-5 deg to 10 deg, thicknesses 1 um to 1 mm, screens up to
1 m above, points on and next to dark fringes, ambient media, substrates, scenes rotated at
random and moved up to 10 m. Run: python3 tools/wedge_mpmath.py > tests/data/wedge_mpmath.csv
"""
import math
import random

import mpmath as mp
from mp_geometry import apply, dot, rotation

mp.mp.dps = 50
rng = random.Random(1129)



def add(a, b, k=1):
    return [x + k * y for x, y in zip(a, b)]


def unit(a):
    m = mp.sqrt(dot(a, a))
    return [x / m for x in a]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def rs(n1, n2, c):
    ct = mp.sqrt(1 - (n1 / n2) ** 2 * (1 - c * c))
    return (n1 * c - n2 * ct) / (n1 * c + n2 * ct), 2 * n1 * c / (n1 * c + n2 * ct)


def intensity(qt, nt, qb, nb, p, n1, n, n3, lam):
    QT, NT, QB, NB, P = ([mp.mpf(x) for x in v] for v in (qt, nt, qb, nb, p))
    N1, N, N3, LAM = (mp.mpf(x) for x in (n1, n, n3, lam))
    NT, NB = unit(NT), unit(NB)
    if dot(NT, NB) < 0:
        NB = [-x for x in NB]
    hinge = unit(cross(NT, NB))
    xd = cross(hinge, NT)
    u0 = [-x for x in NT]
    rel = add(P, QT, -1)
    v = dot(rel, hinge)
    h_obs = dot(rel, NT)

    def trace(u):
        E = add(add(QT, xd, u), hinge, v)
        t1 = dot(add(QB, E, -1), NB) / dot(u0, NB)
        B = add(E, u0, t1)
        u1 = add(u0, NB, -2 * dot(u0, NB))
        t2 = dot(add(QT, B, -1), NT) / dot(u1, NT)
        X = add(B, u1, t2)
        tang = add(u1, NT, -dot(u1, NT))
        k = N / N1
        u2 = add([k * x for x in tang], NT, mp.sqrt(1 - k * k * dot(tang, tang)))
        return t1, t2, X, u1, u2

    def miss(u):
        t1, t2, X, u1, u2 = trace(u)
        d = add(P, X, -1)
        return dot(add(d, u2, -dot(d, u2)), xd)

    u = mp.findroot(miss, mp.mpf(dot(rel, xd)))
    t1, t2, X, u1, u2 = trace(u)
    opd = N * (t1 + t2) + N1 * mp.sqrt(dot(add(P, X, -1), add(P, X, -1))) - N1 * h_obs
    r12, t12 = rs(N1, N, mp.mpf(1))
    r23, _ = rs(N, N3, -dot(u0, NB))
    _, t21 = rs(N, N1, dot(u1, NT))
    return abs(r12 + t12 * r23 * t21 * mp.expjpi(2 * opd / LAM)) ** 2


def local_opd(x, n1, n, a, t0, ho):
    # The closed form in plain floats, only to place points near dark fringes.
    sp = n * math.sin(2 * a) / n1
    psi = math.asin(sp)
    xe = x - ho * math.tan(psi)
    xi = (xe - t0 * math.tan(2 * a)) / (1 + math.tan(a) * math.tan(2 * a))
    D = t0 + xi * math.tan(a)
    return n * D * (1 + 1 / math.cos(2 * a)) + n1 * ho * (1 / math.cos(psi) - 1)


def main():
    print("qtx,qty,qtz,ntx,nty,ntz,qbx,qby,qbz,nbx,nby,nbz,px,py,pz,n1,n,n3,lambda_m,intensity")
    rows = 0
    while rows < 48:
        lam = rng.choice([200e-9, 400e-9, 550e-9, 633e-9, 1064e-9])
        n1 = rng.choice([1.0, 1.0, 1.333, 1.5])
        n = rng.choice([1.45, 1.5, 1.7, 2.4])
        n3 = rng.choice([n1, n1, 1.0, 1.333, 1.9])
        a = math.radians(10 ** rng.uniform(-5, 1))
        t0 = 10 ** rng.uniform(-6, -3)
        ho = 10 ** rng.uniform(-4, 0)
        if n * math.sin(2 * a) >= 0.95 * n1:
            continue
        # A dark fringe: |a1 + a2 e^{i d}| smallest where d = arg a1 - arg a2 + pi (mod 2 pi).
        psi = math.asin(n * math.sin(2 * a) / n1)
        xmax = t0 / math.tan(a) * 0.9 + ho * math.tan(psi)
        x = rng.uniform(-0.5, 1) * min(xmax, 0.1)
        if rng.random() < 0.7:
            slope = (local_opd(x + 1e-9, n1, n, a, t0, ho) - local_opd(x - 1e-9, n1, n, a, t0, ho)) / 2e-9
            c = local_opd(x, n1, n, a, t0, ho) / lam
            target = math.floor(c) + 0.5 + rng.choice([0.0, 0.25])
            if slope != 0:
                x += (target - c) * lam / slope * (1 + rng.choice([0.0, 1e-9, -1e-6]))
        R = rotation(rng) if rows % 4 else [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
        off = [rng.uniform(-10, 10) for _ in range(3)] if rows % 2 else [0.0, 0.0, 0.0]
        loc = lambda v: [o + c for o, c in zip(off, apply(R, v))]
        # Local frame: top face z = 0 normal +z, hinge along y, bottom normal (sin a, 0, cos a)
        # through (0, 0, -t0), as the scene builder makes it (the bottom point rounded anew).
        qt = loc([0.0, 0.0, 0.0])
        nt = apply(R, [0.0, 0.0, 1.0])
        qb = loc([0.0, 0.0, -t0])
        nb = apply(R, [math.sin(a), 0.0, math.cos(a)])
        p = loc([x, rng.uniform(-0.01, 0.01), ho])
        I = intensity(qt, nt, qb, nb, p, n1, n, n3, lam)
        vals = [*qt, *nt, *qb, *nb, *p, n1, n, n3, lam]
        print(",".join(repr(float(v)) for v in vals) + "," + mp.nstr(I, 30))
        rows += 1


if __name__ == "__main__":
    main()
