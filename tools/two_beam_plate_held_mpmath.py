#!/usr/bin/env python3
"""50-digit two-beam intensities of fuzz-found plate scenes whose lateral distance is not an f64,
for tests/suite/truth_thick_plates.rs.

`fringe fuzz --family two_beam_plate --count 300 --seed 1`, scene 4 (shrunk:
tests/fuzz_found/fuzz_two_beam_plate_s1_4.json): a 10 cm plate of n = 1.5 in an ambient of
n = 2, 200 nm, the source 2.5 m off the origin, probes 125 m and 250 m away at grazing incidence
(the top beam totally reflected, the beam through the plate entering below the critical angle).
The lateral distance p - s of the f64 coordinates is exact here (50 digits), where the f64
difference is off by up to half an ulp of 250 m. The formulas are those of tools/mp_two_beam.py
(PHYSICS.md sec. 5 "Plate, two beams"); beyond the top face's critical angle the beam through the
plate is solved for w = tan(theta_t) (as analytic::plate::TwoBeamPlate::entry_by_slope), and the
top beam is the bare face's total reflection (the plate's frustrated coupling e^{-2 kappa d} of a
10 cm plate is below 1e-100). Inputs are the case file's own binary64 numbers.
Run: python3 tools/two_beam_plate_held_mpmath.py > tests/data/two_beam_plate_held_mpmath.csv
"""
import json
import os

import mpmath as mp
from mp_two_beam import intensity_at, landing

mp.mp.dps = 50
M = mp.mpf
HERE = os.path.dirname(os.path.abspath(__file__))


def entry(n1, n2, d, hs, ho, x):
    """The lateral entry offset a of the beam through the plate."""
    if n1 <= n2:
        return mp.findroot(landing(n1, n2, d, hs, ho, x), (M(0), x), solver="anderson")
    r = n2 / n1
    g = lambda w: (hs + ho) * r * w / mp.sqrt(1 + (1 - r * r) * w * w) + 2 * d * w - x
    w = mp.findroot(g, (M(0), x / (2 * d)), solver="anderson")
    return hs * r * w / mp.sqrt(1 + (1 - r * r) * w * w)


def case(name):
    with open(os.path.join(HERE, "..", "tests", "fuzz_found", name + ".json")) as f:
        c = json.load(f)
    sc = c["scene"]
    media = sc["media"]
    plate = [s["plate"] for s in sc["surfaces"] if "plate" in s][0]
    n1 = M(media[plate["above"]]["constant"]["n"])
    n2 = M(media[plate["medium"]]["constant"]["n"])
    d = M(plate["thickness_um"] * 1e-6)  # as the loader forms it, in binary64
    lam = M(c["light"]["monochrome"]["wavelength_nm"] * 1e-9)
    nn = [M(v) for v in plate["normal"]]
    norm = mp.sqrt(sum(v * v for v in nn))
    nn = [v / norm for v in nn]
    dot = lambda a, b: sum(u * v for u, v in zip(a, b))
    top = [M(v) for v in plate["top_point_m"]]
    src = [M(v) - t for v, t in zip(sc["sources"][0]["emitter"]["point"]["position_m"], top)]
    line = c["probe"]["line"]
    assert line["count"] == 2  # the end points themselves (glam's lerp at 0 and 1 is exact)
    out = []
    for p in (line["from_m"], line["to_m"]):
        p = [M(v) - t for v, t in zip(p, top)]
        v = [a - b for a, b in zip(p, src)]
        along = dot(v, nn)
        x = mp.sqrt(dot(v, v) - along * along)
        hs, ho = dot(src, nn), dot(p, nn)
        a = entry(n1, n2, d, hs, ho, x)
        out.append(intensity_at(n1, n2, d, hs, ho, x, lam, a)[0])
    return out


if __name__ == "__main__":
    print("case,point,value")
    for name in ["fuzz_two_beam_plate_s1_4"]:
        for i, v in enumerate(case(name)):
            print(f"{name},{i},{mp.nstr(v, 30)}")
