#include "vtkSPHVolumeRepresentation.h"

#include "vtkColorTransferFunction.h"
#include "vtkDiscretizableColorTransferFunction.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPolyData.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperSetGet.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHVolumeMapper.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cmath>
#include <string>

vtkStandardNewMacro(vtkSPHVolumeRepresentation);

namespace
{
/// An array name from ParaView's selector: null for empty or "None".
const char* arrayOrNull(const char* name)
{
  return name && name[0] && std::string(name) != "None" ? name : nullptr;
}
}

//----------------------------------------------------------------------------
vtkSPHVolumeRepresentation::vtkSPHVolumeRepresentation()
{
  this->Mapper = vtkSmartPointer<vtkSPHVolumeMapper>::New();
  this->Property = vtkSmartPointer<vtkVolumeProperty>::New();
  this->Volume = vtkSmartPointer<vtkVolume>::New();
  this->Volume->SetMapper(this->Mapper);
  this->SetProp(this->Volume, false);
  this->WarnOnlyWhenShown(this->Mapper);
  this->Volume->SetProperty(this->Property);
  this->Property->SetInterpolationTypeToLinear();
  this->SolidColor = vtkSmartPointer<vtkColorTransferFunction>::New();
  this->SolidOpacity = vtkSmartPointer<vtkPiecewiseFunction>::New();
  this->SolidOpacity->AddPoint(0.0, 0.0);
  this->SolidOpacity->AddPoint(1.0, 1.0);
  this->SetDiffuseColor(1.0, 1.0, 1.0);
}

vtkSPHVolumeRepresentation::~vtkSPHVolumeRepresentation() = default;

void vtkSPHVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ScalarOpacityUnitDistance: " << this->ScalarOpacityUnitDistance << "\n";
  os << indent << "ProcessedData: " << this->ProcessedData.Get() << "\n";
}

vtkSPHVolumeMapper* vtkSPHVolumeRepresentation::GetMapper()
{
  return this->Mapper;
}

vtkVolume* vtkSPHVolumeRepresentation::GetVolume()
{
  return this->Volume;
}

vtkVolumeProperty* vtkSPHVolumeRepresentation::GetVolumeProperty()
{
  return this->Property;
}

const char* vtkSPHVolumeRepresentation::GetRenderStatistics()
{
  return this->Mapper->GetStatistics()->GetSummary();
}

//----------------------------------------------------------------------------
vtkDataSet* vtkSPHVolumeRepresentation::GetProcessedData()
{
  return this->ProcessedData;
}

double vtkSPHVolumeRepresentation::GetBoundsMargin()
{
  // The field reaches one support radius beyond the points.
  const double factor = this->Mapper->GetSupportFactor() > 0
    ? this->Mapper->GetSupportFactor()
    : (this->Mapper->GetKernel() == VTK_SPH_KERNEL_POLY6 ? 1.0 : 2.0);
  return factor *
    vtkRayMapperLargestRadius(this->ProcessedData, this->Mapper->GetSmoothingLengthArrayName(),
      this->Mapper->GetSmoothingLength(), this->Mapper->GetSmoothingLengthScale());
}

void vtkSPHVolumeRepresentation::SetDeliveredPiece(vtkDataObject* piece)
{
  this->Mapper->SetInputData(vtkRayMapperDeliveredPoints(piece));
  this->UpdateClassification();
}

void vtkSPHVolumeRepresentation::SetRegion(const double bounds[6])
{
  this->Mapper->SetRegionBounds(bounds);
}

