"""pvpython: the particle representations pick the input's conventional size array by
default (vtkSMParticleSizeArrayDomain and vtkSMParticleSizeDefaultDomain of the plugin).

Checks, for small point sets shown with Show() and each particle representation's
properties read at their defaults:
- a point array "radius" is the size array of all four ("Ray-Traced Spheres", "RBF Volume",
  "SPH Volume", "SPH Fluid"), with their Use...Array flags on and scale 1;
- "diameter" is picked with the scale 0.5 (the SPH Volume, whose smoothing length comes
  from a radius name only as a fallback, keeps 1);
- "h" is the size of RBF Volume, SPH Volume and SPH Fluid, never the spheres' radius;
- with both "radius" and "h" the SPH Volume takes h and the others radius;
- names are matched ignoring case ("Radius");
- without such a name nothing is picked: the flags are off, the SPH arrays "None", the
  scales 1, even when another array is the active scalars;
- the picture at the defaults uses the array: of two particles whose sizes differ 4-fold,
  the larger covers more than 4 times the pixels of the smaller (without the array, at a
  constant size, both cover about as many); a diameter twice the radius gives the same
  spheres as the radius.

usage: pvpython TestParticleSizeArrayDefaults.py PLUGIN OUTPUT_DIR
"""
import os
import sys

from paraview.simple import CreateView, Delete, Hide, LoadPlugin, PVTrivialProducer, Show

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, finish, prepare_view, rmse, screenshot  # noqa: E402

SIZE = [160, 80]
BACKGROUND = [0.0, 0.0, 0.0]

# Each representation's (use flag or None, array, scale) properties.
PROPERTIES = {
    'Ray-Traced Spheres': ('UseRadiusArray', 'RadiusArray', 'RadiusScale'),
    'RBF Volume': ('UseRBFRadiusArray', 'RBFRadiusArray', 'RBFRadiusScale'),
    'SPH Volume': (None, 'SPHSmoothingLengthArray', 'SPHSmoothingLengthScale'),
    'SPH Fluid': (None, 'SPHFluidRadiusArray', 'SPHFluidRadiusScale'),
}

# The point arrays of a dataset (the last one the active scalars) and what each
# representation takes by default: (array, scale), None for no array.
EXPECTED = [
    (['radius', 'temperature'], {'Ray-Traced Spheres': ('radius', 1.0),
                                 'RBF Volume': ('radius', 1.0),
                                 'SPH Volume': ('radius', 1.0),
                                 'SPH Fluid': ('radius', 1.0)}),
    (['diameter', 'temperature'], {'Ray-Traced Spheres': ('diameter', 0.5),
                                   'RBF Volume': ('diameter', 0.5),
                                   'SPH Volume': ('diameter', 1.0),
                                   'SPH Fluid': ('diameter', 0.5)}),
    (['h', 'temperature'], {'Ray-Traced Spheres': None,
                            'RBF Volume': ('h', 1.0),
                            'SPH Volume': ('h', 1.0),
                            'SPH Fluid': ('h', 1.0)}),
    (['h', 'radius'], {'Ray-Traced Spheres': ('radius', 1.0),
                       'RBF Volume': ('radius', 1.0),
                       'SPH Volume': ('h', 1.0),
                       'SPH Fluid': ('radius', 1.0)}),
    (['Radius'], {'Ray-Traced Spheres': ('Radius', 1.0),
                  'RBF Volume': ('Radius', 1.0),
                  'SPH Volume': ('Radius', 1.0),
                  'SPH Fluid': ('Radius', 1.0)}),
    (['temperature', 'radius_of_gyration'], {kind: None for kind in PROPERTIES}),
]

# Two particles 4 apart whose sizes differ 4-fold, and what the pictures need to be seen.
SIZES = [0.15, 0.6]
SETTINGS = {
    'Ray-Traced Spheres': {},
    'RBF Volume': {'ScalarOpacityUnitDistance': 0.05},
    'SPH Volume': {'ScalarOpacityUnitDistance': 0.05},
    'SPH Fluid': {},
}
# The constant size of each, set in the pictures without a size array (0: its default).
CONSTANT = {'Ray-Traced Spheres': 'Radius', 'RBF Volume': 'RBFRadius',
            'SPH Volume': 'SPHSmoothingLength', 'SPH Fluid': 'SPHFluidRadius'}
# The array each representation is shown with in the picture check.
PICTURE_ARRAY = {'Ray-Traced Spheres': 'radius', 'RBF Volume': 'radius', 'SPH Volume': 'h',
                 'SPH Fluid': 'h'}


