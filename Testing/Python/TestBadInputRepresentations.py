"""pvpython: bad input through the RayMappers representations and SPH filters, as a
ParaView user (or a pvpython script) gives it.

One case per run (the ctest Python.TestBadInputRepresentations.<case> and
Python.TestBadInputFilters): spheres, rbf, zsweep, sph or fluid (the representation of
that name), or filters (SPH Voxelizer and SPH Boundary Particles). The data comes from
PVTrivialProducers: a clean data set and the same one with bad elements added (the bad
points inside the clean bounds, so that the view's bounds and camera are the same).

Every message that reaches VTK's output window is counted (vtkStringOutputWindow), and each
step expects exactly the warnings it names, each naming its problem:
- the bad data (NaN / infinite coordinates, bad radii, smoothing lengths and values; bad
  cells for the Z-sweep) gives its warnings and exactly the picture of the clean data
  (screenshots compared with tolerance 0 by raymappers-compare-images);
- a missing array, an integer array (silent, the same picture), a 3-component array (one
  warning, the picture of its first component), an empty data set (one warning, the
  background only);
- NaN, negative and huge values of the representation's properties set from pvpython: one
  warning each; NaN leaves the picture, a clamped value gives the picture of its bound;
- degenerate cameras: a zero view angle draws (silently), the eye at the focal point and a NaN
  camera position warn once and draw nothing;
- after every render that draws, the mapper's float frame has no NaN, infinite or
  out-of-range value (its statistics, with RAYMAPPERS_VALIDATE_FRAMES=1 set by ctest);
- the filters: the output of the bad data equals the clean output, array by array.

usage: pvpython TestBadInputRepresentations.py PLUGIN CASE OUTPUT_DIR
"""
import math
import os
import re
import subprocess
import sys

from paraview.simple import (  # noqa: E402
    ColorBy, CreateView, Delete, GetColorTransferFunction, GetOpacityTransferFunction, Hide,
    LoadPlugin, PVTrivialProducer, Render, SaveScreenshot, Show)
from vtkmodules.vtkCommonCore import (  # noqa: E402
    vtkDoubleArray, vtkIntArray, vtkPoints)
from vtkmodules.vtkCommonDataModel import (  # noqa: E402
    vtkCellArray, vtkPolyData, vtkUnstructuredGrid)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import raymappers_testing  # noqa: E402
from raymappers_testing import finish, prepare_view  # noqa: E402

PLUGIN, CASE, OUTPUT = sys.argv[1], sys.argv[2], sys.argv[3]
LoadPlugin(PLUGIN, remote=False, ns=globals())
os.makedirs(OUTPUT, exist_ok=True)
NAN, INF = float('nan'), float('inf')
SIZE = [160, 160]
BACKGROUND = [0.2, 0.4, 0.6]  # 51 102 153 in 8 bits, exactly
check = raymappers_testing.check


class Messages(raymappers_testing.OutputWindowMessages):
    """What reaches VTK's output window inside the block, with the counts these tests expect."""

    def expect(self, n, text, what, ours_only=False):
        """Exactly n messages, all warnings naming `text`. With `ours_only`, ParaView's own
        messages are left out of the count (printed)."""
        warnings, count = self.warnings, self.count
        if ours_only:
            for message in self.errors + self.warnings:
                if not OURS.search(message):
                    print('note  not counted, not from RayMappers: ' + message.strip())
            warnings = [w for w in self.warnings if OURS.search(w)]
            count = len(warnings) + len([e for e in self.errors if OURS.search(e)])
        named = all(text in w for w in warnings)
        ok = count == n and len(warnings) == n and named
        check(ok, '%s: %d warning(s) naming %r%s' % (
            what, n, text, '' if ok else ' (got: %s)' % ' | '.join(
                ['error: ' + e for e in self.errors] + self.warnings)))


OURS = re.compile(r'^vtk(CGTSphereMapper|RBFVolume|ZSweepVolume|SPHVolume|SPHFluid|'
                  r'RayTracedSpheres|SPHVoxelizer|SPHBoundaryParticles|RayMapper)')


def silent(block, what, ours_only=False):
    block.expect(0, '', what, ours_only)


# -- data ------------------------------------------------------------------------------

