#!/usr/bin/env python3
"""50-digit values of the fuzz-found Airy scenes where the tracer was wrong
(tests/suite/truth_airy_tracer.rs; `fringe fuzz --family airy --count 300 --seed 1`, scenes
114, 159, 175, 291, shrunk into tests/fuzz_found/; `fringe fuzz --seed 3`, airy scenes 4968 and
7540, shrunk).

Each case file is evaluated from its own numbers, at every probe point, in 50-digit
arithmetic, exactly as tools/precision_classes_mpmath.py evaluates its `airy` cases: the
direction d = normalize(sin t a - cos t N) built in binary64 as
`case::build::incidence_direction` builds it, the plate normal normalized in binary64,
cos t1 = |d.N|/(|d||N|) of those binary64 vectors in 50 digits, thickness um*1e-6 and
wavelength nm*1e-9 as the binary64 products the loader forms; then the Airy sum of
tools/airy_mpmath.py (R, or T on the transmitted side), mixed over s and p by the linear
polarization angle (the reference axis is the s direction in these scenes).

Run: python3 tools/airy_tracer_mpmath.py > tests/data/airy_tracer_mpmath.csv
"""
import json
import os

import mpmath as mp

from precision_classes_mpmath import airy_case  # the same 50-digit Airy evaluation

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))
FOUND = os.path.join(HERE, "..", "tests", "fuzz_found")
CASES = [
    "fuzz_airy_s1_114",
    "fuzz_airy_s1_159",
    "fuzz_airy_s1_175",
    "fuzz_airy_s1_291",
    "fuzz_airy_s3_4968",
    "fuzz_airy_s3_7540",
]


print("case,point,value")
for name in CASES:
    case = json.load(open(os.path.join(FOUND, name + ".json")))
    for i, v in enumerate(airy_case(case)):
        print(f"{name},{i},{mp.nstr(v, 30)}")
# #291 as its tail bound (airy_tail_epsilon 1e-12) asks the tracer for: 63 internal reflections,
# the top reflection and reflected orders 1-32, `fuzz_airy_s1_291/orders_0_31`.
case = json.load(open(os.path.join(FOUND, "fuzz_airy_s1_291.json")))
for i, v in enumerate(airy_case(case, orders=31)):
    print(f"fuzz_airy_s1_291/orders_0_31,{i},{mp.nstr(v, 30)}")
