"""pvpython: what RBF Volume's Field Value costs. The bundled PySPH dam break coloured by its
pressure p, seen from the side, drawn with Sum of Heights (Knoll) and with Weighted Average
in alternating rounds (the same view, still renders); prints each mode's median frame time
and their ratio.

usage: pvpython rbf_field_value_cost.py PLUGIN [DATA.vtk] [--rounds N] [--size W H]
"""
import argparse
import statistics
import time

from paraview.simple import ColorBy, CreateView, LegacyVTKReader, LoadPlugin, Render, ResetCamera, Show

parser = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument('plugin')
parser.add_argument('data', nargs='?', default='Data/dam_break_coarse_00674.vtk')
parser.add_argument('--array', default='p')
parser.add_argument('--rounds', type=int, default=7)
parser.add_argument('--size', type=int, nargs=2, default=[800, 600])
args = parser.parse_args()

LoadPlugin(args.plugin, remote=False, ns=globals())
view = CreateView('RenderView')
view.ViewSize = args.size
view.OrientationAxesVisibility = 0
rep = Show(LegacyVTKReader(FileNames=[args.data]), view)
rep.SetRepresentationType('RBF Volume')
ColorBy(rep, ('POINTS', args.array))
Render(view)  # (paraview.simple resets the camera at a view's first render)
view.CameraPosition = [0.9, -2.5, 1.5]
view.CameraFocalPoint = [0.9, 0, 0.25]
view.CameraViewUp = [0, 0, 1]
ResetCamera(view)
Render(view)
times = {'Sum of Heights (Knoll)': [], 'Weighted Average': []}
for _ in range(args.rounds):
    for mode, measured in times.items():
        rep.NormalizeWeights = mode
        Render(view)
        start = time.perf_counter()
        view.StillRender()
        measured.append(time.perf_counter() - start)
for mode, measured in times.items():
    print('%-24s median %.1f ms' % (mode, 1000 * statistics.median(measured)))
print('ratio average / sum: %.2f' % (statistics.median(times['Weighted Average']) /
                                     statistics.median(times['Sum of Heights (Knoll)'])))
