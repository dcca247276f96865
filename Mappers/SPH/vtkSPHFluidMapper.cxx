#include "vtkSPHFluidMapper.h"

#include "FluidParticles.h"
#include "FluidRenderer.h"
#include "FluidSpans.h"
#include "Frame.h"
#include "FrameResample.h"
#include "RenderStatistics.h"
#include "SpanVoxelizer.h"
#include "ViewRays.h"
#include "vtkRayMapperFrameDrawer.h"
#include "vtkRayMapperRenderHelpers.h"
#include "vtkRayMapperScalarArray.h"
#include "vtkRayMapperStatistics.h"

#include "vtkAlgorithm.h"
#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkTimerLog.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

vtkStandardNewMacro(vtkSPHFluidMapper);

struct vtkSPHFluidMapper::Internals
{
  raymappers::FluidParticles Particles;
  raymappers::FluidCells Cells;
  std::string CellsKey; // the particles' key and the culling settings the cells were built with
  raymappers::FluidSpans Spans;
  raymappers::Frame Frame;
  raymappers::Frame Coarse;               // the reduced frame of interactive renders
  double LastFullFrameSeconds = 0;        // the last full-resolution voxelization and render
  vtkRayMapperFrameDrawer Drawer;
  vtkRayMapperRenderHelpers::CameraCheck Camera;
  vtkNew<vtkRayMapperStatistics> Statistics;
  std::string BuiltKey; // what the particles were built from
  vtkMTimeType BuiltInputTime = 0;
  vtkPointSet* BuiltInput = nullptr;
  bool HasParticles = false;
  vtkMTimeType WarnedEmptyInputTime = 0;
  std::string WarnedBudgetKey;
};

namespace
{
std::string str(const char* s)
{
  return s ? s : "";
}
}

vtkSPHFluidMapper::vtkSPHFluidMapper()
  : Impl(new Internals)
{
}

vtkSPHFluidMapper::~vtkSPHFluidMapper()
{
  this->SetRadiusArrayName(nullptr);
}

void vtkSPHFluidMapper::SetInputData(vtkPointSet* input)
{
  this->SetInputDataInternal(0, input);
}

int vtkSPHFluidMapper::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

vtkRayMapperStatistics* vtkSPHFluidMapper::GetStatistics()
{
  return Impl->Statistics;
}

void vtkSPHFluidMapper::ReleaseGraphicsResources(vtkWindow* win)
{
  Impl->Drawer.ReleaseGraphicsResources(win);
  this->Superclass::ReleaseGraphicsResources(win);
}

double* vtkSPHFluidMapper::GetBounds()
{
  // The points' bounds grown by the largest radius, so a camera reset frames the fluid.
  if (vtkAlgorithm* producer = this->GetInputAlgorithm())
  {
    producer->Update();
  }
  auto* input = vtkPointSet::SafeDownCast(this->GetDataSetInput());
  if (!input || input->GetNumberOfPoints() == 0)
  {
    vtkMath::UninitializeBounds(this->Bounds);
    if (input && Impl->WarnedEmptyInputTime != input->GetMTime())
    {
      Impl->WarnedEmptyInputTime = input->GetMTime();
      Impl->Statistics->Set(raymappers::RenderStatistics());
      vtkWarningMacro(<< "The input has no points: no fluid to draw.");
    }
    return this->Bounds;
  }
  vtkRayMapperRenderHelpers::FiniteBounds(input, this->Bounds);
  if (!vtkMath::AreBoundsInitialized(this->Bounds))
  {
    return this->Bounds; // no finite point
  }
  std::string why;
  vtkDataArray* radii =
    vtkRayMapperRenderHelpers::FindPointArray(input, this->RadiusArrayName, "radius", why);
  const double grow = radii
    ? vtkRayMapperRenderHelpers::LargestParticleLength(radii, this->RadiusScale)
    : this->Radius * this->RadiusScale;
  if (grow > 0 && std::isfinite(grow))
  {
    for (int a = 0; a < 3; ++a)
    {
      this->Bounds[2 * a] -= grow;
      this->Bounds[2 * a + 1] += grow;
    }
  }
  return this->Bounds;
}

