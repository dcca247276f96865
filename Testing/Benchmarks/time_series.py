"""Time series as a user plays them: each representation at its defaults on a series, the
animation played with ParaView's AnimationScene (GoToNext), the cost of every new step.

Per step: `step_ms`, the wall time from the time change to the rendered frame (the reader
updated first, then GoToNext: the representation's update, the delivery, the still
render); `reader_ms`, the reader's (or the source pipeline's) update alone; `mapper_ms`,
the sum of the mapper's phases of that frame (its statistics), split into `rebuild_ms`
(the phases that rebuild from the data: spheres, grid_build, bvh_build, particles, cells,
mesh) and `frame_ms` (the rest: tracing, drawing); `rest_ms` = step - reader - mapper (the
representation's update, the delivery, ParaView's own work); `still_ms`, a second render at
the same time (what the frame costs without a new step); `builds`, the mapper's builds in
that step. ParaView's Points and Point Gaussian representations on the same series are the
baseline (no mapper statistics). The tables are medians over the steps.

usage (from the source root, under Xvfb):
  pvpython Testing/Benchmarks/time_series.py --plugin build/lib/paraview-plugins/RayMappers/RayMappers.so \
      --lammps build/data/melt_series.dump --pysph 'build/data/dam_series/dam_*.vtk' \
      [--size 800 600] [--steps 20] [--only NAME ...] [--csv OUT.csv] [--markdown OUT.md]
"""
import argparse
import csv
import glob
import os
import statistics as stat
import sys
import time

from paraview.simple import (  # noqa: E402
    Calculator, ColorBy, CreateView, Delaunay3D, Delete, GetAnimationScene, GetTimeKeeper, Hide, LoadPlugin,
    OpenDataFile, Render, SetActiveSource, Show)

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(here), 'Python'))
from raymappers_testing import prepare_view  # noqa: E402

# (representation, its statistics property or None for ParaView's own)
REPRESENTATIONS = {
    'Points': None,
    'Point Gaussian': None,
    'Ray-Traced Spheres': 'SpheresRenderStatistics',
    'RBF Volume': 'RBFRenderStatistics',
    'SPH Volume': 'SPHRenderStatistics',
    'SPH Fluid': 'SPHFluidRenderStatistics',
    'Z-Sweep Volume': 'ZSweepRenderStatistics',
}
POINT_REPRESENTATIONS = ['Points', 'Point Gaussian', 'Ray-Traced Spheres', 'RBF Volume',
                         'SPH Volume', 'SPH Fluid']
GRID_REPRESENTATIONS = ['Z-Sweep Volume']
REBUILD_PHASES = ('spheres', 'grid_build', 'bvh_build', 'particles', 'cells', 'mesh')


def phase_values(rep, name):
    """The phases of the last frame (statistics() mixes phases and counters: the summary's
    kind tells them apart)."""
    rep.SMProxy.UpdatePropertyInformation()
    text = rep.SMProxy.GetProperty(name).GetElement(0)
    phases, counters = {}, {}
    for line in text.splitlines():
        kind, key, value = line.split()
        if kind == 'phase':
            phases[key] = float(value)
        elif kind == 'counter':
            counters[key] = float(value)
    return phases, counters


def play(dataset, source, view, representation, array, steps, times):
    """Shows `source` as `representation`, goes to the first time, then plays `steps` new
    steps with GoToNext; one row per step."""
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.GoToFirst()
    source.UpdatePipeline(times[0])
    rep = Show(source, view)
    rep.SetRepresentationType(representation)
    ColorBy(rep, ('POINTS', array))
    rep.RescaleTransferFunctionToDataRange(True, False)
    view.ResetCamera()
    Render(view)
    Render(view)
    stats_name = REPRESENTATIONS[representation]
    rows = []
    for k in range(1, min(steps, len(times) - 1) + 1):
        t = times[k]
        start = time.perf_counter()
        source.UpdatePipeline(t)
        read = time.perf_counter()
        scene.GoToNext()
        done = time.perf_counter()
        if GetTimeKeeper().Time != t:
            raise SystemExit('GoToNext went to time %g, not to the next step %g'
                             % (GetTimeKeeper().Time, t))
        row = {'dataset': dataset, 'representation': representation, 'step': k, 'time': t,
               'step_ms': 1000 * (done - start), 'reader_ms': 1000 * (read - start)}
        if stats_name:
            phases, counters = phase_values(rep, stats_name)
            row['rebuild_ms'] = sum(v for p, v in phases.items() if p in REBUILD_PHASES)
            row['mapper_ms'] = sum(phases.values())
            row['frame_ms'] = row['mapper_ms'] - row['rebuild_ms']
            row['builds'] = counters.get('builds_this_render', 0)
            row['phases'] = ' '.join('%s=%.1f' % kv for kv in sorted(phases.items()))
        row['rest_ms'] = row['step_ms'] - row['reader_ms'] - row.get('mapper_ms', 0.0)
        still = time.perf_counter()
        Render(view)
        row['still_ms'] = 1000 * (time.perf_counter() - still)
        if stats_name:
            _, counters = phase_values(rep, stats_name)
            row['still_builds'] = counters.get('builds_this_render', 0)
        rows.append(row)
        print('%-8s %-18s step %2d: %8.1f ms (reader %7.1f, rebuild %7.1f, frame %7.1f, '
              'rest %7.1f), still %7.1f' % (
                  dataset, representation, k, row['step_ms'], row['reader_ms'],
                  row.get('rebuild_ms', 0), row.get('frame_ms', 0), row['rest_ms'],
                  row['still_ms']), flush=True)
    Hide(source, view)
    Delete(rep)
    return rows


