#!/usr/bin/python3
"""Plot a RayMappers benchmark CSV as PNG charts.

Usage: plot_bench.py CSV OUTDIR

CSV columns (exactly, in this order):
  suite,dataset,method,setting,width,height,items,build_ms,render_ms,rmse,max_err,mem_mb
rmse and max_err may be empty (no reference image for that row).

For each (suite, dataset) it writes
  <suite>_<dataset>_time.png   build_ms and render_ms side by side, one bar
                               pair per method + setting
  <suite>_<dataset>_error.png  rmse versus render_ms, one line per method,
                               points labelled by setting; only for methods
                               with at least two settings that have an rmse
Repeated rows (same method, setting and image size) are reduced to their
median, so a CSV with several timing runs plots as one bar.
Run with Debian's /usr/bin/python3 (matplotlib).
"""

import csv
import os
import re
import statistics
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")  # files only: no display on the benchmark machines
import matplotlib.pyplot as plt  # noqa: E402 (must follow matplotlib.use)

COLUMNS = ["suite", "dataset", "method", "setting", "width", "height", "items",
           "build_ms", "render_ms", "rmse", "max_err", "mem_mb"]

# A quantity spanning more than this factor is drawn on a log axis.
LOG_RATIO = 10.0


def read_rows(path):
    """Rows as dicts with numbers parsed; empty rmse/max_err become None."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = [h.strip() for h in next(reader, [])]
        if header != COLUMNS:
            raise ValueError(f"{path}: header must be {','.join(COLUMNS)}, got {','.join(header)}")
        rows = []
        for lineno, values in enumerate(reader, start=2):
            if not values or all(not v.strip() for v in values):
                continue
            if len(values) != len(COLUMNS):
                raise ValueError(f"{path}:{lineno}: {len(values)} fields, expected {len(COLUMNS)}")
            row = dict(zip(COLUMNS, (v.strip() for v in values)))
            for key in ("width", "height", "items"):
                row[key] = int(row[key])
            for key in ("build_ms", "render_ms", "rmse", "max_err", "mem_mb"):
                row[key] = float(row[key]) if row[key] != "" else None
            rows.append(row)
    return rows


def median_or_none(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def reduce_repeats(rows):
    """Merge rows with the same method, setting and size into their medians."""
    groups = OrderedDict()
    for r in rows:
        groups.setdefault((r["method"], r["setting"], r["width"], r["height"]), []).append(r)
    merged = []
    for (method, setting, width, height), runs in groups.items():
        merged.append({"method": method, "setting": setting, "width": width, "height": height,
                       **{k: median_or_none([r[k] for r in runs])
                          for k in ("build_ms", "render_ms", "rmse", "max_err")}})
    return merged


def wants_log(values):
    """Log scale when all values are positive and span more than LOG_RATIO."""
    values = [v for v in values if v is not None]
    return bool(values) and min(values) > 0 and max(values) / min(values) > LOG_RATIO


def file_stem(suite, dataset):
    return re.sub(r"[^A-Za-z0-9._-]+", "_", f"{suite}_{dataset}")


def plot_times(suite, dataset, rows, path):
    """Horizontal bars: render_ms and build_ms side by side per method + setting."""
    several_sizes = len({(r["width"], r["height"]) for r in rows}) > 1
    labels = []
    for r in rows:
        label = f"{r['method']} {r['setting']}".strip()
        if several_sizes:
            label += f" {r['width']}x{r['height']}"
        labels.append(label)
    render = [r["render_ms"] or 0.0 for r in rows]
    build = [r["build_ms"] or 0.0 for r in rows]

    n = len(rows)
    fig, ax = plt.subplots(figsize=(9, 1.0 + 0.45 * n))
    pos = list(range(n))
    height = 0.4
    ax.barh([p - height / 2 for p in pos], render, height, label="render_ms", color="tab:blue")
    ax.barh([p + height / 2 for p in pos], build, height, label="build_ms", color="tab:orange")
    for p, value in zip(pos, render):
        text = f"{value:.0f}" if value >= 100 else f"{value:.3g}"
        ax.annotate(text, (value, p - height / 2), xytext=(3, 0),
                    textcoords="offset points", va="center", fontsize=7)
    ax.margins(x=0.08)  # room for the value labels at the longest bar
    ax.set_yticks(pos)
    ax.set_yticklabels(labels, fontsize=8)
    ax.invert_yaxis()  # first CSV row on top
    if wants_log([v for v in render + build if v > 0]):
        ax.set_xscale("log")  # zero-valued bars are simply not drawn
    ax.set_xlabel("time [ms]")
    size = "" if several_sizes else f", {rows[0]['width']}x{rows[0]['height']}"
    ax.set_title(f"{suite} / {dataset}{size}")
    ax.legend(loc="best", fontsize=8)
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_errors(suite, dataset, rows, path):
    """rmse against render_ms, one line per method and swept parameter (the
    setting's first name, e.g. "ao" in "ao=16": a sweep may have its own
    reference); methods with a single measured setting (e.g. the alternatives a
    user has today) appear as lone markers for comparison. False if nothing has
    several settings."""
    by_method = OrderedDict()
    for r in rows:
        if r["rmse"] is not None and r["render_ms"] is not None:
            swept = r["setting"].split("=", 1)[0] if "=" in r["setting"] else ""
            key = f"{r['method']} ({swept})" if swept else r["method"]
            by_method.setdefault(key, []).append(r)
    if all(len(rs) < 2 for rs in by_method.values()):
        return False

    several_sizes = len({(r["width"], r["height"]) for r in rows}) > 1
    fig, ax = plt.subplots(figsize=(8, 6))
    for method, rs in by_method.items():
        rs = sorted(rs, key=lambda r: r["render_ms"])
        xs = [r["render_ms"] for r in rs]
        ys = [r["rmse"] for r in rs]
        single = len(rs) == 1
        line, = ax.plot(xs, ys, marker="s" if single else "o",
                        linestyle="none" if single else "-", label=method)
        for r, x, y in zip(rs, xs, ys):
            label = r["setting"] + (f" {r['width']}x{r['height']}" if several_sizes else "")
            ax.annotate(label, (x, y), xytext=(4, 4), textcoords="offset points",
                        fontsize=7, color=line.get_color())
    every = [r for rs in by_method.values() for r in rs]
    if wants_log([r["render_ms"] for r in every]):
        ax.set_xscale("log")
    if wants_log([r["rmse"] for r in every]):
        ax.set_yscale("log")
    ax.set_xlabel("render time [ms]")
    ax.set_ylabel("RMSE against reference")
    ax.set_title(f"{suite} / {dataset}: error versus time")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    try:
        rows = read_rows(argv[1])
    except (OSError, ValueError) as e:  # a clear message, not a traceback
        sys.exit(f"plot_bench.py: {e}")
    os.makedirs(argv[2], exist_ok=True)

    groups = OrderedDict()
    for r in rows:
        groups.setdefault((r["suite"], r["dataset"]), []).append(r)
    for (suite, dataset), group in groups.items():
        merged = reduce_repeats(group)
        stem = os.path.join(argv[2], file_stem(suite, dataset))
        plot_times(suite, dataset, merged, stem + "_time.png")
        print(stem + "_time.png")
        if plot_errors(suite, dataset, merged, stem + "_error.png"):
            print(stem + "_error.png")


if __name__ == "__main__":
    main(sys.argv)
