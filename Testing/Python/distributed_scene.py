"""pvbatch (1 to N MPI ranks): one RayMappers representation on data partitioned across the
ranks, rendered by ParaView's distributed engine (IceT compositing), saved as a PNG.

Run through TestDistributedRendering.py (the ctest) or scripts/distributed_scaling.py:
  raymappers-env mpirun -x LD_PRELOAD -np N pvbatch distributed_scene.py \
      --plugin RayMappers.so --data-dir Data --representation spheres --output out.png
Prints one JSON line: the ranks, the ranks holding data, the particles or cells, and the
median time of the still renders after the first (--repeat).
"""
import argparse
import json
import statistics
import time

from paraview import servermanager, simple
from paraview.simple import (
    ColorBy, CreateView, Delete, GetColorTransferFunction, GetOpacityTransferFunction,
    LoadPlugin, Render, SaveScreenshot, Show)

SCENES = ('spheres', 'translucent', 'occlusion', 'shadows', 'rbf', 'sph', 'zsweep', 'fluid',
          'mixed', 'mixed-rbf', 'mixed-zsweep')
REPRESENTATIONS = {'spheres': 'Ray-Traced Spheres', 'translucent': 'Ray-Traced Spheres',
                   'occlusion': 'Ray-Traced Spheres', 'shadows': 'Ray-Traced Spheres',
                   'rbf': 'RBF Volume', 'sph': 'SPH Volume',
                   'zsweep': 'Z-Sweep Volume', 'fluid': 'SPH Fluid', 'mixed': 'SPH Volume',
                   'mixed-rbf': 'RBF Volume', 'mixed-zsweep': 'Z-Sweep Volume'}


def particles(data_dir, fine):
    path = fine if fine else data_dir + '/dam_break_coarse_00674.vtk'
    return simple.LegacyVTKReader(FileNames=[path])


def color(rep, view, array, lo, hi, opacity_points=None):
    ColorBy(rep, ('POINTS', array))
    rep.SetScalarBarVisibility(view, False)
    lut = GetColorTransferFunction(array)
    lut.ApplyPreset('Cool to Warm', True)
    lut.AutomaticRescaleRangeMode = 'Never'
    lut.RescaleTransferFunction(lo, hi)
    if opacity_points:
        GetOpacityTransferFunction(array).Points = opacity_points


def sph_volume(rep, view, opacity=(0.15, 0.6)):
    rep.SPHKernel = 'Wendland C2'
    rep.SPHSmoothingLengthArray = ['POINTS', 'h']
    rep.SPHMassArray = ['POINTS', 'm']
    rep.SPHDensityArray = ['POINTS', 'rho']
    color(rep, view, 'vmag', 0.0, 2.8, [0.0, opacity[0], 0.5, 0.0, 2.8, opacity[1], 0.5, 0.0])
    rep.ScalarOpacityUnitDistance = 0.05


def rbf_volume(rep, view, opacity=0.8):
    color(rep, view, 'vmag', 0.0, 2.5, [0.0, 0.0, 0.5, 0.0, 2.5, opacity, 0.5, 0.0])
    rep.RBFRadius = 0.02
    # The paper's kappa: the automatic one is an estimate on each decomposition's
    # particles (the same on every rank, vtkRBFVolumeRepresentation::PushKappa, but not
    # bit for bit the one rank's), and this scene checks the compositing exactly.
    rep.Kappa = 1.0
    rep.ScalarOpacityUnitDistance = 0.05


def zsweep_volume(rep, view, opacity=0.6):
    color(rep, view, 'Temp', 293.0, 913.0, [293.0, 0.0, 0.5, 0.0, 913.0, opacity, 0.5, 0.0])
    rep.ScalarOpacityUnitDistance = 1.0


def opaque_spheres(source, view, ratio=12, radius=0.04):
    """Every ratio-th point as an opaque sphere inside the volume, from the serial reader:
    rank 0 holds them all, spread over every rank's region and across its faces."""
    some = simple.MaskPoints(Input=source, OnRatio=ratio, MaximumNumberofPoints=10 ** 9,
                             GenerateVertices=1, SingleVertexPerCell=1)
    spheres = Show(some, view)
    spheres.SetRepresentationType('Ray-Traced Spheres')
    spheres.ColorArrayName = ['POINTS', '']
    spheres.AmbientColor = spheres.DiffuseColor = [0.9, 0.85, 0.2]
    spheres.Radius = radius


