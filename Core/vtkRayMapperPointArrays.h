// Reading particles from a VTK data set's points and point arrays, as every RayMappers
// mapper, filter and representation does it: arrays found by name with the reason when one
// is missing, the bounds and centre of the finite points only, the largest particle length
// a kernel admits, and thread-safe reads of float and double arrays.
#ifndef vtkRayMapperPointArrays_h
#define vtkRayMapperPointArrays_h

#include "RayMappersCoreModule.h" // for export macro
#include "vtkDataArray.h"         // for TupleReader

#include <array>
#include <cstddef>
#include <string>

class vtkDataSet;
class vtkObject;
class vtkPoints;

namespace vtkRayMapperPointArrays
{

/// Reads component c of tuple i of a data array, safely from several threads at once:
/// float and double arrays (nearly all data) directly from memory, others through
/// vtkDataArray::GetComponent.
class RAYMAPPERSCORE_EXPORT TupleReader
{
public:
  explicit TupleReader(vtkDataArray* array);
  double get(std::size_t i, int c) const
  {
    const std::size_t k = i * static_cast<std::size_t>(Components) + static_cast<std::size_t>(c);
    return Floats ? Floats[k]
                  : (Doubles ? Doubles[k] : Array->GetComponent(static_cast<vtkIdType>(i), c));
  }

private:
  vtkDataArray* Array;
  const float* Floats = nullptr;
  const double* Doubles = nullptr;
  int Components = 0;
};

/// The point array `name` of `input`. nullptr when the name is empty, and nullptr with the
/// reason in `why` ("<role> array '<name>' is not a point array of the input") when the
/// input has no such array.
RAYMAPPERSCORE_EXPORT vtkDataArray* FindPointArray(vtkDataSet* input,
  const char* name,
  const char* role,
  std::string& why);

/// The particles' size array (a mapper's ScaleArray): FindPointArray of `name` as `role`
/// ("radius", "smoothing length"); when it is named but missing, the warning
/// "<why>; using the constant <role> <constant>." from `self` ("using the automatic <role>"
/// when `constant` is 0, the mappers' automatic size), and nullptr.
RAYMAPPERSCORE_EXPORT vtkDataArray* FindScaleArray(vtkObject* self,
  vtkDataSet* input,
  const char* name,
  const char* role,
  double constant);

/// Centre of the bounds of the finite points (the origin of a kernel's float coordinates);
/// (0, 0, 0) when there is none.
RAYMAPPERSCORE_EXPORT std::array<double, 3> FiniteCenter(vtkPoints* points);

/// The per-axis median of the finite points (of an even sample of at most 16,384 of them):
/// an origin for float coordinates that stays with the bulk of the data when a few points
/// lie far away (a single far outlier moves the bounds' centre off the data, and every
/// coordinate near the data then loses the outlier's distance in float precision);
/// (0, 0, 0) when there is none.
RAYMAPPERSCORE_EXPORT std::array<double, 3> MedianCenter(vtkPoints* points);

/// The bounds of the finite points of `data` (uninitialized when there is none): VTK's own
/// bounds include an infinite coordinate (only NaN is left out), and infinite bounds give
/// the renderer's Reset Camera and clipping range NaN matrices. VTK's cached bounds when
/// they are finite, so the points are looked at again only when some are infinite.
RAYMAPPERSCORE_EXPORT void FiniteBounds(vtkDataSet* data, double bounds[6]);

/// The largest length scale * v (v: component 0 of `array`) that a particle may have,
/// 0 < length <= raymappers::MaxLength (ParticleInput.h skips the others), to grow bounds by;
/// 0 when there is none. VTK's cached finite range when its maximum is within the limit,
/// else a scan (a huge radius must not make the bounds, and so the camera, huge).
RAYMAPPERSCORE_EXPORT double LargestParticleLength(vtkDataArray* array, double scale);

} // namespace vtkRayMapperPointArrays

#endif
