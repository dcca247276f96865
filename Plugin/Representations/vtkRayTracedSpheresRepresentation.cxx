#include "vtkRayTracedSpheresRepresentation.h"

#include "vtkActor.h"
#include "vtkCGTSphereMapper.h"
#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperSetGet.h"
#include "vtkRayMapperStatistics.h"
#include "vtkScalarsToColors.h"


vtkStandardNewMacro(vtkRayTracedSpheresRepresentation);


//----------------------------------------------------------------------------
vtkRayTracedSpheresRepresentation::vtkRayTracedSpheresRepresentation()
{
  this->Mapper = vtkSmartPointer<vtkCGTSphereMapper>::New();
  this->Actor = vtkSmartPointer<vtkActor>::New();
  this->Actor->SetMapper(this->Mapper);
  this->SetProp(this->Actor, true);
  this->WarnOnlyWhenShown(this->Mapper);
  // vtkCGTSphereMapper draws an opaque frame that writes depth: it must run in the
  // opaque pass even when Opacity < 1 or the lookup table maps opacity (a translucent
  // actor would be drawn by ParaView's depth peeling, which the mapper does not support).
  this->Actor->ForceOpaqueOn();
  // Until a color array is chosen, the spheres have the solid color: do not let the
  // mapper pick the active scalars of the data on its own.
  this->Mapper->SetScalarVisibility(0);
  this->Mapper->SetColorMode(VTK_COLOR_MODE_MAP_SCALARS);
  this->UpdateRadiusParameters();
}

//----------------------------------------------------------------------------
vtkRayTracedSpheresRepresentation::~vtkRayTracedSpheresRepresentation() = default;

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "RadiusScale: " << this->RadiusScale << "\n";
  os << indent << "UseRadiusArray: " << this->UseRadiusArray << "\n";
  os << indent << "RadiusArrayName: " << this->RadiusArrayName << "\n";
  os << indent << "ProcessedData: " << this->ProcessedData.Get() << "\n";
}

//----------------------------------------------------------------------------
vtkCGTSphereMapper* vtkRayTracedSpheresRepresentation::GetMapper()
{
  return this->Mapper;
}

//----------------------------------------------------------------------------
const char* vtkRayTracedSpheresRepresentation::GetRenderStatistics()
{
  return this->Mapper->GetStatistics()->GetSummary();
}

//----------------------------------------------------------------------------
vtkActor* vtkRayTracedSpheresRepresentation::GetActor()
{
  return this->Actor;
}

//----------------------------------------------------------------------------
vtkDataSet* vtkRayTracedSpheresRepresentation::GetProcessedData()
{
  return this->ProcessedData;
}

double vtkRayTracedSpheresRepresentation::GetBoundsMargin()
{
  // The spheres stick out of the points' box by up to one radius.
  return vtkRayMapperLargestRadius(this->ProcessedData,
    this->UseRadiusArray && !this->RadiusArrayName.empty() ? this->RadiusArrayName.c_str() : nullptr,
    this->Radius,
    this->RadiusScale);
}

void vtkRayTracedSpheresRepresentation::SetDeliveredPiece(vtkDataObject* piece)
{
  this->Mapper->SetInputData(vtkRayMapperDeliveredPoints(piece));
  // Each rank traces shadow and occlusion rays against its own spheres only.
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!this->WarnedLocalShadows && controller && controller->GetNumberOfProcesses() > 1 &&
    controller->GetLocalProcessId() == 0 &&
    (this->Mapper->GetShadowRays() > 0 || this->Mapper->GetAmbientOcclusionSamples() > 0))
  {
    vtkWarningMacro(<< "with " << controller->GetNumberOfProcesses()
                    << " rendering processes, soft shadows and ambient occlusion see only the "
                       "spheres of each process's own piece");
    this->WarnedLocalShadows = true;
  }
  this->UpdateColoringParameters();
}

