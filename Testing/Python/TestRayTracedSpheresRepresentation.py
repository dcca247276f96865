"""pvpython test of the "Ray-Traced Spheres" representation of the RayMappers plugin.

Usage (under Xvfb):
  pvpython TestRayTracedSpheresRepresentation.py PLUGIN DATA BASELINE OUTPUT
           [--color-array NAME] [--radius-array NAME]
           [--radius-scale S] [--size W H]

  PLUGIN    path of RayMappers.so
  DATA      a dataset: .pdb (PDBReader), .ex2/.exo/.e (ExodusIIReader), else OpenDataFile
  BASELINE  baseline PNG to compare the final image with
  OUTPUT    where the final screenshot is written

What it checks, failing with a non-zero exit code otherwise:
  1. the plugin adds "Ray-Traced Spheres" to the representation types of the data,
     and the representation's properties exist;
  2. the default Radius is 1% of the largest side of the data's bounding box;
  3. every point of the data is rendered (all points of all blocks, not only the surface);
  4. property changes are visible: a hidden representation draws nothing, the solid
     DiffuseColor is used without a color array, larger spheres (the radius array) cover
     more pixels;
  5. the spheres are where ParaView's own sphere glyphs of the same radii are (silhouette
     intersection over union > 0.98, same camera);
  6. the final image (colored by a point array, radii from a point array) matches the
     baseline under its thresholds (raymappers_testing.compare_with_baseline);
  7. the picture against the independent sphere reference (raymappers_reference: every
     pixel's ray against every sphere in closed form, VTK's Phong model under the view's
     lights) with the coherent grid's defaults, with Embree and with packets of 4, at
     200 x 200. Measured on this machine, the same for the three: 2LYZ rmse 0.0082 levels,
     max error 1, no pixel beyond 2 levels; disk_out_ref rmse 0.0041, max error 1, none.
     The bounds leave room for a few silhouette pixels and no more.
  8. translucency, against the reference's exact front-to-back composite of every sphere
     ('render translucent'): Opacity 0.5, then Opacity By Array (OpacityByArray,
     OpacityArray, OpacityTransferFunction as on Point Gaussian: the colour array through
     a ramp from 0.1 to 0.9) times Opacity 0.8; the statistics say "translucency" on, and
     off again with Opacity 1 and OpacityByArray off.
Side images (constant radius, hidden, solid color, glyph reference) are written next to
OUTPUT.
"""
import argparse
import math
import os
import sys

from paraview.simple import *  # noqa: F401,F403 (pvpython test)
import numpy
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, compare_with_baseline, failures, prepare_view  # noqa: E402
import raymappers_reference  # noqa: E402
import raymappers_testing  # noqa: E402

REPRESENTATION = 'Ray-Traced Spheres'
BACKGROUND = [0.1, 0.1, 0.15]
REFERENCE_SIZE = [200, 200]
# (rmse, differing fraction, tolerance, max error) against the reference.
REFERENCE_BOUNDS = (0.05, 0.0005, 2, 3)
# The translucent spheres against the reference: early termination leaves out at most 1/512
# of every channel (SphereRenderer.h), so a level's rounding may differ more often.
TRANSLUCENT_BOUNDS = (0.75, 0.001, 2, 3)



def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('plugin')
    parser.add_argument('data')
    parser.add_argument('baseline')
    parser.add_argument('output')
    parser.add_argument('--color-array', default='residue',
                        help='point array to color by')
    parser.add_argument('--radius-array', default='atom_type',
                        help='1-component point array giving the radii')
    parser.add_argument('--radius-scale', type=float, default=0.15,
                        help='Radius Scale used with the radius array')
    parser.add_argument('--size', type=int, nargs=2, default=[400, 400])
    return parser.parse_args()


def open_data(path):
    ext = os.path.splitext(path)[1].lower()
    if ext == '.pdb':
        return PDBReader(FileName=path)
    if ext in ('.ex2', '.exo', '.e', '.exii'):
        return ExodusIIReader(FileName=path)
    return OpenDataFile(path)


def coverage(png, background):
    """Fraction of the pixels of a PNG that differ from the background color."""
    return float(silhouette(png, background).mean())


def silhouette(png, background):
    """Mask of the pixels of a PNG that differ from the background color."""
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    pixels = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)
    bg = [int(round(255 * c)) for c in background]
    return (abs(pixels - bg) > 3).any(axis=1)


