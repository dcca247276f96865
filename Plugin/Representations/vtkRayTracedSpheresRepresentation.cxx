#include "vtkRayTracedSpheresRepresentation.h"

#include <algorithm>
#include <cmath>

#include "vtkActor.h"
#include "vtkAlgorithmOutput.h"
#include "vtkCommunicator.h"
#include "vtkDataSet.h"
#include "vtkGeometryRepresentation.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkPVLODActor.h"
#include "vtkPVRenderView.h"
#include "vtkPVView.h"
#include "vtkRenderer.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkCGTSphereMapper.h"
#include "vtkCGTSphereOverlayProp.h"
#include "vtkMultiProcessController.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkProperty.h"
#include "vtkRayMapperForward.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperParticleExchange.h"
#include "vtkRayMapperSetGet.h"
#include "vtkRayMapperStatistics.h"
#include "vtkScalarsToColors.h"

vtkStandardNewMacro(vtkRayTracedSpheresRepresentation);

//----------------------------------------------------------------------------
vtkRayTracedSpheresRepresentation::vtkRayTracedSpheresRepresentation()
{
  this->Mapper = vtkSmartPointer<vtkCGTSphereMapper>::New();
  this->Statistics = this->Mapper->GetStatistics();
  this->Actor = vtkSmartPointer<vtkActor>::New();
  this->Actor->SetMapper(this->Mapper);
  this->Overlay = vtkSmartPointer<vtkCGTSphereOverlayProp>::New();
  this->Overlay->SetMapper(this->Mapper);
  this->SetProp(this->Actor, true);
  this->SetParticleMapper(this->Mapper);
  this->WarnOnlyWhenShown(this->Mapper);
  // Until a color array is chosen, the spheres have the solid color: do not let the
  // mapper pick the active scalars of the data on its own.
  this->Mapper->SetScalarVisibility(0);
  this->Mapper->SetColorMode(VTK_COLOR_MODE_MAP_SCALARS);
  // A piece exchanged between processes names where its spheres came from (absent
  // otherwise: the piece's own ids and process).
  this->Mapper->SetPointIdArrayName(vtkRayMapperOriginIdsName);
  this->Mapper->SetProcessIdArrayName(vtkRayMapperOriginProcessesName);
  this->UpdateRadiusParameters();
}

//----------------------------------------------------------------------------
vtkRayTracedSpheresRepresentation::~vtkRayTracedSpheresRepresentation() = default;

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "AmbientOcclusionRadius: " << this->AmbientOcclusionRadius << "\n";
}

//----------------------------------------------------------------------------
int vtkRayTracedSpheresRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request_type, vtkInformation* inInfo, vtkInformation* outInfo)
{
  const int shown = this->Superclass::ProcessViewRequest(request_type, inInfo, outInfo);
  if (shown && request_type == vtkPVView::REQUEST_RENDER())
  {
    this->UpdateSelectionHighlight();
  }
  return shown;
}

