"""pvpython: the "SPH Volume" representation of the RayMappers plugin on a PySPH dam break.

Drives the representation as a ParaView user would (legacy VTK reader, the velocity
magnitude, ParaView's color and opacity maps) and checks:
- "SPH Volume" is offered for the particles, with its panel's properties;
- with PySPH's kernel (Wendland C2), h, m and rho arrays, the picture is the one
  vtkSPHVolumeMapper draws in a plain VTK pipeline with the same settings and camera;
- unnormalized sampling changes the picture; contour shading adds contour samples and no
  gradients; Shade computes gradients;
- an interactive render over the frame budget reduces the sampling rate, the still render
  after it is the exact picture again;
- a hidden representation draws nothing; the image matches its baseline;
- the picture against the independent SPH reference (raymappers_reference: its own kernels,
  uniform converged sampling, every particle), at the representation's quality defaults,
  unnormalized and with 32 samples per support, at 160 x 160. Measured on this machine
  (levels of 255; differing: beyond 2 levels): defaults rmse 0.53, max 13, 0.90%;
  unnormalized 0.41, max 3, 0.13%; 32 samples per support 0.47, max 13, 0.48%. The bounds
  are 1.5 times these (REFERENCE_BOUNDS).

usage: pvpython TestSPHVolumeRepresentation.py PLUGIN BUILD_DIR DATA_FILE BASELINE OUTPUT
"""
import os
import sys

from paraview.simple import (  # noqa: E402
    ColorBy, CreateView, Delete, GetColorTransferFunction, GetOpacityTransferFunction, Hide,
    LegacyVTKReader, LoadPlugin, Render, Show)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import (  # noqa: E402
    check, compare_with_baseline, copy_camera, failures, finish, prepare_view, render_to_png, rmse)
import raymappers_testing  # noqa: E402
import raymappers_reference  # noqa: E402

REPRESENTATION = 'SPH Volume'
BACKGROUND = [0.1, 0.1, 0.15]
SIZE = [320, 240]
UNIT = 0.1
REFERENCE_SIZE = [160, 160]
# (rmse, differing fraction, tolerance, max error) against the reference.
REFERENCE_BOUNDS = {
    'defaults': (0.8, 0.0135, 2, 20),
    'unnormalized': (0.61, 0.002, 2, 5),
    '32 samples per support': (0.71, 0.0072, 2, 20),
}


def plain_vtk_image(particles, view, lut, opacity, path):
    """The same particles drawn by vtkSPHVolumeMapper in a plain VTK pipeline."""
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkVolume, vtkVolumeProperty
    import raymappers

    mapper = raymappers.vtkSPHVolumeMapper()
    mapper.SetInputData(particles)
    mapper.SetKernel(raymappers.VTK_SPH_KERNEL_WENDLAND_C2)
    mapper.SetSmoothingLengthArrayName('h')
    mapper.SetMassArrayName('m')
    mapper.SetDensityArrayName('rho')
    mapper.SetValueArrayName('vmag')
    prop = vtkVolumeProperty()
    prop.SetColor(lut)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(UNIT)
    prop.SetInterpolationTypeToLinear()
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    ren = vtkRenderer()
    ren.SetBackground(BACKGROUND)
    ren.AddVolume(volume)
    copy_camera(view, ren)
    return render_to_png(ren, SIZE, path), mapper.GetStatistics().GetCounter('particles')


def shot(view, path):
    return raymappers_testing.screenshot(view, path, SIZE)


def statistics(rep):
    return raymappers_testing.statistics(rep, 'SPHRenderStatistics')


