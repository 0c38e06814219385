#!/usr/bin/env python3
"""The accumulation core against numpy, side by side: issue #14's ratio, round by round.

Each round runs the 2-thread column rows of the Rust bench (`cpu_rates accumulate-2t`: 1 M
contributions, 16 k points, 4 groups, 50 repetitions) and numpy's `bincount` of the same work
(`accumulate_numpy.py`, 7 repetitions), one right after the other (their order alternating
from round to round), because this VM's speed drifts between minutes. It prints, per round, the
rates and the ratio Rust / numpy of the same statistic: fastest repetition against fastest,
median against median (numpy's `accumulate_numpy.py` used to be quoted at its best against the
Rust mean over all repetitions, which favours numpy).

Throw-away measurement script, not used by the build or the tests. Run from the repository
root (the first round builds the bench):

    python3 examples/accumulate_ratio.py            # 5 rounds
    python3 examples/accumulate_ratio.py 11         # 11 rounds
    CPU_RATES=target/release/deps/cpu_rates-HASH python3 examples/accumulate_ratio.py  # a built bench
"""

import os
import re
import subprocess
import sys

import accumulate_numpy as an

BENCH = ["cargo", "bench", "-q", "-p", "fringe-benches", "--bench", "cpu_rates", "--", "accumulate-2t"]
LINE = re.compile(
    r"columns 2t (plain|compensated): \d+ reps.*?([\d.]+) M/s wall, .*best rep ([\d.]+) M/s, median rep ([\d.]+) M/s"
)


def rust():
    """{summation: (mean, best, median)} in M contributions/s from one bench run (ordinary
    pages; the bench's 2 MiB-page rows are printed by it, not compared here)."""
    binary = os.environ.get("CPU_RATES")
    command = [binary, "accumulate-2t"] if binary else BENCH
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    rates = {m[1]: tuple(float(x) for x in m.groups()[1:]) for m in LINE.finditer(out)}
    assert set(rates) == {"plain", "compensated"}, out
    return rates


def numpy(work):
    """(best, median) in M contributions/s of numpy's bincount."""
    best, median, _ = an.timings(work)
    return an.T / best / 1e6, an.T / median / 1e6


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    point, ids, phase, field = an.data()
    work = lambda: an.accumulate(point, ids, phase, field)  # noqa: E731
    print("round | numpy best, median | Rust plain best, median (mean) | ratio best, median | "
          "Rust compensated best, median | ratio best, median")
    ratios = []
    for r in range(rounds):
        if r % 2 == 0:
            nb, nm = numpy(work)
            rates = rust()
        else:
            rates = rust()
            nb, nm = numpy(work)
        pm, pb, pmed = rates["plain"]
        _, cb, cmed = rates["compensated"]
        ratios.append((pb / nb, pmed / nm))
        print(f"{r + 1} | {nb:.1f}, {nm:.1f} | {pb:.0f}, {pmed:.0f} ({pm:.0f}) | "
              f"{pb / nb:.1f}x, {pmed / nm:.1f}x | {cb:.0f}, {cmed:.0f} | {cb / nb:.1f}x, {cmed / nm:.1f}x",
              flush=True)
    best = sorted(b for b, _ in ratios)
    median = sorted(m for _, m in ratios)
    print(f"plain, over {rounds} rounds: best/best {best[0]:.1f}-{best[-1]:.1f}x "
          f"({sum(b >= 25 for b in best)} of {rounds} >= 25x), median/median "
          f"{median[0]:.1f}-{median[-1]:.1f}x ({sum(m >= 25 for m in median)} of {rounds} >= 25x)")


if __name__ == "__main__":
    main()
