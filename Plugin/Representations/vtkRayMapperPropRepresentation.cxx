#include "vtkRayMapperPropRepresentation.h"

#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPVRenderView.h"
#include "vtkPVView.h"
#include "vtkProp3D.h"
#include "vtkRenderer.h"

vtkRayMapperPropRepresentation::vtkRayMapperPropRepresentation() = default;

vtkRayMapperPropRepresentation::~vtkRayMapperPropRepresentation() = default;

void vtkRayMapperPropRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Prop: " << this->Prop.Get() << "\n";
}

void vtkRayMapperPropRepresentation::SetProp(vtkProp3D* prop, bool selectable)
{
  this->Prop = prop;
  this->Selectable = selectable;
}

int vtkRayMapperPropRepresentation::ProcessViewRequest(vtkInformationRequestKey* request_type,
  vtkInformation* inInfo,
  vtkInformation* outInfo)
{
  // The superclass returns 0 when the representation is hidden: nothing to do then.
  if (!this->Superclass::ProcessViewRequest(request_type, inInfo, outInfo))
  {
    return 0;
  }
  if (request_type == vtkPVView::REQUEST_UPDATE())
  {
    double bounds[6];
    vtkMath::UninitializeBounds(bounds);
    if (vtkDataSet* data = this->GetProcessedData())
    {
      vtkPVView::SetPiece(inInfo, this, data);
      if (data->GetNumberOfPoints() > 0)
      {
        data->GetBounds(bounds);
        const double margin = this->GetBoundsMargin();
        for (int i = 0; i < 3; ++i)
        {
          bounds[2 * i] -= margin;
          bounds[2 * i + 1] += margin;
        }
      }
    }
    vtkNew<vtkMatrix4x4> matrix;
    this->Prop->GetMatrix(matrix);
    vtkPVRenderView::SetGeometryBounds(inInfo, this, bounds, matrix);
  }
  else if (request_type == vtkPVView::REQUEST_RENDER())
  {
    this->SetDeliveredPiece(vtkPVView::GetDeliveredPiece(inInfo, this));
  }
  return 1;
}

vtkDataObject* vtkRayMapperPropRepresentation::GetRenderedDataObject(int port)
{
  vtkDataSet* data = this->GetProcessedData();
  return data ? data : this->Superclass::GetRenderedDataObject(port);
}

bool vtkRayMapperPropRepresentation::AddToView(vtkView* view)
{
  vtkPVRenderView* rview = vtkPVRenderView::SafeDownCast(view);
  if (!rview || !this->Prop)
  {
    return false;
  }
  rview->GetRenderer()->AddViewProp(this->Prop);
  if (this->Selectable)
  {
    rview->RegisterPropForHardwareSelection(this, this->Prop);
  }
  return this->Superclass::AddToView(view);
}

bool vtkRayMapperPropRepresentation::RemoveFromView(vtkView* view)
{
  vtkPVRenderView* rview = vtkPVRenderView::SafeDownCast(view);
  if (!rview || !this->Prop)
  {
    return false;
  }
  rview->GetRenderer()->RemoveViewProp(this->Prop);
  if (this->Selectable)
  {
    rview->UnRegisterPropForHardwareSelection(this, this->Prop);
  }
  return this->Superclass::RemoveFromView(view);
}

void vtkRayMapperPropRepresentation::SetVisibility(bool val)
{
  this->Prop->SetVisibility(val ? 1 : 0);
  this->Superclass::SetVisibility(val);
}

int vtkRayMapperPropRepresentation::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

void vtkRayMapperPropRepresentation::SetOrientation(double x, double y, double z)
{
  this->Prop->SetOrientation(x, y, z);
}

void vtkRayMapperPropRepresentation::SetOrigin(double x, double y, double z)
{
  this->Prop->SetOrigin(x, y, z);
}

void vtkRayMapperPropRepresentation::SetPickable(int val)
{
  this->Prop->SetPickable(val);
}

void vtkRayMapperPropRepresentation::SetPosition(double x, double y, double z)
{
  this->Prop->SetPosition(x, y, z);
}

void vtkRayMapperPropRepresentation::SetScale(double x, double y, double z)
{
  this->Prop->SetScale(x, y, z);
}

void vtkRayMapperPropRepresentation::SetUserTransform(const double matrix[16])
{
  vtkNew<vtkMatrix4x4> m;
  m->DeepCopy(matrix);
  this->Prop->SetUserMatrix(m->IsIdentity() ? nullptr : m.Get());
}
