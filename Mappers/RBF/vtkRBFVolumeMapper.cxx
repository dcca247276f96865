#include "vtkRBFVolumeMapper.h"

#include "Frame.h"
#include "ParticleBVH.h"
#include "RBFParticles.h"
#include "RBFVolumeRenderer.h"
#include "RenderStatistics.h"
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
#include "vtkRenderer.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

vtkStandardNewMacro(vtkRBFVolumeMapper);

struct vtkRBFVolumeMapper::Internals
{
  raymappers::RBFParticles Particles;
  raymappers::ParticleBVH BVH;
  raymappers::Frame Frame;
  vtkRayMapperFrameDrawer Drawer;
  vtkRayMapperRenderHelpers::CameraCheck Camera;
  vtkNew<vtkRayMapperStatistics> Statistics;
  std::int64_t Builds = 0;
  double MeanRadius = 0.0;

  // What the particles were built from: rebuild only when one of these changes.
  bool HasParticles = false;
  vtkMTimeType BuiltInputTime = 0;
  double BuiltRadius = 0, BuiltScale = 0;
  std::string BuiltRadiusArray, BuiltValueArray, BuiltFieldArray;
  bool BVHStale = true;
  int BuiltLeafSize = 0;
  vtkMTimeType WarnedEmptyInputTime = 0;
};

vtkRBFVolumeMapper::vtkRBFVolumeMapper()
  : Impl(new Internals)
{
}

vtkRBFVolumeMapper::~vtkRBFVolumeMapper()
{
  this->SetRadiusArrayName(nullptr);
  this->SetValueArrayName(nullptr);
  this->SetFieldArrayName(nullptr);
}

void vtkRBFVolumeMapper::SetInputData(vtkPointSet* input)
{
  this->SetInputDataInternal(0, input);
}

int vtkRBFVolumeMapper::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

vtkRayMapperStatistics* vtkRBFVolumeMapper::GetStatistics()
{
  return Impl->Statistics;
}

void vtkRBFVolumeMapper::ReleaseGraphicsResources(vtkWindow* win)
{
  Impl->Drawer.ReleaseGraphicsResources(win);
  this->Superclass::ReleaseGraphicsResources(win);
}

