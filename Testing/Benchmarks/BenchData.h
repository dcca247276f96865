// Data for the benchmark and the demo: any file VTK reads (legacy .vtk, XML, Exodus, PDB,
// PLOT3D NAMExyz.bin with NAMEq.bin beside it, LAMMPS text dumps), turned into what a suite
// renders: all points with their point data (particle suites) or the cells (volume suites).
#ifndef RayMappers_BenchData_h
#define RayMappers_BenchData_h

#include "vtkRayMapperParticleSizes.h"
#include "vtkSmartPointer.h"

#include <initializer_list>
#include <string>

class vtkDataObject;
class vtkDataSet;
class vtkPolyData;
class vtkDataArray;

namespace bench
{

/// Reads a file by its extension; nullptr and a message on stderr when it cannot.
vtkSmartPointer<vtkDataObject> ReadAny(const std::string& path);

/// Every point of a data set or composite data set, with its point data, as polydata with
/// one vertex per point (arrays that not every block has are dropped).
vtkSmartPointer<vtkPolyData> ToPointCloud(vtkDataObject* data);

/// The automatic sizes per typical particle spacing: the mappers' own
/// (vtkRayMapperParticleSizes), the SPH smoothing length for the kernels of support 2h.
using vtkRayMapperParticleSizes::FluidRadiusPerSpacing;
using vtkRayMapperParticleSizes::RBFRadiusPerSpacing;
using vtkRayMapperParticleSizes::SphereRadiusPerSpacing;
constexpr double SPHSmoothingPerSpacing = vtkRayMapperParticleSizes::SPHSupportPerSpacing / 2.0;

/// A particle size as a mapper takes it: a point array (ScaleArray) times `scale`, or the
/// constant length `constant` when `array` is empty.
struct ParticleSize
{
  std::string array;
  double scale = 1.0;
  double constant = 0.0;
  /// What was chosen and why, for the suites' printout.
  std::string how;
};

/// The size the representations choose by default, with the bench's override: `override`
/// when positive (--radius, --h); else the array vtkRayMapperParticleSizes::FindSizeArrayName
/// names for `role` (the other role's names too with `acceptOther`); else the automatic
/// constant, `perSpacing` times the points' typical spacing.
ParticleSize ChooseSize(vtkDataSet* points,
  vtkRayMapperParticleSizes::Role role,
  bool acceptOther,
  double perSpacing,
  double override);

/// The first point array whose name is one of `names` (in that order, ignoring case) and
/// that has `components` components (0: any); nullptr if none.
vtkDataArray* FindNamedArray(vtkDataSet* points,
  std::initializer_list<const char*> names,
  int components = 0);

/// The point arrays for a message: "'rho' (1), 'v' (3)" (name and components), "none".
std::string ListPointArrays(vtkDataSet* points);

/// A flow's speed: a 1-component vmag, speed or velocity_magnitude array, else the magnitude
/// of a 3-component v, vel or velocity array, added to the point data as "<name>_magnitude";
/// nullptr if none.
vtkDataArray* FindSpeedArray(vtkPolyData* points);

/// The point array a suite colours or samples by: `requested` (--array) when given; else,
/// with `preferSpeed`, FindSpeedArray; else FindColorArray. False, with a message naming
/// `file`, the array and the arrays present, when `requested` is not a point array of the
/// file; `chosen` may be nullptr otherwise (no 1-component array).
bool ChooseValueArray(vtkPolyData* points,
  const std::string& requested,
  const std::string& file,
  bool preferSpeed,
  vtkDataArray*& chosen);

/// The point array to colour by: the active scalars if 1 component, else the first of
/// type, atom_type, Temp, ... else the first 1-component array; nullptr if none.
vtkDataArray* FindColorArray(vtkDataSet* points);

/// Base name of a path without folders and without the last extension.
std::string BaseName(const std::string& path);

}

#endif
