"""pvpython: the five RayMappers representations in a client-server session.

Renders every representation first in this builtin session, then starts a pvserver on this
machine (on a free port it picks itself), connects to it, loads the plugin on both sides
and renders each representation again with remote rendering forced (RemoteRenderThreshold
0: the server renders, the client only receives the image). Checks:
- every representation is offered for its data on the server too, and the view really
  rendered remotely (vtkPVRenderView::GetUseDistributedRenderingForRender);
- each server picture is not just background and its RGB RMSE to the builtin picture of
  the same representation is below TOLERANCE (of 255): the properties, the colour and
  opacity maps and the camera reach the server's mappers;
- Reset Camera frames each representation as in the builtin session (the view's bounds
  are the server's data, nothing else);
- the client, whose representations hold no data in client-server mode, renders them
  without warnings (in the GUI a warning opens the Output Messages window), but for the
  fluid's one notice that it is gathered to rank 0 when the server has several ranks;
- the server exits when the client disconnects and logged no error (it is killed in any
  case, try/finally).

The server runs without the RayMappersExpatFix preload (build/bin/raymappers-env): with a
single server process no data set crosses a process boundary as XML (the server sends
images), so libexpat's "not well-formed (invalid token)" cannot occur; the server log is
checked for it, so this run is also the check that client-server needs no preload.

With `--ranks N --launcher RAYMAPPERS_ENV` the server is `mpirun -np N pvserver` under the
preload (several server processes do move data sets between them): the serial readers put
all data on rank 0, and the representations split it across the ranks themselves (see
vtkRayMapperPropRepresentation: particles with their ghosts, ZSweep's cells by the view,
the fluid gathered to rank 0); the pictures must still match the builtin ones, within
RANKS_TOLERANCE for the SPH volume, whose ranks place their sample depths apart.

usage: pvpython TestClientServer.py PLUGIN PVSERVER DATA_DIR OUTPUT_DIR
         [--ranks N --launcher RAYMAPPERS_ENV]
"""
import os
import queue
import re
import subprocess
import sys
import threading

from paraview.simple import (  # noqa: E402
    ColorBy, Connect, CreateView, Delete, Disconnect, GetColorTransferFunction,
    GetOpacityTransferFunction, LegacyVTKReader, LoadPlugin, PDBReader, Render, Show)
from vtkmodules.vtkCommonCore import vtkOutputWindow  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, finish, prepare_view, rmse  # noqa: E402
import raymappers_testing  # noqa: E402

SIZE = [300, 300]
BACKGROUND = [0.1, 0.1, 0.15]
# Both sessions run the same mappers on the same data with the same camera, and a
# screenshot comes back from the server losslessly (the pictures are equal: RMSE 0); a
# wrong property, map or camera moves the RMSE by tens of levels.
TOLERANCE = 1.0
RANKS_TOLERANCE = {'sph-volume': 2.0}
# A picture counts as drawn when more than this fraction of its pixels is not background.
MINIMUM_COVER = 0.05
# How long to wait for the server to listen, and to exit after the client disconnected.
# Both only bound a failure (a server that never comes up or hangs); a working run takes
# a few seconds.
SERVER_WAIT = 120
DAM_BREAK = 'dam_break_coarse_00674.vtk'


def color_map(rep, view, array, value_range, opacity_points=None):
    ColorBy(rep, ('POINTS', array))
    rep.SetScalarBarVisibility(view, False)
    lut = GetColorTransferFunction(array)
    lut.ApplyPreset('Cool to Warm', True)
    lut.AutomaticRescaleRangeMode = 'Never'
    lut.RescaleTransferFunction(*value_range)
    if opacity_points is not None:
        GetOpacityTransferFunction(array).Points = opacity_points


# Each case sets its representation's properties before the first render. The SPH
# representations keep their default size array, the dam break's h (SIZE_DEFAULTS).
def spheres(rep, view):
    rep.UseRadiusArray = 1
    rep.RadiusArray = ['POINTS', 'h']
    rep.RadiusScale = 0.8
    color_map(rep, view, 'p', (0.0, 2000.0))


def rbf_volume(rep, view):
    color_map(rep, view, 'atom_type', (0.0, 20.0), [0.0, 0.0, 0.5, 0.0, 20.0, 0.6, 0.5, 0.0])
    rep.RBFRadius = 1.0
    rep.Kappa = 1.0  # the automatic kappa is estimated per decomposition (distributed_scene.py)
    rep.ScalarOpacityUnitDistance = 2.0


def zsweep_volume(rep, view):
    color_map(rep, view, 'scalars', (0.75, 17.4), [0.75, 0.0, 0.5, 0.0, 17.4, 0.8, 0.5, 0.0])
    rep.ScalarOpacityUnitDistance = 0.3


