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
from mp_two_beam import intensity_at, landing

mp.mp.dps = 50


def intensity(n1, n2, d, hs, ho, x, lam, r_top=None):
    N1, N2, D, HS, HO, X, LAM = map(mp.mpf, (n1, n2, d, hs, ho, x, lam))

    land = landing(N1, N2, D, HS, HO, X)

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
    return intensity_at(N1, N2, D, HS, HO, X, LAM, a, r_top)


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
