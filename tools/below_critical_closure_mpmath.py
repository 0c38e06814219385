#!/usr/bin/env python3
"""50-digit reflectances and transmittances of the below-critical fuzz scenes of
tests/suite/truth_tail_closure.rs: films lit 1e-10 deg - 1 deg below the critical angle of their
top face, where the wave inside grazes the film and the Airy tail beyond the cap of internal
reflections is closed exactly (docs/PHYSICS.md 5a). Each shrunk case file
tests/fuzz_found/fuzz_airy_s1_<index>.json is evaluated at every probe point by `airy_case` of
tools/precision_classes_mpmath.py (imported, not copied), times the source's intensity.
Run: python3 tools/below_critical_closure_mpmath.py > tests/data/below_critical_closure_mpmath.csv
"""
import json
import os
import sys

import mpmath as mp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from precision_classes_mpmath import FOUND, airy_case  # noqa: E402

mp.mp.dps = 50
SCENES = [77, 108, 117, 203]


def main():
    print("case,point,value")
    for index in SCENES:
        name = f"fuzz_airy_s1_{index}"
        case = json.load(open(os.path.join(FOUND, name + ".json")))
        intensity = mp.mpf(case["scene"]["sources"][0]["intensity"])
        for k, v in enumerate(airy_case(case)):
            v *= intensity
            print(f"{name},{k},{mp.nstr(v, 30)}")


if __name__ == "__main__":
    main()
