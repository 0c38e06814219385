#!/usr/bin/env python3
"""50-digit (60 here) two-beam plate intensities where the beam through the plate runs steeply
grazing inside it (tan theta_t from 1e2 to 1e10), for tests/suite/truth_refusals.rs.

An ambient denser than the plate (n1 > n2), the top beam beyond the top face's critical angle:
the beam through the plate enters just below the critical angle and covers the lateral distance
inside the plate. The reference once refused tan theta_t > 1e3 (its f64 root solve in the entry
offset a cannot resolve a_c - a ~ cos^2 theta_t); `TwoBeamPlate::beam_bottom` now solves for
tan theta_t in double-double. The formulas, bisection and intensity are those of
tools/beyond_critical_plate_mpmath.py (imported, not copied), at 60 digits, with the top beam's
frustrated r_layer from tools/tunnelling_mpmath.py: cos^2 theta_t = 1e-20
needs a_c - a to 1e-40 of a_c.

Each row's x is made in float from a target w = tan theta_t by x = (h_s + h_o) tan theta + 2 d w,
tan theta = r w / sqrt(1 + (1 - r^2) w^2), r = n2/n1; the tan theta_t column is mpmath's.
Inputs are written with repr() and read back exactly.
Run: python3 tools/steep_plate_mpmath.py > tests/data/steep_plate_mpmath.csv
"""
import math
import os
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from beyond_critical_plate_mpmath import intensity  # noqa: E402
from tunnelling_mpmath import r_layer  # noqa: E402

mp.mp.dps = 60

# (n1, n2, d, h_s, h_o, lambda): the media and plate of refused fuzz scenes of `fringe fuzz
# --family two_beam_plate --seed 1` (25: n 4.76 over 0.0092, 3.35 um; 23: 1.90 over 1.73,
# 0.49 mm; 91: air over 0.0062, 6.5 mm; 85: 0.035 over 0.019, 16 mm) with chosen heights, and
# glass over an air gap.
plates = [
    (4.76161309145762, 0.009241371245341832, 3.352895232544878e-6, 0.3, 0.7, 633e-9),
    (1.9027491589246552, 1.7295601099511728, 4.892275336341095e-4, 1.25, 0.5, 450e-9),
    (1.0, 0.0061777538428291695, 6.452920689674061e-3, 2.0, 3.0, 1.2e-6),
    (0.035184276289052775, 0.01922230405959967, 1.624458471119693e-2, 0.01, 0.02, 550e-9),
    (1.5, 1.0, 1e-3, 0.01, 0.02, 550e-9),
]
targets = [1e2, 1e3, 1e5, 1e8, 1e10]

if __name__ == "__main__":
    print("n1,n2,thickness_m,h_src_m,h_obs_m,x_m,lambda_m,tan_theta_t,intensity")
    for (n1, n2, d, hs, ho, lam) in plates:
        r = n2 / n1
        for w in targets:
            x = (hs + ho) * r * w / math.sqrt(1 + (1 - r * r) * w * w) + 2 * d * w
            row = (n1, n2, d, hs, ho, x, lam)
            # The top beam, beyond the top face's critical angle, takes the plate's frustrated
            # total reflection r_layer (the plane-wave Airy sum with imaginary cos theta_2).
            c_top = mp.mpf(hs + ho) / mp.sqrt(mp.mpf(x) ** 2 + mp.mpf(hs + ho) ** 2)
            r_top = tuple(r_layer(*map(mp.mpf, (n1, n2, d)), c_top, mp.mpf(lam), p) for p in (0, 1))
            I, tan_t = intensity(*row, r_top=r_top)
            print(",".join(repr(v) for v in row) + "," + mp.nstr(tan_t, 6) + "," + mp.nstr(I, 30))
