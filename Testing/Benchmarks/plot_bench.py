#!/usr/bin/python3
"""Plot a RayMappers benchmark CSV as PNG charts.

Usage: plot_bench.py CSV [CSV ...] OUTDIR   (several CSVs of one suite: their rows together)

CSV columns (exactly, in this order, then any extra numeric columns, e.g. the
sph suite's frame_ms, resample_ms, ..., kernel_evaluations):
  suite,dataset,method,setting,width,height,items,build_ms,render_ms,rmse,max_err,mem_mb
rmse, max_err and extra columns may be empty (no reference image for that row).

For each (suite, dataset) it writes
  <suite>_<dataset>_time.png   build_ms and render_ms side by side, one bar
                               pair per method + setting
  <suite>_<dataset>_error.png  rmse versus render_ms, one line per method,
                               points labelled by setting; only for methods
                               with at least two settings that have an rmse;
                               methods named STEM-NUMBER (sph-step-2,
                               sph-step-4) are one line, STEM
  <suite>_<dataset>_error_frame.png
                               the same against frame_ms (a new time step:
                               resample or rebuild plus a frame), when the CSV
                               has that column
  <suite>_<dataset>_effects.png
                               render_ms and kernel counters of sph-raycast
                               and its effects (sph-unnormalized, sph-pseudo,
                               sph-gradient, sph-contour), when present
  <suite>_<dataset>_voxel_error.png
                               the fluid rows (sph-voxel*, sph-contour-surface-
                               grid*; the plots above leave them out): the
                               front surface's mean depth error (depth_mean_abs),
                               its normals' mean angle error (normal_deg) and
                               the image's rmse against frame_ms (a new
                               time step's first image), one line per sweep
                               (angle, spans, smooth; the contour route over
                               its grids); on the synthetic layers the
                               transmittance's rmse against the exact one
  <suite>_<dataset>_voxel_stages.png
                               the fluid rows' frames split into the mapper's
                               stages (splat_ms ... draw_ms)
  <suite>_voxel_stages.png     sph-voxel, -translucent and -noculling of every
                               dataset: the stage table (Zirr 2015, table 2)
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


# The sph suite's effects, in the order of the effects chart (the first is the baseline).
EFFECTS = ["sph-raycast", "sph-unnormalized", "sph-pseudo", "sph-gradient", "sph-contour"]
COUNTERS = ["kernel_evaluations", "weight_sums", "gradient_evaluations"]

# The fluid half of the sph suite (SPHVoxelSuite.cxx): its stages, in frame order, and the
# sweeps of its error plot (method stem, label).
STAGES = ["splat_ms", "compress_ms", "connect_ms", "filter_ms", "normals_ms", "ao_ms",
          "translucent_ms", "refract_ms", "draw_ms"]
# The fluid's lone rows keep one colour in every panel.
LONE_COLORS = {"sph-voxel": "tab:red", "sph-voxel-translucent": "tab:purple",
               "sph-voxel-noculling": "tab:brown", "sph-voxel-reference": "black"}
VOXEL_SWEEPS = [("sph-voxel-angle", "angle resolution [deg]"),
                ("sph-voxel-spans", "spans kept"),
                ("sph-voxel-smooth", "smoothing iterations"),
                ("sph-contour-surface-grid", "contour route: grid")]


def is_voxel(method):
    """A row of the fluid half: drawn by the voxel plots only."""
    return method.startswith("sph-voxel") or method.startswith("sph-contour-surface")


def read_rows(path):
    """Rows as dicts with numbers parsed; empty rmse/max_err/extra values become None."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = [h.strip() for h in next(reader, [])]
        if header[:len(COLUMNS)] != COLUMNS:
            raise ValueError(f"{path}: header must start with {','.join(COLUMNS)}, "
                             f"got {','.join(header)}")
        extra = header[len(COLUMNS):]
        rows = []
        for lineno, values in enumerate(reader, start=2):
            if not values or all(not v.strip() for v in values):
                continue
            if len(values) != len(header):
                raise ValueError(f"{path}:{lineno}: {len(values)} fields, expected {len(header)}")
            row = dict(zip(header, (v.strip() for v in values)))
            for key in ("width", "height", "items"):
                row[key] = int(row[key])
            for key in ["build_ms", "render_ms", "rmse", "max_err", "mem_mb"] + extra:
                row[key] = float(row[key]) if row[key] != "" else None
            rows.append(row)
    return rows, extra


