"""RayMappers demo gallery: renders the bundled data with the ray-traced sphere mapper, the
RBF volume mapper, the ZSweep unstructured-grid mapper, the SPH volume mapper and the SPH
fluid mapper.

Run through ../run.sh demo, or by hand under Xvfb:
    pvpython Examples/gallery.py --build build --out gallery

Each view is saved as a PNG in the output folder; a table of what was rendered and how
long it took is printed at the end (first frame with the build, and the median of the
following frames of the same view).
"""
import argparse
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--build", default=os.path.join(SOURCE, "build"), help="build folder")
    p.add_argument("--out", default=os.path.join(SOURCE, "gallery"), help="output folder")
    p.add_argument("--size", default="1024x768", help="image size WxH")
    p.add_argument("--frames", type=int, default=3, help="frames timed after the first")
    p.add_argument("--skip-generated", action="store_true",
                   help="do not generate / render the 1M-atom LAMMPS melt")
    return p.parse_args()


args = parse_args()
sys.path.insert(0, os.path.join(args.build, "lib", "python3", "dist-packages"))

from vtkmodules import vtkRenderingOpenGL2  # noqa: E402,F401 (OpenGL factory overrides)
from vtkmodules.vtkCommonCore import vtkLookupTable  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPolyData  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkAppendFilter, vtkTubeFilter  # noqa: E402
from vtkmodules.vtkFiltersModeling import vtkOutlineFilter  # noqa: E402
from vtkmodules.vtkIOChemistry import vtkPDBReader  # noqa: E402
from vtkmodules.vtkIOExodus import vtkExodusIIReader  # noqa: E402
from vtkmodules.vtkIOImage import vtkPNGWriter  # noqa: E402
from vtkmodules.vtkIOLegacy import vtkPolyDataReader  # noqa: E402
from vtkmodules.vtkRenderingCore import (  # noqa: E402
    vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow, vtkWindowToImageFilter)

import raymappers  # noqa: E402

WIDTH, HEIGHT = (int(v) for v in args.size.split("x"))
DATA = os.path.join(SOURCE, "Data")


def sphere_actor(points, radius_array=None, radius=1.0, scale=1.0, color_array=None,
                 scalar_range=None, direct_colors=False, lut=None):
    mapper = raymappers.vtkCGTSphereMapper()
    mapper.SetInputData(points)
    if radius_array:
        mapper.SetRadiusArrayName(radius_array)
    mapper.SetRadius(radius)
    mapper.SetRadiusScale(scale)
    if color_array:
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray(color_array)
        if direct_colors:
            mapper.SetColorModeToDirectScalars()
        if scalar_range:
            mapper.SetScalarRange(*scalar_range)
        if lut:
            mapper.SetLookupTable(lut)
    else:
        mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetSpecular(0.35)
    actor.GetProperty().SetSpecularPower(40)
    actor.GetProperty().SetAmbient(0.08)
    return actor, mapper


def volume_of(mapper, color, opacity, unit):
    """A vtkVolume of `mapper` classified by one colour and one opacity function, the
    opacity per `unit` of length."""
    from vtkmodules.vtkRenderingCore import vtkVolume, vtkVolumeProperty
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(unit)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    return volume


def points_only(dataset):
    """All points of a data set with their point data (cells dropped)."""
    pd = vtkPolyData()
    pd.SetPoints(dataset.GetPoints())
    pd.GetPointData().ShallowCopy(dataset.GetPointData())
    return pd