def mean_foreground_color(png):
    """Mean RGB of the pixels of a PNG that differ from the background."""
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    pixels = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())[:, :3].astype(float)
    mask = silhouette(png, BACKGROUND)
    return pixels[mask].mean(axis=0) if mask.any() else pixels[0] * 0


def png_pixels(png):
    """The pixels of a PNG as an array."""
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    return vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars()).copy()


def glyph_reference(source, view, radius_array, radius_scale, path, size):
    """ParaView's own sphere glyphs (tessellated spheres, same radii and camera): the
    reference for where the ray-traced spheres must be."""
    glyphs = Glyph(Input=source, GlyphType='Sphere')
    glyphs.GlyphMode = 'All Points'
    glyphs.ScaleArray = ['POINTS', radius_array]
    glyphs.ScaleFactor = 2.0 * radius_scale  # the glyph sphere's radius is 0.5
    glyphs.GlyphType.ThetaResolution = 32
    glyphs.GlyphType.PhiResolution = 32
    glyph_rep = Show(glyphs, view)
    glyph_rep.ColorArrayName = ['POINTS', '']
    Render(view)
    SaveScreenshot(path, view, ImageResolution=size, TransparentBackground=0)
    Hide(glyphs, view)
    mask = silhouette(path, BACKGROUND)
    Delete(glyphs)
    return mask


def screenshot(view, path, size):
    Render(view)
    SaveScreenshot(path, view, ImageResolution=size, TransparentBackground=0)
    return coverage(path, BACKGROUND)



def reference_spheres(args, source, rep, opacity_of):
    """The reference's sphere lines: every point of every block, radius RadiusScale times
    the radius array, coloured by the color map, opacity opacity_of(colour value)."""
    return raymappers_reference.sphere_lines(
        source, args.color_array, rep.LookupTable.GetClientSideObject(),
        lambda block: raymappers_reference.point_values(block, args.radius_array)
        * args.radius_scale,
        lambda block: [opacity_of(float(v))
                       for v in raymappers_reference.point_values(block, args.color_array)])


def check_reference(args, source, view, rep, stem):
    """The picture against the reference spheres: every point of every block, radius
    RadiusScale times the radius array, coloured by the color map."""
    view.ViewSize = REFERENCE_SIZE
    spheres = reference_spheres(args, source, rep, lambda v: 1.0)
    # The accelerator and the packets change nothing in the reference: one picture for all.
    Render(view)
    lines = raymappers_reference.camera_lines(view, REFERENCE_SIZE)
    lines += raymappers_reference.light_lines(view)
    lines += [raymappers_reference.material_line(rep), 'render spheres'] + spheres
    expected = raymappers_reference.render(lines, REFERENCE_SIZE, stem + '-reference')
    raymappers_reference.write_over(expected, BACKGROUND, REFERENCE_SIZE, stem + '-reference.png')
    settings = (('defaults', {}), ('Embree', {'Accelerator': 1}), ('packets of 4', {'PacketSize': 4}))
    for name, properties in settings:
        before = raymappers_testing.property_values(rep, properties)
        for key, value in properties.items():
            setattr(rep, key, value)
        picture = stem + '-reference-test-%s.png' % name.replace(' ', '-')
        Render(view)
        SaveScreenshot(picture, view, ImageResolution=REFERENCE_SIZE, TransparentBackground=0)
        raymappers_reference.check_against(picture, stem + '-reference.png', REFERENCE_BOUNDS,
                                           'Ray-Traced Spheres, ' + name)
        for key, value in before.items():
            setattr(rep, key, value)
    view.ViewSize = args.size


def check_translucent(args, source, view, rep, stem, name, opacity_of):
    """The picture against the reference composite of the translucent spheres."""
    view.ViewSize = REFERENCE_SIZE
    Render(view)
    lines = raymappers_reference.camera_lines(view, REFERENCE_SIZE)
    lines += raymappers_reference.light_lines(view)
    lines += [raymappers_reference.material_line(rep), 'render translucent']
    lines += reference_spheres(args, source, rep, opacity_of)
    tag = stem + '-translucent-' + name.replace(' ', '-')
    expected = raymappers_reference.render(lines, REFERENCE_SIZE, tag + '-reference')
    raymappers_reference.write_over(expected, BACKGROUND, REFERENCE_SIZE, tag + '-reference.png')
    SaveScreenshot(tag + '.png', view, ImageResolution=REFERENCE_SIZE, TransparentBackground=0)
    raymappers_reference.check_against(tag + '.png', tag + '-reference.png', TRANSLUCENT_BOUNDS,
                                       'Ray-Traced Spheres, ' + name)
    stats = raymappers_testing.statistics(rep, 'SpheresRenderStatistics')
    check(stats.get('translucency') == 'on' and stats.get('translucent_layers', 0) > 0,
          '%s: translucency on, %d layers composited' % (name, stats.get('translucent_layers', 0)))
    view.ViewSize = args.size


