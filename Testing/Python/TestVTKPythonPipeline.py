"""pvpython: the Python-wrapped modules in a plain VTK pipeline.

A single sphere of radius 1 seen from distance 10 with a 30 degree view angle covers a disc
of pixel radius R = f / sqrt(d^2 - 1), f = (H/2) / tan(15 deg): the covered pixel count must
be pi R^2 up to the pixels its rim crosses. Statistics are read from Python, and the LAMMPS
dump reader reads a real dump.

usage: pvpython TestVTKPythonPipeline.py BUILD_DIR SOURCE_DIR
"""
import math
import os
import sys

build, source = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(build, "lib", "python3", "dist-packages"))

from vtkmodules import vtkRenderingOpenGL2  # noqa: F401,E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402
from vtkmodules.vtkRenderingCore import (  # noqa: E402
    vtkActor, vtkRenderer, vtkRenderWindow, vtkWindowToImageFilter)
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402

import raymappers  # noqa: E402

failures = []


def check(condition, message):
    print(("ok    " if condition else "FAIL  ") + message)
    if not condition:
        failures.append(message)


points = vtkPoints()
points.InsertNextPoint(0, 0, 0)
data = vtkPolyData()
data.SetPoints(points)
mapper = raymappers.vtkCGTSphereMapper()
mapper.SetInputData(data)
mapper.SetRadius(0.5)
mapper.SetRadiusScale(2.0)
actor = vtkActor()
actor.SetMapper(mapper)
actor.GetProperty().LightingOff()
actor.GetProperty().SetColor(1, 1, 1)
ren = vtkRenderer()
ren.AddActor(actor)
win = vtkRenderWindow()
win.SetSize(400, 400)
win.AddRenderer(ren)
cam = ren.GetActiveCamera()
cam.SetPosition(0, 0, 10)
cam.SetFocalPoint(0, 0, 0)
cam.SetViewAngle(30)
ren.ResetCameraClippingRange()
win.Render()

grab = vtkWindowToImageFilter()
grab.SetInput(win)
grab.ReadFrontBufferOff()
grab.Update()
rgb = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
covered = int((rgb.max(axis=1) > 0).sum())
f = 200 / math.tan(math.radians(15))
radius_px = f / math.sqrt(100 - 1)
expected = math.pi * radius_px ** 2
rim = 2 * math.pi * radius_px
print("covered %d pixels, pi R^2 = %.1f, rim %.0f pixels" % (covered, expected, rim))
check(abs(covered - expected) < 0.1 * rim, "sphere covers pi R^2 pixels (radius 0.5 x scale 2)")

stats = mapper.GetStatistics()
print(stats.GetSummary())
check(stats.GetCounter("spheres") == 1, "statistics: one sphere")
check(stats.GetCounter("rays") == 400 * 400, "statistics: one ray per pixel")
check(stats.GetCounter("hits") == covered, "statistics: hits = covered pixels")
check(not stats.GetEffect("shading"), "statistics: lighting off, no shading effect")
check(stats.GetPhaseTime("trace") > 0, "statistics: trace phase timed")

reader = raymappers.vtkLAMMPSDumpReader()
reader.SetFileName(os.path.join(source, "Testing", "Data", "lammps_small.dump"))
reader.Update()
check(reader.GetOutput().GetNumberOfPoints() == 256, "LAMMPS dump reader: 256 atoms")

if failures:
    sys.exit(1)
print("all checks passed")
