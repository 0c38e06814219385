#!/usr/bin/env python3
"""50-digit values of the fuzz-found scenes of tests/suite/truth_small_deviations.rs: the
deviations of 1e-12 ... 4e-11 (`fringe fuzz --count 300 --seed 1`, shrunk into
tests/fuzz_found/), each evaluated from the case file's own binary64 numbers.

* airy (fuzz_airy_s1_{230,253,283,1,207}, and 207 moved to the origin): the Airy sum of
  tools/precision_classes_mpmath.py (`airy_case`: the direction built in binary64 as the loader
  builds it, cos t1 of those vectors in 50 digits, R or T mixed over s and p).
* two_beam_plate (fuzz_two_beam_plate_s1_181, a 0.1 nm plate at a dark fringe): the two-beam
  intensity of tools/two_beam_plate_found_mpmath.py (paper two-channel unpolarized source, the
  entry point solved by findroot, heights and lateral distance along the plate normal).
* wedge (fuzz_wedge_s1_{109,291} from `--count 300 --seed 1`, {538,638,866} from
  `--family wedge --count 1000 --seed 1`): the independent 50-digit ray trace of tools/wedge_mpmath.py
  (`intensity`), the bottom face through (0, 0, -t0) with the binary64 normal
  (sin a, 0, cos a), a = radians(angle_deg), as the scene builder makes it (hinge along y, top
  normal +z, top point at the origin in both scenes).

Run: python3 tools/small_deviations_mpmath.py > tests/data/small_deviations_mpmath.csv
"""
import contextlib
import io
import json
import math
import os
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from precision_classes_mpmath import airy_case  # noqa: E402
import wedge_mpmath  # noqa: E402

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))
FOUND = os.path.join(HERE, "..", "tests", "fuzz_found")


def two_beam_module():
    """tools/two_beam_plate_found_mpmath.py's functions, without running its own printout."""
    src = open(os.path.join(HERE, "two_beam_plate_found_mpmath.py")).read()
    src = src.split('print("fuzz_two_beam_plate_s7_5")')[0]
    ns = {}
    exec(compile(src, "two_beam_plate_found_mpmath.py", "exec"), ns)
    return ns


def load(name):
    return json.load(open(os.path.join(FOUND, name + ".json")))


def line_points(probe):
    line = probe["line"]
    a, b, n = line["from_m"], line["to_m"], line["count"]
    if n == 1:
        return [a]
    return [[x + (y - x) * i / (n - 1) for x, y in zip(a, b)] for i in range(n)]


def medium(case, name):
    return case["scene"]["media"][name]["constant"]["n"]


def two_beam_case(case):
    ns = two_beam_module()
    plate = case["scene"]["surfaces"][0]["plate"]
    assert plate["above"] == plate["below"] == case["scene"]["ambient"]
    src = case["scene"]["sources"][0]["emitter"]["point"]["position_m"]
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        ns["scene"](plate["normal"], plate["top_point_m"], src, line_points(case["probe"]),
                    medium(case, plate["above"]), medium(case, plate["medium"]),
                    plate["thickness_um"], case["light"]["monochrome"]["wavelength_nm"])
    return [mp.mpf(v) for v in out.getvalue().split()]


def wedge_case(case):
    w = case["scene"]["surfaces"][0]["wedge"]
    assert w["normal"] == [0.0, 0.0, 1.0] and w["hinge_axis"] == [0.0, 1.0, 0.0]
    assert w["top_point_m"] == [0.0, 0.0, 0.0]
    a = math.radians(w["angle_deg"])
    t0 = w["thickness_um"] * 1e-6
    lam = case["light"]["monochrome"]["wavelength_nm"] * 1e-9
    n1, n, n3 = (medium(case, w[k]) for k in ("above", "medium", "below"))
    return [
        wedge_mpmath.intensity([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -t0],
                               [math.sin(a), 0.0, math.cos(a)], p, n1, n, n3, lam)
        for p in line_points(case["probe"])
    ]


CASES = [
    ("fuzz_airy_s1_230", airy_case),
    ("fuzz_airy_s1_253", airy_case),
    ("fuzz_airy_s1_283", airy_case),
    ("fuzz_airy_s1_1", airy_case),
    ("fuzz_airy_s1_207", airy_case),
    ("fuzz_airy_s1_207_at_origin", airy_case),
    ("fuzz_two_beam_plate_s1_181", two_beam_case),
    ("fuzz_wedge_s1_109", wedge_case),
    ("fuzz_wedge_s1_291", wedge_case),
    ("fuzz_wedge_s1_538", wedge_case),
    ("fuzz_wedge_s1_638", wedge_case),
    ("fuzz_wedge_s1_866", wedge_case),
]

print("case,point,value")
for name, evaluate in CASES:
    for i, v in enumerate(evaluate(load(name))):
        print(f"{name},{i},{mp.nstr(v, 30)}")
