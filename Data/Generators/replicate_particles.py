#!/usr/bin/python3
"""Replicate a particle file NX x NY x NZ times side by side, as LAMMPS's `replicate` does
with a periodic cell: copy (a, b, c) is the input shifted by (a Lx, b Ly, c Lz), L the
extent of the input's points plus `--gap` (default: the largest radius, so that copies
touch without overlapping). Every copy keeps the input's arrays. A real simulator's run
(the LIGGGHTS packings) grows to the millions of particles of the scale benchmarks with
its own radius distribution and packing, which no resampling would keep.

Usage: replicate_particles.py INPUT.vtk OUTPUT.vtk NX NY NZ [--gap G] [--arrays NAMES]
  INPUT     legacy VTK binary polydata (float POINTS, VERTICES, float or int SCALARS;
            int arrays are written as float)
  --arrays  the arrays kept, comma-separated (default radius,type)

Writes OUTPUT and OUTPUT.provenance.txt; an existing OUTPUT is a cache and is kept.
Memory: about 1.3 times the output's size.
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from refine_particles import read_arrays, write_output  # noqa: E402


def replicate(points, arrays, counts, period):
    """The copies' points (copy after copy, x fastest) and arrays, repeated alike."""
    n = len(points)
    copies = int(np.prod(counts))
    out = np.empty((n * copies, 3), np.float32)
    base = points.astype(np.float64)
    index = 0
    for c in range(counts[2]):
        for b in range(counts[1]):
            for a in range(counts[0]):
                out[index * n:(index + 1) * n] = base + period * np.array([a, b, c])
                index += 1
    return out, [(name, np.tile(values.astype(np.float32), copies)) for name, values in arrays.items()]


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input")
    parser.add_argument("output")
    parser.add_argument("counts", type=int, nargs=3, metavar="N")
    parser.add_argument("--gap", type=float)
    parser.add_argument("--arrays", default="radius,type")
    args = parser.parse_args(argv)
    if os.path.exists(args.output):
        print(f"{args.output} exists, not regenerated")
        return 0
    if min(args.counts) < 1:
        parser.error("NX, NY and NZ must be at least 1")
    start = time.time()
    points, arrays = read_arrays(parser, args.input, args.arrays)
    gap = args.gap
    if gap is None:
        gap = float(arrays["radius"].max()) if "radius" in arrays else 0.0
    period = points.max(axis=0).astype(np.float64) - points.min(axis=0) + gap
    out_points, out_arrays = replicate(points, arrays, args.counts, period)
    counts = "x".join(str(c) for c in args.counts)
    write_output(args.output, out_points, out_arrays,
                 f"{os.path.basename(args.input)} replicated {counts}: {len(out_points)} particles",
                 "replicate_particles.py", argv,
                 [f"input: {args.input} ({len(points)} particles)",
                  f"copies: {counts}, period {' '.join(f'{p:g}' for p in period)} (gap {gap:g})",
                  f"arrays: {', '.join(arrays)}"], start)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
