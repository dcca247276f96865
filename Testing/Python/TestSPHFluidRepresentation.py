"""pvpython: the "SPH Fluid" representation and the "SPH Voxelizer" filter of the RayMappers
plugin on a PySPH dam break.

Checks:
- "SPH Fluid" is offered for the particles, with its panel's properties;
- with the radius array h (scale 0.8) the picture is the one vtkSPHFluidMapper draws in a
  plain VTK pipeline with the same settings and camera (ambient light only: the light kit
  of ParaView's view is not a plain renderer's headlight); only the effects asked for run (no
  march at index 1, no AO work when off), and refraction marches when the index is 1.33;
- the SPH Voxelizer filter (Filters menu) with the view's camera and size finds exactly the
  spans and pixels the representation rendered; its arrays are there, with S components;
- the SPH Boundary Particles filter keeps the particles the representation does not cull;
- a hidden representation draws nothing; the image matches its baseline;
- Color By a point array colours the fluid through the color map (an all-red map keeps the
  red channel and drops the green the white fluid scatters), Solid Color gives the picture
  back; with Diffuse 1 and SPHFluidSpecular 0.5 the picture is the plain mapper's under a
  vtkLightKit at its defaults (ParaView's light kit), so the fluid is lit by the view's lights;
- the fluid's front surface (opaque, so the depth buffer holds it) against the analytic union
  of the particles' spheres (raymappers_reference) without smoothing, with AngleResolution 7
  and with AngleResolution 3 (unsmoothed), and at the representation's defaults (smoothing 4
  radii), at 200 x 150: the pixels covered by one and not the other, the distance between
  the surfaces along the rays and the distance of the shown points to the spheres' surface,
  in radii. Measured on this machine: no pixel covered by one only; largest / mean distance
  along the rays 0.099 / 0.041 unsmoothed, 0.048 / 0.020 at AngleResolution 7, 0.021 /
  0.0086 at 3 (the depth layers' thickness), 8.87 / 0.27 at the defaults (the largest where
  a ray grazes the surface: smoothing moves it there far along the ray for a small move in
  space); largest distance to the spheres' surface 0.083, 0.039, 0.017 and 0.82 at the
  defaults. The bounds are 1.5 times these, and 5 pixels (REFERENCE_BOUNDS), except the
  defaults' distance to the spheres' surface: at most 1 radius, what the smoothing default
  must keep.

usage: pvpython TestSPHFluidRepresentation.py PLUGIN BUILD_DIR DATA_FILE BASELINE OUTPUT
"""
import os
import sys

from paraview.simple import (  # noqa: E402
    CreateView, Delete, Hide, LegacyVTKReader, LoadPlugin, Render, Show)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import (  # noqa: E402
    check, compare_with_baseline, copy_camera, failures, finish, prepare_view, render_to_png, rmse)
import raymappers_testing  # noqa: E402
import raymappers_reference  # noqa: E402

REPRESENTATION = 'SPH Fluid'
BACKGROUND = [0.1, 0.1, 0.15]
SIZE = [320, 240]
REFERENCE_SIZE = [200, 150]
# (pixels covered by one surface only, largest and mean distance along the rays, largest
# distance to the spheres' surface, in radii) per setting.
REFERENCE_BOUNDS = {
    'no smoothing': (5, 0.149, 0.061, 0.125),
    'AngleResolution 7': (5, 0.072, 0.031, 0.059),
    'AngleResolution 3': (5, 0.032, 0.013, 0.025),
    'defaults': (5, 13.3, 0.41, 1.0),
}


def surface_distances(view, matrix, depth, radius, centres):
    """Where the window's depth buffer and the reference's front surface both show fluid, the
    distance between them along each pixel's ray in radii; how many pixels only one covers;
    and the largest distance of the shown points to the union's surface in radii,
    | min_i |p - c_i| - r | / r (exact outside the union; a ray grazing the surface moves far
    along itself for a small move of the surface)."""
    from scipy.spatial import cKDTree
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkFloatArray
    w, h = REFERENCE_SIZE
    z = vtkFloatArray()
    view.GetRenderWindow().GetZbufferData(0, 0, w - 1, h - 1, z)
    shown = vtk_to_numpy(z).astype(float)
    inverse = numpy.linalg.inv(matrix)
    i, j = numpy.meshgrid(numpy.arange(w), numpy.arange(h))
    x, y = (2 * (i.ravel() + 0.5) / w - 1), (2 * (j.ravel() + 0.5) / h - 1)

    def unproject(zw):
        p = inverse @ numpy.stack([x, y, 2 * zw - 1, numpy.ones_like(x)])
        return (p[:3] / p[3]).T
    near = unproject(numpy.zeros_like(x))
    both = (shown < 1) & (depth < 1)
    t_shown = numpy.linalg.norm(unproject(shown) - near, axis=1)
    t_wanted = numpy.linalg.norm(unproject(depth) - near, axis=1)
    e = numpy.abs(t_shown - t_wanted)[both] / radius
    offset = numpy.abs(cKDTree(centres).query(unproject(shown)[both])[0] - radius) / radius
    return (int(((shown < 1) != (depth < 1)).sum()), int(both.sum()), float(e.max()),
            float(e.mean()), float(offset.max()))


