#!/usr/bin/env python3
"""Independent cross-check of fringe::colour's Newton (soap-film) colours with colour-science.

Reference pipeline (colour-science only, nothing taken from fringe):
  * reflectance R(lambda) of a soap film (n = 1.33, air both sides, normal incidence) from the
    exact Airy formula r = (r12 + r23 e^{i beta}) / (1 + r12 r23 e^{i beta}),
    r12 = (1-n)/(1+n), r23 = (n-1)/(n+1), beta = 4 pi n d / lambda, R = |r|^2 (numpy complex);
  * colour.sd_to_XYZ(sd, cmfs=CIE 1931 2 Degree Standard Observer (360-830 nm, 1 nm),
    illuminant=colour.SDS_ILLUMINANTS['D65'] (colour aligns it to 1 nm itself),
    method='Integration') / 100, i.e. Y = 1 for a perfect reflector;
  * colour.XYZ_to_sRGB(XYZ) (IEC 61966-2-1, D65 white, encoded, not clipped).

Usage:
  python3 newton_crosscheck.py                    # write the reference CSV
  python3 newton_crosscheck.py RUST.csv           # also compare fringe's CSV (from
      cargo run --example newton_csv > RUST.csv) with colour.delta_E(method='CIE 2000')
  python3 newton_crosscheck.py RUST.csv RUST_E.csv
      # also compare illuminant E + Bradford (cargo run --example newton_csv -- E bradford):
      # colour.sd_constant(1) as illuminant, colour.chromatic_adaptation(Von Kries, Bradford)
      # from (1,1,1) to (0.95047, 1, 1.08883), colour.XYZ_to_RGB(..., 'sRGB') linear.
Exit status 0 only if every max CIEDE2000 is < 1.
"""

import sys
import warnings
from pathlib import Path

import numpy as np

warnings.filterwarnings("ignore")
import colour  # noqa: E402

N_FILM = 1.33
THICKNESSES_NM = np.arange(0, 1501, 10)
OUT = Path(__file__).with_name("newton_reference_colour_science.csv")


def airy_reflectance(n, d_nm, lambdas_nm):
    """|r|^2 of a film of index n, thickness d in air at normal incidence (Airy sum)."""
    r12 = (1 - n) / (1 + n)
    r23 = (n - 1) / (n + 1)
    phase = np.exp(1j * 4 * np.pi * n * d_nm / lambdas_nm)
    r = (r12 + r23 * phase) / (1 + r12 * r23 * phase)
    return np.abs(r) ** 2


def reference():
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]  # 360..830 nm, 1 nm
    illuminant = colour.SDS_ILLUMINANTS["D65"]
    lambdas = cmfs.wavelengths
    rows = []
    for d in THICKNESSES_NM:
        sd = colour.SpectralDistribution(
            dict(zip(lambdas, airy_reflectance(N_FILM, float(d), lambdas)))
        )
        xyz = colour.sd_to_XYZ(sd, cmfs, illuminant, method="Integration") / 100
        rgb = colour.XYZ_to_sRGB(xyz)
        rows.append((d, *xyz, *rgb))
    return np.array(rows)


def write_reference(ref):
    header = (
        f"# Soap-film (n={N_FILM}, air both sides, normal incidence, exact Airy reflectance) "
        f"interference colours, thickness 0..1500 nm step 10 nm. Produced by colour-science "
        f"{colour.__version__} (numpy {np.__version__}) with crosscheck/newton_crosscheck.py: "
        f"colour.sd_to_XYZ(sd, CIE 1931 2 Degree Standard Observer 360-830 nm 1 nm, "
        f"SDS_ILLUMINANTS['D65'], method='Integration')/100 (Y=1 for a perfect reflector), "
        f"then colour.XYZ_to_sRGB (IEC 61966-2-1, encoded, NOT clipped: R_srgb,G_srgb,B_srgb "
        f"may lie outside [0,1]). Independent of fringe's code.\n"
        "thickness_nm,X,Y,Z,R_srgb,G_srgb,B_srgb\n"
    )
    lines = [
        f"{int(r[0])},{r[1]:.10e},{r[2]:.10e},{r[3]:.10e},{r[4]:.8f},{r[5]:.8f},{r[6]:.8f}"
        for r in ref
    ]
    OUT.write_text(header + "\n".join(lines) + "\n")
    print(f"wrote {OUT} ({len(ref)} rows)")


def compare(ref, rust_csv):
    rust = np.loadtxt(rust_csv, delimiter=",", comments="#", skiprows=2)
    assert np.array_equal(rust[:, 0], ref[:, 0]), "thickness columns differ"
    d65 = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    lab_ref = colour.XYZ_to_Lab(ref[:, 1:4], d65)
    lab_rust = colour.XYZ_to_Lab(rust[:, 1:4], d65)
    de = colour.delta_E(lab_ref, lab_rust, method="CIE 2000")
    i = int(np.argmax(de))
    print(f"max CIEDE2000 = {de[i]:.3e} at d = {ref[i, 0]:.0f} nm; mean = {de.mean():.3e}")
    print(f"max |XYZ diff| = {np.abs(ref[:, 1:4] - rust[:, 1:4]).max():.3e}")
    srgb8_ref = np.round(255 * np.clip(ref[:, 4:7], 0, 1)).astype(int)
    diff8 = np.abs(srgb8_ref - rust[:, 7:10].astype(int)).max()
    print(f"max |sRGB8 diff| = {diff8}")
    return de.max()


def compare_e_bradford(rust_csv):
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    illuminant_e = colour.sd_constant(1.0, cmfs.shape)
    lambdas = cmfs.wavelengths
    white_d65 = np.array([0.95047, 1.0, 1.08883])
    rust = np.loadtxt(rust_csv, delimiter=",", comments="#", skiprows=2)
    de, dlin = [], []
    for row in rust:
        sd = colour.SpectralDistribution(
            dict(zip(lambdas, airy_reflectance(N_FILM, row[0], lambdas)))
        )
        xyz_e = colour.sd_to_XYZ(sd, cmfs, illuminant_e, method="Integration") / 100
        xyz_d65 = colour.chromatic_adaptation(
            xyz_e, np.ones(3), white_d65, method="Von Kries", transform="Bradford"
        )
        linear = colour.XYZ_to_RGB(xyz_d65, "sRGB", apply_cctf_encoding=False)
        dlin.append(np.abs(linear - row[4:7]).max())
        # Compare both colours in the same space: Rust's linear sRGB back to XYZ.
        xyz_rust = colour.RGB_to_XYZ(row[4:7], "sRGB", apply_cctf_decoding=False)
        xy = colour.XYZ_to_xy(white_d65)
        xyz_ref = colour.RGB_to_XYZ(linear, "sRGB", apply_cctf_decoding=False)
        de.append(
            colour.delta_E(
                colour.XYZ_to_Lab(xyz_ref, xy),
                colour.XYZ_to_Lab(xyz_rust, xy),
                method="CIE 2000",
            )
        )
    print(f"E+Bradford: max |linear sRGB diff| = {max(dlin):.3e}, max CIEDE2000 = {max(de):.3e}")
    return max(de)


if __name__ == "__main__":
    ref = reference()
    write_reference(ref)
    worst = 0.0
    if len(sys.argv) > 1:
        worst = max(worst, compare(ref, sys.argv[1]))
    if len(sys.argv) > 2:
        worst = max(worst, compare_e_bradford(sys.argv[2]))
    sys.exit(0 if worst < 1 else 1)
