#!/usr/bin/python3
"""Convert one PySPH output file (.hdf5 or .npz) into legacy VTK binary
polydata holding the particles of one particle array (default: fluid).

Usage: pysph_to_vtk.py [--array NAME[,NAME...]] [--title TEXT] INPUT OUTPUT.vtk

The output holds float points (x y z as PySPH stores them, metres for the
dam break), one VERTEX cell per particle and these float point arrays:
  rho   density (kg/m^3; the active scalars)
  h     smoothing length as PySPH stores it (m); the kernel's support
        radius is radius_scale * h (2 h for PySPH's CubicSpline and
        WendlandQuintic)
  m     mass (kg)
  V     volume m / rho (m^3)
  p     pressure (Pa)
  vmag  speed sqrt(u^2 + v^2 + w^2) (m/s)
  u v w velocity components (m/s)
An array that PySPH did not write (the boundary arrays of the dam break have
no u v w) is left out, and so is everything that needs it. Points are in
PySPH's order for the array (which is not the gid order); several arrays
(--array boundary,obstacle) are written one after the other, with only the
properties that all of them have.
--title sets the file's title line; {n} in it becomes the particle count,
{t} the simulated time and {count} the iteration number.
The last line printed is a one-line summary (time, count, value ranges) that
pysph_dam_break.sh copies into the provenance file.
Legacy .vtk is used because Debian 12's VTK fails on XML files with
appended data (see SETUP.md). Run with Debian's /usr/bin/python3: it needs
numpy and PySPH (Debian package python3-pysph) to read the file.
"""

import argparse
import sys

import numpy as np

# (name in the VTK file, how to get it from a dict of PySPH arrays)
FIELDS = [
    ("rho", lambda a: a["rho"]),
    ("h", lambda a: a["h"]),
    ("m", lambda a: a["m"]),
    ("V", lambda a: a["m"] / a["rho"]),
    ("p", lambda a: a["p"]),
    ("vmag", lambda a: np.sqrt(a["u"] ** 2 + a["v"] ** 2 + a["w"] ** 2)),
    ("u", lambda a: a["u"]),
    ("v", lambda a: a["v"]),
    ("w", lambda a: a["w"]),
]


def read_pysph(path, names):
    """Return (solver_data, {property: float64 array}) of the particle arrays
    named (concatenated in that order; only properties that all of them
    have are kept)."""
    from pysph.solver.utils import load

    data = load(path)
    arrays = data["arrays"]
    parts = []
    for name in names:
        if name not in arrays:
            raise ValueError(f"{path}: no particle array '{name}' (have {sorted(arrays)})")
        pa = arrays[name]
        # A copy: pa.get() returns a view of memory that is freed with pa.
        parts.append({prop: np.array(pa.get(prop), dtype=np.float64, copy=True)
                      for prop in (pa.output_property_arrays or pa.properties.keys())})
    common = set.intersection(*(set(part) for part in parts))
    props = {prop: np.concatenate([part[prop] for part in parts]) for prop in common}
    for prop in ("x", "y", "z"):
        if prop not in props:
            raise ValueError(f"{path}: array(s) {names} have no '{prop}'")
    return data["solver_data"], props


def point_arrays(props):
    """[(name, float32 values)] of the FIELDS that the properties allow."""
    arrays = []
    for name, get in FIELDS:
        try:
            values = get(props)
        except KeyError:
            continue
        arrays.append((name, np.asarray(values, dtype=np.float32)))
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
        for name, values in arrays:
            text(f"SCALARS {name} float 1\nLOOKUP_TABLE default\n")
            f.write(values.astype(">f4").tobytes())
            text("\n")


def main(argv):
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--array", default="fluid",
                        help="particle array(s) to write, comma-separated")
    parser.add_argument("--title")
    parser.add_argument("input")
    parser.add_argument("output")
    args = parser.parse_args(argv[1:])

    names = args.array.split(",")
    solver_data, props = read_pysph(args.input, names)
    xyz = np.column_stack([props["x"], props["y"], props["z"]]).astype(np.float32)
    arrays = point_arrays(props)
    n = len(xyz)
    if n == 0:
        sys.exit(f"{args.input}: array '{args.array}' is empty")
    for name, values in [("xyz", xyz)] + arrays:
        if not np.all(np.isfinite(values)):
            sys.exit(f"{args.input}: non-finite values in {name}")
    t = float(solver_data.get("t", 0.0))
    count = int(solver_data.get("count", 0))
    title = args.title or "PySPH {n} particles, t = {t:.4f} s (iteration {count})"
    write_vtk(args.output, xyz, arrays, title.format(n=n, t=t, count=count))

    # One summary line; pysph_dam_break.sh copies it into the provenance file.
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    bounds = " ".join(f"{c} [{lo[i]:.4g}, {hi[i]:.4g}]" for i, c in enumerate("xyz"))
    ranges = ", ".join(f"{name} [{values.min():.4g}, {values.max():.4g}]"
                       for name, values in arrays)
    print(f"t = {t:.6g} s, iteration {count}, {n} {'+'.join(names)} particles; "
          f"bounds {bounds}; ranges {ranges}")


if __name__ == "__main__":
    main(sys.argv)
