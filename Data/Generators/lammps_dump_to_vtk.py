#!/usr/bin/python3
"""Convert a LAMMPS or LIGGGHTS text dump (the first snapshot) into legacy
VTK binary polydata.

Usage: lammps_dump_to_vtk.py [--title TEXT] [--radius-by-type T:R,...]
                             DUMP OUTPUT.vtk

The dump needs the columns id x y z; any others are kept. The output holds
one VERTEX cell per atom (so ParaView shows the points without a glyph
filter) and one point array per dump column other than x y z, in this order:
  type    int    atom type (the active scalars), if the dump has it
  radius  float  sphere radius: the dump's radius column if it has one,
                 otherwise looked up from the type (--radius-by-type)
  id      int    atom id
  ...     float  every other column in dump order, named as in the dump
                 with characters other than letters, digits and _ turned
                 into _ (c_pe stays c_pe, c_f[1] becomes c_f_1_); ix iy iz
                 image flags and mol are int
--radius-by-type defaults to 1:0.5,2:0.4, half of each type's LJ sigma in
lammps_melt.in (sigma_11 = 1.0, sigma_22 = 0.8), i.e. the contact radius of
two like atoms; every type in a dump without a radius column needs a radius.
--title sets the file's title line; {n} in it becomes the atom count and
{box} the box bounds (default: the lammps_melt.sh description).
Legacy .vtk is used because Debian 12's VTK fails on XML files with
appended data (see SETUP.md). Run with Debian's /usr/bin/python3 (numpy).
"""

import argparse
import re
import sys

import numpy as np

DEFAULT_RADIUS_BY_TYPE = "1:0.5,2:0.4"
INT_COLUMNS = {"id", "type", "mol", "ix", "iy", "iz", "proc", "procp1"}


def read_dump(path):
    """Return (columns, table, box) of the first snapshot in a text dump."""
    with open(path, "r") as f:
        natoms = None
        box = []
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: no 'ITEM: ATOMS' section")
            if line.startswith("ITEM: NUMBER OF ATOMS"):
                natoms = int(f.readline())
            elif line.startswith("ITEM: BOX BOUNDS"):
                box = [tuple(float(v) for v in f.readline().split()[:2]) for _ in range(3)]
            elif line.startswith("ITEM: ATOMS"):
                columns = line.split()[2:]
                break
        # Read exactly natoms rows so that a file with several snapshots
        # still converts its first one.
        table = np.loadtxt(f, max_rows=natoms, ndmin=2)
    if natoms is None or table.shape[0] != natoms:
        raise ValueError(f"{path}: header says {natoms} atoms, read {table.shape[0]}")
    if table.shape[1] != len(columns):
        raise ValueError(f"{path}: {len(columns)} column names but {table.shape[1]} columns")
    if len(set(columns)) != len(columns):
        raise ValueError(f"{path}: repeated column names {columns}")
    for name in ("id", "x", "y", "z"):
        if name not in columns:
            raise ValueError(f"{path}: column '{name}' missing (have {columns})")
    return columns, table, box


def array_name(column):
    """A dump column name as a legacy VTK array name (no spaces or brackets)."""
    return re.sub(r"[^A-Za-z0-9_]", "_", column)


def parse_radius_by_type(text):
    radius_by_type = {}
    for item in text.split(","):
        t, r = item.split(":")
        radius_by_type[int(t)] = float(r)
    return radius_by_type


def point_arrays(columns, table, radius_by_type):
    """[(name, values, vtk type, big-endian dtype)] in the order described above."""
    col = {name: i for i, name in enumerate(columns)}
    arrays = []

    def add(column, values=None):
        if values is None:
            values = table[:, col[column]]
        if column in INT_COLUMNS:
            arrays.append((array_name(column), values.astype(np.int32), "int", ">i4"))
        else:
            arrays.append((array_name(column), values.astype(np.float32), "float", ">f4"))

    if "type" in col:
        add("type")
    if "radius" in col:
        add("radius")
    else:
        if "type" not in col:
            raise ValueError("the dump has neither a radius nor a type column")
        types = table[:, col["type"]].astype(np.int32)
        unknown = sorted(set(np.unique(types).tolist()) - set(radius_by_type))
        if unknown:
            raise ValueError(f"no radius defined for atom types {unknown} (--radius-by-type)")
        radius = np.zeros(len(types), dtype=np.float32)
        for t, r in radius_by_type.items():
            radius[types == t] = r
        add("radius", radius)
    add("id")
    for column in columns:
        if column not in ("type", "radius", "id", "x", "y", "z"):
            add(column)
    names = [a[0] for a in arrays]
    if len(set(names)) != len(names):
        raise ValueError(f"array names clash after renaming: {names}")
    return arrays


def write_vtk(path, xyz, arrays, title):
    """Write legacy VTK 3.0 binary polydata (big-endian, as the format requires)."""
    n = len(xyz)
    # VERTICES: n cells, each "1 pointIndex", 2n integers in total.
    verts = np.empty((n, 2), dtype=">i4")
    verts[:, 0] = 1
    verts[:, 1] = np.arange(n)

    with open(path, "wb") as f:
        def text(s):
            f.write(s.encode("ascii"))

        text(f"# vtk DataFile Version 3.0\n{title[:255]}\nBINARY\nDATASET POLYDATA\n")
        text(f"POINTS {n} float\n")
        f.write(xyz.astype(">f4").tobytes())
        text(f"\nVERTICES {n} {2 * n}\n")
        f.write(verts.tobytes())
        text(f"\nPOINT_DATA {n}\n")
        for name, values, vtk_type, dtype in arrays:
            text(f"SCALARS {name} {vtk_type} 1\nLOOKUP_TABLE default\n")
            f.write(values.astype(dtype).tobytes())
            text("\n")


def main(argv):
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--title")
    parser.add_argument("--radius-by-type", default=DEFAULT_RADIUS_BY_TYPE)
    parser.add_argument("dump")
    parser.add_argument("output")
    args = parser.parse_args(argv[1:])

    columns, table, box = read_dump(args.dump)
    col = {name: i for i, name in enumerate(columns)}
    xyz = table[:, [col["x"], col["y"], col["z"]]].astype(np.float32)
    if not np.all(np.isfinite(table)):
        sys.exit(f"{args.dump}: non-finite values")
    arrays = point_arrays(columns, table, parse_radius_by_type(args.radius_by_type))
    n = len(xyz)
    box_text = " ".join(f"[{lo:g},{hi:g}]" for lo, hi in box)
    title = args.title or "LAMMPS binary LJ melt, {n} atoms, box {box}, sigma units"
    write_vtk(args.output, xyz, arrays, title.format(n=n, box=box_text))

    # One summary line; the generator scripts copy it into the provenance file.
    summary = f"{n} atoms"
    if "type" in col:
        counts = np.bincount(table[:, col["type"]].astype(np.int64))
        summary += ", per type: " + ", ".join(
            f"{t}: {counts[t]}" for t in range(1, len(counts)) if counts[t])
    summary += "; point arrays: " + " ".join(a[0] for a in arrays)
    print(summary)


if __name__ == "__main__":
    main(sys.argv)
