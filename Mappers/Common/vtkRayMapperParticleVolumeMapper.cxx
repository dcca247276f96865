#include "vtkRayMapperParticleVolumeMapper.h"
#include "vtkRayMapperSelectionPass.h"

#include "vtkRayMapperCore.h"

#include "vtkAlgorithm.h"
#include "vtkInformation.h"
#include "vtkPointSet.h"
#include "vtkVolumeProperty.h"

#include <algorithm>

vtkRayMapperParticleVolumeMapper::vtkRayMapperParticleVolumeMapper(const char* drawn)
  : Core(new vtkRayMapperCore)
  , Drawn(drawn)
{
}

vtkRayMapperParticleVolumeMapper::~vtkRayMapperParticleVolumeMapper()
{
  this->SetScaleArray(nullptr);
}

void vtkRayMapperParticleVolumeMapper::SetInputData(vtkPointSet* input)
{
  this->SetInputDataInternal(0, input);
}

int vtkRayMapperParticleVolumeMapper::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPointSet");
  return 1;
}

vtkRayMapperStatistics* vtkRayMapperParticleVolumeMapper::GetStatistics()
{
  return this->Core->GetStatistics();
}

void vtkRayMapperParticleVolumeMapper::ReleaseGraphicsResources(vtkWindow* win)
{
  this->Core->ReleaseGraphicsResources(win);
  this->Superclass::ReleaseGraphicsResources(win);
}

double vtkRayMapperParticleVolumeMapper::SizeInUse(double constant, double perSpacing)
{
  return constant > 0.0 ? constant
                        : vtkRayMapperParticleSizes::AutomaticLength(
                            this->GetDataSetInput(), perSpacing, this->Spacing);
}

double* vtkRayMapperParticleVolumeMapper::GetBounds()
{
  vtkPointSet* input = this->Core->PointSetBounds(this, this->Bounds, this->Drawn);
  if (input)
  {
    vtkRayMapperCore::GrowBounds(this->Bounds, this->GetSupportRadius(input));
  }
  return this->Bounds;
}

void vtkRayMapperParticleVolumeMapper::Render(vtkRenderer* ren, vtkVolume* vol)
{
  if (vtkRayMapperSelectionPass::Of(ren))
  {
    // A hardware selection pass: selects nothing, hides what is behind.
    this->Core->PresentSelectionFootprint(ren);
    return;
  }
  this->Core->Execute(this,
    this->NumberOfThreads,
    [&]
    {
      auto* input = vtkPointSet::SafeDownCast(this->GetDataSetInput());
      // (A renderer culls an input without points by its empty bounds, where GetBounds
      // warns; this guards a direct call.)
      if (!input || input->GetNumberOfPoints() == 0 || !input->GetPoints())
      {
        this->Core->Skip(raymappers::RenderStatistics());
        return;
      }
      this->RenderVolume(ren, vol, input);
    },
    [this] { this->ReleaseBuilds(); });
}

void vtkRayMapperParticleVolumeMapper::WarnSkipped(std::size_t count, const char* what)
{
  if (count > 0)
  {
    vtkWarningMacro(<< count << " " << what << " and are not drawn.");
  }
}

void vtkRayMapperParticleVolumeMapper::CopyModelTransform(
  const vtkRayMapperView& view, double modelToWorld[16], double normalToWorld[9])
{
  std::copy(view.model.modelToWorld, view.model.modelToWorld + 16, modelToWorld);
  std::copy(view.model.normalToWorld, view.model.normalToWorld + 9, normalToWorld);
}

bool vtkRayMapperParticleVolumeMapper::GatherShading(vtkRenderer* ren,
  vtkVolumeProperty* property,
  std::vector<raymappers::Light>& lights,
  raymappers::Material& material)
{
  if (property->GetShade() == 0)
  {
    return false;
  }
  lights = vtkRayMapperRenderHelpers::GatherLights(ren);
  material = vtkRayMapperCore::GatherMaterial(property);
  return true;
}

void vtkRayMapperParticleVolumeMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ScaleArray: " << vtkRayMapperString(this->ScaleArray) << "\n";
  os << indent << "ScaleFactor: " << this->ScaleFactor << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
