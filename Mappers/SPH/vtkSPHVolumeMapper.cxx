#include "vtkSPHVolumeMapper.h"
#include "vtkRayMapperPointArrays.h"

#include "Mappers/Common/Frame.h"
#include "Mappers/SPH/PerspectiveGrid.h"
#include "Mappers/Common/RenderStatistics.h"
#include "Mappers/SPH/SPHParticles.h"
#include "Mappers/SPH/SPHVolumeRenderer.h"
#include "Mappers/Common/ViewRays.h"
#include "vtkRayMapperCore.h"
#include "vtkRayMapperRenderHelpers.h"
#include "vtkRayMapperScalarArray.h"

#include "vtkDataArray.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <string>

vtkStandardNewMacro(vtkSPHVolumeMapper);

struct vtkSPHVolumeMapper::Internals
{
  raymappers::SPHParticles Particles;
  raymappers::PerspectiveGrid Grid;
  // The particles are built from the points, the support factor, the smoothing length and
  // its scale, the arrays (and the active scalars' name when no value array is set) and the
  // constant volume, and the float origin when one is given.
  vtkRayMapperStamp<double, double, double, std::string, std::string, std::string, std::string,
    std::string, std::string, double, bool, double, double, double>
    ParticlesStamp;
};

vtkSPHVolumeMapper::vtkSPHVolumeMapper()
  : Superclass("volume")
  , Impl(new Internals)
{
}

vtkSPHVolumeMapper::~vtkSPHVolumeMapper()
{
  this->SetValueArrayName(nullptr);
  this->SetVolumeArrayName(nullptr);
  this->SetMassArrayName(nullptr);
  this->SetDensityArrayName(nullptr);
}

double vtkSPHVolumeMapper::GetSupportPerSmoothingLength()
{
  return this->SupportFactor > 0
    ? this->SupportFactor
    : raymappers::kernelSupportPerSmoothingLength(static_cast<raymappers::SPHKernel>(this->Kernel));
}

double vtkSPHVolumeMapper::GetSupportRadius(vtkPointSet* input)
{
  // The largest support H = factor * scale * h the particles may have.
  std::string why;
  vtkDataArray* h =
    vtkRayMapperPointArrays::FindPointArray(input, this->ScaleArray, "smoothing length", why);
  const double factor = this->GetSupportPerSmoothingLength();
  return h ? vtkRayMapperPointArrays::LargestParticleLength(h, factor * this->ScaleFactor)
           : factor * this->GetSmoothingLengthInUse() * this->ScaleFactor;
}

double vtkSPHVolumeMapper::GetSmoothingLengthInUse()
{
  return this->SizeInUse(
    this->SmoothingLength, GetAutomaticSupportPerSpacing() / this->GetSupportPerSmoothingLength());
}

double vtkSPHVolumeMapper::GetParticlesSmallestSupport(vtkPointSet* input)
{
  if (!input || input->GetNumberOfPoints() == 0 || !input->GetPoints())
  {
    return 0.0;
  }
  this->UpdateParticles(input);
  return Impl->Particles.minSupport;
}

