"""pvpython: one RayMappers representation on one dataset as a ParaView user shows it (the
reader or source, Show, the representation type, ColorBy, the camera reset), timed: the first
still render (the representation's build and its first frame) and the median of the still
renders after it. Run once per representation in a process of its own (volumes_scale.py),
so that the process's peak resident memory is this representation's; --representation
Outline is the baseline (the data read, a window, no RayMappers structures).

Data (--data): a legacy VTK particle file, wavelet:N (ParaView's Wavelet source with the
extent for about N tetrahedra, through Tetrahedralize) or image-wavelet:N (the Wavelet with
about N voxels, through Clean to Grid: Z-Sweep Volume draws them as native hexahedra).
Particle arrays are picked by name: colour by vmag or speed; SPH Volume's h, m and rho and
SPH Fluid's radius h (x 0.8, the bench's look) when the file has them, else the defaults.

usage: pvpython representation_frame.py --plugin RayMappers.so --representation NAME
         --data SPEC [--size W H] [--repeat N] [--output PNG]
Prints one JSON line: points, cells, first_render_s, median_render_s and the mapper's
statistics (phases in ms, counters) of the first and the last render; with --output, the
same line in OUTPUT.json beside the picture.
"""
import argparse
import json
import math
import statistics
import time

from paraview import simple
from paraview.simple import ColorBy, CreateView, LoadPlugin, Render, SaveScreenshot, Show


def source(spec):
    """The pipeline's last proxy for --data."""
    for prefix, per_voxel in (("wavelet:", 5), ("image-wavelet:", 1)):
        if spec.startswith(prefix):
            a = max(1, round(0.5 * (int(spec[len(prefix):]) / per_voxel) ** (1.0 / 3.0)))
            wavelet = simple.Wavelet(WholeExtent=[-a, a, -a, a, -a, a])
            if per_voxel == 5:
                return simple.Tetrahedralize(Input=wavelet)
            return simple.CleantoGrid(Input=wavelet)  # voxels of an unstructured grid
    return simple.LegacyVTKReader(FileNames=[spec])


def configure(rep, view, name, arrays):
    """ColorBy and the size arrays a user of these files sets."""
    color = next((a for a in ("vmag", "speed", "RTData") if a in arrays), None)
    if color:
        ColorBy(rep, ("POINTS", color))
        rep.RescaleTransferFunctionToDataRange(True, False)
        rep.SetScalarBarVisibility(view, False)
    if name == "SPH Volume":
        for prop, array in (("SPHSmoothingLengthArray", "h"), ("SPHMassArray", "m"),
                            ("SPHDensityArray", "rho")):
            if array in arrays:
                setattr(rep, prop, ["POINTS", array])
    elif name == "SPH Fluid" and "h" in arrays:
        rep.ColorArrayName = ["POINTS", ""]
        rep.SPHFluidRadiusArray = ["POINTS", "h"]
        rep.SPHFluidRadiusScale = 0.8


STATISTICS = {"RBF Volume": "RBFRenderStatistics", "SPH Volume": "SPHRenderStatistics",
              "SPH Fluid": "SPHFluidRenderStatistics", "Z-Sweep Volume": "ZSweepRenderStatistics",
              "Ray-Traced Spheres": "SpheresRenderStatistics"}


def mapper_statistics(rep, name):
    """The mapper's statistics of the last render, {kind: {name: value}}: phase (ms),
    counter, effect (on or off); {} for Outline."""
    if name not in STATISTICS:
        return {}
    rep.SMProxy.UpdatePropertyInformation()
    text = rep.SMProxy.GetProperty(STATISTICS[name]).GetElement(0)
    values = {}
    for line in text.splitlines():
        kind, key, value = line.split()
        values.setdefault(kind, {})[key] = value if kind == "effect" else float(value)
    return values


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--representation", required=True)
    parser.add_argument("--data", required=True)
    parser.add_argument("--size", type=int, nargs=2, default=[1024, 1024])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--output", default="")
    args = parser.parse_args()
    LoadPlugin(args.plugin, remote=False, ns=globals())
    data = source(args.data)
    data.UpdatePipeline()
    info = data.GetDataInformation()
    arrays = [info.GetPointDataInformation().GetArrayInformation(i).GetName()
              for i in range(info.GetPointDataInformation().GetNumberOfArrays())]

    view = CreateView("RenderView")
    view.ViewSize = args.size
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.0, 0.0, 0.0]
    rep = Show(data, view)
    rep.SetRepresentationType(args.representation)
    if rep.Representation != args.representation:
        raise SystemExit("%s is not offered for %s (shown as %s)" % (
            args.representation, args.data, rep.Representation))
    configure(rep, view, args.representation, arrays)
    view.ResetCamera(False)
    times, frames = [], []
    for _ in range(1 + max(0, args.repeat)):
        start = time.perf_counter()
        Render(view)
        times.append(time.perf_counter() - start)
        frames.append(mapper_statistics(rep, args.representation))
    if args.output:
        SaveScreenshot(args.output, view, ImageResolution=args.size, TransparentBackground=0)
    result = json.dumps({
        "points": info.GetNumberOfPoints(), "cells": info.GetNumberOfCells(),
        "first_render_s": times[0],
        "median_render_s": statistics.median(times[1:]) if len(times) > 1 else math.nan,
        "first_frame_statistics": frames[0], "last_frame_statistics": frames[-1]})
    if args.output:
        with open(args.output + ".json", "w") as f:
            f.write(result + "\n")
    print(result)


if __name__ == "__main__":
    main()
