#!/usr/bin/env python3
"""50-digit intensities at every probe point of the geometric regression cases in
tests/fuzz_found/ (tests/suite/truth_geometry.rs): scenes where the tracer lost a path (a Young
slit or a Lloyd reflection 25-500 m from the origin, a thin wedge's bottom beam), evaluated
independently of the tracer and of the Rust closed forms.

- Young (two line sources along one axis, the paper's two-channel unpolarized light with its
  reference along the slits, unit intensities): I = 2 + (1 + cos a) cos d, d = 2 pi n (r1 - r2)/lam,
  r_k the distances from p perpendicular to the axis, cos a = v1.v2/(r1 r2) (PHYSICS.md sec. 5).
- Lloyd: tools/lloyd_mpmath.py's image method (r_s complex beyond a rarer mirror's critical angle).
- Wedge: tools/wedge_mpmath.py's 50-digit ray trace of the two beams.

Probe points are formed as the case loader forms them (glam's lerp a (1 - s) + b s in binary64);
every input is read as its exact binary64 value. Run from the repository root:
python3 tools/truth_geometry_mpmath.py > tests/data/truth_geometry_mpmath.csv
"""
import json
import math
import os
import sys

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lloyd_mpmath import intensity as lloyd_intensity  # noqa: E402
from mp_geometry import dot  # noqa: E402
from wedge_mpmath import intensity as wedge_intensity  # noqa: E402

mp.mp.dps = 50

FILES = [
    "fuzz_young_exact_s7_99",
    "fuzz_lloyd_s7_31",
    "fuzz_wedge_s7_9",
    "fuzz_wedge_s7_18",
    "fuzz_wedge_s7_60",
]


def probe_points(probe):
    line = probe["line"]
    a, b, n = line["from_m"], line["to_m"], line["count"]
    pts = []
    for i in range(n):
        s = 0.0 if n == 1 else float(i) / float(n - 1)
        pts.append([x * (1.0 - s) + y * s for x, y in zip(a, b)])
    return pts


def index(case, name):
    return case["scene"]["media"][name]["constant"]["n"]


def young(case, p):
    s1, s2 = (src["emitter"]["line"] for src in case["scene"]["sources"])
    A = [mp.mpf(x) for x in s1["axis"]]
    an = mp.sqrt(dot(A, A))
    A = [x / an for x in A]
    P = [mp.mpf(x) for x in p]

    def perp(s):
        v = [x - mp.mpf(y) for x, y in zip(P, s["point_m"])]
        along = dot(v, A)
        return [x - along * y for x, y in zip(v, A)]

    v1, v2 = perp(s1), perp(s2)
    r1, r2 = mp.sqrt(dot(v1, v1)), mp.sqrt(dot(v2, v2))
    n = mp.mpf(index(case, case["scene"]["ambient"]))
    lam = mp.mpf(case["light"]["monochrome"]["wavelength_nm"] * 1e-9)
    d = 2 * mp.pi * n * (r1 - r2) / lam
    cos_a = dot(v1, v2) / (r1 * r2)
    return 2 + (1 + cos_a) * mp.cos(d)


def lloyd(case, p):
    sc = case["scene"]
    line = sc["sources"][0]["emitter"]["line"]
    m = sc["surfaces"][0]["interface"]
    lam = case["light"]["monochrome"]["wavelength_nm"] * 1e-9
    n1, n2 = index(case, m["front"]), index(case, m["back"])
    return lloyd_intensity(line["point_m"], line["axis"], m["point_m"], m["normal"], p, n1, n2, lam)


def wedge(case, p):
    sc = case["scene"]
    w = sc["surfaces"][0]["wedge"]
    assert w["normal"] == [0.0, 0.0, 1.0] and w["hinge_axis"] == [0.0, 1.0, 0.0]
    a = mp.radians(mp.mpf(w["angle_deg"]))
    t = mp.mpf(w["thickness_um"] * 1e-6)
    qt = w["top_point_m"]
    # The bottom face: the top normal turned by the wedge angle about the hinge (y), through the
    # point `thickness_um` below the top point (the scene builder's construction).
    qb = [mp.mpf(qt[0]), mp.mpf(qt[1]), mp.mpf(qt[2]) - t]
    nb = [mp.sin(a), mp.mpf(0), mp.cos(a)]
    lam = case["light"]["monochrome"]["wavelength_nm"] * 1e-9
    n1, n, n3 = (index(case, w[k]) for k in ("above", "medium", "below"))
    return wedge_intensity(qt, w["normal"], qb, nb, p, n1, n, n3, lam)


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    print("case,point,intensity")
    for name in FILES:
        case = json.load(open(os.path.join(root, "tests", "fuzz_found", name + ".json")))
        model = next(iter(case["references"][0]["model"]))
        f = {"young_exact": young, "lloyd": lloyd, "wedge": wedge}[model]
        for k, p in enumerate(probe_points(case["probe"])):
            print(f"{name},{k},{mp.nstr(f(case, p), 30)}")


if __name__ == "__main__":
    main()
