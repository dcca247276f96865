#include "vtkRayMapperParticleRepresentation.h"


#include "vtkActor.h"
#include "vtkAlgorithm.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperParticleSizes.h"
#include "vtkRayMapperPointArrays.h"
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
  os << indent << "AutomaticRadius: " << this->AutomaticRadius << "\n";
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
  this->UpdateAutomaticRadius();
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

namespace
{
/// The typical spacing of the particles of all processes: each process's sample distances
/// (vtkRayMapperParticleSizes::SpacingSampleDistances, its share of the sample) gathered,
/// and their median, so that a decomposition gives the spacing of the whole set up to the
/// sampling's noise and the sample particles whose neighbour lies on another process.
double GlobalSpacing(vtkPoints* points, vtkMultiProcessController* controller)
{
  vtkIdType local = points ? points->GetNumberOfPoints() : 0, total = 0;
  controller->AllReduce(&local, &total, 1, vtkCommunicator::SUM_OP);
  std::vector<double> mine = vtkRayMapperParticleSizes::SpacingSampleDistances(
    points, static_cast<std::size_t>(total));
  const int ranks = controller->GetNumberOfProcesses();
  vtkIdType length = static_cast<vtkIdType>(mine.size());
  std::vector<vtkIdType> lengths(static_cast<std::size_t>(ranks)),
    offsets(static_cast<std::size_t>(ranks));
  controller->AllGather(&length, lengths.data(), 1);
  vtkIdType sum = 0;
  for (int r = 0; r < ranks; ++r)
  {
    offsets[static_cast<std::size_t>(r)] = sum;
    sum += lengths[static_cast<std::size_t>(r)];
  }
  std::vector<double> all(static_cast<std::size_t>(std::max<vtkIdType>(sum, 1)));
  mine.push_back(0.0); // a valid pointer when this process has no sample
  controller->AllGatherV(mine.data(), all.data(), length, lengths.data(), offsets.data());
  all.resize(static_cast<std::size_t>(sum));
  return vtkRayMapperParticleSizes::MedianSpacing(all);
}
}

bool vtkRayMapperParticleRepresentation::DrawsAutomaticRadius()
{
  // The automatic radius is drawn when no radius is set and no radius array of the data is
  // in use (a missing one falls back to it); with several processes, when it is on some
  // process (a process without particles has no arrays).
  const char* array = this->GetRadiusArrayInUse();
  int draws = this->Radius == 0.0 && this->ProcessedData->GetNumberOfPoints() > 0 &&
    !(array && this->ProcessedData->GetPointData()->GetArray(array));
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    int any = draws;
    controller->AllReduce(&draws, &any, 1, vtkCommunicator::MAX_OP);
    draws = any;
  }
  return draws != 0;
}

void vtkRayMapperParticleRepresentation::UpdateAutomaticRadius()
{
  if (!this->DrawsAutomaticRadius())
  {
    // Not drawn: no spacing to measure (a new time step of points with a radius array
    // costs no neighbour search).
    return;
  }
  // The typical spacing, and the bounds for its fallback, over all processes.
  vtkPoints* points = this->ProcessedData->GetPoints();
  double bounds[6];
  vtkRayMapperPointArrays::FiniteBounds(this->ProcessedData, bounds);
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  double spacing = 0.0;
  if (controller && controller->GetNumberOfProcesses() > 1)
  {
    // One MIN reduction each: the lower corners and the negated upper ones.
    double lo[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
    double hi[3] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
    for (int a = 0; a < 3 && vtkMath::AreBoundsInitialized(bounds); ++a)
    {
      lo[a] = bounds[2 * a];
      hi[a] = -bounds[2 * a + 1];
    }
    double globalLo[3], globalHi[3];
    controller->AllReduce(lo, globalLo, 3, vtkCommunicator::MIN_OP);
    controller->AllReduce(hi, globalHi, 3, vtkCommunicator::MIN_OP);
    vtkMath::UninitializeBounds(bounds);
    for (int a = 0; a < 3 && globalLo[0] <= -globalHi[0]; ++a)
    {
      bounds[2 * a] = globalLo[a];
      bounds[2 * a + 1] = -globalHi[a];
    }
    spacing = GlobalSpacing(points, controller);
  }
  else
  {
    spacing = this->Spacing.Spacing(points);
  }
  const double automatic = vtkRayMapperParticleSizes::AutomaticLengthFrom(
    spacing, bounds, this->GetAutomaticRadiusPerSpacing());
  if (automatic != this->AutomaticRadius)
  {
    this->AutomaticRadius = automatic;
    this->PushRadiusInUse();
  }
}

double vtkRayMapperParticleRepresentation::GetRadiusInUse() const
{
  return this->Radius == 0.0 ? this->AutomaticRadius : this->Radius;
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
           this->ProcessedData, this->GetRadiusArrayInUse(), this->GetRadiusInUse(), this->RadiusScale);
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

void vtkRayMapperParticleRepresentation::PushRadiusInUse()
{
  // The automatic radius is pushed as it is (0 before the first RequestData: the mapper's
  // own automatic radius). A radius the user set goes as it is, so that the mapper warns
  // about a bad one, and is kept as the mapper accepted it: NaN rejected (the radius stays
  // what it was, automatic again when it was the automatic one), a negative one clamped to
  // 0, i.e. automatic.
  double radius = this->GetRadiusInUse();
  this->PushRadius(radius, this->RadiusScale, this->GetRadiusArrayInUse());
  if (this->Radius != 0.0)
  {
    this->Radius = radius == this->AutomaticRadius ? 0.0 : radius;
  }
}

void vtkRayMapperParticleRepresentation::UpdateRadiusParameters()
{
  this->PushRadiusInUse();
  // Executes RequestData again (on every process), not only a render: a radius setting may
  // make the automatic radius drawn, which RequestData measures only then.
  this->MarkModified();
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
  // The scale leaves the automatic radius drawn or not: a render, no new RequestData.
  setIfChanged(this->RadiusScale, scale,
    [this]
    {
      this->PushRadiusInUse();
      this->Modified();
    });
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
