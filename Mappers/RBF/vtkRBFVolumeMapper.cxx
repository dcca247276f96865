#include "vtkRBFVolumeMapper.h"
#include "vtkRayMapperPointArrays.h"

#include "Mappers/Common/Frame.h"
#include "Mappers/RBF/ParticleBVH.h"
#include "Mappers/RBF/RBFParticles.h"
#include "Mappers/RBF/RBFVolumeRenderer.h"
#include "Mappers/Common/RenderStatistics.h"
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
#include <map>
#include <vector>
#include <string>

vtkStandardNewMacro(vtkRBFVolumeMapper);

struct vtkRBFVolumeMapper::Internals
{
  raymappers::RBFParticles Particles;
  raymappers::ParticleBVH BVH;
  double MeanRadius = 0.0;
  // The automatic kappa for the BVH's particles at the sigma it was measured with (-1: none).
  double AutomaticKappa = 1.0;
  double AutomaticKappaSigma = -1.0;
  // The particles are built from the points and the radius, value and field arrays, the
  // BVH from the particles and the leaf size.
  vtkRayMapperStamp<double, double, std::string, std::string, std::string> ParticlesStamp;
  vtkRayMapperStamp<int> BVHStamp;
};

vtkRBFVolumeMapper::vtkRBFVolumeMapper()
  : Superclass("volume")
  , Impl(new Internals)
{
}

vtkRBFVolumeMapper::~vtkRBFVolumeMapper()
{
  this->SetValueArrayName(nullptr);
  this->SetFieldArrayName(nullptr);
}

double vtkRBFVolumeMapper::GetSupportRadius(vtkPointSet* input)
{
  // Sigma * r_max: each Gaussian is truncated at Sigma radii.
  std::string why;
  vtkDataArray* radii =
    vtkRayMapperPointArrays::FindPointArray(input, this->ScaleArray, "radius", why);
  const double rMax = radii
    ? vtkRayMapperPointArrays::LargestParticleLength(radii, this->ScaleFactor)
    : this->GetRadiusInUse() * this->ScaleFactor;
  return this->Sigma * rMax;
}

double vtkRBFVolumeMapper::GetRadiusInUse()
{
  return this->SizeInUse(this->Radius, GetAutomaticRadiusPerSpacing());
}

