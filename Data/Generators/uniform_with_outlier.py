#!/usr/bin/python3
"""A hard case of the sphere grids: N - 1 points uniform in a box of side 100 and one
stray point at x = 1e5 (a thousand box sizes away), as one bad particle in a simulation's
output makes it; legacy VTK binary polydata with a `speed` array (uniform in [0, 1]).

Usage: uniform_with_outlier.py OUTPUT.vtk [N]   (default N 1000000, seed 3)
Run with Debian's /usr/bin/python3 (numpy).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lammps_dump_to_vtk import write_vtk  # noqa: E402


def main(argv):
    if len(argv) not in (1, 2):
        print(__doc__, file=sys.stderr)
        return 2
    n = int(argv[1]) if len(argv) == 2 else 1000000
    rng = np.random.default_rng(3)
    xyz = rng.uniform(0, 100, size=(n, 3)).astype(np.float32)
    xyz[-1] = (1e5, 50, 50)
    speed = rng.uniform(0, 1, n).astype(np.float32)
    write_vtk(argv[0], xyz, [("speed", speed, "float", ">f4")],
              "uniform points with one far outlier")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