def median_or_none(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def reduce_repeats(rows, extra=()):
    """Merge rows with the same method, setting and size into their medians."""
    groups = OrderedDict()
    for r in rows:
        groups.setdefault((r["method"], r["setting"], r["width"], r["height"]), []).append(r)
    merged = []
    for (method, setting, width, height), runs in groups.items():
        merged.append({"method": method, "setting": setting, "width": width, "height": height,
                       **{k: median_or_none([r[k] for r in runs])
                          for k in ("build_ms", "render_ms", "rmse", "max_err", *extra)}})
    return merged


def sweep_of(method):
    """(stem, value) of a method named STEM-NUMBER (sph-step-2 -> sph-step, 2), else None."""
    m = re.fullmatch(r"(.+)-([0-9]+(?:\.[0-9]+)?)", method)
    return (m.group(1), m.group(2)) if m else None


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


def plot_errors(suite, dataset, rows, path, x="render_ms", xlabel="render time [ms]"):
    """rmse against x (render_ms), one line per method and swept parameter (the
    setting's first name, e.g. "ao" in "ao=16": a sweep may have its own
    reference; methods named STEM-NUMBER are one sweep, STEM); methods with a
    single measured setting (e.g. the alternatives a user has today) appear as
    lone markers for comparison. False if nothing has several settings."""
    by_method = OrderedDict()
    for r in rows:
        if r["method"] in EFFECTS[1:]:
            continue  # compared with their own effect's reference: the effects chart
        if r["rmse"] is not None and r.get(x) is not None:
            swept = r["setting"].split("=", 1)[0] if "=" in r["setting"] else ""
            sweep = sweep_of(r["method"])
            if sweep:
                key = sweep[0]
            else:
                key = f"{r['method']} ({swept})" if swept else r["method"]
            by_method.setdefault(key, []).append(r)
    if all(len(rs) < 2 for rs in by_method.values()):
        return False

    several_sizes = len({(r["width"], r["height"]) for r in rows}) > 1
    fig, ax = plt.subplots(figsize=(8, 6))
    markers = "osD^v<>px*h"
    for index, (method, rs) in enumerate(by_method.items()):
        rs = sorted(rs, key=lambda r: r[x])
        xs = [r[x] for r in rs]
        ys = [r["rmse"] for r in rs]
        single = len(rs) == 1
        # A sweep that does not change the picture (tile, slab): its times only.
        same = not single and max(ys) <= 1.03 * min(ys)
        # Lone markers (a default, an alternative) on top of the sweeps that pass by them.
        line, = ax.plot(xs, ys, marker="s" if single else markers[index % len(markers)],
                        linestyle="none" if single else "-",
                        markersize=10 if single else 6, zorder=10 if single else 2,
                        markeredgecolor="black" if single else None,
                        label=method + (" (same image, labels omitted)" if same else ""))
        if same:
            continue
        for r, px, py in zip(rs, xs, ys):
            label = r["setting"] + (f" {r['width']}x{r['height']}" if several_sizes else "")
            ax.annotate(label, (px, py), xytext=(4, 4), textcoords="offset points",
                        fontsize=7, color=line.get_color())
    every = [r for rs in by_method.values() for r in rs]
    if wants_log([r[x] for r in every]):
        ax.set_xscale("log")
    if wants_log([r["rmse"] for r in every]):
        ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("RMSE against reference")
    ax.set_title(f"{suite} / {dataset}: error versus time")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def plot_effects(suite, dataset, rows, path):
    """The effects of the sph suite side by side (Limper 2012, table 4.4): render_ms
    (with the ray casting phase, raycast_ms, when known) and the kernel counters per
    frame, each effect against its own reference (the rmse in the labels). False if
    the rows hold fewer than two of EFFECTS."""
    by_method = {r["method"]: r for r in rows if r["method"] in EFFECTS}
    chosen = [by_method[m] for m in EFFECTS if m in by_method]
    if len(chosen) < 2:
        return False
    labels = []
    for r in chosen:
        label = r["method"]
        if r["rmse"] is not None:
            label += f"\nrmse {255 * r['rmse']:.2f}/255"
        labels.append(label)
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 2.4 + 0.7 * len(chosen)))
    pos = list(range(len(chosen)))
    base = chosen[0]["render_ms"] if chosen[0]["method"] == EFFECTS[0] else None
    render = [r["render_ms"] or 0.0 for r in chosen]
    left.barh(pos, render, 0.6, color="tab:blue", label="render_ms (frame)")
    raycast = [r.get("raycast_ms") for r in chosen]
    if all(v is not None for v in raycast):
        left.barh(pos, raycast, 0.3, color="tab:cyan", label="raycast_ms (of the frame)")
    for p, value, inner in zip(pos, render, raycast):
        text = f"{value:.0f} ms"
        if base:
            text += f" ({value / base:.2f}x)"
        left.annotate(text, (max(value, inner or 0.0), p), xytext=(3, 0),
                      textcoords="offset points", va="center", fontsize=8)
    left.margins(x=0.35)
    left.set_yticks(pos)
    left.set_yticklabels(labels, fontsize=8)
    left.invert_yaxis()
    left.set_xlabel("time [ms]")
    left.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize=8)
    left.grid(axis="x", alpha=0.3)
    height = 0.8 / len(COUNTERS)
    for k, counter in enumerate(COUNTERS):
        values = [(r.get(counter) or 0.0) / 1e6 for r in chosen]
        offsets = [p - 0.4 + height * (k + 0.5) for p in pos]
        right.barh(offsets, values, height, label=counter)
    right.set_yticks(pos)
    right.set_yticklabels([r["method"] for r in chosen], fontsize=8)
    right.invert_yaxis()
    right.set_xlabel("per frame [millions] (SIMD lanes: 16 per row chunk)")
    right.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=3, fontsize=8)
    right.grid(axis="x", alpha=0.3)
    fig.suptitle(f"{suite} / {dataset}, {chosen[0]['width']}x{chosen[0]['height']}: "
                 "effects, each alone (error against the same effect's reference)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def voxel_sweeps(rows):
    """The rows of each sweep (VOXEL_SWEEPS order) with their swept value, sorted by it,
    and the lone rows (sph-voxel, sph-voxel-translucent, the reference)."""
    sweeps = OrderedDict()
    lone = []
    for r in rows:
        for stem, label in VOXEL_SWEEPS:
            m = re.fullmatch(re.escape(stem) + r"-?([0-9]+(?:\.[0-9]+)?)", r["method"])
            if m:
                sweeps.setdefault(label, []).append((float(m.group(1)), r))
                break
        else:
            lone.append(r)
    order = [label for _, label in VOXEL_SWEEPS]
    return (OrderedDict((k, sorted(sweeps[k], key=lambda vr: vr[0]))
                        for k in order if k in sweeps), lone)


def plot_voxel_errors(suite, dataset, rows, path):
    """Error against frame_ms for the fluid rows: the front surface's depth error
    (left) and the image's rmse (right), one line per sweep, points labelled by
    the swept value. False if no row has an error."""
    sweeps, lone = voxel_sweeps(rows)
    panels = [("depth_mean_abs", "front surface: mean |depth - reference| [world units]"),
              ("normal_deg", "front surface: mean angle to the reference's normal [deg]"),
              ("rmse", "image RMSE against the reference (layers: exact transmittance)")]
    panels = [(key, label) for key, label in panels
              if any(r.get(key) is not None and r.get("frame_ms") is not None for r in rows)]
    if not panels:
        return False
    fig, axes = plt.subplots(1, len(panels), figsize=(6.5 * len(panels), 6), squeeze=False)
    markers = "osD^v<>"
    for ax, (key, ylabel) in zip(axes[0], panels):
        drawn = []
        for index, (label, values) in enumerate(sweeps.items()):
            pts = [(r["frame_ms"], r[key], v) for v, r in values
                   if r.get(key) is not None and r.get("frame_ms") is not None]
            if not pts:
                continue
            xs, ys, vs = zip(*pts)
            line, = ax.plot(xs, ys, marker=markers[index % len(markers)], label=label)
            for x, y, v in pts:
                ax.annotate(f"{v:g}", (x, y), xytext=(4, 4), textcoords="offset points",
                            fontsize=7, color=line.get_color())
            drawn += pts
        for r in lone:
            if r.get(key) is None or r.get("frame_ms") is None:
                continue
            ax.plot([r["frame_ms"]], [r[key]], marker="s", markersize=10, linestyle="none",
                    markeredgecolor="black", zorder=10, label=r["method"],
                    color=LONE_COLORS.get(r["method"], "grey"))
            drawn.append((r["frame_ms"], r[key], None))
        if not drawn:
            continue
        if wants_log([x for x, _, _ in drawn]):
            ax.set_xscale("log")
        if wants_log([y for _, y, _ in drawn]):
            ax.set_yscale("log")
        else:
            ax.set_ylim(bottom=0)
        ax.set_xlabel("new time step's first image: rebuild + frame, or resample + "
                      "contour + frame [ms]", fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.suptitle(f"{suite} / {dataset}, {rows[0]['width']}x{rows[0]['height']}: "
                 "fluid rows, error versus time")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def stage_bars(ax, rows, labels):
    """Horizontal bars of rows split into STAGES, the frame's total at the end."""
    pos = list(range(len(rows)))
    left = [0.0] * len(rows)
    colors = plt.get_cmap("tab10")
    for k, stage in enumerate(STAGES):
        values = [r.get(stage) or 0.0 for r in rows]
        if not any(values):
            continue
        ax.barh(pos, values, 0.6, left=left, color=colors(k), label=stage[:-3])
        left = [a + b for a, b in zip(left, values)]
    for p, r, total in zip(pos, rows, left):
        ax.annotate(f"{total:.0f} ms (frame {r['render_ms']:.0f})", (total, p), xytext=(3, 0),
                    textcoords="offset points", va="center", fontsize=7)
    ax.margins(x=0.35)
    ax.set_yticks(pos)
    ax.set_yticklabels(labels, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("time per stage, median frame [ms]")
    ax.grid(axis="x", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside the bars


def plot_voxel_stages(suite, dataset, rows, path):
    """The stages of every fluid row of one dataset. False if none has them."""
    rows = [r for r in rows if r.get("splat_ms") is not None]
    if not rows:
        return False
    fig, ax = plt.subplots(figsize=(11, 1.6 + 0.32 * len(rows)))
    stage_bars(ax, rows, [f"{r['method']} {r['setting']}" for r in rows])
    ax.set_title(f"{suite} / {dataset}, {rows[0]['width']}x{rows[0]['height']}: stages")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def plot_stage_table(suite, rows, extra, path):
    """sph-voxel (refraction), sph-voxel-translucent and sph-voxel-noculling of every dataset and size: the
    stage table as bars. False if there are none."""
    chosen = [r for r in reduce_repeats_by_dataset(rows, extra)
              if r["method"] in ("sph-voxel", "sph-voxel-translucent", "sph-voxel-noculling")
              and r.get("splat_ms") is not None]
    if not chosen:
        return False
    labels = [f"{r['dataset']} {r['width']}x{r['height']}\n{r['method']} "
              f"({r['items']:,} particles, peak {r['mem_mb']:.0f} MB)" for r in chosen]
    fig, ax = plt.subplots(figsize=(12, 1.2 + 0.55 * len(chosen)))
    stage_bars(ax, chosen, labels)
    ax.set_title(f"{suite}: vtkSPHFluidMapper's stages (cf. Zirr 2015, table 2)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def reduce_repeats_by_dataset(rows, extra):
    """reduce_repeats per dataset, the dataset, items and mem_mb kept."""
    out = []
    for dataset in OrderedDict((r["dataset"], None) for r in rows):
        group = [r for r in rows if r["dataset"] == dataset]
        for merged in reduce_repeats(group, tuple(extra) + ("mem_mb",)):
            merged["dataset"] = dataset
            merged["items"] = next(r["items"] for r in group if r["method"] == merged["method"])
            out.append(merged)
    return out


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    rows, extra = [], []
    try:
        for path in argv[1:-1]:  # several CSVs of one suite: their rows together
            more, columns = read_rows(path)
            rows += more
            extra += [c for c in columns if c not in extra]
    except (OSError, ValueError) as e:  # a clear message, not a traceback
        sys.exit(f"plot_bench.py: {e}")
    out = argv[-1]
    os.makedirs(out, exist_ok=True)

    groups = OrderedDict()
    for r in rows:
        groups.setdefault((r["suite"], r["dataset"]), []).append(r)
    for (suite, dataset), group in groups.items():
        every = reduce_repeats(group, extra)
        merged = [r for r in every if not is_voxel(r["method"])]
        voxel = [r for r in every if is_voxel(r["method"])]
        stem = os.path.join(out, file_stem(suite, dataset))
        if voxel and plot_voxel_errors(suite, dataset, voxel, stem + "_voxel_error.png"):
            print(stem + "_voxel_error.png")
        if voxel and plot_voxel_stages(suite, dataset, voxel, stem + "_voxel_stages.png"):
            print(stem + "_voxel_stages.png")
        if not merged:
            continue
        plot_times(suite, dataset, merged, stem + "_time.png")
        print(stem + "_time.png")
        if plot_errors(suite, dataset, merged, stem + "_error.png"):
            print(stem + "_error.png")
        if "frame_ms" in extra and plot_errors(
                suite, dataset, merged, stem + "_error_frame.png", x="frame_ms",
                xlabel="new time step: rebuild or resample + frame [ms]"):
            print(stem + "_error_frame.png")
        if plot_effects(suite, dataset, merged, stem + "_effects.png"):
            print(stem + "_effects.png")
    for suite in OrderedDict((r["suite"], None) for r in rows):
        path = os.path.join(out, file_stem(suite, "voxel_stages") + ".png")
        if plot_stage_table(suite, [r for r in rows if r["suite"] == suite], extra, path):
            print(path)


if __name__ == "__main__":
    main(sys.argv)
