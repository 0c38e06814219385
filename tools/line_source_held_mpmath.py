#!/usr/bin/env python3
"""The found Young scenes with line sources 100-500 m out (issue #12), as held and one rounding
of every coordinate away, for tests/suite/truth_found_edges.rs.

A case file's coordinates are binary64 numbers: the scene the tracer and the closed form both
read. The scene the generator meant (its exact rotation and translation) is a rounding of each
coordinate away, ~u |X| = 5.7e-14 m at 500 m, against slits 1e-4 m apart. This script writes, for
each scene, the scene with every source and probe coordinate moved by one ulp in the direction
that moves the first probe point's 50-digit intensity up (sign of dI/dx), to
tests/fuzz_found/<name>_ulp.json, and prints the 50-digit Young intensities of both scenes
(same model as tools/found_edges_mpmath.py: two-channel unpolarized, I = 2 + (1 + cos a) cos d).

Run from the repository root:
    python3 tools/line_source_held_mpmath.py > tests/data/line_source_held_mpmath.csv
"""
import copy
import json
import math

import mpmath as mp

mp.mp.dps = 50

CASES = ["fuzz_young_exact_s1_5173", "fuzz_young_exact_s1_9633"]


def norm64(v):
    """glam's DVec3::normalize in binary64."""
    length = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    r = 1.0 / length
    return [v[0] * r, v[1] * r, v[2] * r]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def intensity(n, lam, axis, points, p):
    """Young's two-channel intensity at p for line sources through `points` along unit `axis`."""
    vs = []
    for s in points:
        v = [p[k] - s[k] for k in range(3)]
        along = dot(v, axis)
        vs.append([v[k] - along * axis[k] for k in range(3)])
    r1, r2 = mp.sqrt(dot(vs[0], vs[0])), mp.sqrt(dot(vs[1], vs[1]))
    delta = 2 * mp.pi * n * (r1 - r2) / lam
    cos_a = dot(vs[0], vs[1]) / (r1 * r2)
    return 2 + (1 + cos_a) * mp.cos(delta)


def profile(case):
    """50-digit intensities at the probe points (a 2-point line: its two ends, exactly)."""
    lam = mp.mpf(case["light"]["monochrome"]["wavelength_nm"] * 1e-9)
    n = mp.mpf(case["scene"]["media"][case["scene"]["ambient"]]["constant"]["n"])
    lines = [s["emitter"]["line"] for s in case["scene"]["sources"]]
    # The closed form and the tracer both use axis.normalize() of the loader's normalized axis.
    axis = [mp.mpf(x) for x in norm64(norm64(lines[0]["axis"]))]
    points = [[mp.mpf(x) for x in line["point_m"]] for line in lines]
    probe = case["probe"]["line"]
    assert probe["count"] == 2, "the ends of a 2-point line are its probe points, exactly"
    ends = [[mp.mpf(x) for x in probe[k]] for k in ("from_m", "to_m")]
    return [intensity(n, lam, axis, points, p) for p in ends], (n, lam, axis, points, ends)


def moved(case):
    """The case with every source point and probe end coordinate one ulp off, each in the
    direction that raises the first probe point's intensity (gradient by 50-digit differences)."""
    _, (n, lam, axis, points, ends) = profile(case)
    out = copy.deepcopy(case)
    coords = [("source", i, k) for i in range(2) for k in range(3)] + [
        ("probe", j, k) for j in range(2) for k in range(3)
    ]
    for kind, i, k in coords:
        if kind == "source":
            x = case["scene"]["sources"][i]["emitter"]["line"]["point_m"][k]
        else:
            x = case["probe"]["line"][("from_m", "to_m")[i]][k]
        h = mp.mpf(math.ulp(x)) if x != 0.0 else mp.mpf(math.ulp(1e-300))
        pts = [list(p) for p in points]
        es = [list(e) for e in ends]
        (pts if kind == "source" else es)[i][k] += h
        # The probe point whose intensity decides the sign: the first, or the moved one.
        j = i if kind == "probe" else 0
        slope = intensity(n, lam, axis, pts, es[j]) - intensity(n, lam, axis, points, ends[j])
        step = math.inf if slope >= 0 else -math.inf
        y = math.nextafter(x, step)
        if kind == "source":
            out["scene"]["sources"][i]["emitter"]["line"]["point_m"][k] = y
        else:
            out["probe"]["line"][("from_m", "to_m")[i]][k] = y
    out["name"] = case["name"] + "_ulp"
    out["description"] = (
        f"{case['name']} with every source and probe coordinate one ulp away, each in the "
        "direction that raises the intensity (tools/line_source_held_mpmath.py): the same scene "
        "a rounding of each coordinate away, as a generator's exact scene is from its f64 one."
    )
    return out


print("case,point,value")
for name in CASES:
    case = json.load(open(f"tests/fuzz_found/{name}.json"))
    other = moved(case)
    with open(f"tests/fuzz_found/{other['name']}.json", "w") as f:
        json.dump(other, f, indent=2, sort_keys=True)
        f.write("\n")
    for c in (case, other):
        for i, v in enumerate(profile(c)[0]):
            print(f"{c['name']},{i},{mp.nstr(v, 30)}")
