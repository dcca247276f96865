#include "vtkRayMapperParticleVolumeRepresentation.h"

#include "vtkAbstractVolumeMapper.h"
#include "vtkColorTransferFunction.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRayMapperVolumeClassification.h"
#include "vtkScalarsToColors.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

//----------------------------------------------------------------------------
vtkRayMapperParticleVolumeRepresentation::vtkRayMapperParticleVolumeRepresentation()
  : Classification(new vtkRayMapperVolumeClassification)
{
}

vtkRayMapperParticleVolumeRepresentation::~vtkRayMapperParticleVolumeRepresentation() = default;

void vtkRayMapperParticleVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent
     << "ScalarOpacityUnitDistance: " << this->Classification->GetScalarOpacityUnitDistance()
     << "\n";
}

void vtkRayMapperParticleVolumeRepresentation::SetVolumeMapper(vtkAbstractVolumeMapper* mapper)
{
  this->Volume = this->SetVolumeProp(mapper);
  this->Property = this->Volume->GetProperty();
  this->Property->SetInterpolationTypeToLinear();
  this->SetParticleMapper(mapper);
}

vtkVolume* vtkRayMapperParticleVolumeRepresentation::GetVolume()
{
  return this->Volume;
}

vtkVolumeProperty* vtkRayMapperParticleVolumeRepresentation::GetVolumeProperty()
{
  return this->Property;
}

//----------------------------------------------------------------------------
void vtkRayMapperParticleVolumeRepresentation::UpdateMapperParameters()
{
  const char* valueArray = this->GetColorPointArrayName();
  vtkColorTransferFunction* color = nullptr;
  vtkPiecewiseFunction* opacity = nullptr;
  const bool classified = this->Classification->Classify(this, valueArray, color, opacity);
  this->SetValueArray(classified ? valueArray : nullptr);
  for (int field = 0; field < this->GetNumberOfFields(); ++field)
  {
    vtkColorTransferFunction* fieldColor = color;
    vtkPiecewiseFunction* fieldOpacity = opacity;
    if (field > 0 && classified)
    {
      this->GetFieldMaps(field, fieldColor, fieldOpacity);
    }
    this->Property->SetColor(field, fieldColor);
    this->Property->SetScalarOpacity(field, fieldOpacity);
    this->Property->SetScalarOpacityUnitDistance(
      field, this->Classification->GetScalarOpacityUnitDistance());
  }
}

void vtkRayMapperParticleVolumeRepresentation::SetLookupTable(vtkScalarsToColors* lut)
{
  this->Classification->LookupTable = lut;
  this->Modified();
}

void vtkRayMapperParticleVolumeRepresentation::SetScalarOpacity(vtkPiecewiseFunction* opacity)
{
  this->Classification->ScalarOpacity = opacity;
  this->Modified();
}

void vtkRayMapperParticleVolumeRepresentation::SetScalarOpacityUnitDistance(double distance)
{
  if (this->Classification->SetScalarOpacityUnitDistance(this, distance))
  {
    this->Modified();
  }
}

void vtkRayMapperParticleVolumeRepresentation::SetShade(bool shade)
{
  this->Property->SetShade(shade ? 1 : 0);
}

void vtkRayMapperParticleVolumeRepresentation::SetDiffuseColor(double r, double g, double b)
{
  if (this->Classification->SetSolidColor(this, r, g, b))
  {
    this->Modified();
  }
}
