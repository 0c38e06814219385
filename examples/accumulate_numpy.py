#!/usr/bin/env python3
"""The accumulation core's work in numpy (`bincount`), as the baseline of `benches/accumulate.rs`.

Same work as `accumulate/T1M_P16k_G4` in the Rust bench: T = 2^20 contributions laid out point
by point (P = 2^14 points, T/P = 64 each), coherence ids 1..=G (G = 4), phases uniform in
0 … 10^6 cycles, fields complex 3-vectors with components uniform in [-1, 1) + i[-1, 1).
Per point: phasor e^{2πi(c − round c)} of each contribution, grouped by coherence id, the
complex 3-vectors E·phasor summed per group, and the squared lengths |E_g|² summed per point
(eq. 6, docs/PHYSICS.md §3; id 0 would add |E|² incoherently). Plain float64 sums (numpy's
`bincount` adds in input order, like the Rust `plain` variant).

Throw-away measurement script, not used by the build or the tests. Run:

    python3 examples/accumulate_numpy.py            # best and median of 7 runs: wall and CPU time

It also checks itself against a direct per-point loop on the first 64 points. A second line
times the same work on input grouped into runs of one (point, id) (`add.reduceat`): the fair
baseline for an accumulation that is handed grouped input instead of an id per contribution.
"""

import time

import numpy as np

T = 1 << 20
P = 1 << 14
G = 4


def data(seed=1):
    rng = np.random.default_rng(seed)
    ids = 1 + rng.integers(0, G, size=T, dtype=np.int64)
    phase = 1e6 * rng.random(T)
    field = (2.0 * rng.random((T, 3)) - 1.0) + 1j * (2.0 * rng.random((T, 3)) - 1.0)
    point = np.repeat(np.arange(P, dtype=np.int64), T // P)
    return point, ids, phase, field


def accumulate(point, ids, phase, field):
    """Intensity of every point: Σ_g |Σ_{j in g} E_j e^{2πi c_j}|² + Σ_{id 0} |E_j|²."""
    frac = phase - np.round(phase)
    ph = np.exp(2j * np.pi * frac)
    coherent = ids != 0
    key = point * (G + 1) + ids  # one bin per (point, group)
    nbins = P * (G + 1)
    e2 = np.zeros(nbins)
    for c in range(3):
        e = field[:, c] * ph
        re = np.bincount(key, weights=e.real, minlength=nbins)
        im = np.bincount(key, weights=e.imag, minlength=nbins)
        e2 += re * re + im * im
    e2[0 :: G + 1] = 0.0  # id 0 is not a group
    out = e2.reshape(P, G + 1).sum(axis=1)
    if not coherent.all():
        inc = (np.abs(field[~coherent]) ** 2).sum(axis=1)
        out += np.bincount(point[~coherent], weights=inc, minlength=P)
    return out


def grouped(point, ids, phase, field):
    """The same contributions grouped into runs of one (point, id), as a producer that writes
    each coherence group contiguously would hand them over: the data sorted by (point, id), the
    start of every run and of every point's first run."""
    order = np.lexsort((ids, point))
    point, ids, phase, field = point[order], ids[order], phase[order], field[order]
    key = point * (G + 1) + ids
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    run_point = point[starts]
    point_starts = np.flatnonzero(np.r_[True, run_point[1:] != run_point[:-1]])
    return phase, field, starts, point_starts


def accumulate_grouped(phase, field, starts, point_starts):
    """The same intensities from grouped input (all ids coherent, as in `data`): one
    `add.reduceat` per run instead of a `bincount` per (point, id) key."""
    ph = np.exp(2j * np.pi * (phase - np.round(phase)))
    e = np.add.reduceat(field * ph[:, None], starts, axis=0)
    return np.add.reduceat((e.real**2 + e.imag**2).sum(axis=1), point_starts)


def direct(point, ids, phase, field, k):
    sel = point == k
    groups = {}
    inc = 0.0
    for i, c, f in zip(ids[sel], phase[sel], field[sel]):
        if i == 0:
            inc += float((np.abs(f) ** 2).sum())
            continue
        p = np.exp(2j * np.pi * (c - np.round(c)))
        groups[i] = groups.get(i, 0) + f * p
    return inc + sum(float((np.abs(e) ** 2).sum()) for e in groups.values())


def main():
    point, ids, phase, field = data()
    out = accumulate(point, ids, phase, field)
    for k in range(64):
        want = direct(point, ids, phase, field, k)
        assert abs(out[k] - want) <= 1e-12 * max(1.0, want), (k, out[k], want)
    runs = grouped(point, ids, phase, field)
    assert np.all(np.abs(accumulate_grouped(*runs) - out) <= 1e-12 * np.maximum(1.0, out))
    for name, work in [
        ("bincount", lambda: accumulate(point, ids, phase, field)),
        ("reduceat on grouped input", lambda: accumulate_grouped(*runs)),
    ]:
        best, median, best_cpu = timings(work)
        print(
            f"numpy {np.__version__} {name}: T={T} P={P} G={G}: best {best * 1e3:.1f} ms wall "
            f"({T / best / 1e6:.1f} M contributions/s), median {median * 1e3:.1f} ms "
            f"({T / median / 1e6:.1f} M/s), best {best_cpu * 1e3:.1f} ms CPU "
            f"({T / best_cpu / 1e6:.1f} M contributions per CPU-second)"
        )


def timings(work, runs=7):
    """Best and median wall seconds and best CPU seconds of `runs` calls of `work`."""
    wall, cpu = [], []
    for _ in range(runs):
        t0, c0 = time.perf_counter(), time.process_time()
        work()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    wall.sort()
    return wall[0], wall[len(wall) // 2], min(cpu)

if __name__ == "__main__":
    main()