bool vtkSPHFluidMapper::UpdateParticles(vtkPointSet* input)
{
  std::ostringstream key;
  key << this->Radius << '|' << this->RadiusScale << '|' << str(this->RadiusArrayName);
  if (Impl->HasParticles && Impl->BuiltInput == input &&
    Impl->BuiltInputTime == input->GetMTime() && Impl->BuiltKey == key.str())
  {
    return false;
  }
  std::string why;
  vtkDataArray* radii =
    vtkRayMapperRenderHelpers::FindPointArray(input, this->RadiusArrayName, "radius", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << "; using the constant radius " << this->Radius << ".");
  }
  vtkRayMapperWarnIfComponentsDiffer(this, radii, "radius");
  const vtkRayMapperRenderHelpers::TupleReader pointReader(input->GetPoints()->GetData());
  const vtkRayMapperRenderHelpers::TupleReader radiusReader(radii);
  const double scale = this->RadiusScale, constant = this->Radius * this->RadiusScale;
  raymappers::buildFluidParticles(
    static_cast<std::size_t>(input->GetNumberOfPoints()),
    vtkRayMapperRenderHelpers::FiniteCenter(input->GetPoints()),
    [&](std::size_t i) {
      return raymappers::Vec3d(pointReader.get(i, 0), pointReader.get(i, 1), pointReader.get(i, 2));
    },
    [&](std::size_t i) { return radii ? radiusReader.get(i, 0) * scale : constant; },
    Impl->Particles);
  if (Impl->Particles.skippedNonFinite > 0)
  {
    vtkWarningMacro(<< Impl->Particles.skippedNonFinite
                    << " particles have NaN or infinite coordinates and are not drawn.");
  }
  if (Impl->Particles.skippedBadRadius > 0)
  {
    vtkWarningMacro(<< Impl->Particles.skippedBadRadius
                    << " particles have a zero, negative, non-finite or huge (above 1e15) radius and are not drawn.");
  }
  Impl->HasParticles = true;
  Impl->BuiltInput = input;
  Impl->BuiltInputTime = input->GetMTime();
  Impl->BuiltKey = key.str();
  return true;
}

void vtkSPHFluidMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  raymappers::RenderStatistics stats;
  auto* input = vtkPointSet::SafeDownCast(this->GetDataSetInput());
  if (!input || input->GetNumberOfPoints() == 0 || !input->GetPoints())
  {
    if (input && Impl->WarnedEmptyInputTime != input->GetMTime())
    {
      Impl->WarnedEmptyInputTime = input->GetMTime();
      vtkWarningMacro(<< "The input has no points: no fluid to draw.");
    }
    Impl->Statistics->Set(stats);
    return;
  }
  bool built = false;
  {
    raymappers::ScopedPhase phase(stats, "particles");
    built = this->UpdateParticles(input);
  }
  stats.addCounter("particles", static_cast<std::int64_t>(Impl->Particles.size()));
  stats.addCounter("particles_built", built ? 1 : 0);
  {
    // Boundary-cell culling (FluidCells.h): once per particle set and culling setting.
    std::ostringstream key;
    key << Impl->BuiltKey << '|' << this->BoundaryCulling << '|' << this->CellSize;
    const bool rebuild = built || Impl->CellsKey != key.str();
    if (rebuild)
    {
      raymappers::ScopedPhase phase(stats, "cells");
      raymappers::buildFluidCells(Impl->Particles, this->CellSize, this->BoundaryCulling, Impl->Cells);
      Impl->CellsKey = key.str();
    }
    const raymappers::FluidCells& cells = Impl->Cells;
    stats.setEffect("boundary_culling", this->BoundaryCulling);
    stats.addCounter("cells_built", rebuild ? 1 : 0);
    stats.addCounter("occupied_cells", static_cast<std::int64_t>(cells.occupiedCells));
    stats.addCounter("full_cells", static_cast<std::int64_t>(cells.fullCells));
    stats.addCounter("inner_cells", static_cast<std::int64_t>(cells.innerCells));
    stats.addCounter("culled_particles", static_cast<std::int64_t>(cells.culledParticles));
    stats.addCounter("boxes", static_cast<std::int64_t>(cells.boxes.size()));
  }

  raymappers::FluidRenderParameters params;
  params.voxelizer.angleResolutionDeg = this->AngleResolution;
  params.voxelizer.maxLayers = this->MaximumLayers;
  params.voxelizer.maxSpans = this->MaximumSpans;
  params.voxelizer.memoryBudget = static_cast<std::size_t>(this->MemoryBudget * 1024.0 * 1024.0);
  params.voxelizer.gapThreshold = this->GapThreshold;
  params.voxelizer.cells = &Impl->Cells;
  params.smoothingRadius = this->SmoothingRadius;
  params.smoothingIterations = this->SmoothingIterations;
  params.color = { this->Color[0], this->Color[1], this->Color[2] };
  params.translucency = this->Translucency;
  params.absorptionColor = { this->AbsorptionColor[0], this->AbsorptionColor[1],
    this->AbsorptionColor[2] };
  params.density = this->Density;
  params.refractiveIndex = this->RefractiveIndex;
  params.bounces = this->Bounces;
  params.ambientOcclusion = this->AmbientOcclusion;
  params.aoRadius = this->AmbientOcclusionRadius;
  params.aoSamples = this->AmbientOcclusionSamples;
  if (vtkVolumeProperty* property = vol->GetProperty())
  {
    params.material.ambient = property->GetAmbient();
    params.material.diffuse = property->GetDiffuse();
    params.material.specular = property->GetSpecular();
    params.material.specularPower = property->GetSpecularPower();
  }
  params.lights = vtkRayMapperRenderHelpers::GatherLights(ren);
  const auto model = vtkRayMapperRenderHelpers::GatherModelTransform(vol);
  std::copy(model.modelToWorld, model.modelToWorld + 16, params.modelToWorld);
  std::copy(model.normalToWorld, model.normalToWorld + 9, params.normalToWorld);

  int width = 0, height = 0;
  const std::array<double, 16> modelToClip =
    vtkRayMapperRenderHelpers::GatherModelToClip(ren, model, width, height);
  if (!Impl->Camera.Usable(this, modelToClip))
  {
    Impl->Statistics->Set(stats);
    return;
  }
  // Interactive renders: p x p fewer pixels when the last full frame overran the budget.
  const double rate = ren->GetRenderWindow() ? ren->GetRenderWindow()->GetDesiredUpdateRate() : 0;
  const int p = this->Subsampling > 0
    ? this->Subsampling
    : raymappers::interactiveReduction(Impl->LastFullFrameSeconds, this->FrameBudget, rate, 8);
  stats.addCounter("subsampling", p);
  const int rw = p > 1 ? raymappers::reducedSize(width, p) : width;
  const int rh = p > 1 ? raymappers::reducedSize(height, p) : height;
  raymappers::ViewRays rays;
  if (width <= 0 || height <= 0 || !rays.assign(modelToClip, rw, rh, Impl->Particles.origin))
  {
    vtkErrorMacro(<< "The camera's projection is degenerate: nothing drawn.");
    Impl->Statistics->Set(stats);
    return;
  }
  // Opaque geometry drawn before (all of it: volumes come after the opaque pass) ends the
  // fluid. An opaque fluid is depth tested when drawn, a translucent one must stop there.
  std::vector<float> depth, stop;
  int dw = 0, dh = 0;
  {
    raymappers::ScopedPhase phase(stats, "opaque_depth"); // read back, converted to stop depths
    if (this->Translucency && vtkRayMapperRenderHelpers::ReadOpaqueDepth(ren, depth, dw, dh) &&
      dw == width && dh == height)
    {
      if (p > 1)
      {
        depth = raymappers::sampleDepth(depth, width, height, rw, rh);
      }
      stop = raymappers::stopDepthsFromWindowDepth(rays, depth.data());
      params.voxelizer.stopDepth = stop.data();
    }
  }
  stats.setEffect("opaque_depth", params.voxelizer.stopDepth != nullptr);

  const double start = vtkTimerLog::GetUniversalTime();
  raymappers::Frame& target = p > 1 ? Impl->Coarse : Impl->Frame;
  if (!raymappers::renderFluid(Impl->Particles, rays, params, Impl->Spans, target, stats))
  {
    std::ostringstream key;
    key << this->MemoryBudget << '|' << width << 'x' << height << '|' << this->MaximumLayers;
    if (Impl->WarnedBudgetKey != key.str())
    {
      Impl->WarnedBudgetKey = key.str();
      vtkWarningMacro(<< "The memory budget of " << this->MemoryBudget
                      << " MB cannot hold one voxel column of " << stats.counter("layers")
                      << " layers: nothing drawn. Raise MemoryBudget or lower MaximumLayers.");
    }
  }
  if (p > 1)
  {
    Impl->Frame.resize(width, height);
    raymappers::enlarge(Impl->Coarse, Impl->Frame);
    raymappers::enlargeDepth(Impl->Coarse, Impl->Frame);
  }
  else
  {
    Impl->LastFullFrameSeconds = vtkTimerLog::GetUniversalTime() - start;
  }
  {
    raymappers::ScopedPhase phase(stats, "draw");
    Impl->Drawer.Draw(ren, Impl->Frame,
      this->Translucency ? vtkRayMapperFrameDrawer::Mode::BlendPremultiplied
                         : vtkRayMapperFrameDrawer::Mode::OpaqueWithDepth,
      Impl->Statistics->GetValidateFrames(), stats);
  }
  Impl->Statistics->Set(stats);
}

void vtkSPHFluidMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "RadiusArrayName: " << str(this->RadiusArrayName) << "\n";
  os << indent << "RadiusScale: " << this->RadiusScale << "\n";
  os << indent << "AngleResolution: " << this->AngleResolution << "\n";
  os << indent << "MaximumLayers: " << this->MaximumLayers << "\n";
  os << indent << "MaximumSpans: " << this->MaximumSpans << "\n";
  os << indent << "MemoryBudget: " << this->MemoryBudget << "\n";
  os << indent << "GapThreshold: " << this->GapThreshold << "\n";
  os << indent << "BoundaryCulling: " << this->BoundaryCulling << "\n";
  os << indent << "CellSize: " << this->CellSize << "\n";
  os << indent << "Subsampling: " << this->Subsampling << "\n";
  os << indent << "FrameBudget: " << this->FrameBudget << "\n";
  os << indent << "SmoothingRadius: " << this->SmoothingRadius << "\n";
  os << indent << "SmoothingIterations: " << this->SmoothingIterations << "\n";
  os << indent << "Color: " << this->Color[0] << " " << this->Color[1] << " " << this->Color[2]
     << "\n";
  os << indent << "Translucency: " << this->Translucency << "\n";
  os << indent << "AbsorptionColor: " << this->AbsorptionColor[0] << " "
     << this->AbsorptionColor[1] << " " << this->AbsorptionColor[2] << "\n";
  os << indent << "Density: " << this->Density << "\n";
  os << indent << "RefractiveIndex: " << this->RefractiveIndex << "\n";
  os << indent << "Bounces: " << this->Bounces << "\n";
  os << indent << "AmbientOcclusion: " << this->AmbientOcclusion << "\n";
  os << indent << "AmbientOcclusionRadius: " << this->AmbientOcclusionRadius << "\n";
  os << indent << "AmbientOcclusionSamples: " << this->AmbientOcclusionSamples << "\n";
}
