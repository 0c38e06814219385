#!/usr/bin/env python3
"""50-digit reflectances / transmittances of the airy fuzz scenes whose Airy tail was refused
because the ray's Snell invariant lost the ambient's grazing (n0 cos t0)^2 inside the film
(issue #12), for tests/suite/truth_carried_invariant.rs.

`fringe fuzz --family airy --count 10000` (main 3eb0153) refused four scenes as "the Airy tail cannot
be closed exactly" (seed 1: 3916, 5719, 8311; seed 2: 3914); the two the fix closes (8311, seed 2
3914) are evaluated here. Each case file tests/fuzz_found/<name>.json (written by the generator, as
drawn) is evaluated at every probe point by `airy_case` of tools/precision_classes_mpmath.py
(imported, not copied): the binary64 direction and normal as the loader forms them, cos t1 from
them in 50 digits, the Airy sum of tools/airy_mpmath.py, times the source's intensity.
Run: python3 tools/carried_invariant_mpmath.py > tests/data/carried_invariant_mpmath.csv
"""
import json
import os
import sys

import mpmath as mp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from precision_classes_mpmath import FOUND, airy_case  # noqa: E402

mp.mp.dps = 50
NAMES = ["fuzz_airy_s1_8311", "fuzz_airy_s2_3914"]

if __name__ == "__main__":
    print("case,point,value")
    for name in NAMES:
        case = json.load(open(os.path.join(FOUND, name + ".json")))
        intensity = mp.mpf(case["scene"]["sources"][0]["intensity"])
        for k, v in enumerate(airy_case(case)):
            print(f"{name},{k},{mp.nstr(v * intensity, 30)}")