def add_array(data, name, values, components=1, kind=vtkDoubleArray):
    a = kind()
    a.SetName(name)
    a.SetNumberOfComponents(components)
    for v in values:
        if components == 1:
            a.InsertNextValue(v)
        else:
            a.InsertNextTuple(v)
    data.GetPointData().AddArray(a)


def particles(bad=False, empty=False, bad_values=False, zero_density=False):
    """A 4^3 lattice in [-1, 1]^3 with point arrays: radius (0.3), iradius (integer 1, for a
    radius scale of 0.3), radius3 (0.3, 0.6, 0), value (0..4), ivalue (integer), value3
    (v, -v, 2v), h (0.3), ih (1), h3, m (1) and rho (1). With `bad`, 8 particles are added
    inside the bounds: 2 at NaN or infinite coordinates, 6 with the radii and smoothing
    lengths 0, -1, NaN, infinity, 1e20 and 1e300; with `bad_values` also 4 with a NaN,
    infinite or 1e300 value or a zero density (which the spheres, RBF and the fluid draw;
    `zero_density` adds that one alone: the clean data of those that draw it)."""
    rows = []
    if not empty:
        n = 4
        for k in range(n):
            for j in range(n):
                for i in range(n):
                    h = 2.0 / (n - 1)
                    rows.append(((-1 + i * h, -1 + j * h, -1 + k * h), 0.3, (i + j + k) % 5, 1.0))
    if bad:
        rows += [((NAN, 0, 0), 0.3, 1, 1.0), ((0, INF, 0), 0.3, 1, 1.0)]
        rows += [((0.1, 0.2, 0.3), r, 1, 1.0) for r in (0.0, -1.0, NAN, INF, 1e20, 1e300)]
    if bad and bad_values:
        rows += [((0.2, 0.1, 0.3), 0.3, q, 1.0) for q in (NAN, INF, 1e300)]
    if (bad and bad_values) or zero_density:
        rows += [((0.2, 0.1, 0.3), 0.3, 1, 0.0)]
    data = vtkPolyData()
    points = vtkPoints()
    points.SetDataTypeToDouble()
    verts = vtkCellArray()
    for p, *_ in rows:
        verts.InsertNextCell(1)
        verts.InsertCellPoint(points.InsertNextPoint(p))
    data.SetPoints(points)
    data.SetVerts(verts)
    r = [row[1] for row in rows]
    q = [row[2] for row in rows]
    add_array(data, 'radius', r)
    add_array(data, 'iradius', [1] * len(rows), kind=vtkIntArray)
    add_array(data, 'radius3', [(x, 2 * x if math.isfinite(x) else x, 0) for x in r], 3)
    add_array(data, 'value', q)
    add_array(data, 'ivalue', [int(x) if abs(x) < 1e9 else 0 for x in q], kind=vtkIntArray)
    add_array(data, 'value3', [(x, -x, 2 * x) for x in q], 3)
    add_array(data, 'h', r)
    add_array(data, 'ih', [1] * len(rows), kind=vtkIntArray)
    add_array(data, 'h3', [(x, 2 * x if math.isfinite(x) else x, 0) for x in r], 3)
    add_array(data, 'm', [1.0] * len(rows))
    add_array(data, 'rho', [row[3] for row in rows])
    return data


def cube_grid(bad=False, empty=False, **unused):
    """[-1, 1]^3 as 5 tetrahedra with the point scalars s, is (integer 0..4) and s3
    (s, 1 - s, 0.25); with `bad`, cells with a NaN point, a point at infinity, a NaN and an
    infinite scalar, and cells the sweep skips (2 triangles, a quad, a polyhedron)."""
    grid = vtkUnstructuredGrid()
    points = vtkPoints()
    s, iscalar = [], []
    if not empty:
        for k in range(8):
            x, y, z = (1 if k & 1 else -1), (1 if k & 2 else -1), (1 if k & 4 else -1)
            points.InsertNextPoint(x, y, z)
            s.append(0.5 + 0.2 * x + 0.1 * y - 0.15 * z)
            iscalar.append(k % 5)
    grid.SetPoints(points)
    cells = [] if empty else [(10, (0, 1, 2, 4)), (10, (1, 3, 2, 7)), (10, (1, 4, 5, 7)),
                              (10, (2, 4, 7, 6)), (10, (1, 2, 4, 7))]
    if bad:
        for p, v in (((0, 0, NAN), 0.5), ((0, INF, 0), 0.5), ((0.5, 0.5, 0.9), NAN),
                     ((0.5, 0.5, -0.9), INF)):
            points.InsertNextPoint(p)
            s.append(v)
            iscalar.append(0)
            cells.append((10, (0, 1, 2, points.GetNumberOfPoints() - 1)))
        cells += [(5, (0, 1, 2)), (5, (4, 5, 6)), (9, (0, 1, 3, 2))]
    grid.Allocate(len(cells) + 1)
    for kind, ids in cells:
        grid.InsertNextCell(kind, len(ids), ids)
    if bad:
        # A polyhedron (the tetrahedron 0 1 2 4 given by its faces).
        from vtkmodules.vtkCommonCore import vtkIdList
        stream = vtkIdList()  # the face stream: the number of faces, then each face
        for i in (4, 3, 0, 2, 1, 3, 0, 1, 4, 3, 0, 4, 2, 3, 1, 2, 4):
            stream.InsertNextId(i)
        grid.InsertNextCell(42, stream)
    add_array(grid, 's', s)
    add_array(grid, 'is', iscalar, kind=vtkIntArray)
    add_array(grid, 's3', [(v, 1 - v, 0.25) for v in s], 3)
    grid.GetPointData().SetActiveScalars('s')
    return grid


