#!/usr/bin/env python3
"""50-digit values of the scalar rungs' closed Airy tail for mixed s and p light, for
tests/suite/scalar_tail.rs (docs/PHYSICS.md 5a, eq. T2):

    F = sum_{k>=1} sqrt(w_s x^k + w_p y^k) exp(2 pi i k c),  w_s + w_p = 1,
    x = 1 - d_s, y = 1 - d_p.

The inputs are f64 (printed with repr, read back bit for bit) and taken exactly into mpmath.
Each row names the independent method that gave its value:
  direct    the sum term by term in 50 digits until the rest, bounded by
            a^k (w_s + w_p)^(1/2)/(1 - a) (a = sqrt(max(x, y))), is below 1e-30 of the sum
            (1 - max(x, y) >= 10^-2.5: at most ~5e4 terms);
  binomial  near grazing (1 - x down to 1e-12), where the slower-decaying polarization M
            carries at least 2/3 of the light (u = w_m/w_M <= 1/2): sqrt(1 + u rho^k) expanded
            in the convergent binomial series, each power a geometric series q/(1 - q) summed
            exactly, with no split and no acceleration (the Rust code splits at u_k = 1 and
            accelerates), until a term is below 1e-40 of the sum;
  geometric the limits w_p = 0 (or w_s = 0) and x = y, where F = r/(1 - r) with r = sqrt(x) e^{2 pi i c}
            (or sqrt(y)), in closed form.

With --plate it prints the scalar rung's reflectance of plates whose Airy tail the runner
closes (the library's plate_airy_p, n = 1.5, 2 um, 550 nm, in air, linearly polarized at
angle_deg to the s direction: w_s = cos^2, w_p = sin^2), for the regression of
tests/suite/scalar_tail.rs: R_scalar = |sum_{k>=0} sqrt(I_k) e^{2 pi i k c}|^2, I_0 the top
reflection's intensity w_s |r12s|^2 + w_p |r12p|^2, I_k (k >= 1) = sum_sigma w_sigma
|t12 t21 r23|^2 |r21 r23|^{2(k-1)}, c = 2 n2 d cos t2/lambda; summed term by term (direct) or,
where the slower-decaying s light carries >= 2/3 of the orders' light (angle 15 deg), by the binomial series above; and the vector
reflectance w_s R_s + w_p R_p from tools/airy_mpmath.py (a check of the case's convention).
Run: python3 tools/scalar_tail_mpmath.py > tests/data/scalar_tail_mpmath.csv
     python3 tools/scalar_tail_mpmath.py --plate > tests/data/scalar_tail_plate_mpmath.csv
"""
import math
import os
import random
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from airy_mpmath import airy, coeffs  # noqa: E402
from airy_tail_mpmath import traced_cos  # noqa: E402

mp.mp.dps = 50


def direct(ws, wp, ds, dp, c):
    ws, wp = mp.mpf(ws), mp.mpf(wp)
    t = ws + wp
    ws, wp = ws / t, wp / t
    x, y = 1 - mp.mpf(ds), 1 - mp.mpf(dp)
    z = mp.expjpi(2 * mp.mpf(c))
    a = mp.sqrt(max(x, y))
    big_x, big_y, zk, s = mp.mpf(1), mp.mpf(1), mp.mpc(1), mp.mpc(0)
    while True:
        big_x *= x
        big_y *= y
        zk *= z
        s += zk * mp.sqrt(ws * big_x + wp * big_y)
        if mp.sqrt(max(big_x, big_y)) / (1 - a) < mp.mpf(10) ** -30 * abs(s):
            return s


def binomial(ws, wp, ds, dp, c):
    ws, wp = mp.mpf(ws), mp.mpf(wp)
    t = ws + wp
    if ds <= dp:
        w_maj, d_maj, w_min, d_min = ws / t, mp.mpf(ds), wp / t, mp.mpf(dp)
    else:
        w_maj, d_maj, w_min, d_min = wp / t, mp.mpf(dp), ws / t, mp.mpf(ds)
    x, y = 1 - d_maj, 1 - d_min
    rho, u = y / x, w_min / w_maj
    assert u <= 0.5
    r0 = mp.sqrt(x) * mp.expjpi(2 * mp.mpf(c))
    s, j = mp.mpc(0), 0
    while True:
        q = r0 * rho**j
        term = mp.binomial(mp.mpf(1) / 2, j) * u**j * q / (1 - q)
        s += term
        j += 1
        if j > 3 and abs(term) < mp.mpf(10) ** -40 * abs(s):
            return mp.sqrt(w_maj) * s


def geometric(ws, wp, ds, dp, c):
    # w_p = 0: sqrt(x); w_s = 0: sqrt(y); x = y: either.
    d = ds if wp == 0 else dp if ws == 0 else ds
    assert wp == 0 or ws == 0 or ds == dp
    r = mp.sqrt(1 - mp.mpf(d)) * mp.expjpi(2 * mp.mpf(c))
    return r / (1 - r)


