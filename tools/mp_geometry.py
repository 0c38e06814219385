"""Geometry shared by the 50-digit reference scripts in tools/: a random rotation, a matrix
applied to a vector, and the dot product (for lists of floats or mpmath numbers). Imported by
tools/lloyd_mpmath.py, tools/wedge_mpmath.py and tools/plane_wave_mpmath.py (run from the
repository root: Python puts tools/ on the path)."""
import math


def rotation(rng):
    """A random rotation matrix from a random unit quaternion drawn from `rng`."""
    q = [rng.gauss(0, 1) for _ in range(4)]
    m = math.sqrt(sum(x * x for x in q))
    w, x, y, z = (v / m for v in q)
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]


def apply(R, v):
    return [sum(R[i][j] * v[j] for j in range(3)) for i in range(3)]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))
