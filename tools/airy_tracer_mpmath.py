#!/usr/bin/env python3
"""50-digit values of the fuzz-found Airy scenes where the tracer was wrong
(tests/suite/truth_airy_tracer.rs; `fringe fuzz --family airy --count 300 --seed 1`, scenes
114, 159, 175, 291, shrunk into tests/fuzz_found/).

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
import math
import os

import mpmath as mp

from airy_mpmath import airy  # the Airy sum of tests/data/airy_mpmath.csv

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))
FOUND = os.path.join(HERE, "..", "tests", "fuzz_found")
CASES = [
    "fuzz_airy_s1_114",
    "fuzz_airy_s1_159",
    "fuzz_airy_s1_175",
    "fuzz_airy_s1_291",
]


def normalize(v):
    r = 1.0 / math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return [v[0] * r, v[1] * r, v[2] * r]


def index(case, name):
    return case["scene"]["media"][name]["constant"]["n"]


def sweep_points(sw):
    n = sw["count"]
    if n == 1:
        return [sw["from"]]
    return [sw["from"] + (sw["to"] - sw["from"]) * i / (n - 1) for i in range(n)]


def airy_case(case):
    sw = case["probe"]["sweep"]
    par = sw["parameter"]["incidence_angle_deg"]
    side = sw["observe"]["far_field"]["side"]
    plate = case["scene"]["surfaces"][0]["plate"]
    n1, n2, n3 = (index(case, plate[k]) for k in ("above", "medium", "below"))
    d = plate["thickness_um"] * 1e-6
    lam = case["light"]["monochrome"]["wavelength_nm"] * 1e-9
    alpha = math.radians(case["scene"]["sources"][0]["polarization"]["linear"]["angle_deg"])
    fs = mp.cos(mp.mpf(alpha)) ** 2
    normal = normalize(plate["normal"])
    out = []
    for deg in sweep_points(sw):
        t = math.radians(deg)
        n = normalize(par["surface_normal"])
        ax = par["in_plane_axis"]
        k = ax[0] * n[0] + ax[1] * n[1] + ax[2] * n[2]
        a = normalize([ax[i] - k * n[i] for i in range(3)])
        dv = normalize([math.sin(t) * a[i] - math.cos(t) * n[i] for i in range(3)])
        D = [mp.mpf(x) for x in dv]
        N = [mp.mpf(x) for x in normal]
        dot = sum(x * y for x, y in zip(D, N))
        c1 = abs(dot) / mp.sqrt(sum(x * x for x in D) * sum(x * x for x in N))
        Rs, Ts = airy(n1, n2, n3, d, c1, lam, 0)
        Rp, Tp = airy(n1, n2, n3, d, c1, lam, 1)
        v = fs * Rs + (1 - fs) * Rp if side == "reflected" else fs * Ts + (1 - fs) * Tp
        out.append(v)
    return out


print("case,point,value")
for name in CASES:
    case = json.load(open(os.path.join(FOUND, name + ".json")))
    for i, v in enumerate(airy_case(case)):
        print(f"{name},{i},{mp.nstr(v, 30)}")
