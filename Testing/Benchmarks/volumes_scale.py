#!/usr/bin/python3
"""How the volume renderers grow with their input: RBF Volume on Plummer spheres (10M, 30M,
100M particles), SPH Volume on the bundled PySPH dam break refined (9.4M, 31.6M, 99.7M
particles), SPH Fluid on the same (9.4M, 31.6M), Z-Sweep on the wavelet tetrahedralized (1M, 5M, 10M tetrahedra) and
on warped hexahedra of the wavelet (1M, 5M, 10M, native cells). Each method and size runs
twice, each time in a process of its own (views: RBF far and close, SPH Volume outside, SPH
Fluid outside and surface, Z-Sweep far and close on tetrahedra, far on hexahedra):
  vtk  raymappers-bench (the VTK mapper at its defaults, --no-reference, its views);
  pv   pvpython representation_frame.py (the ParaView representation at its defaults, the
       camera reset; Z-Sweep's hexahedra there are the unwarped voxels of Clean to Grid).
Per process: build_ms and render_ms (the bench's medians; for pv the first still render,
which builds, and the median of the renders after it), its peak resident memory
(/usr/bin/time) and that peak less the peak of a process that only reads the data and
opens a window (the bench with no method; pvpython with the Outline representation): the
bytes the method adds per item, against the input's own bytes per item (for particles, the
file's points and float arrays; for cells, the connectivity and offsets as vtkIdType, the
types, the float points and the float scalars of the grid divided by its cells). pv's
build_ms is the first render less the median of the later ones, pv_phases_ms the
mapper's phases in the last render (its statistics property).

The data: build/data/plummer_*.vtk (Data/Generators/plummer_sphere.sh) and
build/data/dam_break_coarse_00674_refinedK.vtk (Data/Generators/refine_particles.py on the
bundled PySPH frame Data/dam_break_coarse_00674.vtk, 9,360 particles, K = 10, 15, 22),
generated once and then kept.

Writes CSV (the bench's columns and path, peak_mb, baseline_mb, added_mb, bytes_per_item,
input_bytes_per_item) and a log-log plot of build time, frame time and added memory.

usage (from the source root; needs a build and Xvfb; 100M needs about 20 GB of memory):
  Testing/Benchmarks/volumes_scale.py [--build build] [--methods rbf sph fluid zsweep
      zsweep-hex] [--paths vtk pv] [--repeat 1] [--csv OUT.csv] [--plot OUT.png]
      [--sizes N ...] (the method's sizes: particles, K of the refinement, cells)
  Testing/Benchmarks/volumes_scale.py --replot OUT.csv --plot OUT.png (the plot again)
"""
import csv
import os
import subprocess
import sys
import tempfile

from scale_runs import (SOURCE, bench, label, legacy_input_bytes, loglog, representation,
                        scale_arguments, write_csv)

# method: (bench suite, --only, views, ParaView representation, data kind, default sizes)
METHODS = {
    "rbf": ("rbf", ":rbf:default$", ["far", "close"], "RBF Volume", "plummer",
            [10000000, 30000000, 100000000]),
    "sph": ("sph", ":sph-raycast:default$", ["outside"], "SPH Volume", "refined",
            [10, 15, 22]),
    "fluid": ("sph", ":sph-voxel:", ["outside", "surface"], "SPH Fluid", "refined", [10, 15]),
    "zsweep": ("zsweep", ":zsweep:exact$", ["far", "close"], "Z-Sweep Volume", "wavelet",
               [1000000, 5000000, 10000000]),
    "zsweep-hex": ("zsweep", ":zsweep:native-cells;exact$", ["far"],
                   "Z-Sweep Volume", "hex-wavelet", [1000000, 5000000, 10000000]),
}
COARSE = os.path.join(SOURCE, "Data", "dam_break_coarse_00674.vtk")


def data_for(build, kind, size):
    """(bench --data, pvpython --data, legacy file or None) of one size."""
    folder = os.path.join(build, "data")
    os.makedirs(folder, exist_ok=True)
    if kind == "plummer":
        path = os.path.join(folder, f"plummer_{label(size)}.vtk")
        subprocess.run(["bash", os.path.join(SOURCE, "Data/Generators/plummer_sphere.sh"), path,
                        str(size)], check=True)
        return path, path, path
    if kind == "refined":
        path = os.path.join(folder, f"{os.path.basename(COARSE)[:-4]}_refined{size}.vtk")
        subprocess.run(["/usr/bin/python3",
                        os.path.join(SOURCE, "Data/Generators/refine_particles.py"), COARSE, path,
                        str(size)], check=True)
        return path, path, path
    if kind == "wavelet":
        return f"wavelet:{size}", f"wavelet:{size}", None
    return f"hex-wavelet:{size}", f"image-wavelet:{size}", None


