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

mp.mp.dps = 50
M = mp.mpf


def fresnel(n1, n2, ci):
    ct = mp.sqrt(1 - (n1 / n2) ** 2 * (1 - ci * ci))
    rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct)
    rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct)
    ts = 2 * n1 * ci / (n1 * ci + n2 * ct)
    tp = 2 * n1 * ci / (n2 * ci + n1 * ct)
    return rs, rp, ts, tp


def intensity(n1, n2, d, hs, ho, x, lam):
    def land(a):
        st = n1 / n2 * a / mp.sqrt(a * a + hs * hs)
        return a + 2 * d * st / mp.sqrt(1 - st * st) + ho * a / hs - x

    a = mp.findroot(land, (M(0), x), solver="anderson")
    l1 = mp.sqrt(a * a + hs * hs)
    st = n1 / n2 * a / l1
    ct = mp.sqrt(1 - st * st)
    xe = a + 2 * d * st / ct
    op2 = n1 * l1 + 2 * n2 * d / ct + n1 * mp.sqrt((x - xe) ** 2 + ho * ho)
    op1 = n1 * mp.sqrt(x * x + (hs + ho) ** 2)
    r12s, r12p, _, _ = fresnel(n1, n2, (hs + ho) / mp.sqrt(x * x + (hs + ho) ** 2))
    _, _, t12s, t12p = fresnel(n1, n2, hs / l1)
    r23s, r23p, t21s, t21p = fresnel(n2, n1, ct)
    a2s, a2p = t12s * r23s * t21s, t12p * r23p * t21p
    e = mp.expjpi(2 * (op1 - op2) / lam)
    overlap = mp.cos(mp.atan2(x, hs + ho) - mp.atan2(a, hs))
    i_s = abs(r12s * e + a2s) ** 2
    i_p = r12p**2 + a2p**2 + 2 * mp.re(r12p * a2p * e) * overlap
    return (i_s + i_p) / 2


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
