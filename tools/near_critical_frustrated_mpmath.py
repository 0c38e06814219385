#!/usr/bin/env python3
"""50-digit reflectances and transmittances of the near-critical fuzz scenes of
tests/suite/truth_tail_closure.rs (`near_critical_frustrated_films_hold_against_50_digits`):
films lit 1e-9 deg - 1e-7 deg beyond the critical angle of their top face, inside the margin the
budget keeps (case::run::budget), where the tracer reflects totally into the frustrated layer and
no order enters the film; they were refused as "the Airy tail ... cannot be closed exactly"
(`fringe fuzz --family airy --seed 1 --count 10000`). Scene 1658's three points straddle the
critical angle (the first is below it: its tail is closed). Each case file
tests/fuzz_found/fuzz_airy_s1_<index>.json (unpolarized light) is evaluated at every probe point
as the frustrated-film scenes are (`print_profiles` of tools/frustrated_film_found_mpmath.py:
`airy_case` of tools/precision_classes_mpmath.py, complex cos t2 beyond the critical angle).
Run: python3 tools/near_critical_frustrated_mpmath.py > tests/data/near_critical_frustrated_mpmath.csv
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from frustrated_film_found_mpmath import print_profiles, unpolarized  # noqa: E402

SCENES = [183, 1658, 6878, 2707, 5606]

if __name__ == "__main__":
    print_profiles(SCENES, unpolarized)
