// The rule of the RayMappers mappers and filters for an array read as a scalar (a radius,
// a smoothing length, a mass, a density, a volume, a value, a ZSweep scalar): its first
// component, as vtkPointGaussianMapper reads its scale array by default (ScaleArrayComponent
// 0) and vtkGlyph3D scales by scalars. When the components differ in some tuple, that
// choice changes the picture, so it is said once (each caller warns when it rebuilds from
// the array, not per render). Arrays whose components are all equal, such as vtkPDBReader's
// 3-component "radius", read the same with any component and give no warning.
//
// Header-only, in the private module RayMappers::Core (its arrays are read through that
// module's vtkRayMapperPointArrays::TupleReader).
#ifndef vtkRayMapperScalarArray_h
#define vtkRayMapperScalarArray_h

#include "vtkDataArray.h"
#include "vtkRayMapperPointArrays.h" // for TupleReader
#include "vtkObject.h"
#include "vtkSetGet.h"

#include <cmath>

/// Warns from `self` "<role> array '<name>' has N components that differ: the first is
/// used." when `array` has several components that differ in some tuple; returns whether
/// it warned.
inline bool vtkRayMapperWarnIfComponentsDiffer(vtkObject* self, vtkDataArray* array, const char* role)
{
  const int n = array ? array->GetNumberOfComponents() : 1;
  if (n < 2)
  {
    return false;
  }
  // Float and double arrays read from memory: GetComponent's virtual call per value was
  // half of the sphere set's build on 2LYZ (3 equal radius components, 1,102 atoms, 28 us).
  const vtkRayMapperPointArrays::TupleReader reader(array);
  const auto tuples = static_cast<std::size_t>(array->GetNumberOfTuples());
  for (std::size_t i = 0; i < tuples; ++i)
  {
    const double first = reader.get(i, 0);
    for (int c = 1; c < n; ++c)
    {
      const double v = reader.get(i, c);
      if (!(v == first) && !(std::isnan(v) && std::isnan(first)))
      {
        vtkWarningWithObjectMacro(self,
          << role << " array '" << (array->GetName() ? array->GetName() : "") << "' has " << n
          << " components that differ: the first is used.");
        return true;
      }
    }
  }
  return false;
}

#endif
