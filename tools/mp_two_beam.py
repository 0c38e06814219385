"""The two-beam plate at 50 digits, shared by the reference scripts in tools/ (PHYSICS.md sec. 5
"Plate, two beams"; paper Fig. 4 left): a point source at height hs above a plate of index n2
and thickness d (the same medium n1 above and below), an observation point at height ho and
lateral distance x. Beam 1 reflects at the top face (amplitudes r12); beam 2 enters at lateral
a, reflects at the bottom face and leaves (amplitudes t12 r23 t21). Unpolarized source with the
paper's channels s and p at every ray:

    I = 1/2 |r12s e^{i phi} + a2s|^2 + 1/2 (|r12p|^2 + |a2p|^2 + 2 Re(r12p conj(a2p) e^{i phi}) cos(t1 - t2)),

phi = 2 pi (Op1 - Op2)/lam, the Fresnel coefficients in the cosine forms (P1-P4) with a complex
cosine beyond the critical angle. Imported by tools/grazing_mpmath.py,
tools/beyond_critical_mpmath.py, tools/beyond_critical_plate_mpmath.py, tools/two_beam_mpmath.py
and tools/two_beam_plate_found_mpmath.py (run from the repository root: Python puts tools/ on
the path). Each script keeps its own root finder for a."""
import mpmath as mp


def fresnel(n1, n2, ci):
    """(rs, rp, ts, tp, cos t) from index n1 into n2 at incidence cosine ci; cos t is +i sqrt(..)
    beyond the critical angle."""
    st2 = (n1 / n2) ** 2 * (1 - ci * ci)
    ct = mp.sqrt(1 - st2)
    rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct)
    rp = (n2 * ci - n1 * ct) / (n2 * ci + n1 * ct)
    ts = 2 * n1 * ci / (n1 * ci + n2 * ct)
    tp = 2 * n1 * ci / (n2 * ci + n1 * ct)
    return rs, rp, ts, tp, ct


def landing(n1, n2, d, hs, ho, x):
    """The landing error of beam 2 entering the top face at lateral a: zero at the exact a."""

    def land(a):
        st = n1 / n2 * a / mp.sqrt(a * a + hs * hs)
        return a + 2 * d * st / mp.sqrt(1 - st * st) + ho * a / hs - x

    return land


def intensity_at(n1, n2, d, hs, ho, x, lam, a, r_top=None):
    """(I, tan t) for beam 2 entering at lateral a (the root of `landing`); t is its angle in
    the plate. `r_top`: the top beam's (r_s, r_p) if not the bare face's Fresnel r12 (beyond
    the critical angle, the plate's frustrated r_layer)."""
    l1 = mp.sqrt(a * a + hs * hs)
    st = n1 / n2 * a / l1
    ct = mp.sqrt(1 - st * st)
    xe = a + 2 * d * st / ct
    op2 = n1 * l1 + 2 * n2 * d / ct + n1 * mp.sqrt((x - xe) ** 2 + ho * ho)
    op1 = n1 * mp.sqrt(x * x + (hs + ho) ** 2)
    r12s, r12p, _, _, _ = fresnel(n1, n2, (hs + ho) / mp.sqrt(x * x + (hs + ho) ** 2))
    if r_top is not None:
        r12s, r12p = r_top
    _, _, t12s, t12p, _ = fresnel(n1, n2, hs / l1)
    r23s, r23p, t21s, t21p, _ = fresnel(n2, n1, ct)
    a2s, a2p = t12s * r23s * t21s, t12p * r23p * t21p
    e = mp.expjpi(2 * (op1 - op2) / lam)
    overlap = mp.cos(mp.atan2(x, hs + ho) - mp.atan2(a, hs))
    i_s = abs(r12s * e + a2s) ** 2
    i_p = abs(r12p) ** 2 + abs(a2p) ** 2 + 2 * mp.re(r12p * mp.conj(a2p) * e) * overlap
    return (i_s + i_p) / 2, st / ct
