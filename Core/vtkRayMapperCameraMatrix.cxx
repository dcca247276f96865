#include "vtkRayMapperCameraMatrix.h"

#include "vtkCamera.h"
#include "vtkMatrix4x4.h"

std::array<double, 16> vtkRayMapperWorldToClip(vtkCamera* camera, double aspect)
{
  vtkMatrix4x4* m = camera->GetCompositeProjectionTransformMatrix(aspect, -1, 1);
  std::array<double, 16> worldToClip;
  for (int i = 0; i < 16; ++i)
  {
    worldToClip[i] = m->GetElement(i / 4, i % 4);
  }
  return worldToClip;
}
