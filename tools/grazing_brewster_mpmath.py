#!/usr/bin/env python3
"""50-digit R or T of the grazing films near Brewster's angle and the thick plate near the
critical angle that `fringe fuzz --family airy` failed at 3eb0153 (issue #12;
tests/suite/truth_grazing_brewster.rs): seed 1 scenes 6567 and 7304 (with its unrotated and
p-polarized variants), seed 2 scenes 2213 and 7972, shrunk into tests/fuzz_found/; and 6567
and 2213 shrunk again after the carried Snell invariant (they keep their rotation: `_rotated`).

Each case file is evaluated from its own binary64 numbers by
tools/precision_classes_mpmath.py `airy_case` (the direction built in binary64 as
`case::build::incidence_direction` builds it, cos t1 = |d.N|/(|d||N|) of those vectors in 50
digits, then the Airy sum of tools/airy_mpmath.py mixed over s and p by the linear
polarization angle). It is also evaluated with the direction normalized once
more in binary64 (as the tracer's launch holds it); the script asserts the two agree to 1e-18
relatively, so the value does not depend on that rounding.

The two 7304 scenes are also given as the cut sum their tail bound asks for (orders 0-15).

Run: python3 tools/grazing_brewster_mpmath.py > tests/data/grazing_brewster_mpmath.csv
"""
import json
import os

import mpmath as mp

from precision_classes_mpmath import airy_case

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))
FOUND = os.path.join(HERE, "..", "tests", "fuzz_found")
CASES = [
    "fuzz_airy_s1_6567",
    "fuzz_airy_s2_2213",
    "fuzz_airy_s1_6567_rotated",
    "fuzz_airy_s2_2213_rotated",
    "fuzz_airy_s1_7304",
    "fuzz_airy_s1_7304_p",
    "fuzz_airy_s1_7304_unrotated",
    "fuzz_airy_s2_7972",
]
CUT = ["fuzz_airy_s1_7304", "fuzz_airy_s1_7304_p"]


def main():
    print("case,point,value")
    for name in CASES:
        case = json.load(open(os.path.join(FOUND, name + ".json")))
        values = airy_case(case)
        again = airy_case(case, extra_normalizations=1)
        for i, (v, w) in enumerate(zip(values, again)):
            assert abs(v - w) <= mp.mpf("1e-18") * abs(v), (name, i, v, w)
            print(f"{name},{i},{mp.nstr(v, 30)}")
    # The transmitted orders 0-15 alone: the sum the case's tail bound (airy_tail_epsilon 1e-15)
    # asks the tracer for (31 internal reflections), `<name>/orders_0_15`.
    for name in CUT:
        case = json.load(open(os.path.join(FOUND, name + ".json")))
        for i, v in enumerate(airy_case(case, orders=15)):
            print(f"{name}/orders_0_15,{i},{mp.nstr(v, 30)}")


if __name__ == "__main__":
    main()
