"""Render an exported plate case with Mitsuba 3 and write a fringe value file.

Usage (outside cargo; needs `pip install mitsuba numpy`):

    fringe export plate_airy_s --out /tmp/pack
    python examples/mitsuba_render_values.py /tmp/pack/plate_airy_s /tmp/mitsuba.csv --plate slab
    fringe grade plate_airy_s --values /tmp/mitsuba.csv

For every probe angle of an incidence-angle sweep observed in the reflected far field, this
builds a scene and renders it with `mi.render` in the `scalar_spectral_polarized` variant:

- the light: a rectangular area emitter seen along the case's (rotated) plane-wave direction,
  behind an ideal linear `polarizer` sheet turned so it passes the case's polarization
  (the sheet's absorbing axis, the V direction of its parameterization, is set perpendicular to
  the case's E vector);
- the plate: `--plate slab` is a closed `dielectric` box (int_ior n, ext_ior the ambient index)
  that the path tracer enters, reflects inside and leaves any number of times;
  `--plate thindielectric` is one rectangle with Mitsuba's `thindielectric` BSDF;
- the sensor: an orthographic camera on the mirror direction looking at the plate, with a
  `stokes` integrator around a `path` integrator (max_depth 200, no Russian roulette), a box
  filter, an `independent` sampler (with Mitsuba's `stratified` sampler the residuals against
  the model were not pure noise: mean z +0.52 ± 0.08 over the 171 angles of plate_airy_s, and
  +0.98 ± 0.32 over 10 seeds at 20°, against -0.55 ± 0.32 for `independent`; not
  investigated further);
- the reference: the same scene with the plate replaced by an ideal mirror (`conductor`,
  material `none`, |r| = 1 for s and p), rendered with the same seed, so that the pixel-wise
  ratio of S0 (summed over the S0 R, G, B channels) is the reflectance R of the case's light
  (the mirror's own noise, from sampling wavelengths, is 0.2 % per pixel at 64 spp, far below
  the plate's noise from choosing reflection or transmission, and part of the pixel spread).
  Each probe point gets its own seed (--seed + its index), so the noise of different points is
  independent.

The plate's thickness is 2e-3 scene units: Mitsuba transports power incoherently, so the
thickness only shifts the internally reflected rays sideways (a large uniform emitter makes
that irrelevant); at the case's 2 µm it would be below float32 ray offsets. The emitter's
spectrum is flat: the case's indices are constant, so R is the same at every wavelength and the
550 nm value is the flat-spectrum value (a 1 nm emitter band would only add wavelength-sampling
noise, since `hdrfilm` samples wavelengths over the visible range; a `specfilm` with a 1 nm band
aborted the process, "double free or corruption", when tried with this setup in 3.9.1).

The value written is the mean over the pixels of the per-pixel ratio; next to OUT.csv,
OUT.stderr.csv gets its standard error (standard deviation of the pixel ratios / sqrt(pixels);
the pixels are independent estimates: every sample draws fresh pseudo-random numbers).
"""
import argparse
import csv
import json
import math
import sys
import time

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_spectral_polarized")
T = mi.ScalarTransform4f


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


# Distances of the emitter and the sensor from the plate, half-size of the emitter and the
# polarizer, half-size of the sensor's view (scene units). The sensor is nearer than the
# polarizer (0.8 DIST) so that at normal incidence, where it sits on the emitter's axis, its
# rays meet the plate before the polarizer (a sensor is not an obstacle to rays). Rays
# transmitted through the plate must not reach the emitter: it has to lie wholly above the
# plate (checked in `main`), and the reflected beam (2 VIEW wide ± the sideways shift of
# internal reflections) has to fall on it.
DIST, EYE, HALF, VIEW = 5.0, 1.0, 0.2, 0.05


