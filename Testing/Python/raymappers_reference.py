"""The independent references of the pvpython tests: a representation's picture in a ParaView
view against the reference picture of the same scene, rendered by raymappers-reference
(Testing/References, no code of the mappers; its path from RAYMAPPERS_REFERENCE) from a
scene file written here from the view's own objects: the camera's world-to-NDC matrix, the
renderer's lights, the color and opacity maps (VTK's functions, sampled finely over the union
of their ranges) and the particles fetched from the pipeline. The comparison is the project's
(raymappers-compare-images --bound, RAYMAPPERS_COMPARE_IMAGES).
"""
import os
import subprocess

import numpy

from raymappers_testing import check

TRANSFER_SAMPLES = 8192


def camera_lines(view, size):
    camera = view.GetActiveCamera()
    m = camera.GetCompositeProjectionTransformMatrix(size[0] / size[1], -1, 1)
    values = ' '.join(repr(m.GetElement(r, c)) for r in range(4) for c in range(4))
    return ['camera %d %d %s' % (size[0], size[1], values)]


def light_lines(view):
    """The switched-on lights of the view's renderer as VTK transforms them (directional)."""
    lines = []
    lights = view.GetRenderer().GetLights()
    lights.InitTraversal()
    light = lights.GetNextItem()
    while light is not None:
        if light.GetSwitch():
            assert not light.GetPositional(), 'the reference has directional lights only'
            p = numpy.array(light.GetTransformedPosition())
            f = numpy.array(light.GetTransformedFocalPoint())
            d = (p - f) / numpy.linalg.norm(p - f)
            c = numpy.array(light.GetDiffuseColor()) * light.GetIntensity()
            lines.append('light %r %r %r %r %r %r' % tuple(list(d) + list(c)))
        light = lights.GetNextItem()
    return lines


def material_line(rep):
    s = rep.SpecularColor
    return 'material %r %r %r %r %r %r %r' % (rep.Ambient, rep.Diffuse, rep.Specular,
                                              rep.SpecularPower, s[0], s[1], s[2])


def transfer_lines(color, opacity, unit):
    """VTK's color and opacity functions (client-side objects) sampled over the union of
    their ranges; they clamp outside it, as the table does."""
    cr, orange = color.GetRange(), opacity.GetRange()
    lo, hi = min(cr[0], orange[0]), max(cr[1], orange[1])
    lines = ['transfer %r %r %r %d' % (lo, hi, unit, TRANSFER_SAMPLES)]
    rgb = [0.0, 0.0, 0.0]
    for v in numpy.linspace(lo, hi, TRANSFER_SAMPLES):
        color.GetColor(float(v), rgb)
        lines.append('%r %r %r %r' % (rgb[0], rgb[1], rgb[2], opacity.GetValue(float(v))))
    return lines


def node_lines(color, opacity, unit, n):
    """VTK's color and opacity functions as n nodes over the color map's range, for the
    piecewise-linear transfer function of 'render unstructured'."""
    lo, hi = color.GetRange()
    lines = ['nodes %r %d' % (unit, n)]
    rgb = [0.0, 0.0, 0.0]
    for v in numpy.linspace(lo, hi, n):
        color.GetColor(float(v), rgb)
        lines.append('%r %r %r %r %r' % (float(v), rgb[0], rgb[1], rgb[2],
                                         opacity.GetValue(float(v))))
    return lines


def leaves(data):
    """The non-composite datasets of fetched data."""
    if not data.IsA('vtkCompositeDataSet'):
        return [data]
    found, it = [], data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        found.append(it.GetCurrentDataObject())
        it.GoToNextItem()
    return found


def sphere_lines(source, color_array, lut, radii_of, opacities_of):
    """'sphere' lines of every point of every block of the source's data: radius
    radii_of(block)[i], coloured by the point array color_array (its first component)
    through the lookup table lut (a VTK object), opacity opacities_of(block)[i]."""
    from paraview import servermanager
    from vtkmodules.util.numpy_support import vtk_to_numpy
    lines = []
    for block in leaves(servermanager.Fetch(source)):
        if block is None or block.GetNumberOfPoints() == 0:
            continue
        xyz = vtk_to_numpy(block.GetPoints().GetData())
        values = point_values(block, color_array)
        c = [0.0, 0.0, 0.0]
        for x, r, v, a in zip(xyz, radii_of(block), values, opacities_of(block)):
            lut.GetColor(float(v), c)
            lines.append('sphere %r %r %r %r %r %r %r %r' % (
                x[0], x[1], x[2], float(r), c[0], c[1], c[2], float(a)))
    return lines


def point_values(block, name):
    """The first component of the block's point array `name`, as numpy."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    values = vtk_to_numpy(block.GetPointData().GetArray(name))
    return values[:, 0] if values.ndim > 1 else values


def render(lines, size, stem):
    """Writes the scene to stem.scene.txt, renders it; returns (W*H, 5) (premultiplied
    RGBA and window depth, rows from the bottom)."""
    scene, raw = stem + '.scene.txt', stem + '.raw'
    with open(scene, 'w') as out:
        out.write('\n'.join(lines) + '\n')
    subprocess.run([os.environ['RAYMAPPERS_REFERENCE'], scene, raw], check=True)
    return numpy.fromfile(raw, dtype=numpy.float64).reshape(size[0] * size[1], 5)


def write_over(reference, background, size, path):
    """The reference over the background as an 8-bit PNG (C + (1 - A) background)."""
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.util.numpy_support import numpy_to_vtk
    rgb = reference[:, :3] + (1 - reference[:, 3:4]) * numpy.array(background)
    rgb = numpy.clip(numpy.rint(255 * rgb), 0, 255).astype(numpy.uint8)
    image = vtkImageData()
    image.SetDimensions(size[0], size[1], 1)
    array = numpy_to_vtk(rgb, deep=True)
    image.GetPointData().SetScalars(array)
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()


def check_against(picture, reference_png, bound, what):
    """The picture (a PNG) against the reference PNG under bound = (rmse, differing
    fraction, tolerance, max error); prints the measured values."""
    rmse, differing, tolerance, worst = bound
    result = subprocess.run(
        [os.environ['RAYMAPPERS_COMPARE_IMAGES'], '--bound', repr(rmse), repr(differing),
         str(tolerance), str(worst), picture, reference_png],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check(result.returncode == 0, '%s against the reference: %s' % (what, result.stdout.strip()))