def grid_input_bytes(kind, cells):
    """The grid's own bytes per cell: vtkIdType connectivity and offset, the cell type's
    byte, and float points (3 x 4 B) with a float scalar (4 B) per point, over the cells."""
    if kind == "wavelet":  # 5 tetrahedra a voxel, a point a voxel
        return 8 * 4 + 8 + 1 + 16.0 / 5
    return 8 * 8 + 8 + 1 + 16.0  # hexahedra: a point a cell


def vtk_rows(build, method, size, images, repeat):
    suite, only, views, _, kind, _ = METHODS[method]
    data, _, path = data_for(build, kind, size)
    _, baseline = bench(build, suite, data, "nothing-at-all", images, repeat=1, views=views)
    rows, peak = bench(build, suite, data, only, images, repeat=repeat, views=views)
    for r in rows:
        r.update(path="vtk", dataset=r["dataset"])
    return rows, peak, baseline, path


def pv_rows(build, method, size, images, repeat):
    suite, _, _, name, kind, _ = METHODS[method]
    _, data, path = data_for(build, kind, size)
    args = ["--data", data, "--size", "1024", "1024", "--repeat", str(repeat)]
    base, baseline = representation(build, ["--representation", "Outline"] + args)
    png = os.path.join(images, f"pv-{method}-{size}.png")
    got, peak = representation(build, ["--representation", name, "--output", png] + args)
    items = got["points"] if kind in ("plummer", "refined") else got["cells"]
    row = {"suite": suite, "dataset": f"{os.path.basename(path)[:-4] if path else data}-reset",
           "method": name, "setting": "default", "width": 1024, "height": 1024, "items": items,
           "build_ms": f"{1000 * (got['first_render_s'] - got['median_render_s']):.1f}",
           "render_ms": f"{1000 * got['median_render_s']:.1f}", "path": "pv",
           "first_render_ms": f"{1000 * got['first_render_s']:.1f}",
           "pv_phases_ms": phases(got.get("last_frame_statistics", {}))}
    return [row], peak, baseline, path


def phases(statistics):
    """The mapper's phases of a render as "name=ms;..." (the representation's statistics)."""
    return ";".join(f"{k}={v:.1f}" for k, v in statistics.get("phase", {}).items())


def main(argv):
    parser = scale_arguments(__doc__, "volumes_scale", repeat=1)
    parser.add_argument("--methods", nargs="+", default=list(METHODS), choices=list(METHODS))
    parser.add_argument("--paths", nargs="+", default=["vtk", "pv"], choices=["vtk", "pv"])
    parser.add_argument("--sizes", type=int, nargs="+")
    parser.add_argument("--replot", metavar="CSV",
                        help="no runs: the plot of a CSV this script wrote")
    args = parser.parse_args(argv)
    if args.replot:
        with open(args.replot, newline="") as f:
            plot(list(csv.DictReader(f)), args.plot)
        print(f"wrote {args.plot}")
        return 0
    images = tempfile.mkdtemp(prefix="volumes_scale_")
    rows = []
    for method in args.methods:
        kind = METHODS[method][4]
        for size in args.sizes or METHODS[method][5]:
            for path in args.paths:
                run = vtk_rows if path == "vtk" else pv_rows
                try:
                    found, peak, baseline, legacy = run(args.build, method, size, images,
                                                        args.repeat)
                except RuntimeError as failed:  # (a process that failed: said, the rest run)
                    print(f"{method} {path} {size}: {failed}", flush=True)
                    continue
                added = max(0.0, peak - baseline)
                for r in found:
                    n = int(r["items"])
                    per_input = legacy_input_bytes(legacy) if legacy else grid_input_bytes(
                        kind, n)
                    r.update(scale_method=method, peak_mb=f"{peak:.1f}",
                             baseline_mb=f"{baseline:.1f}", added_mb=f"{added:.1f}",
                             bytes_per_item=f"{added * 1048576.0 / n:.1f}",
                             input_bytes_per_item=f"{per_input:.1f}")
                    rows.append(r)
                    print(f"{method} {path} {r['dataset']}: {n} items, build "
                          f"{float(r['build_ms']):.0f} ms, frame {float(r['render_ms']):.0f} ms,"
                          f" peak {peak:.0f} MB (read alone {baseline:.0f} MB): "
                          f"{added * 1048576.0 / n:.1f} B per item against the input's "
                          f"{per_input:.1f} B", flush=True)
                write_csv(rows, args.csv)  # after every run: a long run's rows are kept
    plot(rows, args.plot)
    print(f"wrote {args.csv} and {args.plot}; images in {images}")


def plot(rows, path):
    """The log-log plot of build time, frame time and added memory, a line per method, path
    and view."""
    series = {}
    for r in rows:
        view = r["dataset"].rsplit("-", 1)[-1]
        series.setdefault(f"{r['scale_method']} {r['path']} {view}", []).append(r)
    loglog([("build_ms", "build (ms)"), ("render_ms", "frame at 1024x1024 (ms)"),
            ("added_mb", "added peak resident memory (MB)")], series, path,
           "particles or cells")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
