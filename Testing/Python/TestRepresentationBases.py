"""pvpython: what the RayMappers representations share through their bases (the XML base
proxies in the group "representations_base" and the C++ classes
vtkRayMapperPropRepresentation, vtkRayMapperParticleRepresentation,
vtkRayMapperParticleVolumeRepresentation and vtkRayMapperVolumeClassification).

Checks:
- every representation proxy has the properties of its bases, under the names pvpython
  users know (a proxy that stops inheriting its base loses them), and the bases are not
  offered as representations;
- on a small lattice of particles, the view frames the points grown by the reach of each
  particle representation (its bounds margin: one radius, Sigma radii, the SPH kernel's
  support 2h, one radius);
- each lighting coefficient of the particles' material
  reaches the picture of each particle representation ("Ray-Traced Spheres", "RBF Volume",
  "SPH Volume", "SPH Fluid"): a larger Ambient brightens it, a smaller Diffuse darkens it, a
  larger Specular (the fluid's SPHFluidSpecular) brightens it and a smaller SpecularPower (a
  wider highlight) brightens it
  (each by more than 0.5 of 255 in the mean);
- NumberOfThreads (1, 2) reaches each particle type's mapper: its render ran in a task
  arena of that many threads (the statistics' counter "threads");
- for the particle volumes (RBF, SPH) the classification reaches the picture too: a red
  DiffuseColor (no color array) leaves green and blue dark, and a larger
  ScalarOpacityUnitDistance (less opacity per length) makes the field dimmer.

usage: pvpython TestRepresentationBases.py PLUGIN OUTPUT_DIR
"""
import math
import os
import sys

from paraview import servermanager
from paraview.simple import CreateView, Delete, Hide, LoadPlugin, PVTrivialProducer, Show

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, finish, prepare_view, screenshot, statistics  # noqa: E402

SIZE = [96, 72]
BACKGROUND = [0.0, 0.0, 0.0]

# What each tier of bases holds, written again here (not read from the XML).
EVERY_REPRESENTATION = ['Input', 'Visibility', 'Position', 'Scale', 'Orientation', 'Origin',
                        'UserTransform', 'Pickable', 'NumberOfThreads']
PARTICLE = EVERY_REPRESENTATION + ['Ambient', 'Diffuse', 'Specular', 'SpecularPower']
PARTICLE_VOLUME = PARTICLE + ['ColorArrayName', 'LookupTable', 'ScalarOpacityFunction',
                              'ScalarOpacityUnitDistance', 'Shade', 'DiffuseColor']
SHARED = {
    'RayTracedSpheresRepresentation': PARTICLE,
    'SPHFluidRepresentation': PARTICLE,
    'RBFVolumeRepresentation': PARTICLE_VOLUME,
    'SPHVolumeRepresentation': PARTICLE_VOLUME,
    'ZSweepVolumeRepresentation': EVERY_REPRESENTATION,
}
BASES = ['RayMapperRepresentationBase', 'RayMapperParticleRepresentationBase',
         'RayMapperParticleVolumeRepresentationBase']

# Each representation type with the settings that make its material visible (the volumes
# are lit only with Shade on).
PARTICLE_TYPES = {
    'Ray-Traced Spheres': {'Radius': 0.35},
    'RBF Volume': {'RBFRadius': 0.35, 'Shade': 1, 'ScalarOpacityUnitDistance': 0.2},
    # Unnormalized with a small particle volume, so that the field stays below 1, where the
    # solid opacity ramp is not yet opaque.
    'SPH Volume': {'SPHSmoothingLength': 0.6, 'SPHNormalization': 1, 'SPHParticleVolume': 0.05,
                   'Shade': 1, 'ScalarOpacityUnitDistance': 0.2},
    'SPH Fluid': {'SPHFluidRadius': 0.35},
}

# How far each type's rendering reaches beyond the points with these settings: a sphere's
# radius; Sigma (default 3) Gaussian radii; the cubic spline's (the default kernel's) support
# 2h (Limper 2012: h is half the support of M4); a fluid sphere's radius.
# The composite representations expose each type's NumberOfThreads under its own name, and
# its statistics (counter "threads": the concurrency of the arena the render ran in).
THREADS = {'Ray-Traced Spheres': ('SpheresNumberOfThreads', 'SpheresRenderStatistics'),
           'RBF Volume': ('RBFNumberOfThreads', 'RBFRenderStatistics'),
           'SPH Volume': ('SPHNumberOfThreads', 'SPHRenderStatistics'),
           'SPH Fluid': ('SPHFluidNumberOfThreads', 'SPHFluidRenderStatistics')}

MARGINS = {'Ray-Traced Spheres': 0.35, 'RBF Volume': 3.0 * 0.35, 'SPH Volume': 2.0 * 0.6,
           'SPH Fluid': 0.35}


def check_shared_properties():
    """Every representation proxy lists the properties of its bases; the bases are no
    representations."""
    pxm = servermanager.ProxyManager().SMProxyManager
    for name, shared in SHARED.items():
        proxy = pxm.NewProxy('representations', name)
        check(proxy is not None, '%s exists' % name)
        if proxy is None:
            continue
        missing = [p for p in shared if proxy.GetProperty(p) is None]
        check(not missing, '%s has the shared properties %s (missing: %s)'
              % (name, ', '.join(shared), ', '.join(missing) or 'none'))
        proxy.UnRegister(None)
    for base in BASES:
        check(pxm.GetProxyDefinitionManager().HasDefinition('representations', base) == 0,
              '%s is not offered as a representation' % base)
        check(pxm.GetProxyDefinitionManager().HasDefinition('representations_base', base) != 0,
              '%s is defined in representations_base' % base)


