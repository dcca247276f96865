#include "Mappers/Common/View.h"

namespace raymappers
{

View::View(const std::array<double, 16>& modelToClip,
  int width,
  int height,
  const Vec3d& origin,
  const float* opaqueDepth)
  : ModelToClip(modelToClip)
  , Width(width)
  , Height(height)
  , Origin(origin)
  , OpaqueDepth(opaqueDepth)
  , Camera(modelToClip, width, height, origin)
{
  DepthRaysValid = width > 0 && height > 0 && DepthRays.assign(modelToClip, width, height, origin);
}

} // namespace raymappers
