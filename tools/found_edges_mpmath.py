#!/usr/bin/env python3
"""50-digit values of the last near-tolerance fuzz failures (issue #12) for
tests/suite/truth_found_edges.rs: the scenes in tests/fuzz_found/ as the tracer holds them.

Every number of a case file is read as the binary64 value the loader makes of it, and the steps
the scene builder takes in f64 are repeated in f64 here (glam's `normalize` = v * (1/|v|), the
wedge's tilted normal from `DQuat::from_axis_angle`, a sweep's incidence direction, 200 nm as
200.0 * 1e-9); everything after that is evaluated with 50 digits:

* young_exact (two coherent line sources, the paper's two-channel unpolarized model, spreading
  off): I = 2 + (1 + cos a) cos d, d = 2 pi n (r1 - r2)/lam, r_k the distance from the probe
  point to line k perpendicular to the unit axis, cos a = v1.v2/(r1 r2) (PHYSICS.md sec. 5
  "Young").
* wedge (plane wave at normal incidence, s light, two beams): the bottom beam traced exactly
  through the held planes (entry point solved so that the exit ray meets the probe point),
  I = |r12 + t12 r23 t21 e^{i d}|^2, d = 2 pi (S_bottom - S_top)/lam, Fresnel s coefficients at
  the exact angles (PHYSICS.md sec. 5 "Wedge").
* airy (film on a substrate, reflected far field, linear light): R = f_s |r_s|^2 + (1 - f_s)
  |r_p|^2, r = (r12 + r23 e^{2ib})/(1 + r12 r23 e^{2ib}), b = 2 pi n2 d cos t2/lam, cos t1 from the
  held direction and normal, f_s = (e.s)^2 of the launch field (the reference projected
  perpendicular to the ray and turned about it) on s = d x N/|d x N| (PHYSICS.md sec. 5 "Airy").

Run from the repository root:
    python3 tools/found_edges_mpmath.py > tests/data/found_edges_mpmath.csv
"""
import json
import math

import mpmath as mp

mp.mp.dps = 50

CASES = [
    "fuzz_young_exact_s1_5173",
    "fuzz_young_exact_s1_9633",
    "fuzz_young_exact_s2_2559",
    "fuzz_wedge_s1_9953",
    "fuzz_airy_s1_5779",
    "fuzz_airy_s1_5779_p",
]


def norm64(v):
    """glam's DVec3::normalize in binary64."""
    length = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    r = 1.0 / length
    return [v[0] * r, v[1] * r, v[2] * r]


