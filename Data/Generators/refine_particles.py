#!/usr/bin/python3
"""Refine an SPH particle file K-fold per axis: every particle becomes a K x K x K lattice
of particles at spacing dx / K centred on it (offsets dx ((i + 1/2) / K - 1/2), i < K), with
smoothing length h / K and mass m / K^3; the other arrays (density, speed) are kept. The
refined set samples the same fluid at K times the resolution, so a real simulator's frame
(the PySPH dam break) grows to the tens or hundreds of millions of particles of the scale
benchmarks without a simulation of that size.

Usage: refine_particles.py INPUT.vtk OUTPUT.vtk K [--dx DX] [--arrays NAMES]
  INPUT     legacy VTK binary polydata as pysph_to_vtk.py writes it (float POINTS,
            VERTICES, POINT_DATA of float SCALARS)
  K         lattice points per axis (the output has K^3 times the particles)
  --dx      the input's particle spacing (default: h / 1.3, PySPH's hdx of the dam break)
  --arrays  the arrays kept, comma-separated (default h,m,rho,vmag: what the SPH mappers
            read); h is divided by K and m by K^3, the others copied

Writes OUTPUT and OUTPUT.provenance.txt; an existing OUTPUT is a cache and is kept.
Memory: about 1.3 times the output's size (the output arrays and one chunk of the input).
"""
import argparse
import os
import re
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pysph_to_vtk import write_vtk  # noqa: E402

SCALE_POWER = {"h": 1, "m": 3}  # divided by K to this power; the rest copied


def read_vtk(path):
    """(points float32 (n, 3), {name: float32 array}) of a legacy binary polydata file (int
    arrays, such as LIGGGHTS's type and id, read as float32)."""
    with open(path, "rb") as f:
        data = f.read()
    pos = 0

    def line():
        nonlocal pos
        end = data.index(b"\n", pos)
        text = data[pos:end].decode("ascii", "replace").strip()
        pos = end + 1
        return text

    for _ in range(4):  # version, title, BINARY, DATASET POLYDATA
        line()
    head = line()
    m = re.match(r"POINTS (\d+) float", head)
    if not m:
        raise ValueError(f"{path}: expected float POINTS, found '{head}'")
    n = int(m.group(1))
    points = np.frombuffer(data, ">f4", 3 * n, pos).reshape(n, 3)
    pos += 12 * n
    arrays = {}
    while pos < len(data):
        text = line()
        if not text:
            continue
        if text.startswith("VERTICES"):
            pos += 4 * int(text.split()[2])
        elif text.startswith("SCALARS"):
            name, kind = text.split()[1:3]
            if kind not in ("float", "int"):
                raise ValueError(f"{path}: array {name} is {kind}, not float or int")
            line()  # LOOKUP_TABLE default
            values = np.frombuffer(data, ">f4" if kind == "float" else ">i4", n, pos)
            arrays[name] = values if kind == "float" else values.astype(np.float32)
            pos += 4 * n
    return points, arrays


def read_arrays(parser, path, names):
    """read_vtk of `path` keeping only the comma-separated arrays `names` (a parser error
    names the missing ones)."""
    points, arrays = read_vtk(path)
    wanted = [a for a in names.split(",") if a]
    missing = [a for a in wanted if a not in arrays]
    if missing:
        parser.error(f"{path} has no array {', '.join(missing)}; it has {', '.join(arrays)}")
    return points, {a: arrays[a] for a in wanted}


def write_output(output, points, arrays, title, script, argv, facts, start):
    """Write `output` (through a .part file, so that an interrupted run leaves no file the
    cache would accept) and its provenance: the script, its command, the lines `facts`,
    the particle count, date and wall time since `start`."""
    n = len(points)
    part = output + ".part"
    write_vtk(part, points, arrays, title)
    os.replace(part, output)
    seconds = time.time() - start
    with open(output + ".provenance.txt", "w") as f:
        f.write(f"file: {os.path.basename(output)}\n"
                f"generator: Data/Generators/{script}\n"
                f"command: {script} {' '.join(argv)}\n"
                + "".join(line + "\n" for line in facts) +
                f"particles: {n}\n"
                f"date: {time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())}\n"
                f"wall time: {seconds:.0f} s\n")
    print(f"wrote {output} ({n} particles, {seconds:.0f} s)")


def refine(points, arrays, k, dx):
    """The K^3-fold refined points and arrays (particle i's lattice at rows k^3 i ...)."""
    n = len(points)
    axis = dx * ((np.arange(k) + 0.5) / k - 0.5)
    offsets = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
    per = len(offsets)
    out_points = np.empty((n * per, 3), np.float32)
    chunk = 1 << 20
    for start in range(0, n, chunk):
        p = points[start:start + chunk].astype(np.float64)
        out_points[start * per:(start + len(p)) * per] = (
            p[:, None, :] + offsets[None, :, :]).reshape(-1, 3)
    out_arrays = []
    for name, values in arrays.items():
        factor = float(k) ** -SCALE_POWER.get(name, 0)
        out_arrays.append((name, np.repeat(values.astype(np.float32) * np.float32(factor), per)))
    return out_points, out_arrays


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input")
    parser.add_argument("output")
    parser.add_argument("k", type=int)
    parser.add_argument("--dx", type=float)
    parser.add_argument("--arrays", default="h,m,rho,vmag")
    args = parser.parse_args(argv)
    if os.path.exists(args.output):
        print(f"{args.output} exists, not regenerated")
        return 0
    if args.k < 1:
        parser.error("K must be at least 1")
    start = time.time()
    points, arrays = read_arrays(parser, args.input, args.arrays)
    dx = args.dx
    if dx is None:
        if "h" not in arrays:
            parser.error("--dx is needed when the file has no h array")
        dx = float(np.median(arrays["h"])) / 1.3
    out_points, out_arrays = refine(points, arrays, args.k, dx)
    write_output(args.output, out_points, out_arrays,
                 f"{os.path.basename(args.input)} refined {args.k}^3: {len(out_points)} particles, "
                 f"dx {dx / args.k:g}",
                 "refine_particles.py", argv,
                 [f"input: {args.input} ({len(points)} particles, dx {dx:g})",
                  f"refinement: {args.k}^3 lattice per particle, h / {args.k}, m / {args.k ** 3}, "
                  f"other arrays copied: {', '.join(arrays)}"], start)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
