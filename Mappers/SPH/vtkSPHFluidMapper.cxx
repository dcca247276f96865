#include "vtkSPHFluidMapper.h"
#include "vtkRayMapperPointArrays.h"

#include "Mappers/SPH/FluidColors.h"
#include "Mappers/SPH/FluidParticles.h"
#include "Mappers/SPH/FluidRenderer.h"
#include "Mappers/SPH/FluidSpans.h"
#include "Mappers/Common/Frame.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/SPH/SpanVoxelizer.h"
#include "Mappers/Common/ViewRays.h"
#include "vtkRayMapperCore.h"
#include "vtkRayMapperRenderHelpers.h"
#include "vtkRayMapperScalarArray.h"

#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkLookupTable.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

vtkStandardNewMacro(vtkSPHFluidMapper);

struct vtkSPHFluidMapper::Internals
{
  raymappers::FluidParticles Particles;
  raymappers::FluidCells Cells;
  raymappers::FluidColors Colors;
  vtkSmartPointer<vtkScalarsToColors> LookupTable;
  raymappers::FluidSpans Spans;
  raymappers::SurfaceNeighbourhoods Neighbourhoods;
  // The particles are built from the points and the radius settings, the culling cells from
  // the particles and the culling settings.
  vtkRayMapperStamp<double, double, std::string> ParticlesStamp;
  vtkRayMapperStamp<bool, double> CellsStamp;
  // The colours from the particles, the colouring settings and the table's state.
  vtkRayMapperStamp<bool, std::string, vtkScalarsToColors*, vtkMTimeType, vtkMTimeType>
    ColorsStamp;
  // The memory budget, frame size and layer limit last warned about.
  std::tuple<double, int, int, int> WarnedBudget{ -1.0, 0, 0, 0 };
};

vtkSPHFluidMapper::vtkSPHFluidMapper()
  : Superclass("fluid")
  , Impl(new Internals)
{
  // The fluid's surfaces write depth: volumes drawn after it stop there.
  this->GetInformation()->Set(vtkRayMapperRenderHelpers::WRITES_DEPTH(), 1);
}

vtkSPHFluidMapper::~vtkSPHFluidMapper()
{
  this->SetColorArrayName(nullptr);
}

void vtkSPHFluidMapper::SetLookupTable(vtkScalarsToColors* lut)
{
  if (Impl->LookupTable != lut)
  {
    Impl->LookupTable = lut;
    this->Modified();
  }
}

vtkScalarsToColors* vtkSPHFluidMapper::GetLookupTable()
{
  return Impl->LookupTable;
}

vtkMTimeType vtkSPHFluidMapper::GetMTime()
{
  const vtkMTimeType own = this->Superclass::GetMTime();
  return Impl->LookupTable ? std::max(own, Impl->LookupTable->GetMTime()) : own;
}

double vtkSPHFluidMapper::GetSupportRadius(vtkPointSet* input)
{
  // The largest sphere radius: the fluid is the union of the spheres.
  std::string why;
  vtkDataArray* radii =
    vtkRayMapperPointArrays::FindPointArray(input, this->ScaleArray, "radius", why);
  return radii ? vtkRayMapperPointArrays::LargestParticleLength(radii, this->ScaleFactor)
               : this->GetRadiusInUse() * this->ScaleFactor;
}

double vtkSPHFluidMapper::GetRadiusInUse()
{
  return this->SizeInUse(this->Radius, GetAutomaticRadiusPerSpacing());
}

double vtkSPHFluidMapper::GetLengthUnitSize() const
{
  // The mean radius of the particles built (1 for WORLD, and when there are none).
  return this->LengthUnit == PARTICLE_RADIUS && Impl->Particles.meanRadius > 0.0
    ? Impl->Particles.meanRadius
    : 1.0;
}

bool vtkSPHFluidMapper::UpdateParticles(vtkPointSet* input)
{
  if (!Impl->ParticlesStamp.Changed(
        this, input, { this->Radius, this->ScaleFactor, vtkRayMapperString(this->ScaleArray) }))
  {
    return false;
  }
  vtkDataArray* radii = vtkRayMapperPointArrays::FindScaleArray(
    this, input, this->ScaleArray, "radius", this->Radius);
  vtkRayMapperWarnIfComponentsDiffer(this, radii, "radius");
  const vtkRayMapperPointArrays::TupleReader pointReader(input->GetPoints()->GetData());
  const vtkRayMapperPointArrays::TupleReader radiusReader(radii);
  const double scale = this->ScaleFactor;
  const double constant = radii ? 0.0 : this->GetRadiusInUse() * scale;
  raymappers::buildFluidParticles(
    static_cast<std::size_t>(input->GetNumberOfPoints()),
    raymappers::Vec3d(vtkRayMapperPointArrays::FiniteCenter(input->GetPoints())),
    [&](std::size_t i) {
      return raymappers::Vec3d(pointReader.get(i, 0), pointReader.get(i, 1), pointReader.get(i, 2));
    },
    [&](std::size_t i) { return radii ? radiusReader.get(i, 0) * scale : constant; },
    Impl->Particles);
  this->WarnSkipped(
    Impl->Particles.skippedNonFinite, "particles have NaN or infinite coordinates");
  this->WarnSkipped(Impl->Particles.skippedBadRadius,
    "particles have a zero, negative, non-finite or huge (above 1e15) radius");
  Impl->CellsStamp.Invalidate();
  Impl->ColorsStamp.Invalidate();
  return true;
}

