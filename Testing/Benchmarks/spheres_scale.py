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

usage (from the source root; needs a build, Xvfb and about 12 GB of memory for 100M):
  Testing/Benchmarks/spheres_scale.py [--build build] [--sizes 1000000 10000000 100000000]
      [--repeat 3] [--csv OUT.csv] [--plot OUT.png]
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
XVFB = ["xvfb-run", "-a", "-s", "-screen 0 1920x1080x24 -noreset"]
METHODS = [("cgt", "default"), ("embree", "bvh=low")]


def label(n):
    return f"{n // 1000000}M" if n % 1000000 == 0 else str(n)


def generate(build, n):
    path = os.path.join(build, "data", f"plummer_{label(n)}.vtk")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    subprocess.run(["bash", os.path.join(SOURCE, "Data/Generators/plummer_sphere.sh"), path,
                    str(n)], check=True)
    return path


def input_bytes_per_sphere(path):
    """The points and float point arrays of the legacy VTK file, per particle: 12 B of
    coordinates and 4 B per SCALARS section (grep counts them)."""
    out = subprocess.run(["grep", "-a", "-c", "^SCALARS .* float 1$", path],
                         capture_output=True, text=True)
    return 12 + 4 * int(out.stdout.strip() or 0)


def run(build, data, only, repeat, images):
    """One bench process: its CSV row (None without a method) and its peak RSS in MB."""
    with tempfile.NamedTemporaryFile(suffix=".csv") as out, \
            tempfile.NamedTemporaryFile(suffix=".time") as t:
        cmd = XVFB + ["/usr/bin/time", "-f", "%M", "-o", t.name,
                      os.path.join(build, "bin", "raymappers-bench"), "spheres", "--data", data,
                      "--size", "1024x1024", "--repeat", str(repeat), "--no-reference",
                      "--only", only, "--csv", out.name, "--images", images]
        # (the bench exits with 1 when no method ran: the baseline's case)
        done = subprocess.run(cmd, stdout=subprocess.DEVNULL)
        if done.returncode not in (0, 1):
            raise RuntimeError(f"{' '.join(cmd)} failed ({done.returncode})")
        peak = int(open(t.name).read().split()[-1]) / 1024.0
        rows = list(csv.DictReader(open(out.name)))
        return (rows[0] if rows else None), peak


def rmse(a, b):
    import matplotlib.image as mpimg
    x = mpimg.imread(a)[..., :3].astype(np.float64)
    y = mpimg.imread(b)[..., :3].astype(np.float64)
    return float(np.sqrt(np.mean((x - y) ** 2)))


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for key, ax, title in (("build_ms", axes[0], "build (ms)"),
                           ("render_ms", axes[1], "frame at 1024x1024 (ms)"),
                           ("mem_mb", axes[2], "added peak resident memory (MB)")):
        for method, setting in METHODS:
            pts = [(int(r["items"]), float(r[key])) for r in rows
                   if r["method"] == method and r["setting"] == setting]
            if pts:
                xs, ys = zip(*sorted(pts))
                ax.loglog(xs, ys, "o-", label=f"{method} {setting}")
        ax.set_xlabel("spheres (Plummer)")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(SOURCE, "build"))
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000000, 10000000, 100000000])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--csv", default="spheres_scale.csv")
    parser.add_argument("--plot", default="spheres_scale.png")
    args = parser.parse_args(argv)
    images = tempfile.mkdtemp(prefix="spheres_scale_")
    rows = []
    for n in args.sizes:
        data = generate(args.build, n)
        per_input = input_bytes_per_sphere(data)
        _, baseline = run(args.build, data, "nothing-at-all", 1, images)
        pngs = {}
        for method, setting in METHODS:
            row, peak = run(args.build, data, f":{method}:{setting}", args.repeat, images)
            added = max(0.0, peak - baseline)
            row.update(suite="spheres-scale", mem_mb=f"{added:.1f}", peak_mb=f"{peak:.1f}",
                       baseline_mb=f"{baseline:.1f}",
                       bytes_per_sphere=f"{added * 1048576.0 / n:.1f}",
                       input_bytes_per_sphere=str(per_input))
            tag = setting.replace("=", "-")
            pngs[method] = os.path.join(images, f"spheres-{os.path.basename(data)[:-4]}-"
                                                f"{method}-{tag}.png")
            rows.append(row)
            print(f"{label(n)} {method} {setting}: build {float(row['build_ms']):.0f} ms, "
                  f"frame {float(row['render_ms']):.1f} ms, peak {peak:.0f} MB "
                  f"(read alone {baseline:.0f} MB): {added * 1048576.0 / n:.1f} B per sphere "
                  f"against the input's {per_input} B", flush=True)
        err = rmse(pngs["cgt"], pngs["embree"])
        for r in rows[-len(METHODS):]:
            r["rmse"] = f"{err:.6f}"
        print(f"{label(n)}: rmse cgt vs embree {err:.6f}", flush=True)
    fields = list(rows[0].keys())
    with open(args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    plot(rows, args.plot)
    print(f"wrote {args.csv} and {args.plot}")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
