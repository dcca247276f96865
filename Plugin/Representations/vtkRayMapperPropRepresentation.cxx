#include "vtkRayMapperPropRepresentation.h"
#include "vtkRayMapperPointArrays.h"

#include "vtkAbstractVolumeMapper.h"
#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataSet.h"
#include "vtkInformation.h"
#include "vtkLogger.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkMultiProcessController.h"
#include "vtkNew.h"
#include "vtkPVRenderView.h"
#include "vtkPVRenderViewDataDeliveryManager.h"
#include "vtkPVView.h"
#include "vtkPolyData.h"
#include "vtkProp3D.h"
#include "vtkRayMapperGatherPoints.h"
#include "vtkRayMapperParticleExchange.h"
#include "vtkRayMapperStatistics.h"
#include "vtkOutputWindow.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"
#include "vtkWeakPointer.h"

namespace
{
/// The controller of the rendering processes when there are several, else null.
vtkMultiProcessController* parallelController()
{
  vtkMultiProcessController* c = vtkMultiProcessController::GetGlobalController();
  return c && c->GetNumberOfProcesses() > 1 ? c : nullptr;
}
}

struct vtkRayMapperPropRepresentation::Forwarding
{
  vtkWeakPointer<vtkObject> Source;
  unsigned long WarningTag, ErrorTag;
};

vtkRayMapperPropRepresentation::vtkRayMapperPropRepresentation()
{
  this->WarnOnlyWhenShown(this);
}

vtkRayMapperPropRepresentation::~vtkRayMapperPropRepresentation()
{
  for (const Forwarding& f : this->Forwardings)
  {
    if (f.Source && f.Source != this)
    {
      f.Source->RemoveObserver(f.WarningTag);
      f.Source->RemoveObserver(f.ErrorTag);
    }
  }
}

void vtkRayMapperPropRepresentation::WarnOnlyWhenShown(vtkObject* source)
{
  vtkNew<vtkCallbackCommand> forward;
  forward->SetClientData(this);
  forward->SetCallback(
    [](vtkObject*, unsigned long event, void* self, void* text)
    {
      // The text is the whole message ("Warning: In file, line ..."), as the output window
      // would have shown it.
      if (static_cast<vtkRayMapperPropRepresentation*>(self)->GetVisibility() && text)
      {
        if (event == vtkCommand::WarningEvent)
        {
          vtkOutputWindowDisplayWarningText(static_cast<const char*>(text));
        }
        else
        {
          vtkOutputWindowDisplayErrorText(static_cast<const char*>(text));
        }
      }
    });
  this->Forwardings.push_back({ source, source->AddObserver(vtkCommand::WarningEvent, forward),
    source->AddObserver(vtkCommand::ErrorEvent, forward) });
}

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

vtkSmartPointer<vtkVolume> vtkRayMapperPropRepresentation::SetVolumeProp(
  vtkAbstractVolumeMapper* mapper)
{
  auto volume = vtkSmartPointer<vtkVolume>::New();
  volume->SetMapper(mapper);
  volume->SetProperty(vtkSmartPointer<vtkVolumeProperty>::New());
  this->SetProp(volume, false);
  this->WarnOnlyWhenShown(mapper);
  return volume;
}

