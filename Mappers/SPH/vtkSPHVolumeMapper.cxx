#include "vtkSPHVolumeMapper.h"

#include "Frame.h"
#include "FrameResample.h"
#include "PerspectiveGrid.h"
#include "RenderStatistics.h"
#include "SPHParticles.h"
#include "SPHVolumeRenderer.h"
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

vtkStandardNewMacro(vtkSPHVolumeMapper);

struct vtkSPHVolumeMapper::Internals
{
  raymappers::SPHParticles Particles;
  raymappers::PerspectiveGrid Grid;
  raymappers::Frame Frame, Coarse;
  vtkRayMapperFrameDrawer Drawer;
  vtkRayMapperRenderHelpers::CameraCheck Camera;
  vtkNew<vtkRayMapperStatistics> Statistics;
  std::string BuiltKey; // what the particles were built from
  vtkMTimeType BuiltInputTime = 0;
  bool HasParticles = false;
  double Reduction = 1.0;        // r of equation 3.1
  double LastFrameSeconds = 0.0; // of the last render
  vtkMTimeType WarnedEmptyInputTime = 0;
};

namespace
{
std::string str(const char* s)
{
  return s ? s : "";
}
}

vtkSPHVolumeMapper::vtkSPHVolumeMapper()
  : Impl(new Internals)
{
}

vtkSPHVolumeMapper::~vtkSPHVolumeMapper()
{
  this->SetSmoothingLengthArrayName(nullptr);
  this->SetValueArrayName(nullptr);
  this->SetVolumeArrayName(nullptr);
  this->SetMassArrayName(nullptr);
  this->SetDensityArrayName(nullptr);
}

void vtkSPHVolumeMapper::SetInputData(vtkPointSet* input)
{
  this->SetInputDataInternal(0, input);
}

int vtkSPHVolumeMapper::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

vtkRayMapperStatistics* vtkSPHVolumeMapper::GetStatistics()
{
  return Impl->Statistics;
}

void vtkSPHVolumeMapper::ReleaseGraphicsResources(vtkWindow* win)
{
  Impl->Drawer.ReleaseGraphicsResources(win);
  this->Superclass::ReleaseGraphicsResources(win);
}

double* vtkSPHVolumeMapper::GetBounds()
{
  // The points' bounds grown by the largest support, so a camera reset frames the field.
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
      vtkWarningMacro(<< "The input has no points: no volume to draw.");
    }
    return this->Bounds;
  }
  vtkRayMapperRenderHelpers::FiniteBounds(input, this->Bounds);
  if (!vtkMath::AreBoundsInitialized(this->Bounds))
  {
    return this->Bounds; // no finite point
  }
  std::string why;
  vtkDataArray* h = vtkRayMapperRenderHelpers::FindPointArray(
    input, this->SmoothingLengthArrayName, "smoothing length", why);
  const double factor = this->SupportFactor > 0
    ? this->SupportFactor
    : raymappers::kernelSupportPerSmoothingLength(static_cast<raymappers::SPHKernel>(this->Kernel));
  // The largest support H = factor * scale * h the particles may have.
  const double grow = h
    ? vtkRayMapperRenderHelpers::LargestParticleLength(h, factor * this->SmoothingLengthScale)
    : factor * this->SmoothingLength * this->SmoothingLengthScale;
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

