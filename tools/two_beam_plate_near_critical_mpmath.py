#!/usr/bin/env python3
"""50-digit two-beam intensities of the fuzz-found near-Brewster plate scenes, for
tests/suite/truth_point_sources.rs.

`fringe fuzz --family two_beam_plate --count 10000 --seed 1` (main b03e3a0) failed 8 scenes
tagged near_brewster: a point source over a plate of n2 = 0.001 in an ambient of n1 = 1.4...3,
so Brewster's angle atan(n2/n1) lies within (n2/n1)^3/2 of the critical angle asin(n2/n1) and
the top beam meets the plate within ~1e-6 of both. The formulas are those of
tools/mp_two_beam.py (PHYSICS.md sec. 5 "Plate, two beams"; unpolarized source, the paper's
two channels s and p at every ray); beyond the top face's critical angle the top beam is the
plate's frustrated r_layer (the Airy sum with cos t = +i sqrt(..), as the tracer and the closed
form reflect it). The beam through the plate is solved in w = tan t (bisection at 50 digits:
x = (h_s + h_o) tan th + 2 d w, tan th = r w / sqrt(1 + (1 - r^2) w^2), r = n2/n1), since
findroot in the entry offset runs complex near the critical angle. Sources with
`{"unpolarized": {}}` (basis-free, three dipoles) take cos^2(th1 - th2) in the p cross term.

Inputs are the case files themselves (tests/fuzz_found/<case>.json), read exactly as the
loader forms them: heights of source and probe above the top face and their lateral distance
along the plate's normal normalized at 50 digits, thickness_um * 1e-6 and wavelength_nm * 1e-9
in binary64, the line probe's two points `from_m` and `to_m`.
Run: python3 tools/two_beam_plate_near_critical_mpmath.py > tests/data/two_beam_plate_near_critical_mpmath.csv
"""
import json
import os

import mpmath as mp
from mp_two_beam import fresnel, intensity_at

mp.mp.dps = 50
M = mp.mpf

FOUND = [1320, 4441, 4659, 5397, 6372, 7438, 8745, 9342]


def tan_theta_t(n1, n2, d, hs, ho, x):
    """w = tan t inside the plate of the beam through it (n2 < n1), by bisection in w."""
    def miss(w):
        st = w / mp.sqrt(1 + w * w)
        s1 = n2 / n1 * st
        return (hs + ho) * s1 / mp.sqrt(1 - s1 * s1) + 2 * d * w - x

    lo, hi = M(0), M(1)
    while miss(hi) < 0:
        hi *= 2
    for _ in range(400):
        mid = (lo + hi) / 2
        if miss(mid) < 0:
            lo = mid
        else:
            hi = mid
    return (lo + hi) / 2


def intensity(n1, n2, d, hs, ho, x, lam, basis_free):
    w = tan_theta_t(n1, n2, d, hs, ho, x)
    s1 = n2 / n1 * w / mp.sqrt(1 + w * w)
    a = hs * s1 / mp.sqrt(1 - s1 * s1)
    # The top beam: beyond the critical angle the layer's frustrated reflection.
    ci = (hs + ho) / mp.sqrt(x * x + (hs + ho) ** 2)
    rs12, rp12, _, _, ct = fresnel(n1, n2, ci)
    r_top = None
    if mp.im(ct) != 0:
        rs23, rp23, _, _, _ = fresnel(n2, n1, ct)
        e = mp.expj(4 * mp.pi / lam * n2 * d * ct)
        r_top = tuple((r12 + r23 * e) / (1 + r12 * r23 * e)
                      for r12, r23 in ((rs12, rs23), (rp12, rp23)))
    if not basis_free:
        return intensity_at(n1, n2, d, hs, ho, x, lam, a, r_top)[0]
    # Basis-free unpolarized light (three dipoles of weight 1/2, PHYSICS.md sec. 3): the p cross
    # term carries cos^2(th1 - th2) where the two-channel model's has cos(th1 - th2); the
    # two-channel value at overlap c is I(c) = A + B c, so I_basis_free = A + B c^2.
    c = mp.cos(mp.atan2(x, hs + ho) - mp.atan2(a, hs))
    i_c = intensity_at(n1, n2, d, hs, ho, x, lam, a, r_top)[0]
    # B from the two-channel form at the same beams: B = Re(A1p A2p* e^{i phi}) (with the 1/2).
    l1 = mp.sqrt(a * a + hs * hs)
    st = n1 / n2 * a / l1
    ct2 = mp.sqrt(1 - st * st)
    xe = a + 2 * d * st / ct2
    op2 = n1 * l1 + 2 * n2 * d / ct2 + n1 * mp.sqrt((x - xe) ** 2 + ho * ho)
    op1 = n1 * mp.sqrt(x * x + (hs + ho) ** 2)
    r1p = rp12 if r_top is None else r_top[1]
    _, _, _, t12p, _ = fresnel(n1, n2, hs / l1)
    _, r23p, _, t21p, _ = fresnel(n2, n1, ct2)
    b = mp.re(r1p * mp.conj(t12p * r23p * t21p) * mp.expjpi(2 * (op1 - op2) / lam))
    return i_c + b * (c * c - c)


def geometry(c):
    """The intensity() arguments (n1, n2, d, hs, ho, x, lam, basis_free) at the two end points
    of a two_beam_plate case c (parsed JSON), its binary64 numbers taken exactly."""
    sc = c["scene"]
    media = sc["media"]
    plate = [s["plate"] for s in sc["surfaces"] if "plate" in s][0]
    assert plate["above"] == plate["below"] == sc["ambient"]
    n1 = M(media[sc["ambient"]]["constant"]["n"])
    n2 = M(media[plate["medium"]]["constant"]["n"])
    nn = [M(v) for v in plate["normal"]]
    norm = mp.sqrt(sum(v * v for v in nn))
    nn = [v / norm for v in nn]
    dot = lambda a, b: sum(u * v for u, v in zip(a, b))
    top = [M(v) for v in plate["top_point_m"]]
    src = [M(v) - t for v, t in zip(sc["sources"][0]["emitter"]["point"]["position_m"], top)]
    line = c["probe"]["line"]
    assert line["count"] == 2
    lam = M(c["light"]["monochrome"]["wavelength_nm"] * 1e-9)
    d = M(plate["thickness_um"] * 1e-6)
    basis_free = "model" not in sc["sources"][0]["polarization"]["unpolarized"]
    out = []
    for p in (line["from_m"], line["to_m"]):
        p = [M(v) - t for v, t in zip(p, top)]
        v = [a - b for a, b in zip(p, src)]
        along = dot(v, nn)
        lateral = mp.sqrt(dot(v, v) - along * along)
        out.append((n1, n2, d, dot(src, nn), dot(p, nn), lateral, lam, basis_free))
    return out


def scene(path):
    c = json.load(open(path))
    return c["name"], [intensity(*g) for g in geometry(c)]


if __name__ == "__main__":
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fuzz_found")
    print("case,point,value")
    for n in FOUND:
        for suffix in ("", "_at_origin"):
            name, values = scene(os.path.join(here, f"fuzz_two_beam_plate_s1_{n}{suffix}.json"))
            for k, v in enumerate(values):
                print(f"{name},{k},{mp.nstr(v, 30)}")