double* vtkRBFVolumeMapper::GetBounds()
{
  // The points' bounds grown by the largest support, Sigma * r_max, so a camera reset
  // frames the whole field.
  // Bring the input up to date first (as vtkAbstractVolumeMapper::GetBounds does).
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
      // The renderer culls a volume with empty bounds before it renders: warn here, once
      // per input change.
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
  vtkDataArray* radii =
    vtkRayMapperRenderHelpers::FindPointArray(input, this->RadiusArrayName, "radius", why);
  const double rMax = radii
    ? vtkRayMapperRenderHelpers::LargestParticleLength(radii, this->RadiusScale)
    : this->Radius * this->RadiusScale;
  const double grow = this->Sigma * rMax;
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

bool vtkRBFVolumeMapper::UpdateParticles(vtkPointSet* input)
{
  const std::string radiusArray = this->RadiusArrayName ? this->RadiusArrayName : "";
  const std::string valueArray = this->ValueArrayName ? this->ValueArrayName : "";
  const std::string fieldArray = this->FieldArrayName ? this->FieldArrayName : "";
  if (Impl->HasParticles && Impl->BuiltInputTime == input->GetMTime() &&
      Impl->BuiltRadius == this->Radius && Impl->BuiltScale == this->RadiusScale &&
      Impl->BuiltRadiusArray == radiusArray && Impl->BuiltValueArray == valueArray &&
      Impl->BuiltFieldArray == fieldArray)
  {
    return false;
  }
  std::string why;
  vtkDataArray* radii =
    vtkRayMapperRenderHelpers::FindPointArray(input, this->RadiusArrayName, "radius", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << "; using the constant radius " << this->Radius << ".");
    why.clear();
  }
  vtkDataArray* values =
    vtkRayMapperRenderHelpers::FindPointArray(input, this->ValueArrayName, "value", why);
  if (!why.empty())
  {
    vtkWarningMacro(<< why << "; every particle has the value 1.");
    why.clear();
  }
  vtkDataArray* categories =
    vtkRayMapperRenderHelpers::FindPointArray(input, this->FieldArrayName, "field", why);
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

  const vtkRayMapperRenderHelpers::TupleReader pointReader(input->GetPoints()->GetData());
  const vtkRayMapperRenderHelpers::TupleReader radiusReader(radii);
  const vtkRayMapperRenderHelpers::TupleReader valueReader(values);
  const double scale = this->RadiusScale, constantRadius = this->Radius * scale;
  raymappers::buildRBFParticles(
    n,
    vtkRayMapperRenderHelpers::FiniteCenter(input->GetPoints()),
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
  if (Impl->Particles.skippedNonFinite > 0)
  {
    vtkWarningMacro(<< Impl->Particles.skippedNonFinite
                    << " points have NaN or infinite coordinates or values and are not drawn.");
  }
  if (Impl->Particles.skippedBadRadius > 0)
  {
    vtkWarningMacro(<< Impl->Particles.skippedBadRadius
                    << " particles have a zero, negative, non-finite or huge (above 1e15) radius and are not drawn.");
  }
  double sum = 0;
  for (const float r : Impl->Particles.radii)
  {
    sum += r;
  }
  Impl->MeanRadius = Impl->Particles.size() ? sum / Impl->Particles.size() : 0.0;
  Impl->HasParticles = true;
  Impl->BuiltInputTime = input->GetMTime();
  Impl->BuiltRadius = this->Radius;
  Impl->BuiltScale = this->RadiusScale;
  Impl->BuiltRadiusArray = radiusArray;
  Impl->BuiltValueArray = valueArray;
  Impl->BuiltFieldArray = fieldArray;
  Impl->BVHStale = true;
  return true;
}

void vtkRBFVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  raymappers::RenderStatistics stats;
  auto* input = vtkPointSet::SafeDownCast(this->GetDataSetInput());
  if (!input || input->GetNumberOfPoints() == 0 || !input->GetPoints())
  {
    Impl->Statistics->Set(stats);
    return;
  }

  // 1. Update: the particles depend on the input and the arrays, the BVH on the particles
  //    and the leaf size; Kappa, Sigma, the step, the transfer functions and the camera
  //    rebuild nothing.
  stats.declareCounter("builds_this_render");
  {
    raymappers::ScopedPhase phase(stats, "particles");
    this->UpdateParticles(input);
  }
  if (Impl->BVHStale || Impl->BuiltLeafSize != this->LeafSize)
  {
    raymappers::ScopedPhase phase(stats, "bvh_build");
    Impl->BVH.build(Impl->Particles, this->LeafSize);
    Impl->BVHStale = false;
    Impl->BuiltLeafSize = this->LeafSize;
    ++Impl->Builds;
    stats.addCounter("builds_this_render", 1);
  }
  stats.addCounter("builds", Impl->Builds);
  stats.addCounter("particles", static_cast<std::int64_t>(Impl->Particles.size()));
  stats.addCounter("bvh_nodes", static_cast<std::int64_t>(Impl->BVH.nodes().size()));
  stats.addCounter("bvh_bytes", static_cast<std::int64_t>(Impl->BVH.memoryBytes()));
  stats.addCounter("fields", Impl->Particles.numFields);

  // 2. Classification, camera, lights, opaque depth.
  vtkVolumeProperty* property = vol->GetProperty();
  std::vector<raymappers::TransferFunctionTable> tables;
  for (int m = 0; m < Impl->Particles.numFields; ++m)
  {
    tables.push_back(vtkRayMapperRenderHelpers::SampleVolumeProperty(property, m, 1024));
  }
  raymappers::RBFRenderParameters params;
  params.kappa = this->Kappa;
  params.sigma = this->Sigma;
  params.sampleDistance =
    this->SampleDistance > 0 ? this->SampleDistance : 0.5 * std::max(Impl->MeanRadius, 1e-30);
  params.terminationOpacity = this->TerminationOpacity;
  params.samplesPerPass = this->SamplesPerPass;
  params.packetSide = this->PacketSize;
  params.tileSize = this->TileSize;
  params.direct = this->Method == VTK_RBF_METHOD_DIRECT;
  params.region = vtkRayMapperRenderHelpers::RegionFromBounds(this->RegionBounds);
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
  int width = 0, height = 0;
  const std::array<double, 16> modelToClip =
    vtkRayMapperRenderHelpers::GatherModelToClip(ren, model, width, height);
  if (!Impl->Camera.Usable(this, modelToClip))
  {
    Impl->Statistics->Set(stats);
    return;
  }
  const raymappers::RayCamera camera(modelToClip, width, height, Impl->Particles.origin);
  std::vector<float> depth;
  int dw = 0, dh = 0;
  bool haveDepth = false;
  {
    raymappers::ScopedPhase phase(stats, "opaque_depth");
    haveDepth = vtkRayMapperRenderHelpers::ReadOpaqueDepth(ren, depth, dw, dh) &&
      dw == camera.width() && dh == camera.height();
  }
  stats.setEffect("opaque_depth", haveDepth);

  // 3. Trace, 4. show.
  {
    raymappers::ScopedPhase phase(stats, "trace");
    raymappers::renderRBF(Impl->Particles,
      Impl->BVH,
      camera,
      params,
      tables,
      haveDepth ? depth.data() : nullptr,
      Impl->Frame,
      stats);
  }
  {
    raymappers::ScopedPhase phase(stats, "draw");
    Impl->Drawer.Draw(ren, Impl->Frame, vtkRayMapperFrameDrawer::Mode::BlendPremultiplied,
      Impl->Statistics->GetValidateFrames(), stats);
  }
  Impl->Statistics->Set(stats);
}

void vtkRBFVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Kappa: " << this->Kappa << "\n";
  os << indent << "Sigma: " << this->Sigma << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "RadiusArrayName: " << (this->RadiusArrayName ? this->RadiusArrayName : "(none)")
     << "\n";
  os << indent << "RadiusScale: " << this->RadiusScale << "\n";
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
}
