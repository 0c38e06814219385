#!/usr/bin/env python3
"""50-digit two-beam intensities of the fuzz-found plate scenes in tests/suite/truth_plates.rs.

The formulas of tools/two_beam_mpmath.py (PHYSICS.md sec. 5 "Plate, two beams"; unpolarized
source, the paper's two channels s and p), evaluated for the exact f64 inputs of
tests/fuzz_found/fuzz_two_beam_plate_s7_5.json and _s7_84.json: heights of source and probe and
their lateral distance taken along the plate's normal normalized at 50 digits, the thickness
and wavelength as the loader forms them (thickness_um * 1e-6, wavelength_nm * 1e-9 in binary64).
Run: python3 tools/two_beam_plate_found_mpmath.py
"""
import mpmath as mp
from mp_two_beam import intensity_at, landing

mp.mp.dps = 50
M = mp.mpf


def intensity(n1, n2, d, hs, ho, x, lam):
    land = landing(n1, n2, d, hs, ho, x)
    a = mp.findroot(land, (M(0), x), solver="anderson")
    return intensity_at(n1, n2, d, hs, ho, x, lam, a)[0]

def scene(normal, top, source, probes, n1, n2, thickness_um, wavelength_nm):
    nn = [M(v) for v in normal]
    norm = mp.sqrt(sum(v * v for v in nn))
    nn = [v / norm for v in nn]
    dot = lambda a, b: sum(u * v for u, v in zip(a, b))
    t = [M(v) for v in top]
    s = [M(v) - w for v, w in zip(source, t)]
    for p in probes:
        p = [M(v) - w for v, w in zip(p, t)]
        v = [a - b for a, b in zip(p, s)]
        along = dot(v, nn)
        lateral = mp.sqrt(dot(v, v) - along * along)
        i = intensity(M(n1), M(n2), M(thickness_um * 1e-6), dot(s, nn), dot(p, nn), lateral,
                      M(wavelength_nm * 1e-9))
        print(mp.nstr(i, 25))


print("fuzz_two_beam_plate_s7_5")
scene([0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.7689744611748701],
      [[125.0, 0.0, 1.5379489223497402], [250.00000000076898, 0.0, 1.5379489223497402]],
      0.001, 1.0, 1.0, 200.0)
print("fuzz_two_beam_plate_s7_84")
scene([0.01745240643728351, 0.0, 0.9998476951563913], [0.0, 0.0, 0.0],
      [0.01745240643728351, 0.0, 0.9998476951563913],
      [[0.08726203218641757, 0.0, 1.9987814916502333], [0.1396192524981158, 0.0, 1.9978675929702316]],
      0.001, 1.0, 1.0, 1500.0)
