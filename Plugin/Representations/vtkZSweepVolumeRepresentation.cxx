#include "vtkZSweepVolumeRepresentation.h"

#include "vtkAppendFilter.h"
#include "vtkColorTransferFunction.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataSet.h"
#include "vtkDiscretizableColorTransferFunction.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkRayMapperStatistics.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkZSweepVolumeMapper.h"

#include <cmath>

vtkStandardNewMacro(vtkZSweepVolumeRepresentation);

//----------------------------------------------------------------------------
vtkZSweepVolumeRepresentation::vtkZSweepVolumeRepresentation()
{
  this->Mapper = vtkSmartPointer<vtkZSweepVolumeMapper>::New();
  this->Property = vtkSmartPointer<vtkVolumeProperty>::New();
  this->Volume = vtkSmartPointer<vtkVolume>::New();
  this->Volume->SetMapper(this->Mapper);
  this->SetProp(this->Volume, false);
  this->WarnOnlyWhenShown(this->Mapper);
  this->Volume->SetProperty(this->Property);
}

vtkZSweepVolumeRepresentation::~vtkZSweepVolumeRepresentation() = default;

void vtkZSweepVolumeRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
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

const char* vtkZSweepVolumeRepresentation::GetRenderStatistics()
{
  return this->Mapper->GetStatistics()->GetSummary();
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

  auto* color = vtkColorTransferFunction::SafeDownCast(this->LookupTable);
  vtkPiecewiseFunction* opacity = this->ScalarOpacity;
  if (!opacity)
  {
    if (auto* discretizable = vtkDiscretizableColorTransferFunction::SafeDownCast(color))
    {
      opacity = discretizable->GetScalarOpacityFunction();
    }
  }
  if (color)
  {
    this->Property->SetColor(color);
  }
  if (opacity)
  {
    this->Property->SetScalarOpacity(opacity);
  }
}

void vtkZSweepVolumeRepresentation::SetLookupTable(vtkScalarsToColors* lut)
{
  this->LookupTable = lut;
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetScalarOpacity(vtkPiecewiseFunction* opacity)
{
  this->ScalarOpacity = opacity;
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetScalarOpacityUnitDistance(double distance)
{
  if (!(distance > 0) || !std::isfinite(distance))
  {
    vtkWarningMacro(<< "ScalarOpacityUnitDistance must be positive (got " << distance << ").");
    return;
  }
  this->Property->SetScalarOpacityUnitDistance(distance);
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetIntegrator(int integrator)
{
  this->Mapper->SetIntegrator(integrator);
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetTileSize(int size)
{
  this->Mapper->SetTileSize(size);
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetListThreshold(int k)
{
  this->Mapper->SetListThreshold(k);
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetSparsification(bool on)
{
  this->Mapper->SetSparsification(on);
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetTerminationOpacity(double opacity)
{
  this->Mapper->SetTerminationOpacity(opacity);
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetSubsampling(int p)
{
  this->Mapper->SetSubsampling(p);
  this->Modified();
}

void vtkZSweepVolumeRepresentation::SetFrameBudget(double seconds)
{
  this->Mapper->SetFrameBudget(seconds);
  this->Modified();
}