def sph_volume(rep, view):
    rep.SPHKernel = 'Wendland C2'
    rep.SPHMassArray = ['POINTS', 'm']
    rep.SPHDensityArray = ['POINTS', 'rho']
    color_map(rep, view, 'rho', (990.0, 1010.0), [990.0, 0.1, 0.5, 0.0, 1010.0, 0.6, 0.5, 0.0])
    rep.ScalarOpacityUnitDistance = 0.1


def sph_fluid(rep, view):
    rep.ColorArrayName = ['POINTS', '']
    rep.SPHFluidRadiusScale = 0.8
    rep.SPHFluidAbsorptionColor = [4.0, 1.5, 0.8]


# Cameras (focal point, position; +z up) fixed per data set, so that the picture
# comparison does not depend on Reset Camera, which is checked on its own.
DAM_BREAK_CAMERA = ((0.9, 0.0, 0.2), (0.2, -2.6, 1.5))
LYSOZYME_CAMERA = ((1.6, 21.6, 19.2), (60.0, -60.0, 70.0))
HEXA_CAMERA = ((0.48, 0.48, 0.48), (2.2, -1.6, 1.9))

# What each particle case's size property is by default: the client's domains choose it
# from the data information of the session's data (the server's in client-server). The dam
# break's h is a smoothing length, never a sphere radius; 2LYZ has no size array.
SIZE_DEFAULTS = {'spheres': ('UseRadiusArray', 0), 'rbf': ('UseRBFRadiusArray', 0),
                 'sph-volume': ('SPHSmoothingLengthArray', 'h'),
                 'sph-fluid': ('SPHFluidRadiusArray', 'h')}

# (name, representation, data file, properties, camera)
CASES = (
    ('spheres', 'Ray-Traced Spheres', DAM_BREAK, spheres, DAM_BREAK_CAMERA),
    ('rbf', 'RBF Volume', '2LYZ.pdb', rbf_volume, LYSOZYME_CAMERA),
    ('zsweep', 'Z-Sweep Volume', 'hexa.vtk', zsweep_volume, HEXA_CAMERA),
    ('sph-volume', 'SPH Volume', DAM_BREAK, sph_volume, DAM_BREAK_CAMERA),
    ('sph-fluid', 'SPH Fluid', DAM_BREAK, sph_fluid, DAM_BREAK_CAMERA),
)


def open_data(path):
    if path.endswith('.pdb'):
        return PDBReader(FileName=path)
    return LegacyVTKReader(FileNames=[path])


class WarningCounter:
    """Counts the VTK warnings and errors this process reports."""

    def __init__(self):
        self.count = 0
        window = vtkOutputWindow.GetInstance()
        for event in ('WarningEvent', 'ErrorEvent'):
            window.AddObserver(event, self.seen)

    def seen(self, caller, event):
        self.count += 1


def check_size_default(session, name, rep):
    if name not in SIZE_DEFAULTS:
        return
    prop, expected = SIZE_DEFAULTS[name]
    value = rep.GetPropertyValue(prop)
    value = value if isinstance(value, int) else value[1]
    check(value == expected, '%s: %s %s is %r by default (%r)'
          % (session, name, prop, expected, value))


def render_cases(session, data_dir, out_dir, warnings, ranks=1):
    """Every case in a fresh view of the current session: {name: (RGB pixels, camera
    after Reset Camera as (focal point, distance))}."""
    results = {}
    for name, representation, data, properties, (focal, position) in CASES:
        view = CreateView('RenderView')
        prepare_view(view, SIZE, BACKGROUND)
        if session == 'server':
            view.RemoteRenderThreshold = 0.0
        source = open_data(os.path.join(data_dir, data))
        rep = Show(source, view)
        offered = representation in rep.Representation.Available
        check(offered, '%s: "%s" is offered for %s' % (session, representation, data))
        if offered:
            rep.SetRepresentationType(representation)
            check_size_default(session, name, rep)
            properties(rep, view)
            before = warnings.count
            # paraview.simple's first render resets the camera: place it after that one.
            Render(view)
            camera = view.GetActiveCamera()
            camera.SetFocalPoint(focal)
            camera.SetPosition(position)
            camera.SetViewUp(0, 0, 1)
            path = os.path.join(out_dir, '%s-%s.png' % (session, name))
            image = raymappers_testing.screenshot(view, path, SIZE)
            if session == 'server':
                check(view.GetClientSideObject().GetUseDistributedRenderingForRender(),
                      'server: %s rendered remotely' % name)
                # On several server ranks the fluid says once that it is gathered to rank 0
                # (the server's warnings reach the client's output window).
                expected = 1 if ranks > 1 and name == 'sph-fluid' else 0
                check(warnings.count - before == expected,
                      'server: the client renders %s with %d warning(s) (%d)'
                      % (name, expected, warnings.count - before))
            view.ResetCamera(False)
            camera = view.GetActiveCamera()
            results[name] = (image, (camera.GetFocalPoint(), camera.GetDistance()))
            Delete(rep)
        Delete(view)
        Delete(source)
    return results