def check_translucency(args, source, view, rep, stem):
    """Opacity, then Opacity By Array (Point Gaussian's property names), then neither."""
    rep.Opacity = 0.5
    check_translucent(args, source, view, rep, stem, 'Opacity 0.5', lambda v: 0.5)
    lo, hi = source.PointData[args.color_array].GetRange()
    rep.OpacityByArray = 1
    rep.OpacityArray = ['POINTS', args.color_array]
    rep.OpacityTransferFunction.Points = [lo, 0.1, 0.5, 0.0, hi, 0.9, 0.5, 0.0]
    rep.Opacity = 0.8
    function = rep.OpacityTransferFunction.GetClientSideObject()
    check_translucent(args, source, view, rep, stem, 'Opacity By Array x 0.8',
                      lambda v: 0.8 * function.GetValue(v))
    rep.OpacityByArray = 0
    rep.Opacity = 1.0
    Render(view)
    stats = raymappers_testing.statistics(rep, 'SpheresRenderStatistics')
    check(stats.get('translucency') == 'off' and stats.get('translucent_layers') == 0,
          'Opacity 1 and Opacity By Array off: the opaque path (translucency %s, %s layers)'
          % (stats.get('translucency'), stats.get('translucent_layers')))


def main():
    args = parse_args()
    out_dir = os.path.dirname(os.path.abspath(args.output))
    if out_dir == os.path.dirname(os.path.abspath(args.baseline)):
        # A failed comparison writes the test image next to OUTPUT under the baseline's
        # name: it must not land on the baseline itself.
        print('FAIL  OUTPUT must not be in the baseline folder')
        return 2
    os.makedirs(out_dir, exist_ok=True)
    stem = os.path.splitext(os.path.abspath(args.output))[0]

    LoadPlugin(args.plugin, remote=False, ns=globals())

    source = open_data(args.data)
    source.UpdatePipeline()

    view = CreateView('RenderView')
    try:
        return run_checks(args, source, view, stem)
    finally:
        # Deleting the view before the interpreter exits avoids pvpython 5.11's
        # "X Error ... GLXBadContext" at exit (which turns the exit code into 1).
        Delete(view)


