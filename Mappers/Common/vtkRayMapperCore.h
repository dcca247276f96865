// The render skeleton every RayMappers mapper shares, once: the frame a kernel renders into
// and the drawer that shows it, the statistics of the last render, the camera check, the
// mapper's bounds grown by the particles' support, the once-per-input-change warning about
// an empty input, the model transform, clip matrix, opaque depth and material gathered from
// the renderer, and rebuild stamps (vtkRayMapperStamp) keyed on the input's MTime and on the
// parameters a rebuild depends on. An adapter's Render gathers its kernel's parameters,
// calls its kernel into Frame() and lets the core Show() it.
#ifndef vtkRayMapperCore_h
#define vtkRayMapperCore_h

#include "Mappers/Common/Frame.h"
#include "Mappers/Common/Lighting.h"
#include "RayMappersMappersModule.h" // for export macro
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/Common/View.h"
#include "vtkRayMapperFrameDrawer.h"
#include "vtkRayMapperRenderHelpers.h"
#include "vtkRayMapperSelectionPass.h"
#include "vtkRayMapperStatistics.h"

#include "vtkNew.h"
#include "vtkObject.h"

#include <tbb/task_arena.h>

#include <array>
#include <cstdint>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

class vtkAbstractVolumeMapper;
class vtkDataObject;
class vtkHardwareSelector;
class vtkPointSet;
class vtkProp3D;
class vtkRenderer;
class vtkVolumeProperty;
class vtkWindow;

/// A string property's value as a key (nullptr: "").
inline std::string vtkRayMapperString(const char* s)
{
  return s ? s : "";
}

/// What a cache (particles, mesh, accelerator) was built from: the input object and its
/// MTime, and the values of exactly the parameters the build reads (a std::tuple). The
/// mapper's MTime is the quick test: while neither it nor the input changed, the key is not
/// compared; a mapper change that leaves the key alone (a camera-free parameter such as a
/// transfer function or a step) rebuilds nothing.
template <typename... Keys>
class vtkRayMapperStamp
{
public:
  /// Whether the cache must be built again for (mapper, input, key); when it must, the
  /// state is recorded as built (call Invalidate if the build then fails).
  bool Changed(vtkObject* mapper, vtkObject* input, const std::tuple<Keys...>& key)
  {
    const vtkMTimeType mapperTime = mapper->GetMTime();
    const vtkMTimeType inputTime = input ? input->GetMTime() : 0;
    if (this->Built && this->Input == input && this->InputTime == inputTime &&
      (this->MapperTime == mapperTime || this->Key == key))
    {
      this->MapperTime = mapperTime;
      return false;
    }
    this->Built = true;
    this->Input = input;
    this->InputTime = inputTime;
    this->MapperTime = mapperTime;
    this->Key = key;
    return true;
  }
  /// The next Changed is true (what the cache depends on was rebuilt, or its build failed).
  void Invalidate() { this->Built = false; }

private:
  bool Built = false;
  vtkObject* Input = nullptr;
  vtkMTimeType InputTime = 0;
  vtkMTimeType MapperTime = 0;
  std::tuple<Keys...> Key;
};

/// The camera of one render in the prop's model coordinates: the model transform, the
/// model-to-clip matrix of the renderer's tiled viewport and that viewport's size.
struct vtkRayMapperView
{
  vtkRayMapperRenderHelpers::ModelTransform model;
  std::array<double, 16> modelToClip{};
  int width = 0;
  int height = 0;
};

/// A mapper's time-critical properties (vtkRayMapperSampleDistanceMacro, vtkRayMapperSetGet.h).
struct vtkRayMapperSampleDistances
{
  bool autoAdjust = true;
  double imageSampleDistance = 1.0;
  double minimum = 1.0;
  double maximum = 1.0;
  double frameBudget = 0.0;

  template <typename Mapper>
  static vtkRayMapperSampleDistances Of(Mapper* m)
  {
    return { m->GetAutoAdjustSampleDistances() != 0, m->GetImageSampleDistance(),
      m->GetMinimumImageSampleDistance(), m->GetMaximumImageSampleDistance(),
      m->GetFrameBudget() };
  }
  /// The properties as a mapper's PrintSelf prints them.
  void Print(ostream& os, vtkIndent indent) const;
};

class RAYMAPPERSMAPPERS_EXPORT vtkRayMapperCore
{
public:
  using View = vtkRayMapperView;

  vtkRayMapperCore() = default;
  vtkRayMapperCore(const vtkRayMapperCore&) = delete;
  vtkRayMapperCore& operator=(const vtkRayMapperCore&) = delete;

  vtkRayMapperStatistics* GetStatistics() { return this->Statistics; }

  /// The threads of a mapper whose NumberOfThreads is 0: RAYMAPPERS_THREADS when set (> 0);
  /// else, under MPI with L ranks on this machine (Open MPI's OMPI_COMM_WORLD_LOCAL_SIZE,
  /// MPICH's MPI_LOCALNRANKS), the machine's cores divided among them (at least one each), so
  /// that the ranks do not oversubscribe the cores; else all the cores.
  static int DefaultNumberOfThreads();