def check_reference(view, rep, particles, stem):
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    view.ViewSize = REFERENCE_SIZE
    radius = 0.8 * float(vtk_to_numpy(particles.GetPointData().GetArray('h')).min())
    xyz = vtk_to_numpy(particles.GetPoints().GetData())
    rep.SPHFluidTranslucency = 0
    unsmoothed = {'SPHFluidSmoothingRadius': 0.0}
    settings = (('no smoothing', unsmoothed),
                ('AngleResolution 7', dict(unsmoothed, SPHFluidAngleResolution=7.0)),
                ('AngleResolution 3', dict(unsmoothed, SPHFluidAngleResolution=3.0)),
                ('defaults', {}))
    for name, properties in settings:
        before = raymappers_testing.property_values(rep, properties)
        for key, value in properties.items():
            setattr(rep, key, value)
        raymappers_testing.screenshot(view, stem + '-reference-test.png', REFERENCE_SIZE)
        Render(view)
        lines = raymappers_reference.camera_lines(view, REFERENCE_SIZE) + ['render union']
        lines += ['sphere %r %r %r %r 1 1 1' % (p[0], p[1], p[2], radius) for p in xyz]
        expected = raymappers_reference.render(lines, REFERENCE_SIZE, stem + '-reference')
        m = view.GetActiveCamera().GetCompositeProjectionTransformMatrix(
            REFERENCE_SIZE[0] / REFERENCE_SIZE[1], -1, 1)
        matrix = numpy.array([[m.GetElement(r, c) for c in range(4)] for r in range(4)])
        only_one, both, worst, mean, moved = surface_distances(
            view, matrix, expected[:, 4], radius, xyz)
        bound = REFERENCE_BOUNDS[name]
        check(both > 5000 and only_one <= bound[0] and worst <= bound[1] and mean <= bound[2]
              and moved <= bound[3],
              'SPH Fluid, %s, front surface against the reference: %d pixels covered by both, '
              '%d by one only (<= %d); distance %.4f radii at most (<= %.4f), %.4f on average '
              '(<= %.4f); %.4f radii at most from the spheres\' surface (<= %.4f)'
              % (name, both, only_one, bound[0], worst, bound[1], mean, bound[2], moved,
                 bound[3]))
        for key, value in before.items():
            setattr(rep, key, value)
    rep.SPHFluidTranslucency = 1
    view.ViewSize = SIZE


def plain_vtk_image(particles, view, path, diffuse=0.0, specular=0.0):
    """The same particles drawn by vtkSPHFluidMapper in a plain VTK pipeline; with `diffuse`
    or `specular`, lit by a vtkLightKit at its defaults (ParaView's light kit's)."""
    from vtkmodules.vtkRenderingCore import vtkLightKit, vtkRenderer, vtkVolume, vtkVolumeProperty
    import raymappers

    mapper = raymappers.vtkSPHFluidMapper()
    mapper.SetInputData(particles)
    mapper.SetRadiusArrayName('h')
    mapper.SetRadiusScale(0.8)
    mapper.SetAbsorptionColor(4.0, 1.5, 0.8)
    mapper.SetColor(1.0, 1.0, 1.0)  # ParaView's Solid Color (DiffuseColor) by default
    prop = vtkVolumeProperty()
    prop.SetAmbient(1.0)
    prop.SetDiffuse(diffuse)
    prop.SetSpecular(specular)
    prop.SetSpecularPower(100.0)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    ren = vtkRenderer()
    ren.SetBackground(BACKGROUND)
    ren.AddVolume(volume)
    if diffuse or specular:
        vtkLightKit().AddLightsToRenderer(ren)
    copy_camera(view, ren)
    return render_to_png(ren, SIZE, path), mapper.GetStatistics().GetCounter('particles')


