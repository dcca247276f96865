"""What the scale scripts (spheres_scale.py, volumes_scale.py) share: one measured process
(a raymappers-bench suite or a pvpython representation frame) with its peak resident memory
from /usr/bin/time, the input's own bytes, image differences and the log-log plot."""
import argparse
import csv
import json
import os
import subprocess
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
XVFB = ["xvfb-run", "-a", "-s", "-screen 0 1920x1080x24 -noreset"]


def scale_arguments(description, name, repeat):
    """The options every scale run has: --build, --repeat, --csv NAME.csv, --plot NAME.png."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=os.path.join(SOURCE, "build"))
    parser.add_argument("--repeat", type=int, default=repeat)
    parser.add_argument("--csv", default=f"{name}.csv")
    parser.add_argument("--plot", default=f"{name}.png")
    return parser


def label(n):
    return f"{n // 1000000}M" if n % 1000000 == 0 else str(n)


def measured(cmd):
    """Run cmd under Xvfb and /usr/bin/time: (return code, stdout, peak resident MB)."""
    with tempfile.NamedTemporaryFile(suffix=".time") as t:
        done = subprocess.run(XVFB + ["/usr/bin/time", "-f", "%M", "-o", t.name] + cmd,
                              stdout=subprocess.PIPE, text=True)
        peak = int(open(t.name).read().split()[-1]) / 1024.0
    return done.returncode, done.stdout, peak


def bench(build, suite, data, only, images, size="1024x1024", repeat=3, views=()):
    """One raymappers-bench process running only `only` (no references) on `data`: its CSV
    rows (empty when no method ran: the read-alone baseline) and its peak resident MB."""
    with tempfile.NamedTemporaryFile(suffix=".csv") as out:
        cmd = [os.path.join(build, "bin", "raymappers-bench"), suite, "--data", data,
               "--size", size, "--repeat", str(repeat), "--no-reference", "--only", only,
               "--csv", out.name, "--images", images]
        for v in views:
            cmd += ["--view", v]
        code, _, peak = measured(cmd)
        # (the bench exits with 1 when no method ran: the baseline's case)
        if code not in (0, 1):
            raise RuntimeError(f"{' '.join(cmd)} failed ({code})")
        return list(csv.DictReader(open(out.name))), peak


def representation(build, script_args):
    """One pvpython process of representation_frame.py: its JSON line and peak resident MB."""
    plugin = os.path.join(build, "lib", "paraview-plugins", "RayMappers", "RayMappers.so")
    cmd = [os.path.join(build, "bin", "raymappers-env"), "pvpython",
           os.path.join(HERE, "representation_frame.py"), "--plugin", plugin] + script_args
    code, out, peak = measured(cmd)
    lines = [line for line in out.splitlines() if line.startswith("{")]
    if code != 0 or not lines:
        raise RuntimeError(f"{' '.join(cmd)} failed ({code})")
    return json.loads(lines[-1]), peak


def legacy_input_bytes(path):
    """The points and float point arrays of a legacy VTK particle file, per particle: 12 B
    of coordinates and 4 B per SCALARS section (grep counts them)."""
    out = subprocess.run(["grep", "-a", "-c", "^SCALARS .* float 1$", path],
                         capture_output=True, text=True)
    return 12 + 4 * int(out.stdout.strip() or 0)


def rmse(a, b):
    """Root mean square difference of two PNGs' RGB, 0..1 a channel (the bench's rmse)."""
    import matplotlib.image as mpimg
    x = mpimg.imread(a)[..., :3].astype(np.float64)
    y = mpimg.imread(b)[..., :3].astype(np.float64)
    return float(np.sqrt(np.mean((x - y) ** 2)))


def write_csv(rows, path):
    fields = []
    for r in rows:
        fields += [k for k in r if k not in fields]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)


def loglog(panels, series, path, xlabel):
    """One log-log panel per (key, title) of `panels`: each series (name -> rows with
    'items' and the key) a line, points with an empty or non-positive value left out; past
    the colour cycle's 10 colours the lines are dashed, then dotted, so no two look alike."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4.5))
    for (key, title), ax in zip(panels, np.atleast_1d(axes)):
        for k, (name, rows) in enumerate(series.items()):
            pts = sorted((int(r["items"]), float(r[key])) for r in rows
                         if r.get(key) not in (None, "") and float(r[key]) > 0)
            if pts:
                xs, ys = zip(*pts)
                ax.loglog(xs, ys, ("o-", "s--", "^:")[k // 10 % 3], color=f"C{k % 10}",
                          label=name)
        ax.set_xlabel(xlabel)
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