def start_server(pvserver, log_path, ranks, launcher):
    """pvserver on a port it picks itself (--server-port=0), on `ranks` MPI processes when
    more than one; returns (process, port, the thread that copies its output to log_path
    until it exits). The server prints the port it listens on ("Accepting connection(s):
    host:port")."""
    command = [pvserver, '--server-port=0', '--force-offscreen-rendering']
    env = None
    if ranks > 1:
        command = [launcher, 'mpirun', '--allow-run-as-root', '--oversubscribe', '-x',
                   'LD_PRELOAD', '-np', str(ranks)] + command
        # pvpython runs as an MPI singleton; mpirun must not inherit its environment.
        env = {k: v for k, v in os.environ.items()
               if not k.startswith(('OMPI_', 'PMIX_', 'OPAL_'))}
    process = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
        env=env)
    lines = queue.Queue()

    def pump():
        with open(log_path, 'w') as log:
            for line in process.stdout:
                log.write(line)
                log.flush()
                lines.put(line)
        lines.put(None)

    copier = threading.Thread(target=pump, daemon=True)
    copier.start()
    while True:
        try:
            line = lines.get(timeout=SERVER_WAIT)
        except queue.Empty:
            return process, None, copier
        if line is None:
            return process, None, copier
        match = re.search(r'Accepting connection\(s\): \S+:(\d+)', line)
        if match:
            return process, int(match.group(1)), copier


def compare(builtin, served, ranks):
    for name, (image, (focal, distance)) in builtin.items():
        if name not in served:
            continue
        served_image, (served_focal, served_distance) = served[name]
        covered = float((abs(served_image - served_image[0]).sum(axis=1) > 3).mean())
        check(covered > MINIMUM_COVER, '%s: the server\'s picture is not background '
              '(%.1f%% of the pixels)' % (name, 100 * covered))
        difference = rmse(served_image, image)
        tolerance = RANKS_TOLERANCE.get(name, TOLERANCE) if ranks > 1 else TOLERANCE
        check(difference < tolerance, '%s: the server\'s picture is the builtin one (rmse '
              '%.3f < %g of 255)' % (name, difference, tolerance))
        offset = max(abs(a - b) for a, b in zip(focal, served_focal))
        check(offset < 1e-6 * distance and abs(served_distance - distance) < 1e-6 * distance,
              '%s: Reset Camera frames it as in the builtin session (focal point %s, '
              'distance %.4g; builtin %s, %.4g)'
              % (name, ', '.join('%.4g' % x for x in served_focal), served_distance,
                 ', '.join('%.4g' % x for x in focal), distance))


def main():
    plugin, pvserver, data_dir, out_dir = sys.argv[1:5]
    options = dict(zip(sys.argv[5::2], sys.argv[6::2]))
    ranks = int(options.get('--ranks', 1))
    launcher = options.get('--launcher')
    os.makedirs(out_dir, exist_ok=True)
    warnings = WarningCounter()

    LoadPlugin(plugin, remote=False, ns=globals())
    builtin = render_cases('builtin', data_dir, out_dir, warnings)

    log_path = os.path.join(out_dir, 'pvserver.log')
    process, port, copier = start_server(pvserver, log_path, ranks, launcher)
    try:
        check(port is not None, 'pvserver listens (port %s)' % port)
        if port is not None:
            connection = Connect('localhost', port)
            check(connection is not None and connection.IsRemote(),
                  'connected to the pvserver on port %d' % port)
            LoadPlugin(plugin, remote=True, ns=globals())
            LoadPlugin(plugin, remote=False, ns=globals())
            served = render_cases('server', data_dir, out_dir, warnings, ranks)
            # pvpython keeps the disconnected session (and the server) alive until another
            # session replaces it: a builtin one.
            del connection
            Disconnect()
            Connect()
            compare(builtin, served, ranks)
            try:
                code = process.wait(timeout=SERVER_WAIT)
            except subprocess.TimeoutExpired:
                code = None
            check(code == 0, 'the server exits when the client disconnects (exit code %s)'
                  % code)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
        copier.join()
    with open(log_path) as log:
        errors = [line.strip() for line in log
                  if 'ERR|' in line or 'ERROR' in line or 'not well-formed' in line]
    check(not errors, 'the server logged no error%s' % (': ' + errors[0] if errors else ''))
    return finish()


if __name__ == '__main__':
    code = main()
    if code:
        sys.exit(code)