namespace
{
/// The output port that `port` shows, past the vtkPVPostFilter that ParaView puts between
/// a source and its representations.
vtkAlgorithmOutput* SourceOf(vtkAlgorithmOutput* port)
{
  while (port && port->GetProducer()->IsA("vtkPVPostFilter") &&
    port->GetProducer()->GetNumberOfInputConnections(0) > 0)
  {
    port = port->GetProducer()->GetInputConnection(0, 0);
  }
  return port;
}
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::UpdateSelectionHighlight()
{
  vtkView* view = this->GetView();
  vtkAlgorithmOutput* input =
    this->GetNumberOfInputConnections(0) > 0 ? SourceOf(this->GetInputConnection(0, 0)) : nullptr;
  vtkIdTypeArray* selected = nullptr;
  for (int r = 0; view && input && !selected && r < view->GetNumberOfRepresentations(); ++r)
  {
    // The selection representation's geometry: its input is the extraction of our input.
    auto* geometry = vtkGeometryRepresentation::SafeDownCast(view->GetRepresentation(r));
    vtkAlgorithmOutput* extracted = geometry && geometry->GetVisibility() &&
        geometry->GetNumberOfInputConnections(0) > 0
      ? SourceOf(geometry->GetInputConnection(0, 0))
      : nullptr;
    vtkAlgorithm* extract = extracted ? extracted->GetProducer() : nullptr;
    if (!extract || !extract->IsA("vtkPVExtractSelection") ||
      extract->GetNumberOfInputConnections(0) < 1 ||
      SourceOf(extract->GetInputConnection(0, 0)) != input)
    {
      continue;
    }
    // The colour on every process: with an exchanged piece, spheres another process
    // selected may be drawn here.
    this->Mapper->SetSelectionColor(geometry->GetActor()->GetProperty()->GetColor());
    auto* points = vtkDataSet::SafeDownCast(extract->GetOutputDataObject(0));
    selected = points ? vtkIdTypeArray::SafeDownCast(
                          points->GetPointData()->GetArray("vtkOriginalPointIds"))
                      : nullptr;
  }
  if (this->PieceExchanged)
  {
    // The spheres drawn here came from several processes, each of which selected among its
    // own: every selection is shared and matched to the drawn spheres' origins. That
    // exchange (all selections gathered, every drawn sphere looked up) is redone only when
    // some process's selection or piece changed, which one integer's reduction tells all.
    vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
    vtkDataSet* piece = this->Mapper->GetInput();
    const ExchangeInputs inputs{ selected, selected ? selected->GetMTime() : 0, piece,
      piece ? piece->GetMTime() : 0 };
    int changed = inputs != this->ExchangedFrom || !this->ExchangedSelection ? 1 : 0;
    int anyChanged = changed;
    controller->AllReduce(&changed, &anyChanged, 1, vtkCommunicator::MAX_OP);
    if (anyChanged)
    {
      this->ExchangedSelection = vtkRayMapperSelectedOfExchange(selected, piece, controller);
      this->ExchangedFrom = inputs;
    }
    this->Mapper->SetSelectedPoints(this->ExchangedSelection);
    return;
  }
  this->ExchangedSelection = nullptr;
  this->Mapper->SetSelectedPoints(selected);
}

//----------------------------------------------------------------------------
vtkCGTSphereMapper* vtkRayTracedSpheresRepresentation::GetMapper()
{
  return this->Mapper;
}

//----------------------------------------------------------------------------
vtkActor* vtkRayTracedSpheresRepresentation::GetActor()
{
  return this->Actor;
}

//----------------------------------------------------------------------------
vtkRayMapperPropRepresentation::Distribution vtkRayTracedSpheresRepresentation::GetDistribution()
{
  const bool translucent = this->Actor->GetProperty()->GetOpacity() < 1.0 ||
    (this->OpacityByArray && !this->OpacityArrayName.empty());
  const bool secondaryRays =
    this->Mapper->GetShadowRays() > 0 || this->Mapper->GetAmbientOcclusionSamples() > 0;
  return translucent || secondaryRays ? Distribution::Particles : Distribution::Surfaces;
}

//----------------------------------------------------------------------------
double vtkRayTracedSpheresRepresentation::GetGhostMargin()
{
  const double largestRadius = this->GetBoundsMargin();
  if (this->Mapper->GetShadowRays() > 0)
  {
    return VTK_DOUBLE_MAX;
  }
  if (this->Mapper->GetAmbientOcclusionSamples() > 0)
  {
    // A ray of length R from a point in the box meets spheres whose centre lies within
    // R + r of it.
    return largestRadius +
      (this->AmbientOcclusionRadius > 0 ? this->AmbientOcclusionRadius : 2.0 * largestRadius);
  }
  return largestRadius;
}

//----------------------------------------------------------------------------
bool vtkRayTracedSpheresRepresentation::AddToView(vtkView* view)
{
  if (!this->Superclass::AddToView(view))
  {
    return false;
  }
  if (auto* rview = vtkPVRenderView::SafeDownCast(view))
  {
    rview->GetRenderer()->AddViewProp(this->Overlay);
  }
  return true;
}

//----------------------------------------------------------------------------
bool vtkRayTracedSpheresRepresentation::RemoveFromView(vtkView* view)
{
  if (auto* rview = vtkPVRenderView::SafeDownCast(view))
  {
    rview->GetRenderer()->RemoveViewProp(this->Overlay);
  }
  return this->Superclass::RemoveFromView(view);
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::SetRegion(const double bounds[6])
{
  this->Mapper->SetRegionBounds(bounds);
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::UpdateMapperParameters()
{
  // The automatic occlusion radius of exchanged spheres is the one of all processes' (each
  // process's own largest radius would differ where the radii do).
  const bool global = this->PieceExchanged && this->GlobalBoundsMargin > 0;
  this->Mapper->SetAmbientOcclusionRadius(this->AmbientOcclusionRadius > 0 || !global
      ? this->AmbientOcclusionRadius
      : 2.0 * this->GlobalBoundsMargin);
  this->UpdateColoringParameters();
}

//----------------------------------------------------------------------------
void vtkRayTracedSpheresRepresentation::UpdateColoringParameters()
{
  // Only point arrays can color points: anything else shows the solid color.
  const char* colorArrayName = this->GetColorPointArrayName();
  if (colorArrayName)
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
double vtkRayTracedSpheresRepresentation::GetAutomaticRadiusPerSpacing()
{
  return vtkCGTSphereMapper::GetAutomaticRadiusPerSpacing();
}

void vtkRayTracedSpheresRepresentation::PushRadius(double& radius, double& scale, const char* radiusArray)
{
  vtkRayMapperPushRadius(this->Mapper.Get(), radius, scale, radiusArray);
}

//----------------------------------------------------------------------------
// Forwarded to the mapper.
// clang-format off
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetAccelerator, int, SetAccelerator)
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetPacketSize, int, SetPacketSize)
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetNumberOfThreads, int, SetNumberOfThreads)
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetLambda, double, SetLambda)
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetMacrocellSize, int, SetMacrocellSize)
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetAmbientOcclusionSamples, int, SetAmbientOcclusionSamples)
void vtkRayTracedSpheresRepresentation::SetAmbientOcclusionRadius(double radius)
{
  // The mapper checks the value (a NaN is refused with a warning, the rest clamped); the
  // representation keeps the same (not the mapper's value, which may be the automatic
  // radius of all processes that UpdateMapperParameters set).
  this->Mapper->SetAmbientOcclusionRadius(radius);
  if (!std::isnan(radius))
  {
    this->AmbientOcclusionRadius = std::clamp(radius, 0.0, VTK_RAYMAPPER_LENGTH_MAX);
  }
  this->Modified();
}

vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetAmbientOcclusionSamplesPerFrame, int, SetAmbientOcclusionSamplesPerFrame)
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetShadowRays, int, SetShadowRays)
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetAutomaticShadowLight, bool, SetAutomaticShadowLight)
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetShadowLightSize, double, SetShadowLightSize)
vtkRayMapperForwardMacro(vtkRayTracedSpheresRepresentation, SetShadowLightIntensity, double, SetShadowLightIntensity)
// clang-format on

void vtkRayTracedSpheresRepresentation::SetShadowLightPosition(double x, double y, double z)
{
  this->Mapper->SetShadowLightPosition(x, y, z);
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
// Forwarded to the actor's property.
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
  // Below 1 the actor is translucent (vtkActor) and the mapper composites the spheres.
  this->Actor->GetProperty()->SetOpacity(val);
}

void vtkRayTracedSpheresRepresentation::SetOpacityByArray(bool byArray)
{
  this->OpacityByArray = byArray;
  this->UpdateOpacityArray();
}

void vtkRayTracedSpheresRepresentation::SelectOpacityArray(int, int, int, int, const char* name)
{
  this->OpacityArrayName = name ? name : "";
  this->UpdateOpacityArray();
}

void vtkRayTracedSpheresRepresentation::SelectOpacityArrayComponent(int component)
{
  this->OpacityArrayComponent = component;
  this->UpdateOpacityArray();
}

void vtkRayTracedSpheresRepresentation::UpdateOpacityArray()
{
  const bool used = this->OpacityByArray && !this->OpacityArrayName.empty();
  this->Mapper->SetOpacityArray(used ? this->OpacityArrayName.c_str() : nullptr);
  this->Mapper->SetOpacityArrayComponent(used ? this->OpacityArrayComponent : 0);
  this->Modified();
}

void vtkRayTracedSpheresRepresentation::SetOpacityTransferFunction(vtkPiecewiseFunction* function)
{
  this->Mapper->SetScalarOpacityFunction(function);
  this->Modified();
}
