#!/usr/bin/env python3
"""50-digit intensities of the grazing and far-from-the-origin fuzz scenes of
tests/suite/truth_grazing.rs (issue #12).

Each case file in tests/fuzz_found/ named below is read as the loader reads it: probe points
a*(1 - s) + b*s with s = i/(count - 1) in binary64, thickness_um * 1e-6 and wavelength_nm * 1e-9
in binary64; everything else at 50 digits. Two-beam plates use the formulas of
tools/two_beam_mpmath.py (PHYSICS.md sec. 5 "Plate, two beams", the paper's two channels;
the landing point of the beam through the plate by bisection on the bracket where it exists, then
Newton), Lloyd's mirror those of tools/lloyd_mpmath.py (image method).
Run: python3 tools/grazing_mpmath.py > tests/data/grazing_mpmath.csv
"""
import json
import os

import mpmath as mp
from lloyd_mpmath import intensity as lloyd_intensity
from mp_two_beam import intensity_at, landing

mp.mp.dps = 50
M = mp.mpf
ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def two_beam(n1, n2, d, hs, ho, x, lam):
    """Plate of index n2, thickness d in index n1; source and probe heights hs, ho above its top
    face, lateral distance x."""

    land = landing(n1, n2, d, hs, ho, x)

    lo, hi = M(0), x
    for _ in range(300):
        mid = (lo + hi) / 2
        if land(mid) > 0:
            hi = mid
        else:
            lo = mid
    a = mp.findroot(land, (lo + hi) / 2)
    return intensity_at(n1, n2, d, hs, ho, x, lam, a)[0]


def probe_points(line):
    a, b, n = line["from_m"], line["to_m"], line["count"]
    out = []
    for i in range(n):
        s = 0.0 if n == 1 else i / (n - 1)
        out.append([x * (1.0 - s) + y * s for x, y in zip(a, b)])
    return out


def dot(a, b):
    return sum(u * v for u, v in zip(a, b))


def plate_values(case):
    scene = case["scene"]
    plate = [s for s in scene["surfaces"] if "plate" in s][0]["plate"]
    assert plate["above"] == plate["below"] == scene["ambient"]
    n1 = M(scene["media"][plate["above"]]["constant"]["n"])
    n2 = M(scene["media"][plate["medium"]]["constant"]["n"])
    src = scene["sources"][0]["emitter"]["point"]["position_m"]
    lam = M(case["light"]["monochrome"]["wavelength_nm"] * 1e-9)
    nn = [M(v) for v in plate["normal"]]
    norm = mp.sqrt(dot(nn, nn))
    nn = [v / norm for v in nn]
    top = [M(v) for v in plate["top_point_m"]]
    s = [M(v) - t for v, t in zip(src, top)]
    for p in probe_points(case["probe"]["line"]):
        p = [M(v) - t for v, t in zip(p, top)]
        v = [a - b for a, b in zip(p, s)]
        along = dot(v, nn)
        lateral = mp.sqrt(dot(v, v) - along * along)
        yield two_beam(n1, n2, M(plate["thickness_um"] * 1e-6), dot(s, nn), dot(p, nn), lateral, lam)


def lloyd_values(case):
    scene = case["scene"]
    mirror = [s for s in scene["surfaces"] if "interface" in s][0]["interface"]
    n1 = scene["media"][scene["ambient"]]["constant"]["n"]
    n2 = scene["media"][mirror["back"]]["constant"]["n"]
    src = scene["sources"][0]["emitter"]["line"]
    lam = case["light"]["monochrome"]["wavelength_nm"] * 1e-9
    for p in probe_points(case["probe"]["line"]):
        yield lloyd_intensity(src["point_m"], src["axis"], mirror["point_m"], mirror["normal"], p,
                              n1, n2, lam)


CASES = [
    ("fuzz_two_beam_plate_s1_59", plate_values),
    ("fuzz_two_beam_plate_s1_106", plate_values),
    ("fuzz_two_beam_plate_s1_129", plate_values),
    ("fuzz_lloyd_s1_218", lloyd_values),
]


def main():
    print("case,point,intensity")
    for name, values in CASES:
        with open(os.path.join(ROOT, "tests", "fuzz_found", name + ".json")) as f:
            case = json.load(f)
        for i, v in enumerate(values(case)):
            print(f"{name},{i},{mp.nstr(v, 30)}")


if __name__ == "__main__":
    main()
