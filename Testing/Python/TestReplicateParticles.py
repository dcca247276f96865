"""pvpython: Data/Generators/replicate_particles.py (the scale benchmarks' packings) tiles
its input. On the bundled PySPH dam break replicated 3 x 2 x 1 (arrays h and rho kept),
read back by VTK's own legacy reader (not the generator's parser), with gaps 0 and 0.05, it
checks:
- 6 copies of every particle, copy after copy, x fastest;
- copy (a, b, c) is the input shifted by (a, b, c) times the input's extent plus the gap;
- the kept arrays, and only those, repeated copy by copy.
(The default gap, the largest radius, needs a radius array, which the bundled file lacks.)

usage: pvpython TestReplicateParticles.py SOURCE_DIR TEMP_DIR
"""
import os
import subprocess
import sys

import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, finish  # noqa: E402
from TestRefineParticles import read  # noqa: E402


def main(source, temp):
    original = os.path.join(source, 'Data', 'dam_break_coarse_00674.vtk')
    generator = os.path.join(source, 'Data', 'Generators', 'replicate_particles.py')
    points, arrays = read(original)
    n = len(points)
    extent = points.max(axis=0) - points.min(axis=0)
    counts = (3, 2, 1)
    for gap in (0.0, 0.05):
        out = os.path.join(temp, 'replicated-%s.vtk' % gap)
        for f in (out, out + '.provenance.txt'):
            if os.path.exists(f):
                os.remove(f)
        command = ['/usr/bin/python3', generator, original, out] + [str(c) for c in counts]
        command += ['--arrays', 'h,rho', '--gap', str(gap)]
        subprocess.run(command, check=True)
        tiled, tiled_arrays = read(out)
        copies = counts[0] * counts[1] * counts[2]
        check(len(tiled) == copies * n, 'gap %s: %d particles, expected %d' % (gap, len(tiled), copies * n))
        if len(tiled) != copies * n:
            continue
        period = extent + gap
        worst = 0.0
        for index in range(copies):
            a, b, c = index % counts[0], (index // counts[0]) % counts[1], index // (counts[0] * counts[1])
            shift = period * numpy.array([a, b, c])
            block = tiled[index * n:(index + 1) * n]
            worst = max(worst, float(numpy.abs(block - (points + shift)).max()))
        check(worst < 1e-5 * float(extent.max()), 'gap %s: copies at their shifts (off by %g)' % (gap, worst))
        for name in ('h', 'rho'):
            want = numpy.tile(arrays[name], copies)
            check(numpy.array_equal(tiled_arrays[name], want), 'gap %s: %s repeated copy by copy' % (gap, name))
        check(set(tiled_arrays) == {'h', 'rho'}, 'gap %s: only the kept arrays (%s)' % (gap, sorted(tiled_arrays)))
    return finish()


if __name__ == '__main__':
    sys.exit(main(sys.argv[1], sys.argv[2]))