//----------------------------------------------------------------------------
int vtkRayTracedSpheresRepresentation::RequestData(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->ProcessedData = vtkRayMapperGatherPoints(inputVector[0]->GetNumberOfInformationObjects() == 1
      ? vtkDataObject::GetData(inputVector[0], 0)
      : nullptr);
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::UpdateColoringParameters()
{
  const char* colorArrayName = nullptr;
  int fieldAssociation = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkInformation* info = this->GetInputArrayInformation(0);
  if (info && info->Has(vtkDataObject::FIELD_NAME()))
  {
    colorArrayName = info->Get(vtkDataObject::FIELD_NAME());
    if (info->Has(vtkDataObject::FIELD_ASSOCIATION()))
    {
      fieldAssociation = info->Get(vtkDataObject::FIELD_ASSOCIATION());
    }
  }

  // Only point arrays can color points: anything else shows the solid color.
  if (colorArrayName && colorArrayName[0] &&
      fieldAssociation == vtkDataObject::FIELD_ASSOCIATION_POINTS)
  {
    this->Mapper->SetScalarVisibility(1);
    this->Mapper->SetScalarMode(VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);
    this->Mapper->SelectColorArray(colorArrayName);
    this->Mapper->SetUseLookupTableScalarRange(1);
  }
  else
  {
    this->Mapper->SetScalarVisibility(0);
    this->Mapper->SelectColorArray(static_cast<const char*>(nullptr));
  }
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetLookupTable(vtkScalarsToColors* lut)
{
  this->Mapper->SetLookupTable(lut);
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetMapScalars(int val)
{
  if (val != 0 && val != 1)
  {
    vtkWarningMacro(<< "Invalid MapScalars value " << val << ", using 1.");
    val = 1;
  }
  this->Mapper->SetColorMode(val ? VTK_COLOR_MODE_MAP_SCALARS : VTK_COLOR_MODE_DIRECT_SCALARS);
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::UpdateRadiusParameters()
{
  this->Mapper->SetRadius(this->Radius);
  this->Mapper->SetRadiusScale(this->RadiusScale);
  // Keep what the mapper accepted (it rejects NaN and clamps), so that a rejected value is
  // warned about once, not again with every later radius setting.
  this->Radius = this->Mapper->GetRadius();
  this->RadiusScale = this->Mapper->GetRadiusScale();
  const bool useArray = this->UseRadiusArray && !this->RadiusArrayName.empty();
  this->Mapper->SetRadiusArrayName(useArray ? this->RadiusArrayName.c_str() : nullptr);
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetRadius(double radius)
{
  if (this->Radius != radius)
  {
    this->Radius = radius;
    this->UpdateRadiusParameters();
    this->Modified();
  }
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetUseRadiusArray(bool use)
{
  if (this->UseRadiusArray != use)
  {
    this->UseRadiusArray = use;
    this->UpdateRadiusParameters();
    this->Modified();
  }
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SelectRadiusArray(int, int, int, int, const char* name)
{
  const std::string newName = name ? name : "";
  if (this->RadiusArrayName != newName)
  {
    this->RadiusArrayName = newName;
    this->UpdateRadiusParameters();
    this->Modified();
  }
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetAccelerator(int accelerator)
{
  this->Mapper->SetAccelerator(accelerator);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetPacketSize(int side)
{
  this->Mapper->SetPacketSize(side);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetLambda(double lambda)
{
  this->Mapper->SetLambda(lambda);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetMacrocellSize(int cells)
{
  this->Mapper->SetMacrocellSize(cells);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetAmbientOcclusionSamples(int samples)
{
  this->Mapper->SetAmbientOcclusionSamples(samples);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetAmbientOcclusionRadius(double radius)
{
  this->Mapper->SetAmbientOcclusionRadius(radius);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetShadowRays(int side)
{
  this->Mapper->SetShadowRays(side);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetAutomaticShadowLight(bool automatic)
{
  this->Mapper->SetAutomaticShadowLight(automatic);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetShadowLightPosition(double x, double y, double z)
{
  this->Mapper->SetShadowLightPosition(x, y, z);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetShadowLightSize(double size)
{
  this->Mapper->SetShadowLightSize(size);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetShadowLightIntensity(double intensity)
{
  this->Mapper->SetShadowLightIntensity(intensity);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SelectRangeArray(int slot, int, int, int, const char* name)
{
  if (slot < 0 || slot > 3)
  {
    vtkErrorMacro(<< "range slot " << slot << " does not exist (0 to 3)");
    return;
  }
  // The panel's "None" entry (the domain's none_string) turns that range off.
  this->RangeArrayNames[slot] = name && std::string(name) != "None" ? name : "";
  this->UpdateRange(slot);
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetRangeBounds(int slot, double minimum, double maximum)
{
  this->RangeBounds[slot][0] = minimum;
  this->RangeBounds[slot][1] = maximum;
  this->UpdateRange(slot);
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::UpdateRange(int slot)
{
  const std::string& name = this->RangeArrayNames[slot];
  this->Mapper->SetRange(slot,
    name.empty() ? nullptr : name.c_str(),
    this->RangeBounds[slot][0],
    this->RangeBounds[slot][1]);
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetRadiusScale(double scale)
{
  if (this->RadiusScale != scale)
  {
    this->RadiusScale = scale;
    this->UpdateRadiusParameters();
    this->Modified();
  }
}

//----------------------------------------------------------------------------
// Forwarded to the actor.
//----------------------------------------------------------------------------
// Forwarded to the actor's property.
void vtkRayTracedSpheresRepresentation::SetAmbient(double val)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Ambient", val, 0.0, 1.0, this->Actor->GetProperty()->GetAmbient()))
  {
    this->Actor->GetProperty()->SetAmbient(val);
  }
}

void vtkRayTracedSpheresRepresentation::SetDiffuse(double val)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Diffuse", val, 0.0, 1.0, this->Actor->GetProperty()->GetDiffuse()))
  {
    this->Actor->GetProperty()->SetDiffuse(val);
  }
}

void vtkRayTracedSpheresRepresentation::SetSpecular(double val)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "Specular", val, 0.0, 1.0, this->Actor->GetProperty()->GetSpecular()))
  {
    this->Actor->GetProperty()->SetSpecular(val);
  }
}

void vtkRayTracedSpheresRepresentation::SetSpecularPower(double val)
{
  // vtkProperty and vtkVolumeProperty take NaN as it is; the kernels would shade with it.
  if (vtkRayMapperSetGet::Accept(this, "SpecularPower", val, 0.0, 128.0, this->Actor->GetProperty()->GetSpecularPower()))
  {
    this->Actor->GetProperty()->SetSpecularPower(val);
  }
}

void vtkRayTracedSpheresRepresentation::SetAmbientColor(double r, double g, double b)
{
  double rgb[3] = { r, g, b };
  if (vtkRayMapperSetGet::AcceptVector(this, "AmbientColor", rgb, 0.0, 1.0))
  {
    this->Actor->GetProperty()->SetAmbientColor(rgb);
  }
}

void vtkRayTracedSpheresRepresentation::SetDiffuseColor(double r, double g, double b)
{
  double rgb[3] = { r, g, b };
  if (vtkRayMapperSetGet::AcceptVector(this, "DiffuseColor", rgb, 0.0, 1.0))
  {
    this->Actor->GetProperty()->SetDiffuseColor(rgb);
  }
}

void vtkRayTracedSpheresRepresentation::SetSpecularColor(double r, double g, double b)
{
  double rgb[3] = { r, g, b };
  if (vtkRayMapperSetGet::AcceptVector(this, "SpecularColor", rgb, 0.0, 1.0))
  {
    this->Actor->GetProperty()->SetSpecularColor(rgb);
  }
}

void vtkRayTracedSpheresRepresentation::SetOpacity(double val)
{
  if (!vtkRayMapperSetGet::Accept(this, "Opacity", val, 0.0, 1.0, this->Actor->GetProperty()->GetOpacity()))
  {
    return;
  }
  // Kept on the property for the mapper; the actor stays in the opaque pass (see the
  // constructor), so the spheres are drawn opaque until the mapper blends.
  this->Actor->GetProperty()->SetOpacity(val);
}
