#include "vtkCGTSphereMapper.h"
#include "vtkRayMapperParticleSizes.h"
#include "vtkRayMapperPointArrays.h"

#include "Mappers/CGT/CoherentGridAccelerator.h"
#include "Mappers/CGT/EmbreeSphereAccelerator.h"
#include "Mappers/Common/Frame.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/CGT/SphereRenderer.h"
#include "Mappers/CGT/SphereSet.h"
#include "vtkRayMapperCore.h"
#include "vtkRayMapperRenderHelpers.h"
#include "vtkRayMapperScalarArray.h"
#include "vtkRayMapperSelectionPass.h"

#include "vtkActor.h"
#include "vtkCommand.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkHardwareSelector.h"
#include "vtkIdTypeArray.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkSmartPointer.h"
#include "vtkTimeStamp.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWeakPointer.h"
#include "vtkUnsignedIntArray.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkCGTSphereMapper);
vtkCxxSetObjectMacro(vtkCGTSphereMapper, ScalarOpacityFunction, vtkPiecewiseFunction);

struct vtkCGTSphereMapper::Internals
{
  vtkRayMapperCore Core;
  raymappers::SphereSet Spheres;
  raymappers::EmbreeSphereAccelerator Embree;
  raymappers::CoherentGridAccelerator Grid;

  // Parameter ranges: array names (empty: unused slot) and bounds.
  std::array<std::string, raymappers::MaxRangeAttributes> RangeArrays;
  std::array<double, raymappers::MaxRangeAttributes> RangeLo{}, RangeHi{};
  std::array<bool, raymappers::MaxRangeAttributes> RangeArrayFound{};

  // The sphere set is built from the points, the radius settings and the range arrays; its
  // colours from the mapped scalars and the actor's property (their latest MTime); the
  // accelerator from the sphere set and its kind's own parameters.
  vtkRayMapperStamp<double, double, std::string,
    std::array<std::string, raymappers::MaxRangeAttributes>>
    SpheresStamp;
  vtkMTimeType BuiltColorTime = 0;
  vtkRayMapperStamp<int, double, int, int> AcceleratorStamp;
  // Which accelerator the last build made (the automatic choice may reject the grid), and
  // the grid's spheres in crowded leaves that decided it (-1: no grid built).
  bool UsesGrid = true;
  std::int64_t CrowdedSpheres = -1;
  // The opacities: the latest MTime of the input, the mapper and the opacity function they
  // were set at (0: to be set, after a rebuild of the spheres).
  vtkMTimeType OpacityTime = 0;
  // The typical spacing of the input's points, for the automatic radius.
  vtkRayMapperParticleSizes::SpacingCache Spacing;
  // The translucent draw deferred to the end of the renderer's render (RenderPiece): the
  // renderer observed (and its observer's tag), the actor waiting to be drawn there.
  vtkWeakPointer<vtkRenderer> Observed;
  unsigned long ObserverTag = 0;
  vtkWeakPointer<vtkActor> Pending;
  // Hardware selection: the ids of the last pass, and each point's vertex cell + 1 (0: none)
  // for cell selection, built for the input's MTime.
  raymappers::IdFrame Picks;
  std::vector<std::uint32_t> VertexCellOfPoint;
  vtkMTimeType VertexCellsTime = 0;
  // Highlighted points (SetSelectedPoints), and a mask of them by point id.
  std::vector<vtkIdType> SelectedIds;
  vtkWeakPointer<vtkIdTypeArray> SelectedArray; // the array they were copied from
  vtkMTimeType SelectedArrayTime = 0;
  vtkTimeStamp SelectedTime;
  std::vector<bool> SelectedMask;
  // Progressive ambient occlusion: the directions accumulated per pixel so far.
  raymappers::AoAccumulation AmbientOcclusion;
};

vtkCGTSphereMapper::vtkCGTSphereMapper()
  : Impl(new Internals)
{
}

vtkCGTSphereMapper::~vtkCGTSphereMapper()
{
  if (Impl->Observed)
  {
    Impl->Observed->RemoveObserver(Impl->ObserverTag);
  }
  this->SetScaleArray(nullptr);
  this->SetOpacityArray(nullptr);
  this->SetScalarOpacityFunction(nullptr);
  this->SetPointIdArrayName(nullptr);
  this->SetProcessIdArrayName(nullptr);
}

void vtkCGTSphereMapper::SetRange(int index, const char* arrayName, double minimum, double maximum)
{
  if (index < 0 || index >= raymappers::MaxRangeAttributes)
  {
    vtkErrorMacro(<< "range index " << index << " is outside [0, "
                  << raymappers::MaxRangeAttributes - 1 << "]");
    return;
  }
  if (std::isnan(minimum) || std::isnan(maximum))
  {
    // A NaN bound would hide every sphere (no value compares with it).
    vtkWarningMacro(<< "range " << index << " [" << minimum << ", " << maximum
                    << "] has a bound that is not a number: ignored; the range stays ["
                    << Impl->RangeLo[index] << ", " << Impl->RangeHi[index] << "].");
    return;
  }
  const std::string name = arrayName ? arrayName : "";
  if (Impl->RangeArrays[index] != name || Impl->RangeLo[index] != minimum ||
      Impl->RangeHi[index] != maximum)
  {
    Impl->RangeArrays[index] = name;
    Impl->RangeLo[index] = minimum;
    Impl->RangeHi[index] = maximum;
    this->Modified();
  }
}

