#include "vtkSPHVolumeRepresentation.h"

#include "vtkCommunicator.h"
#include "vtkMath.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPointSet.h"
#include "vtkRayMapperForward.h"
#include "vtkRayMapperPointArrays.h"
#include "vtkRayMapperStatistics.h"
#include "vtkSPHVolumeMapper.h"

#include <limits>
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
  this->Statistics = this->Mapper->GetStatistics();
  this->SetVolumeMapper(this->Mapper);
  // The smoothing length array is used whenever one is selected.
  this->UseRadiusArray = true;
}

vtkSPHVolumeRepresentation::~vtkSPHVolumeRepresentation() = default;

void vtkSPHVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}

vtkSPHVolumeMapper* vtkSPHVolumeRepresentation::GetMapper()
{
  return this->Mapper;
}

//----------------------------------------------------------------------------
double vtkSPHVolumeRepresentation::GetAutomaticRadiusPerSpacing()
{
  // The smoothing length whose kernel support is the mapper's automatic support.
  return vtkSPHVolumeMapper::GetAutomaticSupportPerSpacing() /
    this->Mapper->GetSupportPerSmoothingLength();
}

void vtkSPHVolumeRepresentation::PushRadius(double& radius, double& scale, const char* radiusArray)
{
  this->Mapper->SetSmoothingLength(radius);
  this->Mapper->SetScaleFactor(scale);
  radius = this->Mapper->GetSmoothingLength();
  scale = this->Mapper->GetScaleFactor();
  this->Mapper->SetScaleArray(radiusArray);
}

double vtkSPHVolumeRepresentation::GetParticleReach()
{
  return this->Mapper->GetSupportPerSmoothingLength();
}

void vtkSPHVolumeRepresentation::SetRegion(const double bounds[6])
{
  this->Mapper->SetRegionBounds(bounds);
}

void vtkSPHVolumeRepresentation::SetDeliveredPiece(vtkDataObject* piece)
{
  this->Superclass::SetDeliveredPiece(piece);
  // Called on every process for each render (a collective step: see
  // vtkRayMapperPropRepresentation's REQUEST_RENDER).
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (!controller || controller->GetNumberOfProcesses() < 2)
  {
    return;
  }
  // One MIN reduction: the smallest support, the lower corner and the negated upper one of
  // the pieces' finite bounds (infinite where a process has no particles).
  auto* points = vtkPointSet::SafeDownCast(this->Mapper->GetInputDataObject(0, 0));
  constexpr double None = std::numeric_limits<double>::infinity();
  double local[7] = { None, None, None, None, None, None, None }, global[7];
  const double support = this->Mapper->GetParticlesSmallestSupport(points);
  local[0] = support > 0 ? support : None;
  double bounds[6];
  if (points && points->GetNumberOfPoints() > 0)
  {
    vtkRayMapperPointArrays::FiniteBounds(points, bounds);
    for (int a = 0; a < 3 && vtkMath::AreBoundsInitialized(bounds); ++a)
    {
      local[1 + a] = bounds[2 * a];
      local[4 + a] = -bounds[2 * a + 1];
    }
  }
  controller->AllReduce(local, global, 7, vtkCommunicator::MIN_OP);
  this->Mapper->SetSmallestSupport(global[0] < None ? global[0] : 0.0);
  // The float origin: the centre of all pieces' bounds, the same on every process.
  const bool any = global[1] <= -global[4];
  this->Mapper->SetUseFloatOrigin(any);
  if (any)
  {
    this->Mapper->SetFloatOrigin(0.5 * (global[1] - global[4]), 0.5 * (global[2] - global[5]),
      0.5 * (global[3] - global[6]));
  }
}

void vtkSPHVolumeRepresentation::SetValueArray(const char* name)
{
  this->Mapper->SetValueArrayName(name);
}

//----------------------------------------------------------------------------
// Forwarded to the mapper.
// clang-format off
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetKernel, int, SetKernel)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetSupportFactor, double, SetSupportFactor)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetParticleVolume, double, SetVolume)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetNormalization, int, SetNormalization)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetContourShading, bool, SetContourShading)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetContourOpacity, double, SetContourOpacity)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetStepFactor, double, SetStepFactor)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetSamplesPerSupport, double, SetSamplesPerSupport)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetTileSize, int, SetTileSize)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetSlabDepth, int, SetSlabDepth)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetTerminationOpacity, double, SetTerminationOpacity)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetJitter, bool, SetJitter)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetMaximumImageSampleDistance, double, SetMaximumImageSampleDistance)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetFrameBudget, double, SetFrameBudget)
vtkRayMapperForwardMacro(vtkSPHVolumeRepresentation, SetNumberOfThreads, int, SetNumberOfThreads)
// clang-format on

void vtkSPHVolumeRepresentation::SetContourColor(double r, double g, double b)
{
  this->Mapper->SetContourColor(r, g, b);
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

bool vtkSPHVolumeRepresentation::GetLastFrame(double frame[2])
{
  this->Mapper->GetLastFrame(frame);
  return true;
}

void vtkSPHVolumeRepresentation::SetLastFrame(const double frame[2])
{
  this->Mapper->SetLastFrame(frame);
}
