#!/usr/bin/python3
"""How the spheres' accelerators grow with the number of spheres: the CGT defaults and
Embree's BVH (build quality low, the quality of a new time step) on Plummer spheres of
1M, 10M and 100M particles (Data/Generators/plummer_sphere.sh, generated once into the
build's data folder), each method in a process of its own.

Per size and method: build_ms and render_ms (raymappers-bench's median of --repeat frames at
1024x1024), the process's peak resident memory (/usr/bin/time), and that peak less the peak
of a process that only reads the data and opens the window (no method): the bytes the method
adds per sphere, against the input's own bytes per sphere (the file's points and point
arrays, 24 B for the Plummer files). The images of CGT and Embree are compared (rmse over
8-bit RGB, as the bench does).

Writes CSV (suite spheres-scale; the bench's columns, mem_mb the added peak, plus
peak_mb, baseline_mb, bytes_per_sphere, input_bytes_per_sphere) and a log-log plot of build
time, frame time and added memory against the number of spheres.

With --data FILE... the given files run instead of the Plummer spheres (the same columns,
each method in its own process): a build measured in a process where the other method ran
before is not the build a user gets (the CGT build of the 80,000-grain packing took a median
of 3.5 ms alone and 10 ms after Embree's in one raymappers-bench process).

usage (from the source root; needs a build, Xvfb and about 12 GB of memory for 100M):
  Testing/Benchmarks/spheres_scale.py [--build build] [--sizes 1000000 10000000 100000000]
      [--data FILE...] [--repeat 3] [--csv OUT.csv] [--plot OUT.png]
"""
import os
import subprocess
import sys
import tempfile

from scale_runs import (SOURCE, bench, label, legacy_input_bytes, loglog, rmse, scale_arguments,
                        write_csv)

METHODS = [("cgt", "default"), ("embree", "bvh=low")]


def generate(build, n):
    path = os.path.join(build, "data", f"plummer_{label(n)}.vtk")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    subprocess.run(["bash", os.path.join(SOURCE, "Data/Generators/plummer_sphere.sh"), path,
                    str(n)], check=True)
    return path


def main(argv):
    parser = scale_arguments(__doc__, "spheres_scale", repeat=3)
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000000, 10000000, 100000000])
    parser.add_argument("--data", nargs="+", default=[],
                        help="these particle files instead of the generated Plummer spheres")
    args = parser.parse_args(argv)
    images = tempfile.mkdtemp(prefix="spheres_scale_")
    rows = []
    for data in args.data or [generate(args.build, n) for n in args.sizes]:
        per_input = legacy_input_bytes(data)
        _, baseline = bench(args.build, "spheres", data, "nothing-at-all", images, repeat=1)
        pngs = {}
        for method, setting in METHODS:
            found, peak = bench(args.build, "spheres", data, f":{method}:{setting}", images,
                                repeat=args.repeat)
            row = found[0]
            n = int(row["items"])
            added = max(0.0, peak - baseline)
            row.update(suite="spheres-scale", mem_mb=f"{added:.1f}", peak_mb=f"{peak:.1f}",
                       baseline_mb=f"{baseline:.1f}",
                       bytes_per_sphere=f"{added * 1048576.0 / n:.1f}",
                       input_bytes_per_sphere=str(per_input))
            tag = setting.replace("=", "-")
            pngs[method] = os.path.join(images, f"spheres-{os.path.basename(data)[:-4]}-"
                                                f"{method}-{tag}.png")
            rows.append(row)
            print(f"{os.path.basename(data)} {method} {setting}: build {float(row['build_ms']):.0f} ms, "
                  f"frame {float(row['render_ms']):.1f} ms, peak {peak:.0f} MB "
                  f"(read alone {baseline:.0f} MB): {added * 1048576.0 / n:.1f} B per sphere "
                  f"against the input's {per_input} B", flush=True)
        err = rmse(pngs["cgt"], pngs["embree"])
        for r in rows[-len(METHODS):]:
            r["rmse"] = f"{err:.6f}"
        print(f"{os.path.basename(data)}: rmse cgt vs embree {err:.6f}", flush=True)
    write_csv(rows, args.csv)
    loglog([("build_ms", "build (ms)"), ("render_ms", "frame at 1024x1024 (ms)"),
            ("mem_mb", "added peak resident memory (MB)")],
           {f"{m} {s}": [r for r in rows if (r["method"], r["setting"]) == (m, s)]
            for m, s in METHODS}, args.plot, "spheres (given files)" if args.data else "spheres (Plummer)")
    print(f"wrote {args.csv} and {args.plot}")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
