#!/usr/bin/env python3
"""50-digit two-beam plate intensities beyond the top face's critical angle, for
tests/suite/truth_beyond_critical_plates.rs.

An ambient denser than the plate (n1 > n2): the top beam is totally reflected (cos t imaginary,
cos t = +i sqrt(...) for e^{-i omega t}, docs/PHYSICS.md sec. 5, so |r12| = 1 with a phase), and
the beam through the plate enters below the critical angle, at lateral offset a < a_c =
n2 h_s / sqrt(n1^2 - n2^2), and runs grazing inside the plate. The formulas are those of
tools/two_beam_mpmath.py (which uses findroot on (0, x) and real squares, so it fails here:
beyond a_c the landing function is complex); here the entry offset is bisected on (0, min(x, a_c))
at 50 digits and every square is |.|^2. Unpolarized source with channels s and p at every ray:

    I = 1/2 |A1s e^{i phi} + A2s|^2 + 1/2 (|A1p|^2 + |A2p|^2 + 2 Re(A1p A2p* e^{i phi}) cos(th1 - th2)).

Inputs are written with repr() and read back exactly.
Run: python3 tools/beyond_critical_plate_mpmath.py > tests/data/beyond_critical_plate_mpmath.csv
"""
import mpmath as mp

mp.mp.dps = 50


def fresnel(n1, n2, ci):
    st2 = (n1 / n2) ** 2 * (1 - ci * ci)
    ct = mp.sqrt(1 - st2)  # +i sqrt(st2 - 1) beyond the critical angle
    rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct)
    rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct)
    ts = 2 * n1 * ci / (n1 * ci + n2 * ct)
    tp = 2 * n1 * ci / (n2 * ci + n1 * ct)
    return rs, rp, ts, tp, ct


def intensity(n1, n2, d, hs, ho, x, lam):
    N1, N2, D, HS, HO, X, LAM = map(mp.mpf, (n1, n2, d, hs, ho, x, lam))

    def land(a):
        l1 = mp.sqrt(a * a + HS * HS)
        st = N1 / N2 * a / l1
        return a + 2 * D * st / mp.sqrt(1 - st * st) + HO * a / HS - X

    hi = X if N1 <= N2 else min(X, N2 * HS / mp.sqrt(N1 * N1 - N2 * N2))
    lo = mp.mpf(0)
    for _ in range(400):
        m = (lo + hi) / 2
        v = land(m)
        if not isinstance(v, mp.mpf) or v > 0:
            hi = m
        else:
            lo = m
    a = (lo + hi) / 2
    l1 = mp.sqrt(a * a + HS * HS)
    st = N1 / N2 * a / l1
    ct = mp.sqrt(1 - st * st)
    xe = a + 2 * D * st / ct
    l3 = mp.sqrt((X - xe) ** 2 + HO * HO)
    op2 = N1 * l1 + 2 * N2 * D / ct + N1 * l3
    op1 = N1 * mp.sqrt(X * X + (HS + HO) ** 2)
    ci1 = (HS + HO) / mp.sqrt(X * X + (HS + HO) ** 2)
    ci2 = HS / l1
    r12s, r12p, _, _, _ = fresnel(N1, N2, ci1)
    _, _, t12s, t12p, _ = fresnel(N1, N2, ci2)
    r23s, r23p, t21s, t21p, _ = fresnel(N2, N1, ct)
    A1s, A1p = r12s, r12p
    A2s, A2p = t12s * r23s * t21s, t12p * r23p * t21p
    e = mp.expjpi(2 * (op1 - op2) / LAM)
    th1 = mp.atan2(X, HS + HO)
    th2 = mp.atan2(a, HS)
    i_s = abs(A1s * e + A2s) ** 2
    i_p = abs(A1p) ** 2 + abs(A2p) ** 2 + 2 * mp.re(A1p * mp.conj(A2p) * e) * mp.cos(th1 - th2)
    tan_t = st / ct
    return (i_s + i_p) / 2, tan_t


# (n1, n2, d, h_s, h_o, x, lambda): the shrunk fuzz scene 122 of `fringe fuzz --family
# two_beam_plate --seed 1` (unrotated: n = 1 over a 1 m plate of n = 0.001, 200 nm, top beam at
# 89.0 deg and 89.5 deg, the beam through the plate at tan t = 62.5 and 125), and glass over
# an air gap (n = 1.5 over n = 1) beyond the 41.8 deg critical angle.
rows = [
    (1.0, 0.001, 1.0, 0.7271836015534833, 1.4543672031069666, 125.0, 200e-9),
    (1.0, 0.001, 1.0, 0.7271836015534833, 1.4543672031069666, 250.0, 200e-9),
    (1.0, 0.001, 1.0, 0.7271836015534833, 1.4543672031069666, 60.0, 200e-9),
    (1.5, 1.0, 0.001, 0.01, 0.02, 0.05, 550e-9),
    (1.5, 1.0, 0.001, 0.01, 0.02, 0.2, 550e-9),
]
if __name__ == "__main__":
    print("n1,n2,thickness_m,h_src_m,h_obs_m,x_m,lambda_m,tan_theta_t,intensity")
    for r in rows:
        I, tan_t = intensity(*r)
        print(",".join(repr(v) for v in r) + "," + mp.nstr(tan_t, 6) + "," + mp.nstr(I, 30))
