#include "vtkRayMapperRenderHelpers.h"

#include "vtkRayMapperCameraMatrix.h"

#include "vtkAbstractVolumeMapper.h"
#include "vtkObject.h"
#include "vtkActor2D.h"
#include "vtkCamera.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationIntegerKey.h"
#include "vtkLight.h"
#include "vtkLightCollection.h"
#include "vtkMath.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkOpenGLCamera.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkProp3D.h"
#include "vtkPropCollection.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkScalarsToColors.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include "Mappers/Common/Limits.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace vtkRayMapperRenderHelpers
{

ModelTransform GatherModelTransform(vtkProp3D* prop)
{
  ModelTransform t;
  vtkMatrix4x4* m = prop ? prop->GetMatrix() : nullptr;
  vtkNew<vtkMatrix4x4> id;
  if (!m)
  {
    m = id;
  }
  for (int i = 0; i < 16; ++i)
  {
    t.modelToWorld[i] = m->GetElement(i / 4, i % 4);
  }
  t.identity = m->IsIdentity() != 0;
  vtkNew<vtkMatrix3x3> n;
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      n->SetElement(r, c, m->GetElement(r, c));
    }
  }
  n->Invert();
  n->Transpose();
  for (int i = 0; i < 9; ++i)
  {
    t.normalToWorld[i] = n->GetElement(i / 3, i % 3);
  }
  return t;
}

std::array<double, 16> GatherModelToClip(vtkRenderer* ren,
  const ModelTransform& model,
  int& width,
  int& height)
{
  int x0 = 0, y0 = 0;
  width = 0;
  height = 0;
  ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  std::array<double, 16> worldToClip;
  auto* glCamera = vtkOpenGLCamera::SafeDownCast(ren->GetActiveCamera());
  if (glCamera)
  {
    // The key matrices are transposed for OpenGL: WCDC^T holds world -> clip row-major.
    vtkMatrix4x4* wcvc;
    vtkMatrix3x3* normal;
    vtkMatrix4x4* vcdc;
    vtkMatrix4x4* wcdc;
    glCamera->GetKeyMatrices(ren, wcvc, normal, vcdc, wcdc);
    for (int i = 0; i < 16; ++i)
    {
      worldToClip[i] = wcdc->GetElement(i % 4, i / 4);
    }
  }
  else
  {
    const double aspect = height > 0 ? static_cast<double>(width) / height : 1.0;
    worldToClip = vtkRayMapperWorldToClip(ren->GetActiveCamera(), aspect);
  }
  std::array<double, 16> modelToClip{};
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      double s = 0;
      for (int k = 0; k < 4; ++k)
      {
        s += worldToClip[4 * r + k] * model.modelToWorld[4 * k + c];
      }
      modelToClip[4 * r + c] = s;
    }
  }
  return modelToClip;
}

raymappers::RayCamera GatherCamera(vtkRenderer* ren,
  const ModelTransform& model,
  const raymappers::Vec3d& origin)
{
  int width = 0, height = 0;
  const std::array<double, 16> modelToClip = GatherModelToClip(ren, model, width, height);
  return raymappers::RayCamera(modelToClip, width, height, origin);
}

bool CameraCheck::Usable(vtkObject* mapper, const std::array<double, 16>& modelToClip)
{
  const std::string why = raymappers::degenerateProjection(modelToClip);
  if (why.empty())
  {
    Warned.clear();
    return true;
  }
  if (why != Warned)
  {
    vtkWarningWithObjectMacro(mapper, << "The camera is degenerate: " << why << "; nothing drawn.");
    Warned = why;
  }
  return false;
}

std::vector<raymappers::Light> GatherLights(vtkRenderer* ren)
{
  std::vector<raymappers::Light> lights;
  vtkLightCollection* collection = ren->GetLights();
  vtkCollectionSimpleIterator it;
  collection->InitTraversal(it);
  while (vtkLight* l = collection->GetNextLight(it))
  {
    if (!l->GetSwitch() || l->GetIntensity() <= 0)
    {
      continue;
    }
    raymappers::Light light;
    const double* c = l->GetDiffuseColor();
    const double k = l->GetIntensity();
    light.color = { c[0] * k, c[1] * k, c[2] * k };
    double p[3], f[3];
    l->GetTransformedPosition(p);
    l->GetTransformedFocalPoint(f);
    light.direction =
      raymappers::normalize(raymappers::Vec3d(f[0] - p[0], f[1] - p[1], f[2] - p[2]));
    light.positional = l->GetPositional() != 0;
    light.position = { p[0], p[1], p[2] };
    light.coneAngleDeg = l->GetConeAngle();
    const double* a = l->GetAttenuationValues();
    light.attenuation = { a[0], a[1], a[2] };
    lights.push_back(light);
  }
  return lights;
}

