// Turns what a VTK renderer holds into kernel input: the camera of the renderer's (tiled)
// viewport, its lights, the depth of opaque geometry already drawn, and transfer functions
// sampled into tables.
#ifndef vtkRayMapperRenderHelpers_h
#define vtkRayMapperRenderHelpers_h

#include "Mappers/Common/Lighting.h"
#include "Mappers/Common/RayCamera.h"
#include "RayMappersMappersModule.h" // for export macro
#include "Mappers/Common/RegionBox.h"
#include "Mappers/Common/TransferFunctionTable.h"

#include "vtkDataArray.h" // for TupleReader

#include <array>
#include <cstddef>
#include <string>
#include <vector>

class vtkDataSet;
class vtkInformationIntegerKey;
class vtkObject;
class vtkPoints;
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

/// Model-to-clip matrix (row-major, model coordinates not origin-relative) of the
/// renderer's tiled viewport for a prop, and that viewport's size. Uses the same
/// world-to-clip matrix as VTK's OpenGL mappers.
RAYMAPPERSMAPPERS_EXPORT std::array<double, 16> GatherModelToClip(vtkRenderer* ren,
  const ModelTransform& model,
  int& width,
  int& height);

/// Camera for the rays of the renderer's tiled viewport, in the prop's model coordinates,
/// with float coordinates relative to `origin` (model space). Uses the same world-to-clip
/// matrix as VTK's OpenGL mappers, so tiles of a large screenshot line up.
RAYMAPPERSMAPPERS_EXPORT raymappers::RayCamera GatherCamera(vtkRenderer* ren,
  const ModelTransform& model,
  const raymappers::Vec3d& origin);

/// The camera check of a mapper's render: true when the matrix gives rays; otherwise false
/// with the warning "The camera is degenerate: <why>; nothing drawn." from `mapper` (why:
/// raymappers::degenerateProjection, RayCamera.h), given
/// once while the reason stays the same (a camera stays degenerate for many renders) and
/// again after the camera was usable in between.
class RAYMAPPERSMAPPERS_EXPORT CameraCheck
{
public:
  bool Usable(vtkObject* mapper, const std::array<double, 16>& modelToClip);

private:
  std::string Warned;
};

/// The renderer's switched-on lights in world space.
RAYMAPPERSMAPPERS_EXPORT std::vector<raymappers::Light> GatherLights(vtkRenderer* ren);

/// The key a volume mapper sets to 1 in its algorithm information (GetInformation()) when
/// it writes depth like opaque geometry (vtkSPHFluidMapper's surfaces): volumes that come
/// after it must then read the depth buffer.
RAYMAPPERSMAPPERS_EXPORT vtkInformationIntegerKey* WRITES_DEPTH();

/// Whether the renderer may hold opaque geometry in the depth buffer: a visible prop that is
/// neither a volume nor a 2D overlay and has opaque geometry, a volume whose mapper says it
/// writes depth (WRITES_DEPTH), or a preserved depth buffer.
RAYMAPPERSMAPPERS_EXPORT bool HasOpaqueGeometry(vtkRenderer* ren);

/// Window depth of what has been drawn so far in the renderer's tiled viewport, row 0 at
/// the bottom (width x height values). Returns false when it cannot be read, and without
/// reading when the renderer has no opaque geometry (the depth buffer then holds only the
/// far plane, which stops no ray).
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

/// The kernels' region box of a mapper's RegionBounds (xmin, xmax, ymin, ymax, zmin,
/// zmax): +-VTK_DOUBLE_MAX and beyond are unbounded, NaN faces too.
RAYMAPPERSMAPPERS_EXPORT raymappers::RegionBox RegionFromBounds(const double bounds[6]);

}

#endif