def render_view(name, dataset, actors, mapper, camera, count="spheres"):
    ren = vtkRenderer()
    ren.SetBackground(0.12, 0.13, 0.16)
    ren.SetBackground2(0.32, 0.34, 0.43)
    ren.GradientBackgroundOn()
    for a in actors:
        ren.AddActor(a)
    win = vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(WIDTH, HEIGHT)
    win.AddRenderer(ren)
    camera(ren)
    ren.ResetCameraClippingRange()
    t = time.perf_counter()
    win.Render()
    win.WaitForCompletion()
    first = (time.perf_counter() - t) * 1000
    stats = mapper.GetStatistics()
    build = sum(stats.GetPhaseTime(p)
                for p in ("spheres", "grid_build", "bvh_build", "grid", "particles", "cells",
                          "mesh"))
    times = []
    for _ in range(args.frames):
        t = time.perf_counter()
        win.Render()
        win.WaitForCompletion()
        times.append((time.perf_counter() - t) * 1000)
    stats = mapper.GetStatistics()
    grab = vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.ReadFrontBufferOff()
    grab.Update()
    png = os.path.join(args.out, name + ".png")
    writer = vtkPNGWriter()
    writer.SetInputConnection(grab.GetOutputPort())
    writer.SetFileName(png)
    writer.Write()
    return dict(view=name, dataset=dataset, spheres=stats.GetCounter(count),
                build=build, first=first, frame=statistics.median(times) if times else first,
                trace=sum(stats.GetPhaseTime(p) for p in ("trace", "raycast", "splat", "compress",
                                                          "connect", "filter", "normals",
                                                          "render", "refract", "project",
                                                          "bin", "order", "sweep")),
                png=os.path.relpath(png, os.getcwd()))


def look(position, focal=None, up=(0, 1, 0), angle=30, parallel_scale=None, zoom=1.0):
    def setup(ren):
        cam = ren.GetActiveCamera()
        ren.ResetCamera()
        f = focal or cam.GetFocalPoint()
        d = cam.GetDistance()
        cam.SetFocalPoint(*f)
        cam.SetPosition(*(f[i] + position[i] * d for i in range(3)))
        cam.SetViewUp(*up)
        cam.SetViewAngle(angle)
        if parallel_scale:
            cam.ParallelProjectionOn()
            cam.SetParallelScale(parallel_scale)
        cam.Zoom(zoom)
    return setup


def read_lysozyme():
    """2LYZ.pdb: the protein (atoms and bonds) as vtkPDBReader gives it."""
    reader = vtkPDBReader()
    reader.SetFileName(os.path.join(DATA, "2LYZ.pdb"))
    reader.Update()
    return reader.GetOutput()


def read_disk():
    """disk_out_ref.ex2's first block with all nodal arrays, as one unstructured grid."""
    reader = vtkExodusIIReader()
    reader.SetFileName(os.path.join(DATA, "disk_out_ref.ex2"))
    reader.UpdateInformation()
    reader.SetAllArrayStatus(vtkExodusIIReader.NODAL, 1)
    reader.Update()
    append = vtkAppendFilter()
    append.SetInputData(reader.GetOutput().GetBlock(0).GetBlock(0))
    append.Update()
    return append.GetOutput()


def lysozyme_views():
    protein = read_lysozyme()
    atoms = points_only(protein)
    views = []
    actor, mapper = sphere_actor(atoms, "radius", color_array="rgb_colors", direct_colors=True)
    views.append(render_view("lysozyme-spacefill", "2LYZ.pdb", [actor], mapper,
                             look((0.3, 0.25, 1.0), zoom=1.8)))
    # Ball and stick: small ray-traced atoms with OpenGL tubes for the bonds, hiding each
    # other through the depth buffer.
    actor, mapper = sphere_actor(atoms, "radius", scale=0.28, color_array="rgb_colors",
                                 direct_colors=True)
    tubes = vtkTubeFilter()
    tubes.SetInputData(protein)
    tubes.SetRadius(0.14)
    tubes.SetNumberOfSides(10)
    bonds = vtkPolyDataMapper()
    bonds.SetInputConnection(tubes.GetOutputPort())
    bonds.ScalarVisibilityOff()
    bond_actor = vtkActor()
    bond_actor.SetMapper(bonds)
    bond_actor.GetProperty().SetColor(0.8, 0.8, 0.8)
    views.append(render_view("lysozyme-ball-and-stick", "2LYZ.pdb", [actor, bond_actor], mapper,
                             look((0.3, 0.25, 1.0), zoom=1.9)))
    lut = vtkLookupTable()
    lut.SetHueRange(0.6, 0.0)
    lut.Build()
    actor, mapper = sphere_actor(atoms, "radius", color_array="residue", scalar_range=(0, 129),
                                 lut=lut)
    views.append(render_view("lysozyme-residues-parallel", "2LYZ.pdb", [actor], mapper,
                             look((0, 0, 1), parallel_scale=24)))
    return views


