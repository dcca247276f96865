#include "vtkZSweepVolumeRepresentation.h"

#include "vtkAppendFilter.h"
#include "vtkColorTransferFunction.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRayMapperForward.h"
#include "vtkRayMapperStatistics.h"
#include "vtkRayMapperVolumeClassification.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkZSweepVolumeMapper.h"

vtkStandardNewMacro(vtkZSweepVolumeRepresentation);

//----------------------------------------------------------------------------
vtkZSweepVolumeRepresentation::vtkZSweepVolumeRepresentation()
  : Classification(new vtkRayMapperVolumeClassification)
{
  this->Mapper = vtkSmartPointer<vtkZSweepVolumeMapper>::New();
  this->Statistics = this->Mapper->GetStatistics();
  this->Volume = this->SetVolumeProp(this->Mapper);
}

vtkZSweepVolumeRepresentation::~vtkZSweepVolumeRepresentation() = default;

void vtkZSweepVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ScalarOpacityUnitDistance: "
     << this->Classification->GetScalarOpacityUnitDistance() << "\n";
  os << indent << "ProcessedData: " << this->ProcessedData.Get() << "\n";
}

vtkZSweepVolumeMapper* vtkZSweepVolumeRepresentation::GetMapper()
{
  return this->Mapper;
}

vtkVolume* vtkZSweepVolumeRepresentation::GetVolume()
{
  return this->Volume;
}

//----------------------------------------------------------------------------
vtkDataSet* vtkZSweepVolumeRepresentation::GetProcessedData()
{
  return this->ProcessedData;
}

void vtkZSweepVolumeRepresentation::SetDeliveredPiece(vtkDataObject* piece)
{
  auto* delivered = vtkUnstructuredGrid::SafeDownCast(piece);
  if (delivered)
  {
    this->Mapper->SetInputData(delivered);
  }
  else
  {
    vtkNew<vtkUnstructuredGrid> empty;
    this->Mapper->SetInputData(empty);
  }
  this->UpdateClassification();
}

//----------------------------------------------------------------------------
int vtkZSweepVolumeRepresentation::RequestData(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->ProcessedData = vtkSmartPointer<vtkUnstructuredGrid>::New();
  if (inputVector[0]->GetNumberOfInformationObjects() == 1)
  {
    vtkDataObject* input = vtkDataObject::GetData(inputVector[0], 0);
    auto* grid = vtkUnstructuredGrid::SafeDownCast(input);
    if (grid)
    {
      this->ProcessedData->ShallowCopy(grid);
    }
    else if (input)
    {
      // Structured grids, image data and composites: their cells as they are (hexahedra,
      // voxels ...), never split into tetrahedra.
      vtkNew<vtkAppendFilter> append;
      if (auto* composite = vtkCompositeDataSet::SafeDownCast(input))
      {
        for (vtkDataSet* ds : vtkCompositeDataSet::GetDataSets<vtkDataSet>(composite))
        {
          append->AddInputData(ds);
        }
      }
      else
      {
        append->AddInputData(input);
      }
      if (append->GetNumberOfInputConnections(0) > 0)
      {
        append->Update();
        this->ProcessedData->ShallowCopy(append->GetOutput());
      }
    }
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//----------------------------------------------------------------------------
void vtkZSweepVolumeRepresentation::UpdateClassification()
{
  vtkInformation* info = this->GetInputArrayInformation(0);
  const char* name = info && info->Has(vtkDataObject::FIELD_NAME())
    ? info->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  const int association = info && info->Has(vtkDataObject::FIELD_ASSOCIATION())
    ? info->Get(vtkDataObject::FIELD_ASSOCIATION())
    : vtkDataObject::FIELD_ASSOCIATION_POINTS;
  this->Mapper->SelectScalarArray(name);
  this->Mapper->SetScalarMode(association == vtkDataObject::FIELD_ASSOCIATION_CELLS
      ? VTK_SCALAR_MODE_USE_CELL_FIELD_DATA
      : VTK_SCALAR_MODE_USE_POINT_FIELD_DATA);

  // Without a color or an opacity map the property keeps the last one.
  vtkVolumeProperty* property = this->Volume->GetProperty();
  if (vtkColorTransferFunction* color = this->Classification->GetColorMap())
  {
    property->SetColor(color);
  }
  if (vtkPiecewiseFunction* opacity = this->Classification->GetOpacityMap())
  {
    property->SetScalarOpacity(opacity);
  }
  property->SetScalarOpacityUnitDistance(this->Classification->GetScalarOpacityUnitDistance());
}

void vtkZSweepVolumeRepresentation::SetLookupTable(vtkScalarsToColors* lut)
{
  this->Classification->LookupTable = lut;
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetScalarOpacity(vtkPiecewiseFunction* opacity)
{
  this->Classification->ScalarOpacity = opacity;
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetScalarOpacityUnitDistance(double distance)
{
  if (this->Classification->SetScalarOpacityUnitDistance(this, distance))
  {
    this->Modified();
  }
}

//----------------------------------------------------------------------------
// Forwarded to the mapper.
// clang-format off
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetIntegrator, int, SetIntegrator)
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetCellField, int, SetCellField)
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetCurvedTolerance, double, SetCurvedTolerance)
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetTileSize, int, SetTileSize)
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetListThreshold, int, SetListThreshold)
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetSparsification, bool, SetSparsification)
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetTerminationOpacity, double, SetTerminationOpacity)
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetSubsampling, int, SetSubsampling)
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetFrameBudget, double, SetFrameBudget)
vtkRayMapperForwardMacro(vtkZSweepVolumeRepresentation, SetNumberOfThreads, int, SetNumberOfThreads)
// clang-format on

bool vtkZSweepVolumeRepresentation::GetLastFrame(double frame[2])
{
  this->Mapper->GetLastFrame(frame);
  return true;
}

void vtkZSweepVolumeRepresentation::SetLastFrame(const double frame[2])
{
  this->Mapper->SetLastFrame(frame);
}
