#!/usr/bin/env python3
"""50-digit reflectances of the frustrated-film fuzz scenes in tests/suite/truth_tail_closure.rs.

Scenes of `fringe fuzz --family airy --seed 1` (count 300) observed on the reflected side beyond
the critical angle of the film's top face (an evanescent film: frustrated total reflection),
which were refused as "the Airy tail ... cannot be closed exactly" although no order enters the
film there. Each case file tests/fuzz_found/fuzz_airy_s1_<index>.json (unpolarized light) is
evaluated at every probe point by `airy_case` of tools/precision_classes_mpmath.py (imported,
not copied): the binary64 direction and normal as the loader forms them, cos t1 from them in 50
digits, the Airy sum of tools/airy_mpmath.py with complex cos t2 beyond the critical angle,
times the source's intensity.
Run: python3 tools/frustrated_film_found_mpmath.py > tests/data/frustrated_film_mpmath.csv
"""
import json
import os
import sys

import mpmath as mp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from precision_classes_mpmath import FOUND, airy_case  # noqa: E402

mp.mp.dps = 50
SCENES = [6, 55, 80, 119]


def print_profiles(scenes, check=lambda case: None):
    """case,point,value rows of the found airy scenes `scenes` (seed 1): `airy_case` at every
    probe point times the source's intensity; `check(case)` may assert what the scene must be."""
    print("case,point,value")
    for index in scenes:
        name = f"fuzz_airy_s1_{index}"
        case = json.load(open(os.path.join(FOUND, name + ".json")))
        check(case)
        intensity = mp.mpf(case["scene"]["sources"][0]["intensity"])
        for k, v in enumerate(airy_case(case)):
            v *= intensity
            print(f"{name},{k},{mp.nstr(v, 30)}")


def unpolarized(case):
    assert "unpolarized" in case["scene"]["sources"][0]["polarization"]


if __name__ == "__main__":
    print_profiles(SCENES, unpolarized)
