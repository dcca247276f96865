#include "vtkSPHVoxelizer.h"

#include "Mappers/SPH/FluidParticles.h"
#include "Mappers/SPH/FluidSpans.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/SPH/SpanVoxelizer.h"
#include "Mappers/SPH/SurfaceLinks.h"
#include "Mappers/Common/RayCamera.h"
#include "Mappers/Common/View.h"

#include "vtkRayMapperCameraMatrix.h"
#include "vtkRayMapperPointArrays.h"
#include "vtkRayMapperScalarArray.h"
#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnsignedIntArray.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

vtkStandardNewMacro(vtkSPHVoxelizer);

namespace
{
template<typename ArrayT>
vtkSmartPointer<ArrayT> makeArray(const char* name, int components, vtkIdType tuples)
{
  auto a = vtkSmartPointer<ArrayT>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

void addField(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

// The particles of the input (centres relative to the centre of the finite points, radii
// from the radius array or the constant); `bounds` gets the finite points' bounds. One
// warning for each kind of particle left out.
raymappers::Vec3d ReadParticles(vtkSPHVoxelizer* self,
  vtkPointSet* input,
  raymappers::FluidParticles& particles,
  double bounds[6])
{
  vtkPoints* points = input ? input->GetPoints() : nullptr;
  const vtkIdType n = points ? points->GetNumberOfPoints() : 0;
  if (n == 0)
  {
    vtkWarningWithObjectMacro(self, << "The input has no points: the image has no spans.");
  }
  vtkDataArray* radii = n > 0 ? vtkRayMapperPointArrays::FindScaleArray(
                                  self, input, self->GetScaleArray(), "radius", self->GetRadius())
                              : nullptr;
  vtkRayMapperWarnIfComponentsDiffer(self, radii, "radius");
  vtkRayMapperPointArrays::FiniteBounds(input, bounds);
  if (!vtkMath::AreBoundsInitialized(bounds))
  {
    std::fill(bounds, bounds + 6, 0.0);
  }
  const raymappers::Vec3d origin(0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
    0.5 * (bounds[4] + bounds[5]));
  {
    // Read single-threaded (vtkDataArray access), then build.
    std::vector<raymappers::Vec3d> centers(static_cast<std::size_t>(n));
    std::vector<double> r(static_cast<std::size_t>(n));
    const double constant = radii || n == 0 ? 0.0 : self->GetRadiusInUse(input);
    for (vtkIdType i = 0; i < n; ++i)
    {
      double p[3];
      points->GetPoint(i, p);
      centers[i] = raymappers::Vec3d(p[0], p[1], p[2]);
      r[i] = (radii ? radii->GetComponent(i, 0) : constant) * self->GetScaleFactor();
    }
    raymappers::buildFluidParticles(
      static_cast<std::size_t>(n),
      origin,
      [&](std::size_t i) { return centers[i]; },
      [&](std::size_t i) { return r[i]; },
      particles);
  }
  if (particles.skippedNonFinite > 0)
  {
    vtkWarningWithObjectMacro(self,
      << particles.skippedNonFinite
      << " particles have NaN or infinite coordinates and are skipped.");
  }
  if (particles.skippedBadRadius > 0)
  {
    vtkWarningWithObjectMacro(self,
      << particles.skippedBadRadius
      << " particles have a zero, negative, non-finite or huge (above 1e15) radius and are "
         "skipped.");
  }
  return origin;
}

// The camera fitted to the particles' bounds grown by `grow` (when `reset`), its clipping
// range to their depth extent (when `clip`).
void FitCamera(vtkCamera* camera,
  double bounds[6],
  double grow,
  int W,
  int H,
  bool reset,
  bool clip)
{
  for (int a = 0; a < 3; ++a)
  {
    bounds[2 * a] -= grow;
    bounds[2 * a + 1] += grow;
  }
  const double center[3] = {
    0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5])
  };
  double radius = 0;
  for (int a = 0; a < 3; ++a)
  {
    radius += 0.25 * (bounds[2 * a + 1] - bounds[2 * a]) * (bounds[2 * a + 1] - bounds[2 * a]);
  }
  radius = std::sqrt(radius);
  if (!(radius > 0))
  {
    radius = 0.5;
  }
  if (reset)
  {
    double dop[3];
    camera->GetDirectionOfProjection(dop);
    const double angle = vtkMath::RadiansFromDegrees(camera->GetViewAngle());
    const double aspect = static_cast<double>(W) / H;
    // The bounding sphere fits the smaller of the two fields of view.
    const double half = aspect < 1 ? std::atan(std::tan(0.5 * angle) * aspect) : 0.5 * angle;
    const double distance = radius / std::sin(half);
    camera->SetFocalPoint(center);
    camera->SetPosition(
      center[0] - distance * dop[0], center[1] - distance * dop[1], center[2] - distance * dop[2]);
    camera->SetParallelScale(aspect < 1 ? radius / aspect : radius);
  }
  if (clip)
  {
    double dop[3], eye[3];
    camera->GetDirectionOfProjection(dop);
    camera->GetPosition(eye);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int c = 0; c < 8; ++c)
    {
      const double corner[3] = {
        bounds[c & 1], bounds[2 + ((c >> 1) & 1)], bounds[4 + ((c >> 2) & 1)]
      };
      const double d = (corner[0] - eye[0]) * dop[0] + (corner[1] - eye[1]) * dop[1] +
                       (corner[2] - eye[2]) * dop[2];
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    hi = hi + 0.01 * (hi - lo) + 1e-9;
    lo = std::max(lo - 0.01 * (hi - lo), 1e-3 * hi);
    camera->SetClippingRange(lo, hi);
  }
}

// Phases 1-5 of the voxelizer (Zirr & Dachsbacher): cells (boundary culling), layered
// voxelization into spans, surface connection, smoothing and normals.
void Voxelize(vtkSPHVoxelizer* self,
  const raymappers::FluidParticles& particles,
  const raymappers::ViewRays& rays,
  raymappers::FluidSpans& spans,
  raymappers::RenderStatistics& stats)
{
  raymappers::VoxelizerParameters vp;
  vp.angleResolutionDeg = self->GetAngleResolution();
  vp.maxLayers = self->GetMaximumLayers();
  vp.maxSpans = self->GetMaximumSpans();
  vp.memoryBudget = static_cast<std::size_t>(self->GetMemoryBudget() * 1024.0 * 1024.0);
  // Lengths in LengthUnit: the particles' mean radius, or the input's unit.
  const double unit =
    self->GetLengthUnit() == vtkSPHVoxelizer::PARTICLE_RADIUS && particles.meanRadius > 0.0
    ? particles.meanRadius
    : 1.0;
  vp.gapThreshold = self->GetGapThreshold() * unit;
  raymappers::FluidCells cells;
  {
    raymappers::ScopedPhase phase(stats, "cells");
    raymappers::buildFluidCells(
      particles, self->GetCellSize() * unit, self->GetBoundaryCulling(), cells);
  }
  stats.addCounter("culled_particles", static_cast<std::int64_t>(cells.culledParticles));
  vp.cells = &cells;
  if (!raymappers::voxelizeFluid(particles, rays, vp, spans, stats))
  {
    vtkWarningWithObjectMacro(self, << raymappers::describeBudgetShortfall(stats) << ": no spans.");
  }
  raymappers::connectSurfaces(spans, stats);
  raymappers::SurfaceNeighbourhoods neighbourhoods;
  raymappers::findNeighbourhoods(spans, neighbourhoods, stats);
  raymappers::smoothSurfaces(
    spans, neighbourhoods, rays, self->GetSmoothingRadius() * unit, self->GetSmoothingIterations(), stats);
  raymappers::computeNormals(spans, neighbourhoods, rays, stats);
}

// The spans as point arrays of the image (one tuple per pixel, NaN in unused slots).
void WriteSpanArrays(vtkImageData* output,
  const raymappers::FluidSpans& spans,
  const raymappers::ViewRays& rays,
  bool ok,
  int W,
  int H)
{
  const int S = spans.maxSpans;
  const vtkIdType pixels = static_cast<vtkIdType>(W) * H;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  auto count = makeArray<vtkUnsignedCharArray>("SpanCount", 1, pixels);
  auto found = makeArray<vtkUnsignedIntArray>("SpansFound", 1, pixels);
  auto entry = makeArray<vtkFloatArray>("EntryDepth", S, pixels);
  auto exit = makeArray<vtkFloatArray>("ExitDepth", S, pixels);
  auto hidden = makeArray<vtkFloatArray>("HiddenEmpty", 1, pixels);
  auto thickness = makeArray<vtkFloatArray>("Thickness", 1, pixels);
  auto toDistance = makeArray<vtkFloatArray>("DepthToDistance", 1, pixels);
  auto entryNormal = makeArray<vtkFloatArray>("EntryNormal", 3 * S, pixels);
  auto exitNormal = makeArray<vtkFloatArray>("ExitNormal", 3 * S, pixels);
  auto links = makeArray<vtkUnsignedIntArray>("Links", 2 * S, pixels);
  const bool haveLinks = spans.links.size() == spans.depth.size();
  const bool haveNormals = spans.normals.size() == spans.depth.size();
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const std::size_t p = static_cast<std::size_t>(j) * W + i;
      const int c = spans.count.empty() ? 0 : spans.count[p];
      const double B = ok ? raymappers::length(rays.direction(i + 0.5, j + 0.5)) : 1.0;
      count->SetValue(p, static_cast<unsigned char>(c));
      found->SetValue(p, spans.found.empty() ? 0u : spans.found[p]);
      hidden->SetValue(p, spans.hiddenEmpty.empty() ? 0.f : spans.hiddenEmpty[p]);
      thickness->SetValue(p, c > 0 ? static_cast<float>(spans.thickness(p) * B) : 0.f);
      toDistance->SetValue(p, static_cast<float>(B));
      for (int k = 0; k < S; ++k)
      {
        const bool used = k < c;
        entry->SetTypedComponent(p, k, used ? spans.entry(p, k) : nan);
        exit->SetTypedComponent(p, k, used ? spans.exit(p, k) : nan);
        for (int e = 0; e < 2; ++e)
        {
          const std::size_t slot = spans.slot(p, 2 * k + e);
          raymappers::Vec3f nrm(nan, nan, nan);
          if (used && haveNormals)
          {
            nrm = raymappers::decodeNormal(spans.normals[slot]);
          }
          vtkFloatArray* target = e == 0 ? entryNormal : exitNormal;
          target->SetTypedComponent(p, 3 * k, nrm.x);
          target->SetTypedComponent(p, 3 * k + 1, nrm.y);
          target->SetTypedComponent(p, 3 * k + 2, nrm.z);
          links->SetTypedComponent(p, 2 * k + e, used && haveLinks ? spans.links[slot] : 0u);
        }
      }
    }
  }
  vtkPointData* pd = output->GetPointData();
  pd->Initialize();
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(count),
         static_cast<vtkDataArray*>(found),
         static_cast<vtkDataArray*>(entry),
         static_cast<vtkDataArray*>(exit),
         static_cast<vtkDataArray*>(hidden),
         static_cast<vtkDataArray*>(toDistance),
         static_cast<vtkDataArray*>(entryNormal),
         static_cast<vtkDataArray*>(exitNormal),
         static_cast<vtkDataArray*>(links) })
  {
    pd->AddArray(a);
  }
  pd->SetScalars(thickness);
}

