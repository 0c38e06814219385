#!/usr/bin/env python3
"""50-digit truth for the plate scenes whose beam through the plate the path solver could not
land (issue #12), for tests/suite/truth_plate_landing.rs.

`fringe fuzz --family two_beam_plate --count 10000 --seed 1` (main 3550238) refused 80 scenes
with "could not land the path T0 R1 T0": a plate less dense than its ambient (n2 < n1) seen
near grazing, whose beam through the plate enters below the top face's critical angle and
runs grazing inside (tan t up to 1e11 in a 1.2 nm plate). Six of them, their probe lines cut
to the two end points, are tests/fuzz_found/fuzz_two_beam_plate_s1_<n>.json.

Two tables, both `case,point,value` (one row per probe point):
- tests/data/plate_landing_mpmath.csv: the two-beam intensity I (as
  tools/two_beam_plate_near_critical_mpmath.py evaluates it, times the source's intensity: the formulas of
  tools/mp_two_beam.py, the beam through the plate solved in w = tan t by bisection, the top
  beam the plate's frustrated r_layer beyond the critical angle, basis-free sources with
  cos^2 in the p cross term);
- tests/data/plate_landing_paths_mpmath.csv: the beam through the plate itself, cases
  `<name>/run` (its lateral run inside the plate, 2 d tan t, m), `<name>/path` (its optical
  path n1 L1 + 2 n2 d / cos t + n1 L3, m), `<name>/cos_t` (cos t inside the plate) and
  `<name>/amp_s`, `<name>/amp_p`: the magnitude of its Fresnel product t12 r21 t21 per
  polarization (in at the top face, reflected at the bottom face from inside, out at the top
  face; docs/PHYSICS.md §1), which is ∝ cos t near grazing inside.
Inputs are the case files' own binary64 numbers (heights and lateral distance along the
plate's normal normalized at 50 digits; thickness_um * 1e-6, wavelength_nm * 1e-9 in binary64).
Run (from the repository root):
  python3 tools/plate_landing_mpmath.py intensity > tests/data/plate_landing_mpmath.csv
  python3 tools/plate_landing_mpmath.py paths > tests/data/plate_landing_paths_mpmath.csv
"""
import json
import os
import sys

import mpmath as mp
from two_beam_plate_near_critical_mpmath import geometry as case_geometry, intensity, tan_theta_t

mp.mp.dps = 50
M = mp.mpf

FOUND = [271, 1128, 2105, 4795, 6899, 9551]
HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fuzz_found")


def through(n1, n2, d, hs, ho, x):
    """(w = tan t, optical path) of the beam through the plate (n2 < n1)."""
    w = tan_theta_t(n1, n2, d, hs, ho, x)
    s1 = n2 / n1 * w / mp.sqrt(1 + w * w)
    t1 = s1 / mp.sqrt(1 - s1 * s1)
    a, b = hs * t1, ho * t1
    l1, l3 = mp.sqrt(a * a + hs * hs), mp.sqrt(b * b + ho * ho)
    cos_t = 1 / mp.sqrt(1 + w * w)
    return w, n1 * l1 + 2 * n2 * d / cos_t + n1 * l3


def geometry(name):
    """The two end points' geometry of found case `name`, a plate rarer than its ambient."""
    points = case_geometry(json.load(open(os.path.join(HERE, name + ".json"))))
    assert all(n2 < n1 for (n1, n2, *_) in points)
    return points


if __name__ == "__main__":
    what = sys.argv[1]
    print("case,point,value")
    for n in FOUND:
        name = f"fuzz_two_beam_plate_s1_{n}"
        points = geometry(name)
        if what == "intensity":
            # The source's intensity scales the traced field intensity (|E|² of a unit source).
            c = json.load(open(os.path.join(HERE, name + ".json")))
            i0 = M(c["scene"]["sources"][0]["intensity"])
            for k, g in enumerate(points):
                print(f"{name},{k},{mp.nstr(i0 * intensity(*g), 30)}")
            continue
        rows = {"run": [], "path": [], "cos_t": [], "amp_s": [], "amp_p": []}
        for (n1, n2, d, hs, ho, x, _, _) in points:
            w, op = through(n1, n2, d, hs, ho, x)
            rows["run"].append(2 * d * w)
            rows["path"].append(op)
            c2 = 1 / mp.sqrt(1 + w * w)
            s1 = n2 / n1 * w * c2
            c1 = mp.sqrt((1 - s1) * (1 + s1))
            rows["cos_t"].append(c2)
            # |t12 t21| |r21| per polarization, the plate (n2) between ambients n1.
            a, b = n1 * c1, n2 * c2
            rows["amp_s"].append(4 * a * b / (a + b) ** 2 * abs((b - a) / (b + a)))
            a, b = n2 * c1, n1 * c2
            rows["amp_p"].append(4 * a * b / (a + b) ** 2 * abs((b - a) / (b + a)))
        for key, values in rows.items():
            for k, v in enumerate(values):
                print(f"{name}/{key},{k},{mp.nstr(v, 30)}")
