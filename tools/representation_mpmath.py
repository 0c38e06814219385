#!/usr/bin/env python3
"""50-digit values for tests/suite/truth_representation.rs (issue #12: rotated plane-wave scenes
near grazing, Brewster and critical angles, `fringe fuzz --count 10000 --seed 1`).

Rows `case,point,value`:

* `held/<airy case>`: T or R of the case's film (tools/precision_classes_mpmath.py `airy_case`,
  the Airy sum of tools/airy_mpmath.py) for the direction the tracer holds: the case's
  binary64 direction (`case::build::incidence_direction`) normalized once more in binary64.
* `turn/<airy case>`: |V(c1 + dc1) - V(c1)|, the 50-digit change of that value when the incidence
  cosine c1 = |d.N|/(|d||N|) moves by one representation rounding dc1 = 2u sum_i |d_i N_i| (d, N
  the binary64 unit vectors, u = 2^-53; `conditioning::cosine_rounding`): what a direction and a
  normal each held one rounding off the written ones can do to the exact observable.
* `retardance/<rhomb case>`: the exact retardance k (P6 - P5) of the case's plane-wave direction
  at its TIR face (tools/rhomb_mpmath.py), and `turn/<rhomb case>`: its change when sin(theta)
  moves by one representation rounding 2u sum_{i!=j} |u_i n_j| (`tir::rhomb_retardance_representation`).

Run: python3 tools/representation_mpmath.py > tests/data/representation_mpmath.csv
"""
import json
import math
import os

import mpmath as mp

from airy_mpmath import airy
from precision_classes_mpmath import airy_case, index, normalize, sweep_points

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))
FOUND = os.path.join(HERE, "..", "tests", "fuzz_found")
U = mp.mpf(2) ** -53
AIRY = [
    "fuzz_airy_s1_8928",
    "fuzz_airy_s1_8724",
    "fuzz_airy_s1_1225",
    "fuzz_airy_s1_4064",
    "fuzz_airy_s1_3321",
]
RHOMB = [
    "fuzz_rhomb_retardance_s1_2773",
    "fuzz_rhomb_retardance_s1_4425",
    "fuzz_rhomb_retardance_s1_4569",
    "fuzz_rhomb_retardance_s1_7597",
]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def airy_turn(case):
    """|V(c1 + dc1) - V(c1)| at every sweep point (s and p mixed as airy_case does)."""
    sw = case["probe"]["sweep"]
    par = sw["parameter"]["incidence_angle_deg"]
    side = sw["observe"]["far_field"]["side"]
    plate = case["scene"]["surfaces"][0]["plate"]
    n1, n2, n3 = (index(case, plate[k]) for k in ("above", "medium", "below"))
    d = plate["thickness_um"] * 1e-6
    lam = case["light"]["monochrome"]["wavelength_nm"] * 1e-9
    pol = case["scene"]["sources"][0]["polarization"]
    fs = mp.cos(mp.mpf(math.radians(pol["linear"]["angle_deg"]))) ** 2
    normal = normalize(plate["normal"])
    out = []
    for deg in sweep_points(sw):
        t = math.radians(deg)
        n = normalize(par["surface_normal"])
        ax = par["in_plane_axis"]
        k = dot(ax, n)
        a = normalize([ax[i] - k * n[i] for i in range(3)])
        dv = normalize(normalize([math.sin(t) * a[i] - math.cos(t) * n[i] for i in range(3)]))
        D = [mp.mpf(x) for x in dv]
        N = [mp.mpf(x) for x in normal]
        c1 = abs(dot(D, N)) / mp.sqrt(dot(D, D) * dot(N, N))
        dn, nn = normalize(dv), normalize(normal)
        dc1 = 2 * U * sum(abs(mp.mpf(x) * mp.mpf(y)) for x, y in zip(dn, nn))

        def value(c):
            Rs, Ts = airy(n1, n2, n3, d, c, lam, 0)
            Rp, Tp = airy(n1, n2, n3, d, c, lam, 1)
            return fs * Rs + (1 - fs) * Rp if side == "reflected" else fs * Ts + (1 - fs) * Tp

        out.append(abs(value(c1 + dc1) - value(c1)))
    return out


def retardance(ng, no, s2, c, k):
    n21 = mp.mpf(no) / mp.mpf(ng)
    r = mp.sqrt(s2 - n21 * n21)
    return k * (2 * mp.atan(r / c) - 2 * mp.atan(r / (n21 * n21 * c)))


def rhomb(case):
    m = case["scene"]["media"]
    ng, no = m["glass"]["constant"]["n"], m["ambient"]["constant"]["n"]
    k = case["references"][0]["model"]["rhomb_retardance"]["tir_count"]
    d = case["scene"]["sources"][0]["emitter"]["plane_wave"]["direction"]
    face = next(s["interface"] for s in case["scene"]["surfaces"] if s["interface"]["name"] == "tir")
    u = [mp.mpf(x) for x in d]
    n = [mp.mpf(x) for x in face["normal"]]
    lu, ln = mp.sqrt(dot(u, u)), mp.sqrt(dot(n, n))
    u, n = [x / lu for x in u], [x / ln for x in n]
    cr = [u[1] * n[2] - u[2] * n[1], u[2] * n[0] - u[0] * n[2], u[0] * n[1] - u[1] * n[0]]
    sin = mp.sqrt(dot(cr, cr))
    c = abs(dot(u, n))
    uf, nf = normalize(d), normalize(face["normal"])
    dsin = 2 * U * sum(abs(mp.mpf(uf[i]) * mp.mpf(nf[j])) for i in range(3) for j in range(3) if i != j)
    base = retardance(ng, no, sin * sin, c, k)
    s2 = (sin + dsin) ** 2
    turned = retardance(ng, no, s2, mp.sqrt(1 - s2), k)
    return base, abs(turned - base)


def main():
    print("case,point,value")
    for name in AIRY:
        case = json.load(open(os.path.join(FOUND, name + ".json")))
        intensity = mp.mpf(case["scene"]["sources"][0]["intensity"])
        for i, v in enumerate(airy_case(case, 1)):
            print(f"held/{name},{i},{mp.nstr(intensity * v, 30)}")
        for i, v in enumerate(airy_turn(case)):
            print(f"turn/{name},{i},{mp.nstr(intensity * v, 30)}")
    for name in RHOMB:
        case = json.load(open(os.path.join(FOUND, name + ".json")))
        base, turn = rhomb(case)
        print(f"retardance/{name},0,{mp.nstr(base, 30)}")
        print(f"turn/{name},0,{mp.nstr(turn, 30)}")


if __name__ == "__main__":
    main()