def scene_dict(d, e, normal, n_plate, n_ambient, plate, pixels, spp, sampler="independent"):
    """d: light's travel direction, e: its E vector, normal: the plate's outward normal."""
    dist = DIST
    source = -dist * d                        # where the light comes from
    mirror = d - 2.0 * np.dot(d, normal) * normal
    eye = EYE * mirror                       # where the reflected light goes
    origin = [0.0, 0.0, 0.0]
    # Plate frame: the plate's normal is world z in these scenes (checked by the caller).
    scene = {
        "type": "scene",
        "integrator": {
            "type": "stokes",
            "integrator": {"type": "path", "max_depth": 200, "rr_depth": 1000},
        },
        "sensor": {
            "type": "orthographic",
            "to_world": T().look_at(origin=eye.tolist(), target=origin, up=[0, 1, 0])
            @ T().scale([VIEW, VIEW, 1.0]),
            "sampler": {"type": sampler, "sample_count": spp},
            "film": {
                "type": "hdrfilm",
                "width": pixels,
                "height": pixels,
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
            },
        },
        "emitter": {
            "type": "rectangle",
            "to_world": T().look_at(origin=source.tolist(), target=origin, up=[0, 1, 0])
            @ T().scale([HALF, HALF, 1.0]),
            "emitter": {"type": "area", "radiance": {"type": "uniform", "value": 1.0}},
        },
        # Absorbing axis (local V = look_at's up) perpendicular to E: passes E.
        "polarizer": {
            "type": "rectangle",
            "to_world": T().look_at(
                origin=(0.8 * source).tolist(), target=origin, up=np.cross(d, e).tolist()
            )
            @ T().scale([HALF, HALF, 1.0]),
            "bsdf": {"type": "polarizer", "theta": 0.0},
        },
    }
    big = T().scale([50.0, 50.0, 1.0])
    if plate == "mirror":
        scene["plate"] = {
            "type": "rectangle",
            "to_world": big,
            "bsdf": {"type": "conductor", "material": "none"},
        }
    elif plate == "slab":
        scene["plate"] = {
            "type": "cube",
            "to_world": T().translate([0.0, 0.0, -1e-3]) @ T().scale([50.0, 50.0, 1e-3]),
            "bsdf": {"type": "dielectric", "int_ior": n_plate, "ext_ior": n_ambient},
        }
    elif plate == "thindielectric":
        scene["plate"] = {
            "type": "rectangle",
            "to_world": big,
            "bsdf": {"type": "thindielectric", "int_ior": n_plate, "ext_ior": n_ambient},
        }
    else:
        raise ValueError(plate)
    return scene


