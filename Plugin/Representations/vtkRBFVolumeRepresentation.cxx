#include "vtkRBFVolumeRepresentation.h"

#include "vtkColorTransferFunction.h"
#include "vtkDiscretizableColorTransferFunction.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRBFVolumeMapper.h"
#include "vtkRayMapperForward.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperStatistics.h"
#include "vtkVolumeProperty.h"

vtkStandardNewMacro(vtkRBFVolumeRepresentation);

//----------------------------------------------------------------------------
vtkRBFVolumeRepresentation::vtkRBFVolumeRepresentation()
{
  this->Mapper = vtkSmartPointer<vtkRBFVolumeMapper>::New();
  this->Statistics = this->Mapper->GetStatistics();
  this->SetVolumeMapper(this->Mapper);
  // One component per field: field m is classified with component m.
  this->Property->IndependentComponentsOn();
  this->UpdateRadiusParameters();
}

vtkRBFVolumeRepresentation::~vtkRBFVolumeRepresentation() = default;

void vtkRBFVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FieldArrayName: " << this->FieldArrayName << "\n";
  os << indent << "Kappa: " << this->Kappa << "\n";
  os << indent << "NormalizeWeights: " << this->NormalizeWeights << "\n";
}

vtkRBFVolumeMapper* vtkRBFVolumeRepresentation::GetMapper()
{
  return this->Mapper;
}

//----------------------------------------------------------------------------
double vtkRBFVolumeRepresentation::GetAutomaticRadiusPerSpacing()
{
  return vtkRBFVolumeMapper::GetAutomaticRadiusPerSpacing();
}

void vtkRBFVolumeRepresentation::PushRadius(double& radius, double& scale, const char* radiusArray)
{
  vtkRayMapperPushRadius(this->Mapper.Get(), radius, scale, radiusArray);
}

double vtkRBFVolumeRepresentation::GetParticleReach()
{
  return this->Mapper->GetSigma();
}

void vtkRBFVolumeRepresentation::SetRegion(const double bounds[6])
{
  this->Mapper->SetRegionBounds(bounds);
}

void vtkRBFVolumeRepresentation::SetKappa(double kappa)
{
  this->Mapper->SetKappa(kappa);
  this->Kappa = this->Mapper->GetKappa(); // as the mapper accepted it (NaN rejected, clamped)
  this->Modified();
}

void vtkRBFVolumeRepresentation::UpdateMapperParameters()
{
  this->Superclass::UpdateMapperParameters();
  this->PushKappa();
}

void vtkRBFVolumeRepresentation::PushKappa()
{
  this->Mapper->SetKappa(this->Kappa);
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  if (this->Kappa > 0.0 || !controller || controller->GetNumberOfProcesses() < 2)
  {
    return;
  }
  // This process's median weight sum 1 / kappa and particle count (none: no part in it).
  const vtkIdType n = this->Mapper->GetNumberOfParticlesInUse();
  const double kappa = n > 0 ? this->Mapper->GetKappaInUse() : 0.0;
  const double local[2] = { kappa > 0.0 ? static_cast<double>(n) / kappa : 0.0,
    kappa > 0.0 ? static_cast<double>(n) : 0.0 };
  double global[2] = { 0.0, 0.0 };
  controller->AllReduce(local, global, 2, vtkCommunicator::SUM_OP);
  this->Mapper->SetKappa(global[0] > 0.0 ? global[1] / global[0] : 1.0);
}

void vtkRBFVolumeRepresentation::SetValueArray(const char* name)
{
  this->Mapper->SetValueArrayName(name);
  this->PushNormalizeWeights();
}

void vtkRBFVolumeRepresentation::PushNormalizeWeights()
{
  const char* name = this->Mapper->GetValueArrayName();
  this->Mapper->SetNormalizeWeights(this->NormalizeWeights == NormalizeWeightsAutomatic
      ? name != nullptr && name[0] != '\0'
      : this->NormalizeWeights != 0);
}

void vtkRBFVolumeRepresentation::SetNormalizeWeights(int mode)
{
  if (mode < 0 || mode > NormalizeWeightsAutomatic)
  {
    vtkWarningMacro(<< "NormalizeWeights must be 0 (sum), 1 (average) or 2 (automatic), got "
                    << mode << "; keeping " << this->NormalizeWeights << ".");
    return;
  }
  this->NormalizeWeights = mode;
  this->PushNormalizeWeights();
  this->Modified();
}

//----------------------------------------------------------------------------
// Multi-field classification.
void vtkRBFVolumeRepresentation::GetFieldMaps(int field,
  vtkColorTransferFunction*& color,
  vtkPiecewiseFunction*& opacity)
{
  auto* own = vtkDiscretizableColorTransferFunction::SafeDownCast(this->FieldLookupTables[field]);
  if (own)
  {
    color = own;
    if (own->GetScalarOpacityFunction())
    {
      opacity = own->GetScalarOpacityFunction();
    }
  }
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
// The field, forwarded to the mapper.
// clang-format off
vtkRayMapperForwardMacro(vtkRBFVolumeRepresentation, SetSigma, double, SetSigma)
vtkRayMapperForwardMacro(vtkRBFVolumeRepresentation, SetSampleDistance, double, SetSampleDistance)
vtkRayMapperForwardMacro(vtkRBFVolumeRepresentation, SetTerminationOpacity, double, SetTerminationOpacity)
vtkRayMapperForwardMacro(vtkRBFVolumeRepresentation, SetMethod, int, SetMethod)
vtkRayMapperForwardMacro(vtkRBFVolumeRepresentation, SetSamplesPerPass, int, SetSamplesPerPass)
vtkRayMapperForwardMacro(vtkRBFVolumeRepresentation, SetPacketSize, int, SetPacketSize)
vtkRayMapperForwardMacro(vtkRBFVolumeRepresentation, SetLeafSize, int, SetLeafSize)
vtkRayMapperForwardMacro(vtkRBFVolumeRepresentation, SetNumberOfThreads, int, SetNumberOfThreads)
// clang-format on