bool vtkRBFVolumeMapper::UpdateParticles(vtkPointSet* input)
{
  if (!Impl->ParticlesStamp.Changed(this, input,
        { this->Radius, this->ScaleFactor, vtkRayMapperString(this->ScaleArray),
          vtkRayMapperString(this->ValueArrayName), vtkRayMapperString(this->FieldArrayName) }))
  {
    return false;
  }
  vtkDataArray* radii = vtkRayMapperPointArrays::FindScaleArray(
    this, input, this->ScaleArray, "radius", this->Radius);
  std::string why;
  vtkDataArray* values =
    vtkRayMapperPointArrays::FindPointArray(input, this->ValueArrayName, "value", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << "; every particle has the value 1.");
    why.clear();
  }
  vtkDataArray* categories =
    vtkRayMapperPointArrays::FindPointArray(input, this->FieldArrayName, "field", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << "; all particles form one field.");
  }
  vtkRayMapperWarnIfComponentsDiffer(this, radii, "radius");
  vtkRayMapperWarnIfComponentsDiffer(this, values, "value");
  vtkRayMapperWarnIfComponentsDiffer(this, categories, "field");
  // Fields: the distinct values of the categorical array, in increasing order.
  const auto n = static_cast<std::size_t>(input->GetNumberOfPoints());
  std::map<double, int> fieldOf;
  if (categories)
  {
    for (std::size_t i = 0; i < n; ++i)
    {
      const double v = categories->GetComponent(static_cast<vtkIdType>(i), 0);
      if (std::isfinite(v))
      {
        fieldOf.emplace(v, 0);
      }
    }
    int m = 0;
    for (auto& entry : fieldOf)
    {
      entry.second = std::min(m++, raymappers::MaxRBFFields - 1);
    }
    if (m > raymappers::MaxRBFFields)
    {
      vtkWarningMacro(<< "field array '" << this->FieldArrayName << "' has " << m
                      << " distinct values; the values from the " << raymappers::MaxRBFFields
                      << "th on share the last field.");
    }
  }
  const int numFields =
    categories ? std::clamp(static_cast<int>(fieldOf.size()), 1, raymappers::MaxRBFFields) : 1;

  const vtkRayMapperPointArrays::TupleReader pointReader(input->GetPoints()->GetData());
  const vtkRayMapperPointArrays::TupleReader radiusReader(radii);
  const vtkRayMapperPointArrays::TupleReader valueReader(values);
  const double scale = this->ScaleFactor;
  const double constantRadius = radii ? 0.0 : this->GetRadiusInUse() * scale;
  raymappers::buildRBFParticles(
    n,
    raymappers::Vec3d(vtkRayMapperPointArrays::FiniteCenter(input->GetPoints())),
    numFields,
    [&](std::size_t i) {
      return raymappers::Vec3d(pointReader.get(i, 0), pointReader.get(i, 1), pointReader.get(i, 2));
    },
    [&](std::size_t i) { return radii ? radiusReader.get(i, 0) * scale : constantRadius; },
    [&](std::size_t i) { return values ? valueReader.get(i, 0) : 1.0; },
    [&](std::size_t i)
    {
      if (!categories)
      {
        return 0;
      }
      const auto it = fieldOf.find(categories->GetComponent(static_cast<vtkIdType>(i), 0));
      return it == fieldOf.end() ? 0 : it->second;
    },
    Impl->Particles);
  this->WarnSkipped(
    Impl->Particles.skippedNonFinite, "points have NaN or infinite coordinates or values");
  this->WarnSkipped(Impl->Particles.skippedBadRadius,
    "particles have a zero, negative, non-finite or huge (above 1e15) radius");
  double sum = 0;
  for (const float r : Impl->Particles.radii)
  {
    sum += r;
  }
  Impl->MeanRadius = Impl->Particles.size() ? sum / Impl->Particles.size() : 0.0;
  Impl->BVHStamp.Invalidate();
  return true;
}

void vtkRBFVolumeMapper::UpdateAcceleration(vtkPointSet* input, raymappers::RenderStatistics& stats)
{
  // The particles depend on the input and the arrays, the BVH on the particles and the leaf
  // size; Kappa, Sigma, the step, the transfer functions and the camera rebuild nothing.
  {
    raymappers::ScopedPhase phase(stats, "particles");
    this->UpdateParticles(input);
  }
  if (Impl->BVHStamp.Changed(this, nullptr, { this->LeafSize }))
  {
    raymappers::ScopedPhase phase(stats, "bvh_build");
    Impl->BVH.build(Impl->Particles, this->LeafSize);
    Impl->AutomaticKappaSigma = -1.0;
    this->Core->CountBuild();
  }
  this->Core->AddBuildCounters(stats);
  stats.addCounter("particles", static_cast<std::int64_t>(Impl->Particles.size()));
  stats.addCounter("bvh_nodes", static_cast<std::int64_t>(Impl->BVH.nodes().size()));
  stats.addCounter("bvh_bytes", static_cast<std::int64_t>(Impl->BVH.memoryBytes()));
  stats.addCounter("fields", Impl->Particles.numFields);
}

void vtkRBFVolumeMapper::UpdateForCurrentInput()
{
  auto* input = vtkPointSet::SafeDownCast(this->GetDataSetInput());
  if (input && input->GetNumberOfPoints() > 0)
  {
    raymappers::RenderStatistics unused;
    this->UpdateAcceleration(input, unused);
  }
}

vtkIdType vtkRBFVolumeMapper::GetNumberOfParticlesInUse()
{
  this->UpdateForCurrentInput();
  return static_cast<vtkIdType>(Impl->Particles.size());
}

double vtkRBFVolumeMapper::GetKappaInUse()
{
  this->UpdateForCurrentInput();
  return this->KappaForBuiltParticles();
}

