"""Trace time of vtkCGTSphereMapper's secondary rays against a plain frame, both
accelerators: plain, translucent (Opacity 0.5), ambient occlusion with 4, 16 and 64
directions per point (one shot, no accumulation) and 4x4 soft shadows; the trace phase's
median of REPEAT renders after one to warm up, and the ratio to the plain frame.

usage (under Xvfb): pvpython secondary_rays_bench.py BUILD_DIR DATA.vtk SIZE [REPEAT [grid|embree]]
  e.g. pvpython Testing/Benchmarks/secondary_rays_bench.py build build/data/lammps_crack.vtk 1024"""
import os, sys, statistics
build, path, size = sys.argv[1], sys.argv[2], int(sys.argv[3])
repeat = int(sys.argv[4]) if len(sys.argv) > 4 else 5
accelerators = {"grid": (0,), "embree": (1,)}.get(sys.argv[5] if len(sys.argv) > 5 else "", (0, 1))
sys.path.insert(0, os.path.join(build, "lib", "python3", "dist-packages"))
from vtkmodules import vtkRenderingOpenGL2  # noqa
from vtkmodules.vtkRenderingCore import vtkActor, vtkRenderer, vtkRenderWindow
from vtkmodules.vtkIOLegacy import vtkPolyDataReader
import raymappers

reader = vtkPolyDataReader(); reader.SetFileName(path); reader.ReadAllScalarsOn(); reader.ReadAllVectorsOn(); reader.Update()
data = reader.GetOutput()
mapper = raymappers.vtkCGTSphereMapper(); mapper.SetInputData(data)
if data.GetPointData().GetArray("radius"):
    mapper.SetScaleArray("radius")
mapper.ScalarVisibilityOff()
actor = vtkActor(); actor.SetMapper(mapper)
ren = vtkRenderer(); ren.AddActor(actor)
win = vtkRenderWindow(); win.SetSize(size, size); win.AddRenderer(ren); win.SetMultiSamples(0)
win.SetOffScreenRendering(1)
ren.ResetCamera(); ren.ResetCameraClippingRange()
print("%s: %d points, %dx%d, median of %d" % (os.path.basename(path), data.GetNumberOfPoints(), size, size, repeat))

def trace():
    times = []
    for _ in range(repeat + 1):
        win.Render()
        times.append(mapper.GetStatistics().GetPhaseTime("trace"))
    return statistics.median(times[1:])

settings = [("plain", 1.0, 0, 0), ("opacity 0.5", 0.5, 0, 0), ("ao 4", 1.0, 4, 0),
            ("ao 16", 1.0, 16, 0), ("ao 64", 1.0, 64, 0), ("shadows 4x4", 1.0, 0, 4)]
for accel in accelerators:  # 0 grid, 1 Embree
    mapper.SetAccelerator(accel)
    plain = None
    for name, opacity, ao, shadows in settings:
        actor.GetProperty().SetOpacity(opacity)
        mapper.SetAmbientOcclusionSamples(ao)
        mapper.SetShadowRays(shadows)
        t = trace()
        plain = plain or t
        st = mapper.GetStatistics()
        print("  %-6s %-12s trace %8.1f ms  x%.2f  (sphere tests %d, cells %d)"
              % ("grid" if accel == 0 else "embree", name, t, t / plain,
                 st.GetCounter("sphere_tests"), st.GetCounter("cells")))
