"""pvpython: the plugin's LAMMPS dump reader opens a real dump through ParaView's reader
factory, with its atoms, arrays and time steps, and shows as ray-traced spheres.

usage: pvpython TestLAMMPSReaderPlugin.py PLUGIN.so DUMP
"""
import sys

from paraview.simple import (  # noqa: E402
    Delete, GetActiveViewOrCreate, LoadPlugin, OpenDataFile, Render, Show)

plugin, dump = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, remote=False, ns=globals())

failures = []


def check(condition, message):
    print(("ok    " if condition else "FAIL  ") + message)
    if not condition:
        failures.append(message)


reader = OpenDataFile(dump)
check(reader is not None and reader.GetXMLName() == "LAMMPSDumpReader",
      "the reader factory picks the LAMMPS dump reader for .dump")
reader.UpdatePipeline(0.0)
info = reader.GetDataInformation()
check(info.GetNumberOfPoints() == 256, "256 atoms at step 0")
check(list(reader.TimestepValues) == [0.0, 100.0], "time steps 0 and 100")
arrays = [reader.PointData.GetArray(i).GetName() for i in range(len(reader.PointData))]
check("type" in arrays and "vx" in arrays, "point arrays type and vx")

view = GetActiveViewOrCreate("RenderView")
display = Show(reader, view)
display.SetRepresentationType("Ray-Traced Spheres")
display.Radius = 0.4
Render(view)
check(display.GetProperty("Radius") is not None, "shown as Ray-Traced Spheres")
Delete(view)
del view

if failures:
    sys.exit(1)
print("all checks passed")
