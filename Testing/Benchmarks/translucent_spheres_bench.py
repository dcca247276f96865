"""Trace time of vtkCGTSphereMapper with Opacity 1 (the opaque path) and 0.9, 0.5, 0.2
(translucent compositing), both accelerators, on a PDB file's atoms (radius array "radius")
and on 200,000 random points in a cube (automatic radius); the trace phase's median of 5
renders after one to warm up, and the translucency counters.

usage (under Xvfb): pvpython translucent_spheres_bench.py BUILD_DIR DATA.pdb SIZE
  e.g. pvpython Testing/Benchmarks/translucent_spheres_bench.py build Data/2LYZ.pdb 512"""
import os, sys, statistics
build, path, size = sys.argv[1], sys.argv[2], int(sys.argv[3])
sys.path.insert(0, os.path.join(build, "lib", "python3", "dist-packages"))
import numpy
from vtkmodules import vtkRenderingOpenGL2  # noqa
from vtkmodules.vtkRenderingCore import vtkActor, vtkRenderer, vtkRenderWindow
from vtkmodules.vtkIOChemistry import vtkPDBReader
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.util.numpy_support import numpy_to_vtk
import raymappers

def pdb():
    reader = vtkPDBReader(); reader.SetFileName(path); reader.Update()
    return reader.GetOutput(), "radius"

def cloud(n):
    rng = numpy.random.default_rng(3)
    pts = vtkPoints(); pts.SetData(numpy_to_vtk(rng.uniform(-1, 1, (n, 3)), deep=True))
    data = vtkPolyData(); data.SetPoints(pts)
    return data, None

for name, (data, radius) in (("2LYZ", pdb()), ("random 200k", cloud(200000))):
    mapper = raymappers.vtkCGTSphereMapper(); mapper.SetInputData(data)
    if radius:
        mapper.SetScaleArray(radius)
    mapper.ScalarVisibilityOff()
    actor = vtkActor(); actor.SetMapper(mapper)
    ren = vtkRenderer(); ren.AddActor(actor)
    win = vtkRenderWindow(); win.SetSize(size, size); win.AddRenderer(ren); win.SetMultiSamples(0)
    ren.ResetCamera(); ren.GetActiveCamera().Dolly(1.3); ren.ResetCameraClippingRange()
    print("%s: %d points, %dx%d" % (name, data.GetNumberOfPoints(), size, size))
    for accel in (0, 1):
        mapper.SetAccelerator(accel)
        for opacity in (1.0, 0.9, 0.5, 0.2):
            actor.GetProperty().SetOpacity(opacity)
            times = []
            for _ in range(6):
                win.Render()
                times.append(mapper.GetStatistics().GetPhaseTime("trace"))
            st = mapper.GetStatistics()
            print("  %-6s opacity %.1f: trace %7.1f ms (median of 5), translucency %s, layers %d, queries %d (packets %d), terminated %d"
                  % ("grid" if accel == 0 else "embree", opacity, statistics.median(times[1:]),
                     "on" if st.GetEffect("translucency") else "off",
                     st.GetCounter("translucent_layers"), st.GetCounter("translucent_queries"),
                     st.GetCounter("packets"), st.GetCounter("translucent_terminated")))
