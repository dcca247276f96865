"""What the pvpython tests of the RayMappers representations share: a check log, reading
screenshots, a representation's statistics, the project's baseline comparison, and the
messages of VTK's output window."""
import os
import re

from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy

failures = []


def check(condition, message):
    """Prints 'ok' or 'FAIL' and the message (after the OutputWindowMessages block it is made
    in, if any) and counts a failure."""
    line = ('ok    ' if condition else 'FAIL  ') + message
    if OutputWindowMessages.held is None:
        print(line)
    else:
        OutputWindowMessages.held.append(line)
    if not condition:
        failures.append(message)


class OutputWindowMessages:
    """The errors and warnings that reach VTK's output window inside the block (texts in
    `errors` and `warnings`, their number in `count`). pvpython sends print() there too, so
    the lines of checks made inside the block are held and printed after it."""
    held = None

    def __enter__(self):
        OutputWindowMessages.held = []
        self.window = vtkStringOutputWindow()
        self.previous = vtkOutputWindow.GetInstance()
        vtkOutputWindow.SetInstance(self.window)
        return self

    def __exit__(self, *exc):
        vtkOutputWindow.SetInstance(self.previous)
        lines, OutputWindowMessages.held = OutputWindowMessages.held, None
        for line in lines:
            print(line)
        text = self.window.GetOutput()
        self.errors = re.findall(r"ERROR: In [^\n]*\n(.*?)\n\n", text, re.S)
        self.warnings = re.findall(r"Warning: In [^\n]*\n(.*?)\n\n", text, re.S)
        self.count = text.count("ERROR: In ") + text.count("Warning: In ")
        return False


def pixels(png):
    """RGB of a PNG as an (n, 3) float array."""
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    return vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())[:, :3].astype(float)


def screenshot(view, path, size):
    from paraview.simple import Render, SaveScreenshot
    Render(view)
    SaveScreenshot(path, view, ImageResolution=size, TransparentBackground=0)
    return pixels(path)


def prepare_view(view, size, background):
    """A plain view for image checks: the size, a solid background, no orientation axes and
    no FXAA (on by default in 5.11, it blends edges into the background)."""
    from paraview.simple import SetActiveView
    view.ViewSize = size
    view.OrientationAxesVisibility = 0
    if view.GetProperty('UseFXAA') is not None:
        view.UseFXAA = 0
    if view.GetProperty('UseColorPaletteForBackground') is not None:
        view.UseColorPaletteForBackground = 0
    view.Background = background
    SetActiveView(view)


def rmse(a, b):
    return float(((a - b) ** 2).mean() ** 0.5)


def statistics(rep, name):
    """The mapper's statistics of the last render, from the information property `name`:
    {counter or phase: value, effect: 'on' | 'off'}."""
    rep.SMProxy.UpdatePropertyInformation()
    text = rep.SMProxy.GetProperty(name).GetElement(0)
    values = {}
    for line in text.splitlines():
        kind, key, value = line.split()
        values[key] = value if kind == 'effect' else float(value)
    return values


def median_nearest_neighbour(points):
    """The median over all finite points of the distance to the nearest distinct point, by
    brute force (the reference for the automatic particle sizes; it shares nothing with
    ParticleSpacing.h, which estimates the same median on a sample)."""
    import numpy
    p = numpy.asarray(points, dtype=float)
    p = p[numpy.isfinite(p).all(axis=1)]
    nearest = []
    for start in range(0, len(p), 256):
        d = ((p[start:start + 256, None, :] - p[None, :, :]) ** 2).sum(axis=2)
        d[d == 0] = numpy.inf
        nearest.append(d.min(axis=1))
    nearest = numpy.concatenate(nearest)
    return float(numpy.median(numpy.sqrt(nearest[numpy.isfinite(nearest)])))


def check_automatic_size(rep, name, points, per_spacing, what):
    """The information property `name` (the size in use) is `per_spacing` times the
    brute-force median nearest-neighbour distance of `points`, within 5% (the kernel
    estimates the median on a sample of 1024)."""
    rep.SMProxy.UpdatePropertyInformation()
    in_use = rep.SMProxy.GetProperty(name).GetElement(0)
    expected = per_spacing * median_nearest_neighbour(points)
    check(abs(in_use - expected) <= 0.05 * expected,
          'automatic %s %.6g is %g x the median neighbour distance (%.6g)'
          % (what, in_use, per_spacing, expected))


def copy_camera(view, renderer):
    """The view's camera (clipping range included) on a plain VTK renderer."""
    source = view.GetActiveCamera()
    camera = renderer.GetActiveCamera()
    camera.SetPosition(source.GetPosition())
    camera.SetFocalPoint(source.GetFocalPoint())
    camera.SetViewUp(source.GetViewUp())
    camera.SetViewAngle(source.GetViewAngle())
    camera.SetClippingRange(source.GetClippingRange())


def render_to_png(renderer, size, path):
    """Renders a plain VTK renderer off screen into a PNG; returns its pixels."""
    from vtkmodules import vtkRenderingOpenGL2  # noqa: F401
    from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkWindowToImageFilter
    from vtkmodules.vtkIOImage import vtkPNGWriter
    win = vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(size)
    win.AddRenderer(renderer)
    win.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.ReadFrontBufferOff()
    grab.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    win.Finalize()
    return pixels(path)


def compare_with_baseline(output, baseline):
    """The project's image comparison of every image test (Testing/ImageComparison, run as
    raymappers-compare-images, whose path ctest gives in RAYMAPPERS_COMPARE_IMAGES): the
    picture against its baseline under the baseline's thresholds
    (Testing/Data/Baseline/thresholds.txt). `output` stays where the check of the check
    (raymappers-compare-images --perturbations) reads it."""
    import subprocess
    tool = os.environ.get('RAYMAPPERS_COMPARE_IMAGES')
    if not tool:
        print('FAIL  RAYMAPPERS_COMPARE_IMAGES is not set: no image comparison')
        return False
    result = subprocess.run([tool, output, baseline], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    print(('ok    ' if result.returncode == 0 else 'FAIL  ') + result.stdout.strip())
    return result.returncode == 0


def property_values(proxy, names):
    """Plain copies of a proxy's property values (paraview.simple hands back live property
    objects for enumerations and vectors, which change with the property)."""
    from paraview import servermanager
    values = {}
    for name in names:
        value = proxy.GetPropertyValue(name)
        if isinstance(value, servermanager.EnumerationProperty):
            value = value.GetData()
        elif isinstance(value, servermanager.VectorProperty):
            value = list(value)
        values[name] = value
    return values


def finish():
    """Exit code: 0 when every check passed."""
    if failures:
        print('%d check(s) failed' % len(failures))
        return 1
    print('all checks passed')
    return 0