def producer(data):
    source = PVTrivialProducer()
    source.GetClientSideObject().SetOutput(data)
    source.UpdatePipeline()
    return source


# -- pictures and statistics ---------------------------------------------------------------

COMPARE = os.environ.get('RAYMAPPERS_COMPARE_IMAGES')
shots = [0]


def screenshot(view):
    shots[0] += 1
    path = os.path.join(OUTPUT, '%s-%03d.png' % (CASE, shots[0]))
    SaveScreenshot(path, view, ImageResolution=SIZE, TransparentBackground=0)
    return path


def same(a, b, what):
    """The project's comparison with tolerance 0 (no pixel may differ at all)."""
    result = subprocess.run([COMPARE, '--bound', '0', '0', '0', '0', a, b],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    check(result.returncode == 0, '%s: the same picture as %s (%s)' % (
        what, os.path.basename(b), result.stdout.strip().replace('\n', ' ')))


def background_only(path, what):
    pixels = raymappers_testing.pixels(path)
    expected = [round(255 * c) for c in BACKGROUND]
    check(bool((pixels == expected).all()), '%s: the background only' % what)


class Scene:
    """One view, one representation type, a representation per data set (one visible)."""

    def __init__(self, kind, statistics):
        self.view = CreateView('RenderView')
        prepare_view(self.view, SIZE, BACKGROUND)
        self.view.OrientationAxesVisibility = 0
        self.kind = kind
        self.statistics = statistics
        self.reps = {}
        self.shown = None

    def show(self, name, source, configure):
        rep = Show(source, self.view)
        rep.SetRepresentationType(self.kind)
        configure(rep)
        self.reps[name] = rep
        Hide(source, self.view)
        rep.Visibility = 0
        return rep

    def only(self, name):
        for key, rep in self.reps.items():
            rep.Visibility = 1 if key == name else 0
        self.shown = self.reps[name]
        return self.shown

    def shot(self):
        return screenshot(self.view)

    def valid_frame(self, what):
        stats = raymappers_testing.statistics(self.shown, self.statistics)
        ok = (stats.get('frame_validation') == 'on' and stats.get('frame_nonfinite_values') == 0
              and stats.get('frame_out_of_range_values') == 0)
        check(ok, '%s: the float frame is valid (validation %s, %s non-finite, %s out of range)' % (
            what, stats.get('frame_validation'), stats.get('frame_nonfinite_values'),
            stats.get('frame_out_of_range_values')))

    def nothing_drawn(self, what):
        stats = raymappers_testing.statistics(self.shown, self.statistics)
        check(stats.get('frame_validation') != 'on', '%s: the mapper drew no frame' % what)

    def camera(self, position, focal=(0, 0, 0), angle=30):
        self.view.CameraPosition = list(position)
        self.view.CameraFocalPoint = list(focal)
        self.view.CameraViewUp = [0, 1, 0]
        self.view.CameraViewAngle = angle


# -- the representation cases --------------------------------------------------------------

def fixed_maps(names, lo, hi):
    """The same colour and opacity maps for every array name (ParaView keeps one per name)."""
    for name in names:
        lut = GetColorTransferFunction(name)
        lut.ApplyPreset('Cool to Warm', True)
        lut.AutomaticRescaleRangeMode = 'Never'
        lut.RescaleTransferFunction(lo, hi)
        lut.VectorMode = 'Component'
        lut.VectorComponent = 0
        opacity = GetOpacityTransferFunction(name)
        opacity.Points = [lo, 0.05, 0.5, 0.0, hi, 0.8, 0.5, 0.0]
        opacity.RescaleTransferFunction(lo, hi)


def run_representation(spec):
    scene = Scene(spec['type'], spec['statistics'])
    make = spec.get('data', particles)
    with Messages() as m:
        sources = {'clean': producer(make(**spec.get('clean', {}))), 'bad': producer(make(bad=True, **spec.get('bad', {}))),
                   'empty': producer(make(empty=True))}
        fixed_maps(spec.get('maps', []), *spec.get('range', (0, 4)))
        for name in ('clean', 'bad', 'empty'):
            scene.show(name, sources[name], spec['configure'])
        scene.camera(*spec['camera'])
    silent(m, 'the scene is set up', ours_only=True)

    scene.only('clean')
    with Messages() as m:
        clean = scene.shot()
        scene.valid_frame('the clean data')
    silent(m, 'the clean data')

    scene.only('bad')
    with Messages() as m:
        bad = scene.shot()
        scene.valid_frame('the bad data')
        scene.shot()
    m.expect(spec['bad_warnings'][0], spec['bad_warnings'][1], 'the bad data')
    same(bad, clean, 'the bad data')

    scene.only('empty')
    with Messages() as m:
        empty = scene.shot()
    m.expect(1, spec['empty_text'], 'an empty data set')
    background_only(empty, 'an empty data set')

    rep = scene.only('clean')
    for what, settings, warnings, text in spec['arrays']:
        before = raymappers_testing.property_values(rep, list(settings))
        with Messages() as m:
            for key, value in settings.items():
                setattr(rep, key, value)
            picture = scene.shot()
            scene.valid_frame(what)
            scene.shot()
        m.expect(warnings, text, what)
        same(picture, clean, what)
        with Messages() as m:
            for key, value in before.items():
                setattr(rep, key, value)
            scene.shot()
        silent(m, what + ', undone')

    for name, setup, value, bound, text, bound_warnings in spec['properties']:
        what = '%s = %r' % (name, value)
        before = raymappers_testing.property_values(rep, [name] + list(setup))
        with Messages() as m:
            for key, v in setup.items():
                setattr(rep, key, v)
            reference = scene.shot()
            if bound is not None:
                setattr(rep, name, bound)
                reference = scene.shot()
        m.expect(bound_warnings[0], bound_warnings[1], what + ': the setting it is compared in')
        with Messages() as m:
            setattr(rep, name, value)
            picture = scene.shot()
            scene.valid_frame(what)
        m.expect(1, text, what)
        same(picture, reference, what + (' (the picture before it)' if bound is None else
                                         ' (the picture of %r)' % bound))
        with Messages() as m:
            for key, v in before.items():
                setattr(rep, key, v)
            scene.shot()
        m.expect(0, '', what + ', undone')

    # Degenerate cameras.
    position, focal = spec['camera'][0], spec['camera'][1] if len(spec['camera']) > 1 else (0, 0, 0)
    with Messages() as m:
        scene.view.CameraViewAngle = 0
        scene.shot()
        scene.valid_frame('a zero view angle')
    silent(m, 'a zero view angle')
    for what, eye in (('the eye at the focal point', list(focal)),
                      ('a NaN camera position', [NAN] + list(position[1:]))):
        scene.camera(*spec['camera'])
        with Messages() as m:
            scene.view.CameraPosition = eye
            picture = scene.shot()
            scene.nothing_drawn(what)
            scene.shot()
        mapper = [w for w in m.warnings if 'camera is degenerate' in w]
        check(len(mapper) == 1 and all('RayMappers' not in e for e in m.errors),
              '%s: one warning that the camera is degenerate (got %d: %s)' % (
                  what, len(mapper), ' | '.join(m.warnings + m.errors)))
        background_only(picture, what)
        scene.camera(*spec['camera'])
        with Messages() as m:
            restored = scene.shot()
        same(restored, clean, what + ', then the camera restored')
        silent(m, what + ', then the camera restored')
    Delete(scene.view)


def spheres_config(rep):
    rep.UseRadiusArray = 1
    rep.RadiusArray = ['POINTS', 'radius']
    rep.Radius = 0.3
    ColorBy(rep, ('POINTS', 'value'))


def rbf_config(rep):
    ColorBy(rep, ('POINTS', 'value'))
    rep.UseRBFRadiusArray = 1
    rep.RBFRadiusArray = ['POINTS', 'radius']
    rep.RBFRadius = 0.3
    rep.SampleDistance = 0.05
    rep.ScalarOpacityUnitDistance = 0.3


def sph_config(rep):
    ColorBy(rep, ('POINTS', 'value'))
    rep.SPHSmoothingLength = 0.3
    rep.SPHSmoothingLengthArray = ['POINTS', 'h']
    rep.SPHMassArray = ['POINTS', 'm']
    rep.SPHDensityArray = ['POINTS', 'rho']
    rep.ScalarOpacityUnitDistance = 0.3


def fluid_config(rep):
    rep.SPHFluidRadius = 0.3
    rep.SPHFluidRadiusArray = ['POINTS', 'radius']
    # No highlight: it is light added over the body, a premultiplied colour above its alpha
    # that the frame validation counts as out of range. The default coloured absorption
    # stays: with the albedo the body never exceeds its alpha.
    rep.SPHFluidSpecular = 0.0


def zsweep_config(rep):
    ColorBy(rep, ('POINTS', 's'))
    rep.ScalarOpacityUnitDistance = 0.5


NOT_A_NUMBER = 'is not a number'
SPECS = {
    'spheres': dict(
        type='Ray-Traced Spheres', statistics='SpheresRenderStatistics', configure=spheres_config,
        maps=['value', 'ivalue', 'value3'], camera=((0.6, 0.8, 6.5),),
        bad_warnings=(2, 'are not drawn'), empty_text='no points',
        arrays=[
            ('a missing radius array', {'RadiusArray': ['POINTS', 'nosuch'],
                                        'Radius': 0.3}, 1, "'nosuch' is not a point array"),
            ('integer radius and colour arrays', {'RadiusArray': ['POINTS', 'iradius'],
                                                  'RadiusScale': 0.3,
                                                  'ColorArrayName': ['POINTS', 'ivalue']},
             0, ''),
            ('a 3-component radius array', {'RadiusArray': ['POINTS', 'radius3']}, 1,
             "radius array 'radius3' has 3 components that differ: the first is used"),
            ('a missing opacity array', {'OpacityByArray': 1, 'OpacityArray': ['POINTS', 'nosuch']},
             1, "opacity array 'nosuch' is not a point array of the input"),
        ],
        properties=[
            ('RadiusScale', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('Radius', {'UseRadiusArray': 0}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('Lambda', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('AmbientOcclusionRadius', {'AmbientOcclusionSamples': 4}, NAN, None, NOT_A_NUMBER,
             (0, '')),
            ('ShadowLightIntensity', {'ShadowRays': 2}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('Ambient', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SpecularPower', {'Specular': 0.5}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('DiffuseColor', {'ColorArrayName': ['POINTS', '']}, [NAN, 0.5, 0.5], None,
             'not a number', (0, '')),
            ('Lambda', {}, -5.0, 0.01, 'Lambda -5 is outside [0.01, 100]', (0, '')),
            ('RadiusScale', {}, 1e300, 1e15, 'ScaleFactor 1e+300 is outside', (0, '')),
            ('Specular', {}, 7.0, 1.0, 'Specular 7 is outside [0, 1]', (0, '')),
            ('ShadowLightIntensity', {'ShadowRays': 2}, -3.0, 0.0,
             'ShadowLightIntensity -3 is outside', (0, '')),
        ]),
    'rbf': dict(
        type='RBF Volume', statistics='RBFRenderStatistics', configure=rbf_config,
        bad={'bad_values': True}, clean={'zero_density': True},
        maps=['value', 'ivalue', 'value3'], camera=((0.6, 0.8, 6.5),),
        bad_warnings=(2, 'are not drawn'), empty_text='no points',
        arrays=[
            ('a missing radius array', {'RBFRadiusArray': ['POINTS', 'nosuch']}, 1,
             "'nosuch' is not a point array"),
            ('an integer value array', {'ColorArrayName': ['POINTS', 'ivalue']}, 0, ''),
            ('a 3-component value array', {'ColorArrayName': ['POINTS', 'value3']}, 1,
             "value array 'value3' has 3 components that differ: the first is used"),
        ],
        properties=[
            ('Kappa', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('Sigma', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SampleDistance', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('RBFRadiusScale', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('TerminationOpacity', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('Ambient', {'Shade': 1}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('ScalarOpacityUnitDistance', {}, NAN, None, 'must be positive', (0, '')),
            ('Sigma', {}, -5.0, 0.0, 'Sigma -5 is outside [0, 1000]', (0, '')),
            ('Kappa', {}, 1e300, 1e15, 'Kappa 1e+300 is outside', (0, '')),
            ('SamplesPerPass', {}, 100000, 256, 'SamplesPerPass 100000 is outside', (0, '')),
        ]),
    'sph': dict(
        type='SPH Volume', statistics='SPHRenderStatistics', configure=sph_config,
        bad={'bad_values': True},
        maps=['value', 'ivalue', 'value3'], camera=((0.6, 0.8, 6.5),),
        bad_warnings=(2, 'particles have'), empty_text='no points',
        arrays=[
            ('missing h, mass and density arrays', {'SPHSmoothingLengthArray': ['POINTS', 'nosuch'],
                                                    'SPHMassArray': ['POINTS', 'nomass'],
                                                    'SPHDensityArray': ['POINTS', 'norho']},
             2, 'is not a point array'),
            ('integer value and smoothing length arrays',
             {'ColorArrayName': ['POINTS', 'ivalue'], 'SPHSmoothingLengthArray': ['POINTS', 'ih'],
              'SPHSmoothingLengthScale': 0.3}, 0, ''),
            ('a 3-component smoothing length array', {'SPHSmoothingLengthArray': ['POINTS', 'h3']},
             1, "smoothing length array 'h3' has 3 components that differ: the first is used"),
        ],
        properties=[
            ('SPHSmoothingLengthScale', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SPHSupportFactor', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SPHStepFactor', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SPHTerminationOpacity', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SPHContourOpacity', {'SPHContourShading': 1}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('Diffuse', {'Shade': 1}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SPHStepFactor', {}, 0.0, 0.05, 'StepFactor 0 is outside [0.05, 64]', (0, '')),
            ('SPHSupportFactor', {}, 1e300, 100.0, 'SupportFactor 1e+300 is outside', (0, '')),
            ('SPHTileSize', {}, 1000, 64, 'TileSize 1000 is outside [2, 64]', (0, '')),
        ]),
    'fluid': dict(
        type='SPH Fluid', statistics='SPHFluidRenderStatistics', configure=fluid_config,
        camera=((0.6, 0.8, 6.5),), bad_warnings=(2, 'particles have'), empty_text='no points',
        arrays=[
            ('a missing radius array', {'SPHFluidRadiusArray': ['POINTS', 'nosuch']}, 1,
             "'nosuch' is not a point array"),
            ('an integer radius array', {'SPHFluidRadiusArray': ['POINTS', 'iradius'],
                                         'SPHFluidRadiusScale': 0.3}, 0, ''),
            ('a 3-component radius array', {'SPHFluidRadiusArray': ['POINTS', 'radius3']}, 1,
             "radius array 'radius3' has 3 components that differ: the first is used"),
        ],
        properties=[
            ('SPHFluidRadiusScale', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SPHFluidAngleResolution', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SPHFluidDensity', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SPHFluidRefractiveIndex', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('DiffuseColor', {'ColorArrayName': ['POINTS', '']}, [0.5, NAN, 0.5], None,
             'not a number', (0, '')),
            ('SPHFluidAORadius', {'SPHFluidAmbientOcclusion': 1}, NAN, None, NOT_A_NUMBER,
             (0, '')),
            ('SPHFluidSpecular', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('SPHFluidDensity', {}, 1e300, 1e15, 'Density 1e+300 is outside', (0, '')),
            ('SPHFluidRefractiveIndex', {}, 100.0, 10.0, 'RefractiveIndex 100 is outside', (0, '')),
            ('SPHFluidRadiusScale', {}, -1.0, 0.0, 'ScaleFactor -1 is outside',
             (1, 'have a zero, negative, non-finite or huge')),
        ]),
    'zsweep': dict(
        type='Z-Sweep Volume', statistics='ZSweepRenderStatistics', configure=zsweep_config,
        data=cube_grid, maps=['s', 'is', 's3'], range=(0, 1), camera=((2.0, 3.0, 6.0),),
        bad_warnings=(3, 'cells'), empty_text='no points',
        arrays=[
            ('3-component scalars', {'ColorArrayName': ['POINTS', 's3']}, 1,
             "scalar array 's3' has 3 components that differ: the first is used"),
        ],
        properties=[
            ('ZSweepTerminationOpacity', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('ZSweepFrameBudget', {}, NAN, None, NOT_A_NUMBER, (0, '')),
            ('ScalarOpacityUnitDistance', {}, NAN, None, 'must be positive', (0, '')),
            ('ZSweepTerminationOpacity', {}, -2.0, 0.0, 'TerminationOpacity -2 is outside', (0, '')),
            ('ZSweepTileSize', {}, 1, 8, 'TileSize 1 is outside [8, 1024]', (0, '')),
            ('ZSweepListThreshold', {}, 1000000, 4096, 'ListThreshold 1000000 is outside', (0, '')),
        ]),
}


# -- the filters ---------------------------------------------------------------------------

def same_output(a, b):
    """Points and point arrays equal value for value (NaN equal to NaN)."""
    if a.GetNumberOfPoints() != b.GetNumberOfPoints():
        return False
    for i in range(a.GetNumberOfPoints()):
        if a.GetPoint(i) != b.GetPoint(i):
            return False
    pa, pb = a.GetPointData(), b.GetPointData()
    if pa.GetNumberOfArrays() != pb.GetNumberOfArrays():
        return False
    for k in range(pa.GetNumberOfArrays()):
        x = pa.GetArray(k)
        y = pb.GetArray(x.GetName())
        if y is None or x.GetNumberOfValues() != y.GetNumberOfValues():
            return False
        c = x.GetNumberOfComponents()
        for v in range(x.GetNumberOfValues()):
            s, t = x.GetComponent(v // c, v % c), y.GetComponent(v // c, v % c)
            if not (s == t or (math.isnan(s) and math.isnan(t))):
                return False
    return True


def output_of(proxy):
    from vtkmodules.vtkCommonDataModel import vtkDataObject
    proxy.UpdatePipeline()
    data = proxy.GetClientSideObject().GetOutputDataObject(0)
    copy = data.NewInstance()
    copy.DeepCopy(data)
    return copy


def run_filter(name, make_filter, array_property, radius_property, properties,
               bounds_radius=True):
    filters = []
    # A default Radius of 1% of the data's extent (a bounds domain, `bounds_radius`) is
    # infinite for the bad data (its bounds hold the point at infinity) and -1e297 for the
    # empty data (uninitialized bounds): the filter warns once about each and keeps a valid
    # radius. The automatic radius (default 0) gives no warning.
    created = ((particles(), 0, ''), (particles(bad=True), 1, 'Radius inf is not finite'),
               (particles(empty=True), 1, 'is outside [0, 1e+15]'))
    if not bounds_radius:
        created = tuple((data, 0, '') for data, _, _ in created)
    for data, n, text in created:
        with Messages() as m:
            f = make_filter(producer(data))
            setattr(f, array_property, 'radius')
            setattr(f, radius_property, 0.3)
        m.expect(n, text, '%s: created on %s' % (name, ['the clean particles', 'the bad particles',
                                                          'an empty data set'][len(filters)]))
        filters.append(f)
    f_clean, f_bad, f_empty = filters
    with Messages() as m:
        reference = output_of(f_clean)
    silent(m, '%s: the clean particles' % name)
    with Messages() as m:
        result = output_of(f_bad)
    m.expect(2, 'particles have', '%s: the bad particles' % name)
    check(same_output(result, reference), '%s: the bad particles: the output of the clean ones' % name)
    with Messages() as m:
        output_of(f_empty)
    m.expect(1, 'no points', '%s: an empty data set' % name)
    for what, settings, warnings, text in (
            ('a missing radius array', {array_property: 'nosuch'}, 1,
             "'nosuch' is not a point array"),
            ('an integer radius array', {array_property: 'iradius', 'RadiusScale': 0.3}, 0, ''),
            ('a 3-component radius array', {array_property: 'radius3'}, 1,
             "radius array 'radius3' has 3 components that differ: the first is used")):
        before = raymappers_testing.property_values(f_clean, list(settings))
        with Messages() as m:
            for key, value in settings.items():
                setattr(f_clean, key, value)
            result = output_of(f_clean)
        m.expect(warnings, text, '%s: %s' % (name, what))
        check(same_output(result, reference), '%s: %s: the same output' % (name, what))
        for key, value in before.items():
            setattr(f_clean, key, value)
    for prop, value, bound, text in properties:
        what = '%s: %s = %r' % (name, prop, value)
        before = raymappers_testing.property_values(f_clean, [prop])
        with Messages() as m:
            if bound is not None:
                setattr(f_clean, prop, bound)
            expected = output_of(f_clean)
        silent(m, what + ': the setting it is compared in')
        with Messages() as m:
            setattr(f_clean, prop, value)
            result = output_of(f_clean)
        m.expect(1, text, what)
        check(same_output(result, expected), what + ': ' + (
            'the output before it' if bound is None else 'the output of %r' % bound))
        for key, v in before.items():
            setattr(f_clean, key, v)
        with Messages():
            output_of(f_clean)
    return f_clean


def run_filters():
    # The plugin's filters, which LoadPlugin put into this module's namespace.
    SPHVoxelizer, SPHBoundaryParticles = globals()['SPHVoxelizer'], globals()['SPHBoundaryParticles']

    def voxelizer(source):
        f = SPHVoxelizer(Input=source)
        f.ImageSize = [48, 40]
        f.CameraPosition = [0.6, 0.8, 6.5]
        f.CameraFocalPoint = [0, 0, 0]
        f.ResetCamera = 0
        return f
    vox = run_filter('SPH Voxelizer', voxelizer, 'RadiusArray', 'Radius', [
        ('Radius', NAN, None, NOT_A_NUMBER), ('RadiusScale', NAN, None, NOT_A_NUMBER),
        ('AngleResolution', NAN, None, NOT_A_NUMBER), ('GapThreshold', NAN, None, NOT_A_NUMBER),
        ('CameraViewAngle', NAN, None, NOT_A_NUMBER),
        ('CameraPosition', [0.6, NAN, 6.5], None, 'not a number'),
        ('MaximumSpans', 100, 63, 'MaximumSpans 100 is outside [1, 63]'),
        ('AngleResolution', 0.0, 0.01, 'AngleResolution 0 is outside'),
        ('RadiusScale', 1e300, 1e15, 'ScaleFactor 1e+300 is outside')], bounds_radius=False)
    for reset in (0, 1):
        what = 'SPH Voxelizer: the eye at the focal point, Reset Camera %s' % ('on' if reset else 'off')
        # (A new focal point each time: vtkCamera moves its focal point 1e-20 away from an
        # eye set onto it, which makes the next eye at the old focal point a valid camera.)
        with Messages() as m:
            vox.ResetCamera = reset
            vox.CameraFocalPoint = [0.1 * reset, 0, 0]
            vox.CameraPosition = [0.1 * reset, 0, 0]
            out = output_of(vox)
        m.expect(1, 'The camera is degenerate', what)
        counts = out.GetPointData().GetArray('SpanCount').GetRange()
        thickness = out.GetPointData().GetArray('Thickness')
        finite = all(math.isfinite(thickness.GetValue(i)) for i in range(thickness.GetNumberOfValues()))
        check(counts[1] == 0 and finite, what + ': no spans, a finite Thickness')
        vox.CameraPosition = [0.6, 0.8, 6.5]
    run_filter('SPH Boundary Particles', lambda s: SPHBoundaryParticles(Input=s),
               'RadiusArray', 'Radius', [
                   ('Radius', NAN, None, NOT_A_NUMBER), ('RadiusScale', NAN, None, NOT_A_NUMBER),
                   ('CellSize', NAN, None, NOT_A_NUMBER), ('CellSize', -1.0, 0.0, 'CellSize -1 is outside'),
                   ('Radius', 1e300, 1e15, 'Radius 1e+300 is outside')])


if __name__ == '__main__':
    check(os.environ.get('RAYMAPPERS_VALIDATE_FRAMES') == '1',
          'RAYMAPPERS_VALIDATE_FRAMES=1 (the float frames are checked)')
    check(bool(COMPARE), 'RAYMAPPERS_COMPARE_IMAGES names the image comparison')
    if CASE == 'filters':
        run_filters()
    else:
        run_representation(SPECS[CASE])
    sys.exit(finish())
