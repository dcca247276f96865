"""pvpython: the same particles in other units give the same picture, in every particle
representation at its defaults (only ColorBy set).

The data is none of the bundled files: a generated set of three populations of different
density (a dense jittered slab, a sparse cloud above it, a compact Gaussian clump), with a
point array "speed" that varies smoothly. For each of "Ray-Traced Spheres", "RBF Volume",
"SPH Volume" and "SPH Fluid" it is shown at the scales 1e-3, 1 and 1e3 (the points
multiplied, the arrays unchanged), the camera reset, coloured by speed; checks:
- at scale 1 the representation draws something (more than 5% of the pixels differ from
  the background by more than 8 of 255): a ghost or an empty view would pass the rest;
- at 1e-3 and 1e3 the picture is the one at 1 (rmse at most 4 of 255 per channel);
- the automatic size in use scales with the data (the ...InUse property, relative 1e-6).

usage: pvpython TestScaleInvariance.py PLUGIN OUTPUT_DIR
"""
import os
import sys

import numpy
from paraview.simple import (ColorBy, CreateView, Delete, Hide, LoadPlugin, PVTrivialProducer,
                             ResetCamera, Show)
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, finish, prepare_view, rmse, screenshot  # noqa: E402

SIZE = [200, 150]
BACKGROUND = [0.1, 0.1, 0.15]
SCALES = (1e-3, 1.0, 1e3)
# Representation, the information property of its size in use.
REPRESENTATIONS = (('Ray-Traced Spheres', 'RadiusInUse'), ('RBF Volume', 'RBFRadiusInUse'),
                   ('SPH Volume', 'SPHSmoothingLengthInUse'),
                   ('SPH Fluid', 'SPHFluidRadiusInUse'))


def populations():
    """The points (n, 3) and their speed: a slab of 20 x 20 x 6 particles 0.1 apart
    jittered by 0.02, 400 particles spread over the volume above it, 1500 in a Gaussian
    clump of width 0.08."""
    rng = numpy.random.default_rng(25)
    i, j, k = numpy.meshgrid(numpy.arange(20), numpy.arange(20), numpy.arange(6), indexing='ij')
    slab = 0.1 * numpy.stack([i, j, k], axis=-1).reshape(-1, 3).astype(float)
    slab += rng.uniform(-0.02, 0.02, slab.shape)
    cloud = rng.uniform([0.0, 0.0, 0.8], [2.0, 2.0, 1.6], (400, 3))
    clump = rng.normal([1.4, 1.4, 1.1], 0.08, (1500, 3))
    points = numpy.concatenate([slab, cloud, clump])
    speed = 1.0 + numpy.sin(2.0 * points[:, 0]) + points[:, 2]  # a speed: >= 0
    return points, speed


def producer(points, speed, scale):
    data = vtkPolyData()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(numpy.ascontiguousarray(points * scale), deep=1))
    data.SetPoints(vtk_points)
    array = numpy_to_vtk(speed, deep=1)
    array.SetName('speed')
    data.GetPointData().AddArray(array)
    source = PVTrivialProducer()
    source.GetClientSideObject().SetOutput(data)
    source.UpdatePipeline()
    return source


def picture(view, points, speed, representation, size_property, scale, path):
    """The screenshot of the data at `scale` in `representation` at its defaults, and the
    size it used."""
    source = producer(points, speed, scale)
    rep = Show(source, view)
    rep.SetRepresentationType(representation)
    ColorBy(rep, ('POINTS', 'speed'))
    rep.RescaleTransferFunctionToDataRange(True, False)
    rep.SetScalarBarVisibility(view, False)
    ResetCamera(view)
    image = screenshot(view, path, SIZE)
    rep.SMProxy.UpdatePropertyInformation()
    size = rep.SMProxy.GetProperty(size_property).GetElement(0)
    Hide(source, view)
    return image, size


def main():
    plugin, out_dir = sys.argv[1], sys.argv[2]
    LoadPlugin(plugin, remote=False, ns=globals())
    view = CreateView('RenderView')
    prepare_view(view, SIZE, BACKGROUND)
    points, speed = populations()
    for representation, size_property in REPRESENTATIONS:
        stem = os.path.join(out_dir, 'TestScaleInvariance-' + representation.replace(' ', ''))
        shots = {s: picture(view, points, speed, representation, size_property, s,
                            '%s-%g.png' % (stem, s)) for s in SCALES}
        unit, unit_size = shots[1.0]
        drawn = float((numpy.abs(unit - numpy.array(BACKGROUND) * 255).max(axis=1) > 8).mean())
        check(drawn > 0.05, '%s draws the data at scale 1 (%.1f%% of the pixels)'
              % (representation, 100 * drawn))
        for s in (1e-3, 1e3):
            image, size = shots[s]
            error = rmse(image, unit)
            check(error <= 4.0, '%s at scale %g: the picture at 1 (rmse %.3f of 255)'
                  % (representation, s, error))
            check(abs(size - s * unit_size) <= 1e-6 * s * unit_size,
                  '%s at scale %g: the size in use %.6g is %g x %.6g'
                  % (representation, s, size, s, unit_size))
    Delete(view)
    return finish()


if __name__ == '__main__':
    sys.exit(main())