// The projection and the layering as field data of the image.
void WriteFieldData(vtkImageData* output,
  const raymappers::FluidSpans& spans,
  const raymappers::ViewRays& rays,
  bool ok,
  const std::array<double, 16>& modelToClip)
{
  vtkFieldData* fd = output->GetFieldData();
  fd->Initialize();
  vtkNew<vtkDoubleArray> matrix;
  matrix->SetName("ModelToClip");
  for (double v : modelToClip)
  {
    matrix->InsertNextValue(v);
  }
  fd->AddArray(matrix);
  addField(fd, "LayerCount", spans.layers.count);
  addField(fd, "FirstLayerDepth", spans.layers.depths.empty() ? 0.0 : spans.layers.depths.front());
  addField(fd, "LastLayerDepth", spans.layers.depths.empty() ? 0.0 : spans.layers.depths.back());
  addField(fd, "LogarithmicLayers", spans.layers.logarithmic ? 1 : 0);
  addField(fd,
    "AngleResolutionReached",
    ok && spans.layers.count > 0 ? spans.layers.angleDeg(rays.pixelSize()) : 0.0);
  addField(fd, "MaximumSpans", spans.maxSpans);
}
}

vtkSPHVoxelizer::vtkSPHVoxelizer()
  : Camera(vtkSmartPointer<vtkCamera>::New())
{
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
}

