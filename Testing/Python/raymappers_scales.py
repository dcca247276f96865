"""What the scale-invariance test (TestScaleInvariance.py) and the defaults benchmark
(Testing/Benchmarks/defaults_on_data.py) share: particle data in other units of length, and
each particle representation shown on it at its defaults with only ColorBy set.

Data in other units: the points are multiplied by the scale, and every point array by the
scale to the power of its dimension in length (LENGTH_EXPONENT, by the array's name): a
length such as h or radius by the scale, a speed by the scale (the unit of time is kept), a
volume V by its cube, a density rho by the inverse cube, a pressure p (kg m^-1 s^-2) by the
inverse; arrays of other names (counts, types, ids, LJ energies, masses) are unchanged. The
same data in other units must give the same picture.
"""
import time

import numpy
from paraview.simple import ColorBy, Hide, PVTrivialProducer, Render, ResetCamera, Show
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData

from raymappers_testing import screenshot

# Representation, the information property of its constant size in use (0 when a size
# array is used), the property of its size array, the flag that turns the array on (None:
# the array's "None" entry turns it off) and the array's scale.
REPRESENTATIONS = (
    ('Ray-Traced Spheres', 'RadiusInUse', 'RadiusArray', 'UseRadiusArray', 'RadiusScale'),
    ('RBF Volume', 'RBFRadiusInUse', 'RBFRadiusArray', 'UseRBFRadiusArray', 'RBFRadiusScale'),
    ('SPH Volume', 'SPHSmoothingLengthInUse', 'SPHSmoothingLengthArray', None,
     'SPHSmoothingLengthScale'),
    ('SPH Fluid', 'SPHFluidRadiusInUse', 'SPHFluidRadiusArray', None, 'SPHFluidRadiusScale'))
SCALES = (1e-3, 1.0, 1e3)

# The power of length in each array's unit, by name; any other name: 0.
LENGTH_EXPONENT = {
    # lengths: PySPH's smoothing length, the radius and diameter of LAMMPS and LIGGGHTS
    'h': 1, 'hsml': 1, 'smoothing_length': 1, 'radius': 1, 'radii': 1, 'r': 1, 'diameter': 1,
    # speeds and velocity components: PySPH (u v w vmag), LAMMPS (vx vy vz, v_speed)
    'u': 1, 'v': 1, 'w': 1, 'vmag': 1, 'vx': 1, 'vy': 1, 'vz': 1, 'v_speed': 1, 'speed': 1,
    # PySPH's particle volume, density and pressure
    'V': 3, 'rho': -3, 'p': -1,
}


def read_particles(path):
    """The points (n, 3) and the point arrays {name: values} of a legacy VTK polydata file
    (the project's generators write these), all arrays read."""
    from vtkmodules.vtkIOLegacy import vtkPolyDataReader
    reader = vtkPolyDataReader()
    reader.SetFileName(path)
    reader.ReadAllScalarsOn()
    reader.ReadAllVectorsOn()
    reader.Update()
    data = reader.GetOutput()
    if data.GetNumberOfPoints() == 0:
        raise RuntimeError('%s: no points' % path)
    point_data = data.GetPointData()
    arrays = {}
    for i in range(point_data.GetNumberOfArrays()):
        array = point_data.GetArray(i)
        arrays[array.GetName()] = vtk_to_numpy(array).astype(float)
    return vtk_to_numpy(data.GetPoints().GetData()).astype(float), arrays


def producer(points, arrays, scale, exponents=None):
    """A source of the particles in units `scale` times smaller: points and arrays multiplied
    as the module says (`exponents`, {name: power}, overrides LENGTH_EXPONENT)."""
    exponents = dict(LENGTH_EXPONENT, **(exponents or {}))
    data = vtkPolyData()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(numpy.ascontiguousarray(points * scale), deep=1))
    data.SetPoints(vtk_points)
    for name, values in arrays.items():
        array = numpy_to_vtk(numpy.ascontiguousarray(values * scale ** exponents.get(name, 0)),
                             deep=1)
        array.SetName(name)
        data.GetPointData().AddArray(array)
    source = PVTrivialProducer()
    source.GetClientSideObject().SetOutput(data)
    source.UpdatePipeline()
    return source


def size_in_use(rep, source, kind):
    """(the size array the representation uses at its defaults, 'None' for its automatic or
    constant size; the size in use: the constant one, or the median of the array's values
    times the array's scale)."""
    _, size_property, array_property, use_property, scale_property = kind
    value = rep.GetPropertyValue(array_property)
    name = value if isinstance(value, str) else (list(value) or [''])[-1]
    rep.SMProxy.UpdatePropertyInformation()
    if not name or name == 'None' or (use_property is not None
                                      and not rep.GetPropertyValue(use_property)):
        return 'None', rep.SMProxy.GetProperty(size_property).GetElement(0)
    data = source.GetClientSideObject().GetOutputDataObject(0)
    values = vtk_to_numpy(data.GetPointData().GetArray(name))
    return name, float(numpy.median(values)) * rep.GetPropertyValue(scale_property)


def picture(view, source, kind, color, path, size):
    """`source` shown as `kind` (a row of REPRESENTATIONS) at its defaults, coloured by the
    point array `color` with the map rescaled to its range, the camera reset, saved to
    `path`: {image, array and size (size_in_use), seconds (the first still render, which
    also delivers the data and builds the mapper's structures)}."""
    rep = Show(source, view)
    rep.SetRepresentationType(kind[0])
    ColorBy(rep, ('POINTS', color))
    rep.RescaleTransferFunctionToDataRange(True, False)
    rep.SetScalarBarVisibility(view, False)
    ResetCamera(view)
    start = time.perf_counter()
    Render(view)
    seconds = time.perf_counter() - start
    image = screenshot(view, path, size)
    array, size_used = size_in_use(rep, source, kind)
    result = {'image': image, 'size': size_used, 'array': array, 'seconds': seconds}
    Hide(source, view)
    return result


def drawn_fraction(image, background, tolerance=8):
    """The fraction of the pixels that differ from the background by more than `tolerance`
    (of 255) in some channel."""
    return float((numpy.abs(image - numpy.array(background) * 255).max(axis=1) > tolerance)
                 .mean())
