#include "vtkRayMapperParticleSizes.h"

#include "Mappers/Common/ParticleSpacing.h"
#include "vtkRayMapperPointArrays.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkMath.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"

#include <array>
#include <cctype>
#include <cmath>
#include <string>

namespace vtkRayMapperParticleSizes
{
namespace
{
struct SizeName
{
  const char* name;
  double scale;
};
const SizeName RadiusNames[] = { { "radius", 1.0 }, { "radii", 1.0 }, { "r", 1.0 },
  { "diameter", 0.5 } };
const SizeName SmoothingNames[] = { { "h", 1.0 }, { "hsml", 1.0 }, { "smoothing_length", 1.0 },
  { "smoothinglength", 1.0 } };

bool sameIgnoringCase(const char* a, const char* b)
{
  for (; *a && *b; ++a, ++b)
  {
    if (std::tolower(static_cast<unsigned char>(*a)) != std::tolower(static_cast<unsigned char>(*b)))
    {
      return false;
    }
  }
  return *a == *b;
}

/// The index of the first of `names` that matches a candidate (in `candidates`' order), or -1.
template <std::size_t N>
int findIn(const std::vector<std::string>& names, const SizeName (&candidates)[N], double& scale)
{
  for (const SizeName& candidate : candidates)
  {
    for (std::size_t i = 0; i < names.size(); ++i)
    {
      if (sameIgnoringCase(names[i].c_str(), candidate.name))
      {
        scale = candidate.scale;
        return static_cast<int>(i);
      }
    }
  }
  return -1;
}
}

int FindSizeName(const std::vector<std::string>& names, Role role, bool acceptOther, double& scale)
{
  scale = 1.0;
  int found = role == Role::Radius ? findIn(names, RadiusNames, scale)
                                   : findIn(names, SmoothingNames, scale);
  if (found < 0 && acceptOther)
  {
    found = role == Role::Radius ? findIn(names, SmoothingNames, scale)
                                 : findIn(names, RadiusNames, scale);
    scale = 1.0;
  }
  return found;
}

const char* FindSizeArrayName(vtkDataSet* input, Role role, bool acceptOther, double& scale)
{
  scale = 1.0;
  if (!input)
  {
    return nullptr;
  }
  // Arrays without a name or that are not data arrays take an empty name: never matched.
  vtkPointData* data = input->GetPointData();
  std::vector<std::string> names(static_cast<std::size_t>(data->GetNumberOfArrays()));
  for (int a = 0; a < data->GetNumberOfArrays(); ++a)
  {
    const char* name = data->GetArrayName(a);
    names[static_cast<std::size_t>(a)] = name && data->GetArray(a) ? name : "";
  }
  const int found = FindSizeName(names, role, acceptOther, scale);
  return found < 0 ? nullptr : data->GetArrayName(found);
}

double SpacingCache::Spacing(vtkPoints* points)
{
  if (!points)
  {
    return 0.0;
  }
  if (points != this->Points || points->GetMTime() != this->Time)
  {
    const vtkRayMapperPointArrays::TupleReader reader(points->GetData());
    this->Value = raymappers::typicalParticleSpacing(
      static_cast<std::size_t>(points->GetNumberOfPoints()), [&](std::size_t i) {
        return raymappers::Vec3d(reader.get(i, 0), reader.get(i, 1), reader.get(i, 2));
      });
    this->Points = points;
    this->Time = points->GetMTime();
  }
  return this->Value;
}

std::vector<double> SpacingSampleDistances(vtkPoints* points, std::size_t totalCount)
{
  const std::size_t count = points ? static_cast<std::size_t>(points->GetNumberOfPoints()) : 0;
  if (count == 0 || totalCount == 0)
  {
    return {};
  }
  // This piece's share of the whole set's sample, rounded up so that no piece is left out.
  const std::size_t share = (1024 * count + totalCount - 1) / totalCount;
  const vtkRayMapperPointArrays::TupleReader reader(points->GetData());
  return raymappers::spacingSampleDistances(
    count,
    [&](std::size_t i)
    { return raymappers::Vec3d(reader.get(i, 0), reader.get(i, 1), reader.get(i, 2)); },
    share);
}

double MedianSpacing(const std::vector<double>& distances)
{
  return raymappers::medianSpacing(distances);
}

double AutomaticLengthFrom(double spacing, const double bounds[6], double perSpacing)
{
  if (spacing > 0.0 && std::isfinite(spacing))
  {
    return perSpacing * spacing;
  }
  if (bounds && vtkMath::AreBoundsInitialized(bounds))
  {
    const double diagonal = std::sqrt(vtkMath::Distance2BetweenPoints(
      std::array<double, 3>{ bounds[0], bounds[2], bounds[4] }.data(),
      std::array<double, 3>{ bounds[1], bounds[3], bounds[5] }.data()));
    if (diagonal > 0.0 && std::isfinite(diagonal))
    {
      return 0.01 * diagonal;
    }
  }
  return 1.0;
}

double AutomaticLength(vtkDataSet* input, double perSpacing, SpacingCache& cache)
{
  auto* pointSet = vtkPointSet::SafeDownCast(input);
  const double spacing = pointSet ? cache.Spacing(pointSet->GetPoints()) : 0.0;
  double bounds[6];
  vtkRayMapperPointArrays::FiniteBounds(input, bounds);
  return AutomaticLengthFrom(spacing, bounds, perSpacing);
}

} // namespace vtkRayMapperParticleSizes