  /// Runs `render` (the builds, the kernel and the draw of one render) in the mapper's own
  /// tbb::task_arena of `numberOfThreads` threads (0: DefaultNumberOfThreads), so the
  /// kernels' parallel loops use at most that many. The calling thread runs `render`
  /// itself (the arena's slot for it is free: no other thread enters a mapper's arena), so
  /// the OpenGL context stays current. Show records the arena's concurrency in the counter
  /// "threads". A render whose structures or frame do not fit in memory (std::bad_alloc,
  /// from any of its threads, Embree's out-of-memory error among them) or that fails
  /// otherwise (a std::exception, such as an Embree error) calls `release` (the mapper frees
  /// what it has built and invalidates its stamps, so the next render builds again), draws
  /// nothing and reports one error on `mapper` (ReportFailure).
  template <typename Render, typename Release>
  void Execute(vtkObject* mapper, int numberOfThreads, Render&& render, Release&& release)
  {
    const int n = numberOfThreads > 0 ? numberOfThreads : DefaultNumberOfThreads();
    if (!this->Arena || this->ArenaThreads != n)
    {
      this->Arena = std::make_unique<tbb::task_arena>(n);
      this->ArenaThreads = n;
    }
    try
    {
      this->Arena->execute(
        [&]
        {
          this->Concurrency = tbb::this_task_arena::max_concurrency();
          render();
        });
      this->FailedInputTime = 0;
    }
    catch (const std::bad_alloc&)
    {
      release();
      this->ReportFailure(mapper, nullptr);
    }
    catch (const std::exception& failure)
    {
      release();
      this->ReportFailure(mapper, failure.what());
    }
  }

  /// The number of cache builds over the mapper's life (the counter "builds"), one more.
  std::int64_t CountBuild() { return ++this->Builds; }
  std::int64_t GetBuilds() const { return this->Builds; }
  /// The frame's counters of the builds: "builds", all so far, and "builds_this_render",
  /// those counted since the previous call (0: the frame reused what it had built).
  void AddBuildCounters(raymappers::RenderStatistics& stats)
  {
    stats.addCounter("builds", this->Builds);
    stats.addCounter("builds_this_render", this->Builds - this->BuildsReported);
    this->BuildsReported = this->Builds;
  }

  /// The warning "The input has no <what>: no <thing> to draw." from `mapper`, once per
  /// change of `input` (the renderer culls a prop with empty bounds before it renders, so
  /// the bounds are where this is seen); the statistics are emptied with it.
  void WarnEmptyInput(vtkObject* mapper, vtkDataObject* input, const char* what, const char* thing);

  /// vtkAbstractVolumeMapper::GetBounds of a point-set input, of its finite points: the
  /// input when it has some (the caller then grows the bounds by the support), nullptr
  /// with uninitialized bounds (and the empty-input warning) otherwise.
  vtkPointSet* PointSetBounds(vtkAbstractVolumeMapper* mapper, double bounds[6], const char* thing);

  /// Bounds grown by `by` on every side (nothing when `by` is not a positive finite length).
  static void GrowBounds(double bounds[6], double by);

  /// The camera of the renderer's tiled viewport for `prop`: false (with the camera
  /// check's warning, CameraCheck) when it gives no rays.
  bool GatherView(vtkObject* mapper, vtkRenderer* ren, vtkProp3D* prop, View& view);

  /// The kernels' view of this render (raymappers::View): the gathered camera with rays d
  /// pixels apart (SampledSize of the viewport's size; d <= 1: one per pixel), float
  /// coordinates relative to `origin`, and when `withOpaqueDepth` the window depth of opaque
  /// geometry drawn so far at that size (sampled at the pixels' centres when smaller; none
  /// when there is nothing to read; the phase and the effect "opaque_depth" of `stats`).
  /// A view smaller than the viewport makes this a reduced render: Target() is then the
  /// coarse frame and Present enlarges it.
  raymappers::View KernelView(vtkRenderer* ren,
    const View& view,
    double d,
    const raymappers::Vec3d& origin,
    bool withOpaqueDepth,
    raymappers::RenderStatistics& stats);
  /// Whether the kernel view has rays by view depth (the SPH methods need them); false with
  /// the error "The camera's projection is degenerate: nothing drawn." from `mapper`.
  static bool HasDepthRays(vtkObject* mapper, const raymappers::View& kernelView);

  /// The material of a volume property (ambient, diffuse, specular, specular power).
  static raymappers::Material GatherMaterial(vtkVolumeProperty* property);