def particles(names, sizes=(1.0, 2.0, 3.0), factor=1.0):
    """Points on the x axis 4 apart, each named array holding factor * sizes; the last
    array is the active scalars."""
    from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    points = vtkPoints()
    data = vtkPolyData()
    for i in range(len(sizes)):
        points.InsertNextPoint(4.0 * i, 0.0, 0.0)
    data.SetPoints(points)
    for name in names:
        array = vtkDoubleArray()
        array.SetName(name)
        for size in sizes:
            array.InsertNextValue(factor * size)
        data.GetPointData().AddArray(array)
    data.GetPointData().SetActiveScalars(names[-1])
    producer = PVTrivialProducer()
    producer.GetClientSideObject().SetOutput(data)
    producer.UpdatePipeline()
    return producer


def check_defaults(view, names, expected):
    producer = particles(names)
    rep = Show(producer, view)
    for kind, (use, array, scale) in PROPERTIES.items():
        want = expected[kind]
        if use:
            check(rep.GetPropertyValue(use) == (1 if want else 0),
                  '%s, arrays %s: %s is %s' % (kind, names, use, 1 if want else 0))
        if want or not use:
            picked = rep.GetPropertyValue(array)[1]
            check(picked == (want[0] if want else 'None'),
                  '%s, arrays %s: %s is %r (%r)' % (kind, names, array,
                                                    want[0] if want else 'None', picked))
        check(rep.GetPropertyValue(scale) == (want[1] if want else 1.0),
              '%s, arrays %s: %s is %g' % (kind, names, scale, want[1] if want else 1.0))
    Delete(rep)
    Delete(producer)


def picture(view, kind, names, factor, path, constant=0.0):
    """The screenshot of the two particles at the defaults, in solid white (and the
    constant size when given)."""
    producer = particles(names, SIZES, factor)
    rep = Show(producer, view)
    rep.Representation = kind
    rep.ColorArrayName = ['POINTS', '']
    rep.DiffuseColor = [1.0, 1.0, 1.0]
    if constant:
        rep.SetPropertyWithName(CONSTANT[kind], constant)
    for name, value in SETTINGS[kind].items():
        rep.SetPropertyWithName(name, value)
    view.ResetCamera()
    pixels = screenshot(view, path, SIZE)
    Hide(producer, view)
    Delete(rep)
    Delete(producer)
    return pixels


def halves(pixels):
    """The number of lit pixels in the left and the right half of the picture."""
    lit = (pixels.max(axis=1) > 8).reshape(SIZE[1], SIZE[0])
    return int(lit[:, :SIZE[0] // 2].sum()), int(lit[:, SIZE[0] // 2:].sum())


def check_pictures(view, out_dir):
    for kind, name in PICTURE_ARRAY.items():
        stem = os.path.join(out_dir, 'TestParticleSizeArrayDefaults-' + kind.replace(' ', ''))
        small, large = halves(picture(view, kind, [name], 1.0, stem + '-array.png'))
        check(large > 4 * max(small, 1),
              '%s, array %r at the defaults: the 4 times larger particle covers %d pixels, '
              'the smaller %d' % (kind, name, large, small))
        small, large = halves(picture(view, kind, ['mass'], 1.0, stem + '-none.png', 0.3))
        check(small > 0 and large < 2 * small,
              '%s, no size array: both particles have the constant size 0.3 (%d and %d '
              'pixels)' % (kind, small, large))
    stem = os.path.join(out_dir, 'TestParticleSizeArrayDefaults-Spheres')
    radius = picture(view, 'Ray-Traced Spheres', ['radius'], 1.0, stem + '-radius.png')
    diameter = picture(view, 'Ray-Traced Spheres', ['diameter'], 2.0, stem + '-diameter.png')
    check(rmse(radius, diameter) < 1.0,
          'Ray-Traced Spheres: a diameter array twice the radius gives the same spheres '
          '(rmse %.3f levels)' % rmse(radius, diameter))


def main():
    plugin, out_dir = sys.argv[1:3]
    os.makedirs(out_dir, exist_ok=True)
    LoadPlugin(plugin, remote=False, ns=globals())
    view = CreateView('RenderView')
    prepare_view(view, SIZE, BACKGROUND)
    for names, expected in EXPECTED:
        check_defaults(view, names, expected)
    check_pictures(view, out_dir)
    Delete(view)
    return finish()


if __name__ == '__main__':
    sys.exit(main())