vtkSPHVoxelizer::~vtkSPHVoxelizer()
{
  this->SetScaleArray(nullptr);
}

void vtkSPHVoxelizer::SetCamera(vtkCamera* camera)
{
  if (camera == this->Camera && this->CameraGiven)
  {
    return;
  }
  this->CameraGiven = camera != nullptr;
  this->Camera = camera ? camera : vtkSmartPointer<vtkCamera>::New().GetPointer();
  this->Modified();
}

vtkCamera* vtkSPHVoxelizer::GetCamera()
{
  return this->Camera;
}

// The camera settings are checked as the filter's own properties (vtkRayMapperSetGet.h):
// vtkCamera takes a NaN position, focal point, view up or view angle as it is.
void vtkSPHVoxelizer::SetCameraPosition(double x, double y, double z)
{
  double p[3] = { x, y, z };
  if (vtkRayMapperSetGet::AcceptVector(
        this, "CameraPosition", p, -VTK_RAYMAPPER_LENGTH_MAX, VTK_RAYMAPPER_LENGTH_MAX))
  {
    this->Camera->SetPosition(p);
  }
}

void vtkSPHVoxelizer::SetCameraFocalPoint(double x, double y, double z)
{
  double p[3] = { x, y, z };
  if (vtkRayMapperSetGet::AcceptVector(
        this, "CameraFocalPoint", p, -VTK_RAYMAPPER_LENGTH_MAX, VTK_RAYMAPPER_LENGTH_MAX))
  {
    this->Camera->SetFocalPoint(p);
  }
}

