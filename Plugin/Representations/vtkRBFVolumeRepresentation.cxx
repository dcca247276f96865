#include "vtkRBFVolumeRepresentation.h"

#include "vtkColorTransferFunction.h"
#include "vtkDiscretizableColorTransferFunction.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPolyData.h"
#include "vtkRBFVolumeMapper.h"
#include "vtkRayMapperStatistics.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperSetGet.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cmath>

vtkStandardNewMacro(vtkRBFVolumeRepresentation);

//----------------------------------------------------------------------------
vtkRBFVolumeRepresentation::vtkRBFVolumeRepresentation()
{
  this->Mapper = vtkSmartPointer<vtkRBFVolumeMapper>::New();
  this->Property = vtkSmartPointer<vtkVolumeProperty>::New();
  this->Volume = vtkSmartPointer<vtkVolume>::New();
  this->Volume->SetMapper(this->Mapper);
  this->SetProp(this->Volume, false);
  this->WarnOnlyWhenShown(this->Mapper);
  this->Volume->SetProperty(this->Property);
  // One component per field: field m is classified with component m.
  this->Property->IndependentComponentsOn();
  this->Property->SetInterpolationTypeToLinear();
  this->SolidColor = vtkSmartPointer<vtkColorTransferFunction>::New();
  this->SolidOpacity = vtkSmartPointer<vtkPiecewiseFunction>::New();
  this->SolidOpacity->AddPoint(0.0, 0.0);
  this->SolidOpacity->AddPoint(1.0, 1.0);
  this->SetDiffuseColor(1.0, 1.0, 1.0);
  this->UpdateRadiusParameters();
}

//----------------------------------------------------------------------------
vtkRBFVolumeRepresentation::~vtkRBFVolumeRepresentation() = default;

//----------------------------------------------------------------------------
void vtkRBFVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "RadiusScale: " << this->RadiusScale << "\n";
  os << indent << "UseRadiusArray: " << this->UseRadiusArray << "\n";
  os << indent << "RadiusArrayName: " << this->RadiusArrayName << "\n";
  os << indent << "FieldArrayName: " << this->FieldArrayName << "\n";
  os << indent << "ScalarOpacityUnitDistance: " << this->ScalarOpacityUnitDistance << "\n";
  os << indent << "ProcessedData: " << this->ProcessedData.Get() << "\n";
}

//----------------------------------------------------------------------------
vtkRBFVolumeMapper* vtkRBFVolumeRepresentation::GetMapper()
{
  return this->Mapper;
}

vtkVolume* vtkRBFVolumeRepresentation::GetVolume()
{
  return this->Volume;
}

vtkVolumeProperty* vtkRBFVolumeRepresentation::GetVolumeProperty()
{
  return this->Property;
}

const char* vtkRBFVolumeRepresentation::GetRenderStatistics()
{
  return this->Mapper->GetStatistics()->GetSummary();
}

//----------------------------------------------------------------------------
vtkDataSet* vtkRBFVolumeRepresentation::GetProcessedData()
{
  return this->ProcessedData;
}

double vtkRBFVolumeRepresentation::GetBoundsMargin()
{
  // The field reaches Sigma radii beyond the points.
  return this->Mapper->GetSigma() *
    vtkRayMapperLargestRadius(this->ProcessedData,
      this->UseRadiusArray && !this->RadiusArrayName.empty() ? this->RadiusArrayName.c_str()
                                                             : nullptr,
      this->Radius,
      this->RadiusScale);
}

void vtkRBFVolumeRepresentation::SetDeliveredPiece(vtkDataObject* piece)
{
  this->Mapper->SetInputData(vtkRayMapperDeliveredPoints(piece));
  this->UpdateClassification();
}

//----------------------------------------------------------------------------
void vtkRBFVolumeRepresentation::SetRegion(const double bounds[6])
{
  this->Mapper->SetRegionBounds(bounds);
}

int vtkRBFVolumeRepresentation::RequestData(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->ProcessedData = vtkRayMapperGatherPoints(inputVector[0]->GetNumberOfInformationObjects() == 1
      ? vtkDataObject::GetData(inputVector[0], 0)
      : nullptr);
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//----------------------------------------------------------------------------
void vtkRBFVolumeRepresentation::UpdateClassification()
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
  this->Mapper->SetValueArrayName(mapped ? valueArray : nullptr);

  // The first field's maps: ParaView's color map of the value array and its opacity map
  // (the one the color map carries when no ScalarOpacityFunction was set).
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
    this->Mapper->SetValueArrayName(nullptr);
    color = this->SolidColor;
    opacity = this->SolidOpacity;
  }

  for (int field = 0; field < 4; ++field)
  {
    vtkColorTransferFunction* fieldColor = color;
    vtkPiecewiseFunction* fieldOpacity = opacity;
    if (field > 0 && mapped)
    {
      auto* own = vtkDiscretizableColorTransferFunction::SafeDownCast(this->FieldLookupTables[field]);
      if (own)
      {
        fieldColor = own;
        if (own->GetScalarOpacityFunction())
        {
          fieldOpacity = own->GetScalarOpacityFunction();
        }
      }
    }
    this->Property->SetColor(field, fieldColor);
    this->Property->SetScalarOpacity(field, fieldOpacity);
    this->Property->SetScalarOpacityUnitDistance(field, this->ScalarOpacityUnitDistance);
  }
}