void vtkCGTSphereMapper::RemoveAllRanges()
{
  for (int r = 0; r < raymappers::MaxRangeAttributes; ++r)
  {
    this->SetRange(r, nullptr, 0, 0);
  }
}

void vtkCGTSphereMapper::SetUpShadowLight(const vtkRayMapperRenderHelpers::ModelTransform& model,
  raymappers::SphereShading& shading)
{
  // The data's centre and diagonal in world coordinates, from the mapper's bounds.
  double b[6];
  this->GetBounds(b);
  std::array<double, 16> m;
  std::copy(model.modelToWorld, model.modelToWorld + 16, m.begin());
  auto toWorld = [&](const raymappers::Vec3d& p)
  {
    return raymappers::Vec3d(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
      m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
      m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
  };
  const raymappers::Vec3d centerModel(
    0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]));
  const raymappers::Vec3d center = toWorld(centerModel);
  const double diag = std::sqrt(
    (b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
  raymappers::Vec3d position(
    this->ShadowLightPosition[0], this->ShadowLightPosition[1], this->ShadowLightPosition[2]);
  double size = this->ShadowLightSize;
  if (this->AutomaticShadowLight)
  {
    position = center + raymappers::Vec3d(0.5, 1.0, 0.8) * diag;
    size = 0.15 * diag;
  }
  // A square facing the data's centre, in world coordinates, then in the kernel's
  // origin-relative model coordinates.
  raymappers::Vec3d w = raymappers::normalize(center - position);
  const raymappers::Vec3d up =
    std::fabs(w.y) < 0.99 ? raymappers::Vec3d(0, 1, 0) : raymappers::Vec3d(1, 0, 0);
  const raymappers::Vec3d u = raymappers::normalize(raymappers::cross(w, up)) * size;
  const raymappers::Vec3d v = raymappers::normalize(raymappers::cross(u, w)) * size;
  std::array<double, 16> inv;
  if (!raymappers::invert4x4(m, inv))
  {
    vtkWarningMacro(<< "The actor's matrix is singular: no shadows.");
    return;
  }
  auto toModelPoint = [&](const raymappers::Vec3d& p)
  {
    return raymappers::Vec3d(inv[0] * p.x + inv[1] * p.y + inv[2] * p.z + inv[3],
      inv[4] * p.x + inv[5] * p.y + inv[6] * p.z + inv[7],
      inv[8] * p.x + inv[9] * p.y + inv[10] * p.z + inv[11]);
  };
  auto toModelVector = [&](const raymappers::Vec3d& p)
  {
    return raymappers::Vec3d(inv[0] * p.x + inv[1] * p.y + inv[2] * p.z,
      inv[4] * p.x + inv[5] * p.y + inv[6] * p.z,
      inv[8] * p.x + inv[9] * p.y + inv[10] * p.z);
  };
  shading.shadowSide = this->ShadowRays;
  shading.lightCenterWorld = position;
  shading.lightCenter = toModelPoint(position) - Impl->Spheres.origin;
  shading.lightEdgeU = toModelVector(u);
  shading.lightEdgeV = toModelVector(v);
  shading.lightIntensity = this->ShadowLightIntensity;
}

vtkRayMapperStatistics* vtkCGTSphereMapper::GetStatistics()
{
  return Impl->Core.GetStatistics();
}

bool vtkCGTSphereMapper::GetAmbientOcclusionConverged()
{
  vtkRayMapperStatistics* stats = Impl->Core.GetStatistics();
  return stats->GetCounter("ao_converged") > 0 || stats->GetCounter("ao_rays") == 0;
}

std::uint64_t vtkCGTSphereMapper::SceneVersion(vtkActor* actor)
{
  // What the kernel cannot compare itself (it compares the camera, the shading and the
  // range filter): the spheres and their colours, from the MTimes of the input, the mapper
  // (its properties and lookup table), the actor and its property, the mapped colours and
  // the highlighted points, and the accelerator builds. Mixed by FNV-1a.
  const vtkMTimeType colorTime = this->Colors ? this->Colors->GetMTime() : 0;
  const std::uint64_t parts[] = { this->GetInput() ? this->GetInput()->GetMTime() : 0,
    this->GetMTime(),
    actor->GetMTime(),
    actor->GetProperty()->GetMTime(),
    colorTime,
    Impl->SelectedTime.GetMTime(),
    static_cast<std::uint64_t>(Impl->Core.GetBuilds()) };
  std::uint64_t h = 1469598103934665603ull;
  for (const std::uint64_t part : parts)
  {
    h = (h ^ part) * 1099511628211ull;
  }
  return h;
}

void vtkCGTSphereMapper::ReleaseGraphicsResources(vtkWindow* win)
{
  Impl->Core.ReleaseGraphicsResources(win);
  this->Superclass::ReleaseGraphicsResources(win);
}

void vtkCGTSphereMapper::ComputeBounds()
{
  vtkPolyData* input = this->GetInput();
  vtkRayMapperPointArrays::FiniteBounds(input, this->Bounds);
  if (input && input->GetNumberOfPoints() == 0)
  {
    Impl->Core.WarnEmptyInput(this, input, "points", "sphere");
  }
  if (!input || input->GetNumberOfPoints() == 0 || !vtkMath::AreBoundsInitialized(this->Bounds))
  {
    return;
  }
  std::string why;
  vtkDataArray* radii =
    vtkRayMapperPointArrays::FindPointArray(input, this->ScaleArray, "radius", why);
  vtkRayMapperCore::GrowBounds(this->Bounds,
    radii ? vtkRayMapperPointArrays::LargestParticleLength(radii, this->ScaleFactor)
          : this->GetRadiusInUse() * this->ScaleFactor);
}

double vtkCGTSphereMapper::GetRadiusInUse()
{
  return this->Radius > 0.0 ? this->Radius
                            : vtkRayMapperParticleSizes::AutomaticLength(
                                this->GetInput(), GetAutomaticRadiusPerSpacing(), Impl->Spacing);
}

// A sphere's colour: its point's mapped scalar colour (RGB or grey, opaque), or the actor's
// diffuse colour when nothing is mapped.
namespace
{
std::uint32_t PackColor(const double* rgb)
{
  return raymappers::packRGBA8(
    static_cast<unsigned>(std::lround(std::clamp(rgb[0], 0.0, 1.0) * 255)),
    static_cast<unsigned>(std::lround(std::clamp(rgb[1], 0.0, 1.0) * 255)),
    static_cast<unsigned>(std::lround(std::clamp(rgb[2], 0.0, 1.0) * 255)), 255);
}
}

struct vtkCGTSphereMapper::SphereColors
{
  SphereColors(vtkUnsignedCharArray* colors, const double* actorColor,
    const std::vector<bool>& selected, const double* selectionColor)
    : Rgba(colors ? colors->GetPointer(0) : nullptr)
    , Components(colors ? colors->GetNumberOfComponents() : 0)
    , ActorColor(PackColor(actorColor))
    , Selected(selected)
    , SelectionColor(PackColor(selectionColor))
  {
  }
  std::uint32_t operator()(std::size_t i) const
  {
    if (i < Selected.size() && Selected[i])
    {
      return SelectionColor;
    }
    if (!Rgba)
    {
      return ActorColor;
    }
    const unsigned char* c = Rgba + Components * i;
    return Components >= 3 ? raymappers::packRGBA8(c[0], c[1], c[2], 255)
                           : raymappers::packRGBA8(c[0], c[0], c[0], 255);
  }
  const unsigned char* Rgba;
  int Components;
  std::uint32_t ActorColor;
  const std::vector<bool>& Selected; // by point id
  std::uint32_t SelectionColor;
};

void vtkCGTSphereMapper::SetSelectedPoints(vtkIdTypeArray* pointIds)
{
  // The representation hands the selection over at every render: the same array, unchanged
  // since, is not copied and compared again.
  const vtkMTimeType time = pointIds ? pointIds->GetMTime() : 0;
  if (pointIds == Impl->SelectedArray && time == Impl->SelectedArrayTime)
  {
    return;
  }
  Impl->SelectedArray = pointIds;
  Impl->SelectedArrayTime = time;
  std::vector<vtkIdType> ids;
  for (vtkIdType k = 0; pointIds && k < pointIds->GetNumberOfValues(); ++k)
  {
    ids.push_back(pointIds->GetValue(k));
  }
  if (ids != Impl->SelectedIds)
  {
    Impl->SelectedIds = std::move(ids);
    Impl->SelectedTime.Modified();
  }
}

void vtkCGTSphereMapper::SetSelectionColor(double r, double g, double b)
{
  if (r != this->SelectionColor[0] || g != this->SelectionColor[1] || b != this->SelectionColor[2])
  {
    this->SelectionColor[0] = r;
    this->SelectionColor[1] = g;
    this->SelectionColor[2] = b;
    Impl->SelectedTime.Modified();
    this->Modified();
  }
}

void vtkCGTSphereMapper::UpdateSelectedMask(vtkIdType numberOfPoints)
{
  Impl->SelectedMask.assign(Impl->SelectedIds.empty() ? 0 : numberOfPoints, false);
  for (vtkIdType id : Impl->SelectedIds)
  {
    if (id >= 0 && id < numberOfPoints)
    {
      Impl->SelectedMask[static_cast<std::size_t>(id)] = true;
    }
  }
}

void vtkCGTSphereMapper::RenderPiece(vtkRenderer* ren, vtkActor* actor)
{
  if (actor->HasTranslucentPolygonalGeometry() && !vtkRayMapperSelectionPass::Of(ren))
  {
    // VTK's translucent pass draws into the targets of its order-independent blending or
    // depth peeling, whose shaders a frame drawn by a quad does not take part in: the
    // spheres are drawn when the renderer's render ends (DrawDeferred), blended over all it
    // drew, their rays stopped at the depth of its opaque geometry.
    if (Impl->Observed != ren)
    {
      if (Impl->Observed)
      {
        Impl->Observed->RemoveObserver(Impl->ObserverTag);
      }
      Impl->Observed = ren;
      Impl->ObserverTag = ren->AddObserver(vtkCommand::EndEvent, this, &vtkCGTSphereMapper::DrawDeferred);
    }
    Impl->Pending = actor;
    return;
  }
  Impl->Core.Execute(this, this->NumberOfThreads, [&] { this->RenderFrame(ren, actor); },
    [this] { this->ReleaseBuilds(); });
}

void vtkCGTSphereMapper::DrawDeferred(vtkObject* caller, unsigned long, void*)
{
  this->DrawDeferredSpheres(vtkRenderer::SafeDownCast(caller));
}

bool vtkCGTSphereMapper::DrawDeferredSpheres(vtkRenderer* ren)
{
  vtkActor* actor = Impl->Pending;
  if (!ren || !actor || ren != Impl->Observed)
  {
    return false;
  }
  Impl->Pending = nullptr;
  Impl->Core.Execute(this, this->NumberOfThreads, [&] { this->RenderFrame(ren, actor); },
    [this] { this->ReleaseBuilds(); });
  return true;
}

raymappers::SphereAccelerator* vtkCGTSphereMapper::PrepareScene(vtkRenderer* ren,
  vtkActor* actor,
  vtkRayMapperView& view,
  raymappers::RenderStatistics& stats)
{
  vtkPolyData* input = this->GetInput();
  if (!input || input->GetNumberOfPoints() == 0)
  {
    return nullptr;
  }
  // 1. Update: the sphere set and its opacities, then the accelerator over it.
  this->UpdateSpheres(input, actor, stats);
  this->UpdateOpacities(input, stats);
  const bool grid = this->UpdateAccelerator(stats);
  // 2. Gather the camera.
  if (!Impl->Core.GatherView(this, ren, actor, view))
  {
    return nullptr;
  }
  raymappers::SphereAccelerator& accelerator =
    grid ? static_cast<raymappers::SphereAccelerator&>(Impl->Grid) : Impl->Embree;
  this->SetRangeFilter(accelerator);
  return &accelerator;
}

void vtkCGTSphereMapper::ReleaseBuilds()
{
  Impl->Spheres = raymappers::SphereSet();
  Impl->Grid = raymappers::CoherentGridAccelerator();
  Impl->Embree.clear();
  Impl->SpheresStamp.Invalidate();
  Impl->AcceleratorStamp.Invalidate();
  Impl->OpacityTime = 0;
}

void vtkCGTSphereMapper::RenderFrame(vtkRenderer* ren, vtkActor* actor)
{
  raymappers::RenderStatistics stats;
  vtkRayMapperView view;
  raymappers::SphereAccelerator* accelerator = this->PrepareScene(ren, actor, view, stats);
  if (!accelerator)
  {
    Impl->Core.Skip(stats);
    return;
  }
  const int packetSide = accelerator == &Impl->Grid ? this->PacketSize : 4;
  const raymappers::SphereScene scene{ Impl->Spheres, *accelerator,
    vtkRayMapperRenderHelpers::RegionFromBounds(this->RegionBounds) };
  if (vtkHardwareSelector* selector = vtkRayMapperSelectionPass::Of(ren))
  {
    // A hardware selection pass: the ids of the spheres in front instead of colours.
    raymappers::pickSpheres(scene,
      Impl->Core.KernelView(ren, view, 1.0, Impl->Spheres.origin, false, stats), packetSide,
      this->TileSize, Impl->Picks, stats);
    this->PresentSelection(ren, selector, stats);
    return;
  }
  // 3. Gather the lights and material.
  raymappers::SphereRenderParameters params;
  std::copy(view.model.modelToWorld, view.model.modelToWorld + 16, params.shading.modelToWorld);
  std::copy(view.model.normalToWorld, view.model.normalToWorld + 9, params.shading.normalToWorld);
  this->GatherShading(ren, actor, view.model, params.shading);
  params.packetSide = packetSide;
  params.tileSize = this->TileSize;
  params.opacity = actor->GetProperty()->GetOpacity();
  params.aoSamplesPerFrame = this->AmbientOcclusionSamplesPerFrame;
  params.aoAccumulation = &Impl->AmbientOcclusion;
  params.sceneVersion = this->SceneVersion(actor);
  // Translucent spheres stop at the opaque depth and are blended over what is drawn.
  const bool translucent = raymappers::drawsTranslucent(Impl->Spheres, params);
  // 4. Trace, 5. show.
  raymappers::renderSpheres(scene,
    Impl->Core.KernelView(ren, view, 1.0, Impl->Spheres.origin, translucent, stats), params,
    Impl->Core.Target(), stats);
  Impl->Core.Present(ren, view,
    translucent ? vtkRayMapperFrameDrawer::Mode::BlendPremultiplied
                : vtkRayMapperFrameDrawer::Mode::OpaqueWithDepth,
    false, stats);
}

void vtkCGTSphereMapper::PresentSelection(vtkRenderer* ren,
  vtkHardwareSelector* selector,
  raymappers::RenderStatistics& stats)
{
  vtkPolyData* input = this->GetInput();
  vtkRayMapperSelectionPass::Origins origins;
  vtkIdType maximumId = input->GetNumberOfPoints() - 1;
  if (!vtkRayMapperSelectionPass::SelectsPoints(selector))
  {
    maximumId = this->PicksToVertexCells(input);
  }
  else
  {
    vtkPointData* pd = input->GetPointData();
    origins.ids = this->PointIdArrayName
      ? vtkArrayDownCast<vtkIdTypeArray>(pd->GetAbstractArray(this->PointIdArrayName))
      : nullptr;
    origins.processes = this->ProcessIdArrayName
      ? vtkArrayDownCast<vtkUnsignedIntArray>(pd->GetAbstractArray(this->ProcessIdArrayName))
      : nullptr;
    if (origins.ids && origins.ids->GetNumberOfTuples() > 0)
    {
      maximumId = std::max(maximumId, origins.ids->GetValueRange()[1]);
    }
  }
  Impl->Core.PresentSelection(ren, selector, Impl->Picks, origins, maximumId, stats);
}

vtkIdType vtkCGTSphereMapper::PicksToVertexCells(vtkPolyData* input)
{
  // A vtkPolyData numbers its vertex cells (verts) first, so the k-th cell of GetVerts()
  // is cell k. A sphere stands for the first vertex cell holding its point; a point in no
  // vertex cell has no cell to select, and its pixels select nothing.
  vtkCellArray* verts = input->GetVerts();
  if (Impl->VertexCellsTime != input->GetMTime())
  {
    Impl->VertexCellOfPoint.assign(static_cast<std::size_t>(input->GetNumberOfPoints()), 0u);
    auto cells = vtk::TakeSmartPointer(verts->NewIterator());
    for (cells->GoToFirstCell(); !cells->IsDoneWithTraversal(); cells->GoToNextCell())
    {
      vtkIdType count;
      const vtkIdType* points;
      cells->GetCurrentCell(count, points);
      for (vtkIdType k = 0; k < count; ++k)
      {
        std::uint32_t& cell = Impl->VertexCellOfPoint[static_cast<std::size_t>(points[k])];
        cell = cell != 0 ? cell : static_cast<std::uint32_t>(cells->GetCurrentCellId() + 1);
      }
    }
    Impl->VertexCellsTime = input->GetMTime();
  }
  for (std::uint32_t& id : Impl->Picks.ids)
  {
    id = id != 0 ? Impl->VertexCellOfPoint[id - 1] : 0u;
  }
  return verts->GetNumberOfCells() - 1;
}

void vtkCGTSphereMapper::UpdateSpheres(vtkPolyData* input,
  vtkActor* actor,
  raymappers::RenderStatistics& stats)
{
  // The sphere set depends on the points and the radius settings, its colours on the
  // scalars, lookup table and actor colour; a camera or light change reuses both.
  this->MapScalars(input, 1.0);
  vtkMTimeType colorTime = this->Colors ? this->Colors->GetMTime() : 0;
  colorTime = std::max({ colorTime, actor->GetProperty()->GetMTime(), Impl->SelectedTime.GetMTime() });
  const bool geometryChanged = Impl->SpheresStamp.Changed(this, input,
    { this->Radius, this->ScaleFactor, vtkRayMapperString(this->ScaleArray),
      Impl->RangeArrays });
  if (!geometryChanged && Impl->BuiltColorTime == colorTime)
  {
    return;
  }
  raymappers::ScopedPhase phase(stats, geometryChanged ? "spheres" : "recolor");
  int cellFlag = 0;
  vtkUnsignedCharArray* colors = this->MapScalars(input, 1.0, cellFlag);
  if (colors && cellFlag != 0)
  {
    vtkWarningMacro(<< "Sphere glyphs are colored by point data; the selected cell (or field) "
                       "data is ignored and the actor color is used.");
    colors = nullptr;
  }
  this->UpdateSelectedMask(input->GetNumberOfPoints());
  const SphereColors colorOf(
    colors, actor->GetProperty()->GetDiffuseColor(), Impl->SelectedMask, this->SelectionColor);
  if (geometryChanged)
  {
    this->BuildSpheres(input, colorOf);
  }
  else
  {
    // Only the colours changed: recolour in place (the spheres may be in grid order).
    for (std::size_t i = 0; i < Impl->Spheres.size(); ++i)
    {
      Impl->Spheres.colors[i] = colorOf(Impl->Spheres.sourceIds[i]);
    }
  }
  Impl->BuiltColorTime = colorTime;
}

void vtkCGTSphereMapper::BuildSpheres(vtkPolyData* input, const SphereColors& colorOf)
{
  vtkDataArray* radii = vtkRayMapperPointArrays::FindScaleArray(
    this, input, this->ScaleArray, "radius", this->Radius);
  vtkRayMapperWarnIfComponentsDiffer(this, radii, "radius");
  vtkPoints* points = input->GetPoints();
  const double scale = this->ScaleFactor;
  const double constantRadius = radii ? 0.0 : this->GetRadiusInUse() * scale;
  // Float and double arrays (nearly all data) are read directly, others through the
  // generic vtkDataArray interface.
  const vtkRayMapperPointArrays::TupleReader pointReader(points->GetData());
  const vtkRayMapperPointArrays::TupleReader radiusReader(radii);
  raymappers::buildSphereSet(
    static_cast<std::size_t>(input->GetNumberOfPoints()),
    raymappers::Vec3d(vtkRayMapperPointArrays::MedianCenter(points)),
    [&](std::size_t i) {
      return raymappers::Vec3d(pointReader.get(i, 0), pointReader.get(i, 1), pointReader.get(i, 2));
    },
    [&](std::size_t i) { return radii ? radiusReader.get(i, 0) * scale : constantRadius; },
    colorOf,
    Impl->Spheres);
  this->ReadRangeAttributes(input);
  Impl->OpacityTime = 0;
  if (Impl->Spheres.skippedNonFinite > 0)
  {
    vtkWarningMacro(<< Impl->Spheres.skippedNonFinite
                    << " points have NaN or infinite coordinates and are not drawn.");
  }
  if (Impl->Spheres.skippedBadRadius > 0)
  {
    vtkWarningMacro(
      << Impl->Spheres.skippedBadRadius
      << " spheres have a zero, negative, non-finite or huge (above 1e15) radius and are not "
         "drawn.");
  }
  Impl->AcceleratorStamp.Invalidate();
}

void vtkCGTSphereMapper::ReadRangeAttributes(vtkPolyData* input)
{
  // The attributes of parameter-range culling (first component of each range's array).
  vtkDataArray* rangeArrays[raymappers::MaxRangeAttributes] = {};
  int numRanges = 0;
  for (int r = 0; r < raymappers::MaxRangeAttributes; ++r)
  {
    const std::string& name = Impl->RangeArrays[r];
    if (!name.empty())
    {
      rangeArrays[r] = input->GetPointData()->GetArray(name.c_str());
      numRanges = r + 1;
      if (!rangeArrays[r])
      {
        vtkWarningMacro(<< "range array '" << name
                        << "' is not a point array of the input; that range is ignored.");
      }
    }
  }
  raymappers::setSphereAttributes(Impl->Spheres,
    numRanges,
    [&](std::uint32_t id, int a)
    { return rangeArrays[a] ? rangeArrays[a]->GetComponent(static_cast<vtkIdType>(id), 0) : 0.0; });
  Impl->RangeArrayFound.fill(false);
  for (int r = 0; r < numRanges; ++r)
  {
    Impl->RangeArrayFound[r] = rangeArrays[r] != nullptr;
  }
}

vtkDataArray* vtkCGTSphereMapper::FindOpacityArray(vtkPolyData* input, bool warn)
{
  if (!this->OpacityArray || !*this->OpacityArray || !input)
  {
    return nullptr;
  }
  vtkAbstractArray* named = input->GetPointData()->GetAbstractArray(this->OpacityArray);
  vtkDataArray* array = vtkDataArray::SafeDownCast(named);
  if (!array && warn)
  {
    vtkWarningMacro(<< "opacity array '" << this->OpacityArray << "' is "
                    << (named ? std::string("a ") + named->GetClassName() + ", not a numeric array"
                              : std::string("not a point array of the input"))
                    << "; the spheres have the actor's opacity only.");
  }
  return array;
}

void vtkCGTSphereMapper::UpdateOpacities(vtkPolyData* input, raymappers::RenderStatistics& stats)
{
  // The opacities depend on the input, the opacity settings and the function (their latest
  // MTime), and are set again after the spheres are rebuilt.
  vtkPiecewiseFunction* function = this->ScalarOpacityFunction;
  const vtkMTimeType time =
    std::max({ input->GetMTime(), this->GetMTime(), function ? function->GetMTime() : 0 });
  if (Impl->OpacityTime == time)
  {
    return;
  }
  Impl->OpacityTime = time;
  Impl->Spheres.opacities.clear();
  vtkDataArray* array = this->FindOpacityArray(input, true);
  if (!array)
  {
    return;
  }
  raymappers::ScopedPhase phase(stats, "opacities");
  int component = this->OpacityArrayComponent;
  if (component >= array->GetNumberOfComponents())
  {
    vtkWarningMacro(<< "OpacityArrayComponent " << component << " is beyond the "
                    << array->GetNumberOfComponents() << " components of the opacity array '"
                    << this->OpacityArray << "'; component 0 is used.");
    component = 0;
  }
  // The function is evaluated here, serially (vtkPiecewiseFunction is not thread-safe),
  // once per point; the spheres then read their point's value in parallel.
  const vtkIdType n = input->GetNumberOfPoints();
  std::vector<double> opacity(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    const double v = array->GetComponent(i, component);
    opacity[static_cast<std::size_t>(i)] = function && !std::isnan(v) ? function->GetValue(v) : v;
  }
  const std::size_t nan =
    raymappers::setSphereOpacities(Impl->Spheres, [&](std::uint32_t id) { return opacity[id]; });
  if (nan > 0)
  {
    vtkWarningMacro(<< nan << " values of the opacity array '" << this->OpacityArray
                    << "' are NaN: those spheres are not drawn.");
  }
}

bool vtkCGTSphereMapper::HasOpaqueGeometry()
{
  return !this->HasTranslucentPolygonalGeometry();
}

bool vtkCGTSphereMapper::HasTranslucentPolygonalGeometry()
{
  return this->FindOpacityArray(this->GetInput(), false) != nullptr;
}

namespace
{
// The automatic choice (VTK_CGT_ACCELERATOR_AUTOMATIC) keeps the grid unless more than
// CrowdedShare of the spheres lie in leaves of more than CrowdedLeaf spheres: a ray through
// such a leaf tests every sphere of it, where a BVH splits them down to a few (spheres of one
// point, or packed far closer than their radius, which no cell may be smaller than half of).
constexpr std::uint32_t CrowdedLeaf = 1024;
constexpr double CrowdedShare = 0.01;
}

bool vtkCGTSphereMapper::UpdateAccelerator(raymappers::RenderStatistics& stats)
{
  // The accelerator depends on the sphere set and its own parameters: the grid's matter
  // unless Embree is forced, Embree's build quality unless the grid is.
  const int kind = this->Accelerator;
  const bool mayGrid = kind != VTK_CGT_ACCELERATOR_EMBREE;
  if (Impl->AcceleratorStamp.Changed(this, nullptr,
        { kind, mayGrid ? this->Lambda : 0.0, mayGrid ? this->MacrocellSize : 0,
          kind != VTK_CGT_ACCELERATOR_GRID ? this->EmbreeBuildQuality : 0 }))
  {
    Impl->Grid = raymappers::CoherentGridAccelerator();
    Impl->Embree.clear();
    Impl->CrowdedSpheres = -1;
    Impl->UsesGrid = mayGrid && this->BuildGrid(stats);
    if (!Impl->UsesGrid)
    {
      this->BuildEmbree(stats);
    }
    Impl->Core.CountBuild();
  }
  Impl->Core.AddBuildCounters(stats);
  stats.addCounter("spheres", static_cast<std::int64_t>(Impl->Spheres.size()));
  stats.addCounter("accelerator_embree", Impl->UsesGrid ? 0 : 1);
  if (Impl->CrowdedSpheres >= 0)
  {
    stats.addCounter("grid_crowded_spheres", Impl->CrowdedSpheres);
  }
  if (Impl->UsesGrid)
  {
    const auto& d = Impl->Grid.grid().dims();
    stats.addCounter("grid_cells", static_cast<std::int64_t>(d[0]) * d[1] * d[2]);
    stats.addCounter("grid_bytes", static_cast<std::int64_t>(Impl->Grid.grid().memoryBytes()));
    stats.addCounter(
      "grid_nested_cells", static_cast<std::int64_t>(Impl->Grid.grid().nestedCellCount()));
    Impl->Grid.setSimdPath(static_cast<raymappers::SimdPath>(this->SimdInstructions));
    const raymappers::SimdPath path = Impl->Grid.simdPath();
    stats.addCounter("simd_lanes",
      path == raymappers::SimdPath::Avx512 ? 16 : (path == raymappers::SimdPath::Avx2 ? 8 : 1));
  }
  return Impl->UsesGrid;
}

bool vtkCGTSphereMapper::BuildGrid(raymappers::RenderStatistics& stats)
{
  raymappers::ScopedPhase phase(stats, "grid_build");
  raymappers::CoherentGridParameters params;
  params.lambda = this->Lambda;
  params.macrocellSize = this->MacrocellSize;
  Impl->Grid.build(Impl->Spheres, params);
  Impl->CrowdedSpheres =
    static_cast<std::int64_t>(Impl->Grid.grid().spheresInLeavesAbove(CrowdedLeaf));
  if (this->Accelerator == VTK_CGT_ACCELERATOR_GRID ||
    static_cast<double>(Impl->CrowdedSpheres) <=
      CrowdedShare * static_cast<double>(Impl->Spheres.size()))
  {
    return true;
  }
  Impl->Grid = raymappers::CoherentGridAccelerator(); // rejected: its memory goes back
  return false;
}

void vtkCGTSphereMapper::BuildEmbree(raymappers::RenderStatistics& stats)
{
  raymappers::ScopedPhase phase(stats, "bvh_build");
  const auto quality = this->EmbreeBuildQuality == 0
    ? raymappers::EmbreeSphereAccelerator::Quality::Low
    : (this->EmbreeBuildQuality == 2 ? raymappers::EmbreeSphereAccelerator::Quality::High
                                     : raymappers::EmbreeSphereAccelerator::Quality::Medium);
  Impl->Embree.build(Impl->Spheres, quality);
}

void vtkCGTSphereMapper::GatherShading(vtkRenderer* ren,
  vtkActor* actor,
  const vtkRayMapperRenderHelpers::ModelTransform& model,
  raymappers::SphereShading& shading)
{
  vtkProperty* property = actor->GetProperty();
  if (property->GetLighting())
  {
    shading.lights = vtkRayMapperRenderHelpers::GatherLights(ren);
  }
  shading.aoSamples = this->AmbientOcclusionSamples;
  shading.aoRadius =
    this->AmbientOcclusionRadius > 0 ? this->AmbientOcclusionRadius : 2.0 * Impl->Spheres.maxRadius;
  if (this->ShadowRays > 0)
  {
    this->SetUpShadowLight(model, shading);
  }
  shading.material.ambient = property->GetAmbient();
  shading.material.diffuse = property->GetDiffuse();
  shading.material.specular = property->GetSpecular();
  shading.material.specularPower = property->GetSpecularPower();
  const double* sc = property->GetSpecularColor();
  shading.material.specularColor = { sc[0], sc[1], sc[2] };
}

void vtkCGTSphereMapper::SetRangeFilter(raymappers::SphereAccelerator& accelerator)
{
  // Parameter ranges: set on the accelerator at every render, never a rebuild. A range whose
  // array is missing passes everything.
  raymappers::RangeFilter filter;
  filter.count = Impl->Spheres.numAttributes;
  for (int r = 0; r < filter.count; ++r)
  {
    const bool active = Impl->RangeArrayFound[r];
    filter.lo[r] =
      active ? static_cast<float>(Impl->RangeLo[r]) : -std::numeric_limits<float>::max();
    filter.hi[r] =
      active ? static_cast<float>(Impl->RangeHi[r]) : std::numeric_limits<float>::max();
  }
  accelerator.setRangeFilter(filter);
}

void vtkCGTSphereMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "ScaleArray: " << (this->ScaleArray ? this->ScaleArray : "(none)")
     << "\n";
  os << indent << "ScaleFactor: " << this->ScaleFactor << "\n";
  os << indent << "TileSize: " << this->TileSize << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
  os << indent << "PointIdArrayName: " << (this->PointIdArrayName ? this->PointIdArrayName : "(none)")
     << "\n";
  os << indent << "ProcessIdArrayName: "
     << (this->ProcessIdArrayName ? this->ProcessIdArrayName : "(none)") << "\n";
  os << indent << "Accelerator: "
     << (this->Accelerator == VTK_CGT_ACCELERATOR_GRID
            ? "coherent grid"
            : (this->Accelerator == VTK_CGT_ACCELERATOR_EMBREE ? "Embree" : "automatic"))
     << " (last build: " << (Impl->UsesGrid ? "coherent grid" : "Embree") << ")\n";
  os << indent << "PacketSize: " << this->PacketSize << "\n";
  os << indent << "Lambda: " << this->Lambda << "\n";
  os << indent << "MacrocellSize: " << this->MacrocellSize << "\n";
  os << indent << "EmbreeBuildQuality: " << this->EmbreeBuildQuality << "\n";
  os << indent << "SimdInstructions: " << this->SimdInstructions << "\n";
  os << indent << "AmbientOcclusionSamples: " << this->AmbientOcclusionSamples << "\n";
  os << indent << "AmbientOcclusionRadius: " << this->AmbientOcclusionRadius << "\n";
  os << indent << "AmbientOcclusionSamplesPerFrame: " << this->AmbientOcclusionSamplesPerFrame
     << "\n";
  os << indent << "ShadowRays: " << this->ShadowRays << "\n";
  os << indent << "AutomaticShadowLight: " << this->AutomaticShadowLight << "\n";
  os << indent << "ShadowLightPosition: " << this->ShadowLightPosition[0] << " "
     << this->ShadowLightPosition[1] << " " << this->ShadowLightPosition[2] << "\n";
  os << indent << "ShadowLightSize: " << this->ShadowLightSize << "\n";
  os << indent << "ShadowLightIntensity: " << this->ShadowLightIntensity << "\n";
  os << indent << "OpacityArray: " << (this->OpacityArray ? this->OpacityArray : "(none)")
     << "\n";
  os << indent << "OpacityArrayComponent: " << this->OpacityArrayComponent << "\n";
  os << indent << "ScalarOpacityFunction: " << this->ScalarOpacityFunction << "\n";
  os << indent << "RegionBounds: (" << this->RegionBounds[0] << ", " << this->RegionBounds[1]
     << ", " << this->RegionBounds[2] << ", " << this->RegionBounds[3] << ", "
     << this->RegionBounds[4] << ", " << this->RegionBounds[5] << ")\n";
}
