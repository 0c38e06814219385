#!/usr/bin/env python3
"""50-digit two-beam plate intensities for tests/suite/closed_form_precision.rs.

Point source at height h_s above a plate (index n2, thickness d, the same medium n1 above and
below), observation point at height h_o and lateral distance x (paper Fig. 4 left; PHYSICS.md
sec. 5 "Plate, two beams"). Beam 1 reflects at the top face: path n1 sqrt(x^2 + (h_s + h_o)^2),
amplitudes r12. Beam 2 enters at lateral a (solved here with mpmath.findroot at 50 digits),
reflects at the bottom, leaves: path n1 L1 + 2 n2 d / cos t + n1 L3, amplitudes t12 r23 t21.
Unpolarized source with channels s and p at every ray:

    I = 1/2 |A1s e^{i phi} + A2s|^2 + 1/2 (|A1p|^2 + |A2p|^2 + 2 Re(A1p A2p* e^{i phi}) cos(th1 - th2)),

phi = 2 pi (Op1 - Op2)/lam. Fresnel coefficients in the cosine forms (P1-P4). Inputs are
written with repr() and read back exactly. Incidence from 0 to 89.99 degrees, near grazing
included. Run: python3 tools/two_beam_mpmath.py > tests/data/two_beam_mpmath.csv
"""
import math
import random

import mpmath as mp
from mp_two_beam import intensity_at, landing

mp.mp.dps = 50
rng = random.Random(1128)


print("n1,n2,thickness_m,h_src_m,h_obs_m,x_m,lambda_m,intensity")
for k in range(40):
    n1 = rng.choice([1.0, 1.333])
    n2 = rng.choice([1.5, 1.7, 2.4])
    d = rng.choice([1e-6, 1e-5, 1e-4, 1e-3])
    hs = rng.choice([0.01, 0.05, 0.1])
    ho = rng.choice([0.01, 0.05, 0.1])
    lam = rng.choice([400e-9, 550e-9, 700e-9])
    deg = rng.choice([0.0, 10.0, 45.0, 70.0, 85.0, 89.0, 89.9, 89.99])
    x = (hs + ho) * math.tan(math.radians(deg)) + rng.uniform(0, 1e-3)
    N1, N2, D, HS, HO, X, LAM = map(mp.mpf, (n1, n2, d, hs, ho, x, lam))

    land = landing(N1, N2, D, HS, HO, X)
    a = mp.findroot(land, (mp.mpf(0), X), solver="anderson")
    I = intensity_at(N1, N2, D, HS, HO, X, LAM, a)[0]
    print(",".join(repr(v) for v in (n1, n2, d, hs, ho, x, lam)) + "," + mp.nstr(I, 30))
