// Turns what a VTK renderer holds into kernel input: the camera of the renderer's (tiled)
// viewport, its lights, the depth of opaque geometry already drawn, and transfer functions
// sampled into tables.
#ifndef vtkRayMapperRenderHelpers_h
#define vtkRayMapperRenderHelpers_h

#include "Lighting.h"
#include "RayCamera.h"
#include "RayMappersMappersModule.h" // for export macro
#include "TransferFunctionTable.h"

#include <vector>

class vtkProp3D;
class vtkRenderer;
class vtkScalarsToColors;
class vtkVolumeProperty;

namespace vtkRayMapperRenderHelpers
{

/// Model-to-world transform of a prop (row-major) and its normal matrix
/// (inverse transpose of the linear part).
struct ModelTransform
{
  double modelToWorld[16];
  double normalToWorld[9];
  bool identity = true;
};
RAYMAPPERSMAPPERS_EXPORT ModelTransform GatherModelTransform(vtkProp3D* prop);

/// Camera for the rays of the renderer's tiled viewport, in the prop's model coordinates,
/// with float coordinates relative to `origin` (model space). Uses the same world-to-clip
/// matrix as VTK's OpenGL mappers, so tiles of a large screenshot line up.
RAYMAPPERSMAPPERS_EXPORT raymappers::RayCamera GatherCamera(vtkRenderer* ren,
  const ModelTransform& model,
  const raymappers::Vec3d& origin);

/// The renderer's switched-on lights in world space.
RAYMAPPERSMAPPERS_EXPORT std::vector<raymappers::Light> GatherLights(vtkRenderer* ren);

/// Window depth of what has been drawn so far in the renderer's tiled viewport, row 0 at
/// the bottom (width x height values). Returns false when it cannot be read.
RAYMAPPERSMAPPERS_EXPORT bool ReadOpaqueDepth(vtkRenderer* ren,
  std::vector<float>& depth,
  int& width,
  int& height);

/// Colour and scalar opacity of one component of a volume property, sampled at n points
/// over the colour function's range, with the property's scalar opacity unit distance.
RAYMAPPERSMAPPERS_EXPORT raymappers::TransferFunctionTable SampleVolumeProperty(
  vtkVolumeProperty* property,
  int component,
  int n);

/// RGBA of a lookup table / colour transfer function at n points over [lo, hi].
RAYMAPPERSMAPPERS_EXPORT raymappers::TransferFunctionTable SampleScalarsToColors(
  vtkScalarsToColors* colors,
  double lo,
  double hi,
  int n);

}

#endif