def sph_scene(view, particles, lut, opacity, normalized):
    """The reference scene of the dam break: Wendland C2 (support 2h), V = m / rho, Q = vmag,
    a step of a sixty-fourth of the smallest support."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    pd = particles.GetPointData()
    xyz = vtk_to_numpy(particles.GetPoints().GetData())
    h, m, rho, q = (vtk_to_numpy(pd.GetArray(n)) for n in ('h', 'm', 'rho', 'vmag'))
    lines = raymappers_reference.camera_lines(view, REFERENCE_SIZE)
    lines += raymappers_reference.transfer_lines(lut, opacity, UNIT)
    lines.append('sph wendland %s %r' % ('normalized' if normalized else 'unnormalized',
                                         2 * float(h.min()) / 64))
    lines += ['sph_particle %r %r %r %r %r %r' % (x[0], x[1], x[2], 2 * hh, qq, mm / rr)
              for x, hh, qq, mm, rr in zip(xyz, h, q, m, rho)]
    lines.append('render sph')
    return lines


def check_reference(view, rep, particles, lut, opacity, stem):
    view.ViewSize = REFERENCE_SIZE
    settings = (('defaults', {}, True), ('unnormalized', {'SPHNormalization': 'Unnormalized'}, False),
                ('32 samples per support', {'SPHSamplesPerSupport': 32.0}, True))
    references = {}
    for name, properties, normalized in settings:
        before = raymappers_testing.property_values(rep, properties)
        for key, value in properties.items():
            setattr(rep, key, value)
        picture = stem + '-reference-test-%s.png' % name.replace(' ', '-')
        raymappers_testing.screenshot(view, picture, REFERENCE_SIZE)
        if normalized not in references:
            expected = raymappers_reference.render(
                sph_scene(view, particles, lut, opacity, normalized), REFERENCE_SIZE,
                stem + '-reference-%s' % ('normalized' if normalized else 'unnormalized'))
            references[normalized] = stem + '-reference-%s.png' % (
                'normalized' if normalized else 'unnormalized')
            raymappers_reference.write_over(expected, BACKGROUND, REFERENCE_SIZE,
                                            references[normalized])
        raymappers_reference.check_against(picture, references[normalized],
                                           REFERENCE_BOUNDS[name], 'SPH Volume, ' + name)
        for key, value in before.items():
            setattr(rep, key, value)
    view.ViewSize = SIZE


def run_checks(view, source, stem, build_dir, output, baseline):
    prepare_view(view, SIZE, BACKGROUND)
    rep = Show(source, view)
    check(REPRESENTATION in rep.Representation.Available,
          '"%s" is offered for %s' % (REPRESENTATION, rep.GetXMLName()))
    rep.SetRepresentationType(REPRESENTATION)
    for name in ('SPHKernel', 'SPHSmoothingLength', 'SPHSmoothingLengthArray', 'SPHMassArray',
                 'SPHDensityArray', 'SPHVolumeArray', 'SPHNormalization', 'SPHContourShading',
                 'SPHContourColor', 'SPHContourOpacity', 'SPHStepFactor',
                 'SPHTerminationOpacity', 'SPHTileSize', 'SPHSlabDepth', 'SPHJitter',
                 'ScalarOpacityFunction', 'ScalarOpacityUnitDistance', 'Shade'):
        check(rep.GetProperty(name) is not None, 'property %s exists' % name)

    # The smoothing length array starts as the data's h (its conventional name); the other
    # optional arrays as None, not the active scalars (rho here), which as h would make every
    # particle's support 1000 times the data. The picture below uses h at that default.
    check(rep.SPHSmoothingLengthArray[1] == 'h',
          'SPHSmoothingLengthArray defaults to h (%s)' % rep.SPHSmoothingLengthArray[1])
    for name in ('SPHMassArray', 'SPHDensityArray', 'SPHVolumeArray'):
        check(rep.GetProperty(name)[1] in ('', 'None'),
              '%s defaults to None (%s)' % (name, rep.GetProperty(name)[1]))
    rep.SPHKernel = 'Wendland C2'
    rep.SPHMassArray = ['POINTS', 'm']
    rep.SPHDensityArray = ['POINTS', 'rho']
    ColorBy(rep, ('POINTS', 'vmag'))
    rep.SetScalarBarVisibility(view, False)
    lut = GetColorTransferFunction('vmag')
    lut.ApplyPreset('Cool to Warm', True)
    lut.AutomaticRescaleRangeMode = 'Never'
    lut.RescaleTransferFunction(0.0, 2.8)
    opacity = GetOpacityTransferFunction('vmag')
    opacity.Points = [0.0, 0.15, 0.5, 0.0, 2.8, 0.6, 0.5, 0.0]
    check(rep.ScalarOpacityFunction == opacity, 'the representation uses the opacity map')
    rep.ScalarOpacityUnitDistance = UNIT
    camera = view.GetActiveCamera()
    camera.SetFocalPoint(0.9, 0.0, 0.2)
    camera.SetPosition(0.2, -2.6, 1.5)
    camera.SetViewUp(0, 0, 1)
    view.CenterOfRotation = [0.9, 0.0, 0.2]
    Render(view)

    image = shot(view, output)
    covered = float((image.sum(axis=1) > 3 * 0.15 * 255).mean())
    check(0.1 < covered < 0.95, 'the water covers part of the view (%.1f%%)' % (100 * covered))
    stats = statistics(rep)
    check(stats.get('particles') == 9360, 'every particle drawn (%s)' % stats.get('particles'))

    sys.path.insert(0, os.path.join(build_dir, 'lib', 'python3', 'dist-packages'))
    from paraview import servermanager
    particles = servermanager.Fetch(source)
    reference, count = plain_vtk_image(particles, view, lut.GetClientSideObject(),
                                       opacity.GetClientSideObject(),
                                       stem + '-vtk-reference.png')
    check(count == 9360 and rmse(image, reference) < 1.0,
          'the picture is the plain VTK mapper\'s (rmse %.3f of 255)' % rmse(image, reference))
    if not compare_with_baseline(output, baseline):
        failures.append('baseline comparison')
    check_reference(view, rep, particles, lut.GetClientSideObject(),
                    opacity.GetClientSideObject(), stem)

    rep.SPHNormalization = 'Unnormalized'
    unnormalized = shot(view, stem + '-unnormalized.png')
    check(statistics(rep).get('weight_sums') == 0 and rmse(unnormalized, image) > 2.0,
          'unnormalized: no weight sums, another picture (rmse %.2f)' % rmse(unnormalized, image))
    rep.SPHNormalization = 'Normalized'
    rep.SPHContourShading = 1
    contour = shot(view, stem + '-contour.png')
    stats = statistics(rep)
    check(stats.get('contour_samples') > 0 and stats.get('gradient_evaluations') == 0
          and rmse(contour, image) > 1.0,
          'contour shading: %s contour samples, no gradients' % stats.get('contour_samples'))
    rep.SPHContourShading = 0
    rep.Shade = 1
    shot(view, stem + '-shaded.png')
    stats = statistics(rep)
    check(stats.get('gradient_evaluations') == stats.get('kernel_evaluations') > 0,
          'Shade: exact gradients with every kernel evaluation')
    rep.Shade = 0

    # Interaction: during ParaView's interactive renders a frame slower than the budget
    # reduces the sampling rate of the next (equation 3.1); a 1 us budget makes every frame
    # slow, so the check does not depend on the machine's speed.
    rep.SPHFrameBudget = 1e-6
    view.SMProxy.InteractiveRender()
    view.SMProxy.InteractiveRender()
    reduction = statistics(rep).get('reduction_percent')
    check(reduction is not None and reduction > 100,
          'interactive renders over budget: reduced sampling (%s%%)' % reduction)
    still = shot(view, stem + '-still.png')
    check(statistics(rep).get('reduction_percent') == 100 and rmse(still, image) < 1e-9,
          'the still render after it: the exact picture')
    rep.SPHFrameBudget = 0

    Hide(source, view)
    nothing = shot(view, stem + '-hidden.png')
    check(float(abs(nothing.astype(float) - nothing[0]).max()) == 0.0,
          'a hidden representation draws nothing')


def main():
    plugin, build_dir, data_file, baseline, output = sys.argv[1:6]
    out_dir = os.path.dirname(os.path.abspath(output))
    if out_dir == os.path.dirname(os.path.abspath(baseline)):
        print('FAIL  OUTPUT must not be in the baseline folder')
        return 2
    os.makedirs(out_dir, exist_ok=True)
    stem = os.path.splitext(os.path.abspath(output))[0]
    LoadPlugin(plugin, remote=False, ns=globals())
    source = LegacyVTKReader(FileNames=[data_file])
    source.UpdatePipeline()
    arrays = source.PointData.keys()
    check(all(a in arrays for a in ('h', 'm', 'rho', 'vmag')),
          'ParaView reads the particle arrays (%s)' % ', '.join(arrays))
    view = CreateView('RenderView')
    try:
        run_checks(view, source, stem, build_dir, output, baseline)
    finally:
        Delete(view)
    return finish()


if __name__ == '__main__':
    code = main()
    if code:
        sys.exit(code)