def check_coloring(view, rep, solid, stem):
    """Color By a point array through a color map that is red everywhere: every pixel keeps
    the white solid colour's red channel and loses the green and blue the white fluid
    scattered; Solid Color again gives the first picture back."""
    from paraview.simple import ColorBy, GetColorTransferFunction
    ColorBy(rep, ('POINTS', 'vmag'))
    lut = GetColorTransferFunction('vmag')
    lut.RGBPoints = [0.0, 1.0, 0.0, 0.0, 3.0, 1.0, 0.0, 0.0]
    red = shot(view, stem + '-red.png').astype(float)
    stats = statistics(rep)
    fluid = abs(solid.astype(float) - solid[0]).sum(axis=1) > 0
    same_red = float(abs(red[:, 0] - solid[:, 0]).max())
    lost = float((solid[fluid, 1] - red[fluid, 1]).mean())
    check(stats.get('color_samples') > 0 and same_red <= 1.0 and lost > 5.0
          and float((red[:, 1] - solid[:, 1]).max()) <= 1.0,
          'coloured by vmag through an all-red map: the red channel kept (largest change %.0f), '
          'green lost (%.1f levels on average)' % (same_red, lost))
    ColorBy(rep, None)
    again = shot(view, stem + '-solid-again.png')
    check(rmse(again, solid) == 0.0 and statistics(rep).get('color_samples') == 0,
          'Solid Color again: the first picture (rmse %.3f)' % rmse(again, solid))


def check_lights(view, rep, particles, stem):
    """Lit by the view's light kit: with Diffuse 1 and the fluid's Specular the picture is
    the plain mapper's under a vtkLightKit at its defaults (ParaView's light kit's), and not
    the ambient-only one."""
    rep.Diffuse = 1.0
    rep.SPHFluidSpecular = 0.5
    lit = shot(view, stem + '-lit.png')
    reference, _ = plain_vtk_image(particles, view, stem + '-lit-vtk.png', 1.0, 0.5)
    flat, _ = plain_vtk_image(particles, view, stem + '-flat-vtk.png')
    check(rmse(lit, reference) < 1.0 and rmse(lit, flat) > 5.0,
          'lit by the view\'s light kit: the plain mapper\'s picture under vtkLightKit (rmse '
          '%.3f), not the unlit one (%.2f)' % (rmse(lit, reference), rmse(lit, flat)))
    rep.Diffuse = 0.0
    rep.SPHFluidSpecular = 0.0


def shot(view, path):
    return raymappers_testing.screenshot(view, path, SIZE)


def statistics(rep):
    return raymappers_testing.statistics(rep, 'SPHFluidRenderStatistics')


