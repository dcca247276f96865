// The particles' sizes when the user gave none, as every RayMappers mapper, filter,
// representation and the bench choose them: a size array recognised by its name, else a
// constant length proportional to the particles' typical spacing (ParticleSpacing.h), so
// that the same data in other units gives the same picture.
#ifndef vtkRayMapperParticleSizes_h
#define vtkRayMapperParticleSizes_h

#include "RayMappersCoreModule.h" // for export macro
#include "vtkType.h"              // for vtkMTimeType

#include <string> // for std::string
#include <vector> // for std::vector

class vtkDataSet;
class vtkPoints;

namespace vtkRayMapperParticleSizes
{

/// The automatic sizes per typical spacing s (the reasons are in each mapper's header):
/// touching spheres, a Gaussian as wide as the spacing, the SPH kernel support SPH codes use,
/// a fluid of overlapping spheres without cavities.
constexpr double SphereRadiusPerSpacing = 0.5;
constexpr double RBFRadiusPerSpacing = 1.0;
constexpr double SPHSupportPerSpacing = 2.4;
constexpr double FluidRadiusPerSpacing = 1.0;

/// What a size array is to be: a sphere's radius, or an SPH smoothing length h.
enum class Role
{
  Radius,
  SmoothingLength
};

/// The point array of `input` that conventionally holds the size `role` asks for, and in
/// `scale` the factor that turns its values into that size; nullptr when none is there.
/// Names are matched ignoring case, in this order: for Radius "radius", "radii", "r",
/// "diameter" (scale 0.5); for SmoothingLength "h", "hsml", "smoothing_length",
/// "smoothinglength". With `acceptOther`, the other role's names come next (scale 1): an
/// RBF or a fluid radius may come from h, and an SPH smoothing length from a radius.
RAYMAPPERSCORE_EXPORT const char* FindSizeArrayName(vtkDataSet* input,
  Role role,
  bool acceptOther,
  double& scale);

/// The same choice among `names` alone (e.g. the arrays a ParaView domain lists on the
/// client, which has no dataset): the index of the chosen name and its `scale`, or -1.
RAYMAPPERSCORE_EXPORT int FindSizeName(const std::vector<std::string>& names,
  Role role,
  bool acceptOther,
  double& scale);

/// The typical spacing of a point set (raymappers::typicalParticleSpacing: the median
/// nearest-distinct-neighbour distance over a sample), computed again only when the points
/// or their modification time change: a camera change costs nothing.
class RAYMAPPERSCORE_EXPORT SpacingCache
{
public:
  double Spacing(vtkPoints* points);

private:
  vtkPoints* Points = nullptr;
  vtkMTimeType Time = 0;
  double Value = 0.0;
};

/// The sample's nearest-neighbour distances of one process's piece `points` of a set of
/// `totalCount` points over all processes (raymappers::spacingSampleDistances on the piece's
/// share of the 1024 samples): their median gathered from all pieces is the set's typical
/// spacing, up to the sampling's noise.
RAYMAPPERSCORE_EXPORT std::vector<double> SpacingSampleDistances(vtkPoints* points,
  std::size_t totalCount);

/// The median of sample distances gathered from the pieces (raymappers::medianSpacing): 0
/// when there are none or half of them found no neighbour.
RAYMAPPERSCORE_EXPORT double MedianSpacing(const std::vector<double>& distances);

/// The automatic constant size: `perSpacing` times the typical spacing of the input's points;
/// when that is 0 (fewer than two distinct finite points) 1% of the finite bounds' diagonal,
/// and 1 when that is 0 too (a single point).
RAYMAPPERSCORE_EXPORT double AutomaticLength(vtkDataSet* input,
  double perSpacing,
  SpacingCache& cache);

/// The same from a spacing already known (e.g. reduced over processes): `perSpacing` *
/// `spacing` when positive, else the bounds fallback above for `bounds` (may be uninitialized).
RAYMAPPERSCORE_EXPORT double AutomaticLengthFrom(double spacing,
  const double bounds[6],
  double perSpacing);

} // namespace vtkRayMapperParticleSizes

#endif