def rows():
    rng = random.Random(20261129)
    out = []
    # direct: moderate decay, any weights (u below, near and far above 1), any phase.
    for _ in range(24):
        ds = 10 ** rng.uniform(-2.5, -0.05)
        dp = ds * 10 ** rng.uniform(-1, 1) if rng.random() < 0.7 else ds * (1 + rng.uniform(-1e-3, 1e-3))
        dp = min(max(dp, 10**-2.5), 0.9)
        ws = rng.random() ** 3
        if rng.random() < 0.2:
            ws *= 1e-8
        wp = 1 - ws
        c = rng.uniform(-1, 1)
        if rng.random() < 0.3:
            c = rng.choice([0.0, 0.5, 1.0]) + rng.uniform(-1, 1) * min(ds, dp)
        out.append((ws, wp, ds, dp, c, "direct"))
    # binomial: near grazing, the slower-decaying polarization carries >= 2/3 of the light.
    for _ in range(40):
        ds = 10 ** rng.uniform(-12, -5)
        dp = ds * 10 ** rng.uniform(-1, 1) if rng.random() < 0.7 else ds * (1 + rng.uniform(-1, 1) * 10 ** rng.uniform(-9, -2))
        w_maj = rng.uniform(2 / 3, 1)
        ws, wp = (w_maj, 1 - w_maj) if ds <= dp else (1 - w_maj, w_maj)
        c = rng.uniform(-1, 1)
        if rng.random() < 0.5:
            # Near a resonance: within a few 1 - |A| of an integer (or of 1/2 with a jump).
            c = rng.choice([0.0, 0.5, 1.0]) + rng.uniform(-3, 3) * min(ds, dp)
        out.append((ws, wp, ds, dp, c, "binomial"))
    # geometric limits: one polarization alone, and x = y with mixed light.
    for _ in range(12):
        d = 10 ** rng.uniform(-12, -0.1)
        w = rng.uniform(0.05, 0.95)
        c = rng.uniform(-1, 1) if rng.random() < 0.5 else rng.uniform(-3, 3) * d
        kind = rng.randrange(3)
        if kind == 0:
            out.append((1.0, 0.0, d, 10 ** rng.uniform(-12, -0.1), c, "geometric"))
        elif kind == 1:
            out.append((0.0, 1.0, 10 ** rng.uniform(-12, -0.1), d, c, "geometric"))
        else:
            out.append((w, 1 - w, d, d, c, "geometric"))
    return out


def plate_rows():
    """(angle_deg, c, method): the plate at cos(theta1) = c along (sqrt(1 - c^2), 0, -c)."""
    return [(54.0, 0.0075, "direct"), (54.0, 0.004, "direct"), (15.0, 1e-6, "binomial"), (15.0, 1e-9, "binomial")]


def plate():
    print("angle_deg,direction_x,direction_c,cos_theta_1,method,scalar,vector")
    n1, n2, d, lam = mp.mpf(1), mp.mpf("1.5"), mp.mpf("2e-6"), mp.mpf("550e-9")
    for angle, c, method in plate_rows():
        x, c1 = traced_cos(c)
        ang = mp.radians(angle)
        w = [mp.cos(ang) ** 2, mp.sin(ang) ** 2]
        C1 = mp.mpf(c1)
        big_w, xs, i0, vec = [], [], mp.mpf(0), mp.mpf(0)
        for pol in (0, 1):
            r12, t12, c2 = coeffs(n1, n2, C1, pol)
            r21, t21, _ = coeffs(n2, n1, c2, pol)
            r23, _, _ = coeffs(n2, n1, c2, pol)
            i0 += w[pol] * abs(r12) ** 2
            big_w.append(w[pol] * abs(t12 * t21 * r23) ** 2)
            xs.append(abs(r21 * r23) ** 2)
            vec += w[pol] * airy(1, mp.mpf("1.5"), 1, d, C1, lam, pol)[0]
        cyc = 2 * n2 * d * c2 / lam
        g1 = mp.sqrt(big_w[0] + big_w[1])
        sub = {"direct": direct, "binomial": binomial}[method]
        f = sub(big_w[0], big_w[1], 1 - xs[0], 1 - xs[1], cyc)
        z = mp.expjpi(2 * cyc)
        amp = mp.sqrt(i0) + z * g1 * (1 + f)
        print(f"{angle!r},{x!r},{c!r},{c1!r},{method},{mp.nstr(abs(amp) ** 2, 30)},{mp.nstr(vec, 30)}")


def main():
    if "--plate" in sys.argv:
        plate()
        return
    print("w_s,w_p,d_s,d_p,cycles,method,re,im")
    for ws, wp, ds, dp, c, method in rows():
        f = {"direct": direct, "binomial": binomial, "geometric": geometric}[method](ws, wp, ds, dp, c)
        print(
            f"{ws!r},{wp!r},{ds!r},{dp!r},{c!r},{method},"
            f"{mp.nstr(f.real, 30, min_fixed=-1, max_fixed=1)},{mp.nstr(f.imag, 30, min_fixed=-1, max_fixed=1)}"
        )


if __name__ == "__main__":
    main()