def series_sources(args):
    """Yields (dataset name, source proxy, colour array, representations) for each series
    asked, one at a time: the time keeper then holds one series' times, and each source is
    deleted after its turn."""
    if args.lammps:
        reader = OpenDataFile(args.lammps)
        yield 'lammps', reader, args.lammps_array, POINT_REPRESENTATIONS
        if args.lammps_radius:
            # The same series with a radius array (0.5 for type 1, 0.4 for type 2, as
            # lammps_dump_to_vtk.py writes it), which the particle representations draw.
            sized = Calculator(Input=reader, ResultArrayName='radius',
                               Function='0.6 - 0.1 * type')
            yield 'lammps-radius', sized, args.lammps_array, POINT_REPRESENTATIONS
            Delete(sized)
        Delete(reader)
    if args.pysph:
        reader = OpenDataFile(sorted(glob.glob(args.pysph)))
        yield 'pysph', reader, args.pysph_array, POINT_REPRESENTATIONS
        if args.grid:
            # A changing unstructured grid: the Delaunay tetrahedralization of every step.
            grid = Delaunay3D(Input=reader)
            yield 'pysph-delaunay', grid, args.pysph_array, GRID_REPRESENTATIONS
            Delete(grid)
        Delete(reader)


def summarize(rows):
    """Median per (dataset, representation) of every numeric column."""
    keys = []
    for row in rows:
        if (row['dataset'], row['representation']) not in keys:
            keys.append((row['dataset'], row['representation']))
    table = []
    for dataset, representation in keys:
        mine = [r for r in rows if r['dataset'] == dataset and r['representation'] == representation]
        entry = {'dataset': dataset, 'representation': representation, 'steps': len(mine)}
        for column in ('step_ms', 'reader_ms', 'rebuild_ms', 'frame_ms', 'rest_ms', 'still_ms',
                       'builds', 'still_builds'):
            values = [r[column] for r in mine if column in r]
            entry[column] = stat.median(values) if values else None
        table.append(entry)
    return table


def markdown(table, points):
    lines = ['| data | representation | new step | reader | rebuild | frame | rest | '
             'still frame | builds per step |', '|---|---|---|---|---|---|---|---|---|']
    for e in table:
        cell = lambda v, fmt='%.0f ms': '-' if v is None else fmt % v  # noqa: E731
        lines.append('| %s (%s) | %s | %s | %s | %s | %s | %s | %s | %s |' % (
            e['dataset'], points.get(e['dataset'], '?'), e['representation'],
            cell(e['step_ms']), cell(e['reader_ms']), cell(e['rebuild_ms']),
            cell(e['frame_ms']), cell(e['rest_ms']), cell(e['still_ms']),
            cell(e['builds'], '%g')))
    return '\n'.join(lines) + '\n'


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('--plugin', required=True)
    parser.add_argument('--lammps', default='')
    parser.add_argument('--lammps-array', default='vx')
    parser.add_argument('--lammps-radius', action='store_true',
                        help='also the LAMMPS series with a radius array (a Calculator)')
    parser.add_argument('--pysph', default='', help='glob of the series files')
    parser.add_argument('--pysph-array', default='vmag')
    parser.add_argument('--grid', action='store_true',
                        help='also Z-Sweep Volume on the Delaunay 3D of the PySPH series')
    parser.add_argument('--size', type=int, nargs=2, default=[800, 600])
    parser.add_argument('--steps', type=int, default=20)
    parser.add_argument('--grid-steps', type=int, default=4,
                        help='steps of the Delaunay grid (its filter takes seconds a step)')
    parser.add_argument('--only', nargs='*', default=[])
    parser.add_argument('--csv', default='')
    parser.add_argument('--markdown', default='')
    args = parser.parse_args()
    LoadPlugin(args.plugin, remote=False, ns=globals())

    view = CreateView('RenderView')
    prepare_view(view, args.size, [0.32, 0.34, 0.43])
    rows, points = [], {}
    for dataset, source, array, representations in series_sources(args):
        times = list(GetTimeKeeper().TimestepValues)
        source.UpdatePipeline(times[0])
        points[dataset] = '%d points, %d cells' % (
            source.GetDataInformation().GetNumberOfPoints(),
            source.GetDataInformation().GetNumberOfCells())
        SetActiveSource(source)
        for representation in representations:
            if args.only and representation not in args.only:
                continue
            steps = args.grid_steps if representation in GRID_REPRESENTATIONS else args.steps
            rows += play(dataset, source, view, representation, array, steps, times)
    Delete(view)
    table = summarize(rows)
    text = markdown(table, points)
    print(text)
    if args.csv:
        columns = ['dataset', 'representation', 'step', 'time', 'step_ms', 'reader_ms',
                   'rebuild_ms', 'frame_ms', 'mapper_ms', 'rest_ms', 'still_ms', 'builds',
                   'still_builds', 'phases']
        with open(args.csv, 'w', newline='') as f:
            writer = csv.DictWriter(f, fieldnames=columns)
            writer.writeheader()
            for row in rows:
                writer.writerow(row)
    if args.markdown:
        with open(args.markdown, 'w') as f:
            f.write('Command: `%s`\n\n' % ' '.join(sys.argv))
            f.write('Medians over the steps (%d at most per representation), %dx%d.\n\n' % (
                args.steps, args.size[0], args.size[1]))
            f.write(text)


if __name__ == '__main__':
    main()
