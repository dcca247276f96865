#include "ReferenceFromVTK.h"

#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMatrix4x4.h"
#include "vtkPiecewiseFunction.h"
#include "vtkProperty.h"
#include "vtkRenderer.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <stdexcept>

namespace raymappers::reference
{

ReferenceCamera cameraOf(vtkRenderer* renderer)
{
  vtkMatrix4x4* m = renderer->GetActiveCamera()->GetCompositeProjectionTransformMatrix(
    renderer->GetTiledAspectRatio(), -1, 1);
  std::array<double, 16> worldToNDC;
  for (int k = 0; k < 16; ++k)
  {
    worldToNDC[k] = m->GetElement(k / 4, k % 4);
  }
  const int* size = renderer->GetSize();
  return ReferenceCamera(worldToNDC, size[0], size[1]);
}

std::vector<ReferenceLight> lightsOf(vtkRenderer* renderer)
{
  std::vector<ReferenceLight> lights;
  vtkLightCollection* all = renderer->GetLights();
  vtkCollectionSimpleIterator it;
  all->InitTraversal(it);
  while (vtkLight* light = all->GetNextLight(it))
  {
    if (!light->GetSwitch())
    {
      continue;
    }
    if (light->GetPositional())
    {
      throw std::runtime_error("the reference has directional lights only");
    }
    double p[3], f[3], c[3];
    light->GetTransformedPosition(p);
    light->GetTransformedFocalPoint(f);
    light->GetDiffuseColor(c);
    const double s = light->GetIntensity();
    lights.push_back({ unit(Point{ p[0] - f[0], p[1] - f[1], p[2] - f[2] }),
      Point{ c[0] * s, c[1] * s, c[2] * s } });
  }
  return lights;
}

ReferenceTransferFunction transferFunctionOf(vtkVolumeProperty* property, int samples)
{
  vtkColorTransferFunction* color = property->GetRGBTransferFunction();
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity();
  double cr[2], orange[2];
  color->GetRange(cr);
  opacity->GetRange(orange);
  ReferenceTransferFunction tf;
  tf.lo = std::min(cr[0], orange[0]);
  tf.hi = std::max(cr[1], orange[1]);
  tf.unitDistance = property->GetScalarOpacityUnitDistance();
  for (int k = 0; k < samples; ++k)
  {
    const double v = tf.lo + (tf.hi - tf.lo) * k / (samples - 1);
    double rgb[3];
    color->GetColor(v, rgb);
    tf.rgba.push_back({ rgb[0], rgb[1], rgb[2], opacity->GetValue(v) });
  }
  return tf;
}

ReferenceMaterial materialOf(vtkProperty* property)
{
  ReferenceMaterial m;
  m.ambient = property->GetAmbient();
  m.diffuse = property->GetDiffuse();
  m.specular = property->GetSpecular();
  m.specularPower = property->GetSpecularPower();
  double s[3];
  property->GetSpecularColor(s);
  m.specularColor = { s[0], s[1], s[2] };
  return m;
}

}
