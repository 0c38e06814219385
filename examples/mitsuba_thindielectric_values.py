"""Turn Mitsuba 3's `thindielectric` BSDF into a fringe value file for a plate pack.

Usage (outside cargo; needs `pip install mitsuba`):

    fringe export plate_airy_s --out /tmp/pack
    python examples/mitsuba_thindielectric_values.py /tmp/pack/plate_airy_s /tmp/mitsuba.csv
    fringe grade plate_airy_s --values /tmp/mitsuba.csv

For every probe point of an incidence-angle sweep observed in the reflected far field, the
BSDF is sampled in the `scalar_spectral_polarized` variant with the incident direction at that
angle and the sample forced onto the reflected lobe (sample1 = 0). The reflected power for the
case's light is the lobe's probability times the Mueller matrix applied to the incident Stokes
vector; Mitsuba's thin dielectric returns a depolarizing Mueller matrix (only M00 non-zero), so
the value is pdf * M00 for any linear input polarization. This evaluates Mitsuba's BSDF as
shipped (the model a Mitsuba render of the plate uses), not a full image render.
"""
import csv
import json
import math
import sys

import mitsuba as mi

mi.set_variant("scalar_spectral_polarized")


def main(pack_dir, out_csv):
    pack = json.load(open(f"{pack_dir}/pack.json"))
    case = json.load(open(f"{pack_dir}/case.json"))
    if pack["probe"]["coordinate"] != "incidence_angle_deg":
        sys.exit("this script handles incidence-angle sweeps only")
    quantity = pack["quantities"][0]
    if quantity["observable"] != "reflectance":
        sys.exit("this script handles reflected far-field probes only")
    scene = case["scene"]
    plate = next(s["plate"] for s in scene["surfaces"] if "plate" in s)
    index = lambda medium: scene["media"][medium]["constant"]["n"]
    n_in, n_above, n_below = index(plate["medium"]), index(plate["above"]), index(plate["below"])
    if n_above != n_below:
        sys.exit("Mitsuba's thindielectric is a free-standing sheet: above and below must match")
    bsdf = mi.load_dict({"type": "thindielectric", "int_ior": n_in, "ext_ior": n_above})
    ctx = mi.BSDFContext()
    rows = list(csv.DictReader(open(f"{pack_dir}/probes.csv")))
    with open(out_csv, "w") as f:
        f.write(f"# Mitsuba {mi.__version__} thindielectric (int_ior {n_in}, ext_ior {n_above}), "
                "scalar_spectral_polarized, reflected lobe pdf * M00\n")
        f.write("quantity,coordinate,value\n")
        for r in rows:
            theta = math.radians(float(r["coordinate"]))
            si = mi.SurfaceInteraction3f()
            si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
            si.wi = mi.Vector3f(math.sin(theta), 0, math.cos(theta))
            bs, weight = bsdf.sample(ctx, si, 0.0, mi.Point2f(0.5, 0.5))
            value = bs.pdf * weight[0, 0][0]
            f.write(f"{quantity['name']},{r['coordinate']},{value:.17e}\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
