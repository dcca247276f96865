#include "vtkSPHFluidRepresentation.h"

#include "vtkObjectFactory.h"
#include "vtkRayMapperForward.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHFluidMapper.h"
#include "vtkVolume.h"

vtkStandardNewMacro(vtkSPHFluidRepresentation);

//----------------------------------------------------------------------------
vtkSPHFluidRepresentation::vtkSPHFluidRepresentation()
{
  this->Mapper = vtkSmartPointer<vtkSPHFluidMapper>::New();
  this->Statistics = this->Mapper->GetStatistics();
  this->Volume = this->SetVolumeProp(this->Mapper);
  this->SetParticleMapper(this->Mapper);
  // The radius array is used whenever one is selected.
  this->UseRadiusArray = true;
}

vtkSPHFluidRepresentation::~vtkSPHFluidRepresentation() = default;

void vtkSPHFluidRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}

vtkSPHFluidMapper* vtkSPHFluidRepresentation::GetMapper()
{
  return this->Mapper;
}

vtkVolume* vtkSPHFluidRepresentation::GetVolume()
{
  return this->Volume;
}

//----------------------------------------------------------------------------
double vtkSPHFluidRepresentation::GetAutomaticRadiusPerSpacing()
{
  return vtkSPHFluidMapper::GetAutomaticRadiusPerSpacing();
}

void vtkSPHFluidRepresentation::PushRadius(double& radius, double& scale, const char* radiusArray)
{
  vtkRayMapperPushRadius(this->Mapper.Get(), radius, scale, radiusArray);
}

//----------------------------------------------------------------------------
// Forwarded to the mapper.
// clang-format off
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetAngleResolution, double, SetAngleResolution)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetMaximumLayers, int, SetMaximumLayers)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetMaximumSpans, int, SetMaximumSpans)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetMemoryBudget, double, SetMemoryBudget)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetLengthUnit, int, SetLengthUnit)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetGapThreshold, double, SetGapThreshold)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetBoundaryCulling, bool, SetBoundaryCulling)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetCellSize, double, SetCellSize)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetSubsampling, int, SetSubsampling)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetFrameBudget, double, SetFrameBudget)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetNumberOfThreads, int, SetNumberOfThreads)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetSmoothingRadius, double, SetSmoothingRadius)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetSmoothingIterations, int, SetSmoothingIterations)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetTranslucency, bool, SetTranslucency)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetDensity, double, SetDensity)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetRefractiveIndex, double, SetRefractiveIndex)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetBounces, int, SetBounces)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetAmbientOcclusion, bool, SetAmbientOcclusion)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetAmbientOcclusionRadius, double, SetAmbientOcclusionRadius)
vtkRayMapperForwardMacro(vtkSPHFluidRepresentation, SetAmbientOcclusionSamples, int, SetAmbientOcclusionSamples)
// clang-format on

void vtkSPHFluidRepresentation::SetDiffuseColor(double r, double g, double b)
{
  this->Mapper->SetColor(r, g, b);
  this->Modified();
}

void vtkSPHFluidRepresentation::SetFluidSpecular(double value)
{
  this->Superclass::SetSpecular(value);
}

void vtkSPHFluidRepresentation::SetLookupTable(vtkScalarsToColors* lut)
{
  this->Mapper->SetLookupTable(lut);
}

void vtkSPHFluidRepresentation::UpdateMapperParameters()
{
  // Only point arrays color particles: anything else shows the solid color.
  const char* colorArrayName = this->GetColorPointArrayName();
  this->Mapper->SetScalarVisibility(colorArrayName != nullptr);
  this->Mapper->SetColorArrayName(colorArrayName);
}

void vtkSPHFluidRepresentation::SetAbsorptionColor(double r, double g, double b)
{
  this->Mapper->SetAbsorptionColor(r, g, b);
  this->Modified();
}
