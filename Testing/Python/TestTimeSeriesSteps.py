"""pvpython: a time series played as a user plays it costs each particle representation one
rebuild per new step and no copy of the points.

A LAMMPS dump of four snapshots (a jittered lattice of 512 atoms that moves at every
step) opens with the plugin's reader; each particle representation (Ray-Traced Spheres,
RBF Volume, SPH Volume, SPH Fluid) and Z-Sweep Volume (on the Delaunay 3D of the atoms, a
grid that changes at every step) is shown and the animation played with GoToNext. At every
step: the points the representation draws are the reader's vtkPoints object itself (not a
copy: vtkRayMapperGatherPoints shares one point set), the mapper built once in that frame
(its `builds_this_render`), and a second render at the same time builds nothing.

usage: pvpython TestTimeSeriesSteps.py PLUGIN.so FOLDER
"""
import os
import sys

from paraview.simple import (  # noqa: E402
    ColorBy, CreateView, Delaunay3D, Delete, GetAnimationScene, GetTimeKeeper, Hide, LoadPlugin,
    OpenDataFile, Render, Show)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, finish, prepare_view  # noqa: E402

plugin, folder = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, remote=False, ns=globals())
STEPS = (0, 10, 20, 30)
PARTICLES = (('Ray-Traced Spheres', 'SpheresRenderStatistics'),
             ('RBF Volume', 'RBFRenderStatistics'),
             ('SPH Volume', 'SPHRenderStatistics'),
             ('SPH Fluid', 'SPHFluidRenderStatistics'))


def write_dump(path):
    """8^3 atoms on a unit lattice, jittered (a fixed pseudo-random pattern), moved by
    0.05 step/10 along x at every snapshot; column q = x."""
    lines = []
    for step in STEPS:
        lines += ['ITEM: TIMESTEP', str(step), 'ITEM: NUMBER OF ATOMS', '512',
                  'ITEM: BOX BOUNDS pp pp pp', '0 9', '0 9', '0 9',
                  'ITEM: ATOMS id type x y z q']
        for atom in range(512):
            i, j, k = atom % 8, (atom // 8) % 8, atom // 64
            jitter = [((atom * 7919 + 13 * a) % 101) / 101.0 * 0.2 for a in range(3)]
            x = i + jitter[0] + 0.005 * step
            lines.append('%d 1 %.6f %.6f %.6f %.6f' % (
                atom + 1, x, j + jitter[1], k + jitter[2], x))
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


def statistics(rep, name):
    """The phases and the counters of the last frame's statistics."""
    rep.SMProxy.UpdatePropertyInformation()
    phases, values = {}, {}
    for line in rep.SMProxy.GetProperty(name).GetElement(0).splitlines():
        kind, key, value = line.split()
        if kind == 'counter':
            values[key] = int(float(value))
        elif kind == 'phase':
            phases[key] = float(value)
    return phases, values


def counters(rep, name):
    return statistics(rep, name)[1]


def drawn_points(rep):
    """The vtkPoints the representation draws (its rendered data object: the points it
    hands the mapper)."""
    return rep.GetClientSideObject().GetActiveRepresentation().GetRenderedDataObject(0).GetPoints()


def play(source, view, representation, statistics_name, shares_points):
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    scene.GoToFirst()
    rep = Show(source, view)
    rep.SetRepresentationType(representation)
    ColorBy(rep, ('POINTS', 'q'))
    Render(view)
    for step in STEPS[1:]:
        scene.GoToNext()
        check(GetTimeKeeper().Time == step, '%s: the animation is at step %d' % (
            representation, step))
        if shares_points:
            reader_points = source.GetClientSideObject().GetOutputDataObject(0).GetPoints()
            check(drawn_points(rep) is reader_points,
                  "%s, step %d: the representation draws the reader's vtkPoints, not a copy"
                  % (representation, step))
        built = counters(rep, statistics_name).get('builds_this_render', -1)
        check(built == 1, '%s, step %d: one build in the new step\'s frame (%d)' % (
            representation, step, built))
        Render(view)
        built = counters(rep, statistics_name).get('builds_this_render', -1)
        check(built == 0, '%s, step %d: a second render builds nothing (%d)' % (
            representation, step, built))
    if representation == 'Ray-Traced Spheres':
        # Colouring by another array recolours the spheres: no sphere set, no grid built.
        ColorBy(rep, ('POINTS', 'type'))
        Render(view)
        phases, values = statistics(rep, statistics_name)
        check(values.get('builds_this_render', -1) == 0 and 'spheres' not in phases and
              'recolor' in phases, 'a new colour array recolours the spheres, no build '
              '(phases: %s)' % ' '.join(sorted(phases)))
    Hide(source, view)
    Delete(rep)


def main():
    os.makedirs(folder, exist_ok=True)
    dump = os.path.join(folder, 'moving_lattice.dump')
    write_dump(dump)
    view = CreateView('RenderView')
    prepare_view(view, [200, 150], [0.2, 0.2, 0.3])
    reader = OpenDataFile(dump)
    for representation, statistics_name in PARTICLES:
        play(reader, view, representation, statistics_name, True)
    grid = Delaunay3D(Input=reader)
    play(grid, view, 'Z-Sweep Volume', 'ZSweepRenderStatistics', False)
    Delete(grid)
    Delete(reader)
    Delete(view)
    return finish()


if __name__ == '__main__':
    sys.exit(main())