def dot64(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def lin(frm, to, count, i):
    return frm if count == 1 else frm + (to - frm) * i / (count - 1)


def mpv(v):
    return [mp.mpf(x) for x in v]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(a):
    length = mp.sqrt(dot(a, a))
    return [x / length for x in a]


def index(case, name):
    return mp.mpf(case["scene"]["media"][name]["constant"]["n"])


def young(case):
    lam = mp.mpf(case["light"]["monochrome"]["wavelength_nm"] * 1e-9)
    n = index(case, case["scene"]["ambient"])
    lines = [s["emitter"]["line"] for s in case["scene"]["sources"]]
    axis = mpv(norm64(lines[0]["axis"]))
    probe = case["probe"]["line"]
    a, b = probe["from_m"], probe["to_m"]
    out = []
    for i in range(probe["count"]):
        s = lin(0.0, 1.0, probe["count"], i)
        p = mpv([a[k] * (1.0 - s) + b[k] * s for k in range(3)])
        vs = []
        for line in lines:
            v = [p[k] - mp.mpf(line["point_m"][k]) for k in range(3)]
            along = dot(v, axis)
            vs.append([v[k] - along * axis[k] for k in range(3)])
        r1, r2 = mp.sqrt(dot(vs[0], vs[0])), mp.sqrt(dot(vs[1], vs[1]))
        delta = 2 * mp.pi * n * (r1 - r2) / lam
        cos_a = dot(vs[0], vs[1]) / (r1 * r2)
        out.append(2 + (1 + cos_a) * mp.cos(delta))
    return out


def fresnel(n1, n2, c1):
    """(r_s, t_s, r_p) from n1 into n2 at incidence cosine c1 (real, below critical)."""
    c2 = mp.sqrt(1 - (n1 / n2) ** 2 * (1 - c1 * c1))
    rs = (n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2)
    ts = 2 * n1 * c1 / (n1 * c1 + n2 * c2)
    rp = (n2 * c1 - n1 * c2) / (n2 * c1 + n1 * c2)
    return rs, ts, rp, c2


def wedge(case):
    w = case["scene"]["surfaces"][0]["wedge"]
    n1, n, n3 = index(case, w["above"]), index(case, w["medium"]), index(case, w["below"])
    lam = mp.mpf(case["light"]["monochrome"]["wavelength_nm"] * 1e-9)
    top = norm64(w["normal"])
    assert top == [0.0, 0.0, 1.0] and w["hinge_axis"] == [0.0, 1.0, 0.0], "the found scene's frame"
    assert w["top_point_m"] == [0.0, 0.0, 0.0]
    alpha = w["angle_deg"] * (math.pi / 180.0)
    s, c = math.sin(alpha * 0.5), math.cos(alpha * 0.5)
    # DQuat::from_axis_angle(y, alpha) * z, as glam evaluates it, then Plane::new's normalize.
    nb = mpv(norm64([s * (c * 2.0), 0.0, c * c - s * s]))
    nb = unit(nb)
    thickness = mp.mpf(w["thickness_um"] * 1e-6)
    src = case["scene"]["sources"][0]["emitter"]["plane_wave"]
    assert src["direction"] == [0.0, 0.0, -1.0]
    z_ref = mp.mpf(src["reference_point_m"][2])
    probe = case["probe"]["line"]
    a, b = probe["from_m"], probe["to_m"]
    out = []
    for i in range(probe["count"]):
        t = lin(0.0, 1.0, probe["count"], i)
        px, h = mp.mpf(a[0] * (1.0 - t) + b[0] * t), mp.mpf(a[2] * (1.0 - t) + b[2] * t)
        # Down along -z, reflected at the bottom plane (through (0, 0, -thickness), normal nb).
        d = [mp.mpf(0), mp.mpf(0), mp.mpf(-1)]
        k = dot(d, nb)
        r = [d[j] - 2 * k * nb[j] for j in range(3)]
        ox = r[0] * n / n1
        oz = mp.sqrt(1 - ox * ox)

        def path(xi):
            zb = -thickness - xi * nb[0] / nb[2]
            xe = xi + (-zb) * r[0] / r[2]
            return xe + h * ox / oz - px, zb, xe

        xi = mp.findroot(lambda x: path(x)[0], px)
        _, zb, xe = path(xi)
        s_bottom = n1 * z_ref + n * (-zb) + n * mp.sqrt((xe - xi) ** 2 + zb**2) + n1 * mp.sqrt(
            (px - xe) ** 2 + h * h
        )
        s_top = n1 * z_ref + n1 * h
        delta = 2 * mp.pi * (s_bottom - s_top) / lam
        r12, t12, _, _ = fresnel(n1, n, mp.mpf(1))
        r23 = fresnel(n, n3, nb[2])[0]
        t21 = fresnel(n, n1, r[2])[1]
        out.append(abs(r12 + t12 * r23 * t21 * mp.expj(delta)) ** 2)
    return out


def incidence_direction(theta, normal, axis):
    """build::incidence_direction in binary64."""
    nn = norm64(normal)
    k = dot64(axis, nn)
    a = norm64([axis[i] - k * nn[i] for i in range(3)])
    s, c = math.sin(theta), math.cos(theta)
    return norm64([s * a[i] - c * nn[i] for i in range(3)])


def airy(case):
    plate = case["scene"]["surfaces"][0]["plate"]
    n1, n2, n3 = index(case, plate["above"]), index(case, plate["medium"]), index(case, plate["below"])
    N = unit(mpv(norm64(plate["normal"])))
    d_m = mp.mpf(plate["thickness_um"] * 1e-6)
    lam = mp.mpf(case["light"]["monochrome"]["wavelength_nm"] * 1e-9)
    pol = case["scene"]["sources"][0]["polarization"]["linear"]
    ref = mpv(pol["reference"])
    psi = mp.mpf(pol["angle_deg"] * (math.pi / 180.0))
    sweep = case["probe"]["sweep"]
    par = sweep["parameter"]["incidence_angle_deg"]
    assert sweep["observe"]["far_field"]["side"] == "reflected"
    out = []
    for i in range(sweep["count"]):
        x = lin(sweep["from"], sweep["to"], sweep["count"], i)
        d = unit(mpv(incidence_direction(x * (math.pi / 180.0), par["surface_normal"], par["in_plane_axis"])))
        c1 = abs(dot(d, N))
        rs12, _, rp12, c2 = fresnel(n1, n2, c1)
        rs23, _, rp23, _ = fresnel(n2, n3, c2)
        e2b = mp.expj(2 * (2 * mp.pi * n2 * d_m * c2 / lam))

        def film(r12, r23):
            return (r12 + r23 * e2b) / (1 + r12 * r23 * e2b)

        big_rs, big_rp = abs(film(rs12, rs23)) ** 2, abs(film(rp12, rp23)) ** 2
        e_ref = unit([ref[k] - dot(ref, d) * d[k] for k in range(3)])
        turned = cross(d, e_ref)
        e = [mp.cos(psi) * e_ref[k] + mp.sin(psi) * turned[k] for k in range(3)]
        dxn = cross(d, N)
        # At normal incidence R_s = R_p: any split gives R.
        f_s = dot(e, unit(dxn)) ** 2 if dot(dxn, dxn) > mp.mpf("1e-60") else mp.mpf(1) / 2
        out.append(f_s * big_rs + (1 - f_s) * big_rp)
    return out


print("case,point,value")
for name in CASES:
    with open(f"tests/fuzz_found/{name}.json") as f:
        case = json.load(f)
    model = next(iter(case["references"][0]["model"]))
    values = {"young_exact": young, "wedge": wedge, "airy": airy}[model](case)
    for k, v in enumerate(values):
        print(f"{name},{k},{mp.nstr(v, 30)}")
