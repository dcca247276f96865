"""pvpython: Data/Generators/refine_particles.py (the scale benchmarks' SPH data) keeps the
fluid it refines. On the coarse PySPH dam break refined K = 2 and 3, read back by VTK's own
legacy reader (not the generator's parser), it checks:
- K^3 particles per input particle, in the input's order (particle i's lattice at rows
  K^3 i .. K^3 (i + 1) - 1);
- each lattice is centred on its particle (mean offset 0) and spans dx (K - 1) / K per
  axis at spacing dx / K, dx = h / 1.3 (PySPH's hdx);
- h / K, m / K^3 (the total mass kept), rho and vmag copied;
- an existing output is kept (the cache).

usage: pvpython TestRefineParticles.py SOURCE_DIR TEMP_DIR
"""
import os
import subprocess
import sys

import numpy
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOLegacy import vtkPolyDataReader

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import check, finish  # noqa: E402


def read(path):
    reader = vtkPolyDataReader()
    reader.SetFileName(path)
    reader.ReadAllScalarsOn()
    reader.Update()
    data = reader.GetOutput()
    arrays = {data.GetPointData().GetArrayName(i): vtk_to_numpy(data.GetPointData().GetArray(i))
              for i in range(data.GetPointData().GetNumberOfArrays())}
    return vtk_to_numpy(data.GetPoints().GetData()).astype(numpy.float64), arrays


def main(source, temp):
    original = os.path.join(source, 'Data', 'dam_break_coarse_00674.vtk')
    generator = os.path.join(source, 'Data', 'Generators', 'refine_particles.py')
    points, arrays = read(original)
    n = len(points)
    dx = float(numpy.median(arrays['h'])) / 1.3
    for k in (2, 3):
        out = os.path.join(temp, 'refined%d.vtk' % k)
        if os.path.exists(out):
            os.remove(out)
        subprocess.run(['/usr/bin/python3', generator, original, out, str(k)], check=True)
        fine, fine_arrays = read(out)
        per = k ** 3
        check(len(fine) == per * n, 'K=%d: %d particles, expected %d' % (k, len(fine), per * n))
        if len(fine) != per * n:
            continue
        lattice = fine.reshape(n, per, 3) - points[:, None, :]
        centre = numpy.abs(lattice.mean(axis=1)).max()
        check(centre < 1e-6, 'K=%d: lattices centred on their particle (off by %g)' % (k, centre))
        span = (lattice.max(axis=1) - lattice.min(axis=1)).max(axis=0)
        expect = dx * (k - 1) / k
        check(numpy.allclose(span, expect, rtol=1e-4),
              'K=%d: lattice spans %s, expected %g' % (k, span, expect))
        step = numpy.diff(numpy.unique(numpy.round(lattice[0, :, 0] / (dx / k), 3)))
        check(numpy.allclose(step, 1.0, atol=1e-3),
              'K=%d: lattice steps %s in units of dx / K' % (k, step))
        for name, factor in (('h', 1.0 / k), ('m', 1.0 / per), ('rho', 1.0), ('vmag', 1.0)):
            want = numpy.repeat(arrays[name].astype(numpy.float64) * factor, per)
            got = fine_arrays[name].astype(numpy.float64)
            check(numpy.allclose(got, want, rtol=1e-6),
                  'K=%d: %s is the input\'s times %g' % (k, name, factor))
        total = float(fine_arrays['m'].astype(numpy.float64).sum())
        expect_total = float(arrays['m'].astype(numpy.float64).sum())
        check(abs(total - expect_total) < 1e-5 * expect_total,
              'K=%d: total mass %g, the input\'s %g' % (k, total, expect_total))
        stamp = os.path.getmtime(out)
        subprocess.run(['/usr/bin/python3', generator, original, out, str(k)], check=True)
        check(os.path.getmtime(out) == stamp, 'K=%d: the existing output is kept' % k)
    return finish()


if __name__ == '__main__':
    sys.exit(main(sys.argv[1], sys.argv[2]))
