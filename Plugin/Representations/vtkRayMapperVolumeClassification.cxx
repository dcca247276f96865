#include "vtkRayMapperVolumeClassification.h"

#include "vtkColorTransferFunction.h"
#include "vtkDiscretizableColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRayMapperSetGet.h"

#include <cmath>

vtkRayMapperVolumeClassification::vtkRayMapperVolumeClassification()
  : SolidColor(vtkSmartPointer<vtkColorTransferFunction>::New())
  , SolidOpacity(vtkSmartPointer<vtkPiecewiseFunction>::New())
{
  this->SolidOpacity->AddPoint(0.0, 0.0);
  this->SolidOpacity->AddPoint(1.0, 1.0);
  this->SetSolidColor(nullptr, 1.0, 1.0, 1.0);
}

vtkRayMapperVolumeClassification::~vtkRayMapperVolumeClassification() = default;

bool vtkRayMapperVolumeClassification::SetScalarOpacityUnitDistance(vtkObject* self,
  double distance)
{
  if (!(distance > 0) || !std::isfinite(distance))
  {
    vtkWarningWithObjectMacro(self,
      << "ScalarOpacityUnitDistance must be positive (got " << distance << "); keeping "
      << this->UnitDistance << ".");
    return false;
  }
  this->UnitDistance = distance;
  return true;
}

bool vtkRayMapperVolumeClassification::SetSolidColor(vtkObject* self, double r, double g, double b)
{
  double rgb[3] = { r, g, b };
  if (self && !vtkRayMapperSetGet::AcceptVector(self, "DiffuseColor", rgb, 0.0, 1.0))
  {
    return false;
  }
  // A constant color over the field's range [0, 1].
  this->SolidColor->RemoveAllPoints();
  this->SolidColor->AddRGBPoint(0.0, rgb[0], rgb[1], rgb[2]);
  this->SolidColor->AddRGBPoint(1.0, rgb[0], rgb[1], rgb[2]);
  return true;
}

vtkColorTransferFunction* vtkRayMapperVolumeClassification::GetColorMap() const
{
  return vtkColorTransferFunction::SafeDownCast(this->LookupTable);
}

vtkPiecewiseFunction* vtkRayMapperVolumeClassification::GetOpacityMap() const
{
  if (this->ScalarOpacity)
  {
    return this->ScalarOpacity;
  }
  // ParaView's color maps carry their opacity map when no ScalarOpacityFunction was set.
  auto* discretizable = vtkDiscretizableColorTransferFunction::SafeDownCast(this->LookupTable);
  return discretizable ? discretizable->GetScalarOpacityFunction() : nullptr;
}

bool vtkRayMapperVolumeClassification::Classify(vtkObject* self,
  const char* valueArray,
  vtkColorTransferFunction*& color,
  vtkPiecewiseFunction*& opacity) const
{
  const bool mapped = valueArray && valueArray[0] && this->LookupTable;
  color = this->GetColorMap();
  opacity = this->GetOpacityMap();
  if (mapped && color && opacity)
  {
    return true;
  }
  if (mapped)
  {
    vtkWarningWithObjectMacro(self,
      << "The color map of '" << valueArray
      << "' is not a color transfer function with an opacity map; the solid color is used.");
  }
  color = this->SolidColor;
  opacity = this->SolidOpacity;
  return false;
}
