"""pvpython: the same particles in other units give the same picture, in every particle
representation at its defaults (only ColorBy set).

Two data sets, one ctest each:
- `populations` (none of the bundled files): a generated set of three populations of
  different density (a dense jittered slab, a sparse cloud above it, a compact Gaussian
  clump), with a point array "speed" that varies smoothly, kept unchanged at every scale;
- `dambreak`: the bundled PySPH frame Data/dam_break_coarse_00674.vtk (9,360 fluid
  particles of the dam break with an obstacle), coloured by the speed vmag, its arrays in the
  other units as raymappers_scales says: h (the smoothing length, a length: the size array
  RBF Volume, SPH Volume and SPH Fluid pick by default) and the speeds u v w vmag times the
  scale, V times its cube, rho divided by its cube, p divided by it, m unchanged.
For each of "Ray-Traced Spheres", "RBF Volume", "SPH Volume" and "SPH Fluid" the data is
shown at the scales 1e-3, 1 and 1e3 (the points multiplied), the camera reset, coloured by
the array with its map rescaled to the data range; checks:
- at scale 1 the representation draws something (more than 5% of the pixels differ from
  the background by more than 8 of 255): a ghost or an empty view would pass the rest;
- at 1e-3 and 1e3 the picture is the one at 1 (rmse at most 4 of 255 per channel);
- the size in use scales with the data (relative 1e-6), from the same size array at every
  scale: the ...InUse property (the automatic size) without a size array, the median of
  the array times its scale with one.

usage: pvpython TestScaleInvariance.py PLUGIN OUTPUT_DIR [dambreak DAM_BREAK.vtk]
"""
import os
import sys

import numpy
from paraview.simple import CreateView, Delete, LoadPlugin

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_scales import (REPRESENTATIONS, SCALES, drawn_fraction, picture,  # noqa: E402
                               producer, read_particles)
from raymappers_testing import check, finish, prepare_view, rmse  # noqa: E402

SIZE = [200, 150]
BACKGROUND = [0.1, 0.1, 0.15]


def populations():
    """The points (n, 3), their speed and its length exponent: a slab of 20 x 20 x 6
    particles 0.1 apart jittered by 0.02, 400 particles spread over the volume above it,
    1500 in a Gaussian clump of width 0.08; the speed is kept at every scale (exponent 0)."""
    rng = numpy.random.default_rng(25)
    i, j, k = numpy.meshgrid(numpy.arange(20), numpy.arange(20), numpy.arange(6), indexing='ij')
    slab = 0.1 * numpy.stack([i, j, k], axis=-1).reshape(-1, 3).astype(float)
    slab += rng.uniform(-0.02, 0.02, slab.shape)
    cloud = rng.uniform([0.0, 0.0, 0.8], [2.0, 2.0, 1.6], (400, 3))
    clump = rng.normal([1.4, 1.4, 1.1], 0.08, (1500, 3))
    points = numpy.concatenate([slab, cloud, clump])
    speed = 1.0 + numpy.sin(2.0 * points[:, 0]) + points[:, 2]  # a speed: >= 0
    return points, {'speed': speed}, {'speed': 0}


def main():
    plugin, out_dir = sys.argv[1], sys.argv[2]
    if len(sys.argv) == 5 and sys.argv[3] == 'dambreak':
        name, color, exponents = 'dambreak', 'vmag', {}
        points, arrays = read_particles(sys.argv[4])
    elif len(sys.argv) == 3:
        name, color = 'populations', 'speed'
        points, arrays, exponents = populations()
    else:
        sys.exit(__doc__)
    LoadPlugin(plugin, remote=False, ns=globals())
    view = CreateView('RenderView')
    prepare_view(view, SIZE, BACKGROUND)
    for kind in REPRESENTATIONS:
        representation = kind[0]
        stem = os.path.join(out_dir, 'TestScaleInvariance-%s-%s'
                            % (name, representation.replace(' ', '')))
        shots = {s: picture(view, producer(points, arrays, s, exponents), kind, color,
                            '%s-%g.png' % (stem, s), SIZE) for s in SCALES}
        unit = shots[1.0]
        drawn = drawn_fraction(unit['image'], BACKGROUND)
        check(drawn > 0.05, '%s draws the data at scale 1 (%.1f%% of the pixels; size array %s)'
              % (representation, 100 * drawn, unit['array']))
        for s in (1e-3, 1e3):
            shot = shots[s]
            error = rmse(shot['image'], unit['image'])
            check(error <= 4.0, '%s at scale %g: the picture at 1 (rmse %.3f of 255)'
                  % (representation, s, error))
            check(unit['size'] > 0 and shot['array'] == unit['array']
                  and abs(shot['size'] - s * unit['size']) <= 1e-6 * s * unit['size'],
                  '%s at scale %g: the size in use %.6g (array %s) is %g x %.6g'
                  % (representation, s, shot['size'], shot['array'], s, unit['size']))
    Delete(view)
    return finish()


if __name__ == '__main__':
    sys.exit(main())