def disk_view():
    grid = read_disk()
    points = points_only(grid)
    actor, mapper = sphere_actor(points, radius=0.16, color_array="Temp",
                                 scalar_range=grid.GetPointData().GetArray("Temp").GetRange())
    outline = vtkOutlineFilter()
    outline.SetInputData(grid)
    om = vtkPolyDataMapper()
    om.SetInputConnection(outline.GetOutputPort())
    oa = vtkActor()
    oa.SetMapper(om)
    return [render_view("disk-out-ref-temperature", "disk_out_ref.ex2", [actor, oa], mapper,
                        look((1.0, 0.6, 0.8), up=(0, 0, 1), zoom=1.4))]


def lysozyme_rbf_view():
    """2LYZ as a Gaussian RBF field (Knoll et al.), the atoms' van der Waals radii as r_i,
    in two fields classified apart: the carbon atoms (warm colours) and the rest (green)."""
    from vtkmodules.vtkCommonCore import vtkFloatArray
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolume, vtkVolumeProperty
    atoms = points_only(read_lysozyme())
    types = atoms.GetPointData().GetArray("atom_type")
    carbon = vtkFloatArray()
    carbon.SetName("carbon_or_not")
    carbon.SetNumberOfTuples(types.GetNumberOfTuples())
    for i in range(types.GetNumberOfTuples()):
        carbon.SetValue(i, 0.0 if types.GetComponent(i, 0) == 6 else 1.0)
    atoms.GetPointData().AddArray(carbon)
    mapper = raymappers.vtkRBFVolumeMapper()
    mapper.SetInputData(atoms)
    mapper.SetRadiusArrayName("radius")
    mapper.SetFieldArrayName("carbon_or_not")
    prop = vtkVolumeProperty()
    prop.SetIndependentComponents(1)
    peak = 1.5  # about the largest field value (kappa 1, sigma 2)
    for m, points in enumerate(([(0.0, 0.6, 0.2, 0.1), (peak, 1.0, 0.8, 0.3)],
                                [(0.0, 0.1, 0.5, 0.3), (peak, 0.6, 0.95, 0.7)])):
        color = vtkColorTransferFunction()
        for v, r, g, b in points:
            color.AddRGBPoint(v, r, g, b)
        opacity = vtkPiecewiseFunction()
        opacity.AddPoint(0.0, 0.0)
        opacity.AddPoint(0.1 * peak, 0.0)
        opacity.AddPoint(peak, 0.35)
        prop.SetColor(m, color)
        prop.SetScalarOpacity(m, opacity)
        prop.SetScalarOpacityUnitDistance(m, 1.7)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    return [render_view("lysozyme-rbf-two-fields", "2LYZ.pdb", [volume], mapper,
                        look((0.3, 0.25, 1.0), zoom=1.8), count="particles")]


def disk_zsweep_view():
    """disk_out_ref's temperature, volume rendered exactly through its tetrahedra by the
    sweep (Farias et al.)."""
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkFiltersGeneral import vtkDataSetTriangleFilter
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction
    tets = vtkDataSetTriangleFilter()
    tets.SetInputData(read_disk())
    tets.Update()
    grid = tets.GetOutput()
    lo, hi = grid.GetPointData().GetArray("Temp").GetRange()
    mapper = raymappers.vtkZSweepVolumeMapper()
    mapper.SetInputData(grid)
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectScalarArray("Temp")
    color = vtkColorTransferFunction()
    color.AddRGBPoint(lo, 0.23, 0.30, 0.75)
    color.AddRGBPoint(0.5 * (lo + hi), 0.87, 0.87, 0.87)
    color.AddRGBPoint(hi, 0.71, 0.02, 0.15)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(lo, 0.02)
    opacity.AddPoint(0.5 * (lo + hi), 0.15)
    opacity.AddPoint(hi, 0.9)
    volume = volume_of(mapper, color, opacity, 1.0)
    return [render_view("disk-out-ref-zsweep", "disk_out_ref.ex2", [volume], mapper,
                        look((1.0, 0.6, 0.5), up=(0, 0, 1), zoom=2.2), count="cells")]