def run_checks(args, source, view, stem):
    info = source.GetDataInformation()
    n_points = info.GetNumberOfPoints()
    bounds = info.GetBounds()
    extent = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])
    check(n_points > 0, 'the data has points (%d)' % n_points)

    # No FXAA: it would blend the edges of bright spheres into the background and blur the
    # silhouette comparison with the glyphs.
    prepare_view(view, args.size, BACKGROUND)

    rep = Show(source, view)
    available = rep.Representation.Available
    check(REPRESENTATION in available,
          '"%s" is a representation type of %s' % (REPRESENTATION, rep.GetXMLName()))
    if REPRESENTATION not in available:
        return 1
    rep.SetRepresentationType(REPRESENTATION)
    check(rep.Representation == REPRESENTATION, 'the representation is set')

    for name in ('Radius', 'UseRadiusArray', 'RadiusArray', 'RadiusScale',
                 'ColorArrayName', 'LookupTable', 'MapScalars', 'DiffuseColor',
                 'AmbientColor', 'Opacity', 'Ambient', 'Diffuse', 'Specular',
                 'SpecularPower', 'SpecularColor'):
        check(rep.GetProperty(name) is not None, 'property %s exists' % name)

    check(rep.Radius == 0.0, 'default Radius 0: automatic')
    Render(view)
    points = [vtk_to_numpy(leaf.GetPoints().GetData())
              for leaf in raymappers_reference.leaves(servermanager.Fetch(source)) if leaf.GetNumberOfPoints()]
    raymappers_testing.check_automatic_size(
        rep, 'RadiusInUse', numpy.concatenate(points), 0.5, 'radius')
    check(rep.UseRadiusArray == 0 and rep.RadiusScale == 1.0,
          'defaults UseRadiusArray=0, RadiusScale=1')

    # Coloring by a point array through the lookup table.
    ColorBy(rep, ('POINTS', args.color_array))
    rep.RescaleTransferFunctionToDataRange(True, False)
    lut = GetColorTransferFunction(args.color_array)
    lut.ApplyPreset('Cool to Warm', True)
    rep.SetScalarBarVisibility(view, False)
    rep.Specular = 0.4
    rep.SpecularPower = 40.0

    # Constant radius: the default one. (The first Render of paraview.simple resets the
    # camera: render once before placing it.)
    Render(view)
    view.ResetCamera(False)
    view.GetActiveCamera().Dolly(1.4)
    Render(view)

    # Every point of the data is rendered, not only the surface.
    rendered = rep.SMProxy.GetRepresentedDataInformation()
    check(rendered.GetNumberOfPoints() == n_points,
          'all %d points are rendered (%d)' % (n_points, rendered.GetNumberOfPoints()))

    small = screenshot(view, stem + '-constant-radius.png', args.size)
    check(small > 0.005, 'the spheres are drawn (%.1f%% of the pixels)' % (100 * small))

    # Hidden: nothing is drawn.
    Hide(source, view)
    hidden = screenshot(view, stem + '-hidden.png', args.size)
    check(hidden == 0.0, 'a hidden representation draws nothing (%.2f%%)' % (100 * hidden))
    Show(source, view)
    check(rep.Representation == REPRESENTATION, 'the representation survives Hide/Show')

    # No color array: the solid DiffuseColor (red here) colors the spheres.
    ColorBy(rep, None)
    rep.DiffuseColor = [1.0, 0.0, 0.0]
    screenshot(view, stem + '-solid-color.png', args.size)
    red = mean_foreground_color(stem + '-solid-color.png')
    check(red[0] > 4 * max(red[1], red[2], 1.0),
          'without a color array the spheres are DiffuseColor red (mean %s)'
          % [round(c) for c in red])
    rep.DiffuseColor = [1.0, 1.0, 1.0]
    ColorBy(rep, ('POINTS', args.color_array))
    rep.SetScalarBarVisibility(view, False)

    # Radii from a point array: the change must be visible (more pixels covered).
    rep.UseRadiusArray = 1
    rep.RadiusArray = ['POINTS', args.radius_array]
    rep.RadiusScale = args.radius_scale
    large = screenshot(view, args.output, args.size)
    check(large > small * 1.2,
          'radius array x %g covers more pixels: %.1f%% > %.1f%%'
          % (args.radius_scale, 100 * large, 100 * small))

    # The spheres are where ParaView's sphere glyphs of the same radii are: the
    # silhouettes agree (up to the glyphs' tessellation).
    ours = silhouette(args.output, BACKGROUND)
    Hide(source, view)
    theirs = glyph_reference(source, view, args.radius_array, args.radius_scale,
                             stem + '-glyph-reference.png', args.size)
    Show(source, view)
    union = (ours | theirs).sum()
    iou = (ours & theirs).sum() / union if union else 0.0
    check(iou > 0.98, 'silhouette matches ParaView sphere glyphs (IoU %.4f)' % iou)

    if not compare_with_baseline(args.output, args.baseline):
        failures.append('baseline comparison')
    check_reference(args, source, view, rep, stem)
    check_translucency(args, source, view, rep, stem)

    # The accelerator and its parameters change the speed, not the picture: Embree's BVH
    # and the coherent grid with other packet sizes and grid resolutions draw the same
    # silhouette.
    for name, value in (('Accelerator', 1), ('Accelerator', 0), ('PacketSize', 4),
                        ('Lambda', 3.0), ('MacrocellSize', 2)):
        setattr(rep, name, value)
        variant = stem + '-variant.png'
        screenshot(view, variant, args.size)
        other = silhouette(variant, BACKGROUND)
        union = (ours | other).sum()
        same = (ours & other).sum() / union if union else 0.0
        check(same > 0.999, '%s = %s draws the same spheres (IoU %.5f)' % (name, value, same))

    # Ambient occlusion darkens the spheres where they crowd each other.
    def mean_level(png):
        rgb = mean_foreground_color(png)
        return sum(rgb) / 3.0

    rep.AmbientOcclusionSamples = 0

    plain = stem + '-ao-off.png'
    screenshot(view, plain, args.size)
    rep.AmbientOcclusionSamples = 16
    occluded = stem + '-ao-16.png'
    screenshot(view, occluded, args.size)
    check(mean_level(occluded) < 0.97 * mean_level(plain),
          'ambient occlusion darkens the spheres (%.1f < %.1f)'
          % (mean_level(occluded), mean_level(plain)))
    # Progressive: 5 of the 16 rays per render. Four renders of the still view give 5, 10,
    # 15, 16 rays, and the screenshot after them (which renders again, and would restart the
    # rays if it moved the camera) is the one-shot picture. Seen failing with no render
    # before the screenshot (its own renders reach 10 rays), passing from two on.
    rep.AmbientOcclusionSamplesPerFrame = 5
    for _ in range(4):
        Render(view)
    progressive = stem + '-ao-16-progressive.png'
    screenshot(view, progressive, args.size)
    same = (png_pixels(progressive) == png_pixels(occluded)).all()
    check(same, 'progressive occlusion: renders of a still view end in the one-shot picture')
    rep.AmbientOcclusionSamplesPerFrame = 16
    screenshot(view, progressive, args.size)
    check((png_pixels(progressive) == png_pixels(occluded)).all(),
          'progressive occlusion: a budget of all 16 rays is the one-shot picture')
    rep.AmbientOcclusionSamplesPerFrame = 0
    rep.AmbientOcclusionSamples = 0

    # Soft shadows from the automatic area light darken parts of the spheres too.
    rep.ShadowRays = 3
    shadowed = stem + '-shadows.png'
    screenshot(view, shadowed, args.size)
    check(mean_level(shadowed) < 0.97 * mean_level(plain),
          'soft shadows darken the spheres (%.1f < %.1f)'
          % (mean_level(shadowed), mean_level(plain)))
    rep.ShadowLightIntensity = 0.5
    dimmer = stem + '-shadows-dim.png'
    screenshot(view, dimmer, args.size)
    check(mean_level(dimmer) < mean_level(shadowed),
          'a dimmer shadow light darkens the spheres (%.1f < %.1f)'
          % (mean_level(dimmer), mean_level(shadowed)))
    rep.ShadowLightIntensity = 1.0
    rep.ShadowRays = 0

    # Range culling on the colour array: the upper half of its values leaves fewer spheres.
    rep.RangeArray1 = ['POINTS', args.color_array]
    values = source.PointData[args.color_array].GetRange()
    middle = values[0] + 0.5 * (values[1] - values[0])
    rep.Range1 = [middle, values[1]]
    culled = stem + '-range.png'
    culled_cover = screenshot(view, culled, args.size)
    rep.Range1 = [values[0], values[1]]
    full_cover = screenshot(view, stem + '-range-full.png', args.size)
    check(culled_cover < 0.9 * full_cover,
          'the upper half of the values draws fewer spheres (%.1f%% < %.1f%%)'
          % (100 * culled_cover, 100 * full_cover))
    # All ranges must hold: range 4 keeps the lower half of the same array, range 1 the
    # upper half, so only values at the middle itself could remain.
    rep.Range1 = [middle, values[1]]
    rep.RangeArray4 = ['POINTS', args.color_array]
    rep.Range4 = [values[0], middle]
    both_cover = screenshot(view, stem + '-range-both.png', args.size)
    check(both_cover < 0.5 * culled_cover,
          'ranges 1 and 4 together draw less than range 1 alone (%.1f%% < half of %.1f%%)'
          % (100 * both_cover, 100 * culled_cover))
    rep.RangeArray4 = ['POINTS', 'None']
    check(abs(screenshot(view, stem + '-range-one.png', args.size) - culled_cover) < 1e-9,
          'turning range 4 off draws what range 1 alone drew')
    rep.RangeArray1 = ['POINTS', 'None']

    if failures:
        print('%d check(s) failed' % len(failures))
        return 1
    print('all checks passed')
    return 0


if __name__ == '__main__':
    code = main()
    # Exit explicitly only on failure: under `mpirun pvbatch`, sys.exit(0) on rank 0 skips
    # ParaView's MPI finalization and leaves the other ranks waiting.
    if code:
        sys.exit(code)