def s0(scene, seed):
    img = np.array(mi.render(mi.load_dict(scene), seed=seed), dtype=np.float64)
    # Channels: R, G, B, then the stokes integrator's S0.RGB, S1.RGB, S2.RGB, S3.RGB.
    return img[:, :, 3:6].sum(axis=2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("pack_dir")
    ap.add_argument("out_csv")
    ap.add_argument("--plate", choices=["slab", "thindielectric"], default="slab")
    ap.add_argument("--pixels", type=int, default=16)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()

    pack = json.load(open(f"{a.pack_dir}/pack.json"))
    case = json.load(open(f"{a.pack_dir}/case.json"))
    if pack["probe"]["coordinate"] != "incidence_angle_deg":
        sys.exit("this script handles incidence-angle sweeps only")
    if len(pack["quantities"]) != 1 or pack["quantities"][0]["observable"] != "reflectance":
        sys.exit("this script handles one reflectance quantity only")
    if len(pack["spectrum"]) != 1:
        sys.exit("this script handles monochromatic light only")
    scene = case["scene"]
    index = lambda m: scene["media"][m]["constant"]["n"]
    plates = [s["plate"] for s in scene["surfaces"] if "plate" in s]
    if len(plates) != 1 or len(scene["surfaces"]) != 1:
        sys.exit("this script handles a single plate only")
    plate = plates[0]
    n_plate, n_above, n_below = index(plate["medium"]), index(plate["above"]), index(plate["below"])
    if n_above != n_below or scene["ambient"] != plate["above"]:
        sys.exit("a free-standing plate only: above, below and ambient must be the same medium")
    [source] = scene["sources"]
    pol = source["polarization"]["linear"]
    sweep = case["probe"]["sweep"]["parameter"]["incidence_angle_deg"]
    normal = unit(sweep["surface_normal"])
    axis = unit(sweep["in_plane_axis"])
    if not np.allclose(normal, [0, 0, 1]):
        sys.exit("the scene is built with the plate normal on world z")
    if not np.allclose(normal, unit(plate["normal"])):
        sys.exit("the sweep's surface normal must be the plate's")

    rows = list(csv.DictReader(open(f"{a.pack_dir}/probes.csv")))
    quantity = pack["quantities"][0]["name"]
    out, err = [], []
    t0 = time.time()
    for i, r in enumerate(rows):
        seed = a.seed + i  # independent noise per probe point
        theta = math.radians(float(r["incidence_angle_deg"]))
        if 0.8 * DIST * math.cos(theta) <= HALF * math.sin(theta) + 1e-3:
            sys.exit(f"{r['coordinate']}°: too grazing for this geometry (the emitter would dip below the plate)")
        d = unit(math.sin(theta) * axis - math.cos(theta) * normal)
        # cases/README.md: the reference projected perpendicular to the ray, rotated by
        # angle_deg about the ray (right-handed about d).
        ref = np.asarray(pol["reference"], dtype=float)
        e0 = unit(ref - np.dot(ref, d) * d)
        psi = math.radians(pol["angle_deg"])
        e = unit(math.cos(psi) * e0 + math.sin(psi) * np.cross(d, e0))
        args = (d, e, normal, n_plate, n_above)
        mirror = s0(scene_dict(*args, "mirror", a.pixels, a.spp), seed)
        lit = s0(scene_dict(*args, a.plate, a.pixels, a.spp), seed)
        ratio = (lit / mirror).ravel()
        out.append(ratio.mean())
        err.append(ratio.std(ddof=1) / math.sqrt(ratio.size))
        print(f"{r['coordinate']:>24} R = {out[-1]:.6f} ± {err[-1]:.1e}", file=sys.stderr)
    elapsed = time.time() - t0

    what = {
        "slab": f"dielectric slab (closed box, int_ior {n_plate}, ext_ior {n_above})",
        "thindielectric": f"thindielectric (int_ior {n_plate}, ext_ior {n_above})",
    }[a.plate]
    head = (
        f"# Mitsuba {mi.__version__} render, scalar_spectral_polarized: {what};\n"
        f"# stokes(path) integrator, independent sampler, {a.pixels}x{a.pixels} pixels x {a.spp} spp,"
        f" seed {a.seed} + point index; R = S0(plate)/S0(ideal mirror), mean over pixels;"
        f" {len(rows)} render pairs in {elapsed:.0f} s\n"
        f"# made by: python examples/mitsuba_render_values.py PACK/{case['name']} OUT.csv"
        f" --plate {a.plate} --pixels {a.pixels} --spp {a.spp} --seed {a.seed}\n"
    )
    with open(a.out_csv, "w") as f:
        f.write(head)
        f.write("quantity,coordinate,value\n")
        for r, v in zip(rows, out):
            f.write(f"{quantity},{r['coordinate']},{v:.9e}\n")
    stderr_csv = a.out_csv[: -len(".csv")] if a.out_csv.endswith(".csv") else a.out_csv
    with open(stderr_csv + ".stderr.csv", "w") as f:
        f.write(head)
        f.write("coordinate,value,standard_error\n")
        for r, v, s in zip(rows, out, err):
            f.write(f"{r['coordinate']},{v:.9e},{s:.3e}\n")


if __name__ == "__main__":
    main()