void vtkSPHVoxelizer::SetCameraViewUp(double x, double y, double z)
{
  double p[3] = { x, y, z };
  if (vtkRayMapperSetGet::AcceptVector(
        this, "CameraViewUp", p, -VTK_RAYMAPPER_LENGTH_MAX, VTK_RAYMAPPER_LENGTH_MAX))
  {
    this->Camera->SetViewUp(p);
  }
}

void vtkSPHVoxelizer::SetCameraViewAngle(double degrees)
{
  // vtkCamera's own range (it clamps silently, and lets NaN through).
  if (vtkRayMapperSetGet::Accept(
        this, "CameraViewAngle", degrees, 1e-8, 179.0, this->Camera->GetViewAngle()))
  {
    this->Camera->SetViewAngle(degrees);
  }
}

void vtkSPHVoxelizer::SetCameraParallelProjection(bool parallel)
{
  this->Camera->SetParallelProjection(parallel ? 1 : 0);
}

void vtkSPHVoxelizer::SetCameraParallelScale(double scale)
{
  if (vtkRayMapperSetGet::Accept(this, "CameraParallelScale", scale, 0.0,
        VTK_RAYMAPPER_LENGTH_MAX, this->Camera->GetParallelScale()))
  {
    this->Camera->SetParallelScale(scale);
  }
}

const char* vtkSPHVoxelizer::GetStatisticsSummary()
{
  return this->Summary.c_str();
}

vtkMTimeType vtkSPHVoxelizer::GetMTime()
{
  return std::max(this->Superclass::GetMTime(), this->Camera->GetMTime());
}

int vtkSPHVoxelizer::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

