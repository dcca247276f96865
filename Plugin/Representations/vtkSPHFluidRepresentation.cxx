#include "vtkSPHFluidRepresentation.h"

#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperSetGet.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHFluidMapper.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <string>

vtkStandardNewMacro(vtkSPHFluidRepresentation);

namespace
{
/// An array name from ParaView's selector: null for empty or "None".
const char* arrayOrNull(const char* name)
{
  return name && name[0] && std::string(name) != "None" ? name : nullptr;
}
}

//----------------------------------------------------------------------------
vtkSPHFluidRepresentation::vtkSPHFluidRepresentation()
{
  this->Mapper = vtkSmartPointer<vtkSPHFluidMapper>::New();
  this->Property = vtkSmartPointer<vtkVolumeProperty>::New();
  this->Volume = vtkSmartPointer<vtkVolume>::New();
  this->Volume->SetMapper(this->Mapper);
  this->Volume->SetProperty(this->Property);
  this->SetProp(this->Volume, false);
  this->WarnOnlyWhenShown(this->Mapper);
}

vtkSPHFluidRepresentation::~vtkSPHFluidRepresentation() = default;

void vtkSPHFluidRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ProcessedData: " << this->ProcessedData.Get() << "\n";
}

vtkSPHFluidMapper* vtkSPHFluidRepresentation::GetMapper()
{
  return this->Mapper;
}

vtkVolume* vtkSPHFluidRepresentation::GetVolume()
{
  return this->Volume;
}

const char* vtkSPHFluidRepresentation::GetRenderStatistics()
{
  return this->Mapper->GetStatistics()->GetSummary();
}

//----------------------------------------------------------------------------
vtkDataSet* vtkSPHFluidRepresentation::GetProcessedData()
{
  return this->ProcessedData;
}

double vtkSPHFluidRepresentation::GetBoundsMargin()
{
  return vtkRayMapperLargestRadius(this->ProcessedData, this->Mapper->GetRadiusArrayName(),
    this->Mapper->GetRadius(), this->Mapper->GetRadiusScale());
}

void vtkSPHFluidRepresentation::SetDeliveredPiece(vtkDataObject* piece)
{
  this->Mapper->SetInputData(vtkRayMapperDeliveredPoints(piece));
}

int vtkSPHFluidRepresentation::RequestData(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->ProcessedData = vtkRayMapperGatherPoints(inputVector[0]->GetNumberOfInformationObjects() == 1
      ? vtkDataObject::GetData(inputVector[0], 0)
      : nullptr);
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//----------------------------------------------------------------------------
// Forwarded to the mapper.
#define RM_FORWARD(Method, Type, MapperCall)                                                       \
  void vtkSPHFluidRepresentation::Method(Type value)                                               \
  {                                                                                                \
    this->Mapper->MapperCall(value);                                                               \
    this->Modified();                                                                              \
  }
RM_FORWARD(SetRadius, double, SetRadius)
RM_FORWARD(SetRadiusScale, double, SetRadiusScale)
RM_FORWARD(SetAngleResolution, double, SetAngleResolution)
RM_FORWARD(SetMaximumLayers, int, SetMaximumLayers)
RM_FORWARD(SetMaximumSpans, int, SetMaximumSpans)
RM_FORWARD(SetMemoryBudget, double, SetMemoryBudget)
RM_FORWARD(SetGapThreshold, double, SetGapThreshold)
RM_FORWARD(SetBoundaryCulling, bool, SetBoundaryCulling)
RM_FORWARD(SetCellSize, double, SetCellSize)
RM_FORWARD(SetSubsampling, int, SetSubsampling)
RM_FORWARD(SetFrameBudget, double, SetFrameBudget)
RM_FORWARD(SetSmoothingRadius, double, SetSmoothingRadius)
RM_FORWARD(SetSmoothingIterations, int, SetSmoothingIterations)
RM_FORWARD(SetTranslucency, bool, SetTranslucency)
RM_FORWARD(SetDensity, double, SetDensity)
RM_FORWARD(SetRefractiveIndex, double, SetRefractiveIndex)
RM_FORWARD(SetBounces, int, SetBounces)
RM_FORWARD(SetAmbientOcclusion, bool, SetAmbientOcclusion)
RM_FORWARD(SetAmbientOcclusionRadius, double, SetAmbientOcclusionRadius)
RM_FORWARD(SetAmbientOcclusionSamples, int, SetAmbientOcclusionSamples)
#undef RM_FORWARD

void vtkSPHFluidRepresentation::SelectRadiusArray(int, int, int, int, const char* name)
{
  this->Mapper->SetRadiusArrayName(arrayOrNull(name));
  this->Modified();
}

void vtkSPHFluidRepresentation::SetFluidColor(double r, double g, double b)
{
  this->Mapper->SetColor(r, g, b);
  this->Modified();
}

void vtkSPHFluidRepresentation::SetAbsorptionColor(double r, double g, double b)
{
  this->Mapper->SetAbsorptionColor(r, g, b);
  this->Modified();
}

//----------------------------------------------------------------------------
// Lighting.
void vtkSPHFluidRepresentation::SetAmbient(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Ambient", value, 0.0, 1.0, this->Property->GetAmbient()))
  {
    this->Property->SetAmbient(value);
  }
}

void vtkSPHFluidRepresentation::SetDiffuse(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Diffuse", value, 0.0, 1.0, this->Property->GetDiffuse()))
  {
    this->Property->SetDiffuse(value);
  }
}

void vtkSPHFluidRepresentation::SetSpecular(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Specular", value, 0.0, 1.0, this->Property->GetSpecular()))
  {
    this->Property->SetSpecular(value);
  }
}

void vtkSPHFluidRepresentation::SetSpecularPower(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "SpecularPower", value, 0.0, 128.0, this->Property->GetSpecularPower()))
  {
    this->Property->SetSpecularPower(value);
  }
}
