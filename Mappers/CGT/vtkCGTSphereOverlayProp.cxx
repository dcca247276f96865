#include "vtkCGTSphereOverlayProp.h"

#include "vtkCGTSphereMapper.h"
#include "vtkObjectFactory.h"
#include "vtkRenderer.h"

vtkStandardNewMacro(vtkCGTSphereOverlayProp);

vtkCGTSphereOverlayProp::vtkCGTSphereOverlayProp() = default;
vtkCGTSphereOverlayProp::~vtkCGTSphereOverlayProp() = default;

void vtkCGTSphereOverlayProp::SetMapper(vtkCGTSphereMapper* mapper)
{
  if (this->Mapper != mapper)
  {
    this->Mapper = mapper;
    this->Modified();
  }
}

vtkCGTSphereMapper* vtkCGTSphereOverlayProp::GetMapper()
{
  return this->Mapper;
}

int vtkCGTSphereOverlayProp::RenderOverlay(vtkViewport* viewport)
{
  auto* ren = vtkRenderer::SafeDownCast(viewport);
  return this->Mapper && this->Mapper->DrawDeferredSpheres(ren) ? 1 : 0;
}

void vtkCGTSphereOverlayProp::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mapper: " << this->Mapper.GetPointer() << "\n";
}
