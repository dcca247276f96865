"""Install.PackageLoads: `cmake --install` into a scratch root laid out like /usr, then
Debian's pvpython and pvbatch load RayMappers from there alone.

ParaView 5.11 reads <folder of the executable>/paraview.conf (vtkPVPluginTracker::
LoadPluginConfigurationXMLs). To make the scratch root stand for /usr, the test copies
/usr/bin/pvpython3.11 and pvbatch3.11 into <root>/usr/bin: they then read <root>/usr/bin/
paraview.conf exactly as /usr/bin/pvpython reads /usr/bin/paraview.conf. The environment
has no PV_PLUGIN_PATH, PV_PLUGIN_CONFIG_FILE or build-tree path. PYTHONPATH names
<root>/usr/lib/python3/dist-packages only because the root is a scratch one: under /usr
that folder is already on pvpython's sys.path (checked here too).

usage: TestInstalledPackage.py BUILD_DIR SCRATCH_DIR
"""
import os
import shutil
import subprocess
import sys

build, scratch = sys.argv[1], sys.argv[2]
root = os.path.join(scratch, "root")
shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)
env = {k: v for k, v in os.environ.items()
       if not k.startswith("PV_PLUGIN") and k not in ("PYTHONPATH", "LD_LIBRARY_PATH")}
subprocess.run(["cmake", "--install", build, "--prefix", "/usr"], check=True,
               env=dict(env, DESTDIR=root), stdout=subprocess.DEVNULL)

site = os.path.join(root, "usr", "lib", "python3", "dist-packages")
bindir = os.path.join(root, "usr", "bin")
for name in ("pvpython3.11", "pvbatch3.11"):
    shutil.copy2(os.path.join("/usr/bin", name), os.path.join(bindir, name))

# Where a /usr install puts the package is on Debian's pvpython path.
out = subprocess.run(["pvpython", "-c", "import sys; print(sys.path)"], env=env,
                     capture_output=True, text=True, check=True).stdout
assert "/usr/lib/python3/dist-packages" in out, out

check = r'''
import os, sys
root = sys.argv[1]
import raymappers
assert os.path.realpath(raymappers.__file__).startswith(os.path.realpath(root)), raymappers.__file__
mapper = raymappers.vtkCGTSphereMapper()
assert mapper.GetClassName() == "vtkCGTSphereMapper"
from paraview.simple import *
from paraview.modules.vtkRemotingCore import vtkPVPluginTracker
tracker = vtkPVPluginTracker.GetInstance()
plugins = {tracker.GetPluginName(i): i for i in range(tracker.GetNumberOfPlugins())}
assert "RayMappers" in plugins, plugins
i = plugins["RayMappers"]
path = os.path.realpath(tracker.GetPluginFileName(i))
assert path.startswith(os.path.realpath(root)), path
assert tracker.GetPluginAutoLoad(i) and tracker.GetPluginLoaded(i), "not auto-loaded"
sphere = Sphere()
view = CreateRenderView()
view.ViewSize = [200, 200]
view.OrientationAxesVisibility = 0
rep = Show(sphere, view)
rep.SetRepresentationType("Ray-Traced Spheres")
assert rep.Representation == "Ray-Traced Spheres", rep.Representation
Render(view)
shot = os.path.join(sys.argv[2], "installed.png")
SaveScreenshot(shot, view, ImageResolution=[200, 200])
# The frame shows spheres: with nothing else in the view, pixels that differ from the
# background (the corner). At the default radius (1% of the bounds) the Sphere source's 50
# points cover about 0.5% of a 200 x 200 view; nothing drawn leaves 0.
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy
reader = vtkPNGReader()
reader.SetFileName(shot)
reader.Update()
pixels = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)
drawn = (abs(pixels - pixels[0]).max(axis=1) > 10).mean()
assert drawn > 0.002, "the installed plugin drew %.3f of the pixels" % drawn
print("INSTALLED-OK", path, "drawn %.3f" % drawn)
'''
script = os.path.join(scratch, "check_installed.py")
with open(script, "w") as f:
    f.write(check)
for exe in ("pvpython3.11", "pvbatch3.11"):
    run = subprocess.run([os.path.join(bindir, exe), script, root, scratch],
                         env=dict(env, PYTHONPATH=site), capture_output=True, text=True,
                         timeout=120)
    print(exe, run.returncode, run.stdout[-2000:], run.stderr[-2000:])
    if run.returncode != 0 or "INSTALLED-OK" not in run.stdout:
        sys.exit("%s failed on the installed tree" % exe)
print("PASS")
