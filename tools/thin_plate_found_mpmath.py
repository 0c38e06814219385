#!/usr/bin/env python3
"""60-digit two-beam intensities of the thin-plate fuzz scenes in tests/suite/truth_refusals.rs.

Scenes of `fringe fuzz --family two_beam_plate --seed 1` (count 300) that the path solver could
not land (`T0 R1 T0`, "no convergence ... after 1 iterations"): plates of 0.1-14 nm less dense
than their ambient, the beam through the plate entering just below the top face's critical
angle and running grazing inside it (tan theta_t up to ~1e9). Each case file is
tests/fuzz_found/fuzz_two_beam_plate_s1_<index>.json, read here with its exact binary64
inputs. Heights of source and probe above the top face and their lateral distance are taken
along the plate's normal normalized at 60 digits; the probe points as the loader forms them
(from + (to - from) * i/(count - 1) in binary64), the thickness and wavelength as
thickness_um * 1e-6 and wavelength_nm * 1e-9 in binary64. The formulas and bisection are those
of tools/beyond_critical_plate_mpmath.py (PHYSICS.md sec. 5 "Plate, two beams"; unpolarized
source, the paper's two channels s and p), imported, not copied; beyond the top face's
critical angle the top beam takes the plate's frustrated r_layer (tools/tunnelling_mpmath.py).
Values are times the source's intensity.
Run: python3 tools/thin_plate_found_mpmath.py > tests/data/thin_plate_mpmath.csv
"""
import json
import os
import sys

import mpmath as mp

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from beyond_critical_plate_mpmath import intensity  # noqa: E402
from tunnelling_mpmath import r_layer  # noqa: E402

mp.mp.dps = 60
M = mp.mpf
FOUND = os.path.join(HERE, "..", "tests", "fuzz_found")
# The scenes with the paper's two channels (`unpolarized.model = paper_two_channel`, reference
# perpendicular to the plane of incidence): 226 and 240 carry basis-free unpolarized light, whose
# p cross term between the two beams is weighted by the dot product of their launch p vectors,
# which the two-channel sum of tools/mp_two_beam.py does not model.
SCENES = [49, 185, 231, 235, 236, 239]


def probe_points(line):
    a, b, n = line["from_m"], line["to_m"], line["count"]
    ts = [0.0] if n == 1 else [i / (n - 1) for i in range(n)]
    return [[a[k] + (b[k] - a[k]) * t for k in range(3)] for t in ts]


def case_values(case):
    scene = case["scene"]
    plate = scene["surfaces"][0]["plate"]
    media = scene["media"]
    n1 = media[plate["above"]]["constant"]["n"]
    n2 = media[plate["medium"]]["constant"]["n"]
    assert media[plate["below"]]["constant"]["n"] == n1
    d = plate["thickness_um"] * 1e-6
    lam = case["light"]["monochrome"]["wavelength_nm"] * 1e-9
    assert scene["sources"][0]["polarization"]["unpolarized"]["model"] == "paper_two_channel"
    nn = [M(v) for v in plate["normal"]]
    norm = mp.sqrt(sum(v * v for v in nn))
    nn = [v / norm for v in nn]
    dot = lambda u, v: sum(x * y for x, y in zip(u, v))
    top = [M(v) for v in plate["top_point_m"]]
    src = [M(v) - w for v, w in zip(scene["sources"][0]["emitter"]["point"]["position_m"], top)]
    hs = dot(src, nn)
    out = []
    for p in probe_points(case["probe"]["line"]):
        p = [M(v) - w for v, w in zip(p, top)]
        v = [x - y for x, y in zip(p, src)]
        ho = dot(p, nn)
        lateral = mp.sqrt(dot(v, v) - dot(v, nn) ** 2)
        c_top = (hs + ho) / mp.sqrt(lateral**2 + (hs + ho) ** 2)
        r_top = None
        if n1 > n2 and 1 - c_top**2 > (M(n2) / M(n1)) ** 2:
            r_top = tuple(r_layer(M(n1), M(n2), M(d), c_top, M(lam), pol) for pol in (0, 1))
        i, _ = intensity(n1, n2, d, hs, ho, lateral, lam, r_top=r_top)
        out.append(i * M(scene["sources"][0]["intensity"]))
    return out


def main():
    print("case,point,value")
    for index in SCENES:
        name = f"fuzz_two_beam_plate_s1_{index}"
        case = json.load(open(os.path.join(FOUND, name + ".json")))
        for k, v in enumerate(case_values(case)):
            print(f"{name},{k},{mp.nstr(v, 30)}")


if __name__ == "__main__":
    main()
