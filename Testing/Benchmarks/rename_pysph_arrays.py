"""Writes a PySPH legacy file with the arrays renamed as other SPH codes name them (vmag ->
speed, h -> hsml) and the mass m dropped: the data of the Bench.SPHRenamedArrays test, which
checks that raymappers-bench finds its arrays by their conventional names.

usage: pvpython rename_pysph_arrays.py IN.vtk OUT.vtk
"""
import sys

from vtkmodules.vtkIOLegacy import vtkPolyDataReader, vtkPolyDataWriter

reader = vtkPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.ReadAllScalarsOn()
reader.Update()
particles = reader.GetOutput()
arrays = particles.GetPointData()
for old, new in (('vmag', 'speed'), ('h', 'hsml')):
    if not arrays.GetArray(old):
        sys.exit('%s has no point array %s' % (sys.argv[1], old))
    arrays.GetArray(old).SetName(new)
arrays.RemoveArray('m')
writer = vtkPolyDataWriter()
writer.SetInputData(particles)
writer.SetFileName(sys.argv[2])
writer.SetFileTypeToBinary()
sys.exit(0 if writer.Write() == 1 else 1)