//----------------------------------------------------------------------------
void vtkRBFVolumeRepresentation::SetLookupTable(vtkScalarsToColors* lut)
{
  this->LookupTable = lut;
  this->Modified();
}

void vtkRBFVolumeRepresentation::SetScalarOpacity(vtkPiecewiseFunction* opacity)
{
  this->ScalarOpacity = opacity;
  this->Modified();
}

void vtkRBFVolumeRepresentation::SetScalarOpacityUnitDistance(double distance)
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

void vtkRBFVolumeRepresentation::SetFieldLookupTable(int field, vtkScalarsToColors* lut)
{
  this->FieldLookupTables[field] = lut;
  this->Modified();
}

void vtkRBFVolumeRepresentation::SelectFieldArray(int, int, int, int, const char* name)
{
  this->FieldArrayName = name && std::string(name) != "None" ? name : "";
  this->Mapper->SetFieldArrayName(
    this->FieldArrayName.empty() ? nullptr : this->FieldArrayName.c_str());
  this->Modified();
}

//----------------------------------------------------------------------------
// The field.
void vtkRBFVolumeRepresentation::SetKappa(double kappa)
{
  this->Mapper->SetKappa(kappa);
  this->Modified();
}

void vtkRBFVolumeRepresentation::SetSigma(double sigma)
{
  this->Mapper->SetSigma(sigma);
  this->Modified();
}

void vtkRBFVolumeRepresentation::SetSampleDistance(double distance)
{
  this->Mapper->SetSampleDistance(distance);
  this->Modified();
}

void vtkRBFVolumeRepresentation::SetTerminationOpacity(double opacity)
{
  this->Mapper->SetTerminationOpacity(opacity);
  this->Modified();
}

void vtkRBFVolumeRepresentation::UpdateRadiusParameters()
{
  this->Mapper->SetRadius(this->Radius);
  this->Mapper->SetRadiusScale(this->RadiusScale);
  // Keep what the mapper accepted (it rejects NaN and clamps), so that a rejected value is
  // warned about once, not again with every later radius setting.
  this->Radius = this->Mapper->GetRadius();
  this->RadiusScale = this->Mapper->GetRadiusScale();
  const bool useArray = this->UseRadiusArray && !this->RadiusArrayName.empty();
  this->Mapper->SetRadiusArrayName(useArray ? this->RadiusArrayName.c_str() : nullptr);
  this->Modified();
}

void vtkRBFVolumeRepresentation::SetRadius(double radius)
{
  this->Radius = radius;
  this->UpdateRadiusParameters();
}

void vtkRBFVolumeRepresentation::SetUseRadiusArray(bool use)
{
  this->UseRadiusArray = use;
  this->UpdateRadiusParameters();
}

void vtkRBFVolumeRepresentation::SelectRadiusArray(int, int, int, int, const char* name)
{
  this->RadiusArrayName = name ? name : "";
  this->UpdateRadiusParameters();
}

void vtkRBFVolumeRepresentation::SetRadiusScale(double scale)
{
  this->RadiusScale = scale;
  this->UpdateRadiusParameters();
}

void vtkRBFVolumeRepresentation::SetMethod(int method)
{
  this->Mapper->SetMethod(method);
  this->Modified();
}

void vtkRBFVolumeRepresentation::SetSamplesPerPass(int samples)
{
  this->Mapper->SetSamplesPerPass(samples);
  this->Modified();
}

void vtkRBFVolumeRepresentation::SetPacketSize(int side)
{
  this->Mapper->SetPacketSize(side);
  this->Modified();
}

void vtkRBFVolumeRepresentation::SetLeafSize(int particles)
{
  this->Mapper->SetLeafSize(particles);
  this->Modified();
}

//----------------------------------------------------------------------------
// Lighting and solid color.
void vtkRBFVolumeRepresentation::SetShade(bool shade)
{
  this->Property->SetShade(shade ? 1 : 0);
}

void vtkRBFVolumeRepresentation::SetAmbient(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Ambient", value, 0.0, 1.0, this->Property->GetAmbient()))
  {
    this->Property->SetAmbient(value);
  }
}

void vtkRBFVolumeRepresentation::SetDiffuse(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Diffuse", value, 0.0, 1.0, this->Property->GetDiffuse()))
  {
    this->Property->SetDiffuse(value);
  }
}

void vtkRBFVolumeRepresentation::SetSpecular(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Specular", value, 0.0, 1.0, this->Property->GetSpecular()))
  {
    this->Property->SetSpecular(value);
  }
}

void vtkRBFVolumeRepresentation::SetSpecularPower(double value)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "SpecularPower", value, 0.0, 128.0, this->Property->GetSpecularPower()))
  {
    this->Property->SetSpecularPower(value);
  }
}

void vtkRBFVolumeRepresentation::SetDiffuseColor(double r, double g, double b)
{
  double rgb[3] = { r, g, b };
  if (!vtkRayMapperSetGet::AcceptVector(this, "DiffuseColor", rgb, 0.0, 1.0))
  {
    return;
  }
  r = rgb[0];
  g = rgb[1];
  b = rgb[2];
  this->DiffuseColor[0] = r;
  this->DiffuseColor[1] = g;
  this->DiffuseColor[2] = b;
  this->SolidColor->RemoveAllPoints();
  this->SolidColor->AddRGBPoint(0.0, r, g, b);
  this->SolidColor->AddRGBPoint(1.0, r, g, b);
  this->Modified();
}

//----------------------------------------------------------------------------
// Forwarded to the volume.