def melt_view():
    path = os.path.join(args.build, "data", "lammps_melt_1M.vtk")
    if not os.path.exists(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        print("generating the LAMMPS melt (1,000,188 atoms, about a minute) ...", flush=True)
        subprocess.run(["bash", os.path.join(DATA, "Generators", "lammps_melt.sh"), path],
                       check=True)
    reader = vtkPolyDataReader()
    reader.SetFileName(path)
    reader.ReadAllScalarsOn()
    reader.Update()
    melt = reader.GetOutput()
    lut = vtkLookupTable()
    lut.SetNumberOfTableValues(2)
    lut.SetTableValue(0, 0.85, 0.55, 0.2, 1)
    lut.SetTableValue(1, 0.25, 0.55, 0.9, 1)
    lut.Build()
    actor, mapper = sphere_actor(melt, "radius", color_array="type", scalar_range=(1, 2),
                                 lut=lut)
    return [render_view("lammps-melt-1M", "lammps_melt_1M.vtk", [actor], mapper,
                        look((0.9, 0.6, 1.1), zoom=1.7))]


def dam_break_view():
    """A PySPH dam break frame (t = 0.3 s) as its SPH field: velocity magnitude, normalized,
    PySPH's kernel and smoothing lengths, contour shading at the free surface, jittered
    samples."""
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    reader = vtkPolyDataReader()
    reader.SetFileName(os.path.join(DATA, "dam_break_coarse_00674.vtk"))
    reader.ReadAllScalarsOn()
    reader.Update()
    mapper = raymappers.vtkSPHVolumeMapper()
    mapper.SetInputData(reader.GetOutput())
    mapper.SetKernel(raymappers.VTK_SPH_KERNEL_WENDLAND_C2)
    mapper.SetSmoothingLengthArrayName("h")
    mapper.SetMassArrayName("m")
    mapper.SetDensityArrayName("rho")
    mapper.SetValueArrayName("vmag")
    mapper.ContourShadingOn()
    mapper.SetContourColor(0.02, 0.05, 0.15)
    mapper.JitterOn()  # noise instead of wood-grain rings at the fluid's sharp boundary
    color = vtkColorTransferFunction()
    color.AddRGBPoint(0.0, 0.1, 0.3, 0.9)
    color.AddRGBPoint(1.4, 0.9, 0.9, 0.9)
    color.AddRGBPoint(2.8, 0.9, 0.2, 0.1)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(0.0, 0.15)
    opacity.AddPoint(2.8, 0.6)
    volume = volume_of(mapper, color, opacity, 0.1)

    def camera(ren):
        cam = ren.GetActiveCamera()
        cam.SetFocalPoint(0.9, 0.0, 0.2)
        cam.SetPosition(0.0, -3.4, 1.9)
        cam.SetViewUp(0, 0, 1)
    return [render_view("dam-break-sph-volume", "dam_break_coarse_00674", [volume], mapper,
                        camera, count="particles")]


def paraview_view():
    """The same mapper through ParaView: the plugin's 'Ray-Traced Spheres' representation."""
    from paraview import simple
    plugin = os.path.join(args.build, "lib", "paraview-plugins", "RayMappers", "RayMappers.so")
    simple.LoadPlugin(plugin, remote=False, ns=globals())
    reader = simple.OpenDataFile(os.path.join(DATA, "2LYZ.pdb"))
    view = simple.CreateView("RenderView")
    view.ViewSize = [WIDTH, HEIGHT]
    view.OrientationAxesVisibility = 0
    display = simple.Show(reader, view)
    display.SetRepresentationType("Ray-Traced Spheres")
    display.UseRadiusArray = 1
    display.RadiusArray = ["POINTS", "atom_type"]
    display.RadiusScale = 0.2
    simple.ColorBy(display, ("POINTS", "residue"))
    simple.Render(view)
    view.ResetCamera()
    t = time.perf_counter()
    simple.Render(view)
    first = (time.perf_counter() - t) * 1000
    times = []
    for _ in range(args.frames):
        t = time.perf_counter()
        simple.Render(view)
        times.append((time.perf_counter() - t) * 1000)
    png = os.path.join(args.out, "paraview-ray-traced-spheres.png")
    simple.SaveScreenshot(png, view, ImageResolution=[WIDTH, HEIGHT])
    points = reader.GetDataInformation().GetNumberOfPoints()
    simple.Delete(view)
    return [dict(view="paraview-ray-traced-spheres", dataset="2LYZ.pdb", spheres=points,
                 build=float("nan"), first=first,
                 frame=statistics.median(times) if times else first, trace=float("nan"),
                 png=os.path.relpath(png, os.getcwd()))]


def dam_break_fluid_view():
    """The same dam break frame as water (vtkSPHFluidMapper, Zirr 2015): spheres of 0.8 h
    voxelized into spans, at the mapper's defaults (smoothing 4 radii, translucent, the
    default absorption: grey where thin, blue where deep, white highlights; boundary-cell
    culling) with refraction (index 1.33) and a white solid colour."""
    from vtkmodules.vtkRenderingCore import vtkVolume, vtkVolumeProperty
    reader = vtkPolyDataReader()
    reader.SetFileName(os.path.join(DATA, "dam_break_coarse_00674.vtk"))
    reader.ReadAllScalarsOn()
    reader.Update()
    mapper = raymappers.vtkSPHFluidMapper()
    mapper.SetInputData(reader.GetOutput())
    mapper.SetRadiusArrayName("h")
    mapper.SetRadiusScale(0.8)
    mapper.SetRefractiveIndex(1.33)
    mapper.SetColor(1.0, 1.0, 1.0)
    prop = vtkVolumeProperty()
    prop.SetAmbient(0.25)
    prop.SetDiffuse(0.75)
    prop.SetSpecular(0.3)
    prop.SetSpecularPower(40)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    def camera(ren):
        cam = ren.GetActiveCamera()
        cam.SetFocalPoint(0.9, 0.0, 0.2)
        cam.SetPosition(0.0, -3.4, 1.9)
        cam.SetViewUp(0, 0, 1)
    return [render_view("dam-break-sph-fluid", "dam_break_coarse_00674", [volume], mapper,
                        camera, count="particles")]


def main():
    os.makedirs(args.out, exist_ok=True)
    rows = lysozyme_views() + lysozyme_rbf_view() + disk_view() + disk_zsweep_view() + \
        dam_break_view() + dam_break_fluid_view() + paraview_view()
    if not args.skip_generated:
        rows += melt_view()
    print("\nRayMappers demo gallery: %dx%d, CPU ray-traced spheres (coherent grid traversal),"
          " RBF volume ray casting (coherent BVH), exact unstructured-grid volume rendering"
          " (ZSweep), SPH volume ray casting (perspective grid) and SPH fluid voxelization"
          " (spans)" % (WIDTH, HEIGHT))
    header = ("view", "dataset", "points", "build_ms", "first_ms", "frame_ms", "trace_ms", "png")
    print("%-28s %-20s %9s %9s %9s %9s %9s  %s" % header)
    for r in rows:
        print("%-28s %-20s %9d %9.1f %9.1f %9.1f %9.1f  %s" % (
            r["view"], r["dataset"], r["spheres"], r["build"], r["first"], r["frame"], r["trace"],
            r["png"]))


main()