int vtkSPHVolumeRepresentation::RequestData(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->ProcessedData = vtkRayMapperGatherPoints(inputVector[0]->GetNumberOfInformationObjects() == 1
      ? vtkDataObject::GetData(inputVector[0], 0)
      : nullptr);
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//----------------------------------------------------------------------------
void vtkSPHVolumeRepresentation::UpdateClassification()
{
  const char* valueArray = nullptr;
  vtkInformation* info = this->GetInputArrayInformation(0);
  if (info && info->Has(vtkDataObject::FIELD_NAME()) &&
      (!info->Has(vtkDataObject::FIELD_ASSOCIATION()) ||
        info->Get(vtkDataObject::FIELD_ASSOCIATION()) == vtkDataObject::FIELD_ASSOCIATION_POINTS))
  {
    valueArray = info->Get(vtkDataObject::FIELD_NAME());
  }
  const bool mapped = valueArray && valueArray[0] && this->LookupTable;
  // ParaView's color map of the array and its opacity map (the one the color map carries
  // when no ScalarOpacityFunction was set).
  vtkColorTransferFunction* color = vtkColorTransferFunction::SafeDownCast(this->LookupTable);
  vtkPiecewiseFunction* opacity = this->ScalarOpacity;
  if (!opacity)
  {
    if (auto* discretizable = vtkDiscretizableColorTransferFunction::SafeDownCast(color))
    {
      opacity = discretizable->GetScalarOpacityFunction();
    }
  }
  if (!mapped || !color || !opacity)
  {
    if (mapped)
    {
      vtkWarningMacro(<< "The color map of '" << valueArray
                      << "' is not a color transfer function with an opacity map; the solid "
                         "color is used.");
    }
    // Without a quantity every particle carries 1: a constant array, not the active scalars.
    this->Mapper->SetValueArrayName(nullptr);
    color = this->SolidColor;
    opacity = this->SolidOpacity;
  }
  else
  {
    this->Mapper->SetValueArrayName(valueArray);
  }
  this->Property->SetColor(color);
  this->Property->SetScalarOpacity(opacity);
  this->Property->SetScalarOpacityUnitDistance(this->ScalarOpacityUnitDistance);
}

void vtkSPHVolumeRepresentation::SetLookupTable(vtkScalarsToColors* lut)
{
  this->LookupTable = lut;
  this->Modified();
}

void vtkSPHVolumeRepresentation::SetScalarOpacity(vtkPiecewiseFunction* opacity)
{
  this->ScalarOpacity = opacity;
  this->Modified();
}

void vtkSPHVolumeRepresentation::SetScalarOpacityUnitDistance(double distance)
{
  if (!(distance > 0) || !std::isfinite(distance))
  {
    vtkWarningMacro(<< "ScalarOpacityUnitDistance must be positive (got " << distance
                    << "); keeping " << this->ScalarOpacityUnitDistance << ".");
    return;
  }
  this->ScalarOpacityUnitDistance = distance;
  this->Modified();
}

//----------------------------------------------------------------------------
// Forwarded to the mapper.
#define RM_FORWARD(Method, Type, MapperCall)                                                       \
  void vtkSPHVolumeRepresentation::Method(Type value)                                              \
  {                                                                                                \
    this->Mapper->MapperCall(value);                                                               \
    this->Modified();                                                                              \
  }
RM_FORWARD(SetKernel, int, SetKernel)
RM_FORWARD(SetSupportFactor, double, SetSupportFactor)
RM_FORWARD(SetSmoothingLength, double, SetSmoothingLength)
RM_FORWARD(SetSmoothingLengthScale, double, SetSmoothingLengthScale)
RM_FORWARD(SetParticleVolume, double, SetVolume)
RM_FORWARD(SetNormalization, int, SetNormalization)
RM_FORWARD(SetContourShading, bool, SetContourShading)
RM_FORWARD(SetContourOpacity, double, SetContourOpacity)
RM_FORWARD(SetStepFactor, double, SetStepFactor)
RM_FORWARD(SetSamplesPerSupport, double, SetSamplesPerSupport)
RM_FORWARD(SetTileSize, int, SetTileSize)
RM_FORWARD(SetSlabDepth, int, SetSlabDepth)
RM_FORWARD(SetTerminationOpacity, double, SetTerminationOpacity)
RM_FORWARD(SetJitter, bool, SetJitter)
RM_FORWARD(SetMaximumReduction, double, SetMaximumReduction)
RM_FORWARD(SetFrameBudget, double, SetFrameBudget)
#undef RM_FORWARD

void vtkSPHVolumeRepresentation::SetContourColor(double r, double g, double b)
{
  this->Mapper->SetContourColor(r, g, b);
  this->Modified();
}

void vtkSPHVolumeRepresentation::SelectSmoothingLengthArray(int, int, int, int, const char* name)
{
  this->Mapper->SetSmoothingLengthArrayName(arrayOrNull(name));
  this->Modified();
}

void vtkSPHVolumeRepresentation::SelectMassArray(int, int, int, int, const char* name)
{
  this->Mapper->SetMassArrayName(arrayOrNull(name));
  this->Modified();
}

void vtkSPHVolumeRepresentation::SelectDensityArray(int, int, int, int, const char* name)
{
  this->Mapper->SetDensityArrayName(arrayOrNull(name));
  this->Modified();
}

void vtkSPHVolumeRepresentation::SelectVolumeArray(int, int, int, int, const char* name)
{
  this->Mapper->SetVolumeArrayName(arrayOrNull(name));
  this->Modified();
}

//----------------------------------------------------------------------------
// Lighting and solid color.
void vtkSPHVolumeRepresentation::SetShade(bool shade)
{
  this->Property->SetShade(shade ? 1 : 0);
}

void vtkSPHVolumeRepresentation::SetAmbient(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Ambient", value, 0.0, 1.0, this->Property->GetAmbient()))
  {
    this->Property->SetAmbient(value);
  }
}

void vtkSPHVolumeRepresentation::SetDiffuse(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Diffuse", value, 0.0, 1.0, this->Property->GetDiffuse()))
  {
    this->Property->SetDiffuse(value);
  }
}

void vtkSPHVolumeRepresentation::SetSpecular(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Specular", value, 0.0, 1.0, this->Property->GetSpecular()))
  {
    this->Property->SetSpecular(value);
  }
}

void vtkSPHVolumeRepresentation::SetSpecularPower(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "SpecularPower", value, 0.0, 128.0, this->Property->GetSpecularPower()))
  {
    this->Property->SetSpecularPower(value);
  }
}

void vtkSPHVolumeRepresentation::SetDiffuseColor(double r, double g, double b)
{
  double rgb[3] = { r, g, b };
  if (!vtkRayMapperSetGet::AcceptVector(this, "DiffuseColor", rgb, 0.0, 1.0))
  {
    return;
  }
  r = rgb[0];
  g = rgb[1];
  b = rgb[2];
  this->SolidColor->RemoveAllPoints();
  this->SolidColor->AddRGBPoint(0.0, r, g, b);
  this->SolidColor->AddRGBPoint(1.0, r, g, b);
  this->Modified();
}