int vtkSPHVoxelizer::RequestInformation(vtkInformation*, vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int extent[6] = { 0, std::max(1, this->ImageSize[0]) - 1, 0,
    std::max(1, this->ImageSize[1]) - 1, 0, 0 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  const double spacing[3] = { 1, 1, 1 }, origin[3] = { 0, 0, 0 };
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  return 1;
}

int vtkSPHVoxelizer::RequestUpdateExtent(vtkInformation*, vtkInformationVector** inputVector,
  vtkInformationVector*)
{
  // The whole input: every particle can reach any pixel.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  return 1;
}

int vtkSPHVoxelizer::RequestData(vtkInformation*, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkPointSet* input = vtkPointSet::GetData(inputVector[0], 0);
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  const int W = std::max(1, this->ImageSize[0]), H = std::max(1, this->ImageSize[1]);
  output->SetExtent(0, W - 1, 0, H - 1, 0, 0);
  output->SetSpacing(1, 1, 1);
  output->SetOrigin(0, 0, 0);
  raymappers::RenderStatistics stats;

  try
  {
    raymappers::FluidParticles particles;
    double bounds[6] = { 0, 0, 0, 0, 0, 0 };
    const raymappers::Vec3d origin = ReadParticles(this, input, particles, bounds);
    stats.addCounter("particles", static_cast<std::int64_t>(particles.size()));

    // The camera: a copy, fitted to the particles' bounds grown by the largest radius.
    vtkNew<vtkCamera> camera;
    camera->DeepCopy(this->Camera);
    FitCamera(camera,
      bounds,
      particles.maxRadius,
      W,
      H,
      this->ResetCamera,
      this->ResetCamera || !this->CameraGiven);
    const std::array<double, 16> modelToClip =
      vtkRayMapperWorldToClip(camera, static_cast<double>(W) / H);
    const raymappers::View view(modelToClip, W, H, origin);
    const raymappers::ViewRays& rays = view.depthRays();
    raymappers::FluidSpans spans;
    const std::string degenerate = raymappers::degenerateProjection(modelToClip);
    bool ok = degenerate.empty() && view.hasDepthRays();
    if (!ok)
    {
      vtkWarningMacro(<< "The camera is degenerate: "
                      << (degenerate.empty() ? std::string("its rays cannot be formed") : degenerate)
                      << "; no spans.");
      spans.reset(W, H, this->MaximumSpans);
    }
    else
    {
      Voxelize(this, particles, rays, spans, stats);
    }
    this->Summary = stats.summary();

    WriteSpanArrays(output, spans, rays, ok, W, H);
    WriteFieldData(output, spans, rays, ok, modelToClip);
  }
  catch (const std::bad_alloc&)
  {
    // (The voxelizer's own tiles stay within MemoryBudget; this is the particles, the
    // surfaces or the output arrays.)
    output->Initialize();
    vtkErrorMacro(<< "Out of memory voxelizing " << input->GetNumberOfPoints()
                  << " points into " << W << " x " << H << " pixels: the output is empty.");
  }
  return 1;
}

double vtkSPHVoxelizer::GetRadiusInUse(vtkPointSet* input)
{
  return this->Radius > 0.0 ? this->Radius
                            : vtkRayMapperParticleSizes::AutomaticLength(input,
                                vtkRayMapperParticleSizes::FluidRadiusPerSpacing, this->Spacing);
}

void vtkSPHVoxelizer::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "ScaleArray: " << (this->ScaleArray ? this->ScaleArray : "")
     << "\n";
  os << indent << "ScaleFactor: " << this->ScaleFactor << "\n";
  os << indent << "AngleResolution: " << this->AngleResolution << "\n";
  os << indent << "MaximumLayers: " << this->MaximumLayers << "\n";
  os << indent << "MaximumSpans: " << this->MaximumSpans << "\n";
  os << indent << "MemoryBudget: " << this->MemoryBudget << "\n";
  os << indent << "LengthUnit: " << (this->LengthUnit == WORLD ? "WORLD" : "PARTICLE_RADIUS")
     << "\n";
  os << indent << "GapThreshold: " << this->GapThreshold << "\n";
  os << indent << "BoundaryCulling: " << this->BoundaryCulling << "\n";
  os << indent << "CellSize: " << this->CellSize << "\n";
  os << indent << "SmoothingRadius: " << this->SmoothingRadius << "\n";
  os << indent << "SmoothingIterations: " << this->SmoothingIterations << "\n";
  os << indent << "ImageSize: " << this->ImageSize[0] << " " << this->ImageSize[1] << "\n";
  os << indent << "ResetCamera: " << this->ResetCamera << "\n";
  os << indent << "Camera: " << this->Camera.Get() << "\n";
}