  /// The time-critical loop: the image sample distance d of this render (rays d pixels
  /// apart; 1: one ray per pixel), and the start of the frame's clock that Show stops.
  /// Without AutoAdjustSampleDistances, ImageSampleDistance. With it, a still render uses
  /// the minimum; an interactive one (the window's DesiredUpdateRate at least 1 frame per
  /// second, as an interactor sets it while the camera moves) d = d_last sqrt(t_last / budget)
  /// within [minimum, maximum]: a frame's time goes with its number of rays, d^-2, so that d
  /// meets the budget. Counter image_sample_distance_percent (100 d).
  double BeginFrame(vtkRenderer* ren,
    const vtkRayMapperSampleDistances& distances,
    raymappers::RenderStatistics& stats);

  /// The last frame the next interactive render scales from: {its time in seconds, its
  /// sample distance} (the t_last and d_last of BeginFrame; {0, 1} before any frame).
  void GetLastFrame(double frame[2]) const
  {
    frame[0] = this->LastSeconds;
    frame[1] = this->LastDistance;
  }
  void SetLastFrame(const double frame[2])
  {
    this->LastSeconds = frame[0];
    this->LastDistance = frame[1];
  }

  /// The number of rays along a side of `full` pixels at sample distance d (at least 1).
  static int SampledSize(int full, double d);

  /// The frame the kernel renders the last KernelView into: full size, or the coarse one of
  /// a reduced render.
  raymappers::Frame& Target() { return this->Reduced ? this->CoarseFrame : this->FullFrame; }

  /// The frame drawn in `mode` (phase "draw"), then the statistics published; after a
  /// reduced render the coarse frame is enlarged to the view's size first (its depth too
  /// when `withDepth`).
  void Present(vtkRenderer* ren,
    const View& view,
    vtkRayMapperFrameDrawer::Mode mode,
    bool withDepth,
    raymappers::RenderStatistics& stats);
  /// A hardware-selection pass (vtkRayMapperSelectionPass.h): `picks` (the view's size, an
  /// id + 1 per pixel) drawn with their depth as the colours of the selector's current pass,
  /// the ids standing for `origins`, `maximumId` the largest id the prop can write; then the
  /// statistics published.
  void PresentSelection(vtkRenderer* ren,
    vtkHardwareSelector* selector,
    const raymappers::IdFrame& picks,
    const vtkRayMapperSelectionPass::Origins& origins,
    vtkIdType maximumId,
    raymappers::RenderStatistics& stats);
  /// A volume's part in a hardware-selection pass: it selects nothing and hides what is
  /// behind it, as ParaView's Volume of an unstructured grid does (its projected tetrahedra
  /// draw their colours in every pass, which the selector reads as no known prop). The
  /// footprint is the last frame's (the selection renders right after a render, with its
  /// camera): "nothing" (0) is drawn over its pixels of alpha > 0, none when the last frame
  /// is not of the viewport's size.
  void PresentSelectionFootprint(vtkRenderer* ren);
  /// A render that draws nothing: the statistics published.
  void Skip(const raymappers::RenderStatistics& stats) { this->Statistics->Set(stats); }

  void ReleaseGraphicsResources(vtkWindow* win) { this->Drawer.ReleaseGraphicsResources(win); }

private:
  /// After a render that failed: the frames freed, the statistics of a render that drew
  /// nothing with the counter "out_of_memory" 1 (`what` null: it ran out of memory; the
  /// error names the input's size) or "render_failed" 1 (the error quotes `what`), and a
  /// vtkErrorMacro on `mapper`, once while the input is unchanged and no render succeeds
  /// (each render tries again: memory may have been freed meanwhile).
  void ReportFailure(vtkObject* mapper, const char* what);
  const float* OpaqueDepth(vtkRenderer* ren,
    const View& view,
    int width,
    int height,
    raymappers::RenderStatistics& stats);
  void Show(vtkRenderer* ren, vtkRayMapperFrameDrawer::Mode mode, raymappers::RenderStatistics& stats);

  raymappers::Frame FullFrame;
  raymappers::Frame CoarseFrame;
  raymappers::Frame FootprintFrame; // a volume's footprint in a selection pass
  vtkRayMapperFrameDrawer Drawer;
  vtkRayMapperRenderHelpers::CameraCheck Camera;
  vtkNew<vtkRayMapperStatistics> Statistics;
  std::vector<float> Depth;
  std::vector<float> CoarseDepth;
  bool Reduced = false; // the last KernelView is smaller than the viewport
  std::int64_t Builds = 0;
  std::int64_t BuildsReported = 0;
  vtkMTimeType WarnedEmptyInputTime = 0;
  vtkMTimeType FailedInputTime = 0; // of the input the last failed render reported (0: none)
  std::unique_ptr<tbb::task_arena> Arena;
  int ArenaThreads = 0;
  int Concurrency = 0; // of the arena the last render ran in
  // The time-critical loop's last frame: its start, its distance and its time.
  double FrameStart = -1.0;
  double FrameDistance = 1.0;
  double LastDistance = 1.0;
  double LastSeconds = 0.0;
};

#endif
