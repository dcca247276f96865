#!/usr/bin/python3
"""Convert a LAMMPS text dump (one snapshot, columns id type x y z) into
legacy VTK binary polydata.

Usage: lammps_dump_to_vtk.py DUMP OUTPUT.vtk

The output holds one VERTEX cell per atom (so ParaView shows the points
without a glyph filter) and three point arrays:
  type    int    LAMMPS atom type (the active scalars)
  radius  float  sphere radius in LJ sigma units, from the type (RADIUS_BY_TYPE)
  id      int    LAMMPS atom id
Legacy .vtk is used because Debian 12's VTK fails on XML files with
appended data (see SETUP.md). Run with Debian's /usr/bin/python3 (numpy).
"""

import sys

import numpy as np

# Half of each type's LJ sigma (lammps_melt.in: sigma_11 = 1.0, sigma_22 = 0.8),
# i.e. the contact radius of two like atoms.
RADIUS_BY_TYPE = {1: 0.5, 2: 0.4}


def read_dump(path):
    """Return (ids, types, xyz, box) of the first snapshot in a text dump."""
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
    col = {name: i for i, name in enumerate(columns)}
    for name in ("id", "type", "x", "y", "z"):
        if name not in col:
            raise ValueError(f"{path}: column '{name}' missing (have {columns})")
    ids = table[:, col["id"]].astype(np.int32)
    types = table[:, col["type"]].astype(np.int32)
    xyz = table[:, [col["x"], col["y"], col["z"]]].astype(np.float32)
    return ids, types, xyz, box


def write_vtk(path, ids, types, xyz, title):
    """Write legacy VTK 3.0 binary polydata (big-endian, as the format requires)."""
    n = len(ids)
    unknown = sorted(set(np.unique(types).tolist()) - set(RADIUS_BY_TYPE))
    if unknown:
        raise ValueError(f"no radius defined for atom types {unknown}")
    radius = np.zeros(n, dtype=np.float32)
    for t, r in RADIUS_BY_TYPE.items():
        radius[types == t] = r
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
        for name, values, vtk_type, dtype in (("type", types, "int", ">i4"),
                                              ("radius", radius, "float", ">f4"),
                                              ("id", ids, "int", ">i4")):
            text(f"SCALARS {name} {vtk_type} 1\nLOOKUP_TABLE default\n")
            f.write(values.astype(dtype).tobytes())
            text("\n")


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    ids, types, xyz, box = read_dump(argv[1])
    if not np.all(np.isfinite(xyz)):
        sys.exit(f"{argv[1]}: non-finite coordinates")
    box_text = " ".join(f"[{lo:g},{hi:g}]" for lo, hi in box)
    write_vtk(argv[2], ids, types, xyz,
              f"LAMMPS binary LJ melt, {len(ids)} atoms, box {box_text}, sigma units")
    # One summary line; lammps_melt.sh copies it into the provenance file.
    counts = np.bincount(types)
    print(f"{len(ids)} atoms, per type: " +
          ", ".join(f"{t}: {counts[t]}" for t in range(1, len(counts))))


if __name__ == "__main__":
    main(sys.argv)