def run_checks(view, source, stem, build_dir, output, baseline):
    prepare_view(view, SIZE, BACKGROUND)
    # One headlight, as a plain VTK renderer has (not ParaView's light kit).
    rep = Show(source, view)
    check(REPRESENTATION in rep.Representation.Available,
          '"%s" is offered for %s' % (REPRESENTATION, rep.GetXMLName()))
    rep.SetRepresentationType(REPRESENTATION)
    for name in ('SPHFluidRadius', 'SPHFluidRadiusArray', 'SPHFluidRadiusScale',
                 'SPHFluidAngleResolution', 'SPHFluidMaximumLayers', 'SPHFluidMaximumSpans',
                 'SPHFluidMemoryBudget', 'SPHFluidGapThreshold', 'SPHFluidSmoothingRadius',
                 'SPHFluidSmoothingIterations', 'DiffuseColor', 'SPHFluidTranslucency',
                 'SPHFluidAbsorptionColor', 'SPHFluidDensity', 'SPHFluidRefractiveIndex',
                 'SPHFluidBounces', 'SPHFluidAmbientOcclusion', 'SPHFluidAORadius',
                 'SPHFluidAOSamples'):
        check(rep.GetProperty(name) is not None, 'property %s exists' % name)
    # The radius array starts as the data's smoothing length h (a conventional size name),
    # not the active scalars (rho here), which would make every particle a sphere 1000 times
    # the data. The picture below uses h at that default.
    check(rep.SPHFluidRadiusArray[1] == 'h',
          'SPHFluidRadiusArray defaults to h (%s)' % rep.SPHFluidRadiusArray[1])
    rep.ColorArrayName = ['POINTS', '']
    # Ambient light only, so the comparison with a plain VTK renderer (a headlight, where
    # ParaView has its light kit) sees the same shading.
    rep.Ambient = 1.0
    rep.Diffuse = 0.0
    rep.SPHFluidSpecular = 0.0
    rep.SPHFluidRadiusScale = 0.8
    rep.SPHFluidAbsorptionColor = [4.0, 1.5, 0.8]
    camera = view.GetActiveCamera()
    camera.SetFocalPoint(0.9, 0.0, 0.2)
    camera.SetPosition(0.2, -2.6, 1.5)
    camera.SetViewUp(0, 0, 1)
    view.CenterOfRotation = [0.9, 0.0, 0.2]
    Render(view)

    image = shot(view, output)
    stats = statistics(rep)
    covered = float((abs(image - image[0]).sum(axis=1) > 0).mean())
    check(0.1 < covered < 0.95, 'the water covers part of the view (%.1f%%)' % (100 * covered))
    check(stats.get('particles') == 9360, 'every particle drawn (%s)' % stats.get('particles'))
    check(stats.get('march_columns') == 0 and stats.get('ao_samples') == 0
          and stats.get('color_samples') == 0 and stats.get('filter_iterations') > 0
          and stats.get('translucent_pixels') > 0,
          'translucency and the default smoothing: no march, no AO, no colour lookups')

    sys.path.insert(0, os.path.join(build_dir, 'lib', 'python3', 'dist-packages'))
    from paraview import servermanager
    particles = servermanager.Fetch(source)
    reference, count = plain_vtk_image(particles, view, stem + '-vtk-reference.png')
    check(count == 9360 and rmse(image, reference) < 1.0,
          'the picture is the plain VTK mapper\'s (rmse %.3f of 255)' % rmse(image, reference))
    if not compare_with_baseline(output, baseline):
        failures.append('baseline comparison')

    # The SPH Boundary Particles filter keeps exactly the particles the representation splats
    # (boundary-cell culling, on by default in both).
    check('SPHBoundaryParticles' in globals(), 'the SPH Boundary Particles filter is offered')
    boundary = globals()['SPHBoundaryParticles'](Input=source)
    boundary.RadiusArray = 'h'
    boundary.RadiusScale = 0.8
    kept = servermanager.Fetch(boundary)
    culled = kept.GetFieldData().GetArray('CulledParticles').GetValue(0)
    check(culled > 0 and culled == stats.get('culled_particles')
          and kept.GetNumberOfPoints() + culled == 9360,
          'boundary particles: the culling of the representation (%d culled)' % culled)
    Delete(boundary)

    # The filter with the view's camera and size: the same spans.
    # LoadPlugin(..., ns=globals()) made the filter's function in this module.
    check('SPHVoxelizer' in globals(), 'the SPH Voxelizer filter is offered')
    vox = globals()['SPHVoxelizer'](Input=source)
    vox.RadiusArray = 'h'
    vox.RadiusScale = 0.8
    vox.ImageSize = SIZE
    vox.CameraPosition = list(camera.GetPosition())
    vox.CameraFocalPoint = list(camera.GetFocalPoint())
    vox.CameraViewUp = list(camera.GetViewUp())
    vox.CameraViewAngle = camera.GetViewAngle()
    vox.ResetCamera = 0
    vox.UpdatePipeline()
    image_data = servermanager.Fetch(vox)
    from vtkmodules.util.numpy_support import vtk_to_numpy
    pd = image_data.GetPointData()
    names = [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
    check(all(n in names for n in ('SpanCount', 'SpansFound', 'EntryDepth', 'ExitDepth',
                                   'HiddenEmpty', 'Thickness', 'DepthToDistance',
                                   'EntryNormal', 'ExitNormal', 'Links')),
          'the filter\'s arrays: %s' % ', '.join(names))
    check(pd.GetArray('EntryDepth').GetNumberOfComponents() == 7
          and image_data.GetDimensions() == (SIZE[0], SIZE[1], 1),
          'an image of the view size, 7 span components')
    counts = vtk_to_numpy(pd.GetArray('SpanCount')).astype(int)
    stats = statistics(rep)
    check(int(counts.sum()) == stats.get('spans_stored')
          and int((counts > 0).sum()) == stats.get('shaded_pixels'),
          'the filter finds the spans the representation rendered (%d spans, %d pixels; '
          'rendered %s, %s)' % (counts.sum(), (counts > 0).sum(), stats.get('spans_stored'),
                                 stats.get('shaded_pixels')))
    thickness = vtk_to_numpy(pd.GetArray('Thickness'))
    check(float(thickness.max()) > 0.1 and float(thickness.min()) == 0.0,
          'thickness up to %.3f world units' % float(thickness.max()))
    Delete(vox)

    rep.SPHFluidRefractiveIndex = 1.33
    refracted = shot(view, stem + '-refracted.png')
    stats = statistics(rep)
    check(stats.get('march_columns') > 0 and stats.get('refraction_paths') > 0
          and rmse(refracted, image) > 1.0,
          'index 1.33: refraction paths marched (%s columns)' % stats.get('march_columns'))
    rep.SPHFluidRefractiveIndex = 1.0
    rep.SPHFluidAmbientOcclusion = 1
    shot(view, stem + '-ao.png')
    stats = statistics(rep)
    check(stats.get('ao_samples') == 16 * stats.get('shaded_pixels'), 'AO on: 16 samples a pixel')
    rep.SPHFluidAmbientOcclusion = 0

    check_coloring(view, rep, image, stem)
    check_lights(view, rep, particles, stem)
    check_reference(view, rep, particles, stem)
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
