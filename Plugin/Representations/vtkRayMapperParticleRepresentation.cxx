#include "vtkRayMapperParticleRepresentation.h"

#include "vtkActor.h"
#include "vtkAlgorithm.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperSetGet.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

namespace
{
/// Stores `value` in `setting` and runs `update` when they differ (NaN always differs: the
/// mapper then warns about it again).
template<typename T, typename Update>
void setIfChanged(T& setting, const T& value, Update update)
{
  if (setting != value)
  {
    setting = value;
    update();
  }
}

/// Checks `value` for the material coefficient `which` of `property` (a vtkProperty or a
/// vtkVolumeProperty, which both take NaN as it is; the kernels would shade with it) and
/// stores it. Coefficients are in [0, 1], the specular power in [0, 128].
template<typename PropertyType>
void SetMaterialOf(vtkObject* self, PropertyType* property, int which, double value)
{
  static const char* const names[] = { "Ambient", "Diffuse", "Specular", "SpecularPower" };
  const double current[] = { property->GetAmbient(),
    property->GetDiffuse(),
    property->GetSpecular(),
    property->GetSpecularPower() };
  const double maximum = which == 3 ? 128.0 : 1.0;
  if (!vtkRayMapperSetGet::Accept(self, names[which], value, 0.0, maximum, current[which]))
  {
    return;
  }
  switch (which)
  {
    case 0:
      property->SetAmbient(value);
      break;
    case 1:
      property->SetDiffuse(value);
      break;
    case 2:
      property->SetSpecular(value);
      break;
    default:
      property->SetSpecularPower(value);
  }
}
}

//----------------------------------------------------------------------------
vtkRayMapperParticleRepresentation::vtkRayMapperParticleRepresentation() = default;

vtkRayMapperParticleRepresentation::~vtkRayMapperParticleRepresentation() = default;

void vtkRayMapperParticleRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "RadiusScale: " << this->RadiusScale << "\n";
  os << indent << "UseRadiusArray: " << this->UseRadiusArray << "\n";
  os << indent << "RadiusArrayName: " << this->RadiusArrayName << "\n";
  os << indent << "ProcessedData: " << this->ProcessedData.Get() << "\n";
}

//----------------------------------------------------------------------------
int vtkRayMapperParticleRepresentation::RequestData(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->ProcessedData = vtkRayMapperGatherPoints(
    inputVector[0]->GetNumberOfInformationObjects() == 1 ? vtkDataObject::GetData(inputVector[0], 0)
                                                         : nullptr);
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

vtkDataSet* vtkRayMapperParticleRepresentation::GetProcessedData()
{
  return this->ProcessedData;
}

double vtkRayMapperParticleRepresentation::GetBoundsMargin()
{
  // The particles reach GetParticleReach() of their radius beyond their points.
  return this->GetParticleReach() *
         vtkRayMapperLargestRadius(
           this->ProcessedData, this->GetRadiusArrayInUse(), this->Radius, this->RadiusScale);
}

void vtkRayMapperParticleRepresentation::SetDeliveredPiece(vtkDataObject* piece)
{
  this->ParticleMapper->SetInputDataObject(0, vtkRayMapperDeliveredPoints(piece));
  this->UpdateMapperParameters();
}

const char* vtkRayMapperParticleRepresentation::GetColorPointArrayName()
{
  vtkInformation* info = this->GetInputArrayInformation(0);
  if (!info || !info->Has(vtkDataObject::FIELD_NAME()) ||
      (info->Has(vtkDataObject::FIELD_ASSOCIATION()) &&
        info->Get(vtkDataObject::FIELD_ASSOCIATION()) != vtkDataObject::FIELD_ASSOCIATION_POINTS))
  {
    return nullptr;
  }
  const char* name = info->Get(vtkDataObject::FIELD_NAME());
  return name && name[0] ? name : nullptr;
}

//----------------------------------------------------------------------------
// Particle size.
const char* vtkRayMapperParticleRepresentation::GetRadiusArrayInUse() const
{
  return this->UseRadiusArray && !this->RadiusArrayName.empty() ? this->RadiusArrayName.c_str()
                                                                : nullptr;
}

void vtkRayMapperParticleRepresentation::UpdateRadiusParameters()
{
  this->PushRadius(this->Radius, this->RadiusScale, this->GetRadiusArrayInUse());
  this->Modified();
}

void vtkRayMapperParticleRepresentation::SetRadius(double radius)
{
  setIfChanged(this->Radius, radius, [this] { this->UpdateRadiusParameters(); });
}

void vtkRayMapperParticleRepresentation::SetUseRadiusArray(bool use)
{
  setIfChanged(this->UseRadiusArray, use, [this] { this->UpdateRadiusParameters(); });
}

void vtkRayMapperParticleRepresentation::SelectRadiusArray(int, int, int, int, const char* name)
{
  // The panel's "None" entry (the domain's none_string) selects no array.
  const std::string selected = name && std::string(name) != "None" ? name : "";
  setIfChanged(this->RadiusArrayName, selected, [this] { this->UpdateRadiusParameters(); });
}

void vtkRayMapperParticleRepresentation::SetRadiusScale(double scale)
{
  setIfChanged(this->RadiusScale, scale, [this] { this->UpdateRadiusParameters(); });
}

//----------------------------------------------------------------------------
// Lighting.
void vtkRayMapperParticleRepresentation::SetMaterial(Material coefficient, double value)
{
  const int which = static_cast<int>(coefficient);
  if (auto* actor = vtkActor::SafeDownCast(this->Prop))
  {
    SetMaterialOf(this, actor->GetProperty(), which, value);
  }
  else if (auto* volume = vtkVolume::SafeDownCast(this->Prop))
  {
    SetMaterialOf(this, volume->GetProperty(), which, value);
  }
}

void vtkRayMapperParticleRepresentation::SetAmbient(double value)
{
  this->SetMaterial(Material::Ambient, value);
}

void vtkRayMapperParticleRepresentation::SetDiffuse(double value)
{
  this->SetMaterial(Material::Diffuse, value);
}

void vtkRayMapperParticleRepresentation::SetSpecular(double value)
{
  this->SetMaterial(Material::Specular, value);
}

void vtkRayMapperParticleRepresentation::SetSpecularPower(double value)
{
  this->SetMaterial(Material::SpecularPower, value);
}
