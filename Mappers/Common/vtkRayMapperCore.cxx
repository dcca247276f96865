#include "vtkRayMapperCore.h"
#include "vtkRayMapperSelectionPass.h"
#include "vtkRayMapperPointArrays.h"

#include "Mappers/Common/FrameResample.h"
#include "Mappers/Common/Limits.h"
#include "vtkRayMapperSetGet.h"

#include "vtkAbstractVolumeMapper.h"
#include "vtkAlgorithm.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkMath.h"
#include "vtkPointSet.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <thread>

// The property macros' bound (a public header, which cannot include a kernel's) is the
// kernels' limit.
static_assert(VTK_RAYMAPPER_LENGTH_MAX == raymappers::MaxLength,
  "vtkRayMapperSetGet.h and Mappers/Common/Limits.h disagree on the largest length");

namespace
{
int PositiveEnvironment(const char* name)
{
  const char* value = std::getenv(name);
  const int n = value ? std::atoi(value) : 0;
  return n > 0 ? n : 0;
}
}

int vtkRayMapperCore::DefaultNumberOfThreads()
{
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (const int n = PositiveEnvironment("RAYMAPPERS_THREADS"))
  {
    return n;
  }
  int local = PositiveEnvironment("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (!local)
  {
    local = PositiveEnvironment("MPI_LOCALNRANKS");
  }
  return local > 1 ? std::max(1, cores / local) : cores;
}

void vtkRayMapperCore::WarnEmptyInput(vtkObject* mapper,
  vtkDataObject* input,
  const char* what,
  const char* thing)
{
  if (!input || this->WarnedEmptyInputTime == input->GetMTime())
  {
    return;
  }
  this->WarnedEmptyInputTime = input->GetMTime();
  this->Statistics->Set(raymappers::RenderStatistics());
  vtkWarningWithObjectMacro(mapper, << "The input has no " << what << ": no " << thing << " to draw.");
}

void vtkRayMapperCore::ReportFailure(vtkObject* mapper, const char* what)
{
  this->FullFrame = raymappers::Frame();
  this->CoarseFrame = raymappers::Frame();
  std::vector<float>().swap(this->Depth);
  std::vector<float>().swap(this->CoarseDepth);
  raymappers::RenderStatistics stats;
  stats.addCounter(what ? "render_failed" : "out_of_memory", 1);
  this->Statistics->Set(stats);
  auto* algorithm = vtkAlgorithm::SafeDownCast(mapper);
  auto* input = vtkDataSet::SafeDownCast(algorithm ? algorithm->GetInputDataObject(0, 0) : nullptr);
  const vtkMTimeType inputTime = input ? input->GetMTime() : 1;
  if (this->FailedInputTime == inputTime)
  {
    return; // (reported)
  }
  this->FailedInputTime = inputTime;
  if (what)
  {
    vtkErrorWithObjectMacro(mapper, << "The render failed (" << what << "); nothing is drawn.");
  }
  else if (input)
  {
    vtkErrorWithObjectMacro(mapper,
      << "Out of memory: the structures this render builds for its input ("
      << input->GetNumberOfPoints() << " points, " << input->GetNumberOfCells() << " cells, "
      << input->GetActualMemorySize() / 1024 << " MiB) or its frame do not fit; they are "
      << "released and nothing is drawn. Render fewer points or cells (e.g. Mask Points, "
         "Extract Subset) or a smaller image.");
  }
  else
  {
    vtkErrorWithObjectMacro(mapper,
      << "Out of memory: this render's structures or frame do not fit; nothing is drawn.");
  }
}

vtkPointSet* vtkRayMapperCore::PointSetBounds(vtkAbstractVolumeMapper* mapper,
  double bounds[6],
  const char* thing)
{
  // Bring the input up to date first (as vtkAbstractVolumeMapper::GetBounds does).
  if (vtkAlgorithm* producer = mapper->GetInputAlgorithm())
  {
    producer->Update();
  }
  auto* input = vtkPointSet::SafeDownCast(mapper->GetDataSetInput());
  if (!input || input->GetNumberOfPoints() == 0)
  {
    vtkMath::UninitializeBounds(bounds);
    this->WarnEmptyInput(mapper, input, "points", thing);
    return nullptr;
  }
  vtkRayMapperPointArrays::FiniteBounds(input, bounds);
  return vtkMath::AreBoundsInitialized(bounds) ? input : nullptr;
}

void vtkRayMapperCore::GrowBounds(double bounds[6], double by)
{
  if (!(by > 0) || !std::isfinite(by))
  {
    return;
  }
  for (int a = 0; a < 3; ++a)
  {
    bounds[2 * a] -= by;
    bounds[2 * a + 1] += by;
  }
}

bool vtkRayMapperCore::GatherView(vtkObject* mapper, vtkRenderer* ren, vtkProp3D* prop, View& view)
{
  view.model = vtkRayMapperRenderHelpers::GatherModelTransform(prop);
  view.modelToClip =
    vtkRayMapperRenderHelpers::GatherModelToClip(ren, view.model, view.width, view.height);
  return this->Camera.Usable(mapper, view.modelToClip);
}

const float* vtkRayMapperCore::OpaqueDepth(vtkRenderer* ren,
  const View& view,
  int width,
  int height,
  raymappers::RenderStatistics& stats)
{
  bool have = false;
  {
    raymappers::ScopedPhase phase(stats, "opaque_depth");
    int dw = 0, dh = 0;
    have = vtkRayMapperRenderHelpers::ReadOpaqueDepth(ren, this->Depth, dw, dh) &&
      dw == view.width && dh == view.height;
    if (have && (width != view.width || height != view.height))
    {
      this->CoarseDepth = raymappers::sampleDepth(this->Depth, dw, dh, width, height);
    }
  }
  stats.setEffect("opaque_depth", have);
  if (!have)
  {
    return nullptr;
  }
  return width == view.width && height == view.height ? this->Depth.data()
                                                      : this->CoarseDepth.data();
}

raymappers::View vtkRayMapperCore::KernelView(vtkRenderer* ren,
  const View& view,
  double d,
  const raymappers::Vec3d& origin,
  bool withOpaqueDepth,
  raymappers::RenderStatistics& stats)
{
  const int width = SampledSize(view.width, d);
  const int height = SampledSize(view.height, d);
  this->Reduced = width != view.width || height != view.height;
  const float* depth = withOpaqueDepth ? this->OpaqueDepth(ren, view, width, height, stats) : nullptr;
  return raymappers::View(view.modelToClip, width, height, origin, depth);
}

bool vtkRayMapperCore::HasDepthRays(vtkObject* mapper, const raymappers::View& kernelView)
{
  if (kernelView.width() > 0 && kernelView.height() > 0 && kernelView.hasDepthRays())
  {
    return true;
  }
  vtkErrorWithObjectMacro(mapper, << "The camera's projection is degenerate: nothing drawn.");
  return false;
}

void vtkRayMapperSampleDistances::Print(ostream& os, vtkIndent indent) const
{
  os << indent << "ImageSampleDistance: " << this->imageSampleDistance << "\n";
  os << indent << "AutoAdjustSampleDistances: " << this->autoAdjust << "\n";
  os << indent << "MinimumImageSampleDistance: " << this->minimum << "\n";
  os << indent << "MaximumImageSampleDistance: " << this->maximum << "\n";
  os << indent << "FrameBudget: " << this->frameBudget << "\n";
}

double vtkRayMapperCore::BeginFrame(vtkRenderer* ren,
  const vtkRayMapperSampleDistances& distances,
  raymappers::RenderStatistics& stats)
{
  double d = distances.imageSampleDistance;
  if (distances.autoAdjust)
  {
    const double rate = ren->GetRenderWindow() ? ren->GetRenderWindow()->GetDesiredUpdateRate() : 0;
    const double budget =
      distances.frameBudget > 0 ? distances.frameBudget : (rate > 0 ? 1.0 / rate : 0);
    d = distances.minimum;
    if (rate >= 1.0 && budget > 0 && this->LastSeconds > 0)
    {
      d = std::clamp(this->LastDistance * std::sqrt(this->LastSeconds / budget),
        distances.minimum, std::max(distances.minimum, distances.maximum));
    }
  }
  stats.addCounter("image_sample_distance_percent", std::lround(100 * d));
  this->FrameDistance = d;
  this->FrameStart = vtkTimerLog::GetUniversalTime();
  return d;
}

int vtkRayMapperCore::SampledSize(int full, double d)
{
  return d > 1.0 ? std::max(1, static_cast<int>(std::ceil(full / d))) : full;
}

raymappers::Material vtkRayMapperCore::GatherMaterial(vtkVolumeProperty* property)
{
  raymappers::Material material;
  material.ambient = property->GetAmbient();
  material.diffuse = property->GetDiffuse();
  material.specular = property->GetSpecular();
  material.specularPower = property->GetSpecularPower();
  return material;
}

void vtkRayMapperCore::Show(vtkRenderer* ren,
  vtkRayMapperFrameDrawer::Mode mode,
  raymappers::RenderStatistics& stats)
{
  {
    raymappers::ScopedPhase phase(stats, "draw");
    this->Drawer.Draw(ren, this->FullFrame, mode, this->Statistics->GetValidateFrames(), stats);
  }
  stats.addCounter("threads", this->Concurrency);
  this->Statistics->Set(stats);
  if (this->FrameStart >= 0)
  {
    this->LastSeconds = vtkTimerLog::GetUniversalTime() - this->FrameStart;
    this->LastDistance = this->FrameDistance;
    this->FrameStart = -1.0;
  }
}

void vtkRayMapperCore::Present(vtkRenderer* ren,
  const View& view,
  vtkRayMapperFrameDrawer::Mode mode,
  bool withDepth,
  raymappers::RenderStatistics& stats)
{
  if (!this->Reduced)
  {
    this->Show(ren, mode, stats);
    return;
  }
  this->FullFrame.resize(view.width, view.height);
  raymappers::enlarge(this->CoarseFrame, this->FullFrame);
  if (withDepth)
  {
    raymappers::enlargeDepth(this->CoarseFrame, this->FullFrame);
  }
  this->Show(ren, mode, stats);
}

void vtkRayMapperCore::PresentSelection(vtkRenderer* ren,
  vtkHardwareSelector* selector,
  const raymappers::IdFrame& picks,
  const vtkRayMapperSelectionPass::Origins& origins,
  vtkIdType maximumId,
  raymappers::RenderStatistics& stats)
{
  vtkRayMapperSelectionPass::Begin(selector, maximumId);
  vtkRayMapperSelectionPass::Encode(selector, picks, origins, this->FullFrame);
  {
    raymappers::ScopedPhase phase(stats, "draw");
    this->Drawer.Draw(
      ren, this->FullFrame, vtkRayMapperFrameDrawer::Mode::OpaqueWithDepth, false, stats);
  }
  vtkRayMapperSelectionPass::End(selector);
  stats.addCounter("threads", this->Concurrency);
  this->Statistics->Set(stats);
}

void vtkRayMapperCore::PresentSelectionFootprint(vtkRenderer* ren)
{
  int width = 0, height = 0;
  ren->GetTiledSize(&width, &height);
  const raymappers::Frame& last = this->FullFrame;
  if (last.width != width || last.height != height || last.rgba.empty())
  {
    return;
  }
  raymappers::Frame& footprint = this->FootprintFrame;
  footprint.resize(width, height);
  for (std::size_t p = 0; p < last.depth.size(); ++p)
  {
    // Opaque black, premultiplied: the blend writes 0, "no prop", in every pass.
    footprint.rgba[4 * p + 3] = last.rgba[4 * p + 3] > 0.f ? 1.f : 0.f;
  }
  raymappers::RenderStatistics ignored;
  this->Drawer.Draw(
    ren, footprint, vtkRayMapperFrameDrawer::Mode::BlendPremultiplied, false, ignored);
}