def dam_break_camera(view):
    camera = view.GetActiveCamera()
    camera.SetFocalPoint(0.9, 0.0, 0.2)
    camera.SetPosition(0.2, -2.6, 1.5)
    camera.SetViewUp(0, 0, 1)
    camera.SetViewAngle(30)
    view.CenterOfRotation = [0.9, 0.0, 0.2]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('--plugin', required=True)
    parser.add_argument('--data-dir', required=True)
    parser.add_argument('--representation', choices=SCENES, required=True)
    parser.add_argument('--output', required=True)
    parser.add_argument('--size', type=int, nargs=2, default=[400, 300])
    parser.add_argument('--repeat', type=int, default=1)
    parser.add_argument('--fine', default='', help='a larger particle file (scaling runs)')
    args = parser.parse_args()

    LoadPlugin(args.plugin, remote=False, ns=globals())
    scene = args.representation
    if scene in ('zsweep', 'mixed-zsweep'):
        reader = simple.ExodusIIReader(FileName=[args.data_dir + '/disk_out_ref.ex2'])
        reader.PointVariables = ['Temp']
        # One grid: ParaView 5.11 redistributing the reader's multiblock on 3 ranks keeps
        # only the first partition of a block ("More than 1 partition encountered").
        source = simple.MergeBlocks(Input=reader)
    else:
        source = particles(args.data_dir, args.fine)
    # The readers are serial (rank 0 reads everything); the kd-tree redistribution gives
    # every rank a piece, as a parallel reader or a simulation would.
    data = simple.RedistributeDataSet(Input=source)

    view = CreateView('RenderView')
    view.ViewSize = args.size
    view.OrientationAxesVisibility = 0
    view.UseFXAA = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.0, 0.0, 0.0]
    rep = Show(data, view)
    rep.SetRepresentationType(REPRESENTATIONS[scene])
    if scene == 'spheres':
        color(rep, view, 'p', 0.0, 2500.0)
        # The automatic radius (Radius 0, the default): the ranks' sample distances gathered
        # give the one-rank spacing (before, the minimum of the ranks' own estimates gave a
        # radius a few percent off and rmse 12 of 255 against one rank).
        rep.Radius = 0.0
    elif scene == 'translucent':
        # Translucent spheres blend in the ranks' visibility order, each rank drawing the
        # surfaces in its box.
        color(rep, view, 'p', 0.0, 2500.0)
        rep.Radius = 0.03
        rep.Opacity = 0.4
    elif scene == 'occlusion':
        # Occlusion rays from a rank's box reach the spheres of its neighbours' boxes. Radii
        # by the density (0.0247 to 0.0255), the automatic occlusion radius: twice the
        # largest radius of all the ranks' spheres.
        color(rep, view, 'p', 0.0, 2500.0)
        rep.UseRadiusArray = 1
        rep.RadiusArray = ['POINTS', 'rho']
        rep.RadiusScale = 2.5e-5
        rep.AmbientOcclusionSamples = 16
        rep.AmbientOcclusionRadius = 0.0
    elif scene == 'shadows':
        # Shadow rays cross the whole data: the light's side of another rank's box.
        color(rep, view, 'p', 0.0, 2500.0)
        rep.Radius = 0.025
        rep.ShadowRays = 2
        # A light above and in front, so that the spheres in view cast shadows on each other.
        rep.AutomaticShadowLight = 0
        rep.ShadowLightPosition = [0.6, -1.5, 2.5]
        rep.ShadowLightSize = 0.2
    elif scene == 'rbf':
        rbf_volume(rep, view)
    elif scene == 'mixed-rbf':
        rbf_volume(rep, view, 0.3)
        opaque_spheres(source, view)
    elif scene == 'sph':
        sph_volume(rep, view)
    elif scene == 'mixed':
        # A thinner volume, so that the spheres inside it show.
        sph_volume(rep, view, (0.02, 0.1))
        opaque_spheres(source, view)
    elif scene == 'zsweep':
        zsweep_volume(rep, view)
    elif scene == 'mixed-zsweep':
        # Every 40th mesh point (213 of 8,499) as a sphere of 0.2 (the disk is 11.5 wide).
        zsweep_volume(rep, view)
        opaque_spheres(source, view, 40, 0.2)
    else:
        rep.ColorArrayName = ['POINTS', '']
        rep.SPHFluidRadiusArray = ['POINTS', 'h']
        rep.SPHFluidRadiusScale = 0.8
        rep.SPHFluidAbsorptionColor = [4.0, 1.5, 0.8]

    Render(view)
    if scene in ('zsweep', 'mixed-zsweep'):
        view.ResetCamera(False)
        view.GetActiveCamera().Azimuth(30)
        view.GetActiveCamera().Elevation(20)
        view.GetActiveCamera().Dolly(1.3)
    else:
        dam_break_camera(view)
    # Time-independent: still renders only (no interactive reduction).
    times = []
    for _ in range(max(1, args.repeat)):
        start = time.perf_counter()
        Render(view)
        times.append(time.perf_counter() - start)
    SaveScreenshot(args.output, view, ImageResolution=args.size, TransparentBackground=0)

    # Which ranks hold a piece of the data (the partition is real).
    ids = simple.ProcessIdScalars(Input=data)
    ids.UpdatePipeline()
    info = ids.GetDataInformation()
    array = info.GetPointDataInformation().GetArrayInformation('ProcessId')
    ranks = servermanager.vtkProcessModule.GetProcessModule().GetNumberOfLocalPartitions()
    print(json.dumps({
        'ranks': ranks,
        'process_id_range': list(array.GetComponentRange(0)) if array else None,
        'points': info.GetNumberOfPoints(), 'cells': info.GetNumberOfCells(),
        'first_render_s': times[0],
        'median_render_s': statistics.median(times[1:]) if len(times) > 1 else times[0]}))
    Delete(view)


if __name__ == '__main__':
    main()