void vtkSPHFluidMapper::UpdateColors(vtkPointSet* input, raymappers::RenderStatistics& stats)
{
  const std::string name = vtkRayMapperString(this->ColorArrayName);
  const bool wanted = this->ScalarVisibility && !name.empty();
  vtkDataArray* array = wanted ? input->GetPointData()->GetArray(name.c_str()) : nullptr;
  vtkScalarsToColors* lut = Impl->LookupTable;
  const bool rebuild = Impl->ColorsStamp.Changed(this, input,
    { wanted, name, lut, lut ? lut->GetMTime() : 0, array ? array->GetMTime() : 0 });
  stats.addCounter("colors_built", rebuild ? 1 : 0);
  if (!rebuild)
  {
    return;
  }
  Impl->Colors = raymappers::FluidColors();
  if (wanted && !array)
  {
    vtkWarningMacro(<< "The color array '" << name
                    << "' is not a point array of the input: the fluid has its solid Color.");
  }
  if (!array)
  {
    return;
  }
  vtkSmartPointer<vtkScalarsToColors> table = lut;
  if (!table)
  {
    // vtkMapper's default: a lookup table over the array's range.
    auto own = vtkSmartPointer<vtkLookupTable>::New();
    own->SetRange(array->GetRange(0));
    own->Build();
    table = own;
  }
  vtkSmartPointer<vtkUnsignedCharArray> rgba = vtkSmartPointer<vtkUnsignedCharArray>::Take(
    table->MapScalars(array, VTK_COLOR_MODE_MAP_SCALARS, -1, VTK_RGBA));
  raymappers::ScopedPhase phase(stats, "colors");
  raymappers::buildFluidColors(
    Impl->Particles,
    [&](std::uint32_t id)
    {
      const unsigned char* c = rgba->GetPointer(4 * static_cast<vtkIdType>(id));
      return raymappers::Vec3d(c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
    },
    Impl->Colors);
}

void vtkSPHFluidMapper::UpdateCells(raymappers::RenderStatistics& stats)
{
  // Boundary-cell culling (FluidCells.h): once per particle set and culling setting.
  const double cellSize = this->CellSize * this->GetLengthUnitSize();
  const bool rebuild = Impl->CellsStamp.Changed(this, nullptr, { this->BoundaryCulling, cellSize });
  if (rebuild)
  {
    raymappers::ScopedPhase phase(stats, "cells");
    raymappers::buildFluidCells(Impl->Particles, cellSize, this->BoundaryCulling, Impl->Cells);
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

raymappers::FluidRenderParameters vtkSPHFluidMapper::GatherParameters(vtkRenderer* ren,
  vtkVolume* vol,
  const vtkRayMapperView& view)
{
  raymappers::FluidRenderParameters params;
  params.voxelizer.angleResolutionDeg = this->AngleResolution;
  params.voxelizer.maxLayers = this->MaximumLayers;
  params.voxelizer.maxSpans = this->MaximumSpans;
  params.voxelizer.memoryBudget = static_cast<std::size_t>(this->MemoryBudget * 1024.0 * 1024.0);
  // Lengths in LengthUnit, absorption per LengthUnit.
  const double unit = this->GetLengthUnitSize();
  params.voxelizer.gapThreshold = this->GapThreshold * unit;
  params.voxelizer.cells = &Impl->Cells;
  params.smoothingRadius = this->SmoothingRadius * unit;
  params.smoothingIterations = this->SmoothingIterations;
  params.color = { this->Color[0], this->Color[1], this->Color[2] };
  if (!Impl->Colors.empty())
  {
    params.colors = &Impl->Colors;
    params.colorParticles = &Impl->Particles;
  }
  params.translucency = this->Translucency;
  params.absorptionColor = { this->AbsorptionColor[0], this->AbsorptionColor[1],
    this->AbsorptionColor[2] };
  params.density = this->Density / unit;
  params.refractiveIndex = this->RefractiveIndex;
  params.bounces = this->Bounces;
  params.ambientOcclusion = this->AmbientOcclusion;
  params.aoRadius = this->AmbientOcclusionRadius * unit;
  params.aoSamples = this->AmbientOcclusionSamples;
  if (vtkVolumeProperty* property = vol->GetProperty())
  {
    params.material = vtkRayMapperCore::GatherMaterial(property);
  }
  params.lights = vtkRayMapperRenderHelpers::GatherLights(ren);
  CopyModelTransform(view, params.modelToWorld, params.normalToWorld);
  return params;
}

void vtkSPHFluidMapper::WarnAboutMemoryBudget(const vtkRayMapperView& view,
  const raymappers::RenderStatistics& stats)
{
  // Once while the budget, the frame size and the layer limit stay the same.
  const std::tuple<double, int, int, int> key{ this->MemoryBudget, view.width, view.height,
    this->MaximumLayers };
  if (Impl->WarnedBudget != key)
  {
    Impl->WarnedBudget = key;
    vtkWarningMacro(<< raymappers::describeBudgetShortfall(stats)
                    << ": nothing drawn. Raise MemoryBudget or lower MaximumLayers.");
  }
}

void vtkSPHFluidMapper::ReleaseBuilds()
{
  Impl->Particles = raymappers::FluidParticles();
  Impl->Cells = raymappers::FluidCells();
  Impl->Colors = raymappers::FluidColors();
  Impl->Spans = raymappers::FluidSpans();
  Impl->Neighbourhoods = raymappers::SurfaceNeighbourhoods();
  Impl->ParticlesStamp.Invalidate();
  Impl->CellsStamp.Invalidate();
  Impl->ColorsStamp.Invalidate();
}

void vtkSPHFluidMapper::RenderVolume(vtkRenderer* ren, vtkVolume* vol, vtkPointSet* input)
{
  raymappers::RenderStatistics stats;
  vtkRayMapperView view;
  bool built = false;
  {
    raymappers::ScopedPhase phase(stats, "particles");
    built = this->UpdateParticles(input);
  }
  stats.addCounter("particles", static_cast<std::int64_t>(Impl->Particles.size()));
  stats.addCounter("particles_built", built ? 1 : 0);
  if (built)
  {
    this->Core->CountBuild();
  }
  this->Core->AddBuildCounters(stats);
  this->UpdateCells(stats);
  this->UpdateColors(input, stats);
  if (!this->Core->GatherView(this, ren, vol, view))
  {
    this->Core->Skip(stats);
    return;
  }
  const raymappers::FluidRenderParameters params = this->GatherParameters(ren, vol, view);
  // Interactive renders: rays d pixels apart, the image enlarged.
  const double d = this->Core->BeginFrame(ren, vtkRayMapperSampleDistances::Of(this), stats);
  stats.addCounter("subsampling", static_cast<std::int64_t>(std::ceil(d)));
  // Opaque geometry drawn before (all of it: volumes come after the opaque pass) ends the
  // fluid. An opaque fluid is depth tested when drawn, a translucent one must stop there.
  const raymappers::View kernelView =
    this->Core->KernelView(ren, view, d, Impl->Particles.origin, this->Translucency, stats);
  if (!vtkRayMapperCore::HasDepthRays(this, kernelView))
  {
    this->Core->Skip(stats);
    return;
  }
  if (!raymappers::renderFluid(
        { Impl->Particles, Impl->Spans, &Impl->Neighbourhoods }, kernelView, params, this->Core->Target(), stats))
  {
    this->WarnAboutMemoryBudget(view, stats);
  }
  const auto mode = this->Translucency ? vtkRayMapperFrameDrawer::Mode::BlendPremultiplied
                                       : vtkRayMapperFrameDrawer::Mode::OpaqueWithDepth;
  this->Core->Present(ren, view, mode, true, stats);
}

void vtkSPHFluidMapper::GetLastFrame(double frame[2])
{
  this->Core->GetLastFrame(frame);
}

void vtkSPHFluidMapper::SetLastFrame(const double frame[2])
{
  this->Core->SetLastFrame(frame);
}

void vtkSPHFluidMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "LengthUnit: " << (this->LengthUnit == WORLD ? "WORLD" : "PARTICLE_RADIUS")
     << "\n";
  os << indent << "AngleResolution: " << this->AngleResolution << "\n";
  os << indent << "MaximumLayers: " << this->MaximumLayers << "\n";
  os << indent << "MaximumSpans: " << this->MaximumSpans << "\n";
  os << indent << "MemoryBudget: " << this->MemoryBudget << "\n";
  os << indent << "GapThreshold: " << this->GapThreshold << "\n";
  os << indent << "BoundaryCulling: " << this->BoundaryCulling << "\n";
  os << indent << "CellSize: " << this->CellSize << "\n";
  vtkRayMapperSampleDistances::Of(this).Print(os, indent);
  os << indent << "SmoothingRadius: " << this->SmoothingRadius << "\n";
  os << indent << "SmoothingIterations: " << this->SmoothingIterations << "\n";
  os << indent << "Color: " << this->Color[0] << " " << this->Color[1] << " " << this->Color[2]
     << "\n";
  os << indent << "ScalarVisibility: " << this->ScalarVisibility << "\n";
  os << indent << "ColorArrayName: " << vtkRayMapperString(this->ColorArrayName) << "\n";
  os << indent << "LookupTable: " << Impl->LookupTable.Get() << "\n";
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
