#!/usr/bin/env python3
"""50-digit values of layers traced beyond their top face's critical angle (frustrated total
reflection, PHYSICS.md sec. 5) for tests/suite/truth_tunnelling.rs.

Airy cases (tests/tunnelling/*.json, observed on the reflected side, and
tests/tunnelling_transmitted/*.json, the same films and one whose substrate is beyond its own
critical angle over part of the sweep, observed on the transmitted side: the tunnelled wave
the tracer starts on the far face, EventKind::Tunnel): each case file is evaluated from
its own numbers at every probe point, as tools/precision_classes_mpmath.py evaluates its `airy`
cases (the incidence direction built in binary64 as `case::build::incidence_direction` builds
it, cos t1 = |d.N|/(|d||N|) of the binary64 vectors in 50 digits, thickness um*1e-6 and
wavelength nm*1e-9 as the binary64 products the loader forms), then the Airy sum of
tools/airy_mpmath.py with the complex cos t2 = +i sqrt(n1^2 sin^2 t1 - n2^2)/n2 (e^{-i w t}):
R or T = (n3 cos t3)/(n1 cos t1)|t|^2 (0 where n1 sin t1 >= n3: no wave leaves), mixed over s and p by the source's polarization (linear at angle a from the s axis: cos^2 a
of s; the paper's two unpolarized channels: 1/2 each).

Two-beam case (TWO_BEAM below, the scene tests/suite/truth_tunnelling.rs builds): a point source
over a layer of index n2 < n1 between two half-spaces n1, the top beam beyond the critical angle:
its amplitude is the layer's plane-wave reflection r_layer at its angle (the Airy sum with
complex cos t2, not the face's r12), the beam through the layer (entering below the critical
angle, entry point by findroot) as in tools/beyond_critical_mpmath.py; unpolarized light in
the paper's two channels.

Run: python3 tools/tunnelling_mpmath.py > tests/data/tunnelling_mpmath.csv
"""
import glob
import json
import os
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from airy_mpmath import coeffs  # noqa: E402
from mp_two_beam import intensity_at  # noqa: E402
from precision_classes_mpmath import airy_case  # noqa: E402

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))
CASES = os.path.join(HERE, "..", "tests", "tunnelling")
TRANSMITTED = os.path.join(HERE, "..", "tests", "tunnelling_transmitted")


def r_layer(n1, n2, d, c1, lam, pol):
    """The plane-wave reflection of a layer n2 (thickness d) between two half-spaces n1."""
    r12, t12, c2 = coeffs(n1, n2, c1, pol)
    r21, t21, _ = coeffs(n2, n1, c2, pol)
    r23, _, _ = coeffs(n2, n1, c2, pol)
    e = mp.expjpi(4 * n2 * d * c2 / lam)
    return r12 + t12 * t21 * r23 * e / (1 - r21 * r23 * e)


def two_beam(n1, n2, d, hs, ho, x, lam):
    n1, n2, d, hs, ho, x, lam = map(mp.mpf, (n1, n2, d, hs, ho, x, lam))
    ac = n2 * hs / mp.sqrt(n1 * n1 - n2 * n2) if n1 > n2 else x

    def land(a):
        st = n1 / n2 * a / mp.sqrt(a * a + hs * hs)
        return a + 2 * d * st / mp.sqrt(1 - st * st) + ho * a / hs - x

    a = mp.findroot(land, (mp.mpf(0), min(x, ac * (1 - mp.mpf(10) ** -40))), solver="anderson")
    c_top = (hs + ho) / mp.sqrt(x * x + (hs + ho) ** 2)
    r_top = (r_layer(n1, n2, d, c_top, lam, 0), r_layer(n1, n2, d, c_top, lam, 1))
    return intensity_at(n1, n2, d, hs, ho, x, lam, a, r_top)[0]


# (name, n1, n2, thickness_m, h_src_m, h_obs_m, lambda_m, [x_m ...]) as the loader forms them
# (thickness_um * 1e-6, nm * 1e-9): a dense ambient (1.5) over a 2 um air gap, source 1 cm and
# probe 2 cm above it; the top beam 1 mm beyond the lateral distance of the critical angle.
TWO_BEAM = [
    ("two_beam_gap", 1.5, 1.0, 2.0 * 1e-6, 0.01, 0.02, 500.0 * 1e-9, [0.02783281572999748]),
]


def main():
    print("case,point,value")
    for path in sorted(glob.glob(os.path.join(CASES, "*.json"))):
        case = json.load(open(path))
        name = case["name"]
        for i, v in enumerate(airy_case(case)):
            print(f"{name},{i},{mp.nstr(v, 30)}")
    for name, n1, n2, d, hs, ho, lam, xs in TWO_BEAM:
        for k, x in enumerate(xs):
            print(f"{name},{k}," + mp.nstr(two_beam(n1, n2, d, hs, ho, x, lam), 30))
    for path in sorted(glob.glob(os.path.join(TRANSMITTED, "*.json"))):
        case = json.load(open(path))
        name = case["name"]
        for i, v in enumerate(airy_case(case)):
            print(f"{name},{i},{mp.nstr(v, 30)}")


if __name__ == "__main__":
    main()
