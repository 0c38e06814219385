#!/usr/bin/env python3
"""50-digit reflectances and transmittances of the below-critical fuzz scenes of
tests/suite/truth_tail_closure.rs: films lit 1e-10 deg - 1 deg below the critical angle of their
top face, where the wave inside grazes the film and the Airy tail beyond the cap of internal
reflections is closed exactly (docs/PHYSICS.md 5a). Each shrunk case file
tests/fuzz_found/fuzz_airy_s1_<index>.json is evaluated at every probe point as the frustrated-film
scenes are (`print_profiles` of tools/frustrated_film_found_mpmath.py: `airy_case` of
tools/precision_classes_mpmath.py times the source's intensity).
Run: python3 tools/below_critical_closure_mpmath.py > tests/data/below_critical_closure_mpmath.csv
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from frustrated_film_found_mpmath import print_profiles  # noqa: E402

SCENES = [77, 108, 117, 203]

if __name__ == "__main__":
    print_profiles(SCENES)