vtkInformationIntegerKey* WRITES_DEPTH()
{
  // Created once, as vtkInformationKeyMacro creates VTK's keys (registered with VTK's key
  // lookup by the constructor).
  static vtkInformationIntegerKey* key =
    new vtkInformationIntegerKey("WRITES_DEPTH", "vtkRayMapperRenderHelpers");
  return key;
}

bool HasOpaqueGeometry(vtkRenderer* ren)
{
  if (ren->GetPreserveDepthBuffer())
  {
    return true; // the depth of an earlier renderer's geometry is kept
  }
  vtkPropCollection* props = ren->GetViewProps();
  vtkCollectionSimpleIterator it;
  props->InitTraversal(it);
  while (vtkProp* prop = props->GetNextProp(it))
  {
    // Volumes write no depth, except vtkSPHFluidMapper's surface, and 2D overlays are drawn
    // after the 3D props.
    if (!prop->GetVisibility() || vtkActor2D::SafeDownCast(prop))
    {
      continue;
    }
    if (auto* volume = vtkVolume::SafeDownCast(prop))
    {
      vtkAbstractVolumeMapper* mapper = volume->GetMapper();
      if (mapper && mapper->GetInformation()->Get(WRITES_DEPTH()) == 1)
      {
        return true;
      }
      continue;
    }
    if (prop->HasOpaqueGeometry())
    {
      return true;
    }
  }
  return false;
}

bool ReadOpaqueDepth(vtkRenderer* ren, std::vector<float>& depth, int& width, int& height)
{
  if (!HasOpaqueGeometry(ren))
  {
    return false;
  }
  int x0 = 0, y0 = 0;
  ren->GetTiledSizeAndOrigin(&width, &height, &x0, &y0);
  vtkRenderWindow* win = ren->GetRenderWindow();
  if (!win || width <= 0 || height <= 0)
  {
    return false;
  }
  depth.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  return win->GetZbufferData(x0, y0, x0 + width - 1, y0 + height - 1, depth.data()) != 0;
}

raymappers::TransferFunctionTable SampleVolumeProperty(vtkVolumeProperty* property,
  int component,
  int n)
{
  raymappers::TransferFunctionTable table;
  n = std::max(n, 2);
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity(component);
  double range[2] = { 0, 1 };
  std::vector<float> rgba(4 * static_cast<std::size_t>(n));
  std::vector<double> rgb(3 * static_cast<std::size_t>(n)), a(static_cast<std::size_t>(n));
  if (property->GetColorChannels(component) == 3)
  {
    vtkColorTransferFunction* color = property->GetRGBTransferFunction(component);
    color->GetRange(range);
    color->GetTable(range[0], range[1], n, rgb.data());
  }
  else
  {
    vtkPiecewiseFunction* gray = property->GetGrayTransferFunction(component);
    gray->GetRange(range);
    std::vector<double> g(static_cast<std::size_t>(n));
    gray->GetTable(range[0], range[1], n, g.data());
    for (int i = 0; i < n; ++i)
    {
      rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = g[i];
    }
  }
  opacity->GetTable(range[0], range[1], n, a.data());
  for (int i = 0; i < n; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      rgba[4 * i + c] = static_cast<float>(rgb[3 * i + c]);
    }
    rgba[4 * i + 3] = static_cast<float>(a[i]);
  }
  table.assign(
    std::move(rgba), range[0], range[1], property->GetScalarOpacityUnitDistance(component));
  return table;
}

raymappers::TransferFunctionTable SampleScalarsToColors(vtkScalarsToColors* colors,
  double lo,
  double hi,
  int n)
{
  raymappers::TransferFunctionTable table;
  n = std::max(n, 2);
  std::vector<float> rgba(4 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
  {
    const double v = lo + (hi - lo) * i / (n - 1);
    double rgb[3];
    colors->GetColor(v, rgb);
    rgba[4 * i] = static_cast<float>(rgb[0]);
    rgba[4 * i + 1] = static_cast<float>(rgb[1]);
    rgba[4 * i + 2] = static_cast<float>(rgb[2]);
    rgba[4 * i + 3] = static_cast<float>(colors->GetOpacity(v));
  }
  table.assign(std::move(rgba), lo, hi, 1.0);
  return table;
}

raymappers::RegionBox RegionFromBounds(const double bounds[6])
{
  raymappers::RegionBox box;
  for (int a = 0; a < 3; ++a)
  {
    const double l = bounds[2 * a], h = bounds[2 * a + 1];
    if (std::isfinite(l) && l > -VTK_DOUBLE_MAX)
    {
      box.lo[a] = l;
    }
    if (std::isfinite(h) && h < VTK_DOUBLE_MAX)
    {
      box.hi[a] = h;
    }
  }
  return box;
}

}