def lattice():
    """A 4 x 4 x 4 lattice of particles one unit apart."""
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    points = vtkPoints()
    for i in range(64):
        points.InsertNextPoint(i % 4, (i // 4) % 4, i // 16)
    data = vtkPolyData()
    data.SetPoints(points)
    producer = PVTrivialProducer()
    producer.GetClientSideObject().SetOutput(data)
    producer.UpdatePipeline()
    return producer


def check_margin(view, kind):
    """The view frames the lattice's box [0, 3]^3 grown by the rendering's reach: after
    ResetCamera the camera is at distance R / sin(angle / 2) from the centre, R the half
    diagonal sqrt(3) (1.5 + margin) of the grown box."""
    camera = view.GetActiveCamera()
    distance = math.dist(camera.GetPosition(), camera.GetFocalPoint())
    margin = distance * math.sin(math.radians(camera.GetViewAngle()) / 2) / math.sqrt(3) - 1.5
    check(abs(margin - MARGINS[kind]) < 1e-6 * (1.5 + MARGINS[kind]),
          '%s: the view frames the points grown by %g (the reach of the particles: %g)'
          % (kind, margin, MARGINS[kind]))


def check_material(view, rep, kind, stem):
    """Each lighting coefficient changes the mean brightness in the direction it should."""
    def mean(tag):
        return float(screenshot(view, '%s-%s.png' % (stem, tag), SIZE).mean())
    # The fluid's highlight is its own SPHFluidSpecular (it ignores the surface's Specular).
    specular = 'SPHFluidSpecular' if kind == 'SPH Fluid' else 'Specular'
    steps = [('Ambient', 0.5, 'brighter'), ('Diffuse', 0.2, 'darker'),
             (specular, 0.8, 'brighter'), ('SpecularPower', 2.0, 'brighter')]
    rep.Ambient, rep.Diffuse, rep.SpecularPower = 0.0, 1.0, 10.0
    rep.SetPropertyWithName(specular, 0.0)
    last = mean('start')
    for name, value, direction in steps:
        rep.SetPropertyWithName(name, value)
        now = mean(name)
        changed = now > last + 0.5 if direction == 'brighter' else now < last - 0.5
        check(changed, '%s: %s %g makes the picture %s (mean %.2f -> %.2f)'
              % (kind, name, value, direction, last, now))
        last = now


def check_classification(view, rep, kind, stem):
    """The solid DiffuseColor and the unit distance reach the particle volume's picture."""
    rep.Ambient, rep.Diffuse, rep.Specular = 0.3, 0.7, 0.0
    rep.DiffuseColor = [1.0, 0.0, 0.0]
    red = screenshot(view, '%s-red.png' % stem, SIZE)
    check(red[:, 0].max() > 50 and red[:, 1:].max() < 5,
          '%s: a red DiffuseColor leaves green and blue dark (max red %g, green/blue %g)'
          % (kind, red[:, 0].max(), red[:, 1:].max()))
    rep.ScalarOpacityUnitDistance = 2.0
    thinner = screenshot(view, '%s-unit-distance.png' % stem, SIZE)
    check(thinner.mean() < red.mean() - 0.5,
          '%s: ScalarOpacityUnitDistance 0.2 -> 2 dims the field (mean %.2f -> %.2f)'
          % (kind, red.mean(), thinner.mean()))


def check_threads(view, rep, kind, stem):
    """NumberOfThreads reaches the type's mapper: its render runs in an arena of that many
    threads."""
    prop, stats = THREADS[kind]
    for threads in (1, 2):
        rep.SetPropertyWithName(prop, threads)
        screenshot(view, '%s-threads-%d.png' % (stem, threads), SIZE)
        seen = statistics(rep, stats).get('threads')
        check(seen == threads, '%s: %s %d renders on %s thread(s)' % (kind, prop, threads, seen))
    rep.SetPropertyWithName(prop, 0)


def check_particle_types(view, producer, out_dir):
    for kind, settings in PARTICLE_TYPES.items():
        rep = Show(producer, view)
        rep.Representation = kind
        rep.ColorArrayName = ['POINTS', '']
        rep.DiffuseColor = [1.0, 1.0, 1.0]
        for name, value in settings.items():
            rep.SetPropertyWithName(name, value)
        view.ResetCamera()
        check_margin(view, kind)
        stem = os.path.join(out_dir, 'TestRepresentationBases-' + kind.replace(' ', ''))
        check_material(view, rep, kind, stem)
        check_threads(view, rep, kind, stem)
        if kind in ('RBF Volume', 'SPH Volume'):
            check_classification(view, rep, kind, stem)
        Hide(producer, view)


def main():
    plugin, out_dir = sys.argv[1:3]
    os.makedirs(out_dir, exist_ok=True)
    LoadPlugin(plugin, remote=False, ns=globals())
    check_shared_properties()
    view = CreateView('RenderView')
    prepare_view(view, SIZE, BACKGROUND)
    check_particle_types(view, lattice(), out_dir)
    Delete(view)
    return finish()


if __name__ == '__main__':
    sys.exit(main())
