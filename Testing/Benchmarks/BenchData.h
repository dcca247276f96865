// Data for the benchmark and the demo: any file VTK reads (legacy .vtk, XML, Exodus, PDB,
// PLOT3D NAMExyz.bin with NAMEq.bin beside it, LAMMPS text dumps), turned into what a suite
// renders: all points with their point data (particle suites) or the cells (volume suites).
#ifndef RayMappers_BenchData_h
#define RayMappers_BenchData_h

#include "vtkSmartPointer.h"

#include <string>

class vtkDataObject;
class vtkPolyData;
class vtkDataArray;

namespace bench
{

/// Reads a file by its extension; nullptr and a message on stderr when it cannot.
vtkSmartPointer<vtkDataObject> ReadAny(const std::string& path);

/// Every point of a data set or composite data set, with its point data, as polydata with
/// one vertex per point (arrays that not every block has are dropped).
vtkSmartPointer<vtkPolyData> ToPointCloud(vtkDataObject* data);

/// The point array used as particle radius (first component): the first of radius, radii, r,
/// Radius, diameter (halved), smoothing_length (halved) present; nullptr if none.
vtkDataArray* FindRadiusArray(vtkPolyData* points, std::string& name, double& factor);

/// The point array to colour by: the active scalars if 1 component, else the first of
/// type, atom_type, Temp, ... else the first 1-component array; nullptr if none.
vtkDataArray* FindColorArray(vtkPolyData* points);

/// A radius for point sets without a radius array: half the mean spacing
/// (bounding-box volume / N)^(1/3) / 2.
double DefaultRadius(vtkPolyData* points);

/// Base name of a path without folders and without the last extension.
std::string BaseName(const std::string& path);

}

#endif
