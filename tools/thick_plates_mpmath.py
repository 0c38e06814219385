#!/usr/bin/env python3
"""50-digit values of thick plates in a rotated frame, as written and as held
(tests/suite/truth_thick_plates.rs and truth_airy_tracer.rs; issue #12, `fringe fuzz --count 300 --seed 1`, airy scene
159 in its rotated frame: a 1 m plate, n 10 -> 1.5 -> 10, 200 nm, transmitted, 0-10 deg).

For each case file in tests/fuzz_found/ named below, at every probe point, the Airy sum of
tools/airy_mpmath.py in 50 digits (as tools/precision_classes_mpmath.py evaluates its `airy`
cases; s polarization: the reference axis is the s direction in these scenes) at two incident
directions:

* `written/<case>`: d = normalize(sin t a - cos t N) built in binary64 exactly as
  `case::build::incidence_direction` builds it, i.e. the direction the case asks for;
* `held/<case>`: that d normalized once more in binary64 (glam's v * (1/|v|)), as the scene
  holds a plane wave's direction (`scene::source`): a turn of ~1e-17 rad, one rounding.

cos t1 = |d.N|/(|d||N|) of the binary64 vectors in 50 digits, N the plate normal normalized
in binary64 as `geometry::Plane` holds it; thickness um*1e-6 and wavelength nm*1e-9 as the
binary64 products the loader forms.

Run: python3 tools/thick_plates_mpmath.py > tests/data/thick_plates_mpmath.csv
"""
import json
import os

import mpmath as mp

from precision_classes_mpmath import airy_case

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))
FOUND = os.path.join(HERE, "..", "tests", "fuzz_found")
CASES = ["fuzz_airy_s1_159_rotated", "fuzz_airy_s1_159"]


print("case,point,value")
for name in CASES:
    case = json.load(open(os.path.join(FOUND, name + ".json")))
    for label, extra in (("written", 0), ("held", 1)):
        for i, v in enumerate(airy_case(case, extra)):
            print(f"{label}/{name},{i},{mp.nstr(v, 30)}")