double vtkRBFVolumeMapper::KappaForBuiltParticles()
{
  if (this->Kappa > 0.0)
  {
    return this->Kappa;
  }
  // 1 / the median weight sum: measured again only for new particles or another sigma.
  if (Impl->AutomaticKappaSigma != this->Sigma)
  {
    const double w =
      raymappers::medianWeightSum(Impl->Particles, Impl->BVH, static_cast<float>(this->Sigma));
    Impl->AutomaticKappa = w > 0.0 ? 1.0 / w : 1.0;
    Impl->AutomaticKappaSigma = this->Sigma;
  }
  return Impl->AutomaticKappa;
}

raymappers::RBFRenderParameters vtkRBFVolumeMapper::GatherParameters(vtkRenderer* ren,
  vtkVolume* vol,
  const vtkRayMapperView& view)
{
  raymappers::RBFRenderParameters params;
  params.kappa = this->KappaForBuiltParticles();
  params.sigma = this->Sigma;
  params.sampleDistance =
    this->SampleDistance > 0 ? this->SampleDistance : 0.5 * std::max(Impl->MeanRadius, 1e-30);
  params.terminationOpacity = this->TerminationOpacity;
  params.samplesPerPass = this->SamplesPerPass;
  params.packetSide = this->PacketSize;
  params.tileSize = this->TileSize;
  params.direct = this->Method == VTK_RBF_METHOD_DIRECT;
  params.normalizeWeights = this->NormalizeWeights;
  params.region = vtkRayMapperRenderHelpers::RegionFromBounds(this->RegionBounds);
  CopyModelTransform(view, params.modelToWorld, params.normalToWorld);
  params.shade = GatherShading(ren, vol->GetProperty(), params.lights, params.material);
  return params;
}

void vtkRBFVolumeMapper::ReleaseBuilds()
{
  Impl->Particles = raymappers::RBFParticles();
  Impl->BVH = raymappers::ParticleBVH();
  Impl->ParticlesStamp.Invalidate();
  Impl->BVHStamp.Invalidate();
}

void vtkRBFVolumeMapper::RenderVolume(vtkRenderer* ren, vtkVolume* vol, vtkPointSet* input)
{
  raymappers::RenderStatistics stats;
  vtkRayMapperCore::View view;
  this->UpdateAcceleration(input, stats);
  // Classification: component m of the volume property for field m.
  std::vector<raymappers::TransferFunctionTable> tables;
  for (int m = 0; m < Impl->Particles.numFields; ++m)
  {
    tables.push_back(vtkRayMapperRenderHelpers::SampleVolumeProperty(vol->GetProperty(), m, 1024));
  }
  if (!this->Core->GatherView(this, ren, vol, view))
  {
    this->Core->Skip(stats);
    return;
  }
  const raymappers::RBFRenderParameters params = this->GatherParameters(ren, vol, view);
  const raymappers::View kernelView =
    this->Core->KernelView(ren, view, 1.0, Impl->Particles.origin, true, stats);
  {
    raymappers::ScopedPhase phase(stats, "trace");
    raymappers::renderRBF(
      { Impl->Particles, Impl->BVH, tables }, kernelView, params, this->Core->Target(), stats);
  }
  this->Core->Present(ren, view, vtkRayMapperFrameDrawer::Mode::BlendPremultiplied, false, stats);
}

void vtkRBFVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Kappa: " << this->Kappa << "\n";
  os << indent << "Sigma: " << this->Sigma << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "ValueArrayName: " << (this->ValueArrayName ? this->ValueArrayName : "(none)")
     << "\n";
  os << indent << "FieldArrayName: " << (this->FieldArrayName ? this->FieldArrayName : "(none)")
     << "\n";
  os << indent << "TerminationOpacity: " << this->TerminationOpacity << "\n";
  os << indent << "SamplesPerPass: " << this->SamplesPerPass << "\n";
  os << indent << "PacketSize: " << this->PacketSize << "\n";
  os << indent << "LeafSize: " << this->LeafSize << "\n";
  os << indent << "TileSize: " << this->TileSize << "\n";
  os << indent << "RegionBounds: (" << this->RegionBounds[0] << ", " << this->RegionBounds[1]
     << ", " << this->RegionBounds[2] << ", " << this->RegionBounds[3] << ", "
     << this->RegionBounds[4] << ", " << this->RegionBounds[5] << ")\n";
  os << indent << "Method: " << this->Method << "\n";
  os << indent << "NormalizeWeights: " << this->NormalizeWeights << "\n";
}