const char* vtkRayMapperPropRepresentation::GetRenderStatistics()
{
  return this->Statistics ? this->Statistics->GetSummary() : "";
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
    vtkDataSet* processed = this->GetProcessedData();
    vtkDataObject* input = this->GetInputDataObject(0, 0);
    if (input && (!processed || processed->GetNumberOfPoints() == 0) && !parallelController() &&
      this->WarnedEmptyInputTime != input->GetMTime())
    {
      // Once per input (with several processes, a process's piece may be empty).
      this->WarnedEmptyInputTime = input->GetMTime();
      vtkWarningMacro(<< "The input has no points: nothing to draw.");
    }
    if (vtkDataSet* data = processed)
    {
      vtkPVView::SetPiece(inInfo, this, data);
      vtkRayMapperPointArrays::FiniteBounds(data, bounds);
      if (vtkMath::AreBoundsInitialized(bounds))
      {
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

    const Distribution distribution = this->GetDistribution();
    if (distribution != Distribution::Local && distribution != Distribution::Surfaces)
    {
      // Translucent: the images of the processes are blended in visibility order.
      outInfo->Set(vtkPVRenderView::NEED_ORDERED_COMPOSITING(), 1);
    }
    if (distribution == Distribution::Particles || distribution == Distribution::GatherToFirst)
    {
      // The particles balance the partition (ordered compositing needs one); the view does
      // not move them (its redistribution moves cells), DistributedPiece() does.
      vtkPVRenderView::SetOrderedCompositingConfiguration(
        inInfo, this, vtkPVRenderView::USE_DATA_FOR_LOAD_BALANCING);
    }
    else if (distribution == Distribution::Cells)
    {
      vtkPVRenderView::SetOrderedCompositingConfiguration(inInfo, this,
        vtkPVRenderView::DATA_IS_REDISTRIBUTABLE | vtkPVRenderView::USE_DATA_FOR_LOAD_BALANCING);
    }
  }
  else if (request_type == vtkPVView::REQUEST_RENDER())
  {
    vtkDataObject* piece = vtkPVView::GetDeliveredPiece(inInfo, this);
    this->PieceExchanged = false;
    if (parallelController() && this->GetDistribution() != Distribution::Local &&
      this->GetDistribution() != Distribution::Cells)
    {
      piece = this->DistributedPiece(piece);
    }
    this->SetDeliveredPiece(piece);
    this->ShareLastFrame();
    // Nothing to draw here (the client of a remote render, a rank with an empty piece):
    // the prop stays out of the frame and of the renderer's bounds (a vtkVolume would
    // report [-1, 1]^3 for an empty mapper and move ParaView's Reset Camera).
    auto* data = vtkDataSet::SafeDownCast(piece);
    this->HasPiece = data && data->GetNumberOfPoints() > 0;
    this->Prop->SetVisibility(this->GetVisibility() && this->HasPiece);
  }
  return 1;
}

void vtkRayMapperPropRepresentation::ShareLastFrame()
{
  double frame[2];
  vtkMultiProcessController* controller = parallelController();
  if (controller && this->GetLastFrame(frame))
  {
    // The composited image waits for the slowest process: its time (and its distance,
    // the same on all after the first shared frame; {0, 1} where nothing was drawn yet).
    double slowest[2];
    controller->AllReduce(frame, slowest, 2, vtkCommunicator::MAX_OP);
    this->SetLastFrame(slowest);
  }
}

vtkDataObject* vtkRayMapperPropRepresentation::DistributedPiece(vtkDataObject* delivered)
{
  vtkMultiProcessController* controller = parallelController();
  auto* view = vtkPVView::SafeDownCast(this->GetView());
  auto* manager = view
    ? vtkPVRenderViewDataDeliveryManager::SafeDownCast(view->GetDeliveryManager())
    : nullptr;
  const std::vector<vtkBoundingBox> cuts =
    manager ? manager->GetCuts() : std::vector<vtkBoundingBox>();
  const int ranks = controller->GetNumberOfProcesses();
  const bool particles = this->GetDistribution() == Distribution::Particles ||
    this->GetDistribution() == Distribution::Surfaces;
  if (particles && static_cast<int>(cuts.size()) != ranks)
  {
    // No partition (the view renders without ordered compositing, as with the spheres
    // alone): the delivered piece as it is, unclipped.
    const double all[6] = { -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX,
      -VTK_DOUBLE_MAX, VTK_DOUBLE_MAX };
    this->SetRegion(all);
    this->GlobalBoundsMargin = -1.0;
    return delivered;
  }

  // The ghosts reach as far as the largest ghost margin of any process's particles.
  const double margins[2] = { particles ? this->GetBoundsMargin() : 0.0,
    particles ? this->GetGhostMargin() : 0.0 };
  double largest[2];
  controller->AllReduce(margins, largest, 2, vtkCommunicator::MAX_OP);
  this->GlobalBoundsMargin = largest[0];
  const double globalMargin = largest[1];

  // Exchange again only if something changed on some process (a collective decision).
  const vtkMTimeType cutsTime = manager ? manager->GetCutsMTime().GetMTime() : 0;
  int changed = !this->ExchangedPiece || delivered != this->ExchangedFrom ||
    (delivered && delivered->GetMTime() != this->ExchangedFromTime) ||
    cutsTime != this->ExchangedCutsTime || globalMargin != this->ExchangedMargin;
  int anyChanged = changed;
  controller->AllReduce(&changed, &anyChanged, 1, vtkCommunicator::MAX_OP);
  if (anyChanged)
  {
    vtkSmartPointer<vtkPolyData> local = vtkRayMapperGatherPoints(delivered);
    if (particles)
    {
      if (this->Selectable)
      {
        // A selection names a particle by where it came from, not by where it is drawn.
        local = vtkRayMapperTagOrigins(local, controller->GetLocalProcessId());
      }
      long long ghosts = 0;
      this->ExchangedPiece =
        vtkRayMapperDistributeParticles(local, cuts, globalMargin, controller, ghosts);
      vtkLogF(TRACE, "rank %d: %lld particles, %lld ghosts", controller->GetLocalProcessId(),
        static_cast<long long>(local->GetNumberOfPoints()), ghosts);
    }
    else
    {
      this->ExchangedPiece = vtkRayMapperGatherParticlesToFirst(local, controller);
      if (!this->WarnedGathered && controller->GetLocalProcessId() == 0)
      {
        vtkWarningMacro(<< "with " << ranks
                        << " rendering processes all particles are gathered to the first "
                           "one, which renders them alone (refraction and the screen-space "
                           "effects need the whole fluid): exact, not parallel");
        this->WarnedGathered = true;
      }
    }
    this->ExchangedFrom = delivered;
    this->ExchangedFromTime = delivered ? delivered->GetMTime() : 0;
    this->ExchangedCutsTime = cutsTime;
    this->ExchangedMargin = globalMargin;
  }
  this->PieceExchanged = true;
  if (particles)
  {
    double region[6];
    vtkRayMapperRegionOf(cuts, controller->GetLocalProcessId(), region);
    this->SetRegion(region);
  }
  return this->ExchangedPiece;
}

vtkDataObject* vtkRayMapperPropRepresentation::GetRenderedDataObject(int port)
{
  vtkDataSet* data = this->GetProcessedData();
  return data ? data : this->Superclass::GetRenderedDataObject(port);
}

bool vtkRayMapperPropRepresentation::PlaceProp(vtkView* view, bool add)
{
  vtkPVRenderView* rview = vtkPVRenderView::SafeDownCast(view);
  if (!rview || !this->Prop)
  {
    return false;
  }
  if (add)
  {
    rview->GetRenderer()->AddViewProp(this->Prop);
  }
  else
  {
    rview->GetRenderer()->RemoveViewProp(this->Prop);
  }
  if (this->Selectable && add)
  {
    rview->RegisterPropForHardwareSelection(this, this->Prop);
  }
  else if (this->Selectable)
  {
    rview->UnRegisterPropForHardwareSelection(this, this->Prop);
  }
  return true;
}

bool vtkRayMapperPropRepresentation::AddToView(vtkView* view)
{
  return this->PlaceProp(view, true) && this->Superclass::AddToView(view);
}

bool vtkRayMapperPropRepresentation::RemoveFromView(vtkView* view)
{
  return this->PlaceProp(view, false) && this->Superclass::RemoveFromView(view);
}

void vtkRayMapperPropRepresentation::SetVisibility(bool val)
{
  this->Prop->SetVisibility(val && this->HasPiece);
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
