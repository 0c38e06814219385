#!/usr/bin/env python3
"""50-digit Airy reflectances and transmittances of grazing plates whose tail needs more than
2000 internal reflections, for tests/suite/airy_tail.rs (the tail closure, docs/PHYSICS.md 5a).

Each row is one case the test builds: a film (index n2, thickness d) between the ambient n1 (the
light's side) and n3 below, a plane wave along (sqrt(1 - c^2), 0, -c) in f64, as written into
the case file; the tracer normalizes that direction (glam: v * (1/sqrt(x*x + y*y + z*z))), so
the cosine it meets is cos_theta_1 = c * (1/sqrt(...)) in f64, replicated here exactly and
checked bitwise by the test. R and T from tools/airy_mpmath.py's 50-digit Airy sum (T: power
transmittance n3 cos t3/(n1 cos t1)|t|^2). Configurations: a free-standing film (n3 = n1), a
film with total reflection at its bottom face (n1 = 1.5 > n3 = 1, reflected only), and a film on
a substrate barely denser than the ambient (n3 = n1 (1 + 1e-9): its face reflects almost totally
at grazing too, and light still goes through); s and p; cos = 1e-3, 1e-6, 1e-9.
Run: python3 tools/airy_tail_mpmath.py > tests/data/airy_tail_mpmath.csv
"""
import math
import os
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from airy_mpmath import airy  # noqa: E402

mp.mp.dps = 50


def traced_cos(c):
    """The cosine the tracer meets for the case direction (sqrt(1 - c^2), 0, -c) (f64)."""
    x = math.sqrt(1.0 - c * c)
    z = -c
    length = math.sqrt((x * x + 0.0 * 0.0) + z * z)
    rec = 1.0 / length
    return x, -z * rec


def main():
    print("n1,n2,n3,thickness_m,direction_x,direction_c,cos_theta_1,lambda_m,pol,side,value")
    configs = [
        # (n1, n2, n3, sides)
        (1.0, 1.5, 1.0, ("reflected", "transmitted")),
        (1.5, 1.7, 1.0, ("reflected",)),
        (1.0, 1.5, 1.000000001, ("reflected", "transmitted")),
    ]
    lam = 550e-9
    k = 0
    for c in (1e-3, 1e-6, 1e-9):
        for n1, n2, n3, sides in configs:
            for pol in (0, 1):
                # Thicknesses spread over a few micrometres: different round-trip phases.
                d = [1.0e-6, 1.37e-6, 2.9e-6, 4.123e-6, 0.61e-6][k % 5]
                k += 1
                x, c1 = traced_cos(c)
                R, T = airy(n1, n2, n3, d, c1, lam, pol)
                for side in sides:
                    v = R if side == "reflected" else T
                    vals = [n1, n2, n3, d, x, c, c1, lam]
                    print(
                        ",".join(repr(v) for v in vals)
                        + f",{'s' if pol == 0 else 'p'},{side},"
                        + mp.nstr(v, 30)
                    )


if __name__ == "__main__":
    main()