void vtkSPHVolumeMapper::UpdateParticles(vtkPointSet* input)
{
  const double factor = this->GetSupportPerSmoothingLength();
  vtkDataArray* activeScalars = input->GetPointData()->GetScalars();
  if (!Impl->ParticlesStamp.Changed(this, input,
        { factor, this->SmoothingLength, this->ScaleFactor,
          vtkRayMapperString(this->ScaleArray),
          vtkRayMapperString(this->ValueArrayName),
          vtkRayMapperString(activeScalars ? activeScalars->GetName() : nullptr),
          vtkRayMapperString(this->VolumeArrayName), vtkRayMapperString(this->MassArrayName),
          vtkRayMapperString(this->DensityArrayName), this->Volume, this->UseFloatOrigin,
          this->FloatOrigin[0], this->FloatOrigin[1], this->FloatOrigin[2] }))
  {
    return;
  }
  vtkDataArray* h = vtkRayMapperPointArrays::FindScaleArray(
    this, input, this->ScaleArray, "smoothing length", this->SmoothingLength);
  std::string why;
  vtkDataArray* values = vtkRayMapperPointArrays::FindPointArray(input, this->ValueArrayName, "value", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << "; showing the active point scalars.");
    why.clear();
  }
  if (!values)
  {
    values = activeScalars;
  }
  vtkDataArray* volumes = vtkRayMapperPointArrays::FindPointArray(input, this->VolumeArrayName, "volume", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << ".");
    why.clear();
  }
  vtkDataArray* masses = nullptr;
  vtkDataArray* densities = nullptr;
  if (!volumes)
  {
    masses = vtkRayMapperPointArrays::FindPointArray(input, this->MassArrayName, "mass", why);
    densities = vtkRayMapperPointArrays::FindPointArray(input, this->DensityArrayName, "density", why);
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

  const vtkRayMapperPointArrays::TupleReader pointReader(input->GetPoints()->GetData());
  const vtkRayMapperPointArrays::TupleReader hReader(h), valueReader(values),
    volumeReader(volumes), massReader(masses), densityReader(densities);
  const double hScale = this->ScaleFactor * factor;
  const double hConstant = h ? 0.0 : this->GetSmoothingLengthInUse() * hScale;
  const double vConstant = this->Volume;
  const auto n = static_cast<std::size_t>(input->GetNumberOfPoints());
  raymappers::buildSPHParticles(
    n,
    this->UseFloatOrigin
      ? raymappers::Vec3d(this->FloatOrigin[0], this->FloatOrigin[1], this->FloatOrigin[2])
      : raymappers::Vec3d(vtkRayMapperPointArrays::FiniteCenter(input->GetPoints())),
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
  this->Core->CountBuild();
  this->WarnSkipped(Impl->Particles.skippedNonFinite,
    "particles have NaN or infinite coordinates, quantities or volumes");
  this->WarnSkipped(Impl->Particles.skippedBadSupport,
    "particles have a zero, negative, non-finite or huge (above 1e15) smoothing length");
  this->WarnSkipped(Impl->Particles.skippedBadVolume, "particles have a negative volume");
}

raymappers::SPHRenderParameters vtkSPHVolumeMapper::GatherParameters(vtkRenderer* ren,
  vtkVolume* vol,
  const vtkRayMapperView& view)
{
  const auto kernel = static_cast<raymappers::SPHKernel>(this->Kernel);
  raymappers::SPHRenderParameters params;
  params.kernel = kernel;
  params.normalization = static_cast<raymappers::SPHNormalization>(this->Normalization);
  // w_max of equation 3.16: given, or that of the median particle.
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
  CopyModelTransform(view, params.modelToWorld, params.normalToWorld);
  params.shade = GatherShading(ren, vol->GetProperty(), params.lights, params.material);
  return params;
}

void vtkSPHVolumeMapper::ReleaseBuilds()
{
  Impl->Particles = raymappers::SPHParticles();
  Impl->Grid = raymappers::PerspectiveGrid();
  Impl->ParticlesStamp.Invalidate();
}

void vtkSPHVolumeMapper::RenderVolume(vtkRenderer* ren, vtkVolume* vol, vtkPointSet* input)
{
  raymappers::RenderStatistics stats;
  vtkRayMapperView view;
  {
    raymappers::ScopedPhase phase(stats, "particles");
    this->UpdateParticles(input);
  }
  stats.addCounter("particles", static_cast<std::int64_t>(Impl->Particles.size()));
  this->Core->AddBuildCounters(stats);
  const raymappers::TransferFunctionTable table =
    vtkRayMapperRenderHelpers::SampleVolumeProperty(vol->GetProperty(), 0, 1024);
  // The sampling reduction r of equation 3.1: the image sample distance.
  const double r = this->Core->BeginFrame(ren, vtkRayMapperSampleDistances::Of(this), stats);
  stats.addCounter("reduction_percent", static_cast<std::int64_t>(std::lround(100 * r)));
  if (!this->Core->GatherView(this, ren, vol, view))
  {
    this->Core->Skip(stats);
    return;
  }
  raymappers::SPHRenderParameters params = this->GatherParameters(ren, vol, view);
  params.stepFactor = this->StepFactor * r;
  params.samplesPerSupport = this->SamplesPerSupport / r;
  params.smallestSupport = this->SmallestSupport;
  // r times fewer rays along each axis.
  const raymappers::View kernelView =
    this->Core->KernelView(ren, view, r, Impl->Particles.origin, true, stats);
  if (!vtkRayMapperCore::HasDepthRays(this, kernelView))
  {
    this->Core->Skip(stats);
    return;
  }
  raymappers::renderSPH(
    { Impl->Particles, table, Impl->Grid }, kernelView, params, this->Core->Target(), stats);
  this->Core->Present(ren, view, vtkRayMapperFrameDrawer::Mode::BlendPremultiplied, false, stats);
}

void vtkSPHVolumeMapper::GetLastFrame(double frame[2])
{
  this->Core->GetLastFrame(frame);
}

void vtkSPHVolumeMapper::SetLastFrame(const double frame[2])
{
  this->Core->SetLastFrame(frame);
}

void vtkSPHVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Kernel: " << this->Kernel << "\n";
  os << indent << "SupportFactor: " << this->SupportFactor << "\n";
  os << indent << "SmoothingLength: " << this->SmoothingLength << "\n";
  os << indent << "ValueArrayName: " << vtkRayMapperString(this->ValueArrayName) << "\n";
  os << indent << "VolumeArrayName: " << vtkRayMapperString(this->VolumeArrayName) << "\n";
  os << indent << "MassArrayName: " << vtkRayMapperString(this->MassArrayName) << "\n";
  os << indent << "DensityArrayName: " << vtkRayMapperString(this->DensityArrayName) << "\n";
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
  os << indent << "SmallestSupport: " << this->SmallestSupport << "\n";
  os << indent << "FloatOrigin: (" << this->FloatOrigin[0] << ", " << this->FloatOrigin[1] << ", "
     << this->FloatOrigin[2] << ")" << (this->UseFloatOrigin ? "" : " (not used)") << "\n";
  os << indent << "TileSize: " << this->TileSize << "\n";
  os << indent << "SlabDepth: " << this->SlabDepth << "\n";
  os << indent << "TerminationOpacity: " << this->TerminationOpacity << "\n";
  os << indent << "Jitter: " << this->Jitter << "\n";
  vtkRayMapperSampleDistances::Of(this).Print(os, indent);
}