void vtkSPHVolumeMapper::UpdateParticles(vtkPointSet* input)
{
  const double factor = this->SupportFactor > 0
    ? this->SupportFactor
    : raymappers::kernelSupportPerSmoothingLength(static_cast<raymappers::SPHKernel>(this->Kernel));
  vtkDataArray* activeScalars = input->GetPointData()->GetScalars();
  std::ostringstream key;
  key << factor << '|' << this->SmoothingLength << '|' << this->SmoothingLengthScale << '|'
      << str(this->SmoothingLengthArrayName) << '|' << str(this->ValueArrayName) << '|'
      << (activeScalars && activeScalars->GetName() ? activeScalars->GetName() : "") << '|'
      << str(this->VolumeArrayName) << '|' << str(this->MassArrayName) << '|'
      << str(this->DensityArrayName) << '|' << this->Volume;
  if (Impl->HasParticles && Impl->BuiltInputTime == input->GetMTime() && Impl->BuiltKey == key.str())
  {
    return;
  }
  std::string why;
  vtkDataArray* h = vtkRayMapperRenderHelpers::FindPointArray(
    input, this->SmoothingLengthArrayName, "smoothing length", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << "; using the constant smoothing length " << this->SmoothingLength << ".");
    why.clear();
  }
  vtkDataArray* values = vtkRayMapperRenderHelpers::FindPointArray(input, this->ValueArrayName, "value", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << "; showing the active point scalars.");
    why.clear();
  }
  if (!values)
  {
    values = activeScalars;
  }
  vtkDataArray* volumes = vtkRayMapperRenderHelpers::FindPointArray(input, this->VolumeArrayName, "volume", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << ".");
    why.clear();
  }
  vtkDataArray* masses = nullptr;
  vtkDataArray* densities = nullptr;
  if (!volumes)
  {
    masses = vtkRayMapperRenderHelpers::FindPointArray(input, this->MassArrayName, "mass", why);
    densities = vtkRayMapperRenderHelpers::FindPointArray(input, this->DensityArrayName, "density", why);
    if (!why.empty() || (!masses != !densities))
    {
      vtkWarningMacro(<< (why.empty() ? std::string("mass and density arrays go together") : why)
                      << "; using the constant volume " << this->Volume << ".");
      masses = densities = nullptr;
    }
  }
  vtkRayMapperWarnIfComponentsDiffer(this, h, "smoothing length");
  vtkRayMapperWarnIfComponentsDiffer(this, values, "value");
  vtkRayMapperWarnIfComponentsDiffer(this, volumes, "volume");
  vtkRayMapperWarnIfComponentsDiffer(this, masses, "mass");
  vtkRayMapperWarnIfComponentsDiffer(this, densities, "density");

  const vtkRayMapperRenderHelpers::TupleReader pointReader(input->GetPoints()->GetData());
  const vtkRayMapperRenderHelpers::TupleReader hReader(h), valueReader(values),
    volumeReader(volumes), massReader(masses), densityReader(densities);
  const double hScale = this->SmoothingLengthScale * factor;
  const double hConstant = this->SmoothingLength * hScale, vConstant = this->Volume;
  const auto n = static_cast<std::size_t>(input->GetNumberOfPoints());
  raymappers::buildSPHParticles(
    n,
    vtkRayMapperRenderHelpers::FiniteCenter(input->GetPoints()),
    [&](std::size_t i) {
      return raymappers::Vec3d(pointReader.get(i, 0), pointReader.get(i, 1), pointReader.get(i, 2));
    },
    [&](std::size_t i) { return h ? hReader.get(i, 0) * hScale : hConstant; },
    [&](std::size_t i) { return values ? valueReader.get(i, 0) : 1.0; },
    [&](std::size_t i)
    {
      if (volumes)
      {
        return volumeReader.get(i, 0);
      }
      // V = m / rho; a zero density gives an infinite volume, skipped as non-finite.
      return masses ? massReader.get(i, 0) / densityReader.get(i, 0) : vConstant;
    },
    Impl->Particles);
  if (Impl->Particles.skippedNonFinite > 0)
  {
    vtkWarningMacro(<< Impl->Particles.skippedNonFinite
                    << " particles have NaN or infinite coordinates, quantities or volumes and are not drawn.");
  }
  if (Impl->Particles.skippedBadSupport > 0)
  {
    vtkWarningMacro(<< Impl->Particles.skippedBadSupport
                    << " particles have a zero, negative, non-finite or huge (above 1e15) smoothing length and are not drawn.");
  }
  if (Impl->Particles.skippedBadVolume > 0)
  {
    vtkWarningMacro(<< Impl->Particles.skippedBadVolume
                    << " particles have a negative volume and are not drawn.");
  }
  Impl->HasParticles = true;
  Impl->BuiltInputTime = input->GetMTime();
  Impl->BuiltKey = key.str();
}

void vtkSPHVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  raymappers::RenderStatistics stats;
  auto* input = vtkPointSet::SafeDownCast(this->GetDataSetInput());
  if (!input || input->GetNumberOfPoints() == 0 || !input->GetPoints())
  {
    Impl->Statistics->Set(stats);
    return;
  }
  const double start = vtkTimerLog::GetUniversalTime();
  {
    raymappers::ScopedPhase phase(stats, "particles");
    this->UpdateParticles(input);
  }
  stats.addCounter("particles", static_cast<std::int64_t>(Impl->Particles.size()));
  const auto kernel = static_cast<raymappers::SPHKernel>(this->Kernel);

  // Parameters, classification, lights.
  vtkVolumeProperty* property = vol->GetProperty();
  const raymappers::TransferFunctionTable table =
    vtkRayMapperRenderHelpers::SampleVolumeProperty(property, 0, 1024);
  raymappers::SPHRenderParameters params;
  params.kernel = kernel;
  params.normalization = static_cast<raymappers::SPHNormalization>(this->Normalization);
  params.referenceWeightSum = this->ReferenceWeightSum > 0
    ? this->ReferenceWeightSum
    : raymappers::referenceWeightSum(kernel, Impl->Particles.medianVolume, Impl->Particles.medianSupport);
  if (!(params.referenceWeightSum > 0) || !std::isfinite(params.referenceWeightSum))
  {
    params.referenceWeightSum = 1.0;
  }
  params.tileSize = this->TileSize;
  params.slabDepth = this->SlabDepth;
  params.terminationOpacity = this->TerminationOpacity;
  params.jitter = this->Jitter;
  params.contour = this->ContourShading;
  params.region = vtkRayMapperRenderHelpers::RegionFromBounds(this->RegionBounds);
  std::copy(this->ContourColor, this->ContourColor + 3, params.contourColor);
  params.contourOpacity = this->ContourOpacity;
  const auto model = vtkRayMapperRenderHelpers::GatherModelTransform(vol);
  std::copy(model.modelToWorld, model.modelToWorld + 16, params.modelToWorld);
  std::copy(model.normalToWorld, model.normalToWorld + 9, params.normalToWorld);
  params.shade = property->GetShade() != 0;
  if (params.shade)
  {
    params.lights = vtkRayMapperRenderHelpers::GatherLights(ren);
    params.material.ambient = property->GetAmbient();
    params.material.diffuse = property->GetDiffuse();
    params.material.specular = property->GetSpecular();
    params.material.specularPower = property->GetSpecularPower();
  }

  // Sampling-rate reduction while the user interacts (equation 3.1).
  const double rate = ren->GetRenderWindow() ? ren->GetRenderWindow()->GetDesiredUpdateRate() : 0;
  const double budget = this->FrameBudget > 0 ? this->FrameBudget : (rate > 0 ? 1.0 / rate : 0);
  if (rate >= 1.0 && this->MaximumReduction > 1.0)
  {
    if (budget > 0 && Impl->LastFrameSeconds > budget)
    {
      Impl->Reduction = std::min(Impl->Reduction + 0.25, this->MaximumReduction);
    }
  }
  else
  {
    Impl->Reduction = 1.0;
  }
  const double r = Impl->Reduction;
  params.stepFactor = this->StepFactor * r;
  params.samplesPerSupport = this->SamplesPerSupport / r;
  stats.addCounter("reduction_percent", static_cast<std::int64_t>(std::lround(100 * r)));

  int width = 0, height = 0;
  const std::array<double, 16> modelToClip =
    vtkRayMapperRenderHelpers::GatherModelToClip(ren, model, width, height);
  if (!Impl->Camera.Usable(this, modelToClip))
  {
    Impl->Statistics->Set(stats);
    return;
  }
  std::vector<float> depth;
  int dw = 0, dh = 0;
  const bool haveDepth =
    vtkRayMapperRenderHelpers::ReadOpaqueDepth(ren, depth, dw, dh) && dw == width && dh == height;
  stats.setEffect("opaque_depth", haveDepth);
  const int rw = r > 1.0 ? std::max(1, static_cast<int>(std::ceil(width / r))) : width;
  const int rh = r > 1.0 ? std::max(1, static_cast<int>(std::ceil(height / r))) : height;
  raymappers::ViewRays rays;
  if (width <= 0 || height <= 0 || !rays.assign(modelToClip, rw, rh, Impl->Particles.origin))
  {
    vtkErrorMacro(<< "The camera's projection is degenerate: nothing drawn.");
    Impl->Statistics->Set(stats);
    return;
  }
  if (rw == width && rh == height)
  {
    raymappers::renderSPH(Impl->Particles, rays, params, table, haveDepth ? depth.data() : nullptr,
      Impl->Grid, Impl->Frame, stats);
  }
  else
  {
    const std::vector<float> coarseDepth =
      haveDepth ? raymappers::sampleDepth(depth, width, height, rw, rh) : std::vector<float>();
    raymappers::renderSPH(Impl->Particles, rays, params, table,
      haveDepth ? coarseDepth.data() : nullptr, Impl->Grid, Impl->Coarse, stats);
    Impl->Frame.resize(width, height);
    raymappers::enlarge(Impl->Coarse, Impl->Frame);
  }
  {
    raymappers::ScopedPhase phase(stats, "draw");
    Impl->Drawer.Draw(ren, Impl->Frame, vtkRayMapperFrameDrawer::Mode::BlendPremultiplied,
      Impl->Statistics->GetValidateFrames(), stats);
  }
  Impl->LastFrameSeconds = vtkTimerLog::GetUniversalTime() - start;
  Impl->Statistics->Set(stats);
}

void vtkSPHVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Kernel: " << this->Kernel << "\n";
  os << indent << "SupportFactor: " << this->SupportFactor << "\n";
  os << indent << "SmoothingLength: " << this->SmoothingLength << "\n";
  os << indent << "SmoothingLengthArrayName: " << str(this->SmoothingLengthArrayName) << "\n";
  os << indent << "SmoothingLengthScale: " << this->SmoothingLengthScale << "\n";
  os << indent << "ValueArrayName: " << str(this->ValueArrayName) << "\n";
  os << indent << "VolumeArrayName: " << str(this->VolumeArrayName) << "\n";
  os << indent << "MassArrayName: " << str(this->MassArrayName) << "\n";
  os << indent << "DensityArrayName: " << str(this->DensityArrayName) << "\n";
  os << indent << "Volume: " << this->Volume << "\n";
  os << indent << "Normalization: " << this->Normalization << "\n";
  os << indent << "ReferenceWeightSum: " << this->ReferenceWeightSum << "\n";
  os << indent << "RegionBounds: (" << this->RegionBounds[0] << ", " << this->RegionBounds[1]
     << ", " << this->RegionBounds[2] << ", " << this->RegionBounds[3] << ", "
     << this->RegionBounds[4] << ", " << this->RegionBounds[5] << ")\n";
  os << indent << "ContourShading: " << this->ContourShading << "\n";
  os << indent << "ContourColor: " << this->ContourColor[0] << " " << this->ContourColor[1] << " "
     << this->ContourColor[2] << "\n";
  os << indent << "ContourOpacity: " << this->ContourOpacity << "\n";
  os << indent << "StepFactor: " << this->StepFactor << "\n";
  os << indent << "SamplesPerSupport: " << this->SamplesPerSupport << "\n";
  os << indent << "TileSize: " << this->TileSize << "\n";
  os << indent << "SlabDepth: " << this->SlabDepth << "\n";
  os << indent << "TerminationOpacity: " << this->TerminationOpacity << "\n";
  os << indent << "Jitter: " << this->Jitter << "\n";
  os << indent << "MaximumReduction: " << this->MaximumReduction << "\n";
  os << indent << "FrameBudget: " << this->FrameBudget << "\n";
}
